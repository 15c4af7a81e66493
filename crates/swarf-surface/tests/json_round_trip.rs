//! swarf JSON: the contract format, round trips, units and errors with positions.

mod common;

use common::*;
use swarf_geom::math::Vec3;
use swarf_surface::io::{json, ReadError};
use swarf_surface::{
    CompoundSurface, EntityRef, ParametricSurface, Patch, ReadNote, Surface, Tolerances,
};

const TOL: Tolerances = Tolerances::DEFAULT;

const FLOOR: &str = r#"{"units": "mm", "patches": [{"name": "floor", "degree_u": 1, "degree_v": 1,
  "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
  "control_points": [[[0, 0, 0, 1], [0, 10, 0, 1]], [[10, 0, 0, 1], [10, 10, 0, 1]]]}]}"#;

#[test]
fn contract_example_reads_as_documented() {
    let s = json::parse(FLOOR).unwrap();
    assert_eq!(s.patches.len(), 1);
    let p = &s.patches[0];
    assert_eq!(p.name.as_deref(), Some("floor"));
    assert_eq!(p.source.entity, EntityRef::Json { index: 0 });
    // control_points[i][j] along u then v: u runs along x, v along y, S_u × S_v = +z.
    let g = p.local(0.25, 0.75, &TOL);
    assert!((g.point() - Vec3::new(2.5, 7.5, 0.0)).length() < 1e-12);
    assert_eq!(g.normal.vector(), Some(Vec3::Z));
    assert!(s.notes.is_empty());
}

#[test]
fn weights_do_not_multiply_coordinates() {
    // A quarter circle arc in u (weights 1, √2/2, 1), written with plain coordinates.
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let text = format!(
        r#"{{"units": "in", "patches": [{{"degree_u": 2, "degree_v": 1, "knots_u": [0,0,0,1,1,1], "knots_v": [0,0,1,1],
        "control_points": [[[1,0,0,1],[1,0,1,1]], [[1,1,0,{w}],[1,1,1,{w}]], [[0,1,0,1],[0,1,1,1]]]}}]}}"#
    );
    let s = json::parse(&text).unwrap();
    assert!(matches!(&s.notes[0], ReadNote::UnitsConverted { factor, .. } if *factor == 25.4));
    for k in 0..=8 {
        let p = s.patches[0].surface.point(k as f64 / 8.0, 0.5);
        assert!((p.x.hypot(p.y) - 25.4).abs() < 1e-12, "{p:?}");
    }
    assert!(s.patches[0].name.is_none());
}

#[test]
fn round_trip_keeps_every_number_and_the_cutter_side() {
    let mut s = CompoundSurface::new(vec![
        Patch {
            name: Some("wall".into()),
            ..Patch::new(Surface::Nurbs(quarter_cylinder(3.0, 5.0)))
        },
        Patch::new(Surface::Nurbs(torus_quarter(10.0, 2.0))),
        Patch::new(Surface::Nurbs(bilinear_plane())),
    ]);
    s.patches[1].flipped = true;
    let text = json::to_string(&s).unwrap();
    let back = json::parse(&text).unwrap();
    assert_eq!(back.patches.len(), 3);
    assert_eq!(
        back.patches[0].surface, s.patches[0].surface,
        "exact round trip"
    );
    assert_eq!(back.patches[0].name.as_deref(), Some("wall"));
    assert_eq!(back.patches[2].surface, s.patches[2].surface);
    // The flipped patch comes back unflipped with u reversed: same points, same cutter side.
    assert!(!back.patches[1].flipped);
    for k in 0..=10 {
        let (u, v) = (k as f64 / 10.0, 0.3);
        let a = s.patches[1].local(u, v, &TOL);
        let b = back.patches[1].local(1.0 - u, v, &TOL);
        assert!((a.point() - b.point()).length() < 1e-12);
        assert!((a.normal.vector().unwrap() - b.normal.vector().unwrap()).length() < 1e-12);
        let (ca, cb) = (a.curvature.unwrap(), b.curvature.unwrap());
        assert!((ca.k1 - cb.k1).abs() < 1e-12 && (ca.k2 - cb.k2).abs() < 1e-12);
    }
    // Analytic patches have no JSON form.
    let sphere =
        swarf_surface::io::step::parse(&swarf_testdata::fixtures::sphere_step(5.0)).unwrap();
    assert!(json::to_string(&sphere)
        .unwrap_err()
        .to_string()
        .contains("is a sphere"));
}

#[test]
fn errors_name_the_position_what_was_found_and_what_was_expected() {
    let (l, c, m) = json_error("{\"units\": \"cm\", \"patches\": []}");
    assert_eq!((l, c), (1, 14), "the end of the offending value");
    assert!(
        m.contains("unknown variant `cm`, expected one of `mm`, `in`, `inch`"),
        "{m}"
    );
    // A point with three numbers.
    let bad = FLOOR.replace("[10, 10, 0, 1]", "[10, 10, 0]");
    let (l, _, m) = json_error(&bad);
    assert_eq!(l, 3);
    assert!(m.contains("expected an array of length 4"), "{m}");
    // A knot vector too short: validated inside the patch, reported at its end.
    let bad = FLOOR.replace("\"knots_v\": [0, 0, 1, 1]", "\"knots_v\": [0, 1, 1]");
    let (l, c, m) = json_error(&bad);
    assert_eq!((l, c), (3, 86), "just past the patch's closing brace: {m}");
    assert!(
        m.contains("patch 0 \"floor\": 3 knots in v; expected 4"),
        "{m}"
    );
    // A typo in a key.
    let (_, _, m) = json_error(&FLOOR.replace("degree_v", "degre_v"));
    assert!(m.contains("unknown field `degre_v`"), "{m}");
    // Negative weight.
    let (_, _, m) = json_error(&FLOOR.replace("[10, 10, 0, 1]", "[10, 10, 0, -1]"));
    assert!(
        m.contains("control point [1][1]: weight is not a positive finite number"),
        "{m}"
    );
    // A weight so small the derivatives end in 0/0 (found by fuzzing), and a wild coordinate.
    let (_, _, m) = json_error(&FLOOR.replace("[10, 10, 0, 1]", "[10, 10, 0, 1.5e-310]"));
    assert!(m.contains("weight outside [1e-12, 1e12]"), "{m}");
    let (_, _, m) = json_error(&FLOOR.replace("[10, 10, 0, 1]", "[1e300, 10, 0, 1]"));
    assert!(m.contains("coordinate beyond 1e9 mm"), "{m}");
    // Not JSON at all.
    let (l, c, _) = json_error("\n  units: mm");
    assert_eq!((l, c), (2, 3));
    assert!(matches!(
        json::parse(r#"{"patches": []}"#),
        Err(ReadError::Empty { .. })
    ));
    // Missing units: mm assumed, and said.
    let s = json::parse(&FLOOR.replace("\"units\": \"mm\", ", "")).unwrap();
    assert_eq!(s.notes, vec![ReadNote::UnitsAssumed]);
}
