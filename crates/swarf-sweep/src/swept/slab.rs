//! A cylinder slab `{ρ ≤ r, z ∈ [z0, z1]}` (a flat end mill, a ball end mill's side, a shank)
//! swept along a segment with its axis along a world axis, against rays along world axes, in
//! closed form: a ray along the axis meets the sweep over the tool positions whose disc holds
//! it (one quadratic in the move parameter, [`disc_params`]); a ray across it sees, at its
//! fixed height, the stadium of the discs of the positions whose band holds that height (two
//! disc chords and a strip, [`across`]).

use super::quad;
use swarf_geom::math::{greater, lesser};

/// The move seen in the tool's axis-aligned frame: tip cross coordinates `(p_u, p_w)` and axial
/// `p_a` at the start, and the move `(m_u, m_w, m_a)` (u, w the two other world axes in cyclic
/// order after the tool axis).
#[derive(Clone, Copy, Debug)]
pub(crate) struct AxisMove {
    pub(crate) p: [f64; 3],
    pub(crate) m: [f64; 3],
}

/// The move parameters `[s0, s1] ⊂ [0, 1]` at which the disc of radius `r` about the tip path
/// holds the point `(qu, qw)` (cross coordinates), if any.
#[inline]
pub(crate) fn disc_params(mv: &AxisMove, r: f64, qu: f64, qw: f64) -> Option<(f64, f64)> {
    let (du, dw) = (qu - mv.p[0], qw - mv.p[1]);
    let (mu, mw) = (mv.m[0], mv.m[1]);
    let a = mu * mu + mw * mw;
    let c = du * du + dw * dw - r * r;
    if a == 0.0 {
        return (c <= 0.0).then_some((0.0, 1.0));
    }
    let b = -2.0 * (du * mu + dw * mw);
    let (rts, n) = quad(a, b, c);
    if n < 2 {
        // Tangent (or a single root at a float boundary): the chord is a point.
        return (n == 1 && (0.0..=1.0).contains(&rts[0])).then_some((rts[0], rts[0]));
    }
    let (s0, s1) = (rts[0].min(rts[1]).max(0.0), rts[0].max(rts[1]).min(1.0));
    (s0 <= s1).then_some((s0, s1))
}

/// The interval of a ray across the tool axis inside the sweep of the slab. The ray is along
/// cross axis `ray` (0 = u, 1 = w) at the other cross coordinate `q` and axial coordinate `za`.
#[inline]
pub(crate) fn across(
    mv: &AxisMove,
    r: f64,
    z0: f64,
    z1: f64,
    ray: usize,
    q: f64,
    za: f64,
) -> Option<(f64, f64)> {
    // Positions whose band [z0, z1] holds the ray's height: za − p_a − s·m_a ∈ [z0, z1].
    let rel = za - mv.p[2];
    let ma = mv.m[2];
    let (s0, s1) = if ma == 0.0 {
        if rel < z0 || rel > z1 {
            return None;
        }
        (0.0, 1.0)
    } else {
        let (x0, x1) = ((rel - z1) / ma, (rel - z0) / ma);
        let (s0, s1) = (x0.min(x1).max(0.0), x0.max(x1).min(1.0));
        if s0 > s1 {
            return None;
        }
        (s0, s1)
    };
    let o = 1 - ray;
    // The stadium of radius r about the cross-section path from s0 to s1, in (along, across).
    let (a0, b0) = (mv.p[ray] + s0 * mv.m[ray], mv.p[o] + s0 * mv.m[o]);
    let (a1, b1) = (mv.p[ray] + s1 * mv.m[ray], mv.p[o] + s1 * mv.m[o]);
    stadium_chord((a0, b0), (a1, b1), r, q)
}

/// The chord of the line `across = q` (parametrised by `along`) inside the 2-D stadium of
/// radius `r` about the segment from `c0` to `c1` (points as `(along, across)`): the union of
/// the two end discs and the strip between them. `None` when the line misses it.
///
/// Always inlined: called, it returns its pair through memory, and the caller's 16-byte
/// reload of two 8-byte stores stalls on store forwarding (that one instruction held a tenth
/// of the capsule kernel's samples in `perf annotate` of the finishing bench).
#[inline(always)]
pub(crate) fn stadium_chord(c0: (f64, f64), c1: (f64, f64), r: f64, q: f64) -> Option<(f64, f64)> {
    let ((a0, b0), (a1, b1)) = (c0, c1);
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for (ca, cb) in [(a0, b0), (a1, b1)] {
        let dq = q - cb;
        let h2 = r * r - dq * dq;
        if h2 >= 0.0 {
            let hh = h2.sqrt();
            lo = lesser(lo, ca - hh);
            hi = greater(hi, ca + hh);
        }
    }
    // The strip: |(x − c0)·n| ≤ r and 0 ≤ (x − c0)·e ≤ |e|², x = (p, q).
    let (ea, eb) = (a1 - a0, b1 - b0);
    let ee = ea * ea + eb * eb;
    if ee > 0.0 {
        let el = ee.sqrt();
        let (na, nb) = (-eb / el, ea / el);
        let dq = q - b0;
        let (mut x_lo, mut x_hi) = (f64::NEG_INFINITY, f64::INFINITY);
        let mut empty = false;
        for (coef, off, lo_v, hi_v) in [(na, nb * dq, -r, r), (ea, eb * dq, 0.0, ee)] {
            // lo_v ≤ coef·(x − a0) + off ≤ hi_v
            if coef == 0.0 {
                empty |= off < lo_v || off > hi_v;
            } else {
                let (x0, x1) = ((lo_v - off) / coef + a0, (hi_v - off) / coef + a0);
                x_lo = greater(x_lo, lesser(x0, x1));
                x_hi = lesser(x_hi, greater(x0, x1));
            }
        }
        if !empty && x_lo <= x_hi {
            lo = lesser(lo, x_lo);
            hi = greater(hi, x_hi);
        }
    }
    (lo <= hi).then_some((lo, hi))
}
