//! Spline feeds as the LinuxCNC G-code manual defines them ("G5 Cubic spline", "G5.1
//! Quadratic B-spline", "G5.2 G5.3 NURBS Block"): the exact curve in the canonical events,
//! flattened within the tolerance in the move stream.

use swarf_path::canon::Recorder;
use swarf_path::canonical::CanonicalPrinter;
use swarf_path::gcode::{read_gcode, GcodeOptions};
use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::spline::SplineKind;
use swarf_path::{Canon, Machine, MoveKind, Program};

fn program(src: &str) -> Program {
    read_program_str(src, "s.ngc", Machine::three_axis(), &ReadOptions::default()).unwrap()
}

fn splines(src: &str) -> Vec<(SplineKind, Vec<[f64; 3]>)> {
    let mut rec = Recorder::default();
    read_gcode(src, "s.ngc", &GcodeOptions::default(), &mut rec).unwrap();
    rec.events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::Spline { kind, controls, .. } => Some((*kind, controls.to_vec())),
            _ => None,
        })
        .collect()
}

#[test]
fn quadratic_spline_is_flattened_within_the_tolerance() {
    let src = "G21 G17 G0 X0 Y0\nG5.1 X10 Y0 I5 J5 F100\nM2\n";
    assert_eq!(
        splines(src),
        vec![(
            SplineKind::Quadratic,
            vec![[5.0, 5.0, 1.0], [10.0, 0.0, 1.0]]
        )]
    );
    let p = program(src);
    let feeds: Vec<_> = p.moves.iter().skip(1).collect();
    assert!(feeds.len() > 10);
    assert!(feeds.iter().all(|m| m.kind == MoveKind::Linear));
    let end = feeds.last().unwrap().end.tip;
    assert!((end.x - 10.0).abs() < 1e-12 && end.y.abs() < 1e-12);
    // The curve is the parabola y = x (10 − x) / 10 (control point (5, 5)); every piece's
    // midpoint is within 0.001 mm of it, below it (the curve is concave).
    for m in &feeds {
        let mid = (m.start.tip + m.end.tip) / 2.0;
        let on = mid.x * (10.0 - mid.x) / 10.0;
        assert!(on - mid.y >= -1e-9 && on - mid.y <= 1e-3 + 1e-9, "{mid:?}");
    }
}

#[test]
fn cubic_spline_without_ij_continues_smoothly() {
    let src = "G21 G0 X0 Y0\nG5 X10 Y0 I0 J5 P0 Q5 F100\nG5 X20 Y0 P0 Q-5\nM2\n";
    let s = splines(src);
    assert_eq!(s.len(), 2);
    // The second spline's first control point mirrors the first's second one about (10, 0).
    assert_eq!(s[1].1[0], [10.0, -5.0, 1.0]);
    let mut out = CanonicalPrinter::new(Vec::new());
    read_gcode(src, "s.ngc", &GcodeOptions::default(), &mut out).unwrap();
    let text = String::from_utf8(out.finish().unwrap()).unwrap();
    // As rs274 2.9 prints them: the number of control points with the start, and dots.
    assert_eq!(
        text.matches(" N..... NURBS_FEED(4, ...)\n").count(),
        2,
        "{text}"
    );
    let src = "G21 G0 X0 Y0\nG5.1 X3 Y2 I0.5 J1 F100\nG0 X0 Y0\nG5.2 X0 Y1 P1 L3\nX2 Y2 P1\n\
        X2 Y0 P1\nX0 Y0 P2\nG5.3\nM2\n";
    let mut out = CanonicalPrinter::new(Vec::new());
    read_gcode(src, "s.ngc", &GcodeOptions::default(), &mut out).unwrap();
    let text = String::from_utf8(out.finish().unwrap()).unwrap();
    let nurbs: Vec<&str> = text.lines().filter(|l| l.contains("NURBS")).collect();
    assert_eq!(
        nurbs,
        [" N..... NURBS_FEED(3, ...)", " N..... NURBS_FEED(5, ...)"]
    );
}

#[test]
fn nurbs_quarter_circle_stays_on_the_circle() {
    // The rational quadratic quarter circle of radius 10: middle weight √½.
    let src =
        "G21 G0 X10 Y0\nG5.2 X10 Y10 P0.7071067811865476 L3 F100\nX0 Y10 P1\nG5.3\nG0 X0 Y0\nM2\n";
    let p = program(src);
    let arc: Vec<_> = p.moves[1..p.moves.len() - 1].iter().collect();
    assert!(arc.len() > 10);
    for m in &arc {
        let r = m.end.tip.truncate().length();
        assert!((r - 10.0).abs() < 1e-9, "{r}");
        let mid = ((m.start.tip + m.end.tip) / 2.0).truncate().length();
        assert!(10.0 - mid <= 1e-3 + 1e-9);
    }
    let end = arc.last().unwrap().end.tip;
    assert!(end.x.abs() < 1e-12 && (end.y - 10.0).abs() < 1e-12);
}

#[test]
fn spline_errors_name_their_line() {
    let read = |src: &str| {
        read_gcode(
            src,
            "s.ngc",
            &GcodeOptions::default(),
            &mut Recorder::default(),
        )
        .unwrap_err()
    };
    let e = read("G0 X0 Y0\nG5 X1 Y1 P0 Q0 F10\n");
    assert_eq!((e.pos.line, e.pos.column), (2, 1));
    assert!(e.message.contains("I and J"), "{e}");
    let e = read("G18\nG5.1 X1 Y1 I1 J1 F10\n");
    assert!(e.message.contains("XY plane"), "{e}");
    let e = read("G5.2 X1 Y1 F10\nX2 Y2\nG1 X3\n");
    assert_eq!(e.pos.line, 3);
    assert!(e.message.contains("G5.3"), "{e}");
}

/// LinuxCNC's checks on spline words (`convert_nurbs`, `convert_spline`): a NURBS has at
/// least as many control points as its order, each with both X and Y; G5.1's control point is
/// not its start.
#[test]
fn invalid_splines_are_refused_as_linuxcnc_refuses_them() {
    let read = |src: &str| {
        read_gcode(
            src,
            "s.ngc",
            &GcodeOptions::default(),
            &mut Recorder::default(),
        )
    };
    // The start is the first control point: with n G5.2 points a NURBS has n + 1, refused
    // at G5.3 below its order (L3, L4).
    for order in [3_usize, 4] {
        for n in 1..=order {
            let points: String = (1..n).map(|k| format!("X{k} Y{k} P1\n")).collect();
            let src = format!("G21 G90 F100\nG0 X0 Y0\nG5.2 X0 Y1 P1 L{order}\n{points}G5.3\nM2\n");
            let r = read(&src);
            if n + 1 < order {
                let e = r.unwrap_err();
                assert_eq!((e.pos.line, e.pos.column), (3 + n as u32, 1), "{e}");
                assert!(
                    e.message.contains(&format!("has {} control points", n + 1))
                        && e.message.contains(&format!("order L = {order}")),
                    "{e}"
                );
            } else {
                assert!(r.is_ok(), "L{order}, {n} points: {r:?}");
            }
        }
    }
    // A control point with X but no Y (and the other way round), at the word given.
    let e =
        read("G21 G90 F100\nG0 X0 Y0\nG5.2 X1 Y1 P1 L3\nX2 P1\nX3 Y0 P1\nG5.3\nM2\n").unwrap_err();
    assert_eq!((e.pos.line, e.pos.column), (4, 1), "{e}");
    assert!(e.message.contains("both X and Y"), "{e}");
    let e = read("G21 G90 F100\nG0 X0 Y0\nG5.2 Y1 P1 L3\nG5.3\nM2\n").unwrap_err();
    assert_eq!((e.pos.line, e.pos.column), (3, 6), "{e}");
    assert!(e.message.contains("both X and Y"), "{e}");
    // G5.1 whose control point is its start.
    let e = read("G21 G90 F100\nG0 X0 Y0\nG5.1 I0 J0 X10 Y0\nM2\n").unwrap_err();
    assert_eq!((e.pos.line, e.pos.column), (3, 6), "{e}");
    assert!(e.message.contains("I0 J0"), "{e}");
    assert!(read("G21 G90 F100\nG0 X0 Y0\nG5.1 I0 J1 X10 Y0\nM2\n").is_ok());
}
