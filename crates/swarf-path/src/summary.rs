//! Program summary: move counts, tip path lengths, the tip's bounding box, tools, warnings and
//! machining time — what `swarf` prints about a program before simulating it.
//!
//! [`ProgramSummary`] serialises to JSON with stable snake_case keys; the CLI prints it, so the
//! keys are a contract.
//!
//! # Accuracy
//! Straight moves and arcs are measured exactly: an arc's bounding box includes its axis-aligned
//! extreme points, found in closed form (and polished by Newton's method on the rare arc whose
//! radius changes from start to end). A move whose tip leaves the straight line or arc between
//! its ends — a non-TCP move with rotary motion, interpolated linearly in joint space — is
//! sampled adaptively until every chord is within [`SummaryOptions::tolerance_mm`] of the curve
//! at its midpoint; its length is the sum of those chords and its bounding box that of the
//! samples, both within the tolerance, which the summary reports as `path_tolerance_mm`.
//!
//! # Machining time
//! Feed moves only (rapids depend on the machine's rapid rates, which swarf does not know), as
//! LinuxCNC plans them: with G94 the feed applies to the joint-space X Y Z length, or to the
//! rotary angle in degrees for a purely rotary move; with G93 a move takes 1/F minutes; with G95
//! the feed per revolution times the spindle speed gives the rate. Moves with no usable feed
//! (F0, or G95 with the spindle stopped) are left out and counted in a note. Dwells are summed
//! apart (`dwell_time_s`).

use std::f64::consts::TAU;

use serde::Serialize;
use swarf_geom::math::Vec3;

use crate::canon::{Canon, CanonSink};
use crate::moves::{ArcGeom, AxisSource, Move, MoveKind, Program};
use crate::{Machine, MoveBuilder, Warning};

/// Default chordal tolerance for curved (joint-interpolated) tip paths, mm.
pub const DEFAULT_PATH_TOLERANCE_MM: f64 = 1e-3;

/// Lengths below this count as zero (zero-length moves), mm.
pub const ZERO_LENGTH_MM: f64 = 1e-9;

/// Deepest subdivision of one curved move piece: 2^20 chords, far below any useful tolerance
/// on a real move.
const MAX_DEPTH: u32 = 20;

/// Most tip evaluations spent on one curved move — a bound on work for degenerate moves (huge
/// or non-finite values); a move that hits it is counted in a note.
const MAX_SAMPLES: usize = 1 << 18;

/// Options of [`summarize_with`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SummaryOptions {
    /// Chordal tolerance for curved tip paths, mm (default [`DEFAULT_PATH_TOLERANCE_MM`]).
    pub tolerance_mm: f64,
}

impl Default for SummaryOptions {
    fn default() -> Self {
        Self {
            tolerance_mm: DEFAULT_PATH_TOLERANCE_MM,
        }
    }
}

impl SummaryOptions {
    /// These options with another chordal tolerance (mm; non-positive values are replaced by
    /// the default).
    pub fn with_tolerance(mut self, tolerance_mm: f64) -> Self {
        self.tolerance_mm = if tolerance_mm > 0.0 {
            tolerance_mm
        } else {
            DEFAULT_PATH_TOLERANCE_MM
        };
        self
    }
}

/// What a program does, in numbers. Keys are stable (CLI contract).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ProgramSummary {
    /// All moves, zero-length ones included.
    pub moves: usize,
    /// Rapid moves.
    pub rapid_moves: usize,
    /// Feed moves: linear and arc.
    pub feed_moves: usize,
    /// Arc (circular and helical) feed moves.
    pub arc_moves: usize,
    /// Moves whose tip and axis do not move (counted in the totals above too).
    pub zero_length_moves: usize,
    /// Tip path length of the feed moves, mm.
    pub feed_length_mm: f64,
    /// Tip path length of the rapid moves, mm.
    pub rapid_length_mm: f64,
    /// Lower corner of the tip's bounding box over all moves, mm (`null` without moves).
    pub bbox_min: Option<[f64; 3]>,
    /// Upper corner of the tip's bounding box over all moves, mm.
    pub bbox_max: Option<[f64; 3]>,
    /// Lower corner of the tip's bounding box over feed moves only, mm.
    pub feed_bbox_min: Option<[f64; 3]>,
    /// Upper corner of the tip's bounding box over feed moves only, mm.
    pub feed_bbox_max: Option<[f64; 3]>,
    /// Tool numbers loaded, in order of first use.
    pub tools: Vec<u32>,
    /// The readers' warnings.
    pub warnings: Vec<Warning>,
    /// Time spent in feed moves, seconds (rapids excluded; see the module documentation).
    pub machining_time_s: f64,
    /// Time spent in dwells (G4, the dwells of canned cycles, APT `DELAY/`, Heidenhain cycle
    /// dwells), seconds: the spindle turns, the tool stands. Not in `machining_time_s`.
    pub dwell_time_s: f64,
    /// Remarks on how the numbers were obtained (moves left out of the time, sampled paths).
    pub notes: Vec<String>,
    /// Chordal tolerance used for curved tip paths, mm.
    pub path_tolerance_mm: f64,
    /// The machine whose kinematics produced the poses.
    pub machine: String,
    /// Where the tool axis comes from at the program's end: `machine` (G-code) or `program`
    /// (CL data, or G-code after a tilted plane's G53.1 not yet handed back).
    pub axis_source: AxisSource,
}

/// An axis-aligned box, grown point by point.
#[derive(Clone, Copy, Debug)]
struct Bbox {
    min: Vec3,
    max: Vec3,
}

impl Bbox {
    fn empty() -> Self {
        Self {
            min: Vec3::splat(f64::INFINITY),
            max: Vec3::splat(f64::NEG_INFINITY),
        }
    }
    fn add(&mut self, p: Vec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }
    fn corners(&self) -> (Option<[f64; 3]>, Option<[f64; 3]>) {
        if self.min.x <= self.max.x {
            (Some(self.min.to_array()), Some(self.max.to_array()))
        } else {
            (None, None)
        }
    }
}

/// Summarises a program with the default options.
pub fn summarize(program: &Program) -> ProgramSummary {
    summarize_with(program, &SummaryOptions::default())
}

/// Summarises a program.
pub fn summarize_with(program: &Program, options: &SummaryOptions) -> ProgramSummary {
    let mut acc = SummaryAccumulator::new(options);
    for m in &program.moves {
        acc.add(program, m);
    }
    acc.finish(program)
}

/// The summary's sums, move by move: [`summarize_with`] over a program's moves, or
/// [`SummarySink`] over moves as a reader makes them (memory independent of the program's
/// length).
#[derive(Clone, Debug)]
pub struct SummaryAccumulator {
    tol: f64,
    moves: usize,
    rapid_moves: usize,
    feed_moves: usize,
    arc_moves: usize,
    zero_length_moves: usize,
    feed_length_mm: f64,
    rapid_length_mm: f64,
    all: Bbox,
    feed: Bbox,
    no_feed: usize,
    curved: Curved,
    minutes: f64,
}

impl SummaryAccumulator {
    /// No moves yet.
    pub fn new(options: &SummaryOptions) -> Self {
        Self {
            tol: options.tolerance_mm,
            moves: 0,
            rapid_moves: 0,
            feed_moves: 0,
            arc_moves: 0,
            zero_length_moves: 0,
            feed_length_mm: 0.0,
            rapid_length_mm: 0.0,
            all: Bbox::empty(),
            feed: Bbox::empty(),
            no_feed: 0,
            curved: Curved::default(),
            minutes: 0.0,
        }
    }

    /// Adds move `m`; `program` gives the machine and the axis source it is interpolated by
    /// (its moves are not read). Returns the box of the tip's path over it, (min, max).
    pub fn add(&mut self, program: &Program, m: &Move) -> (Vec3, Vec3) {
        let mut bb = Bbox::empty();
        let length = move_extent(program, m, self.tol, &mut bb, &mut self.curved);
        self.moves += 1;
        self.all.add(bb.min);
        self.all.add(bb.max);
        let zero = is_zero_length(m);
        self.zero_length_moves += usize::from(zero);
        match m.kind {
            MoveKind::Rapid => {
                self.rapid_moves += 1;
                self.rapid_length_mm += length;
            }
            MoveKind::Linear | MoveKind::Arc(_) => {
                self.feed_moves += 1;
                self.arc_moves += usize::from(matches!(m.kind, MoveKind::Arc(_)));
                self.feed_length_mm += length;
                self.feed.add(bb.min);
                self.feed.add(bb.max);
                if !zero {
                    match m.feed_minutes(length) {
                        Some(t) => self.minutes += t,
                        None => self.no_feed += 1,
                    }
                }
            }
        }
        (bb.min, bb.max)
    }

    /// The summary of the moves added; tools, warnings, machine and axis source from `program`
    /// (its moves are not read).
    pub fn finish(self, program: &Program) -> ProgramSummary {
        let tol = self.tol;
        let (bbox_min, bbox_max) = self.all.corners();
        let (feed_bbox_min, feed_bbox_max) = self.feed.corners();
        let mut notes = Vec::new();
        if self.no_feed > 0 {
            notes.push(format!(
                "{} feed move(s) without a usable feed rate (F0, or feed per revolution with \
                 the spindle stopped) are left out of machining_time_s",
                self.no_feed
            ));
        }
        if self.curved.moves > 0 {
            notes.push(format!(
                "{} move(s) with rotary motion follow a curved tip path: length and bounding box \
                 sampled to {tol} mm",
                self.curved.moves
            ));
        }
        if self.curved.unconverged > 0 {
            notes.push(format!(
                "{} curved move(s) did not reach the {tol} mm tolerance within {MAX_SAMPLES} \
                 samples",
                self.curved.unconverged
            ));
        }
        ProgramSummary {
            moves: self.moves,
            rapid_moves: self.rapid_moves,
            feed_moves: self.feed_moves,
            arc_moves: self.arc_moves,
            zero_length_moves: self.zero_length_moves,
            feed_length_mm: self.feed_length_mm,
            rapid_length_mm: self.rapid_length_mm,
            bbox_min,
            bbox_max,
            feed_bbox_min,
            feed_bbox_max,
            tools: program.tools.clone(),
            warnings: program.warnings.clone(),
            machining_time_s: self.minutes * 60.0,
            dwell_time_s: program.dwell_s,
            notes,
            path_tolerance_mm: tol,
            machine: program.machine.name.clone(),
            axis_source: program.axis_source,
        }
    }
}

/// A [`CanonSink`] that summarises a program as it is read, keeping no moves: a
/// [`MoveBuilder`] whose moves are summed and dropped after every event. Memory does not grow
/// with the program's length (only with its warnings), so a reader feeding it needs no move
/// limit ([`crate::limit`]).
///
/// Its summary equals [`summarize_with`]'s of the program read whole: each move carries where
/// its tool axis comes from ([`Move::axis_source`](crate::Move)).
#[derive(Debug)]
pub struct SummarySink {
    builder: MoveBuilder,
    context: Program,
    acc: SummaryAccumulator,
    by_tool: std::collections::BTreeMap<u32, Bbox>,
}

/// What [`SummarySink::finish`] returns.
#[derive(Debug)]
pub struct StreamedSummary {
    /// The summary.
    pub summary: ProgramSummary,
    /// The program without its moves: files, tools, cutter definitions, warnings, machine.
    pub program: Program,
    /// A move was made with no tool loaded (tool 0).
    pub tool_zero_moved: bool,
    /// The box of the tool tip's path over each tool's feed moves, (min, max), by tool number.
    pub feed_tip_bounds_by_tool: std::collections::BTreeMap<u32, (Vec3, Vec3)>,
}

impl SummarySink {
    /// A summary of the program read from `file_name` on `machine`.
    pub fn new(machine: Machine, file_name: &str, options: &SummaryOptions) -> Self {
        Self {
            context: Program {
                machine: machine.clone(),
                ..Program::default()
            },
            builder: MoveBuilder::new(machine, file_name),
            acc: SummaryAccumulator::new(options),
            by_tool: std::collections::BTreeMap::new(),
        }
    }

    /// The summary of what was read.
    pub fn finish(mut self) -> StreamedSummary {
        self.drain();
        let tool_zero_moved = self.builder.tool_zero_moved();
        let program = self.builder.finish();
        StreamedSummary {
            summary: self.acc.finish(&program),
            program,
            tool_zero_moved,
            feed_tip_bounds_by_tool: self
                .by_tool
                .into_iter()
                .map(|(t, b)| (t, (b.min, b.max)))
                .collect(),
        }
    }

    fn drain(&mut self) {
        self.context.axis_source = self.builder.context().1;
        for m in self.builder.take_moves() {
            let (lo, hi) = self.acc.add(&self.context, &m);
            if !matches!(m.kind, MoveKind::Rapid) {
                let b = self.by_tool.entry(m.tool).or_insert_with(Bbox::empty);
                b.add(lo);
                b.add(hi);
            }
        }
    }
}

impl CanonSink for SummarySink {
    fn emit(&mut self, line: u32, event: &Canon<'_>) {
        self.builder.emit(line, event);
        self.drain();
    }
    fn warn(&mut self, warning: Warning) {
        self.builder.warn(warning);
    }
    fn position(&self) -> Option<crate::Axes> {
        self.builder.position()
    }
}

/// True when neither the tip nor the joints move.
fn is_zero_length(m: &Move) -> bool {
    let (a, b) = (m.start_joints.to_array(), m.end_joints.to_array());
    let joints_still = a
        .iter()
        .zip(&b)
        .all(|(x, y)| (x - y).abs() <= ZERO_LENGTH_MM);
    let arc_turns = matches!(m.kind, MoveKind::Arc(g) if g.length() > ZERO_LENGTH_MM);
    joints_still
        && !arc_turns
        && (m.start.tip - m.end.tip).length() <= ZERO_LENGTH_MM
        && (m.start.axis - m.end.axis).length() <= ZERO_LENGTH_MM
}

/// Counts of curved moves, and of those whose sampling ran out of budget.
#[derive(Clone, Copy, Debug, Default)]
struct Curved {
    moves: usize,
    unconverged: usize,
}

/// The box of the tool tip's path over move `m` (arcs by their extreme points, curved
/// multi-axis paths sampled within the default tolerance), as (min, max).
pub fn move_tip_bounds(program: &Program, m: &Move) -> (Vec3, Vec3) {
    let mut bb = Bbox::empty();
    let mut curved = Curved::default();
    move_extent(program, m, DEFAULT_PATH_TOLERANCE_MM, &mut bb, &mut curved);
    (bb.min, bb.max)
}

/// Tip path length of `m`, growing `bb` by the tip's path.
fn move_extent(program: &Program, m: &Move, tol: f64, bb: &mut Bbox, curved: &mut Curved) -> f64 {
    bb.add(m.start.tip);
    bb.add(m.end.tip);
    if program.tip_path_is_curved(m) {
        curved.moves += 1;
        let (length, converged) = Sampler {
            program,
            m,
            tol,
            budget: MAX_SAMPLES,
        }
        .run(bb);
        curved.unconverged += usize::from(!converged);
        return length;
    }
    match m.kind {
        MoveKind::Arc(g) => {
            arc_extremes(&g, m.start.tip, bb);
            g.length()
        }
        MoveKind::Rapid | MoveKind::Linear => (m.end.tip - m.start.tip).length(),
    }
}

/// How far (radians, and in `|ratio|` past 1) a spiral's critical points are looked for beyond
/// those of its mean circle: the phase shift is about `atan(ρ'/ρ)`, far below this for any arc a
/// program describes.
const SPIRAL_SLACK: f64 = 0.1;

/// Adds the arc's axis-aligned extreme points to `bb`.
fn arc_extremes(g: &ArcGeom, start: Vec3, bb: &mut Bbox) {
    if g.sweep <= 0.0 {
        return;
    }
    let (u, v, _) = g.start_frame(start);
    let r_mean = 0.5 * (g.start_radius + g.end_radius);
    let dr = (g.end_radius - g.start_radius) / g.sweep;
    let dh = g.helix / g.sweep;
    for k in 0..3 {
        let (uk, vk, nk) = (u[k], v[k], g.normal[k]);
        // x_k(θ) = ρ(θ)(u_k cos θ + v_k sin θ) + n_k h(θ) + const, with ρ and h linear in θ.
        let d1 = |t: f64| {
            let rho = g.start_radius + dr * t;
            let (s, c) = t.sin_cos();
            dr * (uk * c + vk * s) + rho * (vk * c - uk * s) + nk * dh
        };
        let d2 = |t: f64| {
            let rho = g.start_radius + dr * t;
            let (s, c) = t.sin_cos();
            2.0 * dr * (vk * c - uk * s) - rho * (uk * c + vk * s)
        };
        // Constant-radius critical points, closed form: r(v_k cos θ − u_k sin θ) = −n_k h' is
        // R cos(θ + φ) = −m with R = r·|(u_k, v_k)|, φ = atan2(u_k, v_k).
        let amp = r_mean * uk.hypot(vk);
        if amp <= 1e-300 {
            continue;
        }
        let ratio = -(nk * dh) / amp;
        // A spiral's critical phases differ a little from the mean circle's: keep the nearly
        // tangent case (|ratio| a little above 1) for the polish to settle.
        let spiral = dr != 0.0;
        let ratio = if spiral && ratio.abs() <= 1.0 + SPIRAL_SLACK {
            ratio.clamp(-1.0, 1.0)
        } else if ratio.abs() > 1.0 {
            continue;
        } else {
            ratio
        };
        let phi = uk.atan2(vk);
        let acos = ratio.acos();
        // Each critical phase recurs once per turn, its value changing linearly (helix) or
        // nearly so (spiral) from turn to turn: the extreme of a multi-turn arc is on its first
        // or last turn, so those are the only ones visited.
        let ranges = if g.sweep <= 2.0 * TAU {
            [(0.0, g.sweep), (1.0, 0.0)]
        } else {
            [(0.0, TAU), (g.sweep - TAU, g.sweep)]
        };
        // Likewise a spiral's critical point may lie inside the arc while the circle's lies
        // just outside it: candidates a little beyond the ends are polished, then kept if inside.
        let reach = if spiral { SPIRAL_SLACK } else { 0.0 };
        for base in [acos - phi, -acos - phi] {
            for (lo, hi) in ranges {
                let j0 = ((lo - reach - base) / TAU).ceil() as i64;
                let j1 = ((hi + reach - base) / TAU).floor() as i64;
                for j in j0..=j1 {
                    let mut t = base + TAU * j as f64;
                    if spiral {
                        // A spiral: polish on the exact derivative.
                        for _ in 0..8 {
                            let h = d2(t);
                            if h.abs() < 1e-300 {
                                break;
                            }
                            t -= d1(t) / h;
                        }
                    }
                    if (0.0..=g.sweep).contains(&t) {
                        bb.add(g.point_at(start, t / g.sweep));
                    }
                }
            }
        }
    }
}

/// Adaptive sampling of one curved move.
struct Sampler<'p> {
    program: &'p Program,
    m: &'p Move,
    tol: f64,
    /// Evaluations left before giving up on the tolerance.
    budget: usize,
}

impl Sampler<'_> {
    /// Chord length of the move, with every sample added to `bb`, and whether the tolerance
    /// was reached within the budget (if not, the chords found so far are summed).
    fn run(&mut self, bb: &mut Bbox) -> (f64, bool) {
        // Start from pieces of at most 5° of rotary motion so that an S-shaped piece cannot
        // hide behind a midpoint that happens to lie on its chord.
        let (a, b) = (self.m.start_joints, self.m.end_joints);
        let turn = (a.a - b.a)
            .abs()
            .max((a.b - b.b).abs())
            .max((a.c - b.c).abs());
        let pieces = if turn.is_finite() {
            ((turn / 5.0).ceil() as usize).clamp(2, 1 << 12)
        } else {
            2
        };
        let mut length = 0.0;
        let mut prev = self.program.pose_at(self.m, 0.0).tip;
        for i in 1..=pieces {
            let s0 = (i - 1) as f64 / pieces as f64;
            let s1 = i as f64 / pieces as f64;
            let p1 = self.program.pose_at(self.m, s1).tip;
            length += self.refine((s0, prev), (s1, p1), bb, 0);
            bb.add(p1);
            prev = p1;
        }
        (length, self.budget > 0)
    }

    fn refine(
        &mut self,
        (s0, p0): (f64, Vec3),
        (s1, p1): (f64, Vec3),
        bb: &mut Bbox,
        depth: u32,
    ) -> f64 {
        let sm = 0.5 * (s0 + s1);
        let pm = self.program.pose_at(self.m, sm).tip;
        bb.add(pm);
        self.budget = self.budget.saturating_sub(1);
        let deviation = (pm - 0.5 * (p0 + p1)).length();
        // A NaN deviation also stops: no subdivision would cure it.
        let within = deviation.partial_cmp(&self.tol) != Some(std::cmp::Ordering::Greater);
        let done = depth >= MAX_DEPTH || self.budget == 0 || within;
        if done {
            return (pm - p0).length() + (p1 - pm).length();
        }
        self.refine((s0, p0), (sm, pm), bb, depth + 1)
            + self.refine((sm, pm), (s1, p1), bb, depth + 1)
    }
}
