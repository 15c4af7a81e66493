//! `Program::tip_polylines`: feed and rapid motion apart, joined where they meet, arcs in
//! chords on the arc.

use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::Machine;

#[test]
fn feed_and_rapid_polylines_with_arcs_in_chords() {
    let p = read_program_str(
        "G21 G90\nG0 X0 Y0 Z5\nG0 Z1\nG1 Z-1 F100\nG1 X10\nG2 X20 Y0 I5 J0\nG0 Z5\nM30\n",
        "a.ngc",
        Machine::three_axis(),
        &ReadOptions::default(),
    )
    .unwrap();
    let lines = p.tip_polylines(4);
    let kinds: Vec<bool> = lines.iter().map(|(_, r)| *r).collect();
    assert_eq!(kinds, [true, false, true]);
    // Two rapids joined; the feed: plunge, line, arc in 4 chords.
    assert_eq!(lines[1].0.len(), 1 + 1 + 1 + 4);
    for q in &lines[1].0[3..] {
        let r = ((q.x - 15.0).powi(2) + q.y.powi(2)).sqrt();
        assert!((r - 5.0).abs() < 1e-9, "chord end off the arc: {q:?}");
        assert!(
            q.y >= -1e-9,
            "G2 from X10 to X20 about X15 goes through +Y: {q:?}"
        );
    }
    let last = lines[1].0.last().unwrap();
    assert!((last.x - 20.0).abs() < 1e-9 && last.y.abs() < 1e-9);
}
