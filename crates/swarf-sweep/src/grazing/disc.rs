//! Grazing points of a disc or annulus (flat bottom, top cap) and of its rim.
//!
//! **Face.** With normal `N = ±n` (constant), `f(P) = N·V_F + (P − F)·(N × ω)` is affine on the
//! plane: in 3-axis motion it is constant (the whole face grazes when the feed lies in its plane
//! — the floor of a horizontal slot — else none of it does); in 5-axis motion its zero set is a
//! chord, found ring by ring in the harmonic form with `n_ρ = 0`, `n_z = ±1`.
//!
//! **Rim.** The rim is an edge where the disc meets the neighbouring piece (or nothing: a free
//! edge, whose normal cone is the half-circle from `N` through the radial direction to `−N`). A
//! rim point lies on the envelope when its normal cone holds a direction normal to `V(P)`,
//! i.e. where the tangencies `f₁` of the disc and `f₂` of the neighbour have opposite signs.
//! The rim arcs' ends are the roots of `f₁` and `f₂` on the rim circle (closed form); the
//! reported normal `|f₂|·N₁ + |f₁|·N₂` (normalised) lies in the cone and is normal to `V(P)`.
//! A disc translating off its own plane sweeps an oblique elliptic cylinder: the sweep of these
//! rim points.

use std::f64::consts::TAU;

use swarf_geom::math::{Vec2, Vec3};
use swarf_tool::piece::DiscPiece;

use super::{push_parallel_roots, GrazingPoint, GrazingSet, Harmonic, Local, Roots};
use crate::kinematics::MotionState;
use crate::tolerance::TANGENCY_REL_EPS;

/// The disc's outward profile normal `(0, ±1)`.
pub fn normal(disc: &DiscPiece) -> Vec2 {
    Vec2::new(0.0, if disc.facing_up { 1.0 } else { -1.0 })
}

/// Appends the grazing chord of the face of `disc` (piece `piece`) on `samples` rings.
pub fn grazing(
    disc: &DiscPiece,
    piece: usize,
    _state: &MotionState,
    local: &Local,
    samples: usize,
    out: &mut GrazingSet,
) {
    let n = normal(disc);
    let eps = TANGENCY_REL_EPS * local.speed(disc.outer.hypot(disc.z));
    for s in super::parameters(samples) {
        let rho = disc.inner + s * (disc.outer - disc.inner);
        let p = Vec2::new(rho, disc.z);
        let h = Harmonic::on_parallel(p, n, local.v, local.w);
        push_parallel_roots(h.roots(eps), piece, s, p, n, local, out);
    }
}

/// Appends the grazing points of the rim of `disc` at radius `rho` (outer or inner), where the
/// neighbouring piece has outward profile normal `side` (`None`: a free edge): the ends of the
/// grazing arcs and `samples` points spread over the rim within them.
#[allow(clippy::too_many_arguments)]
pub fn rim(
    disc: &DiscPiece,
    piece: usize,
    rho: f64,
    side: Option<Vec2>,
    state: &MotionState,
    local: &Local,
    samples: usize,
    out: &mut GrazingSet,
) {
    let n1 = normal(disc);
    let p = Vec2::new(rho, disc.z);
    let s = if disc.outer > disc.inner {
        (rho - disc.inner) / (disc.outer - disc.inner)
    } else {
        1.0
    };
    let f1 = Harmonic::on_parallel(p, n1, local.v, local.w);
    let eps = TANGENCY_REL_EPS * local.speed(rho.hypot(disc.z));
    let mut thetas: Vec<f64> = (0..samples.max(1))
        .map(|j| TAU * j as f64 / samples.max(1) as f64)
        .collect();
    let f2 = side.map(|n2| Harmonic::on_parallel(p, n2, local.v, local.w));
    for h in std::iter::once(f1).chain(f2) {
        if let Roots::Two(a, b) = h.roots(eps) {
            thetas.extend([a, b]);
        }
    }
    for theta in thetas {
        let point = local.point(rho, theta, disc.z);
        let v = state.velocity_at(point);
        let w1 = local.dir(n1, theta);
        let normal = match side {
            Some(n2) => {
                let w2 = local.dir(n2, theta);
                let (a, b) = (w1.dot(v), w2.dot(v));
                if a * b > 0.0 && a.abs().min(b.abs()) > eps {
                    continue;
                }
                (w1 * b.abs() + w2 * a.abs()).try_normalize()
            }
            None => {
                // Free edge: the cone from N₁ through the radial u to −N₁.
                let u = local.dir(Vec2::new(1.0, 0.0), theta);
                let c = u * w1.dot(v) - w1 * u.dot(v);
                c.try_normalize()
                    .map(|c| if c.dot(u) < 0.0 { -c } else { c })
            }
        };
        let normal = normal.unwrap_or(w1);
        out.points.push(GrazingPoint {
            piece,
            s,
            theta,
            point,
            normal: project_normal(normal, v),
            edge: true,
        });
    }
}

/// `n` with its component along `v` removed and renormalised (the combinations above are
/// normal to `v` up to rounding; this makes `N·V` vanish to rounding of one projection).
fn project_normal(n: Vec3, v: Vec3) -> Vec3 {
    match v.try_normalize() {
        Some(d) => (n - d * n.dot(d)).try_normalize().unwrap_or(n),
        None => n,
    }
}
