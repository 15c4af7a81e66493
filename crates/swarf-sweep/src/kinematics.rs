//! The instantaneous rigid motion of the cutter along a move.
//!
//! A move places the tool at poses `P(s) = (F(s), n(s))` for `s ∈ [0, 1]` (tip and unit axis,
//! [`Program::pose_at`]). The cutter is a solid of revolution about `n`, so its motion is known
//! up to a spin about its own axis, and a spin moves every surface point along its parallel —
//! tangent to the surface — so it changes no tangency function `N·V`. The state therefore keeps
//! the tip velocity `V_F = F'(s)` and the **smallest** angular velocity carrying the axis,
//! `ω = n × n'` (perpendicular to `n`, so `n' = ω × n`, Aras eq. 5.13); the velocity of a
//! point `P` of the tool is `V(P) = V_F + ω × (P − F)` (Aras eq. 5.10).
//!
//! Velocities are per unit of the move parameter `s` (mm, radians): grazing curves depend only
//! on directions, and this keeps one scale for lines, arcs and joint moves. Derivatives are
//! analytic for straight and circular tips and for slerped (CL) axes; rotary motion interpolated
//! through the machine is differentiated by central differences with step
//! [`KINEMATICS_FD_STEP`].

use swarf_geom::math::Vec3;
use swarf_geom::Frame;
use swarf_path::{AxisSource, Move, MoveKind, Program};

use crate::tolerance::KINEMATICS_FD_STEP;

/// The cutter's pose and velocity at one instant (workpiece frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionState {
    /// Tool tip `F`, mm.
    pub tip: Vec3,
    /// Unit tool axis `n` (tip towards the spindle).
    pub axis: Vec3,
    /// Tip velocity `V_F`, mm per unit parameter.
    pub v_tip: Vec3,
    /// Angular velocity `ω` (perpendicular to the axis), radians per unit parameter.
    pub omega: Vec3,
}

impl MotionState {
    /// A state from its parts; `axis` is normalised and the component of `omega` along it
    /// dropped (a spin about the axis moves no surface point off the tool's surface).
    pub fn new(tip: Vec3, axis: Vec3, v_tip: Vec3, omega: Vec3) -> Self {
        let axis = axis.normalize();
        Self {
            tip,
            axis,
            v_tip,
            omega: omega - axis * omega.dot(axis),
        }
    }

    /// A translation with velocity `v` (3-axis and 3+2 moves).
    pub fn translation(tip: Vec3, axis: Vec3, v: Vec3) -> Self {
        Self::new(tip, axis, v, Vec3::ZERO)
    }

    /// The state of move `m` of `program` at parameter `s ∈ [0, 1]`.
    pub fn of_move(program: &Program, m: &Move, s: f64) -> Self {
        let pose = program.pose_at(m, s);
        let cl = m.axis_source == AxisSource::Program;
        let rotary = !cl && m.start_joints.rotary_differs(&m.end_joints);
        if rotary {
            // Joints interpolated through the kinematic chain: central differences, one-sided
            // at the ends of the move (the chain is not defined outside [0, 1]).
            let h = KINEMATICS_FD_STEP;
            let (a, b) = ((s - h).max(0.0), (s + h).min(1.0));
            let (pa, pb) = (program.pose_at(m, a), program.pose_at(m, b));
            let v = (pb.tip - pa.tip) / (b - a);
            let dn = (pb.axis.normalize() - pa.axis.normalize()) / (b - a);
            let n = pose.axis.normalize();
            return Self::new(pose.tip, n, v, n.cross(dn));
        }
        let v_tip = match m.kind {
            MoveKind::Arc(g) => {
                let (u, w, _) = g.start_frame(m.start.tip);
                let (sin, cos) = (s * g.sweep).sin_cos();
                let rho = g.start_radius + s * (g.end_radius - g.start_radius);
                (w * cos - u * sin) * (g.sweep * rho)
                    + (u * cos + w * sin) * (g.end_radius - g.start_radius)
                    + g.normal * g.helix
            }
            MoveKind::Linear | MoveKind::Rapid => m.end.tip - m.start.tip,
        };
        let omega = if cl {
            slerp_rate(m.start.axis.normalize(), m.end.axis.normalize())
        } else {
            Vec3::ZERO
        };
        Self::new(pose.tip, pose.axis, v_tip, omega)
    }

    /// Velocity of the tool point at `p` (workpiece frame): `V_F + ω × (p − F)`.
    #[inline]
    pub fn velocity_at(&self, p: Vec3) -> Vec3 {
        self.v_tip + self.omega.cross(p - self.tip)
    }

    /// A right-handed tool frame at the tip with `z` along the axis (the cutter's own frame:
    /// which `x` is chosen does not matter for a solid of revolution).
    pub fn tool_frame(&self) -> Frame {
        Frame::from_axis(self.tip, self.axis)
    }

    /// The tool coordinate system of Aras eq. 5.1 made right-handed and total: `x` along
    /// `n' = ω × n` when the axis turns, else along the component of `V_F` across the axis;
    /// for a plunge along the axis (where 5.1 is undefined) any perpendicular, which loses
    /// nothing because the motion is then symmetric about the axis. `y = z × x`.
    pub fn feed_frame(&self) -> Frame {
        let n = self.axis;
        let dn = self.omega.cross(n);
        let scale = self.v_tip.length() + dn.length();
        let across = self.v_tip - n * self.v_tip.dot(n);
        if dn.length() > 1e-12 * scale.max(f64::MIN_POSITIVE) {
            Frame::from_axis_and_x(self.tip, n, dn)
        } else if across.length() > 1e-12 * scale.max(f64::MIN_POSITIVE) {
            Frame::from_axis_and_x(self.tip, n, across)
        } else {
            Frame::from_axis(self.tip, n)
        }
    }

    /// True when the axis turns (a 5-axis instant).
    pub fn is_turning(&self) -> bool {
        self.omega.length() > 0.0
    }
}

/// The constant angular velocity of the slerp from unit `a` to unit `b` over `s ∈ [0, 1]`:
/// angle `∠(a, b)` about `a × b`. Opposite axes turn about the perpendicular `slerp` picks.
fn slerp_rate(a: Vec3, b: Vec3) -> Vec3 {
    let c = a.cross(b);
    let angle = c.length().atan2(a.dot(b));
    if angle < 1e-12 {
        return Vec3::ZERO;
    }
    if c.length() < 1e-9 {
        // Antiparallel: swarf_path::slerp turns through a.any_orthonormal_vector().
        let p = a.any_orthonormal_vector();
        return a.cross(p) * std::f64::consts::PI;
    }
    c.normalize() * angle
}

#[cfg(test)]
mod tests {
    use super::*;
    use swarf_path::load::{read_program_str, ReadOptions};
    use swarf_path::Machine;

    /// Analytic derivatives against central differences of `pose_at`.
    fn check(text: &str, file: &str) {
        let p =
            read_program_str(text, file, Machine::three_axis(), &ReadOptions::default()).unwrap();
        let h = 1e-6;
        for m in &p.moves {
            for s in [0.2, 0.5, 0.8] {
                let st = MotionState::of_move(&p, m, s);
                let (a, b) = (p.pose_at(m, s - h), p.pose_at(m, s + h));
                let v = (b.tip - a.tip) / (2.0 * h);
                let dn = (b.axis.normalize() - a.axis.normalize()) / (2.0 * h);
                assert!(
                    (st.v_tip - v).length() < 1e-6 * (1.0 + v.length()),
                    "{:?} vs {v:?}",
                    st.v_tip
                );
                assert!(
                    (st.omega.cross(st.axis) - dn).length() < 1e-6,
                    "{:?} vs {dn:?}",
                    st.omega
                );
            }
        }
    }

    #[test]
    fn lines_arcs_helices_and_slerped_axes() {
        check(
            "G21 G90\nG0 X1 Y2 Z3\nG1 X5 Y-1 Z0 F100\nG2 X9 Y-1 Z2 I2 J0\nG3 X9 Y-1 I0 J3\n",
            "k.ngc",
        );
        check(
            "GOTO/0,0,0,0,0,1\nGOTO/10,5,-1,0.3,0.4,0.8660254\n",
            "k.apt",
        );
    }

    #[test]
    fn plunges_have_a_frame() {
        let st = MotionState::translation(Vec3::ZERO, Vec3::Z, -Vec3::Z);
        let f = st.feed_frame();
        assert!(f.orthonormality_error() < 1e-12 && (f.z - Vec3::Z).length() < 1e-12);
        // x along the feed's component across the axis, right-handed.
        let st = MotionState::translation(Vec3::ZERO, Vec3::Z, Vec3::new(0.0, 2.0, -1.0));
        let f = st.feed_frame();
        assert!((f.x - Vec3::Y).length() < 1e-12 && (f.x.cross(f.y) - f.z).length() < 1e-12);
    }
}
