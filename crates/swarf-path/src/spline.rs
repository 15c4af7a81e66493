//! Spline feeds (LinuxCNC's G5 cubic, G5.1 quadratic and G5.2/G5.3 NURBS, all in the XY plane):
//! the exact curve, evaluation, and flattening into straight feeds within a tolerance.
//!
//! A spline starts at the current position. Its control points follow as (x, y, weight), mm:
//! for a cubic the two inner Bézier points and the end, for a quadratic the inner point and the
//! end (weights 1), for a NURBS every control point after the start with its weight, and its
//! order (degree + 1), on LinuxCNC's clamped uniform knot vector.
//!
//! Flattening: a Bézier piece is cut in halves until its control polygon lies within the
//! tolerance of its chord, which bounds the curve (it lies in the polygon's convex hull); a
//! NURBS is first cut at its knots and each span is sampled the same way, its control
//! polygon's distance to the chord bounding the curve for positive weights.

/// Default chordal tolerance of spline flattening, mm (the simulation's default).
pub const DEFAULT_TOLERANCE_MM: f64 = 0.001;

/// Hard limit on the straight pieces one spline is flattened into.
pub const MAX_PIECES: usize = 1 << 16;

/// The kind of spline.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum SplineKind {
    /// G5: a cubic Bézier (two inner control points and the end).
    Cubic,
    /// G5.1: a quadratic Bézier (one inner control point and the end).
    Quadratic,
    /// G5.2/G5.3: a NURBS of the given order.
    Nurbs {
        /// Order (degree + 1), at least 2.
        order: u32,
    },
}

/// The clamped uniform knot vector LinuxCNC uses for `n` control points of order `k`.
pub fn knots(n: usize, k: usize) -> Vec<f64> {
    let inner = n.saturating_sub(k);
    let mut v = vec![0.0; k];
    v.extend((1..=inner).map(|i| i as f64));
    v.extend(std::iter::repeat((inner + 1) as f64).take(k));
    v
}

/// De Boor evaluation of a NURBS (points `(x, y, w)`, order `k`) at `t`.
pub fn nurbs_point(pts: &[[f64; 3]], k: usize, knots: &[f64], t: f64) -> [f64; 2] {
    let n = pts.len();
    let last = knots[n];
    let t = t.clamp(knots[k - 1], last);
    // The span: knots[s] <= t < knots[s + 1] (the last span closed).
    let mut s = k - 1;
    while s + 1 < n && knots[s + 1] <= t {
        s += 1;
    }
    let mut d: Vec<[f64; 3]> = (0..k)
        .map(|j| {
            let p = pts[s + 1 - k + j];
            [p[0] * p[2], p[1] * p[2], p[2]]
        })
        .collect();
    for r in 1..k {
        for j in (r..k).rev() {
            let i = s + 1 - k + j;
            let den = knots[i + k - r] - knots[i];
            let a = if den == 0.0 {
                0.0
            } else {
                (t - knots[i]) / den
            };
            let prev = d[j - 1];
            for (c, v) in d[j].iter_mut().enumerate() {
                *v = (1.0 - a) * prev[c] + a * *v;
            }
        }
    }
    let w = d[k - 1][2];
    [d[k - 1][0] / w, d[k - 1][1] / w]
}

fn chord_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1]];
    let len2 = d[0] * d[0] + d[1] * d[1];
    let t = if len2 == 0.0 {
        0.0
    } else {
        (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0)
    };
    (p[0] - a[0] - t * d[0]).hypot(p[1] - a[1] - t * d[1])
}

/// Bézier points of one polynomial piece, cut in halves until flat; the end points are pushed.
fn flatten_bezier(ctrl: &[[f64; 2]], tol: f64, out: &mut Vec<[f64; 2]>, depth: u32) {
    let (a, b) = (ctrl[0], ctrl[ctrl.len() - 1]);
    let flat = ctrl[1..ctrl.len() - 1]
        .iter()
        .all(|&p| chord_distance(p, a, b) <= tol);
    if flat || depth >= 24 || out.len() >= MAX_PIECES {
        out.push(b);
        return;
    }
    // de Casteljau at ½.
    let mut left = Vec::with_capacity(ctrl.len());
    let mut right = Vec::with_capacity(ctrl.len());
    let mut work = ctrl.to_vec();
    left.push(work[0]);
    right.push(work[work.len() - 1]);
    for r in 1..ctrl.len() {
        for j in 0..ctrl.len() - r {
            work[j] = [
                (work[j][0] + work[j + 1][0]) / 2.0,
                (work[j][1] + work[j + 1][1]) / 2.0,
            ];
        }
        left.push(work[0]);
        right.push(work[ctrl.len() - r - 1]);
    }
    right.reverse();
    flatten_bezier(&left, tol, out, depth + 1);
    flatten_bezier(&right, tol, out, depth + 1);
}

/// The points (after `start`) of the straight pieces within `tol` of the spline.
pub fn flatten(start: [f64; 2], kind: SplineKind, pts: &[[f64; 3]], tol: f64) -> Vec<[f64; 2]> {
    let tol = tol.max(1e-9);
    let mut out = Vec::new();
    match kind {
        SplineKind::Cubic | SplineKind::Quadratic => {
            let mut ctrl = vec![start];
            ctrl.extend(pts.iter().map(|p| [p[0], p[1]]));
            flatten_bezier(&ctrl, tol, &mut out, 0);
        }
        SplineKind::Nurbs { order } => {
            let mut all = vec![[start[0], start[1], 1.0]];
            all.extend_from_slice(pts);
            let k = (order as usize).clamp(2, all.len().max(2));
            if all.len() < k {
                out.push([all[all.len() - 1][0], all[all.len() - 1][1]]);
                return out;
            }
            let kv = knots(all.len(), k);
            // Each knot span sampled until the chords between samples are flat: a span is cut
            // into pieces whose midpoint and quarter points lie within the tolerance.
            let spans: Vec<(f64, f64)> = kv
                .windows(2)
                .filter(|w| w[1] > w[0])
                .map(|w| (w[0], w[1]))
                .collect();
            for (a, b) in spans {
                let mut stack = vec![(a, b, 0u32)];
                let mut done = Vec::new();
                while let Some((u0, u1, depth)) = stack.pop() {
                    let p0 = nurbs_point(&all, k, &kv, u0);
                    let p1 = nurbs_point(&all, k, &kv, u1);
                    let flat = [0.25, 0.5, 0.75].iter().all(|f| {
                        chord_distance(nurbs_point(&all, k, &kv, u0 + f * (u1 - u0)), p0, p1)
                            <= tol / 2.0
                    });
                    if (flat && depth >= 2) || depth >= 24 || done.len() >= MAX_PIECES {
                        done.push((u1, p1));
                    } else {
                        let m = (u0 + u1) / 2.0;
                        stack.push((m, u1, depth + 1));
                        stack.push((u0, m, depth + 1));
                    }
                }
                out.extend(done.into_iter().map(|(_, p)| p));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn knot_vectors_are_clamped_and_uniform() {
        assert_eq!(knots(4, 3), vec![0.0, 0.0, 0.0, 1.0, 2.0, 2.0, 2.0]);
        assert_eq!(knots(3, 3), vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0]);
    }

    #[test]
    fn a_quarter_circle_nurbs_is_exact() {
        // The rational quadratic quarter circle: (1,0), (1,1) w = √½, (0,1).
        let w = 0.5f64.sqrt();
        let pts = [[1.0, 0.0, 1.0], [1.0, 1.0, w], [0.0, 1.0, 1.0]];
        let kv = knots(3, 3);
        for i in 0..=10 {
            let p = nurbs_point(&pts, 3, &kv, f64::from(i) / 10.0);
            assert!((p[0].hypot(p[1]) - 1.0).abs() < 1e-12);
        }
        let flat = flatten([1.0, 0.0], SplineKind::Nurbs { order: 3 }, &pts[1..], 1e-4);
        let mut prev = [1.0, 0.0];
        for p in flat {
            let mid = [(prev[0] + p[0]) / 2.0, (prev[1] + p[1]) / 2.0];
            assert!(1.0 - mid[0].hypot(mid[1]) <= 1e-4 + 1e-12);
            prev = p;
        }
        assert!((prev[0]).abs() < 1e-12 && (prev[1] - 1.0).abs() < 1e-12);
    }

    #[test]
    fn bezier_flattening_is_within_tolerance() {
        let pts = [[0.0, 10.0, 1.0], [10.0, 10.0, 1.0], [10.0, 0.0, 1.0]];
        let flat = flatten([0.0, 0.0], SplineKind::Cubic, &pts, 1e-3);
        assert!(flat.len() > 8);
        // Against a dense sampling of the cubic.
        let b = |t: f64| {
            let c = [[0.0, 0.0], [0.0, 10.0], [10.0, 10.0], [10.0, 0.0]];
            let m = [
                (1.0 - t).powi(3),
                3.0 * t * (1.0 - t).powi(2),
                3.0 * t * t * (1.0 - t),
                t.powi(3),
            ];
            [
                (0..4).map(|i| m[i] * c[i][0]).sum::<f64>(),
                (0..4).map(|i| m[i] * c[i][1]).sum::<f64>(),
            ]
        };
        let mut poly = vec![[0.0, 0.0]];
        poly.extend(flat);
        for i in 0..=1000 {
            let p = b(f64::from(i) / 1000.0);
            let d = poly
                .windows(2)
                .map(|w| chord_distance(p, w[0], w[1]))
                .fold(f64::INFINITY, f64::min);
            assert!(d <= 1e-3 + 1e-12, "{d}");
        }
    }
}
