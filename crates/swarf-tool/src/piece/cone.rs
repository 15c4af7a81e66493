//! Cone frustums: the lower (bottom) cone of a pointed or chamfered cutter, a tapered side,
//! tapered holder segments.

use super::{in_band, retain_from, segment_normal, Piece};
use swarf_geom::math::{Vec2, Vec3};
use swarf_geom::{Cone, Frame, Implicit, Ray};

/// The frustum swept by the profile segment from `bottom = (ρ0, z0)` to `top = (ρ1, z1)`,
/// `z1 > z0` and `ρ0 ≠ ρ1`. Either radius may be 0 (a pointed end on the axis).
#[derive(Clone, Debug, PartialEq)]
pub struct ConePiece {
    /// Lower profile end `(ρ, z)`.
    pub bottom: Vec2,
    /// Upper profile end `(ρ, z)`.
    pub top: Vec2,
    cone: Cone,
}

impl ConePiece {
    /// The frustum between two profile points (`top.y > bottom.y`, radii different).
    pub fn new(bottom: Vec2, top: Vec2) -> Self {
        let slope = (top.x - bottom.x) / (top.y - bottom.y); // dρ/dz = tan(half-angle)
                                                             // The surface line meets the axis (ρ = 0) at the apex.
        let apex_z = bottom.y - bottom.x / slope;
        let cone = Cone::from_frame(Frame::at(Vec3::new(0.0, 0.0, apex_z)), slope.abs().atan());
        Self { bottom, top, cone }
    }

    /// Angle between the surface and the axis, radians (positive when the radius grows with z).
    pub fn half_angle(&self) -> f64 {
        ((self.top.x - self.bottom.x) / (self.top.y - self.bottom.y)).atan()
    }

    /// Height of the apex (where the surface line meets the axis).
    pub fn apex_z(&self) -> f64 {
        self.cone.frame.origin.z
    }
}

impl Piece for ConePiece {
    fn z_range(&self) -> (f64, f64) {
        (self.bottom.y, self.top.y)
    }

    fn profile_point(&self, s: f64) -> Vec2 {
        self.bottom.lerp(self.top, s)
    }

    fn profile_normal(&self, _s: f64) -> Vec2 {
        segment_normal(self.bottom, self.top)
    }

    fn radius_at(&self, z: f64) -> Option<f64> {
        let (z0, z1) = (self.bottom.y, self.top.y);
        (z >= z0 && z <= z1).then(|| {
            let s = (z - z0) / (z1 - z0);
            self.bottom.x + s * (self.top.x - self.bottom.x)
        })
    }

    fn ray_intersections(&self, ray: &Ray, out: &mut Vec<f64>) {
        let start = out.len();
        self.cone.ray_intersections(ray, out);
        let (z0, z1) = (self.bottom.y, self.top.y);
        // The band selects one nappe of the double cone: the apex is outside (or at the end of)
        // the band.
        retain_from(out, start, ray, |p| in_band(p.z, z0, z1));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn v_bit_cone() {
        // 90° V: radius = z, from the tip to ρ = 5.
        let c = ConePiece::new(Vec2::new(0.0, 0.0), Vec2::new(5.0, 5.0));
        assert!((c.radius_at(2.5).unwrap() - 2.5).abs() < 1e-15);
        assert_eq!(c.radius_at(6.0), None);
        let n = c.profile_normal(0.3);
        assert!((n - Vec2::new(1.0, -1.0).normalize()).length() < 1e-15);
        let mut h = Vec::new();
        // Horizontal ray at z = 2: crosses at x = ±2; the lower nappe (z < 0) never appears.
        c.ray_intersections(&Ray::new(Vec3::new(-10.0, 0.0, 2.0), Vec3::X), &mut h);
        assert_eq!(h.len(), 2);
        assert!((h[0] - 8.0).abs() < 1e-12 && (h[1] - 12.0).abs() < 1e-12);
        h.clear();
        c.ray_intersections(&Ray::new(Vec3::new(-10.0, 0.0, -2.0), Vec3::X), &mut h);
        assert!(h.is_empty());
    }

    #[test]
    fn back_taper_apex_above() {
        // Radius shrinking upwards: apex above the band.
        let c = ConePiece::new(Vec2::new(4.0, 0.0), Vec2::new(2.0, 2.0));
        assert!((c.apex_z() - 4.0).abs() < 1e-15);
        assert!(c.half_angle() < 0.0);
        let mut h = Vec::new();
        c.ray_intersections(&Ray::new(Vec3::new(-10.0, 0.0, 1.0), Vec3::X), &mut h);
        assert_eq!(h.len(), 2);
        assert!((h[0] - 7.0).abs() < 1e-12, "{h:?}");
    }
}
