//! Fuzz target `heidenhain`: any bytes, read as a Heidenhain conversational program, must give
//! events or an error — never a panic, a hang or unbounded memory. Run with
//! `cargo +nightly fuzz run heidenhain` from `crates/swarf-path`. The events go through the
//! move builder (arcs, tilted planes, tool vectors, the blank). No file is read: the program
//! has no folder and the subroutine path is empty, so `CALL PGM` fails cleanly.
#![no_main]

use libfuzzer_sys::fuzz_target;
use swarf_path::gcode::GcodeOptions;
use swarf_path::heidenhain::read_heidenhain;
use swarf_path::{summarize, Machine, MoveBuilder};

#[path = "check.rs"]
mod check;
use check::Check;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    // Small limits: a fuzzed loop must end in milliseconds.
    let opts = GcodeOptions {
        max_loop_iterations: 20_000,
        max_moves: 200_000,
        max_repeat: 1_000,
        ..GcodeOptions::default()
    };
    let mut sink = Check(MoveBuilder::new(Machine::three_axis(), "/fuzz.h"));
    let _ = read_heidenhain(&text, "/nonexistent-dir/fuzz.h", &opts, &mut sink);
    let _ = summarize(&sink.0.finish());
});
