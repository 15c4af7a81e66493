//! Allowable-size solvers on a compound surface of 24 bicubic patches (a 6 × 4 mould-like
//! height field with pockets and ribs): time per CC point of the certified solver per cutter
//! family, against the PSO path, and evaluations per point of both; plus one timed map of
//! 10,000 CC points (rayon, all threads) printed before the criterion runs.
//!
//! `cargo bench -p swarf-plan --bench toolsize`
//!
//! `SWARF_TOOLSIZE_MAP_ONLY=1` prints the timed maps only (no per-point report, no criterion
//! run), with the nodes per point (mean and largest) that explain them, and
//! `SWARF_TOOLSIZE_FAMILY=bull_r2` (or `ball`, `flat`) maps that family only:
//! `SWARF_TOOLSIZE_MAP_ONLY=1 cargo bench -p swarf-plan --bench toolsize`

mod common;

use std::hint::black_box;
use std::time::Instant;

use criterion::{BenchmarkId, Criterion};
use swarf_plan::size::{
    allowable_certified, allowable_map, allowable_pso, best_lead_tilt, best_rotary_angle,
    Axis4Options, Axis5Options, CertifiedOptions, Contact, CutterFamily, LeadTiltFrame, MapOptions,
    PsoOptions,
};
use swarf_surface::PreparedSurface;
use swarf_surface::{CcPoint, CompoundSurface, Tolerances};

fn contacts(part: &CompoundSurface, n: usize) -> Vec<Contact> {
    part.grid(n)
        .iter()
        .filter_map(|cc: &CcPoint| Contact::at(part, cc, &Tolerances::DEFAULT))
        .collect()
}

fn families() -> [(&'static str, CutterFamily); 3] {
    [
        ("ball", CutterFamily::ball()),
        ("flat", CutterFamily::flat()),
        ("bull_r2", CutterFamily::bull(2.0).unwrap()),
    ]
}

fn report(part: &CompoundSurface) {
    if std::env::var_os("SWARF_TOOLSIZE_MAP_ONLY").is_none() {
        report_points(part);
    }
    report_map(part);
}

fn report_points(part: &CompoundSurface) {
    let prep = PreparedSurface::new(part);
    let cs = contacts(part, 5);
    for (name, f) in families() {
        let mut times: Vec<f64> = Vec::new();
        let (mut evals, mut nodes, mut uncertified) = (0u64, 0u64, 0usize);
        for c in &cs {
            let t = Instant::now();
            let a = allowable_certified(&prep, &f, c, &CertifiedOptions::DEFAULT);
            times.push(t.elapsed().as_secs_f64());
            evals += a.evaluations;
            nodes += a.nodes;
            uncertified += usize::from(!a.certified);
        }
        times.sort_by(f64::total_cmp);
        println!(
            "certified {name:8}: median {:.3} ms/point, {:.0} evaluations + {:.0} bounds per point, {uncertified}/{} uncertified",
            1e3 * times[times.len() / 2],
            evals as f64 / cs.len() as f64,
            nodes as f64 / cs.len() as f64,
            cs.len()
        );
    }
    let few = &cs[..cs.len().min(24)];
    let mut evals = 0;
    let t = Instant::now();
    for c in few {
        evals += allowable_pso(part, &CutterFamily::ball(), c, &PsoOptions::DEFAULT).evaluations;
    }
    println!(
        "pso       ball    : {:.3} ms/point, {:.0} evaluations per point",
        1e3 * t.elapsed().as_secs_f64() / few.len() as f64,
        evals as f64 / few.len() as f64
    );
}

fn report_map(part: &CompoundSurface) {
    // 24 patches × 21² = 10,584 CC points, rayon over all threads.
    let ccs = part.grid(21);
    let only = std::env::var("SWARF_TOOLSIZE_FAMILY").ok();
    for (name, f) in families() {
        if only.as_deref().is_some_and(|o| o != name) {
            continue;
        }
        let t = Instant::now();
        let map = allowable_map(part, &f, &ccs, &MapOptions::default());
        let s = map.summary();
        let uncertified = map
            .points
            .iter()
            .filter(|p| p.size.is_some_and(|a| !a.certified))
            .count();
        let nodes: Vec<u64> = map
            .points
            .iter()
            .filter_map(|p| p.size.map(|a| a.nodes))
            .collect();
        println!(
            "map of {} points ({name}, certified, {} threads): {:.2} s, {:.0} evaluations/point, {:.0} bounds/point (max {}), {uncertified} uncertified, radius {:?}..{:?} mm",
            s.points,
            rayon::current_num_threads(),
            t.elapsed().as_secs_f64(),
            s.evaluations_per_point,
            nodes.iter().sum::<u64>() as f64 / nodes.len().max(1) as f64,
            nodes.iter().max().copied().unwrap_or(0),
            s.min_radius_mm,
            s.max_radius_mm
        );
    }
}

fn bench(c: &mut Criterion, part: &CompoundSurface) {
    let prep = PreparedSurface::new(part);
    let cs = contacts(part, 4);
    let mut g = c.benchmark_group("toolsize_per_point");
    for (name, f) in families() {
        g.bench_with_input(BenchmarkId::new("certified", name), &f, |b, f| {
            let mut k = 0;
            b.iter(|| {
                k = (k + 1) % cs.len();
                black_box(allowable_certified(
                    &prep,
                    f,
                    &cs[k],
                    &CertifiedOptions::DEFAULT,
                ))
            });
        });
    }
    g.sample_size(10);
    g.bench_function(BenchmarkId::new("pso", "ball"), |b| {
        let mut k = 0;
        b.iter(|| {
            k = (k + 1) % cs.len();
            black_box(allowable_pso(
                part,
                &CutterFamily::ball(),
                &cs[k],
                &PsoOptions::DEFAULT,
            ))
        });
    });
    g.finish();
}

/// 4-axis (about Y, default search) and 5-axis (±15° lead and tilt, default search) time per CC
/// point: every point is many certified solves (see `Orientation4::solves`).
fn bench_orientation(c: &mut Criterion, part: &CompoundSurface) {
    let prep = PreparedSurface::new(part);
    let pts: Vec<(Contact, LeadTiltFrame)> = part
        .grid(3)
        .iter()
        .filter_map(|cc| {
            let c = Contact::at(part, cc, &Tolerances::DEFAULT)?;
            let su = part.local(cc, &Tolerances::DEFAULT).derivs.su;
            Some((c, LeadTiltFrame::new(c.normal, su)?))
        })
        .collect();
    let mut g = c.benchmark_group("toolsize_orientation_per_point");
    g.sample_size(10);
    for (name, f) in [
        ("ball", CutterFamily::ball()),
        ("flat", CutterFamily::flat()),
    ] {
        g.bench_with_input(BenchmarkId::new("axis4_y", name), &f, |b, f| {
            let mut k = 0;
            b.iter(|| {
                k = (k + 1) % pts.len();
                black_box(best_rotary_angle(
                    &prep,
                    f,
                    &pts[k].0,
                    &Axis4Options::DEFAULT,
                ))
            });
        });
        g.bench_with_input(BenchmarkId::new("axis5_15x15", name), &f, |b, f| {
            let mut k = 0;
            b.iter(|| {
                k = (k + 1) % pts.len();
                let (c, frame) = &pts[k];
                black_box(best_lead_tilt(&prep, f, c, frame, &Axis5Options::DEFAULT))
            });
        });
    }
    g.finish();
}

fn main() {
    let part = common::mould();
    report(&part);
    if std::env::var_os("SWARF_TOOLSIZE_MAP_ONLY").is_some() {
        return;
    }
    let mut c = Criterion::default().configure_from_args();
    bench(&mut c, &part);
    bench_orientation(&mut c, &part);
    c.final_summary();
}
