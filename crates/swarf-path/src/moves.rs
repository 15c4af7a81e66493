//! The move stream: what every later stage (stock, envelopes, engagement, forces) reads.

use serde::Serialize;
use swarf_geom::math::Vec3;

use crate::canon::{Axes, FeedMode, SpindleDir};
use crate::kinematics::Machine;
pub use crate::kinematics::Pose;
use crate::Warning;

/// The geometry of a circular or helical move, in the workpiece frame.
///
/// The tip at parameter `s ∈ [0, 1]` is
/// `center + R(normal, s·sweep)·(start − center)_⊥ · ρ(s)/ρ(0) + normal·(h0 + s·helix)` where ρ
/// interpolates linearly between the start and end radius (LinuxCNC accepts a small mismatch and
/// spirals between them) and `h0` is the start's height along the normal.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ArcGeom {
    /// A point on the arc's axis, mm (in the start's plane).
    pub center: Vec3,
    /// Unit normal of the arc plane; the motion is counter-clockwise about it.
    pub normal: Vec3,
    /// Swept angle, radians, > 0 (more than 2π for multi-turn helices).
    pub sweep: f64,
    /// Radius at the start, mm.
    pub start_radius: f64,
    /// Radius at the end, mm.
    pub end_radius: f64,
    /// Travel along the normal from start to end, mm (0 for a planar arc).
    pub helix: f64,
}

impl ArcGeom {
    /// The tip at parameter `s ∈ [0, 1]` of an arc starting at `start` (workpiece frame), by the
    /// formula in the type's documentation.
    pub fn point_at(&self, start: Vec3, s: f64) -> Vec3 {
        let (u, v, h0) = self.start_frame(start);
        let (sin, cos) = (s * self.sweep).sin_cos();
        let rho = self.start_radius + s * (self.end_radius - self.start_radius);
        self.center + (u * cos + v * sin) * rho + self.normal * (h0 + s * self.helix)
    }

    /// The in-plane unit vectors `u` (towards the start) and `v = normal × u`, and the start's
    /// height along the normal above `center`. A start on the axis (radius 0) gets an arbitrary
    /// `u` perpendicular to the normal.
    pub fn start_frame(&self, start: Vec3) -> (Vec3, Vec3, f64) {
        let d = start - self.center;
        let h0 = self.normal.dot(d);
        let radial = d - self.normal * h0;
        let u = radial
            .try_normalize()
            .unwrap_or_else(|| self.normal.any_orthonormal_vector());
        (u, self.normal.cross(u), h0)
    }

    /// Length of the path (helix and spiral included), mm, integrated to 1e-9 relative.
    pub fn length(&self) -> f64 {
        let r = 0.5 * (self.start_radius + self.end_radius);
        // The radius change is tiny (within the arc tolerance); its effect on length is second
        // order, so the mean radius gives the length of the spiral to far below 1e-9 relative
        // in any program LinuxCNC accepts.
        (self.sweep * r).hypot(self.helix)
    }
}

/// What kind of motion a move is.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub enum MoveKind {
    /// Rapid positioning (G0, `RAPID`): the tool is not meant to cut.
    Rapid,
    /// Straight feed move; with rotary axes, linear in joint space.
    Linear,
    /// Circular or helical feed move.
    Arc(ArcGeom),
}

/// One move of the program, from `start` to `end`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Move {
    /// Rapid, linear or arc.
    pub kind: MoveKind,
    /// Pose at the start, workpiece frame.
    pub start: Pose,
    /// Pose at the end, workpiece frame.
    pub end: Pose,
    /// Joint values at the start (machine frame with offsets; A B C in degrees) — what the
    /// machine interpolates linearly on 4- and 5-axis moves.
    pub start_joints: Axes,
    /// Joint values at the end.
    pub end_joints: Axes,
    /// Feed value as the program gave it, converted to mm (see `feed_mode`).
    pub feed: f64,
    /// How `feed` is read.
    pub feed_mode: FeedMode,
    /// Spindle speed, rpm (0 when stopped).
    pub spindle_rpm: f64,
    /// Spindle direction (M3 / `SPINDL/…,CLW` clockwise seen from the spindle looking at the
    /// tip, M4 / `CCLW` counter-clockwise; `Stopped` after M5 or before any spindle word).
    pub spindle_dir: SpindleDir,
    /// Active tool number (0 when none was loaded).
    pub tool: u32,
    /// Index into [`Program::files`].
    pub file: u16,
    /// 1-based source line.
    pub line: u32,
    /// Where this move's tool axis comes from, which decides how it is interpolated: a
    /// G-code program changes it with a tilted working plane (G53.1 … G69) and CL data
    /// states its axes throughout.
    pub axis_source: AxisSource,
    /// X Y Z of this move's joints are tool-tip positions in the part frame (tool centre
    /// point control: a `-tcp` machine, or a program that turned it on,
    /// [`Canon::ToolCentrePoint`](crate::Canon::ToolCentrePoint)); otherwise the machine's
    /// controlled point. Only matters on a machine with rotary joints.
    pub tcp: bool,
    /// `Some(mm)`: the feed applies to the combined distance of X Y Z and the rotary angles, a
    /// degree counted as one program unit (`mm`: 1 in a millimetre program, 25.4 in an inch
    /// one), as Fanuc and Haas controls apply it
    /// ([`Canon::RotaryFeedCombined`](crate::Canon::RotaryFeedCombined)); `None`: to X Y Z
    /// alone, and to the angles when X Y Z stand still.
    pub rotary_feed_combined: Option<f64>,
}

impl Move {
    /// Minutes this feed move takes, its tip path being `tip_length` mm long in the workpiece
    /// frame; `None` without a usable feed. The controller applies a feed per minute (or per
    /// revolution) to the programmed X Y Z in joint space — the arc length for arcs — and to
    /// the rotary angle (degrees) when X Y Z stand still, as LinuxCNC, Heidenhain and
    /// Sinumerik (FGROUP X Y Z) do — or, under Fanuc's and Haas's rule
    /// ([`Self::rotary_feed_combined`]), to √(ΔX² + ΔY² + ΔZ² + ΔA² + ΔB² + ΔC²) in program
    /// units, a degree counted as one; on CL data and under tool centre point control the axes
    /// are the tip's, so the feed is the tip's. Joint motion is linear in the move's
    /// parameter, so a part `ds` of the move takes `ds` times this.
    pub fn feed_minutes(&self, tip_length: f64) -> Option<f64> {
        let (a, b) = (self.start_joints, self.end_joints);
        let programmed = if self.axis_source == AxisSource::Program {
            tip_length
        } else {
            let xyz = match self.kind {
                MoveKind::Arc(g) => g.length(),
                _ => Vec3::new(b.x - a.x, b.y - a.y, b.z - a.z).length(),
            };
            let abc = Vec3::new(b.a - a.a, b.b - a.b, b.c - a.c).length();
            if let (Some(mm_per_deg), false) = (self.rotary_feed_combined, self.tcp) {
                xyz.hypot(abc * mm_per_deg)
            } else if xyz > crate::summary::ZERO_LENGTH_MM {
                xyz
            } else {
                abc
            }
        };
        let t = match self.feed_mode {
            FeedMode::PerMinute => programmed / self.feed,
            FeedMode::InverseTime => 1.0 / self.feed,
            FeedMode::PerRevolution | FeedMode::SpindleSynchronised => {
                programmed / (self.feed * self.spindle_rpm)
            }
        };
        (self.feed > 0.0 && t.is_finite() && t >= 0.0).then_some(t)
    }
}

/// A line of a program's source: its file (an index into [`Program::files`]) and line.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct SourceLine {
    /// Index into [`Program::files`].
    pub file: u16,
    /// 1-based source line.
    pub line: u32,
}

/// A program read into moves.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Program {
    /// The moves in order.
    pub moves: Vec<Move>,
    /// Source file names, indexed by [`Move::file`].
    pub files: Vec<String>,
    /// Tools loaded, in order of first use.
    pub tools: Vec<u32>,
    /// Cutter geometry the program itself defines (APT `CUTTER/`), per tool number: the seven APT
    /// numbers d, r, e, f, α, β, h.
    pub cutter_definitions: Vec<(u32, [f64; 7])>,
    /// Where each of [`Program::cutter_definitions`] was written (the last record that defined
    /// that tool), in the same order. A definition that differs from the one a tool has already
    /// cut with makes a tool of its own (a number above all others, with a warning), so that
    /// every move keeps the cutter it was written for.
    pub cutter_definition_lines: Vec<SourceLine>,
    /// Harmless things the reader did not act on.
    pub warnings: Vec<Warning>,
    /// The machine whose kinematics turned joints into poses (and interpolates between them).
    pub machine: Machine,
    /// Where the tool axis comes from at the program's end (each move says where its own
    /// comes from: [`Move::axis_source`]).
    pub axis_source: AxisSource,
    /// The workpiece blank the program declares (Heidenhain `BLK FORM`), least and greatest
    /// corner in the workpiece frame, mm: the stock when none is given.
    pub blank: Option<[[f64; 3]; 2]>,
    /// The dwells' total, seconds.
    pub dwell_s: f64,
}

/// Where a program's tool axis comes from, which decides how a move is interpolated.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum AxisSource {
    /// From the machine's rotary joints (G-code): moves are linear in joint space and mapped
    /// through [`Program::machine`].
    #[default]
    Machine,
    /// From the program itself (APT CL data, [`Canon::ToolAxis`](crate::Canon::ToolAxis)): the
    /// tip moves linearly (or along the arc) in the workpiece frame and the axis turns at
    /// constant angular rate (slerp) from the start axis to the end axis.
    Program,
}

impl Program {
    /// The tool tip's path as polylines of feed motion (`false`) and of rapid motion (`true`):
    /// consecutive moves of one kind that join are one polyline; arcs (and moves whose axis
    /// turns) in `chords` chords each, as the machine moves them ([`Program::pose_at`]). Moves
    /// with a non-finite tip are left out. For drawing the toolpath.
    pub fn tip_polylines(&self, chords: usize) -> Vec<(Vec<Vec3>, bool)> {
        let chords = chords.max(1);
        let mut out: Vec<(Vec<Vec3>, bool)> = Vec::new();
        for m in &self.moves {
            let rapid = matches!(m.kind, MoveKind::Rapid);
            let curved = matches!(m.kind, MoveKind::Arc(_)) || m.start.axis != m.end.axis;
            let pts: Vec<Vec3> = if curved {
                (0..=chords)
                    .map(|i| self.pose_at(m, i as f64 / chords as f64).tip)
                    .collect()
            } else {
                vec![m.start.tip, m.end.tip]
            };
            if !pts.iter().all(|p| p.is_finite()) {
                continue;
            }
            match out.last_mut() {
                Some((line, r)) if *r == rapid && line.last() == pts.first() => {
                    line.extend_from_slice(&pts[1..])
                }
                _ => out.push((pts, rapid)),
            }
        }
        out
    }

    /// The pose of move `m` at parameter `s ∈ [0, 1]` (`s` = 0 is `m.start`, 1 is `m.end`), as
    /// the machine moves: arcs exactly; linear moves with rotary motion through
    /// [`Program::machine`] at joints interpolated linearly; CL moves by a linear tip and a
    /// slerped axis.
    pub fn pose_at(&self, m: &Move, s: f64) -> Pose {
        let cl = m.axis_source == AxisSource::Program;
        let rotary = !cl && m.start_joints.rotary_differs(&m.end_joints);
        let lerp_joints = |tip_joint: Option<Vec3>| {
            let (a, b) = (m.start_joints.to_array(), m.end_joints.to_array());
            let mut j = Axes::from_array(std::array::from_fn(|i| a[i] + s * (b[i] - a[i])));
            if let Some(q) = tip_joint {
                (j.x, j.y, j.z) = (q.x, q.y, q.z);
            }
            j
        };
        match m.kind {
            MoveKind::Arc(g) => {
                let tip = g.point_at(m.start.tip, s);
                if cl {
                    Pose {
                        tip,
                        axis: slerp(m.start.axis, m.end.axis, s),
                    }
                } else if rotary {
                    // The arc is stated in the workpiece frame at the start's rotary position;
                    // carry the point back to joint space there, then move all joints.
                    let (r, t) = self
                        .machine
                        .joint_space_to_workpiece_with(&m.start_joints, m.tcp);
                    let q = r.transpose() * (tip - t);
                    self.machine.pose_with(&lerp_joints(Some(q)), m.tcp)
                } else {
                    Pose {
                        tip,
                        axis: m.start.axis,
                    }
                }
            }
            MoveKind::Rapid | MoveKind::Linear => {
                if rotary {
                    self.machine.pose_with(&lerp_joints(None), m.tcp)
                } else {
                    Pose {
                        tip: m.start.tip.lerp(m.end.tip, s),
                        axis: if cl {
                            slerp(m.start.axis, m.end.axis, s)
                        } else {
                            m.start.axis
                        },
                    }
                }
            }
        }
    }

    /// True when the tool axis may turn along `m`, or its tip leave the straight line or arc:
    /// the move is a 4-/5-axis simultaneous move. CL moves whose end axes differ (by more than
    /// [`AXIS_ANGLE_EPS`]); machine moves that turn a rotary joint (the axis can come back to
    /// where it started, or the tip follow a curve with an unchanged axis).
    pub fn is_five_axis(&self, m: &Move) -> bool {
        match m.axis_source {
            AxisSource::Program => {
                let (a, b) = (m.start.axis.normalize(), m.end.axis.normalize());
                a.cross(b).length().atan2(a.dot(b)) > AXIS_ANGLE_EPS
            }
            AxisSource::Machine => {
                self.machine.has_rotary() && m.start_joints.rotary_differs(&m.end_joints)
            }
        }
    }

    /// True when the tip of `m` may leave the straight line or arc between its end points (a
    /// linear or arc move with rotary motion interpolated through the machine).
    pub fn tip_path_is_curved(&self, m: &Move) -> bool {
        m.axis_source == AxisSource::Machine
            && m.start_joints.rotary_differs(&m.end_joints)
            && !m.tcp
    }
}

/// Tool axes closer than this (radians) count as one: a move between them is not 4-/5-axis.
pub const AXIS_ANGLE_EPS: f64 = 1e-9;

/// Spherical linear interpolation between unit vectors `a` and `b` (constant angular rate). For
/// opposite vectors the turn is about an arbitrary perpendicular.
pub fn slerp(a: Vec3, b: Vec3, s: f64) -> Vec3 {
    let d = a.dot(b).clamp(-1.0, 1.0);
    let theta = d.acos();
    if theta < 1e-12 {
        return a;
    }
    let sin = theta.sin();
    if sin < 1e-9 {
        // Antiparallel: any great half-circle will do; pick one through a fixed perpendicular.
        let p = a.any_orthonormal_vector();
        let phi = s * std::f64::consts::PI;
        return a * phi.cos() + p * phi.sin();
    }
    (a * ((1.0 - s) * theta).sin() + b * (s * theta).sin()) / sin
}

impl Default for Pose {
    fn default() -> Self {
        Self {
            tip: Vec3::ZERO,
            axis: Vec3::Z,
        }
    }
}
