//! Grazing points of a cone frustum, the cutter surface as a canal surface (Aras §3.2.2, §3.3).
//!
//! Spine: the tool axis. The profile line `ρ = (z − z_apex) tan γ` (γ the signed half-angle,
//! outward normal `(cos γ, −sin γ)`) is touched along its parallel at height `z` by the sphere
//! centred on the axis at `z_m = z + ρ tan γ` with radius `r = ρ / cos γ`. Along the spine
//! `r(z_m) = (z_m − z_apex) sin γ`, so `r_t = sin γ`, and eq. 3.8–3.9 give back the parallel:
//! `C = m − r r_t n` at height `z`, radius `R = r cos γ = ρ`. The grazing angles are the closed
//! form of the [module docs](super) with `w₁, w₂` the tool frame's `x, y` (the frame of
//! eq. 3.18 is not needed: any orthonormal pair normal to a straight spine will do, which also
//! covers the plunge that eq. 3.18 excludes).

use swarf_geom::math::Vec2;
use swarf_tool::piece::ConePiece;
use swarf_tool::Piece;

use super::{parameters, push_parallel_roots, solve_cos_sin, GrazingSet, Local};
use crate::kinematics::MotionState;
use crate::tolerance::TANGENCY_REL_EPS;

/// Appends the grazing points of `cone` (piece index `piece`) on `samples` parallels.
pub fn grazing(
    cone: &ConePiece,
    piece: usize,
    state: &MotionState,
    local: &Local,
    samples: usize,
    out: &mut GrazingSet,
) {
    let gamma = cone.half_angle();
    let (sg, cg) = gamma.sin_cos();
    let n = Vec2::new(cg, -sg);
    for s in parameters(samples) {
        let p = cone.profile_point(s);
        if p.x <= 0.0 {
            continue; // the apex: a single point, no circle
        }
        // Moving sphere: centre on the axis at z_m, radius r, r_t = sin γ.
        let z_m = p.y + p.x * sg / cg;
        let r = p.x / cg;
        let m = state.tip + state.axis * z_m;
        let m_u = state.velocity_at(m);
        let big_r = r * cg; // = ρ
        let x = local.frame.x;
        let y = local.frame.y;
        let a2 = big_r * x.dot(m_u);
        let a1 = big_r * y.dot(m_u);
        let a0 = r * sg * state.axis.dot(m_u);
        let eps = TANGENCY_REL_EPS * r * m_u.length();
        push_parallel_roots(solve_cos_sin(a2, a1, a0, eps), piece, s, p, n, local, out);
    }
}
