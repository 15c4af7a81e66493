//! Cutting 5-axis simultaneous moves: the constant-axis sub-moves of `swarf_sweep::five_axis`
//! (with its proven bound), or for a round tool its exact instances (second order), screened
//! against the material first and cut exactly.

use super::CutInstance;
use crate::error::StockError;
use crate::tridexel::{CutStats, SegmentCut, TriDexel};
use swarf_geom::Aabb;
use swarf_path::Program;
use swarf_sweep::five_axis::{
    check_tolerance, instance_times, stated_pose, subdivide_range, SubMove,
};
use swarf_sweep::{InstanceBand, Reach, SweepShape, SweptConvex, ToolShape};

/// Bound (mm) with which a 5-axis move is first split to screen it against the material: the
/// pieces whose swept box, grown by this bound and the tolerance, holds no material are not
/// subdivided further (they could not remove anything). Affects speed only, never the result.
pub const SCREEN_TOLERANCE_MM: f64 = 1.0;

/// Sub-moves prepared and subtracted together (bounds the memory of the prepared sweeps).
pub const PIECES_PER_BATCH: usize = 256;

/// Most parts of instances cut together as one move (their rays' chords joined per ray).
const INSTANCE_PARTS: usize = swarf_sweep::InstanceSet::MAX;

/// Box holding the sweep of `shape` along the fixed-axis piece `p`.
fn piece_box(shape: &SweepShape, p: &SubMove) -> Option<Aabb> {
    shape
        .parts()
        .iter()
        .map(|part| SweptConvex::new(part, p.tip0, p.axis, p.tip1 - p.tip0).bbox())
        .reduce(|a, b| a.union(&b))
}

/// Adds to `out` what `cuts` sub-moves or instances of the cutting part (`group` 0) or the
/// shank and holder (1) removed, and their largest bound.
fn record(out: &mut SegmentCut, group: usize, (stats, worst): (CutStats, f64), cuts: usize) {
    out.error_bound_mm = out.error_bound_mm.max(worst);
    if group == 0 {
        out.cutting = out.cutting.merged(stats);
        out.sub_moves += cuts as u64;
    } else {
        out.non_cutting = out.non_cutting.merged(stats);
    }
}

/// True when some ray of `stock` crossing `b` holds material inside `b`. When false, no cut
/// within `b` can change the stock.
fn material_in(stock: &TriDexel, b: &Aabb) -> bool {
    let g = stock.grid();
    // Cell-centre indices along axis `a` within [lo, hi].
    let centres = |a: usize, lo: f64, hi: f64| {
        let i0 = ((lo - g.min[a]) / g.h[a] - 0.5).ceil().max(0.0);
        let i1 = ((hi - g.min[a]) / g.h[a] - 0.5)
            .floor()
            .min(g.n[a] as f64 - 1.0);
        (i0 <= i1).then_some((i0 as usize, i1 as usize))
    };
    (0..3).any(|k| {
        let (u, v) = ((k + 1) % 3, (k + 2) % 3);
        let (Some((i0, i1)), Some((j0, j1))) = (
            centres(u, b.min[u], b.max[u]),
            centres(v, b.min[v], b.max[v]),
        ) else {
            return false;
        };
        stock
            .family(k)
            .material_in((i0, i1), (j0, j1), (b.min[k], b.max[k]))
    })
}

impl TriDexel {
    /// Removes the volume `shape` sweeps along the sub-moves `pieces` (each a fixed-axis
    /// straight move, cut exactly), in order, [`PIECES_PER_BATCH`] at a time through
    /// [`TriDexel::subtract_moves`], all under the current move tag (they are pieces of one move).
    ///
    /// A piece whose bound leaves room under `tol` spends it on its tori: a torus band's
    /// envelope is left out where that moves the piece's sweep by no more than the room
    /// (`SweptConvex::with_envelope_slack`: a few nanometres on pieces a few µm long, for
    /// the degree-8 root isolation that was nearly all of a bull-nose's time). Returns the
    /// removal and the largest bound of any piece, the envelope's share included.
    pub fn cut_shape_pieces(
        &mut self,
        shape: &SweepShape,
        pieces: &[SubMove],
        tol: f64,
    ) -> (CutStats, f64) {
        self.cut_pieces_grouped(shape, pieces, tol, 1)
    }

    /// Removes the tool instances `instances` (pieces that do not move) of `shape`, a few at
    /// a time as the parts of one move, so that each ray they trim is read and changed once
    /// per group ([`swarf_sweep::InstanceSet`]) rather than once per instance; what remains
    /// is what cutting them one by one leaves, up to slivers and the corner's walk tolerance
    /// (10⁻¹² mm). Returns the removal and the largest bound.
    pub fn cut_instance_set(
        &mut self,
        shape: &SweepShape,
        instances: &[SubMove],
    ) -> (CutStats, f64) {
        // (An instance does not move: no envelope to leave out, whatever the tolerance.)
        let per_move = (INSTANCE_PARTS / shape.parts().len().max(1)).max(1);
        self.cut_pieces_grouped(shape, instances, 0.0, per_move)
    }

    /// [`TriDexel::cut_shape_pieces`] with `per_move` consecutive pieces made the parts of one
    /// move (1: each piece its own move).
    fn cut_pieces_grouped(
        &mut self,
        shape: &SweepShape,
        pieces: &[SubMove],
        tol: f64,
        per_move: usize,
    ) -> (CutStats, f64) {
        let mut total = CutStats::default();
        let mut worst = 0.0f64;
        let parts_per_piece = shape.parts().len().max(1);
        for chunk in pieces.chunks(PIECES_PER_BATCH) {
            let mut sweeps: Vec<SweptConvex<'_>> =
                Vec::with_capacity(chunk.len() * parts_per_piece);
            for p in chunk {
                let room = (tol - p.error_bound).max(0.0);
                let mut moved = 0.0f64;
                for part in shape.parts() {
                    let (sweep, m) = SweptConvex::new(part, p.tip0, p.axis, p.tip1 - p.tip0)
                        .with_envelope_slack(room);
                    moved = moved.max(m);
                    sweeps.push(sweep);
                }
                worst = worst.max(p.error_bound + moved);
            }
            let moves: Vec<[&[SweptConvex<'_>]; 1]> = sweeps
                .chunks(per_move * parts_per_piece)
                .map(|g| [g])
                .collect();
            for [st] in self.subtract_pieces(&moves, None) {
                total = total.merged(st);
            }
        }
        (total, worst)
    }

    /// The constant-axis pieces of the band `shape` (reach `reach`) along `range` of move
    /// `index` that can reach material. Coarse pieces are screened first: the fine pieces of a
    /// coarse one sweep within `bound + tol` of its sweep, so if its box grown by that holds no
    /// material they would remove nothing and are not made.
    fn screened_pieces(
        &self,
        program: &Program,
        index: usize,
        range: (f64, f64),
        shape: &SweepShape,
        reach: Reach,
        tol: f64,
    ) -> Result<Vec<SubMove>, StockError> {
        let mut pieces = Vec::new();
        let mut screened = Vec::new();
        subdivide_range(
            program,
            index,
            reach,
            tol.max(SCREEN_TOLERANCE_MM),
            range,
            &mut screened,
        )?;
        for c in screened {
            let Some(b) = piece_box(shape, &c) else {
                continue;
            };
            if !material_in(self, &b.inflated(c.error_bound + tol)) {
                continue;
            }
            if c.error_bound <= tol {
                pieces.push(c);
            } else {
                subdivide_range(program, index, reach, tol, (c.s0, c.s1), &mut pieces)?;
            }
        }
        Ok(pieces)
    }

    /// Cuts the tool around a round region (`region`) as exact tool instances along `range` of
    /// move `index` (`swarf_sweep::five_axis`, "Instances") when they are fewer than `pieces`,
    /// the constant-axis pieces they replace; returns whether it did. Instances whose box holds
    /// no material are skipped (they could remove nothing).
    #[allow(clippy::too_many_arguments)]
    fn cut_instances(
        &mut self,
        program: &Program,
        index: usize,
        range: (f64, f64),
        region: InstanceBand,
        pieces: usize,
        tol: f64,
        out: &mut SegmentCut,
    ) -> Result<bool, StockError> {
        let mut times = Vec::new();
        let gap = instance_times(
            program,
            index,
            (region.rho, region.centre_reach),
            tol,
            range,
            &mut times,
        )?;
        if times.len() >= pieces {
            return Ok(false);
        }
        let m = &program.moves[index];
        let instances: Vec<SubMove> = times
            .iter()
            .map(|&s| {
                let pose = stated_pose(program, m, s);
                SubMove {
                    s0: s,
                    s1: s,
                    tip0: pose.tip,
                    tip1: pose.tip,
                    axis: pose.axis.normalize(),
                    error_bound: gap,
                }
            })
            .collect();
        // A move starting where the last one ended need not cut that instance again (the
        // stock only loses material; `unite` forgets it).
        let first = instances[0];
        let slabs = [&region.slabs[0], &region.slabs[1]];
        let skip = usize::from(
            self.last_instance
                .as_ref()
                .is_some_and(|l| l.is(slabs, first.tip0, first.axis)),
        );
        for (w, slab) in region.slabs.iter().enumerate() {
            let live: Vec<SubMove> = instances[skip..]
                .iter()
                .filter(|c| piece_box(slab, c).is_some_and(|b| material_in(self, &b)))
                .copied()
                .collect();
            let cut = self.cut_instance_set(slab, &live);
            record(out, w, cut, live.len());
        }
        let last = instances[instances.len() - 1];
        self.last_instance = Some(CutInstance {
            slabs: region.slabs,
            tip: last.tip0,
            axis: last.axis,
        });
        Ok(true)
    }

    /// Cuts move `index` of `program`, a 5-axis simultaneous move ([`Program::is_five_axis`]), as
    /// constant-axis sub-moves within `tol` mm of the true sweep (module documentation): the
    /// cutting part and the shank/holder are cut into bands no taller than their radius
    /// ([`ToolShape::rotating_bands`]) and each band is subdivided by its own reach
    /// (`swarf_sweep::five_axis::Reach`), which for a long part is a fraction of the whole
    /// part's.
    /// Pieces that cannot reach any material are screened out first ([`SCREEN_TOLERANCE_MM`]).
    /// The bands that can, and lie in the tool's round region (`ToolShape::round_region`), are
    /// cut together as exact tool instances instead when that takes fewer cuts
    /// (`swarf_sweep::five_axis`, "Instances": second order, never outside the true sweep).
    /// [`SegmentCut::sub_moves`] counts the cutting part's sub-moves and instances that were cut
    /// and [`SegmentCut::error_bound_mm`] is the largest bound of any of them.
    ///
    /// # Errors
    /// As [`swarf_sweep::five_axis::subdivide`].
    pub fn cut_five_axis(
        &mut self,
        program: &Program,
        index: usize,
        tool: &ToolShape,
        tol: f64,
    ) -> Result<SegmentCut, StockError> {
        self.cut_five_axis_range(program, index, (0.0, 1.0), tool, tol)
    }

    /// [`TriDexel::cut_five_axis`] on the part `range` of the move's parameter.
    pub fn cut_five_axis_range(
        &mut self,
        program: &Program,
        index: usize,
        range: (f64, f64),
        tool: &ToolShape,
        tol: f64,
    ) -> Result<SegmentCut, StockError> {
        check_tolerance(program, index, tol)?;
        let mut out = SegmentCut::default();
        // Each band of a part separately: the union of the bands' sweeps is the part's, and a
        // band's bound scales with its own reach, not the part's length. First the pieces of
        // every band that can reach material.
        let mut live = Vec::new();
        for k in 0..2 {
            for ((shape, r), round) in tool.rotating_bands(k).iter().zip(tool.instance_bands(k)) {
                let pieces = self.screened_pieces(program, index, range, shape, *r, tol)?;
                if !pieces.is_empty() {
                    live.push((k, shape, pieces, *round));
                }
            }
        }
        // The live bands round enough for instances, cut together as instances of the tool
        // around them when that takes fewer cuts than their pieces.
        let (mut lo, mut hi, mut round_pieces) = (f64::INFINITY, f64::NEG_INFINITY, 0);
        for (_, _, pieces, round) in &live {
            if let Some((a, b)) = round {
                (lo, hi) = (lo.min(*a), hi.max(*b));
                round_pieces += pieces.len();
            }
        }
        let by_instances = match tool.round_region((lo, hi)) {
            Some(region) => {
                self.cut_instances(program, index, range, region, round_pieces, tol, &mut out)?
            }
            None => false,
        };
        for (k, shape, pieces, round) in live {
            if by_instances && round.is_some() {
                continue;
            }
            let cut = self.cut_shape_pieces(shape, &pieces, tol);
            record(&mut out, k, cut, pieces.len());
        }
        Ok(out)
    }
}
