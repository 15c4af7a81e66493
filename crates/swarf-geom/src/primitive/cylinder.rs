//! Infinite circular cylinders.

use super::{normalized_near, push_scaled, Implicit};
use crate::frame::Frame;
use crate::math::Vec3;
use crate::poly::quadratic_roots;
use crate::ray::Ray;

/// The infinite cylinder of `radius` around the frame's z axis; **inside** is the set of points
/// closer than `radius` to the axis. The signed distance is `ρ - radius` (ρ: distance to the
/// axis), which is exact for the infinite surface.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Cylinder {
    /// Placement; the axis is the frame's z axis through its origin.
    pub frame: Frame,
    /// Radius (≥ 0).
    pub radius: f64,
}

impl Cylinder {
    /// The cylinder of `radius` placed by `frame`.
    pub fn new(frame: Frame, radius: f64) -> Self {
        Self { frame, radius }
    }
}

impl Implicit for Cylinder {
    fn signed_distance(&self, p: Vec3) -> f64 {
        let l = self.frame.to_local(p);
        l.x.hypot(l.y) - self.radius
    }

    fn ray_intersections(&self, ray: &Ray, out: &mut Vec<f64>) {
        let (o, d, t0, len) = normalized_near(ray, self.frame.origin);
        let o = self.frame.to_local(o);
        let d = self.frame.vector_to_local(d);
        let a = d.x * d.x + d.y * d.y;
        let b = 2.0 * (o.x * d.x + o.y * d.y);
        let c = o.x * o.x + o.y * o.y - self.radius * self.radius;
        if a == 0.0 {
            // Parallel to the axis: inside or outside throughout, no isolated crossing.
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

    #[test]
    fn analytic_hits() {
        let c = Cylinder::new(Frame::from_axis(Vec3::new(1.0, 0.0, 0.0), Vec3::Y), 2.0);
        let mut h = Vec::new();
        // Along world Z through the axis at x=1: hits at z = ±2.
        c.ray_intersections(&Ray::new(Vec3::new(1.0, 7.0, -10.0), Vec3::Z), &mut h);
        assert!(
            (h[0] - 8.0).abs() < 1e-12 && (h[1] - 12.0).abs() < 1e-12,
            "{h:?}"
        );
        assert!((c.signed_distance(Vec3::new(4.0, -3.0, 4.0)) - 3.0).abs() < 1e-12);
        h.clear();
        c.ray_intersections(&Ray::new(Vec3::ZERO, Vec3::Y), &mut h);
        assert!(h.is_empty());
    }

    proptest! {
        #![proptest_config(swarf_testdata::proptest_config(256))]
        #[test]
        fn matches_brute_force(ax in -1.0f64..1.0, ay in -1.0f64..1.0, az in -1.0f64..1.0, r in 0.1f64..5.0,
                               ox in -10.0f64..10.0, oy in -10.0f64..10.0, oz in -10.0f64..10.0,
                               dx in -1.0f64..1.0, dy in -1.0f64..1.0, dz in -1.0f64..1.0) {
            let a = Vec3::new(ax, ay, az);
            let d = Vec3::new(dx, dy, dz);
            prop_assume!(a.length() > 0.1 && d.length() > 0.1 && a.normalize().cross(d.normalize()).length() > 0.05);
            let c = Cylinder::new(Frame::from_axis(Vec3::new(1.0, -2.0, 0.5), a), r);
            let res = check_against_brute_force(&c, &Ray::new(Vec3::new(ox, oy, oz), d), 1000.0, 1e-9);
            prop_assert!(res.is_ok(), "{}", res.unwrap_err());
        }
    }
}
