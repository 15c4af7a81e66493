//! Point inversion: the parameters of the point of a [`Surface`] nearest a model-space point,
//! and how far that point lies from the surface.
//!
//! The readers use it to map trimming curves given in model space (STEP edges, IGES 142s with
//! only a model-space curve) onto a patch's parameters, one sample after the other:
//!
//! * **Elementary surfaces** (plane, cylinder, cone, sphere, torus) in closed form, from the
//!   point's coordinates in the surface's frame. Angles come as `atan2` gives them, in
//!   `(−π, π]`, whatever the parameter box: the surface is periodic in them and the caller
//!   unwraps them (to lie near the previous sample, in the box, …). On the axis of a sphere (a
//!   pole) or a cone (the apex) the angle is arbitrary and [`Inversion::pole`] says so. On a
//!   cone v is the point's height along the axis, which is the foot's only for points on the
//!   surface (off it they differ by the distance times the sine of the semi-angle); the
//!   distance is exact on every kind.
//! * **B-spline surfaces** by damped Gauss–Newton iterations on `|S(u, v) − p|` (steps halved
//!   until the distance does not grow, parameters clamped into the box), seeded by the caller's
//!   parameters (the previous sample's). When there is no seed, or the seeded result lies
//!   farther than [`Inverter::new`]'s `accept` distance, the seed is the nearest point of a
//!   coarse grid over the parameter box (4 points per knot span, 9 to 33 a side), built on
//!   first use and kept; such grid searches are limited in number, a guard against curves that
//!   would need one at every sample. Iterations are capped (50 steps, 12 halvings each).
//!
//! A point outside the surface's box maps to the nearest point of the patch (on its edge) — the
//! distance says how far that is; non-finite points give a non-finite distance.

use std::fmt;

use swarf_geom::math::Vec3;
use swarf_geom::Frame;

use super::{ParametricSurface, Surface};

/// `(u, v)`.
type Uv = [f64; 2];

/// Newton steps of one inversion, at most.
const MAX_STEPS: usize = 50;
/// Halvings of one Newton step, at most.
const MAX_HALVINGS: usize = 12;

/// Where a point lands on the surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Inversion {
    /// The parameters of the surface point nearest the point (see the module docs for angles
    /// and cones).
    pub(crate) uv: Uv,
    /// Distance from the point to the surface point at `uv`, mm.
    pub(crate) dist: f64,
    /// The point lies on the axis of a sphere or a cone: u (the angle) is arbitrary.
    pub(crate) pole: bool,
}

/// Why a point was not inverted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum InvertError {
    /// The inverter's grid searches are spent.
    GridSearchesSpent {
        /// How many it was allowed.
        limit: usize,
    },
}

impl fmt::Display for InvertError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            InvertError::GridSearchesSpent { limit } => write!(
                f,
                "more than {limit} points needed a search for their parameters"
            ),
        }
    }
}

/// Inverts points onto one surface, keeping the coarse grid (of a B-spline surface) between
/// calls.
#[derive(Clone, Debug)]
pub(crate) struct Inverter<'s> {
    surface: &'s Surface,
    /// A seeded result this near is taken without a grid search, mm.
    accept: f64,
    /// Grid searches allowed in all.
    limit: usize,
    grid_searches_left: usize,
    /// Parameters and points of the grid, built when first needed.
    grid: Vec<(Uv, Vec3)>,
}

impl<'s> Inverter<'s> {
    /// An inverter onto `surface`: a Newton result from the caller's seed that lies within
    /// `accept` (mm) of the point is taken as it is; at most `max_grid_searches` points may
    /// need a search of the grid (on a B-spline surface).
    pub(crate) fn new(surface: &'s Surface, accept: f64, max_grid_searches: usize) -> Self {
        Self {
            surface,
            accept,
            limit: max_grid_searches,
            grid_searches_left: max_grid_searches,
            grid: Vec::new(),
        }
    }

    /// The surface.
    pub(crate) fn surface(&self) -> &'s Surface {
        self.surface
    }

    /// The parameters of the surface point nearest `p` and the distance left; `near` is a seed
    /// (the parameters of a neighbouring point), used on B-spline surfaces.
    pub(crate) fn invert(&mut self, p: Vec3, near: Option<Uv>) -> Result<Inversion, InvertError> {
        let local = |f: &Frame| {
            let l = p - f.origin;
            (l.dot(f.x), l.dot(f.y), l.dot(f.z))
        };
        let (uv, pole, dist) = match self.surface {
            Surface::Nurbs(_) => {
                let (uv, dist) = self.newton_or_grid(p, near)?;
                (uv, false, dist)
            }
            Surface::Plane(s) => {
                let (x, y, z) = local(&s.frame);
                ([x, y], false, z.abs())
            }
            Surface::Cylinder(s) => {
                let (x, y, z) = local(&s.frame);
                let rho = x.hypot(y);
                ([y.atan2(x), z], false, (rho - s.radius).abs())
            }
            Surface::Cone(s) => {
                let (x, y, z) = local(&s.frame);
                let rho = x.hypot(y);
                let r = s.radius + z * s.semi_angle.tan();
                let mut u = y.atan2(x);
                if r < 0.0 {
                    u += std::f64::consts::PI;
                }
                let scale = s.radius.abs() + z.abs() + rho;
                (
                    [u, z],
                    rho <= 1e-9 * scale,
                    (rho - r.abs()).abs() * s.semi_angle.cos(),
                )
            }
            Surface::Sphere(s) => {
                let (x, y, z) = local(&s.frame);
                let rho = x.hypot(y);
                (
                    [y.atan2(x), z.atan2(rho)],
                    rho <= 1e-9 * s.radius,
                    (rho.hypot(z) - s.radius).abs(),
                )
            }
            Surface::Torus(s) => {
                let (x, y, z) = local(&s.frame);
                let rho = x.hypot(y);
                (
                    [y.atan2(x), z.atan2(rho - s.major)],
                    rho <= 1e-9 * (s.major + s.minor),
                    ((rho - s.major).hypot(z) - s.minor).abs(),
                )
            }
        };
        Ok(Inversion { uv, dist, pole })
    }

    /// Newton iterations from `near` (if given and good enough), else from the nearest grid
    /// point.
    fn newton_or_grid(&mut self, p: Vec3, near: Option<Uv>) -> Result<(Uv, f64), InvertError> {
        let s = self.surface;
        if let Some(seed) = near {
            let (uv, dist) = newton(s, p, seed);
            if dist <= self.accept {
                return Ok((uv, dist));
            }
        }
        if self.grid_searches_left == 0 {
            return Err(InvertError::GridSearchesSpent { limit: self.limit });
        }
        self.grid_searches_left -= 1;
        let dom = s.domain();
        if self.grid.is_empty() {
            let spans = |k: &[f64]| k.windows(2).filter(|w| w[1] > w[0]).count();
            let (nu, nv) = match s {
                Surface::Nurbs(n) => (
                    (4 * spans(n.knots_u()) + 1).clamp(9, 33),
                    (4 * spans(n.knots_v()) + 1).clamp(9, 33),
                ),
                _ => (17, 17),
            };
            for i in 0..nu {
                for j in 0..nv {
                    let uv = [
                        dom.u_at(i as f64 / (nu - 1) as f64),
                        dom.v_at(j as f64 / (nv - 1) as f64),
                    ];
                    self.grid.push((uv, s.point(uv[0], uv[1])));
                }
            }
        }
        let seed = self
            .grid
            .iter()
            .min_by(|a, b| (a.1 - p).length().total_cmp(&(b.1 - p).length()))
            .map_or([dom.u[0], dom.v[0]], |g| g.0);
        Ok(newton(s, p, seed))
    }
}

/// Damped Gauss–Newton iterations for the surface point nearest `p`, from `seed`, parameters
/// clamped into the box: the parameters reached and their distance to `p`.
fn newton(s: &Surface, p: Vec3, seed: Uv) -> (Uv, f64) {
    let dom = s.domain();
    let [mut u, mut v] = seed;
    let mut r = s.point(u, v) - p;
    let mut dist = r.length();
    for _ in 0..MAX_STEPS {
        let d = s.derivs(u, v);
        let (a11, a12, a22) = (d.su.dot(d.su), d.su.dot(d.sv), d.sv.dot(d.sv));
        let (b1, b2) = (-d.su.dot(r), -d.sv.dot(r));
        let eps = 1e-12 * (a11 + a22) + 1e-300;
        let (a11, a22) = (a11 + eps, a22 + eps);
        let det = a11 * a22 - a12 * a12;
        if det.is_nan() || det <= 0.0 {
            break;
        }
        let mut du = (b1 * a22 - b2 * a12) / det;
        let mut dv = (a11 * b2 - a12 * b1) / det;
        let mut improved = false;
        for _ in 0..MAX_HALVINGS {
            let (nu, nv) = dom.clamp(u + du, v + dv);
            if !(nu.is_finite() && nv.is_finite()) {
                break;
            }
            let nr = s.point(nu, nv) - p;
            if nr.length() <= dist {
                let step = (nu - u).abs() + (nv - v).abs();
                u = nu;
                v = nv;
                r = nr;
                dist = nr.length();
                improved = step > 1e-15 * (dom.span().0 + dom.span().1);
                break;
            }
            du *= 0.5;
            dv *= 0.5;
        }
        if !improved {
            break;
        }
    }
    ([u, v], dist)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::{
        CylindricalSurface, NurbsSurface, ParamBox, PlaneSurface, SphericalSurface,
    };
    use std::f64::consts::{FRAC_PI_2, PI, TAU};

    /// Tilted, moved frame (so no axis is a coordinate axis).
    fn frame() -> Frame {
        Frame::from_axis_and_x(
            Vec3::new(3.0, -2.0, 7.0),
            Vec3::new(0.3, -0.4, 1.0),
            Vec3::new(1.0, 0.5, 0.0),
        )
    }

    /// The difference of two angles, wrapped into (−π, π].
    fn angle_gap(a: f64, b: f64) -> f64 {
        let d = (a - b).rem_euclid(TAU);
        if d > PI {
            d - TAU
        } else {
            d
        }
    }

    /// A bicubic rational B-spline over [0, 2] × [0, 1] (two spans in u): a wavy sheet about
    /// 40 × 30 mm with weights between 0.7 and 1.5.
    fn bicubic() -> Surface {
        let (nu, nv) = (5, 4);
        let points: Vec<Vec<Vec3>> = (0..nu)
            .map(|i| {
                (0..nv)
                    .map(|j| {
                        let (x, y) = (10.0 * i as f64, 10.0 * j as f64);
                        Vec3::new(x + 0.7 * j as f64, y, 3.0 * ((i + 2 * j) % 3) as f64 - 2.0)
                    })
                    .collect()
            })
            .collect();
        let weights: Vec<Vec<f64>> = (0..nu)
            .map(|i| {
                (0..nv)
                    .map(|j| 0.7 + 0.2 * ((i * 3 + j) % 5) as f64)
                    .collect()
            })
            .collect();
        let ku = vec![0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 2.0, 2.0, 2.0];
        let kv = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
        Surface::Nurbs(NurbsSurface::new(3, 3, ku, kv, &points, Some(&weights)).unwrap())
    }

    /// Unit normal of `s` at `(u, v)`.
    fn normal(s: &Surface, u: f64, v: f64) -> Vec3 {
        let d = s.derivs(u, v);
        d.su.cross(d.sv).normalize()
    }

    #[test]
    fn plane_points_and_feet() {
        let f = frame();
        let s = Surface::Plane(PlaneSurface::new(f, ParamBox::new(-5.0, 5.0, -5.0, 5.0)));
        let mut inv = Inverter::new(&s, 1e-3, 4);
        for (u, v) in [(0.0, 0.0), (1.25, -3.5), (-4.9, 4.9), (3.0, 1.0)] {
            let q = s.point(u, v);
            let i = inv.invert(q, None).unwrap();
            assert!((i.uv[0] - u).abs() < 1e-9 && (i.uv[1] - v).abs() < 1e-9);
            assert!(i.dist < 1e-9 && !i.pole);
            // Off the plane by 2.5 along the normal: the same parameters, the distance 2.5.
            let i = inv.invert(q + 2.5 * f.z, Some([0.0, 0.0])).unwrap();
            assert!((i.uv[0] - u).abs() < 1e-9 && (i.uv[1] - v).abs() < 1e-9);
            assert!((i.dist - 2.5).abs() < 1e-9);
        }
    }

    #[test]
    fn cylinder_points_and_feet() {
        let s = Surface::Cylinder(
            CylindricalSurface::new(frame(), 4.0, ParamBox::new(0.0, TAU, -10.0, 10.0)).unwrap(),
        );
        let mut inv = Inverter::new(&s, 1e-3, 4);
        for (u, v) in [(0.0, 0.0), (1.0, 2.0), (3.0, -7.5), (5.5, 9.0), (PI, 0.5)] {
            let q = s.point(u, v);
            for h in [0.0, 1.5, -2.0] {
                let i = inv.invert(q + h * normal(&s, u, v), None).unwrap();
                assert!(angle_gap(i.uv[0], u).abs() < 1e-9, "{:?} {u}", i.uv);
                assert!((i.uv[1] - v).abs() < 1e-9);
                assert!((i.dist - h.abs()).abs() < 1e-9);
                // S(uv) is the foot, whatever turn the angle is given in.
                assert!((s.point(i.uv[0].rem_euclid(TAU), i.uv[1]) - q).length() < 1e-9);
            }
        }
    }

    #[test]
    fn sphere_points_feet_and_poles() {
        let f = frame();
        let s = Surface::Sphere(SphericalSurface::new(f, 6.0, SphericalSurface::FULL).unwrap());
        let mut inv = Inverter::new(&s, 1e-3, 4);
        for (u, v) in [(0.5, 0.0), (2.0, 1.2), (4.0, -1.0), (6.0, 0.3)] {
            let q = s.point(u, v);
            for h in [0.0, 2.0, -3.0] {
                let i = inv.invert(q + h * normal(&s, u, v), None).unwrap();
                assert!(angle_gap(i.uv[0], u).abs() < 1e-9);
                assert!((i.uv[1] - v).abs() < 1e-9);
                assert!((i.dist - h.abs()).abs() < 1e-9);
                assert!(!i.pole);
            }
        }
        // The north pole: v = π/2, u free.
        let i = inv.invert(f.origin + 6.0 * f.z, None).unwrap();
        assert!(i.pole && (i.uv[1] - FRAC_PI_2).abs() < 1e-12 && i.dist < 1e-12);
    }

    #[test]
    fn bicubic_points_invert_to_their_parameters() {
        let s = bicubic();
        let mut inv = Inverter::new(&s, 1e-3, 1000);
        let mut worst = 0.0f64;
        let mut prev = None;
        for i in 0..=20 {
            for j in 0..=20 {
                let (u, v) = (2.0 * i as f64 / 20.0, j as f64 / 20.0);
                // Unseeded (grid) and seeded by the previous point.
                for seed in [None, prev] {
                    let r = inv.invert(s.point(u, v), seed).unwrap();
                    worst = worst.max((r.uv[0] - u).abs()).max((r.uv[1] - v).abs());
                    assert!(r.dist < 1e-9 && !r.pole);
                }
                prev = Some([u, v]);
            }
        }
        assert!(worst < 1e-9, "{worst}");
    }

    #[test]
    fn bicubic_points_off_the_surface_invert_to_the_foot() {
        let s = bicubic();
        let mut inv = Inverter::new(&s, 1e-3, 1000);
        let mut worst = 0.0f64;
        for (u, v) in [(0.3, 0.4), (1.0, 0.5), (1.7, 0.2), (0.9, 0.85), (1.5, 0.6)] {
            let n = normal(&s, u, v);
            for h in [-0.5, 0.1, 0.5] {
                let r = inv.invert(s.point(u, v) + h * n, Some([1.0, 0.5])).unwrap();
                worst = worst.max((r.uv[0] - u).abs()).max((r.uv[1] - v).abs());
                assert!((r.dist - h.abs()).abs() < 1e-9, "{} {h}", r.dist);
            }
        }
        println!("off-surface worst parameter error {worst:e}");
        assert!(worst < 1e-9, "{worst}");
    }

    #[test]
    fn points_beyond_the_box_land_on_its_edge_and_searches_are_limited() {
        let s = bicubic();
        let mut inv = Inverter::new(&s, 1e-3, 2);
        // Beyond the u = 2 edge, in the tangent plane, square to the edge: the foot is on it.
        let d = s.derivs(2.0, 0.5);
        let n = d.su.cross(d.sv);
        let mut out = n.cross(d.sv).normalize();
        if out.dot(d.su) < 0.0 {
            out = -out;
        }
        let r = inv.invert(d.point + 0.5 * out, None).unwrap();
        assert!((r.uv[0] - 2.0).abs() < 1e-12, "{:?}", r.uv);
        assert!((r.uv[1] - 0.5).abs() < 1e-6, "{:?}", r.uv);
        assert!((r.dist - 0.5).abs() < 1e-6, "{}", r.dist);
        inv.invert(Vec3::new(100.0, 0.0, 0.0), None).unwrap();
        assert_eq!(
            inv.invert(Vec3::new(100.0, 0.0, 0.0), None),
            Err(InvertError::GridSearchesSpent { limit: 2 })
        );
        // A good seed needs no search.
        let q = s.point(0.5, 0.5);
        assert!(inv.invert(q, Some([0.45, 0.55])).unwrap().dist < 1e-9);
        // Non-finite points: a non-finite distance, no panic.
        let mut inv = Inverter::new(&s, 1e-3, 2);
        let r = inv
            .invert(Vec3::new(f64::NAN, 0.0, 0.0), Some([0.5, 0.5]))
            .unwrap();
        assert!(!r.dist.is_finite());
    }
}
