//! Machine kinematics: known poses by hand, pivot offsets, TCP, inverse ∘ forward, files.

use proptest::prelude::*;
use swarf_geom::math::Vec3;
use swarf_path::builder::MoveBuilder;
use swarf_path::kinematics::{Machine, MachineError, BUILTIN_NAMES, BUILTIN_PIVOT_LENGTH};
use swarf_path::summary::summarize;
use swarf_path::{Axes, Canon, CanonSink, Pose};

fn j(x: f64, y: f64, z: f64, a: f64, b: f64, c: f64) -> Axes {
    Axes { x, y, z, a, b, c }
}

fn assert_vec(a: Vec3, b: Vec3, what: &str) {
    assert!((a - b).length() < 1e-12, "{what}: {a} vs {b}");
}

#[test]
fn three_axis_is_identity() {
    let m = Machine::from_name("3axis").unwrap();
    let p = m.pose(&j(1.0, 2.0, 3.0, 40.0, 50.0, 60.0));
    assert_vec(p.tip, Vec3::new(1.0, 2.0, 3.0), "tip");
    assert_vec(p.axis, Vec3::Z, "axis");
}

#[test]
fn rotary_tables_by_hand() {
    // Table about X turned +90°: the part's +Z face looks towards −Y, so seen from the part the
    // tool axis is +Y. A point of the part at (0, −5, 0) has come under the tool at (0, 0, −5)…
    // in reverse: the machine point (0, 0, 5) is the part point (0, 5, 0).
    let m = Machine::from_name("4axis-a").unwrap();
    let p = m.pose(&j(0.0, 0.0, 5.0, 90.0, 0.0, 0.0));
    assert_vec(p.axis, Vec3::Y, "A table axis");
    assert_vec(p.tip, Vec3::new(0.0, 5.0, 0.0), "A table tip");
    // Table about Y turned +90°: tool axis −X in the part frame.
    let m = Machine::from_name("4axis-b").unwrap();
    assert_vec(
        m.pose(&j(0.0, 0.0, 0.0, 0.0, 90.0, 0.0)).axis,
        -Vec3::X,
        "B table axis",
    );
    // A/C trunnion, A 90 then C 90: axis = (sin A sin C, sin A cos C, cos A) = +X.
    let m = Machine::from_name("table-ac").unwrap();
    assert_vec(
        m.pose(&j(0.0, 0.0, 0.0, 90.0, 0.0, 90.0)).axis,
        Vec3::X,
        "AC axis",
    );
    // With A = 0 the C table only spins the part: machine point (10, 0, 0) is part point
    // (0, −10, 0) after C = +90.
    let p = m.pose(&j(10.0, 0.0, 0.0, 0.0, 0.0, 90.0));
    assert_vec(p.tip, Vec3::new(0.0, -10.0, 0.0), "C table tip");
}

#[test]
fn reverse_flag_counts_the_other_way() {
    let text = "[[table]]\njoint = \"A\"\nreverse = true\n";
    let m = Machine::from_toml(text, "r.toml", "r").unwrap();
    assert_vec(
        m.pose(&j(0.0, 0.0, 0.0, 90.0, 0.0, 0.0)).axis,
        -Vec3::Y,
        "reversed A",
    );
}

#[test]
fn table_pivot_offset() {
    // A axis 50 mm below the origin: machine (0, 0, 0) with A = 90 is part point (0, 50, −50).
    let text = "[[table]]\njoint = \"A\"\ncenter = [0.0, 0.0, -50.0]\n";
    let m = Machine::from_toml(text, "t.toml", "t").unwrap();
    assert_eq!(m.name, "t");
    let p = m.pose(&j(0.0, 0.0, 0.0, 90.0, 0.0, 0.0));
    assert_vec(p.tip, Vec3::new(0.0, 50.0, -50.0), "offset table tip");
    // TCP: the same joints put the tip at the programmed point.
    let p = m
        .clone()
        .with_tcp(true)
        .pose(&j(0.0, 0.0, 0.0, 90.0, 0.0, 0.0));
    assert_vec(p.tip, Vec3::ZERO, "TCP tip");
    assert_vec(p.axis, Vec3::Y, "TCP axis");
}

#[test]
fn head_pivot_length() {
    // Fork head: pivot L above the tip. A = 90 swings the tip forward to (0, L, L); the axis is
    // −Y and the pivot is L along it from the tip.
    let l = BUILTIN_PIVOT_LENGTH;
    let m = Machine::from_name("head-ac").unwrap();
    let p = m.pose(&j(0.0, 0.0, 0.0, 90.0, 0.0, 0.0));
    assert_vec(p.axis, -Vec3::Y, "head axis");
    assert_vec(p.tip, Vec3::new(0.0, l, l), "head tip");
    assert_vec(p.tip + p.axis * l, Vec3::new(0.0, 0.0, l), "pivot");
    // C first: C = 90 turns the A-tilted head about Z: axis −Y → +X.
    let p = m.pose(&j(0.0, 0.0, 0.0, 90.0, 0.0, 90.0));
    assert_vec(p.axis, Vec3::X, "head C then A");
    // TCP: tip stays at X Y Z.
    let m = Machine::from_name("head-bc-tcp").unwrap();
    let p = m.pose(&j(1.0, 2.0, 3.0, 0.0, 90.0, 0.0));
    assert_vec(p.tip, Vec3::new(1.0, 2.0, 3.0), "TCP head tip");
    assert_vec(p.axis, Vec3::X, "head B axis");
}

#[test]
fn names_and_files() {
    for n in BUILTIN_NAMES {
        assert!(Machine::from_name(n).is_ok());
        assert!(Machine::from_name(&format!("{n}-tcp")).unwrap().tcp);
    }
    assert!(matches!(
        Machine::from_name("6axis"),
        Err(MachineError::UnknownName(_))
    ));
    let bad = [
        "[[table]]\njoint = \"D\"\n",
        "[[table]]\njoint = \"A\"\nwobble = 1\n",
        "[[table]]\njoint = \"A\"\n[[table]]\njoint = \"A\"\ndirection = [0.0, 1.0, 0.0]\n",
        "[[table]]\njoint = \"A\"\n[[head]]\njoint = \"B\"\ndirection = [1.0, 0.0, 0.0]\n",
        "[[table]]\njoint = \"A\"\n[[table]]\njoint = \"B\"\n[[head]]\njoint = \"C\"\n",
        "[[head]]\njoint = \"C\"\ndirection = [0.0, 0.0, 0.0]\n",
    ];
    for text in bad {
        assert!(
            Machine::from_toml(text, "bad.toml", "bad").is_err(),
            "{text}"
        );
    }
    let dir = swarf_testdata::scratch_dir("kin");
    let path = dir.join("mill.toml");
    std::fs::write(
        &path,
        "tcp = true\n[[table]]\njoint = \"B\"\n[[table]]\njoint = \"C\"\n",
    )
    .unwrap();
    let m = Machine::from_file(&path).unwrap();
    assert_eq!((m.name.as_str(), m.tcp, m.table.len()), ("mill", true, 2));
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(matches!(
        Machine::from_file(&dir.join("none.toml")),
        Err(MachineError::Io { .. })
    ));
}

#[test]
fn unreachable_axes_have_no_inverse() {
    let m = Machine::from_name("4axis-a").unwrap();
    // A table about X cannot lean the tool towards X.
    let pose = Pose {
        tip: Vec3::ZERO,
        axis: Vec3::X,
    };
    assert!(m.inverse(&pose, &Axes::default()).is_none());
    assert!(Machine::three_axis()
        .inverse(&pose, &Axes::default())
        .is_none());
}

#[test]
fn singular_pose_keeps_the_free_joint() {
    let m = Machine::from_name("table-ac").unwrap();
    let near = j(0.0, 0.0, 0.0, 0.0, 0.0, 33.0);
    let got = m
        .inverse(
            &Pose {
                tip: Vec3::new(1.0, 2.0, 3.0),
                axis: Vec3::Z,
            },
            &near,
        )
        .unwrap();
    assert!((got.c - 33.0).abs() < 1e-12 && got.a.abs() < 1e-12);
    assert_vec(m.pose(&got).tip, Vec3::new(1.0, 2.0, 3.0), "tip");
}

#[test]
fn joint_interpolation_curves_the_tip() {
    // C table 0 → 90 with the tool fixed at machine (10, 0, 0): in the part frame the tip runs a
    // quarter circle of radius 10, length 5π.
    let mut b = MoveBuilder::new(Machine::from_name("table-ac").unwrap(), "t.ngc");
    b.emit(
        1,
        &Canon::Traverse {
            end: j(10.0, 0.0, 0.0, 0.0, 0.0, 0.0),
        },
    );
    b.emit(2, &Canon::FeedRate(100.0));
    b.emit(
        3,
        &Canon::Feed {
            end: j(10.0, 0.0, 0.0, 0.0, 0.0, 90.0),
        },
    );
    let p = b.finish();
    let m = &p.moves[1];
    for i in 0..=8 {
        let s = f64::from(i) / 8.0;
        let t = p.pose_at(m, s).tip;
        let ang = -s * std::f64::consts::FRAC_PI_2;
        assert_vec(
            t,
            Vec3::new(10.0 * ang.cos(), 10.0 * ang.sin(), 0.0),
            "tip on circle",
        );
    }
    let sum = summarize(&p);
    let exact = 5.0 * std::f64::consts::PI;
    assert!(
        (sum.feed_length_mm - exact).abs() < 1e-3,
        "{}",
        sum.feed_length_mm
    );
    // Bounding box of the quarter circle from (10, 0) to (0, −10), within the tolerance.
    let (lo, hi) = (sum.feed_bbox_min.unwrap(), sum.feed_bbox_max.unwrap());
    assert!((lo[1] + 10.0).abs() < 1e-9 && (hi[0] - 10.0).abs() < 1e-9 && hi[1].abs() < 1e-9);
    // A purely rotary G94 move: the feed applies to the 90° of C, as LinuxCNC does.
    assert!((sum.machining_time_s - 90.0 / 100.0 * 60.0).abs() < 1e-9);
    assert_eq!(sum.notes.len(), 1);
    // With TCP the tip stays put and only the axis turns.
    let mut b = MoveBuilder::new(Machine::from_name("table-ac-tcp").unwrap(), "t.ngc");
    b.emit(
        1,
        &Canon::Traverse {
            end: j(10.0, 0.0, 0.0, 0.0, 0.0, 0.0),
        },
    );
    b.emit(
        2,
        &Canon::Feed {
            end: j(10.0, 0.0, 0.0, 45.0, 0.0, 90.0),
        },
    );
    let p = b.finish();
    let mid = p.pose_at(&p.moves[1], 0.5);
    assert_vec(mid.tip, Vec3::new(10.0, 0.0, 0.0), "TCP tip");
    assert_vec(
        mid.axis,
        p.machine.pose(&j(10.0, 0.0, 0.0, 22.5, 0.0, 45.0)).axis,
        "TCP axis",
    );
}

fn angle_close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-7
}

proptest! {
    #![proptest_config(swarf_testdata::proptest_config(256))]
    /// inverse ∘ forward is the identity for every built-in machine, TCP or not, away from the
    /// singular tilt (where the free joint keeps the hint's value, tested above).
    #[test]
    fn inverse_of_forward_is_identity(
        name in prop::sample::select(BUILTIN_NAMES.to_vec()),
        tcp in any::<bool>(),
        x in -500.0f64..500.0, y in -500.0f64..500.0, z in -500.0f64..500.0,
        a in -170.0f64..170.0, b in -170.0f64..170.0, c in -170.0f64..170.0,
    ) {
        let m = Machine::from_name(name).unwrap().with_tcp(tcp);
        // Joints the machine has; the others stay 0 (they do not act).
        let words: Vec<_> = m.table.iter().chain(&m.head).map(|j| j.word).collect();
        let has = |w| words.iter().any(|&v| format!("{v:?}") == w);
        let joints = j(x, y, z,
            if has("A") { a } else { 0.0 },
            if has("B") { b } else { 0.0 },
            if has("C") { c } else { 0.0 });
        let pose = m.pose(&joints);
        // Stay away from the gimbal singularity of the two-rotary machines.
        prop_assume!(words.len() < 2 || pose.axis.z.abs() < 1.0 - 1e-4);
        let back = m.inverse(&pose, &joints).unwrap();
        prop_assert!((back.x - x).abs() < 1e-8 && (back.y - y).abs() < 1e-8 && (back.z - z).abs() < 1e-8,
            "{back:?} vs {joints:?}");
        prop_assert!(angle_close(back.a, joints.a) && angle_close(back.b, joints.b) && angle_close(back.c, joints.c),
            "{back:?} vs {joints:?}");
        // The other branch of a 5-axis solution is a valid answer too: hinted from far away it
        // gives the same pose.
        let other = m.inverse(&pose, &Axes::default()).unwrap();
        let again = m.pose(&other);
        prop_assert!((again.tip - pose.tip).length() < 1e-8 && (again.axis - pose.axis).length() < 1e-9);
    }
}
