//! A CAMotics project shaped like the heart example CAMotics ships (written here: imperial
//! tools, metric bounds), and the example itself from the third-party data where present.

use swarf_tool::table::parse_camotics;
use swarf_tool::{CutterKind, LengthUnit, ToolTable};

/// A project as CAMotics writes one: a 0.1" ball nose and a 1/16" flat end mill, an 80 × 80 ×
/// 12.7 mm workpiece.
const PROJECT: &str = r#"{
  "units": "metric",
  "resolution-mode": "high",
  "resolution": 0.253321,
  "tools": {
    "1": {
      "units": "imperial",
      "shape": "ballnose",
      "length": 0.625,
      "diameter": 0.1,
      "description": ""
    },
    "2": {
      "units": "imperial",
      "shape": "cylindrical",
      "length": 1,
      "diameter": 0.0625,
      "description": ""
    }
  },
  "workpiece": {
    "automatic": false,
    "margin": 5,
    "bounds": {
      "min": [-40, -40, -12.7],
      "max": [40, 40, 0]
    }
  },
  "files": ["heart.ngc", "cutout.ngc"]
}
"#;

/// [`PROJECT`] written to a file of the calling test's own (tests run in parallel).
fn path() -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "swarf-tool-camotics-{}-{:?}",
        std::process::id(),
        std::thread::current().id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("heart.camotics");
    std::fs::write(&p, PROJECT).unwrap();
    p
}

fn check_heart(t: &ToolTable) {
    assert_eq!(t.tools.len(), 2);
    let ball = &t.tools[&1].cutter;
    assert_eq!(ball.kind(), CutterKind::Ball);
    assert!((ball.apt_params().d - 2.54).abs() < 1e-12);
    assert!((ball.flute_length() - 0.625 * 25.4).abs() < 1e-12);
    let flat = &t.tools[&2].cutter;
    assert_eq!(flat.kind(), CutterKind::Flat);
    assert!((flat.apt_params().d - 1.5875).abs() < 1e-12);
    let w = t.workpiece.as_ref().unwrap();
    assert_eq!(w.min.to_array(), [-40.0, -40.0, -12.7]);
    assert_eq!(w.max.to_array(), [40.0, 40.0, 0.0]);
}

#[test]
fn the_shipped_example_reads() {
    let Some(p) = swarf_testdata::path("gcode/camotics_heart.camotics") else {
        return;
    };
    check_heart(&ToolTable::read(&p, LengthUnit::Mm).unwrap());
}

#[test]
fn reads_tools_and_workpiece() {
    let t = ToolTable::read(&path(), LengthUnit::Mm).unwrap();
    check_heart(&t);
}

#[test]
fn automatic_workpiece_has_no_bounds_and_bad_json_has_a_position() {
    let text = PROJECT.replace("\"automatic\": false", "\"automatic\": true");
    assert!(parse_camotics(&text, "heart").unwrap().workpiece.is_none());
    let broken = PROJECT.replace("\"length\": 1,", "\"length\": one,");
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
