//! What the engagement's cuts hit besides cutting reaches the caller, as the simulation reports
//! it: a rapid through the material, a shank in the material.

mod common;

use std::f64::consts::PI;

use common::*;
use swarf_engage::{EngageOptions, Engager};
use swarf_tool::{Cutter, ToolSet};

/// A rapid at Z−4 from x = −8 to x = 20 across the block's edge at x = 0 (a 10 mm flat end
/// mill at y = 10), then a feed on to x = 35: the rapid removes the slot from x = 0 to 20 and
/// the half disc ahead of it, 4·(10·20 + π·5²/2) = 957.08 mm³, the feed 4·10·15 = 600 mm³
/// (its front half disc replaces the rapid's). Before, the engager cut the rapid and said
/// nothing: `removed_volume_mm3` 1558 against 600 over the locations.
#[test]
fn a_rapid_through_the_material_is_reported_with_its_line_and_volume() {
    let text = "G21 G90 G94\nS8000 M3\nG0 X-8 Y10 Z5\nG0 Z-4\nG0 X20\nG1 X35 F1000\nG0 Z5\nM30\n";
    let p = program(text, "rapidthru.ngc");
    let mut stock = block([0.0, 0.0, -10.0], [40.0, 20.0, 0.0], 0.1);
    let tools = ToolSet::single(Cutter::from_spec("flat:d=10").unwrap());
    let mut engager = Engager::new(&p, &tools, &mut stock, EngageOptions::default()).unwrap();
    let removed_at_locations: f64 = engager.by_ref().map(|e| e.unwrap().removed_mm3).sum();
    let rapid = 4.0 * (10.0 * 20.0 + PI * 25.0 / 2.0);
    let c = engager.rapid_collisions();
    assert_eq!(c.len(), 1, "{c:?}");
    assert_eq!((c[0].move_index, c[0].line), (2, 5));
    assert_eq!(c[0].file, "rapidthru.ngc");
    println!(
        "rapid: {:.2} mm³ (exact {rapid:.2}); feed: {removed_at_locations:.2} mm³ (exact 600)",
        c[0].volume_mm3
    );
    assert!(rel(c[0].volume_mm3, rapid) < 0.005, "{}", c[0].volume_mm3);
    assert!(rel(removed_at_locations, 600.0) < 0.005);
    let total = engager.stats().removed_volume_mm3;
    assert!((total - removed_at_locations - c[0].volume_mm3).abs() < 1e-6 * total);
    assert!(engager.holder_collisions().is_empty());
}

/// A 10 mm end mill with 3 mm of flutes and a 10 mm shank feeding 4 mm deep: the shank's
/// 1 mm above the flutes is in the material along the whole feed, reported once for the move
/// (its pieces summed): the slot from x = 0 to 20 and the half disc ahead, 1 mm deep,
/// 1·(10·20 + π·5²/2) = 239.27 mm³. A feed is no rapid collision.
#[test]
fn a_shank_in_the_material_is_reported_once_for_its_move() {
    let text = "G21 G90 G94\nS8000 M3\nG0 X-8 Y10 Z5\nG0 Z-4\nG1 X20 F500\nG0 Z5\nM30\n";
    let p = program(text, "shank.ngc");
    let mut stock = block([0.0, 0.0, -10.0], [40.0, 20.0, 0.0], 0.1);
    let cutter = Cutter::from_spec("flat:d=10,flute-length=3,shank=10").unwrap();
    let tools = ToolSet::single(cutter);
    let mut engager = Engager::new(&p, &tools, &mut stock, EngageOptions::default()).unwrap();
    let n = engager.by_ref().map(Result::unwrap).count();
    assert!(n > 20);
    assert!(engager.rapid_collisions().is_empty());
    let c = engager.holder_collisions();
    assert_eq!(c.len(), 1, "{c:?}");
    assert_eq!((c[0].move_index, c[0].line), (2, 5));
    let want = 10.0 * 20.0 + PI * 25.0 / 2.0;
    println!("shank: {:.2} mm³ (exact {want:.2})", c[0].volume_mm3);
    assert!(rel(c[0].volume_mm3, want) < 0.01, "{}", c[0].volume_mm3);
}

/// After a rotary cut, the engagement judges a far rapid skim 5 µm deep as the simulation
/// does: a collision (the rotary cut's sliver allowance holds near it only). Before, a running
/// maximum of the multi-axis error bounds dropped every shallow removal for the rest of the
/// program, and the simulation's rule differed from it.
#[test]
fn after_a_rotary_cut_a_far_skim_is_a_collision_as_simulate_says() {
    let text = "G21 G90 G94\nS8000 M3\nG0 X-10 Y0 Z30 A0\nG0 X0 Z12\nG1 Z9 F200\n\
        G1 X20 A360 F500\nG0 Z30\nG0 X120 Y5\nG0 Z9.995\nG0 X140\nG0 Z30\nM30\n";
    let p = swarf_path::load::read_program_str(
        text,
        "far.ngc",
        swarf_path::Machine::from_name("4axis-a").unwrap(),
        &swarf_path::load::ReadOptions {
            gcode: swarf_path::gcode::GcodeOptions::default().with_home([-10.0, 0.0, 30.0]),
            ..Default::default()
        },
    )
    .unwrap();
    let tools = ToolSet::single(Cutter::from_spec("flat:d=6").unwrap());
    let opts = EngageOptions {
        chordal_tolerance_mm: 0.01,
        step_mm: 5.0,
        ..EngageOptions::default()
    };
    let mut stock = block([0.0, -10.0, -10.0], [150.0, 10.0, 10.0], 0.5);
    let mut engager = Engager::new(&p, &tools, &mut stock, opts).unwrap();
    engager.by_ref().for_each(|e| drop(e.unwrap()));
    let lines: Vec<u32> = engager.rapid_collisions().iter().map(|c| c.line).collect();
    let sim = {
        let mut stock = block([0.0, -10.0, -10.0], [150.0, 10.0, 10.0], 0.5);
        let o = swarf_stock::SimOptions {
            chordal_tolerance: 0.01,
        };
        swarf_stock::simulate(&p, &tools, &mut stock, &o).unwrap()
    };
    let sim_lines: Vec<u32> = sim.rapid_collisions.iter().map(|c| c.line).collect();
    assert_eq!(lines, [9, 10], "{:?}", engager.rapid_collisions());
    assert_eq!(lines, sim_lines);
}
