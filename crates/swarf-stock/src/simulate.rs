//! Running a whole program on a stock: tools, options, collisions and the report.

use crate::cut::{COLLISION_EPS_MM, DEFAULT_CHORDAL_TOLERANCE_MM};
use crate::error::StockError;
use crate::tridexel::{CutStats, LinearMove, TriDexel};
use std::collections::BTreeMap;
use std::time::Instant;
use swarf_geom::math::Vec3;
use swarf_geom::progress::{Observer, Quiet};
use swarf_path::{Move, MoveKind, Program};
use swarf_sweep::ToolShape;
use swarf_tool::{Cutter, ToolSet};

/// Simulation options; accuracy parameters with their defaults in one place.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SimOptions {
    /// Largest distance between an arc (or helix) and the chords that replace it, mm
    /// (default [`DEFAULT_CHORDAL_TOLERANCE_MM`]).
    pub chordal_tolerance: f64,
}

impl Default for SimOptions {
    fn default() -> Self {
        Self {
            chordal_tolerance: DEFAULT_CHORDAL_TOLERANCE_MM,
        }
    }
}

impl SimOptions {
    /// The options with another chordal tolerance.
    pub fn with_chordal_tolerance(mut self, tol: f64) -> Self {
        self.chordal_tolerance = tol;
        self
    }
}

/// The sweep shapes of the cutters `program`'s moves use, each built once from `tools`; a
/// number `tools` has no cutter for is left out.
fn shapes_of(program: &Program, tools: &ToolSet) -> BTreeMap<u32, ToolShape> {
    let mut shapes = BTreeMap::new();
    for m in &program.moves {
        if let std::collections::btree_map::Entry::Vacant(e) = shapes.entry(m.tool) {
            if let Some(c) = tools.get(m.tool) {
                e.insert(ToolShape::new(c));
            }
        }
    }
    shapes
}

/// The radii of spheres about the tool tip that hold its cutting part, and the whole tool
/// (cutting part, shank and holder), in any orientation: each one's height plus its largest
/// radius.
pub fn reach(c: &Cutter) -> Reach {
    let holder = c.holder().map_or((0.0, 0.0), |h| {
        let top = h.base_z_mm + h.segments.iter().map(|s| s.length_mm).sum::<f64>();
        let r = h
            .segments
            .iter()
            .map(|s| 0.5 * s.bottom_diameter_mm.max(s.top_diameter_mm))
            .fold(0.0, f64::max);
        (top, r)
    });
    let height = c.overall_length().max(holder.0);
    let radius = (0.5 * c.max_diameter())
        .max(0.5 * c.shank_diameter())
        .max(holder.1);
    Reach {
        cutting: c.flute_length().min(c.overall_length()) + 0.5 * c.max_diameter(),
        whole: height + radius,
    }
}

/// How far a tool reaches from its tip ([`reach`]), mm.
#[derive(Clone, Copy, Debug, Default)]
pub struct Reach {
    /// The cutting part.
    pub cutting: f64,
    /// The whole tool: cutting part, shank and holder.
    pub whole: f64,
}

/// The box of move `m`'s tip path, sampled, grown by the largest step between samples (the path
/// between two samples stays within that of them): grown further by a tool's reach, it holds
/// everything the tool sweeps.
fn tip_box(program: &Program, m: &Move) -> (Vec3, Vec3) {
    const SAMPLES: u32 = 16;
    let (mut lo, mut hi) = (Vec3::splat(f64::INFINITY), Vec3::splat(f64::NEG_INFINITY));
    let (mut prev, mut step) = (None::<Vec3>, 0.0f64);
    for i in 0..=SAMPLES {
        let p = program.pose_at(m, f64::from(i) / f64::from(SAMPLES)).tip;
        (lo, hi) = (lo.min(p), hi.max(p));
        if let Some(q) = prev {
            step = step.max((p - q).length());
        }
        prev = Some(p);
    }
    (lo - Vec3::splat(step), hi + Vec3::splat(step))
}

/// `(lo, hi)` grown by `r` on every side.
fn grown((lo, hi): (Vec3, Vec3), r: f64) -> (Vec3, Vec3) {
    (lo - Vec3::splat(r), hi + Vec3::splat(r))
}

/// Where multi-axis moves may have left slivers (see [`collides`]): the boxes their cutting
/// parts and their whole tools swept, with their error bounds. The simulation and the
/// engagement judge their rapids' and holders' removals with it alike.
#[derive(Clone, Debug, Default)]
pub struct SliverZones {
    cutting: Vec<(Vec3, Vec3, f64)>,
    whole: Vec<(Vec3, Vec3, f64)>,
}

impl SliverZones {
    /// Move `index` of `program`, by a tool of reach `reach`, was cut within `error_bound` mm
    /// of its sweep (0: exactly, nothing recorded).
    pub fn record(&mut self, program: &Program, index: usize, reach: Reach, error_bound: f64) {
        if error_bound > 0.0 {
            // The tip path sampled once for both boxes.
            let tip = tip_box(program, &program.moves[index]);
            let (lo, hi) = grown(tip, reach.cutting);
            self.cutting.push((lo, hi, error_bound));
            let (lo, hi) = grown(tip, reach.whole);
            self.whole.push((lo, hi, error_bound));
        }
    }

    /// Whether what move `index` removed is a collision ([`collides`], with the error bound of
    /// the recorded moves whose sweeps meet its own): `cutting` its cutting part's removal (a
    /// rapid's), else its shank's and holder's.
    pub fn collision(
        &self,
        program: &Program,
        index: usize,
        reach: Reach,
        st: &CutStats,
        cutting: bool,
    ) -> bool {
        let (zones, r) = if cutting {
            (&self.cutting, reach.cutting)
        } else {
            (&self.whole, reach.whole)
        };
        let bound = if zones.is_empty() || !st.removed_any(COLLISION_EPS_MM) {
            0.0
        } else {
            bound_near(zones, grown(tip_box(program, &program.moves[index]), r))
        };
        collides(st, bound)
    }
}

/// The largest error bound of `zones` whose boxes meet `(lo, hi)`.
fn bound_near(zones: &[(Vec3, Vec3, f64)], (lo, hi): (Vec3, Vec3)) -> f64 {
    zones
        .iter()
        .filter(|(a, b, _)| a.cmple(hi).all() && lo.cmple(*b).all())
        .map(|z| z.2)
        .fold(0.0, f64::max)
}

/// A move that brought a non-cutting thing into the material.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Collision {
    /// Move index in the program.
    pub move_index: usize,
    /// Source file name.
    pub file: String,
    /// 1-based source line.
    pub line: u32,
    /// Volume the offending part removed (from the Z rays), mm³.
    pub volume_mm3: f64,
}

/// What a simulation did.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SimulationReport {
    /// Stock volume before the program (Z rays), mm³.
    pub stock_volume_mm3: f64,
    /// Removed volume (Z rays), mm³.
    pub removed_volume_mm3: f64,
    /// Stock volume after the program (Z rays), mm³.
    pub final_volume_mm3: f64,
    /// Final volume estimated from the X, Y and Z rays (a cross-check), mm³.
    pub final_volume_xyz_mm3: [f64; 3],
    /// Moves simulated.
    pub moves: usize,
    /// Rays in the stock.
    pub rays: u64,
    /// Intervals in the final stock.
    pub intervals: u64,
    /// Bytes per interval of the final stock.
    pub bytes_per_interval: f64,
    /// Rapids whose cutting part entered the material (the material is removed).
    pub rapid_collisions: Vec<Collision>,
    /// Moves whose shank or holder entered the material (the material is removed).
    pub holder_collisions: Vec<Collision>,
    /// Wall-clock time of the simulation, s.
    pub elapsed_s: f64,
    /// Removed volume per move (Z rays), mm³, in program order.
    pub removed_per_move_mm3: Vec<f64>,
    /// Rays whose exact swept interval was computed.
    pub rays_tested: u64,
    /// Rays whose material changed (summed over moves).
    pub ray_updates: u64,
    /// Chordal tolerance used for arcs and 5-axis moves, mm.
    pub chordal_tolerance_mm: f64,
    /// Moves whose tool axis turned (5-axis simultaneous), cut by constant-axis sub-moves.
    pub five_axis_moves: usize,
    /// Constant-axis sub-moves the cutting part was cut as on those moves.
    pub five_axis_sub_moves: u64,
    /// Largest proven bound on the distance between a 5-axis sub-move's sweep and the true
    /// one, mm (at most `chordal_tolerance_mm`; 0 without 5-axis moves).
    pub five_axis_error_bound_mm: f64,
    /// Grid cell sizes along X, Y, Z, mm.
    pub resolution_mm: [f64; 3],
}

/// Runs every move of `program` through `stock`, each with its tool's cutter from `tools`
/// ([`ToolSet::get`]). Stops at the first move it cannot cut (a tool `tools` has no cutter for,
/// non-finite pose, a 5-axis move needing more than
/// [`swarf_sweep::five_axis::MAX_SUB_MOVES`] sub-moves) with that move's error.
pub fn simulate(
    program: &Program,
    tools: &ToolSet,
    stock: &mut TriDexel,
    options: &SimOptions,
) -> Result<SimulationReport, StockError> {
    simulate_observed(program, tools, stock, options, &Quiet)
}

/// Most consecutive straight fixed-axis moves cut as one batch by [`simulate`] (a batch is
/// the unit of progress reports and cancellation; about 50 ms of finishing moves).
pub const BATCH_MOVES: usize = 256;

/// True when move `m` is a straight move with a fixed tool axis and finite poses: what
/// [`TriDexel::cut_move`] cuts as one [`TriDexel::cut_linear`].
fn batchable(program: &Program, m: &swarf_path::Move) -> bool {
    let finite =
        |p: &swarf_path::Pose| p.tip.is_finite() && p.axis.is_finite() && p.axis.length() > 0.5;
    matches!(m.kind, MoveKind::Rapid | MoveKind::Linear)
        && finite(&m.start)
        && finite(&m.end)
        && !program.is_five_axis(m)
}

/// [`simulate`], telling `observer` between moves how many of the program's moves are done
/// (`progress(done, moves)`, after each move or each batch of up to [`BATCH_MOVES`] straight
/// moves; not before the first nor after the last); the observer may stop the run (Ctrl-C),
/// which then ends with [`StockError::Cancelled`] and leaves the stock as the finished moves
/// made it.
pub fn simulate_observed(
    program: &Program,
    tools: &ToolSet,
    stock: &mut TriDexel,
    options: &SimOptions,
    observer: &dyn Observer,
) -> Result<SimulationReport, StockError> {
    // The moves cut one by one (5-axis, arcs) are each a short parallel section: on a pool
    // kept awake each starts at once (`pool::hot`).
    crate::pool::hot(|| simulate_on_worker(program, tools, stock, options, observer))
}

/// [`simulate_observed`]'s body, run on a worker of rayon's pool kept awake.
fn simulate_on_worker(
    program: &Program,
    tools: &ToolSet,
    stock: &mut TriDexel,
    options: &SimOptions,
    observer: &dyn Observer,
) -> Result<SimulationReport, StockError> {
    let t0 = Instant::now();
    let stock_volume = stock.volume();
    let area_z = stock.ray_area(2);
    let mut per_move = Vec::with_capacity(program.moves.len());
    let mut rapid_collisions = Vec::new();
    let mut holder_collisions = Vec::new();
    let (mut tested, mut updates) = (0u64, 0u64);
    let (mut five_moves, mut five_subs, mut five_err) = (0usize, 0u64, 0.0f64);
    let file_of = |f: u16| program.files.get(f as usize).cloned().unwrap_or_default();
    let shapes = shapes_of(program, tools);
    let reaches: BTreeMap<u32, Reach> = shapes
        .keys()
        .filter_map(|&t| tools.get(t).map(|c| (t, reach(c))))
        .collect();
    let mut zones = SliverZones::default();
    let total = program.moves.len() as u64;
    let mut next = 0;
    while next < program.moves.len() {
        let i0 = next;
        if i0 > 0 && observer.progress(i0 as u64, total).is_break() {
            return Err(StockError::Cancelled { done: i0 });
        }
        let m0 = &program.moves[i0];
        let tool = shapes.get(&m0.tool).ok_or(StockError::UnknownTool {
            index: i0,
            line: m0.line,
            tool: m0.tool,
        })?;
        // Interval ends this batch (or move) makes remember it: move `i0 + n` has tag
        // `i0 + n` (the last tags saturate at `UNCUT − 1` on absurdly long programs).
        stock.set_move_tag(i0.min(crate::dexel::UNCUT as usize - 1) as u32);
        // A run of straight fixed-axis moves of one tool is cut as one batch (the same stock
        // and per-move figures as move by move, without a parallel barrier per move).
        let run = program.moves[i0..]
            .iter()
            .take(BATCH_MOVES)
            .take_while(|m| m.tool == m0.tool && batchable(program, m))
            .count();
        let cuts = if run > 1 {
            let lin: Vec<LinearMove> = program.moves[i0..i0 + run]
                .iter()
                .map(|m| LinearMove {
                    tip0: m.start.tip,
                    tip1: m.end.tip,
                    axis: m.start.axis.normalize(),
                })
                .collect();
            stock.cut_linear_batch(tool, &lin)
        } else {
            vec![stock.cut_move(program, i0, tool, options.chordal_tolerance)?]
        };
        next = i0 + cuts.len();
        for (i, cut) in (i0..).zip(cuts) {
            let m = &program.moves[i];
            let reach = reaches.get(&m.tool).copied().unwrap_or_default();
            if program.is_five_axis(m) {
                five_moves += 1;
                five_subs += cut.sub_moves;
                five_err = five_err.max(cut.error_bound_mm);
                zones.record(program, i, reach, cut.error_bound_mm);
            }
            let removed =
                (cut.cutting.removed_length[2] + cut.non_cutting.removed_length[2]) * area_z;
            per_move.push(removed);
            tested += cut.cutting.rays_tested + cut.non_cutting.rays_tested;
            updates += cut.cutting.updates + cut.non_cutting.updates;
            if matches!(m.kind, MoveKind::Rapid)
                && zones.collision(program, i, reach, &cut.cutting, true)
            {
                rapid_collisions.push(Collision {
                    move_index: i,
                    file: file_of(m.file),
                    line: m.line,
                    volume_mm3: cut.cutting.removed_length[2] * area_z,
                });
            }
            if zones.collision(program, i, reach, &cut.non_cutting, false) {
                holder_collisions.push(Collision {
                    move_index: i,
                    file: file_of(m.file),
                    line: m.line,
                    volume_mm3: cut.non_cutting.removed_length[2] * area_z,
                });
            }
        }
    }
    let final_volume = stock.volume();
    let st = stock.stats();
    Ok(SimulationReport {
        stock_volume_mm3: stock_volume,
        removed_volume_mm3: stock_volume - final_volume,
        final_volume_mm3: final_volume,
        final_volume_xyz_mm3: stock.volumes(),
        moves: program.moves.len(),
        rays: st.rays,
        intervals: st.intervals,
        bytes_per_interval: st.bytes_per_interval,
        rapid_collisions,
        holder_collisions,
        elapsed_s: t0.elapsed().as_secs_f64(),
        removed_per_move_mm3: per_move,
        rays_tested: tested,
        ray_updates: updates,
        chordal_tolerance_mm: options.chordal_tolerance,
        five_axis_moves: five_moves,
        five_axis_sub_moves: five_subs,
        five_axis_error_bound_mm: five_err,
        resolution_mm: stock.grid().h,
    })
}

/// Whether what a rapid or a holder removed is a collision, after multi-axis moves cut within
/// `error_bound` mm of their sweeps (the largest bound of those whose swept boxes meet this
/// move's: a removal elsewhere cannot be their sliver). Those cuts may leave slivers up to
/// `error_bound` thick along their surfaces, which the next move — often a rapid retract —
/// takes away: that is the approximation's, not the program's. A flat sliver `ε` thick is crossed by a ray of the
/// family closest to its normal (at most 54.7° off it) over at most `√3·ε`, so a removal with
/// some family's longest piece within that is such a sliver; a collision must be deeper in
/// every family that removed anything (a family whose rays miss a shallow cut — X and Y rays
/// above a 0.2 mm skim at h = 0.5 — says nothing of its depth). Without multi-axis moves
/// (`error_bound` 0) any removal over [`COLLISION_EPS_MM`] counts. (A sliver on a small
/// convex radius is crossed longer by every family and may still be reported.)
pub fn collides(st: &CutStats, error_bound: f64) -> bool {
    let sliver = 3f64.sqrt() * error_bound;
    st.removed_any(COLLISION_EPS_MM)
        && (error_bound == 0.0
            || st
                .longest_removal
                .iter()
                .filter(|&&l| l > 0.0)
                .all(|&l| l > sliver))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ops::ControlFlow;
    use std::sync::atomic::{AtomicU64, Ordering};
    use swarf_geom::math::Vec3;
    use swarf_path::load::{read_program_str, ReadOptions};
    use swarf_path::Machine;

    /// A plunge and ten arcs: every arc is cut on its own, so the observer hears of each.
    fn arcs() -> Program {
        let mut text = String::from("G21 G90\nG0 X0 Y10 Z5\nG1 Z-1 F600\n");
        for k in 0..10 {
            let g = if k % 2 == 0 { "G2" } else { "G3" };
            text += &format!("{g} X{} Y10 I2 J0\n", 4 * (k + 1));
        }
        read_program_str(
            &text,
            "arcs.ngc",
            Machine::three_axis(),
            &ReadOptions::default(),
        )
        .unwrap()
    }

    fn stock() -> TriDexel {
        TriDexel::from_box(Vec3::new(-5.0, 0.0, -5.0), Vec3::new(45.0, 20.0, 0.0), 0.5).unwrap()
    }

    #[test]
    fn an_observer_that_breaks_stops_the_run_and_a_quiet_one_changes_nothing() {
        let program = arcs();
        let tools = ToolSet::single(swarf_tool::Cutter::flat(4.0).unwrap());
        let opts = SimOptions::default();
        let moves = program.moves.len() as u64;

        // Counting only: told after every batch, never before the first or after the last.
        let calls = AtomicU64::new(0);
        let count = |done: u64, total: u64| {
            assert!(done > 0 && done < total && total == moves);
            calls.fetch_add(1, Ordering::Relaxed);
            ControlFlow::Continue(())
        };
        let mut observed = stock();
        let a = simulate_observed(&program, &tools, &mut observed, &opts, &count).unwrap();
        // The rapid and the plunge are one batch, then one call per arc but the last.
        assert_eq!(calls.load(Ordering::Relaxed), 10);
        let mut quiet = stock();
        let b = simulate(&program, &tools, &mut quiet, &opts).unwrap();
        assert_eq!(a.removed_per_move_mm3, b.removed_per_move_mm3);
        assert_eq!(a.final_volume_xyz_mm3, b.final_volume_xyz_mm3);
        assert_eq!(a.intervals, b.intervals);
        assert!(b.removed_volume_mm3 > 0.0);

        // Stopped at the first report: one call, nothing after it cut.
        let calls = AtomicU64::new(0);
        let stop = |_: u64, _: u64| {
            calls.fetch_add(1, Ordering::Relaxed);
            ControlFlow::Break(())
        };
        let mut stopped = stock();
        let r = simulate_observed(&program, &tools, &mut stopped, &opts, &stop);
        assert_eq!(r, Err(StockError::Cancelled { done: 2 }));
        assert_eq!(calls.load(Ordering::Relaxed), 1);
        assert!(stopped.volume() > quiet.volume());
    }
}
