//! Tori: ring (R > r), horn (R = r), spindle (R < r) and the sphere limit R = 0.

use super::{normalized_near, push_scaled, Implicit};
use crate::frame::Frame;
use crate::math::Vec3;
use crate::poly::{real_roots_in, RootTolerance};
use crate::ray::Ray;

/// The torus swept by a circle of radius `minor` whose centre runs on the circle of radius
/// `major` around the frame's z axis, in the frame's xy plane.
///
/// The surface is the set of points at distance exactly `minor` from that spine circle and
/// **inside** is the solid swept by the ball, `{p : dist(p, spine) < minor}`. For a spindle
/// torus (`major < minor`) the algebraic quartic also contains an inner "lemon" whose points lie
/// at distance `minor` from the *far* side of the spine; those points are inside the solid, not
/// on its surface, and are neither reported by [`Implicit::ray_intersections`] nor used by
/// [`Implicit::signed_distance`]. With `major = 0` the torus is a sphere of radius `minor`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Torus {
    /// Placement: origin at the centre, z along the axis.
    pub frame: Frame,
    /// Radius of the spine circle, R ≥ 0.
    pub major: f64,
    /// Radius of the tube, r > 0.
    pub minor: f64,
    /// Accuracy of the quartic root isolation (ray parameter, mm for a unit direction).
    pub root_tol: RootTolerance,
}

impl Torus {
    /// A torus placed by `frame` with the default root tolerance.
    pub fn new(frame: Frame, major: f64, minor: f64) -> Self {
        Self {
            frame,
            major,
            minor,
            root_tol: RootTolerance::DEFAULT,
        }
    }

    /// The same torus with another root-isolation tolerance.
    pub fn with_root_tolerance(mut self, tol: RootTolerance) -> Self {
        self.root_tol = tol;
        self
    }
}

impl Implicit for Torus {
    fn signed_distance(&self, p: Vec3) -> f64 {
        let l = self.frame.to_local(p);
        let rho = l.x.hypot(l.y);
        let (big_r, r) = (self.major, self.minor);
        // Nearest point of a surface of revolution lies in the meridian half-plane of p, where
        // the surface is the circle of radius r about (R, 0), clipped to ρ ≥ 0.
        let g = (rho - big_r).hypot(l.z);
        let inside = g < r;
        if big_r >= r || g == 0.0 {
            return g - r;
        }
        // Spindle: the radial projection of (ρ, z) onto the circle may fall at ρ < 0 (the part
        // clipped away); the nearest point is then an end of the clipped arc, on the axis.
        let foot_rho = big_r + r * (rho - big_r) / g;
        if foot_rho >= 0.0 {
            return g - r;
        }
        let h = (r * r - big_r * big_r).sqrt();
        let d = rho.hypot(l.z.abs() - h);
        if inside {
            -d
        } else {
            d
        }
    }

    fn ray_intersections(&self, ray: &Ray, out: &mut Vec<f64>) {
        let (big_r, r) = (self.major, self.minor);
        // Parameter origin at the point of the line nearest the centre: then |o|² is the
        // squared distance of the line to the centre and o·d = 0, which removes the cubic
        // cancellation that makes far-away ray origins lose digits.
        let (o, d, t0, len) = normalized_near(ray, self.frame.origin);
        let o = self.frame.to_local(o);
        let d = self.frame.vector_to_local(d);
        let a = o.length_squared();
        let reach = big_r + r;
        if a > reach * reach {
            return; // the line misses the bounding sphere
        }
        let b = o.dot(d); // ≈ 0 by construction; kept for exactness
        let k = a + big_r * big_r - r * r;
        let r2 = big_r * big_r;
        let dxy2 = d.x * d.x + d.y * d.y;
        let oxy_dxy = o.x * d.x + o.y * d.y;
        let oxy2 = o.x * o.x + o.y * o.y;
        // (s² + 2bs + k)² - 4R²(|o_xy + s d_xy|²) = 0, ascending coefficients.
        let c = [
            k * k - 4.0 * r2 * oxy2,
            4.0 * b * k - 8.0 * r2 * oxy_dxy,
            4.0 * b * b + 2.0 * k - 4.0 * r2 * dxy2,
            4.0 * b,
            1.0,
        ];
        // Every root has |o + s d| ≤ R + r, so |s| ≤ √((R+r)² - |o|²) + |b|.
        let half = (reach * reach - a).max(0.0).sqrt() + b.abs();
        let margin = 1e-9 * reach.max(1.0);
        let start = out.len();
        real_roots_in(&c, -half - margin, half + margin, self.root_tol, out);
        // Keep the roots on the outer surface: a root of the quartic satisfies one of
        // f± = (ρ ∓ R)² + z² - r² = 0, and f+ - f- = -4Rρ; the outer surface is f+ = 0, so a
        // root belongs to it when |f+| is the smaller of the two (always true for R ≥ r).
        let mut w = start;
        for i in start..out.len() {
            let s = out[i];
            let keep = if big_r >= r {
                true
            } else {
                let p = o + d * s;
                let rho = p.x.hypot(p.y);
                let f_plus = (rho - big_r).powi(2) + p.z * p.z - r * r;
                f_plus.abs() <= 2.0 * big_r * rho + 1e-9 * r * r
            };
            if keep {
                out[w] = s;
                w += 1;
            }
        }
        out.truncate(w);
        let found = out.len() - start;
        let mut tmp = [0.0; crate::poly::MAX_DEGREE];
        tmp[..found].copy_from_slice(&out[start..]);
        out.truncate(start);
        push_scaled(&tmp[..found], t0, len, out);
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::check_against_brute_force;
    use super::super::Sphere;
    use super::*;
    use proptest::prelude::*;

    fn torus(big_r: f64, r: f64) -> Torus {
        Torus::new(Frame::WORLD, big_r, r)
    }

    #[test]
    fn ray_through_the_hole_and_tube() {
        let t = torus(5.0, 1.0);
        let mut h = Vec::new();
        t.ray_intersections(&Ray::new(Vec3::new(-10.0, 0.0, 0.0), Vec3::X), &mut h);
        let expect = [4.0, 6.0, 14.0, 16.0];
        assert_eq!(h.len(), 4, "{h:?}");
        for (a, b) in h.iter().zip(expect) {
            assert!((a - b).abs() < 1e-9, "{h:?}");
        }
    }

    #[test]
    fn ray_along_axis_misses_ring_and_hits_spindle() {
        let mut h = Vec::new();
        torus(5.0, 1.0).ray_intersections(&Ray::new(Vec3::new(0.0, 0.0, -10.0), Vec3::Z), &mut h);
        assert!(h.is_empty(), "{h:?}");
        // Spindle R=1, r=2: the axis meets the outer surface at z = ±√3 (the lemon's tips
        // coincide with it there); reported once each.
        torus(1.0, 2.0).ray_intersections(&Ray::new(Vec3::new(0.0, 0.0, -10.0), Vec3::Z), &mut h);
        assert_eq!(h.len(), 2, "{h:?}");
        assert!(
            (h[0] - (10.0 - 3f64.sqrt())).abs() < 1e-7
                && (h[1] - (10.0 + 3f64.sqrt())).abs() < 1e-7,
            "{h:?}"
        );
    }

    #[test]
    fn spindle_lemon_not_reported() {
        // R = 1, r = 2, horizontal line through the centre: the outer surface at x = ±3; the
        // lemon at x = ±1 must not appear.
        let mut h = Vec::new();
        torus(1.0, 2.0).ray_intersections(&Ray::new(Vec3::new(-10.0, 0.0, 0.0), Vec3::X), &mut h);
        assert_eq!(h.len(), 2, "{h:?}");
        assert!(
            (h[0] - 7.0).abs() < 1e-9 && (h[1] - 13.0).abs() < 1e-9,
            "{h:?}"
        );
        // Signed distance at the centre: nearest surface points are the tips at z = ±√3.
        assert!((torus(1.0, 2.0).signed_distance(Vec3::ZERO) + 3f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn tangent_to_the_tube_top() {
        // The line z = r touches the ring torus along the top circle: at x = ±R.
        let t = torus(5.0, 1.0);
        let mut h = Vec::new();
        t.ray_intersections(&Ray::new(Vec3::new(-10.0, 0.0, 1.0), Vec3::X), &mut h);
        assert_eq!(h.len(), 2, "{h:?}");
        assert!(
            (h[0] - 5.0).abs() < 1e-6 && (h[1] - 15.0).abs() < 1e-6,
            "{h:?}"
        );
        // Tangent to the outer equator: the line x = R + r, along y.
        h.clear();
        t.ray_intersections(&Ray::new(Vec3::new(6.0, -10.0, 0.0), Vec3::Y), &mut h);
        assert_eq!(h.len(), 1, "{h:?}");
        assert!((h[0] - 10.0).abs() < 1e-6, "{h:?}");
        // Just above the tube: nothing.
        h.clear();
        t.ray_intersections(
            &Ray::new(Vec3::new(-10.0, 0.0, 1.0 + 1e-6), Vec3::X),
            &mut h,
        );
        assert!(h.is_empty(), "{h:?}");
        // Just below: two close crossings at each side.
        h.clear();
        t.ray_intersections(
            &Ray::new(Vec3::new(-10.0, 0.0, 1.0 - 1e-6), Vec3::X),
            &mut h,
        );
        assert_eq!(h.len(), 4, "{h:?}");
        for &s in &h {
            assert!(
                t.signed_distance(Vec3::new(-10.0 + s, 0.0, 1.0 - 1e-6))
                    .abs()
                    < 1e-9
            );
        }
    }

    #[test]
    fn zero_major_is_a_sphere() {
        let t = Torus::new(
            Frame::from_axis(Vec3::new(1.0, 1.0, 1.0), Vec3::new(1.0, 2.0, 0.5)),
            0.0,
            3.0,
        );
        let s = Sphere::new(Vec3::new(1.0, 1.0, 1.0), 3.0);
        let ray = Ray::new(Vec3::new(-4.0, 0.3, 2.0), Vec3::new(1.0, 0.1, -0.2));
        let (mut a, mut b) = (Vec::new(), Vec::new());
        t.ray_intersections(&ray, &mut a);
        s.ray_intersections(&ray, &mut b);
        assert_eq!(a.len(), 2);
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() < 1e-9);
        }
        let p = Vec3::new(2.0, -0.5, 3.0);
        assert!((t.signed_distance(p) - s.signed_distance(p)).abs() < 1e-12);
    }

    #[test]
    fn distance_is_exact_by_sampling() {
        // Compare with the minimum over a dense sampling of the surface (ring and spindle).
        for (big_r, r) in [(5.0, 1.0), (1.0, 2.0), (2.0, 2.0)] {
            let t = torus(big_r, r);
            for p in [
                Vec3::new(0.3, 0.2, 0.1),
                Vec3::new(4.0, 1.0, -2.0),
                Vec3::new(0.0, 0.0, 5.0),
                Vec3::new(1.5, 0.0, 0.4),
            ] {
                let rho = p.x.hypot(p.y);
                let mut best = f64::INFINITY;
                let n = 200_000;
                for i in 0..n {
                    let phi = std::f64::consts::TAU * i as f64 / n as f64;
                    let (q_rho, q_z) = (big_r + r * phi.cos(), r * phi.sin());
                    if q_rho < 0.0 {
                        continue;
                    }
                    best = best.min((rho - q_rho).hypot(p.z - q_z));
                }
                if big_r < r {
                    // The ends of the clipped meridian arc, on the axis.
                    let h = (r * r - big_r * big_r).sqrt();
                    best = best.min(rho.hypot(p.z - h)).min(rho.hypot(p.z + h));
                }
                let sd = t.signed_distance(p);
                assert!(
                    (sd.abs() - best).abs() < 1e-6,
                    "R={big_r} r={r} p={p}: {sd} vs {best}"
                );
            }
        }
    }

    proptest! {
        #![proptest_config(swarf_testdata::proptest_config(256))]
        #[test]
        fn matches_brute_force(ax in -1.0f64..1.0, ay in -1.0f64..1.0, az in -1.0f64..1.0,
                               big_r in 0.0f64..6.0, r in 0.2f64..3.0,
                               ox in -10.0f64..10.0, oy in -10.0f64..10.0, oz in -10.0f64..10.0,
                               dx in -1.0f64..1.0, dy in -1.0f64..1.0, dz in -1.0f64..1.0) {
            let a = Vec3::new(ax, ay, az);
            let d = Vec3::new(dx, dy, dz);
            prop_assume!(a.length() > 0.1 && d.length() > 0.1);
            let t = Torus::new(Frame::from_axis(Vec3::new(1.0, -2.0, 0.5), a), big_r, r);
            let res = check_against_brute_force(&t, &Ray::new(Vec3::new(ox, oy, oz), d), 60.0, 1e-9);
            prop_assert!(res.is_ok(), "{}", res.unwrap_err());
        }
    }
}
