//! Cutting moves into the stock: linear moves with a fixed tool axis exactly, arcs and helices
//! by chords within a chordal tolerance, with the shank and holder checked for collisions.

pub(crate) mod five_axis;

pub use five_axis::{PIECES_PER_BATCH, SCREEN_TOLERANCE_MM};

use crate::error::StockError;
use crate::tridexel::{CutStats, LinearMove, SegmentCut, TriDexel};
use swarf_geom::math::Vec3;
use swarf_path::{Move, MoveKind, Pose, Program};
use swarf_sweep::{arc_chords, SweepShape, SweptConvex, ToolShape};

/// Two axes closer than this angle (radians) are the same axis (a fixed-axis move).
pub use swarf_path::moves::AXIS_ANGLE_EPS;

/// Default chordal tolerance for arcs, helices and 5-axis moves, mm.
pub use swarf_sweep::DEFAULT_CHORDAL_TOLERANCE_MM;

/// Chordal tolerance of rapids whose tool axis turns, mm: a rapid cuts nothing in a correct
/// program, so its sweep is refined only as far as collision reporting needs (a turning rapid
/// passing within this distance of material may be reported as meeting it).
pub const RAPID_TOLERANCE_MM: f64 = 0.01;

/// A tool instance the stock has been cut with, while nothing has put material back: two
/// groups of parts (a tool's cutting part and its shank and holder, or the tool around the
/// round region of a 5-axis move, `InstanceBand::slabs`) with the tip at `tip` and the axis
/// `axis`. The stock holds no material inside it, so a move starting there need not cut it
/// again.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct CutInstance {
    pub(crate) slabs: [SweepShape; 2],
    pub(crate) tip: Vec3,
    pub(crate) axis: Vec3,
}

impl CutInstance {
    /// Whether this is the instance of `slabs` at `tip` with `axis`.
    pub(crate) fn is(&self, slabs: [&SweepShape; 2], tip: Vec3, axis: Vec3) -> bool {
        self.tip == tip
            && self.axis == axis
            && self.slabs[0] == *slabs[0]
            && self.slabs[1] == *slabs[1]
    }

    /// Makes `last` the instance of `slabs` at `tip` with `axis`, copying the shapes only when
    /// they change (chained calls with one tool, e.g. an arc's chords, copy nothing).
    pub(crate) fn record(
        last: &mut Option<CutInstance>,
        slabs: [&SweepShape; 2],
        tip: Vec3,
        axis: Vec3,
    ) {
        match last {
            Some(l) if l.slabs[0] == *slabs[0] && l.slabs[1] == *slabs[1] => {
                (l.tip, l.axis) = (tip, axis);
            }
            _ => {
                *last = Some(CutInstance {
                    slabs: slabs.map(SweepShape::clone),
                    tip,
                    axis,
                })
            }
        }
    }
}

/// Material removed below this length (mm, on any ray) does not count as a collision.
pub const COLLISION_EPS_MM: f64 = 1e-6;

impl TriDexel {
    /// Removes the volume swept by `shape` (tool frame: tip at the origin, axis +Z) with its
    /// tip moving straight from `tip0` to `tip1` along the fixed unit `axis`.
    pub fn cut_shape_linear(
        &mut self,
        shape: &SweepShape,
        tip0: Vec3,
        tip1: Vec3,
        axis: Vec3,
    ) -> CutStats {
        let parts: Vec<SweptConvex<'_>> = shape
            .parts()
            .iter()
            .map(|p| SweptConvex::new(p, tip0, axis, tip1 - tip0))
            .collect();
        self.subtract_swept(&parts)
    }

    /// Removes what the tool sweeps on a straight move with a fixed axis: the cutting part's
    /// sweep, then the shank's and holder's.
    pub fn cut_linear(
        &mut self,
        tool: &ToolShape,
        tip0: Vec3,
        tip1: Vec3,
        axis: Vec3,
    ) -> SegmentCut {
        let m = LinearMove { tip0, tip1, axis };
        self.cut_linear_batch(tool, &[m])[0]
    }

    /// Cuts move `index` of `program` with `tool`: linear moves and rapids exactly (fixed
    /// axis), arcs and helices by chords through points of the exact arc such that the tip path
    /// is within `chordal_tol` of the arc, and moves whose tool axis turns (5-axis simultaneous)
    /// by constant-axis sub-moves within `chordal_tol` of the true sweep
    /// ([`TriDexel::cut_five_axis`]).
    pub fn cut_move(
        &mut self,
        program: &Program,
        index: usize,
        tool: &ToolShape,
        chordal_tol: f64,
    ) -> Result<SegmentCut, StockError> {
        self.cut_move_range(program, index, 0.0, 1.0, tool, chordal_tol)
    }

    /// Cuts the part `[s0, s1]` of move `index` (move parameter, 0 at its start, 1 at its end)
    /// as [`TriDexel::cut_move`] cuts a whole move: cutting `[0, a]` then `[a, 1]` leaves the
    /// stock as cutting `[0, 1]` does (up to the chords of arcs, which then pass through the
    /// arc's point at `a` too).
    pub fn cut_move_range(
        &mut self,
        program: &Program,
        index: usize,
        s0: f64,
        s1: f64,
        tool: &ToolShape,
        chordal_tol: f64,
    ) -> Result<SegmentCut, StockError> {
        let m = &program.moves[index];
        check_move(index, m)?;
        if program.is_five_axis(m) {
            let tol = if matches!(m.kind, MoveKind::Rapid) {
                chordal_tol.max(RAPID_TOLERANCE_MM)
            } else {
                chordal_tol
            };
            return self.cut_five_axis_range(program, index, (s0, s1), tool, tol);
        }
        let pose = |s: f64| {
            if s == 0.0 {
                m.start.tip
            } else if s == 1.0 {
                m.end.tip
            } else {
                program.pose_at(m, s).tip
            }
        };
        let axis = m.start.axis.normalize();
        let mut total = SegmentCut::default();
        match m.kind {
            MoveKind::Rapid | MoveKind::Linear => {
                total = self.cut_linear(tool, pose(s0), pose(s1), axis);
            }
            MoveKind::Arc(g) => {
                let radius = g.start_radius.max(g.end_radius);
                let n = arc_chords(radius, g.sweep * (s1 - s0), chordal_tol);
                if n > swarf_sweep::MAX_CHORDS {
                    return Err(
                        swarf_sweep::too_many_chords(index, m.line, radius, chordal_tol).into(),
                    );
                }
                // The chords cut as one batch, as `simulate` cuts a run of straight moves: the
                // same stock and figures as chord by chord, without a parallel section (and its
                // barrier) per chord — an arc at the default 1 µm has one chord per ≈ 0.09 mm
                // of a 10 mm radius.
                let tips: Vec<Vec3> = (0..=n)
                    .map(|i| match i {
                        0 => pose(s0),
                        i if i == n => pose(s1),
                        i => pose(s0 + (s1 - s0) * (i as f64 / n as f64)),
                    })
                    .collect();
                let chords = LinearMove::chain(&tips, axis);
                for cut in self.cut_chords(tool, &chords) {
                    total.add(cut);
                }
            }
        }
        Ok(total)
    }
}

fn check_move(index: usize, m: &Move) -> Result<(), StockError> {
    let finite = |p: &Pose| p.tip.is_finite() && p.axis.is_finite() && p.axis.length() > 0.5;
    if !finite(&m.start) || !finite(&m.end) {
        return Err(StockError::NonFinite {
            index,
            line: m.line,
        });
    }
    Ok(())
}
