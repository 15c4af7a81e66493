//! Fuzz target `tool_t`: any bytes read as a Heidenhain `TOOL.T` table give a tool table or an
//! error naming the file, line and column — never a panic or a hang — and every tool read is
//! usable (`swarf_tool_fuzz::exercise`). Run with `cargo +nightly fuzz run tool_t` from
//! `crates/swarf-tool`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(table) = swarf_tool::table::parse_heidenhain(&text, "fuzz.T") {
        swarf_tool_fuzz::exercise(&table);
    }
});
