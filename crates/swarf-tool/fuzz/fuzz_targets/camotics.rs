//! Fuzz target `camotics`: any bytes read as a CAMotics project (`.camotics`) give a tool table or an error naming the
//! file, line and column — never a panic or a hang — and every tool read is usable
//! (`swarf_tool_fuzz::exercise`). Run with `cargo +nightly fuzz run camotics` from
//! `crates/swarf-tool`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(table) = swarf_tool::table::parse_camotics(&text, "fuzz.camotics") {
        swarf_tool_fuzz::exercise(&table);
    }
});
