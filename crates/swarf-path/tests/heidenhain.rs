//! Heidenhain conversational programs: each figure below is worked out by hand from the
//! TNC's rules (contour elements, polar coordinates, cycles, coordinate transformations,
//! Q-parameter programming) and compared with the moves swarf reads.

use std::f64::consts::PI;

mod common;

use common::{close, tips};
use swarf_path::canon::Recorder;
use swarf_path::gcode::GcodeOptions;
use swarf_path::heidenhain::read_heidenhain;
use swarf_path::load::{read_program_str, ProgramFormat, ReadOptions};
use swarf_path::rewrite::rewrite_feeds;
use swarf_path::{Canon, FeedMode, Machine, MoveKind, PathError, PathErrorKind, Program};

fn read_with(src: &str, machine: Machine, opts: GcodeOptions) -> Result<Program, PathError> {
    let o = ReadOptions {
        gcode: opts,
        ..ReadOptions::default()
    };
    read_program_str(src, "t.h", machine, &o)
}

fn read(src: &str) -> Program {
    read_with(src, Machine::three_axis(), GcodeOptions::default()).unwrap()
}

fn err(src: &str) -> PathError {
    read_with(src, Machine::three_axis(), GcodeOptions::default()).unwrap_err()
}

/// The program's blocks numbered from 0 between `BEGIN PGM` and `END PGM`, as a TNC writes
/// them.
fn pgm(body: &str) -> String {
    let mut out = String::from("0 BEGIN PGM T MM\n");
    let mut n = 1;
    for l in body.lines() {
        if l.starts_with(' ') {
            out.push_str(l);
        } else {
            out.push_str(&format!("{n} {l}"));
            n += 1;
        }
        out.push('\n');
    }
    out.push_str(&format!("{n} END PGM T MM\n"));
    out
}

#[test]
fn contour_elements_end_where_the_rules_put_them() {
    let p = read(&pgm("TOOL CALL 1 Z S6000 F800\n\
         L X+60 Y+40 Z-1 R0 F300 M3\n\
         CC X+60 Y+0\n\
         C X+60 Y-40 DR-\n\
         CR X+20 Y-20 R+25 DR+\n\
         CT X+0 Y+0\n\
         LP PR+10 PA+45\n\
         CC X+0 Y+0\n\
         CP IPA+720 IZ-2 DR+"));
    let m = &p.moves;
    assert_eq!(m.len(), 6);
    // C: the clockwise half circle about (60, 0) through (100, 0).
    let MoveKind::Arc(a) = m[1].kind else {
        panic!("{:?}", m[1].kind)
    };
    assert!(close(a.center, [60.0, 0.0, -1.0], 1e-12) && a.normal.z < 0.0);
    assert!((a.sweep - PI).abs() < 1e-12);
    // CR: radius 25, counter-clockwise the short way: centre (35, −40), 126.87°.
    let MoveKind::Arc(a) = m[2].kind else {
        panic!()
    };
    assert!(close(a.center, [35.0, -40.0, -1.0], 1e-12) && a.normal.z > 0.0);
    assert!((a.sweep - (20.0f64).atan2(-15.0)).abs() < 1e-12);
    // CT: tangent to the CR at (20, −20), whose direction there is (−0.8, −0.6): the centre
    // lies on the normal (0.6, −0.8) at −800/56 mm, the arc clockwise.
    let MoveKind::Arc(a) = m[3].kind else {
        panic!()
    };
    let rho = -800.0 / 56.0;
    assert!(close(
        a.center,
        [20.0 + 0.6 * rho, -20.0 - 0.8 * rho, -1.0],
        1e-9
    ));
    assert!(a.normal.z < 0.0);
    // LP about the last pole (60, 0): radius 10 at 45°.
    let s = 10.0 / 2f64.sqrt();
    assert!(close(m[4].end.tip, [60.0 + s, s, -1.0], 1e-12));
    // CP: two turns about the new pole down 2 mm, ending where it started.
    let MoveKind::Arc(a) = m[5].kind else {
        panic!()
    };
    assert!((a.sweep - 4.0 * PI).abs() < 1e-9, "{}", a.sweep);
    assert!((a.helix + 2.0).abs() < 1e-12);
    assert!(close(m[5].end.tip, [60.0 + s, s, -3.0], 1e-9));
    assert!(m[1..].iter().all(|m| m.feed == 300.0));
}

#[test]
fn fmax_holds_for_its_block_and_fauto_takes_the_tool_feed() {
    let p = read(&pgm("TOOL CALL 1 Z S1000 F250\n\
         L X+10 FMAX\n\
         L X+20\n\
         L X+30 F100\n\
         L X+40 FMAX\n\
         L X+50\n\
         L X+60 FAUTO\n\
         L X+70 FU0.1"));
    let kinds: Vec<bool> = p.moves.iter().map(|m| m.kind == MoveKind::Rapid).collect();
    assert_eq!(kinds, [true, false, false, true, false, false, false]);
    let feeds: Vec<f64> = p.moves.iter().map(|m| m.feed).collect();
    assert_eq!(&feeds[1..], [250.0, 100.0, 100.0, 100.0, 250.0, 0.1]);
    assert_eq!(p.moves[6].feed_mode, FeedMode::PerRevolution);
}

#[test]
fn inch_programs_are_converted_and_feeds_are_tenths_of_an_inch() {
    let text = "0 BEGIN PGM I INCH\n1 TOOL CALL 1 Z S1000\n2 L X+1 Y+0.5 Z-0.1 F100\n\
                3 END PGM I INCH\n";
    let p = read(text);
    assert!(close(p.moves[0].end.tip, [25.4, 12.7, -2.54], 1e-12));
    // F100 in an inch program is 10 inch/min.
    assert!((p.moves[0].feed - 254.0).abs() < 1e-9);
}

/// The tool-axis heights of a drilling cycle's moves at X20 Y20, and whether each is rapid.
fn drill_moves(p: &Program) -> Vec<(f64, bool)> {
    p.moves
        .iter()
        .filter(|m| close(m.end.tip, [20.0, 20.0, m.end.tip.z], 1e-12))
        .map(|m| (m.end.tip.z, m.kind == MoveKind::Rapid))
        .collect()
}

#[test]
fn cycle_200_pecks_and_retracts_to_the_second_clearance() {
    let tnc640 = pgm("TOOL CALL 1 Z S3000\n\
         L Z+50 R0 FMAX M3\n\
         CYCL DEF 200 DRILLING ~\n\
         \x20 Q200=+2 ;SET-UP CLEARANCE ~\n\
         \x20 Q201=-12 ;DEPTH ~\n\
         \x20 Q206=+150 ;FEED RATE FOR PLNGNG ~\n\
         \x20 Q202=+5 ;PLUNGING DEPTH ~\n\
         \x20 Q210=+0 ;DWELL TIME AT TOP ~\n\
         \x20 Q203=+0 ;SURFACE COORDINATE ~\n\
         \x20 Q204=+30 ;2ND SET-UP CLEARANCE ~\n\
         \x20 Q211=+0.5 ;DWELL TIME AT DEPTH\n\
         L X+20 Y+20 R0 FMAX M99");
    let p = read(&tnc640);
    let expected = [
        (50.0, true),
        (2.0, true),
        (-5.0, false),
        (2.0, true),
        (-3.0, true),
        (-10.0, false),
        (2.0, true),
        (-8.0, true),
        (-12.0, false),
        (2.0, true),
        (30.0, true),
    ];
    assert_eq!(drill_moves(&p), expected);
    assert!(p
        .moves
        .iter()
        .filter(|m| m.kind == MoveKind::Linear)
        .all(|m| m.feed == 150.0));
    // The TNC 530 writes the parameters as blocks of their own after the definition.
    let tnc530 = pgm("TOOL CALL 1 Z S3000\n\
         L Z+50 R0 FMAX M3\n\
         CYCL DEF 200 DRILLING\n\
         \x20 Q200=2 ;SET-UP CLEARANCE\n\
         \x20 Q201=-12 ;DEPTH\n\
         \x20 Q206=150 ;FEED RATE FOR PLNGNG\n\
         \x20 Q202=5 ;PLUNGING DEPTH\n\
         \x20 Q210=0 ;DWELL TIME AT TOP\n\
         \x20 Q203=+0 ;SURFACE COORDINATE\n\
         \x20 Q204=30 ;2ND SET-UP CLEARANCE\n\
         \x20 Q211=0.5 ;DWELL TIME AT DEPTH\n\
         L X+20 Y+20 R0 FMAX M99");
    assert_eq!(drill_moves(&read(&tnc530)), expected);
    // The dwell at depth, once, after the last plunge.
    let mut rec = Recorder::default();
    read_heidenhain(&tnc640, "t.h", &GcodeOptions::default(), &mut rec).unwrap();
    let dwells: Vec<usize> = rec
        .events
        .iter()
        .enumerate()
        .filter(|(_, (_, e))| matches!(e, Canon::Dwell(d) if *d == 0.5))
        .map(|(i, _)| i)
        .collect();
    assert_eq!(dwells.len(), 1);
    let Canon::Feed { end } = &rec.events[dwells[0] - 1].1 else {
        panic!("{:?}", rec.events[dwells[0] - 1])
    };
    assert_eq!(end.z, -12.0);
}

#[test]
fn cycle_call_pos_takes_its_surface_and_m89_calls_at_every_position() {
    let p = read(&pgm("TOOL CALL 1 Z S3000\n\
         L Z+10 R0 FMAX M3\n\
         CYCL DEF 200 DRILLING ~\n\
         \x20 Q200=+1 ~\n\
         \x20 Q201=-3 ~\n\
         \x20 Q206=+100 ~\n\
         \x20 Q202=+0 ~\n\
         \x20 Q203=-5 ~\n\
         \x20 Q204=+20\n\
         CYCL CALL POS X+20 Y+20 Z+5 FMAX\n\
         L X+40 Y+0 FMAX M89\n\
         L X+60 FMAX\n\
         L Z+30 FMAX"));
    let t = tips(&p);
    // POS: below the second clearance above its surface (5 + 20), up first, then over the
    // hole, then 6 → 2 (feed) → 6 → 25.
    assert_eq!(
        &t[1..6],
        [
            [0.0, 0.0, 25.0],
            [20.0, 20.0, 25.0],
            [20.0, 20.0, 6.0],
            [20.0, 20.0, 2.0],
            [20.0, 20.0, 6.0]
        ]
    );
    assert_eq!(t[6], [20.0, 20.0, 25.0]);
    // M89: the surface is Q203 = −5: the holes go to −8 at X40 and X60.
    let bottoms: Vec<[f64; 3]> = t.iter().copied().filter(|p| p[2] == -8.0).collect();
    assert_eq!(bottoms, [[40.0, 0.0, -8.0], [60.0, 0.0, -8.0]]);
    // A move along the tool axis alone calls nothing: the last move is Z30's.
    assert_eq!(*t.last().unwrap(), [60.0, 0.0, 30.0]);
}

#[test]
fn datum_shift_and_rotation_move_the_part_frame() {
    let p = read(&pgm("TOOL CALL 1 Z S3000 F100\n\
         CYCL DEF 7.0 DATUM SHIFT\n\
         CYCL DEF 7.1 X+100\n\
         CYCL DEF 7.2 Y+50\n\
         CYCL DEF 10.0 ROTATION\n\
         CYCL DEF 10.1 ROT+90\n\
         L X+10 Y+0 Z+0 R0 F100\n\
         CYCL DEF 7.0 DATUM SHIFT\n\
         CYCL DEF 7.1 IX+5\n\
         L X+10 Y+0\n\
         CYCL DEF 10.0 ROTATION\n\
         CYCL DEF 10.1 ROT+0\n\
         CYCL DEF 7.0 DATUM SHIFT\n\
         CYCL DEF 7.1 X+0\n\
         CYCL DEF 7.2 Y+0\n\
         L X+10 Y+0"));
    let t = tips(&p);
    assert!(
        close(p.moves[0].end.tip, [100.0, 60.0, 0.0], 1e-12),
        "{t:?}"
    );
    assert!(
        close(p.moves[1].end.tip, [105.0, 60.0, 0.0], 1e-12),
        "{t:?}"
    );
    assert!(close(p.moves[2].end.tip, [10.0, 0.0, 0.0], 1e-12), "{t:?}");
}

#[test]
fn plane_spatial_turns_the_tool_and_reset_turns_it_back() {
    let p = read(&pgm("TOOL CALL 1 Z S3000 F100\n\
         L X+0 Y+0 Z+50 R0 FMAX\n\
         PLANE SPATIAL SPA+0 SPB+45 SPC+0 TURN MB 10 FMAX\n\
         L X+0 Y+0 Z+10 FMAX\n\
         L Z-2 F500\n\
         PLANE RESET TURN FMAX\n\
         L Z+50 FMAX"));
    let m = &p.moves;
    // MB 10: 10 mm up along the (vertical) tool axis before the axes turn.
    assert!(close(m[1].end.tip, [0.0, 0.0, 60.0], 1e-12));
    let s = 0.5f64.sqrt();
    // In the plane turned 45° about Y, its Z is (s, 0, s).
    assert!(close(m[2].end.tip, [10.0 * s, 0.0, 10.0 * s], 1e-12));
    assert!(close(m[2].end.axis, [s, 0.0, s], 1e-12));
    assert!(close(m[3].end.tip, [-2.0 * s, 0.0, -2.0 * s], 1e-12));
    assert!(close(m[4].end.tip, [-2.0 * s, 0.0, 50.0], 1e-12));
    // RESET TURN turns the rotary axes back.
    assert!(close(m[4].end.axis, [0.0, 0.0, 1.0], 1e-12));
}

#[test]
fn a_plane_tilted_again_after_reset_turn_turns_the_tool_to_it() {
    // No move between the reset and the next tilt (posts write this between operations).
    let p = read(&pgm("TOOL CALL 1 Z S5000\n\
         PLANE SPATIAL SPA+0 SPB+30 SPC+0 TURN FMAX\n\
         PLANE RESET TURN FMAX\n\
         PLANE SPATIAL SPA+0 SPB-45 SPC+0 TURN FMAX\n\
         L X+0 Y+0 Z+10 R0 FMAX\nL Z-3 F500\nL Y+20"));
    let s = 0.5f64.sqrt();
    for m in &p.moves {
        assert!(close(m.end.axis, [-s, 0.0, s], 1e-12), "{:?}", m.end.axis);
    }
}

#[test]
fn a_program_that_never_ends_meets_the_loop_limit() {
    let opts = GcodeOptions {
        max_loop_iterations: 1000,
        ..GcodeOptions::default()
    };
    let e = read_with(
        &pgm("LBL 1\nCALL LBL 1 REP 2\nFN 9: IF +0 EQU +0 GOTO LBL 1"),
        Machine::three_axis(),
        opts,
    )
    .unwrap_err();
    assert_eq!(e.kind, PathErrorKind::Limit, "{e}");
    // Three jumps a round: the 1001st is the second repeat of a round.
    assert_eq!((e.pos.line, e.pos.column), (3, 3), "{e}");
}

#[test]
fn ln_blocks_state_the_tool_axis() {
    let p = read(&pgm("TOOL CALL 1 Z S3000 F100\n\
         M128\n\
         LN X+10 Y+0 Z+5 NX+0 NY+0 NZ+1 TX+0 TY+0 TZ+1 F1000\n\
         LN X+12 Y+0 Z+5 NX+0 NY+0 NZ+1 TX+0.6 TY+0 TZ+0.8"));
    assert!(close(p.moves[0].end.axis, [0.0, 0.0, 1.0], 1e-12));
    assert!(close(p.moves[1].end.axis, [0.6, 0.0, 0.8], 1e-12));
    assert!(close(p.moves[1].end.tip, [12.0, 0.0, 5.0], 1e-12));
}

#[test]
fn q_parameters_labels_and_repeats_run_as_the_control_runs_them() {
    let p = read(&pgm("TOOL CALL 1 Z S3000 F100\n\
         FN 0: Q1 = +0\n\
         Q2 = 2 * SIN(30) + SQRT(9)\n\
         LBL 1\n\
         FN 1: Q1 = +Q1 + +1\n\
         L X+Q1 Y+Q2 F100\n\
         FN 12: IF +Q1 LT +3 GOTO LBL 1\n\
         LBL \"SECTION\"\n\
         L IZ-1\n\
         CALL LBL \"SECTION\" REP 2\n\
         CALL LBL 5\n\
         CALL LBL 5\n\
         M30\n\
         LBL 5\n\
         L IY+10\n\
         LBL 0"));
    let t = tips(&p);
    assert_eq!(
        t,
        [
            [1.0, 4.0, 0.0],
            [2.0, 4.0, 0.0],
            [3.0, 4.0, 0.0],
            [3.0, 4.0, -1.0],
            [3.0, 4.0, -2.0],
            [3.0, 4.0, -3.0],
            [3.0, 14.0, -3.0],
            [3.0, 24.0, -3.0]
        ]
    );
}

#[test]
fn other_programs_are_called_from_beside_the_program() {
    let dir = std::env::temp_dir().join(format!("swarf-heid-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("HOLE.h"),
        "0 BEGIN PGM HOLE MM\n1 L IZ-5 F100\n2 L IZ+5 FMAX\n3 END PGM HOLE MM\n",
    )
    .unwrap();
    let main = dir.join("MAIN.h");
    let text = pgm("TOOL CALL 1 Z S3000 F100\nL X+10 Z+2 FMAX\nCALL PGM TNC:\\PARTS\\HOLE.H\nL X+20 FMAX\nCALL PGM HOLE");
    let mut rec = Recorder::default();
    read_heidenhain(
        &text,
        &main.display().to_string(),
        &GcodeOptions::default(),
        &mut rec,
    )
    .unwrap();
    let z: Vec<f64> = rec
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::Feed { end } | Canon::Traverse { end } => Some(end.z),
            _ => None,
        })
        .collect();
    assert_eq!(z, [2.0, -3.0, 2.0, 2.0, -3.0, 2.0]);
    assert!(rec
        .events
        .iter()
        .any(|(_, e)| matches!(e, Canon::SourceFile(f) if f.ends_with("HOLE.h"))));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn refused_and_wrong_blocks_are_errors_at_their_place() {
    let cases: [(&str, PathErrorKind, u32, u32, &str); 9] = [
        ("L X+10 RL F100", PathErrorKind::Unsupported, 1, 10, "RL"),
        ("L X+10 X+20 F100", PathErrorKind::Semantic, 1, 10, "X+20"),
        ("RND R2", PathErrorKind::Unsupported, 1, 3, "RND"),
        (
            "L X+10 Y+0 F100\nCC X+0 Y+0\nC X+0 Y+12 DR+",
            PathErrorKind::Semantic,
            3,
            3,
            "C",
        ),
        (
            "L X+0 Y+0 F100\nCR X+30 Y+0 R+10 DR+",
            PathErrorKind::Semantic,
            2,
            3,
            "CR",
        ),
        (
            "Q1 = 10 / (2 - 2)",
            PathErrorKind::Semantic,
            1,
            11,
            "10 / (2 - 2)",
        ),
        ("L X+10", PathErrorKind::Semantic, 1, 3, "L"),
        ("FOO BAR", PathErrorKind::Syntax, 1, 3, "FOO"),
        ("L X+1.2.3 F100", PathErrorKind::Syntax, 1, 6, "+1.2.3"),
    ];
    for (body, kind, line, col, found) in cases {
        let e = err(&pgm(body));
        assert_eq!(e.kind, kind, "{body}: {e}");
        assert_eq!((e.pos.line, e.pos.column), (line + 1, col), "{body}: {e}");
        assert_eq!(e.found, found, "{body}: {e}");
        assert_eq!(e.pos.file, "t.h");
    }
}

#[test]
fn heidenhain_text_is_recognised_whatever_the_extension() {
    let text = pgm("L X+1 F100");
    for name in ["a.h", "a.H", "a.ptp", "a.nc", "a"] {
        assert_eq!(
            ProgramFormat::detect(std::path::Path::new(name), &text),
            ProgramFormat::Heidenhain,
            "{name}"
        );
    }
    assert_eq!(
        ProgramFormat::detect(std::path::Path::new("a.ptp"), "G0 X1\nM30\n"),
        ProgramFormat::Gcode
    );
}

#[test]
fn schedule_rewrites_heidenhain_feed_words() {
    let text = "0 BEGIN PGM T MM\n1 TOOL CALL 1 Z S1000 F200\n2 L X+10 F100 ; cut\n\
                3 L X+20 ; more\n4 L X+30 FMAX\n5 END PGM T MM\n";
    // (Keys are file lines: BEGIN PGM is line 1.)
    let factors = [(3, 1.5), (4, 0.5)].into_iter().collect();
    let r = rewrite_feeds(
        text,
        "t.h",
        ProgramFormat::Heidenhain,
        &factors,
        &Default::default(),
    )
    .unwrap();
    assert_eq!(
        r.text,
        "0 BEGIN PGM T MM\n1 TOOL CALL 1 Z S1000 F200\n2 L X+10 F150 ; cut\n\
         3 L X+20 F50 ; more\n4 L X+30 FMAX\n5 END PGM T MM\n"
    );
    // The rewritten program reads with the new feeds.
    let p = read(&r.text);
    let feeds: Vec<f64> = p.moves.iter().map(|m| m.feed).collect();
    assert_eq!(&feeds[..2], [150.0, 50.0]);
    // A cycle call's feed is its Q206: not rewritten.
    let cyc = "0 BEGIN PGM T MM\n1 L X+10 F100 M99\n2 END PGM T MM\n";
    let factors = [(2, 1.5)].into_iter().collect();
    let e = rewrite_feeds(
        cyc,
        "t.h",
        ProgramFormat::Heidenhain,
        &factors,
        &Default::default(),
    )
    .unwrap_err();
    assert_eq!(e.pos.line, 2, "{e}");
}

#[test]
fn review_cases_read_as_the_control_reads_them() {
    // SEQ− and TABLE ROT in a PLANE block say how the axes move, not where the plane is.
    let p = read(&pgm("TOOL CALL 1 Z S3000 F100\n\
         PLANE SPATIAL SPA+0 SPB+90 SPC+0 TURN FMAX SEQ- TABLE ROT\n\
         L X+0 Y+0 Z+10 FMAX"));
    assert!(close(p.moves[0].end.tip, [10.0, 0.0, 0.0], 1e-12));
    // A datum shift and a rotation programmed in the tilted plane act along its axes: its X is
    // the machine's −Z, its Y the machine's Y.
    let p = read(&pgm("TOOL CALL 1 Z S3000 F100\n\
         PLANE SPATIAL SPA+0 SPB+90 SPC+0 TURN FMAX\n\
         CYCL DEF 7.0 DATUM SHIFT\n\
         CYCL DEF 7.1 X+10\n\
         L X+0 Y+0 Z+0 FMAX\n\
         CYCL DEF 10.0 ROTATION\n\
         CYCL DEF 10.1 ROT+90\n\
         L X+10 Y+0 Z+0 FMAX"));
    assert!(
        close(p.moves[0].end.tip, [0.0, 0.0, -10.0], 1e-12),
        "{:?}",
        tips(&p)
    );
    assert!(
        close(p.moves[1].end.tip, [0.0, 10.0, -10.0], 1e-12),
        "{:?}",
        tips(&p)
    );
    // Tool axis Y: M140 retracts along Y.
    let p = read(&pgm("TOOL CALL 1 Y S3000 F100\n\
         L X+0 Y+10 Z+0 R0 FMAX\n\
         M140 MB+20"));
    assert!(close(p.moves[1].end.tip, [0.0, 30.0, 0.0], 1e-12));
    let e = err(&pgm(
        "TOOL CALL 1 Y S3000 F100\nCYCL DEF 10.0 ROTATION\nCYCL DEF 10.1 ROT+90",
    ));
    assert_eq!(e.kind, PathErrorKind::Unsupported);
    // The F after M128 is M128's; `L M3` is no move.
    let p = read(&pgm("TOOL CALL 1 Z S3000 F100\n\
         L M3\n\
         L X+0 Y+0 Z+50 R0 FMAX M128 F1000\n\
         L X+10 R0 F125 M128 F2000"));
    assert_eq!(p.moves.len(), 2);
    assert_eq!(p.moves[0].kind, MoveKind::Rapid);
    assert_eq!(p.moves[1].feed, 125.0);
    // M126: the shortest way round.
    let p = read(&pgm("TOOL CALL 1 Z S3000 F100\n\
         L C+350 R0 FMAX M126\n\
         L C+10 FMAX\n\
         M127\n\
         L C+350 FMAX"));
    let c: Vec<f64> = p.moves.iter().map(|m| m.end_joints.c).collect();
    // (From C0 the shortest way to 350 is −10°, then +20° to 10; M127: +340° to 350.)
    assert_eq!(c, [-10.0, 10.0, 350.0]);
    // A CR whose chord is a rounding longer than its diameter is the half circle.
    let p = read(&pgm(
        "TOOL CALL 1 Z S3000 F100\nL X+0 Y+0 Z+0 F100\nCR X+10.0004 Y+0 R+5 DR+",
    ));
    let MoveKind::Arc(a) = p.moves[1].kind else {
        panic!()
    };
    assert!((a.sweep - PI).abs() < 1e-9, "{}", a.sweep);
    // REP written without its space; anything else after the label is an error at its word.
    let p = read(&pgm(
        "TOOL CALL 1 Z S3000 F100\nLBL 1\nL IX+1\nCALL LBL 1 REP2",
    ));
    assert_eq!(p.moves.len(), 3);
    let e = err(&pgm("LBL 1\nCALL LBL 1 FOO"));
    assert_eq!(
        (e.pos.line, e.pos.column, e.found.as_str()),
        (3, 14, "FOO"),
        "{e}"
    );
    let e = err(&pgm("FN 9: IF +0 EQU +0 GOTO LBL 7"));
    assert_eq!((e.pos.column, e.found.as_str()), (31, "7"), "{e}");
    // An inch program's PLANE MB with a space: inches.
    let text = "0 BEGIN PGM I INCH\n1 TOOL CALL 1 Z S1000 F100\n2 L X+0 Y+0 Z+1 FMAX\n\
                3 PLANE SPATIAL SPA+0 SPB+0 SPC+0 TURN MB 2 FMAX\n4 END PGM I INCH\n";
    let p = read(text);
    assert!(close(p.moves[1].end.tip, [0.0, 0.0, 3.0 * 25.4], 1e-9));
}

#[test]
fn cycle_203_breaks_chips_and_retracts_at_its_feed() {
    let p = read(&pgm("TOOL CALL 1 Z S3000\n\
         L X+20 Y+20 Z+10 R0 FMAX M3\n\
         CYCL DEF 203 UNIVERSAL DRILLING ~\n\
         \x20 Q200=+2 ~\n\
         \x20 Q201=-9 ~\n\
         \x20 Q206=+100 ~\n\
         \x20 Q202=+4 ~\n\
         \x20 Q210=+0 ~\n\
         \x20 Q203=+0 ~\n\
         \x20 Q204=+10 ~\n\
         \x20 Q212=+1 ~\n\
         \x20 Q213=+1 ~\n\
         \x20 Q205=+2 ~\n\
         \x20 Q211=+0 ~\n\
         \x20 Q208=+0 ~\n\
         \x20 Q256=+0.5\n\
         CYCL CALL"));
    // Pecks of 4, 3 (4 − 1), then 2 to the depth of 9; after the first a chip break (0.5 mm
    // back), after the second a full retract at the plunging feed (Q208 = 0), down again at
    // rapid to 2 above the depth reached; out at the plunging feed, then to Q204.
    let expected = [
        (10.0, true),
        (2.0, true),
        (-4.0, false),
        (-3.5, true),
        (-7.0, false),
        (2.0, false),
        (-5.0, true),
        (-9.0, false),
        (2.0, false),
        (10.0, true),
    ];
    assert_eq!(drill_moves(&p), expected);
}

#[test]
fn schedule_puts_a_new_heidenhain_feed_before_the_m_functions() {
    let text = "0 BEGIN PGM T MM\n1 L X+10 F100\n2 L X+30 M8 ; on\n3 END PGM T MM\n";
    let factors = [(3, 0.628733)].into_iter().collect();
    let r = rewrite_feeds(
        text,
        "t.h",
        ProgramFormat::Heidenhain,
        &factors,
        &Default::default(),
    )
    .unwrap();
    assert_eq!(r.text.lines().nth(2), Some("2 L X+30 F62.873 M8 ; on"));
    // The F after M128 is not the program's feed.
    let text = "0 BEGIN PGM T MM\n1 L X+10 F2000 M128 F500\n2 END PGM T MM\n";
    let factors = [(2, 0.5)].into_iter().collect();
    let r = rewrite_feeds(
        text,
        "t.h",
        ProgramFormat::Heidenhain,
        &factors,
        &Default::default(),
    )
    .unwrap();
    assert_eq!(r.text.lines().nth(1), Some("1 L X+10 F1000 M128 F500"));
}

#[test]
fn second_review_cases() {
    // M140 in a motion block retracts at the block's end: the cut at Z0 stays.
    let p = read(&pgm(
        "TOOL CALL 1 Z S3000 F100\nL X+0 Y+0 Z+0 R0 F100\nL X+10 Y+10 R0 F100 M140 MB 50",
    ));
    assert_eq!(
        tips(&p),
        [[0.0, 0.0, 0.0], [10.0, 10.0, 0.0], [10.0, 10.0, 50.0]]
    );
    // An absolute datum shift in a tilted plane is measured from the preset: clearing it
    // there clears the shift programmed before the tilt too.
    let p = read(&pgm("TOOL CALL 1 Z S3000 F100\n\
         CYCL DEF 7.0 DATUM SHIFT\n\
         CYCL DEF 7.1 X+10\n\
         PLANE SPATIAL SPA+0 SPB+30 SPC+0 TURN FMAX\n\
         CYCL DEF 7.0 DATUM SHIFT\n\
         CYCL DEF 7.1 X+0\n\
         CYCL DEF 7.2 Y+0\n\
         CYCL DEF 7.3 Z+0\n\
         PLANE RESET TURN FMAX\n\
         L X+0 Y+0 Z+50 F100"));
    assert!(
        close(p.moves.last().unwrap().end.tip, [0.0, 0.0, 50.0], 1e-12),
        "{:?}",
        tips(&p)
    );
    // An error in a called file names that file.
    let dir = std::env::temp_dir().join(format!("swarf-heid2-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("SUB.h"),
        "0 BEGIN PGM SUB MM\n1 LBL 1\n2 LBL 1\n3 END PGM SUB MM\n",
    )
    .unwrap();
    let main = dir.join("MAIN.h").display().to_string();
    let e = read_heidenhain(
        &pgm("CALL PGM SUB"),
        &main,
        &GcodeOptions::default(),
        &mut Recorder::default(),
    )
    .unwrap_err();
    assert!(e.pos.file.ends_with("SUB.h") && e.pos.line == 3, "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn preset_and_table_selections_are_warned_not_refused() {
    let text = pgm("PRESET SELECT #1\nSEL TABLE \"TNC:\\TABLE\\ZERO.D\"\nDECLARE STRING QS1 = \"A\"\nL X+1 F100");
    let mut rec = Recorder::default();
    read_heidenhain(&text, "t.h", &GcodeOptions::default(), &mut rec).unwrap();
    assert_eq!(rec.warnings.len(), 3, "{:?}", rec.warnings);
    assert_eq!(err(&pgm("PATTERN DEF")).kind, PathErrorKind::Unsupported);
}

#[test]
fn a_name_the_tool_library_lacks_gets_a_number_it_does_not_use() {
    let opts = GcodeOptions {
        tool_names: [("MILL_D10".to_string(), 1), ("BALL_D6".to_string(), 7)]
            .into_iter()
            .collect(),
        ..GcodeOptions::default()
    };
    let text =
        pgm("TOOL CALL \"ball_d6\" Z S1000\nTOOL CALL \"NOSUCH\" Z S1000\nTOOL CALL \"nosuch\" Z");
    let mut rec = Recorder::default();
    read_heidenhain(&text, "t.h", &opts, &mut rec).unwrap();
    let tools: Vec<u32> = rec
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::ToolChange { tool } => Some(*tool),
            _ => None,
        })
        .collect();
    // (Names are matched in any case: "NOSUCH" and "nosuch" are one tool, numbered above the
    // library's 7.)
    assert_eq!(tools, [7, 8, 8]);
}

/// M functions that take parameters (`M120 LA5`, `M124 T0.01`, M118's handwheel limits,
/// M138's axes) keep them: the words after them are not the block's coordinates, and the path
/// is the one without them. `SEL CORR-TABLE` is warned and passed, as `SEL TABLE` is.
#[test]
fn m_function_parameters_are_not_coordinates() {
    let plain = read(&pgm("L X+0 Y+0 Z+10 R0 FMAX\nL X+5 F100\nL Y+3\nM30"));
    let p = read(&pgm(
        "L X+0 Y+0 Z+10 R0 FMAX M120 LA5\nM118 X1 Y2\nM124 T0.01\nL X+5 F100 M138 B C\n\
         M112 T0.01 A10\nM94 C\nSEL CORR-TABLE TCS \"T.TCO\"\nL Y+3 M3 M120 LA2\nM30",
    ));
    assert_eq!(tips(&p), tips(&plain));
    assert_eq!(p.warnings.len(), 1, "{:?}", p.warnings);
    assert!(
        p.warnings[0].message.starts_with("SEL CORR-TABLE"),
        "{:?}",
        p.warnings
    );
}

/// `got` equal to `want` within 1e-9 mm (heights and rapid or not).
fn same_moves(got: &[(f64, bool)], want: &[(f64, bool)]) {
    assert!(
        got.len() == want.len()
            && got
                .iter()
                .zip(want)
                .all(|(a, b)| (a.0 - b.0).abs() < 1e-9 && a.1 == b.1),
        "got {got:?}\nwant {want:?}"
    );
}

/// Cycle 205 at X+20 Y+20 from Z+100 with the given Q parameters after the common ones
/// (Q200 2, Q203 0, Q204 50, Q206 150, Q208 99999, Q211 0).
fn cycle_205(qs: &str) -> Program {
    let mut body = String::from(
        "TOOL CALL 3 Z S2000\n\
         L X+20 Y+20 Z+100 R0 FMAX M3\n\
         CYCL DEF 205 UNIVERSAL PECKING ~\n\
         \x20 Q200=+2 ~\n\
         \x20 Q203=+0 ~\n\
         \x20 Q204=+50 ~\n\
         \x20 Q206=+150 ~\n\
         \x20 Q208=+99999 ~\n",
    );
    for q in qs.split_whitespace() {
        body.push_str(&format!("\x20 {q} ~\n"));
    }
    body.push_str("\x20 Q211=+0\nCYCL CALL");
    read(&pgm(&body))
}

#[test]
fn cycle_205_breaks_chips_and_reenters_at_its_advanced_stop_distances() {
    // The review's program (h14.h): depth 20 in plunges of 10, Q258 = Q259 = 0.5, chip
    // breaking every 4 mm (Q257) by 0.2 (Q256). The TNC manual's run of cycle 205: after each
    // Q257 of a plunge back Q256 and on at the feed; after the plunge out to the set-up
    // clearance, back in at rapid to the advanced stop distance above the depth reached;
    // at the depth out to the set-up clearance at Q208, then to Q204 at rapid. (swarf made no
    // chip breaks and re-entered at Q200, 2 above the depth.)
    let p = cycle_205(
        "Q201=-20 Q202=+10 Q212=+0 Q205=+0 Q258=+0.5 Q259=+0.5 Q257=+4 Q256=+0.2 Q379=+0 \
         Q253=+750 Q395=+0",
    );
    same_moves(
        &drill_moves(&p),
        &[
            (100.0, true),
            (2.0, true),
            (-4.0, false),
            (-3.8, true),
            (-8.0, false),
            (-7.8, true),
            (-10.0, false),
            (2.0, true),
            (-9.5, true),
            (-14.0, false),
            (-13.8, true),
            (-18.0, false),
            (-17.8, true),
            (-20.0, false),
            (2.0, false),
            (50.0, true),
        ],
    );
    // Q258 ≠ Q259: from 1 before the first re-entry (at 5) to 0.4 before the last (at 15),
    // evenly between: 0.7 at 10. No chip breaking (Q257 = 0).
    let p = cycle_205("Q201=-20 Q202=+5 Q212=+0 Q205=+0 Q258=+1 Q259=+0.4 Q257=+0 Q256=+0.2");
    same_moves(
        &drill_moves(&p),
        &[
            (100.0, true),
            (2.0, true),
            (-5.0, false),
            (2.0, true),
            (-4.0, true),
            (-10.0, false),
            (2.0, true),
            (-9.3, true),
            (-15.0, false),
            (2.0, true),
            (-14.6, true),
            (-20.0, false),
            (2.0, false),
            (50.0, true),
        ],
    );
    // One plunge (Q202 at least the depth) with chip breaking: breaks at 4 and 8 of 9.
    let p = cycle_205("Q201=-9 Q202=+10 Q212=+0 Q205=+0 Q258=+0.5 Q259=+0.5 Q257=+4 Q256=+0.2");
    same_moves(
        &drill_moves(&p),
        &[
            (100.0, true),
            (2.0, true),
            (-4.0, false),
            (-3.8, true),
            (-8.0, false),
            (-7.8, true),
            (-9.0, false),
            (2.0, false),
            (50.0, true),
        ],
    );
}
