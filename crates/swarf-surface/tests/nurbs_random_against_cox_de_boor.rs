//! Random NURBS of degree 1–6 with repeated interior knots and random weights: points agree
//! with a naive evaluation from the Cox–de Boor recursion (an independent implementation), and
//! derivatives with finite differences; normals are unit, curvatures finite.

mod common;

use common::max_fd_error_between;
use proptest::prelude::*;
use swarf_geom::math::Vec3;
use swarf_surface::{NurbsSurface, ParametricSurface, Surface, Tolerances};

/// N_{i,p}(u) by the recursive definition, with the right end of the domain included.
fn basis(i: usize, p: usize, u: f64, k: &[f64], end: f64) -> f64 {
    if p == 0 {
        let inside = k[i] <= u && u < k[i + 1];
        let at_end = u == end && k[i] < k[i + 1] && k[i + 1] == end;
        return if inside || at_end { 1.0 } else { 0.0 };
    }
    let mut s = 0.0;
    if k[i + p] > k[i] {
        s += (u - k[i]) / (k[i + p] - k[i]) * basis(i, p - 1, u, k, end);
    }
    if k[i + p + 1] > k[i + 1] {
        s += (k[i + p + 1] - u) / (k[i + p + 1] - k[i + 1]) * basis(i + 1, p - 1, u, k, end);
    }
    s
}

#[derive(Debug)]
struct Naive {
    p: usize,
    q: usize,
    ku: Vec<f64>,
    kv: Vec<f64>,
    pts: Vec<Vec<Vec3>>,
    w: Vec<Vec<f64>>,
}

impl Naive {
    fn point(&self, u: f64, v: f64) -> Vec3 {
        let (eu, ev) = (self.ku[self.ku.len() - 1], self.kv[self.kv.len() - 1]);
        let (mut num, mut den) = (Vec3::ZERO, 0.0);
        for (i, row) in self.pts.iter().enumerate() {
            let bu = basis(i, self.p, u, &self.ku, eu);
            for (j, pt) in row.iter().enumerate() {
                let b = bu * basis(j, self.q, v, &self.kv, ev) * self.w[i][j];
                num += b * *pt;
                den += b;
            }
        }
        num / den
    }
}

/// A clamped knot vector on [0, 1] for `n` points of degree `p`, from `cuts` (interior knots,
/// some repeated up to the degree).
fn knots(p: usize, n: usize, cuts: &[(f64, usize)]) -> Vec<f64> {
    let mut inner = Vec::new();
    // Cut k lies in [k/3, (k+1)/3): distinct cuts, each repeated at most p times.
    for (k, &(c, m)) in cuts.iter().enumerate() {
        for _ in 0..m.min(p) {
            if inner.len() < n - p - 1 {
                inner.push(0.05 + 0.9 * (k as f64 + 0.999 * c) / 3.0);
            }
        }
    }
    while inner.len() < n - p - 1 {
        inner.push(0.05 + 0.9 * (inner.len() as f64 + 0.5) / (n - p) as f64);
    }
    inner.sort_by(f64::total_cmp);
    let mut k = vec![0.0; p + 1];
    k.extend(inner);
    k.extend(vec![1.0; p + 1]);
    k
}

fn surface() -> impl Strategy<Value = (NurbsSurface, Naive)> {
    (1usize..=6, 1usize..=6, 0usize..4, 0usize..4).prop_flat_map(|(p, q, eu, ev)| {
        let (nu, nv) = (p + 1 + eu, q + 1 + ev);
        (
            proptest::collection::vec((0.0..1.0f64, 1usize..4), 3),
            proptest::collection::vec((0.0..1.0f64, 1usize..4), 3),
            proptest::collection::vec(
                (-50.0..50.0f64, -50.0..50.0f64, -50.0..50.0f64, 0.2..5.0f64),
                nu * nv,
            ),
        )
            .prop_map(move |(cu, cv, net)| {
                let ku = knots(p, nu, &cu);
                let kv = knots(q, nv, &cv);
                let pts: Vec<Vec<Vec3>> = (0..nu)
                    .map(|i| {
                        (0..nv)
                            .map(|j| {
                                let c = net[i * nv + j];
                                // A height field over a grid keeps the patch regular (no folds).
                                Vec3::new(
                                    10.0 * i as f64 + 0.05 * c.0,
                                    10.0 * j as f64 + 0.05 * c.1,
                                    c.2,
                                )
                            })
                            .collect()
                    })
                    .collect();
                let w: Vec<Vec<f64>> = (0..nu)
                    .map(|i| (0..nv).map(|j| net[i * nv + j].3).collect())
                    .collect();
                let s = NurbsSurface::new(p, q, ku.clone(), kv.clone(), &pts, Some(&w)).unwrap();
                (
                    s,
                    Naive {
                        p,
                        q,
                        ku,
                        kv,
                        pts,
                        w,
                    },
                )
            })
    })
}

proptest! {
    #![proptest_config(swarf_testdata::proptest_config(64))]

    #[test]
    fn random_nurbs_match_the_naive_evaluation((s, naive) in surface()) {
        let scale = s.bounding_box().size().length();
        for i in 0..=12 {
            for j in 0..=12 {
                let (u, v) = (i as f64 / 12.0, j as f64 / 12.0);
                let d = (s.point(u, v) - naive.point(u, v)).length();
                prop_assert!(d <= 1e-12 * scale, "({u}, {v}): {d}");
                prop_assert_eq!(s.derivs(u, v).point, s.point(u, v));
            }
        }
        // Knots are where the random surface's higher derivatives jump.
        prop_assert!(max_fd_error_between(&s, 7, &naive.ku, &naive.kv) < 1e-5);
        let surf = Surface::Nurbs(s);
        for i in 0..=6 {
            for j in 0..=6 {
                let g = surf.local(i as f64 / 6.0, j as f64 / 6.0, &Tolerances::DEFAULT);
                let n = g.normal.vector().unwrap();
                prop_assert!((n.length() - 1.0).abs() < 1e-12);
                let c = g.curvature.unwrap();
                prop_assert!(c.k1.is_finite() && c.k2.is_finite() && c.k1 >= c.k2);
                prop_assert!(c.dir1.dot(n).abs() < 1e-9 && c.dir1.dot(c.dir2).abs() < 1e-9);
                // Euler: the normal curvature along dir1 is k1 (II(d,d)/I(d,d) in parameters).
                let d = g.derivs;
                let (e, f, gg) = (d.su.dot(d.su), d.su.dot(d.sv), d.sv.dot(d.sv));
                let det = e * gg - f * f;
                let (a, b) = ((gg * c.dir1.dot(d.su) - f * c.dir1.dot(d.sv)) / det, (e * c.dir1.dot(d.sv) - f * c.dir1.dot(d.su)) / det);
                let ii = a * a * d.suu.dot(n) + 2.0 * a * b * d.suv.dot(n) + b * b * d.svv.dot(n);
                let kn = ii / (a * a * e + 2.0 * a * b * f + b * b * gg);
                prop_assert!((kn - c.k1).abs() <= 1e-8 * (1.0 + c.k1.abs()), "{kn} vs {}", c.k1);
            }
        }
    }
}
