//! Fuzz target `ply`: any bytes read as a PLY file give a mesh or an error naming the file —
//! never a panic or a hang — and a mesh that is read survives what the commands do with it
//! (`swarf_io_fuzz::exercise`). Run with `cargo +nightly fuzz run ply` from `crates/swarf-io`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(mesh) = swarf_io::ply::parse_ply(data, Path::new("fuzz.ply")) {
        swarf_io_fuzz::exercise(mesh);
    }
});
