//! Helpers shared by the engagement tests: read a program, run it, pick a location.
#![allow(dead_code)]

use swarf_engage::{EngageOptions, Engagement, Engager};
use swarf_geom::math::Vec3;
use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::{Machine, Program};
use swarf_stock::TriDexel;
use swarf_tool::{Cutter, ToolSet};

/// Reads a program (G-code or APT by the file name's extension) on a 3-axis machine.
pub(crate) fn program(text: &str, file: &str) -> Program {
    read_program_str(text, file, Machine::three_axis(), &ReadOptions::default()).unwrap()
}

/// A box stock.
pub(crate) fn block(min: [f64; 3], max: [f64; 3], h: f64) -> TriDexel {
    TriDexel::from_box(Vec3::from(min), Vec3::from(max), h).unwrap()
}

/// Every location of `program` run with `cutter` on `stock`.
pub(crate) fn run(
    program: &Program,
    cutter: Cutter,
    stock: &mut TriDexel,
    opts: EngageOptions,
) -> Vec<Engagement> {
    let tools = ToolSet::single(cutter);
    Engager::new(program, &tools, stock, opts)
        .unwrap()
        .map(Result::unwrap)
        .collect()
}

/// Every location of the program `text` (file name `file`) with `cutter` in the block from
/// `min` to `max` at the tests' ray spacing of 0.1 mm, default options.
pub(crate) fn run_in_block(
    text: &str,
    file: &str,
    min: [f64; 3],
    max: [f64; 3],
    cutter: Cutter,
) -> Vec<Engagement> {
    let p = program(text, file);
    let mut stock = block(min, max, 0.1);
    run(&p, cutter, &mut stock, EngageOptions::default())
}

/// The location whose tip is nearest to `p`.
pub(crate) fn at(locations: &[Engagement], p: [f64; 3]) -> &Engagement {
    let p = Vec3::from(p);
    locations
        .iter()
        .min_by(|a, b| (a.tip - p).length().total_cmp(&(b.tip - p).length()))
        .unwrap()
}

/// Relative error.
pub(crate) fn rel(got: f64, want: f64) -> f64 {
    (got - want).abs() / want.abs()
}

/// Asserts the area within `rel_tol`, the angles within `deg_tol` and prints them.
pub(crate) fn check(e: &Engagement, area: f64, entry: f64, exit: f64, rel_tol: f64, deg_tol: f64) {
    let (a, b) = (e.phi_entry_deg.unwrap(), e.phi_exit_deg.unwrap());
    println!(
        "area {:.5} (exact {area:.5}, {:.3} %), entry {a:.4}° (exact {entry:.4}°), exit {b:.4}° (exact {exit:.4}°), ap {:.4}",
        e.area_mm2,
        100.0 * rel(e.area_mm2, area),
        e.ap_mm
    );
    assert!(
        rel(e.area_mm2, area) < rel_tol,
        "area {} vs {area}",
        e.area_mm2
    );
    let d = |x: f64, y: f64| ((x - y + 180.0).rem_euclid(360.0) - 180.0).abs();
    assert!(d(a, entry) < deg_tol, "entry {a} vs {entry}");
    assert!(d(b, exit) < deg_tol, "exit {b} vs {exit}");
}
