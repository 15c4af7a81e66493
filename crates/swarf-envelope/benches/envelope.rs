//! Envelope meshing time: a full program (by lattice spacing), and issue 14's single line at
//! h = 0.05 with every cell and with blocks of cells merged.

use criterion::{criterion_main, BenchmarkId, Criterion};
use swarf_envelope::{envelope, EnvelopeOptions};
use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::{Machine, Program};
use swarf_tool::{Cutter, ToolSet};

/// A pocketing program: a spiral of lines and arcs with plunges, 3-axis, then a 5-axis pass.
fn program_text() -> String {
    let mut t = String::from("G21 G90\nG0 X0 Y0 Z5\nG1 Z-2 F300\n");
    for i in 0..10 {
        let r = 4.0 + 2.0 * i as f64;
        t += &format!("G1 X{r} Y0\nG3 X-{r} Y0 I-{r} J0\nG3 X{r} Y0 I{r} J0\n");
    }
    t += "G1 X30 Y0 Z-3\nG1 X30 Y30\nG1 X0 Y30 Z-1\n";
    t
}

/// A program read on a 3-axis machine (G-code or APT by the file name).
fn read(text: &str, file: &str) -> Program {
    read_program_str(text, file, Machine::three_axis(), &ReadOptions::default()).unwrap()
}

fn meshing(c: &mut Criterion) {
    let mut g = c.benchmark_group("program_envelope");
    g.sample_size(10);
    let program = read(&program_text(), "bench.ngc");
    let tools = ToolSet::single(Cutter::ball(6.0).unwrap());
    for h in [0.5, 0.25] {
        g.bench_with_input(BenchmarkId::new("ball6_pocket", h), &h, |b, &h| {
            let opts = EnvelopeOptions::default().with_resolution(h);
            b.iter(|| envelope(&program, &tools, 0..program.moves.len(), &opts).unwrap())
        });
    }
    let five = read(
        "GOTO/0,0,0,0,0,1\nGOTO/20,0,0,0.3420201,0,0.9396926\nGOTO/20,20,0,0,0.3420201,0.9396926\n",
        "bench.apt",
    );
    g.bench_function("ball6_5axis_h0.25", |b| {
        let opts = EnvelopeOptions::default();
        b.iter(|| envelope(&five, &tools, 0..five.moves.len(), &opts).unwrap())
    });
    g.finish();
    // Issue 14's case: one 36 mm line of a 10 mm ball at h = 0.05, with the default blocks of
    // cells merged within 1 µm and with every cell (`--simplify 0`); the mesh is made, not
    // written.
    let mut g = c.benchmark_group("line_envelope");
    g.sample_size(10);
    let line = read("G21 G90\nG0 X0 Y0 Z0\nG1 X36 F300\n", "line.ngc");
    let ball10 = ToolSet::single(Cutter::ball(10.0).unwrap());
    for (name, simplify) in [
        ("ball10_h0.05", Some(swarf_envelope::DEFAULT_SIMPLIFY_MM)),
        ("ball10_h0.05_every_cell", None),
    ] {
        let opts = EnvelopeOptions::default()
            .with_resolution(0.05)
            .with_simplify(simplify);
        let report = envelope(&line, &ball10, 0..line.moves.len(), &opts)
            .unwrap()
            .report;
        println!("{name}: {} triangles", report.triangles);
        g.bench_function(name, |b| {
            b.iter(|| envelope(&line, &ball10, 0..line.moves.len(), &opts).unwrap())
        });
    }
    g.finish();
}

#[allow(missing_docs)]
mod group {
    criterion::criterion_group!(benches, super::meshing);
}
criterion_main!(group::benches);
