//! Engagement benchmark: the finishing program of `swarf-stock`'s `cut` bench (a 10 mm ball end
//! mill raster of ~0.5 mm moves over a wavy surface in a 120 × 120 × 50 mm block, h = 0.1 mm),
//! read as G-code, with one cutter location per move (`step` 0), against the plain simulation
//! of the same program.
//!
//! `SWARF_BENCH_REPORT_ONLY=1 cargo bench -p swarf-engage --bench engage` prints the report
//! alone: the median of 3 runs of each (the two alternately), the median of the runs' ratios
//! engagement / simulation, µs per location and the extrapolation to 50,000 moves;
//! `SWARF_BENCH_MOVES=N` sets the moves (default 3000),
//! `SWARF_BENCH_RUNS=N` the runs of each (default 3; 0: the engagement once, no simulation).
//! Without it, criterion also times 300 moves of each.

use criterion::{criterion_main, Criterion};
use std::time::Instant;
use swarf_engage::bench::{finishing_program as program, median};
use swarf_engage::{EngageOptions, Engager};
use swarf_geom::math::Vec3;
use swarf_path::Program;
use swarf_stock::{simulate, SimOptions, TriDexel};
use swarf_tool::{Cutter, ToolSet};

fn stock() -> TriDexel {
    TriDexel::from_box(Vec3::ZERO, Vec3::new(120.0, 120.0, 50.0), 0.1).unwrap()
}

fn simulate_once(p: &Program) -> f64 {
    let mut s = stock();
    let t = Instant::now();
    let tools = ToolSet::single(Cutter::ball(10.0).unwrap());
    simulate(p, &tools, &mut s, &SimOptions::default()).unwrap();
    t.elapsed().as_secs_f64()
}

/// (wall s, engaged locations, cutting s, stock probes, sum of the engaged areas in mm²).
fn engage_once(p: &Program) -> (f64, usize, f64, u64, f64) {
    let mut s = stock();
    let t = Instant::now();
    let tools = ToolSet::single(Cutter::ball(10.0).unwrap());
    let opts = EngageOptions::default().with_step(0.0);
    let mut run = Engager::new(p, &tools, &mut s, opts).unwrap();
    let (mut n, mut area) = (0, 0.0);
    for e in run.by_ref().map(Result::unwrap) {
        n += usize::from(e.is_engaged());
        area += e.area_mm2;
    }
    let st = run.stats();
    (
        t.elapsed().as_secs_f64(),
        n,
        st.simulate_elapsed_s,
        st.probes,
        area,
    )
}

fn report() {
    if let Some(p) = swarf_testdata::host::probe_unless_asked_not_to() {
        println!("{p}");
    }
    let n: usize = std::env::var("SWARF_BENCH_MOVES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3000);
    // Runs of each (median reported); `SWARF_BENCH_RUNS=0` skips the simulation and runs the
    // engagement once (for instruction counts of the engagement alone).
    let reps: usize = std::env::var("SWARF_BENCH_RUNS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3);
    let p = program(n);
    // The simulation and the engagement alternately, so that a machine whose speed drifts
    // during the run weighs on both alike; the ratio is the median of the runs' ratios.
    let mut sims = Vec::new();
    let mut runs: Vec<(f64, usize, f64, u64, f64)> = Vec::new();
    for _ in 0..reps.max(1) {
        if reps > 0 {
            sims.push(simulate_once(&p));
        }
        runs.push(engage_once(&p));
    }
    let (sim, ratio) = if reps == 0 {
        (f64::NAN, f64::NAN)
    } else {
        let ratios = sims.iter().zip(&runs).map(|(s, r)| r.0 / s).collect();
        (median(sims), median(ratios))
    };
    let (engaged, probes, area) = (runs[0].1, runs[0].3, runs[0].4);
    let cutting = median(runs.iter().map(|r| r.2).collect());
    let eng = median(runs.into_iter().map(|r| r.0).collect());
    let moves = p.moves.len();
    println!(
        "engage bench: {moves} moves, {engaged} engaged locations, h = 0.1 mm, {} threads",
        rayon_threads()
    );
    if reps > 0 {
        println!(
            "  simulate   median {sim:.3} s  ({:.1} µs/move, {:.1} s per 50,000)",
            sim / moves as f64 * 1e6,
            sim / moves as f64 * 5e4
        );
    }
    println!(
        "  engagement median {eng:.3} s  ({:.1} µs/location, {:.1} s per 50,000)",
        eng / moves as f64 * 1e6,
        eng / moves as f64 * 5e4
    );
    println!(
        "    of which cutting the stock {cutting:.3} s; {:.0} stock probes per location, \
         {:.0} ns per probe (wall, all threads)",
        probes as f64 / moves as f64,
        (eng - cutting) * 1e9 / probes.max(1) as f64
    );
    println!("  sum of the engaged areas {area:.10} mm² (a check that a change kept the results)");
    if reps > 0 {
        println!("  ratio engagement / simulation: {ratio:.2} (median of the runs' ratios)");
    }
}

fn rayon_threads() -> String {
    std::env::var("RAYON_NUM_THREADS").unwrap_or_else(|_| "all".into())
}

fn bench(c: &mut Criterion) {
    let p = program(300);
    let mut g = c.benchmark_group("finish300");
    g.sample_size(10);
    g.bench_function("simulate", |b| b.iter(|| simulate_once(&p)));
    g.bench_function("engage", |b| b.iter(|| engage_once(&p)));
    g.finish();
}

fn benches() {
    report();
    if std::env::var_os("SWARF_BENCH_REPORT_ONLY").is_some() {
        return;
    }
    let mut c = Criterion::default().configure_from_args();
    bench(&mut c);
    c.final_summary();
}

criterion_main!(benches);
