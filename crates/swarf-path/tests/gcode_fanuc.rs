//! Fanuc forms, each with a small program whose moves are written out from the control's rules
//! (FANUC Series 0i-MF operator's manual: "Canned cycle cancel (G80)" with G00–G03 in group 01
//! and the cycles in group 09; "Power-on modal state" G00; "Subprogram call (M98)"; "Reference
//! position return (G28)"; "Coordinate system rotation (G68, G69)"; "Scaling (G50, G51)";
//! "Optional block skip").

mod common;
use common::fanuc_warnings as warnings;
use swarf_path::canon::Recorder;
use swarf_path::gcode::{read_gcode, GcodeDialect, GcodeOptions};
use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::{Canon, Machine, PathError};

/// The moves as (`R` rapid / `L` feed / `A` arc, x, y, z).
fn moves(src: &str, options: &GcodeOptions) -> Result<Vec<(char, f64, f64, f64)>, PathError> {
    let mut rec = Recorder::default();
    read_gcode(src, "fanuc.nc", options, &mut rec)?;
    Ok(rec
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::Traverse { end } => Some(('R', end.x, end.y, end.z)),
            Canon::Feed { end } => Some(('L', end.x, end.y, end.z)),
            Canon::Arc { end, .. } => Some(('A', end.x, end.y, end.z)),
            _ => None,
        })
        .collect())
}

fn fanuc() -> GcodeOptions {
    GcodeOptions::default().with_dialect(GcodeDialect::Fanuc)
}

#[test]
fn the_dialect_is_detected_and_can_be_forced() {
    assert_eq!(
        GcodeDialect::detect("%\nO1234\nG0 X0\nM98 P10\nM30\n"),
        GcodeDialect::Fanuc
    );
    assert_eq!(GcodeDialect::detect("G80 G0 Z5\n"), GcodeDialect::Fanuc);
    assert_eq!(
        GcodeDialect::detect("O1234\no<side> sub\no<side> endsub\n"),
        GcodeDialect::LinuxCnc
    );
    assert_eq!(
        GcodeDialect::detect("G0 X1\nG1 X2 F3\n"),
        GcodeDialect::LinuxCnc
    );
    // M words by number: M098 is M98; M980, M990 and M999 (a machine's own codes) are not.
    assert_eq!(GcodeDialect::detect("M098 P10\n"), GcodeDialect::Fanuc);
    assert_eq!(GcodeDialect::detect("G0 Z5\nM99\n"), GcodeDialect::Fanuc);
    for not_a_call in ["M980\n", "M981 P2\n", "G0 Z5\nM990\nM2\n", "M999\n"] {
        assert_eq!(
            GcodeDialect::detect(not_a_call),
            GcodeDialect::LinuxCnc,
            "{not_a_call}"
        );
    }
    // LinuxCNC runs M98/M99 programs too: its own comments tell them apart (a `;` at a
    // block's end is Fanuc's end-of-block mark, a `;` inside a comment nothing).
    for linuxcnc in [
        "O1\nG0 X1 ; over the hole\nM98 P1\nM30\n",
        "%\nM98 P2 L5\n(PRINT,X MAIN END: 1=#1)\nM30\nO2\nM99\n%\n",
        "M98 P1\n( debug, #1)\nM30\n",
    ] {
        assert_eq!(
            GcodeDialect::detect(linuxcnc),
            GcodeDialect::LinuxCnc,
            "{linuxcnc}"
        );
    }
    // The choice is said, at the line that decided it, unless the dialect is given.
    let said = |src: &str, o: &GcodeOptions| -> Vec<(u32, String)> {
        read_with(src, o)
            .1
            .into_iter()
            .filter(|w| w.2.contains(" rules"))
            .map(|w| (w.0, w.2))
            .collect()
    };
    let w = said("G21 G90\nO1\nG0 X1.\nM30\n", &GcodeOptions::default());
    assert!(
        w.len() == 1 && w[0].0 == 2 && w[0].1.starts_with("read by Fanuc rules"),
        "{w:?}"
    );
    let w = said("G21 (print,x)\nO1\nG0 X1.\nM30\n", &GcodeOptions::default());
    assert!(
        w.len() == 1 && w[0].1.contains("line 1 has something only LinuxCNC"),
        "{w:?}"
    );
    assert!(said("G21 G90\nO1\nG0 X1.\nM30\n", &fanuc()).is_empty());
    assert!(said("G21 G90\nG0 X1.\nM2\n", &GcodeOptions::default()).is_empty());
    for fanuc in [
        "O1\nG0 X1. ;\nM98 P1 ;\nM30 ;\n",
        "O1 (T1; 10 MM END MILL)\nM98 P1\n(MSG, CHECK)\nM30\n",
    ] {
        assert_eq!(GcodeDialect::detect(fanuc), GcodeDialect::Fanuc, "{fanuc}");
    }
    // Forced: LinuxCNC reads G80 with G0 in one block too (rs274's read_g: G80 yields to the
    // other motion code) but refuses axis words after G80 with no motion code, which a Fanuc
    // control moves with the last G0–G3.
    let linuxcnc = GcodeOptions::default().with_dialect(GcodeDialect::LinuxCnc);
    assert_eq!(moves("G80 G0 Z5\n", &linuxcnc).unwrap().len(), 1);
    let e = moves("G0 X1\nG80\nZ5\n", &linuxcnc).unwrap_err();
    assert!(e.message.contains("without a motion"), "{e}");
    assert_eq!(moves("G0 X1\nG80\nZ5\n", &fanuc()).unwrap().len(), 2);
}

#[test]
fn g80_and_g0_share_a_block_and_the_group_01_motion_resumes() {
    let src = "O1234\nG90 G17 G21 G0 X0 Y0 Z10\nG81 X5 Y5 Z-2 R2 F100\nX10\nG80 G0 Z20\nX0 Y0\nG1 X1\nG81 X5 Y5 Z-2 R2\nG80\nX3\nM30\n";
    let m = moves(src, &fanuc()).unwrap();
    let want = [
        ('R', 0.0, 0.0, 10.0),
        // G81 at (5, 5): to the hole, down to R, feed to Z, back to the initial level (G98).
        ('R', 5.0, 5.0, 10.0),
        ('R', 5.0, 5.0, 2.0),
        ('L', 5.0, 5.0, -2.0),
        ('R', 5.0, 5.0, 10.0),
        ('R', 10.0, 5.0, 10.0),
        ('R', 10.0, 5.0, 2.0),
        ('L', 10.0, 5.0, -2.0),
        ('R', 10.0, 5.0, 10.0),
        // G80 G0 Z20: the cycle is cancelled and G0 moves.
        ('R', 10.0, 5.0, 20.0),
        ('R', 0.0, 0.0, 20.0),
        ('L', 1.0, 0.0, 20.0),
        ('R', 5.0, 5.0, 20.0),
        ('R', 5.0, 5.0, 2.0),
        ('L', 5.0, 5.0, -2.0),
        ('R', 5.0, 5.0, 20.0),
        // After a lone G80 the last group 01 code (G1) moves the axes.
        ('L', 3.0, 5.0, 20.0),
    ];
    assert_eq!(m, want);
}

#[test]
fn power_on_motion_is_g0() {
    // `G43 Z50 H1` with no motion code yet: a rapid on a Fanuc control.
    let m = moves("O0001\nG90 G21\nG43 Z50 H1\nX10\nM30\n", &fanuc()).unwrap();
    assert_eq!(m, vec![('R', 0.0, 0.0, 50.0), ('R', 10.0, 0.0, 50.0)]);
    // LinuxCNC needs a motion code.
    let e = moves(
        "G90 G21\nG43 Z50 H1\nM30\n",
        &GcodeOptions::default().with_dialect(GcodeDialect::LinuxCnc),
    )
    .unwrap_err();
    assert!(e.message.contains("without a motion G code"), "{e}");
}

#[test]
fn m98_packs_the_repeat_count_in_p_and_m99_returns() {
    // M98 P30010: three runs of O0010; M98 P20 L2: two runs of O20.
    let src = "O1\nG91 G21\nM98 P30010\nM98 P20 L2\nM30\nO0010\nG0 X1\nM99\nO20\nG0 Y1\nM99\n";
    let m = moves(src, &fanuc()).unwrap();
    let xs: Vec<_> = m.iter().map(|&(_, x, y, _)| (x, y)).collect();
    assert_eq!(
        xs,
        vec![(1.0, 0.0), (2.0, 0.0), (3.0, 0.0), (3.0, 1.0), (3.0, 2.0)]
    );
}

#[test]
fn g28_with_g91_goes_home_through_the_current_point() {
    // G91 G28 Z0: the intermediate point is 0 away (where the tool is), then Z to the home
    // position (machine 0).
    let m = moves("O1\nG90 G21 G0 X5 Y6 Z7\nG91 G28 Z0\nM30\n", &fanuc()).unwrap();
    assert_eq!(
        m,
        vec![
            ('R', 5.0, 6.0, 7.0),
            ('R', 5.0, 6.0, 7.0),
            ('R', 5.0, 6.0, 0.0)
        ]
    );
}

#[test]
fn sequence_numbers_and_block_skip_on_every_kind_of_line() {
    let src = "%\nO1\nN1 G90 G21\nN2 /G0 X99\n/N3 G0 X98\nN4 G0 X1\nN5 M98 P7\nN6 M30\nO7\nN70 G0 Y1\nN71 M99\n%\n";
    let m = moves(src, &fanuc().with_block_delete(true)).unwrap();
    assert_eq!(m, vec![('R', 1.0, 0.0, 0.0), ('R', 1.0, 1.0, 0.0)]);
    // With the switch off (the default) both are read.
    let m = moves(src, &fanuc()).unwrap();
    let xs: Vec<f64> = m.iter().map(|m| m.1).collect();
    assert_eq!(xs, [99.0, 98.0, 1.0, 1.0]);
}

#[test]
fn g68_turns_the_program_about_its_centre() {
    // G68 X10 Y0 R90: X20 Y0 is (10, 10) on the part; G69 ends it.
    let src = "O1\nG90 G17 G21\nG68 X10 Y0 R90\nG1 X20 Y0 F100\nG69\nG1 X20 Y0\nM30\n";
    let read = ReadOptions {
        gcode: fanuc(),
        ..ReadOptions::default()
    };
    let p = read_program_str(src, "r.nc", Machine::three_axis(), &read).unwrap();
    let tip = |i: usize| p.moves[i].end.tip;
    assert!(
        (tip(0).x - 10.0).abs() < 1e-9 && (tip(0).y - 10.0).abs() < 1e-9,
        "{:?}",
        tip(0)
    );
    assert!(
        (tip(1).x - 20.0).abs() < 1e-9 && tip(1).y.abs() < 1e-9,
        "{:?}",
        tip(1)
    );
}

#[test]
fn g51_scales_about_its_centre_and_g50_ends_it() {
    let src = "O1\nG90 G17 G21\nG51 X0 Y0 P2\nG1 X5 Y5 F100\nG91 X1\nG90 G2 X15 Y5 R5\nG50\nG1 X5 Y5\nM30\n";
    let m = moves(src, &fanuc()).unwrap();
    assert_eq!(
        m,
        vec![
            ('L', 10.0, 10.0, 0.0),
            ('L', 12.0, 10.0, 0.0),
            ('A', 30.0, 10.0, 0.0),
            ('L', 5.0, 5.0, 0.0),
        ]
    );
    let e = moves("G51 X0 Y0 I1 J2\nG2 X1 Y1 R1 F1\n", &fanuc()).unwrap_err();
    assert!(e.message.contains("ellipse"), "{e}");
    // G50 alone is accepted anywhere.
    moves("G50\nG0 X1\nM30\n", &GcodeOptions::default()).unwrap();
}

#[test]
fn g70_and_g71_alone_are_units_and_with_words_lathe_cycles() {
    // Vectric's Mach3 posts write `N110G70G91.1` (inch) and `N110G71G91.1` (mm), as Mach3 and
    // Fanuc lathes in G-code system B read them; with words they are lathe cycles, refused.
    for options in [fanuc(), GcodeOptions::default()] {
        let m = moves("N100G00G17G90\nN110G70G91.1\nN120X1.Y2.\nM30\n", &options).unwrap();
        // (LinuxCNC moves on the bare G00, a traverse of length zero, as rs274 prints it.)
        let bare = if options.dialect == Some(GcodeDialect::Fanuc) {
            vec![]
        } else {
            vec![('R', 0.0, 0.0, 0.0)]
        };
        assert_eq!(m, [bare, vec![('R', 25.4, 50.8, 0.0)]].concat());
        let m = moves("G20\nG71\nG0 X1. Y2.\nM30\n", &options).unwrap();
        assert_eq!(m, [('R', 1.0, 2.0, 0.0)]);
        let e = moves("G71 U2. R1.\n", &options).unwrap_err();
        assert_eq!(e.kind, swarf_path::PathErrorKind::Unsupported);
        assert!(e.message.starts_with("G71: G70/G71 with words"), "{e}");
        assert_eq!((e.pos.line, e.pos.column), (1, 1));
        let e = moves("G21 G71\n", &options).unwrap_err();
        assert!(e.message.contains("G21 and G71"), "{e}");
    }
    // Said where it changes the units.
    let w = warnings("O1\nG21\nG70\nG0 X1.\nG71\nM30\n");
    assert!(
        w.iter()
            .any(|(l, m)| *l == 3 && m.starts_with("G70 read as G20")),
        "{w:?}"
    );
    assert!(
        w.iter()
            .any(|(l, m)| *l == 5 && m.starts_with("G71 read as G21")),
        "{w:?}"
    );
}

#[test]
fn controller_modes_are_reported_and_left_out() {
    // Look-ahead and smoothing modes (G05.1 Q1, G05 P10000, G08 P1, Haas G187 and G103) and
    // the additional work offsets (G54.1 P, G154 P) change no programmed point: the moves are
    // those of the program without them, each code reported once with its line, and its P, Q
    // and E words are not reported as unused.
    let body = "G0 X1 Y2 Z5\nG1 X4 F100\n";
    let plain = moves(&format!("O1\nG21 G90\n{body}M30\n"), &fanuc()).unwrap();
    let src = format!(
        "O1\nG21 G90\nG05.1 Q1.\nG05 P10000\nG08 P1\nG187 P1 E0.01\nG103 P4\nG54.1 P2\nG154 P1\n{body}G05.1 Q0\nM30\n"
    );
    assert_eq!(moves(&src, &fanuc()).unwrap(), plain);
    let w = warnings(&src);
    let lines: Vec<u32> = w.iter().map(|(l, _)| *l).collect();
    // (Line 10: X1, the first number without a decimal point.)
    assert_eq!(lines, [3, 4, 5, 6, 7, 8, 9, 10, 12], "{w:?}");
    assert!(
        w[0].1.starts_with("G5.1 (AI contour control) ignored"),
        "{w:?}"
    );
    assert!(w[5].1.contains("current work offset stays"), "{w:?}");
    assert!(w[7].1.starts_with("X1 has no decimal point"), "{w:?}");
    // In LinuxCNC, G5.1 is a quadratic spline and needs its end point.
    let linuxcnc = GcodeOptions::default().with_dialect(GcodeDialect::LinuxCnc);
    let e = moves(&src, &linuxcnc).unwrap_err();
    assert!(e.message.contains("spline"), "{e}");
    // A tilted working plane is read (tests/gcode_tilted_plane.rs); its other forms are
    // refused by name.
    assert!(moves("O1\nG68.2 X0 Y0 Z0 I0 J45 K0\nM30\n", &fanuc()).is_ok());
    let e = moves("O1\nG68.3 X0 Y0 Z0 R45\nM30\n", &fanuc()).unwrap_err();
    assert!(e.message.contains("G68.3"), "{e}");
}

#[test]
fn tool_centre_point_and_fine_boring() {
    // G43.4 H1: a tool length offset with TCP (the tool table is empty: 0).
    let m = moves("O1\nG21 G90\nG43.4 H1 Z50.\nG1 X5 F100\nM30\n", &fanuc()).unwrap();
    assert_eq!(m, [('R', 0.0, 0.0, 50.0), ('L', 5.0, 0.0, 50.0)]);
    // G76 (fine boring) follows G86's path: down at feed, up at rapid.
    let src = "O1\nG21 G90\nG0 X0 Y0 Z10\nG98 G76 X5. Y5. Z-5. R1. Q0.2 P500 F50\nG80\nM30\n";
    let m = moves(src, &fanuc()).unwrap();
    assert_eq!(
        m,
        [
            ('R', 0.0, 0.0, 10.0),
            ('R', 5.0, 5.0, 10.0),
            ('R', 5.0, 5.0, 1.0),
            ('L', 5.0, 5.0, -5.0),
            ('R', 5.0, 5.0, 10.0),
        ]
    );
    // (And Z10's missing decimal point, line 3.)
    let w = warnings(src);
    assert_eq!(w.len(), 2, "{w:?}");
    assert!(w[1].1.starts_with("G76 (fine boring) read as G86"), "{w:?}");
    // LinuxCNC has no G43.4.
    let linuxcnc = GcodeOptions::default().with_dialect(GcodeDialect::LinuxCnc);
    let e = moves("G21 G90\nG43.4 H1 Z50.\nM2\n", &linuxcnc).unwrap_err();
    assert!(e.message.contains("unknown G code G43.4"), "{e}");
}

#[test]
fn arcs_as_fanuc_reads_them() {
    // A centre and no end point: a full circle (helical with Z); the out-of-plane K and the
    // centre words beside R are dropped with a warning, R wins.
    let src = "O1\nG21 G90 G17\nG0 X10 Y0 Z0\nG2 I-10. F200\nG2 X-10 Y0 I-10 J0 K0\nG2 X10 Y0 I-10. J0 R10.\nG3 J5. Z-8\nM30\n";
    let m = moves(src, &fanuc()).unwrap();
    assert_eq!(
        m,
        [
            ('R', 10.0, 0.0, 0.0),
            ('A', 10.0, 0.0, 0.0),
            ('A', -10.0, 0.0, 0.0),
            ('A', 10.0, 0.0, 0.0),
            ('A', 10.0, 0.0, -8.0),
        ]
    );
    let w = warnings(src);
    let w: Vec<(u32, &str)> = w.iter().map(|(l, m)| (*l, &m[..2])).collect();
    // (X10 at line 3: the program's first number without a decimal point.)
    assert_eq!(w, [(3, "X1"), (5, "K0"), (6, "I-"), (6, "J0")]);
    // LinuxCNC refuses the last two; the first is a full circle in rs274 2.9 too.
    let linuxcnc = GcodeOptions::default().with_dialect(GcodeDialect::LinuxCnc);
    for bad in ["G2 X-10 Y0 I-10 J0 K0 F200", "G2 X-10 Y0 I-10 R10 F200"] {
        let src = format!("G21 G90 G17\nG0 X10 Y0 Z0\n{bad}\nM2\n");
        assert!(moves(&src, &linuxcnc).is_err(), "{bad}");
    }
}

#[test]
fn canned_cycle_repeats_with_k_and_k0_stores_the_cycle() {
    // G91 G81 … K2: two holes 5 mm apart; K0 drills nothing where the tool is, the next
    // position drills with the stored data.
    let src = "O1\nG21 G90\nG0 X0 Y0 Z10\nG91 G98 G81 X5. Y0 Z-8. R-8. F100 K2\nG80 G90\nM30\n";
    let holes = |m: &[(char, f64, f64, f64)]| -> Vec<(f64, f64)> {
        m.iter()
            .filter(|s| s.0 == 'L')
            .map(|s| (s.1, s.3))
            .collect()
    };
    assert_eq!(
        holes(&moves(src, &fanuc()).unwrap()),
        [(5.0, -6.0), (10.0, -6.0)]
    );
    // (Only Z10's missing decimal point is reported: not the repeat count K2.)
    let w = warnings(src);
    assert!(
        w.len() == 1 && w[0].0 == 3 && w[0].1.starts_with("Z10 has no decimal point"),
        "{w:?}"
    );
    let src = "O1\nG21 G90\nG0 X0 Y0 Z10\nG98 G81 X5. Y5. Z-5. R1. F100 K0\nX10. Y10.\nG80\nM30\n";
    assert_eq!(holes(&moves(src, &fanuc()).unwrap()), [(10.0, -5.0)]);
    let src = "O1\nG21 G90\nG0 X0 Y0 Z10\nG98 G81 X5. Y5. Z-5. R1. F100 L0\nX10. Y10.\nG80\nM30\n";
    assert_eq!(holes(&moves(src, &fanuc()).unwrap()), [(10.0, -5.0)]);
    // K0 moves nothing, not even up to R from below it.
    let src = "O1\nG21 G90\nG0 X0 Y0 Z0\nG98 G81 X5. Y5. Z-5. R1. F100 K0\nM30\n";
    assert_eq!(moves(src, &fanuc()).unwrap(), [('R', 0.0, 0.0, 0.0)]);
}

#[test]
fn a_short_compensation_entry_is_taken_with_a_warning() {
    // Fanuc starts compensation on an entry move shorter than the radius (LinuxCNC refuses
    // it): the tool ends the radius to the left of the entry's end, normal to it. The
    // register D1 is set by the program (G10): a Fanuc register never comes from the tool
    // library, whose cutters are the simulation's.
    let body = "G0 X3.6 Y2.6 Z0\nG1 G41 X3.5 D1 F100\nY5\nG40 X3.5 Y10\nM30\n";
    let src = format!("O1\nG21 G90\nG10 L1 P1 R1\n{body}");
    let src = src.as_str();
    let opts = fanuc();
    let m = moves(src, &opts).unwrap();
    assert_eq!(m[1], ('L', 3.5, 1.6, 0.0), "{m:?}");
    // Without the G10, a tool library's diameter leaves the path as programmed (wear
    // compensation), with a warning.
    let m = moves(
        &format!("O1\nG21 G90\n{body}"),
        &fanuc().with_tool_diameter(1, 2.0),
    )
    .unwrap();
    assert_eq!(m[1], ('L', 3.5, 2.6, 0.0), "{m:?}");
    let p = read_program_str(
        src,
        "fanuc.nc",
        Machine::three_axis(),
        &ReadOptions {
            gcode: opts,
            ..ReadOptions::default()
        },
    )
    .unwrap();
    // (After R1's missing decimal point, line 3.)
    assert!(
        p.warnings[1].message.contains("entry move"),
        "{:?}",
        p.warnings
    );
    let linuxcnc = GcodeOptions::default()
        .with_dialect(GcodeDialect::LinuxCnc)
        .with_tool_diameter(1, 2.0);
    let e = moves(&format!("G21 G90\n{body}"), &linuxcnc).unwrap_err();
    assert!(e.message.contains("entry move"), "{e}");
}

#[test]
fn the_home_is_where_the_program_starts_and_g28_returns() {
    // A Haas-style program: the first rapid is at the home's height, `G28 G91 Z0.` retracts to
    // it; without a home given, the reference return goes to the work's Z0 and says so.
    let src = "%\nO1\nG21 G90\nG54 G0 X10. Y10.\nG43 Z40. H1\nG1 Z-1. F300.\nG0 Z25.\nG28 G91 Z0.\nG90\nM30\n%\n";
    let homed = fanuc().with_home([0.0, 0.0, 300.0]);
    let m = moves(src, &homed).unwrap();
    assert_eq!(m[0], ('R', 10.0, 10.0, 300.0));
    assert_eq!(*m.last().unwrap(), ('R', 10.0, 10.0, 300.0));
    let p = read_program_str(
        src,
        "fanuc.nc",
        Machine::three_axis(),
        &ReadOptions {
            gcode: homed,
            ..ReadOptions::default()
        },
    )
    .unwrap();
    assert_eq!(
        p.moves[0].start.tip.z, 300.0,
        "the program starts at the home"
    );
    assert!(p
        .warnings
        .iter()
        .all(|w| !w.message.contains("reference return")));
    let m = moves(src, &fanuc()).unwrap();
    assert_eq!(m[0], ('R', 10.0, 10.0, 0.0));
    assert_eq!(*m.last().unwrap(), ('R', 10.0, 10.0, 0.0));
    let w = warnings(src);
    assert!(
        w.iter().any(|(l, m)| *l == 8 && m.contains("--home")),
        "{w:?}"
    );
}

#[test]
fn haas_m97_calls_a_local_subprogram_by_line_number() {
    // M97 P100 L2 runs from the line N100 to its M99 twice, then returns after the call.
    let src =
        "O1\nG21 G90\nG0 X0 Y0 Z5.\nM97 P100 L2\nG0 Z10.\nM30\nN100 G91 G1 X1. F100.\nG90\nM99\n";
    let m = moves(src, &fanuc()).unwrap();
    assert_eq!(
        m,
        [
            ('R', 0.0, 0.0, 5.0),
            ('L', 1.0, 0.0, 5.0),
            ('L', 2.0, 0.0, 5.0),
            ('R', 2.0, 0.0, 10.0),
        ]
    );
    let e = moves("O1\nM97 P7\nM30\n", &fanuc()).unwrap_err();
    assert!(e.message.contains("no line numbered N7"), "{e}");
}

/// Fanuc Custom Macro B: unbracketed assignments, WHILE … DO m / END m, IF … GOTO, IF …
/// THEN and GOTO, the moves worked out by running the program by hand.
#[test]
fn macro_b_control_flow() {
    // A counted loop: X 0, 2, 4 at Y = #1's square; an IF … THEN; a GOTO over a block.
    let src = "O1\nG21 G90\n#1=0\nWHILE [#1 LT 3] DO1\nG1 X[#1*2] Y[#1*#1] F100\n#1=#1+1\nEND1\n\
               IF [#1 EQ 3] THEN #2=7\nG0 Z#2\nGOTO 30\nG0 Z99\nN30 G0 X-1\nM30\n";
    let got = moves(src, &fanuc()).unwrap();
    assert_eq!(
        got,
        [
            ('L', 0.0, 0.0, 0.0),
            ('L', 2.0, 1.0, 0.0),
            ('L', 4.0, 4.0, 0.0),
            ('R', 4.0, 4.0, 7.0),
            ('R', -1.0, 4.0, 7.0),
        ]
    );
    // Nested loops, an IF … GOTO leaving the inner one, a false WHILE skipped past its END.
    let src = "O1\nG21\n#1=0\nWHILE [#1 LT 2] DO1\n#2=0\nWHILE [#2 LT 5] DO2\n\
               IF [#2 EQ 2] GOTO 10\nG0 X#1 Y#2\n#2=#2+1\nEND2\nN10 #1=#1+1\nEND1\n\
               WHILE [0] DO3\nG0 Z50\nEND3\nG0 Z1\nM30\n";
    let got = moves(src, &fanuc()).unwrap();
    assert_eq!(
        got,
        [
            ('R', 0.0, 0.0, 0.0),
            ('R', 0.0, 1.0, 0.0),
            ('R', 1.0, 0.0, 0.0),
            ('R', 1.0, 1.0, 0.0),
            ('R', 1.0, 1.0, 1.0),
        ]
    );
    // Errors at their lines; an endless GOTO loop ends at the reader's iteration limit.
    for (src, line) in [
        ("O1\nG21\nGOTO 5\nM30\n", 3),
        ("O1\nG21\nEND1\nM30\n", 3),
        ("O1\nG21\nWHILE [0] DO1\nM30\n", 3),
        ("O1\nG21\nIF [1] G0 X1\nM30\n", 3),
    ] {
        let e = moves(src, &fanuc()).unwrap_err();
        assert_eq!(e.pos.line, line, "{src}: {e}");
    }
    let e = moves("O1\nN1 #1=1\nGOTO 1\n", &fanuc()).unwrap_err();
    assert!(e.message.contains("iterations"), "{e}");
    // Loops are per program: a subprogram's loop left by a GOTO and M99 is not the caller's,
    // and a GOTO goes to the N number of the program it is in (subprograms reuse them).
    let src = "O1\nG21\n#1=0\nWHILE [#1 LT 2] DO1\nM98 P100\n#1=#1+1\nEND1\nN10 G0 X99\nM30\n\
               O100\n#2=0\nWHILE [#2 LT 5] DO1\n#2=#2+1\nIF [#2 EQ 2] GOTO 10\nEND1\nN10 G0 Z#2\nM99\n";
    let got = moves(src, &fanuc()).unwrap();
    assert_eq!(
        got,
        [
            ('R', 0.0, 0.0, 2.0),
            ('R', 0.0, 0.0, 2.0),
            ('R', 99.0, 0.0, 2.0)
        ]
    );
    // FIX truncates towards zero and FUP away from it, as a Fanuc control does.
    let got = moves(
        "O1\nG21\nG0 X[FIX[-1.5]] Y[FUP[-1.2]] Z[FUP[1.2]]\nM30\n",
        &fanuc(),
    )
    .unwrap();
    assert_eq!(got, [('R', -1.0, -2.0, 2.0)]);
    // A program that says nothing else is read by Fanuc's rules when it has Macro B flow.
    assert_eq!(
        GcodeDialect::detect("G21\n#1=0\nWHILE [#1 LT 3] DO1\n#1=#1+1\nEND1\n"),
        GcodeDialect::Fanuc
    );
    // Under LinuxCNC's rules an unbracketed expression is still an error.
    let linuxcnc = GcodeOptions::default().with_dialect(GcodeDialect::LinuxCnc);
    assert!(moves("G21\n#1=#1+1\n", &linuxcnc).is_err());
}

/// The dwells as the reader hands them on, seconds.
fn dwells(src: &str, options: &GcodeOptions) -> Vec<f64> {
    let mut rec = Recorder::default();
    read_gcode(src, "fanuc.nc", options, &mut rec).unwrap_or_else(|e| panic!("{e}"));
    rec.events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::Dwell(s) => Some(*s),
            _ => None,
        })
        .collect()
}

#[test]
fn g04_x_is_a_dwell_and_p_without_a_point_counts_milliseconds() {
    // Fanuc: `G04 X1.5` dwells 1.5 s (X is the time, not an axis: nothing moves); `G04 P500`
    // dwells 500 ms (P takes no decimal point); Haas reads `G04 P0.5` as seconds.
    let src = "O1\nG21 G90 G0 X10. Y10. Z5.\nG04 X1.5\nG04 P500\nG4 P0.5\nG1 X20. F100.\nM30\n";
    let m = moves(src, &fanuc()).unwrap();
    assert_eq!(m, [('R', 10.0, 10.0, 5.0), ('L', 20.0, 10.0, 5.0)]);
    assert_eq!(dwells(src, &fanuc()), [1.5, 0.5, 0.5]);
    // LinuxCNC: P in seconds, whatever its form.
    let linuxcnc = GcodeOptions::default().with_dialect(GcodeDialect::LinuxCnc);
    assert_eq!(dwells("G4 P2\nG4 P0.5\nM2\n", &linuxcnc), [2.0, 0.5]);
}

#[test]
fn canned_cycle_dwell_p_without_a_point_counts_milliseconds() {
    // Fanuc: `G82 … P500` dwells 500 ms at the bottom, as `G04 P500` does (it dwelt 500 s);
    // the P stays for the next holes; `P0.5` is seconds (Haas).
    let src = "O1\nG21 G90 G0 X0 Y0 Z10.\nG82 X5. Y5. Z-2. R2. P500 F100.\nX10.\nG80\nG89 X15. Z-2. R2. P0.5\nG80\nM30\n";
    assert_eq!(dwells(src, &fanuc()), [0.5, 0.5, 0.5]);
    // LinuxCNC: P in seconds.
    let linuxcnc = GcodeOptions::default().with_dialect(GcodeDialect::LinuxCnc);
    let src = "G21 G90 G0 X0 Y0 Z10\nG82 X5 Y5 Z-2 R2 P2 F100\nG80\n";
    assert_eq!(dwells(src, &linuxcnc), [2.0]);
}

#[test]
fn g00_beside_g28_is_modal_and_g28_takes_the_axes() {
    // `G00 G91 G28 Z0.`: the reference return moves; G00 is the motion of the next blocks.
    let src = "O1\nG21 G90 G1 X10. Y10. Z5. F100.\nG00 G91 G28 Z0.\nG90 X20.\nM30\n";
    let m = moves(src, &fanuc().with_home([0.0, 0.0, 300.0])).unwrap();
    assert_eq!(
        m,
        [
            ('L', 10.0, 10.0, 5.0),
            ('R', 10.0, 10.0, 5.0),
            ('R', 10.0, 10.0, 300.0),
            ('R', 20.0, 10.0, 300.0),
        ]
    );
    // LinuxCNC refuses it: G0 and G28 both want the axis words.
    let linuxcnc = GcodeOptions::default().with_dialect(GcodeDialect::LinuxCnc);
    let e = moves(&src.replace("O1\n", ""), &linuxcnc).unwrap_err();
    assert!(e.message.contains("both want the axis words"), "{e}");
}

#[test]
fn g53_positions_are_measured_from_the_home() {
    // Fusion's Haas NGC post retracts with `G53 G0 Z0.` (machine zero: the home); without a
    // home given it goes to the work's Z0 and says so, once.
    let src = "%\nO1\nG21 G90 G0 X10. Y10.\nG1 Z-1. F100.\nG53 G0 Z0.\nG0 X20.\nG53 Z-5.\nM30\n%\n";
    let m = moves(src, &fanuc().with_home([0.0, 0.0, 300.0])).unwrap();
    assert_eq!(m[2], ('R', 10.0, 10.0, 300.0));
    assert_eq!(m[3], ('R', 20.0, 10.0, 300.0));
    assert_eq!(m[4], ('R', 20.0, 10.0, 295.0));
    let m = moves(src, &fanuc()).unwrap();
    assert_eq!(m[2], ('R', 10.0, 10.0, 0.0));
    // The home is G53's zero for the whole run, whatever offsets the program sets: with a work
    // origin at Z-100 in the frame the home is given in, G53 Z0. is the home, 400 mm above the
    // work; with no home given, the frame's origin, 100 mm above.
    let own = "O1\nG21 G90\nG10 L2 P1 Z-100.\nG54 G0 X0 Y0\nG53 G0 Z0.\nM30\n";
    let m = moves(own, &fanuc().with_home([0.0, 0.0, 300.0])).unwrap();
    assert_eq!(m.last(), Some(&('R', 0.0, 0.0, 400.0)));
    let m = moves(own, &fanuc()).unwrap();
    assert_eq!(m.last(), Some(&('R', 0.0, 0.0, 100.0)));
    let w = warnings(src);
    let g53: Vec<_> = w.iter().filter(|(_, m)| m.contains("G53")).collect();
    assert_eq!(g53.len(), 1, "{w:?}");
    assert_eq!(g53[0].0, 5);
    assert!(g53[0].1.contains("--home"), "{w:?}");
}

#[test]
fn g53_keeps_the_home_as_its_zero_after_g92_and_work_offsets() {
    // G92 moves the work's zero, not the machine's: the second `G53 G0 Z0.` goes back to the
    // home where the first went, which G92 Z0 has just called Z0 (it went 300 mm below, to
    // program Z-300, when the home counted only while no offset was set).
    let home = fanuc().with_home([0.0, 0.0, 300.0]);
    let src = "O1\nG21 G90\nG53 G0 Z0.\nG92 Z0\nG53 G0 Z0.\nM30\n";
    let m = moves(src, &home).unwrap();
    assert_eq!(m, [('R', 0.0, 0.0, 300.0), ('R', 0.0, 0.0, 0.0)]);
    // A work offset chosen after a G53 move: G53 Z-5. is 5 mm below the home either way (the
    // work's Z0 at Z-50 of the home's frame puts it at program Z345).
    let src = "O1\nG21 G90\nG53 G0 Z-5.\nG10 L2 P2 Z-50.\nG55\nG53 G0 Z-5.\nM30\n";
    let m = moves(src, &home).unwrap();
    assert_eq!(m, [('R', 0.0, 0.0, 295.0), ('R', 0.0, 0.0, 345.0)]);
    // The machine position (#5023) reads in the same G53 coordinates.
    let linuxcnc = GcodeOptions::default()
        .with_dialect(GcodeDialect::LinuxCnc)
        .with_home([0.0, 0.0, 300.0]);
    let m = moves("G21 G90\nG53 G0 Z-5.\nG0 Z[#5023]\n", &linuxcnc).unwrap();
    assert_eq!(m.last(), Some(&('R', 0.0, 0.0, -5.0)));
}

#[test]
fn haas_tcpc_and_dynamic_work_offset_are_read() {
    // G234 is Haas's tool centre point control (as G43.4: on until G49, with no warning, see
    // tool_centre_point.rs); G254/G255 switch the dynamic work offset (left out, with a
    // warning saying how X Y Z are read).
    let src = "O1\nG21 G90 G0 A30. X0 Y0 Z50.\nG254\nG234 H1 Z20.\nG1 X10. F100.\nG49\nG255\nM30\n";
    let m = moves(src, &fanuc()).unwrap();
    assert_eq!(m.last(), Some(&('L', 10.0, 0.0, 20.0)));
    let w = warnings(src);
    assert!(!w.iter().any(|(_, m)| m.starts_with("G234")), "{w:?}");
    assert!(
        w.iter().any(|(l, m)| *l == 3 && m.contains("G254")),
        "{w:?}"
    );
    assert!(
        w.iter().any(|(l, m)| *l == 7 && m.contains("G255")),
        "{w:?}"
    );
    // Fusion's Haas 4-axis posts unclamp and clamp the rotary around its moves.
    let w = warnings("O1\nG21 G90\nM11\nG0 X1.\nM10\nM29 S500\nM30\n");
    let named: Vec<_> = w
        .iter()
        .map(|(l, m)| (*l, m.split(" ignored").next().unwrap_or("")))
        .collect();
    assert_eq!(
        named,
        [
            (3, "M11 (rotary axis brake unclamp)"),
            (5, "M10 (rotary axis brake clamp)"),
            (6, "M29 (rigid tapping mode)")
        ]
    );
    // Not in LinuxCNC.
    let linuxcnc = GcodeOptions::default().with_dialect(GcodeDialect::LinuxCnc);
    let e = moves("G234 H1 Z20.\n", &linuxcnc).unwrap_err();
    assert!(e.message.contains("unknown G code G234"), "{e}");
}

#[test]
fn macro_calls_are_refused_by_name() {
    // A Renishaw probing cycle: its moves are in the macro, which is not in the program.
    let e = moves("O1\nG21\nG65 P9810 X10. Y10. F1000.\nM30\n", &fanuc()).unwrap_err();
    assert_eq!(e.kind, swarf_path::PathErrorKind::Unsupported);
    assert!(e.message.starts_with("G65: custom macro"), "{e}");
    assert_eq!((e.pos.line, e.pos.column), (3, 1));
}

/// M99 in the main program runs it again from the top (FANUC 0i-MF "Subprogram call": "when
/// M99 is executed in a main program, control returns to the start of the main program";
/// LinuxCNC likewise), with the parameters kept — so a counter can end it with M30.
#[test]
fn m99_in_the_main_program_runs_it_again_until_m30() {
    let src =
        "%\nO1\n#100=#100+1\nIF [#100 GT 3] GOTO 9\nG0 X#100 Y0 Z1\nG1 Z0 F100\nM99\nN9 M30\n%\n";
    let m = moves(src, &fanuc()).unwrap();
    let want: Vec<(char, f64, f64, f64)> = (1..=3)
        .flat_map(|i| [('R', i as f64, 0.0, 1.0), ('L', i as f64, 0.0, 0.0)])
        .collect();
    assert_eq!(m, want);
    // (The program states no units, and Z1 has no decimal point: lines 5.)
    let w = warnings(src);
    assert_eq!(w.len(), 3, "{w:?}");
    assert!(w[2].1.contains("run again from the top"), "{w:?}");
    // The same with LinuxCNC's O-words.
    let src = "o1 if [#1 GE 2]\nM2\no1 endif\n#1 = [#1 + 1]\nG0 X#1\nM99\n";
    let lcnc = GcodeOptions::default().with_dialect(GcodeDialect::LinuxCnc);
    assert_eq!(
        moves(src, &lcnc).unwrap(),
        [('R', 1.0, 0.0, 0.0), ('R', 2.0, 0.0, 0.0)]
    );
}

/// A main program that cannot end (no M2/M30 in any file it reads: a bar feeder's loop), or
/// whose pass changed no parameter, position or offset (so that the next pass starts as it
/// did), would repeat for ever: reading ends at its M99 with a warning. The first pass of the
/// third starts at the home and ends at X1, so a second runs before the loop is seen.
#[test]
fn an_endless_main_program_loop_is_read_once() {
    for (src, moves_read, why) in [
        (
            "G0 X1 Y0 Z1\nG1 Z0 F100\nM99\n",
            2,
            "no file it reads has an M2/M30",
        ),
        (
            "#1=#1+1\nG0 X#1\nM99\n",
            1,
            "no file it reads has an M2/M30",
        ),
        (
            "IF [#1 GT 5] GOTO 9\nG0 X1\nM99\nN9 M30\n",
            2,
            "changed no parameter, position, offset, tool or mode",
        ),
    ] {
        let m = moves(src, &fanuc()).unwrap();
        assert_eq!(m.len(), moves_read, "{src}");
        let w = warnings(src);
        assert!(
            w.iter()
                .any(|(_, t)| t.contains(why) && t.contains("reading ends here")),
            "{src}: {w:?}"
        );
    }
    // Incremental moves change the position every pass: a test of #5420 ends the loop, as
    // a control runs it (X10, X20, X30, X40, then M30).
    let src = "G91\nG1 X10 F100\nIF [#5420 GT 35] GOTO 9\nM99\nN9 M30\n";
    assert_eq!(moves(src, &fanuc()).unwrap().len(), 4);
    // An offset moved each pass likewise (G10 L2 P1: #5221), and M99 P10 goes back to N10.
    let src = "#100=0\nN10 #100=#100+1\nG10 L2 P1 X[#5221+20]\nG0 X0\n\
               IF [#5221 GT 50] GOTO 99\nM99 P10\nN99 M30\n";
    assert_eq!(moves(src, &fanuc()).unwrap().len(), 3);
    // M99 P in a subprogram (back to the caller's N<P>) is refused at its P, not ignored.
    let e = moves("M98 P100\nM30\nO100\nG0 X1\nM99 P5\n", &fanuc()).unwrap_err();
    assert_eq!((e.pos.line, e.pos.column), (5, 5), "{e}");
}

/// A pass that wrote a parameter it then found unchanged counts as no change: `#1=5` runs
/// twice (0 → 5, then 5 → 5; the position, at X5 after the first, stays), `#2=#2+0` changes
/// nothing. An O-word call's arguments (#1–#30, put back on return) are not the pass's.
#[test]
fn a_pass_that_rewrites_a_parameter_to_its_value_ends_the_loop() {
    let src = "#1=5\nG0 X#1 Y#2\n#2=#2+0\nM99\nM30\n";
    assert_eq!(
        moves(src, &fanuc()).unwrap(),
        [('R', 5.0, 0.0, 0.0), ('R', 5.0, 0.0, 0.0)]
    );
    let w = warnings(src);
    assert!(
        w.iter()
            .any(|(l, t)| *l == 4 && t.contains("changed no parameter")),
        "{w:?}"
    );
    let lcnc = GcodeOptions::default().with_dialect(GcodeDialect::LinuxCnc);
    let src = "o100 sub\n#1 = [#1 + 1]\no100 endsub\nG0 X1\no100 call [5]\n\
               o1 if [#2 GT 0]\nM30\no1 endif\nM99\n";
    assert_eq!(moves(src, &lcnc).unwrap().len(), 2);
}

/// A counter that never reaches its M30 restarts until the reader's iteration limit ends it
/// with an error at the M99 (each restart counts as an iteration).
#[test]
fn a_main_program_loop_that_never_ends_meets_the_iteration_limit() {
    let opts = fanuc().with_max_loop_iterations(1000);
    let e = moves("#1=#1+1\nIF [#1 LT 0] GOTO 9\nM99\nN9 M30\n", &opts).unwrap_err();
    assert_eq!(e.pos.line, 3, "{e}");
    assert!(e.message.contains("more than 1000"), "{e}");
}

/// Fanuc writes a thread's lead as F (`G33 Z-10. F1.5`: 1.5 mm a revolution at S500, 15 mm in
/// 0.02 min).
#[test]
fn fanuc_g33_takes_its_lead_from_f() {
    use swarf_path::load::read_program_str;
    use swarf_path::summary::summarize;
    let src = "G21 G90\nS500 M3\nG0 X0 Y0 Z5\nG33 Z-10. F1.5\nM30\n";
    let p = read_program_str(
        src,
        "t.nc",
        Machine::three_axis(),
        &ReadOptions {
            gcode: fanuc(),
            ..ReadOptions::default()
        },
    )
    .unwrap();
    assert_eq!(p.moves.len(), 2);
    let t = summarize(&p).machining_time_s;
    assert!((t - 1.2).abs() < 1e-9, "{t}");
}

/// A pass may change only what the control keeps, and the next pass read it: the tool loaded
/// (#5400), a stored parameter from #5000 on (#5500), the feed (#<_feed>). Each runs until its
/// M30 (three passes), not one pass more or less. A name holding "m2" is no M2, so a counter
/// `#<_sum2>` with no M2/M30 anywhere ends at its M99 with the warning.
#[test]
fn a_pass_that_changes_only_control_state_runs_again() {
    let lcnc = GcodeOptions::default().with_dialect(GcodeDialect::LinuxCnc);
    for src in [
        "o1 if [#5400 EQ 3]\nM30\no1 endif\nT[#5400+1] M6\nG0 X1\nM99\n",
        "#5500=[#5500+1]\no1 if [#5500 GT 3]\nM30\no1 endif\nG0 X1\nM99\n",
        "o1 if [#<_feed> GT 250]\nM30\no1 endif\nF[#<_feed>+100]\nG1 X1\nM99\n",
    ] {
        // Three passes: the first moves from the home to X1, the next two stay there.
        assert_eq!(moves(src, &lcnc).unwrap().len(), 3, "{src}");
    }
    let src =
        "o2 if [EXISTS[#<_sum2>] EQ 0]\n#<_sum2>=0\no2 endif\n#<_sum2>=[#<_sum2>+1]\nG0 X1\nM99\n";
    assert_eq!(moves(src, &lcnc).unwrap().len(), 1);
    // Fanuc's M99 P looks for N<P> in the main program only, not in a subprogram after it.
    let e = moves(
        "O1000\nN1 G0 X1\nM98 P2000\nM99 P5\nM30\nO2000\nN5 G0 Y1\nM99\n",
        &fanuc(),
    )
    .unwrap_err();
    assert!(
        e.message
            .contains("no line numbered N5 in the main program"),
        "{e}"
    );
}

/// The moves (as [`moves`]) and the warnings (line, column, message) of a program read with
/// `options`.
#[allow(clippy::type_complexity)]
fn read_with(
    src: &str,
    options: &GcodeOptions,
) -> (Vec<(char, f64, f64, f64)>, Vec<(u32, u32, String)>) {
    let (rec, w) = recorded(src, options);
    let m = rec
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::Traverse { end } => Some(('R', end.x, end.y, end.z)),
            Canon::Feed { end } => Some(('L', end.x, end.y, end.z)),
            Canon::Arc { end, .. } => Some(('A', end.x, end.y, end.z)),
            _ => None,
        })
        .collect();
    (m, w)
}

/// The recorded events of a program read with `options`, and its warnings (line, column,
/// message).
fn recorded(src: &str, options: &GcodeOptions) -> (Recorder, Vec<(u32, u32, String)>) {
    let mut rec = Recorder::default();
    read_gcode(src, "fanuc.nc", options, &mut rec).unwrap_or_else(|e| panic!("{e}"));
    let w = std::mem::take(&mut rec.warnings)
        .into_iter()
        .map(|w| (w.line, w.column, w.message))
        .collect();
    (rec, w)
}

/// FANUC 0i-MF "Canned cycle", "Initial level and point R level": the initial level is the Z
/// where the cycle mode starts (its first block after G80 or a G00–G03 cancel) and it stays
/// until the cancel, so G98 returns to it after G99 holes; in G91, R is measured from the
/// initial level and Z from R, for every hole. LinuxCNC 2.9 keeps an initial level too
/// (`cycle_il`), but reaches each G98 hole at it (rs274's calls, written in below).
#[test]
fn canned_cycles_keep_the_initial_level_until_they_are_cancelled() {
    let src = "%\nO0001\nG0 X0. Y0. Z50.\nG43 H1 Z20.\nG99 G81 X10. Y10. Z-5. R2. F100.\nX20.\n\
               G98 Y20.\nG80\nM30\n%\n";
    let mut want = vec![
        ('R', 0.0, 0.0, 50.0),
        ('R', 0.0, 0.0, 20.0),
        // The first hole from the initial level Z20, back to R (G99).
        ('R', 10.0, 10.0, 20.0),
        ('R', 10.0, 10.0, 2.0),
        ('L', 10.0, 10.0, -5.0),
        ('R', 10.0, 10.0, 2.0),
        // The second at the R level.
        ('R', 20.0, 10.0, 2.0),
        ('L', 20.0, 10.0, -5.0),
        ('R', 20.0, 10.0, 2.0),
        // The third (G98) back to the initial level, Z20, not Z2.
        ('R', 20.0, 20.0, 2.0),
        ('L', 20.0, 20.0, -5.0),
        ('R', 20.0, 20.0, 20.0),
    ];
    assert_eq!(moves(src, &GcodeOptions::default()).unwrap(), want);
    // LinuxCNC 2.9 (rs274): the G98 hole is reached at the initial level Z20, from the R
    // level of the G99 hole, and the tool goes down to R there.
    let linuxcnc = GcodeOptions::default().with_dialect(GcodeDialect::LinuxCnc);
    let lcnc_src = src.replace("%\nO0001\n", "").replace("%\n", "");
    want.splice(9..10, [('R', 20.0, 20.0, 20.0), ('R', 20.0, 20.0, 2.0)]);
    assert_eq!(moves(&lcnc_src, &linuxcnc).unwrap(), want);

    // G91: R-18. from the initial level Z20 is Z2, Z-7. from R is Z-5 — for the second hole
    // too, although the tool waits at Z2.
    let src = "%\nO0001\nG0 X0. Y0. Z20.\nG91 G99 G81 X10. Y0. Z-7. R-18. F100.\nX10.\n\
               G90 G80 G0 Z50.\nM30\n%\n";
    assert_eq!(
        moves(src, &GcodeOptions::default()).unwrap(),
        [
            ('R', 0.0, 0.0, 20.0),
            ('R', 10.0, 0.0, 20.0),
            ('R', 10.0, 0.0, 2.0),
            ('L', 10.0, 0.0, -5.0),
            ('R', 10.0, 0.0, 2.0),
            ('R', 20.0, 0.0, 2.0),
            ('L', 20.0, 0.0, -5.0),
            ('R', 20.0, 0.0, 2.0),
            ('R', 20.0, 0.0, 50.0),
        ]
    );
    // LinuxCNC 2.9 measures R from the initial level Z20 for the second hole too (rs274:
    // R at Z2, the bottom at Z-5; 2.7 measured from the block's Z2).
    let lcnc_src = "G0 X0 Y0 Z20\nG91 G99 G81 X10 Y0 Z-7 R-18 F100\nX10\nG80\nG90 G0 Z50\nM2\n";
    let m = moves(lcnc_src, &linuxcnc).unwrap();
    assert_eq!(m[5], ('R', 20.0, 0.0, 2.0), "{m:?}");
    assert_eq!(m[6], ('L', 20.0, 0.0, -5.0), "{m:?}");

    // A G0 cancels the cycle mode: the next cycle's initial level is where that leaves the
    // tool (Z30), not the first cycle's (Z20).
    let src =
        "%\nO0001\nG0 X0. Y0. Z20.\nG98 G81 X10. Z-5. R2. F100.\nG0 Z30.\nG99 G81 X20. Z-5. R2.\n\
               G98 X30.\nG80\nM30\n%\n";
    let m = moves(src, &GcodeOptions::default()).unwrap();
    assert_eq!(m[4], ('R', 10.0, 0.0, 20.0), "{m:?}");
    assert_eq!(m.last(), Some(&('R', 30.0, 0.0, 30.0)), "{m:?}");
}

/// FANUC 0i-MF "Additional workpiece coordinate systems (G54.1 or G54)": `G10 L20 Pn X Y Z`
/// sets additional offset n (absolute values, as G10 L2 for G54–G59), `G54.1 Pn` — also
/// written `G54 Pn`, and Haas's `G154 Pn` — selects it; G54 keeps its own offset. An
/// additional offset the program never set is reported and the current offset stays.
#[test]
fn g10_l20_sets_the_additional_work_offsets_that_g54_1_selects() {
    let src = "%\nO0001\nG21 G90\nG10 L2 P1 X5.\nG10 L20 P1 X100. Y50. Z-10.\nG10 L20 P7 X-20.\n\
               G54 G0 X0. Y0. Z0.\nG54.1 P1 X0. Y0. Z0.\nG54 X1.\nG54 P7 X0.\nG154 P1 X0. Y0.\n\
               G54.1 P2 X10.\nM30\n%\n";
    let p = read_program_str(src, "f.nc", Machine::three_axis(), &ReadOptions::default()).unwrap();
    let tips: Vec<[f64; 3]> = p
        .moves
        .iter()
        .map(|m| [m.end.tip.x, m.end.tip.y, m.end.tip.z])
        .collect();
    assert_eq!(
        tips,
        [
            [5.0, 0.0, 0.0],
            [100.0, 50.0, -10.0],
            [6.0, 50.0, -10.0],
            [-20.0, 50.0, -10.0],
            [100.0, 50.0, -10.0],
            [110.0, 50.0, -10.0],
        ]
    );
    let w: Vec<_> = p
        .warnings
        .iter()
        .filter(|w| w.message.contains("G54.1") || w.message.contains("G154"))
        .collect();
    assert_eq!(w.len(), 1, "{:?}", p.warnings);
    assert_eq!(w[0].line, 12, "{:?}", w);
    assert_eq!(
        w[0].message,
        "G54.1 P2 (additional work offset 2) ignored: its values are not in the program (no \
         G10 L20 P2 before it), so the current work offset stays"
    );
    // P beyond the 300 offsets a control has.
    let e = moves("O1\nG21\nG10 L20 P301 X0.\nM30\n", &fanuc()).unwrap_err();
    assert_eq!((e.pos.line, e.pos.column), (3, 9), "{e}");
}

/// FANUC 0i-MF "Machine coordinate system selection (G53)": G53 positions at rapid whatever
/// the modal motion, which stays for the next block. LinuxCNC moves G53 with G0 or G1.
#[test]
fn g53_is_a_rapid_whatever_the_modal_motion() {
    let src = "%\nO0001\nG21 G90\nG0 X10. Y10. Z5.\nG1 Z-1. F100.\nG53 Z0.\nX20.\nM30\n%\n";
    assert_eq!(
        moves(src, &GcodeOptions::default()).unwrap(),
        [
            ('R', 10.0, 10.0, 5.0),
            ('L', 10.0, 10.0, -1.0),
            ('R', 10.0, 10.0, 0.0),
            ('L', 20.0, 10.0, 0.0),
        ]
    );
    let src =
        "%\nO0001\nG21 G90\nG0 X0. Y0. Z5.\nG2 X10. Y0. R5. F100.\nG53 Z0.\nX0. Y0. R5.\nM30\n%\n";
    assert_eq!(
        moves(src, &GcodeOptions::default()).unwrap(),
        [
            ('R', 0.0, 0.0, 5.0),
            ('A', 10.0, 0.0, 5.0),
            ('R', 10.0, 0.0, 0.0),
            ('A', 0.0, 0.0, 0.0),
        ]
    );
    let linuxcnc = GcodeOptions::default().with_dialect(GcodeDialect::LinuxCnc);
    let m = moves(
        "G21 G90\nG0 X10 Y10 Z5\nG1 Z-1 F100\nG53 Z0\nM2\n",
        &linuxcnc,
    )
    .unwrap();
    assert_eq!(m.last(), Some(&('L', 10.0, 10.0, 0.0)));
    let e = moves(
        "G21 G90\nG0 X0 Y0 Z5\nG2 X10 Y0 R5 F100\nG53 Z0\nM2\n",
        &linuxcnc,
    )
    .unwrap_err();
    assert!(e.message.contains("G53 needs G0 or G1"), "{e}");
}

/// The cancel codes of a Fanuc safe-start line (polar coordinates G15, programmable mirror
/// image G50.1, modal macro call G67) cancel modes swarf never lets on: read past, G50.1's
/// axis words with it (they name the axes, they move nothing). The codes that would turn the
/// modes on stay refused.
#[test]
fn safe_start_cancel_codes_are_read_past() {
    let src = "%\nO0001\nG15 G17 G21 G40 G49 G50 G50.1 G67 G69 G80 G90 G94\nG50.1 X0. Y0.\n\
               G0 X10. Y10. Z5.\nG67\nG15\nM30\n%\n";
    let (m, w) = read_with(src, &GcodeOptions::default());
    assert_eq!(m, [('R', 10.0, 10.0, 5.0)]);
    for code in ["G15", "G50.1", "G67"] {
        let n = w.iter().filter(|(_, _, t)| t.contains(code)).count();
        assert!(n <= 1, "{code}: {w:?}");
    }
    for bad in ["G51.1 X0.", "G16", "G66 P9000"] {
        let e = moves(&format!("O1\nG21\n{bad}\nM30\n"), &fanuc()).unwrap_err();
        assert_eq!(e.pos.line, 3, "{bad}: {e}");
    }
}

/// Fanuc's ATAN gives 0° to 360° (parameter NAT = 0, the default) and the 30i's `ATAN[a,b]`
/// means `ATAN[a]/[b]`; LinuxCNC's gives −180° to 180°.
#[test]
fn fanuc_atan_is_0_to_360_and_takes_a_comma() {
    let src = "%\nO0001\nG21\n#9=ATAN[-1]/[-1]\n#10=ATAN[1,-1]\n#11=ATAN[-1,1]\nG0 X#9 Y#10 Z#11\nM30\n%\n";
    let m = moves(src, &GcodeOptions::default()).unwrap();
    assert_eq!(m.len(), 1);
    let (x, y, z) = (m[0].1, m[0].2, m[0].3);
    assert!((x - 225.0).abs() < 1e-9, "{m:?}");
    assert!((y - 135.0).abs() < 1e-9, "{m:?}");
    assert!((z - 315.0).abs() < 1e-9, "{m:?}");
    let linuxcnc = GcodeOptions::default().with_dialect(GcodeDialect::LinuxCnc);
    let m = moves("G21\n#9=[ATAN[-1]/[-1]]\nG0 X#9\nM2\n", &linuxcnc).unwrap();
    assert!((m[0].1 + 135.0).abs() < 1e-9, "{m:?}");
    assert!(moves("G21\n#9=[ATAN[1,-1]]\nM2\n", &linuxcnc).is_err());
}

/// More Fanuc habits decide the dialect: G05.1 Q, G43.4/G43.5, G54.1, G154, a dwell P in
/// milliseconds (no decimal point, 100 or more: 100 s and more would be an odd LinuxCNC
/// dwell, while `G4 P1` is an ordinary one); under LinuxCNC's rules the codes that are
/// Fanuc's say how to read them.
#[test]
fn more_fanuc_habits_decide_the_dialect() {
    for src in [
        "G0 X0\nG05.1 Q1\n",
        "G43.4 H1\n",
        "G43.5 H1\n",
        "G54.1 P1\n",
        "G154 P2\n",
        "G04 P500\n",
        "G82 X1. Y1. Z-1. R1. P250 F100.\n",
    ] {
        assert_eq!(GcodeDialect::detect(src), GcodeDialect::Fanuc, "{src}");
    }
    for src in [
        "G4 P1\n",
        "G4 P0.5\n",
        "G4 P2000.\n",
        "G04 P500\no<x> sub\no<x> endsub\n",
        "G5.1 X1 Y1 I1 J0\n",
    ] {
        assert_eq!(GcodeDialect::detect(src), GcodeDialect::LinuxCnc, "{src}");
    }
    let linuxcnc = GcodeOptions::default().with_dialect(GcodeDialect::LinuxCnc);
    for src in [
        "G43.4 H1 Z50.\n",
        "G43.5 H1 Z50.\n",
        "G54.1 P1\n",
        "G05.1 Q1\n",
    ] {
        let e = moves(&format!("G21 G90\n{src}M2\n"), &linuxcnc).unwrap_err();
        assert!(e.message.contains("--dialect fanuc"), "{src}: {e}");
        assert_eq!(e.pos.line, 2, "{e}");
    }
}

/// A Fanuc control set for least-increment input (DPI = 0, its default) reads `X1000` as
/// 1.000 mm; swarf reads 1000 mm, as a control set for calculator-type input does. The first
/// such word is reported once, with both readings.
#[test]
fn a_number_without_a_decimal_point_is_reported_once() {
    let src = "%\nO0001\nG21 G90\nG0 X0 Y0\nG04 P500\nG0 X1000 Y2000\nG1 X-5 F100\nM30\n%\n";
    let (m, w) = read_with(src, &GcodeOptions::default());
    assert_eq!(m[1], ('R', 1000.0, 2000.0, 0.0));
    let dp: Vec<_> = w
        .iter()
        .filter(|(_, _, t)| t.contains("decimal point"))
        .collect();
    assert_eq!(
        dp,
        [&(
            6,
            4,
            "X1000 has no decimal point: read as 1000 mm (calculator-type input); a Fanuc \
             control set for least-increment input (DPI=0) reads 1.000 mm — check the program"
                .to_string()
        )],
        "{w:?}"
    );
    // Inch (least increment 0.0001 in) and degrees (0.001°).
    let (_, w) = read_with("O1\nG20 G90\nG0 Y-25\nM30\n", &fanuc());
    assert!(
        w.iter().any(|(l, _, t)| *l == 3
            && t.starts_with("Y-25 has no decimal point: read as -25 in")
            && t.contains("reads -0.0025 in")),
        "{w:?}"
    );
    let (_, w) = read_with("O1\nG21 G90\nG0 A90\nM30\n", &fanuc());
    assert!(
        w.iter().any(
            |(_, _, t)| t.starts_with("A90 has no decimal point: read as 90°")
                && t.contains("reads 0.090°")
        ),
        "{w:?}"
    );
    // Words that are no lengths or angles: a repeat count K, a mode's Q, a dwell.
    let src = "O1\nG21 G90\nG0 X0. Y0. Z10.\nG05.1 Q1\nG04 X2\nG98 G81 X5. Y0. Z-1. R1. K2 F100.\nG80\nM30\n";
    let (_, w) = read_with(src, &fanuc());
    assert!(
        w.iter().all(|(_, _, t)| !t.contains("decimal point")),
        "{w:?}"
    );
    // LinuxCNC reads numbers so by definition.
    let linuxcnc = GcodeOptions::default().with_dialect(GcodeDialect::LinuxCnc);
    let (_, w) = read_with("G21 G90\nG0 X1000\nM2\n", &linuxcnc);
    assert!(w.is_empty(), "{w:?}");
}

/// A program that moves without stating its units (G20/G21, or G70/G71 read as them) is read
/// in the initial units (`--initial-units`), which the first move's warning names.
#[test]
fn units_never_stated_are_reported_at_the_first_move() {
    let linuxcnc = GcodeOptions::default().with_dialect(GcodeDialect::LinuxCnc);
    let (_, w) = read_with("G90\nG0 X1 Y1\nG1 X2 F100\nM2\n", &linuxcnc);
    assert_eq!(w.len(), 1, "{w:?}");
    assert_eq!(w[0].0, 2, "{w:?}");
    assert!(
        w[0].2.contains("--initial-units") && w[0].2.contains("mm"),
        "{w:?}"
    );
    let inch = linuxcnc.clone().with_initial_units(swarf_path::Units::Inch);
    let (m, w) = read_with("G0 X1\nM2\n", &inch);
    assert_eq!(m, [('R', 25.4, 0.0, 0.0)]);
    assert!(
        w.len() == 1 && w[0].2.contains("inch") && w[0].2.contains("--initial-units"),
        "{w:?}"
    );
    let (_, w) = read_with(
        "%\nO0001\nG90\nG0 X1. Y1.\nM30\n%\n",
        &GcodeOptions::default(),
    );
    assert!(
        w.iter()
            .any(|(l, _, t)| *l == 4 && t.contains("--initial-units")),
        "{w:?}"
    );
    // Stated, or no motion: nothing to say.
    for (src, options) in [
        ("G21\nG0 X1\nM2\n", &linuxcnc),
        ("G70\nG0 X1.\nM2\n", &linuxcnc),
        ("G4 P1\nM2\n", &linuxcnc),
        ("O1\nG20\nG0 X1.\nM30\n", &fanuc()),
    ] {
        let (_, w) = read_with(src, options);
        assert!(
            w.iter().all(|(_, _, t)| !t.contains("--initial-units")),
            "{src}: {w:?}"
        );
    }
}

/// A `WHILE … DOm` whose `ENDm` never comes is an error at the WHILE (a control stops with
/// an alarm), and only DO1–DO3 exist.
#[test]
fn macro_b_loops_need_their_end_and_numbers_1_to_3() {
    let e = moves(
        "O1\nG21\n#1=0\nWHILE [#1 LT 3] DO1\n#1=#1+1\nM30\n",
        &fanuc(),
    )
    .unwrap_err();
    assert_eq!(e.pos.line, 4, "{e}");
    assert!(e.message.contains("END1"), "{e}");
    for src in [
        "O1\nG21\n#1=0\nWHILE [#1 LT 3] DO4\n#1=#1+1\nEND4\nM30\n",
        "O1\nG21\n#1=0\nWHILE [#1 LT 3] DO0\n#1=#1+1\nEND0\nM30\n",
    ] {
        let e = moves(src, &fanuc()).unwrap_err();
        assert_eq!(e.pos.line, 4, "{src}: {e}");
        assert!(e.message.contains("DO1"), "{e}");
    }
}

/// Custom Macro B vacant variables (Fanuc Custom Macro B manual, "Vacant variables"): `#0`
/// and the local and common variables never assigned are vacant. A word whose value is a
/// vacant variable is not written (`G90 X#1` is `G90`); in arithmetic a vacant variable is 0,
/// but a plain copy keeps it vacant; `EQ`/`NE` tell it from 0, `GE GT LE LT` take it as 0.
/// The reviewer's program: the G1 moves Y alone (X#110 is not written), and `#111=#0` reads.
#[test]
fn a_word_holding_a_vacant_variable_is_not_written() {
    let src = "%\nO0001\nG0 X10. Y10. Z5.\nG1 X#110 Y20. F100.\n#111=#0\nM30\n";
    let want = [('R', 10.0, 10.0, 5.0), ('L', 10.0, 20.0, 5.0)];
    assert_eq!(moves(src, &fanuc()).unwrap(), want);
    // Detected as a Fanuc program (`O0001`), it reads the same.
    assert_eq!(moves(src, &GcodeOptions::default()).unwrap(), want);
    // #111 is vacant after `#111=#0`: its X is not written either, while `#112=0` is 0.
    let src = "O0001\nG21 G90\nG0 X10. Y10. Z5.\n#111=#0\nG0 X#111 Z20.\n#112=0\nG0 X#112\nM30\n";
    assert_eq!(
        moves(src, &fanuc()).unwrap(),
        [
            ('R', 10.0, 10.0, 5.0),
            ('R', 10.0, 10.0, 20.0),
            ('R', 0.0, 10.0, 20.0)
        ]
    );
    // `G90 X#1` is `G90` (a G word holding a vacant variable is not written either: the
    // modal G0 moves), and `X[#1]` is an expression, whose vacant #1 is 0.
    let src = "O1\nG21\nG91 G0 X2.\nG90 X#1\nG#1 X3.\nG0 X[#1] Y#500\nM30\n";
    assert_eq!(
        moves(src, &fanuc()).unwrap(),
        [
            ('R', 2.0, 0.0, 0.0),
            ('R', 3.0, 0.0, 0.0),
            ('R', 0.0, 0.0, 0.0)
        ]
    );
}

#[test]
fn eq_and_ne_tell_a_vacant_variable_from_0() {
    // #1 never set: `#1 EQ #0` holds, the GOTO skips the X move.
    let src = "O1\nG21 G90\nIF [#1 EQ #0] GOTO 10\nG0 X1.\nN10 G0 Y1.\nM30\n";
    assert_eq!(moves(src, &fanuc()).unwrap(), [('R', 0.0, 1.0, 0.0)]);
    // After `#1=0` it does not.
    let src = "O1\nG21 G90\n#1=0\nIF [#1 EQ #0] GOTO 10\nG0 X1.\nN10 G0 Y1.\nM30\n";
    assert_eq!(
        moves(src, &fanuc()).unwrap(),
        [('R', 1.0, 0.0, 0.0), ('R', 1.0, 1.0, 0.0)]
    );
    // A vacant #1 is not EQ 0, and is NE 0.
    let src = "O1\nG21 G90\nIF [#1 EQ 0] GOTO 10\nG0 X1.\nN10 IF [#1 NE 0] GOTO 20\nG0 Y1.\n\
               N20 G0 Z1.\nM30\n";
    assert_eq!(
        moves(src, &fanuc()).unwrap(),
        [('R', 1.0, 0.0, 0.0), ('R', 1.0, 0.0, 1.0)]
    );
    // IF … THEN on a common variable: #101 is set only once #100 is no longer vacant, and
    // until then `X#101` is not written.
    let src = "O1\nG21 G90\nIF [#100 NE #0] THEN #101=5.\nG0 X#101 Y1.\n#100=0\n\
               IF [#100 NE #0] THEN #101=5.\nG0 X#101\nM30\n";
    assert_eq!(
        moves(src, &fanuc()).unwrap(),
        [('R', 0.0, 1.0, 0.0), ('R', 5.0, 1.0, 0.0)]
    );
    // A loop that runs while #1 is vacant and sets it: one pass.
    let src = "O1\nG21 G90\nWHILE [#1 EQ #0] DO1\nG0 X1.\n#1=2.\nEND1\nG0 Y#1\nM30\n";
    assert_eq!(
        moves(src, &fanuc()).unwrap(),
        [('R', 1.0, 0.0, 0.0), ('R', 1.0, 2.0, 0.0)]
    );
}

#[test]
fn ge_gt_le_lt_take_a_vacant_variable_as_0() {
    // Each IF that holds skips a move: #1 GE #0 (0 ≥ 0) and #0 LT 1 hold; #1 GT #0 (0 > 0) and
    // #1 LE -1 do not.
    let src = "O1\nG21 G90\nIF [#1 GE #0] GOTO 10\nG0 X1.\nN10 IF [#1 GT #0] GOTO 20\nG0 Y1.\n\
               N20 IF [#0 LT 1] GOTO 30\nG0 Z1.\nN30 IF [#1 LE -1] GOTO 40\nG0 X2.\nN40 M30\n";
    assert_eq!(
        moves(src, &fanuc()).unwrap(),
        [('R', 0.0, 1.0, 0.0), ('R', 2.0, 1.0, 0.0)]
    );
}

#[test]
fn a_copy_keeps_a_variable_vacant_and_arithmetic_makes_it_0() {
    // `#2=#1` leaves #2 vacant (its X is not written); `#2=#1+0` makes it 0 (X0).
    let src = "O1\nG21 G90\nG0 X5. Y5.\n#2=#1\nG1 X#2 Y7. F100.\n#2=#1+0\nG1 X#2 Y9.\nM30\n";
    assert_eq!(
        moves(src, &fanuc()).unwrap(),
        [
            ('R', 5.0, 5.0, 0.0),
            ('L', 5.0, 7.0, 0.0),
            ('L', 0.0, 9.0, 0.0)
        ]
    );
    // `#1*5` and `#1+#1` are 0 too; `#3=#0` is vacant.
    for value in ["#1*5", "#1+#1", "#0+0", "[#1]"] {
        let src = format!("O1\nG21 G90\nG0 X5.\n#2={value}\nG0 X#2\nM30\n");
        assert_eq!(
            moves(&src, &fanuc()).unwrap(),
            [('R', 5.0, 0.0, 0.0), ('R', 0.0, 0.0, 0.0)],
            "{value}"
        );
    }
    let src = "O1\nG21 G90\nG0 X5.\n#3=7\n#3=#0\nG0 X#3 Y1.\nM30\n";
    assert_eq!(
        moves(src, &fanuc()).unwrap(),
        [('R', 5.0, 0.0, 0.0), ('R', 5.0, 1.0, 0.0)]
    );
}

#[test]
fn assigning_to_0_is_an_error_at_its_place() {
    for (src, col) in [
        ("O1\nG21\n#0=1\nM30\n", 1),
        ("O1\nG21\nG0 X1. #0=1\nM30\n", 8),
        // `#[#1]` with #1 vacant is #0.
        ("O1\nG21\n#[#1]=1\nM30\n", 1),
        ("O1\nG21\nIF [1 EQ 1] THEN #0=1\nM30\n", 18),
    ] {
        let e = moves(src, &fanuc()).unwrap_err();
        assert_eq!(
            (e.pos.file.as_str(), e.pos.line, e.pos.column),
            ("fanuc.nc", 3, col),
            "{src}: {e}"
        );
        assert!(
            e.to_string().starts_with(&format!("fanuc.nc:3:{col}")),
            "{e}"
        );
        assert!(
            e.message.contains("#0") && e.message.contains("vacant"),
            "{e}"
        );
    }
    // LinuxCNC has no vacant variables: #0 is no parameter, and an unset one reads 0.
    let linuxcnc = GcodeOptions::default().with_dialect(GcodeDialect::LinuxCnc);
    for src in ["G21\n#0=1\nM2\n", "G21\nG0 X#0\nM2\n"] {
        let e = moves(src, &linuxcnc).unwrap_err();
        assert!(
            e.message.contains("parameter number 0 is out of range"),
            "{e}"
        );
    }
    assert_eq!(
        moves("G21\nG0 X5\nG0 X#1 Y#110\nM2\n", &linuxcnc).unwrap(),
        [('R', 5.0, 0.0, 0.0), ('R', 0.0, 0.0, 0.0)]
    );
}

/// Fanuc's (and Haas's) feed for a move that turns a rotary axis with linear ones: F applies
/// to √(ΔX² + ΔY² + ΔZ² + ΔA²), degrees counted as mm (FANUC 0i-MF, "Feedrate for
/// simultaneous linear and rotary axes"); LinuxCNC applies it to X Y Z alone. `G1 X10 A90
/// F100`: 0.1 min by LinuxCNC's rule, √8200/100 = 0.90554 min by Fanuc's.
#[test]
fn a_rotary_move_feeds_over_the_combined_distance() {
    use swarf_path::load::{read_program_str, ReadOptions};
    use swarf_path::Machine;
    let minutes = |src: &str, d: GcodeDialect| {
        let opts = ReadOptions {
            gcode: GcodeOptions::default().with_dialect(d),
            ..ReadOptions::default()
        };
        let p =
            read_program_str(src, "t.nc", Machine::from_name("4axis-a").unwrap(), &opts).unwrap();
        let m = p.moves.last().unwrap();
        m.feed_minutes(m.start.tip.distance(m.end.tip)).unwrap()
    };
    let src = "G21 G90 G94\nG0 X0 Y0 Z5 A0\nG1 X10 A90 F100\nM30\n";
    let fanuc = minutes(src, GcodeDialect::Fanuc);
    assert!((fanuc - 8200f64.sqrt() / 100.0).abs() < 1e-12, "{fanuc}");
    let linuxcnc = minutes(src, GcodeDialect::LinuxCnc);
    assert!((linuxcnc - 0.1).abs() < 1e-12, "{linuxcnc}");
    // A rotary move alone: both rules give the angle over F.
    let src = "G21 G90 G94\nG0 X0 Y0 Z5 A0\nG1 A90 F100\nM30\n";
    for d in [GcodeDialect::Fanuc, GcodeDialect::LinuxCnc] {
        assert!((minutes(src, d) - 0.9).abs() < 1e-12);
    }
}

/// Fanuc's combined feed in an inch program counts a degree as an inch (√(1² + 90²)/10 =
/// 9.0006 min for `G1 X1. A90. F10.` in G20), and under tool centre point control (G43.4) F is
/// the tip's speed, the rotary axes left out.
#[test]
fn the_combined_feed_counts_degrees_in_program_units_and_not_under_tcp() {
    use swarf_path::load::{read_program_str, ReadOptions};
    use swarf_path::Machine;
    let minutes = |src: &str, machine: &str| {
        let opts = ReadOptions {
            gcode: GcodeOptions::default().with_dialect(GcodeDialect::Fanuc),
            ..ReadOptions::default()
        };
        let p = read_program_str(src, "t.nc", Machine::from_name(machine).unwrap(), &opts).unwrap();
        let m = p.moves.last().unwrap();
        m.feed_minutes(m.start.tip.distance(m.end.tip)).unwrap()
    };
    let t = minutes(
        "G20 G90 G94\nG0 X0 Y0 Z1. A0\nG1 X1. A90. F10.\nM30\n",
        "4axis-a",
    );
    assert!((t - 8101f64.sqrt() / 10.0).abs() < 1e-12, "{t}");
    let t = minutes(
        "G21 G90 G94\nG0 X0 Y0 Z50. A0 C0\nG43.4 H1\nG1 X10. A90. F100.\nM30\n",
        "table-ac",
    );
    assert!((t - 0.1).abs() < 1e-9, "{t}");
}

/// An F word in the block that selects the units: a Fanuc control reads the whole block in the
/// units it selects (F10. with G20 is 10 in/min); LinuxCNC sets the feed first (rs274's order:
/// F at step 3, units at step 13), so there F10 is read in the units before — and says so.
#[test]
fn a_feed_beside_g20_is_read_in_the_blocks_units_by_fanuc() {
    let feed = |src: &str, o: &GcodeOptions| -> (Vec<f64>, Vec<(u32, u32, String)>) {
        let (rec, w) = recorded(src, o);
        let f = rec
            .events
            .iter()
            .filter_map(|(_, e)| match e {
                Canon::FeedRate(f) => Some(*f),
                _ => None,
            })
            .collect();
        (f, w)
    };
    let src = "O1\nG20 G90 F10.\nG1 X1.\nM30\n";
    let (f, w) = feed(src, &fanuc());
    assert_eq!(f, [254.0]);
    assert!(w.iter().all(|(_, _, m)| !m.contains("F read in")), "{w:?}");
    let linuxcnc = GcodeOptions::default().with_dialect(GcodeDialect::LinuxCnc);
    let (f, w) = feed("G21\nG20 G90 F10\nG1 X1\nM2\n", &linuxcnc);
    assert_eq!(f, [10.0]);
    let said: Vec<_> = w
        .iter()
        .filter(|(_, _, m)| m.contains("F read in"))
        .collect();
    assert_eq!(said.len(), 1, "{w:?}");
    assert_eq!((said[0].0, said[0].1), (2, 9), "{said:?}");
    // No word where the block's units are those already in force.
    let (_, w) = feed("G20\nG20 G90 F10\nG1 X1\nM2\n", &linuxcnc);
    assert!(w.iter().all(|(_, _, m)| !m.contains("F read in")), "{w:?}");
}
