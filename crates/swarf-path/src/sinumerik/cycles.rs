//! Sinumerik cycles: drilling (`CYCLE81`–`CYCLE86`, `CYCLE89`) along the tool axis at the
//! tool's position, the swivel plane `CYCLE800`, and `CYCLE832` (noted).
//!
//! Drilling parameters, by position: `RTP` retraction plane, `RFP` reference plane (the
//! surface), `SDIS` safety distance, `DP` final depth (absolute) or `DPR` depth below `RFP`,
//! then per cycle `DTB` (dwell at depth, s), `CYCLE83`'s `FDEP`/`FDPR` (first depth), `DAM`
//! (degression), `DTS` (dwell at the top when removing chips), `FRF` (feed factor for the first
//! depth), `VARI` (0 chip breaking: back `_VRT`, 1 mm by default; 1 chip removal: out to the
//! safety distance, back in at rapid to `_DIS1` above the depth reached, by default the cycle's
//! own 0.6 mm to 7 mm), `CYCLE84`'s `MPIT`/`PIT` (thread size or pitch: the feed is the pitch per
//! spindle revolution), `CYCLE85`'s `FFR`/`RFF` (feeds in and out). The tool goes at rapid to
//! the safety distance above `RFP`, feeds to the depth, and leaves at rapid (or the cycle's
//! feed) to the retraction plane.
//!
//! `CYCLE800(_FR, _TC, _ST, _MODE, _X0, _Y0, _Z0, _A, _B, _C, _X1, _Y1, _Z1, _DIR, …)` in its
//! axis-by-axis modes (`_MODE` bits 7–6 zero; bits 0–5 the order of the rotation axes, two bits
//! each, 1 = X, 2 = Y, 3 = Z, first axis lowest): the frame is moved to `_X0 _Y0 _Z0`, turned
//! about the named axes in turn (each about the already turned frame's), then moved by `_X1 _Y1
//! _Z1` in the turned frame; the tool turns normal to the plane. `_ST` ending in 1 adds to the
//! plane in effect. No arguments, or all angles and offsets zero, resets.

use super::words::args;
use super::{Block, Reader, Res};
use crate::part_frame::{mat, rx, ry, rz, Mat};
use crate::{Canon, FeedMode, PathErrorKind};

/// Most pecks one cycle call may make.
const MAX_PECKS: f64 = 10_000.0;

/// Coarse metric thread pitches (ISO 261) by nominal diameter, for `CYCLE84`'s `MPIT`.
const METRIC: [(f64, f64); 19] = [
    (3.0, 0.5),
    (4.0, 0.7),
    (5.0, 0.8),
    (6.0, 1.0),
    (8.0, 1.25),
    (10.0, 1.5),
    (12.0, 1.75),
    (14.0, 2.0),
    (16.0, 2.0),
    (18.0, 2.5),
    (20.0, 2.5),
    (22.0, 2.5),
    (24.0, 3.0),
    (27.0, 3.0),
    (30.0, 3.5),
    (33.0, 3.5),
    (36.0, 4.0),
    (42.0, 4.5),
    (48.0, 5.0),
];

impl Reader<'_> {
    /// The call `name(args)` at byte `at` of block `b`.
    pub(super) fn cycle(&mut self, b: &Block, name: &str, at: usize, a: &str) -> Res<()> {
        if name == "CYCLE832" {
            // (Its arguments name the control's tolerance modes: nothing to evaluate.)
            self.warn_once(
                "cycle832",
                b.line,
                super::col(b, at),
                "CYCLE832 (path smoothing) is not read: swarf follows the programmed path \
                 exactly"
                    .into(),
            );
            return Ok(());
        }
        let parts = args(a);
        // Each argument's value (`None` when left empty).
        let mut v = Vec::with_capacity(parts.len());
        let base = at + name.len() + 1;
        let mut off = 0;
        for p in &parts {
            let pos = a[off..].find(p).map_or(off, |i| i + off);
            off = pos + p.len();
            v.push(if p.is_empty() || p.starts_with('"') {
                None
            } else {
                Some(self.eval(b, base + pos, p)?)
            });
        }
        let get = |i: usize| v.get(i).copied().flatten();
        match name {
            "CYCLE800" => self.cycle800(b, at, &v),
            _ => self.drill(b, at, name, &get),
        }
    }

    fn cycle800(&mut self, b: &Block, at: usize, v: &[Option<f64>]) -> Res<()> {
        let g = |i: usize| v.get(i).copied().flatten().unwrap_or(0.0);
        let refuse = |m: &str| {
            Reader::fault(
                b,
                at,
                PathErrorKind::Unsupported,
                m,
                "CYCLE800 by axis-by-axis angles",
            )
        };
        let mode = g(3) as i64;
        let (a, bb, c) = (g(7), g(8), g(9));
        let r0 = [g(4), g(5), g(6)].map(|x| x * self.scale);
        let r1 = [g(10), g(11), g(12)].map(|x| x * self.scale);
        let reset = v.iter().all(Option::is_none)
            || (a == 0.0 && bb == 0.0 && c == 0.0 && r0 == [0.0; 3] && r1 == [0.0; 3]);
        if reset {
            // `CYCLE800()` deselects the swivel data: the frames go, the rotary axes stay
            // where they are (the tool keeps its axis until the program turns one); a reset
            // to zero angles with a swivel direction (`_DIR` ≠ 0) turns them back.
            let tilted = self.frame.tilt.is_some();
            self.swivel = None;
            self.set_chain(b.line, self.trans, self.rot);
            let stays = v.iter().all(Option::is_none) || g(13) == 0.0;
            if tilted && !stays {
                self.emit(b.line, Canon::MachineAxis);
            }
            return Ok(());
        }
        if mode & 0xC0 != 0 {
            return Err(refuse(
                "CYCLE800 by solid or projection angles or by rotary axis positions is not read",
            ));
        }
        if g(0) != 0.0 {
            self.warn_once(
                "cycle800fr",
                b.line,
                super::col(b, at),
                "CYCLE800's retract (_FR) is not made: the tool swivels where it stands".into(),
            );
        }
        // The rotation axes, lowest bits first, each turning the frame turned before.
        let mut r: Mat = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let angles = [a, bb, c];
        for (k, angle) in angles.into_iter().enumerate() {
            let turn = match (mode >> (2 * k)) & 3 {
                1 => rx(angle),
                2 => ry(angle),
                3 => rz(angle),
                _ => return Err(refuse("CYCLE800's _MODE names no rotation axis")),
            };
            r = mat(&r, &turn);
        }
        // `_ST` ending in 1 adds to the swivel in effect: its pivot moved by _X0… along its
        // turned axes, its turn turned further.
        let additive = (g(2) as i64) % 10 == 1;
        self.swivel = Some(match (additive, self.swivel) {
            (true, Some((p0, r0m, o0))) => {
                let d = crate::part_frame::mul(&r0m, std::array::from_fn(|k| o0[k] + r0[k]));
                (std::array::from_fn(|k| p0[k] + d[k]), mat(&r0m, &r), r1)
            }
            _ => (r0, r, r1),
        });
        self.set_chain(b.line, self.trans, self.rot);
        Ok(())
    }

    fn drill(
        &mut self,
        b: &Block,
        at: usize,
        name: &str,
        get: &dyn Fn(usize) -> Option<f64>,
    ) -> Res<()> {
        let s = self.scale;
        let (rtp, rfp, sdis) = (
            get(0).unwrap_or(self.c.pos[self.c.plane.axes().2] / s) * s,
            get(1).unwrap_or(0.0) * s,
            get(2).unwrap_or(0.0).abs() * s,
        );
        // Both given: the depth comes from DPR.
        let depth = match (get(3), get(4)) {
            (_, Some(dpr)) => rfp - dpr.abs() * s,
            (Some(dp), None) => dp * s,
            (None, None) => {
                return Err(Reader::fault(
                    b,
                    at,
                    PathErrorKind::Semantic,
                    format!("{name} without a depth (DP or DPR)"),
                    "the fourth or fifth argument",
                ))
            }
        };
        if depth > rfp {
            return Err(Reader::fault(
                b,
                at,
                PathErrorKind::Semantic,
                "the drilling depth is above the reference plane",
                "DP below RFP",
            ));
        }
        let f = self.feed.ok_or_else(|| {
            Reader::fault(
                b,
                at,
                PathErrorKind::Semantic,
                "a drilling cycle before any feed rate",
                "F<feed>",
            )
        });
        let per_min = FeedMode::PerMinute;
        let fs = if self.feed_mode == FeedMode::InverseTime {
            1.0
        } else {
            self.feed_scale
        };
        // (feed, mode), retract (None: rapid), dwell at depth, first peck, degression, break.
        let (feed, retract, dwell, first, dam, chip_break) = match name {
            "CYCLE81" => ((f?, self.feed_mode), None, 0.0, 0.0, 0.0, false),
            "CYCLE82" => (
                (f?, self.feed_mode),
                None,
                get(5).unwrap_or(0.0),
                0.0,
                0.0,
                false,
            ),
            "CYCLE83" => {
                let first = match (get(5), get(6)) {
                    (Some(d), _) => rfp - d * s,
                    (None, Some(d)) => d.abs() * s,
                    _ => 0.0,
                };
                let vari = get(11).unwrap_or(0.0);
                let f = f?;
                (
                    (f, self.feed_mode),
                    None,
                    get(8).unwrap_or(0.0),
                    first,
                    get(7).unwrap_or(0.0).abs() * s,
                    vari == 0.0,
                )
            }
            "CYCLE84" => {
                let pit = get(8).unwrap_or(0.0).abs() * s;
                let pitch = if pit > 0.0 {
                    pit
                } else {
                    let m = get(7).unwrap_or(0.0).abs();
                    METRIC
                        .iter()
                        .find(|(d, _)| (*d - m).abs() < 1e-9)
                        .map(|(_, p)| *p)
                        .ok_or_else(|| {
                            Reader::fault(
                                b,
                                at,
                                PathErrorKind::Semantic,
                                "CYCLE84 without a pitch (PIT) or a coarse metric thread size (MPIT)",
                                "PIT or MPIT",
                            )
                        })?
                };
                let sync = FeedMode::SpindleSynchronised;
                (
                    (pitch, sync),
                    Some((pitch, sync)),
                    get(5).unwrap_or(0.0),
                    0.0,
                    0.0,
                    false,
                )
            }
            "CYCLE85" => {
                let ffr = get(6).map(|x| x * fs);
                let rff = get(7).map(|x| x * fs);
                let f = match ffr {
                    Some(x) if x > 0.0 => x,
                    _ => f?,
                };
                let r = rff.filter(|x| *x > 0.0).unwrap_or(f);
                (
                    (f, per_min),
                    Some((r, per_min)),
                    get(5).unwrap_or(0.0),
                    0.0,
                    0.0,
                    false,
                )
            }
            "CYCLE86" => (
                (f?, self.feed_mode),
                None,
                get(5).unwrap_or(0.0),
                0.0,
                0.0,
                false,
            ),
            "CYCLE89" => {
                let f = f?;
                (
                    (f, self.feed_mode),
                    Some((f, self.feed_mode)),
                    get(5).unwrap_or(0.0),
                    0.0,
                    0.0,
                    false,
                )
            }
            _ => {
                return Err(Reader::fault(
                    b,
                    at,
                    PathErrorKind::Unsupported,
                    format!(
                        "{name} is not read (swarf runs CYCLE81–CYCLE86, CYCLE89 and CYCLE800)"
                    ),
                    "a drilling cycle",
                ))
            }
        };
        if feed.0 <= 0.0 {
            return Err(Reader::fault(
                b,
                at,
                PathErrorKind::Semantic,
                "the cycle's feed is zero",
                "a positive feed",
            ));
        }
        let total = rfp - depth;
        if first > 0.0 && total / first.min(if dam > 0.0 { dam } else { first }) > MAX_PECKS {
            return Err(Reader::fault(
                b,
                at,
                PathErrorKind::Limit,
                "the cycle makes more than 10,000 pecks",
                "a larger first depth or degression",
            ));
        }
        let line = b.line;
        let top = rfp + sdis;
        let c83 = name == "CYCLE83";
        let arg = |i: usize| get(i).filter(|x| *x > 0.0);
        // CYCLE83, by the 840D cycles manual (its sequence of motions and parameter list):
        // - FRF (feed factor, 0.001…1) scales the feed to the first drilling depth only; 0 or
        //   not given is 1.
        // - VARI = 0 (chip breaking): back by _VRT after each depth, 0 or not given is the
        //   manual's 1 mm. The manual's "1 mm" is taken in the program's units, as swarf did
        //   before (an inch program backs 1 in); the manual does not say, so that stays.
        // - VARI = 1 (chip removal): out to SDIS above RFP, dwell DTS there ("dwell at the
        //   starting point and for chip removal"; seconds, only a positive value), then at rapid
        //   to the advance distance _DIS1 above the depth reached. _DIS1 0 or not given: the
        //   cycle's own, 0.6 mm up to a drilling depth of 30 mm, above that the drilling depth
        //   / 50, at most 7 mm. "Drilling depth" is read as the hole's depth below RFP (the
        //   manual's name for DP/DPR), so one distance serves the whole call; in the program's
        //   units like _VRT's default.
        // - DTB stays a dwell at the final depth only: the manual's sequence lists it after
        //   the first depth and says the sequence repeats, but newer cycles move the final
        //   depth's dwell to _DTD; ambiguous, so swarf's former reading stays.
        let first_feed = if c83 {
            (feed.0 * arg(10).unwrap_or(1.0), feed.1)
        } else {
            feed
        };
        let back = arg(14).unwrap_or(1.0) * s;
        let ahead = match arg(16) {
            Some(d) => d * s,
            None => {
                let d = total / s;
                (if d <= 30.0 { 0.6 } else { (d / 50.0).min(7.0) }) * s
            }
        };
        let at_top = if c83 { arg(9).unwrap_or(0.0) } else { 0.0 };
        self.axis_to(line, top, None);
        let mut reached = 0.0;
        let mut peck = first;
        loop {
            let next = if peck > 0.0 {
                (reached + peck).min(total)
            } else {
                total
            };
            let fd = if reached == 0.0 { first_feed } else { feed };
            self.axis_to(line, rfp - next, Some(fd));
            reached = next;
            if reached >= total {
                break;
            }
            if chip_break {
                self.axis_to(line, rfp - reached + back, None);
            } else {
                self.axis_to(line, top, None);
                if at_top > 0.0 {
                    self.emit(line, Canon::Dwell(at_top));
                }
                self.axis_to(line, (rfp - reached + ahead).min(top), None);
            }
            if dam > 0.0 {
                peck = (peck - dam).max(dam);
            }
        }
        if dwell > 0.0 {
            self.emit(line, Canon::Dwell(dwell));
        }
        if let Some(r) = retract {
            self.axis_to(line, top, Some(r));
        }
        self.axis_to(line, rtp, None);
        Ok(())
    }

    fn axis_to(&mut self, line: u32, to: f64, feed: Option<(f64, FeedMode)>) {
        let (_, _, n) = self.c.plane.axes();
        let mut end = self.c.pos;
        end[n] = to;
        if let Some((f, mode)) = feed {
            let events: Vec<Canon<'static>> = self.c.feed(mode, f).collect();
            for e in events {
                self.emit(line, e);
            }
        }
        self.line_to(line, end, feed.is_none());
    }
}
