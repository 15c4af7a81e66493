//! Fuzz target `tool_spec`: any text as a tool spec string (`ball:d=10`, `apt:…`) or a
//! cutter family (`swarf toolsize --cutter`) gives a cutter or an error saying what was
//! expected — never a panic — and a cutter that is made is usable
//! (`swarf_tool_fuzz::exercise_cutter`). Run with `cargo +nightly fuzz run tool_spec` from
//! `crates/swarf-tool`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(c) = swarf_tool::spec::parse(&text) {
        swarf_tool_fuzz::exercise_cutter(&c);
    }
    let _ = swarf_tool::FamilySpec::parse(&text);
});
