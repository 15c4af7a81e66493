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
