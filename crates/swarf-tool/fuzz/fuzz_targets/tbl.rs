//! Fuzz target `tbl`: any bytes read as a LinuxCNC tool table (`.tbl`, in inches: the larger numbers) give a tool table or an error naming the
//! file, line and column — never a panic or a hang — and every tool read is usable
//! (`swarf_tool_fuzz::exercise`). Run with `cargo +nightly fuzz run tbl` from
//! `crates/swarf-tool`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(table) =
        swarf_tool::table::parse_linuxcnc(&text, "fuzz.tbl", swarf_tool::LengthUnit::Inch)
    {
        swarf_tool_fuzz::exercise(&table);
    }
});
