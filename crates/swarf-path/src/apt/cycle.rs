//! APT canned cycles: `CYCLE/DRILL` and its kin, read from the record and expanded, at every
//! `GOTO/` until `CYCLE/OFF`, into the rapids, feeds and dwells a controller makes — along the
//! tool axis of that `GOTO/`, so holes drilled on a tilted axis are drilled along it.
//!
//! # The record
//! `CYCLE/type[,modifier…][,FEDTO,d][,RAPTO,c][,RTRCTO,r│AUTO][,MMPM│IPM│MMPR│IPR,f]
//! [,DWELL,t][,STEP│INCR│PECK,s]`, the keywords in any order (NX, Vericut and most posts), or
//! APT's positional form `CYCLE/DRILL,d,IPM,f,c` (depth, feed, clearance): a bare number is the
//! depth, a second one the clearance, a third one a peck cycle's step. All distances are along
//! the tool axis from the `GOTO/` point, the top of the hole:
//! * the hole's bottom is `|d|` below it — posts write the depth either as a positive depth or
//!   as a signed offset along the axis (`FEDTO,-12`), which is the same bottom;
//! * the tool rapids to the clearance `c` above it (signed along the axis; 0 when not given);
//! * it leaves the hole to `r` above it (`RTRCTO,r`), to the level it came from
//!   (`RTRCTO,AUTO`, G98's initial level) or, by default, to the clearance (G99's R plane);
//! * `f` is the cycle's feed, in force for the cycle's feed moves only (the program's own
//!   feed is restored after each hole); `t` a dwell at the bottom, seconds; `s` a peck depth.
//!
//! | type | motion (LinuxCNC's cycle with the same motion) |
//! |---|---|
//! | `DRILL`, `CSINK`, `FACE` | feed to the bottom, dwell, rapid out (G81/G82) |
//! | `DEEP` (or `DRILL,DEEP`) | pecks of `s` from the clearance, rapid back to it after each (G83) |
//! | `BRKCHP` (or `DRILL,BRKCHP`) | pecks of `s`, a short rapid back after each (G73) |
//! | `TAP`, `BORE`, `REAM` | feed to the bottom, dwell, feed back to the clearance (G84/G85) |
//!
//! The approach is G81's: up along the axis to the higher of the tool's level and the
//! clearance, over to the hole at that level, down to the clearance. Other cycle types
//! (`MILL`, `THREAD`, …) are errors naming the record: their motion would be missing from the
//! simulation.

use super::{axes, Field, Reader, Record};
use crate::canon::{Canon, CanonSink, FeedMode};
use crate::error::{PathError, PathErrorKind};
use swarf_geom::math::{Vec3, MACHINE_RANGE_MM};

/// How far a peck's rapid stops short of the depth already drilled, mm (LinuxCNC's G73/G83
/// `0.010` inch).
const PECK_CLEARANCE_MM: f64 = 0.254;

/// Most pecks one hole may make: bounds the moves a hostile step can ask for.
const MAX_PECKS: f64 = 100_000.0;

/// The types a `CYCLE/` may name, for the error that names the others.
const TYPES: &str = "DRILL, DEEP, BRKCHP, CSINK, FACE, TAP, BORE, REAM, ON or OFF";

/// How the tool leaves a hole.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Retract {
    /// To the clearance level (G99).
    Clearance,
    /// To the level the tool came from (G98; `RTRCTO,AUTO`).
    Initial,
    /// To this height above the hole's top, mm.
    At(f64),
}

/// The motion at the bottom and on the way out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// Straight in, rapid out.
    Drill,
    /// Pecks with a full retract to the clearance.
    Deep,
    /// Pecks with a short retract.
    ChipBreak,
    /// Straight in, fed out (tapping, boring, reaming).
    FeedOut,
}

/// An active cycle, in mm along the tool axis from each hole's top.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Cycle {
    kind: Kind,
    /// Depth of the bottom below the top, ≥ 0.
    depth: f64,
    /// Clearance level above the top (signed).
    clearance: f64,
    retract: Retract,
    /// The cycle's own feed, mm/min or mm/rev.
    feed: Option<(FeedMode, f64)>,
    dwell_s: f64,
    /// Peck depth, > 0.
    peck: Option<f64>,
}

impl Reader<'_, '_> {
    /// `CYCLE/…`: starts, restarts (`ON`) or ends (`OFF`) a cycle.
    pub(super) fn cycle_record(
        &mut self,
        rec: &Record<'_>,
        fields: &[Field<'_>],
        minor_off: usize,
    ) -> Result<(), PathError> {
        let word = |f: &Field<'_>| f.text.to_ascii_uppercase();
        let Some(first) = fields.first() else {
            return Err(self.error(
                rec,
                minor_off,
                PathErrorKind::Syntax,
                "CYCLE/ without a cycle type",
                "",
                TYPES,
            ));
        };
        let mut kind = match word(first).as_str() {
            "OFF" => {
                self.cycle = None;
                return Ok(());
            }
            "ON" => {
                let Some(c) = self.last_cycle else {
                    return Err(self.error(
                        rec,
                        first.off,
                        PathErrorKind::Semantic,
                        "CYCLE/ON without an earlier cycle to restart",
                        first.text,
                        "a CYCLE/DRILL (or other type) before it",
                    ));
                };
                self.cycle = Some(c);
                return Ok(());
            }
            "DRILL" | "CSINK" | "FACE" => Kind::Drill,
            "DEEP" => Kind::Deep,
            "BRKCHP" => Kind::ChipBreak,
            "TAP" | "BORE" | "REAM" => Kind::FeedOut,
            _ => {
                return Err(self.error(
                    rec,
                    first.off,
                    PathErrorKind::Unsupported,
                    format!(
                        "CYCLE/{} is not a cycle swarf expands, so its motion would be missing \
                         from the simulation",
                        first.text
                    ),
                    first.text,
                    TYPES,
                ))
            }
        };
        let mut depth = None;
        let mut clearance = None;
        let mut retract = Retract::Clearance;
        // Where the clearance and the retract height were written, for their errors.
        let (mut clearance_at, mut retract_at) = (*first, *first);
        let mut feed = None;
        let mut dwell_s = 0.0;
        let mut peck = None;
        let mut rest = fields[1..].iter().peekable();
        while let Some(f) = rest.next() {
            let w = word(f);
            // The number a keyword takes, at the field after it, in mm when it is a length
            // (and then within the machine's range).
            let value = |rest: &mut std::iter::Peekable<std::slice::Iter<'_, Field<'_>>>,
                         what: &str,
                         length: bool|
             -> Result<f64, PathError> {
                let Some(n) = rest.next() else {
                    return Err(self.error(
                        rec,
                        f.off,
                        PathErrorKind::Syntax,
                        format!("CYCLE/: {w} without its value"),
                        f.text,
                        "a number after it",
                    ));
                };
                let v = self.number(rec, *n, what)?;
                if length {
                    self.cycle_length(rec, *n, v)
                } else {
                    Ok(v)
                }
            };
            match w.as_str() {
                "DEEP" => kind = Kind::Deep,
                "BRKCHP" => kind = Kind::ChipBreak,
                "FEDTO" => depth = Some(value(&mut rest, "CYCLE/ FEDTO", true)?.abs()),
                "RAPTO" => {
                    let at = rest.peek().map_or(*f, |n| **n);
                    clearance = Some(value(&mut rest, "CYCLE/ RAPTO", true)?);
                    clearance_at = at;
                }
                "RTRCTO" => {
                    retract = if rest.peek().is_some_and(|n| word(n) == "AUTO") {
                        rest.next();
                        Retract::Initial
                    } else {
                        retract_at = rest.peek().map_or(*f, |n| **n);
                        Retract::At(value(&mut rest, "CYCLE/ RTRCTO", true)?)
                    }
                }
                "AUTO" => retract = Retract::Initial,
                "MMPM" | "IPM" | "MMPR" | "IPR" => {
                    let v = value(&mut rest, "CYCLE/ feed", false)?;
                    let inch = if w.starts_with('I') { 25.4 } else { 1.0 };
                    let mode = if w.ends_with("PM") {
                        FeedMode::PerMinute
                    } else {
                        FeedMode::PerRevolution
                    };
                    feed = Some((mode, v.abs() * inch));
                }
                "DWELL" => {
                    if rest.peek().is_some_and(|n| word(n) == "SEC") {
                        rest.next();
                    }
                    dwell_s = value(&mut rest, "CYCLE/ DWELL", false)?.abs();
                }
                "STEP" | "INCR" | "PECK" => {
                    let at = rest.peek().map_or(*f, |n| **n);
                    let s = value(&mut rest, "CYCLE/ peck depth", true)?.abs();
                    if s <= 0.0 {
                        return Err(self.error(
                            rec,
                            at.off,
                            PathErrorKind::Semantic,
                            "CYCLE/: a peck depth of zero",
                            at.text,
                            "a peck depth greater than zero",
                        ));
                    }
                    peck = Some((s, at));
                    // NX writes a second step for the later pecks; the first is kept.
                    while rest
                        .peek()
                        .is_some_and(|n| self.number(rec, **n, "").is_ok())
                    {
                        rest.next();
                    }
                }
                _ => {
                    let Ok(v) = self.number(rec, *f, "CYCLE/") else {
                        return Err(self.error(
                            rec,
                            f.off,
                            PathErrorKind::Syntax,
                            format!("CYCLE/: unknown word {}", f.text),
                            f.text,
                            "FEDTO, RAPTO, RTRCTO, MMPM, IPM, MMPR, IPR, DWELL, STEP or a number",
                        ));
                    };
                    let v = self.cycle_length(rec, *f, v)?;
                    // APT's positional form: depth, then clearance.
                    if depth.is_none() {
                        depth = Some(v.abs());
                    } else if clearance.is_none() {
                        clearance = Some(v);
                        clearance_at = *f;
                    } else if matches!(kind, Kind::Deep | Kind::ChipBreak) && peck.is_none() {
                        // A peck cycle's third number is its step (which changes the cycle's
                        // time, not what it removes).
                        if v == 0.0 {
                            return Err(self.error(
                                rec,
                                f.off,
                                PathErrorKind::Semantic,
                                "CYCLE/: a peck depth of zero",
                                f.text,
                                "a peck depth greater than zero",
                            ));
                        }
                        peck = Some((v.abs(), *f));
                    } else {
                        return Err(self.error(
                            rec,
                            f.off,
                            PathErrorKind::Syntax,
                            "CYCLE/: a third bare number (depth and clearance already given)",
                            f.text,
                            "a keyword (RTRCTO, DWELL, STEP, …) before it",
                        ));
                    }
                }
            }
        }
        let Some(depth) = depth else {
            return Err(self.error(
                rec,
                first.off,
                PathErrorKind::Semantic,
                format!("CYCLE/{} without a depth", first.text),
                rec.text.trim(),
                "FEDTO,d (or the depth as the first number)",
            ));
        };
        if matches!(kind, Kind::Deep | Kind::ChipBreak) && peck.is_none() {
            // A peck cycle without its step drills in one go.
            kind = Kind::Drill;
        }
        let clearance = clearance.unwrap_or(0.0);
        // A level below the hole's bottom would rapid into the material or feed upwards to the
        // bottom (LinuxCNC refuses an R plane below the hole's Z too).
        for (level, at, what) in [
            (Some(clearance), clearance_at, "clearance (RAPTO)"),
            (
                match retract {
                    Retract::At(r) => Some(r),
                    _ => None,
                },
                retract_at,
                "retract height (RTRCTO)",
            ),
        ] {
            if let Some(level) = level.filter(|l| *l < -depth) {
                return Err(self.error(
                    rec,
                    at.off,
                    PathErrorKind::Semantic,
                    format!(
                        "CYCLE/: the {what} {level} mm lies below the hole's bottom ({} mm)",
                        -depth
                    ),
                    at.text,
                    "a level at or above the bottom",
                ));
            }
        }
        if let Some((s, f)) = peck {
            if (clearance + depth) / s > MAX_PECKS {
                return Err(self.error(
                    rec,
                    f.off,
                    PathErrorKind::Semantic,
                    format!(
                        "CYCLE/: a peck of {s} mm makes more than {MAX_PECKS} pecks in a hole \
                         {} mm deep from the clearance",
                        clearance + depth
                    ),
                    f.text,
                    "a peck depth of at least 1/100000 of the hole",
                ));
            }
        }
        let c = Cycle {
            kind,
            depth,
            clearance,
            retract,
            feed,
            dwell_s,
            peck: peck.map(|p| p.0),
        };
        self.cycle = Some(c);
        self.last_cycle = Some(c);
        Ok(())
    }

    /// A cycle's length `v` (program units, as written in `f`) in mm, within the machine's
    /// range.
    fn cycle_length(&self, rec: &Record<'_>, f: Field<'_>, v: f64) -> Result<f64, PathError> {
        let mm = v * self.scale;
        if mm.abs() <= MACHINE_RANGE_MM {
            return Ok(mm);
        }
        Err(self.error(
            rec,
            f.off,
            PathErrorKind::Semantic,
            format!(
                "CYCLE/ distance {mm:e} mm is beyond the machine range of ±{MACHINE_RANGE_MM:e} mm"
            ),
            f.text,
            "a distance within ±1e6 mm",
        ))
    }

    /// One hole of the active cycle at `top` (workpiece frame, mm), along `axis` or the current
    /// tool axis.
    pub(super) fn drill(&mut self, line: u32, cycle: Cycle, top: Vec3, axis: Option<Vec3>) {
        self.state_axis(line, axis);
        self.rapid_next = false;
        if let Some(c) = self.circle.take() {
            self.warn(
                c.line,
                c.column,
                format!(
                    "CIRCLE/ ignored: the GOTO/ on line {line} drills a hole of the active CYCLE/"
                ),
            );
        }
        let a = self.axis;
        let at = |h: f64| top + a * h;
        let start = match self.pos {
            Some(q) => q,
            None => {
                // No position before the first hole: the tool starts above it.
                let q = at(cycle.clearance);
                self.sink.emit(line, &Canon::SetPosition(axes(q)));
                self.pos = Some(q);
                q
            }
        };
        let initial = a.dot(start - top).max(cycle.clearance);
        self.go(line, start + a * (initial - a.dot(start - top)), true);
        self.go(line, at(initial), true);
        self.go(line, at(cycle.clearance), true);
        if let Some((mode, f)) = cycle.feed {
            if mode != self.feed_mode {
                self.sink.emit(line, &Canon::FeedMode(mode));
            }
            self.sink.emit(line, &Canon::FeedRate(f));
        }
        let bottom = -cycle.depth;
        if let (Kind::Deep | Kind::ChipBreak, Some(step)) = (cycle.kind, cycle.peck) {
            let mut depth = cycle.clearance - step;
            while depth > bottom {
                self.go(line, at(depth), false);
                if cycle.kind == Kind::Deep {
                    self.go(line, at(cycle.clearance), true);
                }
                self.go(line, at(depth + PECK_CLEARANCE_MM), true);
                depth -= step;
            }
        }
        self.go(line, at(bottom), false);
        if cycle.dwell_s > 0.0 {
            self.sink.emit(line, &Canon::Dwell(cycle.dwell_s));
        }
        let out = match cycle.retract {
            Retract::Clearance => cycle.clearance,
            Retract::Initial => initial,
            Retract::At(r) => r,
        };
        if cycle.kind == Kind::FeedOut {
            self.go(line, at(out.min(cycle.clearance)), false);
        }
        self.go(line, at(out), true);
        if let Some((mode, _)) = cycle.feed {
            if mode != self.feed_mode {
                self.sink.emit(line, &Canon::FeedMode(self.feed_mode));
            }
            // Without a FEDRAT/ before the cycle, no feed was in effect: none is again.
            self.sink
                .emit(line, &Canon::FeedRate(self.program_feed.unwrap_or(0.0)));
        }
    }

    /// A rapid or feed to `p` unless the tool is there.
    fn go(&mut self, line: u32, p: Vec3, rapid: bool) {
        if self.pos.is_some_and(|q| (q - p).length() <= 1e-12) {
            return;
        }
        let end = axes(p);
        let ev = if rapid {
            Canon::Traverse { end }
        } else {
            Canon::Feed { end }
        };
        self.sink.emit(line, &ev);
        self.pos = Some(p);
    }
}
