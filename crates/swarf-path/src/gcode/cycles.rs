//! Canned cycles G73 G74 G81–G89, expanded into traverses, feeds, dwells and spindle events
//! exactly as LinuxCNC 2.9's `convert_cycle_xy`/`_zx`/`_yz` and `CYCLE_MACRO` do (checked call
//! for call against its `rs274`), in any plane, absolute or incremental, with `L` repeats,
//! G98/G99 retract modes and polar holes (`@` `^`, G17 only; in G91 the radius and the angle
//! grow at every repeat: `G91 G81 ^60 L6` drills a bolt circle).
//!
//! Tapping (G84 right hand, G74 left hand) feeds down, reverses the spindle, dwells `P` and
//! feeds back out at the same feed to the clearance level (R for G99, the initial level for
//! G98), then restores the spindle. Boring: G85 feeds out to R and rapids to the clearance
//! level; G89 dwells and feeds all the way out to it; G86 stops the spindle at the bottom and
//! rapids out; G88 stops it and pauses — the operator takes the tool out by hand, so there is
//! no programmed move out: the tool is put at the clearance level without one
//! ([`Canon::SetPosition`]) — and restarts it; G87 (back boring) moves off by `I`/`J`, stops
//! the spindle, rapids down to the bottom, comes back to the hole, starts the spindle, feeds up
//! to `K` (in G91 counted from the bottom), feeds back down, stops, moves off again and rapids
//! out — the twelve steps of the LinuxCNC manual's G87.
//!
//! In the plane's own coordinates (`aa`, `bb` in the plane, `cc` along its normal — Z for G17):
//! the *initial level* is the level where the cycle mode began, kept until G80 or a G00–G03
//! cancels the mode (through changes of cycle, retract mode or plane); in G91, R is measured
//! from it and the bottom from R, for every hole. LinuxCNC: if the initial level is below R
//! the tool first rises to R where it stands (at every block of the mode, a move of no length
//! once there); the first hole is reached at the clearance level (R for G99, the higher of the
//! initial level and R for G98) or where the tool is if higher; then, for each repeat, it goes
//! down to R if not there, runs the cycle body and retracts to the clearance level. Fanuc
//! starts from the tool's own level, rising to R if below it, and G98 returns to the higher of
//! the initial level and R.

use super::block::{group, Block};
use super::interp::{Interp, AXIS_LETTERS};
use super::{Fault, Res, Span};
use crate::{Axes, Canon, FeedMode, PathErrorKind, Plane, SpindleDir};

/// LinuxCNC's `G83_RAPID_DELTA`: 0.010 inch, how far above the last depth a peck re-enters.
const RAPID_DELTA_MM: f64 = 0.010 * 25.4;

impl Interp<'_, '_> {
    /// A point from the cycle's plane coordinates.
    fn cycle_point(&self, aa: f64, bb: f64, cc: f64) -> [f64; 6] {
        let (fi, si, ni) = self.plane.axes();
        let mut p = self.p;
        p[fi] = aa;
        p[si] = bb;
        p[ni] = cc;
        p
    }

    fn cyc_traverse(&mut self, aa: f64, bb: f64, cc: f64) {
        let p = self.cycle_point(aa, bb, cc);
        self.emit(Canon::Traverse {
            end: Axes::from_array(p),
        });
    }

    /// A tapping feed. LinuxCNC (its `g84` tests, G18 and G19) writes the feed moves of a
    /// tapping cycle in the ZX plane with the YZ plane's axes and the other way round; the
    /// control moves as its canonical calls say, so swarf does the same (and says so).
    /// A Fanuc control taps along the plane's drilling axis as it drills, so under Fanuc's
    /// rules the feeds are the plane's own.
    fn tap_feed(&mut self, aa: f64, bb: f64, cc: f64) {
        let swapped = match self.plane {
            _ if self.fanuc => self.plane,
            Plane::XY => Plane::XY,
            Plane::XZ => Plane::YZ,
            Plane::YZ => Plane::XZ,
        };
        let (fi, si, ni) = swapped.axes();
        let mut p = self.p;
        p[fi] = aa;
        p[si] = bb;
        p[ni] = cc;
        if swapped != self.plane && !self.tap_quirk_warned {
            self.tap_quirk_warned = true;
            self.warn_at(
                0,
                "tapping outside G17: the feed moves follow LinuxCNC, which swaps the axes of \
                 the ZX and YZ planes in them"
                    .into(),
            );
        }
        self.emit(Canon::Feed {
            end: Axes::from_array(p),
        });
    }

    fn cyc_spindle(&mut self, dir: SpindleDir) {
        self.emit(Canon::Spindle { rpm: self.rpm, dir });
    }

    fn cyc_feed(&mut self, aa: f64, bb: f64, cc: f64) {
        let p = self.cycle_point(aa, bb, cc);
        self.emit(Canon::Feed {
            end: Axes::from_array(p),
        });
    }

    /// LinuxCNC's refusals, at the hole (after the moves to it): tapping needs the spindle
    /// turning the tap's way, boring needs it turning.
    fn check_spindle(&self, motion: u16, span: Span) -> Res<()> {
        let g = motion / 10;
        let problem = match (motion, self.dir) {
            (840, SpindleDir::CounterClockwise) => "turning counterclockwise",
            (740, SpindleDir::Clockwise) => "turning clockwise",
            (740 | 840 | 860..=880, SpindleDir::Stopped) => "not turning",
            _ => return Ok(()),
        };
        let fix = match motion {
            840 => "M3 before a right-hand tapping cycle",
            740 => "M4 before a left-hand tapping cycle",
            _ => "M3 or M4 before the cycle",
        };
        Err(Fault::new(
            PathErrorKind::Semantic,
            span,
            format!("spindle {problem} in G{g} canned cycle"),
            fix,
        ))
    }

    /// Runs canned cycle `motion` (G code × 10) for one block; `old_motion` is the motion mode
    /// before the block (a repeated cycle may omit R and the depth).
    pub(crate) fn cycle(&mut self, b: &Block, motion: u16, old_motion: Option<u16>) -> Res<()> {
        let gspan = b
            .g(group::MOTION)
            .map_or(Span::Line, |_| b.g_span(group::MOTION));
        let (fi, si, ni) = self.plane.axes();
        let (fl, sl, nl) = (AXIS_LETTERS[fi], AXIS_LETTERS[si], AXIS_LETTERS[ni]);
        let nname = (nl as char).to_ascii_uppercase();
        let same = old_motion == Some(motion);
        if self.comp.on() {
            return Err(Fault::semantic(
                gspan,
                "cannot use canned cycles with cutter radius compensation on",
            ));
        }
        if self.g51.is_some() {
            return Err(Fault::new(
                PathErrorKind::Unsupported,
                gspan,
                "canned cycles under G51 scaling are not read",
                "G50 before the cycle",
            ));
        }
        if self.feed_mode == FeedMode::InverseTime {
            return Err(Fault::semantic(
                gspan,
                "canned cycles cannot be used in inverse time feed mode (G93)",
            ));
        }
        // Polar holes (`@` radius, `^` angle, XY plane only): in G90 the hole's place from the
        // origin, the missing one taken from where the tool is; in G91 increments of the
        // radius and the angle applied at every repeat (a bolt circle: `G91 G81 ^60 L6`).
        let polar = b.has(b'@') || b.has(b'^');
        if polar {
            let c = if b.has(b'@') { b'@' } else { b'^' };
            if self.plane != Plane::XY {
                return Err(Fault::new(
                    PathErrorKind::Semantic,
                    b.span(c),
                    "polar coordinates (@ ^) cannot be used outside the G17 plane",
                    "G17, or the plane's own axis words",
                ));
            }
            if b.has(b'x') || b.has(b'y') {
                let c = if b.has(b'x') { b'x' } else { b'y' };
                return Err(Fault::semantic(
                    b.span(c),
                    "X or Y cannot be used with polar coordinates (@ ^)",
                ));
            }
        }
        // Fanuc and Haas (4th-axis drilling posts) turn a rotary axis the block names in the
        // cycle's positioning step, with X and Y; LinuxCNC refuses it.
        let mut rotary: [Option<f64>; 3] = [None; 3];
        for (k, c) in [b'a', b'b', b'c'].into_iter().enumerate() {
            if let Some(v) = b.get(c) {
                if !self.fanuc {
                    return Err(Fault::semantic(
                        b.span(c),
                        "rotary axis words cannot be used in a canned cycle",
                    ));
                }
                if !v.is_finite() {
                    return Err(Fault::semantic(
                        b.span(c),
                        "canned cycle positions are out of range (not finite numbers)",
                    ));
                }
                rotary[k] = Some(v);
            }
        }
        if !same && !b.has(nl) {
            return Err(Fault::new(
                PathErrorKind::Semantic,
                gspan,
                format!("{nname} value unspecified in canned cycle"),
                format!("{nname}, the bottom of the hole"),
            ));
        }
        let cc_word = b.get(nl).map_or(self.cycle.cc, |v| v * self.scale);
        let r_word = match b.get(b'r') {
            Some(r) => r * self.scale,
            None if same => self.cycle.r,
            None => {
                return Err(Fault::new(
                    PathErrorKind::Semantic,
                    gspan,
                    "R clearance plane unspecified in canned cycle",
                    "R",
                ))
            }
        };
        // LinuxCNC 2.9 leaves G74 out of the codes an L word may go with.
        if !self.fanuc && motion == 740 && b.has(b'l') {
            return Err(Fault::new(
                PathErrorKind::Semantic,
                b.span(b'l'),
                "L word with G74: LinuxCNC repeats no left-hand tapping cycle",
                "one G74 block per hole",
            ));
        }
        // Fanuc counts repeats with K (L on older controls), and K0 / L0 stores the cycle's
        // data without drilling where the tool is.
        let (rw, least) = match self.fanuc {
            true if b.has(b'k') && motion != 870 => (b'k', 0.0),
            true => (b'l', 0.0),
            false => (b'l', 1.0),
        };
        let repeats = match b.get(rw) {
            None => 1,
            Some(l) if l.fract() != 0.0 || l < least => {
                return Err(Fault::new(
                    PathErrorKind::Semantic,
                    b.span(rw),
                    "bad number of canned cycle repeats",
                    if least == 0.0 {
                        "K or L, a non-negative integer"
                    } else {
                        "L, a positive integer"
                    },
                ))
            }
            Some(l) if l > self.opts.max_repeat as f64 => {
                return Err(Fault::new(
                    PathErrorKind::Limit,
                    b.span(rw),
                    format!(
                        "{}{l} asks for more than {} repeats (the reader's limit on repeats)",
                        char::from(rw.to_ascii_uppercase()),
                        self.opts.max_repeat
                    ),
                    "",
                ))
            }
            Some(l) => l as u64,
        };
        if self.feed <= 0.0 {
            return Err(Fault::new(
                PathErrorKind::Semantic,
                gspan,
                "canned cycle with zero feed rate",
                "an F word",
            ));
        }
        // LinuxCNC asks G86 and G88 for their dwell as G82 and G89 (a Fanuc G86 has none).
        let dwell = if matches!(motion, 740 | 840) || (self.fanuc && matches!(motion, 860 | 880)) {
            match b.get(b'p') {
                Some(p) if p >= 0.0 => self.dwell_seconds(b, b'p', p),
                Some(_) => return Err(Fault::semantic(b.span(b'p'), "negative dwell time")),
                None if same => self.cycle.p,
                None => 0.0,
            }
        } else if matches!(motion, 820 | 890 | 860 | 880) {
            match b.get(b'p') {
                Some(p) if p >= 0.0 => self.dwell_seconds(b, b'p', p),
                Some(_) => return Err(Fault::semantic(b.span(b'p'), "negative dwell time")),
                None if same => self.cycle.p,
                None => {
                    return Err(Fault::new(
                        PathErrorKind::Semantic,
                        gspan,
                        "dwell time P missing in canned cycle",
                        if self.fanuc {
                            "P<milliseconds>"
                        } else {
                            "P<seconds>"
                        },
                    ))
                }
            }
        } else {
            0.0
        };
        let delta = if matches!(motion, 730 | 830) {
            match b.get(b'q') {
                Some(q) if q > 0.0 => q * self.scale,
                Some(_) => {
                    return Err(Fault::semantic(
                        b.span(b'q'),
                        "the peck increment Q must be positive",
                    ))
                }
                None if same => self.cycle.q,
                None => {
                    return Err(Fault::new(
                        PathErrorKind::Semantic,
                        gspan,
                        "Q word missing in peck cycle",
                        "Q<increment>",
                    ))
                }
            }
        } else {
            0.0
        };
        let mut back_bore_words = self.cycle.back_bore;
        let (back_bore_offset, back_bore_k) = if motion == 870 {
            let off = [b'i', b'j', b'k'];
            let (oi, oj, ok) = (off[fi], off[si], off[ni]);
            // A G87 repeated without them keeps the last I J K (LinuxCNC's `cycle_i/j/k`).
            let need = |c: u8, kept: f64| {
                b.get(c)
                    .map(|v| v * self.scale)
                    .or(same.then_some(kept))
                    .ok_or_else(|| {
                        Fault::new(
                            PathErrorKind::Semantic,
                            gspan,
                            format!(
                                "{} word missing in G87 back boring",
                                (c as char).to_ascii_uppercase()
                            ),
                            "I, J (the offset to pass the hole) and K (the back bore's level)",
                        )
                    })
            };
            let kept = self.cycle.back_bore;
            let (i, j, k) = (need(oi, kept[0])?, need(oj, kept[1])?, need(ok, kept[2])?);
            back_bore_words = [i, j, k];
            (Some((i, j)), k)
        } else {
            (None, 0.0)
        };
        // The initial level: the level along the plane's normal where the canned-cycle mode
        // began (its first block after G80 or a G00–G03), kept for every later block of the
        // mode, through changes of cycle, retract mode or plane (LinuxCNC's `cycle_il`, Fanuc's
        // initial point level). A G91 R counts from it. LinuxCNC starts each block's moves at
        // it (first rising to R where the tool stands when it is below R), so G98 returns to
        // it after G99 holes; Fanuc starts at the tool's level and returns to the higher of
        // the initial level and R.
        let current_cc = self.p[ni];
        let in_cycle_mode = matches!(old_motion, Some(730 | 740 | 810..=890));
        let initial = match self.initial_level {
            Some(z) if in_cycle_mode => z,
            _ => current_cc,
        };
        self.initial_level = Some(initial);
        let mut old_cc = if self.fanuc { current_cc } else { initial };
        let (mut aa, mut bb, aa_inc, bb_inc, r, cc);
        let (mut radius_inc, mut theta_inc) = (0.0, 0.0);
        if self.absolute {
            aa_inc = 0.0;
            bb_inc = 0.0;
            r = r_word;
            cc = cc_word;
            if polar {
                // `@` radius and `^` angle from the origin, as for G0/G1.
                let e = self.find_ends(b, false)?;
                (aa, bb) = (e[0], e[1]);
            } else {
                aa = b.get(fl).map_or(self.p[fi], |v| v * self.scale);
                bb = b.get(sl).map_or(self.p[si], |v| v * self.scale);
            }
        } else {
            aa_inc = b.get(fl).map_or(0.0, |v| v * self.scale);
            bb_inc = b.get(sl).map_or(0.0, |v| v * self.scale);
            if polar {
                radius_inc = b.get(b'@').map_or(0.0, |v| v * self.scale);
                theta_inc = b.get(b'^').map_or(0.0, f64::to_radians);
            }
            r = r_word + initial;
            cc = r + cc_word;
            aa = self.p[fi];
            bb = self.p[si];
        }
        // G87's K: the back bore's level, from the bottom of the hole in G91 (LinuxCNC).
        let back_bore_k = if self.absolute {
            back_bore_k
        } else {
            cc + back_bore_k
        };
        let n = repeats as f64;
        if ![
            aa,
            bb,
            r,
            cc,
            back_bore_k,
            aa + aa_inc * n,
            bb + bb_inc * n,
            aa.hypot(bb) + radius_inc.abs() * n,
        ]
        .iter()
        .all(|v| v.is_finite())
        {
            return Err(Fault::semantic(
                gspan,
                "canned cycle positions are out of range (not finite numbers)",
            ));
        }
        if r < cc {
            return Err(Fault::semantic(
                b.get(b'r').map_or(gspan, |_| b.span(b'r')),
                format!("R less than {nname} in canned cycle"),
            ));
        }
        // Below the R level: rise to it first, where the tool is (Fanuc's K0 stores the
        // cycle and moves nothing). LinuxCNC asks whether the initial level is below R, and
        // then rises even from R itself (a move of no length) at every block of the mode.
        if old_cc < r && repeats > 0 {
            let p = self.cycle_point(self.p[fi], self.p[si], r);
            self.emit(Canon::Traverse {
                end: Axes::from_array(p),
            });
            self.p = p;
            old_cc = r;
        }
        let clear = match (self.retract_r, self.fanuc) {
            (true, _) => r,
            (false, true) => initial.max(r),
            (false, false) => old_cc,
        };
        if !self.fanuc {
            // LinuxCNC goes over to the first hole where the tool is when that is above R, else
            // at the clearance level (after G99 holes at R, G98 rises to the initial level on
            // the way; a G98 block whose R is lower passes at the old R level, as rs274 does).
            old_cc = if self.p[ni] > r { self.p[ni] } else { clear };
        }
        for k in 0..repeats {
            if k > 0 {
                self.count_iteration(gspan)?;
            }
            aa += aa_inc;
            bb += bb_inc;
            if radius_inc != 0.0 || theta_inc != 0.0 {
                // LinuxCNC's CYCLE_MACRO: the radius increment, then the angle's, each about
                // the origin from the last hole.
                if aa == 0.0 && bb == 0.0 {
                    let c = if b.has(b'@') { b'@' } else { b'^' };
                    return Err(Fault::semantic(
                        b.span(c),
                        "incremental motion with polar coordinates is indeterminate at the origin",
                    ));
                }
                let radius = aa.hypot(bb) + radius_inc;
                let theta = bb.atan2(aa) + theta_inc;
                (aa, bb) = (radius * theta.cos(), radius * theta.sin());
            }
            // The rotary words: an absolute angle, or (G91) an increment for each hole, as X
            // and Y are.
            for (k, v) in rotary.iter().enumerate() {
                if let Some(v) = v {
                    self.p[3 + k] = if self.absolute { *v } else { self.p[3 + k] + v };
                }
            }
            self.cyc_traverse(aa, bb, old_cc);
            if old_cc != r {
                self.cyc_traverse(aa, bb, r);
            }
            if !self.fanuc {
                self.check_spindle(motion, gspan)?;
            }
            match motion {
                810 => {
                    self.cyc_feed(aa, bb, cc);
                    self.cyc_traverse(aa, bb, clear);
                }
                820 => {
                    self.cyc_feed(aa, bb, cc);
                    self.emit(Canon::Dwell(dwell));
                    self.cyc_traverse(aa, bb, clear);
                }
                730 | 830 => {
                    // The pecks counted in the program's units, as LinuxCNC counts them: in mm
                    // an inch program's last peck can land a rounding short of the bottom and
                    // add a degenerate one (R0.1 Z-0.6 Q0.05: 14 feeds, not 15).
                    let u = self.scale;
                    let (r_u, cc_u, delta_u) = (r / u, cc / u, delta / u);
                    let mut depth_u = r_u - delta_u;
                    while depth_u > cc_u {
                        self.count_iteration(gspan)?;
                        let depth = depth_u * u;
                        self.cyc_feed(aa, bb, depth);
                        if motion == 830 {
                            self.cyc_traverse(aa, bb, r);
                        }
                        self.cyc_traverse(aa, bb, depth + RAPID_DELTA_MM);
                        depth_u -= delta_u;
                    }
                    self.cyc_feed(aa, bb, cc);
                    self.cyc_traverse(aa, bb, clear);
                }
                740 | 840 => {
                    // Tapping: reverse at the bottom and feed out at the same feed.
                    let (down, up) = if motion == 840 {
                        (SpindleDir::Clockwise, SpindleDir::CounterClockwise)
                    } else {
                        (SpindleDir::CounterClockwise, SpindleDir::Clockwise)
                    };
                    self.tap_feed(aa, bb, cc);
                    self.cyc_spindle(SpindleDir::Stopped);
                    self.cyc_spindle(up);
                    self.emit(Canon::Dwell(dwell));
                    if self.fanuc {
                        // A Fanuc control feeds out (spindle reversed) to R only, turns the
                        // spindle forward again there, and rapids on to the initial level
                        // under G98.
                        self.tap_feed(aa, bb, r);
                        self.cyc_spindle(SpindleDir::Stopped);
                        self.cyc_spindle(down);
                        if clear > r {
                            self.cyc_traverse(aa, bb, clear);
                        }
                    } else {
                        self.tap_feed(aa, bb, clear);
                        self.cyc_spindle(SpindleDir::Stopped);
                        self.cyc_spindle(down);
                    }
                }
                860 => {
                    let dir = self.dir;
                    self.cyc_feed(aa, bb, cc);
                    self.emit(Canon::Dwell(dwell));
                    self.cyc_spindle(SpindleDir::Stopped);
                    self.cyc_traverse(aa, bb, clear);
                    self.cyc_spindle(dir);
                }
                880 => {
                    // The control stops (LinuxCNC's PROGRAM_STOP) for the operator to take the
                    // tool out by hand, and goes on from the clearance level: the program has
                    // no move out, so the tool is put there without one. (Fanuc's G88, after
                    // the operator's retract, rapids to the level.)
                    let dir = self.dir;
                    self.cyc_feed(aa, bb, cc);
                    self.emit(Canon::Dwell(dwell));
                    self.cyc_spindle(SpindleDir::Stopped);
                    self.warn_at(
                        0,
                        "G88 pauses for the operator to retract the tool by hand: the \
                         simulation takes it straight out to the clearance level"
                            .into(),
                    );
                    if self.fanuc {
                        self.cyc_traverse(aa, bb, clear);
                    } else {
                        let p = self.cycle_point(aa, bb, clear);
                        self.emit(Canon::SetPosition(Axes::from_array(p)));
                    }
                    self.cyc_spindle(dir);
                }
                870 => {
                    let dir = self.dir;
                    let (oi, oj) = back_bore_offset.unwrap_or((0.0, 0.0));
                    // The hole's clearance level was reached above; the tool is at R.
                    self.cyc_traverse(aa + oi, bb + oj, r);
                    self.cyc_spindle(SpindleDir::Stopped);
                    self.cyc_traverse(aa + oi, bb + oj, cc);
                    self.cyc_traverse(aa, bb, cc);
                    self.cyc_spindle(dir);
                    self.cyc_feed(aa, bb, back_bore_k);
                    self.cyc_feed(aa, bb, cc);
                    self.cyc_spindle(SpindleDir::Stopped);
                    self.cyc_traverse(aa + oi, bb + oj, cc);
                    self.cyc_traverse(aa + oi, bb + oj, clear);
                    self.cyc_traverse(aa, bb, clear);
                    self.cyc_spindle(dir);
                }
                _ if self.fanuc => {
                    // Fanuc's G85 and G89: feed out to R, then rapid to the initial level
                    // under G98.
                    self.cyc_feed(aa, bb, cc);
                    if motion == 890 {
                        self.emit(Canon::Dwell(dwell));
                    }
                    self.cyc_feed(aa, bb, r);
                    if clear > r {
                        self.cyc_traverse(aa, bb, clear);
                    }
                }
                850 => {
                    // LinuxCNC's G85: feed out to R, then rapid to the clearance level (a
                    // move of no length under G99).
                    self.cyc_feed(aa, bb, cc);
                    self.cyc_feed(aa, bb, r);
                    self.cyc_traverse(aa, bb, clear);
                }
                _ => {
                    // LinuxCNC's G89: dwell, then feed all the way out to the clearance level.
                    self.cyc_feed(aa, bb, cc);
                    self.emit(Canon::Dwell(dwell));
                    self.cyc_feed(aa, bb, clear);
                }
            }
            old_cc = clear;
        }
        if repeats > 0 {
            // (Fanuc's K0 stores the cycle's data and leaves the tool where it is.)
            self.p = self.cycle_point(aa, bb, clear);
        }
        self.cycle = super::interp::CycleMemory {
            r: r_word,
            cc: cc_word,
            p: dwell,
            q: delta,
            back_bore: back_bore_words,
        };
        Ok(())
    }
}
