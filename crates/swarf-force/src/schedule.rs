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
    /// Split a long move whose locations allow different feeds into pieces with their own
    /// feeds (at location boundaries, neighbours within [`SPLIT_MERGE`] of each other merged).
    pub split: bool,
}

/// Neighbouring locations whose feed caps differ by less than this ratio share a piece.
pub const SPLIT_MERGE: f64 = 0.1;

/// One piece of a feed move: the part up to move parameter `s_end` at one feed.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FeedPiece {
    /// Move parameter where the piece ends (the last piece ends at 1).
    pub s_end: f64,
    /// Its feed, mm/min.
    pub feed_mm_min: f64,
    /// The limit's cap over its locations (`None`: not engaged).
    pub cap_mm_min: Option<f64>,
    /// Still over the limit at its feed.
    pub over_limit: bool,
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
    /// The move's pieces in order: one (the whole move at `new_feed_mm_min`) unless it was
    /// split; `new_feed_mm_min` is then the slowest piece's feed.
    pub pieces: Vec<FeedPiece>,
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
    /// Per move, its locations' parameters and caps, in order.
    locations: Vec<Vec<(f64, LocationCap)>>,
}

impl MoveCaps {
    /// Caps for a program of `moves` moves.
    pub fn new(moves: usize) -> Self {
        Self {
            caps: vec![None; moves],
            infeasible: vec![false; moves],
            locations: vec![Vec::new(); moves],
        }
    }

    /// Takes the location at parameter `s` of move `index` into account (locations of a move
    /// arrive in order).
    pub fn add(&mut self, index: usize, s: f64, cap: LocationCap) {
        self.locations[index].push((s, cap));
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

/// Groups a move's locations into pieces. Pieces end at locations, and what a piece's feed
/// must hold for is every location it spans, **both ends included**: the location where a
/// piece starts is the last one of the piece before, so the stretch between two neighbouring
/// locations gets the cap of both of its ends (the smaller), and each piece the smallest cap of
/// its stretches. (The first stretch starts where the move starts, which is no location of the
/// move: it has the cap of the move's first location, as the unsplit move has its locations'.)
/// Between two locations the engagement is known only at them, as everywhere along a program:
/// `--step` sets how closely it is sampled. Neighbouring stretches whose caps are within
/// [`SPLIT_MERGE`] of the piece's smallest share it. `(s_end, cap, infeasible)` per piece; an
/// unloaded location counts as uncapped.
fn pieces_of(locations: &[(f64, LocationCap)]) -> Vec<(f64, Option<f64>, bool)> {
    let of = |cap: LocationCap| match cap {
        LocationCap::Unloaded => (None, false),
        LocationCap::Feed(f) => (Some(f), false),
        LocationCap::OverAtAnyFeed => (Some(0.0), true),
    };
    let mut out: Vec<(f64, Option<f64>, bool)> = Vec::new();
    let mut span: Option<(f64, f64)> = None;
    let mut before: Option<(Option<f64>, bool)> = None;
    for &(s, cap) in locations {
        let here = of(cap);
        // The stretch from the location before (its start) to this one.
        let (c, bad) = match before {
            Some((c0, bad0)) => (
                match (c0, here.0) {
                    (Some(a), Some(b)) => Some(a.min(b)),
                    (a, b) => a.or(b),
                },
                bad0 || here.1,
            ),
            None => here,
        };
        before = Some(here);
        let key = c.unwrap_or(f64::INFINITY);
        let joins = match (out.last(), span) {
            (Some(_), Some((lo, hi))) => {
                let (lo, hi) = (lo.min(key), hi.max(key));
                (lo.is_infinite() && hi.is_infinite())
                    || (lo.is_finite() && hi <= lo * (1.0 + SPLIT_MERGE))
            }
            _ => false,
        };
        if joins {
            let last = out.last_mut().expect("joined a piece");
            last.0 = s;
            last.1 = match (last.1, c) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            };
            last.2 |= bad;
            span = span.map(|(lo, hi)| (lo.min(key), hi.max(key)));
        } else {
            out.push((s, c, bad));
            span = Some((key, key));
        }
    }
    if let Some(last) = out.last_mut() {
        last.0 = 1.0;
    }
    out
}

/// The feeds of `program`'s feed moves from the caps its locations gave; with
/// [`ScheduleOptions::split`], moves for which `can_split` says yes may be split into pieces.
/// Moves for which `fixed` says yes keep their feed (spindle-synchronised motion, whose speed
/// is the thread's lead times the spindle speed) and are marked over the limit where it is.
pub fn schedule_feeds(
    program: &Program,
    caps: &MoveCaps,
    opts: &ScheduleOptions,
    can_split: &dyn Fn(usize) -> bool,
    fixed: &dyn Fn(usize) -> bool,
) -> ScheduleResult {
    let mut out = ScheduleResult::default();
    let step = opts.max_step_percent.map(|p| 1.0 + p / 100.0);
    let mut run: Vec<MoveFeed> = Vec::new();
    let flush = |run: &mut Vec<MoveFeed>, out: &mut ScheduleResult| {
        // The pieces of the run, in order, bounded in their change and from below.
        let mut feeds: Vec<&mut FeedPiece> =
            run.iter_mut().flat_map(|m| m.pieces.iter_mut()).collect();
        if let Some(q) = step {
            for i in 1..feeds.len() {
                feeds[i].feed_mm_min = feeds[i].feed_mm_min.min(feeds[i - 1].feed_mm_min * q);
            }
            for i in (0..feeds.len().saturating_sub(1)).rev() {
                feeds[i].feed_mm_min = feeds[i].feed_mm_min.min(feeds[i + 1].feed_mm_min * q);
            }
        }
        for p in feeds {
            p.feed_mm_min = p.feed_mm_min.max(opts.min_feed_mm_min);
            if let Some(c) = p.cap_mm_min {
                p.over_limit |= p.feed_mm_min > c * (1.0 + 1e-9);
            }
        }
        for m in run.iter_mut() {
            m.new_feed_mm_min = m
                .pieces
                .iter()
                .map(|p| p.feed_mm_min)
                .fold(f64::INFINITY, f64::min);
            m.over_limit = m.pieces.iter().any(|p| p.over_limit);
        }
        out.moves.append(run);
    };
    for (i, m) in program.moves.iter().enumerate() {
        if matches!(m.kind, MoveKind::Rapid) {
            flush(&mut run, &mut out);
            continue;
        }
        let old = swarf_engage::feed_rate(m, swarf_engage::path_length(program, m));
        if fixed(i) {
            // Its own run: a feed that cannot change bounds no neighbour's step.
            flush(&mut run, &mut out);
            let cap = caps.caps[i];
            let over = caps.infeasible[i] || cap.is_some_and(|c| old > c * (1.0 + 1e-9));
            out.moves.push(MoveFeed {
                move_index: i,
                old_feed_mm_min: old,
                new_feed_mm_min: old,
                cap_mm_min: cap,
                over_limit: over,
                pieces: vec![FeedPiece {
                    s_end: 1.0,
                    feed_mm_min: old,
                    cap_mm_min: cap,
                    over_limit: over,
                }],
            });
            continue;
        }
        let ceiling = opts
            .max_feed_mm_min
            .unwrap_or(old)
            .max(opts.min_feed_mm_min);
        let cap = caps.caps[i];
        let whole = vec![(1.0, cap, caps.infeasible[i])];
        let parts = if opts.split && can_split(i) {
            let p = pieces_of(&caps.locations[i]);
            if p.len() > 1 {
                p
            } else {
                whole
            }
        } else {
            whole
        };
        let pieces = parts
            .into_iter()
            .map(|(s_end, cap, bad)| FeedPiece {
                s_end,
                feed_mm_min: cap.map_or(ceiling, |c| c.min(ceiling)),
                cap_mm_min: cap,
                over_limit: bad,
            })
            .collect();
        run.push(MoveFeed {
            move_index: i,
            old_feed_mm_min: old,
            new_feed_mm_min: 0.0,
            cap_mm_min: cap,
            over_limit: false,
            pieces,
        });
    }
    flush(&mut run, &mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn locations_group_into_pieces_by_their_caps() {
        use LocationCap::{Feed, OverAtAnyFeed, Unloaded};
        // A stretch between two locations takes the smaller cap of its two ends.
        let locs = [
            (0.1, Unloaded),
            (0.2, Unloaded),
            (0.3, Feed(500.0)),  // stretch 0.2–0.3: 500
            (0.4, Feed(540.0)),  // 0.3–0.4: 500
            (0.5, Feed(600.0)),  // 0.4–0.5: 540, within 10 % of 500: the same piece
            (0.55, Feed(600.0)), // 0.5–0.55: 600 > 500·1.1, a new piece
            (0.6, OverAtAnyFeed),
            (0.7, OverAtAnyFeed),
            (0.8, Unloaded), // 0.7–0.8 starts at a location over the limit at any feed
        ];
        let p = pieces_of(&locs);
        assert_eq!(
            p,
            vec![
                (0.2, None, false),
                (0.5, Some(500.0), false),
                (0.55, Some(600.0), false),
                (1.0, Some(0.0), true),
            ]
        );
        assert_eq!(
            pieces_of(&[(0.5, Feed(100.0)), (1.0, Feed(105.0))]),
            vec![(1.0, Some(100.0), false)]
        );
    }

    /// The reviewer's slot leaving the block (`--step 2` on a 44 mm move): the full slot's
    /// last location caps 715.7 mm/min, the next (half out) 1050.5, then air. The piece that
    /// starts at the full slot's last location spans it, so it may not go faster than 715.7:
    /// every location a piece spans, both ends included, allows the piece's feed.
    #[test]
    fn a_piece_holds_at_the_location_where_it_starts() {
        use LocationCap::{Feed, Unloaded};
        let mut locs: Vec<(f64, LocationCap)> = vec![(2.0 / 44.0, Unloaded)];
        for k in 2..=20 {
            locs.push((2.0 * k as f64 / 44.0, Feed(715.702)));
        }
        locs.push((42.0 / 44.0, Feed(1050.5)));
        locs.push((1.0, Unloaded));
        let p = pieces_of(&locs);
        assert_eq!(
            p,
            vec![
                (2.0 / 44.0, None, false),
                (42.0 / 44.0, Some(715.702), false),
                (1.0, Some(1050.5), false),
            ]
        );
        // The invariant, location by location.
        let mut start = f64::NEG_INFINITY;
        for &(end, cap, _) in &p {
            for &(s, c) in &locs {
                if s >= start && s <= end {
                    if let (Some(cap), Feed(c)) = (cap, c) {
                        assert!(cap <= c, "piece to {end} at {cap} spans {s} capped {c}");
                    }
                }
            }
            start = end;
        }
    }
}
