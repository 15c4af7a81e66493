//! Grazing points of a spherical zone (ball-nose): the characteristic circle of each parallel
//! meets the great circle `S` of the ball normal to the velocity of its centre (Aras §3.2,
//! Remark 3.2; §3.5 notes the full sphere's profile is that great circle).
//!
//! With the centre `c` and `m_u = V(c)`, the parallel at polar angle φ has centre
//! `C = c − r cos φ · n` and radius `R = r sin φ`, and `(P − c)·m_u = 0` reads
//! `R (x·m_u) cos θ + R (y·m_u) sin θ = r cos φ (n·m_u)`.

use swarf_geom::math::Vec2;
use swarf_tool::piece::SpherePiece;
use swarf_tool::Piece;

use super::{parameters, push_parallel_roots, solve_cos_sin, GrazingSet, Local};
use crate::kinematics::MotionState;
use crate::tolerance::TANGENCY_REL_EPS;

/// Appends the grazing points of `ball` (piece index `piece`) on `samples` parallels.
pub fn grazing(
    ball: &SpherePiece,
    piece: usize,
    state: &MotionState,
    local: &Local,
    samples: usize,
    out: &mut GrazingSet,
) {
    let c = state.tip + state.axis * ball.center_z;
    let m_u = state.velocity_at(c);
    let (x, y) = (local.frame.x, local.frame.y);
    let eps = TANGENCY_REL_EPS * ball.radius * m_u.length();
    for s in parameters(samples) {
        let p = ball.profile_point(s);
        let n: Vec2 = ball.profile_normal(s);
        if p.x <= 0.0 {
            continue; // the pole: a point, not a circle
        }
        let big_r = p.x;
        let a2 = big_r * x.dot(m_u);
        let a1 = big_r * y.dot(m_u);
        // −(C − c)·m_u with C − c = (z − z_c)·n.
        let a0 = -(p.y - ball.center_z) * state.axis.dot(m_u);
        push_parallel_roots(solve_cos_sin(a2, a1, a0, eps), piece, s, p, n, local, out);
    }
}
