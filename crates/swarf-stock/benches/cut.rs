//! Finishing benchmark: short moves (about 0.5 mm) of a 10 mm ball end mill over a wavy
//! surface in a 120 × 120 × 50 mm stock at h = 0.1 mm, all three ray families cut exactly.
//!
//! `cargo bench -p swarf-stock --bench cut` runs the criterion groups; with
//! `SWARF_BENCH_REPORT=1` it first prints a one-shot report (moves/s, ray-interval updates/s,
//! extrapolation to 50,000 moves, peak memory from `/proc/self/status` VmHWM).

use criterion::{criterion_main, BenchmarkId, Criterion, Throughput};
use std::time::Instant;
use swarf_geom::math::Vec3;
use swarf_stock::{ConvexProfile, CutStats, SweptConvex, ToolShape, TriDexel};
use swarf_tool::Cutter;

/// Height of the wavy finishing surface (tip of the ball), mm.
fn surface(x: f64, y: f64) -> f64 {
    40.0 + 3.0 * (x / 12.0).sin() * (y / 15.0).cos()
}

/// Zig-zag raster over the surface: passes along X spaced `step_over` apart, points every
/// `seg` mm; returns the tip positions.
fn finishing_path(n_moves: usize, seg: f64, step_over: f64) -> Vec<Vec3> {
    let mut pts = Vec::with_capacity(n_moves + 1);
    let (x0, x1) = (5.0, 115.0);
    let per_pass = ((x1 - x0) / seg) as usize;
    let mut y = 5.0;
    let mut pass = 0;
    while pts.len() <= n_moves {
        for i in 0..=per_pass {
            let t = i as f64 * seg;
            let x = if pass % 2 == 0 { x0 + t } else { x1 - t };
            pts.push(Vec3::new(x, y, surface(x, y)));
            if pts.len() > n_moves {
                break;
            }
        }
        y += step_over;
        pass += 1;
        if y > 115.0 {
            y = 5.0;
        }
    }
    pts
}

fn vm_hwm_kib() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// Runs the moves; returns the summed statistics.
fn run(stock: &mut TriDexel, tool: &ToolShape, pts: &[Vec3]) -> CutStats {
    let mut st = CutStats::default();
    for w in pts.windows(2) {
        let c = stock.cut_linear(tool, w[0], w[1], Vec3::Z);
        st = st.merged(c.cutting).merged(c.non_cutting);
    }
    st
}

fn new_stock(h: f64) -> TriDexel {
    TriDexel::from_box(Vec3::ZERO, Vec3::new(120.0, 120.0, 50.0), h).unwrap()
}

fn report() {
    let h = 0.1;
    let n = 3000;
    let t = Instant::now();
    let mut stock = new_stock(h);
    let build = t.elapsed().as_secs_f64();
    let tool = ToolShape::new(&Cutter::ball(10.0).unwrap());
    let pts = finishing_path(n, 0.5, 0.5);
    // Warm-up pass: the first moves of a finishing program on a raw block cut deep; measure
    // a second pass over the same path too (steady-state finishing).
    let t = Instant::now();
    let upd = run(&mut stock, &tool, &pts);
    let first = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let upd2 = run(&mut stock, &tool, &pts);
    let second = t.elapsed().as_secs_f64();
    let st = stock.stats();
    println!(
        "finishing bench: stock 120x120x50 mm, h = {h} mm, ball d = 10 mm, {n} moves of 0.5 mm"
    );
    println!(
        "  build {build:.3} s; rays {}, intervals {}, {:.1} bytes/interval, {:.1} MB",
        st.rays,
        st.intervals,
        st.bytes_per_interval,
        st.bytes as f64 / 1e6
    );
    for (name, secs, st) in [
        ("first pass (raw block)", first, upd),
        ("second pass (same path)", second, upd2),
    ] {
        let per = |a: [u64; 3]| a.map(|x| (x as f64 / n as f64).round() as u64);
        println!(
            "  {name}: {secs:.3} s, {:.0} moves/s, {:.3e} ray-interval updates/s, 50,000 moves ≈ {:.1} s",
            n as f64 / secs,
            st.updates as f64 / secs,
            secs / n as f64 * 50_000.0
        );
        println!(
            "    per move, X/Y/Z families: rays visited {:?}, exact queries {:?}, rays updated {:?}",
            per(st.visited_per_family),
            per(st.tested_per_family),
            per(st.updates_per_family)
        );
    }
    if let Some(k) = vm_hwm_kib() {
        println!("  peak memory (VmHWM): {:.1} MB", k as f64 / 1024.0);
    }
}

/// The exact-interval kernel alone: 10,000 parallel lines along X, Y or Z through a 0.5 mm
/// finishing move of a Ø10 ball (no pruning: every piece is evaluated).
fn bench_kernel(c: &mut Criterion) {
    let cutter = Cutter::ball(10.0).unwrap();
    let prof = ConvexProfile::from_solid(cutter.cutting_solid()).unwrap();
    let sw = SweptConvex::new(
        &prof,
        Vec3::new(50.0, 50.0, 40.0),
        Vec3::Z,
        Vec3::new(0.5, 0.0, 0.02),
    );
    let mut g = c.benchmark_group("line_interval_ball10");
    g.throughput(Throughput::Elements(10_000));
    for (k, name) in ["x", "y", "z"].iter().enumerate() {
        let origins: Vec<Vec3> = (0..10_000)
            .map(|n| {
                let (a, b) = (0.105 * (n % 100) as f64, 0.1 * (n / 100) as f64);
                let mut o = Vec3::new(45.0 + a, 45.0 + b, 40.0 + b);
                o[k] = 0.0;
                if k == 2 {
                    o.y = 45.0 + b;
                }
                o
            })
            .collect();
        g.bench_with_input(BenchmarkId::new("family", name), &k, |bch, &k| {
            bch.iter(|| {
                let mut lb = sw.lines(Vec3::AXES[k]);
                origins.iter().filter_map(|&o| lb.interval(o)).count()
            })
        });
    }
    g.finish();
}

fn bench(c: &mut Criterion) {
    bench_kernel(c);
    if std::env::var_os("SWARF_BENCH_REPORT").is_some() {
        report();
    }
    let tool = ToolShape::new(&Cutter::ball(10.0).unwrap());
    let mut g = c.benchmark_group("finishing_ball10");
    g.sample_size(10);
    for &h in &[0.2, 0.1] {
        let pts = finishing_path(500, 0.5, 0.5);
        let base = new_stock(h);
        g.bench_with_input(BenchmarkId::new("500_moves_h", h), &h, |b, _| {
            b.iter_batched_ref(
                || base.clone(),
                |s| run(s, &tool, &pts).updates,
                criterion::BatchSize::LargeInput,
            )
        });
    }
    g.finish();
}

// criterion_group! generates an undocumented public function.
#[allow(missing_docs)]
mod group {
    criterion::criterion_group!(benches, super::bench);
}
criterion_main!(group::benches);
