//! Fuzz target `camotics`: any bytes read as a CAMotics project (`.camotics`) give a tool table or an error naming the
//! file, line and column — never a panic or a hang — and every tool read is usable. Run with
//! `cargo +nightly fuzz run camotics` from `crates/swarf-tool`.
#![no_main]

use libfuzzer_sys::fuzz_target;

/// What the commands do with the tools of a table: describe them and query their shapes at
/// heights and points over and beyond them. None of it may panic, and a radius that is given
/// is a number.
fn exercise(table: &swarf_tool::ToolTable) {
    for entry in table.tools.values() {
        exercise_cutter(&entry.cutter);
    }
}

fn exercise_cutter(c: &swarf_tool::Cutter) {
    let _ = swarf_tool::CutterDescription::of(c);
    let top = c.overall_length().max(c.flute_length());
    for k in -2..=22 {
        let z = top * k as f64 / 20.0;
        if let Some(r) = c.profile_radius(z) {
            assert!(!r.is_nan(), "profile radius NaN at z = {z}");
        }
        let _ = c.contains(swarf_geom::math::Vec3::new(0.3 * z, 0.1, z));
    }
}

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(table) = swarf_tool::table::parse_camotics(&text, "fuzz.camotics") {
        exercise(&table);
    }
});
