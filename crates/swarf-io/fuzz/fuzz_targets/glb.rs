//! Fuzz target `glb`: any bytes read as a glb container give its document and buffer or an
//! error naming the file — never a panic or a hang. Run with `cargo +nightly fuzz run glb` from
//! `crates/swarf-io`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let _ = swarf_io::glb::parse_glb(data, Path::new("fuzz.glb"));
});
