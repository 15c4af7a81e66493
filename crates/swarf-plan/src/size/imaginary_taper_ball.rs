//! Imaginary size of the tapered ball end mill (Liu §2.3.3): taper `θ` fixed, ball radius `r`
//! solved for; `θ = 0` is the ball end mill with its cylindrical side.
//!
//! The cutter is the cone of half-angle `θ` with apex at the ball centre `O = C + r·n`, grown
//! by a ball of radius `r`. A test point is reached either by the sphere (Liu eq. 2.35, valid
//! when the point lies below the tangent circle, `z − O_z ≤ −r·sin θ`) or by the side cone
//! (the quadratic of eqs. 2.39–2.44, valid above it). Rather than Liu's reference radius
//! (eqs. 2.36–2.37), every candidate root is checked against the region it belongs to, and the
//! smallest valid one is the answer; the family is nested, so it is unique. Branches:
//!
//! * inside the cone with apex `C` (eq. 2.33, only for `θ > 0`): `r = 0`;
//! * behind the tangent plane and not reached by the cone: `r = ∞` (eq. 2.32);
//! * `e₁ = 0` (`n_z = sin θ`): the quadratic is linear (eq. 2.45).

use swarf_geom::math::Vec3;
use swarf_geom::poly::quadratic_roots;

use super::{imaginary_ball, Contact, SizeTolerances};

/// Relative tolerance of the region test on a candidate root.
const REGION_EPS: f64 = 1e-12;

pub(super) fn imaginary(taper: f64, c: &Contact, p: Vec3, tol: &SizeTolerances) -> f64 {
    let n = c.normal;
    let d = p - c.point;
    let dh = Vec3::new(d.x, d.y, 0.0);
    let rho = dh.length();
    let (st, ct, tt) = (taper.sin(), taper.cos(), taper.tan());
    if taper > 0.0 && rho < d.z * tt - tol.contact / ct {
        return 0.0;
    }
    let scale = d.length().max(1e-300);
    let mut best = f64::INFINITY;
    // Sphere.
    let rs = imaginary_ball::sphere(c.point, n, p);
    if rs.is_finite() && d.z - rs * n.z <= -rs * st + REGION_EPS * scale {
        best = rs;
    }
    // Side cone: |d_h − r n_h| = d_z tan θ + r (sec θ − n_z tan θ).
    let k = 1.0 / ct - n.z * tt;
    let nh = Vec3::new(n.x, n.y, 0.0);
    let e1 = k * k - nh.length_squared();
    let e2 = 2.0 * d.z * tt * k + 2.0 * nh.dot(dh);
    let e3 = d.z * d.z * tt * tt - rho * rho;
    let roots = if e1.abs() <= 1e-15 {
        // Linear (eq. 2.45).
        if e2 != 0.0 {
            vec![-e3 / e2]
        } else {
            vec![]
        }
    } else {
        quadratic_roots(e1, e2, e3).as_slice().to_vec()
    };
    for r in roots {
        if !(r >= 0.0 && r < best) {
            continue;
        }
        let above = d.z - r * n.z >= -r * st - REGION_EPS * scale;
        let reach = d.z * tt + r * k >= -REGION_EPS * scale;
        if above && reach {
            best = r;
        }
    }
    best
}
