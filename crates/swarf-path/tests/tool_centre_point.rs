//! Tool centre point control as a mode of the program (Fanuc G43.4 / G43.5 … G49 or G43,
//! Heidenhain M128 … M129, Sinumerik TRAORI … TRAFOOF) on a machine with rotary joints: while
//! it is on, X Y Z are tool-tip positions in the part frame; the tool stays where it is when
//! the mode changes; moves keep the reading they were made with.

use swarf_geom::math::Vec3;
use swarf_path::kinematics::Machine;
use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::Program;

fn read(text: &str, file: &str, machine: &str) -> Program {
    read_program_str(
        text,
        file,
        Machine::from_name(machine).unwrap(),
        &ReadOptions::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

/// Every pose along every move (11 samples each) as the machine moves it.
fn samples(p: &Program) -> Vec<(Vec3, Vec3)> {
    p.moves
        .iter()
        .flat_map(|m| (0..=10).map(move |i| p.pose_at(m, f64::from(i) / 10.0)))
        .map(|q| (q.tip, q.axis))
        .collect()
}

#[test]
fn fanuc_g43_4_reads_tip_positions_until_g49() {
    let text = "%\nO6000\nG21 G90 G17 G54 G40 G49 G80\nT1 M6\nS1000 M3\nG0 A0. C0.\n\
        G43.4 H1\nG0 X0. Y0. Z50.\nG1 Z10. F100.\nG1 X10. Y0. Z10. A30. C90.\n\
        G1 X20. A0. C0.\nG49\nG0 Z100.\nM30\n%\n";
    let p = read(text, "t.nc", "table-ac");
    // Under G43.4 the tip stays on the line Y = 0, Z = 10 while the table turns.
    let tcp: Vec<_> = p.moves.iter().map(|m| m.tcp).collect();
    assert_eq!(tcp, vec![false, true, true, true, true, false], "{tcp:?}");
    for m in &p.moves[3..5] {
        for i in 0..=10 {
            let q = p.pose_at(m, f64::from(i) / 10.0);
            assert!(
                q.tip.y.abs() < 1e-9 && (q.tip.z - 10.0).abs() < 1e-9,
                "{q:?}"
            );
        }
    }
    // The tool axis at A30 C90 is the table's turn seen from the part.
    let a = p.moves[3].end.axis;
    let want = Machine::from_name("table-ac-tcp")
        .unwrap()
        .pose(&p.moves[3].end_joints)
        .axis;
    assert!((a - want).length() < 1e-12, "{a:?} {want:?}");
    // After G49 the same Z100 is the machine's: the rapid starts where the tool stood.
    let last = &p.moves[5];
    assert!((last.start.tip - p.moves[4].end.tip).length() < 1e-9);
    assert!((last.end.tip - Vec3::new(20.0, 0.0, 100.0)).length() < 1e-9);
    // The whole program as a `-tcp` machine would read it, but for the last rapid.
    let all_tcp = read(text, "t.nc", "table-ac-tcp");
    for (a, b) in samples(&p).iter().zip(samples(&all_tcp)).take(5 * 11) {
        assert!((a.0 - b.0).length() < 1e-9 && (a.1 - b.1).length() < 1e-12);
    }
}

#[test]
fn fanuc_plain_g43_is_the_machine_reading_even_on_a_tcp_machine() {
    // A 3+2 section written in machine coordinates (G43, table turned 90° about X): the part
    // point (0, 50, 0) is under the tool at machine (0, 0, 50).
    let text = "%\nO6001\nG21 G90 G17 G54\nT1 M6\nG43 H1\nG0 A90. C0.\nG0 X0. Y0. Z50.\n\
        G1 Z10. F100.\nG49\nM30\n%\n";
    for machine in ["table-ac", "table-ac-tcp"] {
        let p = read(text, "t.nc", machine);
        let end = p.moves[1].end.tip;
        assert!(
            (end - Vec3::new(0.0, 50.0, 0.0)).length() < 1e-9,
            "{machine}: {end:?}"
        );
    }
}

#[test]
fn heidenhain_m128_and_sinumerik_traori_switch_it_too() {
    let h = "BEGIN PGM T MM\nTOOL CALL 1 Z S1000\nL A+0 C+0 R0 FMAX\nL X+0 Y+0 Z+50 R0 FMAX M128\n\
        L Z+10 R0 F100\nL X+10 A+30 C+90 R0 F100\nL X+20 A+0 C+0 R0 F100 M129\nL Z+100 R0 FMAX\n\
        END PGM T MM\n";
    let s = "G71 G90 G17\nT1 M6\nG0 A0 C0\nTRAORI\nG0 X0 Y0 Z50\nG1 Z10 F100\n\
        G1 X10 A30 C90\nG1 X20 A0 C0\nTRAFOOF\nG0 Z100\nM30\n";
    for (text, file) in [(h, "t.h"), (s, "t.mpf")] {
        let p = read(text, file, "table-ac");
        let n = p.moves.len();
        let tcp: Vec<_> = p.moves.iter().map(|m| m.tcp).collect();
        assert!(tcp[n - 2] && !tcp[n - 1], "{file}: {tcp:?}");
        for m in &p.moves[n - 3..n - 1] {
            for i in 0..=10 {
                let q = p.pose_at(m, f64::from(i) / 10.0);
                assert!(
                    q.tip.y.abs() < 1e-9 && (q.tip.z - 10.0).abs() < 1e-9,
                    "{file}: {q:?}"
                );
            }
        }
        let last = &p.moves[n - 1];
        assert!(
            (last.start.tip - p.moves[n - 2].end.tip).length() < 1e-9,
            "{file}"
        );
    }
}

#[test]
fn fanuc_g43_5_takes_the_tool_direction_from_i_j_k() {
    // Tool centre point control type 2: a straight move's I J K are the tool's direction in
    // the part frame (an omitted one is 0, none keeps it); I J K alone turn the tool in place.
    let text = "%\nO6001\nG21 G90 G17 G54\nT1 M6\nS1000 M3\n\
        G43.5 H1 X0. Y0. Z50. I0 J0 K1.\nG1 X10. Z40. I0.6 K0.8 F500.\nG1 X20.\nJ-0.6 K0.8\n\
        G49\nM30\n%\n";
    let p = read(text, "t.nc", "table-ac");
    assert_eq!(p.moves.len(), 4, "{:?}", p.moves);
    let axes: Vec<Vec3> = p.moves.iter().map(|m| m.end.axis).collect();
    let want = [
        Vec3::Z,
        Vec3::new(0.6, 0.0, 0.8),
        Vec3::new(0.6, 0.0, 0.8),
        Vec3::new(0.0, -0.6, 0.8),
    ];
    for (a, w) in axes.iter().zip(want) {
        assert!((*a - w).length() < 1e-12, "{axes:?}");
    }
    // X Y Z are tip positions: the last move turns the tool about its tip at (20, 0, 40).
    let last = &p.moves[3];
    assert!((last.start.tip - Vec3::new(20.0, 0.0, 40.0)).length() < 1e-9);
    assert!((last.end.tip - Vec3::new(20.0, 0.0, 40.0)).length() < 1e-9);
    // No word is reported unused (I J K were read) and none as a length without a point.
    assert!(
        p.warnings
            .iter()
            .all(|w| !w.message.contains("ignored") && !w.message.contains("decimal point")),
        "{:?}",
        p.warnings
    );
}

/// The last move's end: tip and axis.
fn last_end(p: &Program) -> (Vec3, Vec3) {
    let m = p.moves.last().expect("a move");
    (m.end.tip, m.end.axis)
}

#[test]
fn a_rotary_word_after_a_stated_tool_vector_gives_the_axis_back_to_the_machine() {
    // The same programs with and without one move that states the tool's direction as a vector
    // (Heidenhain LN … TX TY TZ, Sinumerik A3= B3= C3=, Fanuc G43.5 I J K): the rotary words
    // after it set the tool axis again, so both end with the tool where the machine's axes put
    // it. (The vector kept the axis for the rest of the program.)
    let cases = [
        (
            "t.h",
            "BEGIN PGM T MM\nTOOL CALL 1 Z S8000\nM128\nL X+0 Y+0 Z+50 A+0 C+0 R0 FMAX\n\
             @ F500\nL X+10 Y+0 Z+50 R0 FMAX\nL X+10 Y+0 Z+50 A+90 C+0 R0 FMAX\n\
             L X+10 Y+0 Z+5 R0 F500\nM129\nL X+0 Y+0 Z+100 A-45 C+90 R0 FMAX\nEND PGM T MM\n",
            ["LN X+10 Y+0 Z+5 TX+0 TY+0 TZ+1", "L X+10 Y+0 Z+5"],
        ),
        (
            "t.mpf",
            "G90 G17 G71\nT1 D1\nM6\nTRAORI\nORIWKS\nG0 X10 Y0 Z50 A0 C0\nG1 Z5 F500\n@\n\
             G1 X40 A90 C90\nTRAFOOF\nG0 X0 Y0 Z100 A-45 C90\nM30\n",
            ["G1 X20 A3=0.6 B3=0 C3=0.8", "G1 X20 A0 C0"],
        ),
        (
            "t.nc",
            "%\nO1\nG21 G90 G17 G94\nT1 M6\nG43.4 H1\nG0 X0. Y0. Z50. A0. C0.\n@\nG49\n\
             G43.4 H1\nG0 X10. Y0. Z50. A90. C0.\nG1 Z5. F500.\nG49\nG0 X0. Y0. Z100. A-45. C90.\n\
             M30\n%\n",
            [
                "G43.5 H1 G1 X10. Z5. I0.6 J0 K0.8 F500.",
                "G1 X10. Z5. F500.",
            ],
        ),
    ];
    for (file, text, [vector, plain]) in cases {
        let with = read(&text.replace('@', vector), file, "table-ac");
        let without = read(&text.replace('@', plain), file, "table-ac");
        let (a, b) = (last_end(&with), last_end(&without));
        assert!(
            (a.0 - b.0).length() < 1e-9 && (a.1 - b.1).length() < 1e-12,
            "{file}: {a:?} against {b:?}"
        );
        // At A-45 C90 without tool centre point control: the machine's point (0, 0, 100)
        // seen from the turned table, the axis turned with it.
        let h = std::f64::consts::FRAC_1_SQRT_2;
        assert!(
            (a.1 - Vec3::new(-h, 0.0, h)).length() < 1e-12,
            "{file}: {a:?}"
        );
        assert!(
            (a.0 - Vec3::new(-100.0 * h, 0.0, 100.0 * h)).length() < 1e-9,
            "{file}: {a:?}"
        );
        // The moves between the vector and the rotary words kept the stated axis.
        let stated = with
            .moves
            .iter()
            .find(|m| (m.end.axis - Vec3::new(0.6, 0.0, 0.8)).length() < 1e-12);
        assert!(file == "t.h" || stated.is_some(), "{file}");
    }
}

#[test]
fn after_tool_centre_point_control_the_axes_a_block_leaves_out_are_the_machines() {
    // With the table at A-45 C90 and the tip at (20, 0, 5), turning tool centre point control
    // off re-expresses X Y Z as the machine's point; an incremental Z100 then moves only the
    // machine's Z: straight up the tool axis, 100 mm. (The readers kept the tip's X Y Z and
    // put the machine's X Y where the tip had been.)
    let cases = [
        (
            "t.nc",
            "G21 G90 G17 G94\nT1 M6\nG0 A-45. C90.\nG43.4 H1\nG0 X20. Y0. Z50.\nG1 Z5. F500.\n\
             G49\nG91 G0 Z100.\nG90\nM30\n",
        ),
        (
            "t.h",
            "BEGIN PGM M MM\nTOOL CALL 1 Z S8000\nL A-45 C+90 R0 FMAX\nM128\n\
             L X+20 Y+0 Z+50 R0 FMAX\nL Z+5 F500\nM129\nL IZ+100 R0 FMAX\nEND PGM M MM\n",
        ),
        (
            "t.mpf",
            "G90 G17 G71\nT1 D1\nM6\nG0 A-45 C90\nTRAORI\nG0 X20 Y0 Z50\nG1 Z5 F500\nTRAFOOF\n\
             G91 G0 Z100\nG90\nM30\n",
        ),
    ];
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let axis = Vec3::new(-h, 0.0, h);
    for (file, text) in cases {
        let p = read(text, file, "table-ac");
        let last = p.moves.last().unwrap();
        assert!(
            (last.start.tip - Vec3::new(20.0, 0.0, 5.0)).length() < 1e-9,
            "{file}: {:?}",
            last.start
        );
        let want = Vec3::new(20.0, 0.0, 5.0) + axis * 100.0;
        assert!(
            (last.end.tip - want).length() < 1e-9 && (last.end.axis - axis).length() < 1e-12,
            "{file}: {:?} instead of {want:?}",
            last.end
        );
    }
}

#[test]
fn heidenhain_tcpm_axis_spat_reads_a_b_c_as_the_tools_spatial_angles() {
    // FUNCTION TCPM … AXIS SPAT: A B C are spatial angles (about the fixed X, then Y, then Z);
    // B+45 tilts the tool towards +X, whatever rotary axes the machine has. (They were read as
    // the machine's B axis: towards −X on a B-C table.)
    let text = "BEGIN PGM S MM\nTOOL CALL 1 Z S8000\n\
        FUNCTION TCPM F CONT AXIS SPAT PATHCTRL VECTOR\nL X+0 Y+0 Z+50 R0 FMAX\n\
        L X+10 Y+0 Z+5 A+0 B+45 C+0 F500\nL X+20 C+90\nL X+30 IB-45\nFUNCTION RESET TCPM\n\
        END PGM S MM\n";
    let h = std::f64::consts::FRAC_1_SQRT_2;
    for machine in ["table-bc", "head-ac", "table-ac"] {
        let p = read(text, "t.h", machine);
        let axes: Vec<Vec3> = p.moves.iter().map(|m| m.end.axis).collect();
        let want = [
            Vec3::Z,
            Vec3::new(h, 0.0, h),
            // C+90 turns the B+45 tilt about Z: towards +Y.
            Vec3::new(0.0, h, h),
            Vec3::Z,
        ];
        assert_eq!(axes.len(), want.len(), "{machine}: {axes:?}");
        for (a, w) in axes.iter().zip(want) {
            assert!((*a - w).length() < 1e-12, "{machine}: {axes:?}");
        }
        // The tip is where X Y Z say.
        let last = p.moves.last().unwrap();
        assert!(
            (last.end.tip - Vec3::new(30.0, 0.0, 5.0)).length() < 1e-9,
            "{machine}"
        );
    }
}

#[test]
fn a_stated_axis_the_machine_cannot_reach_keeps_the_tip_when_tcp_ends() {
    // A table about X cannot tilt the tool towards X: when G49 ends the stated axis, the
    // rotary axes keep the program's values (A0), with a warning, and the tip stays where it
    // was (it jumped by the machine's reading of the old tip coordinates).
    let text = "%\nO1\nG21 G90 G17\nT1 M6\nG43.5 H1 X0. Y0. Z50. I0 J0 K1.\n\
        G1 X10. Z40. I0.6 K0.8 F500.\nG49\nG91 G0 Z100.\nG90\nM30\n%\n";
    let p = read(text, "t.nc", "4axis-a");
    let last = p.moves.last().unwrap();
    assert!(
        (last.start.tip - Vec3::new(10.0, 0.0, 40.0)).length() < 1e-9,
        "{:?}",
        last.start
    );
    assert!(
        (last.end.tip - Vec3::new(10.0, 0.0, 140.0)).length() < 1e-9,
        "{:?}",
        last.end
    );
    assert!(
        p.warnings
            .iter()
            .any(|w| w.message.contains("cannot turn the tool") && !w.message.contains("  ")),
        "{:?}",
        p.warnings
    );
}

#[test]
fn the_canonical_print_on_a_machine_follows_the_simulation_after_tcp_ends() {
    // Printed on the machine, the retract after G49 starts from the machine's point (its X Y
    // where the machine is), as the simulated move does; it printed the tip's old X Y.
    let text = "G21 G90 G17 G94\nT1 M6\nG0 A-45. C90.\nG43.4 H1\nG0 X20. Y0. Z50.\nG1 Z5. F500.\n\
        G49\nG91 G0 Z100.\nG90\nM30\n";
    let machine = Machine::from_name("table-ac").unwrap();
    let mut printer = swarf_path::canonical::CanonicalPrinter::new(Vec::new())
        .with_machine(machine.clone(), "t.nc");
    swarf_path::gcode::read_gcode(
        text,
        "t.nc",
        &swarf_path::gcode::GcodeOptions::default(),
        &mut printer,
    )
    .unwrap();
    let out = String::from_utf8(printer.finish().unwrap()).unwrap();
    let last = out
        .lines()
        .rfind(|l| l.contains("STRAIGHT_TRAVERSE"))
        .unwrap()
        .to_string();
    let p = read(text, "t.nc", "table-ac");
    let j = p.moves.last().unwrap().end_joints;
    let want = format!(
        " N..... STRAIGHT_TRAVERSE({:.4}, {:.4}, {:.4}, {:.4}, {:.4}, {:.4})",
        j.x, j.y, j.z, j.a, j.b, j.c
    );
    assert_eq!(last, want);
    // The machine's X Y are not the tip's 20, 0 (the table is turned).
    assert!((j.x - 20.0).abs() > 1.0 || j.y.abs() > 1.0, "{j:?}");
}
