//! The CAMotics example project shipped with the test data: imperial tools, metric bounds.

use swarf_tool::table::parse_camotics;
use swarf_tool::{CutterKind, LengthUnit, ToolTable};

fn path() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/data/gcode/camotics_heart.camotics")
}

#[test]
fn reads_tools_and_workpiece() {
    let t = ToolTable::read(&path(), LengthUnit::Mm).unwrap();
    assert_eq!(t.tools.len(), 2);
    let ball = &t.tools[&1].cutter;
    assert_eq!(ball.kind(), CutterKind::Ball);
    assert!((ball.apt_params().d - 2.54).abs() < 1e-12);
    assert!((ball.flute_length() - 0.625 * 25.4).abs() < 1e-12);
    let flat = &t.tools[&2].cutter;
    assert_eq!(flat.kind(), CutterKind::Flat);
    assert!((flat.apt_params().d - 1.5875).abs() < 1e-12);
    let w = t.workpiece.unwrap();
    assert_eq!(w.min.to_array(), [-40.0, -40.0, -12.7]);
    assert_eq!(w.max.to_array(), [40.0, 40.0, 0.0]);
}

#[test]
fn automatic_workpiece_has_no_bounds_and_bad_json_has_a_position() {
    let text = std::fs::read_to_string(path())
        .unwrap()
        .replace("\"automatic\": false", "\"automatic\": true");
    assert!(parse_camotics(&text, "heart").unwrap().workpiece.is_none());
    let broken = std::fs::read_to_string(path())
        .unwrap()
        .replace("\"length\": 1,", "\"length\": one,");
    match parse_camotics(&broken, "heart.camotics") {
        Err(swarf_tool::TableError::Parse {
            file, line, column, ..
        }) => {
            assert_eq!(file, "heart.camotics");
            assert_eq!(line, 16); // `"length": one,` in the second tool
            assert!(column > 10, "{column}");
        }
        other => panic!("{other:?}"),
    }
    let missing = ToolTable::read(
        std::path::Path::new("no/such/file.camotics"),
        LengthUnit::Mm,
    )
    .unwrap_err();
    assert!(
        missing
            .to_string()
            .starts_with("no/such/file.camotics: cannot read"),
        "{missing}"
    );
}
