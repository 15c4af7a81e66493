//! Helpers shared by the scenario tests.
#![allow(dead_code, unreachable_pub)]

use swarf_geom::math::Vec3;
use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::{Axes, FeedMode, Machine, Move, MoveKind, Pose, Program};

/// Reads G-code text on a 3-axis machine.
pub fn gcode(text: &str) -> Program {
    read_program_str(
        text,
        "test.ngc",
        Machine::three_axis(),
        &ReadOptions::default(),
    )
    .unwrap()
}

/// A program of straight feed moves (or rapids) through `tips` with a fixed `axis`, one
/// move per line starting at line 1.
pub fn moves(tips: &[Vec3], axis: Vec3, rapid: bool) -> Program {
    let mut p = Program {
        files: vec!["test.cl".into()],
        ..Program::default()
    };
    for (i, w) in tips.windows(2).enumerate() {
        p.moves.push(Move {
            kind: if rapid {
                MoveKind::Rapid
            } else {
                MoveKind::Linear
            },
            start: Pose { tip: w[0], axis },
            end: Pose { tip: w[1], axis },
            start_joints: Axes::default(),
            end_joints: Axes::default(),
            feed: 100.0,
            feed_mode: FeedMode::PerMinute,
            spindle_rpm: 10000.0,
            tool: 1,
            file: 0,
            line: i as u32 + 1,
        });
    }
    p
}

/// Relative error.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}
