//! Fanuc/Haas post-processor forms a reviewer ran swarf on, each with a small program whose
//! moves are written out from the control's rules (FANUC Series 0i-MF operator's manual:
//! "Tool compensation values (G10)" memory C, "Tapping cycle (G84)", "System variables",
//! "Subprogram call (M98)"; Haas mill operator's manual: G10, M98, 4th-axis drilling).

mod common;
use common::fanuc_warnings as warnings;
use swarf_path::canon::Recorder;
use swarf_path::gcode::{read_gcode, GcodeDialect, GcodeOptions};
use swarf_path::{Canon, PathError};

/// The moves as (`R` rapid / `L` feed, x, y, z, a).
fn moves(src: &str, options: &GcodeOptions) -> Result<Vec<(char, [f64; 4])>, PathError> {
    let mut rec = Recorder::default();
    read_gcode(src, "fanuc.nc", options, &mut rec)?;
    Ok(rec
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::Traverse { end } => Some(('R', [end.x, end.y, end.z, end.a])),
            Canon::Feed { end } => Some(('L', [end.x, end.y, end.z, end.a])),
            _ => None,
        })
        .collect())
}

fn fanuc() -> GcodeOptions {
    GcodeOptions::default().with_dialect(GcodeDialect::Fanuc)
}

fn close(got: &[(char, [f64; 4])], want: &[(char, [f64; 4])]) {
    assert_eq!(got.len(), want.len(), "{got:?}\n{want:?}");
    for (g, w) in got.iter().zip(want) {
        assert!(
            g.0 == w.0 && g.1.iter().zip(&w.1).all(|(a, b)| (a - b).abs() < 1e-9),
            "{got:?}\n{want:?}"
        );
    }
}

#[test]
fn g10_l10_sets_a_length_register_not_the_cutter_radius() {
    // Memory C: L10 is H1's geometry. D1 is not set, so G41 D1 leaves the path as written
    // (it was taken as a 120 mm radius: a gouging error, or a path 3 mm off with R3.).
    let src = "O1\nG21 G90 G17\nG10 L10 P1 R3.\nG00 X-20. Y-20. Z10.\nG01 Z-1. F100.\n\
               G41 D1 X0 Y-10.\nY20.\nG40 X30. Y40.\nM30\n";
    let got = moves(src, &fanuc()).unwrap();
    close(
        &got,
        &[
            ('R', [-20.0, -20.0, 10.0, 0.0]),
            ('L', [-20.0, -20.0, -1.0, 0.0]),
            ('L', [0.0, -10.0, -1.0, 0.0]),
            ('L', [0.0, 20.0, -1.0, 0.0]),
            ('L', [30.0, 40.0, -1.0, 0.0]),
        ],
    );
    // G43 H1 takes geometry plus wear (L11), in program units.
    let mut rec = Recorder::default();
    let src = "O1\nG20\nG10 L10 P1 R2.\nG10 L11 P1 R-0.1\nG43 H1 Z1.\nG10 L10 P2 R5.\n\
               G91 G10 L11 P2 R0.5\nG10 L11 P2 R0.5\nG90 G43 H2 Z1.\nM30\n";
    read_gcode(src, "fanuc.nc", &fanuc(), &mut rec).unwrap();
    let lengths: Vec<f64> = rec
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::ToolLengthOffset(l) => Some(*l),
            _ => None,
        })
        .collect();
    assert_eq!(lengths.len(), 2, "{lengths:?}");
    assert!((lengths[0] - 1.9 * 25.4).abs() < 1e-9, "{lengths:?}");
    assert!((lengths[1] - 6.0 * 25.4).abs() < 1e-9, "{lengths:?}");
}

#[test]
fn g10_l12_and_l13_set_the_d_register_geometry_plus_wear() {
    // D1 = 3 − 0.5: the tool runs 2.5 mm left of the line X0 (Y up): at X−2.5.
    let src = "O1\nG21 G90 G17\nG10 L12 P1 R3.\nG10 L13 P1 R-0.5\nG00 X-20. Y-20. Z10.\n\
               G01 Z-1. F100.\nG41 D1 X0 Y-10.\nY20.\nM30\n";
    let got = moves(src, &fanuc()).unwrap();
    let last = got.last().unwrap().1;
    assert!(
        (last[0] + 2.5).abs() < 1e-9 && (last[1] - 20.0).abs() < 1e-9,
        "{got:?}"
    );
    // LinuxCNC's G10 L10 still sets tool 1's radius (R3: the tool at X−3).
    let src = "G21 G90 G17\nG10 L10 P1 R3.\nG00 X-20. Y-20. Z10.\nG01 Z-1. F100.\n\
               G41 D1 X0 Y-10.\nY20.\nM2\n";
    let linuxcnc = GcodeOptions::default().with_dialect(GcodeDialect::LinuxCnc);
    let got = moves(src, &linuxcnc).unwrap();
    let last = got.last().unwrap().1;
    assert!((last[0] + 3.0).abs() < 1e-9, "{got:?}");
    // A G10 L number Fanuc has not is named with Fanuc's.
    let e = moves("O1\nG10 L14 P1 R3.\nM30\n", &fanuc()).unwrap_err();
    assert!(e.to_string().contains("L10 to L13"), "{e}");
}

#[test]
fn fanuc_taps_along_the_planes_drilling_axis_in_g18() {
    // G18: the drilling axis is Y. The tap feeds from R (Y2) to Y−10 and back to R.
    let src = "O1\nG21 G90 G18\nG00 X10. Y20. Z5. S500 M03\nG99 G84 X10. Z5. Y-10. R2. F500.\n\
               G80\nM30\n";
    let got = moves(src, &fanuc()).unwrap();
    close(
        &got,
        &[
            ('R', [10.0, 20.0, 5.0, 0.0]),
            ('R', [10.0, 20.0, 5.0, 0.0]),
            ('R', [10.0, 2.0, 5.0, 0.0]),
            ('L', [10.0, -10.0, 5.0, 0.0]),
            ('L', [10.0, 2.0, 5.0, 0.0]),
        ],
    );
    assert!(
        warnings(src).iter().all(|(_, m)| !m.contains("swaps")),
        "{:?}",
        warnings(src)
    );
}

#[test]
fn fanuc_g98_tapping_feeds_out_to_r_and_rapids_to_the_initial_level() {
    let src = "O1\nG21 G90 G17\nG00 X0 Y0 Z10. S500 M03\nG98 G84 X10. Y0. Z-10. R2. F625.\n\
               G80\nM30\n";
    let got = moves(src, &fanuc()).unwrap();
    close(
        &got,
        &[
            ('R', [0.0, 0.0, 10.0, 0.0]),
            ('R', [10.0, 0.0, 10.0, 0.0]),
            ('R', [10.0, 0.0, 2.0, 0.0]),
            ('L', [10.0, 0.0, -10.0, 0.0]),
            ('L', [10.0, 0.0, 2.0, 0.0]),
            ('R', [10.0, 0.0, 10.0, 0.0]),
        ],
    );
}

#[test]
fn fanuc_cycles_turn_the_rotary_axis_in_the_positioning_step() {
    let src = "O1\nG21 G90 G17\nG00 X0. Y0. A0. S1000 M03\nZ50.\nG98 G81 Z-5. R2. F100.\n\
               A90.\nG91 A45.\nG90 G80\nM30\n";
    let got = moves(src, &fanuc()).unwrap();
    close(
        &got,
        &[
            ('R', [0.0, 0.0, 0.0, 0.0]),
            ('R', [0.0, 0.0, 50.0, 0.0]),
            ('R', [0.0, 0.0, 50.0, 0.0]),
            ('R', [0.0, 0.0, 2.0, 0.0]),
            ('L', [0.0, 0.0, -5.0, 0.0]),
            ('R', [0.0, 0.0, 50.0, 0.0]),
            ('R', [0.0, 0.0, 50.0, 90.0]),
            ('R', [0.0, 0.0, 2.0, 90.0]),
            ('L', [0.0, 0.0, -5.0, 90.0]),
            ('R', [0.0, 0.0, 50.0, 90.0]),
            // G91: A turns by 45°, and R and Z count from the initial level (R2: 52, Z−5
            // below R: 47), Fanuc's incremental cycle.
            ('R', [0.0, 0.0, 52.0, 90.0]),
            ('R', [0.0, 0.0, 52.0, 135.0]),
            ('L', [0.0, 0.0, 47.0, 135.0]),
            ('R', [0.0, 0.0, 52.0, 135.0]),
        ],
    );
    // LinuxCNC refuses them, as before.
    let linuxcnc = GcodeOptions::default().with_dialect(GcodeDialect::LinuxCnc);
    let e = moves("G0 X0 Y0 Z5\nG81 Z-5 R2 A90 F100\nM2\n", &linuxcnc).unwrap_err();
    assert!(e.to_string().contains("rotary axis words"), "{e}");
}

#[test]
fn system_variables_read_the_interpreters_state() {
    // #4120 T, #4001 group 01 (G01: 1), #5041 X, #4014 (G55: 55), #4109 F, #4006 (G21: 21),
    // #5001 the block end X, #4003 (G90), #4111 the last H, #4107 the last D.
    let src = "O1\nG21 G90 G17\nT3 M06\nG55 G00 X7. Y8. Z10.\nG43 H4 G01 X9. F100.\n\
               G41 D5 X10.\nG40 X9.\n#1=#4120\n#2=#4001\n#3=#5041\n#4=#4014\n#5=#4109\n\
               #6=#4006\n#7=#5001\n#8=#4003\n#9=#4111\n#10=#4107\n\
               G01 X#1 Y#2 Z#4\nG01 X#3 Y#5 Z#6\nG01 X#7 Y#8 Z#9\nX#10\nM30\n";
    let got = moves(src, &fanuc()).unwrap();
    let tail: Vec<[f64; 4]> = got[got.len() - 4..].iter().map(|m| m.1).collect();
    assert_eq!(
        tail,
        vec![
            [3.0, 1.0, 55.0, 0.0],
            [9.0, 100.0, 21.0, 0.0],
            [9.0, 90.0, 4.0, 0.0],
            [5.0, 90.0, 4.0, 0.0]
        ]
    );
    // An inch program reads positions (#5001: X) and feeds in inches; #4009 the cycle,
    // #4010 G98/G99.
    let src = "O1\nG20 G90 G00 X1. Y2. Z1.\nG99 G81 Z-0.5 R0.1 F10.\n#1=#4009\n#2=#4010\n\
               #3=#5001\n#4=#4109\n#5=#4006\nG80\nG01 X#1 Y#2 Z#3\nX#4 Y#5\nM30\n";
    let got = moves(src, &fanuc()).unwrap();
    let tail: Vec<[f64; 4]> = got[got.len() - 2..].iter().map(|m| m.1).collect();
    let mm = |v: [f64; 3]| [v[0] * 25.4, v[1] * 25.4, v[2] * 25.4, 0.0];
    assert_eq!(tail, vec![mm([81.0, 99.0, 1.0]), mm([10.0, 20.0, 1.0])]);
}

#[test]
fn an_unmodelled_system_variable_is_told_once_by_number() {
    let src = "O1\nG21 G90\n#1=#2001\n#2=#2001+#3901\nG00 X#1\n#3901=#3901+1\n#3=#3901\nM30\n";
    let w = warnings(src);
    let told: Vec<_> = w
        .iter()
        .filter(|(_, m)| m.contains("system variable"))
        .collect();
    assert_eq!(told.len(), 2, "{w:?}");
    assert_eq!(told[0].0, 3, "{w:?}");
    assert!(told[0].1.contains("#2001"), "{w:?}");
    assert_eq!(told[1].0, 4, "{w:?}");
    assert!(told[1].1.contains("#3901"), "{w:?}");
    // LinuxCNC's tool parameters (#5400…) are Haas's tool timers: told too; the machine
    // position (#5021) and G54's X (#5221) are modelled.
    let w = warnings("O1\nG21 G90\n#1=#5401\n#2=#5021+#5221\nG00 X#2\nM30\n");
    let told: Vec<_> = w
        .iter()
        .filter(|(_, m)| m.contains("system variable"))
        .collect();
    assert_eq!(told.len(), 1, "{w:?}");
    assert!(told[0].1.contains("#5401"), "{w:?}");
}

#[test]
fn a_macro_alarm_stops_the_program_at_its_block() {
    let src = "O1\nG21 G90 G17\nG00 X0 Y0 Z10.\n#3000=1(TOOL BROKEN)\nG00 X5.\nM30\n";
    let e = moves(src, &fanuc()).unwrap_err();
    let s = e.to_string();
    assert!(s.contains("fanuc.nc:4:1"), "{s}");
    assert!(
        s.contains("macro alarm 3001") && s.contains("TOOL BROKEN"),
        "{s}"
    );
    // #3006 stops until cycle start: the program reads on, with a warning.
    let src = "O1\nG21\nG00 X0\n#3006=1(CHECK)\nG00 X1.\nM30\n";
    assert_eq!(moves(src, &fanuc()).unwrap().len(), 2);
    assert!(warnings(src)
        .iter()
        .any(|(l, m)| *l == 4 && m.contains("CHECK")));
}

#[test]
fn m98_with_five_digits_calls_that_program_when_it_exists() {
    // Haas: O10005 exists, so P10005 is it (not one repeat of O5).
    let src = "O00100\nG20 G90 G17\nG00 X0 Y0 Z1.\nM98 P10005\nM30\n%\nO10005\n\
               G91 G01 X1. F10.\nG90\nM99\n%\nO00005\nG91 G01 Y1. F10.\nG90\nM99\n%\n";
    let got = moves(src, &fanuc()).unwrap();
    close(
        &got,
        &[('R', [0.0, 0.0, 25.4, 0.0]), ('L', [25.4, 0.0, 25.4, 0.0])],
    );
    // Without O10005 the Fanuc split stays: one repeat of O5... and P20005 two.
    let src = "O00100\nG20 G90 G17\nG00 X0 Y0 Z1.\nM98 P20005\nM30\n%\nO00005\n\
               G91 G01 Y1. F10.\nG90\nM99\n%\n";
    let got = moves(src, &fanuc()).unwrap();
    assert_eq!(got.len(), 3, "{got:?}");
    assert!((got[2].1[1] - 50.8).abs() < 1e-9, "{got:?}");
}

#[test]
fn m98_reads_the_subprogram_file_from_the_subroutine_path() {
    let dir = swarf_testdata::scratch_dir("fanuc-m98-files");
    std::fs::create_dir_all(dir.join("lib")).unwrap();
    std::fs::write(
        dir.join("lib/2001.nc"),
        "%\nO2001 (SUB)\nG91 G01 X5. F100.\nG90\nM99\n%\n",
    )
    .unwrap();
    // A file without its O label starts at its first line.
    std::fs::write(dir.join("lib/O2002.TAP"), "G91 G01 Y5. F100.\nG90\nM99\n").unwrap();
    let main = dir.join("main.nc").display().to_string();
    let src = "O1\nG21 G90 G17\nG00 X0 Y0 Z10.\nM98 P2001\nM98 P2002 L2\nM30\n";
    let options = fanuc().with_subroutine_dir(dir.join("lib"));
    let mut rec = Recorder::default();
    read_gcode(src, &main, &options, &mut rec).unwrap();
    let ends: Vec<[f64; 2]> = rec
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::Feed { end } => Some([end.x, end.y]),
            _ => None,
        })
        .collect();
    assert_eq!(ends, vec![[5.0, 0.0], [5.0, 5.0], [5.0, 10.0]]);
    // Not found anywhere: the error names where it looked.
    let src = "O1\nM98 P2003\nM30\n";
    let e = read_gcode(src, &main, &options, &mut Recorder::default()).unwrap_err();
    assert!(e.to_string().contains("O2003"), "{e}");
}
