//! A cutter of the APT family placed in the part: the exact solid, its signed distance and
//! outward normal. The solvers use it for normals and fallbacks; the tests use it to check
//! every imaginary size against geometry.
//!
//! The profile, in a meridian half-plane `(ρ, z)` with `z` measured from the corner-circle
//! centre plane: a side line of taper `θ` (radius grows upwards), the corner arc of radius `r`
//! centred at `(R, 0)`, and a bottom cone of angle `ψ` down to the tip on the axis (`ψ = 0`: a
//! flat bottom at `z = −r`). A ball or tapered ball is the case `R = 0`, `ψ = 0`. At height `z`
//! the solid's radius is `R + t(z)`:
//!
//! * side, `z ≥ −r·sin θ`: `t = z·tan θ + r/cos θ`;
//! * corner, `−r·cos ψ < z < −r·sin θ`: `t = √(r² − z²)`;
//! * bottom, `z ≤ −r·cos ψ`: `t = z/tan ψ + r/sin ψ` (Liu's eq. 2.30 with the erratum), and for
//!   `ψ = 0` nothing below `z = −r`.

use swarf_geom::math::{Vec2, Vec3};

use super::imaginary_apt::AptTrig;

/// An APT-family cutter placed with its axis along `+Z`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlacedCutter {
    /// A point of the axis (its z is ignored).
    pub axis: Vec3,
    /// Height of the corner-circle centre plane, mm.
    pub corner_z: f64,
    /// Distance from the axis to the corner-circle centre, mm (≥ 0).
    pub big_r: f64,
    /// Corner radius, mm (≥ 0).
    pub r: f64,
    /// Side taper θ, radians, `[0, π/2)`.
    pub taper: f64,
    /// Bottom cone angle ψ, radians, `[0, π/2)`.
    pub cone: f64,
    /// A bare sphere (`R = 0`, no side): the ball of [`super::CutterFamily::Sphere`].
    pub sphere_only: bool,
}

impl PlacedCutter {
    /// `t(z)` of the module docs, or `None` below a flat bottom (never inside).
    pub fn t(&self, z: f64) -> Option<f64> {
        let (r, th, ps) = (self.r, self.taper, self.cone);
        if self.sphere_only {
            return (z.abs() < r).then(|| (r * r - z * z).sqrt());
        }
        if ps == 0.0 && z <= -r {
            return None;
        }
        if z >= -r * th.sin() {
            Some(z * th.tan() + r / th.cos())
        } else if z > -r * ps.cos() {
            Some((r * r - z * z).max(0.0).sqrt())
        } else if ps > 0.0 {
            Some(z / ps.tan() + r / ps.sin())
        } else {
            None
        }
    }

    /// Meridian coordinates `(ρ, z)` of `p` and the unit horizontal direction from the axis.
    pub fn meridian(&self, p: Vec3) -> (f64, f64, Vec3) {
        let h = Vec3::new(p.x - self.axis.x, p.y - self.axis.y, 0.0);
        let rho = h.length();
        let e = if rho > 0.0 { h / rho } else { Vec3::X };
        (rho, p.z - self.corner_z, e)
    }

    /// True when `p` is strictly inside the solid by more than `slack` in radius.
    pub fn contains(&self, p: Vec3, slack: f64) -> bool {
        let (rho, z, _) = self.meridian(p);
        match self.t(z) {
            Some(t) => self.big_r + t >= 0.0 && rho < self.big_r + t - slack,
            None => false,
        }
    }

    /// The profile's point nearest `q` (meridian coordinates) and its outward normal.
    fn closest_on_profile(&self, q: Vec2) -> (Vec2, Vec2) {
        let (r, th, ps) = (self.r, self.taper, self.cone);
        let c = Vec2::new(self.big_r, 0.0);
        if self.sphere_only {
            let d = q - c;
            let nrm = if d.length() > 0.0 {
                d.normalize()
            } else {
                Vec2::new(0.0, -1.0)
            };
            return (c + r * nrm, nrm);
        }
        AptTrig::new(th, ps).closest_on_profile(self.big_r, r, q)
    }

    /// Signed distance from `p` to the solid's boundary: negative inside.
    pub fn signed_distance(&self, p: Vec3) -> f64 {
        let (rho, z, _) = self.meridian(p);
        let (pt, _) = self.closest_on_profile(Vec2::new(rho, z));
        let d = (Vec2::new(rho, z) - pt).length();
        if self.contains(p, 0.0) {
            -d
        } else {
            d
        }
    }

    /// The outward unit normal of the boundary nearest to `p`.
    pub fn outward_normal(&self, p: Vec3) -> Vec3 {
        let (rho, z, e) = self.meridian(p);
        let (_, n) = self.closest_on_profile(Vec2::new(rho, z));
        (n.x * e + n.y * Vec3::Z).normalize()
    }

    /// The lowest point of the solid (the tip, or the centre of the flat bottom).
    pub fn tip(&self) -> Vec3 {
        let (r, ps) = (self.r, self.cone);
        let z = if self.sphere_only {
            -r
        } else if ps > 0.0 {
            -self.big_r * ps.tan() - r / ps.cos()
        } else {
            -r
        };
        Vec3::new(self.axis.x, self.axis.y, self.corner_z + z)
    }
}
