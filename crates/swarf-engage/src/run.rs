//! Engagement along a program: cutter locations, the stock cut up to each, the engagement at
//! each — an iterator the force model consumes without files.

use std::collections::{BTreeMap, VecDeque};
use std::time::Instant;

use rayon::prelude::*;

use swarf_geom::math::{lesser, Vec3};
use swarf_geom::progress::{Observer, Quiet};
use swarf_geom::Aabb;
use swarf_path::{Move, MoveKind, Program};
use swarf_stock::{
    Collision, ColumnTops, StockError, TriDexel, DEFAULT_CHORDAL_TOLERANCE_MM, TILE,
};
use swarf_sweep::MotionState;
use swarf_sweep::ToolShape;
use swarf_tool::{Cutter, ToolSet};

use crate::engagement::{integrate, Engagement, StripResult, StripSamples};
use crate::probe::MaterialProbe;
use crate::sides;
use crate::strip::{Circle, Strip};

/// Default spacing of cutter locations along a move, mm of tool-tip travel.
pub const DEFAULT_STEP_MM: f64 = 1.0;
/// Default height of the axial discs (and width of the bottom rings), mm.
pub const DEFAULT_DZ_MM: f64 = 0.1;
/// Default immersion-angle sampling, degrees.
pub const DEFAULT_DPHI_DEG: f64 = 1.0;
/// `f = N·V/|V|` at or below this is not pushing into the material (grazing or backward).
pub const FEASIBLE_EPS: f64 = 1e-9;
/// Default [`EngageOptions::lag_mm`], mm of tool-tip travel.
pub const DEFAULT_LAG_MM: f64 = 0.5;

/// Engagement options; accuracy parameters with their defaults in one place.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct EngageOptions {
    /// Cutter locations every `step_mm` of tool-tip travel along a feed move, and at its end;
    /// 0: at move ends only.
    pub step_mm: f64,
    /// Height of the axial discs (and width of the bottom rings), mm.
    pub dz_mm: f64,
    /// Immersion-angle sampling, degrees (rounded so that a whole number of steps makes 360°).
    pub dphi_deg: f64,
    /// Chordal tolerance of arcs and 5-axis moves when cutting the stock, mm.
    pub chordal_tolerance_mm: f64,
    /// The stock a location is taken against is cut up to the location before, or up to this
    /// far back along the path (mm of tool-tip travel) where that is nearer: a point of the cutter's front
    /// lies in that stock by the travel times `f` — the chip a location sees — and a chip
    /// thinner than the stock's uncertainty (the chordal tolerance and `h²/8R`, ≈ 1.25 µm) is
    /// taken for a rub (a location 0.01 mm after the one before read a slot's entry 6° late
    /// and its area 7 % short). Material the motion since then removed lies behind the front
    /// surface, so the engaged region is that of the instant — but for a path curving tighter
    /// than the tool's radius, whose recent poses cover points beside the front (a helix inside
    /// the tool's radius: its entry angle is set by the drop since that stock's cut), so this is
    /// short: at 0.5 mm a chip is missed within 0.14° of where the front starts.
    pub lag_mm: f64,
    /// Probe every feasible sample, instead of guessing the side of those away from the
    /// boundary from their nearest ray (the same results except around features narrower
    /// than the ray spacing; this is the reference the fast path is tested against).
    pub exhaustive: bool,
}

impl Default for EngageOptions {
    fn default() -> Self {
        Self {
            step_mm: DEFAULT_STEP_MM,
            dz_mm: DEFAULT_DZ_MM,
            dphi_deg: DEFAULT_DPHI_DEG,
            chordal_tolerance_mm: DEFAULT_CHORDAL_TOLERANCE_MM,
            lag_mm: DEFAULT_LAG_MM,
            exhaustive: false,
        }
    }
}

impl EngageOptions {
    /// With another location spacing.
    pub fn with_step(mut self, step_mm: f64) -> Self {
        self.step_mm = step_mm;
        self
    }
    /// With another disc height.
    pub fn with_dz(mut self, dz_mm: f64) -> Self {
        self.dz_mm = dz_mm;
        self
    }
    /// With another angular sampling.
    pub fn with_dphi(mut self, dphi_deg: f64) -> Self {
        self.dphi_deg = dphi_deg;
        self
    }
    /// With another chordal tolerance.
    pub fn with_chordal_tolerance(mut self, tol: f64) -> Self {
        self.chordal_tolerance_mm = tol;
        self
    }
    /// With another lag (see [`EngageOptions::lag_mm`]).
    pub fn with_lag(mut self, lag_mm: f64) -> Self {
        self.lag_mm = lag_mm;
        self
    }
    /// Probing every sample (see [`EngageOptions::exhaustive`]).
    pub fn with_exhaustive(mut self, exhaustive: bool) -> Self {
        self.exhaustive = exhaustive;
        self
    }

    /// Whether every option is in range ([`Engager::new`] checks too; a caller that does other
    /// work with the options first — a force model's edges at the discs' height — checks
    /// before it).
    ///
    /// # Errors
    /// The first option out of range.
    pub fn check(&self) -> Result<(), EngageError> {
        let bad = |name: &'static str, value: f64, want: &'static str| {
            Err(EngageError::BadOption { name, value, want })
        };
        if !(self.step_mm.is_finite() && self.step_mm >= 0.0) {
            return bad("step", self.step_mm, "a non-negative number of mm");
        }
        // Discs coarser than a millimetre misplace the engaged height by their size (a 5 mm
        // slot read 6.5 mm deep at 3 mm discs, nothing at 100), and forces and feeds with it.
        if !(self.dz_mm.is_finite() && self.dz_mm > 1e-4 && self.dz_mm <= 1.0) {
            return bad("dz", self.dz_mm, "a number of mm above 0.0001, at most 1");
        }
        if !(self.dphi_deg.is_finite() && self.dphi_deg >= 0.01 && self.dphi_deg <= 30.0) {
            return bad("dphi", self.dphi_deg, "between 0.01 and 30 degrees");
        }
        if !(self.lag_mm.is_finite() && self.lag_mm > 0.0 && self.lag_mm <= 1e3) {
            return bad("lag", self.lag_mm, "a positive number of mm, at most 1000");
        }
        if !(self.chordal_tolerance_mm.is_finite() && self.chordal_tolerance_mm > 0.0) {
            return bad(
                "tolerance",
                self.chordal_tolerance_mm,
                "a positive number of mm",
            );
        }
        Ok(())
    }
}

/// Why an engagement run stopped.
#[derive(Debug, thiserror::Error)]
pub enum EngageError {
    /// The observer ([`Engager::observed`]) stopped the run after `locations` cutter
    /// locations.
    #[error("stopped after {locations} cutter locations")]
    Cancelled {
        /// Cutter locations handed out before the stop.
        locations: usize,
    },
    /// An option out of range.
    #[error("--{name} must be {want}, got {value}")]
    BadOption {
        /// Option name.
        name: &'static str,
        /// Value given.
        value: f64,
        /// What it must be.
        want: &'static str,
    },
    /// A move uses a tool nothing defines.
    #[error("{file}:{line}: move {index} uses tool {tool}, which nothing defines")]
    UnknownTool {
        /// Source file.
        file: String,
        /// Source line.
        line: u32,
        /// Move index.
        index: usize,
        /// Tool number.
        tool: u32,
    },
    /// A move would have more cutter locations than [`MAX_LOCATIONS_PER_MOVE`].
    #[error("{file}:{line}: --step {step} mm gives {locations} cutter locations on this move, more than {max}; give a larger --step", max = MAX_LOCATIONS_PER_MOVE)]
    TooManyLocations {
        /// Source file.
        file: String,
        /// Source line.
        line: u32,
        /// Locations the move would have.
        locations: f64,
        /// The step asked for, mm.
        step: f64,
    },
    /// The discs and angles would sample a cutter more finely than [`MAX_SAMPLES_PER_LOCATION`].
    #[error("--dz {dz} mm and --dphi {dphi}° sample {what} at {circles} circles × {angles} angles, more than {max} samples a location; give a larger --dz or --dphi", max = MAX_SAMPLES_PER_LOCATION)]
    TooManySamples {
        /// Which cutter, in words.
        what: String,
        /// Circles of its strips.
        circles: usize,
        /// Angles per circle.
        angles: usize,
        /// The options asked for.
        dz: f64,
        /// The options asked for.
        dphi: f64,
    },
    /// Cutting the stock failed (non-finite pose, a 5-axis move beyond the sub-move limit).
    #[error(transparent)]
    Stock(#[from] StockError),
}

/// A cutter prepared for engagement: its sweep shapes and its surface strips.
#[derive(Clone, Debug)]
struct Prepared {
    shape: ToolShape,
    /// How far the tool reaches from its tip (the collisions' sliver zones).
    reach: swarf_stock::Reach,
    side: Option<Strip>,
    bottom: Option<Strip>,
    radius: f64,
    /// Height above the tip of the highest sampled circle, mm.
    height: f64,
}

impl Prepared {
    fn new(cutter: &Cutter, opts: &EngageOptions) -> Self {
        let (side, bottom) = (
            Strip::side(cutter, opts.dz_mm),
            Strip::bottom(cutter, opts.dz_mm),
        );
        let top = side
            .iter()
            .chain(&bottom)
            .flat_map(|s| &s.circles)
            .map(|c| c.z)
            .fold(cutter.apt_params().h, f64::max);
        Self {
            shape: ToolShape::new(cutter),
            reach: swarf_stock::reach(cutter),
            radius: 0.5 * cutter.max_diameter(),
            height: top,
            side,
            bottom,
        }
    }
}

/// The prepared cutters by tool number, and the one for every other number.
#[derive(Clone, Debug, Default)]
struct PreparedTools {
    by_number: BTreeMap<u32, Prepared>,
    fallback: Option<Prepared>,
}

impl PreparedTools {
    /// The cutter of move `index`.
    fn of(&self, program: &Program, index: usize) -> Result<&Prepared, EngageError> {
        let m = &program.moves[index];
        self.by_number
            .get(&m.tool)
            .or(self.fallback.as_ref())
            .ok_or_else(|| EngageError::UnknownTool {
                file: file_of(program, m),
                line: m.line,
                index,
                tool: m.tool,
            })
    }
}

/// A feed move being walked: its index, tip path length, the spacing and number of its
/// locations, and how many of them are done.
#[derive(Clone, Copy, Debug)]
struct Walk {
    index: usize,
    length: f64,
    step: f64,
    count: usize,
    done: usize,
}

impl Walk {
    /// The move parameter of location `i` (the last is the move's end).
    fn s(&self, i: usize) -> f64 {
        if i + 1 >= self.count {
            1.0
        } else {
            (i + 1) as f64 * self.step / self.length
        }
    }
}

/// Most cutter locations one move may have (a `step` far below the move's length would
/// otherwise run for days).
pub const MAX_LOCATIONS_PER_MOVE: usize = 1_000_000;

/// Most samples (circles × angles) one cutter location may take: each keeps a few words of
/// working memory, so this bounds it at a few hundred MB (the defaults take ≈ 10⁵ for a 10 mm
/// cutter).
pub const MAX_SAMPLES_PER_LOCATION: usize = 10_000_000;

/// The source file name of `m`.
fn file_of(program: &Program, m: &Move) -> String {
    program
        .files
        .get(usize::from(m.file))
        .cloned()
        .unwrap_or_default()
}

/// Figures of a run so far.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct EngageStats {
    /// Cutter locations produced.
    pub locations: usize,
    /// Of those, engaged ones.
    pub engaged_locations: usize,
    /// Volume removed by the program so far (rapids included), mm³.
    pub removed_volume_mm3: f64,
    /// Time spent cutting the stock, s.
    pub simulate_elapsed_s: f64,
    /// Surface points whose side was measured / voted (see [`MaterialProbe`]).
    pub probes: u64,
}

/// The sampled angles `j·dφ` of a run.
#[derive(Clone, Debug)]
struct Angles {
    dphi_deg: f64,
    sin: Vec<f64>,
    cos: Vec<f64>,
}

impl Angles {
    fn new(dphi_deg: f64) -> Self {
        let n = (360.0 / dphi_deg).round().max(12.0) as usize;
        let d = 360.0 / n as f64;
        let (sin, cos) = (0..n)
            .map(|j| (j as f64 * d).to_radians().sin_cos())
            .unzip();
        Self {
            dphi_deg: d,
            sin,
            cos,
        }
    }
}

/// The engagement at every cutter location of a program, in order: an iterator of
/// [`Engagement`]s that cuts the stock as it goes (the stock ends as `swarf_stock::simulate`
/// leaves it).
///
/// For each feed move the locations lie every [`EngageOptions::step_mm`] of tool-tip travel
/// and at its end. The engagement at a location is taken against the stock with the program
/// cut up to the location before, or up to [`EngageOptions::lag_mm`] back along the path where
/// that is nearer: the motion since then only removes
/// material behind the cutter's forward surface, so this is the stock "at that instant" on
/// the surface that can touch it, and the material there is still whole around the surface
/// (its boundary is not the surface itself). The cuts run in the program's order, a piece per
/// location (and per rapid) — in two where the lag falls inside it — so the stock and each
/// location's removed volume are those of cutting location after location; a location is
/// handed out once its piece is cut.
pub struct Engager<'a> {
    program: &'a Program,
    stock: &'a mut TriDexel,
    opts: EngageOptions,
    tools: PreparedTools,
    angles: Angles,
    next_move: usize,
    /// The feed move being walked.
    current: Option<Walk>,
    last_x: Option<Vec3>,
    stats: EngageStats,
    failed: bool,
    observer: &'a dyn Observer,
    /// Sample buffers kept from one location to the next (no allocation per location).
    scratch: Scratch,
    /// Rapids whose cutting part entered the material, and moves whose shank or holder did,
    /// as `swarf_stock::simulate` reports them.
    rapid_collisions: Vec<Collision>,
    holder_collisions: Vec<Collision>,
    /// Where the multi-axis cuts so far may have left slivers (collisions judged as the
    /// simulation judges them).
    zones: swarf_stock::SliverZones,
    /// Tool-tip travel along the program so far (feed moves and rapids), mm.
    travel: f64,
    /// The pieces of the path walked but not cut yet (the last `lag_mm` of travel), in order.
    pending: VecDeque<Piece>,
    /// Locations whose piece is cut, to hand out in order.
    ready: VecDeque<Engagement>,
    /// Locations computed so far (the next one's number).
    computed: usize,
}

/// A piece of the path walked and not cut yet: `[s0, s1]` of move `index`, from `start` to
/// `end` mm of travel into the program, and the location at its end with the parameter of the
/// location before (`None`: a rapid's), whose removed volume is the piece's — `removed` of it
/// cut already, where the piece was cut in part.
struct Piece {
    index: usize,
    s0: f64,
    s1: f64,
    start: f64,
    end: f64,
    /// The move's tip path length, mm (for the removal rate).
    length: f64,
    removed: f64,
    location: Option<(Engagement, f64)>,
}

/// The per-sample buffers of [`sample_strip`], reused.
#[derive(Default)]
struct Scratch {
    rf: Vec<f64>,
    g: Vec<f64>,
    /// Each sample's side (1: engaged), for the integration.
    side: Vec<u8>,
    /// The same packed (`sides.rs`), for pass 3; and where a feasible sample is not probed
    /// yet (its side a guess).
    side_bits: Vec<u64>,
    open_bits: Vec<u64>,
    /// Pass 3's rows to look at, samples to probe and their probed values.
    scan: Vec<bool>,
    todo: Vec<usize>,
    values: Vec<f64>,
    /// The stock's column map about the cutter (refilled at each location with a vertical
    /// tool axis); its readings for the bands of a strip's circles, each row's band, and a row
    /// of +∞ (no claim) for rows without one (`sample_strip`).
    tops: ColumnTops,
    mapped_tops: Vec<f64>,
    band_of: Vec<u32>,
    no_claim: Vec<f64>,
}

impl<'a> Engager<'a> {
    /// A run of `program` on `stock` with the cutters of `tools`.
    ///
    /// # Errors
    /// Options out of range.
    pub fn new(
        program: &'a Program,
        tools: &ToolSet,
        stock: &'a mut TriDexel,
        opts: EngageOptions,
    ) -> Result<Self, EngageError> {
        opts.check()?;
        let mut by_number = BTreeMap::new();
        let mut used: Vec<u32> = program.tools.clone();
        used.extend(program.moves.iter().map(|m| m.tool));
        used.sort_unstable();
        used.dedup();
        for n in used {
            if let Some(c) = tools.resolved().get(&n) {
                by_number.insert(n, Prepared::new(&c.cutter, &opts));
            }
        }
        let tools = PreparedTools {
            by_number,
            fallback: tools.fallback().map(|c| Prepared::new(c, &opts)),
        };
        let angles = Angles::new(opts.dphi_deg);
        let named = tools
            .by_number
            .iter()
            .map(|(n, p)| (format!("tool {n}"), p));
        for (what, p) in named.chain(tools.fallback.iter().map(|p| ("the cutter".into(), p))) {
            let circles: usize = p.side.iter().chain(&p.bottom).map(Strip::len).sum();
            if circles.saturating_mul(angles.sin.len()) > MAX_SAMPLES_PER_LOCATION {
                return Err(EngageError::TooManySamples {
                    what,
                    circles,
                    angles: angles.sin.len(),
                    dz: opts.dz_mm,
                    dphi: opts.dphi_deg,
                });
            }
        }
        Ok(Self {
            program,
            stock,
            opts,
            tools,
            angles,
            next_move: 0,
            current: None,
            last_x: None,
            scratch: Scratch::default(),
            stats: EngageStats::default(),
            failed: false,
            observer: &Quiet,
            rapid_collisions: Vec::new(),
            holder_collisions: Vec::new(),
            zones: swarf_stock::SliverZones::default(),
            travel: 0.0,
            pending: VecDeque::new(),
            ready: VecDeque::new(),
            computed: 0,
        })
    }

    /// The rapids so far whose cutting part entered the material (the material is removed,
    /// as `swarf_stock::simulate` does), one per move with the volume it removed (Z rays).
    pub fn rapid_collisions(&self) -> &[Collision] {
        &self.rapid_collisions
    }

    /// The moves so far whose shank or holder entered the material (removed too), one per
    /// move with the volume they removed (Z rays), summed over the move's pieces.
    pub fn holder_collisions(&self) -> &[Collision] {
        &self.holder_collisions
    }

    /// This run, telling `observer` `progress(moves done, moves)` after each cutter location
    /// (before the next is computed). When it answers `Break` the iterator yields
    /// [`EngageError::Cancelled`] and ends; the stock is left cut up to the last location computed (those not handed out yet are dropped).
    #[must_use]
    pub fn observed(mut self, observer: &'a dyn Observer) -> Self {
        self.observer = observer;
        self
    }

    /// Figures so far (complete once the iterator has ended).
    pub fn stats(&self) -> EngageStats {
        self.stats
    }

    /// Moves of the program done so far.
    pub fn moves_done(&self) -> usize {
        self.next_move
    }

    /// Cuts `[s0, s1]` of move `index`; returns the volume removed (mm³).
    fn cut(&mut self, index: usize, s0: f64, s1: f64) -> Result<f64, EngageError> {
        let t0 = Instant::now();
        let prepared = self.tools.of(self.program, index)?;
        let (shape, reach) = (&prepared.shape, prepared.reach);
        let cut = self.stock.cut_move_range(
            self.program,
            index,
            s0,
            s1,
            shape,
            self.opts.chordal_tolerance_mm,
        )?;
        self.stats.simulate_elapsed_s += t0.elapsed().as_secs_f64();
        let area = self.stock.ray_area(2);
        let removed = (cut.cutting.removed_length[2] + cut.non_cutting.removed_length[2]) * area;
        self.stats.removed_volume_mm3 += removed;
        // Collisions, as the simulation tells them (a multi-axis cut's slivers are not).
        self.zones
            .record(self.program, index, reach, cut.error_bound_mm);
        let m = &self.program.moves[index];
        let hit = |list: &mut Vec<Collision>, volume_mm3: f64| match list.last_mut() {
            Some(c) if c.move_index == index => c.volume_mm3 += volume_mm3,
            _ => list.push(Collision {
                move_index: index,
                file: file_of(self.program, m),
                line: m.line,
                volume_mm3,
            }),
        };
        if matches!(m.kind, MoveKind::Rapid)
            && self
                .zones
                .collision(self.program, index, reach, &cut.cutting, true)
        {
            hit(
                &mut self.rapid_collisions,
                cut.cutting.removed_length[2] * area,
            );
        }
        if self
            .zones
            .collision(self.program, index, reach, &cut.non_cutting, false)
        {
            hit(
                &mut self.holder_collisions,
                cut.non_cutting.removed_length[2] * area,
            );
        }
        Ok(removed)
    }

    /// The walk of feed move `index`, whose tip path is `length` mm long: a location every
    /// `step` mm of tip travel and at the end.
    fn walk(&self, index: usize, length: f64) -> Result<Walk, EngageError> {
        let step = self.opts.step_mm;
        let inner = if step > 0.0 && length > step {
            // Locations i·step for i = 1 … while short of the end by more than a hair.
            let n = (length / step * (1.0 - 1e-9)).ceil() - 1.0;
            if n + 1.0 > MAX_LOCATIONS_PER_MOVE as f64 {
                let m = &self.program.moves[index];
                return Err(EngageError::TooManyLocations {
                    file: file_of(self.program, m),
                    line: m.line,
                    locations: n + 1.0,
                    step,
                });
            }
            n.max(0.0) as usize
        } else {
            0
        };
        Ok(Walk {
            index,
            length,
            step,
            count: inner + 1,
            done: 0,
        })
    }

    /// Cuts the path walked up to `travel` mm into the program (all of it at +∞), in order:
    /// the pending pieces that end by then, and the part of the next one before it; the
    /// locations of the pieces cut whole become ready.
    fn cut_until(&mut self, travel: f64) -> Result<(), EngageError> {
        // (A hair's slack: locations `lag_mm` apart, their travel summed, are that far apart.)
        let limit = travel + 1e-9 * (1.0 + travel.abs());
        while let Some(p) = self.pending.front() {
            if p.end > limit {
                // The piece's part before `travel` (its parameter in proportion to its travel).
                if p.start < travel {
                    let (index, s0, t) = (p.index, p.s0, (travel - p.start) / (p.end - p.start));
                    let s = s0 + (p.s1 - s0) * t;
                    let removed = self.cut(index, s0, s)?;
                    if let Some(p) = self.pending.front_mut() {
                        (p.s0, p.start, p.removed) = (s, travel, p.removed + removed);
                    }
                }
                break;
            }
            let Some(p) = self.pending.pop_front() else {
                break;
            };
            let removed = p.removed + self.cut(p.index, p.s0, p.s1)?;
            if let Some((mut e, s_prev)) = p.location {
                e.removed_mm3 = removed;
                e.mrr_mm3_min = mrr(
                    &self.program.moves[p.index],
                    p.s1 - s_prev,
                    p.length,
                    removed,
                );
                self.ready.push_back(e);
            }
        }
        Ok(())
    }

    fn step(&mut self) -> Result<Option<Engagement>, EngageError> {
        loop {
            if let Some(e) = self.ready.pop_front() {
                self.stats.locations += 1;
                if e.is_engaged() {
                    self.stats.engaged_locations += 1;
                }
                return Ok(Some(e));
            }
            if let Some(mut walk) = self.current.take() {
                if walk.done < walk.count {
                    let (index, done, walk_length) = (walk.index, walk.done, walk.length);
                    let s0 = if done == 0 { 0.0 } else { walk.s(done - 1) };
                    let s1 = walk.s(done);
                    walk.done += 1;
                    self.current = Some(walk);
                    let end = self.travel + (s1 - s0) * walk_length;
                    let lag = self.opts.lag_mm;
                    // On a pool kept awake, so that each of the location's parallel sections
                    // starts at once, without waking a worker and waiting for it.
                    let e = swarf_stock::pool::hot(|| {
                        self.cut_until(end - lag)?;
                        self.engagement_at(index, s1, walk_length)
                    })?;
                    self.computed += 1;
                    self.travel = end;
                    self.pending.push_back(Piece {
                        index,
                        s0,
                        s1,
                        start: end - (s1 - s0) * walk_length,
                        end,
                        length: walk_length,
                        removed: 0.0,
                        location: Some((e, s0)),
                    });
                }
                continue;
            }
            let index = self.next_move;
            if index >= self.program.moves.len() {
                if self.pending.is_empty() {
                    return Ok(None);
                }
                swarf_stock::pool::hot(|| self.cut_until(f64::INFINITY))?;
                continue;
            }
            self.next_move += 1;
            let m = &self.program.moves[index];
            let length = path_length(self.program, m);
            if matches!(m.kind, MoveKind::Rapid) {
                self.pending.push_back(Piece {
                    index,
                    s0: 0.0,
                    s1: 1.0,
                    start: self.travel,
                    end: self.travel + length,
                    length,
                    removed: 0.0,
                    location: None,
                });
                self.travel += length;
                continue;
            }
            self.current = Some(self.walk(index, length)?);
        }
    }

    /// The engagement at parameter `s` of move `index`, against the stock as it is now.
    fn engagement_at(
        &mut self,
        index: usize,
        s: f64,
        length: f64,
    ) -> Result<Engagement, EngageError> {
        let program = self.program;
        let m = &program.moves[index];
        let state = MotionState::of_move(program, m, s);
        let speed = state.v_tip.length();
        let (tip_direction, axis_rate) = if speed > 0.0 {
            (state.v_tip / speed, state.omega / speed)
        } else {
            (Vec3::ZERO, Vec3::ZERO)
        };
        let pose = program.pose_at(m, s);
        let z = pose.axis.normalize();
        // x_L: the tip's feed direction across the axis; for a move along the axis the last
        // such direction, else workpiece +X (or +Y) across the axis.
        let across = state.v_tip - z * state.v_tip.dot(z);
        let scale = state.v_tip.length().max(1e-300);
        let x = if across.length() > 1e-9 * scale {
            let x = across.normalize();
            self.last_x = Some(x);
            x
        } else {
            [self.last_x.unwrap_or(Vec3::X), Vec3::X, Vec3::Y]
                .into_iter()
                .map(|h| h - z * h.dot(z))
                .find(|h| h.length() > 1e-6)
                .unwrap_or(Vec3::X)
                .normalize()
        };
        let y = z.cross(x);
        let mut e = Engagement {
            location: self.computed,
            move_index: index,
            file: file_of(program, m),
            line: m.line,
            tool: m.tool,
            s,
            tip: pose.tip,
            axis: z,
            x_l: x,
            y_l: y,
            tip_direction,
            axis_rate,
            feed_mm_min: feed_rate(m, length),
            spindle_rpm: m.spindle_rpm,
            spindle_dir: m.spindle_dir,
            discs: Vec::new(),
            bottom: Vec::new(),
            area_mm2: 0.0,
            ap_mm: 0.0,
            side_extent_mm: None,
            phi_entry_deg: None,
            phi_exit_deg: None,
            removed_mm3: 0.0,
            mrr_mm3_min: 0.0,
        };
        let tool = self.tools.of(program, index)?;
        let frame = LocalFrame {
            tip: pose.tip,
            x,
            y,
            z,
        };
        // The highest material over the cutter's footprint (conservative, from tile bounds):
        // circles above it cannot be engaged.
        // Distances measured out to the samples' spacing (the discs' height, the arc between
        // two angles at the tool's radius), so that a crossing interpolated between two
        // samples is not pulled by a clamped distance.
        let spacing = self
            .opts
            .dz_mm
            .max(tool.radius * self.angles.dphi_deg.to_radians());
        let probe = MaterialProbe::new(self.stock).with_reach(spacing);
        // The box of the cylinder that holds every sampled circle: the tip's and the top's
        // points grown by the radius.
        let top = pose.tip + z * tool.height;
        let bbox = Aabb::new(
            pose.tip.min(top) - Vec3::splat(tool.radius),
            pose.tip.max(top) + Vec3::splat(tool.radius),
        );
        let Some(material) = self.stock.material_range(2, &bbox) else {
            return Ok(e);
        };
        // The column map, for the guesses that `sample_strip` spares: filled, and handed on,
        // only where it is read (a vertical axis, samples guessed), so no strip can read one
        // left from an earlier location.
        let mut tops = std::mem::take(&mut self.scratch.tops);
        let mapped = z.x == 0.0 && z.y == 0.0 && !self.opts.exhaustive;
        if mapped {
            tops.fill(self.stock, &bbox);
        }
        let mut probes = 0u64;
        let h = self.stock.grid().h;
        let rub = Rub::new(
            self.opts.chordal_tolerance_mm,
            h[0].max(h[1]).max(h[2]),
            tool.radius,
        );
        let mut run_strip = |strip: &Strip, scratch: &mut Scratch| {
            let samples = sample_strip(
                strip,
                &frame,
                &state,
                &probe,
                &self.angles,
                tool.radius,
                material,
                rub,
                self.opts.exhaustive,
                mapped.then_some(&tops),
                &mut probes,
                scratch,
            );
            let result = integrate(strip, &samples, self.angles.dphi_deg);
            (scratch.g, scratch.side) = (samples.g, samples.side);
            result
        };
        let side = tool.side.as_ref().map(|s| run_strip(s, &mut self.scratch));
        let bottom = tool
            .bottom
            .as_ref()
            .map(|s| run_strip(s, &mut self.scratch));
        self.stats.probes += probes;
        self.scratch.tops = tops;
        e.set_from(
            side.filter(|r| r.area > 0.0 || !r.circles.is_empty()),
            bottom.filter(|r: &StripResult| r.area > 0.0 || !r.circles.is_empty()),
            self.angles.dphi_deg,
        );
        Ok(e)
    }
}

impl Iterator for Engager<'_> {
    type Item = Result<Engagement, EngageError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.failed {
            return None;
        }
        let (done, total) = (self.next_move as u64, self.program.moves.len() as u64);
        if self.stats.locations > 0 && self.observer.progress(done, total).is_break() {
            self.failed = true;
            // The pieces walked are cut, so that the stock is left as the doc says.
            if let Err(err) = swarf_stock::pool::hot(|| self.cut_until(f64::INFINITY)) {
                return Some(Err(err));
            }
            return Some(Err(EngageError::Cancelled {
                locations: self.stats.locations,
            }));
        }
        match self.step() {
            Ok(e) => e.map(Ok),
            Err(err) => {
                self.failed = true;
                Some(Err(err))
            }
        }
    }
}

/// The tool frame at a location.
#[derive(Clone, Copy, Debug)]
struct LocalFrame {
    tip: Vec3,
    x: Vec3,
    y: Vec3,
    z: Vec3,
}

/// Samples `g` on the circles of `strip` that can reach the material (world heights up to
/// `material.1`), growing the row range while its border rows are engaged.
#[allow(clippy::too_many_arguments)]
fn sample_strip(
    strip: &Strip,
    f: &LocalFrame,
    state: &MotionState,
    probe: &MaterialProbe<'_>,
    angles: &Angles,
    radius: f64,
    material: (f64, f64),
    rub: Rub,
    exhaustive: bool,
    tops: Option<&ColumnTops>,
    probes: &mut u64,
    scratch: &mut Scratch,
) -> StripSamples {
    let n = angles.sin.len();
    // Rows whose circle's lowest world point is below the highest material.
    let horiz = (1.0 - f.z.z * f.z.z).max(0.0).sqrt();
    let reachable = |k: usize| {
        let c = strip.circles[k];
        let centre_z = f.tip.z + c.z * f.z.z;
        centre_z - c.rho * horiz <= material.1 + 1e-9
            && centre_z + c.rho * horiz >= material.0 - 1e-9
    };
    let (Some(lo), Some(hi)) = (
        (0..strip.len()).position(reachable),
        (0..strip.len()).rposition(reachable),
    ) else {
        return StripSamples {
            rows: (0, 0),
            n_phi: n,
            g: std::mem::take(&mut scratch.g),
            side: std::mem::take(&mut scratch.side),
        };
    };
    let (lo, hi) = (lo.saturating_sub(1), (hi + 2).min(strip.len()));
    let rows = hi - lo;
    // With the tool axis along +Z or −Z (the only case where the column map `tops` is given)
    // the circles' samples lie at their circle's height, and at each angle on one radial line:
    // for the circles of a band of radii (`BAND_TILES`) the map (`ColumnTops`) is read once an
    // angle, over the square that holds the band's points at that angle grown by 1.25 ray
    // spacings, and a feasible sample more than two ray spacings above it is guessed outside
    // without reading its ray. The guess's ray (of any family) passes within half a spacing of
    // the sample; had it material there, the Z rays on either side of the sample along its
    // direction would reach within half a spacing of that height, unless the material were a
    // sliver between them. The sample stays open, so pass 3 probes it wherever it borders a
    // side change, as any guess. (Read at each sample, the map costs more than the guesses it
    // spares.)
    let h = probe.stock().grid().h.into_iter().fold(0.0, f64::max);
    let (air_margin, near) = (2.0 * h, 1.25 * h);
    // The rows in bands (runs of consecutive rows whose radii span at most the band's width);
    // `band_of[r]` is row `lo + r`'s band (`u32::MAX`: none, no claim), `mapped_tops` the
    // map's reading for a band at each angle.
    let mut mapped_tops = std::mem::take(&mut scratch.mapped_tops);
    let mut band_of = std::mem::take(&mut scratch.band_of);
    mapped_tops.clear();
    band_of.clear();
    if let Some(tops) = tops {
        let band_width = BAND_TILES * TILE as f64 * h;
        for (start, end, mid, half) in radius_bands(&strip.circles[lo..hi], band_width) {
            let band = (mapped_tops.len() / n) as u32;
            band_of.resize(band_of.len() + (end - start), band);
            mapped_tops.extend(angles.sin.iter().zip(&angles.cos).map(|(&sin, &cos)| {
                let p = f.tip + (f.x * sin + f.y * cos) * mid;
                tops.top_near(p.x, p.y, near + half)
            }));
        }
    } else {
        band_of.resize(rows, u32::MAX);
    }
    let mut no_claim = std::mem::take(&mut scratch.no_claim);
    no_claim.resize(n, f64::INFINITY);
    let vscale = state.v_tip.length() + state.omega.length() * radius;
    // The surface point of circle `k` at angle `j`, and its outward normal.
    let point = |k: usize, j: usize| {
        let c = strip.circles[k];
        let radial = f.x * angles.sin[j] + f.y * angles.cos[j];
        (
            f.tip + radial * c.rho + f.z * c.z,
            radial * c.normal.x + f.z * c.normal.y,
        )
    };
    // g at a probed feasible sample (`rf` its `R·f`): its depth, finite so that depths
    // interpolate (a point far from every ray is ±∞ deep), capped by `R·f` — unless it rubs.
    let probed = |k: usize, j: usize, rf: f64| {
        let (p, normal) = point(k, j);
        rub.g(probe.depth(p), normal, rf)
    };
    // Pass 1 (per circle, before its depths), no stock: `R·f` where the motion pushes into the
    // material (> 0), `R·(f − ε)` (≤ 0) where it does not.
    // The buffers keep their length from the last location: every value is written below
    // before it is read, so only growth is initialised.
    let mut rf = std::mem::take(&mut scratch.rf);
    rf.resize(rows * n, 0.0);
    let translating = state.omega == Vec3::ZERO;
    let speed = state.v_tip.length();
    let tangency = |r: usize, row: &mut [f64]| {
        let feasibility = |feas: f64| {
            radius
                * (feas
                    - if feas > FEASIBLE_EPS {
                        0.0
                    } else {
                        FEASIBLE_EPS
                    })
        };
        if translating {
            // One velocity for every point: f = n_ρ·(sin φ·x̂ + cos φ·ŷ)·v̂ + n_z·ẑ·v̂.
            let c = strip.circles[lo + r];
            let v = if speed > 0.0 {
                state.v_tip / speed
            } else {
                Vec3::ZERO
            };
            let (a, b, z) = (
                c.normal.x * f.x.dot(v),
                c.normal.x * f.y.dot(v),
                c.normal.y * f.z.dot(v),
            );
            // Without a branch per sample, so that the loop runs on vector registers: the
            // same values as `feasibility`.
            for ((out, &sin), &cos) in row.iter_mut().zip(&angles.sin).zip(&angles.cos) {
                let feas = a * sin + b * cos + z;
                let below = f64::from(u8::from(feas <= FEASIBLE_EPS));
                *out = radius * (feas - below * FEASIBLE_EPS);
            }
            return;
        }
        for (j, out) in row.iter_mut().enumerate() {
            let (p, normal) = point(lo + r, j);
            let v = state.velocity_at(p);
            let vl = v.length();
            let feas = if vl > 1e-12 * vscale.max(1e-300) {
                normal.dot(v) / vl
            } else {
                0.0
            };
            *out = feasibility(feas);
        }
    };
    // Pass 2, the side of each feasible sample (f > ε), where g = min(δ, R·f): first guessed
    // from the one ray nearest to it in the family most aligned with the cutter's normal there
    // (`MaterialProbe::inside_nearest_ray`), which agrees with the probe except within about a
    // ray spacing of the boundary; the guess's value is a placeholder of its sign.
    let mut g = std::mem::take(&mut scratch.g);
    g.resize(rows * n, 0.0);
    // Each sample's side as a byte (1: engaged) for the integration, and packed with whether
    // it is open (feasible, its side still a guess) for pass 3.
    let mut side = std::mem::take(&mut scratch.side);
    side.resize(rows * n, 0);
    let nw = sides::words(n);
    let mut side_bits = std::mem::take(&mut scratch.side_bits);
    side_bits.resize(rows * nw, 0);
    let mut open_bits = std::mem::take(&mut scratch.open_bits);
    open_bits.resize(rows * nw, 0);
    let mut counted: u64 = g
        .par_chunks_mut(n)
        .zip(side.par_chunks_mut(n))
        .zip(side_bits.par_chunks_mut(nw))
        .zip(open_bits.par_chunks_mut(nw))
        .zip(rf.par_chunks_mut(n))
        .enumerate()
        .map(|(r, ((((row, side), side_bits), open_bits), rfr))| {
            tangency(r, rfr);
            let mut count = 0u64;
            if exhaustive {
                for (j, (out, &rfj)) in row.iter_mut().zip(rfr.iter()).enumerate() {
                    *out = if rfj <= 0.0 {
                        rfj
                    } else {
                        count += 1;
                        probed(lo + r, j, rfj)
                    };
                }
                for (s, &v) in side.iter_mut().zip(&*row) {
                    *s = u8::from(v > 0.0);
                }
                sides::pack(side_bits, side, |&s| s != 0);
                open_bits.fill(0);
                return count;
            }
            // Only the feasible samples are visited, a word of their bits at a time: about
            // half of a circle is not, and there `g = R·(f − ε)`, no side (a loop over every
            // sample spent a third of the sampling's instructions on them).
            sides::pack(open_bits, rfr, |&v| v > 0.0);
            row.copy_from_slice(rfr);
            side.fill(0);
            side_bits.fill(0);
            // The circle's point at angle φ is `centre + sin φ·a + cos φ·b`, its normal
            // `sin φ·na + cos φ·nb + nz` (as `point` computes them).
            let c = strip.circles[lo + r];
            let centre = f.tip + f.z * c.z;
            let (a, b) = (f.x * c.rho, f.y * c.rho);
            let (na, nb, nz) = (f.x * c.normal.x, f.y * c.normal.x, f.z * c.normal.y);
            // The column map under this circle's samples where it was read (else +∞: no
            // claim), and the circle's height.
            let below = match band_of[r] {
                u32::MAX => &no_claim[..],
                band => &mapped_tops[band as usize * n..(band as usize + 1) * n],
            };
            let z_row = centre.z;
            let (sin, cos) = (&angles.sin[..n], &angles.cos[..n]);
            for (w, (&open, bits)) in open_bits.iter().zip(side_bits.iter_mut()).enumerate() {
                let mut todo = open;
                while todo != 0 {
                    let bit = todo.trailing_zeros() as usize;
                    todo &= todo - 1;
                    let j = w * 64 + bit;
                    let inside = z_row - below[j] <= air_margin && {
                        let p = centre + a * sin[j] + b * cos[j];
                        // The family most aligned with the normal (ties to the lower).
                        let k = (na * sin[j] + nb * cos[j] + nz).abs().max_position();
                        probe.inside_nearest_ray(k, p)
                    };
                    if inside {
                        side[j] = 1;
                        *bits |= 1 << bit;
                    } else {
                        row[j] = -GUESSED_OUTSIDE;
                    }
                }
            }
            count
        })
        .sum();
    // Pass 3: the value of g matters only where a cell or a circle changes sign (the boundary
    // is interpolated there), and the guess may be wrong only near the boundary: every open
    // sample with a neighbour of the other side (on its circle or the neighbouring ones; rows
    // outside the range count as not engaged) is probed, which may flip its side and so give
    // its own neighbours a neighbour of the other side: they are probed in turn, until no open
    // sample borders a side change. The sides next to the boundary are then the probe's, so
    // the boundary is where probing every sample puts it, wherever the guesses' errors touch
    // it (a guess wrong on a whole feature — a sliver of material or air that the nearest rays
    // all miss — goes unseen: it is narrower than the ray spacing).
    if !exhaustive {
        // The rows to look at (all at first; then those around a flipped side), the samples
        // to probe and their probed values; a row's samples that border a change of side
        // are found 64 at a time (`sides::borders`).
        let (scan, todo, values) = (&mut scratch.scan, &mut scratch.todo, &mut scratch.values);
        scan.clear();
        scan.resize(rows, true);
        loop {
            todo.clear();
            for r in (0..rows).filter(|&r| scan[r]) {
                let open_row = &open_bits[r * nw..(r + 1) * nw];
                for (w, &open) in open_row.iter().enumerate().filter(|(_, &o)| o != 0) {
                    let mut due = sides::borders(&side_bits, rows, n, r, w) & open;
                    while due != 0 {
                        todo.push(r * n + w * 64 + due.trailing_zeros() as usize);
                        due &= due - 1;
                    }
                }
            }
            if todo.is_empty() {
                break;
            }
            let (rf_now, probed) = (&rf, &probed);
            values.clear();
            values.par_extend(
                todo.par_iter()
                    .map(|&i| probed(lo + i / n, i % n, rf_now[i])),
            );
            counted += todo.len() as u64;
            scan.fill(false);
            for (&i, &v) in todo.iter().zip(values.iter()) {
                let now = u8::from(v > 0.0);
                let (r, j) = (i / n, i % n);
                let (word, bit) = (r * nw + j / 64, 1u64 << (j % 64));
                if now != side[i] {
                    side[i] = now;
                    side_bits[word] ^= bit;
                    scan[r.saturating_sub(1)..(r + 2).min(rows)].fill(true);
                }
                g[i] = v;
                open_bits[word] &= !bit;
            }
        }
    }
    (scratch.side_bits, scratch.open_bits) = (side_bits, open_bits);
    (scratch.mapped_tops, scratch.no_claim) = (mapped_tops, no_claim);
    scratch.band_of = band_of;
    *probes += counted;
    scratch.rf = rf;
    StripSamples {
        rows: (lo, hi),
        n_phi: n,
        g,
        side,
    }
}

/// The runs of consecutive `circles` whose radii span at most `width`, in order, as (first,
/// end, middle radius, half the span): every circle of a run lies within the half-span of the
/// middle, so a square grown by it about the middle's point at an angle holds each circle's
/// point there (with a vertical tool axis, the circles' points at one angle lie on one radial
/// line).
fn radius_bands(
    circles: &[Circle],
    width: f64,
) -> impl Iterator<Item = (usize, usize, f64, f64)> + '_ {
    let mut start = 0;
    std::iter::from_fn(move || {
        let first = circles.get(start)?;
        let (mut a, mut b) = (first.rho, first.rho);
        let mut end = start + 1;
        while let Some(c) = circles.get(end) {
            let (a2, b2) = (a.min(c.rho), b.max(c.rho));
            if b2 - a2 > width {
                break;
            }
            (a, b, end) = (a2, b2, end + 1);
        }
        let band = (start, end, 0.5 * (a + b), 0.5 * (b - a));
        start = end;
        Some(band)
    })
}

/// Where contact is a **rub**, not engagement: the cutter grazing a wall from the air side —
/// its outward normal against the wall's — no deeper than the stock's own uncertainty. A tool
/// that comes back along a concave wall it cut before (each turn of a helix, a second pass round
/// a pocket) touches it along a line; but arcs and 5-axis moves are cut within the chordal
/// tolerance, leaving such a wall up to that proud, and between two rays the probe's sheet runs
/// inside a concave wall by up to `h²/(8ρ)` (`ρ ≥ R` where the tool fits): without this the side
/// would be found in the material within a degree or two of the contact, all the way up the
/// wall. Shallowness alone is no sign of a rub — the depth is the distance to the *nearest*
/// boundary, and a point entering a face across it (the normals square) or about to break
/// through a face it cuts (the normals alike) is as shallow and engaged.
#[derive(Clone, Copy, Debug)]
struct Rub {
    /// The uncertainty, mm: the chordal tolerance plus the probe's `h²/(8R)`.
    depth: f64,
}

/// A rub's normals are within this of opposite: `n_cutter · n_wall < −RUB_COS` (10°).
const RUB_COS: f64 = 0.984_807_753_012_208;

impl Rub {
    fn new(chordal_tolerance: f64, h: f64, radius: f64) -> Self {
        Self {
            depth: chordal_tolerance + h * h / (8.0 * radius),
        }
    }

    /// `g` at a feasible probed sample of cutter normal `normal` and `R·f = rf`: the depth
    /// capped by `R·f`, or below 0 (by the rub's own depth) for a rub.
    #[inline]
    fn g(&self, depth: crate::Depth, normal: Vec3, rf: f64) -> f64 {
        let d = depth.distance.clamp(-FAR_MM, FAR_MM);
        let grazing = depth.normal.is_some_and(|n| n.dot(normal) < -RUB_COS);
        if d > 0.0 && d < self.depth && grazing {
            d - self.depth
        } else {
            lesser(d, rf)
        }
    }
}

/// Depths beyond this (mm) are reported as this: far enough from any boundary for any cutter.
const FAR_MM: f64 = 1e6;

/// The placeholder value of g at a feasible sample guessed outside the material (mm): never
/// interpolated, since every sample next to a side change is probed.
const GUESSED_OUTSIDE: f64 = 1.0;

/// The widest band of radii whose circles share one reading of the column map, in the
/// stock's tiles (`TILE` ray spacings). Wider, fewer readings certify less: on the finishing
/// bench (1,000 locations, h = 0.1 mm) 0.25 / 0.6 / 1.2 / 2 / 3 mm gave 12.67 / 12.11 / 12.01 /
/// 11.98 / 12.05 G instructions.
const BAND_TILES: f64 = 2.0;

/// Tool-tip path length of `m`, mm (arcs exact; curved 5-axis tips by 64 chords).
pub fn path_length(program: &Program, m: &Move) -> f64 {
    match m.kind {
        MoveKind::Arc(g) if !program.tip_path_is_curved(m) => g.length(),
        _ if program.tip_path_is_curved(m) => {
            let mut len = 0.0;
            let mut prev = m.start.tip;
            for i in 1..=64 {
                let p = program.pose_at(m, i as f64 / 64.0).tip;
                len += (p - prev).length();
                prev = p;
            }
            len
        }
        _ => (m.end.tip - m.start.tip).length(),
    }
}

/// The tip feed rate of `m` (tip path `length` mm), mm/min — its tip path over the time the
/// controller takes for it ([`Move::feed_minutes`]: on a rotary move without tool centre point
/// control the feed is the joints', not the tip's); 0 when undefined.
pub fn feed_rate(m: &Move, length: f64) -> f64 {
    match m.feed_minutes(length) {
        Some(t) if t > 0.0 && (length / t).is_finite() => length / t,
        _ => 0.0,
    }
}

/// Removal rate of `removed` mm³ over a part `ds` of move `m` (tip path `length` mm in all),
/// mm³/min (0 at zero feed): the joints move linearly in the move's parameter, so the part
/// takes `ds` of the move's time.
fn mrr(m: &Move, ds: f64, length: f64, removed: f64) -> f64 {
    let minutes = m.feed_minutes(length).map_or(f64::NAN, |t| t * ds);
    if minutes.is_finite() && minutes > 0.0 {
        removed / minutes
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Depth;

    #[test]
    fn radius_bands_cover_the_rows_in_runs_that_hold_each_radius() {
        // Radii as profiles give them: rising along a ball's arc, constant on a shank, falling
        // along a taper, with jumps at the joints.
        let circle = |rho: f64| Circle {
            z: 0.0,
            rho,
            normal: swarf_geom::math::Vec2::new(1.0, 0.0),
        };
        let mut rhos: Vec<f64> = (0..60).map(|i| 5.0 * (i as f64 / 60.0).sqrt()).collect();
        rhos.extend(std::iter::repeat(5.0).take(40));
        rhos.extend((0..30).map(|i| 5.0 - 0.13 * i as f64));
        rhos.extend([0.2, 4.9, 0.3, 0.3]);
        let circles: Vec<Circle> = rhos.iter().map(|&r| circle(r)).collect();
        for width in [0.0, 0.1, 0.25, 2.0, 10.0] {
            let bands: Vec<_> = radius_bands(&circles, width).collect();
            let mut next = 0;
            for &(start, end, mid, half) in &bands {
                assert_eq!(start, next, "width {width}: contiguous");
                assert!(end > start && half <= 0.5 * width, "width {width}");
                // (Within rounding, which `ColumnTops::top_near`'s grown square absorbs.)
                for c in &circles[start..end] {
                    assert!((c.rho - mid).abs() <= half + 1e-14 * c.rho, "width {width}");
                }
                // Maximal: the next radius would widen the run beyond `width`.
                if let Some(c) = circles.get(end) {
                    let (lo, hi) = (mid - half, mid + half);
                    assert!(hi.max(c.rho) - lo.min(c.rho) > width * (1.0 - 1e-12));
                }
                next = end;
            }
            assert_eq!(next, circles.len(), "width {width}: every row");
        }
        assert_eq!(radius_bands(&circles, 10.0).count(), 1);
        assert_eq!(radius_bands(&[], 1.0).count(), 0);
    }

    #[test]
    fn a_rub_is_shallow_and_against_the_wall_and_nothing_else_is() {
        // The uncertainty at the defaults: 1 µm of chords and 0.25 µm of the probe's sheet.
        let rub = Rub::new(1e-3, 0.1, 5.0);
        assert!((rub.depth - 1.25e-3).abs() < 1e-15);
        let at = |distance: f64, wall: Option<Vec3>| Depth {
            distance,
            measured: true,
            normal: wall,
        };
        let cutter = Vec3::X;
        let (rf, shallow) = (0.2, 0.5e-3);
        // Against the wall (within 10° of opposite): a rub, below 0.
        for deg in [0.0f64, 5.0, 9.9] {
            let wall = Vec3::new(-deg.to_radians().cos(), deg.to_radians().sin(), 0.0);
            assert!(rub.g(at(shallow, Some(wall)), cutter, rf) < 0.0, "{deg}°");
        }
        // Past 10°, across the wall, along it, deeper than the uncertainty, outside, or with no
        // sheet measured: the depth capped by R·f.
        let beyond = 10.1f64.to_radians();
        for (d, wall) in [
            (shallow, Some(Vec3::new(-beyond.cos(), beyond.sin(), 0.0))),
            (shallow, Some(Vec3::Z)),
            (shallow, Some(Vec3::X)),
            (2e-3, Some(-Vec3::X)),
            (-shallow, Some(-Vec3::X)),
            (shallow, None),
        ] {
            assert_eq!(rub.g(at(d, wall), cutter, rf), d.min(rf), "{d} {wall:?}");
        }
        assert_eq!(rub.g(at(0.3, Some(Vec3::Z)), cutter, rf), rf);
    }
}
