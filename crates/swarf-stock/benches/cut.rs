//! Finishing benchmark: short moves (about 0.5 mm) of a 10 mm ball end mill over a wavy
//! surface in a 120 × 120 × 50 mm stock at h = 0.1 mm, all three ray families cut exactly.
//!
//! `cargo bench -p swarf-stock --bench cut` runs the criterion groups (the exact kernel per
//! family, 500 finishing moves at two resolutions, the scaling with h and with the program's
//! length, the exact kernel against the brute-force reference); with `SWARF_BENCH_REPORT=1` it
//! first prints a one-shot report (moves/s, ray-interval updates/s, CPU time, extrapolation to
//! 50,000 moves, peak memory from `/proc/self/status` VmHWM, the scaling table, the ratio to
//! the brute-force reference). `SWARF_BENCH_REPORT_ONLY=1` prints the report alone;
//! `SWARF_BENCH_PROVENANCE=1` makes its stock keep the provenance of every interval end;
//! `SWARF_BENCH_EXHAUSTIVE=1` turns the front test off (`TriDexel::set_exhaustive`);
//! `SWARF_BENCH_MOVES=N` sets its number of moves (default 3000) and leaves out the
//! scaling table and the brute-force comparison; `SWARF_BENCH_H=0.05` sets the report's ray
//! spacing (default 0.1 mm). `RAYON_NUM_THREADS` sets the threads.

use criterion::{criterion_main, BenchmarkId, Criterion, Throughput};
use std::time::Instant;
use swarf_geom::math::Vec3;
use swarf_geom::{Frame, Ray};
use swarf_stock::{CutStats, LinearMove, TriDexel};
use swarf_sweep::{ConvexProfile, SweptConvex, ToolShape};
use swarf_tool::Cutter;

/// Height of the wavy finishing surface (tip of the ball), mm.
fn surface(x: f64, y: f64) -> f64 {
    40.0 + 3.0 * (x / 12.0).sin() * (y / 15.0).cos()
}

/// Zig-zag raster over the surface: passes along X spaced `step_over` apart, points every
/// `seg` mm, over a square stock of side `side` (5 mm margins); returns the tip positions.
fn finishing_path(n_moves: usize, seg: f64, step_over: f64) -> Vec<Vec3> {
    raster(n_moves, seg, step_over, 120.0)
}

fn raster(n_moves: usize, seg: f64, step_over: f64, side: f64) -> Vec<Vec3> {
    let mut pts = Vec::with_capacity(n_moves + 1);
    let (x0, x1) = (5.0, side - 5.0);
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
        if y > side - 5.0 {
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

/// Process CPU time (user + system, all threads), s, from `/proc/self/stat` (clock ticks
/// of 10 ms); `None` off Linux.
fn cpu_s() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/self/stat").ok()?;
    let rest = &s[s.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

/// Runs the moves (one batched call, as `simulate` does); returns the summed statistics.
fn run(stock: &mut TriDexel, tool: &ToolShape, pts: &[Vec3]) -> CutStats {
    stock
        .cut_linear_batch(tool, &LinearMove::chain(pts, Vec3::Z))
        .into_iter()
        .fold(CutStats::default(), |st, c| {
            st.merged(c.cutting).merged(c.non_cutting)
        })
}

fn new_stock(h: f64) -> TriDexel {
    TriDexel::from_box(Vec3::ZERO, Vec3::new(120.0, 120.0, 50.0), h).unwrap()
}

fn report() {
    if let Some(p) = swarf_testdata::host::probe_unless_asked_not_to() {
        println!("{p}");
    }
    let h: f64 = std::env::var("SWARF_BENCH_H")
        .ok()
        .and_then(|s| s.parse().ok())
        .filter(|h: &f64| *h >= 0.02 && *h <= 1.0)
        .unwrap_or(0.1);
    let n: usize = std::env::var("SWARF_BENCH_MOVES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3000);
    let provenance = std::env::var_os("SWARF_BENCH_PROVENANCE").is_some();
    let t = Instant::now();
    let mut stock = new_stock(h);
    stock.set_exhaustive(std::env::var_os("SWARF_BENCH_EXHAUSTIVE").is_some());
    if provenance {
        stock.track_provenance();
    }
    let build = t.elapsed().as_secs_f64();
    let tool = ToolShape::new(&Cutter::ball(10.0).unwrap());
    let pts = finishing_path(n, 0.5, 0.5);
    // Warm-up pass: the first moves of a finishing program on a raw block cut deep; measure
    // a second pass over the same path too (steady-state finishing).
    let (t, c) = (Instant::now(), cpu_s());
    let upd = run(&mut stock, &tool, &pts);
    let (first, cpu1) = (
        t.elapsed().as_secs_f64(),
        cpu_s().zip(c).map(|(a, b)| a - b),
    );
    let (t, c) = (Instant::now(), cpu_s());
    let upd2 = run(&mut stock, &tool, &pts);
    let (second, cpu2) = (
        t.elapsed().as_secs_f64(),
        cpu_s().zip(c).map(|(a, b)| a - b),
    );
    let st = stock.stats();
    println!(
        "finishing bench: stock 120x120x50 mm, h = {h} mm, ball d = 10 mm, {n} moves of 0.5 mm{}",
        if provenance {
            ", provenance tracked"
        } else {
            ""
        }
    );
    println!(
        "  build {build:.3} s; rays {}, intervals {}, {:.1} bytes/interval, {:.1} MB",
        st.rays,
        st.intervals,
        st.bytes_per_interval,
        st.bytes as f64 / 1e6
    );
    for (name, secs, cpu, st) in [
        ("first pass (raw block)", first, cpu1, upd),
        ("second pass (same path)", second, cpu2, upd2),
    ] {
        let per = |a: [u64; 3]| a.map(|x| (x as f64 / n as f64).round() as u64);
        println!(
            "  {name}: {secs:.3} s, {:.0} moves/s, {:.3e} ray-interval updates/s, 50,000 moves ≈ {:.1} s",
            n as f64 / secs,
            st.updates as f64 / secs,
            secs / n as f64 * 50_000.0
        );
        if let Some(c) = cpu {
            println!(
                "    CPU {c:.2} s on {} threads ({:.2} cores busy)",
                rayon::current_num_threads(),
                c / secs
            );
        }
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
    if std::env::var_os("SWARF_BENCH_MOVES").is_none() {
        scaling_report();
        brute_force_report();
    }
}

/// A 40 × 40 × 50 mm block for the scaling runs (small enough for h = 0.05 mm).
const SCALE_SIDE: f64 = 40.0;

/// Runs of each scaling row; the median is printed.
const SCALING_RUNS: usize = 3;

/// One scaling run: a fresh block at `h`, `n` raster moves; (wall s, CPU s, stats).
fn scaling_run(h: f64, n: usize) -> (f64, Option<f64>, CutStats) {
    let mut stock =
        TriDexel::from_box(Vec3::ZERO, Vec3::new(SCALE_SIDE, SCALE_SIDE, 50.0), h).unwrap();
    let tool = ToolShape::new(&Cutter::ball(10.0).unwrap());
    let pts = raster(n, 0.5, 0.5, SCALE_SIDE);
    let (t, c) = (Instant::now(), cpu_s());
    let st = run(&mut stock, &tool, &pts);
    (
        t.elapsed().as_secs_f64(),
        cpu_s().zip(c).map(|(a, b)| a - b),
        st,
    )
}

/// How the time grows when h halves and when the program doubles, against the work touched.
fn scaling_report() {
    println!(
        "scaling: {SCALE_SIDE} x {SCALE_SIDE} x 50 mm block, ball d = 10 mm, 0.5 mm moves, median of {SCALING_RUNS} runs"
    );
    println!(
        "  {:>6} {:>6} {:>9} {:>9} {:>12} {:>12} {:>12}",
        "h", "moves", "wall s", "CPU s", "ray visits", "updates", "ns/visit"
    );
    for (h, n) in [(0.2, 400), (0.1, 400), (0.05, 400), (0.1, 800), (0.1, 1600)] {
        // The median of three runs (by wall time): single runs of a tenth of a second vary
        // by tens of per cent on a shared machine.
        let mut runs: Vec<_> = (0..SCALING_RUNS).map(|_| scaling_run(h, n)).collect();
        runs.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (wall, cpu, st) = runs.swap_remove(SCALING_RUNS / 2);
        let visits: u64 = st.visited_per_family.iter().sum();
        println!(
            "  {h:>6} {n:>6} {wall:>9.3} {:>9.2} {visits:>12} {:>12} {:>12.1}",
            cpu.unwrap_or(f64::NAN),
            st.updates,
            wall * 1e9 / visits as f64
        );
    }
}

/// The rays of the three families at spacing `h` through the bounding box of `sw`, as
/// `(origin, axis)`.
fn rays_through(sw: &SweptConvex<'_>, h: f64) -> Vec<(Vec3, usize)> {
    let bb = sw.bbox();
    let mut out = Vec::new();
    for k in 0..3 {
        let (u, v) = ((k + 1) % 3, (k + 2) % 3);
        let cells = |a: usize| {
            let (lo, hi) = (
                (bb.min[a] / h).floor() as i64,
                (bb.max[a] / h).ceil() as i64,
            );
            (lo..=hi).map(move |i| (i as f64 + 0.5) * h)
        };
        for cu in cells(u) {
            for cv in cells(v) {
                let mut o = Vec3::ZERO;
                o[u] = cu;
                o[v] = cv;
                out.push((o, k));
            }
        }
    }
    out
}

/// The brute-force reference of `tests/brute_force_reference.rs`: the union of the ray's
/// intersections with `samples + 1` tool instances along the move.
fn brute_force(
    cutter: &Cutter,
    tip: Vec3,
    delta: Vec3,
    o: Vec3,
    k: usize,
    samples: usize,
    hits: &mut Vec<f64>,
) -> Option<(f64, f64)> {
    let frame = Frame::from_axis(Vec3::ZERO, Vec3::Z);
    let dir = Vec3::AXES[k];
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..=samples {
        let t = tip + delta * (i as f64 / samples as f64);
        let ray = Ray::new(frame.vector_to_local(o - t), frame.vector_to_local(dir));
        hits.clear();
        cutter.ray_intersections(&ray, hits);
        if hits.len() >= 2 {
            lo = lo.min(hits[0]);
            hi = hi.max(*hits.last().unwrap());
        }
    }
    (lo <= hi).then_some((lo, hi))
}

/// Exact kernel against the brute-force reference on the same rays (all three families at
/// h = 0.1 mm through one 0.5 mm finishing move of the Ø10 ball), one thread each.
fn brute_force_report() {
    let cutter = Cutter::ball(10.0).unwrap();
    let prof = ConvexProfile::from_solid(cutter.cutting_solid()).unwrap();
    let (tip, delta) = (Vec3::new(50.0, 50.0, 40.0), Vec3::new(0.5, 0.0, 0.02));
    let sw = SweptConvex::new(&prof, tip, Vec3::Z, delta);
    let rays = rays_through(&sw, 0.1);
    let t = Instant::now();
    let mut exact_hits = 0;
    for _ in 0..20 {
        exact_hits = rays
            .iter()
            .filter(|&&(o, k)| sw.axis_ray_interval(o, k).is_some())
            .count();
    }
    let exact = t.elapsed().as_secs_f64() / 20.0;
    let mut hits = Vec::new();
    let samples = 300;
    let t = Instant::now();
    let mut worst: f64 = 0.0;
    for &(o, k) in &rays {
        let b = brute_force(&cutter, tip, delta, o, k, samples, &mut hits);
        if let (Some(b), Some(e)) = (b, sw.axis_ray_interval(o, k)) {
            // The exact interval holds the sampled one.
            worst = worst.max(e.0 - b.0).max(b.1 - e.1);
        }
    }
    let brute = t.elapsed().as_secs_f64();
    println!(
        "vs brute force: {} rays ({exact_hits} hit) through one move; exact {:.1} ns/ray, reference ({samples} tool instances) {:.1} µs/ray: {:.0}x faster (exact holds the sampled union to {worst:.1e} mm)",
        rays.len(),
        exact * 1e9 / rays.len() as f64,
        brute * 1e6 / rays.len() as f64,
        brute / exact
    );
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
    if std::env::var_os("SWARF_BENCH_REPORT_ONLY").is_some() {
        report();
        return;
    }
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
    // How the time grows when h halves and when the program doubles.
    let mut g = c.benchmark_group("scaling_ball10");
    g.sample_size(10);
    for &(h, n) in &[(0.2, 400), (0.1, 400), (0.05, 400), (0.1, 800), (0.1, 1600)] {
        let pts = raster(n, 0.5, 0.5, SCALE_SIDE);
        let base =
            TriDexel::from_box(Vec3::ZERO, Vec3::new(SCALE_SIDE, SCALE_SIDE, 50.0), h).unwrap();
        g.bench_with_input(BenchmarkId::new(format!("h{h}"), n), &n, |b, _| {
            b.iter_batched_ref(
                || base.clone(),
                |s| run(s, &tool, &pts).updates,
                criterion::BatchSize::LargeInput,
            )
        });
    }
    g.finish();
    // The exact kernel against the brute-force reference, per ray.
    let cutter = Cutter::ball(10.0).unwrap();
    let prof = ConvexProfile::from_solid(cutter.cutting_solid()).unwrap();
    let (tip, delta) = (Vec3::new(50.0, 50.0, 40.0), Vec3::new(0.5, 0.0, 0.02));
    let sw = SweptConvex::new(&prof, tip, Vec3::Z, delta);
    let rays: Vec<_> = rays_through(&sw, 0.1).into_iter().step_by(50).collect();
    let mut g = c.benchmark_group("vs_brute_force");
    g.throughput(Throughput::Elements(rays.len() as u64));
    g.bench_function("exact", |b| {
        b.iter(|| {
            rays.iter()
                .filter(|&&(o, k)| sw.axis_ray_interval(o, k).is_some())
                .count()
        })
    });
    g.sample_size(10);
    g.bench_function("brute_force_300", |b| {
        let mut hits = Vec::new();
        b.iter(|| {
            rays.iter()
                .filter(|&&(o, k)| brute_force(&cutter, tip, delta, o, k, 300, &mut hits).is_some())
                .count()
        })
    });
    g.finish();
}

// criterion_group! generates an undocumented public function.
#[allow(missing_docs)]
mod group {
    criterion::criterion_group!(benches, super::bench);
}
criterion_main!(group::benches);
