//! The G-code language as swarf reads it, scenario by scenario: arcs, units, distance modes,
//! offsets, parameters and expressions, control flow, subprograms, limits, dialects and error
//! positions.

use std::time::{Duration, Instant};

use swarf_path::canon::{OwnedCanon, Recorder};
use swarf_path::gcode::{read_gcode, GcodeOptions};
use swarf_path::{Axes, Canon, MessageKind, PathError, PathErrorKind, Plane};

fn run_with(src: &str, opts: &GcodeOptions) -> Result<Recorder, PathError> {
    let mut rec = Recorder::default();
    read_gcode(src, "t.ngc", opts, &mut rec)?;
    Ok(rec)
}

fn run(src: &str) -> Recorder {
    run_with(src, &GcodeOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

fn err(src: &str) -> PathError {
    run_with(src, &GcodeOptions::default()).expect_err("should fail")
}

/// The texts of the messages (`MSG`, `DEBUG`, `PRINT` comments), in order.
fn message_texts(rec: &Recorder) -> Vec<String> {
    rec.events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::Message { text, .. } => Some(text.to_string()),
            _ => None,
        })
        .collect()
}

/// The motion events only.
fn motion(rec: &Recorder) -> Vec<OwnedCanon> {
    rec.events
        .iter()
        .filter(|(_, e)| {
            matches!(
                e,
                Canon::Traverse { .. } | Canon::Feed { .. } | Canon::Arc { .. }
            )
        })
        .map(|(_, e)| e.clone())
        .collect()
}

fn end_of(e: &OwnedCanon) -> Axes {
    match e {
        Canon::Traverse { end } | Canon::Feed { end } | Canon::Arc { end, .. } => *end,
        _ => panic!("not a move: {e:?}"),
    }
}

/// Where each move ends, X Y Z.
fn tip_ends(rec: &Recorder) -> Vec<[f64; 3]> {
    motion(rec)
        .iter()
        .map(|e| {
            let a = end_of(e);
            [a.x, a.y, a.z]
        })
        .collect()
}

fn last_pos(rec: &Recorder) -> Axes {
    end_of(motion(rec).last().expect("a move"))
}

fn assert_xyz(a: Axes, x: f64, y: f64, z: f64) {
    assert!(
        (a.x - x).abs() < 1e-9 && (a.y - y).abs() < 1e-9 && (a.z - z).abs() < 1e-9,
        "got ({}, {}, {}), want ({x}, {y}, {z})",
        a.x,
        a.y,
        a.z
    );
}

fn arc(e: &OwnedCanon) -> (Axes, [f64; 2], i32, Plane) {
    match e {
        Canon::Arc {
            end,
            center,
            rotation,
            plane,
        } => (*end, *center, *rotation, *plane),
        _ => panic!("not an arc: {e:?}"),
    }
}

#[test]
fn initial_events_state_units_offsets_plane() {
    let rec = run("");
    assert_eq!(rec.events[0].1, Canon::Units(swarf_path::Units::Mm));
    assert!(matches!(rec.events[1].1, Canon::Offsets { index: 1, .. }));
    assert_eq!(rec.events[2].1, Canon::XyRotation(0.0));
    assert_eq!(rec.events[3].1, Canon::Plane(Plane::XY));
    assert_eq!(rec.warnings.len(), 1, "no program end is reported");
}

#[test]
fn arcs_ijk_both_directions_and_full_circle() {
    let rec = run("G0 X10 Y0\nG3 X0 Y10 I-10 J0 F100\nG2 X10 Y0 I0 J-10\nG2 X10 Y0 I-10\nM2");
    let m = motion(&rec);
    let (end, c, rot, plane) = arc(&m[1]);
    assert_xyz(end, 0.0, 10.0, 0.0);
    assert_eq!((c, rot, plane), ([0.0, 0.0], 1, Plane::XY));
    let (_, c, rot, _) = arc(&m[2]);
    assert_eq!((c, rot), ([0.0, 0.0], -1));
    let (end, c, rot, _) = arc(&m[3]);
    assert_xyz(end, 10.0, 0.0, 0.0);
    assert_eq!((c, rot), ([0.0, 0.0], -1), "end = start: a full circle");
}

#[test]
fn arcs_r_form_signs_and_errors() {
    let rec = run("G0 X10 Y0\nG2 X0 Y10 R10 F100\nG0 X10 Y0\nG2 X0 Y10 R-10\n");
    let m = motion(&rec);
    let (_, c, rot, _) = arc(&m[1]);
    assert!(
        (c[0] - 10.0).abs() < 1e-9 && (c[1] - 10.0).abs() < 1e-9,
        "short cw arc bulges away from the origin: {c:?}"
    );
    assert_eq!(rot, -1);
    let (_, c, _, _) = arc(&m[3]);
    assert!(
        c[0].abs() < 1e-9 && c[1].abs() < 1e-9,
        "negative R: the long way round: {c:?}"
    );
    let e = err("G0 X10 Y0\nG2 X10 Y0 R5 F100\n");
    assert_eq!((e.kind, e.pos.line), (PathErrorKind::Semantic, 2));
    assert!(e.message.contains("same as the end point"), "{e}");
    let e = err("G2 X30 Y0 R5 F100\n");
    assert!(e.message.contains("too small"), "{e}");
}

#[test]
fn helix_turns_and_planes() {
    let rec = run(
        "G0 X10 Y0 Z0\nG3 X10 Y0 Z-3 I-10 P3 F100\nG18 G2 Z17 X10 K10 I0\nG19 G3 Y10 Z7 J0 K-10\n",
    );
    let m = motion(&rec);
    let (end, c, rot, plane) = arc(&m[1]);
    assert_xyz(end, 10.0, 0.0, -3.0);
    assert_eq!((c, rot, plane), ([0.0, 0.0], 3, Plane::XY));
    // G18: first axis Z, second X; from (x10, z-3) centre = (z-3+10, x10+0).
    let (end, c, rot, plane) = arc(&m[2]);
    assert_xyz(end, 10.0, 0.0, 17.0);
    assert_eq!((c, rot, plane), ([7.0, 10.0], -1, Plane::XZ));
    // G19: first Y, second Z; from (y0, z17), centre (y0, z7).
    let (end, c, _, plane) = arc(&m[3]);
    assert_xyz(end, 10.0, 10.0, 7.0);
    assert_eq!((c, plane), ([0.0, 7.0], Plane::YZ));
}

#[test]
fn arc_radius_mismatch_is_an_error_with_linuxcnc_tolerance() {
    // 0.015 mm off on 10 mm: accepted. 0.05 mm off: rejected.
    run("G0 X10 Y0\nG3 X0 Y10.015 I-10 F100\n");
    let e = err("G0 X10 Y0\nG3 X0 Y10.05 I-10 F100\n");
    assert_eq!(
        (e.kind, e.pos.line, e.pos.column),
        (PathErrorKind::Semantic, 2, 1)
    );
    assert!(e.message.contains("radius to end of arc differs"), "{e}");
    // In inches the absolute tolerance is 0.002 in = 0.0508 mm: 0.0015 in off on 1 in passes.
    run("G20 G0 X1 Y0\nG3 X0 Y1.0015 I-1 F10\n");
    assert!(run_with(
        "G20 G0 X1 Y0\nG3 X0 Y1.003 I-1 F10\n",
        &GcodeOptions::default()
    )
    .is_err());
    // Missing words: the R form needs its end point (rs274: "X and y words missing for arc in
    // xy plane"); with a centre and no end point in the plane the arc is a full circle, as
    // rs274 2.9 reads LinuxCNC's own 3dtest.ngc (`G2 I.5 J.5`).
    assert!(err("G0 X1\nG2 R1 F10\n")
        .message
        .contains("X and Y words missing"));
    let rec = run("G21 G0 X1 Y1\nG2 I.5 J.5 F100\nG91 G3 I1 Z-1\n");
    let arcs: Vec<_> = rec
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::Arc {
                end,
                center,
                rotation,
                ..
            } => Some((end.x, end.y, end.z, center[0], center[1], *rotation)),
            _ => None,
        })
        .collect();
    assert_eq!(
        arcs,
        [(1.0, 1.0, 0.0, 1.5, 1.5, -1), (1.0, 1.0, -1.0, 2.0, 1.0, 1)]
    );
    assert!(err("G2 X1 F10\n").message.contains("I and J words missing"));
    assert!(err("G2 X1 I1 K1 F10\n").message.contains("K word given"));
    assert!(err("G2 X1 I1 R1 F10\n")
        .message
        .contains("both R and I/J/K"));
}

#[test]
fn absolute_arc_centres_g90_1() {
    let rec = run("G90.1 G0 X10 Y0\nG3 X0 Y10 I0 J0 F100\n");
    let (_, c, _, _) = arc(&motion(&rec)[1]);
    assert_eq!(c, [0.0, 0.0]);
}

#[test]
fn units_and_distance_modes() {
    let rec = run("G20 G0 X1 Y2\nG91 G1 X1 F10\nG21 X1\nG90 G1 Z-1\n");
    let m = motion(&rec);
    assert_xyz(end_of(&m[0]), 25.4, 50.8, 0.0);
    assert_xyz(end_of(&m[1]), 50.8, 50.8, 0.0);
    assert_xyz(end_of(&m[2]), 51.8, 50.8, 0.0);
    assert_xyz(end_of(&m[3]), 51.8, 50.8, -1.0);
    // Feed in inches per minute becomes mm per minute.
    assert!(rec.events.iter().any(|(_, e)| *e == Canon::FeedRate(254.0)));
}

#[test]
fn work_offsets_g54_g55_g10_g92_and_g53() {
    let rec = run(
        "G10 L2 P2 X100 Y50\nG0 X1 Y1\nG55\nG0 X1\nG92 X0 Y0\nG1 X1 F10\nG53 G0 X0 Y0\nG92.1\nG54\nG10 L20 P1 X5\nG0 X5\n",
    );
    let m = motion(&rec);
    // Positions are in the current coordinate system.
    assert_xyz(end_of(&m[0]), 1.0, 1.0, 0.0);
    // After G55 the tool has not moved: machine (1, 1) is program (-99, -49).
    assert_xyz(end_of(&m[1]), 1.0, -49.0, 0.0);
    assert_xyz(end_of(&m[2]), 1.0, 0.0, 0.0);
    // G53 X0 Y0 is machine zero: program = −G55 − G92 = (−100 − 1, −50 − (−49)).
    assert_xyz(end_of(&m[3]), -101.0, -1.0, 0.0);
    let offsets: Vec<_> = rec
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::Offsets { index, g5x, g92 } => Some((*index, *g5x, *g92)),
            _ => None,
        })
        .collect();
    assert_eq!(offsets[1].0, 2);
    assert_eq!((offsets[1].1.x, offsets[1].1.y), (100.0, 50.0));
    assert_eq!((offsets[2].2.x, offsets[2].2.y), (1.0, -49.0));
    assert_eq!(offsets[3].2, Axes::default(), "G92.1 clears G92");
    // Back in G54 at machine (0, 0), G10 L20 P1 X5 makes that point X5: G54 x offset = −5.
    let (_, g5x, _) = offsets[5];
    assert_eq!(g5x.x, -5.0);
    assert_xyz(end_of(m.last().unwrap()), 5.0, 0.0, 0.0);
    assert!(err("G91 G53 G0 X0\n").message.contains("incremental"));
}

#[test]
fn g28_goes_through_the_intermediate_point_to_the_stored_position() {
    let rec = run("G0 X5 Y5 Z5\nG28.1\nG0 X0 Y0 Z0\nG28 Z2\nG28\n#5161=7\nG28 X1\n");
    let m = motion(&rec);
    assert_xyz(end_of(&m[2]), 0.0, 0.0, 2.0);
    assert_xyz(end_of(&m[3]), 0.0, 0.0, 5.0);
    // G28 alone: through the current point (LinuxCNC's zero-length traverse), then home.
    assert_xyz(end_of(&m[4]), 0.0, 0.0, 5.0);
    assert_xyz(end_of(&m[5]), 5.0, 5.0, 5.0);
    assert_xyz(end_of(&m[6]), 1.0, 5.0, 5.0);
    assert_xyz(end_of(&m[7]), 7.0, 5.0, 5.0);
}

#[test]
fn tool_length_and_spindle_events() {
    let rec = run("T3 M6\nS1200 M3\nG43 H3\nG43.1 Z2.5\nG49\nM5\nG4 P0.5\n");
    let ev: Vec<_> = rec.events.iter().map(|(_, e)| e.clone()).collect();
    assert!(ev.contains(&Canon::ToolChange { tool: 3 }));
    assert!(ev.contains(&Canon::Spindle {
        rpm: 1200.0,
        dir: swarf_path::SpindleDir::Clockwise
    }));
    assert!(ev.contains(&Canon::ToolLengthOffset(2.5)));
    assert!(ev.contains(&Canon::Spindle {
        rpm: 1200.0,
        dir: swarf_path::SpindleDir::Stopped
    }));
    assert!(ev.contains(&Canon::Dwell(0.5)));
    assert!(rec.warnings.iter().any(|w| w.message.contains("H3")));
    assert!(
        motion(&rec).is_empty(),
        "tool-tip programs: G43 moves nothing"
    );
}

#[test]
fn coolant_and_unknown_m_codes_warn_with_position() {
    let rec = run("G21 G0 X1 M8\nM428\nM9\nM2\n");
    let w: Vec<_> = rec
        .warnings
        .iter()
        .map(|w| (w.line, w.column, w.message.clone()))
        .collect();
    assert_eq!(w.len(), 3, "{w:?}");
    assert_eq!((w[0].0, w[0].1), (1, 11));
    assert!(w[1].2.contains("M428"));
}

#[test]
fn cutter_compensation_needs_the_tool_radius() {
    // G41 D1 takes tool 1's diameter from the tool table (LinuxCNC: the D word names a tool).
    let e = err("G0 X0\nG1 F10 g41 D1 X1\n");
    assert_eq!(
        (e.kind, e.pos.line, e.pos.column),
        (PathErrorKind::Semantic, 2, 12)
    );
    assert!(e.message.contains("diameter of tool 1"), "{e}");
    run("G40 G64 G94 G97 G17 G80\n");
    // G10 L1 P1 R2 gives it (LinuxCNC's tool table radius), in program units, and #5410 reads
    // the loaded tool's diameter: the straight cut along X runs 2 mm to its left (+Y); the
    // inch program's R0.1 is 2.54 mm, read back as 0.2 in.
    let rec = run("G21 G10 L1 P1 R2\nT1 M6\n(debug,#5410)\nG0 X0 Y0\nG1 F10 G41 X10\nG1 X20\nG40 G1 X30\nM2\n");
    let ends: Vec<[f64; 6]> = motion(&rec).iter().map(|e| end_of(e).to_array()).collect();
    assert!(
        ends.iter()
            .any(|e| (e[0] - 20.0).abs() < 1e-9 && (e[1] - 2.0).abs() < 1e-9),
        "{ends:?}"
    );
    assert!(
        rec.messages().iter().any(|m| m == "4.000000"),
        "{:?}",
        rec.messages()
    );
    // #5410 reads the tool table's diameter, kept in the machine's units (the parameter
    // units; G10 converts R on the way in): 0.2 in on an inch machine, 5.08 mm on a mm one.
    let rec = run_with(
        "G20 G10 L1 P1 R0.1\nT1 M6\n(debug,#5410)\nM2\n",
        &GcodeOptions::default().with_parameter_units(swarf_path::Units::Inch),
    )
    .unwrap();
    assert!(
        rec.messages().iter().any(|m| m == "0.200000"),
        "{:?}",
        rec.messages()
    );
    let rec = run("G20 G10 L1 P1 R0.1\nT1 M6\n(debug,#5410)\nM2\n");
    assert!(
        rec.messages().iter().any(|m| m == "5.080000"),
        "{:?}",
        rec.messages()
    );
    let e = err("G21 G10 L1 P1 R-1\n");
    assert_eq!((e.pos.line, e.pos.column), (1, 15), "{e}");
}

#[test]
fn inverse_time_needs_f_on_every_feed_move() {
    let rec = run("G93 G1 X1 F2\nG1 X2 F3\n");
    assert_eq!(motion(&rec).len(), 2);
    let e = err("G93 G1 X1 F2\nG1 X2\n");
    assert_eq!(e.pos.line, 2);
    let e = err("G1 X1\n");
    assert!(e.message.contains("zero feed"), "{e}");
}

#[test]
fn canned_cycles_retract_to_r_until_g98() {
    // LinuxCNC's interpreter starts in G99: from Z5, a G81 with R1 retracts to Z1 and goes
    // to the next hole there; after G98 back to the Z of the cycle's start.
    let rec =
        run("G21 F100 G0 X0 Y0 Z5\nG81 X1 Y1 Z-2 R1\nX2\nG80\nG0 Z5\nG98 G81 X3 Z-2 R1\nM2\n");
    let zs: Vec<f64> = motion(&rec).iter().map(|e| end_of(e).z).collect();
    assert_eq!(
        zs,
        [5.0, 5.0, 1.0, -2.0, 1.0, 1.0, -2.0, 1.0, 5.0, 5.0, 1.0, -2.0, 5.0],
        "{zs:?}"
    );
}

#[test]
fn canned_cycles_peck_and_other_planes() {
    // G83 Z-1 R1 Q0.4 from Z5: pecks at 0.6, 0.2, -0.2, -0.6, then the bottom.
    let rec = run("F100 G0 Z5\nG98 G83 X1 Y1 Z-1 R1 Q0.4\n");
    let m = motion(&rec);
    let zs: Vec<f64> = m.iter().map(|e| end_of(e).z).collect();
    let d = 0.254;
    let want = [
        5.0,
        5.0,
        1.0,
        0.6,
        1.0,
        0.6 + d,
        0.2,
        1.0,
        0.2 + d,
        -0.2,
        1.0,
        -0.2 + d,
        -0.6,
        1.0,
        -0.6 + d,
        -1.0,
        5.0,
    ];
    assert_eq!(zs.len(), want.len(), "{zs:?}");
    for (g, w) in zs.iter().zip(want) {
        assert!((g - w).abs() < 1e-9, "{zs:?}");
    }
    // G18 (drilling along Y) G82 with dwell, repeated with only X on the next line.
    let rec = run("F100 G18 G0 Y5\nG99 G82 X1 Z2 Y-1 R1 P0.5\nX3\nG80\n");
    let m = motion(&rec);
    let ends: Vec<_> = m.iter().map(end_of).map(|a| (a.x, a.y, a.z)).collect();
    assert_eq!(
        ends[1..],
        [
            (1.0, 5.0, 2.0),
            (1.0, 1.0, 2.0),
            (1.0, -1.0, 2.0),
            (1.0, 1.0, 2.0),
            (3.0, 1.0, 2.0),
            (3.0, -1.0, 2.0),
            (3.0, 1.0, 2.0)
        ]
    );
    assert_eq!(
        rec.events
            .iter()
            .filter(|(_, e)| *e == Canon::Dwell(0.5))
            .count(),
        2
    );
    let e = err("F100 G0 Z0\nG81 X1 Z1 R0.5\n");
    assert!(e.message.contains("R less than Z"), "{e}");
    assert!(err("F100 G81 X1 R1\n")
        .message
        .contains("Z value unspecified"));
    assert!(err("G80 X1\n").message.contains("G80"));
    assert!(err("G0 X0\nG80\nX1\n").message.contains("without a motion"));
}

#[test]
fn parameters_take_effect_after_the_line() {
    let rec = run("#1=1\n#1=2 #2=#1\nG0 X#1 Y#2\n");
    let m = motion(&rec);
    assert_xyz(end_of(&m[0]), 2.0, 1.0, 0.0);
    // rs274 2.9 defines #<a> (0) when it reads `#<a>=`, so the rest of the line reads 0
    // (it printed STRAIGHT_TRAVERSE(0.0000, …) for this line).
    let rec = run("#1=1\n#<a>=3 G0 X#<a> Y1\n");
    assert_xyz(end_of(&motion(&rec)[0]), 0.0, 1.0, 0.0);
    let e = err("#1=1\n#<b>=3 G0 X#<a>\n");
    assert_eq!(
        (e.pos.line, e.pos.column, e.found.as_str()),
        (2, 12, "#<a>")
    );
    assert!(e.message.contains("not defined"));
}

#[test]
fn expressions_and_predefined_parameters() {
    let rec =
        run("G0 X[1+2*3] Y[2**3**2/64] Z[ATAN[1]/[1]]\nG0 X[#<_x>+1] Y#5421\nG20\nG0 X[#<_x>]\n");
    let m = motion(&rec);
    assert_xyz(end_of(&m[0]), 7.0, 1.0, 45.0);
    assert_xyz(end_of(&m[1]), 8.0, 1.0, 45.0);
    assert!(
        (end_of(&m[2]).x - 8.0).abs() < 1e-12,
        "#<_x> reads program units"
    );
    let e = err("G0 X[1/0]\n");
    assert_eq!((e.pos.column, e.kind), (7, PathErrorKind::Semantic));
}

#[test]
fn control_flow_while_do_repeat_if_break_continue() {
    let src = "\
#1=0
o10 while [#1 LT 5]
  #1=[#1+1]
  o11 if [#1 EQ 2]
    o10 continue
  o11 elseif [#1 EQ 4]
    G0 X[#1*100]
  o11 else
    G0 X#1
  o11 endif
o10 endwhile
o20 do
  G0 Y#1
  #1=[#1-2]
o20 while [#1 GT 0]
o30 repeat [3]
  G0 Z#1
  #1=[#1+1]
o30 endrepeat
M2
";
    let rec = run(src);
    let got: Vec<(f64, f64, f64)> = motion(&rec)
        .iter()
        .map(end_of)
        .map(|a| (a.x, a.y, a.z))
        .collect();
    let want = vec![
        (1.0, 0.0, 0.0),
        (3.0, 0.0, 0.0),
        (400.0, 0.0, 0.0),
        (5.0, 0.0, 0.0),
        (5.0, 5.0, 0.0),
        (5.0, 3.0, 0.0),
        (5.0, 1.0, 0.0),
        (5.0, 1.0, -1.0),
        (5.0, 1.0, 0.0),
        (5.0, 1.0, 1.0),
    ];
    assert_eq!(got, want);
    // A break out of a repeat loop: rs274 2.9 refuses it ("no matching while/do label"), at
    // the break's line, with the moves before it made.
    let src = src.replace(
        "  #1=[#1+1]\no30 endrepeat",
        "  #1=[#1+1]\n  o40 if [#1 GE 2]\n    o30 break\n  o40 endif\no30 endrepeat",
    );
    let e = err(&src);
    assert_eq!(e.pos.line, 20, "{e}");
    assert!(e.message.contains("while/do"), "{e}");
}

#[test]
fn subroutines_with_arguments_locals_and_return_values() {
    let src = "\
o<square> sub
  #<half> = [#1 / 2]
  G1 X#<half> Y#2 F100
  o<square> return [#1 * #1]
o<square> endsub
#1 = 7
#<half> = 99
o<square> call [4] [5]
G0 X#<_value> Y#1 Z#<half>
o100 call [3]
G0 X#<_value>
M30
o100 sub
  o<square> call [#1 + 1]
o100 endsub [#<_value> + 1]
";
    let rec = run(src);
    let got: Vec<(f64, f64, f64)> = motion(&rec)
        .iter()
        .map(end_of)
        .map(|a| (a.x, a.y, a.z))
        .collect();
    assert_eq!(
        got,
        vec![
            (2.0, 5.0, 0.0),
            (16.0, 7.0, 99.0),
            (2.0, 0.0, 99.0),
            (17.0, 0.0, 99.0)
        ]
    );
    assert!(err("o<nope> call\n").message.contains("not defined"));
    assert!(err("o1 return\n").message.contains("outside"));
}

#[test]
fn fanuc_m98_m99_subprograms() {
    let src = "%\nO0001\nG91 F100\nM98 P1000 L3\nG90 G0 X0\nM30\n\nO1000 (SUB)\nG1 X1\nM99\n%\n";
    let rec = run(src);
    let xs: Vec<f64> = motion(&rec).iter().map(|e| end_of(e).x).collect();
    assert_eq!(xs, vec![1.0, 2.0, 3.0, 0.0]);
    assert!(err("M98 P5\n").message.contains("O5"));
}

/// Counts events without keeping them: hostile programs can emit millions before a limit.
#[derive(Default)]
struct Counter(u64);
impl swarf_path::CanonSink for Counter {
    fn emit(&mut self, _: u32, _: &Canon<'_>) {
        self.0 += 1;
    }
    fn warn(&mut self, _: swarf_path::Warning) {}
}

fn limit(src: &str, opts: &GcodeOptions) -> PathError {
    let mut c = Counter::default();
    let e = read_gcode(src, "t.ngc", opts, &mut c).expect_err("should hit a limit");
    assert_eq!(e.kind, PathErrorKind::Limit, "{e}");
    e
}

#[test]
fn infinite_loop_ends_with_the_default_limit() {
    let t = Instant::now();
    let e = limit("o1 while [1]\no1 endwhile\n", &GcodeOptions::default());
    assert_eq!(e.pos.line, 2);
    assert!(
        e.message.contains("loop iterations") && !e.message.contains("GcodeOptions"),
        "{e}"
    );
    assert!(t.elapsed() < Duration::from_secs(30), "{:?}", t.elapsed());
}

#[test]
fn hostile_programs_end_quickly_with_limit_errors() {
    let t = Instant::now();
    let opts = GcodeOptions::default().with_max_loop_iterations(200_000);
    let e = limit("o1 sub\no1 call\no1 endsub\no1 call\n", &opts);
    assert!(e.message.contains("deep"), "{e}");
    // Doubly recursive: the depth stays low, the call count explodes.
    limit("o1 sub\no2 if [#1 LT 40]\no1 call [#1+1]\no1 call [#1+1]\no2 endif\no1 endsub\no1 call [0]\n", &opts);
    limit("o1 do\no1 while [1]\n", &opts);
    limit("o1 repeat [1000000000000]\no1 endrepeat\n", &opts);
    limit("F1 G81 X1 Z-1 R1 L100000000\n", &opts);
    limit("F1 G83 X1 Z-1000000 R1 Q0.000001\n", &opts);
    limit("F1 G73 X1 Z-1000000 R1 Q0.000001\n", &opts);
    limit("M98 P1 L1000000\nM30\nO1\nM98 P1\nM99\n", &opts);
    limit(
        "M98 P1 L1000\nM30\nO1\nG0 X1\nM99\n",
        &opts.clone().with_max_loop_iterations(500),
    );
    limit(
        &format!("G0 X{}1{}\n", "[".repeat(100_000), "]".repeat(100_000)),
        &opts,
    );
    assert!(t.elapsed() < Duration::from_secs(10), "{:?}", t.elapsed());
}

#[test]
fn loops_around_long_skipped_blocks_stay_fast() {
    // Each iteration skips 20 000 lines of a false `if`: a rescan per iteration would take
    // 10^9 line reads.
    let body = "G1 X1\n".repeat(20_000);
    let src = format!("#1=0\no1 while [#1 LT 50000]\n#1=[#1+1]\no2 if [0]\n{body}o2 endif\no1 endwhile\nG0 X#1\nM2\n");
    let t = Instant::now();
    let mut c = Counter::default();
    read_gcode(&src, "t.ngc", &GcodeOptions::default(), &mut c).unwrap();
    assert!(t.elapsed() < Duration::from_secs(10), "{:?}", t.elapsed());
    let rec = run(&src);
    assert_eq!(last_pos(&rec).x, 50000.0);
}

#[test]
fn other_dialects_are_named() {
    let e = err("0 BEGIN PGM TEST MM\n1 BLK FORM 0.1 Z X+0 Y+0 Z-40\n2 L X+10 Y+5 R0 FMAX\n");
    assert_eq!(e.kind, PathErrorKind::Unsupported);
    assert!(e.message.contains("Heidenhain"), "{e}");
    let e = err("N10 G0 X0 Y0\nN20 G2 X10 Y10 CR=5\n");
    assert_eq!((e.kind, e.pos.line), (PathErrorKind::Unsupported, 2));
    assert!(e.message.contains("Siemens"), "{e}");
    assert!(err("TRAORI\n").message.contains("Siemens"));
    assert!(err("CYCLE81(10, 0, 2, -5)\n").message.contains("Siemens"));
}

#[test]
fn malformed_lines_give_line_column_found_and_expected() {
    let e = err("G0 X0\nG1 X1.2.3 Y4\n");
    assert_eq!(
        (e.kind, e.pos.line, e.pos.column),
        (PathErrorKind::Syntax, 2, 4)
    );
    assert_eq!(e.found, "X1.2.3");
    assert_eq!(e.expected, "a number");
    assert_eq!(e.pos.file, "t.ngc");
    let e = err("G1 X1 (unclosed\n");
    assert_eq!((e.pos.column, e.found.as_str()), (7, "(unclosed"));
    let e = err("G1 Q X1\n");
    assert_eq!((e.pos.line, e.pos.column), (1, 4));
    let e = err("G1 X[1+2\n");
    assert_eq!(e.pos.column, 9);
    assert!(e.expected.contains("]"));
    let e = err("\n\nG7.3\n");
    assert_eq!(
        (e.pos.line, e.pos.column, e.kind),
        (3, 1, PathErrorKind::Syntax)
    );
    let e = err("G1 X1 X2\n");
    assert_eq!((e.pos.column, e.found.as_str()), (7, "X2"));
    let e = err("G0 U1\n");
    assert_eq!(e.kind, PathErrorKind::Unsupported);
    let e = err("o100 frobnicate\n");
    assert_eq!(e.pos.column, 6);
    let msg = e.to_string();
    assert!(msg.starts_with("t.ngc:1:6: "), "{msg}");
}

#[test]
fn case_and_spacing_do_not_matter() {
    let a = motion(&run("G1 X1.5 Y-2 Z.25 F100\nG2 X3 Y-2 I.75 J0\n"));
    let b = motion(&run("g1x1.5y-2z.25f100\ng 2 x 3 y - 2 i . 7 5 j 0\n"));
    let c = motion(&run(
        "N10 G01 X 1.5 Y-2.0 Z0.25 F100.\nN20 G02 X3. Y-2. I0.75 J0.\n",
    ));
    assert_eq!(a, b);
    assert_eq!(a, c);
}

/// LinuxCNC's active comments: `MSG` as written, `DEBUG` and `PRINT` with parameters replaced
/// (`%f`, six decimals; LinuxCNC G-code manual, "Messages" and "Debug Messages").
#[test]
fn active_comments_are_messages() {
    let rec = run("#1=2.5\n#<depth>=-1\n(MSG, hello #1)\n(debug,at #1 and #<depth> #<nope>)\n(PRINT,x=#1)\nM2\n");
    let msgs: Vec<_> = rec
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::Message { kind, text } => Some((*kind, text.to_string())),
            _ => None,
        })
        .collect();
    assert_eq!(
        msgs,
        vec![
            (MessageKind::Msg, " hello #1".to_string()),
            (
                MessageKind::Debug,
                "at 2.500000 and -1.000000 ######".to_string()
            ),
            (MessageKind::Print, "x=2.500000".to_string()),
        ]
    );
}

/// rs274 2.9's format words in `DEBUG`/`PRINT` texts (`%d`, `%f`, `%.Nf`, sticky to the end
/// of the comment, printing nothing themselves; other `%` text as it is; `MSG` untouched), and
/// a line's last comment only. Expected texts: rs274 2.9's output for the same lines. (swarf
/// printed `%d3.700000` and both comments.)
#[test]
fn format_words_and_the_last_comment_as_rs274_prints_them() {
    let src = "G21\n#1=3.7\n#2=-2.5\n(debug,a %d#1 b %d#2 c #1 d %.9f#1 e #2 f %.12f#1 g %.0f#1 \
        h %x#1 i %% j %.1f #1 k %f#<_x>)\n(debug,l #1 %d)\n(msg,m %d#1)\n(print,p %d#1 %.3f#1)\n\
        G1 X1 F100 (msg,first) (msg,second)\n(c) G1 X2 (debug,d)\nM2\n";
    let rec = run(src);
    let msgs: Vec<String> = rec
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::Message { text, .. } => Some(text.to_string()),
            _ => None,
        })
        .collect();
    assert_eq!(
        msgs,
        [
            "a 4 b -2 c 4 d 3.700000000 e -2.500000000 f .12f3.700000000 g 4 h %x4 i %% j  3.7 \
             k 0.0000",
            "l 3.700000 ",
            "m %d#1",
            "p 4 3.700",
            "second",
            "d",
        ]
    );
}

#[test]
fn comments_block_delete_and_tape_markers() {
    let rec = run_with(
        "%\n(a note) G0 X1 ; not emitted\n/G0 X99\nG0 X2\n%\nG0 X3\n",
        &GcodeOptions::default().with_block_delete(true),
    )
    .unwrap();
    let comments: Vec<_> = rec
        .events
        .iter()
        .filter(|(_, e)| matches!(e, Canon::Comment(_)))
        .collect();
    assert_eq!(comments.len(), 1);
    assert_eq!(comments[0].1, Canon::Comment("a note".into()));
    let xs: Vec<f64> = motion(&rec).iter().map(|e| end_of(e).x).collect();
    assert_eq!(
        xs,
        vec![1.0, 2.0],
        "block delete skips, the second % ends the program"
    );
    // By default the switch is off, as rs274 starts: the line is read.
    let rec = run("/G0 X99\n");
    assert_eq!(motion(&rec).len(), 1);
}

#[test]
fn polar_coordinates_absolute_and_incremental() {
    let rec = run("G0 @10 ^90\nG91 G0 ^90\nG0 @-5\n");
    let m = motion(&rec);
    assert_xyz(end_of(&m[0]), 0.0, 10.0, 0.0);
    assert_xyz(end_of(&m[1]), -10.0, 0.0, 0.0);
    assert_xyz(end_of(&m[2]), -5.0, 0.0, 0.0);
    assert!(err("G91 G0 @1\n").message.contains("origin"));
    assert!(err("G0 @1 X1\n").message.contains("polar"));
}

#[test]
fn rotary_axes_in_degrees() {
    let rec = run("G20 G0 X1 A90 B-45 C370\n");
    let a = last_pos(&rec);
    assert_eq!((a.x, a.a, a.b, a.c), (25.4, 90.0, -45.0, 370.0));
}

#[test]
fn words_without_meaning_in_their_block_are_warned_not_dropped() {
    let rec = run("G21\nG1 X1 E5 F100\nG0 X2 I3\nG2 X3 Y0 R5\nG4 P1\nG81 X1 Y1 Z-1 R1\nG80\nM30\n");
    let ignored: Vec<(u32, u32, &str)> = rec
        .warnings
        .iter()
        .filter(|w| w.message.contains("no meaning"))
        .map(|w| (w.line, w.column, w.message.as_str()))
        .collect();
    assert_eq!(ignored.len(), 2, "{ignored:?}");
    assert_eq!((ignored[0].0, ignored[0].1), (2, 7));
    assert!(ignored[0].2.starts_with("E5"));
    assert_eq!((ignored[1].0, ignored[1].1), (3, 7));
    assert!(ignored[1].2.starts_with("I3"));
}

/// A UTF-8 byte order mark (Windows editors, some posts) is not a word of the first line.
#[test]
fn a_byte_order_mark_is_skipped() {
    let with = "\u{feff}G21 G90\nG0 X1 Y2 Z5\nM30\n";
    let mut a = swarf_path::canon::Recorder::default();
    let mut b = swarf_path::canon::Recorder::default();
    swarf_path::gcode::read_gcode(with, "bom.ngc", &Default::default(), &mut a).unwrap();
    swarf_path::gcode::read_gcode(&with[3..], "bom.ngc", &Default::default(), &mut b).unwrap();
    assert_eq!(a.events, b.events);
}

/// Lines starting with `/` are read by default (the block-delete switch off, as rs274 2.9
/// starts: it prints their moves) and skipped with the switch on; either way the first one is
/// reported. (They were skipped by default.)
#[test]
fn block_deleted_lines_are_reported_once() {
    use swarf_path::load::{read_program_str, ReadOptions};
    let src = "G21 G90\nG0 X0 Y0 Z5\n/G1 X5 F100\n/G1 X6\nG1 Y5 F100\nM2\n";
    let read = |on: bool| {
        let options = ReadOptions {
            gcode: swarf_path::gcode::GcodeOptions::default().with_block_delete(on),
            ..ReadOptions::default()
        };
        read_program_str(src, "bd.ngc", swarf_path::Machine::three_axis(), &options).unwrap()
    };
    let on = read(true);
    assert_eq!(on.moves.len(), 2);
    assert_eq!(on.warnings.len(), 1, "{:?}", on.warnings);
    assert_eq!(on.warnings[0].line, 3);
    assert!(on.warnings[0].message.contains("block delete"));
    let off = read(false);
    assert_eq!(off.moves.len(), 4);
    assert_eq!(off.warnings.len(), 1, "{:?}", off.warnings);
    assert_eq!(off.warnings[0].line, 3);
    assert!(off.warnings[0].message.starts_with("line read"));
    let default = read_program_str(
        src,
        "bd.ngc",
        swarf_path::Machine::three_axis(),
        &ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(default.moves.len(), 4);
}

/// I/O, override and spindle-orientation M codes are named for what they do and their words
/// are theirs (not reported as unused), each at its first use only; a pause points at its M
/// word.
#[test]
fn io_and_pause_m_codes_are_reported_at_their_words() {
    use swarf_path::load::{read_program_str, ReadOptions};
    let src =
        "G21 G90\nM66 P0 L3 Q5\nM62 P1\nM67 E0 Q2.5\nG0 X1 M1\nM62 P2\nM50 P0\nM19 R90 Q1 P0\nM2\n";
    let p = read_program_str(
        src,
        "io.ngc",
        swarf_path::Machine::three_axis(),
        &ReadOptions::default(),
    )
    .unwrap();
    let w: Vec<(u32, u32, &str)> = p
        .warnings
        .iter()
        .map(|w| (w.line, w.column, w.message.as_str()))
        .collect();
    assert_eq!(
        w,
        [
            (
                2,
                1,
                "M66 (wait on input) ignored: it does not move the tool (the first M66; later \
                 ones are not reported)"
            ),
            (
                3,
                1,
                "M62 (digital output) ignored: it does not move the tool (the first M62; later \
                 ones are not reported)"
            ),
            (
                4,
                1,
                "M67 (analog output) ignored: it does not move the tool (the first M67; later \
                 ones are not reported)"
            ),
            (5, 7, "M1 (program pause) ignored: the simulation runs on"),
            (
                7,
                1,
                "M50 (override control) ignored: it does not move the tool (the first M50; \
                 later ones are not reported)"
            ),
            (
                8,
                1,
                "M19 (spindle orientation) ignored: it does not move the tool (the first M19; \
                 later ones are not reported)"
            ),
        ]
    );
}

/// GRBL's own lines (`$H` homing, `$X` unlock, `$$`, settings) are skipped with a warning
/// naming them where skipping cannot change the motion; a jog, and a homing cycle after the
/// program has moved, are refused.
#[test]
fn grbl_system_commands_are_skipped_or_refused() {
    let rec = run("$H\n$X\nG21 G90\nG0 X10 Y10\n$$\n$1=25\nG1 Z-1 F100\nM30\n");
    assert_xyz(last_pos(&rec), 10.0, 10.0, -1.0);
    let w: Vec<(u32, u32, &str)> = rec
        .warnings
        .iter()
        .map(|w| (w.line, w.column, w.message.as_str()))
        .collect();
    assert_eq!(w.len(), 4, "{w:?}");
    assert_eq!((w[0].0, w[0].1), (1, 1));
    assert!(w[0].2.starts_with("`$H` skipped"), "{w:?}");
    assert!(w[3].2.starts_with("`$1=25` skipped"), "{w:?}");
    let e = err("G21\nG0 X1\n$H\nM30\n");
    assert_eq!(e.kind, PathErrorKind::Unsupported);
    assert_eq!((e.pos.line, e.pos.column), (3, 1));
    assert!(e.message.contains("homing"), "{e}");
    let e = err("$J=G91 X10 F100\n");
    assert_eq!(e.kind, PathErrorKind::Unsupported);
    assert_eq!(e.found, "$J=G91 X10 F100");
    // The rest of GRBL's grammar.
    let rec = run("$G\n$I\n$N\n$C\n$#\n$SLP\n$RST=$\n$N0=G20 G54\n$110=500.000\n$HZ\nG0 X1\n");
    assert_xyz(last_pos(&rec), 1.0, 0.0, 0.0);
    let skipped: Vec<u32> = rec
        .warnings
        .iter()
        .filter(|w| w.message.contains("skipped"))
        .map(|w| w.line)
        .collect();
    assert_eq!(skipped, (1..=10).collect::<Vec<_>>(), "{:?}", rec.warnings);
}

/// A line that starts with `$` but is not GRBL's (LinuxCNC 2.8+'s spindle select `$1`, word
/// order free) goes to the G-code reader, which reads the `$` word: `$0` and `$-1` (every
/// spindle) quietly, another spindle with a warning (one spindle is simulated); a malformed
/// one is an error at its place.
#[test]
fn dollar_lines_outside_grbl_grammar_are_g_code() {
    let rec = run("$1 M3 S1000\nG21 G0 X1\nM3 $0 S800\nM5 $-1\nM30\n");
    assert_xyz(last_pos(&rec), 1.0, 0.0, 0.0);
    let w: Vec<(u32, u32)> = rec.warnings.iter().map(|w| (w.line, w.column)).collect();
    assert_eq!(w, [(1, 1)], "{:?}", rec.warnings);
    assert!(rec.warnings[0]
        .message
        .starts_with("$1: spindle 1 selected"));
    run("$0M5\nM30\n");
    for (src, column, what) in [
        ("$12=\n", 4, "unexpected text"),
        ("$1=2=3\n", 3, "unexpected text"),
        ("$HQ\n", 1, "without a value"),
        ("$SLPX\n", 1, "without a value"),
        ("M3 $0.5\n", 4, "spindle $0.5"),
        ("M3 $0 $1\n", 7, "two $ words"),
    ] {
        let e = err(src);
        assert_eq!((e.pos.line, e.pos.column), (1, column), "{src:?}: {e}");
        assert!(e.message.contains(what), "{src:?}: {e}");
    }
}

/// Real posts' spelling: no spaces (Vectric), leading zeros, `5.` `.5` `-0.` `+1.`, spaces
/// inside words (dxf2gcode's `X  10.000`), a comment stuck to a word (Inkscape's
/// `F100.0(Penetrate)`), tabs, `\r\n`, and a last line without its newline.
#[test]
fn post_processor_spellings_read_as_written() {
    let src =
        "G00G21G17G90G40G49G80\r\nG0X10.000Y10.000Z5.000\r\n\tG01 Z-1.000000 F100.0(Penetrate)\r\n\
               G1 X  -10.000 Y  .5\t\r\ng01 x+20. y-0.\r\nG1 X 1 0 Y 5.\r\nN0010.5 G1 X-.5\r\nM30";
    let rec = run(src);
    let ends = tip_ends(&rec);
    assert_eq!(
        ends,
        [
            [10.0, 10.0, 5.0],
            [10.0, 10.0, -1.0],
            [-10.0, 0.5, -1.0],
            [20.0, 0.0, -1.0],
            [10.0, 5.0, -1.0],
            [-0.5, 5.0, -1.0],
        ]
    );
    // (`G00 … G80` reads it by Fanuc's rules, said at line 1, which report `X 1 0`: no
    // decimal point.)
    let w: Vec<_> = rec.warnings.iter().map(|w| (w.line, w.column)).collect();
    assert_eq!(w, [(1, 1), (6, 4)], "{:?}", rec.warnings);
    assert!(rec.warnings[0].message.starts_with("read by Fanuc rules"));
    assert!(rec.warnings[1]
        .message
        .starts_with("X10 has no decimal point"));
}

/// The noise of every CAM program is said once: a reference return with no home given, in any
/// dialect (Fusion's LinuxCNC and Mach3 posts write `G28 G91 Z0` too), and G43 H with no
/// tool table entry (the tip goes where X Y Z say all the same). LinuxCNC's G64 Q (naive CAM
/// tolerance) is a word of G64.
#[test]
fn cam_program_noise_is_reported_once() {
    let src = "G21 G90\nG28 G91 Z0\nG90\nT1 M6\nG0 G43 H1 Z15\nG64 P0.01 Q0.01\nG0 X1\nT2 M6\nG43 H2 Z15\nG28 G91 Z0\nG90\nM30\n";
    let rec = run(src);
    let w: Vec<(u32, &str)> = rec
        .warnings
        .iter()
        .map(|w| (w.line, w.message.as_str()))
        .collect();
    assert_eq!(w.len(), 2, "{w:?}");
    assert_eq!(w[0].0, 2);
    assert!(w[0].1.contains("--home"), "{w:?}");
    assert_eq!(w[1].0, 5);
    assert!(w[1].1.starts_with("G43 H1"), "{w:?}");
    // With a home, or a stored G28 position, the reference return says nothing.
    let homed = run_with(src, &GcodeOptions::default().with_home([0.0, 0.0, 100.0])).unwrap();
    assert_eq!(homed.warnings.len(), 1, "{:?}", homed.warnings);
    let stored = run("G21 G90\nG0 Z50\nG28.1\nG0 Z5\nG28 G91 Z0\nG90\nM30\n");
    assert!(stored.warnings.is_empty(), "{:?}", stored.warnings);
}

/// Old Mac editors end lines with a lone `\r`; DOS tools and DNC senders end a file with Ctrl-Z.
#[test]
fn lone_carriage_returns_end_lines_and_ctrl_z_is_blank() {
    let rec = run("G21 G90\rG0 X1\rG1 X2 F100\rM2\r");
    assert_eq!(motion(&rec).len(), 2);
    assert_xyz(last_pos(&rec), 2.0, 0.0, 0.0);
    let e = err("G21 G90\rG0 X1\rG1 X2 X3\r");
    assert_eq!(e.pos.line, 3);
    let rec = run("G21 G90\r\nG0 X1\r\n\u{1a}");
    assert_xyz(last_pos(&rec), 1.0, 0.0, 0.0);
    // The dialect is told from such lines too.
    use swarf_path::gcode::GcodeDialect;
    assert_eq!(
        GcodeDialect::detect("%\rO1234\rG0 X0\rM98 P10\rM30\r"),
        GcodeDialect::Fanuc
    );
}

/// A huge word is quoted in part: the message stays readable (the error keeps all of it).
#[test]
fn long_found_text_is_shortened_in_the_message() {
    let word = format!("Y{}", "1".repeat(5000));
    let e = err(&format!("G21 G90\nG0 X1\nG1 {word} F100\nM2\n"));
    // (The number is infinite as a double: rs274's "Calculation resulted in 'infinity'", about
    // the number after the Y.)
    assert_eq!(e.found, word[1..]);
    let shown = e.to_string();
    assert!(shown.len() < 400, "{shown}");
    assert!(shown.contains("… (4880 more characters)"), "{shown}");
}

#[test]
fn utf16_files_with_a_byte_order_mark_read_as_their_utf8_text() {
    // Windows editors save "Unicode" text as UTF-16 with a byte-order mark: the same program
    // as UTF-8 (a comment with an accent, CR LF ends), little- and big-endian, G-code and APT.
    use swarf_path::load::{read_program, ReadOptions};
    use swarf_path::Machine;
    let dir = swarf_testdata::scratch_dir("utf16");
    let cases = [
        ("p.ngc", "G21 G90 (pièce)\r\nG0 X0 Y0 Z5\r\nG1 Z-1 F100\r\nG2 X10 Y0 I5 J0\r\nM2\r\n"),
        (
            "p.apt",
            "PARTNO/PIÈCE\r\nUNITS/MM\r\nCUTTER/6\r\nGOTO/0,0,5\r\nFEDRAT/100\r\nGOTO/10,0,-1\r\nFINI\r\n",
        ),
    ];
    for (name, text) in cases {
        let utf8 = dir.join(name);
        std::fs::write(&utf8, text).unwrap();
        let want = read_program(&utf8, Machine::three_axis(), &ReadOptions::default()).unwrap();
        assert!(!want.moves.is_empty());
        for be in [false, true] {
            let mut bytes = if be {
                vec![0xFE, 0xFF]
            } else {
                vec![0xFF, 0xFE]
            };
            for u in text.encode_utf16() {
                bytes.extend(if be { u.to_be_bytes() } else { u.to_le_bytes() });
            }
            let p = dir.join(format!("{}{name}", if be { "be-" } else { "le-" }));
            std::fs::write(&p, bytes).unwrap();
            let got = read_program(&p, Machine::three_axis(), &ReadOptions::default())
                .unwrap_or_else(|e| panic!("{name} be={be}: {e}"));
            assert_eq!(got.moves.len(), want.moves.len(), "{name} be={be}");
            for (a, b) in got.moves.iter().zip(&want.moves) {
                assert_eq!(
                    (a.start.tip, a.end.tip, a.line),
                    (b.start.tip, b.end.tip, b.line)
                );
            }
        }
    }
}

/// LinuxCNC's M70 (save), M72 (restore), M71 (forget) and M73 (save, restored when the
/// subroutine returns): units, distance mode, feed and coordinate system come back; the state
/// is per call level.
#[test]
fn modal_state_save_and_restore_m70_to_m73() {
    // Saved in mm and G90 at F100; inch and G91 in between; restored before the second move.
    let rec = run("G21 G90 F100\nM70\nG20 G91 F10\nG0 X1\nM72\nG0 X1\nM2\n");
    let m = motion(&rec);
    assert_xyz(end_of(&m[0]), 25.4, 0.0, 0.0);
    assert_xyz(end_of(&m[1]), 1.0, 0.0, 0.0);
    let feeds: Vec<f64> = rec
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::FeedRate(f) => Some(*f),
            _ => None,
        })
        .collect();
    assert_eq!(feeds.last(), Some(&100.0), "{feeds:?}");
    // M73 in a subroutine: restored at its endsub; in an M98 subprogram at its M99.
    for src in [
        "G21 G90\no100 sub\nM73\nG20 G91\nG0 X1\no100 endsub\no100 call\nG0 X1\nM2\n",
        "G21 G90\nM98 P100\nG0 X1\nM2\nO100\nM73\nG20 G91\nG0 X1\nM99\n",
    ] {
        let m = motion(&run(src));
        assert_xyz(end_of(&m[0]), 25.4, 0.0, 0.0);
        assert_xyz(end_of(&m[1]), 1.0, 0.0, 0.0);
    }
    // M70 in a subroutine is not restored by its return: G20 stays.
    let m = motion(&run(
        "G21 G90\no100 sub\nM70\nG20\no100 endsub\no100 call\nG0 X1\nM2\n",
    ));
    assert_xyz(end_of(&m[0]), 25.4, 0.0, 0.0);
    // The coordinate system comes back.
    let rec = run("G21 G90\nG10 L2 P2 X10\nG54\nM70\nG55\nG0 X0\nM72\nG0 X0\nM2\n");
    let index: Vec<u8> = rec
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::Offsets { index, .. } => Some(*index),
            _ => None,
        })
        .collect();
    assert_eq!(index.last(), Some(&1), "{index:?}");
    // M71 forgets; M72 with nothing saved at this level is an error at its line; a state
    // saved in the main program is not the subroutine's.
    assert_eq!(err("G21\nM70\nM71\nM72\n").pos.line, 4);
    assert_eq!(err("G21\nM72\n").pos.line, 2);
    let e = err("G21\nM70\no1 sub\nM72\no1 endsub\no1 call\nM2\n");
    assert_eq!(e.pos.line, 4);
    // M70 after M73 in a subroutine keeps the restore on return (with M70's state).
    let m = motion(&run(
        "G21 G90\no100 sub\nM73\nG20\nM70\nG91\no100 endsub\no100 call\nG0 X1\nM2\n",
    ));
    assert_xyz(end_of(&m[0]), 25.4, 0.0, 0.0);
}

/// M61 Q sets the tool in the spindle without a change: the moves after it use that tool.
#[test]
fn m61_sets_the_current_tool() {
    let rec = run("G21\nT1 M6\nM61 Q3\nG0 X1\nM2\n");
    let tools: Vec<u32> = rec
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::ToolChange { tool } => Some(*tool),
            _ => None,
        })
        .collect();
    assert_eq!(tools, [1, 3]);
    assert_eq!(err("G21\nM61\n").pos.line, 2);
    // M61 leaves the selected tool: a later M6 loads T5, not tool 3; #5400 is the loaded tool.
    let rec =
        run("G21\nT5\nM61 Q3\n(debug,#5400 #<_current_tool> #<_selected_tool>)\nM6\nG0 X1\nM2\n");
    let last = rec.events.iter().rev().find_map(|(_, e)| match e {
        Canon::ToolChange { tool } => Some(*tool),
        _ => None,
    });
    assert_eq!(last, Some(5));
    assert_eq!(rec.messages(), ["3.000000 3.000000 5.000000"]);
}

/// LinuxCNC's `(ABORT,…)` stops the program with its text (parameters replaced) as the error,
/// at its line, after the moves before it.
#[test]
fn abort_comment_ends_the_program_with_its_message() {
    let mut rec = Recorder::default();
    let e = read_gcode(
        "G21\nG0 X1\n(abort,stopped at #<_x>)\nG0 X2\nM2\n",
        "t.ngc",
        &GcodeOptions::default(),
        &mut rec,
    )
    .unwrap_err();
    assert_eq!(e.pos.line, 3);
    assert!(e.message.contains("stopped at 1.000000"), "{}", e.message);
    assert_eq!(motion(&rec).len(), 1);
    // In a branch not taken it does nothing.
    run("G21\no1 if [0]\n(ABORT,never)\no1 endif\nG0 X1\nM2\n");
}

/// G43.2 adds to the tool length offset in effect: tool H's, or the axis words'. The offset
/// shows in the position the program reads (#5422: Z) as G43's does.
#[test]
fn g43_2_adds_a_tool_length_offset() {
    let msgs = |src: &str| run(src).messages();
    // At Z0 with offsets 5 then 5 + 2: the program reads Z −5, then −7.
    let got = msgs(
        "G21\nG10 L1 P1 Z5\nG10 L1 P2 Z2\nG43 H1\n(debug,#5422)\nG43.2 H2\n(debug,#5422)\n\
         G43.2 Z0.5\n(debug,#5422)\nG49\n(debug,#5422)\nM2\n",
    );
    assert_eq!(got, ["-5.000000", "-7.000000", "-7.500000", "0.000000"]);
    // H and axis words together are refused.
    assert_eq!(err("G21\nG43.2 H1 Z1\n").pos.line, 2);
}

/// LinuxCNC's predefined named parameters for the modes (G-code manual, "Predefined Named
/// Parameters"): codes × 10 for motion, plane, compensation and coordinate system, 1/0 flags
/// for the rest; the tool in the spindle changes at M6, the selected one at T. (The
/// interpreter starts in G99: `_retract_r_plane` 1.)
#[test]
fn predefined_named_parameters_read_the_modes() {
    let names = [
        "_motion_mode",
        "_plane",
        "_ccomp",
        "_coord_system",
        "_inverse_time",
        "_units_per_minute",
        "_tool_offset",
        "_retract_r_plane",
        "_retract_old_z",
        "_spindle_on",
        "_spindle_cw",
        "_spindle_css_mode",
        "_mist",
        "_flood",
        "_feed_override",
        "_adaptive_feed",
        "_current_tool",
        "_selected_tool",
        "_call_level",
        "_ijk_absolute_mode",
    ];
    let probe: String = names.iter().map(|n| format!("#<{n}> ")).collect();
    let text = |src: &str| run(src).messages().join("|");
    // The version, as rs274 2.9 prints it for LinuxCNC's roparams.ngc (it printed ######).
    assert_eq!(
        text("(debug,#<_vmajor> #<_vminor>)\nM2\n"),
        "2.900000 0.000000"
    );
    let start = text(&format!("G21\n(debug,{probe})\nM2\n"));
    assert_eq!(
        start,
        "800.000000 170.000000 400.000000 540.000000 0.000000 1.000000 0.000000 \
         1.000000 0.000000 0.000000 0.000000 0.000000 0.000000 0.000000 1.000000 0.000000 \
         0.000000 0.000000 0.000000 0.000000 "
    );
    let later = text(&format!(
        "G21\nT2 M6\nT5\nG18 G55 G93 G43 G99 G90.1 G96 S100 M3 M7 M8 M50 P0\nM52\n\
         G41.1 D4\nG1 X10 F2\nG40\nG1 X20 F2\no1 sub\n(debug,{probe})\no1 endsub\no1 call\nM2\n"
    ));
    assert_eq!(
        later,
        "10.000000 180.000000 400.000000 550.000000 1.000000 0.000000 1.000000 \
         1.000000 0.000000 1.000000 1.000000 1.000000 1.000000 1.000000 0.000000 1.000000 \
         2.000000 5.000000 1.000000 1.000000 "
    );
    let comp = text(
        "G21\nG41.1 D4\n(debug,#<_ccomp>)\nG1 X10 F100\nG40\nG1 X20\n(debug,#<_ccomp>)\n\
         G42.1 D4\n(debug,#<_ccomp>)\nM2\n",
    );
    assert_eq!(comp, "411.000000|400.000000|421.000000");
}

/// G33 moves K per spindle revolution and G33.1 taps down and back along the same line
/// (LinuxCNC: "after the rigid tap cycle we'll be in the same spot"), the retract at I times
/// the spindle speed; the feed mode and rate are the program's again afterwards. Times worked
/// out by hand: F200 over 4 mm = 1.2 s; down 11 mm at 1.25 × 500 = 625 mm/min = 1.056 s; up at
/// 1.25 × 1000 = 1250 mm/min = 0.528 s; G33 from Z1 to Z-10 at 1.5 × 500 = 750 mm/min = 0.88 s;
/// F200 over
/// 10 mm = 3 s.
#[test]
fn g33_and_rigid_tapping_follow_the_spindle() {
    use swarf_path::load::{read_program_str, ReadOptions};
    use swarf_path::summary::summarize;
    let src = "G21 G90 G17\nG0 X0 Y0 Z5\nM3 S500\nG1 F200 Z1\nG33.1 Z-10 K1.25 I2\nG0 X20\n\
               G33 Z-10 K1.5\nG0 Z5\nG1 X30\nM2\n";
    let m = motion(&run(src));
    let feeds: Vec<[f64; 3]> = m
        .iter()
        .filter_map(|e| match e {
            Canon::Feed { end } => Some([end.x, end.y, end.z]),
            _ => None,
        })
        .collect();
    assert_eq!(
        feeds,
        [
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -10.0],
            [0.0, 0.0, 1.0],
            [20.0, 0.0, -10.0],
            [30.0, 0.0, 5.0]
        ]
    );
    let opts = ReadOptions::default();
    let p = read_program_str(src, "t.ngc", swarf_path::Machine::three_axis(), &opts).unwrap();
    // (Machining time counts feed moves only.)
    let t = summarize(&p).machining_time_s;
    assert!((t - (1.2 + 1.056 + 0.528 + 0.88 + 3.0)).abs() < 1e-9, "{t}");
    // In inches K is in inches; a stopped spindle, a missing or negative K, and compensation
    // are refused where they are.
    let inch = motion(&run("G20 G90\nM3 S100\nG33 Z-1 K0.1\nM2\n"));
    assert!(inch
        .iter()
        .any(|e| matches!(e, Canon::Feed { end } if (end.z + 25.4).abs() < 1e-12)));
    for (src, col, what) in [
        ("G21\nG33 Z-1 K1\nM2\n", 1, "spindle stopped"),
        ("G21\nM3 S100\nG33 Z-1\nM2\n", 1, "without K"),
        ("G21\nM3 S100\nG33 Z-1 K-1\nM2\n", 9, "K-1"),
        ("G21\nM3 S100\nG33.1 Z-1 K1 I0\nM2\n", 14, "I0"),
    ] {
        let e = err(src);
        assert!(e.message.contains(what), "{src}: {e}");
        assert_eq!(
            (e.pos.line, e.pos.column),
            (
                src.lines().position(|l| l.contains("G33")).unwrap() as u32 + 1,
                col
            ),
            "{src}: {e}"
        );
    }
    assert!(err("G21 G76 P1 Z-1\n").message.contains("lathe"));
    // G33.1 with X/Y goes over the hole at its Z first, taps straight down and comes back up.
    let ends = tip_ends(&run(
        "G21 G90\nM3 S100\nG0 X0 Y0 Z2\nG33.1 X5 Y6 Z-4 K1\nG0 Z10\nM2\n",
    ));
    assert_eq!(
        ends,
        [
            [0.0, 0.0, 2.0],
            [5.0, 6.0, 2.0],
            [5.0, 6.0, -4.0],
            [5.0, 6.0, 2.0],
            [5.0, 6.0, 10.0]
        ]
    );
}

/// Review cases (LinuxCNC's interpreter as the reference): under G90.1 a centre word left out
/// is the start's coordinate (not 0); a line's parameter assignments are made before its
/// comments are shown; an inch program's pecks are counted in inches.
#[test]
fn absolute_centres_messages_after_assignments_and_inch_pecks() {
    // From (10, 0), `G2 X10 Y20 J10` under G90.1: centre (10, 10), a half circle (with the
    // missing I as 0 the centre was (0, 10) and the arc three quarters of a circle).
    let rec = run("G21 G17 G90 F100\nG0 X10 Y0 Z0\nG90.1\nG2 X10 Y20 J10\nM2\n");
    let arc = rec
        .events
        .iter()
        .find_map(|(_, e)| match e {
            Canon::Arc { center, .. } => Some(*center),
            _ => None,
        })
        .unwrap();
    assert_eq!(arc, [10.0, 10.0]);
    // `#1=5 (DEBUG,#1)`: 5, as LinuxCNC copies the line's assignments first.
    let rec = run("#1=5 (DEBUG,#1)\n#<_n>=2 (DEBUG,#<_n>)\nM2\n");
    let msgs = message_texts(&rec);
    assert_eq!(msgs, ["5.000000", "2.000000"]);
    // G83 R0.1 Z-0.6 Q0.05 in inches: pecks to -0.05 … -0.55 (13), then the bottom: 14
    // feeds, the last at -0.6 in (in mm the 14th peck landed a rounding above the bottom and
    // a 15th, degenerate one followed).
    let rec = run("G20 F10\nG0 X0 Y0 Z1\nG98 G83 X0 Y0 R0.1 Z-0.6 Q0.05\nM2\n");
    let feeds: Vec<f64> = rec
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::Feed { end } => Some(end.z),
            _ => None,
        })
        .collect();
    assert_eq!(feeds.len(), 14, "{feeds:?}");
    for (k, z) in feeds.iter().enumerate() {
        let want = if k < 13 {
            0.1 - 0.05 * (k + 1) as f64
        } else {
            -0.6
        };
        assert!((z - want * 25.4).abs() < 1e-9, "feed {k}: {z}");
    }
}

/// A G87 repeated on a new hole without I J K keeps the last ones (LinuxCNC's `cycle_i/j/k`);
/// LinuxCNC's G86 and G88 need their dwell P where the cycle starts (a Fanuc G86 has none).
#[test]
fn back_boring_repeats_and_boring_dwells() {
    let rec = run(
        "G21 G17 G90 F100 S1000 M3\nG0 X0 Y0 Z10\nG98 G87 X5 Y0 R2 Z-8 I1 J0 K-5\nX10\nG80\nM2\n",
    );
    // Each hole: two feeds, up to K then down to the bottom, at the hole's X.
    let feeds: Vec<[f64; 3]> = rec
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::Feed { end } => Some([end.x, end.y, end.z]),
            _ => None,
        })
        .collect();
    assert_eq!(
        feeds,
        [
            [5.0, 0.0, -5.0],
            [5.0, 0.0, -8.0],
            [10.0, 0.0, -5.0],
            [10.0, 0.0, -8.0]
        ]
    );
    let e = err("G21 F100 S500 M3\nG0 Z5\nG86 X1 Y1 R2 Z-5\nM2\n");
    assert_eq!((e.pos.line, e.pos.column), (3, 1), "{e}");
    assert!(e.message.contains("dwell time P missing"), "{e}");
    run("G21 F100 S500 M3\nG0 Z5\nG88 X1 Y1 R2 Z-5 P0.5\nX2\nG80\nM2\n");
}

/// G43.1 takes the offset along every axis given (a lathe's `G43.1 X Z`) and keeps the
/// others: `G43.1 X1` from X5 puts the program's X at 4; a later `G43.1 Z2` keeps that X.
#[test]
fn dynamic_offsets_per_axis() {
    let rec =
        run("G21\nG0 X5 Z5\nG43.1 X1\n(DEBUG,#5420 #5422)\nG43.1 Z2\n(DEBUG,#5420 #5422)\nM2\n");
    let msgs = message_texts(&rec);
    assert_eq!(msgs, ["4.000000 5.000000", "4.000000 3.000000"]);
    let e = err("G21\nG43.1\nM2\n");
    assert!(e.message.contains("G43.1 needs an axis word"), "{e}");
}

/// G53, G28/G30 and G28.1/G30.1 work with the controlled point, as LinuxCNC's `find_ends`,
/// `convert_home` and `convert_savehome`: the tool length offset is subtracted like the work
/// and G92 offsets, so with a 10 mm tool under G43 `G53 G0 Z0` puts the tip (swarf's
/// positions) at machine Z −10, and the machine position (#5023) does not move on a G43 that
/// moves nothing.
#[test]
fn machine_coordinate_moves_subtract_the_tool_length_offset() {
    // Tool 1 is 10 long; G43 leaves the controlled point at machine Z0, the tip reads Z −10.
    let rec = run("G21 G90\nG10 L1 P1 Z10\nT1 M6 G43\nG53 G0 Z0\nG0 Z0\nG28\nM2\n");
    assert_eq!(
        tip_ends(&rec),
        [
            [0.0, 0.0, -10.0], // G53 Z0: controlled point at machine 0
            [0.0, 0.0, 0.0],   // G0 Z0: the tip at the work's 0
            [0.0, 0.0, 0.0],   // G28: through the current point
            [0.0, 0.0, -10.0], // G28: home (0) is the controlled point's
        ]
    );
    // G54 Z −50: at work Z5 the machine reads −45, before and after G43; G53 Z0 puts the tip
    // at work Z 50 − 10 = 40 and G28.1 stores the controlled point (0), which G28 returns to
    // (tip at 40 again); G49 keeps the controlled point, so the tip reads 50.
    let rec = run(
        "G21 G90\nG10 L1 P1 Z10\nG10 L2 P1 Z-50\nT1 M6\nG0 X0 Y0 Z5\n(DEBUG,#5422 #5023)\n\
         G43\n(DEBUG,#5422 #5023)\nG53 G0 Z0\n(DEBUG,#5422 #5023)\nG28.1\n(DEBUG,#5163)\n\
         G0 Z5\nG28\n(DEBUG,#5422 #5023)\nG49\n(DEBUG,#5422 #5023)\nM2\n",
    );
    assert_eq!(
        rec.messages(),
        [
            "5.000000 -45.000000",
            "-5.000000 -45.000000",
            "40.000000 0.000000",
            "0.000000",
            "40.000000 0.000000",
            "50.000000 0.000000",
        ]
    );
    let z: Vec<f64> = tip_ends(&rec).iter().map(|e| e[2]).collect();
    assert_eq!(z, [5.0, 40.0, 5.0, 5.0, 40.0]);
    // G30 and a G28 intermediate point alike; G28 Z given: only Z goes home.
    let rec = run("G21 G90\nG10 L1 P1 Z10\nT1 M6 G43\n#5183=20\nG0 X1 Z5\nG30 Z7\nM2\n");
    assert_eq!(
        tip_ends(&rec),
        [[1.0, 0.0, 5.0], [1.0, 0.0, 7.0], [1.0, 0.0, 10.0]]
    );
}

/// The tool table's offsets (a LinuxCNC `.tbl`'s Z column, [`GcodeOptions::tool_offsets`])
/// are what G43 and G43 H apply and #5401–#5406 read, as `G10 L1` entries, which replace
/// them.
#[test]
fn the_tool_tables_offsets_are_the_tool_length() {
    let opts = GcodeOptions::default()
        .with_tool_diameter(1, 2.0)
        .with_tool_offsets(1, [0.0, 0.0, 10.0, 0.0, 0.0, 0.0]);
    let msgs = |src: &str| {
        run_with(src, &opts)
            .unwrap_or_else(|e| panic!("{e}"))
            .messages()
    };
    // At Z0, G43 H1 with a 10 mm tool: #5403 reads 10 and the tip's Z −10.
    assert_eq!(
        msgs("G21\nT1 M6\nG43 H1\n(DEBUG, #5403 z=#5422)\nM2\n"),
        [" 10.000000 z=-10.000000"]
    );
    // G43 without H: the loaded tool's; G10 L1 replaces the table's entry.
    assert_eq!(
        msgs("G21\nT1 M6\nG43\n(DEBUG,#5422)\nG10 L1 P1 Z4\nG43\n(DEBUG,#5403 #5422)\nM2\n"),
        ["-10.000000", "4.000000 -4.000000"]
    );
    // No warning that the table has no offset for the tool.
    let rec = run_with("G21\nT1 M6\nG43 H1\nM2\n", &opts).unwrap();
    assert!(
        rec.warnings.iter().all(|w| !w.message.contains("G43")),
        "{:?}",
        rec.warnings
    );
}

/// LinuxCNC's `#<_current_pocket>` and `#<_selected_pocket>`: the pockets of the loaded and
/// selected tools in the tool table (the tool's number where the table gives none; no tool
/// loaded: 0, none selected: −1, as `#<_selected_tool>`).
#[test]
fn current_and_selected_pockets() {
    let opts = GcodeOptions::default().with_tool_pocket(3, 7);
    let rec = run_with(
        "G21\n(DEBUG,#<_current_pocket> #<_selected_pocket>)\nT3\n\
         (DEBUG,#<_current_pocket> #<_selected_pocket>)\nM6\n\
         (DEBUG,#<_current_pocket> #<_selected_pocket>)\nT5 M6\n\
         (DEBUG,#<_current_pocket> #<_selected_pocket>)\nM2\n",
        &opts,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        rec.messages(),
        [
            "0.000000 -1.000000",
            "0.000000 7.000000",
            "7.000000 7.000000",
            "5.000000 5.000000"
        ]
    );
}

/// `#<_ini[…]…>` and `#<_hal[…]>` read LinuxCNC's INI file and HAL pins, which swarf does not
/// have: refused, saying so and what to do.
#[test]
fn ini_and_hal_parameters_are_refused_with_the_reason() {
    for src in [
        "G21\n#2 = #<_ini[traj]max_velocity>\nM2\n",
        "G21\n#2 = #<_hal[motion.spindle-speed-out]>\nM2\n",
    ] {
        let e = err(src);
        assert_eq!(e.kind, PathErrorKind::Unsupported, "{e}");
        assert_eq!(e.pos.line, 2);
        let what = if src.contains("_ini") {
            "INI file"
        } else {
            "HAL"
        };
        assert!(
            e.message.contains(what) && e.message.contains("swarf does not have"),
            "{e}"
        );
        assert!(
            e.expected.contains("replace the parameter with the value"),
            "{e}"
        );
    }
}

/// The words of G96 (D: the maximum spindle speed) and of user M codes (M100–M199 P Q) are
/// not "ignored".
#[test]
fn g96_d_and_user_m_code_arguments_are_not_ignored_words() {
    let rec = run("G21\nG96 S100 D2000 M3\nM101 P1 Q2\nM2\n");
    let w: Vec<_> = rec.warnings.iter().map(|w| w.message.clone()).collect();
    assert!(w.iter().all(|m| !m.contains("no meaning")), "{w:?}");
    // D elsewhere still is.
    let rec = run("G21\nG97 S100 D2000 M3\nM2\n");
    assert!(
        rec.warnings
            .iter()
            .any(|w| w.message.starts_with("D2000 ignored")),
        "{:?}",
        rec.warnings
    );
}

/// LinuxCNC's `convert_comment`: blanks before the keyword are skipped, none may stand before
/// the comma, the keyword's case does not matter.
#[test]
fn active_comments_need_the_keyword_right_before_the_comma() {
    let rec = run("G21\n( msg , spaced)\n(  MsG,shown)\n(debug ,no)\n(\tPRINT,p)\nM2\n");
    assert_eq!(rec.messages(), ["shown", "p"]);
    let comments: Vec<_> = rec
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::Comment(t) => Some(t.to_string()),
            _ => None,
        })
        .collect();
    assert_eq!(comments, [" msg , spaced", "debug ,no"]);
    // (ABORT, …) alike.
    assert!(run_with("G21\n(abort ,x)\nM2\n", &GcodeOptions::default()).is_ok());
    assert_eq!(err("G21\n( ABORT,x)\nM2\n").pos.line, 2);
}

/// Messages that name the real cause: P turns over swarf's cap, and the G10 L forms read.
#[test]
fn arc_turn_cap_and_g10_l_forms_are_named() {
    let e = err("G21 G0 X0 Y0\nG2 X0 Y0 I5 P1000000000 F100\n");
    assert_eq!(e.kind, PathErrorKind::Limit, "{e}");
    assert!(e.message.contains("cap of 1000000 turns"), "{e}");
    // Not a positive integer: as before.
    let e = err("G21 G0 X0 Y0\nG2 X0 Y0 I5 P0 F100\n");
    assert!(e.expected.contains("positive integer"), "{e}");
    let e = err("G21\nG10 L0 P1 X0\n");
    assert_eq!(e.expected, "L1, L2, L10, L11 or L20", "{e}");
}
