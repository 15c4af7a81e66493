//! Imaginary size of the APT family (Liu §2.3.2): corner radius `r`, taper `θ` and cone angle
//! `ψ` fixed, `R` solved for. The flat end mill (`r = θ = ψ = 0`) and the bull-nose (`θ = ψ =
//! 0`) are the special cases the map uses.
//!
//! With the contact on the corner, the corner-circle centre `Q = C + r·n` is fixed and the axis
//! lies at `Q_xy + R·u`. A test point at height `Δz` above `Q` and horizontal offset `d` from
//! `Q` is inside the cutter iff `|d − R·u| < R + t(Δz)` (see [`PlacedCutter`](super::PlacedCutter)
//! for `t`), which is Liu's eqs. 2.10, 2.21 and 2.29 in one: squaring gives a *linear* equation
//! in `R`, `R = (|d|² − t²) / (2(d·u + t))` (eqs. 2.11, 2.22, 2.30 corrected), and the branches
//! are
//!
//! * `|d| < t`: inside even the smallest cutter, `R = 0` (eqs. 2.6, 2.12);
//! * `d·u + t ≤ 0`: never reached, `R = ∞` (eqs. 2.9, 2.18–2.20) — also below a flat bottom;
//! * otherwise the formula, which is ≥ 0 and satisfies `R + t ≥ 0` (the root is the real one).
//!
//! With the contact on the bottom (vertical normal, or within `ψ` of vertical for a conical
//! bottom) the axis passes through `C`: for `ψ = 0` the corner-centre plane is fixed at
//! `C_z + r` and `R = ρ − t(Δz)`; for `ψ > 0` it rises with `R` and the size is found by
//! bisection on the nested family (rare: conical bottoms under near-horizontal spots).

use swarf_geom::math::{Vec2, Vec3};

use super::{Contact, CutterFamily, Regime, SizeTolerances};

/// Bisection steps for the conical-bottom placement (halves the bracket each step).
const BISECTION_STEPS: u32 = 200;
/// The largest finite size the bisection tries before answering `∞`, mm.
const SIZE_CEILING: f64 = 1e12;

/// The sines, cosines and tangents of an APT cutter's side taper `θ` and bottom cone `ψ`,
/// computed once: the solvers evaluate imaginary sizes by the million.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct AptTrig {
    pub(super) sin_t: f64,
    pub(super) cos_t: f64,
    pub(super) tan_t: f64,
    pub(super) sin_c: f64,
    pub(super) cos_c: f64,
    pub(super) tan_c: f64,
    /// `ψ = 0`: a flat bottom.
    pub(super) flat_bottom: bool,
}

impl AptTrig {
    pub(super) fn new(taper: f64, cone: f64) -> Self {
        Self {
            sin_t: taper.sin(),
            cos_t: taper.cos(),
            tan_t: taper.tan(),
            sin_c: cone.sin(),
            cos_c: cone.cos(),
            tan_c: cone.tan(),
            flat_bottom: cone == 0.0,
        }
    }

    /// The point of the profile nearest `q` (meridian coordinates `(ρ, z − corner centre)`, the
    /// corner circle of radius `r` centred at `(big_r, 0)`) and the outward normal there: the
    /// nearest of the side ray, the corner arc (its normal clamped to the arc's ends without
    /// angles: outside the arc the nearer end is the one whose normal leans more towards `q`) and
    /// the bottom segment to the axis.
    pub(super) fn closest_on_profile(&self, big_r: f64, r: f64, q: Vec2) -> (Vec2, Vec2) {
        let c = Vec2::new(big_r, 0.0);
        let mut best = (f64::INFINITY, Vec2::ZERO, Vec2::new(0.0, -1.0));
        let mut consider = |pt: Vec2, normal: Vec2| {
            let d = (q - pt).length();
            if d < best.0 {
                best = (d, pt, normal);
            }
        };
        // Side ray from the top of the corner, direction (sin θ, cos θ).
        let n_side = Vec2::new(self.cos_t, -self.sin_t);
        let s0 = c + r * n_side;
        let dir = Vec2::new(self.sin_t, self.cos_t);
        consider(s0 + (q - s0).dot(dir).max(0.0) * dir, n_side);
        // Corner arc, normals from the bottom's (sin ψ, −cos ψ) to the side's (less than a
        // quarter turn).
        let n_bot = Vec2::new(self.sin_c, -self.cos_c);
        let v = q - c;
        let inside_arc = n_bot.perp_dot(v) >= 0.0 && v.perp_dot(n_side) >= 0.0;
        let nrm = if inside_arc && v.length_squared() > 0.0 {
            v.normalize()
        } else if v.dot(n_bot) > v.dot(n_side) {
            n_bot
        } else {
            n_side
        };
        consider(c + r * nrm, nrm);
        // Bottom, from the corner's lowest tangent point to the tip on the axis.
        let b0 = c + r * n_bot;
        let seg = Vec2::new(0.0, b0.y - b0.x * self.tan_c) - b0;
        let len2 = seg.length_squared();
        let s = if len2 > 0.0 {
            ((q - b0).dot(seg) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        consider(b0 + s * seg, n_bot);
        (best.1, best.2)
    }

    /// The profile's radius beyond `R` at height `dz` above the corner-circle centre (`t(z)` of
    /// [`super::PlacedCutter`]), `None` on or below a flat bottom's plane.
    pub(super) fn t(&self, r: f64, dz: f64, tol: &SizeTolerances) -> Option<f64> {
        if self.flat_bottom && dz <= -r + tol.contact {
            // On or below the flat bottom's plane: touching at most, never gouging.
            return None;
        }
        if dz >= -r * self.sin_t {
            Some(dz * self.tan_t + r / self.cos_t)
        } else if dz > -r * self.cos_c {
            Some((r * r - dz * dz).max(0.0).sqrt())
        } else if !self.flat_bottom {
            Some(dz / self.tan_c + r / self.sin_c)
        } else {
            None
        }
    }
}

/// Corner contact: closed form.
pub(super) fn corner(
    trig: &AptTrig,
    r: f64,
    q: Vec3,
    u: Vec3,
    p: Vec3,
    tol: &SizeTolerances,
) -> f64 {
    let dz = p.z - q.z;
    let Some(t) = trig.t(r, dz, tol) else {
        return f64::INFINITY;
    };
    let d = Vec3::new(p.x - q.x, p.y - q.y, 0.0);
    let b = d.length_squared();
    // Touching within the contact tolerance is not gouging.
    if b.sqrt() < t - tol.contact {
        return 0.0;
    }
    let den = d.dot(u) + t;
    if den <= 0.0 {
        return f64::INFINITY;
    }
    ((b - t * t) / (2.0 * den)).max(0.0)
}

/// Bottom contact: the axis through the CC point.
pub(super) fn bottom(
    family: &CutterFamily,
    trig: &AptTrig,
    r: f64,
    cone: f64,
    c: &Contact,
    p: Vec3,
    tol: &SizeTolerances,
) -> f64 {
    let rho = Vec3::new(p.x - c.point.x, p.y - c.point.y, 0.0).length();
    let z = p.z - c.point.z;
    if cone == 0.0 {
        let Some(t) = trig.t(r, z - r, tol) else {
            return f64::INFINITY;
        };
        return if rho < t - tol.contact { 0.0 } else { rho - t };
    }
    // Conical bottom: below the cone through the tip, never reached.
    if z <= rho * cone.tan() + tol.contact {
        return f64::INFINITY;
    }
    let inside_by = |l: f64, slack: f64| {
        family
            .placed(c, &Regime::Bottom, l)
            .is_some_and(|k| k.contains(p, slack))
    };
    let inside = |l: f64| inside_by(l, 0.0);
    if inside_by(0.0, tol.contact) {
        return 0.0;
    }
    let mut hi = 1.0;
    while !inside(hi) {
        hi *= 2.0;
        if hi > SIZE_CEILING {
            return f64::INFINITY;
        }
    }
    let mut lo = 0.0;
    for _ in 0..BISECTION_STEPS {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if inside(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}
