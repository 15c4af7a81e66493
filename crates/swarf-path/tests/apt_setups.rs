//! APT files of several operations as CAM systems write them: a cutter per operation with no
//! tool change between, NX operations under different machine coordinate systems (MSYS), and
//! what CL data does not hold (part-program motion, units, dwells in revolutions, old line
//! ends).

use swarf_geom::math::Vec3;
use swarf_path::apt::{read_apt, AptOptions};
use swarf_path::builder::MoveBuilder;
use swarf_path::kinematics::Machine;
use swarf_path::{PathErrorKind, Program, Units};

mod common;
use common::{apt_err, close, tips};

fn program_with(text: &str, options: &AptOptions) -> Program {
    let mut b = MoveBuilder::new(Machine::three_axis(), "t.cls");
    read_apt(text, "t.cls", options, &mut b).unwrap();
    b.finish()
}

fn program(text: &str) -> Program {
    program_with(text, &AptOptions::default())
}

/// Two NX operations, each with its `TLDATA/` and no `LOADTL/` (as the shared NX sample).
const TWO_OPERATIONS: &str = "TOOL PATH/OP1,TOOL,FLAT10\n\
TLDATA/MILL,10.0000,0.0000,50.0000,0.0000,0.0000\n\
RAPID\nGOTO/0,0,10,0,0,1\nFEDRAT/MMPM,300\nGOTO/0,0,0\nGOTO/20,0,0\nEND-OF-PATH\n\
TOOL PATH/OP2,TOOL,BALL4\n\
TLDATA/MILL,4.0000,2.0000,50.0000,0.0000,0.0000\n\
RAPID\nGOTO/0,20,10\nGOTO/0,20,0\nGOTO/20,20,0\nEND-OF-PATH\n\
TOOL PATH/OP3,TOOL,BALL4\n\
TLDATA/MILL,4.0000,2.0000,50.0000,0.0000,0.0000\n\
GOTO/20,30,0\nFINI\n";

#[test]
fn a_cutter_redefined_without_a_tool_change_keeps_the_earlier_moves_cutter() {
    let p = program(TWO_OPERATIONS);
    // The first operation's moves cut with the Ø10 flat end mill, the second's with the Ø4
    // ball; the third operation repeats the ball's definition: the same tool.
    let tools: Vec<u32> = p.moves.iter().map(|m| m.tool).collect();
    assert_eq!(
        tools,
        vec![0, 0, 1_000_000, 1_000_000, 1_000_000, 1_000_000],
        "{tools:?}"
    );
    let def = |t: u32| {
        p.cutter_definitions
            .iter()
            .find(|(n, _)| *n == t)
            .map(|(_, d)| d[..2].to_vec())
    };
    assert_eq!(def(0), Some(vec![10.0, 0.0]));
    assert_eq!(def(1_000_000), Some(vec![4.0, 2.0]));
    assert_eq!(p.cutter_definitions.len(), 2);
    let w: Vec<&str> = p.warnings.iter().map(|w| w.message.as_str()).collect();
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].contains("given tool 1000000"), "{w:?}");
    assert_eq!(p.warnings[0].line, 10);

    // Generic APT: `CUTTER/` twice, and with a tool number loaded.
    // Its number is one a later tool change does not load: `LOADTL/1` is tool 1 (undefined
    // here), not the redefined cutter.
    let p = program(
        "CUTTER/10\nFROM/0,0,5\nGOTO/10,0,5\nCUTTER/4,2\nGOTO/20,0,5\nLOADTL/1\nGOTO/30,0,5\n",
    );
    let tools: Vec<u32> = p.moves.iter().map(|m| m.tool).collect();
    assert_eq!(tools, vec![0, 1_000_000, 1]);
    assert!(!p.cutter_definitions.iter().any(|(t, _)| *t == 1));
    let p = program("LOADTL/7\nCUTTER/10\nFROM/0,0,5\nGOTO/10,0,5\nCUTTER/4,2\nGOTO/20,0,5\n");
    let tools: Vec<u32> = p.moves.iter().map(|m| m.tool).collect();
    assert_eq!(tools, vec![7, 1_000_000]);
    // A definition before any motion, then another before the first move: the last one holds
    // (nothing has cut yet), and one given after the last move names no tool.
    let p = program("CUTTER/10\nCUTTER/6\nFROM/0,0,5\nGOTO/10,0,5\nCUTTER/4\n");
    assert_eq!(
        p.cutter_definitions,
        vec![(0, [6.0, 0.0, 3.0, 0.0, 0.0, 0.0, 0.0])]
    );
    assert!(p.warnings.is_empty());
}

#[test]
fn operations_under_another_mcs_are_mapped_into_the_first() {
    // OP2's MCS: origin (5, 0, 0), X along world X, Y along world Z (so its Z is world −Y).
    let text = "TOOL PATH/TOP,TOOL,FLAT6\nTLDATA/MILL,6,0,50,0,0\n\
        MSYS/0,0,0,1,0,0,0,1,0\nFEDRAT/MMPM,300\nGOTO/0,0,10,0,0,1\nGOTO/10,0,10\n\
        END-OF-PATH\nTOOL PATH/SIDE,TOOL,FLAT6\nTLDATA/MILL,6,0,50,0,0\n\
        MSYS/5,0,0,1,0,0,0,0,1\nGOTO/0,0,10,0,0,1\nGOTO/10,0,10\nCIRCLE/5,0,10,0,0,1,5\n\
        GOTO/0,0,10\nEND-OF-PATH\nMSYS/0,0,0,1,0,0,0,1,0\nGOTO/0,0,20,0,0,1\nFINI\n";
    let p = program(text);
    let t = tips(&p);
    // Local (0, 0, 10) of OP2 is world (5, −10, 0); (10, 0, 10) is (15, −10, 0).
    assert!(close(Vec3::from(t[1]), [5.0, -10.0, 0.0], 1e-12), "{t:?}");
    assert!(close(Vec3::from(t[2]), [15.0, -10.0, 0.0], 1e-12), "{t:?}");
    // The tool axis (0, 0, 1) of OP2 points along world −Y.
    let a = p.moves[2].end.axis;
    assert!(close(a, [0.0, -1.0, 0.0], 1e-12), "{a:?}");
    // The half circle about local (5, 0, 10), axis local Z: centre world (10, −10, 0), in the
    // world XZ plane, from (15, −10, 0) to (5, −10, 0).
    assert!(close(Vec3::from(t[3]), [5.0, -10.0, 0.0], 1e-9), "{t:?}");
    let swarf_path::MoveKind::Arc(g) = p.moves[3].kind else {
        panic!("{:?}", p.moves[3].kind)
    };
    assert!(close(g.center, [10.0, -10.0, 0.0], 1e-9), "{g:?}");
    assert!(close(g.normal.abs(), [0.0, 1.0, 0.0], 1e-12), "{g:?}");
    assert!((g.sweep - std::f64::consts::PI).abs() < 1e-9, "{g:?}");
    // Back to the first MCS: points as written, and the axis the MCS's Z again.
    assert!(close(Vec3::from(t[4]), [0.0, 0.0, 20.0], 1e-12), "{t:?}");
    assert!(close(p.moves[4].end.axis, [0.0, 0.0, 1.0], 1e-12));
    let w: Vec<&str> = p.warnings.iter().map(|w| w.message.as_str()).collect();
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("another MCS than the first (line 3)"),
        "{w:?}"
    );

    // Axes that are not perpendicular are refused where they are written.
    let e = apt_err("MSYS/0,0,0,1,0,0,1,1,0\nGOTO/0,0,0\n");
    assert_eq!((e.pos.line, e.kind), (1, PathErrorKind::Semantic), "{e}");
}

#[test]
fn part_program_motion_is_refused_not_dropped() {
    for rec in [
        "GOLFT/L1,TANTO,C1",
        "GORGT/L2,PAST,L3",
        "GOFWD/L1,PAST,L2",
        "GOBACK/L1",
        "GOUP/PL1",
        "GODOWN/PL1",
        "PSIS/PL1",
        "GOTTO/1,2,3",
    ] {
        let e = apt_err(&format!("GOTO/0,0,0\n{rec}\nGOTO/5,5,5\n"));
        assert_eq!(
            (e.pos.line, e.pos.column, e.kind),
            (2, 1, PathErrorKind::Unsupported),
            "{rec}: {e}"
        );
    }
}

#[test]
fn lone_carriage_returns_end_lines() {
    let text =
        "PARTNO/BRACKET\rUNITS/MM\rFEDRAT/100\rGOTO/0,0,0\rGOTO/10,0,0\rGOTO/10,10,0\rFINI\r";
    let p = program(text);
    assert_eq!(tips(&p), vec![[10.0, 0.0, 0.0], [10.0, 10.0, 0.0]]);
    // A bad record is found on its own line.
    let e = apt_err("UNITS/MM\rGOTO/1,x,0\r");
    assert_eq!((e.pos.line, e.pos.column), (2, 8), "{e}");
}

#[test]
fn units_before_any_units_record_and_inch_feeds_without_one() {
    let text = "FEDRAT/IPM,10\nGOTO/0,0,0\nGOTO/1,0,0\n";
    let p = program_with(text, &AptOptions::default().with_initial_units(Units::Inch));
    assert_eq!(tips(&p), vec![[25.4, 0.0, 0.0]]);
    assert!(p.warnings.is_empty(), "{:?}", p.warnings);
    let p = program(text);
    assert_eq!(tips(&p), vec![[1.0, 0.0, 0.0]]);
    assert_eq!(p.warnings.len(), 1);
    assert!(p.warnings[0].message.contains("--initial-units inch"));
    // A file that says its units is read so, whatever the option.
    let p = program_with(
        &format!("UNITS/MM\n{text}"),
        &AptOptions::default().with_initial_units(Units::Inch),
    );
    assert_eq!(tips(&p), vec![[1.0, 0.0, 0.0]]);
}

#[test]
fn dwells_in_revolutions_and_negative_dwells() {
    let p = program("SPINDL/600\nGOTO/0,0,0\nDELAY/10,REV\nDELAY/2\nGOTO/1,0,0\n");
    assert!((p.dwell_s - 3.0).abs() < 1e-12, "{}", p.dwell_s);
    let e = apt_err("DELAY/-5\n");
    assert_eq!((e.pos.line, e.kind), (1, PathErrorKind::Semantic), "{e}");
    // The unit word first, as NX writes it (it was "not a number").
    let p = program("SPINDL/600\nGOTO/0,0,0\nDELAY/REV,10\nDELAY/SEC,2\nGOTO/1,0,0\n");
    assert!((p.dwell_s - 3.0).abs() < 1e-12, "{}", p.dwell_s);
    let e = apt_err("DELAY/REV,SEC\n");
    assert_eq!((e.pos.line, e.pos.column), (1, 11), "{e}");
    // A circle that nothing uses before FINI is said.
    let p = program("GOTO/0,0,0\nCIRCLE/0,0,0,0,0,1,1\nFINI\n");
    assert_eq!(p.warnings.len(), 1);
    assert_eq!(p.warnings[0].line, 2);
}

#[test]
fn gotos_without_an_axis_take_the_z_of_their_mcs() {
    // NX writes `GOTO/x,y,z` for fixed-axis operations: under a second MCS whose Z is the
    // first's +X (origin (100, 0, 0), X = world Y, Y = world Z), the tool points along +X.
    let text = "MSYS/0,0,0,1,0,0,0,1,0\nRAPID\nGOTO/0,0,10\nGOTO/10,0,10\n\
        MSYS/100,0,0,0,1,0,0,0,1\nRAPID\nGOTO/0,0,10\nGOTO/10,0,10\nFINI\n";
    let p = program(text);
    let t = tips(&p);
    assert!(close(Vec3::from(t[1]), [110.0, 0.0, 0.0], 1e-12), "{t:?}");
    assert!(close(Vec3::from(t[2]), [110.0, 10.0, 0.0], 1e-12), "{t:?}");
    for m in &p.moves[1..] {
        assert!(
            close(m.end.axis, [1.0, 0.0, 0.0], 1e-12),
            "{:?}",
            m.end.axis
        );
    }
    // The first operation's moves keep the first MCS's Z.
    assert!(close(p.moves[0].end.axis, [0.0, 0.0, 1.0], 1e-12));
}

/// `GODLTA/d` moves d along the tool axis (it was refused: "GODLTA/ with 1 value(s)"); a
/// Ctrl-Z after the last record is a blank, as in G-code; a negative feed is refused at its
/// column (it was read and its moves left out of the time).
#[test]
fn one_value_godlta_ctrl_z_and_negative_feeds() {
    let p = program("GOTO/0,0,0,0,0.6,0.8\nGODLTA/10\nGODLTA/-5\n\u{1a}");
    let t = tips(&p);
    assert!(close(Vec3::from(t[0]), [0.0, 6.0, 8.0], 1e-12), "{t:?}");
    assert!(close(Vec3::from(t[1]), [0.0, 3.0, 4.0], 1e-12), "{t:?}");
    let e = apt_err("FEDRAT/-100,MMPM\nGOTO/0,0,0\n");
    assert_eq!(
        (e.pos.line, e.pos.column, e.kind),
        (1, 8, PathErrorKind::Semantic),
        "{e}"
    );
    let e = apt_err("FEDRAT/MMPM,-100\n");
    assert_eq!((e.pos.line, e.pos.column), (1, 13), "{e}");
}

/// NX's 7-parameter mill (`TLDATA/MILL,D,R,L,B,A,X1,Y1`) is read as the 5-parameter one; where
/// X1 Y1 are not the centre D and R imply, a warning says they are left out (they were dropped
/// silently).
#[test]
fn tldata_values_past_the_fifth_are_checked() {
    let p = program("TLDATA/MILL,10,2,50,0,0,3,2\nGOTO/0,0,0\nGOTO/1,0,0\n");
    assert!(p.warnings.is_empty(), "{:?}", p.warnings);
    let p = program("TLDATA/MILL,10,2,50,0,0,2.5,2\nGOTO/0,0,0\nGOTO/1,0,0\n");
    assert_eq!(p.warnings.len(), 1, "{:?}", p.warnings);
    assert_eq!(p.warnings[0].line, 1);
    assert!(
        p.warnings[0].message.contains("centre X1 Y1 is left out"),
        "{:?}",
        p.warnings
    );
    assert_eq!(p.cutter_definitions[0].1[2], 3.0, "e = D/2 - R");
}
