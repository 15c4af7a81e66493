//! Cutter radius compensation as LinuxCNC's interpreter has it where swarf differed: an arc as
//! the entry move (`convert_arc_comp1`, `arc_data_comp_ijk`, `arc_data_comp_r`), offsets and
//! coordinate systems changed under compensation (`convert_axis_offsets`,
//! `convert_coordinate_system` refuse; `convert_setup`, G10 L2/L20, does not), and a zero
//! radius, which turns compensation on without offsetting the moves.

use swarf_path::canon::{OwnedCanon, Recorder};
use swarf_path::gcode::{read_gcode, GcodeOptions};
use swarf_path::{Canon, PathError, PathErrorKind};

fn read(src: &str) -> Result<Recorder, PathError> {
    let mut rec = Recorder::default();
    read_gcode(src, "comp.ngc", &GcodeOptions::default(), &mut rec)?;
    Ok(rec)
}

/// The moves: `(kind, end x, end y, centre)`, kind `L` feed, `R` rapid, `A+`/`A-` arcs.
fn moves(rec: &Recorder) -> Vec<(&'static str, f64, f64, Option<[f64; 2]>)> {
    rec.events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::Feed { end } => Some(("L", end.x, end.y, None)),
            Canon::Traverse { end } => Some(("R", end.x, end.y, None)),
            Canon::Arc {
                end,
                center,
                rotation,
                ..
            } => Some((
                if *rotation > 0 { "A+" } else { "A-" },
                end.x,
                end.y,
                Some(*center),
            )),
            _ => None,
        })
        .collect()
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

fn assert_move(
    got: (&str, f64, f64, Option<[f64; 2]>),
    kind: &str,
    x: f64,
    y: f64,
    centre: Option<[f64; 2]>,
) {
    let centre_ok = match (got.3, centre) {
        (Some(a), Some(b)) => close(a[0], b[0]) && close(a[1], b[1]),
        (None, None) => true,
        _ => false,
    };
    assert!(
        got.0 == kind && close(got.1, x) && close(got.2, y) && centre_ok,
        "got {got:?}, want ({kind}, {x}, {y}, {centre:?})"
    );
}

#[test]
fn an_entry_arc_keeps_its_centre_and_ends_the_radius_from_its_programmed_end() {
    // G41 (tool left), r = 1, counter-clockwise about (10, 0): the tool is inside the arc. The
    // programmed end (10, 11) is 11 from the centre; the tool ends 1 nearer, at (10, 10), on
    // the start's radius (10): LinuxCNC's ARC_FEED(10, 10, 10, 0, 1).
    let rec = read("G21 G90 F100\nG0 X0 Y0\nG41.1 D2\nG3 X10 Y11 I10 J0\nG1 X0\nG40 G1 X-5\nM2\n")
        .unwrap();
    let m = moves(&rec);
    assert_eq!(m.len(), 4, "{m:?}");
    assert_move(m[1], "A+", 10.0, 10.0, Some([10.0, 0.0]));
    // The arc ends going −X, as the next line does (tangent): the line is offset to y = 10.
    assert_move(m[2], "L", 0.0, 10.0, None);

    // Clockwise with the tool on the left: outside. End radius 9 + 1 = the start's 10.
    let rec = read("G21 G90 F100\nG0 X0 Y0\nG41.1 D2\nG2 X10 Y-9 I10 J0\nM2\n").unwrap();
    assert_move(moves(&rec)[1], "A-", 10.0, -10.0, Some([10.0, 0.0]));

    // R form: the centre through the current point and the programmed end, (0, 10) for a
    // counter-clockwise quarter from (0, 0) to (10, 10); the tool (inside) ends 1 nearer the
    // centre, at (9, 10): the arc goes from radius 10 to radius 9, as LinuxCNC emits it.
    let rec = read("G21 G90 F100\nG0 X0 Y0\nG41.1 D2\nG3 X10 Y10 R10\nM2\n").unwrap();
    assert_move(moves(&rec)[1], "A+", 9.0, 10.0, Some([0.0, 10.0]));

    // G18 (Z first, X second): G41 counter-clockwise about (Z 0, X 10) seen from +Y.
    let rec = read("G21 G90 F100 G18\nG0 X0 Z0\nG41.1 D2\nG3 X10 Z-11 I10 K0\nM2\n").unwrap();
    let arc = rec
        .events
        .iter()
        .find_map(|(_, e)| match e {
            OwnedCanon::Arc { end, center, .. } => Some((*end, *center)),
            _ => None,
        })
        .unwrap();
    // The centre (Z 0, X 10); the end 11 from it along −Z, the tool 1 nearer or farther.
    assert!(close(arc.1[0], 0.0) && close(arc.1[1], 10.0), "{arc:?}");
    assert!(close(arc.0.x, 10.0), "{arc:?}");
    assert!(
        close(arc.0.z.abs(), 10.0) || close(arc.0.z.abs(), 12.0),
        "{arc:?}"
    );
    let r_start = 10.0;
    let r_end = (arc.0.z - arc.1[0]).hypot(arc.0.x - arc.1[1]);
    assert!(
        close(r_end, r_start),
        "the IJK entry arc keeps its radius: {r_end}"
    );
}

#[test]
fn entry_arc_errors_are_linuxcncs() {
    let err = |src: &str| read(src).unwrap_err();
    // End no farther than r = 2 from the start.
    let e = err("G21 F100\nG41.1 D4\nG3 X1 Y1 I1 J0\nM2\n");
    assert_eq!(
        (e.kind, e.pos.line, e.pos.column),
        (PathErrorKind::Semantic, 3, 1)
    );
    assert!(
        e.message.contains(
            "radius of cutter compensation entry arc is not greater than the tool radius"
        ),
        "{e}"
    );
    // The end radius less r (inside) is 9, the start radius 10.
    let e = err("G21 F100\nG41.1 D2\nG3 X10 Y10 I10 J0\nM2\n");
    assert_eq!((e.pos.line, e.pos.column), (3, 1));
    assert!(e.message.contains("radius to end of arc differs"), "{e}");
    // Inside an arc of radius 1 with a tool of radius 2 (end radius 1 + 2).
    let e = err("G21 F100\nG41.1 D4\nG3 X1 Y3 I1 J0\nM2\n");
    assert!(e.message.contains("not less than the arc radius"), "{e}");
    // R form: |R| = 2 with a tool of radius 2, inside.
    let e = err("G21 F100\nG41.1 D4\nG3 X4 Y0 R2\nM2\n");
    assert_eq!((e.pos.line, e.pos.column), (3, 10));
    assert!(e.message.contains("not less than the arc radius"), "{e}");
}

#[test]
fn offsets_and_coordinate_systems_cannot_change_under_compensation() {
    let head = "G21 G90 F100\nG10 L2 P2 Y-5\nG0 X0 Y0 Z0\nG41.1 D2\nG1 X10 Y0\n";
    for (line, what) in [
        ("G92 Y5", "axis offsets"),
        ("G52 Y-5", "axis offsets"),
        ("G92.1", "axis offsets"),
        ("G92.2", "axis offsets"),
        ("G92.3", "axis offsets"),
        ("G55", "coordinate systems"),
        ("X1 G59.3", "coordinate systems"),
    ] {
        let e = read(&format!("{head}{line}\nG1 X20 Y5\nG40\nM2\n")).unwrap_err();
        let column = line.find('G').unwrap() as u32 + 1;
        assert_eq!(
            (e.kind, e.pos.line, e.pos.column),
            (PathErrorKind::Semantic, 6, column),
            "{line}: {e}"
        );
        assert!(
            e.message.contains(&format!(
                "cannot change {what} with cutter radius compensation"
            )),
            "{line}: {e}"
        );
    }
    // With a zero radius too (compensation is on), and fine after G40.
    assert!(read("G21\nG41.1 D0\nG92 X0\nM2\n").is_err());
    assert!(read("G21 F100\nG41.1 D2\nG1 X10\nG40\nG92 X0\nG55\nM2\n").is_ok());
}

#[test]
fn g10_l2_of_the_active_system_under_compensation_keeps_the_tool_in_step() {
    // Along +X with the tool on the left (y = +1), the origin moves 5 along X, then the
    // contour turns to +Y at machine x = 10 (program x = 5): a concave corner, the first
    // line is cut back to where the two offset lines meet, machine (10 − 1, 1).
    let rec = read(
        "G21 G90 F100\nG0 X0 Y0\nG41.1 D2\nG1 X10 Y0\nG10 L2 P1 X5\nG1 X5 Y10\nG40 G1 X5 Y20\nM2\n",
    )
    .unwrap();
    let m = moves(&rec);
    // The first line was made before the change (no offset): machine = program.
    assert_move(m[1], "L", 9.0, 1.0, None);
    // The second after it (G5x X = 5): machine (9, 10) is program (4, 10).
    let offset_x = rec
        .events
        .iter()
        .rev()
        .find_map(|(_, e)| match e {
            OwnedCanon::Offsets { g5x, .. } => Some(g5x.x),
            _ => None,
        })
        .unwrap();
    assert!(close(offset_x, 5.0));
    assert_move(m[2], "L", 9.0 - offset_x, 10.0, None);
    assert_move(m[3], "L", 5.0, 20.0, None);
}

#[test]
fn a_zero_radius_turns_compensation_on_without_offsetting() {
    // The moves are as programmed ...
    let rec = read("G21 F100\nG0 X0 Y0\nG41.1 D0\nG1 X10 Y0\nG3 X20 Y0 R5\nG40\nM2\n").unwrap();
    let m = moves(&rec);
    assert_move(m[1], "L", 10.0, 0.0, None);
    assert_move(m[2], "A+", 20.0, 0.0, Some([15.0, 0.0]));
    // ... but compensation is on: units, another G41 and a tool change are refused.
    for (src, what, line) in [
        ("G21\nG41.1 D0\nG20\nM2\n", "cannot change units", 3),
        ("G21\nG41 D0\nG41.1 D2\nM2\n", "already on", 3),
        ("G21\nG41.1 D0\nT1 M6\nM2\n", "cannot change tools", 3),
    ] {
        let e = read(src).unwrap_err();
        assert_eq!(e.pos.line, line, "{src}: {e}");
        assert!(e.message.contains(what), "{src}: {e}");
    }
}
