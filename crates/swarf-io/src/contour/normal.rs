//! Normal estimation at a crossing from the crossings of the same ray family nearby.
//!
//! Seen from the family of axis `a`, the surface near a crossing at `t` on line `(u, v)` is a
//! height field `t = f(u, v)`. The matching interval ends (entries for an entry, exits for an
//! exit) nearest to `t` on the lines `u ± 1, u ± 2` (and likewise along `v`) sample `f`; one
//! farther than `max_slope × spacing × lines apart` is not the same surface. The slope along
//! each direction is chosen ENO-style among the central difference and the two one-sided ones:
//! the candidate whose second difference is smallest wins (central on ties), so flat faces give
//! exactly flat normals and a one-sided stencil looks away from a nearby edge. With only
//! first differences available, the smaller one wins. The outward normal of an exit is
//! `e_a − f_u e_u − f_v e_v` normalised (negated for an entry).

use super::lines::{nearest, Store};
use crate::tolerance::ENO_ONE_SIDED_FACTOR;
use swarf_geom::math::Vec3;

fn unit(k: usize) -> Vec3 {
    let mut e = Vec3::ZERO;
    e[k] = 1.0;
    e
}

/// The estimated outward unit normal at the crossing `t` (an exit when `exit`) on line
/// `(u, v)` of family `a`, or `None` when some direction has no usable neighbour.
pub(crate) fn estimate(
    store: &Store,
    a: usize,
    u: isize,
    v: isize,
    t: f64,
    exit: bool,
    max_slope: f64,
) -> Option<Vec3> {
    let fam = &store.fam[a];
    let mut grad = [0.0; 2];
    for (d, g) in grad.iter_mut().enumerate() {
        let axis = (a + 1 + d) % 3;
        let h = store.lattice.spacing[axis];
        let at = |k: isize| -> Option<f64> {
            let spans = if d == 0 {
                fam.get(u + k, v)
            } else {
                fam.get(u, v + k)
            };
            nearest(spans, t, exit)
                .filter(|&s| (s - t).abs() <= max_slope * h * k.unsigned_abs() as f64)
        };
        let (m1, p1) = (at(-1), at(1));
        let m2 = m1.and_then(|_| at(-2));
        let p2 = p1.and_then(|_| at(2));
        let dm = m1.map(|m| t - m);
        let dp = p1.map(|p| p - t);
        // (slope × h, smoothness score)
        let mut best: Option<(f64, f64)> = None;
        let mut consider = |c: Option<(f64, f64)>| {
            if let Some((s, score)) = c {
                if best.map_or(true, |(_, b)| score < b) {
                    best = Some((s, score));
                }
            }
        };
        // The central difference is second-order accurate on smooth surfaces: a one-sided one
        // must be clearly smoother to replace it.
        consider(
            dm.zip(dp)
                .map(|(m, p)| (0.5 * (m + p), ENO_ONE_SIDED_FACTOR * (p - m).abs())),
        );
        consider(
            dm.zip(m1.zip(m2))
                .map(|(dm, (m1, m2))| (dm, (t - 2.0 * m1 + m2).abs())),
        );
        consider(
            dp.zip(p1.zip(p2))
                .map(|(dp, (p1, p2))| (dp, (p2 - 2.0 * p1 + t).abs())),
        );
        let slope = match best {
            Some((s, _)) => s,
            None => match (dm, dp) {
                (Some(m), Some(p)) => {
                    if m.abs() <= p.abs() {
                        m
                    } else {
                        p
                    }
                }
                (Some(s), None) | (None, Some(s)) => s,
                (None, None) => return None,
            },
        };
        *g = slope / h;
    }
    let (eb, ec) = (unit((a + 1) % 3), unit((a + 2) % 3));
    let n = (unit(a) - grad[0] * eb - grad[1] * ec).normalize();
    Some(if exit { n } else { -n })
}
