//! `swarf toolsize --check FILE.stl`: a closed box standing on a floor, its wall 10 mm from the
//! middle of the floor, limits the flat end mill there to a radius of 10 (interference), in
//! 3-axis; in 4- and 5-axis, walls on all four sides (a tilted tool could lean away from one)
//! still limit it; an open mesh is refused.
mod common;
use common::*;

use std::path::{Path, PathBuf};

const FLOOR: &str = r#"{"units": "mm", "patches": [{"name": "floor", "degree_u": 1,
  "degree_v": 1, "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
  "control_points": [[[-20, -20, 0, 1], [-20, 20, 0, 1]], [[20, -20, 0, 1], [20, 20, 0, 1]]]}]}"#;

/// Agreement with the analytic answer, mm.
const TOL: f64 = 1e-6;

/// The box of the 3-axis case: `[10, 15] × [−5, 5] × [0, 8]`.
const BOX: [[f64; 3]; 2] = [[10.0, -5.0, 0.0], [15.0, 5.0, 8.0]];

/// Four walls around the middle of the floor, 10 mm from it, with gaps at the corners: every
/// half-plane through the middle meets one of them.
const WALLS: [[[f64; 3]; 2]; 4] = [
    [[10.0, -9.0, 0.0], [15.0, 9.0, 8.0]],
    [[-15.0, -9.0, 0.0], [-10.0, 9.0, 8.0]],
    [[-9.0, 10.0, 0.0], [9.0, 15.0, 8.0]],
    [[-9.0, -15.0, 0.0], [9.0, -10.0, 8.0]],
];

/// A fresh folder with `floor.json` and `box.stl` (`boxes`, `drop` triangles missing).
fn scene(tag: &str, boxes: &[[[f64; 3]; 2]], drop: usize) -> PathBuf {
    let dir = swarf_testdata::scratch_dir(&format!("check-{tag}"));
    std::fs::write(dir.join("floor.json"), FLOOR).unwrap();
    std::fs::write(dir.join("box.stl"), boxes_stl(boxes, drop)).unwrap();
    dir
}

fn toolsize(dir: &Path, extra: &[&str]) -> std::process::Output {
    let surface = dir.join("floor.json");
    let out = dir.join("out");
    let mut args = vec![
        "toolsize",
        "--surface",
        surface.to_str().unwrap(),
        "--cutter",
        "flat",
        "--grid",
        "3",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ];
    args.extend_from_slice(extra);
    swarf(&args)
}

/// The CSV row of the middle of the floor, as `(radius_mm, limit_x, limit)`.
fn centre_row(dir: &Path) -> (f64, String, String) {
    let csv = std::fs::read_to_string(dir.join("out/toolsize.csv")).unwrap();
    let row = csv
        .lines()
        .skip(1)
        .find(|r| {
            let f: Vec<&str> = r.split(',').collect();
            f[1].parse::<f64>().unwrap() == 0.5 && f[2].parse::<f64>().unwrap() == 0.5
        })
        .expect("the centre row");
    let f: Vec<&str> = row.split(',').collect();
    (f[9].parse().unwrap(), f[10].to_string(), f[13].to_string())
}

#[test]
fn the_box_limits_the_flat_end_mill_in_three_axis() {
    let dir = scene("3", &[BOX], 0);
    let o = toolsize(&dir, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(centre_row(&dir).0.is_infinite());

    let stl = dir.join("box.stl");
    let o = toolsize(&dir, &["--check", stl.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (r, x, limit) = centre_row(&dir);
    assert!((r - 10.0).abs() < TOL, "{r}");
    assert!((x.parse::<f64>().unwrap() - 10.0).abs() < TOL, "{x}");
    assert_eq!(limit, "interference");
    assert!(json(&o)["min_radius_mm"].as_f64().unwrap() <= 10.0 + TOL);
}

#[test]
fn the_box_is_checked_in_four_and_five_axis() {
    let dir = scene("45", &WALLS, 0);
    let stl = dir.join("box.stl");
    for mode in [&["--axis4", "Y"][..], &["--five-axis", "20,20"][..]] {
        let mut args = vec!["--check", stl.to_str().unwrap()];
        args.extend_from_slice(mode);
        let o = toolsize(&dir, &args);
        assert!(o.status.success(), "{mode:?}: {}", stderr(&o));
        let (r, _, limit) = centre_row(&dir);
        // Never below the 3-axis answer (the upright tool is one of the orientations tried),
        // and still limited by the box.
        assert!(r.is_finite() && r >= 10.0 - TOL, "{mode:?}: {r}");
        assert_eq!(limit, "interference", "{mode:?}");
    }
}

#[test]
fn an_open_check_mesh_is_refused_naming_the_file() {
    let dir = scene("open", &[BOX], 1);
    let stl = dir.join("box.stl");
    let o = toolsize(&dir, &["--check", stl.to_str().unwrap()]);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(e.contains("box.stl") && e.contains("3 open edge"), "{e}");
}

#[test]
fn check_geometry_needs_the_certified_solver() {
    let dir = scene("pso", &[BOX], 0);
    let stl = dir.join("box.stl");
    let o = toolsize(&dir, &["--check", stl.to_str().unwrap(), "--solver", "pso"]);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(e.contains("--solver certified"), "{e}");
}
