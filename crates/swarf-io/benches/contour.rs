//! Dual contouring throughput, normals estimated (as for a tri-dexel), reported per lattice
//! cell: a sphere (all curved) and a machined block (flat faces, a pocket and a drilled hole,
//! spans given per ray exactly as a tri-dexel stores them) at decreasing spacings.

use criterion::{criterion_main, BenchmarkId, Criterion, Throughput};
use swarf_geom::math::Vec3;
use swarf_geom::Aabb;
use swarf_io::{dual_contour, ContourOptions, FnGrid, HermiteGrid, Lattice, Span};

/// The sphere's spans precomputed, so the bench measures contouring, not root finding.
struct Tabulated {
    lattice: Lattice,
    lines: [Vec<Vec<Span>>; 3],
}

impl HermiteGrid for Tabulated {
    fn lattice(&self) -> Lattice {
        self.lattice
    }
    fn line_spans(&self, axis: usize, u: usize, v: usize, out: &mut Vec<Span>) {
        let nu = self.lattice.n[(axis + 1) % 3];
        out.extend_from_slice(&self.lines[axis][u + nu * v]);
    }
}

fn tabulate(h: f64) -> Tabulated {
    let r = 10.0;
    let lattice = Lattice::covering(
        Aabb::new(Vec3::splat(-r), Vec3::splat(r)).inflated(2.0 * h),
        h,
    );
    let g = FnGrid::new(lattice, move |p: Vec3| p.length() - r);
    let lines = [0, 1, 2].map(|a| {
        let (nu, nv) = (lattice.n[(a + 1) % 3], lattice.n[(a + 2) % 3]);
        let mut all = Vec::with_capacity(nu * nv);
        for v in 0..nv {
            for u in 0..nu {
                let mut s = Vec::new();
                g.line_spans(a, u, v, &mut s);
                all.push(s);
            }
        }
        all
    });
    Tabulated { lattice, lines }
}

/// A 60 × 40 × 20 block with a 30 × 20 × 8 pocket and a through hole of radius 6, as rays
/// through the centres of cells of size `h`.
fn machined_block(h: f64) -> Tabulated {
    let stock = Aabb::new(Vec3::ZERO, Vec3::new(60.0, 40.0, 20.0));
    let n = [60.0, 40.0, 20.0].map(|s: f64| (s / h).round() as usize);
    let lattice = Lattice::cell_centres(stock, n);
    let pocket = Aabb::new(Vec3::new(8.0, 10.0, 12.0), Vec3::new(38.0, 30.0, 25.0));
    let (cx, cy, r) = (48.0, 20.0, 6.0);
    let lines = [0, 1, 2].map(|a| {
        let (nu, nv) = (lattice.n[(a + 1) % 3], lattice.n[(a + 2) % 3]);
        let mut all = Vec::with_capacity(nu * nv);
        for v in 0..nv {
            for u in 0..nu {
                let mut p = Vec3::ZERO;
                p[(a + 1) % 3] = lattice.coord((a + 1) % 3, u as isize);
                p[(a + 2) % 3] = lattice.coord((a + 2) % 3, v as isize);
                let mut cuts: Vec<(f64, f64)> = Vec::new();
                let (b, c) = ((a + 1) % 3, (a + 2) % 3);
                if p[b] > pocket.min[b]
                    && p[b] < pocket.max[b]
                    && p[c] > pocket.min[c]
                    && p[c] < pocket.max[c]
                {
                    cuts.push((pocket.min[a], pocket.max[a]));
                }
                if a == 2 {
                    if (p.x - cx).powi(2) + (p.y - cy).powi(2) < r * r {
                        cuts.push((f64::NEG_INFINITY, f64::INFINITY));
                    }
                } else {
                    let (off, centre) = if a == 0 {
                        (p.y - cy, cx)
                    } else {
                        (p.x - cx, cy)
                    };
                    if off.abs() < r {
                        let w = (r * r - off * off).sqrt();
                        cuts.push((centre - w, centre + w));
                    }
                }
                let mut spans = vec![Span {
                    enter: stock.min[a],
                    exit: stock.max[a],
                }];
                for (lo, hi) in cuts {
                    let mut next = Vec::new();
                    for s in spans {
                        if s.exit <= lo || s.enter >= hi {
                            next.push(s);
                        } else {
                            if s.enter < lo {
                                next.push(Span {
                                    enter: s.enter,
                                    exit: lo,
                                });
                            }
                            if s.exit > hi {
                                next.push(Span {
                                    enter: hi,
                                    exit: s.exit,
                                });
                            }
                        }
                    }
                    spans = next;
                }
                all.push(spans);
            }
        }
        all
    });
    Tabulated { lattice, lines }
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("dual_contour_sphere_r10");
    group.sample_size(10);
    for h in [0.4, 0.2, 0.1] {
        let grid = tabulate(h);
        let cells = grid.lattice.cell_count() as u64;
        group.throughput(Throughput::Elements(cells));
        group.bench_with_input(BenchmarkId::from_parameter(cells), &grid, |b, g| {
            b.iter(|| dual_contour(g, &ContourOptions::default()))
        });
    }
    group.finish();
    let mut group = c.benchmark_group("dual_contour_machined_block");
    group.sample_size(10);
    for h in [0.4, 0.2, 0.1] {
        let grid = machined_block(h);
        let cells = grid.lattice.cell_count() as u64;
        group.throughput(Throughput::Elements(cells));
        group.bench_with_input(BenchmarkId::from_parameter(cells), &grid, |b, g| {
            b.iter(|| dual_contour(g, &ContourOptions::default()))
        });
    }
    group.finish();
    // The same with 2 × 2 × 2 blocks of cells merged within 1 µm (`ContourOptions::simplify`).
    let simplify = ContourOptions::default().with_simplify(Some(1e-3));
    for (name, grid) in [
        ("dual_contour_sphere_r10_simplified", tabulate(0.1)),
        (
            "dual_contour_machined_block_simplified",
            machined_block(0.1),
        ),
    ] {
        let (plain, merged) = (
            dual_contour(&grid, &ContourOptions::default()),
            dual_contour(&grid, &simplify),
        );
        eprintln!("{name}: {} → {} triangles", plain.len(), merged.len());
        let mut group = c.benchmark_group(name);
        group.sample_size(10);
        let cells = grid.lattice.cell_count() as u64;
        group.throughput(Throughput::Elements(cells));
        group.bench_with_input(BenchmarkId::from_parameter(cells), &grid, |b, g| {
            b.iter(|| dual_contour(g, &simplify))
        });
        group.finish();
    }
}

// criterion_group! generates an undocumented public function.
#[allow(missing_docs)]
mod group {
    criterion::criterion_group!(benches, super::bench);
}
criterion_main!(group::benches);
