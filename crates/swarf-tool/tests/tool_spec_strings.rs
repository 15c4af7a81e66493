//! Tool spec strings: every kind, options, round trips, and errors with columns.

use swarf_tool::{Cutter, CutterKind, SpecError};

fn syntax(spec: &str) -> (usize, String, String) {
    match Cutter::from_spec(spec) {
        Err(SpecError::Syntax {
            column,
            found,
            expected,
        }) => (column, found, expected),
        other => panic!("{spec}: expected a syntax error, got {other:?}"),
    }
}

#[test]
fn every_kind_parses() {
    let cases = [
        ("flat:d=12", CutterKind::Flat, 6.0),
        ("ball:d=10", CutterKind::Ball, 5.0),
        ("bull:d=16,r=2", CutterKind::Bull, 8.0),
        (
            "taper-ball:d=6,taper=3",
            CutterKind::TaperBall,
            3.0 * 3f64.to_radians().cos(),
        ),
        ("taper-flat:d=10,taper=5", CutterKind::TaperFlat, 5.0),
        ("chamfer:d=10,angle=90", CutterKind::Chamfer, 5.0),
        ("drill:d=8,angle=118", CutterKind::Drill, 4.0),
        ("drill:d=8", CutterKind::Drill, 4.0),
        ("apt:10,2,3,2,0,0,30", CutterKind::Apt, 5.0),
        (" Bull : d = 16 , r = 2 ", CutterKind::Bull, 8.0),
    ];
    for (spec, kind, half_d) in cases {
        let c = Cutter::from_spec(spec).unwrap_or_else(|e| panic!("{spec}: {e}"));
        assert_eq!(c.kind(), kind, "{spec}");
        assert!((c.apt_params().d / 2.0 - half_d).abs() < 1e-12, "{spec}");
        // The spec of the built cutter rebuilds the same cutter.
        let again = Cutter::from_spec(&c.spec()).unwrap_or_else(|e| panic!("{}: {e}", c.spec()));
        assert_eq!(again.apt_params(), c.apt_params(), "{spec} -> {}", c.spec());
        assert_eq!(again.overall_length(), c.overall_length());
    }
    assert_eq!(
        Cutter::from_spec("drill:d=8")
            .unwrap()
            .apt_params()
            .alpha_deg,
        31.0
    );
}

#[test]
fn options_apply() {
    let c =
        Cutter::from_spec("flat:d=6,flutes=3,helix=45,flute-length=20,shank=8,length=70").unwrap();
    assert_eq!(c.flutes(), 3);
    assert_eq!(c.helix_deg(), 45.0);
    assert_eq!(c.flute_length(), 20.0);
    assert_eq!(c.apt_params().h, 20.0);
    assert_eq!(c.shank_diameter(), 8.0);
    assert_eq!(c.overall_length(), 70.0);
    assert!(c
        .shank_solid()
        .contains(swarf_geom::math::Vec3::new(3.9, 0.0, 50.0)));
    assert!(!c
        .shank_solid()
        .contains(swarf_geom::math::Vec3::new(3.9, 0.0, 71.0)));
    let a = Cutter::from_spec("apt:10,2,3,2,0,0,30,flutes=4").unwrap();
    assert_eq!(a.flutes(), 4);
}

#[test]
fn errors_point_at_the_column() {
    let (col, found, expected) = syntax("bull:d=16,q=2");
    assert_eq!(col, 11);
    assert_eq!(found, "unknown key \"q\"");
    assert!(expected.contains("d, r, flutes"), "{expected}");
    let (col, found, _) = syntax("flat:d=1x");
    assert_eq!((col, found.as_str()), (8, "\"1x\""));
    let (col, found, _) = syntax("flot:d=1");
    assert_eq!((col, found.as_str()), (1, "\"flot\""));
    let (col, _, expected) = syntax("bull:d=16");
    assert_eq!(col, 10);
    assert!(expected.contains("r=NUMBER"), "{expected}");
    let (col, _, expected) = syntax("apt:10,2,3");
    assert_eq!(col, 11);
    assert!(expected.contains("APT number 4 (f)"), "{expected}");
    let (col, found, _) = syntax("flat:d=1,d=2");
    assert_eq!((col, found.as_str()), (10, "\"d\" a second time"));
    let (col, _, _) = syntax("flat:d=1,flutes=2.5");
    assert_eq!(col, 17);
    let (col, _, expected) = syntax("flat");
    assert_eq!(col, 5);
    assert!(expected.contains("KIND:PARAMS"));
    let (col, _, _) = syntax("flat:d=1,,");
    assert_eq!(col, 10);
    let (col, found, _) = syntax("ball:d=NaN");
    assert_eq!((col, found.as_str()), (8, "\"NaN\""));
    // A value out of its range, at its column.
    let (col, found, expected) = syntax("flat:d=-10");
    assert_eq!((col, found.as_str()), (8, "-10"));
    assert_eq!(expected, "d (diameter) > 0 mm");
    let (col, _, expected) = syntax("bull:d=16,r=-1");
    assert_eq!(col, 13);
    assert!(expected.starts_with("r "), "{expected}");
    // Valid syntax, invalid cutter: the tool error comes through.
    match Cutter::from_spec("bull:d=10,r=6") {
        Err(SpecError::Tool(e)) => assert!(e.to_string().contains("corner radius r = 6")),
        other => panic!("{other:?}"),
    }
}

#[test]
fn arbitrary_input_never_panics() {
    for s in [
        "",
        ":",
        "::",
        "apt:",
        "apt:1,2,3,4,5,6,7,8",
        "é:d=1",
        "flat:é=1",
        "flat:d=é",
        "flat:d=1,",
        ",,,",
        "ball:d=1e400",
    ] {
        let _ = Cutter::from_spec(s);
    }
}

#[test]
fn a_derived_shank_out_of_range_says_where_it_came_from() {
    // A taper of 89.9° makes a cutting part 34 m wide at its top, the shank's default: the
    // error says the shank was derived (it read as if a shank had been given).
    let e = Cutter::from_spec("taper-flat:d=10,taper=89.9")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("the cutting part's diameter at its top") && e.contains("34387.4"),
        "{e}"
    );
    let e = Cutter::from_spec("flat:d=10,shank=600")
        .unwrap_err()
        .to_string();
    // (Given, it is told at its column.)
    assert!(
        e.contains("column 17: found 600, expected shank diameter") && !e.contains("at its top"),
        "{e}"
    );
}
