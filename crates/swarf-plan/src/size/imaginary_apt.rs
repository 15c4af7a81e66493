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

use swarf_geom::math::Vec3;

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
