//! The move stream: what every later stage (stock, envelopes, engagement, forces) reads.

use serde::Serialize;
use swarf_geom::math::Vec3;

use crate::canon::{Axes, FeedMode};
use crate::Warning;

/// Tool tip and tool axis in the workpiece frame. The axis is a unit vector pointing from the
/// tip up the tool, towards the spindle (+Z on a 3-axis machine).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Pose {
    /// Tool tip (the cutter's lowest point on its axis, the APT reference point), mm.
    pub tip: Vec3,
    /// Unit tool axis, tip towards spindle.
    pub axis: Vec3,
}

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
    /// Active tool number (0 when none was loaded).
    pub tool: u32,
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
    /// Harmless things the reader did not act on.
    pub warnings: Vec<Warning>,
}

impl Default for Pose {
    fn default() -> Self {
        Self { tip: Vec3::ZERO, axis: Vec3::Z }
    }
}
