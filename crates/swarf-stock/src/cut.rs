//! Cutting moves into the stock: linear moves with a fixed tool axis exactly, arcs and helices
//! by chords within a chordal tolerance, with the shank and holder checked for collisions.

use crate::error::StockError;
use crate::sweep::{SweepShape, SweptConvex};
use crate::tridexel::{CutStats, TriDexel};
use swarf_geom::math::Vec3;
use swarf_path::{Move, MoveKind, Pose, Program};
use swarf_tool::Cutter;

/// Default chordal tolerance for arcs and helices, mm.
pub const DEFAULT_CHORDAL_TOLERANCE_MM: f64 = 0.001;

/// Two axes closer than this angle (radians) are the same axis (a fixed-axis move).
pub use swarf_path::moves::AXIS_ANGLE_EPS;

/// Material removed below this length (mm, on any ray) does not count as a collision.
pub const COLLISION_EPS_MM: f64 = 1e-6;

/// A cutter prepared for sweeping: its cutting part and its non-cutting parts (shank and
/// holder) as unions of convex profiles.
#[derive(Clone, Debug)]
pub struct ToolShape {
    cutting: SweepShape,
    non_cutting: SweepShape,
}

impl ToolShape {
    /// The shapes of `cutter` (cutting part; shank plus holder).
    pub fn new(cutter: &Cutter) -> Self {
        let cutting = SweepShape::from_solid(cutter.cutting_solid());
        let mut nc = SweepShape::from_solid(cutter.shank_solid())
            .parts()
            .to_vec();
        if let Some(h) = cutter.holder_solid() {
            nc.extend_from_slice(SweepShape::from_solid(h).parts());
        }
        Self {
            cutting,
            non_cutting: SweepShape::from_parts(nc),
        }
    }

    /// The cutting part.
    pub fn cutting(&self) -> &SweepShape {
        &self.cutting
    }

    /// Shank and holder.
    pub fn non_cutting(&self) -> &SweepShape {
        &self.non_cutting
    }
}

/// What one move (or straight sub-move) removed.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SegmentCut {
    /// By the cutting part.
    pub cutting: CutStats,
    /// By the shank and holder (non-zero means a holder collision).
    pub non_cutting: CutStats,
    /// Straight fixed-axis pieces the cutting part was cut as: 1 for a line, the chords of an
    /// arc, the constant-axis sub-moves of a 5-axis move ([`crate::five_axis`]).
    pub sub_moves: u64,
    /// Largest bound on the distance between the volume cut and the true swept volume of a
    /// 5-axis move, mm (0 for other moves: exact, or arcs within the chordal tolerance).
    pub error_bound_mm: f64,
}

impl SegmentCut {
    fn add(&mut self, o: SegmentCut) {
        self.cutting = self.cutting.merged(o.cutting);
        self.non_cutting = self.non_cutting.merged(o.non_cutting);
        self.sub_moves += o.sub_moves;
        self.error_bound_mm = self.error_bound_mm.max(o.error_bound_mm);
    }
}

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
        let m = crate::tridexel::LinearMove { tip0, tip1, axis };
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
            return self.cut_five_axis_range(program, index, (s0, s1), tool, chordal_tol);
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
                let n = arc_chords(
                    g.start_radius.max(g.end_radius),
                    g.sweep * (s1 - s0),
                    chordal_tol,
                );
                let mut prev = pose(s0);
                for i in 1..=n {
                    let s = if i == n {
                        s1
                    } else {
                        s0 + (s1 - s0) * (i as f64 / n as f64)
                    };
                    let p = pose(s);
                    total.add(self.cut_linear(tool, prev, p, axis));
                    prev = p;
                }
            }
        }
        Ok(total)
    }
}

/// Number of equal chords for an arc of radius `radius` sweeping `sweep` radians so that the
/// sagitta `radius·(1 − cos(Δ/2))` is at most `tol`. For a helix or spiral, the axial travel
/// is linear in the parameter on both the arc and the chord, so the distance between points of
/// equal parameter is the in-plane sagitta of the larger radius (a bound).
pub fn arc_chords(radius: f64, sweep: f64, tol: f64) -> usize {
    if !(radius > tol && tol > 0.0 && sweep.is_finite()) {
        return 1.max((sweep / std::f64::consts::FRAC_PI_2).ceil() as usize);
    }
    let step = 2.0 * (1.0 - tol / radius).acos();
    let n = (sweep.abs() / step).ceil().max(1.0);
    // Never coarser than quarter turns (keeps each chord's sweep convex-hull argument simple).
    n.max((sweep.abs() / std::f64::consts::FRAC_PI_2).ceil()) as usize
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chord_count_honours_tolerance() {
        for (r, sweep, tol) in [
            (10.0, std::f64::consts::PI, 0.001),
            (3.0, 7.0, 0.01),
            (50.0, 0.1, 1e-4),
        ] {
            let n = arc_chords(r, sweep, tol);
            let d = sweep / n as f64;
            assert!(
                r * (1.0 - (d / 2.0).cos()) <= tol * (1.0 + 1e-12),
                "{r} {sweep} {tol} {n}"
            );
            // And not wastefully fine: one chord fewer would break it (when not capped).
            if n > (sweep / std::f64::consts::FRAC_PI_2).ceil() as usize {
                let d1 = sweep / (n - 1) as f64;
                assert!(r * (1.0 - (d1 / 2.0).cos()) > tol);
            }
        }
    }
}
