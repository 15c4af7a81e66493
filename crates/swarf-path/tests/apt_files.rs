//! The APT CL files of the third-party test data (`SWARF_TEST_DATA`, `apt/`) read into the
//! expected moves; each test skips, saying so, without the data.
//!
//! Expected numbers come from an independent Python pass over each file (not from swarf): it
//! counts GOTO/CIRCLE/RAPID records, treats the first GOTO as the start point, turns each
//! CIRCLE + GOTO into an arc in the XY plane (NX: clockwise about the CIRCLE axis, SolidWorks
//! CAM: counter-clockwise) and adds to the bounding box the arc's end points and every
//! cardinal point (0°, 90°, 180°, 270°) inside its sweep, at the start radius; lengths are chord
//! lengths and (mean radius)·sweep, times length/feed. NX rounds to 4 decimals, so its arcs'
//! start and end radii differ by up to ~4e-5 mm (the tool spirals between them): NX box
//! coordinates on arcs are compared to 1e-4 mm.

use std::f64::consts::PI;

use swarf_path::apt::{read_apt, read_apt_file, AptOptions, CircleSense};
use swarf_path::builder::MoveBuilder;
use swarf_path::canon::Recorder;
use swarf_path::kinematics::Machine;
use swarf_path::moves::AxisSource;
use swarf_path::summary::summarize;
use swarf_path::{Canon, MoveKind, Program};

const NX: &str = "apt/nx_1_KONTUR_NAR_40_N2.cls";
const SW: &str = "apt/swcam_Paralelipipedo.apt";

/// The data file `rel` read, or `None` (the test skips, saying so) without it.
fn read(rel: &str, options: &AptOptions) -> Option<Program> {
    let path = swarf_testdata::path(rel)?;
    let mut b = MoveBuilder::new(Machine::three_axis(), &path.display().to_string());
    read_apt_file(&path, options, &mut b).unwrap();
    Some(b.finish())
}

fn assert_close(a: f64, b: f64, tol: f64, what: &str) {
    assert!((a - b).abs() <= tol, "{what}: {a} vs {b}");
}

fn assert_vec(a: Option<[f64; 3]>, b: [f64; 3], tol: f64, what: &str) {
    let a = a.unwrap();
    for k in 0..3 {
        assert_close(a[k], b[k], tol, what);
    }
}

#[test]
fn nx_contour() {
    let Some(p) = read(NX, &AptOptions::default()) else {
        return;
    };
    let s = summarize(&p);
    assert_eq!(p.axis_source, AxisSource::Program);
    // 46 GOTOs, the first places the tool: 45 moves; 2 RAPIDs; 19 CIRCLEs.
    assert_eq!(s.moves, 45);
    assert_eq!(s.rapid_moves, 2);
    assert_eq!(s.feed_moves, 43);
    assert_eq!(s.arc_moves, 19);
    assert_close(s.feed_length_mm, 5360.604185160009, 1e-6, "feed length");
    assert_close(s.rapid_length_mm, 18.0, 1e-9, "rapid length");
    assert_close(s.machining_time_s, 517.9327715130445, 1e-6, "time");
    assert_vec(
        s.bbox_min,
        [-13.000039871294348, -871.0000130247789, 466.0],
        1e-4,
        "bbox min",
    );
    assert_vec(s.bbox_max, [2133.0, 39.94, 478.0], 1e-7, "bbox max");
    assert_vec(
        s.feed_bbox_max,
        [2133.0, 39.94, 469.0],
        1e-7,
        "feed bbox max",
    );
    // Every arc in this contour is a corner or a blend of less than 180° — the wrong direction
    // convention would make them all reflex.
    for m in &p.moves {
        if let MoveKind::Arc(g) = m.kind {
            assert!(g.sweep < PI, "line {}: sweep {}", m.line, g.sweep);
            assert!((g.start_radius - g.end_radius).abs() < 1e-3);
        }
        assert!((m.start.axis - swarf_geom::math::Vec3::Z).length() < 1e-15);
    }
    // TLDATA/MILL,40,1,50 → a torus cutter d 40, r 1, e 19, f 1, h 50 (no tool loaded: tool 0).
    assert_eq!(
        p.cutter_definitions,
        vec![(0, [40.0, 1.0, 19.0, 1.0, 0.0, 0.0, 50.0])]
    );
    // One warning: the MSYS record that is not the identity.
    assert_eq!(p.warnings.len(), 1, "{:?}", p.warnings);
    assert!(p.warnings[0].message.starts_with("MSYS/"));
    assert_eq!(p.warnings[0].line, 3);
}

#[test]
fn swcam_pocket() {
    let Some(p) = read(SW, &AptOptions::default()) else {
        return;
    };
    let s = summarize(&p);
    assert_eq!(s.moves, 193);
    assert_eq!(s.rapid_moves, 49);
    assert_eq!(s.feed_moves, 144);
    assert_eq!(s.arc_moves, 32);
    assert_close(s.feed_length_mm, 3882.6278472365693, 1e-6, "feed length");
    assert_close(s.rapid_length_mm, 3639.562319239387, 1e-6, "rapid length");
    assert_close(s.machining_time_s, 83.70268674027751, 1e-6, "time");
    assert_vec(s.bbox_min, [-8.368118, -8.368118, -30.0], 1e-9, "bbox min");
    assert_vec(s.bbox_max, [180.868118, 43.368118, 25.0], 1e-9, "bbox max");
    assert_vec(
        s.feed_bbox_max,
        [180.868118, 43.368118, 3.0],
        1e-9,
        "feed bbox max",
    );
    assert_eq!(s.tools, vec![19]);
    assert_eq!(
        p.cutter_definitions,
        vec![(19, [8.0, 0.0, 4.0, 0.0, 0.0, 0.0, 64.0])]
    );
    for m in &p.moves {
        if let MoveKind::Arc(g) = m.kind {
            assert_close(g.sweep, PI / 4.0, 1e-5, "lead-in arc sweep");
        }
        assert_eq!(m.spindle_rpm, 10296.0);
    }
    // 3 INSERT, 2 unknown CSI_ records, 16 CUTCOM/LEFT.
    let count = |prefix: &str| {
        p.warnings
            .iter()
            .filter(|w| w.message.starts_with(prefix))
            .count()
    };
    assert_eq!(count("INSERT/"), 3);
    assert_eq!(count("unknown record"), 2);
    assert_eq!(count("CUTCOM/LEFT"), 16);
    assert_eq!(p.warnings.len(), 21);
    let w = p
        .warnings
        .iter()
        .find(|w| w.message.starts_with("unknown record"))
        .unwrap();
    assert_eq!((w.line, w.column), (6, 1));
}

#[test]
fn forcing_the_other_sense_makes_reflex_arcs() {
    // Guards the NX detection: with the right-hand convention forced, NX's corners go the long way.
    let Some(p) = read(
        NX,
        &AptOptions::default().with_circle_sense(CircleSense::CounterClockwise),
    ) else {
        return;
    };
    for m in &p.moves {
        if let MoveKind::Arc(g) = m.kind {
            assert!(g.sweep > PI, "line {}", m.line);
        }
    }
}

#[test]
fn events_of_the_first_records() {
    let Some(sw) = swarf_testdata::path(SW) else {
        return;
    };
    let text = std::fs::read_to_string(sw).unwrap();
    let mut rec = Recorder::default();
    read_apt(&text, "sw.apt", &AptOptions::default(), &mut rec).unwrap();
    let ev: Vec<&Canon> = rec.events.iter().map(|(_, e)| e).collect();
    assert_eq!(ev[0], &Canon::Comment("1".into()));
    assert_eq!(ev[1], &Canon::Units(swarf_path::Units::Mm));
    assert!(matches!(ev.last(), Some(Canon::ProgramEnd)));
    let gotos = rec
        .events
        .iter()
        .filter(|(_, e)| {
            matches!(
                e,
                Canon::Feed { .. } | Canon::Traverse { .. } | Canon::Arc { .. }
            )
        })
        .count();
    assert_eq!(gotos, 193);
}

#[test]
fn every_file_in_the_data_folder_reads() {
    let Some(dir) = swarf_testdata::path("apt") else {
        return;
    };
    let mut n = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let mut b = MoveBuilder::new(Machine::three_axis(), &path.display().to_string());
        read_apt_file(&path, &AptOptions::default(), &mut b)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let s = summarize(&b.finish());
        assert!(
            s.feed_moves > 0 && s.feed_length_mm > 0.0,
            "{}",
            path.display()
        );
        n += 1;
    }
    assert!(n >= 2);
}
