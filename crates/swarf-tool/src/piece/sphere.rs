//! Sphere arcs: the corner of a ball-nose (APT corner centre on the axis, e = 0).

use super::{in_band, retain_from, Piece};
use swarf_geom::math::{Vec2, Vec3};
use swarf_geom::{Implicit, Ray, Sphere};

/// The arc of the circle of `radius` centred on the axis at `center_z`, for polar angles
/// `φ ∈ [phi0, phi1] ⊂ [0, π]`, revolved: profile point `(radius·sin φ, center_z − radius·cos φ)`.
#[derive(Clone, Debug, PartialEq)]
pub struct SpherePiece {
    /// Ball radius.
    pub radius: f64,
    /// Height of the ball centre.
    pub center_z: f64,
    /// Lower polar angle, radians (0 = the tip).
    pub phi0: f64,
    /// Upper polar angle, radians.
    pub phi1: f64,
}

impl SpherePiece {
    /// The spherical zone between polar angles `phi0 < phi1` (radians).
    pub fn new(radius: f64, center_z: f64, phi0: f64, phi1: f64) -> Self {
        Self {
            radius,
            center_z,
            phi0,
            phi1,
        }
    }

    fn phi(&self, s: f64) -> f64 {
        self.phi0 + s * (self.phi1 - self.phi0)
    }
}

impl Piece for SpherePiece {
    fn z_range(&self) -> (f64, f64) {
        (
            self.center_z - self.radius * self.phi0.cos(),
            self.center_z - self.radius * self.phi1.cos(),
        )
    }

    fn profile_point(&self, s: f64) -> Vec2 {
        let (sn, cs) = self.phi(s).sin_cos();
        Vec2::new(self.radius * sn, self.center_z - self.radius * cs)
    }

    fn profile_normal(&self, s: f64) -> Vec2 {
        let (sn, cs) = self.phi(s).sin_cos();
        Vec2::new(sn, -cs)
    }

    fn radius_at(&self, z: f64) -> Option<f64> {
        let (z0, z1) = self.z_range();
        (z >= z0 && z <= z1).then(|| {
            let dz = z - self.center_z;
            (self.radius * self.radius - dz * dz).max(0.0).sqrt()
        })
    }

    fn ray_intersections(&self, ray: &Ray, out: &mut Vec<f64>) {
        let start = out.len();
        Sphere::new(Vec3::new(0.0, 0.0, self.center_z), self.radius).ray_intersections(ray, out);
        let (z0, z1) = self.z_range();
        retain_from(out, start, ray, |p| in_band(p.z, z0, z1));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn lower_hemisphere() {
        let s = SpherePiece::new(5.0, 5.0, 0.0, FRAC_PI_2);
        assert_eq!(s.z_range(), (0.0, 5.0));
        assert!((s.radius_at(1.0).unwrap() - 3.0).abs() < 1e-15);
        let mut h = Vec::new();
        s.ray_intersections(&Ray::new(Vec3::new(0.0, 0.0, -1.0), Vec3::Z), &mut h);
        assert_eq!(h, vec![1.0]); // the top intersection (z = 10) is outside the band
        assert!((s.point(0.0, 0.3) - Vec3::ZERO).length() < 1e-15);
    }
}
