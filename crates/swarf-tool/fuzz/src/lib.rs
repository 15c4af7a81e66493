//! What every tool fuzz target does with the tools it read: describe each one and query its
//! shape at heights and points over and beyond it, as the commands do. Nothing may panic, and
//! a profile radius that is given is a number.

use swarf_geom::math::Vec3;
use swarf_tool::{Cutter, CutterDescription, ToolTable};

/// Exercises every tool of `table` (see the crate docs).
pub fn exercise(table: &ToolTable) {
    for entry in table.tools.values() {
        exercise_cutter(&entry.cutter);
    }
}

/// Exercises one cutter (see the crate docs).
pub fn exercise_cutter(c: &Cutter) {
    let _ = CutterDescription::of(c);
    let top = c.overall_length().max(c.flute_length());
    for k in -2..=22 {
        let z = top * k as f64 / 20.0;
        if let Some(r) = c.profile_radius(z) {
            assert!(!r.is_nan(), "profile radius NaN at z = {z}");
        }
        let _ = c.contains(Vec3::new(0.3 * z, 0.1, z));
    }
}
