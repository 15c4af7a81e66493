//! Fuzz target `tool_spec`: any text as a tool spec string (`ball:d=10`, `apt:…`) gives a
//! cutter or an error saying what was expected — never a panic — and a cutter that is made is
//! usable. Run with `cargo +nightly fuzz run tool_spec` from `crates/swarf-tool`.
#![no_main]

use libfuzzer_sys::fuzz_target;

/// Describe the cutter and query its shape at heights and points over and beyond it: no
/// panic, and a radius that is given is a number.
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
    if let Ok(c) = swarf_tool::spec::parse(&text) {
        exercise_cutter(&c);
    }
    let _ = swarf_tool::FamilySpec::parse(&text);
});
