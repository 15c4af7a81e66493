//! A design mesh of several bodies is their union, as for the stock: bodies that overlap or
//! nest measure from the union's boundary (not from faces buried inside it) and enclose the
//! union's volume; a flipped triangle is turned outwards, as the stock's reader repairs it.

use swarf_geom::math::Vec3;
use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::Machine;
use swarf_stock::{simulate, SimOptions, TriDexel};
use swarf_tool::{Cutter, ToolSet};
use swarf_verify::{box_mesh, verify, DefectKind, Design, MeshDesign, VerifyOptions};

fn v(x: f64, y: f64, z: f64) -> Vec3 {
    Vec3::new(x, y, z)
}

/// The reviewer's stock (the box 20 × 20 × 10, top at 0, h = 0.5) faced to z = −5 with a
/// 10 mm flat end mill, passes every 5 mm across the whole top.
fn faced_to_minus_5() -> TriDexel {
    let mut stock = TriDexel::from_box(v(0.0, 0.0, -10.0), v(20.0, 20.0, 0.0), 0.5).unwrap();
    stock.track_provenance();
    let text = "G21 G90\nG0 Z5\nG0 X-6 Y0\nG1 Z-5 F500\nG1 X26\nG1 Y5\nG1 X-6\nG1 Y10\n\
                G1 X26\nG1 Y15\nG1 X-6\nG1 Y20\nG1 X26\nG0 Z5\n";
    let program = read_program_str(
        text,
        "face5.ngc",
        Machine::three_axis(),
        &ReadOptions::default(),
    )
    .unwrap();
    let tools = ToolSet::single(Cutter::flat(10.0).unwrap());
    simulate(&program, &tools, &mut stock, &SimOptions::default()).unwrap();
    stock
}

/// Facing 4 mm below the design's top (z = −1) over the whole 20 × 20 part: one gouge, 4 mm
/// deep on the floor's middle (its ends there are 4 mm from the top and more from every other
/// face), over the footprint of the 40 × 40 Z rays (0.25 mm² each: 400 mm²), 4 × 400 mm³.
fn assert_one_gouge_of_the_facing(design: &MeshDesign) {
    let stock = faced_to_minus_5();
    let v = verify(&stock, design, None, &VerifyOptions::default()).unwrap();
    assert_eq!(v.regions.len(), 1, "{:#?}", v.regions);
    let g = &v.regions[0];
    assert_eq!(g.kind, DefectKind::Gouge);
    assert!((g.depth_mm - 4.0).abs() < 1e-12, "{}", g.depth_mm);
    assert!((g.area_mm2 - 400.0).abs() < 1e-9, "{}", g.area_mm2);
    assert!((g.volume_mm3 - 1600.0).abs() < 1e-9, "{}", g.volume_mm3);
    assert!((v.max_gouge_mm - 4.0).abs() < 1e-12);
    assert!(v.max_excess_mm < 1e-12, "{}", v.max_excess_mm);
    assert!((v.gouge_volume_mm3.unwrap() - 1600.0).abs() < 1e-9);
    assert!(v.excess_volume_mm3.unwrap() < 1e-9);
}

#[test]
fn overlapping_bodies_measure_from_their_union() {
    // Boxes x 0–12 and 8–20 (y 0–20, z −10…−1): the 20 × 20 × 9 part, tops flush.
    let mut m = box_mesh(v(0.0, 0.0, -10.0), v(12.0, 20.0, -1.0));
    m.merge(&box_mesh(v(8.0, 0.0, -10.0), v(20.0, 20.0, -1.0)));
    let d = MeshDesign::new(&m).unwrap();
    assert!((d.volume() - 3600.0).abs() < 1e-9, "{}", d.volume());
    // Between the bodies' buried faces (x = 8 and 12), 4 mm under the top: 4 mm inside the
    // union (it measured 2 mm, to a buried face).
    let p = d.project(v(10.0, 10.0, -5.0)).unwrap();
    assert!((p.distance + 4.0).abs() < 1e-12, "{p:?}");
    // Outside, above the flush tops: the distance to the top.
    let p = d.project(v(10.0, 10.0, 1.0)).unwrap();
    assert!((p.distance - 2.0).abs() < 1e-12, "{p:?}");
    assert!(d.describe().contains("union"), "{}", d.describe());
    assert!(d.repairs().is_some());
    assert_one_gouge_of_the_facing(&d);
}

#[test]
fn a_body_nested_inside_another_is_no_surface() {
    // The part with a 10 × 10 × 5 box inside it (a second body of the export).
    let mut m = box_mesh(v(0.0, 0.0, -10.0), v(20.0, 20.0, -1.0));
    m.merge(&box_mesh(v(5.0, 5.0, -8.0), v(15.0, 15.0, -3.0)));
    let d = MeshDesign::new(&m).unwrap();
    // The union's volume, not the bodies' sum (4100).
    assert!((d.volume() - 3600.0).abs() < 1e-9, "{}", d.volume());
    // Inside the nested box, 2 mm from its faces: 4 mm inside the part.
    let p = d.project(v(10.0, 10.0, -5.0)).unwrap();
    assert!((p.distance + 4.0).abs() < 1e-12, "{p:?}");
    assert_one_gouge_of_the_facing(&d);
    // Either orientation of the whole mesh.
    let mut inverted = m.clone();
    inverted.flip();
    let d = MeshDesign::new(&inverted).unwrap();
    assert!((d.volume() - 3600.0).abs() < 1e-9, "{}", d.volume());
    assert_one_gouge_of_the_facing(&d);
}

#[test]
fn a_body_crossing_another_is_cut_where_it_crosses() {
    // A 4 × 4 post through the part's top, from z = −6 to +3, not flush with anything: the
    // union is the part and the post's 3 mm above it.
    let mut m = box_mesh(v(0.0, 0.0, -10.0), v(20.0, 20.0, -1.0));
    m.merge(&box_mesh(v(8.0, 8.0, -6.0), v(12.0, 12.0, 3.0)));
    let d = MeshDesign::new(&m).unwrap();
    assert!(
        (d.volume() - (3600.0 + 16.0 * 4.0)).abs() < 1e-9,
        "{}",
        d.volume()
    );
    // Under the post, in the part: 3.5 mm above the part's bottom (it measured 0.5 mm to the
    // post's buried bottom at −6, and called it outside).
    let p = d.project(v(10.0, 10.0, -6.5)).unwrap();
    assert!((p.distance + 3.5).abs() < 1e-12, "{p:?}");
    // Beside the post above the top: 1 mm from the top, 1 mm from the post's side.
    let p = d.project(v(7.0, 10.0, 0.0)).unwrap();
    assert!((p.distance - 1.0).abs() < 1e-12, "{p:?}");
    // Just inside the post above the top: inside, 0.5 mm from its side.
    let p = d.project(v(8.5, 10.0, 1.5)).unwrap();
    assert!((p.distance + 0.5).abs() < 1e-12, "{p:?}");
}

#[test]
fn a_design_with_one_flipped_triangle_is_read_as_the_stock_reads_it() {
    // The part with its first triangle turned inside out: its three edges disagree with their
    // neighbours (refused before, while the stock read the same file).
    let clean = box_mesh(v(0.0, 0.0, -10.0), v(20.0, 20.0, -1.0));
    let mut m = clean.clone();
    m.triangles[0].swap(1, 2);
    assert_eq!(m.edge_report().misoriented, 3);
    let d = MeshDesign::new(&m).unwrap_or_else(|e| panic!("{e}"));
    let c = MeshDesign::new(&clean).unwrap();
    assert!((d.volume() - 3600.0).abs() < 1e-9, "{}", d.volume());
    let said = d.repairs().unwrap();
    assert!(
        said.contains("1 turned outwards") && said.contains("triangle 0"),
        "{said}"
    );
    // Every distance as the clean part's, around the flipped triangle's face and elsewhere.
    let [a, b, cc] = m.corners(0);
    let centre = (a + b + cc) / 3.0;
    let n = clean.triangle_normal(0);
    let mut points = vec![centre + n, centre - n, centre + 0.25 * n, centre - 0.25 * n];
    for i in 0..9 {
        for j in 0..9 {
            for k in 0..5 {
                points.push(v(
                    -2.0 + 3.0 * i as f64,
                    -2.0 + 3.0 * j as f64,
                    -12.0 + 3.0 * k as f64,
                ));
            }
        }
    }
    for p in points {
        let (got, want) = (d.project(p).unwrap(), c.project(p).unwrap());
        assert!(
            (got.distance - want.distance).abs() < 1e-12,
            "{p}: {got:?} vs {want:?}"
        );
    }
    // And verification reads it as the clean part: facing 4 mm too deep.
    assert_one_gouge_of_the_facing(&d);
}
