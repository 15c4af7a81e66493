//! Rapids into material, shank and holder collisions, 5-axis moves in the report (and the
//! tolerance they refuse), and the simple stock shapes.

mod common;

use common::{gcode, moves};
use swarf_geom::math::Vec3;
use swarf_stock::{simulate, MeshOptions, SimOptions, StockError, TriDexel};
use swarf_sweep::SweepError;
use swarf_tool::{Cutter, CutterOptions, Holder, HolderSegment, ToolSet};

#[test]
fn rapid_through_material_is_reported_and_cuts() {
    let mut s =
        TriDexel::from_box(Vec3::new(10.0, 0.0, 0.0), Vec3::new(40.0, 20.0, 10.0), 0.2).unwrap();
    let p = gcode("G21 G90\nG0 Z20\nG0 X5 Y10\nG0 Z5\nG0 X45\nG0 Z20\nM30\n");
    let tools = ToolSet::single(Cutter::flat(6.0).unwrap());
    let r = simulate(&p, &tools, &mut s, &SimOptions::default()).unwrap();
    assert_eq!(r.rapid_collisions.len(), 1, "{:?}", r.rapid_collisions);
    let c = &r.rapid_collisions[0];
    assert_eq!((c.move_index, c.line, c.file.as_str()), (3, 5, "test.ngc"));
    // The rapid still removed its slot: 30 × 6 × 5.
    assert!(
        (r.removed_volume_mm3 - 900.0).abs() < 0.01 * 900.0,
        "{}",
        r.removed_volume_mm3
    );
    assert!((c.volume_mm3 - r.removed_volume_mm3).abs() < 1e-9);
    assert!(r.holder_collisions.is_empty());
    assert_eq!(r.removed_per_move_mm3.len(), r.moves);
}

#[test]
fn shank_and_holder_collisions_are_reported() {
    // A straight plunge never buries the shank (the flutes clear the hole first), but a side
    // move 25 mm deep with an 18 mm cutting part pushes the shank into the wall above.
    let mut s =
        TriDexel::from_box(Vec3::new(10.0, 0.0, 0.0), Vec3::new(40.0, 20.0, 30.0), 0.25).unwrap();
    let p = gcode("G21 G90\nG0 Z40\nG0 X0 Y10\nG1 Z5 F100\nG1 X25\nG0 Z40\nM30\n");
    let tools = ToolSet::single(Cutter::flat(6.0).unwrap());
    let r = simulate(&p, &tools, &mut s, &SimOptions::default()).unwrap();
    assert_eq!(r.holder_collisions.len(), 1, "{:?}", r.holder_collisions);
    assert_eq!(r.holder_collisions[0].line, 5);
    assert!(r.rapid_collisions.is_empty());
    // Everything the tool occupied is gone (cutting part and shank have the same radius):
    // 15 mm of slot 6 wide and 25 high plus a half cylinder at the end.
    let exact = (15.0 * 6.0 + std::f64::consts::PI * 9.0 / 2.0) * 25.0;
    assert!(
        (r.removed_volume_mm3 - exact).abs() < 0.01 * exact,
        "{}",
        r.removed_volume_mm3
    );

    // A wide holder low on the tool hits the top of the block on a shallow slot.
    let holder = Holder {
        base_z_mm: 20.0,
        segments: vec![HolderSegment {
            length_mm: 30.0,
            bottom_diameter_mm: 30.0,
            top_diameter_mm: 40.0,
        }],
    };
    let c = Cutter::flat(6.0)
        .unwrap()
        .with_options(&CutterOptions {
            holder: Some(holder),
            overall_length: Some(20.0),
            ..CutterOptions::default()
        })
        .unwrap();
    // (The block is well clear of the origin, where the program starts: the holder is 40 mm
    // wide.)
    let mut s =
        TriDexel::from_box(Vec3::new(30.0, 0.0, 0.0), Vec3::new(60.0, 20.0, 30.0), 0.25).unwrap();
    // Holder bottom at tip + 20: a plunge to z = 5 brings it 5 mm into the 30 mm block.
    let p = gcode("G21 G90\nG0 Z60\nG0 X45 Y10\nG1 Z5 F100\nG0 Z60\nM30\n");
    let r = simulate(
        &p,
        &ToolSet::single(c.clone()),
        &mut s,
        &SimOptions::default(),
    )
    .unwrap();
    assert_eq!(r.holder_collisions.len(), 1, "{:?}", r.holder_collisions);
    assert_eq!(r.holder_collisions[0].line, 4);
}

#[test]
fn five_axis_move_is_cut_and_reported() {
    // A CL move whose axis tilts 5.7° while the tip crosses the block: cut in constant-axis
    // sub-moves, counted in the report, every bound within the tolerance. A zero tolerance
    // cannot be honoured and is refused naming the move's line.
    let mut p = moves(
        &[Vec3::new(0.0, 5.0, 8.0), Vec3::new(10.0, 5.0, 8.0)],
        Vec3::Z,
        false,
    );
    p.axis_source = swarf_path::AxisSource::Program;
    p.moves[0].axis_source = swarf_path::AxisSource::Program;
    p.moves[0].end.axis = Vec3::new(0.1, 0.0, 1.0).normalize();
    let tools = ToolSet::single(Cutter::ball(6.0).unwrap());
    let mut s = TriDexel::from_box(Vec3::ZERO, Vec3::new(10.0, 10.0, 10.0), 0.5).unwrap();
    let opts = SimOptions::default().with_chordal_tolerance(0.01);
    let r = simulate(&p, &tools, &mut s, &opts).unwrap();
    assert_eq!(r.five_axis_moves, 1);
    assert!(r.five_axis_sub_moves > 10, "{}", r.five_axis_sub_moves);
    assert!(r.five_axis_error_bound_mm > 0.0 && r.five_axis_error_bound_mm <= 0.01);
    assert!(r.removed_volume_mm3 > 0.0);

    let mut s = TriDexel::from_box(Vec3::ZERO, Vec3::new(10.0, 10.0, 10.0), 0.5).unwrap();
    let e = simulate(&p, &tools, &mut s, &opts.with_chordal_tolerance(0.0)).unwrap_err();
    assert!(
        matches!(
            e,
            StockError::Sweep(SweepError::Unsupported {
                index: 0,
                line: 1,
                ..
            })
        ),
        "{e}"
    );
    assert!(e.to_string().contains("line 1"), "{e}");
}

#[test]
fn three_plus_two_equals_rotated_three_axis() {
    // Rotate a block (as a closed mesh), the tool axis and the path together: the removed
    // volume must be the 3-axis slot's exact volume, (l·d + π·d²/4)·depth.
    use swarf_geom::math::Quat;
    let rot =
        Quat::from_rotation_x(30f64.to_radians()) * Quat::from_rotation_y(-20f64.to_radians());
    let (lo, hi) = (Vec3::ZERO, Vec3::new(40.0, 20.0, 10.0));
    let m = swarf_io::TriMesh::cuboid(lo, hi);
    let tris: Vec<[Vec3; 3]> = m
        .triangles
        .iter()
        .map(|t| t.map(|i| rot * m.vertices[i as usize]))
        .collect();
    let mut s = TriDexel::from_triangles(&tris, 0.1, MeshOptions::default()).unwrap();
    let v0 = s.volume();
    assert!((v0 - 8000.0).abs() < 0.003 * 8000.0, "{v0}");
    let tool = swarf_sweep::ToolShape::new(&Cutter::flat(6.0).unwrap());
    let (a, b) = (Vec3::new(8.03, 10.01, 7.0), Vec3::new(31.97, 10.01, 7.0));
    let cut = s.cut_linear(&tool, rot * a, rot * b, rot * Vec3::Z);
    assert_eq!(cut.non_cutting.removed_length, [0.0; 3]);
    let removed = v0 - s.volume();
    let exact = ((b.x - a.x) * 6.0 + std::f64::consts::PI * 9.0) * 3.0;
    println!("3+2 slot: removed {removed:.3}, exact {exact:.3}");
    assert!(
        (removed - exact).abs() < 0.003 * exact,
        "{removed} vs {exact}"
    );
}

#[test]
fn cylinder_and_mesh_stocks() {
    let s = TriDexel::from_cylinder(5.0, -3.0, 1.0, 4.0, 6.0, 0.05).unwrap();
    let exact = std::f64::consts::PI * 16.0 * 6.0;
    for v in s.volumes() {
        assert!((v - exact).abs() < 0.002 * exact, "{v} vs {exact}");
    }
    // A closed tetrahedron with vertices on round coordinates (rays meet its edges and
    // vertices exactly at their nominal positions; the nudge keeps parity right).
    let p = [
        Vec3::ZERO,
        Vec3::new(10.0, 0.0, 0.0),
        Vec3::new(0.0, 10.0, 0.0),
        Vec3::new(0.0, 0.0, 10.0),
    ];
    let tris = vec![
        [p[0], p[2], p[1]],
        [p[0], p[1], p[3]],
        [p[0], p[3], p[2]],
        [p[1], p[2], p[3]],
    ];
    let s = TriDexel::from_triangles(&tris, 0.1, MeshOptions::default()).unwrap();
    let exact = 1000.0 / 6.0;
    for v in s.volumes() {
        assert!((v - exact).abs() < 0.003 * exact, "{v} vs {exact}");
    }
    let st = s.stats();
    assert!(st.bytes_per_interval > 0.0 && st.intervals > 0 && st.rays == 3 * 100 * 100);
}

/// A rotary cut is cut within its error bound ε of the true sweep, and the retract after it
/// takes the slivers (≤ ε thick) it left: no collision. A rapid into the part after it still
/// is one.
#[test]
fn slivers_a_rotary_cut_leaves_are_no_collision() {
    let program = |tail: &str| {
        swarf_path::load::read_program_str(
            &format!(
                "G21 G90 G94\nG0 X-10 Y0 Z30 A0\nG0 X0 Z12\nG1 Z9 F200\nG1 X20 A360 F500\n\
                 G93 G1 X40 A720 F1\nG94 G0 Z30\n{tail}M30\n"
            ),
            "rot4.ngc",
            swarf_path::Machine::from_name("4axis-a").unwrap(),
            &swarf_path::load::ReadOptions {
                // Start clear of the block.
                gcode: swarf_path::gcode::GcodeOptions::default().with_home([-10.0, 0.0, 30.0]),
                ..Default::default()
            },
        )
        .unwrap()
    };
    let tools = ToolSet::single(Cutter::flat(6.0).unwrap());
    let block = || {
        TriDexel::from_box(
            Vec3::new(0.0, -10.0, -10.0),
            Vec3::new(60.0, 10.0, 10.0),
            0.5,
        )
        .unwrap()
    };
    let r = simulate(&program(""), &tools, &mut block(), &SimOptions::default()).unwrap();
    assert!(r.five_axis_error_bound_mm > 0.0);
    assert!(r.rapid_collisions.is_empty(), "{:?}", r.rapid_collisions);
    assert!(r.holder_collisions.is_empty(), "{:?}", r.holder_collisions);
    // The same retract, then a rapid plunge 5 mm into the block beside the turned part.
    let r = simulate(
        &program("G0 X50 Y5\nG0 Z5\n"),
        &tools,
        &mut block(),
        &SimOptions::default(),
    )
    .unwrap();
    let lines: Vec<u32> = r.rapid_collisions.iter().map(|c| c.line).collect();
    assert_eq!(lines, [9], "{:?}", r.rapid_collisions);
    // A rapid skimming 0.2 mm off the block's end (no X or Y ray in that depth at h = 0.5:
    // only the Z rays see it) is still a collision.
    let r = simulate(
        &program("G0 X55 Y0\nG0 Z9.8\nG0 X58\nG0 Z30\n"),
        &tools,
        &mut block(),
        &SimOptions::default(),
    )
    .unwrap();
    let lines: Vec<u32> = r.rapid_collisions.iter().map(|c| c.line).collect();
    assert_eq!(lines, [9, 10], "{:?}", r.rapid_collisions);
}

/// The sliver allowance of a rotary cut holds where that cut was, not over the whole part for
/// the rest of the program: a rapid skimming 5 µm deep far from it (shallower than √3·ε, which
/// near the rotary cut may be a sliver it left) is a collision. (It was dropped anywhere once
/// any multi-axis move had been cut.)
#[test]
fn the_sliver_allowance_holds_only_near_the_multi_axis_cuts() {
    let program = swarf_path::load::read_program_str(
        "G21 G90 G94\nG0 X-10 Y0 Z30 A0\nG0 X0 Z12\nG1 Z9 F200\nG1 X20 A360 F500\n\
         G0 Z30\nG0 X120 Y5\nG0 Z9.995\nG0 X140\nG0 Z30\nM30\n",
        "far.ngc",
        swarf_path::Machine::from_name("4axis-a").unwrap(),
        &swarf_path::load::ReadOptions {
            gcode: swarf_path::gcode::GcodeOptions::default().with_home([-10.0, 0.0, 30.0]),
            ..Default::default()
        },
    )
    .unwrap();
    let tools = ToolSet::single(Cutter::flat(6.0).unwrap());
    let mut block = TriDexel::from_box(
        Vec3::new(0.0, -10.0, -10.0),
        Vec3::new(150.0, 10.0, 10.0),
        0.5,
    )
    .unwrap();
    // A coarse tolerance: the rotary cut's slivers may be ~10 µm.
    let opts = SimOptions {
        chordal_tolerance: 0.01,
    };
    let r = simulate(&program, &tools, &mut block, &opts).unwrap();
    // The skim is within what a sliver near the rotary cut could be.
    assert!(3f64.sqrt() * r.five_axis_error_bound_mm > 0.005, "{r:?}");
    let lines: Vec<u32> = r.rapid_collisions.iter().map(|c| c.line).collect();
    assert_eq!(lines, [8, 9], "{:?}", r.rapid_collisions);
    // The plunge takes a disc 5 µm thick, the skim a strip 20 mm long beside it.
    let skim = r.rapid_collisions[1].volume_mm3;
    let exact = 0.005 * 6.0 * 20.0;
    assert!((skim - exact).abs() < 0.1 * exact, "{skim} vs {exact}");
}
