//! Cutter ray intersections per second, by cutter shape (the torus corner needs the quartic).

use criterion::{criterion_main, BenchmarkId, Criterion, Throughput};
use swarf_geom::math::Vec3;
use swarf_geom::Ray;
use swarf_tool::Cutter;

fn rays(n: usize, r: f64, h: f64) -> Vec<Ray> {
    // Deterministic spread of rays through the cutter's bounding box, in all directions.
    (0..n)
        .map(|i| {
            let a = i as f64 * 2.399_963; // golden angle
            let z = h * ((i * 7919) % n) as f64 / n as f64;
            let target = Vec3::new(0.5 * r * a.cos(), 0.5 * r * a.sin(), z);
            let dir = Vec3::new(a.cos(), a.sin(), (a * 0.7).sin() * 0.5).normalize();
            Ray::new(target - dir * 3.0 * (r + h), dir)
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let n = 1024;
    let mut group = c.benchmark_group("cutter_ray_intersections");
    group.throughput(Throughput::Elements(n as u64));
    for spec in [
        "flat:d=12",
        "ball:d=10",
        "bull:d=16,r=2",
        "taper-ball:d=6,taper=3",
        "drill:d=8",
    ] {
        let cutter = Cutter::from_spec(spec).unwrap();
        let rs = rays(n, cutter.max_diameter() / 2.0, cutter.apt_params().h);
        let mut out = Vec::with_capacity(16);
        group.bench_with_input(BenchmarkId::from_parameter(spec), &rs, |b, rs| {
            b.iter(|| {
                let mut count = 0;
                for ray in rs {
                    out.clear();
                    cutter.ray_intersections(ray, &mut out);
                    count += out.len();
                }
                count
            })
        });
    }
    group.finish();
}

// criterion_group! generates an undocumented public function.
#[allow(missing_docs)]
mod group {
    criterion::criterion_group!(benches, super::bench);
}
criterion_main!(group::benches);
