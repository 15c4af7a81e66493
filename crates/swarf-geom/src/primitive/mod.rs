//! Implicit primitives (plane, sphere, cylinder, cone, torus) and the [`Implicit`] trait.
//!
//! Each primitive is placed by a [`Frame`](crate::Frame) whose z axis is its axis, answers the
//! exact Euclidean signed distance (negative inside) and all crossings of a line with its
//! surface. One file per shape, as parry does; shared helpers live here.

mod cone;
mod cylinder;
mod plane;
mod sphere;
mod torus;

pub use cone::Cone;
pub use cylinder::Cylinder;
pub use plane::Plane;
pub use sphere::Sphere;
pub use torus::Torus;

use crate::math::Vec3;
use crate::ray::Ray;

/// A surface given implicitly, with the two queries the simulation needs.
pub trait Implicit {
    /// Exact Euclidean distance from `p` to the surface, negative when `p` is inside (each
    /// primitive documents its inside).
    fn signed_distance(&self, p: Vec3) -> f64;

    /// Appends to `out` every parameter `t` where `ray` meets the surface, ascending, a tangency
    /// once. Parameters may be negative (the ray is a line). A ray lying *in* the surface (a
    /// generator of a cylinder or cone, a line in a plane) meets it in a continuum and appends
    /// nothing. Allocates nothing besides growing `out`; what was in `out` is kept.
    fn ray_intersections(&self, ray: &Ray, out: &mut Vec<f64>);
}

/// Appends sorted `roots` (parameters for a unit direction, measured from `t0`) to `out`,
/// converted to the ray's own parameter (`dir` of length `len`).
fn push_scaled(roots: &[f64], t0: f64, len: f64, out: &mut Vec<f64>) {
    out.extend(roots.iter().map(|s| (t0 + s) / len));
}

/// Normalises a ray and moves its parameter origin to the point closest to `center`, which
/// keeps the quadratic/quartic coefficients small (less cancellation far from the shape).
/// Returns `(origin, unit dir, t0, |dir|)` with `origin = ray.origin + t0·unit dir`.
fn normalized_near(ray: &Ray, center: Vec3) -> (Vec3, Vec3, f64, f64) {
    let len = ray.dir.length();
    let d = ray.dir / len;
    let t0 = (center - ray.origin).dot(d);
    (ray.origin + d * t0, d, t0, len)
}

#[cfg(test)]
pub(crate) mod test_support {
    //! Brute-force checks shared by the primitive tests.
    use super::Implicit;
    use crate::ray::Ray;

    /// Sign changes of the signed distance sampled densely on `[t_lo, t_hi]`, refined by
    /// bisection: an independent oracle for crossings (misses tangencies, by design).
    pub(crate) fn brute_force_crossings<S: Implicit>(
        s: &S,
        ray: &Ray,
        t_lo: f64,
        t_hi: f64,
        n: usize,
    ) -> Vec<f64> {
        let mut out = Vec::new();
        let f = |t: f64| s.signed_distance(ray.at(t));
        let mut t_prev = t_lo;
        let mut f_prev = f(t_lo);
        for i in 1..=n {
            let t = t_lo + (t_hi - t_lo) * i as f64 / n as f64;
            let ft = f(t);
            if (f_prev < 0.0) != (ft < 0.0) {
                let (mut a, mut b, mut fa) = (t_prev, t, f_prev);
                for _ in 0..200 {
                    let m = 0.5 * (a + b);
                    let fm = f(m);
                    if (fm < 0.0) == (fa < 0.0) {
                        a = m;
                        fa = fm;
                    } else {
                        b = m;
                    }
                    if b - a < 1e-14 {
                        break;
                    }
                }
                out.push(0.5 * (a + b));
            }
            t_prev = t;
            f_prev = ft;
        }
        out
    }

    /// Asserts that every reported hit is on the surface and that the reported and brute-force
    /// crossings match one to one (reported tangencies excepted: they have no sign change).
    pub(crate) fn check_against_brute_force<S: Implicit>(
        s: &S,
        ray: &Ray,
        span: f64,
        tol: f64,
    ) -> Result<(), String> {
        let mut hits = Vec::new();
        s.ray_intersections(ray, &mut hits);
        if hits.windows(2).any(|w| w[0] > w[1]) {
            return Err(format!("unsorted {hits:?}"));
        }
        let scale = ray.dir.length();
        for &t in &hits {
            let d = s.signed_distance(ray.at(t));
            if d.abs() > tol {
                return Err(format!("hit t={t} is {d} from the surface; hits {hits:?}"));
            }
        }
        let brute = brute_force_crossings(s, ray, -span / scale, span / scale, 20_000);
        for &b in &brute {
            if !hits.iter().any(|&h| ((h - b) * scale).abs() < 1e-7) {
                return Err(format!(
                    "brute-force crossing {b} not reported; hits {hits:?}, brute {brute:?}"
                ));
            }
        }
        Ok(())
    }
}
