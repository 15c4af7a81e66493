//! Allowable-size solvers on a compound surface of 24 bicubic patches (a 6 × 4 mould-like
//! height field with pockets and ribs): time per CC point of the certified solver per cutter
//! family, against the PSO path, and evaluations per point of both; plus one timed map of
//! 10,000 CC points (rayon, all threads) printed before the criterion runs.
//!
//! `cargo bench -p swarf-plan --bench toolsize`

use std::hint::black_box;
use std::time::Instant;

use criterion::{BenchmarkId, Criterion};
use swarf_geom::math::Vec3;
use swarf_plan::size::{
    allowable_certified, allowable_map, allowable_pso, best_lead_tilt, best_rotary_angle,
    Axis4Options, Axis5Options, CertifiedOptions, Contact, CutterFamily, LeadTiltFrame, MapOptions,
    PreparedSurface, PsoOptions,
};
use swarf_plan::{CcPoint, CompoundSurface, NurbsSurface, Patch, Surface, Tolerances};

/// The height field: two pockets, a rib and a gentle wave (mm).
fn height(x: f64, y: f64) -> f64 {
    let pocket = |cx: f64, cy: f64, r: f64, d: f64| {
        let q = ((x - cx).powi(2) + (y - cy).powi(2)) / (r * r);
        -d * (-q).exp()
    };
    8.0 + pocket(20.0, 15.0, 9.0, 6.0)
        + pocket(45.0, 25.0, 7.0, 5.0)
        + 4.0 * (-((x - 33.0) / 2.5).powi(2)).exp()
        + 0.8 * (x / 9.0).sin() * (y / 7.0).cos()
}

/// 6 × 4 patches of 10 × 10 mm, each a bicubic Bézier through the height field.
fn mould() -> CompoundSurface {
    let knots = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
    let mut patches = Vec::new();
    for a in 0..6 {
        for b in 0..4 {
            let (x0, y0) = (10.0 * a as f64, 10.0 * b as f64);
            let pts: Vec<Vec<Vec3>> = (0..4)
                .map(|i| {
                    (0..4)
                        .map(|j| {
                            let (x, y) = (x0 + 10.0 * i as f64 / 3.0, y0 + 10.0 * j as f64 / 3.0);
                            Vec3::new(x, y, height(x, y))
                        })
                        .collect()
                })
                .collect();
            let s = NurbsSurface::new(3, 3, knots.clone(), knots.clone(), &pts, None).unwrap();
            patches.push(Patch::new(Surface::Nurbs(s)));
        }
    }
    CompoundSurface::new(patches)
}

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
    // 24 patches × 21² = 10,584 CC points, rayon over all threads.
    let ccs = part.grid(21);
    for (name, f) in families() {
        let t = Instant::now();
        let map = allowable_map(part, &f, &ccs, &MapOptions::default());
        let s = map.summary();
        let uncertified = map
            .points
            .iter()
            .filter(|p| p.size.is_some_and(|a| !a.certified))
            .count();
        println!(
            "map of {} points ({name}, certified, {} threads): {:.2} s, {:.0} evaluations/point, {uncertified} uncertified, radius {:?}..{:?} mm",
            s.points,
            rayon::current_num_threads(),
            t.elapsed().as_secs_f64(),
            s.evaluations_per_point,
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
    let part = mould();
    report(&part);
    let mut c = Criterion::default().configure_from_args();
    bench(&mut c, &part);
    bench_orientation(&mut c, &part);
    c.final_summary();
}
