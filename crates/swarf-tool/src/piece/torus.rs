//! Torus arcs: the corner of a bull-nose (or any APT cutter with the corner centre off-axis).

use super::{in_band, retain_from, Piece};
use swarf_geom::math::{Vec2, Vec3};
use swarf_geom::{Frame, Implicit, Ray, Torus};

/// The arc of the circle of radius `minor` centred at `(major, center_z)` in the profile, for
/// polar angles `φ ∈ [phi0, phi1] ⊂ [0, π]`, revolved about the axis. The profile point at
/// angle φ is `(major + minor·sin φ, center_z − minor·cos φ)`: φ = 0 is the bottom of the
/// corner circle, φ = π/2 its outermost point.
#[derive(Clone, Debug, PartialEq)]
pub struct TorusPiece {
    /// Distance from the axis to the corner centre (> 0).
    pub major: f64,
    /// Corner radius (> 0).
    pub minor: f64,
    /// Height of the corner centre.
    pub center_z: f64,
    /// Lower polar angle, radians.
    pub phi0: f64,
    /// Upper polar angle, radians.
    pub phi1: f64,
    torus: Torus,
}

impl TorusPiece {
    /// The corner arc between polar angles `phi0 < phi1` (radians, within `[0, π]`).
    pub fn new(major: f64, minor: f64, center_z: f64, phi0: f64, phi1: f64) -> Self {
        let torus = Torus::new(Frame::at(Vec3::new(0.0, 0.0, center_z)), major, minor);
        Self {
            major,
            minor,
            center_z,
            phi0,
            phi1,
            torus,
        }
    }

    fn phi(&self, s: f64) -> f64 {
        self.phi0 + s * (self.phi1 - self.phi0)
    }
}

impl Piece for TorusPiece {
    fn z_range(&self) -> (f64, f64) {
        (
            self.center_z - self.minor * self.phi0.cos(),
            self.center_z - self.minor * self.phi1.cos(),
        )
    }

    fn profile_point(&self, s: f64) -> Vec2 {
        let (sn, cs) = self.phi(s).sin_cos();
        Vec2::new(
            self.major + self.minor * sn,
            self.center_z - self.minor * cs,
        )
    }

    fn profile_normal(&self, s: f64) -> Vec2 {
        let (sn, cs) = self.phi(s).sin_cos();
        Vec2::new(sn, -cs)
    }

    fn radius_at(&self, z: f64) -> Option<f64> {
        let (z0, z1) = self.z_range();
        (z >= z0 && z <= z1).then(|| {
            let dz = z - self.center_z;
            self.major + (self.minor * self.minor - dz * dz).max(0.0).sqrt()
        })
    }

    fn ray_intersections(&self, ray: &Ray, out: &mut Vec<f64>) {
        let start = out.len();
        self.torus.ray_intersections(ray, out);
        let (z0, z1) = self.z_range();
        let major = self.major;
        // z band ⇔ φ band (z is monotone in φ on [0, π]); ρ ≥ major keeps the outer half of
        // the tube, where sin φ ≥ 0.
        retain_from(out, start, ray, |p| {
            in_band(p.z, z0, z1) && p.x.hypot(p.y) >= major
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn bull_corner_quarter() {
        // Bull nose d=16, r=2: centre (6, 2), arc φ ∈ [0, π/2], z ∈ [0, 2].
        let t = TorusPiece::new(6.0, 2.0, 2.0, 0.0, FRAC_PI_2);
        let (z0, z1) = t.z_range();
        assert!(z0 == 0.0 && (z1 - 2.0).abs() < 1e-15);
        assert!((t.radius_at(z1).unwrap() - 8.0).abs() < 1e-15);
        assert!((t.radius_at(0.0).unwrap() - 6.0).abs() < 1e-15);
        // At z = 2 - √2·... : radius 6 + √(4 - 1) at z = 1.
        assert!((t.radius_at(1.0).unwrap() - (6.0 + 3f64.sqrt())).abs() < 1e-15);
        let mut h = Vec::new();
        // Horizontal ray at z = 1: outer crossings only at x = ±(6 + √3).
        t.ray_intersections(&Ray::new(Vec3::new(-20.0, 0.0, 1.0), Vec3::X), &mut h);
        h.sort_by(f64::total_cmp);
        assert_eq!(h.len(), 2, "{h:?}");
        assert!((h[0] - (20.0 - 6.0 - 3f64.sqrt())).abs() < 1e-9);
        // The upper half of the tube (z > 2) is not part of the piece.
        h.clear();
        t.ray_intersections(&Ray::new(Vec3::new(-20.0, 0.0, 3.0), Vec3::X), &mut h);
        assert!(h.is_empty(), "{h:?}");
    }
}
