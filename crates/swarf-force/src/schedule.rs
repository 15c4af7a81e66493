//! Force-limited feed scheduling: a feed per feed move so that the predicted peak force (or
//! torque, or power) stays at or under a limit.
//!
//! The engagement does not depend on the feed, so one engagement run gives every location's
//! forces as a function of the feed per tooth ([`crate::UnitForces`]): per location the largest
//! feed under the limit is found by bisection ([`ForceModel::max_feed_per_tooth`]), a move takes
//! the smallest over its locations, and then the feeds are bounded:
//!
//! 1. by `--max-feed` (without it, a move is never made faster than programmed);
//! 2. in their change between consecutive feed moves (`--max-step-percent p`, within each run
//!    of feed moves between rapids): the largest sequence under the caps whose ratio between
//!    neighbours stays within `1 + p/100`, `f_i = min_j cap_j·(1 + p)^|i−j|` (one forward and one
//!    backward pass);
//! 3. from below by `--min-feed`; a move held there while still over the limit is reported.

use serde::Serialize;
use swarf_path::{MoveKind, Program};

use crate::location::{Evaluated, ForceModel, Limit};

/// Options of a schedule.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ScheduleOptions {
    /// The bound.
    pub limit: Limit,
    /// Slowest feed, mm/min.
    pub min_feed_mm_min: f64,
    /// Fastest feed, mm/min; `None`: never faster than programmed.
    pub max_feed_mm_min: Option<f64>,
    /// Largest change between consecutive feed moves, percent; `None`: unbounded.
    pub max_step_percent: Option<f64>,
}

/// The scheduled feed of one feed move.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MoveFeed {
    /// Move index in the program.
    pub move_index: usize,
    /// Programmed feed, mm/min.
    pub old_feed_mm_min: f64,
    /// Scheduled feed, mm/min.
    pub new_feed_mm_min: f64,
    /// The limit's feed cap from the forces (`None`: not engaged, or no spindle).
    pub cap_mm_min: Option<f64>,
    /// Still over the limit at the scheduled feed: the minimum feed is above the cap, or the
    /// edge forces alone exceed the limit.
    pub over_limit: bool,
}

/// A schedule.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct ScheduleResult {
    /// Every feed move, in program order.
    pub moves: Vec<MoveFeed>,
}

/// Per-move caps gathered while the locations stream by.
#[derive(Clone, Debug, Default)]
pub struct MoveCaps {
    caps: Vec<Option<f64>>,
    infeasible: Vec<bool>,
}

impl MoveCaps {
    /// Caps for a program of `moves` moves.
    pub fn new(moves: usize) -> Self {
        Self {
            caps: vec![None; moves],
            infeasible: vec![false; moves],
        }
    }

    /// Takes a location of move `index` into account.
    pub fn add(&mut self, index: usize, cap: LocationCap) {
        let cap = match cap {
            LocationCap::Unloaded => return,
            LocationCap::Feed(f) => f,
            LocationCap::OverAtAnyFeed => {
                self.infeasible[index] = true;
                0.0
            }
        };
        let slot = &mut self.caps[index];
        *slot = Some(slot.map_or(cap, |c: f64| c.min(cap)));
    }
}

/// What one location allows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LocationCap {
    /// Not engaged, or no spindle: no bound.
    Unloaded,
    /// The fastest feed under the limit, mm/min.
    Feed(f64),
    /// Over the limit even as the feed goes to zero (edge forces alone).
    OverAtAnyFeed,
}

impl LocationCap {
    /// The cap of an evaluated location, searching feeds per tooth up to `c_max` mm.
    pub fn of(model: &ForceModel, ev: &Evaluated, limit: Limit, c_max: f64) -> Self {
        if !ev.unit.engaged || ev.spindle_rpm <= 0.0 {
            return LocationCap::Unloaded;
        }
        match model.max_feed_per_tooth(ev, limit, c_max) {
            Some(c) => LocationCap::Feed(c * ev.spindle_rpm * ev.flutes as f64),
            None => LocationCap::OverAtAnyFeed,
        }
    }
}

/// The feeds of `program`'s feed moves from the caps its locations gave.
pub fn schedule_feeds(
    program: &Program,
    caps: &MoveCaps,
    opts: &ScheduleOptions,
) -> ScheduleResult {
    let mut out = ScheduleResult::default();
    let step = opts.max_step_percent.map(|p| 1.0 + p / 100.0);
    let mut run: Vec<MoveFeed> = Vec::new();
    let flush = |run: &mut Vec<MoveFeed>, out: &mut ScheduleResult| {
        if let Some(q) = step {
            for i in 1..run.len() {
                run[i].new_feed_mm_min = run[i].new_feed_mm_min.min(run[i - 1].new_feed_mm_min * q);
            }
            for i in (0..run.len().saturating_sub(1)).rev() {
                run[i].new_feed_mm_min = run[i].new_feed_mm_min.min(run[i + 1].new_feed_mm_min * q);
            }
        }
        for m in run.iter_mut() {
            m.new_feed_mm_min = m.new_feed_mm_min.max(opts.min_feed_mm_min);
        }
        out.moves.append(run);
    };
    for (i, m) in program.moves.iter().enumerate() {
        if matches!(m.kind, MoveKind::Rapid) {
            flush(&mut run, &mut out);
            continue;
        }
        let old = swarf_engage::feed_rate(m, swarf_engage::path_length(program, m));
        let ceiling = opts
            .max_feed_mm_min
            .unwrap_or(old)
            .max(opts.min_feed_mm_min);
        let cap = caps.caps[i];
        run.push(MoveFeed {
            move_index: i,
            old_feed_mm_min: old,
            new_feed_mm_min: cap.map_or(ceiling, |c| c.min(ceiling)),
            cap_mm_min: cap,
            over_limit: caps.infeasible[i],
        });
    }
    flush(&mut run, &mut out);
    for m in &mut out.moves {
        if let Some(c) = m.cap_mm_min {
            m.over_limit |= m.new_feed_mm_min > c * (1.0 + 1e-9);
        }
    }
    out
}
