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
    scratch: &mut Scratch,
) {
    let p = o - Vec3::new(0.0, 0.0, f);
    let g = p.dot(d);
    let pp = p.length_squared();
    // Parameter range inside the bounding sphere of radius e + r.
    let (bs, nb) = super::quad(1.0, 2.0 * g, pp - (e + r) * (e + r));
    if nb < 2 {
        return;
    }
    let bs = [bs[0].min(bs[1]), bs[0].max(bs[1])];
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
    real_roots_in(&c, bs[0], bs[1], ROOT_TOL, &mut scratch.roots);
    for &t in &scratch.roots {
        let q = o + d * t;
        if q.z >= z0 - BAND_EPS && q.z <= z1 + BAND_EPS && q.x.hypot(q.y) >= e - BAND_EPS {
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
