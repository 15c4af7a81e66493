//! APT records one by one: forms, conversions, errors with their positions, robustness.

use proptest::prelude::*;
use swarf_path::apt::{read_apt, AptOptions};
use swarf_path::builder::MoveBuilder;
use swarf_path::canon::Recorder;
use swarf_path::kinematics::Machine;
use swarf_path::summary::summarize;
use swarf_path::{Axes, Canon, FeedMode, MoveKind, PathErrorKind, Plane, SpindleDir, Units};

mod common;
use common::{apt_err as err, apt_events as events};

fn at(x: f64, y: f64, z: f64) -> Axes {
    Axes {
        x,
        y,
        z,
        ..Axes::default()
    }
}

#[test]
fn first_point_places_the_tool_then_rapid_applies_once() {
    let e = events("GOTO/1,2,3\nRAPID\nGOTO/1,2,10\nGOTO/4,2,10\n");
    assert_eq!(
        e,
        vec![
            Canon::ToolAxis([0.0, 0.0, 1.0]),
            Canon::SetPosition(at(1.0, 2.0, 3.0)),
            Canon::Traverse {
                end: at(1.0, 2.0, 10.0)
            },
            Canon::Feed {
                end: at(4.0, 2.0, 10.0)
            },
        ]
    );
}

#[test]
fn inches_are_converted_and_feeds_in_both_orders() {
    let e =
        events("UNITS/INCHES\nFROM/0,0,1\nFEDRAT/10,IPM\nFEDRAT/MMPR,0.1\nFEDRAT/2\nGOTO/1,0,1\n");
    assert_eq!(e[0], Canon::Units(Units::Inch));
    assert_eq!(e[3], Canon::FeedRate(254.0));
    assert_eq!(e[4], Canon::FeedMode(FeedMode::PerRevolution));
    assert_eq!(e[5], Canon::FeedRate(0.1));
    // A bare number keeps the mode and unit of the FEDRAT/ before it (MMPR here).
    assert_eq!(e[6], Canon::FeedRate(2.0));
    assert_eq!(
        e[7],
        Canon::Feed {
            end: at(25.4, 0.0, 25.4)
        }
    );
}

/// `FEDRAT/f` without a mode word keeps the last one, as posts read it: after `MMPR` a bare
/// 0.2 is 0.2 mm/rev (it was 0.2 mm/min: 100 mm took 500 min instead of 30 s), said with a
/// warning; after `IPM` a bare 20 is 20 in/min = 508 mm/min; before any, per minute in the
/// file's units.
#[test]
fn a_feed_without_a_mode_word_keeps_the_last_mode() {
    let e = events("SPINDL/1000,RPM\nFEDRAT/0.1,MMPR\nFEDRAT/0.2\nGOTO/100,0,0\n");
    assert!(e.contains(&Canon::FeedMode(FeedMode::PerRevolution)));
    assert!(e.contains(&Canon::FeedRate(0.2)));
    assert!(!e.contains(&Canon::FeedMode(FeedMode::PerMinute)));
    let p = swarf_path::load::read_program_str(
        "SPINDL/1000,RPM\nFROM/0,0,0\nFEDRAT/0.1,MMPR\nGOTO/100,0,0\nFEDRAT/0.2\nGOTO/200,0,0\n",
        "fedmode.apt",
        swarf_path::Machine::three_axis(),
        &Default::default(),
    )
    .unwrap();
    let s = swarf_path::summary::summarize(&p);
    // 100/(0.1·1000) + 100/(0.2·1000) minutes.
    assert!(
        (s.machining_time_s - 90.0).abs() < 1e-9,
        "{}",
        s.machining_time_s
    );
    let w: Vec<_> = p
        .warnings
        .iter()
        .map(|w| (w.line, w.message.as_str()))
        .collect();
    assert_eq!(w.len(), 1, "{w:?}");
    assert_eq!(w[0].0, 5);
    assert!(w[0].1.contains("read per revolution"), "{w:?}");
    let e = events("FEDRAT/IPM,20\nFEDRAT/30\nFEDRAT/40,MMPM\nFEDRAT/50\n");
    let rates: Vec<f64> = e
        .iter()
        .filter_map(|c| match c {
            Canon::FeedRate(f) => Some(*f),
            _ => None,
        })
        .collect();
    assert_eq!(rates, [508.0, 762.0, 40.0, 50.0]);
    let e = events("UNITS/INCHES\nFEDRAT/10\n");
    assert!(e.contains(&Canon::FeedRate(254.0)));
}

#[test]
fn continuation_comments_and_case() {
    let e = events("goto/1,$\n  2,3 $$ a comment\n$$ only a comment\ngoto/4,5,6,0,0,1\n");
    assert_eq!(e[1], Canon::SetPosition(at(1.0, 2.0, 3.0)));
    assert_eq!(
        e[2],
        Canon::Feed {
            end: at(4.0, 5.0, 6.0)
        }
    );
}

#[test]
fn tools_spindle_and_cutter() {
    let e = events(
        "CUTTER/10,2\nLOADTL/7\nLOAD/TOOL,8\nSPINDL/RPM,1200,CCLW\nSPINDL/OFF\nSPINDL/900\n",
    );
    // APT's two-number form is a toroidal cutter: e = d/2 − r = 3, f = r = 2; h not given.
    assert_eq!(
        e[0],
        Canon::CutterDefinition([10.0, 2.0, 3.0, 2.0, 0.0, 0.0, 0.0])
    );
    assert_eq!(e[1], Canon::ToolChange { tool: 7 });
    assert_eq!(e[2], Canon::ToolChange { tool: 8 });
    assert_eq!(
        e[3],
        Canon::Spindle {
            rpm: 1200.0,
            dir: SpindleDir::CounterClockwise
        }
    );
    assert_eq!(
        e[4],
        Canon::Spindle {
            rpm: 1200.0,
            dir: SpindleDir::Stopped
        }
    );
    assert_eq!(
        e[5],
        Canon::Spindle {
            rpm: 900.0,
            dir: SpindleDir::CounterClockwise
        }
    );
}

#[test]
fn circles_about_principal_axes_become_arcs() {
    // Counter-clockwise about +Y (right-hand rule, not an NX file): plane XZ, rotation +1; the
    // centre is given as (Z, X), LinuxCNC's order for G18.
    let e = events("GOTO/10,0,0\nCIRCLE/0,0,0,0,1,0,10\nGOTO/0,0,-10\n");
    assert_eq!(
        e[2],
        Canon::Arc {
            end: at(0.0, 0.0, -10.0),
            center: [0.0, 0.0],
            rotation: 1,
            plane: Plane::XZ
        }
    );
    let e = events("GOTO/0,10,0\nCIRCLE/0,0,5,-1,0,0,10\nGOTO/0,0,10\n");
    assert_eq!(
        e[2],
        Canon::Arc {
            end: at(0.0, 0.0, 10.0),
            center: [0.0, 5.0],
            rotation: -1,
            plane: Plane::YZ
        }
    );
}

#[test]
fn circle_about_a_general_axis_is_exact() {
    // A circle of radius 5 about n = (0, 1, 1)/√2 through the origin: from (5, 0, 0) a quarter
    // turn counter-clockwise about n reaches 5·(n × X) = 5·(0, 1, −1)/√2.
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let text = format!(
        "GOTO/5,0,0\nCIRCLE/0,0,0,0,1,1,5\nGOTO/0,{},{}\n",
        5.0 * s,
        -5.0 * s
    );
    let e = events(&text);
    let Canon::ArcAxis { normal, turns, .. } = e[2] else {
        panic!("{:?}", e[2])
    };
    assert_eq!(turns, 1);
    assert!((normal[1] - s).abs() < 1e-15 && (normal[2] - s).abs() < 1e-15);
    let mut b = MoveBuilder::new(Machine::three_axis(), "t.apt");
    read_apt(&text, "t.apt", &AptOptions::default(), &mut b).unwrap();
    let p = b.finish();
    let MoveKind::Arc(g) = p.moves[0].kind else {
        panic!()
    };
    assert!(
        (g.sweep - std::f64::consts::FRAC_PI_2).abs() < 1e-12,
        "{}",
        g.sweep
    );
    for i in 0..=10 {
        let q = p.pose_at(&p.moves[0], f64::from(i) / 10.0).tip;
        assert!((q.length() - 5.0).abs() < 1e-12);
        assert!(q.dot(g.normal).abs() < 1e-12);
    }
}

#[test]
fn full_circle_when_the_goto_returns_to_the_start() {
    let text = "FEDRAT/600\nGOTO/10,0,0\nCIRCLE/0,0,0,0,0,1,10\nGOTO/10,0,0\n";
    let mut b = MoveBuilder::new(Machine::three_axis(), "t.apt");
    read_apt(text, "t.apt", &AptOptions::default(), &mut b).unwrap();
    let s = summarize(&b.finish());
    assert!((s.feed_length_mm - 20.0 * std::f64::consts::PI).abs() < 1e-12);
    assert_eq!(s.bbox_min, Some([-10.0, -10.0, 0.0]));
    assert_eq!(s.bbox_max, Some([10.0, 10.0, 0.0]));
    assert!((s.machining_time_s - 20.0 * std::f64::consts::PI / 600.0 * 60.0).abs() < 1e-12);
}

#[test]
fn tool_axis_changes_are_stated() {
    let e = events("GOTO/0,0,0,0,0,1\nGOTO/1,0,0,0,1,1\nGOTO/2,0,0\n");
    let axes: Vec<_> = e
        .iter()
        .filter(|x| matches!(x, Canon::ToolAxis(_)))
        .collect();
    assert_eq!(axes.len(), 2);
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let Canon::ToolAxis(a) = axes[1] else {
        unreachable!()
    };
    assert!((a[0]).abs() < 1e-15 && (a[1] - s).abs() < 1e-15 && (a[2] - s).abs() < 1e-15);
}

#[test]
fn csys_transforms_following_points() {
    // A quarter turn about Z and a shift of (100, 0, 0): local (1, 0, 0) is (100, 1, 0).
    let text = "CSYS/0,-1,0,100,1,0,0,0,0,0,1,0\nGOTO/1,0,0,1,0,0\n";
    let mut rec = Recorder::default();
    read_apt(text, "t.apt", &AptOptions::default(), &mut rec).unwrap();
    assert_eq!(rec.warnings.len(), 1);
    let pos = rec.events.iter().find_map(|(_, e)| match e {
        Canon::SetPosition(p) => Some(*p),
        _ => None,
    });
    assert_eq!(pos, Some(at(100.0, 1.0, 0.0)));
    assert!(rec
        .events
        .iter()
        .any(|(_, e)| *e == Canon::ToolAxis([0.0, 1.0, 0.0])));
    // Not applied on request.
    let mut rec = Recorder::default();
    read_apt(
        text,
        "t.apt",
        &AptOptions::default().with_apply_csys(false),
        &mut rec,
    )
    .unwrap();
    assert!(rec
        .events
        .iter()
        .any(|(_, e)| *e == Canon::SetPosition(at(1.0, 0.0, 0.0))));
}

#[test]
fn byte_order_mark_and_crlf() {
    let e = events("\u{feff}PARTNO/X\r\nGOTO/1,2,3\r\n");
    assert_eq!(e[0], Canon::Comment("X".into()));
    assert_eq!(e[2], Canon::SetPosition(at(1.0, 2.0, 3.0)));
}

#[test]
fn fini_ends_reading() {
    let e = events("GOTO/0,0,0\nFINI\nGOTO/garbage\n");
    assert_eq!(e.last(), Some(&Canon::ProgramEnd));
}

#[test]
fn errors_say_where_and_what() {
    let e = err("GOTO/1,2,3\nGOTO/1, x2 ,3\n");
    assert_eq!((e.pos.line, e.pos.column), (2, 9));
    assert_eq!(e.kind, PathErrorKind::Syntax);
    assert_eq!(e.found, "x2");
    assert_eq!(e.expected, "a number");
    assert_eq!(e.pos.file, "t.apt");

    let e = err("GOTO/1,2\n");
    assert_eq!((e.pos.line, e.pos.column), (1, 6));
    assert_eq!(e.found, "1,2");

    let e = err("FROM/0,0,0\n  CIRCLE/0,0,0,0,0,0,1\n");
    assert_eq!(e.kind, PathErrorKind::Semantic);
    assert_eq!(e.pos.line, 2);

    // A continuation: the error is on the physical line where the bad value is.
    let e = err("GOTO/1,$\n 2,z\n");
    assert_eq!((e.pos.line, e.pos.column), (2, 4));

    let e = err("@#!\n");
    assert_eq!(e.pos.line, 1);
    assert!(err("UNITS/FURLONGS\n").message.contains("units"));
    assert!(err("LOADTL/-3\n").message.contains("tool number"));
    assert!(err("CSYS/2,0,0,0,0,1,0,0,0,0,1,0\n")
        .message
        .contains("rotation"));
    assert_eq!(
        err("GOTO/1,2,3\nCIRCLE/1,2,3,0,0,1,0\nGOTO/2,2,3\n").kind,
        PathErrorKind::Semantic
    );
}

#[test]
fn unknown_records_warn_with_their_position() {
    let mut rec = Recorder::default();
    read_apt(
        "PAINT/COLOR,3\n  FOO/1,2\n",
        "x.cls",
        &AptOptions::default(),
        &mut rec,
    )
    .unwrap();
    assert_eq!(rec.warnings.len(), 1);
    let w = &rec.warnings[0];
    assert_eq!((w.file.as_str(), w.line, w.column), ("x.cls", 2, 3));
}

/// The arcs of a file as (end, centre in the arc's plane, rotation ±1).
fn arcs(e: &[Canon<'static>]) -> Vec<(Axes, [f64; 2], i32)> {
    e.iter()
        .filter_map(|x| match x {
            Canon::Arc {
                end,
                center,
                rotation,
                plane: Plane::XY,
            } => Some((*end, *center, *rotation)),
            _ => None,
        })
        .collect()
}

#[test]
fn catia_circles_go_forward_in_the_indirv_direction_to_the_line() {
    // CATIA's circular output: from (50, 10, -1) about (50, 20, -1), radius 10, first along +X
    // (counter-clockwise about the tool axis +Z) to the line from the centre through (60, 20).
    let head = "MULTAX\nGOTO  /   50.00000,  10.00000, -1.00000,  0.000000,  0.000000,  1.000000\n";
    let catia = format!(
        "{head}INDIRV/   1.000000,  0.000000,  0.000000\nTLON,GOFWD/ (CIRCLE/  50.00000,  20.00000, \
         -1.00000,  10.00000),$\n ON,(LINE/  50.00000,  20.00000, -1.00000,  60.00000,  20.00000, \
         -1.00000)\nGOTO  /   60.00000,  40.00000, -1.00000,  0.000000,  0.000000,  1.000000\n"
    );
    let e = events(&catia);
    assert_eq!(arcs(&e), [(at(60.0, 20.0, -1.0), [50.0, 20.0], 1)]);
    assert_eq!(
        e.last(),
        Some(&Canon::Feed {
            end: at(60.0, 40.0, -1.0)
        })
    );
    // Started along -X it goes the long way round, clockwise, to the same end.
    let cw = catia.replace("INDIRV/   1.0", "INDIRV/   -1.0");
    assert_eq!(
        arcs(&events(&cw)),
        [(at(60.0, 20.0, -1.0), [50.0, 20.0], -1)]
    );
    // The circle's own axis (7 numbers), and a line not through the centre: the end is where
    // the tool first meets it (x = 55 going counter-clockwise from the bottom).
    let own = format!(
        "{head}INDIRV/1,0,0\nTLON,GOFWD/(CIRCLE/50,20,-1,0,0,1,10),ON,(LINE/55,0,-1,55,40,-1)\n"
    );
    let a = arcs(&events(&own));
    assert_eq!(a.len(), 1);
    let (end, _, rot) = a[0];
    assert_eq!(rot, 1);
    assert!((end.x - 55.0).abs() < 1e-12 && (end.y - (20.0 - 75f64.sqrt())).abs() < 1e-12);
    // No INDIRV, another modifier, no position yet: errors that say so.
    let e = err(&format!(
        "{head}TLON,GOFWD/(CIRCLE/50,20,-1,10),ON,(LINE/50,20,-1,60,20,-1)\n"
    ));
    assert_eq!((e.kind, e.pos.line), (PathErrorKind::Semantic, 3));
    assert!(e.message.contains("INDIRV"), "{e}");
    let e = err(&format!(
        "{head}INDIRV/1,0,0\nTLON,GOFWD/(CIRCLE/50,20,-1,10),PAST,(LINE/50,20,-1,60,20,-1)\n"
    ));
    assert_eq!(e.kind, PathErrorKind::Unsupported);
    assert!(e.message.contains("PAST"), "{e}");
    let e = err("INDIRV/1,0,0\nTLON,GOFWD/(CIRCLE/50,20,-1,10),ON,(LINE/50,20,-1,60,20,-1)\n");
    assert!(e.message.contains("before any position"), "{e}");
}

/// A CATIA arc is planar, at the start's height along the circle's axis, whatever the heights
/// of the CIRCLE's centre and the LINE's points; a LINE through the centre gives the ray from
/// the centre towards its far point, written either way round. Before, the end took the line's
/// far point's height (a centre at z = 0 turned a start at z = -1 into a 1 mm helix), or the
/// centre's, and a line written end → centre was cut where the tool first met it.
#[test]
fn catia_arcs_stay_at_the_start_height_and_lines_from_the_centre_read_both_ways() {
    let head = "MULTAX\nGOTO/50,10,-1,0,0,1\nINDIRV/1,0,0\n";
    let end = |tail: &str| {
        let e = events(&format!("{head}{tail}\n"));
        let a = arcs(&e);
        assert_eq!(a.len(), 1, "{tail}");
        (a[0].0, a[0].2)
    };
    let close = |p: Axes, q: Axes| {
        (p.x - q.x).abs() < 1e-12 && (p.y - q.y).abs() < 1e-12 && (p.z - q.z).abs() < 1e-12
    };
    for tail in [
        // The centre and line at z = 0, and a far point above it.
        "TLON,GOFWD/(CIRCLE/50,20,0,10),ON,(LINE/50,20,0,60,20,0)",
        "TLON,GOFWD/(CIRCLE/50,20,0,10),ON,(LINE/50,20,-1,60,20,5)",
        // Written end → centre.
        "TLON,GOFWD/(CIRCLE/50,20,0,10),ON,(LINE/60,20,0,50,20,0)",
        "TLON,GOFWD/(CIRCLE/50,20,-1,10),ON,(LINE/70,20,-1,50,20,-1)",
    ] {
        let (p, rot) = end(tail);
        assert!(close(p, at(60.0, 20.0, -1.0)), "{tail}: {p:?}");
        assert_eq!(rot, 1, "{tail}");
    }
    // Clockwise (the long way round) to a line written end → centre: still its ray, not the
    // first crossing at (40, 20).
    let cw = events(
        "MULTAX\nGOTO/50,10,-1,0,0,1\nINDIRV/-1,0,0\nTLON,GOFWD/(CIRCLE/50,20,-1,10),ON,(LINE/60,20,-1,50,20,-1)\n",
    );
    let a = arcs(&cw);
    assert_eq!(a.len(), 1);
    assert!(close(a[0].0, at(60.0, 20.0, -1.0)), "{:?}", a[0].0);
    assert_eq!(a[0].2, -1);
    // A line not through the centre, the circle at z = 0: the crossing at the start's height.
    let (p, _) = end("TLON,GOFWD/(CIRCLE/50,20,0,0,0,1,10),ON,(LINE/55,0,3,55,40,3)");
    assert!(close(p, at(55.0, 20.0 - 75f64.sqrt(), -1.0)), "{p:?}");
}

proptest! {
    #![proptest_config(swarf_testdata::proptest_config(512))]
    /// Any text: an error or events, never a panic.
    #[test]
    fn never_panics(text in "(?s)[A-Z/,.0-9$ \n\\-+eE]{0,200}") {
        let mut rec = Recorder::default();
        let _ = read_apt(&text, "fuzz.apt", &AptOptions::default(), &mut rec);
    }

    /// Record-shaped text with random numbers reads and builds without panicking.
    #[test]
    fn records_build(
        recs in prop::collection::vec(
            (prop::sample::select(vec!["GOTO", "CIRCLE", "FROM", "RAPID", "FEDRAT", "CUTTER", "GODLTA", "SPINDL", "LOADTL", "CSYS"]),
             prop::collection::vec(-1e3f64..1e3, 0..13)),
            0..30)
    ) {
        let text: String = recs
            .iter()
            .map(|(w, v)| format!("{w}/{}\n", v.iter().map(|x| x.to_string()).collect::<Vec<_>>().join(",")))
            .collect();
        let mut b = MoveBuilder::new(Machine::three_axis(), "p.apt");
        let _ = read_apt(&text, "p.apt", &AptOptions::default(), &mut b);
        let _ = summarize(&b.finish());
    }
}

#[test]
fn circle_direction_words_override_the_convention() {
    let rotation = |text: &str| {
        events(text)
            .into_iter()
            .find_map(|e| match e {
                Canon::Arc { rotation, .. } => Some(rotation),
                _ => None,
            })
            .unwrap()
    };
    let base = "FEDRAT/100\nGOTO/10,0,0\nCIRCLE/0,0,0,0,0,1,10";
    // Counter-clockwise about +Z by default (not an NX file), either way when stated.
    assert_eq!(rotation(&format!("{base}\nGOTO/0,10,0\n")), 1);
    assert_eq!(rotation(&format!("{base},CLW\nGOTO/0,10,0\n")), -1);
    assert_eq!(rotation(&format!("{base},CLOCKWISE\nGOTO/0,10,0\n")), -1);
    assert_eq!(
        rotation(&format!("{base},COUNTERCLOCKWISE\nGOTO/0,10,0\n")),
        1
    );
    assert_eq!(rotation(&format!("{base},CCLW,\nGOTO/0,10,0\n")), 1);
    // Any other word is still an error at its field.
    let e = err(&format!("{base},SIDEWAYS\nGOTO/0,10,0\n"));
    assert_eq!((e.pos.line, e.pos.column), (3, 23));
    // SolidWorks CAM's trailing comma after CUTTER/.
    assert!(events("CUTTER/10.000000,0.000000,\nGOTO/0,0,0\n")
        .iter()
        .any(|e| matches!(e, Canon::CutterDefinition(c) if c[0] == 10.0)));
}

#[test]
fn motion_swarf_cannot_generate_is_an_error_not_a_warning() {
    let e = err("FEDRAT/100\nGOTO/0,0,5\nCYCLE/MILL,5,MMPM,100,2\nGOTO/10,10,0\nCYCLE/OFF\n");
    assert_eq!(e.kind, PathErrorKind::Unsupported);
    assert_eq!((e.pos.line, e.pos.column), (3, 7));
    assert!(e.message.contains("CYCLE/"), "{}", e.message);
    let e = err("FEDRAT/100\nGOTO/0,0,5\nNURBS/\nKNOT/0,0,0,0,1,1,1,1\nCNTRL/0,0,0\n");
    assert_eq!(e.pos.line, 3);
    assert!(e.message.contains("NURBS/"), "{}", e.message);
    // CYCLE/OFF alone changes nothing.
    assert!(events("GOTO/0,0,5\nCYCLE/OFF\nGOTO/1,0,5\n").len() > 2);
}

/// CATIA writes free text after `PPRINT` and `PARTNO` without a slash, with any characters in
/// it; `TLAXIS/i,j,k` gives the axis of the `GOTO`s that follow without one.
#[test]
fn free_text_records_and_tlaxis() {
    let e = events(
        "PARTNO PART TO BE MACHINED\nPPRINT OPERATION NAME : Multi-Axis Sweeping.1\n\
         PPRINT/TOOL DIA = 10.0, (BALL)\nINSERT G0 X0. Y0.\nREMARK a, b: c\n\
         TPRINT/T1 Ball Mill D 10,Default Tool Assembly\nFROM/0,0,10\n\
         TLAXIS/ 0.6, 0.0, 0.8\nGOTO/1,0,10\nGOTO/2,0,10,0,0,1\n",
    );
    let comments: Vec<&str> = e
        .iter()
        .filter_map(|c| match c {
            Canon::Comment(t) => Some(t.as_ref()),
            _ => None,
        })
        .collect();
    assert_eq!(
        comments,
        [
            "PART TO BE MACHINED",
            "OPERATION NAME : Multi-Axis Sweeping.1",
            "TOOL DIA = 10.0, (BALL)",
            "G0 X0. Y0.",
            "a, b: c",
            "T1 Ball Mill D 10,Default Tool Assembly",
        ]
    );
    let mut rec = Recorder::default();
    // (A direction written with huge components is a direction: its squared length would
    // overflow, and it read as a zero axis.)
    let text = "FROM/0,0,10\nTLAXIS/ 0.6, 0.0, 0.8\nGOTO/1,0,10\nGOTO/2,0,10,0,0,1e155\n";
    read_apt(text, "t.apt", &AptOptions::default(), &mut rec).unwrap();
    let mut b = MoveBuilder::new(Machine::three_axis(), "t.apt");
    for (line, ev) in &rec.events {
        swarf_path::canon::CanonSink::emit(&mut b, *line, ev);
    }
    let p = b.finish();
    let axis = |v: swarf_geom::math::Vec3| [v.x, v.y, v.z];
    assert_eq!(axis(p.moves[0].end.axis), [0.6, 0.0, 0.8]);
    assert_eq!(axis(p.moves[1].end.axis), [0.0, 0.0, 1.0]);
    assert_eq!(
        err("TLAXIS/0,0,0\n").to_string().split(": ").nth(1),
        Some("zero tool axis (found `0,0,0`, expected a non-zero tool axis i,j,k)")
    );
}

/// `GOHOME` returns to the `FROM/` point (a rapid after `RAPID`); without one it is a warning,
/// not a move to a guessed place.
#[test]
fn gohome_returns_to_the_from_point() {
    let e = events("FROM/0,0,100\nGOTO/10,0,5\nRAPID\nGOHOME\n");
    assert_eq!(
        e.last(),
        Some(&Canon::Traverse {
            end: at(0.0, 0.0, 100.0)
        })
    );
    assert_eq!(
        events("FROM/0,0,100\nGOTO/10,0,5\nGOHOME\n").last(),
        Some(&Canon::Feed {
            end: at(0.0, 0.0, 100.0)
        })
    );
    let mut rec = Recorder::default();
    read_apt(
        "GOTO/10,0,5\nGOHOME\n",
        "t.apt",
        &AptOptions::default(),
        &mut rec,
    )
    .unwrap();
    assert!(rec
        .warnings
        .iter()
        .any(|w| w.message.contains("GOHOME") && w.line == 2));
    assert!(!rec
        .events
        .iter()
        .any(|(_, e)| matches!(e, Canon::Feed { .. } | Canon::Traverse { .. })));
}

/// NX's `GOHOME/x,y,z[,i,j,k]` states the home itself: a move there (a rapid after `RAPID`, as
/// NX writes it), with its axis, whether or not a `FROM/` came before — not the `FROM/` point,
/// and not a warning. A cycle still on does not drill a hole there.
#[test]
fn gohome_with_coordinates_moves_to_them() {
    let e = events("FROM/0,0,100\nGOTO/10,0,5\nRAPID\nGOHOME/5,5,50\n");
    assert_eq!(
        e.last(),
        Some(&Canon::Traverse {
            end: at(5.0, 5.0, 50.0)
        })
    );
    let mut rec = Recorder::default();
    read_apt(
        "GOTO/10,0,5\nRAPID\nGOHOME/0,0,50,0.6,0,0.8\nGOTO/0,0,40\n",
        "t.apt",
        &AptOptions::default(),
        &mut rec,
    )
    .unwrap();
    assert!(rec.warnings.is_empty(), "{:?}", rec.warnings);
    let e: Vec<_> = rec.events.into_iter().map(|(_, e)| e).collect();
    assert_eq!(
        e[2..],
        [
            Canon::ToolAxis([0.6, 0.0, 0.8]),
            Canon::Traverse {
                end: at(0.0, 0.0, 50.0)
            },
            // The rapid was that move's only.
            Canon::Feed {
                end: at(0.0, 0.0, 40.0)
            },
        ]
    );
    let e = events(
        "FEDRAT/MMPM,500\nGOTO/0,0,50\nCYCLE/DRILL,FEDTO,-12,RAPTO,3,RTRCTO,AUTO,MMPM,100\n\
         GOTO/10,0,0\nRAPID\nGOHOME/0,0,80\n",
    );
    assert_eq!(
        e.last(),
        Some(&Canon::Traverse {
            end: at(0.0, 0.0, 80.0)
        })
    );
    assert_eq!(
        err("GOTO/0,0,5\nGOHOME/1,2\n")
            .to_string()
            .split(": ")
            .nth(1),
        Some("GOHOME/ with 2 value(s) (found `1,2`, expected x,y,z or x,y,z,i,j,k)")
    );
}

/// The cutter definitions `text` states, in order.
fn definitions(text: &str) -> Vec<[f64; 7]> {
    events(text)
        .into_iter()
        .filter_map(|e| match e {
            Canon::CutterDefinition(c) => Some(c),
            _ => None,
        })
        .collect()
}

fn assert_cutter(got: [f64; 7], want: [f64; 7]) {
    assert!(
        got.iter().zip(&want).all(|(g, w)| (g - w).abs() < 1e-12),
        "{got:?} != {want:?}"
    );
}

/// NX's `TLDATA/MILL,D,R,L,B,A` with a taper angle B or a tip angle A, and `TLDATA/DRILL`, are
/// APT generic cutters (d, r, e, f, α, β, h) as `CUTTER/` states them — not a warning that left
/// the operation cutting with the previous operation's cutter.
#[test]
fn tldata_taper_tip_and_drill_are_cutters() {
    let c5 = 5f64.to_radians().cos();
    let d = definitions(
        "TLDATA/MILL,6.0000,3.0000,50.0000,5.0000,0.0000\n\
         TLDATA/MILL,10,0,40,3,0\n\
         TLDATA/MILL,10,1,40,0,10\n\
         TLDATA/DRILL,8.0000,0.0000,60.0000,118.0000,40.0000\n\
         TLDATA/MILL,10,2,40\n",
    );
    assert_eq!(d.len(), 5);
    // A Ø6 tapered ball: the ball's centre on the axis, 3 above the tip; the side leaves it
    // at Ø6·cos 5° (APT's d), as swarf's `taper-ball:d=6,taper=5`.
    assert_cutter(d[0], [6.0 * c5, 3.0, 0.0, 3.0, 0.0, 5.0, 50.0]);
    // A tapered flat end mill, Ø10 at the tip.
    assert_cutter(d[1], [10.0, 0.0, 5.0, 0.0, 0.0, 3.0, 40.0]);
    // A 10° tip angle: the bottom through the tip rises to the R1 corner centred 4 out.
    let a = 10f64.to_radians();
    assert_cutter(
        d[2],
        [
            10.0,
            1.0,
            4.0,
            (1.0 + 4.0 * a.sin()) / a.cos(),
            10.0,
            0.0,
            40.0,
        ],
    );
    // A 118° drill: a cone 31° from the horizontal to Ø8.
    let a = 31f64.to_radians();
    assert_cutter(d[3], [8.0, 0.0, 4.0, 4.0 * a.tan(), 31.0, 0.0, 60.0]);
    // Without angles, as before: a torus.
    assert_eq!(d[4], [10.0, 2.0, 3.0, 2.0, 0.0, 0.0, 40.0]);

    // What makes no cutter is refused at its field, not left to the previous cutter.
    let msg = |text: &str| err(text).to_string();
    assert_eq!(
        msg("TLDATA/MILL,6,3,50,95,0\n"),
        "t.apt:1:20: TLDATA/MILL angle that makes no cutter (found `95`, expected a taper \
         angle in (-90°, 90°) from the tool axis)"
    );
    assert!(
        msg("TLDATA/MILL,10,0,50,0,-5\n").starts_with("t.apt:1:23: TLDATA/MILL angle"),
        "{}",
        msg("TLDATA/MILL,10,0,50,0,-5\n")
    );
    assert!(msg("TLDATA/MILL,10,0,50,30,70\n").contains("at most 90°"));
    assert_eq!(
        msg("TLDATA/DRILL,8,0,60,0,40\n"),
        "t.apt:1:21: TLDATA/DRILL point angle out of range (found `0`, expected an included \
         point angle in (0°, 180°] (118 for a twist drill))"
    );
    assert!(msg("TLDATA/DRILL,8,0,60\n").contains("expected DRILL,d,r,h,point angle"));
    // Tool types swarf has no cutter for still warn.
    let mut rec = Recorder::default();
    read_apt(
        "TLDATA/TURN,0.8,0,0\n",
        "t.apt",
        &AptOptions::default(),
        &mut rec,
    )
    .unwrap();
    assert!(rec.warnings[0].message.starts_with("TLDATA/TURN"));
}

/// A file that ends inside a record continued with `$` was cut short: read, and said.
#[test]
fn a_record_continued_past_the_end_is_said() {
    let mut rec = Recorder::default();
    read_apt(
        "UNITS/MM\nFEDRAT/MMPM,100\nGOTO/0,0,0\nGOTO/20,0,0,$\n",
        "cut.apt",
        &AptOptions::default(),
        &mut rec,
    )
    .unwrap();
    let said: Vec<_> = rec
        .warnings
        .iter()
        .filter(|w| w.message.contains("past the end of the file"))
        .collect();
    assert_eq!(said.len(), 1, "{:?}", rec.warnings);
    assert_eq!(said[0].line, 4);
    // Ended with FINI, or simply without a continued record: nothing said.
    for text in [
        "GOTO/0,0,0\nGOTO/20,0,0\nFINI\n",
        "GOTO/0,0,0\nGOTO/20,0,0\n",
    ] {
        let mut rec = Recorder::default();
        read_apt(text, "ok.apt", &AptOptions::default(), &mut rec).unwrap();
        assert!(
            rec.warnings
                .iter()
                .all(|w| !w.message.contains("past the end")),
            "{:?}",
            rec.warnings
        );
    }
}
