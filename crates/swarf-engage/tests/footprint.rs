//! Material beside the cutter's footprint changes neither the engagement nor the work: the
//! circles sampled at a location are those below the highest material over the box of the
//! cutter itself, not over a box its height wide (a wall 15 mm away made every circle up to
//! its top "reachable", and each was then probed along its whole front).

mod common;

use common::*;
use swarf_engage::{EngageOptions, Engagement, Engager};
use swarf_stock::{simulate, SimOptions, TriDexel};
use swarf_tool::{Cutter, ToolSet};

/// A 10 mm ball cutting a groove 0.5 mm deep along y = 10 in a floor at z = 0.
const GROOVE: &str = "G21 G90\nG0 X5 Y10 Z5\nG1 Z-0.5 F600\nG1 X55\n";

/// The groove's engagements on `stock`, and the probes they took.
fn groove(stock: &mut TriDexel) -> (Vec<Engagement>, u64) {
    let p = program(GROOVE, "groove.ngc");
    let tools = ToolSet::single(Cutter::ball(10.0).unwrap());
    let mut run = Engager::new(&p, &tools, stock, EngageOptions::default()).unwrap();
    let e: Vec<Engagement> = run.by_ref().map(Result::unwrap).collect();
    (e, run.stats().probes)
}

#[test]
fn a_wall_beside_the_footprint_changes_nothing() {
    // The floor alone.
    let mut floor = block([0.0, 0.0, -10.0], [60.0, 40.0, 0.0], 0.1);
    // The same floor, cleared down to z = 0 by a 20 mm flat end mill for y < 30, beside a
    // 30 mm wall from y = 30 to 40: 15 mm from the groove's cutter, well within its height.
    let mut walled = block([0.0, 0.0, -10.0], [60.0, 40.0, 30.0], 0.1);
    let clear = program(
        "G21 G90\nG0 X-15 Y0 Z40\nG1 Z0 F1000\nG1 X75\nG1 Y10\nG1 X-15\nG1 Y20\nG1 X75\nG0 Z40\n",
        "clear.ngc",
    );
    let flat = ToolSet::single(Cutter::flat(20.0).unwrap());
    simulate(&clear, &flat, &mut walled, &SimOptions::default()).unwrap();

    let (a, probes_floor) = groove(&mut floor);
    let (b, probes_walled) = groove(&mut walled);
    assert_eq!(a.len(), b.len());
    let mut engaged = 0;
    for (x, y) in a.iter().zip(&b) {
        assert!(
            (x.area_mm2 - y.area_mm2).abs() <= 1e-9 * x.area_mm2.max(1.0),
            "location {}: {} vs {} mm²",
            x.location,
            x.area_mm2,
            y.area_mm2
        );
        assert_eq!(x.phi_entry_deg, y.phi_entry_deg);
        assert_eq!(x.phi_exit_deg, y.phi_exit_deg);
        engaged += usize::from(x.is_engaged());
    }
    assert!(engaged > 40, "{engaged} engaged locations");
    // The wall's rays are read by some probes (it is the nearest material to far samples),
    // so the counts may differ a little; sampling every circle up to the wall's top would
    // multiply them.
    println!("probes: floor {probes_floor}, floor beside a wall {probes_walled}");
    assert!(
        probes_walled as f64 <= 1.1 * probes_floor as f64,
        "{probes_walled} probes beside the wall, {probes_floor} without it"
    );
}
