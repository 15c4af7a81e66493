//! Tilted working planes (Fanuc and Haas `G68.2 X Y Z I J K`, `G53.1`, `G69`): program
//! positions are feature coordinates, work position = origin + R·p with R = Rz(I)·Rx(J)·Rz(K)
//! (Euler angles: about Z, the new X, the new Z), and after G53.1 the tool axis is the
//! feature's Z. Expected values are worked out by hand below.

use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::{Machine, MoveKind, PathErrorKind, Program};

fn read(src: &str) -> Program {
    read_program_str(
        src,
        "tilt.ngc",
        Machine::three_axis(),
        &ReadOptions::default(),
    )
    .unwrap()
}

fn err(src: &str) -> swarf_path::PathError {
    read_program_str(
        src,
        "tilt.ngc",
        Machine::three_axis(),
        &ReadOptions::default(),
    )
    .unwrap_err()
}

fn close(a: swarf_geom::math::Vec3, b: [f64; 3]) -> bool {
    (a.x - b[0]).abs() < 1e-9 && (a.y - b[1]).abs() < 1e-9 && (a.z - b[2]).abs() < 1e-9
}

/// J−90: the feature's X is the work's X, its Y the work's −Z, its Z the work's +Y (a face on
/// the +Y side); feature (1, 2, 3) about the origin (10, 0, 0) is work (11, 3, −2).
#[test]
fn feature_coordinates_and_the_tool_axis() {
    let p = read(
        "G21 G90\nG0 X10 Y20 Z50\nG68.2 X10 Y0 Z0 I0 J-90 K0\nG53.1\nG1 X1 Y2 Z3 F100\n\
         G91 G1 Z1\nG90\nG69\nG0 Z60\nG0 B0 C0\nG0 X0\nM30\n",
    );
    // The tool stays where it was when the plane is set and when it turns: the first feed
    // starts at (10, 20, 50), tilted.
    let m = &p.moves[1];
    assert!(close(m.start.tip, [10.0, 20.0, 50.0]), "{:?}", m.start.tip);
    assert!(close(m.start.axis, [0.0, 1.0, 0.0]), "{:?}", m.start.axis);
    assert!(close(m.end.tip, [11.0, 3.0, -2.0]), "{:?}", m.end.tip);
    assert!(close(m.end.axis, [0.0, 1.0, 0.0]));
    // Incremental Z is along the feature's Z, the tool axis.
    assert!(
        close(p.moves[2].end.tip, [11.0, 4.0, -2.0]),
        "{:?}",
        p.moves[2].end.tip
    );
    // G69: back to work coordinates; the rotary axes stay where G53.1 turned them, so the
    // tool keeps its axis (a Fanuc control cancels the plane, not the rotation) until the
    // program turns a rotary axis, from when the machine gives it again.
    let m = &p.moves[3];
    assert!(close(m.start.tip, [11.0, 4.0, -2.0]), "{:?}", m.start.tip);
    assert!(close(m.end.tip, [11.0, 4.0, 60.0]), "{:?}", m.end.tip);
    assert!(close(m.end.axis, [0.0, 1.0, 0.0]));
    assert_eq!(m.axis_source, swarf_path::AxisSource::Program);
    // The block that turns the rotary axes is the move that turns the tool back, tip
    // straight and axis turning evenly (a CL move).
    let m = &p.moves[4];
    assert!(close(m.start.axis, [0.0, 1.0, 0.0]) && close(m.end.axis, [0.0, 0.0, 1.0]));
    assert_eq!(m.axis_source, swarf_path::AxisSource::Program);
    let last = p.moves.last().unwrap();
    assert!(close(last.end.tip, [0.0, 4.0, 60.0]), "{:?}", last.end.tip);
    assert!(close(last.end.axis, [0.0, 0.0, 1.0]));
    assert_eq!(last.axis_source, swarf_path::AxisSource::Machine);
    // The moves before G53.1 keep the machine's interpolation (each move says which).
    assert_eq!(p.moves[0].axis_source, swarf_path::AxisSource::Machine);
    // The usual unwind, `G91 G28 B0 C0`, is such a block too.
    let p = read(
        "G21 G90\nG68.2 X0 Y0 Z0 I0 J-90 K0\nG53.1\nG0 Z5\nG69\nG91 G28 B0 C0\nG90\nG0 X1\nM30\n",
    );
    let unwind = &p.moves[1];
    assert!(
        close(unwind.start.axis, [0.0, 1.0, 0.0]),
        "{:?}",
        unwind.start.axis
    );
    let last = p.moves.last().unwrap();
    assert!(close(last.end.axis, [0.0, 0.0, 1.0]));
    assert_eq!(last.axis_source, swarf_path::AxisSource::Machine);
}

/// Euler angles compose about Z, then the new X, then the new Z: I90 J45 K90 gives the
/// feature's Z = Rz(90°)·Rx(45°)·ẑ = (√½, 0, √½) and its X = Rz(90°)·Rx(45°)·Rz(90°)·x̂ =
/// Rz(90°)·Rx(45°)·ŷ = Rz(90°)·(0, √½, √½) = (−√½, 0, √½).
#[test]
fn euler_angles_compose_z_x_z() {
    let p = read("G21 G90\nG68.2 X0 Y0 Z0 I90 J45 K90\nG53.1\nG1 X1 F100\nG1 X0 Z1\nM30\n");
    let h = 0.5f64.sqrt();
    assert!(
        close(p.moves[0].end.tip, [-h, 0.0, h]),
        "{:?}",
        p.moves[0].end.tip
    );
    assert!(
        close(p.moves[1].end.tip, [h, 0.0, h]),
        "{:?}",
        p.moves[1].end.tip
    );
    assert!(close(p.moves[1].end.axis, [h, 0.0, h]));
}

/// Arcs and canned cycles are in the feature frame: a G2 in its XY plane turns clockwise
/// about its Z; a G81 drills along its −Z.
#[test]
fn arcs_and_drilling_cycles_in_the_tilted_plane() {
    let p = read(
        "G21 G90\nG0 X0 Y0 Z50\nG68.2 X0 Y0 Z0 I0 J-90 K0\nG53.1\nG0 X5 Y0 Z2\n\
         G2 X-5 Y0 I-5 J0 F100\nG81 X0 Y0 Z-4 R1\nG80\nG69\nM30\n",
    );
    let arc = p
        .moves
        .iter()
        .find_map(|m| match m.kind {
            MoveKind::Arc(g) => Some(g),
            _ => None,
        })
        .unwrap();
    // Feature Z is work +Y: clockwise about it is counter-clockwise about −Y.
    assert!(close(arc.normal, [0.0, -1.0, 0.0]), "{:?}", arc.normal);
    assert!(close(arc.center, [0.0, 2.0, 0.0]), "{:?}", arc.center);
    assert!((arc.sweep - std::f64::consts::PI).abs() < 1e-12);
    // The drill's feed: from R1 (work y = 1) to Z−4 (work y = −4) at feature (0, 0).
    let feed = p.moves.iter().find(|m| m.kind == MoveKind::Linear).unwrap();
    assert!(
        close(feed.start.tip, [0.0, 1.0, 0.0]),
        "{:?}",
        feed.start.tip
    );
    assert!(close(feed.end.tip, [0.0, -4.0, 0.0]), "{:?}", feed.end.tip);
    assert!(close(feed.end.axis, [0.0, 1.0, 0.0]));
}

/// Without G53.1 the coordinates are tilted and the tool axis stays the machine's.
#[test]
fn without_g53_1_the_axis_stays() {
    let p = read("G21 G90\nG68.2 X0 Y0 Z0 I0 J-90 K0\nG1 Z3 F100\nM30\n");
    assert!(close(p.moves[0].end.tip, [0.0, 3.0, 0.0]));
    assert!(close(p.moves[0].end.axis, [0.0, 0.0, 1.0]));
}

#[test]
fn what_is_not_read_is_an_error_at_its_word() {
    let e = err("G21\nG53.1\n");
    assert_eq!((e.pos.line, e.kind), (2, PathErrorKind::Semantic));
    assert!(e.message.contains("G53.1"), "{}", e.message);
    let e = err("G21\nG68.2 P1 X0 Y0 Z0 I0 J0 K0\n");
    assert_eq!(
        (e.pos.line, e.pos.column, e.kind),
        (2, 7, PathErrorKind::Unsupported)
    );
    let e = err("G21\nG68.2 X0 Y0 Z0 I0 J30 K0\nG68 X0 Y0 R10\n");
    assert_eq!(e.pos.line, 3);
    let e = err("G21\nG68 X0 Y0 R10\nG68.2 X0 Y0 Z0 I0 J30 K0\n");
    assert_eq!(e.pos.line, 3);
    let e = err("G21\nG68.3 X0 Y0 Z0 R30\n");
    assert_eq!(e.kind, PathErrorKind::Unsupported);
    // Position-setting codes would mix the plane's and the work's coordinates: refused in it.
    for code in ["G91 G28 Z0", "G30", "G92 X0", "G52 X1", "G10 L20 P1 X0"] {
        let e = err(&format!("G21\nG68.2 X0 Y0 Z0 I0 J30 K0\n{code}\n"));
        assert_eq!(
            (e.pos.line, e.kind),
            (3, PathErrorKind::Unsupported),
            "{code}"
        );
    }
    assert!(read_program_str(
        "G21\nG68.2 X0 Y0 Z0 I0 J30 K0\nG69\nG91 G28 Z0\nM30\n",
        "tilt.ngc",
        Machine::three_axis(),
        &ReadOptions::default()
    )
    .is_ok());
}
