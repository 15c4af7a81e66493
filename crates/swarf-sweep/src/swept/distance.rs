//! Point queries on a convex solid of revolution: its support function and its signed distance
//! with the outward direction, in the tool frame (meridian coordinates) and placed in the part.
//!
//! # Why these two
//! For a convex solid `K` the signed distance is the largest separation over all directions,
//! `sd_K(x) = max_{|n| = 1} (n·x − h_K(n))` with `h_K(n) = max_{y ∈ K} n·y` the support
//! function, inside as well as outside. Fixing one direction `n` therefore gives a lower bound
//! of `sd_K` over any set `X`: `min_{x ∈ X} sd_K(x) ≥ min_{x ∈ X} n·x − h_K(n)`, and over a
//! convex hull the right-hand side is a minimum over the hull's vertices. The program check
//! (`swarf-plan`'s gouge search) bounds how deep a surface patch can reach into a cutter that
//! way, with `n` the outward direction at the nearest boundary point, which makes the bound
//! tight to second order.
//!
//! # Meridian coordinates
//! A point `x` of the part is `(ρ, z)` for a tool at tip `T` with unit axis `a`:
//! `z = (x − T)·a`, `ρ` its distance from the axis. The solid's section in the plane through
//! the axis and `x` is the profile mirrored about the axis, a convex region, and the nearest
//! boundary point of the solid lies in that plane, so the 3-D distance is the 2-D one.

use super::profile::{ConvexProfile, Element};
use swarf_geom::math::{Vec2, Vec3};

/// Signed distance from a point to a solid's boundary (negative inside), with the outward unit
/// direction of steepest increase at that point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SignedDistance {
    /// Distance, mm: negative inside the solid.
    pub distance: f64,
    /// Outward unit direction: from the nearest boundary point towards the point outside, the
    /// boundary's outward normal there inside or on it.
    pub normal: Vec3,
}

impl ConvexProfile {
    /// The support value `max (a·ρ + b·z)` over the profile region, for a direction with radial
    /// component `a ≥ 0` and axial component `b` (tool frame).
    pub fn support_meridian(&self, a: f64, b: f64) -> f64 {
        let mut best = f64::NEG_INFINITY;
        for (i, el) in self.elements().iter().enumerate() {
            match *el {
                Element::Line { p, q } => {
                    best = best.max(a * p.x + b * p.y).max(a * q.x + b * q.y);
                }
                Element::Arc {
                    e,
                    f,
                    r,
                    phi0,
                    phi1,
                } => {
                    // Profile point c + r·u(φ), u = (sin φ, −cos φ): a·ρ + b·z is largest where
                    // u points along (a, b), if that direction is on the arc, else at an end.
                    let (u0, u1) = self.arc_ends(i);
                    let w = Vec2::new(a, b);
                    let base = a * e + b * f;
                    best = best.max(base + r * w.dot(u0)).max(base + r * w.dot(u1));
                    if on_arc(w, u0, u1, phi1 - phi0) {
                        best = best.max(base + r * w.length());
                    }
                }
            }
        }
        best
    }

    /// The support function `h(n) = max n·y` of the solid placed with its tip at `tip` and unit
    /// axis `axis`.
    pub fn support(&self, tip: Vec3, axis: Vec3, n: Vec3) -> f64 {
        let b = n.dot(axis);
        let a = (n - b * axis).length();
        n.dot(tip) + self.support_meridian(a, b)
    }

    /// Signed distance from the meridian point `q = (ρ, z)` (`ρ ≥ 0`) to the profile region's
    /// boundary, and the outward direction there in meridian coordinates.
    pub fn signed_distance_meridian(&self, q: Vec2) -> (f64, Vec2) {
        let mut best = (f64::INFINITY, Vec2::ZERO, Vec2::new(0.0, -1.0));
        for (i, el) in self.elements().iter().enumerate() {
            let (pt, outward) = match *el {
                Element::Line { p, q: end } => {
                    let seg = end - p;
                    let len2 = seg.length_squared();
                    let s = if len2 > 0.0 {
                        ((q - p).dot(seg) / len2).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    // The profile runs counter-clockwise: outward is the tangent turned clockwise.
                    let t = if len2 > 0.0 {
                        seg / len2.sqrt()
                    } else {
                        Vec2::X
                    };
                    (p + s * seg, Vec2::new(t.y, -t.x))
                }
                Element::Arc {
                    e,
                    f,
                    r,
                    phi0,
                    phi1,
                } => {
                    let c = Vec2::new(e, f);
                    let d = q - c;
                    let (u0, u1) = self.arc_ends(i);
                    let len = d.length();
                    if len > 0.0 && on_arc(d, u0, u1, phi1 - phi0) {
                        let u = d / len;
                        (c + r * u, u)
                    } else if len == 0.0 {
                        // The centre: every point of the arc is as near; take its start.
                        (c + r * u0, u0)
                    } else {
                        let (a, b) = (c + r * u0, c + r * u1);
                        if (q - a).length_squared() <= (q - b).length_squared() {
                            (a, u0)
                        } else {
                            (b, u1)
                        }
                    }
                }
            };
            let dist = (q - pt).length();
            if dist < best.0 {
                best = (dist, pt, outward);
            }
        }
        let (dist, pt, outward) = best;
        let inside = self.radius_at(q.y).is_some_and(|rad| q.x <= rad);
        if inside {
            (-dist, outward)
        } else {
            let away = q - pt;
            let n = if dist > 0.0 { away / dist } else { outward };
            (dist, n)
        }
    }

    /// Signed distance from `x` to the solid placed with its tip at `tip` and unit axis `axis`.
    pub fn signed_distance(&self, tip: Vec3, axis: Vec3, x: Vec3) -> SignedDistance {
        let rel = x - tip;
        let z = rel.dot(axis);
        let radial = rel - z * axis;
        let mut rho = radial.length();
        // On the axis the radial direction is rounding noise, not even perpendicular to it.
        let e = if rho > 1e-12 * (1.0 + rel.length()) {
            radial / rho
        } else {
            rho = 0.0;
            axis.any_orthonormal_vector()
        };
        let (distance, n) = self.signed_distance_meridian(Vec2::new(rho, z));
        SignedDistance {
            distance,
            normal: n.x * e + n.y * axis,
        }
    }
}

/// True when the direction `w` (any length) lies on the arc running counter-clockwise from the
/// unit direction `u0` to `u1` through the angle `span`.
#[inline]
fn on_arc(w: Vec2, u0: Vec2, u1: Vec2, span: f64) -> bool {
    if span <= std::f64::consts::PI {
        u0.perp_dot(w) >= 0.0 && w.perp_dot(u1) >= 0.0
    } else {
        // More than a half turn: on it unless strictly inside the complementary (short) arc.
        !(u1.perp_dot(w) > 0.0 && w.perp_dot(u0) > 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::swept::test_rng;
    use swarf_tool::Cutter;

    fn profiles() -> Vec<(String, ConvexProfile)> {
        [
            "flat:d=10",
            "ball:d=10",
            "bull:d=10,r=2",
            "taper-ball:d=6,taper=5",
            "taper-flat:d=8,taper=10",
            "chamfer:d=10,angle=90",
            "drill:d=8,angle=118",
        ]
        .iter()
        .map(|s| {
            let c = swarf_tool::spec::parse(s).unwrap();
            (
                s.to_string(),
                ConvexProfile::from_solid(c.cutting_solid()).unwrap(),
            )
        })
        .collect()
    }

    /// Dense samples of the profile boundary (ρ ≥ 0 and its mirror).
    fn boundary_samples(p: &ConvexProfile) -> Vec<Vec2> {
        let mut out = Vec::new();
        for el in p.elements() {
            let len = match *el {
                Element::Line { p, q } => (q - p).length(),
                Element::Arc { r, phi0, phi1, .. } => r * (phi1 - phi0),
            };
            let n = (len / 1e-3).ceil().max(16.0) as usize;
            for k in 0..=n {
                let s = k as f64 / n as f64;
                let pt = match *el {
                    Element::Line { p, q } => p + s * (q - p),
                    Element::Arc {
                        e,
                        f,
                        r,
                        phi0,
                        phi1,
                    } => {
                        let phi = phi0 + s * (phi1 - phi0);
                        Vec2::new(e + r * phi.sin(), f - r * phi.cos())
                    }
                };
                out.push(pt);
                out.push(Vec2::new(-pt.x, pt.y));
            }
        }
        out
    }

    #[test]
    fn support_matches_dense_boundary_samples() {
        for (name, p) in profiles() {
            let pts = boundary_samples(&p);
            for k in 0..72 {
                let ang = k as f64 * 5.0_f64.to_radians();
                let (a, b) = (ang.cos().abs(), ang.sin());
                let brute = pts
                    .iter()
                    .map(|q| a * q.x + b * q.y)
                    .fold(f64::NEG_INFINITY, f64::max);
                let h = p.support_meridian(a, b);
                // Exact ≥ samples; samples within the spacing of the exact value.
                assert!(h >= brute - 1e-9, "{name} {ang}: {h} < {brute}");
                assert!(h <= brute + 1e-4, "{name} {ang}: {h} ≫ {brute}");
            }
        }
    }

    #[test]
    fn signed_distance_matches_dense_boundary_samples() {
        let mut rnd = test_rng(12345);
        for (name, p) in profiles() {
            let pts = boundary_samples(&p);
            for _ in 0..300 {
                let q = Vec2::new(
                    rnd() * 1.5 * p.r_max(),
                    p.z_min() - 3.0 + rnd() * (p.z_max() - p.z_min() + 6.0),
                );
                let brute = pts
                    .iter()
                    .map(|b| (q - *b).length())
                    .fold(f64::INFINITY, f64::min);
                let (d, n) = p.signed_distance_meridian(q);
                assert!(
                    (d.abs() - brute).abs() < 2e-3,
                    "{name} at {q:?}: |{d}| vs {brute}"
                );
                let inside = p.radius_at(q.y).is_some_and(|r| q.x < r);
                assert_eq!(d < 0.0, inside, "{name} at {q:?}: sign");
                assert!((n.length() - 1.0).abs() < 1e-12);
                // Moving along n increases the distance at unit rate (first order).
                let h = 1e-6;
                let (d2, _) = p.signed_distance_meridian(q + h * n);
                if q.x > 1e-3 {
                    assert!(((d2 - d) / h - 1.0).abs() < 1e-3, "{name} at {q:?}: slope");
                }
            }
        }
    }

    #[test]
    fn placed_queries_agree_with_the_tool_frame() {
        let c = Cutter::bull(10.0, 2.0).unwrap();
        let p = ConvexProfile::from_solid(c.cutting_solid()).unwrap();
        let tip = Vec3::new(1.0, -2.0, 3.0);
        let axis = Vec3::new(0.3, -0.2, 1.0).normalize();
        let frame = swarf_geom::Frame::from_axis(tip, axis);
        for (rho, z, ang) in [
            (1.0, 1.0, 0.3),
            (6.0, 1.0, 2.0),
            (4.0, -1.0, 4.0),
            (0.0, 9.0, 0.0),
        ] {
            let local = Vec3::new(rho * f64::cos(ang), rho * f64::sin(ang), z);
            let x = frame.to_world(local);
            let sd = p.signed_distance(tip, axis, x);
            let (d, _) = p.signed_distance_meridian(Vec2::new(rho, z));
            assert!((sd.distance - d).abs() < 1e-12);
            // The support bound holds at x: n·x − h(n) ≤ sd(x) for any n, with equality for
            // the outward direction.
            let h = p.support(tip, axis, sd.normal);
            assert!(
                (sd.normal.dot(x) - h - sd.distance).abs() < 1e-9,
                "{rho} {z}: {} {} {:?}",
                sd.normal.dot(x) - h,
                sd.distance,
                sd.normal
            );
            for n in [
                Vec3::X,
                Vec3::Y,
                -Vec3::Z,
                Vec3::new(1.0, 1.0, 1.0).normalize(),
            ] {
                assert!(n.dot(x) - p.support(tip, axis, n) <= sd.distance + 1e-12);
            }
        }
    }
}
