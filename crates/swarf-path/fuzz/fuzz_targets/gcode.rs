//! Fuzz target `gcode`: any bytes, read as a G-code program, must give events or an error —
//! never a panic, a hang or unbounded memory. Run with `cargo +nightly fuzz run gcode` from
//! `crates/swarf-path`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use swarf_path::gcode::{read_gcode, GcodeOptions};
use swarf_path::{Canon, CanonSink, Warning};

/// Checks the events as they come: every position is finite.
struct Check;

impl CanonSink for Check {
    fn emit(&mut self, _line: u32, event: &Canon<'_>) {
        if let Canon::Traverse { end } | Canon::Feed { end } | Canon::Arc { end, .. } = event {
            // Infinite values can only come from overflowing arithmetic on huge inputs, which
            // is allowed; NaN would mean an unchecked domain error.
            assert!(
                !end.to_array().iter().any(|v| v.is_nan()),
                "NaN position {event:?}"
            );
        }
    }
    fn warn(&mut self, _warning: Warning) {}
}

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    // A small iteration budget keeps each run short; limits are reported as errors.
    let opts = GcodeOptions::default()
        .with_max_loop_iterations(20_000)
        .with_max_repeat(20_000);
    let _ = read_gcode(&text, "fuzz.ngc", &opts, &mut Check);
});
