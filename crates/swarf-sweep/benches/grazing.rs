//! Grazing-curve evaluation (points per second, by samples per piece).

use criterion::{criterion_main, BenchmarkId, Criterion, Throughput};
use swarf_geom::math::Vec3;
use swarf_sweep::fold::whole_tool_pieces;
use swarf_sweep::{grazing_points, MotionState};
use swarf_tool::Cutter;

fn grazing(c: &mut Criterion) {
    let mut g = c.benchmark_group("grazing_points");
    let cutter = Cutter::bull(10.0, 2.0).unwrap();
    let pieces = whole_tool_pieces(&cutter);
    let st = MotionState::new(
        Vec3::new(1.0, 2.0, 3.0),
        Vec3::new(0.2, 0.1, 1.0),
        Vec3::new(30.0, -10.0, -5.0),
        Vec3::new(0.1, -0.3, 0.05),
    );
    for samples in [16usize, 64, 256] {
        let n = grazing_points(&pieces, &st, samples).points.len();
        g.throughput(Throughput::Elements(n as u64));
        g.bench_with_input(
            BenchmarkId::new("bull_5axis", samples),
            &samples,
            |b, &s| b.iter(|| grazing_points(&pieces, &st, s)),
        );
    }
    g.finish();
}

#[allow(missing_docs)]
mod group {
    criterion::criterion_group!(benches, super::grazing);
}
criterion_main!(group::benches);
