//! End to end: G-code text → `read_gcode` → `MoveBuilder` → `summarize`.

use std::f64::consts::PI;

use swarf_path::builder::MoveBuilder;
use swarf_path::gcode::{read_gcode, GcodeOptions};
use swarf_path::kinematics::Machine;
use swarf_path::summary::summarize;
use swarf_path::MoveKind;

#[test]
fn two_half_circles() {
    let text =
        "G21 G17 G90 G94\nG0 X10 Y0 Z0\nG1 Z-1 F100\nG3 X-10 Y0 I-10 J0\nG2 X10 Y0 I10 J0\nM2\n";
    let mut b = MoveBuilder::new(Machine::three_axis(), "half.ngc");
    read_gcode(text, "half.ngc", &GcodeOptions::default(), &mut b).unwrap();
    let p = b.finish();
    let s = summarize(&p);
    assert_eq!(
        (s.moves, s.rapid_moves, s.feed_moves, s.arc_moves),
        (4, 1, 3, 2)
    );
    let arcs: Vec<_> = p
        .moves
        .iter()
        .filter_map(|m| match m.kind {
            MoveKind::Arc(g) => Some((m.line, g)),
            _ => None,
        })
        .collect();
    assert_eq!(arcs[0].0, 4);
    assert!((arcs[0].1.sweep - PI).abs() < 1e-12 && arcs[0].1.normal.z == 1.0);
    assert!((arcs[1].1.sweep - PI).abs() < 1e-12 && arcs[1].1.normal.z == -1.0);
    let length = 1.0 + 20.0 * PI;
    assert!((s.feed_length_mm - length).abs() < 1e-12);
    assert!((s.rapid_length_mm - 10.0).abs() < 1e-12);
    assert!((s.machining_time_s - length / 100.0 * 60.0).abs() < 1e-9);
    // Both halves pass over the top (0, 10); neither reaches y = −10.
    assert_eq!(s.feed_bbox_min, Some([-10.0, 0.0, -1.0]));
    assert_eq!(s.feed_bbox_max, Some([10.0, 10.0, 0.0]));
}

#[test]
fn rotary_words_on_a_machine_without_them_are_reported_once() {
    use swarf_path::load::{read_program_str, ReadOptions};
    let text = "G21 G90\nG1 X1 A10 F100\nG1 X2 A20 C5\nM30\n";
    let p = read_program_str(
        text,
        "r.ngc",
        Machine::three_axis(),
        &ReadOptions::default(),
    )
    .unwrap();
    let about: Vec<_> = p
        .warnings
        .iter()
        .filter(|w| w.message.contains("has no"))
        .collect();
    assert_eq!(about.len(), 2, "{about:?}");
    assert_eq!((about[0].line, about[1].line), (2, 3));
    let on_table = Machine::from_name("table-ac").unwrap();
    let p = read_program_str(text, "r.ngc", on_table, &ReadOptions::default()).unwrap();
    assert!(p.warnings.iter().all(|w| !w.message.contains("has no")));
}
