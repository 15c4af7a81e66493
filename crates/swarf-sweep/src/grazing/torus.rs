//! Grazing points of a torus arc (the corner of a bull-nose): a pipe surface whose spine is the
//! circle of corner centres (Aras §3.2.3, Property 3.2).
//!
//! Spine angle θ: centre `m = F + z_c·n + R·u(θ)`, tangent `m_t = R·(n × u)`, velocity
//! `m_u = V(m)`. The grazing normals are `±N/|N|` with `N = m_t × m_u`; each is a point
//! `m + r·N/|N|` of the full torus, kept when its polar angle
//! `φ = atan2(N·u, −N·n)` lies on the piece's arc `[φ₀, φ₁]`. `N = 0` (the centre moves along
//! the spine's tangent) makes the whole meridian circle graze.

use std::f64::consts::TAU;

use swarf_tool::piece::TorusPiece;

use super::{GrazingPoint, GrazingSet, Local};
use crate::kinematics::MotionState;
use crate::tolerance::TANGENCY_REL_EPS;

/// Slack (radians) with which a polar angle counts as on the arc (rounding only).
const ARC_EPS: f64 = 1e-12;

/// Appends the grazing points of `torus` (piece index `piece`) at `samples` spine angles.
pub fn grazing(
    torus: &TorusPiece,
    piece: usize,
    state: &MotionState,
    local: &Local,
    samples: usize,
    out: &mut GrazingSet,
) {
    let n = state.axis;
    let span = torus.phi1 - torus.phi0;
    for j in 0..samples.max(1) {
        let theta = TAU * j as f64 / samples.max(1) as f64;
        let (st, ct) = theta.sin_cos();
        let u = local.frame.x * ct + local.frame.y * st;
        let m = state.tip + n * torus.center_z + u * torus.major;
        let m_t = n.cross(u) * torus.major;
        let m_u = state.velocity_at(m);
        let big_n = m_t.cross(m_u);
        if big_n.length() <= TANGENCY_REL_EPS * torus.major * m_u.length() || m_u.length() == 0.0 {
            out.whole.push((piece, theta));
            continue;
        }
        for sign in [1.0, -1.0] {
            let normal = big_n.normalize() * sign;
            let phi = normal.dot(u).atan2(-normal.dot(n));
            if phi < torus.phi0 - ARC_EPS || phi > torus.phi1 + ARC_EPS {
                continue;
            }
            out.points.push(GrazingPoint {
                piece,
                s: ((phi - torus.phi0) / span).clamp(0.0, 1.0),
                theta,
                point: m + normal * torus.minor,
                normal,
                edge: false,
            });
        }
    }
}
