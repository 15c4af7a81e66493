//! Analytic cases: a program that gouges a known depth at a known place is reported there
//! with that depth and line; an untouched stock is all excess, stock − part; a program that
//! exactly follows the design reports nothing; facing at any height above or below the design
//! reports exactly that step.

use proptest::prelude::*;
use swarf_geom::math::Vec3;
use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::{Machine, Program};
use swarf_stock::{simulate, SimOptions, TriDexel};
use swarf_tool::{Cutter, ToolSet};
use swarf_verify::{box_mesh, verify, DefectKind, MeshDesign, VerifyOptions};

fn gcode(text: &str) -> Program {
    read_program_str(
        text,
        "part.ngc",
        Machine::three_axis(),
        &ReadOptions::default(),
    )
    .unwrap()
}

/// The part's corner: away from the origin, where every program starts (with the tool's tip).
const O: f64 = 20.0;

/// Faces the top of the 40 × 40 block from (O, O) at height `z` with a 10 mm flat end mill:
/// passes along X every 8 mm from y = O − 3 to O + 45, from x = O − 10 to O + 50.
fn facing(z: f64) -> String {
    let mut s = format!(
        "G21 G90\nG0 Z20\nG0 X{} Y{}\nG1 Z{z:.4} F500\n",
        O - 10.0,
        O - 3.0
    );
    let mut y = O - 3.0;
    let mut left = true;
    while y <= O + 45.0 {
        s += &format!("G1 X{} Y{y}\n", if left { O + 50.0 } else { O - 10.0 });
        y += 8.0;
        if y <= O + 45.0 {
            s += &format!("G1 Y{y}\n");
        }
        left = !left;
    }
    s + "G0 Z20\n"
}

/// A 40 × 40 × 12 stock cut by `program` (h = 0.25) with tracked provenance.
fn machined(program: &Program) -> TriDexel {
    machined_with(program, 12.0, 10.0)
}

/// A 40 × 40 stock `top` mm high cut by `program` with a flat end mill of diameter `d` (h =
/// 0.25), provenance tracked.
fn machined_with(program: &Program, top: f64, d: f64) -> TriDexel {
    let mut stock = TriDexel::from_box(
        Vec3::new(O, O, 0.0),
        Vec3::new(O + 40.0, O + 40.0, top),
        0.25,
    )
    .unwrap();
    stock.track_provenance();
    let tools = ToolSet::single(Cutter::flat(d).unwrap());
    simulate(program, &tools, &mut stock, &SimOptions::default()).unwrap();
    stock
}

/// The design: the 40 × 40 × 10 block.
fn design() -> MeshDesign {
    MeshDesign::new(&box_mesh(
        Vec3::new(O, O, 0.0),
        Vec3::new(O + 40.0, O + 40.0, 10.0),
    ))
    .unwrap()
}

#[test]
fn a_known_gouge_is_found_with_its_depth_place_and_line() {
    // Facing exactly at the design's top, then a slot 0.3 mm too deep from x = 10 to 30 at
    // y = 20 (from the part's corner; the line after the plunge).
    let text = facing(10.0) + "G0 X30 Y40\nG1 Z9.7 F200\nG1 X50\nG0 Z20\n";
    let slot_line = text.lines().position(|l| l == "G1 X50").unwrap() as u32 + 1;
    let program = gcode(&text);
    let stock = machined(&program);
    let v = verify(&stock, &design(), Some(&program), &VerifyOptions::default()).unwrap();
    let gouges: Vec<_> = v.gouges().collect();
    assert_eq!(gouges.len(), 1, "{:#?}", v.regions);
    let g = gouges[0];
    // A flat floor: the ray ends on it lie exactly 0.3 mm inside the part.
    assert!((g.depth_mm - 0.3).abs() < 1e-6, "{}", g.depth_mm);
    assert!((v.max_gouge_mm - 0.3).abs() < 1e-6);
    // The deepest point is on the slot's floor: within the stadium of radius 5 about the
    // segment (10, 20)–(30, 20), at z = 9.7.
    let p = g.deepest;
    let dx = (p.x - p.x.clamp(O + 10.0, O + 30.0)).abs();
    assert!(
        dx.hypot(p.y - O - 20.0) <= 5.0 && (p.z - 9.7).abs() < 1e-9,
        "{p}"
    );
    // The lines that cut it: the plunge (its floor, as deep) and the slot, nothing else.
    let m = &program.moves[g.deepest_move.unwrap()];
    assert!([slot_line - 1, slot_line].contains(&m.line), "{}", m.line);
    let lines: Vec<u32> = g.moves.iter().map(|m| m.line).collect();
    assert!(
        lines.iter().all(|l| [slot_line - 1, slot_line].contains(l)),
        "{lines:?}"
    );
    let slot = g.moves.iter().find(|m| m.line == slot_line).unwrap();
    assert!((slot.depth_mm - 0.3).abs() < 1e-6 && slot.file == "part.ngc");
    // Volume: the stadium's area (20 × 10 + π·5²) times 0.3, within the grid's resolution
    // (the stadium's boundary passes between rays: ±perimeter·h/2·0.3 ≈ 2.4 mm³ at most).
    let exact = (200.0 + std::f64::consts::PI * 25.0) * 0.3;
    assert!(
        (g.volume_mm3 - exact).abs() < 2.4,
        "{} vs {exact}",
        g.volume_mm3
    );
    assert!((v.gouge_volume_mm3.unwrap() - exact).abs() < 2.4);
    // Area: the footprint on the design's face, the stadium (the 0.3 mm walls project onto
    // the face's edge: nothing), within the grid's resolution.
    assert!(
        (g.area_mm2 - exact / 0.3).abs() < 0.02 * exact / 0.3,
        "{}",
        g.area_mm2
    );
    // Facing exactly at the top leaves nothing beyond the tolerance.
    assert_eq!(v.excesses().count(), 0, "{:#?}", v.regions);
}

#[test]
fn a_gouge_reaching_the_design_edge_counts_up_to_it() {
    // Facing at the top, then a slot 0.5 mm too deep right across the part, y = 15..25 from
    // its corner: its footprint is 40 × 10 mm², although within 0.5 mm of the two end faces
    // the floor's nearest point of the design is on them (390 mm² when that decided); the
    // walls, under the top face, add nothing.
    let text = facing(10.0)
        + &format!(
            "G0 X{} Y{}\nG1 Z9.5 F200\nG1 X{}\nG0 Z20\n",
            O - 10.0,
            O + 20.0,
            O + 50.0
        );
    let program = gcode(&text);
    let stock = machined(&program);
    let v = verify(&stock, &design(), Some(&program), &VerifyOptions::default()).unwrap();
    let gouges: Vec<_> = v.gouges().collect();
    assert_eq!(gouges.len(), 1, "{:#?}", v.regions);
    let g = gouges[0];
    assert!((g.depth_mm - 0.5).abs() < 1e-6, "{}", g.depth_mm);
    assert!((g.area_mm2 - 400.0).abs() < 1e-6, "{}", g.area_mm2);
    assert!((g.volume_mm3 - 200.0).abs() < 1e-6, "{}", g.volume_mm3);
}

#[test]
fn a_narrow_gouge_beside_the_edge_counts_its_floor_not_its_walls() {
    // A 1 mm slot 2 mm too deep right across the part at y = 38..39, a millimetre from its
    // side face: the footprint is the slot's floor, 1 × 40 mm². A wall's ray, followed across
    // the slot's air and on through the millimetre of material beyond, would meet the side
    // face within the depth and count the wall (120 mm² in all) — the ray stops at the
    // slot's far wall.
    let text = format!(
        "G21 G90\nG0 Z20\nG0 X{} Y{}\nG1 Z8 F200\nG1 X{}\nG0 Z20\n",
        O - 10.0,
        O + 38.5,
        O + 50.0
    );
    let program = gcode(&text);
    let stock = machined_with(&program, 10.0, 1.0);
    let v = verify(&stock, &design(), Some(&program), &VerifyOptions::default()).unwrap();
    let gouges: Vec<_> = v.gouges().collect();
    assert_eq!(gouges.len(), 1, "{:#?}", v.regions);
    let g = gouges[0];
    // The depth is the distance to the design: from the floor's ray at y = 38.125 the side
    // face is nearer (1.875 mm) than the top (2 mm).
    assert!((g.depth_mm - 1.875).abs() < 1e-6, "{}", g.depth_mm);
    assert!((g.area_mm2 - 40.0).abs() < 1e-6, "{}", g.area_mm2);
}

#[test]
fn a_program_that_follows_the_design_reports_nothing() {
    let program = gcode(&facing(10.0));
    let stock = machined(&program);
    let v = verify(&stock, &design(), Some(&program), &VerifyOptions::default()).unwrap();
    assert!(v.regions.is_empty(), "{:#?}", v.regions);
    assert!(v.max_gouge_mm < 1e-9 && v.max_excess_mm < 1e-9, "{v:?}");
    assert!(v.excess_volume_mm3.unwrap() < 1e-6 && v.gouge_volume_mm3.unwrap() < 1e-6);
    assert!(v.ends_checked > 50_000);
}

/// A design exported with its fixture (a plate under the part, wider than the stock): the
/// plate is never stock, so a program that follows the part reports nothing — no gouge volume
/// either (it counted the plate's 48,000 mm³ under the stock's footprint) — and the plate's
/// volume there is reported apart, with the design's box flagged as reaching beyond the stock.
#[test]
fn a_fixture_exported_with_the_design_is_not_a_gouge() {
    let program = gcode(&facing(10.0));
    let stock = machined(&program);
    let mut mesh = box_mesh(Vec3::new(O, O, 0.0), Vec3::new(O + 40.0, O + 40.0, 10.0));
    mesh.merge(&box_mesh(
        Vec3::new(O - 20.0, O - 20.0, -30.0),
        Vec3::new(O + 60.0, O + 60.0, -0.5),
    ));
    let with_plate = MeshDesign::new(&mesh).unwrap();
    let v = verify(
        &stock,
        &with_plate,
        Some(&program),
        &VerifyOptions::default(),
    )
    .unwrap();
    assert!(v.regions.is_empty(), "{:#?}", v.regions);
    assert!(v.gouge_volume_mm3.unwrap() < 1e-6, "{v:?}");
    assert!(v.excess_volume_mm3.unwrap() < 1e-6, "{v:?}");
    let outside = v.design_outside_stock_mm3.unwrap();
    assert!((outside - 40.0 * 40.0 * 29.5).abs() < 1e-6, "{outside}");
    assert!(v.design_beyond_stock_box);
    // The part alone lies within the stock's box.
    let v = verify(&stock, &design(), Some(&program), &VerifyOptions::default()).unwrap();
    assert!(!v.design_beyond_stock_box && v.design_outside_stock_mm3.unwrap() < 1e-9);
}

#[test]
fn an_untouched_stock_is_all_excess_stock_minus_part() {
    // The design sits inset 5 mm on four sides and 5 mm below the top of the stock.
    let stock = TriDexel::from_box(Vec3::ZERO, Vec3::new(40.0, 30.0, 20.0), 0.5).unwrap();
    let design = MeshDesign::new(&box_mesh(
        Vec3::new(5.0, 5.0, 0.0),
        Vec3::new(35.0, 25.0, 15.0),
    ))
    .unwrap();
    let v = verify(&stock, &design, None, &VerifyOptions::default()).unwrap();
    let exact = 40.0 * 30.0 * 20.0 - 30.0 * 20.0 * 15.0;
    let got = v.excess_volume_mm3.unwrap();
    assert!((got - exact).abs() < 1e-6, "{got} vs {exact}");
    assert_eq!(v.gouges().count(), 0);
    assert_eq!(v.regions.len(), 1, "{:#?}", v.regions);
    let r = &v.regions[0];
    assert_eq!(r.kind, DefectKind::Excess);
    assert!((r.volume_mm3 - exact).abs() < 1e-6, "{}", r.volume_mm3);
    // The farthest ray end: near a top corner of the stock, √(4.75² + 4.75² + 5²) from the
    // design's corner at the coarsest.
    assert!(
        r.depth_mm > 8.3 && r.depth_mm < 75f64.sqrt(),
        "{}",
        r.depth_mm
    );
    assert!(r.deepest_move.is_none() && r.moves.is_empty());
}

#[test]
fn a_design_with_a_hole_in_its_mesh_is_refused() {
    let mut m = box_mesh(Vec3::ZERO, Vec3::ONE);
    m.triangles.pop();
    let e = MeshDesign::new(&m).unwrap_err().to_string();
    assert!(
        e.contains("not a closed mesh") && e.contains("3 edges"),
        "{e}"
    );
}

#[test]
fn a_design_beyond_the_machine_range_is_refused_naming_the_file() {
    // The range stock meshes are held to: a 2 km long design STL is an error naming it.
    let dir = swarf_testdata::scratch_dir("verify-range");
    std::fs::create_dir_all(&dir).unwrap();
    let far = dir.join("far.stl");
    let near = dir.join("near.stl");
    swarf_io::write_stl(&far, &box_mesh(Vec3::ZERO, Vec3::new(2e6, 20.0, 10.0))).unwrap();
    swarf_io::write_stl(&near, &box_mesh(Vec3::ZERO, Vec3::new(9e5, 20.0, 10.0))).unwrap();
    let e = MeshDesign::read_stl(&far).unwrap_err().to_string();
    assert!(
        e.contains(&far.display().to_string())
            && e.contains("reaches 2e6 mm")
            && e.contains("machine range of 1e6 mm"),
        "{e}"
    );
    assert!(MeshDesign::read_stl(&near).is_ok());
    std::fs::remove_dir_all(&dir).unwrap();
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 8, .. ProptestConfig::default() })]

    /// Facing at 10 + δ over the whole top: |δ| beyond the tolerance is one region of that
    /// depth and of volume |δ|·40·40; within it, nothing.
    #[test]
    fn facing_step_is_reported_exactly(delta in -0.8f64..0.8) {
        let program = gcode(&facing(10.0 + delta));
        let stock = machined(&program);
        let o = VerifyOptions::default();
        let v = verify(&stock, &design(), Some(&program), &o).unwrap();
        let depth = (delta * 1e4).round() / 1e4; // as printed in the program
        if depth.abs() <= o.gouge_tolerance {
            prop_assert!(v.regions.is_empty(), "{:#?}", v.regions);
        } else {
            prop_assert_eq!(v.regions.len(), 1);
            let r = &v.regions[0];
            let kind = if depth < 0.0 { DefectKind::Gouge } else { DefectKind::Excess };
            prop_assert_eq!(r.kind, kind);
            prop_assert!((r.depth_mm - depth.abs()).abs() < 1e-6, "{} vs {}", r.depth_mm, depth);
            let exact = depth.abs() * 1600.0;
            prop_assert!((r.volume_mm3 - exact).abs() < 1e-6 * 1600.0, "{} vs {exact}", r.volume_mm3);
            // The whole top face, up to its edges (a gouge's floor beside an edge is nearer
            // the side face than the top; its rays still meet the top).
            prop_assert!((r.area_mm2 - 1600.0).abs() < 1e-6, "{}", r.area_mm2);
            if kind == DefectKind::Gouge {
                prop_assert!(r.deepest_move.is_some());
            }
        }
    }
}

#[test]
fn surface_patches_meeting_at_an_edge_count_a_gouge_up_to_it() {
    // The design as two planar surface patches, the top z = 0 over [0, 40]² and the side
    // x = 0 (facing −X) below it; facing 0.5 mm too deep: the floor's ends within 0.5 mm of
    // the side have their nearest point on it, and their rays, followed up (sphere tracing),
    // meet the top: 40 × 40 mm² (1,580 when the nearest point decided).
    use swarf_geom::Frame;
    use swarf_surface::compound::{CompoundSurface, Patch};
    use swarf_surface::surface::{ParamBox, PlaneSurface, Surface};
    use swarf_verify::surface::SurfaceDesign;
    let top = PlaneSurface::new(Frame::at(Vec3::ZERO), ParamBox::new(0.0, 40.0, 0.0, 40.0));
    let side = PlaneSurface::new(
        Frame::from_axis_and_x(Vec3::ZERO, -Vec3::X, Vec3::Y),
        ParamBox::new(0.0, 40.0, 0.0, 20.0),
    );
    let surface = CompoundSurface {
        patches: vec![
            Patch::new(Surface::Plane(top)),
            Patch::new(Surface::Plane(side)),
        ],
        notes: Vec::new(),
    };
    let design = SurfaceDesign::new(&surface, 0.0).unwrap();
    let mut text = String::from("G21 G90\nG0 Z20\nG0 X-10 Y-3\nG1 Z-0.5 F500\n");
    let mut y = -3.0;
    let mut left = true;
    while y <= 45.0 {
        text += &format!("G1 X{} Y{y}\n", if left { 50 } else { -10 });
        y += 8.0;
        if y <= 45.0 {
            text += &format!("G1 Y{y}\n");
        }
        left = !left;
    }
    let program = gcode(&(text + "G0 Z20\n"));
    let mut stock =
        TriDexel::from_box(Vec3::new(0.0, 0.0, -20.0), Vec3::new(40.0, 40.0, 0.0), 0.25).unwrap();
    stock.track_provenance();
    let tools = ToolSet::single(Cutter::flat(10.0).unwrap());
    simulate(&program, &tools, &mut stock, &SimOptions::default()).unwrap();
    let v = verify(&stock, &design, Some(&program), &VerifyOptions::default()).unwrap();
    let gouges: Vec<_> = v.gouges().collect();
    assert_eq!(gouges.len(), 1, "{:#?}", v.regions);
    let g = gouges[0];
    assert!((g.depth_mm - 0.5).abs() < 2e-4, "{}", g.depth_mm);
    assert!((g.area_mm2 - 1600.0).abs() < 1e-6, "{}", g.area_mm2);
}
