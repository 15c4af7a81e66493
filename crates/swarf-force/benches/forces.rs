//! Force benchmark: every cutter location of the finishing program (10 mm ball end mill, 2
//! flutes, 30° helix; one location per move, h = 0.1 mm), forces at 360 samples per revolution,
//! against the engagement that feeds them.
//!
//! `SWARF_BENCH_REPORT_ONLY=1 cargo bench -p swarf-force --bench forces` prints the report
//! alone: medians of 3 runs, µs per location and the ratio forces / engagement (the target is
//! < 1); `SWARF_BENCH_MOVES=N` sets the moves (default 3000). Without it, criterion also times
//! the forces of 300 locations.

use std::time::Instant;

use criterion::{criterion_main, Criterion};
use rayon::prelude::*;
use swarf_engage::bench::{finishing_program as program, median};
use swarf_engage::{EngageOptions, Engagement, Engager};
use swarf_force::{CoefficientSource, Coefficients, ForceModel, Material};
use swarf_geom::math::Vec3;
use swarf_path::Program;
use swarf_stock::TriDexel;
use swarf_tool::{Cutter, ToolSet};

fn tools() -> ToolSet {
    ToolSet::single(Cutter::from_spec("ball:d=10,flutes=2,helix=30").unwrap())
}

fn opts() -> EngageOptions {
    EngageOptions::default().with_step(0.0)
}

fn engage(p: &Program) -> (f64, Vec<Engagement>) {
    let mut s = TriDexel::from_box(Vec3::ZERO, Vec3::new(120.0, 120.0, 50.0), 0.1).unwrap();
    let t = Instant::now();
    let tools = tools();
    let all: Vec<Engagement> = Engager::new(p, &tools, &mut s, opts())
        .unwrap()
        .map(Result::unwrap)
        .collect();
    (t.elapsed().as_secs_f64(), all)
}

fn model() -> ForceModel {
    let m = Material {
        name: "bench".into(),
        coefficients: CoefficientSource::Fixed(Coefficients {
            ktc: 796.0,
            krc: 168.8,
            kac: 222.0,
            kte: 27.7,
            kre: 30.8,
            kae: 1.8,
        }),
        source: "bench".into(),
    };
    ForceModel::new(m, &tools(), &[0], &opts(), 360).unwrap()
}

/// Forces at every location, in parallel as `swarf forces` computes them.
fn forces(model: &ForceModel, all: &[Engagement]) -> (f64, f64) {
    let t = Instant::now();
    let peak = all
        .par_iter()
        .map(|e| model.forces(&model.evaluate(e), None).0.peak_resultant_n)
        .reduce(|| 0.0, f64::max);
    (t.elapsed().as_secs_f64(), peak)
}

fn report() {
    let n: usize = std::env::var("SWARF_BENCH_MOVES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3000);
    let p = program(n);
    let m = model();
    let mut eng = Vec::new();
    let mut frc = Vec::new();
    let mut engaged = 0;
    let mut peak = 0.0;
    for _ in 0..3 {
        let (te, all) = engage(&p);
        engaged = all.iter().filter(|e| e.is_engaged()).count();
        let (tf, pk) = forces(&m, &all);
        eng.push(te);
        frc.push(tf);
        peak = pk;
    }
    let (eng, frc) = (median(eng), median(frc));
    let locs = p.moves.len();
    println!("forces bench: {locs} moves, {engaged} engaged locations, 360 samples/rev, peak {peak:.1} N");
    println!(
        "  engagement median {eng:.3} s  ({:.1} µs/location)",
        eng / locs as f64 * 1e6
    );
    println!(
        "  forces     median {frc:.3} s  ({:.1} µs/location, {:.1} µs/engaged location)",
        frc / locs as f64 * 1e6,
        frc / engaged.max(1) as f64 * 1e6
    );
    println!("  ratio forces / engagement: {:.3}", frc / eng);
}

fn bench(c: &mut Criterion) {
    let p = program(300);
    let (_, all) = engage(&p);
    let m = model();
    let mut g = c.benchmark_group("finish300");
    g.sample_size(10);
    g.bench_function("forces", |b| b.iter(|| forces(&m, &all)));
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
