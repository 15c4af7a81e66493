//! Every volume of excess belongs to a region: material left away from the stock's surface (a
//! hole not drilled, a cavity of the design the stock fills) is counted in the region its
//! pieces reach, or makes one; stock faces no move cut where the design is wider than the
//! stock are no gouge; and a surface that meets the design within rounding is no defect even
//! with tolerances of 0.

use swarf_geom::math::Vec3;
use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::Machine;
use swarf_stock::{simulate, SimOptions, TriDexel};
use swarf_tool::{Cutter, ToolSet};
use swarf_verify::{box_mesh, verify, DefectKind, MeshDesign, VerifyOptions};

fn v(x: f64, y: f64, z: f64) -> Vec3 {
    Vec3::new(x, y, z)
}

/// The closed, outward mesh of the cells `filled(i, j, k)` of the grid with planes `xs`, `ys`,
/// `zs` (the faces between a filled and an empty cell, two triangles each), welded.
fn cells_mesh(
    xs: &[f64],
    ys: &[f64],
    zs: &[f64],
    filled: impl Fn(usize, usize, usize) -> bool,
) -> swarf_io::TriMesh {
    let n = [xs.len() - 1, ys.len() - 1, zs.len() - 1];
    let planes = [xs, ys, zs];
    let full = |c: [i64; 3]| {
        (0..3).all(|a| c[a] >= 0 && (c[a] as usize) < n[a])
            && filled(c[0] as usize, c[1] as usize, c[2] as usize)
    };
    let mut m = swarf_io::TriMesh::new();
    for i in 0..n[0] {
        for j in 0..n[1] {
            for k in 0..n[2] {
                let c = [i as i64, j as i64, k as i64];
                if !full(c) {
                    continue;
                }
                for ax in 0..3 {
                    for side in [0usize, 1] {
                        let mut nb = c;
                        nb[ax] += if side == 1 { 1 } else { -1 };
                        if full(nb) {
                            continue;
                        }
                        let (u, w) = ((ax + 1) % 3, (ax + 2) % 3);
                        let at = planes[ax][c[ax] as usize + side];
                        let (u0, u1) = (planes[u][c[u] as usize], planes[u][c[u] as usize + 1]);
                        let (w0, w1) = (planes[w][c[w] as usize], planes[w][c[w] as usize + 1]);
                        let p = |a: f64, b: f64| {
                            let mut q = Vec3::ZERO;
                            q[ax] = at;
                            q[u] = a;
                            q[w] = b;
                            q
                        };
                        // Counter-clockwise about +ax (u, w right-handed with it); reversed on
                        // the low side.
                        let mut quad = [p(u0, w0), p(u1, w0), p(u1, w1), p(u0, w1)];
                        if side == 0 {
                            quad.reverse();
                        }
                        let base = m.vertices.len() as u32;
                        m.vertices.extend_from_slice(&quad);
                        m.triangles.push([base, base + 1, base + 2]);
                        m.triangles.push([base, base + 2, base + 3]);
                    }
                }
            }
        }
    }
    m.weld(0.0);
    m
}

#[test]
fn a_hole_left_undrilled_is_all_in_its_region() {
    // The 40 × 20 × 10 part with a 4 × 4 hole along X, 20 mm deep from its x = 0 face (y 8–12,
    // z −6…−2); the stock is the part's box, untouched.
    let d = MeshDesign::new(&cells_mesh(
        &[0.0, 20.0, 40.0],
        &[0.0, 8.0, 12.0, 20.0],
        &[-10.0, -6.0, -2.0, 0.0],
        |i, j, k| (i, j, k) != (0, 1, 1),
    ))
    .unwrap();
    assert!(
        (d.volume() - (8000.0 - 320.0)).abs() < 1e-9,
        "{}",
        d.volume()
    );
    let stock = TriDexel::from_box(v(0.0, 0.0, -10.0), v(40.0, 20.0, 0.0), 0.5).unwrap();
    let r = verify(&stock, &d, None, &VerifyOptions::default()).unwrap();
    // The hole's material: 40 × 8 Z rays (0.25 mm² each) crossing it for 4 mm.
    let total = r.excess_volume_mm3.unwrap();
    assert!((total - 320.0).abs() < 1e-9, "{total}");
    assert_eq!(r.regions.len(), 1, "{:#?}", r.regions);
    let h = &r.regions[0];
    assert_eq!(h.kind, DefectKind::Excess);
    // All of it, not the 32 mm³ next to the hole's mouth (where the only ray ends are).
    assert!((h.volume_mm3 - 320.0).abs() < 1e-9, "{}", h.volume_mm3);
    // The mouth's X-ray ends (8 × 8 of them) at most 1.75 mm from the hole's walls (the rays
    // nearest its axis, 0.25 mm off it).
    assert_eq!(h.ends, 64);
    assert!((h.depth_mm - 1.75).abs() < 1e-12, "{}", h.depth_mm);
}

#[test]
fn a_cavity_of_the_design_the_stock_fills_is_a_region() {
    // The 20 × 20 × 9 part with a closed 10 × 10 × 5 cavity inside (x, y 5–15, z −7…−2): the
    // outer box outward, the cavity's box inward.
    let mut m = box_mesh(v(0.0, 0.0, -10.0), v(20.0, 20.0, -1.0));
    let mut cavity = box_mesh(v(5.0, 5.0, -7.0), v(15.0, 15.0, -2.0));
    cavity.flip();
    m.merge(&cavity);
    let d = MeshDesign::new(&m).unwrap();
    assert!((d.volume() - 3100.0).abs() < 1e-9, "{}", d.volume());
    let stock = TriDexel::from_box(v(0.0, 0.0, -10.0), v(20.0, 20.0, -1.0), 0.5).unwrap();
    let r = verify(&stock, &d, None, &VerifyOptions::default()).unwrap();
    assert!((r.excess_volume_mm3.unwrap() - 500.0).abs() < 1e-9);
    // No ray end lies off the design, yet the cavity's material is a region.
    assert_eq!(r.excess_ends, 0);
    assert_eq!(r.regions.len(), 1, "{:#?}", r.regions);
    let c = &r.regions[0];
    assert_eq!(c.kind, DefectKind::Excess);
    assert!((c.volume_mm3 - 500.0).abs() < 1e-9, "{}", c.volume_mm3);
    assert_eq!((c.ends, c.area_mm2, c.deepest_move), (0, 0.0, None));
    // Its thickest: the middle of a Z piece (z −4.5), 2.5 mm from the cavity's floor and top
    // and at least 4.75 mm from its sides (the rays nearest the middle, 0.25 mm off it).
    assert!((c.depth_mm - 2.5).abs() < 1e-12, "{}", c.depth_mm);
    assert!((c.deepest.z + 4.5).abs() < 1e-12, "{}", c.deepest);
    assert!((r.max_excess_mm - 2.5).abs() < 1e-12);
    // Its box: the rays crossing it (x, y 5.25…14.75), the cavity's height (where the rays
    // cross the cavity's faces, computed to rounding).
    for (got, want) in [
        (c.bbox_min, v(5.25, 5.25, -7.0)),
        (c.bbox_max, v(14.75, 14.75, -2.0)),
    ] {
        assert!((got - want).abs().max_element() < 1e-12, "{got} vs {want}");
    }
}

#[test]
fn material_nowhere_thicker_than_the_tolerance_is_no_region() {
    // The stock 0.005 mm above the design's top: excess volume, but no region (the tolerance
    // is 0.01 mm), as a cavity that thin makes none.
    let d = MeshDesign::new(&box_mesh(v(0.0, 0.0, -10.0), v(20.0, 20.0, -1.0))).unwrap();
    let stock = TriDexel::from_box(v(0.0, 0.0, -10.0), v(20.0, 20.0, -0.995), 0.5).unwrap();
    let r = verify(&stock, &d, None, &VerifyOptions::default()).unwrap();
    assert!(r.regions.is_empty(), "{:#?}", r.regions);
    let total = r.excess_volume_mm3.unwrap();
    assert!((total - 400.0 * 0.005).abs() < 1e-9, "{total}");
}

#[test]
fn stock_faces_no_move_cut_beyond_a_wider_design_are_no_gouge() {
    // The design (x −5…25) is wider than the stock (x 0…20); facing its top at z = −1 leaves
    // the stock's x = 0 and x = 20 faces as built, inside the design: the stock never held
    // what lies beyond them, the program could not cut it.
    let d = MeshDesign::new(&box_mesh(v(-5.0, 0.0, -10.0), v(25.0, 20.0, -1.0))).unwrap();
    let mut stock = TriDexel::from_box(v(0.0, 0.0, -10.0), v(20.0, 20.0, 0.0), 0.5).unwrap();
    stock.track_provenance();
    let text = "G21 G90\nG0 Z5\nG0 X-6 Y0\nG1 Z-1 F500\nG1 X26\nG1 Y5\nG1 X-6\nG1 Y10\n\
                G1 X26\nG1 Y15\nG1 X-6\nG1 Y20\nG1 X26\nG0 Z5\n";
    let program = read_program_str(
        text,
        "face.ngc",
        Machine::three_axis(),
        &ReadOptions::default(),
    )
    .unwrap();
    let tools = ToolSet::single(Cutter::flat(10.0).unwrap());
    simulate(&program, &tools, &mut stock, &SimOptions::default()).unwrap();
    let r = verify(&stock, &d, Some(&program), &VerifyOptions::default()).unwrap();
    assert!(r.regions.is_empty(), "{:#?}", r.regions);
    assert_eq!(r.gouge_ends, 0);
    // The X rays' ends on those two faces: 40 rays across Y by the 18 along Z below the
    // faced top, two ends each, none on a face of the design.
    assert_eq!(r.ends_unmatched, 40 * 18 * 2);
    assert!(r.gouge_volume_mm3.unwrap() < 1e-9);
    assert!(r.design_beyond_stock_box);
}

#[test]
fn a_surface_on_the_design_within_rounding_is_no_defect_with_tolerances_of_zero() {
    // The stock's top at 0.3, the design's at 0.1 + 0.2 = 0.30000000000000004: the stock's
    // top lies 5.6e-17 mm inside the design — rounding, not a gouge.
    let top = 0.1 + 0.2;
    assert!(top > 0.3);
    let d = MeshDesign::new(&box_mesh(Vec3::ZERO, v(10.0, 10.0, top))).unwrap();
    let stock = TriDexel::from_box(Vec3::ZERO, v(10.0, 10.0, 0.3), 0.5).unwrap();
    let zero = VerifyOptions::default()
        .with_gouge_tolerance(0.0)
        .with_excess_tolerance(0.0);
    let r = verify(&stock, &d, None, &zero).unwrap();
    assert!(
        r.max_gouge_mm > 0.0 && r.max_gouge_mm < 1e-15,
        "{}",
        r.max_gouge_mm
    );
    assert!(r.regions.is_empty(), "{:#?}", r.regions);
    assert_eq!((r.gouge_ends, r.excess_ends), (0, 0));
    // A real step of a micrometre still is one, at any tolerance down to 0.
    let stock = TriDexel::from_box(Vec3::ZERO, v(10.0, 10.0, top - 1e-6), 0.5).unwrap();
    let r = verify(&stock, &d, None, &zero).unwrap();
    assert_eq!(r.gouges().count(), 1, "{:#?}", r.regions);
}
