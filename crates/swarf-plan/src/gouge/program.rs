//! The check of a whole program: every move cut into fixed-axis sub-moves, every sub-move
//! searched part by part, stretches deeper than the tolerance located by bisection, and every
//! program point checked as a pose; moves in parallel (rayon).

use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;
use swarf_geom::math::Vec3;
use swarf_path::{MoveKind, Pose, Program};
use swarf_stock::five_axis::subdivide;
use swarf_tool::Cutter;

use super::search::{deepest, Deepest, Query, SearchScratch, Segment};
use super::{
    GougeError, GougeOptions, GougeReport, GougeSurface, GougeTool, PointCheck, SurfaceRef,
    ToolPart, Violation, ViolationKind,
};

/// The cutters of a program by tool number, with an optional default for every other number.
#[derive(Clone, Debug, Default)]
pub struct GougeTools {
    default: Option<GougeTool>,
    numbered: Vec<(u32, GougeTool)>,
}

impl GougeTools {
    /// One cutter for every move.
    pub fn single(cutter: &Cutter) -> Self {
        Self {
            default: Some(GougeTool::new(cutter)),
            numbered: Vec::new(),
        }
    }

    /// These tools with `cutter` as tool `n`.
    pub fn with(mut self, n: u32, cutter: &Cutter) -> Self {
        self.numbered.retain(|(k, _)| *k != n);
        self.numbered.push((n, GougeTool::new(cutter)));
        self
    }

    fn get(&self, n: u32) -> Option<&GougeTool> {
        self.numbered
            .iter()
            .find(|(k, _)| *k == n)
            .map(|(_, t)| t)
            .or(self.default.as_ref())
    }
}

/// [`check_program_observed`] without progress reports.
///
/// # Errors
/// See [`check_program_observed`].
pub fn check_program(
    surface: &GougeSurface,
    program: &Program,
    tools: &GougeTools,
    opts: &GougeOptions,
) -> Result<GougeReport, GougeError> {
    check_program_observed(surface, program, tools, opts, &|_, _| {})
}

/// Checks every point and move of `program` against `surface` (see the module docs), calling
/// `progress(done, total)` as moves finish (from any thread).
///
/// # Errors
/// [`GougeError::UnknownTool`] for a move whose tool has no cutter, [`GougeError::BadOption`]
/// for a non-positive tolerance, accuracy, resolution or motion tolerance, and
/// [`GougeError::Motion`] when a move cannot be cut into sub-moves.
pub fn check_program_observed(
    surface: &GougeSurface,
    program: &Program,
    tools: &GougeTools,
    opts: &GougeOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
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
    for m in &program.moves {
        if tools.get(m.tool).is_none() {
            return Err(GougeError::UnknownTool {
                tool: m.tool,
                line: m.line,
            });
        }
    }
    let total = program.moves.len();
    let done = AtomicUsize::new(0);
    let outcomes: Vec<Result<MoveOutcome, GougeError>> = (0..total)
        .into_par_iter()
        .map_init(SearchScratch::default, |scratch, i| {
            let r = check_move(surface, program, tools, opts, i, scratch);
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, total);
            r
        })
        .collect();
    let mut report = GougeReport {
        points: Vec::with_capacity(total + 1),
        violations: Vec::new(),
        sub_moves: 0,
        nodes: 0,
        unresolved: 0,
    };
    for (i, o) in outcomes.into_iter().enumerate() {
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

/// One leaf of the bisection: a stretch `[s0, s1]` of the move deeper than the tolerance.
struct Leaf {
    s0: f64,
    s1: f64,
    kind: ViolationKind,
    found: Deepest,
    s_deepest: f64,
    tip: Vec3,
    axis: Vec3,
    motion_error: f64,
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
    tools: &GougeTools,
    opts: &GougeOptions,
    index: usize,
    scratch: &mut SearchScratch,
) -> Result<MoveOutcome, GougeError> {
    let m = &program.moves[index];
    let rapid = matches!(m.kind, MoveKind::Rapid);
    let tool = tools.get(m.tool).ok_or(GougeError::UnknownTool {
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
        let mut leaves: Vec<Leaf> = Vec::new();
        for sub in &subs {
            let seg = Segment {
                part: profile,
                tip0: sub.tip0,
                delta: sub.tip1 - sub.tip0,
                axis: sub.axis,
            };
            let mut stack = vec![(0.0, 1.0)];
            // Depth-first, right half pushed first, so the leaves come out in order.
            while let Some((t0, t1)) = stack.pop() {
                let travel = seg.delta.length() * (t1 - t0);
                let leaf = travel <= opts.resolution;
                let q = Query {
                    t0,
                    t1,
                    floor: opts.tolerance,
                    stop_above: if leaf { f64::INFINITY } else { opts.tolerance },
                    accuracy: opts.accuracy,
                    max_nodes: opts.max_nodes,
                };
                let d = deepest(surface, &seg, &q, scratch);
                out.nodes += d.nodes;
                if !d.certified {
                    out.unresolved += 1;
                }
                if d.upper <= opts.tolerance {
                    continue;
                }
                if !leaf {
                    let tm = 0.5 * (t0 + t1);
                    stack.push((tm, t1));
                    stack.push((t0, tm));
                    continue;
                }
                if d.depth <= opts.tolerance {
                    continue; // within the accuracy of the tolerance
                }
                let s_at = |t: f64| sub.s0 + t * (sub.s1 - sub.s0);
                leaves.push(Leaf {
                    s0: s_at(t0),
                    s1: s_at(t1),
                    kind: kind_of(*part, rapid, d.check),
                    found: d,
                    s_deepest: s_at(d.t),
                    tip: seg.tip0 + d.t * seg.delta,
                    axis: seg.axis,
                    motion_error: sub.error_bound,
                });
            }
        }
        merge_leaves(
            index,
            m.file,
            m.line,
            *part,
            rapid,
            leaves,
            &mut out.violations,
        );
    }
    out.violations
        .sort_by(|a, b| a.s_start.total_cmp(&b.s_start));
    Ok(out)
}

/// Joins touching leaves of the same kind into violations.
fn merge_leaves(
    index: usize,
    file: u16,
    line: u32,
    part: ToolPart,
    rapid: bool,
    leaves: Vec<Leaf>,
    out: &mut Vec<Violation>,
) {
    let mut cur: Option<Violation> = None;
    for l in leaves {
        let v = Violation {
            move_index: index,
            file,
            line,
            kind: l.kind,
            part,
            rapid,
            s_start: l.s0,
            s_end: l.s1,
            depth: l.found.depth,
            depth_upper: l.found.upper + l.motion_error,
            s_deepest: l.s_deepest,
            tip: l.tip,
            axis: l.axis,
            point: l.found.point,
            surface: surface_ref(&l.found),
        };
        match &mut cur {
            Some(c) if c.kind == v.kind && (v.s_start - c.s_end).abs() <= 1e-12 => {
                c.s_end = v.s_end;
                c.depth_upper = c.depth_upper.max(v.depth_upper);
                if v.depth > c.depth {
                    let (s0, s1, up) = (c.s_start, c.s_end, c.depth_upper);
                    *c = v;
                    (c.s_start, c.s_end, c.depth_upper) = (s0, s1, up);
                }
            }
            _ => {
                if let Some(c) = cur.take() {
                    out.push(c);
                }
                cur = Some(v);
            }
        }
    }
    if let Some(c) = cur {
        out.push(c);
    }
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
            floor: opts.tolerance,
            stop_above: f64::INFINITY,
            accuracy: opts.accuracy,
            max_nodes: opts.max_nodes,
        };
        let d = deepest(surface, &seg, &q, scratch);
        upper = upper.max(d.upper);
        if best.as_ref().is_none_or(|(b, _)| d.depth > b.depth) {
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
