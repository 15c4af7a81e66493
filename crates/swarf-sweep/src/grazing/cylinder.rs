//! Grazing points of a cylinder band: a pipe surface with a straight spine (Aras §3.2.1,
//! Property 3.2). The sphere centred at `m = F + z·n` with velocity `m_u = V(m)` grazes at
//! `m ± r·N/|N|`, `N = m_t × m_u = n × m_u`. A plunge along the axis (`N = 0`) makes the whole
//! parallel graze.

use swarf_geom::math::Vec2;
use swarf_tool::piece::CylinderPiece;
use swarf_tool::Piece;

use super::{parameters, GrazingPoint, GrazingSet, Local};
use crate::kinematics::MotionState;
use crate::tolerance::TANGENCY_REL_EPS;

/// Appends the grazing points of `cyl` (piece index `piece`) on `samples` parallels.
pub fn grazing(
    cyl: &CylinderPiece,
    piece: usize,
    state: &MotionState,
    local: &Local,
    samples: usize,
    out: &mut GrazingSet,
) {
    for s in parameters(samples) {
        let p: Vec2 = cyl.profile_point(s);
        let m = state.tip + state.axis * p.y;
        let m_u = state.velocity_at(m);
        let big_n = state.axis.cross(m_u);
        if big_n.length() <= TANGENCY_REL_EPS * m_u.length() || m_u.length() == 0.0 {
            out.whole.push((piece, s));
            continue;
        }
        let dir = big_n.normalize();
        for sign in [1.0, -1.0] {
            let normal = dir * sign;
            let theta = normal.dot(local.frame.y).atan2(normal.dot(local.frame.x));
            out.points.push(GrazingPoint {
                piece,
                s,
                theta,
                point: m + normal * cyl.radius,
                normal,
                edge: false,
            });
        }
    }
}
