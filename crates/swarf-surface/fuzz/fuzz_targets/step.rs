//! Fuzz target `step`: any bytes, read as a STEP (ISO 10303-21) file, must give a compound surface or an error —
//! never a panic or a hang — and a surface that is read must be usable: its patches evaluate
//! without NaN points and cut into Bézier pieces for the solvers. Run with
//! `cargo +nightly fuzz run step` from `crates/swarf-surface`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use swarf_surface::io::{parse, Format};

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(surface) = parse(Format::Step, &text) {
        swarf_surface_fuzz::exercise(&surface);
    }
});
