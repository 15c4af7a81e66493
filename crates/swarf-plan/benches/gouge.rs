//! The program check on the 24-patch mould: a 3-axis finishing raster of a 6 mm ball end mill
//! placed tangent to the surface at every CC point (0.5 mm along, 2 mm stepover), checked
//! move by move; it gouges where the mould is concave tighter than the ball (the pockets'
//! rims). Prints the median of 5 full checks (moves/s, nodes per move, violations), then
//! criterion times one pose check.
//!
//! `cargo bench -p swarf-plan --bench gouge` (`SWARF_BENCH_REPORT_ONLY=1` skips criterion).

mod common;

use std::hint::black_box;
use std::time::Instant;

use criterion::Criterion;
use swarf_geom::math::Vec3;
use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::Machine;
use swarf_plan::gouge::{check_program, GougeOptions, GougeSurface, ViolationKind};
use swarf_surface::PreparedSurface;
use swarf_surface::{CompoundSurface, Tolerances};

const RADIUS: f64 = 3.0;

/// The raster's G-code: tip = S + R·n − R·z for the CC point S with unit normal n.
fn raster(part: &CompoundSurface) -> String {
    let mut g = String::from("G21 G90 G0 X0.5 Y0.5 Z20\n");
    let mut y: f64 = 0.5;
    let mut row = 0;
    while y < 40.0 {
        let xs: Vec<f64> = (0..=118).map(|k| 0.5 + 0.5 * k as f64).collect();
        let order: Vec<f64> = if row % 2 == 0 {
            xs
        } else {
            xs.into_iter().rev().collect()
        };
        for (k, x) in order.iter().enumerate() {
            let (a, b) = ((x / 10.0).floor().min(5.0), (y / 10.0).floor().min(3.0));
            let patch = &part.patches[(4.0 * a + b) as usize];
            let (u, v) = (x / 10.0 - a, y / 10.0 - b);
            let (s, n) = patch.point_normal(u, v, &Tolerances::DEFAULT);
            let n = n.vector().unwrap_or(Vec3::Z);
            let tip = s + RADIUS * n - RADIUS * Vec3::Z;
            let word = if k == 0 { "G1" } else { "" };
            g += &format!("{word} X{:.6} Y{:.6} Z{:.6} F2000\n", tip.x, tip.y, tip.z);
        }
        y += 2.0;
        row += 1;
    }
    g + "G0 Z20\n"
}

fn main() {
    let part = common::mould();
    let prep = PreparedSurface::new(&part);
    let surface = GougeSurface::new(&prep);
    let text = raster(&part);
    let program = read_program_str(
        &text,
        "raster.ngc",
        Machine::three_axis(),
        &ReadOptions::default(),
    )
    .unwrap();
    let cutter = swarf_tool::Cutter::ball(2.0 * RADIUS).unwrap();
    let tools = swarf_tool::ToolSet::single(cutter.clone());
    let opts = GougeOptions::DEFAULT;
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..5 {
        let t = Instant::now();
        let r = check_program(&surface, &program, &tools, &opts).unwrap();
        times.push(t.elapsed().as_secs_f64());
        last = Some(r);
    }
    times.sort_by(f64::total_cmp);
    let r = last.unwrap();
    let median = times[times.len() / 2];
    let moves = program.moves.len();
    println!(
        "gouge check, 24-patch mould, ball d={} raster: {moves} moves, {} threads: median {:.3} s \
         (min {:.3}, max {:.3}) = {:.0} moves/s, {:.0} nodes/move, {} gouging moves (deepest \
         {:.4} mm), {} unresolved",
        2.0 * RADIUS,
        rayon::current_num_threads(),
        median,
        times[0],
        times[times.len() - 1],
        moves as f64 / median,
        r.nodes as f64 / moves as f64,
        r.moves_with(ViolationKind::Gouge),
        r.max_depth(ViolationKind::Gouge),
        r.unresolved
    );
    if std::env::var_os("SWARF_BENCH_REPORT_ONLY").is_some() {
        return;
    }
    let one = swarf_path::Program {
        moves: program.moves[100..101].to_vec(),
        ..program.clone()
    };
    let mut c = Criterion::default().configure_from_args();
    c.bench_function("gouge_one_tangent_move", |b| {
        b.iter(|| black_box(check_program(&surface, &one, &tools, &opts).unwrap()))
    });
    c.final_summary();
}
