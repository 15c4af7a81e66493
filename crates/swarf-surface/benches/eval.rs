//! Evaluation throughput on NURBS patches: point + first and second derivatives, and the full
//! local geometry (normal + principal curvatures), parameterised by degree.

use criterion::{criterion_main, BenchmarkId, Criterion, Throughput};
use std::hint::black_box;
use swarf_geom::math::Vec3;
use swarf_surface::{NurbsSurface, ParametricSurface, Patch, Surface, Tolerances};

/// A wavy `n × n` patch of degree `p` in both directions, clamped uniform knots.
fn patch(p: usize, n: usize) -> NurbsSurface {
    let knots = |n: usize| {
        let inner = n - p;
        let mut k = vec![0.0; p + 1];
        k.extend((1..inner).map(|i| i as f64 / inner as f64));
        k.extend(vec![1.0; p + 1]);
        k
    };
    let pts: Vec<Vec<Vec3>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| {
                    let (x, y) = (i as f64 * 10.0, j as f64 * 10.0);
                    Vec3::new(x, y, 5.0 * (0.3 * x).sin() * (0.2 * y).cos())
                })
                .collect()
        })
        .collect();
    let w: Vec<Vec<f64>> = (0..n)
        .map(|i| (0..n).map(|j| 1.0 + 0.1 * ((i + j) % 3) as f64).collect())
        .collect();
    NurbsSurface::new(p, p, knots(n), knots(n), &pts, Some(&w)).unwrap()
}

fn bench(c: &mut Criterion) {
    const N: usize = 1000;
    let params: Vec<(f64, f64)> = (0..N)
        .map(|k| {
            let t = k as f64 / N as f64;
            (t, (t * 7.31).fract())
        })
        .collect();
    let tol = Tolerances::DEFAULT;
    let mut g = c.benchmark_group("rational_nurbs_10x10");
    g.throughput(Throughput::Elements(N as u64));
    for p in [1usize, 3, 5] {
        let patch = Patch::new(Surface::Nurbs(patch(p, 10)));
        g.bench_with_input(BenchmarkId::new("derivs", p), &patch, |b, s| {
            b.iter(|| {
                let mut acc = Vec3::ZERO;
                for &(u, v) in &params {
                    acc += s.surface.derivs(u, v).suv;
                }
                black_box(acc)
            })
        });
        g.bench_with_input(BenchmarkId::new("local_geometry", p), &patch, |b, s| {
            b.iter(|| {
                let mut acc = 0.0;
                for &(u, v) in &params {
                    acc += s.local(u, v, &tol).curvature.map_or(0.0, |c| c.k1);
                }
                black_box(acc)
            })
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
