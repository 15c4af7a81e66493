//! Fuzz target `stl`: any bytes read as an STL file (binary or ASCII) give a mesh or an error
//! naming the file — never a panic, a hang or an allocation the bytes do not justify — and a
//! mesh that is read survives what the commands do with it (`swarf_io_fuzz::exercise`). Run
//! with `cargo +nightly fuzz run stl` from `crates/swarf-io`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(mesh) = swarf_io::stl::parse_stl(data, Path::new("fuzz.stl")) {
        swarf_io_fuzz::exercise(mesh);
    }
});
