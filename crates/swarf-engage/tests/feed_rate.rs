//! The feed of a location is the tip's speed over the workpiece: on a rotary move without tool
//! centre point control the controller applies F to the joints (X Y Z, else the rotary angle),
//! so the tip runs at its path over the move's time, not at F.

mod common;

use std::f64::consts::FRAC_PI_2;

use common::*;
use swarf_engage::{EngageOptions, Engager};
use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::Machine;
use swarf_tool::{Cutter, ToolSet};

/// On a 4-axis machine (A about X, table at the origin) the tip stands 9 mm above the axis.
/// `G1 A90 F100`: 90° at 100°/min take 0.9 min while the tip runs a quarter circle of radius
/// 9 over the workpiece, 9·π/2 mm: 15.708 mm/min. `G1 X20 A180 F500`: X Y Z move 20 mm, so
/// 0.04 min, along a helix of hypot(20, 9·π/2) = 24.49 mm: 612.3 mm/min. (Both read F as the
/// tip's before: 100 and 500.) The removal rate is the removed volume over the same minutes.
#[test]
fn a_rotary_move_without_tcp_feeds_the_tip_at_its_path_over_the_joints_time() {
    let text = "G21 G90 G94\nS8000 M3\nG0 X0 Y0 Z12 A0\nG1 Z9 F200\nG1 A90 F100\n\
        G1 X20 A180 F500\nM30\n";
    let p = read_program_str(
        text,
        "wrap.ngc",
        Machine::from_name("4axis-a").unwrap(),
        &ReadOptions::default(),
    )
    .unwrap();
    let tools = ToolSet::single(Cutter::from_spec("flat:d=6").unwrap());
    let opts = EngageOptions {
        chordal_tolerance_mm: 0.01,
        ..EngageOptions::default()
    }
    .with_step(0.0);
    let mut stock = block([-5.0, -10.0, -10.0], [25.0, 10.0, 10.0], 0.25);
    let locations: Vec<_> = Engager::new(&p, &tools, &mut stock, opts)
        .unwrap()
        .map(Result::unwrap)
        .collect();
    assert_eq!(locations.len(), 3, "one location at the end of each feed");
    let plunge = &locations[0];
    assert!(
        rel(plunge.feed_mm_min, 200.0) < 1e-12,
        "{}",
        plunge.feed_mm_min
    );
    let turn = &locations[1];
    let want = 9.0 * FRAC_PI_2 / 0.9;
    println!("A90 F100: {:.4} mm/min (exact {want:.4})", turn.feed_mm_min);
    assert!(rel(turn.feed_mm_min, want) < 1e-4, "{}", turn.feed_mm_min);
    let helix = &locations[2];
    let want = 20f64.hypot(9.0 * FRAC_PI_2) / 0.04;
    println!(
        "X20 A180 F500: {:.4} mm/min (exact {want:.4})",
        helix.feed_mm_min
    );
    assert!(rel(helix.feed_mm_min, want) < 1e-4, "{}", helix.feed_mm_min);
    for (e, minutes) in [(turn, 0.9), (helix, 0.04)] {
        assert!(e.removed_mm3 > 1.0, "{}", e.removed_mm3);
        assert!(
            rel(e.mrr_mm3_min, e.removed_mm3 / minutes) < 1e-9,
            "{} {}",
            e.mrr_mm3_min,
            e.removed_mm3
        );
    }
}
