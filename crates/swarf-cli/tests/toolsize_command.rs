//! `swarf toolsize`: the CSV and summary contract on the analytic STEP sphere.
mod common;
use common::*;

#[test]
fn inside_of_the_step_sphere_admits_a_ball_of_its_radius() {
    let sphere = sphere_step(&temp_dir("toolsize-sphere"), 5.0);
    let dir = swarf_testdata::scratch_dir("toolsize");
    let o = swarf(&[
        "toolsize",
        "--surface",
        &sphere,
        "--cutter",
        "ball",
        "--flip",
        "--grid",
        "9",
        "--out",
        dir.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    for k in [
        "points",
        "bounded_points",
        "unreachable_points",
        "min_radius_mm",
        "median_radius_mm",
        "max_radius_mm",
        "evaluations_per_point",
        "elapsed_s",
    ] {
        assert!(j.get(k).is_some(), "{k}: {j}");
    }
    assert!(
        (j["max_radius_mm"].as_f64().unwrap() - 5.0).abs() < 1e-6,
        "{j}"
    );
    // The summary is in --out too (what `swarf report --from` reads), the printed one's twin.
    let written: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(written["points"], j["points"]);
    assert_eq!(written["max_radius_mm"], j["max_radius_mm"]);
    // Options that mean nothing are refused.
    for (opt, value) in [
        ("--grid", "1"),
        ("--flute-length", "-3"),
        ("--flute-length", "0"),
    ] {
        let o = swarf(&[
            "toolsize",
            "--surface",
            &sphere,
            "--cutter",
            "ball",
            opt,
            value,
            "--out",
            dir.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(1), "{opt} {value}");
        assert!(stderr(&o).contains(opt), "{}", stderr(&o));
    }
    let csv = std::fs::read_to_string(dir.join("toolsize.csv")).unwrap();
    let mut rows = csv.lines();
    assert_eq!(
        rows.next().unwrap(),
        "patch,u,v,x,y,z,nx,ny,nz,radius_mm,limit_x,limit_y,limit_z,limit,certified"
    );
    // Every reachable point of the lower half (normal pointing up into the sphere) gets 5.
    let mut checked = 0;
    for r in rows {
        let f: Vec<&str> = r.split(',').collect();
        let (z, nz) = (
            f[5].parse::<f64>().unwrap(),
            f[8].parse::<f64>().unwrap_or(0.0),
        );
        if z < -1.0 && nz > 0.2 {
            let radius: f64 = f[9].parse().unwrap();
            assert!((radius - 5.0).abs() < 1e-6, "{r}");
            checked += 1;
        }
    }
    assert!(checked > 10);
    // From the convex outside nothing limits a ball.
    let o = swarf(&[
        "toolsize",
        "--surface",
        &sphere,
        "--cutter",
        "ball",
        "--grid",
        "5",
        "--out",
        dir.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let csv = std::fs::read_to_string(dir.join("toolsize.csv")).unwrap();
    assert!(
        csv.lines()
            .skip(1)
            .any(|r| r.split(',').nth(9) == Some("inf")),
        "{csv}"
    );
}

#[test]
fn a_trimmed_wall_limits_only_where_it_is_left() {
    // A 20 × 20 floor and a 10 mm wall at x = 20 facing it, a slot y ∈ [5, 15] cut out of the
    // wall by its trim (JSON `trim`, wall parameters: u along z, v along y).
    let dir = swarf_testdata::scratch_dir("toolsize-trim");
    let surface = dir.join("slot.json");
    std::fs::write(
        &surface,
        r#"{"units": "mm", "patches": [
  {"name": "floor", "degree_u": 1, "degree_v": 1, "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
   "control_points": [[[0, 0, 0, 1], [0, 20, 0, 1]], [[20, 0, 0, 1], [20, 20, 0, 1]]]},
  {"name": "wall", "degree_u": 1, "degree_v": 1, "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
   "control_points": [[[20, 0, 0, 1], [20, 20, 0, 1]], [[20, 0, 10, 1], [20, 20, 10, 1]]],
   "trim": {"holes": [[[-0.1, 0.25], [1.1, 0.25], [1.1, 0.75], [-0.1, 0.75]]]}}]}"#,
    )
    .unwrap();
    let out = dir.join("out");
    let o = swarf(&[
        "toolsize",
        "--surface",
        surface.to_str().unwrap(),
        "--cutter",
        "flat",
        "--grid",
        "11",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // The wall's grid points with v = 0.3 … 0.7 are in the slot: 5 columns of 11.
    assert_eq!(json(&o)["points"].as_u64(), Some(2 * 121 - 55));
    let csv = std::fs::read_to_string(out.join("toolsize.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 2 * 121 - 55);
    let centre = csv
        .lines()
        .find(|r| r.starts_with("floor,0.5,0.5,"))
        .expect("the floor's centre");
    let radius: f64 = centre.split(',').nth(9).unwrap().parse().unwrap();
    // Not the wall at 10 mm: the slot's edges at √(10² + 5²).
    assert!((radius - 125f64.sqrt()).abs() < 1e-5, "{centre}");
    assert!(out.join("maps/patch_wall.png").is_file() && out.join("part.glb").is_file());
    std::fs::remove_dir_all(&dir).ok();
}

/// A patch whose trimmed region falls between the grid's rows and columns gets no point: a
/// warning names it (its sizes are missing from the map, silently before). The grid spans the
/// outer boundary's box (the readers cut the parameter box down to it), so a diamond touching
/// that box's sides at their middles holds none of its corners (`--grid 2`) but its centre
/// (`--grid 3`).
#[test]
fn a_patch_the_grid_misses_is_named() {
    let dir = swarf_testdata::scratch_dir("toolsize-offgrid");
    let surface = dir.join("island.json");
    std::fs::write(
        &surface,
        r#"{"units": "mm", "patches": [
  {"name": "floor", "degree_u": 1, "degree_v": 1, "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
   "control_points": [[[0, 0, 0, 1], [0, 20, 0, 1]], [[20, 0, 0, 1], [20, 20, 0, 1]]]},
  {"name": "island", "degree_u": 1, "degree_v": 1, "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
   "control_points": [[[20, 0, 0, 1], [20, 20, 0, 1]], [[20, 0, 10, 1], [20, 20, 10, 1]]],
   "trim": {"outer": [[0.25, 0.2], [0.3, 0.25], [0.25, 0.3], [0.2, 0.25]]}}]}"#,
    )
    .unwrap();
    let out = dir.join("out");
    let run = |grid: &str| {
        swarf(&[
            "toolsize",
            "--surface",
            surface.to_str().unwrap(),
            "--cutter",
            "ball",
            "--grid",
            grid,
            "--out",
            out.to_str().unwrap(),
        ])
    };
    let o = run("2");
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains(
            "warning: 1 of 2 patches get no grid point on the part at --grid 2 (patch 1 (island))"
        ),
        "{}",
        stderr(&o)
    );
    // At --grid 3 the island holds grid points (its centre and the middles of its box's sides).
    let o = run("3");
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("no grid point"), "{}", stderr(&o));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn faces_that_share_a_name_keep_their_own_rows_and_maps() {
    // CAD systems name every face after the product ("PartBody"): each face must still get its
    // own patch value in the CSV and its own map.
    let dir = swarf_testdata::scratch_dir("toolsize-names");
    let surface = dir.join("same.json");
    std::fs::write(
        &surface,
        r#"{"units": "mm", "patches": [
  {"name": "PartBody", "degree_u": 1, "degree_v": 1, "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
   "control_points": [[[0, 0, 0, 1], [0, 20, 0, 1]], [[20, 0, 0, 1], [20, 20, 0, 1]]]},
  {"name": "PartBody", "degree_u": 1, "degree_v": 1, "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
   "control_points": [[[20, 0, 0, 1], [20, 20, 0, 1]], [[20, 0, 10, 1], [20, 20, 10, 1]]]},
  {"name": "PartBody#1", "degree_u": 1, "degree_v": 1, "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
   "control_points": [[[0, 20, 0, 1], [20, 20, 0, 1]], [[0, 20, 10, 1], [20, 20, 10, 1]]]}]}"#,
    )
    .unwrap();
    let out = dir.join("out");
    let o = swarf(&[
        "toolsize",
        "--surface",
        surface.to_str().unwrap(),
        "--cutter",
        "flat",
        "--grid",
        "3",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let csv = std::fs::read_to_string(out.join("toolsize.csv")).unwrap();
    let mut labels: Vec<&str> = csv
        .lines()
        .skip(1)
        .map(|r| r.split(',').next().unwrap())
        .collect();
    labels.dedup();
    assert_eq!(labels, ["PartBody#0", "#1", "#2"], "{csv}");
    let mut maps: Vec<String> = std::fs::read_dir(out.join("maps"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    maps.sort();
    assert_eq!(
        maps,
        ["patch_PartBody_0.png", "patch__1.png", "patch__2.png"]
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn outputs_are_written_as_a_set_or_not_at_all() {
    // `part.glb` is in the way as a folder: that file cannot be written, so none may be.
    let dir = swarf_testdata::scratch_dir("toolsize-set");
    let surface = dir.join("floor.json");
    std::fs::write(
        &surface,
        r#"{"units": "mm", "patches": [
  {"name": "floor", "degree_u": 1, "degree_v": 1, "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
   "control_points": [[[0, 0, 0, 1], [0, 20, 0, 1]], [[20, 0, 0, 1], [20, 20, 0, 1]]]}]}"#,
    )
    .unwrap();
    let out = dir.join("out");
    std::fs::create_dir_all(out.join("part.glb")).unwrap();
    let o = swarf(&[
        "toolsize",
        "--surface",
        surface.to_str().unwrap(),
        "--cutter",
        "ball",
        "--grid",
        "3",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(!out.join("toolsize.csv").exists() && !out.join("maps").exists());
    // No staging folder is left behind.
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains("staging"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_text_summary_prints_numbers_not_debug_options() {
    // Without --json the radii were printed as Rust's `Some(5.0)` / `None`.
    let dir = temp_dir("toolsize-text");
    let sphere = sphere_step(&dir, 5.0);
    // A plane facing up: nothing limits a ball on it.
    let plane = dir.join("plane.step");
    std::fs::write(
        &plane,
        "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n#1=CARTESIAN_POINT('',(0.,0.,0.));\n\
         #2=DIRECTION('',(0.,0.,1.));\n#3=DIRECTION('',(1.,0.,0.));\n\
         #4=AXIS2_PLACEMENT_3D('',#1,#2,#3);\n#5=PLANE('floor',#4);\nENDSEC;\nEND-ISO-10303-21;\n",
    )
    .unwrap();
    let run = |surface: &str, flip: bool| {
        let out = dir.join(if flip { "flipped" } else { "as-is" });
        let mut args = vec![
            "toolsize",
            "--surface",
            surface,
            "--cutter",
            "ball",
            "--grid",
            "5",
        ];
        if flip {
            args.push("--flip");
        }
        args.extend(["--out", out.to_str().unwrap()]);
        let o = swarf(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        stdout(&o)
    };
    // Inside the sphere: bounded points, the largest ball the sphere's radius.
    let text = run(&sphere, true);
    assert!(!text.contains("Some(") && !text.contains("None"), "{text}");
    assert!(text.contains("max 5.000 mm"), "{text}");
    // On the plane: no bounded point, no radius to give.
    let text = run(plane.to_str().unwrap(), false);
    assert!(
        text.contains("0 bounded (0 unreachable), radius min none median none max none mm"),
        "{text}"
    );
}

#[test]
fn faces_the_reader_could_not_carry_over_are_counted_and_said() {
    // A floor plane and a face on a surface kind the STEP reader does not evaluate: the radii
    // take no account of that face, which the summary (skipped_faces, with the note) and
    // stderr say; verify with the same file as its design says it too.
    let dir = swarf_testdata::scratch_dir("toolsize-caveats");
    let step = "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n\
        #1=CARTESIAN_POINT('',(0.,0.,0.));#2=DIRECTION('',(0.,0.,1.));#3=DIRECTION('',(1.,0.,0.));\n\
        #4=AXIS2_PLACEMENT_3D('',#1,#2,#3);#5=PLANE('',#4);\n\
        #6=CARTESIAN_POINT('',(0.,0.,0.));#7=VERTEX_POINT('',#6);\n\
        #8=CARTESIAN_POINT('',(20.,20.,0.));#9=VERTEX_POINT('',#8);\n\
        #10=VERTEX_LOOP('',#7);#11=FACE_BOUND('',#10,.T.);#12=VERTEX_LOOP('',#9);#13=FACE_BOUND('',#12,.T.);\n\
        #14=ADVANCED_FACE('floor',(#11,#13),#5,.T.);\n\
        #25=CURVE_BOUNDED_SURFACE('',#5,(),.F.);#26=ADVANCED_FACE('odd',(),#25,.T.);\n\
        ENDSEC;\nEND-ISO-10303-21;\n";
    let surface = dir.join("part.step");
    std::fs::write(&surface, step).unwrap();
    let out = dir.join("out");
    let o = swarf(&[
        "toolsize",
        "--surface",
        surface.to_str().unwrap(),
        "--cutter",
        "ball",
        "--grid",
        "3",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(s["skipped_faces"], 1, "{s}");
    assert_eq!(s["untrimmed_faces"], 0, "{s}");
    assert!(s["skipped_face_notes"][0]
        .as_str()
        .unwrap()
        .contains("CURVE_BOUNDED_SURFACE"));
    assert!(
        stderr(&o).contains("warning: 1 face(s) of the surface were not read"),
        "{}",
        stderr(&o)
    );
    let file: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(file["skipped_faces"], 1);
}
