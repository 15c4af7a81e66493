//! Rotated and local coordinate systems: G10 L2/L20 with R, G52, G53 and G28 under rotation,
//! carried into the move stream (machine position = rotate(program + G92 offset) + G5x
//! offset, LinuxCNC's canon layer; LinuxCNC G-code manual, "G10 L2", "G52").

use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::{Machine, MoveKind, Program};

fn read(src: &str) -> Program {
    read_program_str(
        src,
        "frames.ngc",
        Machine::three_axis(),
        &ReadOptions::default(),
    )
    .unwrap()
}

fn close(a: swarf_geom::math::Vec3, b: [f64; 3]) -> bool {
    (a.x - b[0]).abs() < 1e-9 && (a.y - b[1]).abs() < 1e-9 && (a.z - b[2]).abs() < 1e-9
}

#[test]
fn g10_l2_r_turns_the_work_offset_about_its_origin() {
    // G54 at X10, turned 90°: program X1 is machine (10, 1).
    let p = read("G21 G90\nG10 L2 P1 X10 Y0 R90\nG54\nG1 X1 Y0 F100\nG1 X1 Y2\nM2\n");
    assert!(
        close(p.moves[0].end.tip, [10.0, 1.0, 0.0]),
        "{:?}",
        p.moves[0].end.tip
    );
    assert!(
        close(p.moves[1].end.tip, [8.0, 1.0, 0.0]),
        "{:?}",
        p.moves[1].end.tip
    );
}

#[test]
fn arcs_turn_with_the_system() {
    // A quarter circle from (1, 0) to (0, 1) about the origin, system turned 90° at (5, 5).
    let p = read("G21 G90\nG10 L2 P1 X5 Y5 R90\nG0 X1 Y0\nG3 X0 Y1 I-1 J0 F100\nM2\n");
    let m = &p.moves[1];
    let MoveKind::Arc(g) = m.kind else {
        panic!("{:?}", m.kind)
    };
    assert!(close(g.center, [5.0, 5.0, 0.0]), "{:?}", g.center);
    assert!(close(g.normal, [0.0, 0.0, 1.0]));
    assert!((g.sweep - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    assert!(close(m.end.tip, [4.0, 5.0, 0.0]), "{:?}", m.end.tip);
}

#[test]
fn g10_l20_sets_the_offset_so_the_position_reads_as_given() {
    // At machine (0, 0), system turned 45°: X-1 means the origin is at (√½, √½).
    let p = read(
        "G21 G90\nG10 L2 P1 X0 Y0 R45\nG53 G0 X0 Y0\nG10 L20 P1 X-1\n(debug,#5221 #5222 #5420)\nG1 X0 F10\nM2\n",
    );
    let h = 0.5f64.sqrt();
    assert!(
        close(p.moves[1].end.tip, [h, h, 0.0]),
        "{:?}",
        p.moves[1].end.tip
    );
}

#[test]
fn g52_is_a_local_origin_in_the_g92_offset() {
    let src = "G21 G90\nG52 X5 Y-2\nG0 X1 Y1\n(debug,#5210 #5211 #5212)\nG52 X0 Y0\nG0 X1 Y1\nM2\n";
    let p = read(src);
    assert!(close(p.moves[0].end.tip, [6.0, -1.0, 0.0]));
    assert!(close(p.moves[1].end.tip, [1.0, 1.0, 0.0]));
    let mut rec = swarf_path::canon::Recorder::default();
    swarf_path::gcode::read_gcode(src, "f.ngc", &Default::default(), &mut rec).unwrap();
    assert_eq!(rec.messages()[0], "1.000000 5.000000 -2.000000");
}

#[test]
fn g53_and_g28_go_to_machine_positions_under_rotation() {
    // G53 X1 Y1 under a 45° system at the origin is program (√2, 0); G28 returns to the
    // G28.1 point.
    let p = read("G21 G90\nG10 L2 P1 R45\nG53 G0 X1 Y1\nG28.1\nG0 X0 Y0\nG28\nM2\n");
    assert!(close(p.moves[0].end.tip, [1.0, 1.0, 0.0]));
    assert!(close(p.moves[1].end.tip, [0.0, 0.0, 0.0]));
    assert!(close(p.moves.last().unwrap().end.tip, [1.0, 1.0, 0.0]));
}

/// Every move starts where the one before ended on the machine, whatever frame change came
/// between (G55, G92, G52, G10 L2/L20, rotation): the tool does not jump when the program's
/// coordinates are redefined.
#[test]
fn a_frame_change_leaves_the_tool_where_it_is() {
    let cases: [(&str, [f64; 3], f64); 6] = [
        // (program, where the last move ends on the machine, its length)
        (
            "G10 L2 P2 X100\nG54 G0 X10 Y10\nG55\nG1 X5 F100\n",
            [105.0, 10.0, 0.0],
            95.0,
        ),
        (
            "G0 X10 Y10\nG92 X0 Y0\nG1 X5 F100\n",
            [15.0, 10.0, 0.0],
            5.0,
        ),
        ("G0 X10 Y10\nG52 X4\nG1 X5 F100\n", [9.0, 10.0, 0.0], 1.0),
        (
            "G0 X10 Y10\nG10 L20 P1 X0\nG1 X5 F100\n",
            [15.0, 10.0, 0.0],
            5.0,
        ),
        // Turned 90° about the origin: program (10, 0) is machine (0, 10).
        (
            "G0 X10 Y0\nG10 L2 P1 R90\nG1 X10 Y0 F100\n",
            [0.0, 10.0, 0.0],
            200f64.sqrt(),
        ),
        (
            "G0 X10 Y0 Z5\nG10 L2 P1 Z-5\nG1 Z0 F100\n",
            [10.0, 0.0, -5.0],
            10.0,
        ),
    ];
    for (body, end, length) in cases {
        let p = read(&format!("G21 G90\n{body}M2\n"));
        for w in p.moves.windows(2) {
            assert!(
                (w[0].end.tip - w[1].start.tip).length() < 1e-12,
                "{body}: {:?} then {:?}",
                w[0].end.tip,
                w[1].start.tip
            );
        }
        let last = p.moves.last().unwrap();
        assert!(close(last.end.tip, end), "{body}: {:?}", last.end.tip);
        let len = (last.end.tip - last.start.tip).length();
        assert!((len - length).abs() < 1e-9, "{body}: {len}");
    }
}

/// Offsets the parameters set before the program starts (a LinuxCNC `.var` file) leave the
/// tool at the machine's origin: the interpreter and the move builder agree on where it is,
/// so a first move that omits an axis keeps the machine position of that axis.
#[test]
fn parameter_offsets_at_start_leave_the_tool_at_the_machine_origin() {
    use swarf_path::gcode::GcodeOptions;
    // G54 at X10 (#5221) and a stored, active G92 of Y5 (#5210, #5212).
    let options = ReadOptions {
        gcode: GcodeOptions {
            parameters: vec![(5221, 10.0), (5210, 1.0), (5212, 5.0)],
            ..GcodeOptions::default()
        },
        ..ReadOptions::default()
    };
    let p = read_program_str(
        "G21 G90\nG1 Z-1 F100\nG1 X0\nM2\n",
        "frames.ngc",
        Machine::three_axis(),
        &options,
    )
    .unwrap();
    // The first move goes down from the machine origin; then X0 is machine X10 (the G54
    // offset), Y staying at the machine's 0 (program −5).
    assert!(
        close(p.moves[0].start.tip, [0.0, 0.0, 0.0]),
        "{:?}",
        p.moves[0].start.tip
    );
    assert!(
        close(p.moves[0].end.tip, [0.0, 0.0, -1.0]),
        "{:?}",
        p.moves[0].end.tip
    );
    assert!(
        close(p.moves[1].end.tip, [10.0, 0.0, -1.0]),
        "{:?}",
        p.moves[1].end.tip
    );
}
