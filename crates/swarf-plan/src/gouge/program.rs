//! The check of a whole program: every move cut into fixed-axis sub-moves, every sub-move
//! searched part by part, stretches deeper than the tolerance located by bisection, and every
//! program point checked as a pose; moves in parallel (rayon).

use std::collections::btree_map::Entry;
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use rayon::prelude::*;
use swarf_geom::math::{Vec3, MACHINE_RANGE_MM};
use swarf_geom::progress::{Observer, Quiet};
use swarf_path::{MoveKind, Pose, Program};
use swarf_sweep::five_axis::subdivide;
use swarf_sweep::SubMove;
use swarf_tool::ToolSet;

use super::search::{deepest, Deepest, Pieces, Query, SearchScratch, Segment};
use super::{
    GougeError, GougeOptions, GougeReport, GougeSurface, GougeTool, PointCheck, SurfaceRef,
    ToolPart, Violation, ViolationKind,
};

/// The parts of the cutters `program`'s moves use, each built once from `tools`; a number
/// `tools` has no cutter for is left out.
fn tools_of(program: &Program, tools: &ToolSet) -> BTreeMap<u32, GougeTool> {
    let mut parts = BTreeMap::new();
    for m in &program.moves {
        if let Entry::Vacant(e) = parts.entry(m.tool) {
            if let Some(c) = tools.get(m.tool) {
                e.insert(GougeTool::new(c));
            }
        }
    }
    parts
}

/// [`check_program_observed`] without progress reports.
///
/// # Errors
/// See [`check_program_observed`].
pub fn check_program(
    surface: &GougeSurface,
    program: &Program,
    tools: &ToolSet,
    opts: &GougeOptions,
) -> Result<GougeReport, GougeError> {
    check_program_observed(surface, program, tools, opts, &Quiet)
}

/// Checks every point and move of `program`, each with its tool's cutter from `tools`
/// ([`ToolSet::get`]), against `surface` (see the module docs), telling
/// `observer` `progress(done, moves)` as moves finish (from any thread, in any order). When it
/// answers `Break` no further move is started and the check ends with
/// [`GougeError::Cancelled`].
///
/// # Errors
/// [`GougeError::UnknownTool`] for a move whose tool has no cutter, [`GougeError::BadOption`]
/// for a non-positive tolerance, accuracy, resolution or motion tolerance,
/// [`GougeError::Motion`] when a move cannot be cut into sub-moves, and
/// [`GougeError::Cancelled`] when the observer stopped the check.
pub fn check_program_observed(
    surface: &GougeSurface,
    program: &Program,
    tools: &ToolSet,
    opts: &GougeOptions,
    observer: &dyn Observer,
) -> Result<GougeReport, GougeError> {
    for (name, value) in [
        ("tolerance", opts.tolerance),
        ("accuracy", opts.accuracy),
        ("resolution", opts.resolution),
        ("motion tolerance", opts.motion_tolerance),
    ] {
        if !(value.is_finite() && value > 0.0) {
            return Err(GougeError::BadOption { name, value });
        }
    }
    let travel_mm: f64 = program
        .moves
        .iter()
        .map(|m| match m.kind {
            swarf_path::MoveKind::Arc(g) => g.length(),
            _ => (m.end.tip - m.start.tip).length(),
        })
        // A move that is not finite is refused below, with its line.
        .filter(|l| l.is_finite())
        .sum();
    let pieces = travel_mm / opts.resolution;
    if pieces > super::MAX_LOCATED_PIECES {
        return Err(GougeError::TooFine {
            resolution: opts.resolution,
            travel_mm,
            pieces,
            max: super::MAX_LOCATED_PIECES,
        });
    }
    let tools = tools_of(program, tools);
    for m in &program.moves {
        if !tools.contains_key(&m.tool) {
            return Err(GougeError::UnknownTool {
                tool: m.tool,
                line: m.line,
            });
        }
    }
    let total = program.moves.len();
    let done = AtomicUsize::new(0);
    let stopped = AtomicBool::new(false);
    let outcomes: Vec<Option<Result<MoveOutcome, GougeError>>> = (0..total)
        .into_par_iter()
        .map_init(SearchScratch::default, |scratch, i| {
            if stopped.load(Ordering::Relaxed) {
                return None;
            }
            let r = check_move(surface, program, &tools, opts, i, scratch);
            let n = done.fetch_add(1, Ordering::Relaxed) + 1;
            if observer.progress(n as u64, total as u64).is_break() {
                stopped.store(true, Ordering::Relaxed);
            }
            Some(r)
        })
        .collect();
    if stopped.load(Ordering::Relaxed) {
        return Err(GougeError::Cancelled {
            done: done.load(Ordering::Relaxed),
            total,
        });
    }
    let mut report = GougeReport {
        points: Vec::with_capacity(total + 1),
        violations: Vec::new(),
        sub_moves: 0,
        nodes: 0,
        unresolved: 0,
    };
    // Not stopped: every move was checked (a `None` only follows a stop).
    for (i, o) in outcomes.into_iter().flatten().enumerate() {
        let o = o?;
        if i == 0 {
            if let Some(p) = o.start_point {
                report.points.push(p);
            }
        }
        report.points.push(o.end_point);
        report.violations.extend(o.violations);
        report.sub_moves += o.sub_moves;
        report.nodes += o.nodes;
        report.unresolved += o.unresolved;
    }
    Ok(report)
}

struct MoveOutcome {
    start_point: Option<PointCheck>,
    end_point: PointCheck,
    violations: Vec<Violation>,
    sub_moves: usize,
    nodes: u64,
    unresolved: usize,
}

fn kind_of(part: ToolPart, rapid: bool, check: bool) -> ViolationKind {
    if part == ToolPart::Cutting && !rapid && !check {
        ViolationKind::Gouge
    } else {
        ViolationKind::Interference
    }
}

fn surface_ref(d: &Deepest) -> SurfaceRef {
    if d.check {
        SurfaceRef::Check(d.patch)
    } else {
        SurfaceRef::Patch(d.patch)
    }
}

fn check_move(
    surface: &GougeSurface,
    program: &Program,
    tools: &BTreeMap<u32, GougeTool>,
    opts: &GougeOptions,
    index: usize,
    scratch: &mut SearchScratch,
) -> Result<MoveOutcome, GougeError> {
    let m = &program.moves[index];
    for pose in [m.start, m.end] {
        let sane = |v: Vec3| v.is_finite() && v.abs().max_element() <= MACHINE_RANGE_MM;
        if !(sane(pose.tip) && sane(pose.axis)) {
            return Err(GougeError::BadMove {
                line: m.line,
                end: pose.tip.to_array(),
                range: MACHINE_RANGE_MM,
            });
        }
    }
    let rapid = matches!(m.kind, MoveKind::Rapid);
    let tool = tools.get(&m.tool).ok_or(GougeError::UnknownTool {
        tool: m.tool,
        line: m.line,
    })?;
    let mut out = MoveOutcome {
        start_point: None,
        end_point: check_pose(surface, tool, m.end, rapid, opts, scratch),
        violations: Vec::new(),
        sub_moves: 0,
        nodes: 0,
        unresolved: 0,
    };
    out.end_point.move_index = Some(index);
    out.end_point.file = m.file;
    out.end_point.line = m.line;
    if index == 0 {
        let mut p = check_pose(surface, tool, m.start, rapid, opts, scratch);
        p.file = m.file;
        p.line = m.line;
        out.start_point = Some(p);
    }
    for (part, profile, reach) in tool.parts() {
        let subs = subdivide(program, index, *reach, opts.motion_tolerance)?;
        out.sub_moves += subs.len();
        let segs: Vec<Segment> = subs
            .iter()
            .map(|sub| Segment {
                part: profile,
                tip0: sub.tip0,
                delta: sub.tip1 - sub.tip0,
                axis: sub.axis,
            })
            .collect();
        // The cutting part at a feed move gouges the surface and interferes with the check
        // geometry; everything else interferes with anything.
        let classes: &[(Pieces, ViolationKind)] = if *part == ToolPart::Cutting && !rapid {
            &[
                (Pieces::Surface, ViolationKind::Gouge),
                (Pieces::Check, ViolationKind::Interference),
            ]
        } else {
            &[(Pieces::All, ViolationKind::Interference)]
        };
        for &(pieces, kind) in classes {
            let leaves = scan(surface, &segs, pieces, opts, scratch, &mut out);
            for stretch in stretches(&subs, &leaves) {
                let found = deepest_in(surface, &segs, &stretch, pieces, opts, scratch, &mut out);
                let Some((d, k)) = found else { continue };
                let s_at = |k: usize, t: f64| subs[k].s0 + t * (subs[k].s1 - subs[k].s0);
                let (first, last) = (stretch[0], stretch[stretch.len() - 1]);
                out.violations.push(Violation {
                    move_index: index,
                    file: m.file,
                    line: m.line,
                    kind,
                    part: *part,
                    rapid,
                    s_start: s_at(first.0, first.1),
                    s_end: s_at(last.0, last.2),
                    depth: d.depth,
                    depth_upper: d.upper + subs[k].error_bound,
                    s_deepest: s_at(k, d.t),
                    tip: segs[k].tip0 + d.t * segs[k].delta,
                    axis: segs[k].axis,
                    point: d.point,
                    surface: surface_ref(&d),
                });
            }
        }
    }
    out.violations
        .sort_by(|a, b| a.s_start.total_cmp(&b.s_start));
    Ok(out)
}

/// A stretch `[t0, t1]` of sub-move `k`: `(k, t0, t1)`.
type Span = (usize, f64, f64);

/// The leaves of the bisection of every sub-move (in order) where the part is deeper than the
/// tolerance in `pieces`, each `resolution` of travel or shorter. A search stops at the first
/// point deeper than the tolerance: a leaf only needs to know that it violates.
fn scan(
    surface: &GougeSurface,
    segs: &[Segment],
    pieces: Pieces,
    opts: &GougeOptions,
    scratch: &mut SearchScratch,
    out: &mut MoveOutcome,
) -> Vec<Span> {
    let mut leaves = Vec::new();
    for (k, seg) in segs.iter().enumerate() {
        let mut stack = vec![(0.0, 1.0)];
        // Depth-first, right half pushed first, so the leaves come out in order.
        while let Some((t0, t1)) = stack.pop() {
            let q = Query {
                t0,
                t1,
                pieces,
                floor: opts.tolerance,
                stop_above: opts.tolerance,
                accuracy: opts.accuracy,
                relative_accuracy: opts.relative_accuracy,
                max_nodes: opts.max_nodes,
            };
            let d = deepest(surface, seg, &q, scratch);
            out.nodes += d.nodes;
            out.unresolved += usize::from(!d.certified);
            if d.upper <= opts.tolerance {
                continue;
            }
            if seg.delta.length() * (t1 - t0) > opts.resolution {
                let tm = 0.5 * (t0 + t1);
                stack.push((tm, t1));
                stack.push((t0, tm));
            } else if d.depth > opts.tolerance {
                leaves.push((k, t0, t1));
            }
            // Else the depth is within the accuracy of the tolerance: not reported.
        }
    }
    leaves
}

/// Leaves that touch (within a sub-move, or across the joint of two consecutive ones) joined
/// into stretches.
fn stretches(subs: &[SubMove], leaves: &[Span]) -> Vec<Vec<Span>> {
    let mut out: Vec<Vec<Span>> = Vec::new();
    for &l in leaves {
        let joins = out
            .last()
            .and_then(|s| s.last())
            .is_some_and(|&(k, _, t1)| {
                let same = k == l.0 && t1 == l.1;
                let next = k + 1 == l.0 && t1 == 1.0 && l.1 == 0.0 && subs[k].s1 == subs[l.0].s0;
                same || next
            });
        match out.last_mut() {
            Some(s) if joins => s.push(l),
            _ => out.push(vec![l]),
        }
    }
    out
}

/// The deepest point of a stretch, searched to the full accuracy over each sub-move's part of
/// it, with the sub-move it lies on; `None` when it is within the accuracy of the tolerance.
fn deepest_in(
    surface: &GougeSurface,
    segs: &[Segment],
    stretch: &[Span],
    pieces: Pieces,
    opts: &GougeOptions,
    scratch: &mut SearchScratch,
    out: &mut MoveOutcome,
) -> Option<(Deepest, usize)> {
    let mut best: Option<(Deepest, usize)> = None;
    let mut upper = f64::NEG_INFINITY;
    let mut i = 0;
    while i < stretch.len() {
        let (k, t0, mut t1) = stretch[i];
        while i + 1 < stretch.len() && stretch[i + 1].0 == k {
            i += 1;
            t1 = stretch[i].2;
        }
        i += 1;
        let q = Query {
            t0,
            t1,
            pieces,
            floor: opts.tolerance,
            stop_above: f64::INFINITY,
            accuracy: opts.accuracy,
            relative_accuracy: opts.relative_accuracy,
            max_nodes: opts.max_nodes,
        };
        let d = deepest(surface, &segs[k], &q, scratch);
        out.nodes += d.nodes;
        out.unresolved += usize::from(!d.certified);
        upper = upper.max(d.upper);
        if best.as_ref().map_or(true, |(b, _)| d.depth > b.depth) {
            best = Some((d, k));
        }
    }
    best.map(|(d, k)| (Deepest { upper, ..d }, k))
        .filter(|(d, _)| d.depth > opts.tolerance)
}

/// The depth of every part of `tool` at one pose.
fn check_pose(
    surface: &GougeSurface,
    tool: &GougeTool,
    pose: Pose,
    rapid: bool,
    opts: &GougeOptions,
    scratch: &mut SearchScratch,
) -> PointCheck {
    let axis = pose.axis.normalize();
    let mut best: Option<(Deepest, ToolPart)> = None;
    let mut upper = f64::NEG_INFINITY;
    for (part, profile, _) in tool.parts() {
        let seg = Segment {
            part: profile,
            tip0: pose.tip,
            delta: Vec3::ZERO,
            axis,
        };
        let q = Query {
            t0: 0.0,
            t1: 0.0,
            pieces: Pieces::All,
            relative_accuracy: opts.relative_accuracy,
            floor: opts.tolerance,
            stop_above: f64::INFINITY,
            accuracy: opts.accuracy,
            max_nodes: opts.max_nodes,
        };
        let d = deepest(surface, &seg, &q, scratch);
        upper = upper.max(d.upper);
        if best.as_ref().map_or(true, |(b, _)| d.depth > b.depth) {
            best = Some((d, *part));
        }
    }
    let (d, part) = best.map_or((None, ToolPart::Cutting), |(d, p)| (Some(d), p));
    let depth = d.map_or(f64::NEG_INFINITY, |d| d.depth);
    PointCheck {
        move_index: None,
        file: 0,
        line: 0,
        tip: pose.tip,
        axis,
        depth,
        depth_upper: upper,
        status: d
            .filter(|d| d.depth > opts.tolerance)
            .map(|d| kind_of(part, rapid, d.check)),
        part,
        surface: d.filter(|d| d.depth.is_finite()).map(|d| surface_ref(&d)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ops::ControlFlow;
    use std::sync::atomic::AtomicU64;
    use swarf_path::load::{read_program_str, ReadOptions};
    use swarf_path::Machine;
    use swarf_surface::{CompoundSurface, NurbsSurface, Patch, PreparedSurface, Surface};

    /// The floor `z = 0` over `[0, 100] × [0, 20]`.
    fn floor() -> CompoundSurface {
        let (o, du, dv) = (
            Vec3::ZERO,
            Vec3::new(100.0, 0.0, 0.0),
            Vec3::new(0.0, 20.0, 0.0),
        );
        let pts = vec![vec![o, o + dv], vec![o + du, o + du + dv]];
        let k = vec![0.0, 0.0, 1.0, 1.0];
        let s = NurbsSurface::new(1, 1, k.clone(), k, &pts, None).unwrap();
        CompoundSurface::new(vec![Patch::new(Surface::Nurbs(s))])
    }

    /// Forty moves along the floor, every other one 0.5 mm into it.
    fn program() -> Program {
        let mut text = String::from("G21 G90\nG0 X0 Y10 Z5\nG1 Z0 F600\n");
        for k in 0..40 {
            let z = if k % 2 == 0 { -0.5 } else { 0.0 };
            text += &format!("G1 X{} Z{z}\n", 2 * (k + 1));
        }
        read_program_str(
            &text,
            "floor.ngc",
            Machine::three_axis(),
            &ReadOptions::default(),
        )
        .unwrap()
    }

    #[test]
    fn an_observer_that_breaks_stops_the_check_and_a_quiet_one_changes_nothing() {
        let surface = floor();
        let gs = GougeSurface::new(&PreparedSurface::new(&surface));
        let p = program();
        let tools = ToolSet::single(swarf_tool::Cutter::ball(6.0).unwrap());
        let opts = GougeOptions::DEFAULT;
        let total = p.moves.len();

        let calls = AtomicU64::new(0);
        let count = |done: u64, all: u64| {
            assert!(done >= 1 && done <= all && all == total as u64);
            calls.fetch_add(1, Ordering::Relaxed);
            ControlFlow::Continue(())
        };
        let a = check_program_observed(&gs, &p, &tools, &opts, &count).unwrap();
        assert_eq!(calls.load(Ordering::Relaxed), total as u64);
        let b = check_program(&gs, &p, &tools, &opts).unwrap();
        assert_eq!(a.points, b.points);
        assert_eq!(a.violations, b.violations);
        assert!(!b.violations.is_empty());

        // Stopped at the first report: no further move starts, so only the moves already
        // running on other threads report (at most one per thread).
        let calls = AtomicU64::new(0);
        let stop = |_: u64, _: u64| {
            calls.fetch_add(1, Ordering::Relaxed);
            ControlFlow::Break(())
        };
        let r = check_program_observed(&gs, &p, &tools, &opts, &stop);
        let n = calls.load(Ordering::Relaxed) as usize;
        assert!(n >= 1 && n <= rayon::current_num_threads(), "{n} calls");
        match r {
            Err(GougeError::Cancelled { done, total: t }) => {
                assert_eq!((done, t), (n, total));
            }
            other => panic!("{other:?}"),
        }
    }
}
