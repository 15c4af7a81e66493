//! The program check against answers known in closed form: a ball too large for a concave
//! trough, a flat end mill driven into a wall (where the gouge starts along the move), a shank
//! wider than the cutter beside a wall, a flat end mill tilting on a floor along a 5-axis CL
//! move, a rapid through the part, and a finishing pass that only touches (clear).

mod common;

use swarf_geom::math::Vec3;
use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::Machine;
use swarf_plan::gouge::{
    check_program, GougeOptions, GougeReport, GougeSurface, SurfaceRef, ToolPart, ViolationKind,
};
use swarf_surface::PreparedSurface;
use swarf_surface::{CompoundSurface, NurbsSurface, Patch, Surface};
use swarf_tool::{Cutter, ToolSet};

/// A planar bilinear patch with corners `o`, `o + du`, `o + dv`, `o + du + dv`; its normal is
/// `du × dv`.
fn plane(o: Vec3, du: Vec3, dv: Vec3) -> Patch {
    let pts = vec![vec![o, o + dv], vec![o + du, o + du + dv]];
    let k = vec![0.0, 0.0, 1.0, 1.0];
    Patch::new(Surface::Nurbs(
        NurbsSurface::new(1, 1, k.clone(), k, &pts, None).unwrap(),
    ))
}

fn surface(patches: Vec<Patch>) -> GougeSurface {
    GougeSurface::new(&PreparedSurface::new(&CompoundSurface::new(patches)))
}

fn run(s: &GougeSurface, program: &str, cutter: &Cutter) -> GougeReport {
    let file = if program.contains("GOTO/") {
        "t.apt"
    } else {
        "t.ngc"
    };
    let p = read_program_str(
        program,
        file,
        Machine::three_axis(),
        &ReadOptions::default(),
    )
    .unwrap();
    check_program(
        s,
        &p,
        &ToolSet::single(cutter.clone()),
        &GougeOptions::DEFAULT,
    )
    .unwrap()
}

/// The certificate gap the reports promise at a depth.
#[allow(non_snake_case)]
fn GAP(depth: f64) -> f64 {
    GougeOptions::DEFAULT.gap(depth)
}

fn spec(s: &str) -> Cutter {
    swarf_tool::spec::parse(s).unwrap()
}

#[test]
fn ball_larger_than_a_concave_trough_gouges_its_flanks() {
    let (rc, alpha) = (10.0_f64, 60f64.to_radians());
    let s = surface(vec![common::trough(rc, alpha, 40.0)]);
    let rb = 12.0;
    // Ball centre at height rb over the bottom: the flank edges at φ = ±α are deepest.
    let expected = rb - (rc * rc + (rb - rc).powi(2) + 2.0 * rc * (rb - rc) * alpha.cos()).sqrt();
    // The program starts at the origin, on the trough's end: both moves gouge all along.
    let r = run(&s, "G1 X5 Y0 Z0 F100\nG1 X35\n", &spec("ball:d=24"));
    assert_eq!(r.violations.len(), 2, "{:#?}", r.violations);
    let v = &r.violations[1];
    assert_eq!(v.move_index, 1);
    assert_eq!(v.kind, ViolationKind::Gouge);
    assert_eq!(v.part, ToolPart::Cutting);
    assert_eq!(v.surface, SurfaceRef::Patch(0));
    assert!(v.s_start <= 1e-12 && v.s_end >= 1.0 - 1e-12, "{v:?}");
    assert!(
        (v.depth - expected).abs() <= GAP(expected),
        "{} vs {expected}",
        v.depth
    );
    assert!(v.depth_upper >= expected - 1e-9 && v.depth_upper <= expected + 2.0 * GAP(expected));
    // The program points gouge too.
    assert_eq!(r.points.len(), 3);
    assert_eq!(r.points_with(ViolationKind::Gouge), 3);
    // A ball that fits the trough (radius below 10) only touches it.
    let r = run(&s, "G1 X5 Y0 Z0 F100\nG1 X35\n", &spec("ball:d=19.9"));
    assert!(r.violations.is_empty(), "{:#?}", r.violations);
    assert_eq!(r.unresolved, 0);
}

#[test]
fn flat_end_mill_driven_into_a_wall_gouges_from_where_it_meets_it() {
    // Floor z = 0 (normal +z) and a wall at x = 50 facing −x, 20 mm high.
    let s = surface(vec![
        plane(Vec3::ZERO, Vec3::X * 50.0, Vec3::Y * 50.0),
        plane(Vec3::new(50.0, 0.0, 0.0), Vec3::Z * 20.0, Vec3::Y * 50.0),
    ]);
    // R = 5 from x = 40 to 48: the side reaches the wall at x = 45, 3 mm past it at the end.
    let r = run(&s, "G1 X40 Y25 Z0 F100\nG1 X48\n", &spec("flat:d=10"));
    let gouges: Vec<_> = r.violations.iter().filter(|v| v.move_index == 1).collect();
    assert_eq!(gouges.len(), 1, "{:#?}", r.violations);
    let v = gouges[0];
    assert_eq!(v.kind, ViolationKind::Gouge);
    assert_eq!(v.surface, SurfaceRef::Patch(1));
    let res = GougeOptions::DEFAULT.resolution / 8.0;
    assert!((v.s_start - 0.625).abs() <= res + 1e-9, "{v:?}");
    assert!((v.s_end - 1.0).abs() <= 1e-12);
    assert!((v.depth - 3.0).abs() <= GAP(3.0), "{v:?}");
    assert!((v.tip.x - 48.0).abs() <= 0.05, "{v:?}");
    assert!((v.point.x - 50.0).abs() < 1e-9);
    let end = r.points.last().unwrap();
    assert!((end.depth - 3.0).abs() <= GAP(3.0));
    assert_eq!(end.status, Some(ViolationKind::Gouge));
}

#[test]
fn wide_shank_beside_a_wall_interferes_by_its_excess() {
    let s = surface(vec![plane(
        Vec3::new(50.0, 0.0, 0.0),
        Vec3::Z * 40.0,
        Vec3::Y * 50.0,
    )]);
    // Ball R = 5 at 5.5 mm from the wall; the 12 mm shank above 15 mm is 0.5 mm into it.
    let r = run(
        &s,
        "G0 X44.5 Y25 Z30\nG1 Z0 F100\n",
        &spec("ball:d=10,shank=12,flute-length=15"),
    );
    let v: Vec<_> = r.violations.iter().filter(|v| v.move_index == 1).collect();
    assert_eq!(v.len(), 1, "{:#?}", r.violations);
    assert_eq!(v[0].kind, ViolationKind::Interference);
    assert_eq!(v[0].part, ToolPart::Shank);
    assert!((v[0].depth - 0.5).abs() <= GAP(0.5), "{:?}", v[0]);
    // The cutting part never reaches the wall.
    assert!(r.violations.iter().all(|v| v.part == ToolPart::Shank));
}

#[test]
fn flat_end_mill_tilting_on_a_floor_dips_in_by_the_closed_form() {
    let s = surface(vec![plane(
        Vec3::new(-50.0, -50.0, 0.0),
        Vec3::X * 100.0,
        Vec3::Y * 100.0,
    )]);
    let th = 10f64.to_radians();
    let cl = format!("GOTO/0,0,0,0,0,1\nGOTO/0,0,0,{},0,{}\n", th.sin(), th.cos());
    let r = run(&s, &cl, &spec("flat:d=10"));
    // Floor points inside: depth min(s·sin θ, R − s·cos θ), largest R·sin θ/(sin θ + cos θ).
    let expected = 5.0 * th.sin() / (th.sin() + th.cos());
    let deepest = r.violations.iter().map(|v| v.depth).fold(0.0, f64::max);
    let bound = GougeOptions::DEFAULT.motion_tolerance;
    assert!(
        (deepest - expected).abs() <= bound + GAP(expected),
        "{deepest} vs {expected}"
    );
    assert!(r.violations.iter().all(|v| v.kind == ViolationKind::Gouge));
    let end = r.points.last().unwrap();
    assert!((end.depth - expected).abs() <= GAP(expected), "{end:?}");
    assert!(r.sub_moves > 2);
}

#[test]
fn a_rapid_through_the_part_is_interference() {
    let s = surface(vec![plane(Vec3::ZERO, Vec3::X * 50.0, Vec3::Y * 50.0)]);
    let r = run(&s, "G0 X10 Y10 Z5\nG0 Z-1\n", &spec("flat:d=6"));
    assert!(!r.violations.is_empty());
    assert!(r
        .violations
        .iter()
        .all(|v| v.kind == ViolationKind::Interference && v.rapid));
    let v = &r.violations[0];
    assert!((v.depth - 1.0).abs() <= GAP(1.0), "{v:?}");
}

#[test]
fn a_tangent_finishing_pass_is_proven_clear() {
    let s = surface(vec![common::trough(10.0, 60f64.to_radians(), 40.0)]);
    // A 6 mm ball along the trough at several offsets, tangent to it everywhere: tip on the
    // offset surface (ball centre at distance 7 from the axis, 3 mm inside the cylinder).
    let mut prog = String::from("G1 X5 Y0 Z0 F100\n");
    for k in -4..=4 {
        let phi = k as f64 * 10f64.to_radians();
        let (y, zc) = (7.0 * phi.sin(), 10.0 - 7.0 * phi.cos());
        let x = if k % 2 == 0 { 35.0 } else { 5.0 };
        prog += &format!("G1 X{x:.12} Y{y:.12} Z{:.12}\n", zc - 3.0);
    }
    let r = run(&s, &prog, &spec("ball:d=6"));
    assert!(r.violations.is_empty(), "{:#?}", r.violations);
    assert_eq!(r.unresolved, 0);
    assert!(r.points.iter().all(|p| p.depth_upper <= 0.001));
}
