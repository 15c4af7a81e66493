//! Siemens Sinumerik 840D programs: each figure below is worked out by hand from the
//! control's rules (arcs by centre, radius and intermediate point, frames, the swivel cycle,
//! drilling cycles, R parameters and program flow) and compared with the moves swarf reads.

use std::f64::consts::PI;

mod common;

use common::{close, tips};
use swarf_path::canon::Recorder;
use swarf_path::gcode::GcodeOptions;
use swarf_path::load::{read_program_str, ProgramFormat, ReadOptions};
use swarf_path::sinumerik::read_sinumerik;
use swarf_path::{Canon, FeedMode, Machine, MoveKind, PathError, PathErrorKind, Program};

fn read_with(src: &str, opts: GcodeOptions) -> Result<Program, PathError> {
    let o = ReadOptions {
        gcode: opts,
        ..ReadOptions::default()
    };
    read_program_str(src, "t.mpf", Machine::three_axis(), &o)
}

/// Reads `src` as a Sinumerik program (its first line makes the detection sure).
fn read(src: &str) -> Program {
    read_with(&format!("G500\n{src}"), GcodeOptions::default()).unwrap()
}

fn err(src: &str) -> PathError {
    read_with(&format!("G500\n{src}"), GcodeOptions::default()).unwrap_err()
}

#[test]
fn arcs_by_centre_radius_and_intermediate_point() {
    let p = read(
        "G90 G17 G710 G94\n\
         G1 X50 Y-30 Z-2 F300\n\
         G2 X60 Y-20 CR=10\n\
         G3 X70 Y-10 I=AC(60) J=AC(-10)\n\
         G2 X50 Y-10 I-10 J0\n\
         CIP X30 Y-10 I1=40 J1=-10 K1=-12\n\
         G3 X50 Y-10 I10 J0 Z-4 TURN=2",
    );
    let m = &p.moves;
    // CR=10 clockwise the short way from (50, −30) to (60, −20): centre (60, −30), 90°.
    let MoveKind::Arc(a) = m[1].kind else {
        panic!()
    };
    assert!(close(a.center, [60.0, -30.0, -2.0], 1e-12) && a.normal.z < 0.0);
    assert!((a.sweep - PI / 2.0).abs() < 1e-12);
    // Absolute centre (60, −10).
    let MoveKind::Arc(a) = m[2].kind else {
        panic!()
    };
    assert!(close(a.center, [60.0, -10.0, -2.0], 1e-12) && a.normal.z > 0.0);
    // Incremental centre: a clockwise half circle about (60, −10).
    let MoveKind::Arc(a) = m[3].kind else {
        panic!()
    };
    assert!(close(a.center, [60.0, -10.0, -2.0], 1e-12) && (a.sweep - PI).abs() < 1e-12);
    // CIP through (40, −10, −12) from (50, −10, −2) to (30, −10, −2): the circle of radius 10
    // about (40, −10, −2) in the plane Y = −10, a half turn.
    let MoveKind::Arc(a) = m[4].kind else {
        panic!("{:?}", m[4].kind)
    };
    assert!(close(a.center, [40.0, -10.0, -2.0], 1e-9), "{:?}", a.center);
    assert!((a.sweep - PI).abs() < 1e-9 && a.normal.y.abs() > 1.0 - 1e-12);
    // TURN=2: a half circle plus two turns, down 2 mm.
    let MoveKind::Arc(a) = m[5].kind else {
        panic!()
    };
    assert!((a.sweep - 5.0 * PI).abs() < 1e-9 && (a.helix + 2.0).abs() < 1e-12);
    assert!(m[1..].iter().all(|m| m.feed == 300.0));
}

#[test]
fn coordinates_units_and_feeds() {
    let p = read(
        "G91 G1 X10 Y10 F100\n\
         X=AC(0) Y=IC(5)\n\
         G90 G700 G1 X1 F10\n\
         G70 G1 X2 F100\n\
         G71 G95 G1 X0 F0.1 S1000 M3\n\
         G94 G4 F2.5\n\
         G4 S10",
    );
    let t = tips(&p);
    assert_eq!(&t[..2], [[10.0, 10.0, 0.0], [0.0, 15.0, 0.0]]);
    // G700: inch lengths and feeds; G70: inch lengths, the feed in the basic system (mm).
    assert!(close(p.moves[2].end.tip, [25.4, 15.0, 0.0], 1e-12));
    assert!((p.moves[2].feed - 254.0).abs() < 1e-9);
    assert!(close(p.moves[3].end.tip, [50.8, 15.0, 0.0], 1e-12));
    assert_eq!(p.moves[3].feed, 100.0);
    assert_eq!(p.moves[4].feed_mode, FeedMode::PerRevolution);
    assert_eq!(p.moves[4].feed, 0.1);
    // G4 F2.5 s and G4 S10 revolutions at 1000 rpm (0.6 s).
    assert!((p.dwell_s - 3.1).abs() < 1e-12, "{}", p.dwell_s);
}

#[test]
fn frames_shift_and_turn_the_program() {
    let p = read(
        "G1 F100\n\
         TRANS X100 Y50\n\
         AROT RPL=90\n\
         G1 X10 Y0\n\
         ATRANS X5\n\
         G1 X10 Y0\n\
         ROT\n\
         G1 X10 Y0\n\
         TRANS\n\
         G1 X10 Y0",
    );
    let t = tips(&p);
    assert!(
        close(p.moves[0].end.tip, [100.0, 60.0, 0.0], 1e-12),
        "{t:?}"
    );
    // ATRANS along the turned X: (0, 5).
    assert!(
        close(p.moves[1].end.tip, [100.0, 65.0, 0.0], 1e-12),
        "{t:?}"
    );
    // ROT alone: a new programmable frame, nothing in it.
    assert!(close(p.moves[2].end.tip, [10.0, 0.0, 0.0], 1e-12), "{t:?}");
    assert!(close(p.moves[3].end.tip, [10.0, 0.0, 0.0], 1e-12), "{t:?}");
}

#[test]
fn cycle800_tilts_the_plane_and_turns_the_tool() {
    let p = read(
        "G0 X0 Y0 Z50\n\
         CYCLE800(1,\"TC1\",0,57,10,0,0,0,45,0,0,0,5,1,100,1)\n\
         G0 X0 Y0 Z10\n\
         CYCLE800()\n\
         G0 Z50",
    );
    let s = 0.5f64.sqrt();
    // Pivot at X10, turned 45° about Y, then 5 along the turned Z: the plane's origin is
    // (10 + 5s, 0, 5s) and its Z (s, 0, s).
    let m = &p.moves;
    let o = [10.0 + 5.0 * s, 0.0, 5.0 * s];
    assert!(
        close(m[1].end.tip, [o[0] + 10.0 * s, 0.0, o[2] + 10.0 * s], 1e-9),
        "{:?}",
        tips(&p)
    );
    assert!(close(m[1].end.axis, [s, 0.0, s], 1e-12));
    // `CYCLE800()` deselects the swivel: the frame is the old one, the rotary axes stay,
    // so the tool keeps its axis.
    assert!(
        close(m[2].end.tip, [o[0] + 10.0 * s, 0.0, 50.0], 1e-9),
        "{:?}",
        tips(&p)
    );
    assert!(close(m[2].end.axis, [s, 0.0, s], 1e-12));
    // A reset to zero angles with a swivel direction turns the axes back: the machine's axis.
    let p = read(
        "CYCLE800(1,\"TC1\",0,57,0,0,0,0,45,0,0,0,0,1,100,1)\nG0 X0 Y0 Z10\n\
         CYCLE800(1,\"TC1\",0,57,0,0,0,0,0,0,0,0,0,1,100,1)\nG0 Z50",
    );
    assert!(close(p.moves[0].end.axis, [s, 0.0, s], 1e-12));
    assert!(close(p.moves[1].end.axis, [0.0, 0.0, 1.0], 1e-12));
}

#[test]
fn a_plane_tilted_again_after_a_reset_turns_the_tool_to_it() {
    // Posts write a reset between 3+2 operations, often with no move before the next tilt:
    // the tool takes the second plane's axis (it kept the machine's).
    let s = 0.5f64.sqrt();
    for reset in [
        "CYCLE800()",
        "CYCLE800(1,\"TC1\",200000,57,0,0,0,0,0,0,0,0,0,1,100,1)",
    ] {
        let p = read(&format!(
            "T1 M6\nCYCLE800(1,\"TC1\",200000,57,0,0,0,0,30,0,0,0,0,1,100,1)\n{reset}\n\
             CYCLE800(1,\"TC1\",200000,57,0,0,0,0,-45,0,0,0,0,1,100,1)\n\
             G0 X0 Y0 Z10\nG1 Z-3 F500\nY20"
        ));
        for m in &p.moves {
            assert!(
                close(m.end.axis, [-s, 0.0, s], 1e-12),
                "{reset}: {:?}",
                m.end.axis
            );
        }
    }
}

#[test]
fn traori_takes_the_tool_vector() {
    let p = read("TRAORI\nG1 X10 Y0 Z5 A3=0 B3=0 C3=1 F1000\nX12 A3=0.6 B3=0 C3=0.8\nTRAFOOF");
    assert!(close(p.moves[0].end.axis, [0.0, 0.0, 1.0], 1e-12));
    assert!(close(p.moves[1].end.axis, [0.6, 0.0, 0.8], 1e-12));
}

/// The heights of the moves at X20 Y20, and whether each is rapid.
fn at_hole(p: &Program) -> Vec<(f64, bool)> {
    p.moves
        .iter()
        .filter(|m| close(m.end.tip, [20.0, 20.0, m.end.tip.z], 1e-12))
        .map(|m| (m.end.tip.z, m.kind == MoveKind::Rapid))
        .collect()
}

#[test]
fn drilling_cycles_run_where_the_tool_stands_and_under_mcall() {
    // CYCLE81(RTP 30, RFP 0, SDIS 2, DP −10): down to 2 at rapid, fed to −10, out to 30.
    let p = read("G0 X20 Y20 Z50 S1000 M3\nG1 F100\nCYCLE81(30,0,2,-10)\nM30");
    assert_eq!(
        at_hole(&p),
        [(50.0, true), (2.0, true), (-10.0, false), (30.0, true)]
    );
    // CYCLE83 (deep hole, chip removal): first depth 4 below RFP, degression 1 → pecks of 4,
    // 3, 2 (not below the degression's 1… but the hole ends at 9); back in at rapid to the
    // cycle's own advance distance above the depth reached (_DIS1 not given: 0.6 mm, the
    // hole being under 30 mm deep).
    let p = read(
        "G0 X20 Y20 Z50 S1000 M3\nG1 F100\n\
         CYCLE83(30,0,2,-9,,,4,1,0,0,1,1)\nM30",
    );
    assert_eq!(
        at_hole(&p),
        [
            (50.0, true),
            (2.0, true),
            (-4.0, false),
            (2.0, true),
            (-4.0 + 0.6, true),
            (-7.0, false),
            (2.0, true),
            (-7.0 + 0.6, true),
            (-9.0, false),
            (30.0, true)
        ]
    );
    // CYCLE84 M8: pitch 1.25, spindle-synchronised down and back.
    let p = read("G0 X20 Y20 Z50 S500 M3\nG1 F100\nCYCLE84(30,0,2,-10,,0,3,8)\nM30");
    let tap: Vec<&swarf_path::Move> = p
        .moves
        .iter()
        .filter(|m| m.kind == MoveKind::Linear)
        .collect();
    assert_eq!(tap.len(), 2);
    assert!(tap
        .iter()
        .all(|m| m.feed_mode == FeedMode::SpindleSynchronised && m.feed == 1.25));
    // MCALL: the cycle at each position until MCALL alone.
    let p = read(
        "G0 X0 Y0 Z50 S1000 M3\nG1 F100\nMCALL CYCLE81(30,0,2,-5)\nG0 X20 Y20\nX40\nMCALL\nX60",
    );
    let bottoms: Vec<[f64; 3]> = tips(&p).into_iter().filter(|t| t[2] == -5.0).collect();
    assert_eq!(bottoms, [[20.0, 20.0, -5.0], [40.0, 20.0, -5.0]]);
}

#[test]
fn parameters_and_program_flow() {
    let p = read(
        "DEF REAL STEP=2.5, N\n\
         R1=0\n\
         G1 F100\n\
         LOOP1: R1=R1+1\n\
         G1 X=R1*STEP\n\
         IF R1<3 GOTOB LOOP1\n\
         FOR N=1 TO 2\n\
         G1 Y=N\n\
         ENDFOR\n\
         WHILE R1<5\n\
         R1=R1+1\n\
         G1 Z=-R1\n\
         ENDWHILE\n\
         IF R1==5\n\
         G1 X0\n\
         ELSE\n\
         G1 X99\n\
         ENDIF\n\
         GOTOF SKIP\n\
         G1 X99\n\
         SKIP: M30",
    );
    let t = tips(&p);
    assert_eq!(
        t,
        [
            [2.5, 0.0, 0.0],
            [5.0, 0.0, 0.0],
            [7.5, 0.0, 0.0],
            [7.5, 1.0, 0.0],
            [7.5, 2.0, 0.0],
            [7.5, 2.0, -4.0],
            [7.5, 2.0, -5.0],
            [0.0, 2.0, -5.0]
        ]
    );
}

#[test]
fn subprograms_are_called_from_beside_the_program() {
    let dir = std::env::temp_dir().join(format!("swarf-sinu-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("HOLE.SPF"),
        "PROC HOLE\nG91 G1 Z-5 F100\nG0 Z5\nG90\nM17\n",
    )
    .unwrap();
    std::fs::write(dir.join("L20.spf"), "G91 G0 X1\nG90\nRET\n").unwrap();
    let main = dir.join("MAIN.MPF");
    let text = "G500\nG0 X10 Z2\nHOLE\nL20 P2\nHOLE P2\nM30\n";
    let mut rec = Recorder::default();
    read_sinumerik(
        text,
        &main.display().to_string(),
        &GcodeOptions::default(),
        &mut rec,
    )
    .unwrap();
    let ends: Vec<(f64, f64)> = rec
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::Feed { end } | Canon::Traverse { end } => Some((end.x, end.z)),
            _ => None,
        })
        .collect();
    assert_eq!(
        ends,
        [
            (10.0, 2.0),
            (10.0, -3.0),
            (10.0, 2.0),
            (11.0, 2.0),
            (12.0, 2.0),
            (12.0, -3.0),
            (12.0, 2.0),
            (12.0, -3.0),
            (12.0, 2.0)
        ]
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn refused_and_wrong_blocks_are_errors_at_their_place() {
    // (Line 1 is the G500 the helpers put first.)
    let cases: [(&str, PathErrorKind, u32, u32, &str); 7] = [
        (
            "N10 G1 G41 X10 F100",
            PathErrorKind::Unsupported,
            2,
            8,
            "G41",
        ),
        (
            "G1 X10 F100\nG2 X40 Y0 CR=5",
            PathErrorKind::Semantic,
            3,
            1,
            "G2",
        ),
        ("R1=10/(2-2)", PathErrorKind::Semantic, 2, 6, "10/(2-2)"),
        ("G1 X10", PathErrorKind::Semantic, 2, 1, "G1"),
        (
            "POCKET3(1,2,3)",
            PathErrorKind::Unsupported,
            2,
            1,
            "POCKET3(1,2,3)",
        ),
        ("GOTOF NOWHERE", PathErrorKind::Semantic, 2, 7, "NOWHERE"),
        (
            "WHILE R1<5\nG1 X1 F100",
            PathErrorKind::Syntax,
            2,
            1,
            "WHILE",
        ),
    ];
    for (body, kind, line, col, found) in cases {
        let e = err(body);
        assert_eq!(e.kind, kind, "{body}: {e}");
        assert_eq!((e.pos.line, e.pos.column), (line, col), "{body}: {e}");
        assert_eq!(e.found, found, "{body}: {e}");
    }
    let opts = GcodeOptions {
        max_loop_iterations: 1000,
        ..GcodeOptions::default()
    };
    let e = read_with("G500\nL1: G0 X1\nGOTOB L1\n", opts).unwrap_err();
    assert_eq!(e.kind, PathErrorKind::Limit, "{e}");
}

#[test]
fn siemens_text_is_recognised_whatever_the_extension() {
    let text = "N10 G0 X0 Y0\nN20 G2 X10 Y10 CR=5\nN30 M30\n";
    for name in ["a.mpf", "a.MPF", "a.nc", "a.ptp", "a"] {
        assert_eq!(
            ProgramFormat::detect(std::path::Path::new(name), text),
            ProgramFormat::Sinumerik,
            "{name}"
        );
    }
}

#[test]
fn review_cases_read_as_the_control_reads_them() {
    // A marker-free program with the control's archive header, named .MPF.
    let o = ReadOptions::default();
    let p = read_program_str(
        "%_N_PART_MPF\n;$PATH=/_N_WKS_DIR/_N_PART_WPD\nG17 G90 G710 G94\nG0 X10 Y0 Z5\nG1 Z-1 F100\nM30\n",
        "PART.MPF",
        Machine::three_axis(),
        &o,
    )
    .unwrap();
    assert_eq!(p.moves.len(), 2);
    // Both DP and DPR: the depth comes from DPR.
    let p = read("G0 X20 Y20 Z50 S1000 M3\nG1 F100\nCYCLE81(10,0,2,-5,8)");
    assert!(tips(&p).iter().any(|t| t[2] == -8.0) && !tips(&p).iter().any(|t| t[2] == -5.0));
    // Parenthesised conditions, a variable named like a function, spaces in expressions.
    let p = read(
        "DEF REAL SQ1=3, MAX_Z=7\nR1 = 1\nIF (R1==1) GOTOF SKIP\nG0 X99\nSKIP: G0 X = SQ1 + 1 Y=MAX_Z\n\
         WHILE(R1<3)\nR1=R1+1\nENDWHILE\nG0 Z=R1",
    );
    assert_eq!(tips(&p), [[4.0, 7.0, 0.0], [4.0, 7.0, 3.0]]);
    // ROT RPL in G18 is refused; G75 goes at rapid to the home, its words in any order.
    assert_eq!(err("G18\nROT RPL=90").kind, PathErrorKind::Unsupported);
    let opts = GcodeOptions {
        home: Some([0.0, 0.0, 100.0]),
        ..GcodeOptions::default()
    };
    let p = read_with(
        "G500\nG1 X5 Z5 F100\nZ1=0 G75 FP=1\nG642 ADIS=0.1 CTOL=0.01\n",
        opts,
    )
    .unwrap();
    assert_eq!(p.moves[1].kind, MoveKind::Rapid);
    assert!(close(p.moves[1].end.tip, [5.0, 0.0, 100.0], 1e-12));
    // Block numbers may repeat: GOTOF finds the next one.
    let p = read("N10 G0 X1\nGOTOF N10\nG0 X2\nN10 G0 X3");
    assert_eq!(tips(&p), [[1.0, 0.0, 0.0], [3.0, 0.0, 0.0]]);
    assert_eq!(
        err("L1: G0 X1\nREPEATB L1 P=2").kind,
        PathErrorKind::Unsupported
    );
    // TRANS in a swivelled plane keeps CYCLE800's offset (here 5 along the turned X).
    let p = read("CYCLE800(1,\"TC1\",0,57,0,0,0,0,0,90,5,0,0,1)\nTRANS X1\nG0 X0 Y0 Z0");
    assert!(
        close(p.moves[0].end.tip, [0.0, 6.0, 0.0], 1e-12),
        "{:?}",
        tips(&p)
    );
    // Rotary directions: shortest, positive, negative.
    let p = read("G0 C350\nC=DC(10)\nC=ACP(0)\nC=ACN(350)");
    let c: Vec<f64> = p.moves.iter().map(|m| m.end_joints.c).collect();
    // (10° to 0° the positive way is +350°; 0° to 350° the negative way −10°.)
    assert_eq!(c, [350.0, 370.0, 720.0, 710.0]);
    // MCALL after a block moving Z only.
    let p = read("G0 X20 Y20 Z50 S1000 M3\nG1 F100\nMCALL CYCLE81(30,0,2,-5)\nG0 Z40\nMCALL");
    assert!(tips(&p).iter().any(|t| t[2] == -5.0));
    // An axis twice, two motion codes, a call with arguments: errors.
    assert_eq!(err("G1 X10 X20 F100").kind, PathErrorKind::Semantic);
    assert_eq!(
        err("G1 X10 F100 G2 X0 Y0 I99").kind,
        PathErrorKind::Semantic
    );
    assert_eq!(err("POCK(5)").kind, PathErrorKind::Unsupported);
    // Columns count characters.
    let e = err("T=\"ÄÖÜ\" G0 X=*");
    assert_eq!(e.pos.column, 14, "{e}");
    // Nested repeats meet the loop limit.
    let dir = std::env::temp_dir().join(format!("swarf-sinu-rep-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("SUBA.SPF"), "SUBB P=1000000\nM17\n").unwrap();
    std::fs::write(dir.join("SUBB.SPF"), "R1=R1+1\nM17\n").unwrap();
    let opts = GcodeOptions {
        max_loop_iterations: 10_000,
        ..GcodeOptions::default()
    };
    let mut rec = Recorder::default();
    let e = read_sinumerik(
        "G500\nSUBA P=1000000\nM30\n",
        &dir.join("M.MPF").display().to_string(),
        &opts,
        &mut rec,
    )
    .unwrap_err();
    assert_eq!(e.kind, PathErrorKind::Limit, "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn second_review_cases() {
    // The programmable frame sits inside the swivel: TRANS before or after CYCLE800, reset
    // in either order, leaves nothing.
    for prog in [
        "TRANS X10\nCYCLE800(1,\"T\",0,57,0,0,0,0,30,0,0,0,0,1)\nTRANS\nCYCLE800()\nG1 X0 Y0 Z50 F100",
        "TRANS X10\nCYCLE800(1,\"T\",0,57,0,0,0,0,30,0,0,0,0,1)\nCYCLE800()\nTRANS\nG1 X0 Y0 Z50 F100",
    ] {
        let p = read(prog);
        assert!(close(p.moves.last().unwrap().end.tip, [0.0, 0.0, 50.0], 1e-12), "{prog}: {:?}", tips(&p));
    }
    // APT text that mentions Siemens words is still APT.
    for name in ["a.cls", "a.txt"] {
        assert_eq!(
            ProgramFormat::detect(
                std::path::Path::new(name),
                "PARTNO TEST\nINSERT TRAORI\nPPRINT CR=5\nGOTO/1,2,3\nFINI\n"
            ),
            ProgramFormat::Apt,
            "{name}"
        );
    }
    // CYCLE85's feeds under G70 stay in the basic system.
    let p = read("G0 X20 Y20 Z10 S1000 M3\nG70 G1 F100\nCYCLE85(1,0,0.1,-1,,0,100,100)");
    assert!(p
        .moves
        .iter()
        .filter(|m| m.kind == MoveKind::Linear)
        .all(|m| m.feed == 100.0));
    // Word operators with spaces.
    let p = read("R1=10 MOD 3\nR2=R1==1 AND 1\nG0 X=R1 Y=R2");
    assert!(close(p.moves[0].end.tip, [1.0, 1.0, 0.0], 1e-12));
    // The F of a G4 block is its dwell: the schedule leaves it.
    let text = "G500\nG1 X10 F100\nG4 F2\nG1 X20\nM30\n";
    let factors = [(2, 1.0), (4, 0.5)].into_iter().collect();
    let r = swarf_path::rewrite::rewrite_feeds(
        text,
        "t.mpf",
        ProgramFormat::Sinumerik,
        &factors,
        &Default::default(),
    )
    .unwrap();
    assert_eq!(r.text.lines().nth(3), Some("G1 X20 F50"));
}

/// Settings a CAM post writes that do not move the tool — the kind of radius compensation
/// (`CUT3DC`, names with digits read whole), its approach (`NORM`, `KONT`), collision
/// detection, working-area limits, `G643` — are read past; an orientation interpolation swarf
/// does not follow is warned once; a transformation that changes what X Y Z mean is refused at
/// its word.
#[test]
fn post_settings_without_motion_are_read_past() {
    let p = read(
        "G0 X0 Y0 Z10\nCUT3DC CDON NORM\nCUT2DF CDOF2 KONT\nORIVIRT1 ORIPLANE WALIMON\nG643\n\
         G1 X5 F100\nM30",
    );
    assert_eq!(tips(&p).last().copied(), Some([5.0, 0.0, 10.0]));
    assert!(p.warnings.is_empty(), "{:?}", p.warnings);
    let p = read("ORIPATH\nG1 X5 F100\nORICONCW\nM30");
    assert_eq!(p.warnings.len(), 1, "{:?}", p.warnings);
    assert!(p.warnings[0].message.contains("great circle"));
    let p = read("CUT3DCC CUT3DCCD\nG1 X5 F100\nM30");
    assert!(p.warnings.is_empty(), "{:?}", p.warnings);
    for (src, word) in [
        ("TRACYL(40)\n", "TRACYL"),
        ("G0 X1\nDIAMON\n", "DIAMON"),
        ("DIAM90\n", "DIAM90"),
    ] {
        let e = err(src);
        assert_eq!(e.kind, PathErrorKind::Unsupported, "{e}");
        assert!(e.message.starts_with(&format!("{word} is not read")), "{e}");
    }
}

#[test]
fn a_skipped_block_is_said_and_siemens_words_tell_a_program_apart() {
    // Read, as the control with its skip switch off (the state it starts in), and said.
    let p = read("G0 X0 Y0 Z10\n/G1 X30 F100\nG1 X10 F100\nM30");
    assert_eq!(p.moves.len(), 3);
    assert!(
        p.warnings
            .iter()
            .any(|w| w.line == 3 && w.message.starts_with("block read: it starts with `/`")),
        "{:?}",
        p.warnings
    );
    // A `.nc` file whose only Siemens words are G710 and a tool by name: read as Sinumerik.
    let src = "N10 G17 G90 G710\nT=\"EM10\" D1\nM6\nG0 X0 Y0 Z10\nG1 Z-1 F100\nX10\nM30\n";
    assert_eq!(
        ProgramFormat::detect(std::path::Path::new("part.nc"), src),
        ProgramFormat::Sinumerik
    );
    // ATAN2 with two arguments (the one-argument ATAN took its name).
    let p = read("R1=5*ATAN2(1,1)\nG0 X=R1\nM30");
    assert!(
        close(p.moves[0].end.tip, [225.0, 0.0, 0.0], 1e-9),
        "{:?}",
        tips(&p)
    );
}

/// What a cycle does along Z at its hole: rapid (`R`) or fed (`F`) to a height, a dwell
/// (`D`), a new feed (`Rate`).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Z {
    R(f64),
    F(f64),
    D(f64),
    Rate(f64),
}

/// The cycle's events from the first move at (x, y) on (the positioning move at the hole
/// left out), read by the Sinumerik reader.
fn cycle_events(text: &str, x: f64, y: f64) -> Vec<Z> {
    let mut rec = Recorder::default();
    read_sinumerik(text, "t.mpf", &GcodeOptions::default(), &mut rec).unwrap();
    let mut out = Vec::new();
    let mut at_hole = false;
    for (_, e) in &rec.events {
        match e {
            Canon::Traverse { end } | Canon::Feed { end } => {
                let here = (end.x - x).abs() < 1e-12 && (end.y - y).abs() < 1e-12;
                if !here {
                    if at_hole {
                        break;
                    }
                    continue;
                }
                if !at_hole {
                    at_hole = true;
                    continue;
                }
                out.push(match e {
                    Canon::Traverse { .. } => Z::R(end.z),
                    _ => Z::F(end.z),
                });
            }
            Canon::Dwell(t) if at_hole => out.push(Z::D(*t)),
            Canon::FeedRate(f) if at_hole => out.push(Z::Rate(*f)),
            _ => {}
        }
    }
    out
}

/// `got` and `want` equal to 1e-9.
fn same_z(got: &[Z], want: &[Z]) {
    let close = |a: &Z, b: &Z| match (a, b) {
        (Z::R(p), Z::R(q)) | (Z::F(p), Z::F(q)) | (Z::D(p), Z::D(q)) | (Z::Rate(p), Z::Rate(q)) => {
            (p - q).abs() < 1e-9
        }
        _ => false,
    };
    assert!(
        got.len() == want.len() && got.iter().zip(want).all(|(a, b)| close(a, b)),
        "got {got:?}\nwant {want:?}"
    );
}

#[test]
fn cycle83_chip_removal_reenters_at_the_advance_distance() {
    use Z::*;
    // The review's program (s8.mpf): RTP 50, RFP 0, SDIS 2, DP −20, FDEP −5, DAM 2, VARI 1,
    // _DIS1 0. Pecks of 5, 3 (5 − 2), then 2 (not below DAM) to 20. The 840D cycles manual:
    // out to SDIS above RFP at rapid, back in at rapid to the advance distance above the depth
    // reached, which the cycle computes when _DIS1 is 0: 0.6 mm for a depth up to 30 mm.
    // (swarf re-entered at SDIS, 2 above the depth.)
    let s8 = "N10 G17 G90 G71\nN20 T1 M6\nN30 G0 X0 Y0 Z50 S1000 M3\nN40 F100\n\
              N50 MCALL CYCLE83(50,0,2,-20,,-5,,2,0,0,1,1,0,0,0,0,0)\nN60 X10 Y10\n\
              N70 X30 Y10\nN80 MCALL\nN90 X0 Y0\nN110 M30\n";
    let mut want = vec![R(2.0), Rate(100.0), F(-5.0), R(2.0), R(-4.4), F(-8.0)];
    for d in [10.0, 12.0, 14.0, 16.0, 18.0, 20.0] {
        want.extend([R(2.0), R(-(d - 2.0) + 0.6), F(-d)]);
    }
    want.push(R(50.0));
    same_z(&cycle_events(s8, 10.0, 10.0), &want);
    same_z(
        &cycle_events(s8, 30.0, 10.0),
        &want[..1]
            .iter()
            .chain(&want[2..])
            .copied()
            .collect::<Vec<_>>(),
    );

    // Deeper than 30 mm: depth / 50, at most 7 mm. 150 deep in pecks of 60: 3 mm.
    let deep = |dp: f64, fdpr: f64| {
        format!("G0 X20 Y20 Z50 S1000 M3\nG1 F100\nCYCLE83(30,0,2,{dp},,,{fdpr},,0,0,1,1)\nM30")
    };
    same_z(
        &cycle_events(&deep(-150.0, 60.0), 20.0, 20.0),
        &[
            R(2.0),
            Rate(100.0),
            F(-60.0),
            R(2.0),
            R(-57.0),
            F(-120.0),
            R(2.0),
            R(-117.0),
            F(-150.0),
            R(30.0),
        ],
    );
    // 400 deep (400 / 50 = 8): 7 mm.
    same_z(
        &cycle_events(&deep(-400.0, 200.0), 20.0, 20.0),
        &[
            R(2.0),
            Rate(100.0),
            F(-200.0),
            R(2.0),
            R(-193.0),
            F(-400.0),
            R(30.0),
        ],
    );
    // _DIS1 given: 1.5 above the depth reached; DTS 0.25 s at the top after each chip
    // removal; FRF 0.5 halves the feed to the first depth only.
    same_z(
        &cycle_events(
            "G0 X20 Y20 Z50 S1000 M3\nG1 F100\n\
             CYCLE83(30,0,2,-9,,,4,,0,0.25,0.5,1,0,0,0,0,1.5)\nM30",
            20.0,
            20.0,
        ),
        &[
            R(2.0),
            Rate(50.0),
            F(-4.0),
            R(2.0),
            D(0.25),
            R(-2.5),
            Rate(100.0),
            F(-8.0),
            R(2.0),
            D(0.25),
            R(-6.5),
            F(-9.0),
            R(30.0),
        ],
    );
}

#[test]
fn cycle83_chip_breaking_backs_by_vrt() {
    use Z::*;
    // VARI 0: back _VRT (0.5) after each depth at rapid, on from there at the feed; pecks of 4
    // to 9. (swarf backed 1 mm whatever _VRT said.)
    same_z(
        &cycle_events(
            "G0 X20 Y20 Z50 S1000 M3\nG1 F100\nCYCLE83(30,0,2,-9,,,4,,0,0,1,0,0,0,0.5)\nM30",
            20.0,
            20.0,
        ),
        &[
            R(2.0),
            Rate(100.0),
            F(-4.0),
            R(-3.5),
            F(-8.0),
            R(-7.5),
            F(-9.0),
            R(30.0),
        ],
    );
    // _VRT 0 or not given: the manual's 1 mm.
    for call in [
        "CYCLE83(30,0,2,-9,,,4,,0,0,1,0,0,0,0)",
        "CYCLE83(30,0,2,-9,,,4,,0,0,1,0)",
    ] {
        same_z(
            &cycle_events(
                &format!("G0 X20 Y20 Z50 S1000 M3\nG1 F100\n{call}\nM30"),
                20.0,
                20.0,
            ),
            &[
                R(2.0),
                Rate(100.0),
                F(-4.0),
                R(-3.0),
                F(-8.0),
                R(-7.0),
                F(-9.0),
                R(30.0),
            ],
        );
    }
}

#[test]
fn orientations_not_read_are_named_as_such() {
    // Euler/RPY angles and lead/tilt angles state the tool's orientation in forms swarf does
    // not read: the error says so and names the form it reads (it said "unexpected word").
    for (text, word) in [
        (
            "G71 G90\nTRAORI\nORIEULER\nG1 X10 A2=0 B2=30 C2=0 F500\n",
            "A2",
        ),
        (
            "G71 G90\nTRAORI\nORIPATH\nG1 X10 LEAD=10 TILT=5 F500\n",
            "LEAD",
        ),
    ] {
        let e = err(text);
        assert_eq!(e.kind, PathErrorKind::Unsupported, "{e}");
        assert_eq!(e.pos.line, 5, "{e}");
        let m = e.to_string();
        assert!(
            m.contains(&format!("{word}= states the tool orientation"))
                && m.contains("A3= B3= C3="),
            "{m}"
        );
    }
}
