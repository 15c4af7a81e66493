//! The summary's JSON contract and its handling of empty programs, zero feeds, tolerance and
//! curved 5-axis moves.

use swarf_path::builder::MoveBuilder;
use swarf_path::kinematics::Machine;
use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::summary::{summarize, summarize_with, SummaryOptions, DEFAULT_PATH_TOLERANCE_MM};
use swarf_path::{Axes, Canon, CanonSink, FeedMode, Program, Warning};

fn at(x: f64, y: f64, z: f64) -> Axes {
    Axes {
        x,
        y,
        z,
        ..Axes::default()
    }
}

#[test]
fn keys_are_the_contract() {
    let mut b = MoveBuilder::new(Machine::three_axis(), "k.ngc");
    b.warn(Warning {
        file: "k.ngc".into(),
        line: 3,
        column: 1,
        message: "M8 ignored".into(),
    });
    b.emit(
        1,
        &Canon::Feed {
            end: at(1.0, 0.0, 0.0),
        },
    );
    let json = serde_json::to_value(summarize(&b.finish())).unwrap();
    let mut keys: Vec<&str> = json
        .as_object()
        .unwrap()
        .keys()
        .map(String::as_str)
        .collect();
    keys.sort_unstable();
    assert_eq!(
        keys,
        [
            "arc_moves",
            "axis_source",
            "bbox_max",
            "bbox_min",
            "dwell_time_s",
            "feed_bbox_max",
            "feed_bbox_min",
            "feed_length_mm",
            "feed_moves",
            "machine",
            "machining_time_s",
            "moves",
            "notes",
            "path_tolerance_mm",
            "rapid_length_mm",
            "rapid_moves",
            "tools",
            "warnings",
            "zero_length_moves",
        ]
    );
    assert_eq!(json["warnings"][0]["line"], 3);
    assert_eq!(json["warnings"][0]["message"], "M8 ignored");
    assert_eq!(json["axis_source"], "machine");
    assert_eq!(json["machine"], "3axis");
    assert_eq!(json["bbox_max"], serde_json::json!([1.0, 0.0, 0.0]));
    // No feed rate: the move is left out of the time, and a note says so.
    assert_eq!(json["machining_time_s"], 0.0);
    assert_eq!(json["notes"].as_array().unwrap().len(), 1);
}

#[test]
fn empty_program() {
    let s = summarize(&Program::default());
    assert_eq!((s.moves, s.bbox_min, s.bbox_max), (0, None, None));
    assert_eq!(s.path_tolerance_mm, DEFAULT_PATH_TOLERANCE_MM);
    assert!(serde_json::to_value(&s).unwrap()["bbox_min"].is_null());
}

#[test]
fn inverse_time_and_per_revolution_without_spindle() {
    let mut b = MoveBuilder::new(Machine::three_axis(), "t.ngc");
    b.emit(1, &Canon::FeedMode(FeedMode::InverseTime));
    b.emit(2, &Canon::FeedRate(0.5)); // each move takes 2 minutes, whatever its length
    b.emit(
        3,
        &Canon::Feed {
            end: at(1.0, 0.0, 0.0),
        },
    );
    b.emit(
        4,
        &Canon::Feed {
            end: at(1000.0, 0.0, 0.0),
        },
    );
    b.emit(5, &Canon::FeedMode(FeedMode::PerRevolution));
    b.emit(6, &Canon::FeedRate(0.2));
    b.emit(
        7,
        &Canon::Feed {
            end: at(0.0, 0.0, 0.0),
        },
    ); // spindle stopped: no rate
    let s = summarize(&b.finish());
    assert!((s.machining_time_s - 240.0).abs() < 1e-12);
    assert_eq!(s.notes.len(), 1);
    assert!(s.notes[0].starts_with("1 feed move"));
}

#[test]
fn curved_moves_honour_the_tolerance() {
    // Head B/C non-TCP, pivot 100 mm: swinging B 0 → 90 with X Y Z fixed sweeps the tip along a
    // quarter circle of radius 100 about the pivot (0, 0, 100): length 50π.
    let mut b = MoveBuilder::new(Machine::from_name("head-bc").unwrap(), "h.ngc");
    b.emit(1, &Canon::FeedRate(1000.0));
    b.emit(
        2,
        &Canon::Feed {
            end: Axes {
                b: 90.0,
                ..Axes::default()
            },
        },
    );
    let p = b.finish();
    let exact = 50.0 * std::f64::consts::PI;
    let coarse = summarize_with(&p, &SummaryOptions::default().with_tolerance(1.0));
    let fine = summarize_with(&p, &SummaryOptions::default().with_tolerance(1e-6));
    assert_eq!(fine.path_tolerance_mm, 1e-6);
    assert!(
        (fine.feed_length_mm - exact).abs() < 1e-5,
        "{}",
        fine.feed_length_mm
    );
    // Chords are shorter than the arc; the coarse sum is further off but within its tolerance.
    assert!(coarse.feed_length_mm < fine.feed_length_mm);
    assert!(exact - coarse.feed_length_mm < 1.0);
    // B = +90 turns the head about +Y, taking the tool end (below the pivot) towards −X: the tip
    // goes from (0, 0, 0) to (−100, 0, 100).
    let end = p.moves[0].end.tip;
    assert!(
        (end - swarf_geom::math::Vec3::new(-100.0, 0.0, 100.0)).length() < 1e-12,
        "{end}"
    );
    let (lo, hi) = (fine.bbox_min.unwrap(), fine.bbox_max.unwrap());
    assert!((lo[0] + 100.0).abs() < 1e-9 && hi[0].abs() < 1e-9 && (hi[2] - 100.0).abs() < 1e-9);
}

#[test]
fn dwells_are_summed_apart_from_the_feed_time() {
    // G4 P2.5, and a G82 hole with P0.5 twice (L2): 3.5 s of dwells; the feed time is the
    // 10 mm line at 100 mm/min and the two 6 mm plunges at 60.
    let p = read_program_str(
        "G21 G90 G94\nG0 X0 Y0 Z5\nG1 X10 F100\nG4 P2.5\nG91 G82 X5 Y0 Z-6 R-3 P0.5 F60 L2\nG80 G90\nM2\n",
        "t.ngc",
        Machine::three_axis(),
        &ReadOptions::default(),
    )
    .unwrap();
    let s = summarize(&p);
    assert!((s.dwell_time_s - 3.5).abs() < 1e-12, "{}", s.dwell_time_s);
    assert!(
        (s.machining_time_s - (6.0 + 2.0 * 6.0)).abs() < 1e-9,
        "{}",
        s.machining_time_s
    );
}
