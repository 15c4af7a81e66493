//! Building a trim's cell grid, parameterised by the number of edges: a star of long spikes
//! across the whole box (every edge long, the hostile case of a quadratic build). The time grows
//! linearly with the edges' length in cells; the unit test `many_long_edges_build_in_linear_time`
//! asserts the count behind it.

use criterion::{criterion_main, BenchmarkId, Criterion, Throughput};
use std::hint::black_box;
use swarf_surface::{ParamBox, Trim};

fn star(spikes: usize) -> Vec<[f64; 2]> {
    (0..spikes)
        .map(|k| {
            let a = k as f64 / spikes as f64 * std::f64::consts::TAU;
            let r = if k % 2 == 0 { 0.5 } else { 0.01 };
            [0.5 + r * a.cos(), 0.5 + r * a.sin()]
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let unit = ParamBox::new(0.0, 1.0, 0.0, 1.0);
    let mut g = c.benchmark_group("trim_build_star");
    g.sample_size(10);
    for spikes in [2_500usize, 10_000, 40_000] {
        let pts = star(spikes);
        g.throughput(Throughput::Elements(spikes as u64));
        g.bench_with_input(BenchmarkId::from_parameter(spikes), &pts, |b, pts| {
            b.iter(|| black_box(Trim::new(&unit, Some(pts.clone()), vec![]).unwrap()))
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
