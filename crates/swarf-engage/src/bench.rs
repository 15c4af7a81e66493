//! The finishing benchmark's program, shared by the engagement and force benchmarks.

use std::fmt::Write as _;

use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::{Machine, Program};

/// [`finishing_gcode`] read on a 3-axis machine.
pub fn finishing_program(n: usize) -> Program {
    read_program_str(
        &finishing_gcode(n),
        "finish.ngc",
        Machine::three_axis(),
        &ReadOptions::default(),
    )
    .expect("the generated finishing program reads")
}

/// The median of some timings.
pub fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The raster of `swarf-stock`'s `cut` bench as G-code with `n` feed moves: a 10 mm ball end
/// mill's ~0.5 mm moves over a wavy surface `z = 40 + 3·sin(x/12)·cos(y/15)` in a
/// 120 × 120 × 50 mm block, 0.6 mm step-over, F2000 at S10000.
pub fn finishing_gcode(n: usize) -> String {
    let z = |x: f64, y: f64| 40.0 + 3.0 * (x / 12.0).sin() * (y / 15.0).cos();
    let mut text = String::from("G21 G90\nS10000 M3\nG0 Z60\nG0 X5 Y5\nG1 Z43 F2000\n");
    let (seg, step_over) = (0.5, 0.6);
    let per_pass = (110.0 / seg) as usize;
    let (mut y, mut moves, mut pass) = (5.0, 0, 0);
    while moves < n {
        for i in 0..=per_pass {
            let x = if pass % 2 == 0 {
                5.0 + i as f64 * seg
            } else {
                115.0 - i as f64 * seg
            };
            let _ = writeln!(text, "G1 X{x:.4} Y{y:.4} Z{:.4}", z(x, y));
            moves += 1;
            if moves >= n {
                break;
            }
        }
        y += step_over;
        pass += 1;
    }
    text
}
