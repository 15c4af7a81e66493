//! Fuzz target: the APT CL reader and everything after it never panic, whatever the bytes.
//! Run with `cargo +nightly fuzz run apt` from `crates/swarf-path`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use swarf_path::apt::{read_apt, AptOptions};
use swarf_path::builder::MoveBuilder;
use swarf_path::kinematics::Machine;
use swarf_path::summary::summarize;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let mut builder = MoveBuilder::new(Machine::three_axis(), "fuzz.apt");
    // Errors are fine; panics are not. Build and summarise what was read either way, so that
    // odd arcs and axes reach the builder and the bounding-box code too.
    let _ = read_apt(&text, "fuzz.apt", &AptOptions::default(), &mut builder);
    let _ = summarize(&builder.finish());
});
