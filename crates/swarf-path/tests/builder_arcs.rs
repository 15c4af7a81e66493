//! MoveBuilder on hand-written canonical events (independent of the G-code reader): arcs in
//! the three planes, helices, full and multi-turn circles, offsets, lengths, bounding boxes and
//! machining time, against values worked out by hand.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use proptest::prelude::*;
use swarf_geom::math::Vec3;
use swarf_path::builder::MoveBuilder;
use swarf_path::kinematics::Machine;
use swarf_path::summary::summarize;
use swarf_path::{ArcGeom, Axes, Canon, CanonSink, FeedMode, MoveKind, Plane, Program};

fn at(x: f64, y: f64, z: f64) -> Axes {
    Axes {
        x,
        y,
        z,
        ..Axes::default()
    }
}

/// Builds a program: a rapid to `start`, then the events.
fn program(start: Axes, events: &[Canon<'static>]) -> Program {
    let mut b = MoveBuilder::new(Machine::three_axis(), "t.ngc");
    b.emit(1, &Canon::Traverse { end: start });
    for (i, e) in events.iter().enumerate() {
        b.emit(u32::try_from(i).unwrap() + 2, e);
    }
    b.finish()
}

fn arc(p: &Program, i: usize) -> ArcGeom {
    match p.moves[i].kind {
        MoveKind::Arc(g) => g,
        k => panic!("move {i} is {k:?}"),
    }
}

fn assert_vec(a: Vec3, b: Vec3, tol: f64, what: &str) {
    assert!((a - b).length() <= tol, "{what}: {a} vs {b}");
}

/// The sampled tip matches the move's ends and lies on the arc's circle or helix.
fn check_samples(p: &Program, i: usize) {
    let m = &p.moves[i];
    let g = arc(p, i);
    assert_vec(p.pose_at(m, 0.0).tip, m.start.tip, 1e-9, "s = 0");
    assert_vec(p.pose_at(m, 1.0).tip, m.end.tip, 1e-9, "s = 1");
    let h0 = g.normal.dot(m.start.tip - g.center);
    for k in 0..=64 {
        let s = f64::from(k) / 64.0;
        let d = p.pose_at(m, s).tip - g.center;
        let h = g.normal.dot(d);
        let radial = (d - g.normal * h).length();
        let rho = g.start_radius + s * (g.end_radius - g.start_radius);
        assert!(
            (radial - rho).abs() < 1e-9,
            "radius at {s}: {radial} vs {rho}"
        );
        assert!((h - h0 - s * g.helix).abs() < 1e-9, "height at {s}");
    }
}

#[test]
fn arcs_in_the_three_planes() {
    let cases = [
        // (plane, start, end, centre, rotation, normal, sweep)
        (
            Plane::XY,
            at(10.0, 0.0, 0.0),
            at(0.0, 10.0, 0.0),
            [0.0, 0.0],
            1,
            Vec3::Z,
            FRAC_PI_2,
        ),
        (
            Plane::XY,
            at(10.0, 0.0, 0.0),
            at(0.0, 10.0, 0.0),
            [0.0, 0.0],
            -1,
            -Vec3::Z,
            3.0 * FRAC_PI_2,
        ),
        // G18: centre given as (Z, X); counter-clockwise about +Y takes +X towards −Z.
        (
            Plane::XZ,
            at(10.0, 0.0, 0.0),
            at(0.0, 0.0, -10.0),
            [0.0, 0.0],
            1,
            Vec3::Y,
            FRAC_PI_2,
        ),
        (
            Plane::XZ,
            at(10.0, 0.0, 0.0),
            at(0.0, 0.0, -10.0),
            [0.0, 0.0],
            -1,
            -Vec3::Y,
            3.0 * FRAC_PI_2,
        ),
        // G19: centre (Y, Z); counter-clockwise about +X takes +Y towards +Z.
        (
            Plane::YZ,
            at(0.0, 10.0, 0.0),
            at(0.0, 0.0, 10.0),
            [0.0, 0.0],
            1,
            Vec3::X,
            FRAC_PI_2,
        ),
        (
            Plane::YZ,
            at(0.0, 10.0, 0.0),
            at(0.0, 0.0, 10.0),
            [0.0, 0.0],
            -1,
            -Vec3::X,
            3.0 * FRAC_PI_2,
        ),
    ];
    for (plane, start, end, center, rotation, normal, sweep) in cases {
        let p = program(
            start,
            &[Canon::Arc {
                end,
                center,
                rotation,
                plane,
            }],
        );
        let g = arc(&p, 1);
        assert_vec(g.normal, normal, 0.0, "normal");
        assert!(
            (g.sweep - sweep).abs() < 1e-12,
            "{plane:?} {rotation}: {}",
            g.sweep
        );
        assert_eq!((g.start_radius, g.end_radius, g.helix), (10.0, 10.0, 0.0));
        assert_vec(g.center, Vec3::ZERO, 0.0, "centre");
        assert!((g.length() - 10.0 * sweep).abs() < 1e-12);
        check_samples(&p, 1);
        let s = summarize(&p);
        assert!((s.feed_length_mm - 10.0 * sweep).abs() < 1e-12);
    }
}

#[test]
fn helix_multi_turn_and_full_circle() {
    // G2 helix, one full turn, 5 mm up: the normal is −Z so the travel along it is −5.
    let p = program(
        at(10.0, 0.0, 0.0),
        &[Canon::Arc {
            end: at(10.0, 0.0, 5.0),
            center: [0.0, 0.0],
            rotation: -1,
            plane: Plane::XY,
        }],
    );
    let g = arc(&p, 1);
    assert!((g.sweep - TAU).abs() < 1e-15);
    assert_eq!(g.helix, -5.0);
    assert!((summarize(&p).feed_length_mm - (TAU * 10.0).hypot(5.0)).abs() < 1e-12);
    check_samples(&p, 1);
    // Three turns (P3) ending a quarter turn on: 2 extra full turns.
    let p = program(
        at(10.0, 0.0, 0.0),
        &[Canon::Arc {
            end: at(0.0, 10.0, -6.0),
            center: [0.0, 0.0],
            rotation: 3,
            plane: Plane::XY,
        }],
    );
    let g = arc(&p, 1);
    assert!((g.sweep - (FRAC_PI_2 + 2.0 * TAU)).abs() < 1e-12);
    check_samples(&p, 1);
    let s = summarize(&p);
    assert!((s.feed_length_mm - (g.sweep * 10.0).hypot(6.0)).abs() < 1e-12);
    assert_eq!(s.feed_bbox_min.unwrap()[2], -6.0);
    // A full circle about (3, 4): the box is the centre ± r, exactly.
    let p = program(
        at(13.0, 4.0, 2.0),
        &[Canon::Arc {
            end: at(13.0, 4.0, 2.0),
            center: [3.0, 4.0],
            rotation: 1,
            plane: Plane::XY,
        }],
    );
    check_samples(&p, 1);
    let s = summarize(&p);
    assert_eq!(s.feed_bbox_min, Some([-7.0, -6.0, 2.0]));
    assert_eq!(s.feed_bbox_max, Some([13.0, 14.0, 2.0]));
    assert_eq!(s.zero_length_moves, 0);
    assert!((s.feed_length_mm - 20.0 * PI).abs() < 1e-12);
}

#[test]
fn quarter_arc_box_has_only_the_extremes_it_passes() {
    // From 45° to 135° about the origin, r = 10: the top (0, 10) is inside, the sides are not.
    let r = 10.0 * std::f64::consts::FRAC_1_SQRT_2;
    let p = program(
        at(r, r, 0.0),
        &[Canon::Arc {
            end: at(-r, r, 0.0),
            center: [0.0, 0.0],
            rotation: 1,
            plane: Plane::XY,
        }],
    );
    let s = summarize(&p);
    let (lo, hi) = (s.feed_bbox_min.unwrap(), s.feed_bbox_max.unwrap());
    assert!((lo[0] + r).abs() < 1e-12 && (hi[0] - r).abs() < 1e-12);
    assert!((lo[1] - r).abs() < 1e-12 && (hi[1] - 10.0).abs() < 1e-12);
}

#[test]
fn offsets_feeds_tools_and_time() {
    let g54 = Axes {
        x: 100.0,
        y: 0.0,
        z: -50.0,
        ..Axes::default()
    };
    let mut b = MoveBuilder::new(Machine::three_axis(), "t.ngc");
    b.emit(
        1,
        &Canon::Offsets {
            index: 1,
            g5x: g54,
            g92: Axes {
                y: 1.0,
                ..Axes::default()
            },
        },
    );
    b.emit(2, &Canon::ToolChange { tool: 4 });
    b.emit(
        3,
        &Canon::CutterDefinition([6.0, 0.0, 0.0, 0.0, 0.0, 0.0, 30.0]),
    );
    b.emit(
        4,
        &Canon::Traverse {
            end: at(0.0, 0.0, 0.0),
        },
    );
    b.emit(5, &Canon::FeedRate(100.0));
    b.emit(
        6,
        &Canon::Feed {
            end: at(30.0, 40.0, 0.0),
        },
    ); // 50 mm at 100 mm/min: 30 s
    b.emit(
        7,
        &Canon::Feed {
            end: at(30.0, 40.0, 0.0),
        },
    ); // zero length
    b.emit(8, &Canon::FeedMode(FeedMode::InverseTime));
    b.emit(9, &Canon::FeedRate(4.0));
    b.emit(
        10,
        &Canon::Feed {
            end: at(0.0, 0.0, 0.0),
        },
    ); // 1/4 min: 15 s
    b.emit(11, &Canon::FeedMode(FeedMode::PerRevolution));
    b.emit(
        12,
        &Canon::Spindle {
            rpm: 1000.0,
            dir: swarf_path::SpindleDir::Clockwise,
        },
    );
    b.emit(13, &Canon::FeedRate(0.1));
    b.emit(
        14,
        &Canon::Feed {
            end: at(50.0, 0.0, 0.0),
        },
    ); // 100 mm/min: 30 s
    b.emit(15, &Canon::FeedMode(FeedMode::PerMinute));
    b.emit(16, &Canon::FeedRate(0.0));
    b.emit(
        17,
        &Canon::Feed {
            end: at(60.0, 0.0, 0.0),
        },
    ); // F0: left out, noted
    let p = b.finish();
    assert_eq!(p.moves.len(), 6);
    assert_vec(
        p.moves[0].end.tip,
        Vec3::new(100.0, 1.0, -50.0),
        0.0,
        "offsets applied",
    );
    assert_eq!(
        p.moves[0].end_joints,
        Axes {
            x: 100.0,
            y: 1.0,
            z: -50.0,
            ..Axes::default()
        }
    );
    assert_eq!(
        (p.moves[1].line, p.moves[1].tool, p.moves[1].feed),
        (6, 4, 100.0)
    );
    assert_eq!(
        p.cutter_definitions,
        vec![(4, [6.0, 0.0, 0.0, 0.0, 0.0, 0.0, 30.0])]
    );
    let s = summarize(&p);
    // The rapid starts where the tool stands on the machine (its origin: the offsets came
    // after the tool was there) and ends at the offset program origin; one zero-length move,
    // the repeated feed.
    assert_vec(p.moves[0].start.tip, Vec3::ZERO, 0.0, "start stays put");
    assert_eq!(
        (
            s.moves,
            s.rapid_moves,
            s.feed_moves,
            s.arc_moves,
            s.zero_length_moves
        ),
        (6, 1, 5, 0, 1)
    );
    assert!(
        (s.machining_time_s - 75.0).abs() < 1e-12,
        "{}",
        s.machining_time_s
    );
    assert!((s.feed_length_mm - 160.0).abs() < 1e-12);
    assert_eq!(s.tools, vec![4]);
    assert_eq!(s.notes.len(), 1, "{:?}", s.notes);
    let json = serde_json::to_value(&s).unwrap();
    for key in [
        "moves",
        "rapid_moves",
        "feed_moves",
        "arc_moves",
        "feed_length_mm",
        "rapid_length_mm",
        "bbox_min",
        "bbox_max",
        "tools",
        "warnings",
        "machining_time_s",
    ] {
        assert!(json.get(key).is_some(), "{key}");
    }
}

/// Pushes a polyline of feed moves.
fn polyline(points: &[[f64; 3]], feed: f64) -> Program {
    let mut b = MoveBuilder::new(Machine::three_axis(), "p.ngc");
    b.emit(1, &Canon::FeedRate(feed));
    b.emit(
        1,
        &Canon::Traverse {
            end: at(points[0][0], points[0][1], points[0][2]),
        },
    );
    for (i, q) in points[1..].iter().enumerate() {
        b.emit(
            u32::try_from(i).unwrap() + 2,
            &Canon::Feed {
                end: at(q[0], q[1], q[2]),
            },
        );
    }
    b.finish()
}

fn pt() -> impl Strategy<Value = [f64; 3]> {
    [-100.0f64..100.0, -100.0f64..100.0, -100.0f64..100.0]
}

proptest! {
    #![proptest_config(swarf_testdata::proptest_config(128))]
    #[test]
    fn polyline_lengths_and_boxes(points in prop::collection::vec(pt(), 2..20), feed in 1.0f64..5000.0, k in 0usize..18) {
        let p = polyline(&points, feed);
        let s = summarize(&p);
        let total: f64 = points.windows(2).map(|w| Vec3::from_array(w[0]).distance(Vec3::from_array(w[1]))).sum();
        prop_assert!((s.feed_length_mm - total).abs() <= 1e-9 * total.max(1.0));
        prop_assert!((s.machining_time_s - total / feed * 60.0).abs() <= 1e-9 * s.machining_time_s.max(1.0));
        let (lo, hi) = (Vec3::from_array(s.bbox_min.unwrap()), Vec3::from_array(s.bbox_max.unwrap()));
        for m in &p.moves {
            for i in 0..=10 {
                let q = p.pose_at(m, f64::from(i) / 10.0).tip;
                prop_assert!(q.cmpge(lo - 1e-12).all() && q.cmple(hi + 1e-12).all());
            }
        }
        // Splitting one segment at its midpoint changes neither length nor box.
        let k = k % (points.len() - 1);
        let mid = (Vec3::from_array(points[k]) + Vec3::from_array(points[k + 1])) * 0.5;
        let mut split = points.clone();
        split.insert(k + 1, mid.to_array());
        let s2 = summarize(&polyline(&split, feed));
        prop_assert!((s2.feed_length_mm - s.feed_length_mm).abs() <= 1e-9 * total.max(1.0));
        prop_assert_eq!(s2.bbox_min, s.bbox_min);
        prop_assert_eq!(s2.bbox_max, s.bbox_max);
        prop_assert_eq!(s2.feed_moves, s.feed_moves + 1);
    }

    /// Random arcs: ends sampled exactly, and the summary box is the box of a dense sampling up
    /// to the sampling's own chordal error (so a missed or spurious extreme fails).
    #[test]
    fn arc_boxes_are_tight(
        c in [-50.0f64..50.0, -50.0f64..50.0],
        r in 0.5f64..40.0,
        a0 in -PI..PI, a1 in -PI..PI,
        rotation in prop::sample::select(vec![-3, -2, -1, 1, 2, 3]),
        plane in prop::sample::select(vec![Plane::XY, Plane::XZ, Plane::YZ]),
        h0 in -20.0f64..20.0, dh in -20.0f64..20.0,
    ) {
        let (i1, i2, n) = plane.axes();
        let mut s = [0.0; 3];
        let mut e = [0.0; 3];
        s[i1] = c[0] + r * a0.cos(); s[i2] = c[1] + r * a0.sin(); s[n] = h0;
        e[i1] = c[0] + r * a1.cos(); e[i2] = c[1] + r * a1.sin(); e[n] = h0 + dh;
        let p = program(Axes::from_array([s[0], s[1], s[2], 0.0, 0.0, 0.0]),
            &[Canon::Arc { end: Axes::from_array([e[0], e[1], e[2], 0.0, 0.0, 0.0]), center: c, rotation, plane }]);
        let m = &p.moves[1];
        prop_assert!((p.pose_at(m, 0.0).tip - m.start.tip).length() < 1e-9);
        prop_assert!((p.pose_at(m, 1.0).tip - m.end.tip).length() < 1e-9);
        let g = arc(&p, 1);
        let sm = summarize(&p);
        let (lo, hi) = (Vec3::from_array(sm.feed_bbox_min.unwrap()), Vec3::from_array(sm.feed_bbox_max.unwrap()));
        let steps = (g.sweep / TAU * 1440.0).ceil() as usize + 2;
        let (mut slo, mut shi) = (Vec3::splat(f64::INFINITY), Vec3::splat(f64::NEG_INFINITY));
        for i in 0..=steps {
            let q = p.pose_at(m, i as f64 / steps as f64).tip;
            prop_assert!(q.cmpge(lo - 1e-9).all() && q.cmple(hi + 1e-9).all(), "{q} outside {lo} {hi}");
            slo = slo.min(q); shi = shi.max(q);
        }
        let chord = r * (1.0 - (PI / 1440.0).cos()) + 1e-9;
        prop_assert!((slo - lo).abs().max_element() <= chord && (shi - hi).abs().max_element() <= chord,
            "box {lo} {hi} vs sampled {slo} {shi}");
        let len = (g.sweep * r).hypot(dh);
        prop_assert!((sm.feed_length_mm - len).abs() < 1e-9 * len.max(1.0));
    }
}

proptest! {
    #![proptest_config(swarf_testdata::proptest_config(128))]
    /// Arcs about arbitrary axes (APT `CIRCLE/`), spiralling a little (end radius ≠ start
    /// radius, the Newton-polished case): the box is that of a dense sampling up to its
    /// chordal error.
    #[test]
    fn general_axis_spiral_boxes(
        n in [-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0],
        c in [-50.0f64..50.0, -50.0f64..50.0, -50.0f64..50.0],
        r in 1.0f64..40.0,
        a1 in 0.01f64..6.2,
        grow in -1e-3f64..1e-3,
        dh in -10.0f64..10.0,
        turns in 1u32..3,
    ) {
        let n = Vec3::from_array(n);
        prop_assume!(n.length() > 0.1);
        let n = n.normalize();
        let u = n.any_orthonormal_vector();
        let v = n.cross(u);
        let c = Vec3::from_array(c);
        let start = c + u * r;
        let end = c + (u * a1.cos() + v * a1.sin()) * (r * (1.0 + grow)) + n * dh;
        let to = |p: Vec3| Axes::from_array([p.x, p.y, p.z, 0.0, 0.0, 0.0]);
        let p = program(to(start), &[Canon::ArcAxis { end: to(end), center: c.to_array(), normal: n.to_array(), turns }]);
        let m = &p.moves[1];
        let g = arc(&p, 1);
        prop_assert!((g.sweep - (a1 + f64::from(turns - 1) * TAU)).abs() < 1e-9);
        prop_assert!((p.pose_at(m, 1.0).tip - end).length() < 1e-9);
        let sm = summarize(&p);
        let (lo, hi) = (Vec3::from_array(sm.feed_bbox_min.unwrap()), Vec3::from_array(sm.feed_bbox_max.unwrap()));
        let steps = (g.sweep / TAU * 1440.0).ceil() as usize + 2;
        let (mut slo, mut shi) = (Vec3::splat(f64::INFINITY), Vec3::splat(f64::NEG_INFINITY));
        for i in 0..=steps {
            let q = p.pose_at(m, i as f64 / steps as f64).tip;
            prop_assert!(q.cmpge(lo - 1e-9).all() && q.cmple(hi + 1e-9).all(), "{q} outside {lo} {hi}");
            slo = slo.min(q);
            shi = shi.max(q);
        }
        let chord = 1.01 * r * (1.0 - (PI / 1440.0).cos()) + 1e-9;
        prop_assert!((slo - lo).abs().max_element() <= chord && (shi - hi).abs().max_element() <= chord,
            "box {lo} {hi} vs sampled {slo} {shi}");
    }
}
