//! Joint circles of a profile (the flat bottom's edge, the top cap's edge, corner joints)
//! extruded along the move: elliptic cylinders, solved in closed form without trigonometry.

use super::{Acc, DirConsts, BAND_EPS};
use swarf_geom::math::Vec3;

/// Crossings of the line `o + t·d` with the circle of radius `rho` at height `z0` extruded
/// along `v`, for `s ∈ [0, 1]`.
#[inline]
pub(crate) fn envelope(rho: f64, z0: f64, o: Vec3, dc: &DirConsts, acc: &mut Acc) {
    // The line and the extrusion line through c(θ) are coplanar (they meet) iff
    // w·(c(θ) − o) = 0 with w = d × v: ρ·(w_x cos θ + w_y sin θ) = w·o − w_z·z0.
    let w = dc.w;
    let rw = w.x.hypot(w.y);
    if rw <= 1e-14 * w.length() {
        return;
    }
    let c = (w.dot(o) - w.z * z0) / (rho * rw);
    if c.abs() > 1.0 {
        return;
    }
    let (nx, ny) = (w.x / rw, w.y / rw);
    let sn = (1.0 - c * c).sqrt();
    let se = BAND_EPS / dc.vv.sqrt();
    for k in [sn, -sn] {
        let (x, y) = (c * nx - k * ny, c * ny + k * nx);
        let g = Vec3::new(rho * x, rho * y, z0);
        let (t, s) = dc.solve_ts(o, g);
        if (-se..=1.0 + se).contains(&s) {
            acc.add(t);
        }
        if sn == 0.0 {
            break;
        }
    }
}
