//! Torus-arc profile elements (bull-nose corners): the torus band against a line (a quartic)
//! and the envelope of the swept torus (a degree-8 polynomial in `u = tan(θ/2)`), both by the
//! guaranteed root isolation of `swarf_geom::poly`.
//!
//! # The envelope, re-derived
//! The corner is the spine circle `c(θ) = (e cos θ, e sin θ, f)` thickened by a ball of radius
//! `r`. A point `c(θ) + r·n` of it has normal `n` in the meridian plane, so `n ⊥ c′(θ)`; it is
//! grazing for the move `v` when also `n ⊥ v`, so `n = ±m(θ)`, `m = (c′ × v)/|c′ × v|`. With
//! `v = (a, 0, b)`: `c′ × v = (b cos θ, b sin θ, −a cos θ)`. The line `o + t·d` meets the
//! grazing curve's extrusion along `v` where (coplanarity with `w = d × v`)
//! `w·(c(θ) − o) ± r·w·m(θ) = 0`; squaring away the sign and the norm,
//!
//! `(w·(c − o))²·(b² + a² cos² θ) − r²·(w·(c′ × v))² = 0`,
//!
//! of degree 4 in `(cos θ, sin θ)`. With `cos θ = (1 − u²)/(1 + u²)`, `sin θ = 2u/(1 + u²)`
//! and `u ∈ [−1, 1]` (θ ∈ [−π/2, π/2]; the other half by θ → θ + π) this is a degree-8
//! polynomial — Aras's eq. 4.54 and Algorithm 4.1 solve the same problem with a different
//! parameterisation (and, per the errata, with slips in eqs. 4.15/4.17/4.51). Each root gives
//! θ; the sign is the one that satisfies the unsquared equation; the grazing point must lie on
//! the arc's band, and `s ∈ [0, 1]`.
//!
//! For a horizontal move (`b = 0`) the polynomial has the factor `cos² θ`: the grazing set is
//! then the bottom circle (a joint) and the two whole meridian arcs at `θ = ±π/2`, whose
//! extrusions are circular cylinders about lines parallel to `v` — solved in closed form here.

use super::convex::{min_between, walk, zero_between, ConvexLine, Walk};
use super::{Acc, DirConsts, Scratch, BAND_EPS};
use swarf_geom::math::Vec3;
use swarf_geom::poly::{real_roots_in, RootTolerance};

/// Root tolerance for the quartic and octic (in `t`, mm, and in `u`, dimensionless).
const ROOT_TOL: RootTolerance = RootTolerance {
    x_tol: 1e-12,
    max_iter: 200,
};

/// Crossings of the line `o + t·d` (unit `d`) with the torus of spine radius `e`, tube radius
/// `r`, centre height `f`, kept on the arc `φ ∈ [phi0, phi1]` (band `z ∈ [z0, z1]`, outer
/// half `ρ ≥ e`).
///
/// Only the outer half of the tube can bound the convex cutter, and there the crossings are
/// the zeros of `F(t) = ρ(t) − e − √(r² − (z(t) − f)²)` on the heights of the tube: `ρ(t)`, the
/// distance of a point of a line from the axis, is convex, and the square root of `r²` minus
/// the square of a linear function is concave, so `F` is **convex** and has at most two
/// zeros, one on each side of its minimum. They are found by Newton steps kept inside a
/// bracket (derivatives in closed form), a handful of square roots per line instead of the
/// quartic's root isolation ([`cap_quartic`], kept as the reference it is tested against).
#[allow(clippy::too_many_arguments)]
pub(crate) fn cap(
    e: f64,
    f: f64,
    r: f64,
    _phi: (f64, f64),
    (z0, z1): (f64, f64),
    o: Vec3,
    d: Vec3,
    acc: &mut Acc,
    _scratch: &mut Scratch,
) {
    let p = o - Vec3::new(0.0, 0.0, f);
    // Parameter range inside the bounding sphere …
    let Some((mut lo, mut hi)) = sphere_span(e, r, p, d) else {
        return;
    };
    // … and within the tube's heights |z − f| ≤ r.
    if d.z != 0.0 {
        let (ta, tb) = ((-r - p.z) / d.z, (r - p.z) / d.z);
        lo = lo.max(ta.min(tb));
        hi = hi.min(ta.max(tb));
    } else if p.z.abs() > r {
        return;
    }
    if lo > hi {
        return;
    }
    let tube = TubeLine::new(e, r, p, d);
    let (f_lo, f_hi) = (tube.value(lo), tube.value(hi));
    let mut add = |t: f64| {
        if on_band(o + d * t, e, (z0, z1)) {
            acc.add(t);
        }
    };
    match (f_lo >= 0.0, f_hi >= 0.0) {
        // Convex: below zero at both ends, below zero between them.
        (false, false) => {}
        // One zero, between the ends: walked to from the end above zero, else bracketed.
        (true, false) => match walk(&tube, lo, (f_lo, None), hi) {
            Walk::Zero(t) => add(t),
            _ => add(zero_between(&tube, lo, hi, f_lo)),
        },
        (false, true) => match walk(&tube, hi, (f_hi, None), lo) {
            Walk::Zero(t) => add(t),
            _ => add(zero_between(&tube, lo, hi, f_lo)),
        },
        // None or two, on both sides of the minimum.
        (true, true) => {
            if tube.slope(lo) >= 0.0 || tube.slope(hi) <= 0.0 {
                // Smallest at an end, where it is ≥ 0: at most a touch there.
                for (t, v) in [(lo, f_lo), (hi, f_hi)] {
                    if v == 0.0 {
                        add(t);
                    }
                }
                return;
            }
            // Walking in from both ends finds both zeros without the minimum.
            match walk(&tube, lo, (f_lo, None), hi) {
                Walk::NoZero => return,
                Walk::Zero(a) => {
                    if let Walk::Zero(b) = walk(&tube, hi, (f_hi, None), lo) {
                        add(a);
                        add(b);
                        return;
                    }
                }
                Walk::Stuck => {}
            }
            let t_min = min_between(&tube, lo, hi);
            let f_min = tube.value(t_min);
            if f_min > 0.0 {
                return;
            }
            if f_min == 0.0 {
                add(t_min);
                return;
            }
            add(zero_between(&tube, lo, t_min, f_lo));
            add(zero_between(&tube, t_min, hi, f_min));
        }
    }
}

/// The parameter range of the line `p + t·d` (unit `d`, torus frame: centre at the origin)
/// inside the torus's bounding sphere of radius `e + r`, if it meets it.
#[inline]
fn sphere_span(e: f64, r: f64, p: Vec3, d: Vec3) -> Option<(f64, f64)> {
    let (bs, nb) = super::quad(1.0, 2.0 * p.dot(d), p.length_squared() - (e + r) * (e + r));
    (nb == 2).then(|| (bs[0].min(bs[1]), bs[0].max(bs[1])))
}

/// Whether a point of the torus (cutter frame) lies on the band: within its heights and on the
/// tube's outer half.
#[inline]
fn on_band(q: Vec3, e: f64, (z0, z1): (f64, f64)) -> bool {
    q.z >= z0 - BAND_EPS && q.z <= z1 + BAND_EPS && (q.x * q.x + q.y * q.y).sqrt() >= e - BAND_EPS
}

/// `F(t) = ρ(t) − e − √(r² − z(t)²)` along a line `p + t·d` (torus frame: centre at the
/// origin), with its derivatives.
struct TubeLine {
    e: f64,
    r: f64,
    p: Vec3,
    d: Vec3,
    /// `|d_xy|²` and `p_xy·d_xy`.
    dd: f64,
    pd: f64,
    pp: f64,
}

impl TubeLine {
    fn new(e: f64, r: f64, p: Vec3, d: Vec3) -> Self {
        Self {
            e,
            r,
            p,
            d,
            dd: d.x * d.x + d.y * d.y,
            pd: p.x * d.x + p.y * d.y,
            pp: p.x * p.x + p.y * p.y,
        }
    }

    /// `ρ(t)²` (clamped at 0), `ρ`, `z(t)` and `√(r² − z²)` (clamped at 0).
    #[inline]
    fn parts(&self, t: f64) -> (f64, f64, f64, f64) {
        let q = (self.pp + t * (2.0 * self.pd + t * self.dd)).max(0.0);
        let z = self.p.z + t * self.d.z;
        (q, q.sqrt(), z, (self.r * self.r - z * z).max(0.0).sqrt())
    }

    /// `F′` from the parts at `t`.
    #[inline]
    fn slope_of(&self, t: f64, (_, rho, z, s): (f64, f64, f64, f64)) -> f64 {
        let half_dq = self.pd + t * self.dd;
        let radial = if rho > 0.0 { half_dq / rho } else { 0.0 };
        let axial = if s > 0.0 {
            z * self.d.z / s
        } else if z * self.d.z == 0.0 {
            0.0
        } else {
            f64::INFINITY.copysign(z * self.d.z)
        };
        radial + axial
    }
}

impl ConvexLine for TubeLine {
    #[inline]
    fn value(&self, t: f64) -> f64 {
        let (_, rho, _, s) = self.parts(t);
        rho - self.e - s
    }

    /// `(F(t), F′(t))` from one evaluation of the parts (the Newton steps need both).
    #[inline]
    fn value_slope(&self, t: f64) -> (f64, f64) {
        let parts = self.parts(t);
        let (_, rho, _, s) = parts;
        (rho - self.e - s, self.slope_of(t, parts))
    }

    /// `F′(t)`: `(q′/2)/ρ + z·d_z/√(r² − z²)` (±∞ at the tube's top and bottom, where the
    /// square root vanishes; a subgradient where the line crosses the axis).
    #[inline]
    fn slope(&self, t: f64) -> f64 {
        self.slope_of(t, self.parts(t))
    }

    /// `F″(t) ≥ 0`: `(|d_xy|²·q − (q′/2)²)/ρ³ + d_z²·r²/√(r² − z²)³`.
    #[inline]
    fn curvature(&self, t: f64) -> Option<f64> {
        let (q, rho, _, s) = self.parts(t);
        let half_dq = self.pd + t * self.dd;
        let radial = if rho > 0.0 {
            ((self.dd * q - half_dq * half_dq) / (rho * q)).max(0.0)
        } else {
            0.0
        };
        let axial = if s > 0.0 {
            self.d.z * self.d.z * self.r * self.r / (s * s * s)
        } else {
            0.0
        };
        Some(radial + axial)
    }
}

/// [`cap`] by isolating the real roots of the line's quartic with the whole torus (the
/// previous kernel; the reference of the tests). Where the tube crosses the axis (`r > e`) the
/// algebraic torus also holds the sheet `ρ = √(r² − z²) − e` (the circle's part beyond the axis,
/// revolved); that kernel kept its points with `ρ ≥ e` — inside the solid, so harmless as
/// candidates — and this reference drops them, keeping crossings of the band itself.
#[cfg(test)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn cap_quartic(
    e: f64,
    f: f64,
    r: f64,
    _phi: (f64, f64),
    (z0, z1): (f64, f64),
    o: Vec3,
    d: Vec3,
    acc: &mut Acc,
    scratch: &mut Scratch,
) {
    let p = o - Vec3::new(0.0, 0.0, f);
    let g = p.dot(d);
    let pp = p.length_squared();
    let Some(bs) = sphere_span(e, r, p, d) else {
        return;
    };
    let hh = pp + e * e - r * r;
    let dxy = d.x * d.x + d.y * d.y;
    let pdxy = p.x * d.x + p.y * d.y;
    let pxy = p.x * p.x + p.y * p.y;
    let e4 = 4.0 * e * e;
    let c = [
        hh * hh - e4 * pxy,
        4.0 * g * hh - 2.0 * e4 * pdxy,
        4.0 * g * g + 2.0 * hh - e4 * dxy,
        4.0 * g,
        1.0,
    ];
    scratch.roots.clear();
    real_roots_in(&c, bs.0, bs.1, ROOT_TOL, &mut scratch.roots);
    for &t in &scratch.roots {
        let q = o + d * t;
        let outer = e + (r * r - (q.z - f).powi(2)).max(0.0).sqrt();
        if on_band(q, e, (z0, z1)) && (q.x.hypot(q.y) - outer).abs() <= 1e-6 {
            acc.add(t);
        }
    }
}

/// Ascending-coefficient product of two polynomials into `out` (`out.len() ≥ a + b − 1`).
fn mul(a: &[f64], b: &[f64], out: &mut [f64]) {
    out.iter_mut().for_each(|x| *x = 0.0);
    for (i, &x) in a.iter().enumerate() {
        for (j, &y) in b.iter().enumerate() {
            out[i + j] += x * y;
        }
    }
}

/// Crossings of the line with the envelope of the torus arc swept along `dc.v`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn envelope(
    e: f64,
    f: f64,
    r: f64,
    (phi0, phi1): (f64, f64),
    (z0, z1): (f64, f64),
    o: Vec3,
    dc: &DirConsts,
    acc: &mut Acc,
    scratch: &mut Scratch,
) {
    let (a, b) = (dc.v.x, dc.v.z);
    let w = dc.w;
    let se = BAND_EPS / dc.vv.sqrt();
    if b == 0.0 {
        // Horizontal move: the meridian arcs at θ = ±π/2 (planes y = ±…, normal to v = a·x)
        // extruded along x: cylinders about (·, ±e, f) of radius r.
        for sy in [1.0, -1.0] {
            let (py, pz) = (o.y - sy * e, o.z - f);
            let qa = dc.d.y * dc.d.y + dc.d.z * dc.d.z;
            if qa <= 1e-20 {
                continue;
            }
            let qb = 2.0 * (py * dc.d.y + pz * dc.d.z);
            let qc = py * py + pz * pz - r * r;
            let (rts, nr) = super::quad(qa, qb, qc);
            for &t in &rts[..nr] {
                let p = o + dc.d * t;
                let s = p.x / a;
                if s < -se || s > 1.0 + se {
                    continue;
                }
                if sy * p.y >= e - BAND_EPS && p.z >= z0 - BAND_EPS && p.z <= z1 + BAND_EPS {
                    acc.add(t);
                }
            }
        }
        return;
    }
    let k0 = w.z * f - w.dot(o);
    let pw = b * w.x - a * w.z;
    let cc = [
        a * a + b * b,
        0.0,
        2.0 * (b * b - a * a),
        0.0,
        a * a + b * b,
    ];
    let dd = [1.0, 0.0, 2.0, 0.0, 1.0];
    for half in [1.0f64, -1.0] {
        // α(1+u²) and β(1+u²) as quadratics in u; the second half flips cos and sin.
        let (ex, ey) = (half * e * w.x, half * e * w.y);
        let aq = [ex + k0, 2.0 * ey, -ex + k0];
        let (bx, by) = (half * pw, half * b * w.y);
        let bq = [bx, 2.0 * by, -bx];
        let mut a2 = [0.0; 5];
        mul(&aq, &aq, &mut a2);
        let mut b2 = [0.0; 5];
        mul(&bq, &bq, &mut b2);
        let mut t1 = [0.0; 9];
        mul(&a2, &cc, &mut t1);
        let mut t2 = [0.0; 9];
        mul(&b2, &dd, &mut t2);
        let mut poly = [0.0; 9];
        let r2 = r * r;
        for i in 0..9 {
            poly[i] = t1[i] - r2 * t2[i];
        }
        scratch.roots.clear();
        real_roots_in(&poly, -1.0, 1.0, ROOT_TOL, &mut scratch.roots);
        for ri in 0..scratch.roots.len() {
            let u = scratch.roots[ri];
            let den = 1.0 + u * u;
            let (x, y) = (half * (1.0 - u * u) / den, half * 2.0 * u / den);
            let cxv = Vec3::new(b * x, b * y, -a * x);
            let m = cxv / cxv.length();
            let cpt = Vec3::new(e * x, e * y, f);
            let alpha = w.dot(cpt - o);
            let wm = r * w.dot(m);
            let (ep, em) = ((alpha + wm).abs(), (alpha - wm).abs());
            let tolv = 1e-9 * (alpha.abs() + wm.abs()).max(1e-300);
            for (sign, err) in [(1.0, ep), (-1.0, em)] {
                if err > ep.min(em) + tolv {
                    continue;
                }
                let n = m * sign;
                // Polar angle of the normal: n = (sin φ cos θ, sin φ sin θ, −cos φ).
                let sphi = n.x * x + n.y * y;
                let phi = sphi.atan2(-n.z);
                let pe = BAND_EPS / r;
                if phi < phi0 - pe || phi > phi1 + pe {
                    continue;
                }
                let g = cpt + n * r;
                if g.z < z0 - BAND_EPS || g.z > z1 + BAND_EPS {
                    continue;
                }
                let (t, s) = dc.solve_ts(o, g);
                if (-se..=1.0 + se).contains(&s) {
                    acc.add(t);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tiny deterministic generator.
    struct Lcg(u64);
    impl Lcg {
        fn f(&mut self, a: f64, b: f64) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            a + (b - a) * ((self.0 >> 11) as f64) / ((1u64 << 53) as f64)
        }
    }

    /// The convex zeros agree with the quartic's isolated roots on random lines through and
    /// around bull-nose bands (spine 0.5–6, tube 0.3–4, quarter and other arcs), grazing lines
    /// and lines along and across the axis included.
    #[test]
    fn convex_zeros_match_the_quartic() {
        let mut rng = Lcg(7);
        let mut scratch = Scratch::new();
        let (mut hits, mut worst) = (0usize, 0.0f64);
        for case in 0..20_000 {
            let (e, r) = (rng.f(0.5, 6.0), rng.f(0.3, 4.0));
            let f = rng.f(-2.0, 2.0);
            let (phi0, phi1) = if case % 3 == 0 {
                (0.0, std::f64::consts::FRAC_PI_2)
            } else {
                let a = rng.f(0.0, 1.5);
                (a, rng.f(a + 0.01, std::f64::consts::PI))
            };
            let z0 = f - r * phi0.cos();
            let z1 = f - r * phi1.cos();
            let (z0, z1) = (z0.min(z1), z0.max(z1));
            let reach = e + r;
            let o = Vec3::new(
                rng.f(-reach, reach),
                rng.f(-reach, reach),
                f + rng.f(-1.5 * r, 1.5 * r),
            );
            // Every 11th line passes close to the tube's bottom or top circle, nearly level:
            // where F′ is huge and the zeros crowd the minimum.
            let o = if case % 11 == 0 {
                let a = rng.f(0.0, 6.3);
                let up = if case % 2 == 0 { 1.0 } else { -1.0 };
                let h = f + up * r * (1.0 - rng.f(0.0, 1e-3));
                Vec3::new((e + rng.f(-0.05, 0.05)) * a.cos(), e * a.sin(), h)
            } else {
                o
            };
            let d = match case % 7 {
                _ if case % 11 == 0 => {
                    Vec3::new(rng.f(-1.0, 1.0), rng.f(-1.0, 1.0), rng.f(-1e-3, 1e-3)).normalize()
                }
                0 => Vec3::Z,
                1 => Vec3::new(rng.f(-1.0, 1.0), rng.f(-1.0, 1.0), 0.0).normalize(),
                _ => Vec3::new(rng.f(-1.0, 1.0), rng.f(-1.0, 1.0), rng.f(-1.0, 1.0)).normalize(),
            };
            let (mut a, mut b) = (Acc::EMPTY, Acc::EMPTY);
            cap(e, f, r, (phi0, phi1), (z0, z1), o, d, &mut a, &mut scratch);
            cap_quartic(e, f, r, (phi0, phi1), (z0, z1), o, d, &mut b, &mut scratch);
            match (a.get(), b.get()) {
                (None, None) => {}
                (Some((a0, a1)), Some((b0, b1))) => {
                    hits += 1;
                    let err = (a0 - b0).abs().max((a1 - b1).abs());
                    worst = worst.max(err);
                    assert!(
                        err < 1e-7,
                        "case {case}: {:?} vs {:?} e {e} r {r} f {f} o {o} d {d} z {z0} {z1}",
                        (a0, a1),
                        (b0, b1)
                    );
                }
                // A line that only touches the tube (a double root) may be seen by one and
                // not the other; the touching point is then where both are within a hair.
                (x, y) => {
                    let (t0, t1) = x.or(y).unwrap();
                    assert!(
                        (t1 - t0).abs() < 1e-4,
                        "case {case}: {x:?} vs {y:?}, e {e} r {r} f {f} o {o} d {d}"
                    );
                }
            }
        }
        eprintln!("{hits} lines crossing a band, worst difference {worst:.2e} mm");
        assert!(hits > 4000, "{hits}");
    }
}
