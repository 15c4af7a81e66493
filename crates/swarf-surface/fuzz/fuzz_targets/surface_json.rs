//! Fuzz target `surface_json`: any bytes, read as a swarf JSON surface file, must give a compound surface or an error —
//! never a panic or a hang — and a surface that is read must be usable: its patches evaluate
//! without NaN points and cut into Bézier pieces for the solvers. Run with
//! `cargo +nightly fuzz run surface_json` from `crates/swarf-surface`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use swarf_surface::io::{parse, Format};

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(surface) = parse(Format::Json, &text) {
        swarf_surface_fuzz::exercise(&surface);
    }
});
