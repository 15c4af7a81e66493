//! The program check (Liu 2007's future work): for a cutter and an NC or CL program, every
//! program point and every stretch of motion between points where the cutter gouges the part
//! surface or any part of the tool interferes with the part or the check geometry, and by how
//! much — located, bounded and certified.
//!
//! # What is measured
//! The tool is its **cutting part**, its **shank** and its **holder**, each a union of convex
//! solids of revolution ([`swarf_sweep::SweepShape`]). At a pose (tip `T`, unit axis `a`) a
//! surface point `S` is inside a part `K` by the depth `−sd_K(S)`, `sd` the signed distance
//! (negative inside). The *depth* of the pose is the largest over the surface, and the depth of
//! a stretch of motion the largest over its poses: how far the tool reaches past the surface,
//! the amount the part is overcut by (or the holder pushed into it). The surface's orientation
//! plays no part (a surface point inside the tool is a violation from either side), and a tool
//! sunk deeper than its own radius reads at least its radius deep: the distance to the
//! boundary saturates there, which only understates violations already far past any
//! tolerance.
//!
//! * **Gouge**: the cutting part deeper than the tolerance in the machined surface at a feed
//!   move.
//! * **Interference**: the shank or holder deeper than the tolerance in the surface or the check
//!   geometry, the cutting part in the check geometry (fixtures, clamps, neighbouring parts),
//!   and any part of the tool in anything during a rapid.
//!
//! Touching is not gouging: a finishing pass is tangent to the surface along its whole length,
//! so only depths above [`GougeOptions::tolerance`] are reported.
//!
//! # The bound (why the answer is certified)
//! A convex part's signed distance is `sd_K(x) = max_n (n·x − h_K(n))` over unit `n`, `h_K`
//! its support function ([`swarf_sweep::ConvexProfile::support`]). A rational Bézier sub-patch
//! lies in the convex hull of its control points `b_i` (positive weights), so for any fixed
//! `n` no point of it is deeper than `h_K(n) − min_i n·b_i`. While the tool moves along a
//! fixed-axis straight stretch `T(t) = T₀ + t·Δ`, `t ∈ [t₀, t₁]`, the support is
//! `h_K(n) + n·T(t)`, largest at an end of the interval, so over the stretch no point is deeper
//! than
//!
//! ```text
//! h_K(n; T(t_m)) + (t₁ − t₀)/2 · |n·Δ| − min_i n·b_i,     t_m the middle of the interval.
//! ```
//!
//! With `n` the outward direction of `K` at the point nearest to the sub-patch the bound is
//! tight to second order in the sub-patch's size and the interval's length. The search
//! (`search`) keeps (sub-patch × interval) nodes in a heap ordered by this bound, evaluates
//! real surface points (the sub-patch corners) as evidence, splits whichever — the sub-patch
//! into quarters, or the interval into halves — holds most of a node's gap, and stops when no
//! node can beat the deepest point found by more than [`GougeOptions::accuracy`] (or reach the
//! tolerance at all: a clear stretch is *proven* clear).
//!
//! Where two faces of the part are equally near — the medial ridge of a flat bottom's rim, along
//! which a flat end mill sunk into a slope has a line of near-ties — either plane alone leaves a
//! gap at every node size. The depth is at most the smaller of the two planes' gaps at every
//! point, so the hull's largest such minimum (at a control point, or where the gaps cross on a
//! segment between two) bounds the node too; a search that has expanded more than a few hundred
//! nodes tries this pair of planes on every node it would expand.
//!
//! # Motion
//! Every move is cut into fixed-axis straight sub-moves by
//! [`swarf_sweep::five_axis::subdivide`], which bounds the Hausdorff distance between the true
//! motion of each part (arcs, helices, 5-axis joint or CL interpolation) and the sub-moves by
//! [`GougeOptions::motion_tolerance`] (a straight fixed-axis move is one exact sub-move). A
//! depth is therefore within that bound of the true motion's depth; the report's upper bounds
//! include it. Along a move the stretches deeper than the tolerance are located by bisecting
//! the sub-moves down to [`GougeOptions::resolution`] of tool travel.

mod program;
mod report;
pub(crate) mod search;

pub use program::{check_program, check_program_observed};
pub use report::{surface_label, GougeSummary};
pub use search::GougeSurface;

use serde::Serialize;
use swarf_geom::math::Vec3;
use swarf_sweep::{ConvexProfile, Reach, SweepShape};
use swarf_tool::Cutter;

/// Options of the program check (documented defaults).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GougeOptions {
    /// Depths at or below this are touching, not gouging, mm. Default `0.001`.
    pub tolerance: f64,
    /// Certificate gap: the reported depth of a violation is within this of the deepest depth
    /// of the (sub-)motion, mm (or within [`GougeOptions::relative_accuracy`] of it, if
    /// larger). Default `1e-4`.
    pub accuracy: f64,
    /// Relative certificate gap, for deep violations. Default `1e-3`.
    pub relative_accuracy: f64,
    /// Where a violation starts and ends along a move is located to this much tool travel, mm.
    /// Default `0.05`.
    pub resolution: f64,
    /// Bound on the distance between the true motion of arcs and 5-axis moves and the
    /// fixed-axis straight sub-moves it is checked as, mm. Default `0.0005`.
    pub motion_tolerance: f64,
    /// Node budget of one search. Default `200 000`.
    pub max_nodes: u64,
}

impl GougeOptions {
    /// The documented defaults.
    pub const DEFAULT: GougeOptions = GougeOptions {
        tolerance: 0.001,
        accuracy: 1e-4,
        relative_accuracy: 1e-3,
        resolution: 0.05,
        motion_tolerance: 0.0005,
        max_nodes: 200_000,
    };

    /// The certificate gap at `depth`: the larger of the absolute and the relative accuracy.
    pub fn gap(&self, depth: f64) -> f64 {
        self.accuracy.max(self.relative_accuracy * depth)
    }

    /// These options with `tolerance`, the motion tolerance at most half of it and the
    /// accuracy at most a tenth of it (a violation just above the tolerance must still be told
    /// from one just below).
    pub fn with_tolerance(mut self, tolerance: f64) -> Self {
        self.tolerance = tolerance;
        self.motion_tolerance = self.motion_tolerance.min(0.5 * tolerance);
        self.accuracy = self.accuracy.min(0.1 * tolerance);
        self
    }
}

impl Default for GougeOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Which part of the tool.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ToolPart {
    /// The fluted part.
    Cutting,
    /// The shank above the flutes.
    Shank,
    /// The holder.
    Holder,
}

impl ToolPart {
    /// `cutting`, `shank` or `holder`.
    pub fn as_str(self) -> &'static str {
        match self {
            ToolPart::Cutting => "cutting",
            ToolPart::Shank => "shank",
            ToolPart::Holder => "holder",
        }
    }
}

/// Gouge or interference (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ViolationKind {
    /// The cutting part into the machined surface at a feed move.
    Gouge,
    /// Shank or holder into anything, anything into the check geometry, anything at a rapid.
    Interference,
}

impl ViolationKind {
    /// `gouge` or `interference`.
    pub fn as_str(self) -> &'static str {
        match self {
            ViolationKind::Gouge => "gouge",
            ViolationKind::Interference => "interference",
        }
    }
}

/// Where on the part a depth was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case", tag = "kind", content = "index")]
pub enum SurfaceRef {
    /// Patch of the machined surface (its index in the compound surface).
    Patch(usize),
    /// Triangle of the check geometry.
    Check(usize),
}

/// A stretch of one move where one part of the tool is deeper than the tolerance.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Violation {
    /// Index of the move in the program.
    pub move_index: usize,
    /// Source file index and 1-based line of the move.
    pub file: u16,
    /// Line.
    pub line: u32,
    /// Gouge or interference.
    pub kind: ViolationKind,
    /// Which part of the tool.
    pub part: ToolPart,
    /// True for a rapid move.
    pub rapid: bool,
    /// Move parameter where the stretch starts and ends (0 = the move's start point, 1 its
    /// end), located to [`GougeOptions::resolution`].
    pub s_start: f64,
    /// End of the stretch.
    pub s_end: f64,
    /// Depth of the deepest point found, mm (a real surface point at a real pose of the
    /// checked motion).
    pub depth: f64,
    /// Nothing in the stretch is deeper than this, mm (includes the motion tolerance).
    pub depth_upper: f64,
    /// Move parameter of the deepest pose.
    pub s_deepest: f64,
    /// Tip and axis of the deepest pose.
    pub tip: Vec3,
    /// Axis of the deepest pose.
    pub axis: Vec3,
    /// The deepest surface point.
    pub point: Vec3,
    /// Where it lies.
    pub surface: SurfaceRef,
}

/// One program point (the start of the program and the end of every move).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PointCheck {
    /// The move ending at this point (`None`: the start of the first move).
    pub move_index: Option<usize>,
    /// Source file index of the move.
    pub file: u16,
    /// Line.
    pub line: u32,
    /// Tip.
    pub tip: Vec3,
    /// Axis.
    pub axis: Vec3,
    /// The largest depth of any part of the tool at this pose, mm (negative: clearance of the
    /// nearest point evaluated).
    pub depth: f64,
    /// No surface point is deeper than this in any part at this pose, mm.
    pub depth_upper: f64,
    /// What that depth is when above the tolerance (`None`: clear).
    pub status: Option<ViolationKind>,
    /// The part with the largest depth.
    pub part: ToolPart,
    /// Where the deepest point lies (`None` when nothing is near).
    pub surface: Option<SurfaceRef>,
}

/// The whole check.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GougeReport {
    /// Every program point.
    pub points: Vec<PointCheck>,
    /// Every violation, in program order.
    pub violations: Vec<Violation>,
    /// Fixed-axis sub-moves checked.
    pub sub_moves: usize,
    /// Search nodes expanded.
    pub nodes: u64,
    /// Searches whose node budget ran out (their bounds stay valid but may be loose).
    pub unresolved: usize,
}

impl GougeReport {
    /// Deepest violation of `kind` (0 when none).
    pub fn max_depth(&self, kind: ViolationKind) -> f64 {
        self.violations
            .iter()
            .filter(|v| v.kind == kind)
            .map(|v| v.depth)
            .fold(0.0, f64::max)
    }

    /// Number of distinct moves with a violation of `kind`.
    pub fn moves_with(&self, kind: ViolationKind) -> usize {
        let mut m: Vec<usize> = self
            .violations
            .iter()
            .filter(|v| v.kind == kind)
            .map(|v| v.move_index)
            .collect();
        m.dedup();
        m.len()
    }

    /// Number of program points whose status is `kind`.
    pub fn points_with(&self, kind: ViolationKind) -> usize {
        self.points
            .iter()
            .filter(|p| p.status == Some(kind))
            .count()
    }
}

/// A cutter prepared for the check: every convex piece of its cutting part, shank and holder,
/// with the pivot and reach its sub-moves are made for.
#[derive(Clone, Debug)]
pub struct GougeTool {
    parts: Vec<(ToolPart, ConvexProfile, Reach)>,
}

impl GougeTool {
    /// The parts of `cutter`.
    pub fn new(cutter: &Cutter) -> Self {
        let mut parts = Vec::new();
        let mut add = |part: ToolPart, shape: SweepShape| {
            for p in shape.parts() {
                let one = SweepShape::from_parts(vec![p.clone()]);
                if let Some(reach) = Reach::of(&one) {
                    parts.push((part, p.clone(), reach));
                }
            }
        };
        add(
            ToolPart::Cutting,
            SweepShape::from_solid(cutter.cutting_solid()),
        );
        add(
            ToolPart::Shank,
            SweepShape::from_solid(cutter.shank_solid()),
        );
        if let Some(h) = cutter.holder_solid() {
            add(ToolPart::Holder, SweepShape::from_solid(h));
        }
        Self { parts }
    }

    pub(crate) fn parts(&self) -> &[(ToolPart, ConvexProfile, Reach)] {
        &self.parts
    }
}

/// Most pieces of [`GougeOptions::resolution`] the program's tool travel may be cut into while
/// violations are located (each gouging stretch is bisected down to the resolution): ten
/// million, a few hundred megabytes at most.
pub const MAX_LOCATED_PIECES: f64 = 1e7;

/// Why a program cannot be checked.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum GougeError {
    /// The observer ([`swarf_geom::progress::Observer`]) stopped the check after `done` of
    /// `total` moves; nothing is reported.
    #[error("stopped after {done} of {total} moves")]
    Cancelled {
        /// Moves checked.
        done: usize,
        /// Moves in the program.
        total: usize,
    },
    /// A move uses a tool the caller gave no cutter for.
    #[error("line {line}: tool {tool} is not defined (give a cutter for it)")]
    UnknownTool {
        /// Tool number.
        tool: u32,
        /// Line of the first move using it.
        line: u32,
    },
    /// An option is out of range.
    #[error("{name} must be a positive number of mm, got {value}")]
    BadOption {
        /// Option name.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// The resolution is so fine that locating violations along the program's tool travel
    /// could take more pieces than memory and time allow.
    #[error(
        "resolution {resolution} mm over {travel_mm:.1} mm of tool travel could locate \
         violations in up to {pieces:.3e} pieces, more than {max:.0e}; give a coarser resolution"
    )]
    TooFine {
        /// The resolution asked for, mm.
        resolution: f64,
        /// The program's tool travel (all moves), mm.
        travel_mm: f64,
        /// Travel over resolution.
        pieces: f64,
        /// The limit ([`MAX_LOCATED_PIECES`]).
        max: f64,
    },
    /// A move could not be cut into sub-moves.
    #[error(transparent)]
    Motion(#[from] swarf_sweep::SweepError),
    /// A move with a coordinate that is not finite or lies beyond the machine range
    /// ([`swarf_geom::math::MACHINE_RANGE_MM`]): no search over it could certify anything, so
    /// the check refuses it rather than skip it.
    #[error(
        "line {line}: the move ends at {end:?} mm, not finite or beyond the machine range of \
         ±{range:e} mm; it cannot be checked"
    )]
    BadMove {
        /// Source line of the move.
        line: u32,
        /// Its end (or start) tip, mm.
        end: [f64; 3],
        /// The machine range, mm.
        range: f64,
    },
}
