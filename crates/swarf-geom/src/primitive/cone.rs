//! Infinite double cones.

use super::{normalized_near, push_scaled, Implicit};
use crate::frame::Frame;
use crate::math::Vec3;
use crate::poly::quadratic_roots;
use crate::ray::Ray;

/// The infinite double cone with apex at the frame origin, axis the frame's z axis and
/// `half_angle` (radians, in `(0, π/2)`) between axis and surface.
///
/// **Inside** is the solid double cone: points whose line to the apex makes an angle below
/// `half_angle` with the axis (either nappe). Both nappes are part of the surface, so a ray can
/// meet it twice on different nappes; callers that want one nappe clip by the local z.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Cone {
    /// Placement: origin at the apex, z along the axis.
    pub frame: Frame,
    /// Angle between the axis and the surface, radians.
    pub half_angle: f64,
}

impl Cone {
    /// The double cone with `apex`, `axis` direction (non-zero) and `half_angle` in radians.
    pub fn new(apex: Vec3, axis: Vec3, half_angle: f64) -> Self {
        Self {
            frame: Frame::from_axis(apex, axis),
            half_angle,
        }
    }

    /// The double cone placed by `frame` (apex at its origin).
    pub fn from_frame(frame: Frame, half_angle: f64) -> Self {
        Self { frame, half_angle }
    }
}

impl Implicit for Cone {
    fn signed_distance(&self, p: Vec3) -> f64 {
        // In the meridian half-plane through p the surface is the two half-lines from the apex
        // at ±half_angle to the axis; reflecting z to |z| leaves the nearer one, the upper. The
        // foot of the perpendicular from (ρ, |z|) lies on that half-line (its projection
        // ρ·sin a + |z|·cos a ≥ 0 for a in (0, π/2)), so the distance is the line distance.
        let l = self.frame.to_local(p);
        let rho = l.x.hypot(l.y);
        let (s, c) = self.half_angle.sin_cos();
        rho * c - l.z.abs() * s
    }

    fn ray_intersections(&self, ray: &Ray, out: &mut Vec<f64>) {
        let (o, d, t0, len) = normalized_near(ray, self.frame.origin);
        let o = self.frame.to_local(o);
        let d = self.frame.vector_to_local(d);
        let k2 = self.half_angle.tan().powi(2);
        // x² + y² - k² z² = 0 along the line.
        let a = d.x * d.x + d.y * d.y - k2 * d.z * d.z;
        let b = 2.0 * (o.x * d.x + o.y * d.y - k2 * o.z * d.z);
        let c = o.x * o.x + o.y * o.y - k2 * o.z * o.z;
        if a == 0.0 && b == 0.0 {
            // A generator of the cone (or a line through the apex parallel to one).
            return;
        }
        let roots = quadratic_roots(a, b, c);
        push_scaled(roots.as_slice(), t0, len, out);
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::check_against_brute_force;
    use super::*;
    use proptest::prelude::*;
    use std::f64::consts::FRAC_PI_4;

    #[test]
    fn analytic_distance_and_hits() {
        let c = Cone::new(Vec3::ZERO, Vec3::Z, FRAC_PI_4);
        // A point on the axis at height 2 is √2 inside.
        assert!((c.signed_distance(Vec3::new(0.0, 0.0, 2.0)) + 2f64.sqrt()).abs() < 1e-12);
        assert!((c.signed_distance(Vec3::new(0.0, 3.0, -1.0)) - 2f64.sqrt()).abs() < 1e-12);
        let mut h = Vec::new();
        // Horizontal line at z = 2 meets the upper nappe at x = ±2.
        c.ray_intersections(&Ray::new(Vec3::new(-5.0, 0.0, 2.0), Vec3::X), &mut h);
        assert!(
            (h[0] - 3.0).abs() < 1e-12 && (h[1] - 7.0).abs() < 1e-12,
            "{h:?}"
        );
        // Along the axis: only the apex (a tangency-like touch), reported once.
        h.clear();
        c.ray_intersections(&Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z), &mut h);
        assert_eq!(h.len(), 1);
        assert!((h[0] - 5.0).abs() < 1e-12);
        // A generator: a continuum; rounding may leave an isolated point, which must then lie
        // on the surface.
        h.clear();
        let g = Ray::new(Vec3::ZERO, Vec3::new(1.0, 0.0, 1.0));
        c.ray_intersections(&g, &mut h);
        assert!(
            h.len() <= 1 && h.iter().all(|&t| c.signed_distance(g.at(t)).abs() < 1e-12),
            "{h:?}"
        );
    }

    proptest! {
        #![proptest_config(swarf_testdata::proptest_config(256))]
        #[test]
        fn matches_brute_force(ax in -1.0f64..1.0, ay in -1.0f64..1.0, az in -1.0f64..1.0, ang in 0.05f64..1.5,
                               ox in -10.0f64..10.0, oy in -10.0f64..10.0, oz in -10.0f64..10.0,
                               dx in -1.0f64..1.0, dy in -1.0f64..1.0, dz in -1.0f64..1.0) {
            let a = Vec3::new(ax, ay, az);
            let d = Vec3::new(dx, dy, dz);
            prop_assume!(a.length() > 0.1 && d.length() > 0.1);
            // Keep the line away from being parallel to a generator (roots at infinity).
            let cos_ad = a.normalize().dot(d.normalize()).abs();
            prop_assume!((cos_ad - ang.cos()).abs() > 0.05);
            let c = Cone::new(Vec3::new(1.0, -2.0, 0.5), a, ang);
            let res = check_against_brute_force(&c, &Ray::new(Vec3::new(ox, oy, oz), d), 2000.0, 1e-8);
            prop_assert!(res.is_ok(), "{}", res.unwrap_err());
        }
    }
}
