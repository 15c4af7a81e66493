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

/// `swarf gouge` of `dir`'s `surface` and `job.ngc` with a 10 mm flat end mill, no check mesh,
/// into `dir/out`, then `extra`.
fn gouge_flat(dir: &Path, surface: &str, extra: &[&str]) -> std::process::Output {
    let p = |f: &str| dir.join(f).to_str().unwrap().to_string();
    let (surface, program, out) = (p(surface), p("job.ngc"), p("out"));
    let mut args = vec![
        "gouge",
        "--surface",
        &surface,
        "--program",
        &program,
        "--tool",
        "flat:d=10",
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
        "skipped_faces",
        "skipped_face_notes",
        "untrimmed_faces",
        "untrimmed_face_notes",
        "unapplied_placements",
        "unapplied_placement_notes",
        "nodes",
        "tolerance_mm",
        "accuracy_mm",
        "accuracy_relative",
        "motion_tolerance_mm",
        "elapsed_s",
    ] {
        assert!(s.get(key).is_some(), "summary lacks {key}: {s}");
    }
    assert_eq!(s["moves"], 7);
    assert_eq!(s["points"], 8);
    assert_eq!(s["certified"], true);
    assert_eq!(
        (&s["skipped_faces"], &s["skipped_face_notes"]),
        (&0.into(), &serde_json::json!([]))
    );
    assert_eq!(
        (&s["unapplied_placements"], &s["unapplied_placement_notes"]),
        (&0.into(), &serde_json::json!([]))
    );
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
fn part_at_places_the_surface_and_the_check_mesh_together() {
    let dir = scene("part-at", 0);
    let figures = |at: &str| {
        let o = gouge(&dir, &["--tool", "flat:d=10", "--part-at", at, "--json"]);
        assert!(o.status.success(), "{}", stderr(&o));
        let s = json(&o);
        assert_eq!(s["certified"], true, "{s}");
        (
            s["max_gouge_mm"].as_f64().unwrap(),
            s["max_interference_mm"].as_f64().unwrap(),
        )
    };
    // Placed 1 mm up: the plunge to z = −0.5 gouges 1.5 mm, and the rapid back up out of it
    // runs through 1.5 mm of the part (more than the clamp's 1 mm).
    let (g, i) = figures("0,0,1");
    assert!(
        (g - 1.5).abs() <= 2e-3 && (i - 1.5).abs() <= 2e-3,
        "{g} {i}"
    );
    // Placed 5 mm along X: the clamp moves with the floor to x = 15..25, out of the tool's
    // reach (x ≤ 11); left is the plunge's 0.5 mm, gouge and rapid alike.
    let (g, i) = figures("5,0,0");
    assert!(
        (g - 0.5).abs() <= 5e-4 && (i - 0.5).abs() <= 5e-4,
        "{g} {i}"
    );
}

#[test]
fn without_the_clamp_the_pass_is_clear() {
    let dir = scene("noclamp", 0);
    let o = gouge_flat(&dir, "floor.json", &["--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = json(&o);
    // Only the retract from the plunge interferes (a rapid leaving the floor).
    assert_eq!(s["interfering_moves"], 1, "{s}");
    let v = rows(&dir.join("out/violations.csv"));
    assert!(v.iter().all(|r| r["line"] != "3"), "{v:?}");
}

#[test]
fn a_face_checked_without_its_trim_is_not_certified() {
    // A floor plane at z = 0 whose face is the disc of radius 10 about the origin, its circle
    // edge 1 mm above the plane: the trim is not honoured and the whole plane is checked, so
    // a gouge found may be outside the disc (no gouge of the part): not certified.
    let dir = swarf_testdata::scratch_dir("gouge-untrimmed");
    let step = "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n\
        #1=CARTESIAN_POINT('',(0.,0.,0.));#2=DIRECTION('',(0.,0.,1.));#3=DIRECTION('',(1.,0.,0.));\n\
        #4=AXIS2_PLACEMENT_3D('',#1,#2,#3);#5=PLANE('',#4);\n\
        #6=CARTESIAN_POINT('',(0.,0.,1.));#7=AXIS2_PLACEMENT_3D('',#6,#2,#3);#8=CIRCLE('',#7,10.);\n\
        #9=CARTESIAN_POINT('',(10.,0.,1.));#10=VERTEX_POINT('',#9);\n\
        #11=EDGE_CURVE('',#10,#10,#8,.T.);#12=ORIENTED_EDGE('',*,*,#11,.T.);\n\
        #13=EDGE_LOOP('',(#12));#14=FACE_OUTER_BOUND('',#13,.T.);\n\
        #15=ADVANCED_FACE('disc',(#14),#5,.T.);\n\
        ENDSEC;\nEND-ISO-10303-21;\n";
    std::fs::write(dir.join("part.step"), step).unwrap();
    std::fs::write(dir.join("job.ngc"), "G0 X5 Y0 Z5\nG1 Z-0.5 F300\nG0 Z5\n").unwrap();
    let o = gouge_flat(&dir, "part.step", &["--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = json(&o);
    assert_eq!(s["untrimmed_faces"], 1, "{s}");
    assert_eq!(s["skipped_faces"], 0, "{s}");
    assert_eq!(s["certified"], false, "{s}");
    assert!(s["max_gouge_mm"].as_f64().unwrap() > 0.4, "{s}");
    let o = gouge_flat(&dir, "part.step", &[]);
    assert!(
        stdout(&o).contains("not certified: 1 face(s) were checked on their whole surface"),
        "{}",
        stdout(&o)
    );
}

#[test]
fn a_surface_with_skipped_faces_is_not_certified() {
    // A STEP part of two faces: a floor plane at z = 0 and a face on a surface kind the
    // reader does not evaluate (skipped with a note on stderr). The summary said "certified":
    // true although the wall was never checked; it now lists the skipped face and withdraws
    // the certificate, in summary.json as in the printed JSON.
    let dir = swarf_testdata::scratch_dir("gouge-skipped");
    let step = "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n\
        #1=CARTESIAN_POINT('',(0.,0.,0.));#2=DIRECTION('',(0.,0.,1.));#3=DIRECTION('',(1.,0.,0.));\n\
        #4=AXIS2_PLACEMENT_3D('',#1,#2,#3);#5=PLANE('',#4);\n\
        #6=CARTESIAN_POINT('',(-40.,-40.,0.));#7=VERTEX_POINT('',#6);\n\
        #8=CARTESIAN_POINT('',(40.,40.,0.));#9=VERTEX_POINT('',#8);\n\
        #10=VERTEX_LOOP('',#7);#11=FACE_BOUND('',#10,.T.);#12=VERTEX_LOOP('',#9);#13=FACE_BOUND('',#12,.T.);\n\
        #14=ADVANCED_FACE('floor',(#11,#13),#5,.T.);\n\
        #20=CARTESIAN_POINT('',(30.,0.,0.));#21=DIRECTION('',(0.,1.,0.));#22=VECTOR('',#21,1.);\n\
        #23=LINE('',#20,#22);#24=VECTOR('',#2,10.);#25=CURVE_BOUNDED_SURFACE('',#5,(),.F.);\n\
        #26=ADVANCED_FACE('wall',(),#25,.T.);\n\
        ENDSEC;\nEND-ISO-10303-21;\n";
    std::fs::write(dir.join("part.step"), step).unwrap();
    std::fs::write(
        dir.join("job.ngc"),
        "G0 X-20 Y0 Z5\nG1 Z0.5 F300\nG1 X20\nG0 Z5\n",
    )
    .unwrap();
    let o = gouge_flat(&dir, "part.step", &["--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("CURVE_BOUNDED_SURFACE is not supported; skipped"));
    let printed = json(&o);
    let file: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("out/summary.json")).unwrap())
            .unwrap();
    for s in [&printed, &file] {
        assert_eq!(s["skipped_faces"], 1, "{s}");
        assert_eq!(s["certified"], false, "{s}");
        assert_eq!(s["unresolved_searches"], 0, "{s}");
        assert_eq!(s["violations"], 0, "{s}");
        let notes = s["skipped_face_notes"].as_array().unwrap();
        assert_eq!(notes.len(), 1);
        assert!(
            notes[0]
                .as_str()
                .unwrap()
                .contains("#25 (face #26): surface type CURVE_BOUNDED_SURFACE"),
            "{s}"
        );
    }
    // The printed report says why it is not certified.
    let o = gouge_flat(&dir, "part.step", &[]);
    assert!(
        stdout(&o).contains("not certified: 1 face(s) of the surface were not read"),
        "{}",
        stdout(&o)
    );
}

#[test]
fn step_assembly_placements_are_applied_and_one_that_is_not_withdraws_the_certificate() {
    // A floor plane at z = 0 in its part, placed in an assembly by a MAPPED_ITEM 1 mm up; the
    // pass at z = 0.5 gouges the placed floor by 0.5 mm (it would clear the unplaced one) and
    // the check is certified. The same part placed by a mirroring operator: the reader cannot
    // apply it, reads the floor unplaced and says so; the pass is clear but not certified.
    let dir = swarf_testdata::scratch_dir("gouge-assembly");
    let part = "#1=CARTESIAN_POINT('',(0.,0.,0.));#2=DIRECTION('',(0.,0.,1.));#3=DIRECTION('',(1.,0.,0.));\n\
        #4=AXIS2_PLACEMENT_3D('',#1,#2,#3);#5=PLANE('',#4);\n\
        #6=CARTESIAN_POINT('',(-40.,-40.,0.));#7=VERTEX_POINT('',#6);\n\
        #8=CARTESIAN_POINT('',(40.,40.,0.));#9=VERTEX_POINT('',#8);\n\
        #10=VERTEX_LOOP('',#7);#11=FACE_BOUND('',#10,.T.);#12=VERTEX_LOOP('',#9);#13=FACE_BOUND('',#12,.T.);\n\
        #14=ADVANCED_FACE('floor',(#11,#13),#5,.T.);#15=OPEN_SHELL('',(#14));\n\
        #16=SHELL_BASED_SURFACE_MODEL('',(#15));\n\
        #17=(GEOMETRIC_REPRESENTATION_CONTEXT(3) REPRESENTATION_CONTEXT('',''));\n\
        #18=MANIFOLD_SURFACE_SHAPE_REPRESENTATION('part',(#4,#16),#17);\n\
        #19=REPRESENTATION_MAP(#4,#18);#20=MAPPED_ITEM('',#19,#30);\n\
        #21=SHAPE_REPRESENTATION('assembly',(#20),#17);\n";
    let up = "#30=AXIS2_PLACEMENT_3D('',#31,#2,#3);#31=CARTESIAN_POINT('',(0.,0.,1.));\n";
    let mirror = "#30=CARTESIAN_TRANSFORMATION_OPERATOR_3D('',#3,#32,#1,1.,#2);\n\
        #32=DIRECTION('',(0.,-1.,0.));\n";
    let file = |target: &str| {
        format!(
            "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n{part}{target}ENDSEC;\nEND-ISO-10303-21;\n"
        )
    };
    std::fs::write(dir.join("up.step"), file(up)).unwrap();
    std::fs::write(dir.join("mirrored.step"), file(mirror)).unwrap();
    std::fs::write(
        dir.join("job.ngc"),
        "G0 X-20 Y0 Z5\nG1 Z0.5 F300\nG1 X20\nG0 Z5\n",
    )
    .unwrap();
    let o = gouge_flat(&dir, "up.step", &["--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("assembly placements applied: 1 placed instance(s) of 1 part(s)"),
        "{}",
        stderr(&o)
    );
    let s = json(&o);
    assert_eq!(s["certified"], true, "{s}");
    assert_eq!(s["unapplied_placements"], 0, "{s}");
    assert!(
        (s["max_gouge_mm"].as_f64().unwrap() - 0.5).abs() <= 5e-4,
        "{s}"
    );

    let o = gouge_flat(&dir, "mirrored.step", &["--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("MAPPED_ITEM #20: placement not applied: it mirrors"),
        "{}",
        stderr(&o)
    );
    let s = json(&o);
    assert_eq!(s["certified"], false, "{s}");
    assert_eq!(s["unapplied_placements"], 1, "{s}");
    assert_eq!(s["skipped_faces"], 0, "{s}");
    assert_eq!(s["max_gouge_mm"], 0.0, "{s}");
    let notes = s["unapplied_placement_notes"].as_array().unwrap();
    assert!(
        notes[0].as_str().unwrap().contains("MAPPED_ITEM #20"),
        "{s}"
    );
    let o = gouge_flat(&dir, "mirrored.step", &[]);
    assert!(
        stdout(&o)
            .contains("not certified: 1 assembly placement(s) of the surface were not applied"),
        "{}",
        stdout(&o)
    );
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
