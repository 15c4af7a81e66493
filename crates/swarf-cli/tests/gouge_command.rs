//! `swarf gouge`: a flat end mill run along a floor into a clamp (a closed STL box) and down
//! through the floor; the outputs, their field names and the figures the closed form gives;
//! bad input refused with a message that names it.
mod common;
use common::*;

use std::path::{Path, PathBuf};

const FLOOR: &str = r#"{"units": "mm", "patches": [{"name": "floor", "degree_u": 1,
  "degree_v": 1, "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
  "control_points": [[[-40, -40, 0, 1], [-40, 40, 0, 1]], [[40, -40, 0, 1], [40, 40, 0, 1]]]}]}"#;

/// The clamp: `[10, 20] × [−5, 5] × [0, 8]`.
const CLAMP: [[f64; 3]; 2] = [[10.0, -5.0, 0.0], [20.0, 5.0, 8.0]];

/// Line 3 runs the tool (R = 5) from x = −15 into the clamp, touching it at x = 5 (s = 2/3)
/// and ending 1 mm inside (x = 6). Line 5 plunges 0.5 mm into the floor far from the clamp.
const PROGRAM: &str = "G0 X-15 Y0 Z5\nG1 Z0 F300\nG1 X6\nG0 Z5\nG0 X-30 Y-30\nG1 Z-0.5\nG0 Z5\n";

fn scene(tag: &str, drop: usize) -> PathBuf {
    let dir = swarf_testdata::scratch_dir(&format!("gouge-{tag}"));
    std::fs::write(dir.join("floor.json"), FLOOR).unwrap();
    std::fs::write(dir.join("clamp.stl"), boxes_stl(&[CLAMP], drop)).unwrap();
    std::fs::write(dir.join("job.ngc"), PROGRAM).unwrap();
    dir
}

fn gouge(dir: &Path, extra: &[&str]) -> std::process::Output {
    let p = |f: &str| dir.join(f).to_str().unwrap().to_string();
    let (surface, program, check, out) = (p("floor.json"), p("job.ngc"), p("clamp.stl"), p("out"));
    let mut args = vec![
        "gouge",
        "--surface",
        &surface,
        "--program",
        &program,
        "--check",
        &check,
        "--out",
        &out,
    ];
    args.extend_from_slice(extra);
    swarf(&args)
}

/// The rows of a CSV as maps from header to field.
fn rows(path: &Path) -> Vec<std::collections::HashMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    lines
        .map(|l| {
            header
                .iter()
                .cloned()
                .zip(l.split(',').map(String::from))
                .collect()
        })
        .collect()
}

#[test]
fn clamp_interference_and_floor_gouge_are_found_located_and_measured() {
    let dir = scene("ok", 0);
    let o = gouge(&dir, &["--tool", "flat:d=10", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = json(&o);
    for key in [
        "points",
        "moves",
        "sub_moves",
        "violations",
        "gouging_moves",
        "interfering_moves",
        "gouging_points",
        "interfering_points",
        "max_gouge_mm",
        "max_interference_mm",
        "certified",
        "unresolved_searches",
        "nodes",
        "tolerance_mm",
        "accuracy_mm",
        "motion_tolerance_mm",
        "elapsed_s",
    ] {
        assert!(s.get(key).is_some(), "summary lacks {key}: {s}");
    }
    assert_eq!(s["moves"], 7);
    assert_eq!(s["points"], 8);
    assert_eq!(s["certified"], true);
    // The plunge: 0.5 mm into the floor; the clamp: 1 mm deep at the end of line 3 (each to
    // the certificate gap, 1e-4 mm or 0.1 % of the depth).
    assert!(
        (s["max_gouge_mm"].as_f64().unwrap() - 0.5).abs() <= 5e-4,
        "{s}"
    );
    assert!(
        (s["max_interference_mm"].as_f64().unwrap() - 1.0).abs() <= 1e-3,
        "{s}"
    );
    let v = rows(&dir.join("out/violations.csv"));
    let clamp: Vec<_> = v.iter().filter(|r| r["line"] == "3").collect();
    assert_eq!(clamp.len(), 1, "{v:?}");
    let r = clamp[0];
    assert_eq!(r["kind"], "interference");
    assert_eq!(r["part"], "cutting");
    assert!(r["surface"].starts_with("check:"));
    // Located to the resolution: 0.05 mm of 21 mm of travel.
    let s_start: f64 = r["s_start"].parse().unwrap();
    assert!(
        (s_start - 20.0 / 21.0).abs() <= 0.05 / 21.0 + 1e-6,
        "{s_start}"
    );
    let plunge: Vec<_> = v.iter().filter(|r| r["line"] == "6").collect();
    assert_eq!(plunge.len(), 1, "{v:?}");
    assert_eq!(plunge[0]["kind"], "gouge");
    assert_eq!(plunge[0]["surface"], "floor");
    // The retract from the plunge is a rapid starting inside the floor: interference.
    assert!(v
        .iter()
        .any(|r| r["line"] == "7" && r["kind"] == "interference" && r["rapid"] == "true"));
    let p = rows(&dir.join("out/points.csv"));
    assert_eq!(p.len(), 8);
    assert_eq!(p[3]["status"], "interference");
    assert_eq!(p[6]["status"], "gouge");
    assert_eq!(p[1]["status"], "clear");
    assert!(dir.join("out/summary.json").is_file());
}

#[test]
fn without_the_clamp_the_pass_is_clear() {
    let dir = scene("noclamp", 0);
    let p = |f: &str| dir.join(f).to_str().unwrap().to_string();
    let (surface, program, out) = (p("floor.json"), p("job.ngc"), p("out"));
    let o = swarf(&[
        "gouge",
        "--surface",
        &surface,
        "--program",
        &program,
        "--tool",
        "flat:d=10",
        "--out",
        &out,
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = json(&o);
    // Only the retract from the plunge interferes (a rapid leaving the floor).
    assert_eq!(s["interfering_moves"], 1, "{s}");
    let v = rows(&dir.join("out/violations.csv"));
    assert!(v.iter().all(|r| r["line"] != "3"), "{v:?}");
}

#[test]
fn bad_input_is_refused_naming_it() {
    let dir = scene("bad", 1);
    // An open check mesh.
    let o = gouge(&dir, &["--tool", "flat:d=10"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("clamp.stl"), "{}", stderr(&o));
    let dir = scene("bad2", 0);
    // No cutter for the program's tool.
    let o = gouge(&dir, &[]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("tool 0"), "{}", stderr(&o));
    // A tolerance that is not positive.
    let o = gouge(&dir, &["--tool", "flat:d=10", "--tolerance", "0"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("tolerance"), "{}", stderr(&o));
    assert!(!dir.join("out/violations.csv").exists());
    // A program that is not there.
    std::fs::remove_file(dir.join("job.ngc")).unwrap();
    let o = gouge(&dir, &["--tool", "flat:d=10"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("job.ngc"), "{}", stderr(&o));
}
