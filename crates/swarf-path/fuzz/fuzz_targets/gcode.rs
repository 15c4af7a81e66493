//! Fuzz target `gcode`: any bytes, read as a G-code program, must give events or an error —
//! never a panic, a hang or unbounded memory. Run with `cargo +nightly fuzz run gcode` from
//! `crates/swarf-path`. The first byte picks the dialect (LinuxCNC, Fanuc, detected) and
//! whether tools 0–9 have diameters (so `G41 D3` compensates), so cutter compensation, Fanuc
//! blocks, G68/G51 frames, splines and subroutine calls are all reached; the events also go
//! through the move builder (rotation, spline flattening). No file is read: the program has
//! no folder and the subroutine path is empty.
#![no_main]

use libfuzzer_sys::fuzz_target;
use swarf_path::gcode::{read_gcode, GcodeDialect, GcodeOptions};
use swarf_path::{Machine, MoveBuilder};

#[path = "check.rs"]
mod check;
use check::Check;

fuzz_target!(|data: &[u8]| {
    let (mode, data) = data.split_first().map_or((0, data), |(m, d)| (*m, d));
    let text = String::from_utf8_lossy(data);
    // A small iteration budget keeps each run short; limits are reported as errors.
    let mut opts = GcodeOptions::default()
        .with_max_loop_iterations(20_000)
        .with_max_repeat(20_000);
    match mode % 3 {
        0 => opts = opts.with_dialect(GcodeDialect::LinuxCnc),
        1 => opts = opts.with_dialect(GcodeDialect::Fanuc),
        _ => {}
    }
    if mode & 4 != 0 {
        for t in 0..10 {
            opts = opts.with_tool_diameter(t, f64::from(t) * 1.5);
        }
    }
    let mut check = Check(MoveBuilder::new(Machine::three_axis(), "fuzz.ngc"));
    let _ = read_gcode(&text, "fuzz.ngc", &opts, &mut check);
    let program = check.0.finish();
    for m in &program.moves {
        assert!(!m.end.tip.is_nan(), "NaN tip {m:?}");
    }
});
