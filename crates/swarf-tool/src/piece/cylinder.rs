//! Cylinder bands: the straight side of an end mill, shanks, straight holder segments.

use super::{in_band, retain_from, Piece};
use swarf_geom::math::{Vec2, Vec3};
use swarf_geom::{Cylinder, Frame, Implicit, Ray};

/// The cylinder of `radius` between heights `z0 < z1`.
#[derive(Clone, Debug, PartialEq)]
pub struct CylinderPiece {
    /// Radius.
    pub radius: f64,
    /// Lower height.
    pub z0: f64,
    /// Upper height.
    pub z1: f64,
}

impl CylinderPiece {
    /// The band of the cylinder of `radius` between `z0` and `z1`.
    pub fn new(radius: f64, z0: f64, z1: f64) -> Self {
        Self { radius, z0, z1 }
    }
}

impl Piece for CylinderPiece {
    fn z_range(&self) -> (f64, f64) {
        (self.z0, self.z1)
    }

    fn profile_point(&self, s: f64) -> Vec2 {
        Vec2::new(self.radius, self.z0 + s * (self.z1 - self.z0))
    }

    fn profile_normal(&self, _s: f64) -> Vec2 {
        Vec2::X
    }

    fn radius_at(&self, z: f64) -> Option<f64> {
        (z >= self.z0 && z <= self.z1).then_some(self.radius)
    }

    fn ray_intersections(&self, ray: &Ray, out: &mut Vec<f64>) {
        let start = out.len();
        Cylinder::new(Frame::at(Vec3::ZERO), self.radius).ray_intersections(ray, out);
        let (z0, z1) = (self.z0, self.z1);
        retain_from(out, start, ray, |p| in_band(p.z, z0, z1));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn band_clipping() {
        let c = CylinderPiece::new(3.0, 0.5, 4.0);
        let mut h = Vec::new();
        // Slanted ray: x = -6 + t, z = t/3; crosses x = ±3 at t = 3 (z = 1) and t = 9 (z = 3).
        c.ray_intersections(
            &Ray::new(Vec3::new(-6.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 1.0 / 3.0)),
            &mut h,
        );
        assert_eq!(h.len(), 2);
        assert!((h[0] - 3.0).abs() < 1e-12 && (h[1] - 9.0).abs() < 1e-12);
        assert_eq!(c.radius_at(0.25), None);
        assert_eq!(c.normal(0.2, std::f64::consts::FRAC_PI_2).y, 1.0);
    }
}
