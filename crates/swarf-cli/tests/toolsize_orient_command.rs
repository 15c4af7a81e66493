//! `swarf toolsize --axis4` / `--five-axis`: the orientation columns and the trough's answer
//! (a concave half-cylinder of radius 5 along Y, open towards +X: about Y the ball end mill
//! with its shank reaches its curvature radius at B = 90°).
mod common;
use common::*;

const TROUGH: &str = r#"{"units": "mm", "patches": [{"name": "trough", "degree_u": 2,
  "degree_v": 1, "knots_u": [0, 0, 0, 0.5, 0.5, 1, 1, 1], "knots_v": [0, 0, 1, 1],
  "control_points": [
    [[0, -20, -5, 1], [0, 20, -5, 1]],
    [[-5, -20, -5, 0.7071067811865476], [-5, 20, -5, 0.7071067811865476]],
    [[-5, -20, 0, 1], [-5, 20, 0, 1]],
    [[-5, -20, 5, 0.7071067811865476], [-5, 20, 5, 0.7071067811865476]],
    [[0, -20, 5, 1], [0, 20, 5, 1]]]}]}"#;

fn run(tag: &str, extra: &[&str]) -> (std::process::Output, String) {
    let dir = swarf_testdata::scratch_dir(&format!("orient-{tag}"));
    let surface = dir.join("trough.json");
    std::fs::write(&surface, TROUGH).unwrap();
    let mut args = vec![
        "toolsize",
        "--surface",
        surface.to_str().unwrap(),
        "--cutter",
        "ball-side",
        "--flip",
        "--grid",
        "3",
        "--out",
        dir.to_str().unwrap(),
        "--json",
    ];
    args.extend_from_slice(extra);
    let o = swarf(&args);
    let csv = std::fs::read_to_string(dir.join("toolsize.csv")).unwrap_or_default();
    (o, csv)
}

#[test]
fn axis4_y_writes_b_deg_and_reaches_the_curvature_radius() {
    let (o, csv) = run("a4", &["--axis4", "Y"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    assert!(
        (j["min_radius_mm"].as_f64().unwrap() - 5.0).abs() < 1e-6,
        "{j}"
    );
    let mut lines = csv.lines();
    assert!(lines
        .next()
        .unwrap()
        .ends_with(",radius_mm,limit_x,limit_y,limit_z,limit,b_deg,certified"));
    for row in lines {
        let b: f64 = row.rsplit(',').nth(1).unwrap().parse().unwrap();
        assert!((b - 90.0).abs() < 1e-3, "{row}");
    }
}

#[test]
fn five_axis_writes_lead_and_tilt_within_the_limits() {
    let (o, csv) = run("a5", &["--five-axis", "10,5"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let mut lines = csv.lines();
    assert!(lines
        .next()
        .unwrap()
        .ends_with(",limit,lead_deg,tilt_deg,certified"));
    for row in lines {
        let f: Vec<f64> = row
            .rsplit(',')
            .skip(1)
            .take(2)
            .map(|x| x.parse().unwrap())
            .collect();
        assert!(f[0].abs() <= 5.0 && f[1].abs() <= 10.0, "{row}");
    }
}

#[test]
fn bad_orientation_arguments_are_refused() {
    for extra in [
        &["--axis4", "Z"][..],
        &["--five-axis", "10"],
        &["--five-axis", "95,10"],
        &["--axis4", "Y", "--five-axis", "10,10"],
        &["--axis4", "Y", "--solver", "pso"],
    ] {
        let (o, _) = run("bad", extra);
        assert!(!o.status.success(), "{extra:?} accepted");
    }
}
