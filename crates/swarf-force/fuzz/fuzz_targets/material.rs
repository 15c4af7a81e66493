//! Fuzz target `material`: any bytes read as a material file (`swarf forces --coefficients`)
//! give cutting coefficients or an error naming the file, line and column — never a panic —
//! and coefficients that are read give numbers at any chip thickness. Run with
//! `cargo +nightly fuzz run material` from `crates/swarf-force`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(m) = swarf_force::parse_material(&text, "fuzz.toml") {
        for h in [0.0, 1e-4, 0.01, 0.1, 1.0] {
            let _ = m.coefficients(Some(10.0), 30.0, h);
            let _ = m.coefficients(None, 0.0, h);
        }
    }
});
