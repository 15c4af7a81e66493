//! `swarf verify`: a known gouge found at its place, depth and line through the command; the
//! summary contract; the deviation map's legend; bad designs and options refused with the
//! file named and a non-zero exit.
mod common;
use common::*;
use std::path::{Path, PathBuf};

fn temp_dir(name: &str) -> PathBuf {
    swarf_testdata::fresh_scratch_dir(&format!("verify-{name}"))
}

/// Faces a 40 × 40 × 12 block at (20..60)² down to the design's top (z = 10) with a 10 mm
/// flat end mill, then plunges to 9.7 and runs a slot from x = 30 to 50 at y = 40: a gouge
/// 0.3 mm deep. Returns the program's path and the slot's line.
fn gouging_program(dir: &Path) -> (PathBuf, usize) {
    let mut s = String::from("G21 G90\nG0 Z20\nG0 X10 Y17\nG1 Z10 F500\n");
    let mut y = 17.0;
    let mut left = true;
    while y <= 65.0 {
        s += &format!("G1 X{} Y{y}\n", if left { 70 } else { 10 });
        y += 8.0;
        if y <= 65.0 {
            s += &format!("G1 Y{y}\n");
        }
        left = !left;
    }
    s += "G0 Z20\nG0 X30 Y40\nG1 Z9.7 F200\n";
    let line = s.lines().count() + 1;
    s += "G1 X50 (too deep)\nG0 Z20\nM30\n";
    let p = dir.join("gouge.ngc");
    std::fs::write(&p, s).unwrap();
    (p, line)
}

fn design(dir: &Path) -> PathBuf {
    let p = dir.join("part.stl");
    std::fs::write(&p, boxes_stl(&[[[20.0, 20.0, 0.0], [60.0, 60.0, 10.0]]], 0)).unwrap();
    p
}

fn run(dir: &Path, program: &Path, design: &Path, extra: &[&str]) -> std::process::Output {
    let out = dir.join("out");
    let mut args = vec![
        "verify",
        "--stock",
        "box:20,20,0,60,60,12",
        "--program",
        program.to_str().unwrap(),
        "--tool",
        "flat:d=10",
        "--design",
        design.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    swarf(&args)
}

#[test]
fn a_known_gouge_is_reported_with_its_line_and_the_outputs_hold_together() {
    let dir = temp_dir("gouge");
    let (prog, line) = gouging_program(&dir);
    let o = run(&dir, &prog, &design(&dir), &["--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    for k in [
        "max_gouge_mm",
        "max_excess_mm",
        "gouge_regions",
        "excess_regions",
        "excess_volume_mm3",
        "tolerance_mm",
        "collisions",
        "elapsed_s",
    ] {
        assert!(j.get(k).is_some(), "summary lacks {k}: {j}");
    }
    // The design reader's caveats are there for an STL design too (README): 0, notes empty.
    for k in ["skipped_faces", "untrimmed_faces", "unapplied_placements"] {
        assert_eq!(j[k], 0, "{k}: {j}");
    }
    for k in [
        "skipped_face_notes",
        "untrimmed_face_notes",
        "unapplied_placement_notes",
    ] {
        assert_eq!(j[k].as_array().map(Vec::len), Some(0), "{k}: {j}");
    }
    assert!(
        (j["max_gouge_mm"].as_f64().unwrap() - 0.3).abs() < 1e-6,
        "{j}"
    );
    assert_eq!(j["gouge_regions"], 1);
    assert_eq!(j["excess_regions"], 0);
    assert_eq!(j["collisions"], 0);
    assert_eq!(j["tolerance_mm"], 0.01);
    // The file equals what was printed.
    let out = dir.join("out");
    let file: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(file["regions"], j["regions"]);
    // defects.csv: one gouge row at the slot (its plunge or itself), 0.3 deep.
    let csv = std::fs::read_to_string(out.join("defects.csv")).unwrap();
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(
        rows[0],
        "region,kind,depth_mm,area_mm2,volume_mm3,x,y,z,move,file,line"
    );
    assert_eq!(rows.len(), 2, "{csv}");
    let f: Vec<&str> = rows[1].split(',').collect();
    assert_eq!(f[1], "gouge");
    assert!((f[2].parse::<f64>().unwrap() - 0.3).abs() < 1e-6);
    let vol: f64 = f[4].parse().unwrap();
    let exact = (200.0 + std::f64::consts::PI * 25.0) * 0.3;
    assert!((vol - exact).abs() < 2.4, "{vol} vs {exact}");
    assert!(f[9].ends_with("gouge.ngc"), "{}", f[9]);
    let l: usize = f[10].parse().unwrap();
    assert!(l == line || l == line - 1, "{l} vs {line}");
    let lines: Vec<u64> = j["regions"][0]["moves"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["line"].as_u64().unwrap())
        .collect();
    assert!(lines.contains(&(line as u64)), "{lines:?}");
    // deviation.glb: a glb whose extras carry the legend, coloured per vertex.
    let glb = std::fs::read(out.join("deviation.glb")).unwrap();
    assert_eq!(&glb[0..4], b"glTF");
    let n = u32::from_le_bytes([glb[12], glb[13], glb[14], glb[15]]) as usize;
    let doc: serde_json::Value = serde_json::from_slice(&glb[20..20 + n]).unwrap();
    let legend = &doc["extras"]["swarf_deviation_legend"];
    assert!(
        (legend["min_mm"].as_f64().unwrap() + 0.3).abs() < 1e-6,
        "{legend}"
    );
    assert!((legend["max_mm"].as_f64().unwrap() - 0.3).abs() < 1e-6);
    assert!(doc["meshes"][0]["primitives"][0]["attributes"]
        .get("COLOR_0")
        .is_some());
    // The human report names the line.
    let o = run(&dir, &prog, &design(&dir), &[]);
    assert!(o.status.success());
    assert!(
        stdout(&o).contains(&format!("gouge.ngc:{line}")),
        "{}",
        stdout(&o)
    );
}

#[test]
fn bad_designs_are_refused_with_the_file_named() {
    let dir = temp_dir("bad");
    let (prog, _) = gouging_program(&dir);
    let missing = dir.join("missing.stl");
    let garbage = dir.join("garbage.stl");
    std::fs::write(
        &garbage,
        "solid x\nfacet normal 0 0 1\nouter loop\nvertex 1 2\n",
    )
    .unwrap();
    let open = dir.join("open.stl");
    std::fs::write(
        &open,
        boxes_stl(&[[[20.0, 20.0, 0.0], [60.0, 60.0, 10.0]]], 1),
    )
    .unwrap();
    let unknown = dir.join("part.obj");
    std::fs::write(&unknown, "v 0 0 0\n").unwrap();
    let bad_json = dir.join("part.json");
    std::fs::write(&bad_json, "{\"units\": \"mm\", \"patches\": [{]}").unwrap();
    // A patch whose corners all coincide: no surface, so nothing to compare (it passed,
    // with 0 ray ends compared).
    let point = dir.join("point.json");
    std::fs::write(
        &point,
        "{\"units\": \"mm\", \"patches\": [{\"name\": \"p\", \"degree_u\": 1, \"degree_v\": 1, \
         \"knots_u\": [0, 0, 1, 1], \"knots_v\": [0, 0, 1, 1], \"control_points\": \
         [[[30, 30, 10, 1], [30, 30, 10, 1]], [[30, 30, 10, 1], [30, 30, 10, 1]]]}]}",
    )
    .unwrap();
    for (path, expect) in [
        (&missing, "missing.stl"),
        (&garbage, "garbage.stl"),
        (&open, "not a closed mesh"),
        (&unknown, "unknown format"),
        (&bad_json, "part.json"),
        (&point, "no ray end of the machined stock was compared"),
    ] {
        let o = run(&dir, &prog, path, &[]);
        assert_eq!(o.status.code(), Some(1), "{}", path.display());
        let e = stderr(&o);
        assert!(e.contains(expect), "{}: {e}", path.display());
        assert!(
            e.contains(path.file_name().unwrap().to_str().unwrap()),
            "{e}"
        );
        assert!(!e.contains("panicked"), "{e}");
        assert!(!dir.join("out/summary.json").exists());
    }
    let o = run(&dir, &prog, &design(&dir), &["--tolerance=-1"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("--tolerance"), "{}", stderr(&o));
}

/// The demo job: the finishing raster's known overcut (0.080 mm on the steepest slope of the
/// wavy floor) is found by `swarf gouge` (from the tool positions) and by `swarf verify` (from
/// the machined stock against the floor surface), the two within the ray spacing's error.
#[test]
fn demo_overcut_agrees_with_the_program_check() {
    let dir = temp_dir("demo");
    let d = dir.join("demo");
    let o = swarf(&["demo", "--out", d.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let gouge: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("gouge/summary.json")).unwrap()).unwrap();
    let g = gouge["max_gouge_mm"].as_f64().unwrap();
    assert!((g - 0.080).abs() < 0.001, "{g}");
    let o = swarf(&[
        "verify",
        "--stock",
        "box:0,0,-20,100,80,0",
        "--program",
        d.join("demo.ngc").to_str().unwrap(),
        "--tools",
        d.join("tools.toml").to_str().unwrap(),
        "--design",
        d.join("floor.json").to_str().unwrap(),
        "--out",
        dir.join("v").to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    let v = j["max_gouge_mm"].as_f64().unwrap();
    // At h = 0.25 the deepest ray end lies within h/2 of the deepest point; on this floor
    // (curvature ≤ 0.04/mm, the ball's 1/3) that costs well under 0.005 mm.
    assert!(
        (v - g).abs() < 0.005 && v <= g + 1e-3,
        "verify {v} vs gouge {g}"
    );
    assert!(j["gouge_regions"].as_u64().unwrap() > 0);
    assert_eq!(j["volume_method"], "surface-integral");
    // Every gouge was cut by the finishing raster (tool 2's moves), never by the roughing.
    let program = std::fs::read_to_string(d.join("demo.ngc")).unwrap();
    let finishing_starts = program
        .lines()
        .position(|l| l.contains("Op 2") && l.starts_with("(----"))
        .unwrap() as u64;
    for r in j["regions"].as_array().unwrap() {
        if r["kind"] == "gouge" {
            for m in r["moves"].as_array().unwrap() {
                assert!(m["line"].as_u64().unwrap() > finishing_starts, "{m}");
            }
        }
    }
}

#[test]
fn a_design_exported_in_another_frame_is_placed_with_part_at() {
    // The same part as `design`, as CAD might export it: turned −90° about Z and moved, so
    // that `--part-at 20,20,10,90` (turn 90° about Z, then move) puts it back on the stock.
    let dir = temp_dir("part-at");
    let (prog, _) = gouging_program(&dir);
    let cad = dir.join("cad.stl");
    std::fs::write(
        &cad,
        boxes_stl(&[[[0.0, -40.0, -10.0], [40.0, 0.0, 0.0]]], 0),
    )
    .unwrap();
    let o = run(&dir, &prog, &cad, &["--part-at", "20,20,10,90", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    assert!(
        (j["max_gouge_mm"].as_f64().unwrap() - 0.3).abs() < 1e-6,
        "{j}"
    );
    assert_eq!(
        (&j["gouge_regions"], &j["excess_regions"]),
        (&1.into(), &0.into())
    );
    // Unplaced, the part is nowhere near what was cut.
    let o = run(&dir, &prog, &cad, &["--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_ne!(json(&o)["excess_regions"], 0);
    // Bad placements are usage errors naming the form.
    for bad in ["1,2", "1,2,3,4,5", "1,2,x", "1,2,3,inf", "2e6,0,0"] {
        let o = run(&dir, &prog, &cad, &["--part-at", bad]);
        assert_eq!(o.status.code(), Some(2), "{bad}: {}", stderr(&o));
        assert!(stderr(&o).contains("X,Y,Z"), "{bad}: {}", stderr(&o));
    }
}

/// The shared SolidWorks CAM sample: its STL is the whole set-up (part, table, blocks, clamps)
/// in the program's frame. The fixture is never stock: no gouge volume comes of it, its volume
/// under the stock is reported apart, and a warning names both boxes.
#[test]
fn a_design_exported_with_its_fixture_is_compared_where_the_stock_is() {
    let Some([apt, stl]) = swarf_testdata::paths([
        "apt/swcam_Paralelipipedo.apt",
        "stl/swcam_Paralelipipedo.stl",
    ]) else {
        return;
    };
    let dir = temp_dir("fixture");
    let out = dir.join("out");
    let o = swarf(&[
        "verify",
        "--stock",
        "box:0,-4,-30,176.5,35,0",
        "--program",
        apt.to_str().unwrap(),
        "--tool",
        "flat:d=8",
        "--design",
        stl.to_str().unwrap(),
        "--resolution",
        "0.5",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    assert_eq!(j["gouge_regions"], 0, "{j}");
    assert!(j["gouge_volume_mm3"].as_f64().unwrap() < 1e-6, "{j}");
    assert_eq!(j["design_beyond_stock_box"], true);
    assert!(
        j["design_outside_stock_mm3"].as_f64().unwrap() > 600_000.0,
        "{j}"
    );
    assert!(
        stderr(&o).contains("reaches beyond the stock's box"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_surface_design_with_faces_not_read_says_so() {
    // The top of the part as a STEP plane at z = 10, and a face of a kind the reader does not
    // evaluate: the summary counts it (skipped_faces) and stderr says what it means.
    let dir = temp_dir("verify-caveats");
    let (program, _) = gouging_program(&dir);
    let step = "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n\
        #1=CARTESIAN_POINT('',(0.,0.,10.));#2=DIRECTION('',(0.,0.,1.));#3=DIRECTION('',(1.,0.,0.));\n\
        #4=AXIS2_PLACEMENT_3D('',#1,#2,#3);#5=PLANE('',#4);\n\
        #6=CARTESIAN_POINT('',(20.,20.,10.));#7=VERTEX_POINT('',#6);\n\
        #8=CARTESIAN_POINT('',(60.,60.,10.));#9=VERTEX_POINT('',#8);\n\
        #10=VERTEX_LOOP('',#7);#11=FACE_BOUND('',#10,.T.);#12=VERTEX_LOOP('',#9);#13=FACE_BOUND('',#12,.T.);\n\
        #14=ADVANCED_FACE('top',(#11,#13),#5,.T.);\n\
        #25=CURVE_BOUNDED_SURFACE('',#5,(),.F.);#26=ADVANCED_FACE('odd',(),#25,.T.);\n\
        ENDSEC;\nEND-ISO-10303-21;\n";
    let design = dir.join("part.step");
    std::fs::write(&design, step).unwrap();
    let o = run(&dir, &program, &design, &["--json", "--resolution", "1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(s["skipped_faces"], 1, "{s}");
    assert!(
        stderr(&o).contains("warning: 1 face(s) of the surface were not read"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_surface_design_with_no_excess_writes_a_volume_of_zero_not_minus_zero() {
    // The part's top as a JSON plane at z = 10: the slot gouges it, nothing is left above it.
    // The excess volume is the excess regions' added up — none: 0 (the sum of an empty list
    // of floats was −0.0, printed "-0.0" and "-0.000 mm³ left").
    let dir = temp_dir("verify-zero-excess");
    let (program, _) = gouging_program(&dir);
    let design = dir.join("top.json");
    std::fs::write(
        &design,
        r#"{"units": "mm", "patches": [{"name": "top", "degree_u": 1, "degree_v": 1,
            "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1], "control_points":
            [[[20, 20, 10, 1], [20, 60, 10, 1]], [[60, 20, 10, 1], [60, 60, 10, 1]]]}]}"#,
    )
    .unwrap();
    let o = run(&dir, &program, &design, &["--resolution", "1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let said = stdout(&o);
    assert!(
        said.contains(" 0 excess regions (thickest 0.0000 mm, 0.000 mm³ left)"),
        "{said}"
    );
    let text = std::fs::read_to_string(dir.join("out").join("summary.json")).unwrap();
    assert!(text.contains("\n  \"excess_volume_mm3\": 0.0,\n"), "{text}");
    assert!(
        text.contains("\"volume_method\": \"surface-integral\""),
        "{text}"
    );
}
