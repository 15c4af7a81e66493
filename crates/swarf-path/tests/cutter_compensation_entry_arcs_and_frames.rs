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

/// Within LinuxCNC's printing: rs274 prints four decimals.
fn near(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-4
}

/// `got` (from [`moves`]) is LinuxCNC's `(kind, end x, end y, centre)`, compared to 1e-4.
fn assert_rs274(got: (&str, f64, f64, Option<[f64; 2]>), want: (&str, f64, f64, Option<[f64; 2]>)) {
    let centre_ok = match (got.3, want.3) {
        (Some(a), Some(b)) => near(a[0], b[0]) && near(a[1], b[1]),
        (None, None) => true,
        _ => false,
    };
    assert!(
        got.0 == want.0 && near(got.1, want.1) && near(got.2, want.2) && centre_ok,
        "got {got:?}, want {want:?}"
    );
}

#[test]
fn an_entry_arc_is_made_round_about_a_centre_moved_to_be_as_far_from_its_start_as_its_end() {
    // LinuxCNC's `convert_arc_comp1`: the tool ends r from the programmed end along the radius
    // (towards the programmed centre with the tool inside), then the centre moves along that
    // radius to where it is as far from the start as from the new end. The expected numbers
    // are rs274's (LinuxCNC 2.9) canonical calls for each program.
    let path = |src: &str| moves(&read(src).unwrap())[1..].to_vec();

    // R format, G2 with the tool on the left (outside), r = 1: the centre (5, 0) through the
    // current point and the programmed end moves to (5.3667, 0.4889).
    let m = path("G21 G90 F100\nG0 X0 Y0 Z0\nG41.1 D2\nG2 X8 Y4 R5\nG40 G1 X12 Y0\nM2\n");
    assert_rs274(m[0], ("A-", 8.6, 4.8, Some([5.3667, 0.4889])));
    assert_rs274(m[1], ("L", 12.0, 0.0, None));

    // The same arc by I J K: start and end radii are both 5 (LinuxCNC's `arc_data_comp_ijk`
    // compares the programmed radii); a concave corner then cuts it back onto x = 7.
    let m =
        path("G21 G90 F100\nG0 X0 Y0 Z0\nG41.1 D2\nG2 X8 Y4 I5 J0\nG1 X8 Y10\nG40 G1 X0 Y10\nM2\n");
    assert_rs274(m[0], ("A-", 7.0, 5.6243, Some([5.3667, 0.4889])));
    assert_rs274(m[1], ("L", 7.0, 10.0, None));
    assert_rs274(m[2], ("L", 0.0, 10.0, None));

    // A half circle with the tool inside: end radius 5 − 1, the centre moves to (4.5, 0).
    let m = path(
        "G21 G90 F100\nG0 X0 Y0 Z0\nG41.1 D2\nG3 X10 Y0 I5 J0\nG1 X10 Y10\nG40 G1 X0 Y10\nM2\n",
    );
    assert_rs274(m[0], ("A+", 9.0, 0.0, Some([4.5, 0.0])));
    assert_rs274(m[1], ("L", 9.0, 10.0, None));

    // R format with the tool inside: the centre (0, 10) moves to (−1.0556, 10).
    let m = path("G21 G90 F100\nG0 X0 Y0\nG41.1 D2\nG3 X10 Y10 R10\nM2\n");
    assert_rs274(m[0], ("A+", 9.0, 10.0, Some([-1.0556, 10.0])));

    // G18: plane coordinates (Z, X). The centre (Z 0, X 10) moves to (Z 1.0556, X 10).
    let rec =
        read("G21 G90 F100 G18\nG0 X0 Z0\nG41.1 D2\nG3 X10 Z-10 I10 K0\nG1 X20\nM2\n").unwrap();
    let arcs: Vec<_> = rec
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            OwnedCanon::Arc { end, center, .. } => Some((end.z, end.x, *center)),
            _ => None,
        })
        .collect();
    let (z, x, c) = arcs[0];
    assert!(
        near(z, -9.0) && near(x, 10.0) && near(c[0], 1.0556) && near(c[1], 10.0),
        "{arcs:?}"
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
    // Start radius 10, end radius 11: refused as any arc is (rs274 too).
    let e = err("G21 F100\nG41.1 D2\nG3 X10 Y11 I10 J0\nM2\n");
    assert_eq!((e.pos.line, e.pos.column), (3, 1));
    assert!(e.message.contains("radius to end of arc differs"), "{e}");
    // Inside an arc of radius 1.5 with a tool of radius 2.
    let e = err("G21 F100\nG41.1 D4\nG3 X3 Y0 I1.5 J0\nM2\n");
    assert!(e.message.contains("not less than the arc radius"), "{e}");
    // The offset end (1.8, 2.4) sees the start and the centre (5, 0) at a right angle: no
    // centre on that radius is as far from both (rs274: "Tool radius not less than arc radius
    // with comp").
    let e = err("G21 F100\nG41.1 D2\nG3 X1 Y3 I5 J0\nM2\n");
    assert_eq!((e.pos.line, e.pos.column), (3, 1));
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
    // ... but compensation is on: another G41 and a tool change are refused. (A change of
    // units is not: rs274 2.9 takes `G20` under compensation and printed
    // STRAIGHT_FEED(1.0000, 0.0000, …) for this program.)
    let rec = read("G21\nG41.1 D0\nG20\nG1 X1 F10\nM2\n").unwrap();
    assert_move(moves(&rec)[0], "L", 25.4, 0.0, None);
    for (src, what, line) in [
        ("G21\nG41 D0\nG41.1 D2\nM2\n", "already on", 3),
        ("G21\nG41.1 D0\nT1 M6\nM2\n", "cannot change tools", 3),
    ] {
        let e = read(src).unwrap_err();
        assert_eq!(e.pos.line, line, "{src}: {e}");
        assert!(e.message.contains(what), "{src}: {e}");
    }
}
