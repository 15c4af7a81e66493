//! Imaginary size of the ball end mill's sphere (Liu eq. 2.35): the ball tangent at `C` (centre
//! `C + ρ·n`) through `P` has `ρ = |P − C|² / (2 n·(P − C))`; `∞` when `P` is on or behind the
//! tangent plane. The ball end mill as a whole is the tapered ball with taper 0 (sphere and the
//! cylinder above its equator, [`super::imaginary_taper_ball`]), which uses this for its sphere.

use swarf_geom::math::Vec3;

/// The sphere radius through `p` tangent at `c` with normal `n`; `∞` when `n·(p − c) ≤ 0`.
pub(super) fn sphere(c: Vec3, n: Vec3, p: Vec3) -> f64 {
    let d = p - c;
    let w = n.dot(d);
    if w <= 0.0 {
        f64::INFINITY
    } else {
        d.length_squared() / (2.0 * w)
    }
}
