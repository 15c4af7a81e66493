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

/// An imperial project's workpiece bounds are mm all the same (CAMotics stores them in mm and
/// shows them in the display units): the heart's −12.7 stays half an inch, not 12.7 inches.
#[test]
fn imperial_project_bounds_are_mm() {
    let text = PROJECT.replace("\"units\": \"metric\"", "\"units\": \"imperial\"");
    let t = parse_camotics(&text, "heart.camotics").unwrap();
    check_heart(&t);
}

/// Shapes in any letter case; a spheroid, which swarf cannot model, leaves the project
/// loading, its tool left out with why (file, line, column, tool).
#[test]
fn shape_case_and_spheroid() {
    let text = PROJECT
        .replace("\"ballnose\"", "\"Ballnose\"")
        .replace("\"cylindrical\"", "\"CYLINDRICAL\"")
        .replace(
            "\"2\": {",
            "\"3\": {\"units\": \"metric\", \"shape\": \"spheroid\", \"length\": 10, \
             \"diameter\": 6},\n    \"2\": {",
        );
    let t = parse_camotics(&text, "heart.camotics").unwrap();
    check_heart(&t);
    assert!(!t.tools.contains_key(&3));
    assert_eq!(
        t.left_out[&3],
        "heart.camotics:13:5: tool 3 is a spheroid (an ellipsoid 6 mm wide, 10 mm long), a \
         shape swarf cannot model"
    );
    assert_eq!(t.left_out.len(), 1);
}

/// The project's `files` are not run: a warning names them and says what swarf runs.
#[test]
fn listed_files_are_warned_about() {
    let t = parse_camotics(PROJECT, "heart.camotics").unwrap();
    assert_eq!(
        t.warnings,
        vec![
            "heart.camotics: the project runs heart.ngc, cutout.ngc in turn; swarf simulates \
             only the program given to it (--program)"
                .to_string()
        ]
    );
    let none = PROJECT.replace(
        "\"files\": [\"heart.ngc\", \"cutout.ngc\"]",
        "\"files\": []",
    );
    assert!(parse_camotics(&none, "heart.camotics")
        .unwrap()
        .warnings
        .is_empty());
}
