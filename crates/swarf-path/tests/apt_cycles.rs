//! APT canned cycles (`CYCLE/DRILL` and kin) expanded into the motion a controller makes: every
//! expected move below is worked out by hand from the cycle's definition (module docs of
//! `swarf_path::apt::cycle`), not recorded from the reader.

use swarf_path::{Canon, FeedMode, PathErrorKind};

mod common;
use common::{apt_err as err, apt_events as events};

/// The motion only: `R` for a rapid, `F` for a feed, `D` for a dwell, `f` for a feed rate.
#[derive(Debug, PartialEq)]
enum M {
    R(f64, f64, f64),
    F(f64, f64, f64),
    D(f64),
    Rate(f64),
}

fn motion(text: &str) -> Vec<M> {
    events(text)
        .into_iter()
        .filter_map(|e| match e {
            Canon::Traverse { end: a } => Some(M::R(a.x, a.y, a.z)),
            Canon::Feed { end: a } => Some(M::F(a.x, a.y, a.z)),
            Canon::Dwell(t) => Some(M::D(t)),
            Canon::FeedRate(f) => Some(M::Rate(f)),
            _ => None,
        })
        .collect()
}

/// `got` and `want` equal to 1e-9 mm.
fn same(got: &[M], want: &[M]) {
    let close = |a: &M, b: &M| {
        let d = |p: [f64; 3], q: [f64; 3]| p.iter().zip(q).all(|(u, v)| (u - v).abs() < 1e-9);
        match (a, b) {
            (M::R(x, y, z), M::R(u, v, w)) | (M::F(x, y, z), M::F(u, v, w)) => {
                d([*x, *y, *z], [*u, *v, *w])
            }
            (M::D(s), M::D(t)) | (M::Rate(s), M::Rate(t)) => (s - t).abs() < 1e-9,
            _ => false,
        }
    };
    assert!(
        got.len() == want.len() && got.iter().zip(want).all(|(a, b)| close(a, b)),
        "got  {got:?}\nwant {want:?}"
    );
}

/// NX's keyword form: FEDTO a signed depth below the hole's top, RAPTO the clearance above it,
/// RTRCTO,AUTO back to the level the tool came from; the cycle's feed for the feed moves only.
#[test]
fn keyword_form_drills_each_goto_and_restores_the_feed() {
    let got = motion(
        "FEDRAT/MMPM,500\nGOTO/0,0,50\nCYCLE/DRILL,FEDTO,-12,RAPTO,3,RTRCTO,AUTO,MMPM,100\n\
         GOTO/10,20,0,0,0,1\nGOTO/30,20,5\nCYCLE/OFF\nGOTO/0,0,50\n",
    );
    use M::*;
    same(
        &got,
        &[
            Rate(500.0),
            // Hole 1: over at the tool's level (50), down to 3 above the top, in to 12 below.
            R(10.0, 20.0, 50.0),
            R(10.0, 20.0, 3.0),
            Rate(100.0),
            F(10.0, 20.0, -12.0),
            R(10.0, 20.0, 50.0),
            Rate(500.0),
            // Hole 2, its top at 5: the tool's level is 45 above it.
            R(30.0, 20.0, 50.0),
            R(30.0, 20.0, 8.0),
            Rate(100.0),
            F(30.0, 20.0, -7.0),
            R(30.0, 20.0, 50.0),
            Rate(500.0),
            // After CYCLE/OFF a GOTO is a move again.
            F(0.0, 0.0, 50.0),
        ],
    );
}

/// APT's positional form `CYCLE/DRILL,d,IPM,f,c`, in inches: converted; out to the clearance
/// (the default retract); a positive depth is the same bottom as a signed one.
#[test]
fn positional_form_in_inches() {
    let got = motion("UNITS/INCHES\nGOTO/0,0,2\nCYCLE/DRILL,0.5,IPM,4,0.1\nGOTO/1,1,0\n");
    use M::*;
    same(
        &got,
        &[
            R(25.4, 25.4, 50.8),
            R(25.4, 25.4, 2.54),
            Rate(101.6),
            F(25.4, 25.4, -12.7),
            R(25.4, 25.4, 2.54),
            // No FEDRAT/ before the cycle: no feed in force after the hole.
            Rate(0.0),
        ],
    );
}

/// A hole on a tilted tool axis is drilled along that axis; the tool below the clearance level
/// first rises along the axis.
#[test]
fn tilted_hole_along_the_goto_axis() {
    let got = motion(
        "GOTO/0,0,0.5,0.6,0,0.8\nCYCLE/DRILL,FEDTO,5,RAPTO,2\nGOTO/0,0,0,0.6,0,0.8\nCYCLE/OFF\n",
    );
    use M::*;
    // The tool stands 0.5 along Z above the top: 0.4 along the axis, under the clearance 2.
    let a = [0.6, 0.0, 0.8];
    let up = 2.0 - 0.4;
    same(
        &got,
        &[
            R(a[0] * up, 0.0, 0.5 + a[2] * up),
            R(a[0] * 2.0, 0.0, a[2] * 2.0),
            F(-a[0] * 5.0, 0.0, -a[2] * 5.0),
            R(a[0] * 2.0, 0.0, a[2] * 2.0),
        ],
    );
    // The axis is stated before the hole.
    assert!(
        events("GOTO/0,0,10\nCYCLE/DRILL,FEDTO,5\nGOTO/0,0,0,0.6,0,0.8\n")
            .contains(&Canon::ToolAxis([0.6, 0.0, 0.8]))
    );
}

/// DEEP pecks back to the clearance (G83), BRKCHP a short way (G73), both stopping 0.254 mm
/// above the depth already drilled; TAP, BORE and REAM feed out; DWELL at the bottom.
#[test]
fn pecking_feeding_out_and_dwell() {
    use M::*;
    let deep = motion("GOTO/0,0,10\nCYCLE/DEEP,FEDTO,-10,RAPTO,2,STEP,4\nGOTO/0,0,0\n");
    same(
        &deep,
        &[
            R(0.0, 0.0, 2.0),
            F(0.0, 0.0, -2.0),
            R(0.0, 0.0, 2.0),
            R(0.0, 0.0, -1.746),
            F(0.0, 0.0, -6.0),
            R(0.0, 0.0, 2.0),
            R(0.0, 0.0, -5.746),
            F(0.0, 0.0, -10.0),
            R(0.0, 0.0, 2.0),
        ],
    );
    // NX's second step (for the later pecks) is read past; the modifier after DRILL.
    let chip = motion("GOTO/0,0,10\nCYCLE/DRILL,BRKCHP,FEDTO,-10,RAPTO,2,STEP,4,3\nGOTO/0,0,0\n");
    same(
        &chip,
        &[
            R(0.0, 0.0, 2.0),
            F(0.0, 0.0, -2.0),
            R(0.0, 0.0, -1.746),
            F(0.0, 0.0, -6.0),
            R(0.0, 0.0, -5.746),
            F(0.0, 0.0, -10.0),
            R(0.0, 0.0, 2.0),
        ],
    );
    let tap = motion("GOTO/0,0,10\nCYCLE/TAP,FEDTO,-8,RAPTO,2,RTRCTO,AUTO,DWELL,0.5\nGOTO/0,0,0\n");
    same(
        &tap,
        &[
            R(0.0, 0.0, 2.0),
            F(0.0, 0.0, -8.0),
            D(0.5),
            F(0.0, 0.0, 2.0),
            R(0.0, 0.0, 10.0),
        ],
    );
    // RTRCTO to a height of its own.
    let out = motion("GOTO/0,0,10\nCYCLE/REAM,FEDTO,-8,RAPTO,2,RTRCTO,5\nGOTO/0,0,0\n");
    same(
        &out,
        &[
            R(0.0, 0.0, 2.0),
            F(0.0, 0.0, -8.0),
            F(0.0, 0.0, 2.0),
            R(0.0, 0.0, 5.0),
        ],
    );
}

/// CYCLE/ON restarts the last cycle after an OFF; a per-revolution cycle feed switches the
/// feed mode and back.
#[test]
fn cycle_on_and_feed_modes() {
    let got = motion(
        "GOTO/0,0,10\nCYCLE/DRILL,FEDTO,-1,RAPTO,1\nCYCLE/OFF\nGOTO/5,0,10\nCYCLE/ON\nGOTO/5,0,0\n",
    );
    use M::*;
    same(
        &got,
        &[
            F(5.0, 0.0, 10.0),
            R(5.0, 0.0, 1.0),
            F(5.0, 0.0, -1.0),
            R(5.0, 0.0, 1.0),
        ],
    );
    // Without a FEDRAT/ before it, the cycle's feed does not stay in force after the hole.
    let got = motion("GOTO/0,0,10\nCYCLE/DRILL,FEDTO,-1,MMPM,50\nGOTO/0,0,0\n");
    assert_eq!(got.last(), Some(&M::Rate(0.0)), "{got:?}");
    let e = events("FEDRAT/MMPM,300\nGOTO/0,0,10\nCYCLE/DRILL,FEDTO,-1,MMPR,0.1\nGOTO/0,0,0\n");
    let modes: Vec<_> = e
        .iter()
        .filter_map(|e| match e {
            Canon::FeedMode(m) => Some(*m),
            _ => None,
        })
        .collect();
    assert_eq!(modes, [FeedMode::PerRevolution, FeedMode::PerMinute]);
}

/// What cannot be expanded is an error at its field, never a silently missing hole.
#[test]
fn cycles_that_cannot_be_expanded_are_errors_at_their_field() {
    let e = err("GOTO/0,0,5\nCYCLE/MILL,5,MMPM,100\nGOTO/10,10,0\n");
    assert_eq!(e.kind, PathErrorKind::Unsupported);
    assert_eq!((e.pos.line, e.pos.column), (2, 7));
    assert!(e.message.contains("CYCLE/MILL"), "{}", e.message);
    let e = err("GOTO/0,0,5\nCYCLE/DRILL,RAPTO,3\n");
    assert!(e.message.contains("without a depth"), "{}", e.message);
    let e = err("GOTO/0,0,5\nCYCLE/DRILL,RAPTO,3,FEDTO\n");
    assert_eq!((e.pos.line, e.pos.column), (2, 21));
    assert!(
        e.message.contains("FEDTO without its value"),
        "{}",
        e.message
    );
    let e = err("GOTO/0,0,5\nCYCLE/DRILL,FEDTO,3,SIDEWAYS,2\n");
    assert_eq!((e.pos.line, e.pos.column), (2, 21));
    let e = err("GOTO/0,0,5\nCYCLE/DRILL,5,2,1\n");
    assert_eq!((e.pos.line, e.pos.column), (2, 17));
    // A peck cycle's third bare number is its step: the same motion as STEP,4.
    assert_eq!(
        motion("GOTO/0,0,10\nCYCLE/DEEP,10,2,4,MMPM,100\nGOTO/0,0,0\n"),
        motion("GOTO/0,0,10\nCYCLE/DEEP,FEDTO,10,RAPTO,2,STEP,4,MMPM,100\nGOTO/0,0,0\n")
    );
    let e = err("GOTO/0,0,5\nCYCLE/DEEP,5,2,0\n");
    assert!(e.message.contains("peck"), "{}", e.message);
    let e = err("GOTO/0,0,5\nCYCLE/DEEP,5,2,1,1\n");
    assert_eq!((e.pos.line, e.pos.column), (2, 18));
    let e = err("GOTO/0,0,5\nCYCLE/ON\n");
    assert!(e.message.contains("CYCLE/ON"), "{}", e.message);
    let e = err("GOTO/0,0,5\nCYCLE/DEEP,FEDTO,5,STEP,0\n");
    assert!(e.message.contains("peck"), "{}", e.message);
    // A clearance or a retract height below the hole's bottom, at its field.
    let e = err("GOTO/0,0,5\nCYCLE/DRILL,FEDTO,5,RAPTO,-8\n");
    assert_eq!((e.pos.line, e.pos.column), (2, 27));
    let e = err("GOTO/0,0,5\nCYCLE/DRILL,5,-6\n");
    assert_eq!((e.pos.line, e.pos.column), (2, 15));
    let e = err("GOTO/0,0,5\nCYCLE/DRILL,FEDTO,5,RTRCTO,-5.5\n");
    assert_eq!((e.pos.line, e.pos.column), (2, 28));
    assert!(
        e.message.contains("below the hole's bottom"),
        "{}",
        e.message
    );
    // CYCLE/OFF alone changes nothing.
    assert_eq!(
        motion("GOTO/0,0,5\nCYCLE/OFF\nGOTO/1,0,5\n"),
        [M::F(1.0, 0.0, 5.0)]
    );
}

proptest::proptest! {
    /// The hole's bottom is `top − depth·axis` whatever the approach: random holes, axes and
    /// starts. The deepest point a feed reaches along the axis is the bottom, and the tool
    /// ends at the clearance level above the top.
    #[test]
    fn every_hole_reaches_its_bottom_and_no_deeper(
        (x, y, z) in (-50.0..50.0f64, -50.0..50.0f64, -10.0..10.0f64),
        (i, j) in (-0.7..0.7f64, -0.7..0.7f64),
        (d, c, s, start) in (0.1..30.0f64, 0.0..10.0f64, 0.5..8.0f64, -20.0..60.0f64),
        kind in 0usize..4,
    ) {
        let k = (1.0 - i * i - j * j).sqrt();
        let kinds = ["DRILL", "DEEP", "BRKCHP", "BORE"];
        let text = format!(
            "GOTO/0,0,{start}\nCYCLE/{},FEDTO,{d},RAPTO,{c},STEP,{s}\n\
             GOTO/{x},{y},{z},{i},{j},{k}\n",
            kinds[kind]
        );
        let got = motion(&text);
        let (top, axis) = ([x, y, z], [i, j, k]);
        let h = |p: [f64; 3]| (0..3).map(|n| (p[n] - top[n]) * axis[n]).sum::<f64>();
        let lowest = got
            .iter()
            .filter_map(|m| match m {
                M::F(a, b, c) => Some(h([*a, *b, *c])),
                _ => None,
            })
            .fold(f64::INFINITY, f64::min);
        proptest::prop_assert!((lowest + d).abs() < 1e-9, "lowest {}, depth {}", lowest, d);
        let end = got.iter().rev().find_map(|m| match m {
            M::R(a, b, c) | M::F(a, b, c) => Some([*a, *b, *c]),
            _ => None,
        });
        proptest::prop_assert!(end.is_some_and(|e| (h(e) - c).abs() < 1e-9));
    }
}

/// Hostile numbers: a peck step that would make 10³⁰⁰ pecks, and distances beyond the machine's
/// range, are errors at their fields, not endless loops or moves off the map.
#[test]
fn hostile_steps_and_distances_are_refused() {
    let e = err("GOTO/0,0,10\nCYCLE/DEEP,FEDTO,10,RAPTO,2,STEP,1e-300\nGOTO/0,0,0\n");
    assert_eq!((e.pos.line, e.pos.column), (2, 34));
    assert!(e.message.contains("pecks"), "{}", e.message);
    let e = err("GOTO/0,0,10\nCYCLE/DRILL,FEDTO,1e300\nGOTO/0,0,0\n");
    assert_eq!((e.pos.line, e.pos.column), (2, 19));
    assert!(e.message.contains("machine range"), "{}", e.message);
    let e = err("GOTO/0,0,10\nCYCLE/DRILL,5,-2e6\n");
    assert_eq!((e.pos.line, e.pos.column), (2, 15));
    // 100,000 pecks are allowed (12 mm in 0.12 µm steps is not a real program, but not hostile).
    assert!(
        motion("GOTO/0,0,10\nCYCLE/DEEP,FEDTO,10,RAPTO,2,STEP,0.001\nGOTO/0,0,0\n").len() > 30_000
    );
}
