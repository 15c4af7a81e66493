//! Fuzz target `ini`: any bytes, split at the first NUL into a LinuxCNC INI and a G-code
//! program, must give events or an error — never a panic, a hang or unbounded memory: the INI
//! parsed and applied (`with_linuxcnc_ini`: its start-up code, `#<_ini[…]>` values, tool-change
//! moves), then the program read under it through the move builder. Run with
//! `cargo +nightly fuzz run ini` from `crates/swarf-path`.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use swarf_path::gcode::{read_gcode, GcodeOptions, LinuxCncIni};
use swarf_path::{summarize, Machine, MoveBuilder};

#[path = "check.rs"]
mod check;
use check::Check;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let (ini, program) = text.split_once('\0').unwrap_or((&text, "G0 X1\nM6 T1\nM2\n"));
    let ini = LinuxCncIni::parse(ini, Path::new("/nonexistent-dir/fuzz.ini"));
    let _ = ini.tool_table();
    // Small limits: a fuzzed loop must end in milliseconds.
    let opts = GcodeOptions {
        max_loop_iterations: 20_000,
        max_moves: 200_000,
        max_repeat: 1_000,
        ..GcodeOptions::default()
    };
    let Ok(opts) = opts.with_linuxcnc_ini(ini) else {
        return;
    };
    let mut sink = Check(MoveBuilder::new(Machine::three_axis(), "/fuzz.ngc"));
    let _ = read_gcode(program, "/nonexistent-dir/fuzz.ngc", &opts, &mut sink);
    let _ = summarize(&sink.0.finish());
});
