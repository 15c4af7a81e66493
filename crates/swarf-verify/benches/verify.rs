//! Verification time: every ray end of a 120 × 120 × 50 mm stock compared with a closed design
//! mesh, at three resolutions (`BenchmarkId` = h in mm). Two cases: `clean` (the stock is the
//! design but for a 0.005 mm skin on top: every end is projected, none is a defect) and
//! `all_excess` (the design is inset by 5 mm on five sides: every end of the stock's sides and
//! top is an excess end, grouped into one region, with the Z-ray volumes).
//!
//! `cargo bench -p swarf-verify --bench verify`

use criterion::{criterion_main, BenchmarkId, Criterion};
use swarf_geom::math::Vec3;
use swarf_stock::TriDexel;
use swarf_verify::{box_mesh, verify, MeshDesign, VerifyOptions};

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("verify");
    g.sample_size(10);
    let clean = MeshDesign::new(&box_mesh(Vec3::ZERO, Vec3::new(120.0, 120.0, 49.995))).unwrap();
    let inset = MeshDesign::new(&box_mesh(
        Vec3::new(5.0, 5.0, 0.0),
        Vec3::new(115.0, 115.0, 45.0),
    ))
    .unwrap();
    for h in [1.0, 0.5, 0.25] {
        let stock = TriDexel::from_box(Vec3::ZERO, Vec3::new(120.0, 120.0, 50.0), h).unwrap();
        for (name, design) in [("clean", &clean), ("all_excess", &inset)] {
            g.bench_with_input(BenchmarkId::new(name, h), &h, |b, _| {
                b.iter(|| verify(&stock, design, None, &VerifyOptions::default()).unwrap())
            });
        }
    }
    g.finish();
}

// criterion_group! generates an undocumented public function.
#[allow(missing_docs)]
mod group {
    criterion::criterion_group!(benches, super::bench);
}
criterion_main!(group::benches);
