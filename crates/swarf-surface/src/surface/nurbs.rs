//! Tensor-product NURBS surfaces, evaluated with their derivatives by de Boor / Cox recursion
//! (Piegl & Tiller, *The NURBS Book*, A2.1, A2.3, A3.6) and the quotient rule for the rational
//! case (A4.4).
//!
//! Evaluation allocates nothing for degrees up to 7 in each direction (the basis-function
//! buffers live on the stack); higher degrees work too, with a small heap buffer.

use glam::DVec4;
use smallvec::SmallVec;
use swarf_geom::math::Vec3;
use swarf_geom::Aabb;

use super::{Derivs, ParamBox, ParametricSurface};

/// Largest control-point coordinate accepted, mm (a kilometre-sized part is no part; beyond,
/// products in the derivatives overflow).
const MAX_COORDINATE: f64 = 1e9;

/// Smallest weight accepted (and the reciprocal the largest): weights are relative, and a
/// spread past 1e24 leaves no digits for the shape.
const MIN_WEIGHT: f64 = 1e-12;

/// Why a NURBS definition is rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum NurbsError {
    /// Degree 0 (or absurdly large).
    #[error("degree in {dir} is {degree}; expected 1 to {max}", max = NurbsSurface::MAX_DEGREE)]
    Degree {
        /// `"u"` or `"v"`.
        dir: &'static str,
        /// The degree found.
        degree: usize,
    },
    /// Too few control points for the degree.
    #[error("{count} control points in {dir}; degree {degree} needs at least {}", degree + 1)]
    TooFewPoints {
        /// `"u"` or `"v"`.
        dir: &'static str,
        /// Control points found.
        count: usize,
        /// The degree.
        degree: usize,
    },
    /// Knot vector length does not match.
    #[error("{found} knots in {dir}; expected {expected} (control points + degree + 1)")]
    KnotCount {
        /// `"u"` or `"v"`.
        dir: &'static str,
        /// Knots found.
        found: usize,
        /// Knots expected.
        expected: usize,
    },
    /// Knots decrease, are not finite, or are too often repeated.
    #[error("knots in {dir}: {reason}")]
    Knots {
        /// `"u"` or `"v"`.
        dir: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// A parameter range that is empty, not finite or not within the domain.
    #[error("parameter range [{}, {}] in {dir} is not a part of the domain [{}, {}]", range[0], range[1], domain[0], domain[1])]
    Range {
        /// `"u"` or `"v"`.
        dir: &'static str,
        /// The range asked for.
        range: [f64; 2],
        /// The surface's domain in that direction.
        domain: [f64; 2],
    },
    /// The control net is not rectangular.
    #[error("control net row {row} has {found} points; expected {expected}")]
    Ragged {
        /// Row (u index).
        row: usize,
        /// Points found.
        found: usize,
        /// Points expected.
        expected: usize,
    },
    /// A coordinate is not finite or a weight is not positive.
    #[error("control point [{i}][{j}]: {reason}")]
    ControlPoint {
        /// u index.
        i: usize,
        /// v index.
        j: usize,
        /// What is wrong.
        reason: &'static str,
    },
}

/// A tensor-product NURBS surface `S(u, v) = Σ N_i,p(u) N_j,q(v) w_ij P_ij / Σ N_i,p(u) N_j,q(v) w_ij`.
///
/// Control point `[i][j]` is indexed along u (i) then v (j). The parameter domain is
/// `[U_p, U_n] × [V_q, V_m]` (the whole knot range for clamped knot vectors).
#[derive(Clone, Debug, PartialEq)]
pub struct NurbsSurface {
    degree_u: usize,
    degree_v: usize,
    knots_u: Vec<f64>,
    knots_v: Vec<f64>,
    nu: usize,
    nv: usize,
    /// Homogeneous control points `(w·x, w·y, w·z, w)`, row-major `i·nv + j`.
    pw: Vec<DVec4>,
    /// Euclidean control points as given (kept for exact output), row-major.
    cp: Vec<Vec3>,
    rational: bool,
}

type Buf = SmallVec<[f64; 64]>;

impl NurbsSurface {
    /// Largest accepted degree (a guard against absurd files, far above any CAD use).
    pub const MAX_DEGREE: usize = 64;

    /// A surface from Euclidean control points `points[i][j]` and weights `weights[i][j]`
    /// (`None` for a polynomial surface, all weights 1). Validates everything.
    pub fn new(
        degree_u: usize,
        degree_v: usize,
        knots_u: Vec<f64>,
        knots_v: Vec<f64>,
        points: &[Vec<Vec3>],
        weights: Option<&[Vec<f64>]>,
    ) -> Result<Self, NurbsError> {
        let nu = points.len();
        let nv = points.first().map_or(0, Vec::len);
        check_dir("u", degree_u, nu, &knots_u)?;
        check_dir("v", degree_v, nv, &knots_v)?;
        let mut pw = Vec::with_capacity(nu * nv);
        let mut cp = Vec::with_capacity(nu * nv);
        let mut rational = false;
        for (i, row) in points.iter().enumerate() {
            if row.len() != nv {
                return Err(NurbsError::Ragged {
                    row: i,
                    found: row.len(),
                    expected: nv,
                });
            }
            let wrow = match weights {
                Some(w) => {
                    let r = w.get(i).ok_or(NurbsError::Ragged {
                        row: i,
                        found: 0,
                        expected: nv,
                    })?;
                    if r.len() != nv {
                        return Err(NurbsError::Ragged {
                            row: i,
                            found: r.len(),
                            expected: nv,
                        });
                    }
                    Some(r)
                }
                None => None,
            };
            for (j, p) in row.iter().enumerate() {
                let w = wrow.map_or(1.0, |r| r[j]);
                if !p.is_finite() {
                    return Err(NurbsError::ControlPoint {
                        i,
                        j,
                        reason: "coordinate is not finite",
                    });
                }
                if p.abs().max_element() > MAX_COORDINATE {
                    return Err(NurbsError::ControlPoint {
                        i,
                        j,
                        reason: "coordinate beyond 1e9 mm",
                    });
                }
                if !(w > 0.0 && w.is_finite()) {
                    return Err(NurbsError::ControlPoint {
                        i,
                        j,
                        reason: "weight is not a positive finite number",
                    });
                }
                // Derivatives divide by w²: a weight near the bottom of the floating-point range
                // (or a spread of weights past the digits a double holds) decides the shape by
                // rounding and ends in 0/0.
                if !(MIN_WEIGHT..=1.0 / MIN_WEIGHT).contains(&w) {
                    return Err(NurbsError::ControlPoint {
                        i,
                        j,
                        reason: "weight outside [1e-12, 1e12]",
                    });
                }
                rational |= w != 1.0;
                pw.push(DVec4::new(w * p.x, w * p.y, w * p.z, w));
                cp.push(*p);
            }
        }
        if weights.is_some_and(|w| w.len() != nu) {
            return Err(NurbsError::Ragged {
                row: nu,
                found: nv,
                expected: 0,
            });
        }
        Ok(Self {
            degree_u,
            degree_v,
            knots_u,
            knots_v,
            nu,
            nv,
            pw,
            cp,
            rational,
        })
    }

    /// Degree in u.
    pub fn degree_u(&self) -> usize {
        self.degree_u
    }
    /// Degree in v.
    pub fn degree_v(&self) -> usize {
        self.degree_v
    }
    /// Knot vector in u.
    pub fn knots_u(&self) -> &[f64] {
        &self.knots_u
    }
    /// Knot vector in v.
    pub fn knots_v(&self) -> &[f64] {
        &self.knots_v
    }
    /// Control net size `(n_u, n_v)`.
    pub fn net_size(&self) -> (usize, usize) {
        (self.nu, self.nv)
    }
    /// True when some weight differs from 1.
    pub fn is_rational(&self) -> bool {
        self.rational
    }
    /// Euclidean control point `[i][j]`.
    pub fn control_point(&self, i: usize, j: usize) -> Vec3 {
        self.cp[i * self.nv + j]
    }
    /// Weight of control point `[i][j]`.
    pub fn weight(&self, i: usize, j: usize) -> f64 {
        self.pw[i * self.nv + j].w
    }

    /// The same surface with the u direction reversed (`S'(u, v) = S(u0 + u1 − u, v)`), which
    /// negates `S_u × S_v`.
    pub fn reversed_u(&self) -> Self {
        let (a, b) = (self.knots_u[0], self.knots_u[self.knots_u.len() - 1]);
        let knots_u = self.knots_u.iter().rev().map(|k| a + b - k).collect();
        let mut pw = Vec::with_capacity(self.pw.len());
        let mut cp = Vec::with_capacity(self.cp.len());
        for i in (0..self.nu).rev() {
            pw.extend_from_slice(&self.pw[i * self.nv..(i + 1) * self.nv]);
            cp.extend_from_slice(&self.cp[i * self.nv..(i + 1) * self.nv]);
        }
        Self {
            knots_u,
            pw,
            cp,
            ..self.clone()
        }
    }

    /// The part of the surface over `[u0, u1] × [v0, v1]` (within its domain), with the same
    /// parameters: its point at `(u, v)` is this surface's. Each bound is inserted as a knot
    /// until it is full (degree + 1 copies; Boehm's insertion, Piegl & Tiller A5.1) and the
    /// knots and control points outside are dropped, so the result is exact.
    ///
    /// ```
    /// use swarf_geom::math::Vec3;
    /// use swarf_surface::{NurbsSurface, ParametricSurface};
    /// // A quadratic in v over [0, 1]²; its middle half in u and v.
    /// let pts: Vec<Vec<Vec3>> = (0..2)
    ///     .map(|i| (0..3).map(|j| Vec3::new(20.0 * i as f64, 10.0 * j as f64 - 10.0, (j % 2) as f64)).collect())
    ///     .collect();
    /// let s = NurbsSurface::new(1, 2, vec![0., 0., 1., 1.], vec![0., 0., 0., 1., 1., 1.], &pts, None)?;
    /// let r = s.restricted([0.25, 0.75], [0.25, 0.75])?;
    /// assert_eq!(r.domain().u, [0.25, 0.75]);
    /// assert!((r.point(0.3, 0.6) - s.point(0.3, 0.6)).length() < 1e-12);
    /// # Ok::<(), swarf_surface::NurbsError>(())
    /// ```
    ///
    /// # Errors
    /// [`NurbsError::Range`] when a range is empty, not finite or not within the domain.
    pub fn restricted(&self, u: [f64; 2], v: [f64; 2]) -> Result<Self, NurbsError> {
        let d = self.domain();
        for (dir, r, dd) in [("u", u, d.u), ("v", v, d.v)] {
            if !(r[0] < r[1] && r[0] >= dd[0] && r[1] <= dd[1]) {
                return Err(NurbsError::Range {
                    dir,
                    range: r,
                    domain: dd,
                });
            }
        }
        // Columns (fixed j, along u) cut in u, then rows (fixed i, along v) cut in v.
        let (p, q) = (self.degree_u, self.degree_v);
        let mut cols: Vec<Vec<DVec4>> = (0..self.nv)
            .map(|j| (0..self.nu).map(|i| self.pw[i * self.nv + j]).collect())
            .collect();
        let knots_u = restrict_curves(p, &self.knots_u, &mut cols, u);
        let nu = cols[0].len();
        let mut rows: Vec<Vec<DVec4>> = (0..nu)
            .map(|i| cols.iter().map(|c| c[i]).collect())
            .collect();
        let knots_v = restrict_curves(q, &self.knots_v, &mut rows, v);
        let points: Vec<Vec<Vec3>> = rows
            .iter()
            .map(|r| r.iter().map(|h| h.truncate() / h.w).collect())
            .collect();
        let weights: Vec<Vec<f64>> = rows
            .iter()
            .map(|r| r.iter().map(|h| h.w).collect())
            .collect();
        Self::new(p, q, knots_u, knots_v, &points, Some(&weights))
    }

    /// Homogeneous derivatives `A_kl` (k + l ≤ 2) at `(u, v)`, in the order
    /// 00, 10, 01, 20, 11, 02.
    fn homogeneous(&self, u: f64, v: f64, order: usize) -> [DVec4; 6] {
        let (p, q) = (self.degree_u, self.degree_v);
        let su = find_span(self.nu, p, u, &self.knots_u);
        let sv = find_span(self.nv, q, v, &self.knots_v);
        let mut nu_buf: Buf = SmallVec::from_elem(0.0, 3 * (p + 1));
        let mut nv_buf: Buf = SmallVec::from_elem(0.0, 3 * (q + 1));
        let (nu_d, nv_d) = (&mut nu_buf[..], &mut nv_buf[..]);
        ders_basis(su, u, p, order, &self.knots_u, nu_d);
        ders_basis(sv, v, q, order, &self.knots_v, nv_d);
        let mut out = [DVec4::ZERO; 6];
        for r in 0..=p {
            let row = (su - p + r) * self.nv + (sv - q);
            let net = &self.pw[row..row + q + 1];
            // tmp_l = Σ_s N_v^(l)[s] Pw[r][s]
            let mut t = [DVec4::ZERO; 3];
            for (s, c) in net.iter().enumerate() {
                t[0] += nv_d[s] * *c;
                if order > 0 {
                    t[1] += nv_d[(q + 1) + s] * *c;
                    t[2] += nv_d[2 * (q + 1) + s] * *c;
                }
            }
            let (n0, n1, n2) = (nu_d[r], nu_d[(p + 1) + r], nu_d[2 * (p + 1) + r]);
            out[0] += n0 * t[0];
            if order > 0 {
                out[1] += n1 * t[0];
                out[2] += n0 * t[1];
                out[3] += n2 * t[0];
                out[4] += n1 * t[1];
                out[5] += n0 * t[2];
            }
        }
        out
    }
}

impl ParametricSurface for NurbsSurface {
    fn domain(&self) -> ParamBox {
        ParamBox::new(
            self.knots_u[self.degree_u],
            self.knots_u[self.nu],
            self.knots_v[self.degree_v],
            self.knots_v[self.nv],
        )
    }

    fn point(&self, u: f64, v: f64) -> Vec3 {
        let (u, v) = self.domain().clamp(u, v);
        let a = self.homogeneous(u, v, 0)[0];
        // Same arithmetic as `derivs` so that both give bit-identical points.
        a.truncate() * (1.0 / a.w)
    }

    fn derivs(&self, u: f64, v: f64) -> Derivs {
        let (u, v) = self.domain().clamp(u, v);
        let a = self.homogeneous(u, v, 2);
        let w = |k: usize| a[k].w;
        let x = |k: usize| a[k].truncate();
        let inv = 1.0 / w(0);
        let s = x(0) * inv;
        let su = (x(1) - w(1) * s) * inv;
        let sv = (x(2) - w(2) * s) * inv;
        let suu = (x(3) - 2.0 * w(1) * su - w(3) * s) * inv;
        let suv = (x(4) - w(1) * sv - w(2) * su - w(4) * s) * inv;
        let svv = (x(5) - 2.0 * w(2) * sv - w(5) * s) * inv;
        Derivs {
            point: s,
            su,
            sv,
            suu,
            suv,
            svv,
        }
    }

    fn bounding_box(&self) -> Aabb {
        let b = Aabb::from_points(self.cp.iter().copied());
        b.unwrap_or(Aabb::new(Vec3::ZERO, Vec3::ZERO))
    }
}

fn check_dir(dir: &'static str, degree: usize, n: usize, knots: &[f64]) -> Result<(), NurbsError> {
    if degree == 0 || degree > NurbsSurface::MAX_DEGREE {
        return Err(NurbsError::Degree { dir, degree });
    }
    if n < degree + 1 {
        return Err(NurbsError::TooFewPoints {
            dir,
            count: n,
            degree,
        });
    }
    if knots.len() != n + degree + 1 {
        return Err(NurbsError::KnotCount {
            dir,
            found: knots.len(),
            expected: n + degree + 1,
        });
    }
    let bad = |reason: String| Err(NurbsError::Knots { dir, reason });
    if let Some(k) = knots.iter().position(|k| !k.is_finite()) {
        return bad(format!("knot {k} is not finite"));
    }
    if let Some(k) = knots.windows(2).position(|w| w[1] < w[0]) {
        return bad(format!(
            "knot {} ({}) is smaller than knot {k} ({})",
            k + 1,
            knots[k + 1],
            knots[k]
        ));
    }
    if knots[degree] >= knots[n] {
        return bad(format!(
            "empty domain [{}, {}] (knots {degree} and {n})",
            knots[degree], knots[n]
        ));
    }
    // Interior knots (strictly inside the domain) may repeat at most `degree` times.
    let (a, b) = (knots[degree], knots[n]);
    let mut run = 1;
    for k in 1..knots.len() {
        run = if knots[k] == knots[k - 1] { run + 1 } else { 1 };
        if knots[k] > a && knots[k] < b && run > degree {
            return bad(format!(
                "interior knot {} repeats {run} times; at most {degree} (the degree) keep the surface continuous",
                knots[k]
            ));
        }
    }
    Ok(())
}

/// Cuts the B-spline curves sharing degree `p` and `knots` (each a control polygon in
/// `curves`) to `[a, b]` within their domain: each bound is inserted until it has `p + 1`
/// copies, then the knots and control points outside are dropped. Returns the new knots.
fn restrict_curves(
    p: usize,
    knots: &[f64],
    curves: &mut [Vec<DVec4>],
    [a, b]: [f64; 2],
) -> Vec<f64> {
    let mut u = knots.to_vec();
    for t in [a, b] {
        while u.iter().filter(|&&k| k == t).count() < p + 1 {
            // Boehm: Q_i = α_i P_i + (1 − α_i) P_{i−1}, α_i = (t − U_i)/(U_{i+p} − U_i) clamped
            // to [0, 1] (1 left of the span holding t, 0 right of it), for i = 0..=n.
            let n = curves[0].len();
            let alpha: Vec<f64> = (0..=n)
                .map(|i| {
                    let den = u[i + p] - u[i];
                    if den > 0.0 {
                        ((t - u[i]) / den).clamp(0.0, 1.0)
                    } else {
                        f64::from(u8::from(u[i] <= t))
                    }
                })
                .collect();
            for c in curves.iter_mut() {
                let q: Vec<DVec4> = alpha
                    .iter()
                    .enumerate()
                    .map(|(i, &al)| match (i.checked_sub(1), i < n) {
                        (_, true) if al == 1.0 => c[i],
                        (Some(h), _) if al == 0.0 => c[h],
                        (Some(h), true) => al * c[i] + (1.0 - al) * c[h],
                        // t lies in the domain: the ends keep their points.
                        (None, _) => c[0],
                        (Some(h), false) => c[h],
                    })
                    .collect();
                *c = q;
            }
            let at = u.partition_point(|&k| k <= t);
            u.insert(at, t);
        }
    }
    // First of the last p + 1 copies of a; first copy of b.
    let lo = u.partition_point(|&k| k <= a) - (p + 1);
    let hi = u.partition_point(|&k| k < b);
    for c in curves.iter_mut() {
        *c = c[lo..hi].to_vec();
    }
    u[lo..=hi + p].to_vec()
}

/// The knot span index `i` with `U_i ≤ u < U_{i+1}` (the last non-empty span at the domain end).
fn find_span(n: usize, p: usize, u: f64, knots: &[f64]) -> usize {
    if u >= knots[n] {
        // Last non-empty span.
        let mut i = n - 1;
        while i > p && knots[i] >= knots[n] {
            i -= 1;
        }
        return i;
    }
    if u <= knots[p] {
        let mut i = p;
        while i + 1 < n && knots[i + 1] <= knots[p] {
            i += 1;
        }
        return i;
    }
    let (mut lo, mut hi) = (p, n);
    let mut mid = (lo + hi) / 2;
    while u < knots[mid] || u >= knots[mid + 1] {
        if u < knots[mid] {
            hi = mid;
        } else {
            lo = mid;
        }
        mid = (lo + hi) / 2;
    }
    mid
}

/// Basis functions and their derivatives up to `order ≤ 2` at `u` in span `i` (A2.3): `out` holds
/// `3·(p+1)` values, row `k` = k-th derivatives of `N_{i-p..i, p}`; rows above `order` are left 0.
fn ders_basis(i: usize, u: f64, p: usize, order: usize, knots: &[f64], out: &mut [f64]) {
    let w = p + 1;
    // Slices taken once: indexing a SmallVec re-checks inline/heap at every access.
    let mut ndu_buf: Buf = SmallVec::from_elem(0.0, w * w);
    let mut lr_buf: Buf = SmallVec::from_elem(0.0, 2 * w);
    let ndu = &mut ndu_buf[..];
    let (left, right) = lr_buf.split_at_mut(w);
    ndu[0] = 1.0;
    for j in 1..=p {
        left[j] = u - knots[i + 1 - j];
        right[j] = knots[i + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            // Lower triangle: knot differences.
            ndu[j * w + r] = right[r + 1] + left[j - r];
            let temp = ndu[r * w + (j - 1)] / ndu[j * w + r];
            // Upper triangle: basis functions.
            ndu[r * w + j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j * w + j] = saved;
    }
    for j in 0..=p {
        out[j] = ndu[j * w + p];
    }
    if order == 0 {
        return;
    }
    let n = order.min(p);
    let mut a_buf: Buf = SmallVec::from_elem(0.0, 2 * w);
    let a = &mut a_buf[..];
    for r in 0..=p {
        let (mut s1, mut s2) = (0usize, 1usize);
        a[0] = 1.0;
        for k in 1..=n {
            let mut d = 0.0;
            let rk = r as isize - k as isize;
            let pk = p - k;
            if rk >= 0 {
                let rk = rk as usize;
                a[s2 * w] = a[s1 * w] / ndu[(pk + 1) * w + rk];
                d = a[s2 * w] * ndu[rk * w + pk];
            }
            let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
            let j2 = if (r as isize - 1) <= pk as isize {
                k - 1
            } else {
                p - r
            };
            for j in j1..=j2 {
                let idx = (rk + j as isize) as usize;
                a[s2 * w + j] = (a[s1 * w + j] - a[s1 * w + j - 1]) / ndu[(pk + 1) * w + idx];
                d += a[s2 * w + j] * ndu[idx * w + pk];
            }
            if r <= pk {
                a[s2 * w + k] = -a[s1 * w + k - 1] / ndu[(pk + 1) * w + r];
                d += a[s2 * w + k] * ndu[r * w + pk];
            }
            out[k * w + r] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut f = p as f64;
    for k in 1..=n {
        for j in 0..=p {
            out[k * w + j] *= f;
        }
        f *= (p - k) as f64;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol
    }

    #[test]
    fn basis_partition_of_unity_and_derivative_sum() {
        let knots = [0.0, 0.0, 0.0, 0.0, 0.3, 0.5, 0.5, 1.0, 1.0, 1.0, 1.0];
        let (n, p) = (7, 3);
        for s in 0..=50 {
            let u = s as f64 / 50.0;
            let i = find_span(n, p, u, &knots);
            assert!(knots[i] <= u && (u < knots[i + 1] || (u == 1.0 && knots[i] < knots[i + 1])));
            let mut out = [0.0; 12];
            ders_basis(i, u, p, 2, &knots, &mut out);
            let sum: f64 = out[..4].iter().sum();
            let d1: f64 = out[4..8].iter().sum();
            let d2: f64 = out[8..].iter().sum();
            assert!(close(sum, 1.0, 1e-14) && close(d1, 0.0, 1e-12) && close(d2, 0.0, 1e-10));
        }
    }

    #[test]
    fn validation() {
        let row = vec![Vec3::ZERO, Vec3::X];
        let pts = vec![row.clone(), row.clone()];
        let k = vec![0.0, 0.0, 1.0, 1.0];
        assert!(NurbsSurface::new(1, 1, k.clone(), k.clone(), &pts, None).is_ok());
        assert!(matches!(
            NurbsSurface::new(1, 1, vec![0.0, 0.0, 1.0], k.clone(), &pts, None),
            Err(NurbsError::KnotCount {
                dir: "u",
                found: 3,
                expected: 4
            })
        ));
        assert!(matches!(
            NurbsSurface::new(1, 1, vec![0.0, 1.0, 0.5, 1.0], k.clone(), &pts, None),
            Err(NurbsError::Knots { dir: "u", .. })
        ));
        assert!(matches!(
            NurbsSurface::new(0, 1, k.clone(), k.clone(), &pts, None),
            Err(NurbsError::Degree { .. })
        ));
        let w = vec![vec![1.0, 1.0], vec![1.0, -1.0]];
        assert!(matches!(
            NurbsSurface::new(1, 1, k.clone(), k.clone(), &pts, Some(&w)),
            Err(NurbsError::ControlPoint { i: 1, j: 1, .. })
        ));
        let ragged = vec![row.clone(), vec![Vec3::ZERO]];
        assert!(matches!(
            NurbsSurface::new(1, 1, k.clone(), k.clone(), &ragged, None),
            Err(NurbsError::Ragged { row: 1, .. })
        ));
        let flat = vec![0.0, 0.0, 0.0, 0.0];
        assert!(NurbsSurface::new(1, 1, flat, k, &pts, None).is_err());
    }

    #[test]
    fn a_restricted_surface_is_the_same_surface_over_the_part() {
        // Degree 2 × 3, rational, an interior knot of multiplicity 2 in u, and an unclamped
        // knot vector in v: the part crosses interior knots and ends inside spans.
        let (nu, nv) = (6, 5);
        let pts: Vec<Vec<Vec3>> = (0..nu)
            .map(|i| {
                (0..nv)
                    .map(|j| {
                        let (x, y) = (i as f64, j as f64);
                        Vec3::new(3.0 * x + 0.2 * y, 2.0 * y - 0.1 * x * y, (x * y).sin())
                    })
                    .collect()
            })
            .collect();
        let w: Vec<Vec<f64>> = (0..nu)
            .map(|i| {
                (0..nv)
                    .map(|j| 1.0 + 0.3 * ((i + 2 * j) % 3) as f64)
                    .collect()
            })
            .collect();
        let ku = vec![0.0, 0.0, 0.0, 0.4, 0.4, 0.7, 1.0, 1.0, 1.0];
        let kv = vec![-3.0, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
        let s = NurbsSurface::new(2, 3, ku, kv, &pts, Some(&w)).unwrap();
        let d = s.domain();
        assert_eq!((d.u, d.v), ([0.0, 1.0], [0.0, 2.0]));
        for (u, v) in [
            ([0.25, 0.85], [0.3, 1.6]),
            ([0.4, 0.7], [0.0, 2.0]),
            ([0.0, 1.0], [1.0, 1.5]),
            ([0.0, 0.1], [1.9, 2.0]),
        ] {
            let r = s.restricted(u, v).unwrap();
            assert_eq!((r.domain().u, r.domain().v), (u, v));
            for a in 0..=8 {
                for b in 0..=8 {
                    let x = u[0] + (u[1] - u[0]) * a as f64 / 8.0;
                    let y = v[0] + (v[1] - v[0]) * b as f64 / 8.0;
                    let (p, q) = (s.derivs(x, y), r.derivs(x, y));
                    assert!(
                        (p.point - q.point).length() < 1e-12,
                        "{u:?} {v:?} at ({x}, {y})"
                    );
                    assert!((p.su - q.su).length() < 1e-9 && (p.sv - q.sv).length() < 1e-9);
                }
            }
            // Its hull (control points) lies within the original's.
            let (bb, rb) = (s.bounding_box(), r.bounding_box());
            assert!(bb.inflated(1e-12).contains(rb.min) && bb.inflated(1e-12).contains(rb.max));
        }
        for (u, v) in [
            ([0.5, 0.5], [0.0, 2.0]),
            ([-0.1, 0.5], [0.0, 2.0]),
            ([0.0, 1.0], [1.0, 2.5]),
        ] {
            assert!(
                matches!(s.restricted(u, v), Err(NurbsError::Range { .. })),
                "{u:?} {v:?}"
            );
        }
    }
}
