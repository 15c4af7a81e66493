//! Spheres.

use super::{normalized_near, push_scaled, Implicit};
use crate::math::Vec3;
use crate::poly::quadratic_roots;
use crate::ray::Ray;

/// The sphere of `radius` around `center`; **inside** is the open ball.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Sphere {
    /// Centre.
    pub center: Vec3,
    /// Radius (≥ 0).
    pub radius: f64,
}

impl Sphere {
    /// The sphere of `radius` around `center`.
    pub fn new(center: Vec3, radius: f64) -> Self {
        Self { center, radius }
    }
}

impl Implicit for Sphere {
    fn signed_distance(&self, p: Vec3) -> f64 {
        (p - self.center).length() - self.radius
    }

    fn ray_intersections(&self, ray: &Ray, out: &mut Vec<f64>) {
        // From the point closest to the centre, |o + s d|² = r² has b = 0 (o ⟂ d), so
        // s = ±√(r² - |o|²) with no cancellation at all.
        let (o, _d, t0, len) = normalized_near(ray, self.center);
        let q = o - self.center;
        let roots = quadratic_roots(1.0, 0.0, q.length_squared() - self.radius * self.radius);
        push_scaled(roots.as_slice(), t0, len, out);
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::check_against_brute_force;
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn tangent_ray_reported_once() {
        let s = Sphere::new(Vec3::new(1.0, 2.0, 3.0), 2.0);
        let mut h = Vec::new();
        s.ray_intersections(&Ray::new(Vec3::new(-9.0, 2.0, 5.0), Vec3::X * 2.0), &mut h);
        assert_eq!(h, vec![5.0]);
    }

    #[test]
    fn far_ray_keeps_precision() {
        // A ray starting 1e7 mm away still hits within 1e-9 mm.
        let s = Sphere::new(Vec3::ZERO, 1.0);
        let mut h = Vec::new();
        s.ray_intersections(&Ray::new(Vec3::new(-1e7, 0.5, 0.0), Vec3::X), &mut h);
        let x = (1.0f64 - 0.25).sqrt();
        assert!(
            (h[0] - (1e7 - x)).abs() < 1e-8 && (h[1] - (1e7 + x)).abs() < 1e-8,
            "{h:?}"
        );
    }

    proptest! {
        #![proptest_config(swarf_testdata::proptest_config(256))]
        #[test]
        fn matches_brute_force(cx in -5.0f64..5.0, r in 0.1f64..5.0, ox in -10.0f64..10.0, oy in -10.0f64..10.0,
                               oz in -10.0f64..10.0, dx in -1.0f64..1.0, dy in -1.0f64..1.0, dz in -1.0f64..1.0) {
            let d = Vec3::new(dx, dy, dz);
            prop_assume!(d.length() > 0.1);
            let s = Sphere::new(Vec3::new(cx, -cx, 0.5), r);
            let res = check_against_brute_force(&s, &Ray::new(Vec3::new(ox, oy, oz), d), 40.0, 1e-9);
            prop_assert!(res.is_ok(), "{}", res.unwrap_err());
        }
    }
}
