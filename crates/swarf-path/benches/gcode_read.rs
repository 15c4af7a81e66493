//! Throughput of the G-code reader on typical 3-axis programs (linear moves with X Y Z F and
//! some arcs), with a sink that only counts events — the reader's own cost. Throughput is in
//! elements = program lines.

// criterion_group! generates an undocumented public function.
#![allow(missing_docs)]

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use swarf_path::gcode::{read_gcode, GcodeOptions};
use swarf_path::{Canon, CanonSink, Warning};

/// Counts events.
#[derive(Default)]
struct Count(u64);

impl CanonSink for Count {
    fn emit(&mut self, _line: u32, event: &Canon<'_>) {
        self.0 += 1;
        black_box(event);
    }
    fn warn(&mut self, _warning: Warning) {}
}

/// A program of `lines` lines: mostly `G1 X Y Z F` feed moves, every 10th line an arc pair
/// leg, every 50th a rapid, as a CAM post-processor writes them (4 decimals).
fn program(lines: usize) -> String {
    let mut s = String::with_capacity(lines * 36);
    s.push_str("G21 G90 G17 G94\n");
    // A deterministic walk: a linear congruential generator keeps the numbers varied.
    let mut seed: u64 = 0x2545_f491_4f6c_dd1d;
    let mut next = || {
        seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((seed >> 33) % 100_000) as f64 / 1000.0
    };
    let (mut x, mut y) = (0.0f64, 0.0f64);
    for i in 1..lines.saturating_sub(1) {
        if i % 50 == 0 {
            x = next();
            y = next();
            s.push_str(&format!("G0 X{x:.4} Y{y:.4} Z5.0000\n"));
        } else if i % 10 == 0 {
            // A half circle of radius 2 to the right and back: start and end radii agree.
            s.push_str(&format!(
                "G2 X{:.4} Y{y:.4} I2.0000 J0.0000 F1200\n",
                x + 4.0
            ));
            x += 4.0;
        } else {
            x = next();
            y = next();
            let z = -next() / 20.0;
            s.push_str(&format!(
                "G1 X{x:.4} Y{y:.4} Z{z:.4} F{}\n",
                800 + (i % 7) * 100
            ));
        }
    }
    s.push_str("M30\n");
    s
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("gcode_read");
    g.sample_size(10);
    for lines in [10_000usize, 100_000, 1_000_000] {
        let text = program(lines);
        let n = text.lines().count();
        g.throughput(Throughput::Elements(n as u64));
        g.bench_with_input(BenchmarkId::from_parameter(lines), &text, |b, text| {
            b.iter(|| {
                let mut sink = Count::default();
                read_gcode(text, "bench.ngc", &GcodeOptions::default(), &mut sink).unwrap();
                black_box(sink.0)
            });
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
