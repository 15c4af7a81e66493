//! Cycles and tilted planes: coordinate transformations (`CYCL DEF 7`, `10`, `19`), dwell,
//! the drilling and tapping cycles run at a cycle call, and the `PLANE` functions.
//!
//! A drilling cycle's parameters are Q parameters (`Q200` set-up clearance, `Q201` depth —
//! negative, below the surface —, `Q206` plunging feed, `Q202` plunging depth, `Q203` surface
//! coordinate, `Q204` second set-up clearance, `Q210`/`Q211` dwells, `Q208` retraction feed,
//! `Q212` decrement, `Q205` least plunging depth, `Q239` thread pitch), read when the cycle is
//! called: the TNC 640's `~` definition sets them in its own block, a TNC 530's in the blocks
//! that follow it. Along the tool axis, from the call position: rapid to the set-up clearance
//! above the surface, plunge at the feed (pecks: back to the set-up clearance at rapid after
//! each, then down again to the set-up clearance above the depth reached; cycle 205: to its
//! advanced stop distances `Q258`/`Q259` above it, with chip breaking by `Q256` every `Q257`),
//! dwell, back to the set-up clearance (at rapid, or at the retraction feed for reaming, boring
//! and tapping), then to the second set-up clearance when it is higher.

use super::lexer::{self, Block, Tok};
use super::{Fault, Reader, Res};
use crate::part_frame::{cross, frame_of as frame, mat, rx, ry, rz, spatial};
use crate::{Canon, FeedMode, PathErrorKind};

/// Most pecks one drilling cycle call may make (a tiny plunging depth would otherwise make
/// millions of moves).
const MAX_PECKS: f64 = 10_000.0;

/// Where a drilling cycle runs and how, in mm along the tool axis.
struct Drill {
    surface: f64,
    clearance: f64,
    /// Above the surface.
    clearance2: f64,
    /// Below the surface (positive).
    depth: f64,
    feed: f64,
    mode: FeedMode,
    /// Plunging depth (0: all at once), its decrement and least value.
    peck: f64,
    decrement: f64,
    least: f64,
    dwell_top: f64,
    dwell_depth: f64,
    /// Retraction feed (`None`: rapid), at the end and between pecks.
    retract: Option<f64>,
    peck_retract: Option<f64>,
    /// Chip breaking (cycle 203): this many short retracts of `break_retract` between full
    /// ones.
    breaks: u32,
    break_retract: f64,
    /// Chip breaking by depth (cycle 205's Q257; 0: none): back `break_retract` after each
    /// this much of a plunge.
    break_depth: f64,
    /// Advanced stop distances (cycle 205's Q258, Q259: before the first and the last
    /// re-entry); `None`: the set-up clearance.
    stops: Option<(f64, f64)>,
}

/// Splits a `PLANE` word (`SPA+30`, `P1X-5`, `TURN`) into its name and value.
fn plane_word(t: &Tok) -> (&str, Option<f64>) {
    let s = t.text.as_str();
    match s.find(['+', '-']) {
        Some(i) => (&s[..i], lexer::number(&s[i..])),
        None => {
            let n = s.bytes().take_while(u8::is_ascii_alphabetic).count();
            (&s[..n], lexer::number(&s[n..]))
        }
    }
}

impl Reader<'_> {
    fn qd(&self, n: u32) -> f64 {
        self.q.get(&(b'Q', n)).copied().unwrap_or(0.0)
    }

    /// `CYCL DEF n …` (and `n.m` sub-blocks).
    pub(super) fn cycle_def(&mut self, b: &Block) -> Res<()> {
        let Some(nt) = b.toks.get(2) else {
            return Err(Fault::at(
                &b.toks[0],
                PathErrorKind::Syntax,
                "CYCL DEF without a cycle number",
                "CYCL DEF <number>",
            ));
        };
        let (major, minor) = match nt.text.split_once('.') {
            Some((a, m)) => (a.parse::<u32>().ok(), m.parse::<u32>().ok()),
            None => (nt.text.parse::<u32>().ok(), Some(0)),
        };
        let (Some(major), Some(minor)) = (major, minor) else {
            return Err(Fault::at(
                nt,
                PathErrorKind::Syntax,
                "bad cycle number",
                "a cycle number such as 200 or 7.1",
            ));
        };
        // The `~` form's parameters: `Q200=+2` words.
        for t in &b.toks[3..] {
            if t.text.starts_with('Q') && t.text.contains('=') {
                self.assign(&t.text, t.line, t.col)?;
            }
        }
        let rest = &b.toks[3..];
        match (major, minor) {
            (_, 0) => {
                match major {
                    7 | 8 | 9 | 10 | 11 | 19 | 26 => {}
                    32 => self.warn_once(
                        "cycle32",
                        b.line,
                        nt.col,
                        "cycle 32 (tolerance) is not read: swarf follows the programmed path \
                         exactly"
                            .into(),
                    ),
                    247 => self.warn(
                        b.line,
                        nt.col,
                        "cycle 247 (datum setting from the preset table) is not read: the \
                         table is not known, positions stay in the current datum"
                            .into(),
                    ),
                    _ => {
                        self.cycle = Some(major);
                        self.old_cycle.clear();
                        self.modal_call = false;
                    }
                }
                Ok(())
            }
            (7, _) => {
                if rest.iter().any(|t| t.text.starts_with('#')) {
                    return Err(Fault::at(
                        nt,
                        PathErrorKind::Unsupported,
                        "a datum shift from the datum table is not read (the table is not known)",
                        "CYCL DEF 7.1 X…",
                    ));
                }
                let w = self.words(rest, b.line)?;
                // Under a tilted plane the values are along its axes.
                let mut v = self.frame.programmed_shift();
                for (k, a) in w.axes.iter().take(3).enumerate() {
                    if let Some((x, inc)) = *a {
                        v[k] = if inc { v[k] + x } else { x };
                    }
                }
                self.change_frame(b.line, true, |s| s.frame.set_programmed_shift(v));
                Ok(())
            }
            (10, _) => {
                let mut rot = self.frame.rot;
                for t in rest {
                    let (name, val) = lexer::word(t)?;
                    match name {
                        "ROT" => rot = self.value(val, t)?,
                        "IROT" => rot += self.value(val, t)?,
                        _ => {}
                    }
                }
                if rot != self.frame.rot && self.c.plane != crate::Plane::XY {
                    return Err(Fault::at(
                        nt,
                        PathErrorKind::Unsupported,
                        "a rotation (cycle 10) with tool axis X or Y is not read",
                        "tool axis Z",
                    ));
                }
                self.change_frame(b.line, true, |s| s.frame.rot = rot);
                Ok(())
            }
            (9, _) => {
                let secs = rest
                    .iter()
                    .rev()
                    .find_map(|t| {
                        let n = t
                            .text
                            .trim_start_matches(|c: char| c.is_ascii_alphabetic() || c == '.');
                        lexer::number(n)
                    })
                    .unwrap_or(0.0);
                if secs > 0.0 {
                    self.emit(b.line, Canon::Dwell(secs));
                }
                Ok(())
            }
            (11, _) | (26, _) => {
                let scale = rest.iter().find_map(|t| {
                    let n = t.text.trim_start_matches(|c: char| c.is_ascii_alphabetic());
                    lexer::number(n).filter(|v| *v != 1.0)
                });
                match scale {
                    None => Ok(()),
                    Some(_) => Err(Fault::at(
                        nt,
                        PathErrorKind::Unsupported,
                        "scaling (cycles 11 and 26) is not read",
                        "a scale factor of 1",
                    )),
                }
            }
            (8, _) => match rest.is_empty() {
                true => Ok(()),
                false => Err(Fault::at(
                    nt,
                    PathErrorKind::Unsupported,
                    "mirror images (cycle 8) are not read",
                    "no mirrored axis",
                )),
            },
            (19, _) => {
                let (mut a, mut bb, mut c) = (0.0, 0.0, 0.0);
                for t in rest {
                    let (name, val) = lexer::word(t)?;
                    match name {
                        "A" => a = self.value(val, t)?,
                        "B" => bb = self.value(val, t)?,
                        "C" => c = self.value(val, t)?,
                        _ => {}
                    }
                }
                self.warn_once(
                    "cycle19",
                    b.line,
                    nt.col,
                    "cycle 19's angles are read as spatial angles (about X, then Y, then Z), \
                     the tool turned normal to the plane; Q120–Q122 read them"
                        .into(),
                );
                for (n, v) in [(120, a), (121, bb), (122, c)] {
                    self.q.insert((b'Q', n), v);
                }
                let tilt = (a != 0.0 || bb != 0.0 || c != 0.0).then(|| spatial(a, bb, c));
                self.set_tilt(b.line, tilt);
                Ok(())
            }
            (1 | 2 | 17, m) => {
                let v = rest
                    .iter()
                    .rev()
                    .find_map(|t| {
                        let n = t
                            .text
                            .trim_start_matches(|c: char| c.is_ascii_alphabetic() || c == '.');
                        lexer::number(n).or_else(|| lexer::qref(n).map(|q| self.qv(q)))
                    })
                    .ok_or_else(|| {
                        Fault::at(
                            nt,
                            PathErrorKind::Syntax,
                            "a cycle value is missing",
                            "a number",
                        )
                    })?;
                self.old_cycle.insert(m, v);
                Ok(())
            }
            _ => Ok(()),
        }
    }

    /// Tilts the working plane (or untilts it), the tool turned to its Z.
    pub(super) fn set_tilt(&mut self, line: u32, tilt: Option<[[f64; 3]; 3]>) {
        if tilt.is_none() {
            self.emit(line, Canon::WorkPlane(None));
        }
        // (The tilted plane, turned by any rotation, is stated with the offsets.)
        self.change_frame(line, true, |s| s.frame.tilt = tilt);
    }

    /// `CYCL CALL`, `CYCL CALL POS X… Y… Z…`.
    pub(super) fn cycle_call_block(&mut self, b: &Block) -> Res<()> {
        let head = &b.toks[0];
        let pos = b.toks.get(2).is_some_and(|t| t.text == "POS");
        if b.toks.get(2).is_some_and(|t| t.text == "PAT") {
            return Err(Fault::at(
                &b.toks[2],
                PathErrorKind::Unsupported,
                "point patterns (CYCL CALL PAT) are not read",
                "CYCL CALL or CYCL CALL POS",
            ));
        }
        let rest = &b.toks[if pos { 3 } else { 2 }..];
        let w = self.words(rest, b.line)?;
        self.m_before(&w, b.line);
        let mut surface = None;
        if pos {
            let (i1, i2, n) = self.c.plane.axes();
            let target = self.target(&w);
            surface = w.axes[n].map(|_| target[n]);
            // Up to the second set-up clearance first if below it, then over the hole.
            let safe = surface.unwrap_or(self.qd(203) * self.scale)
                + (self.qd(204) * self.scale).max(self.qd(200) * self.scale);
            if self.c.pos[n] < safe {
                let mut up = self.c.pos;
                up[n] = safe;
                self.line_to(b.line, up, true);
            }
            let mut over = self.c.pos;
            (over[i1], over[i2]) = (target[i1], target[i2]);
            let rapid = !matches!(w.feed, Some(super::Feed::Value(_) | super::Feed::PerRev(_)));
            if !rapid {
                self.feed_for(&w, head)?;
            }
            self.line_to(b.line, over, rapid);
        }
        self.cycle_call(head, surface)?;
        self.m_after(&w, rest, b.line)?;
        Ok(())
    }

    /// Runs the defined cycle where the tool stands (`surface`: the `CYCL CALL POS`
    /// surface, instead of Q203).
    pub(super) fn cycle_call(&mut self, at: &Tok, surface: Option<f64>) -> Res<()> {
        let Some(num) = self.cycle else {
            return Err(Fault::at(
                at,
                PathErrorKind::Semantic,
                "a cycle call without a cycle defined",
                "CYCL DEF before the call",
            ));
        };
        let s = self.scale;
        let fs = self.feed_scale;
        let q = |n| self.qd(n);
        let (_, _, axis) = self.c.plane.axes();
        let here = self.c.pos[axis];
        let drill = |surface_q: f64, retract: Option<f64>| Drill {
            surface: surface.unwrap_or(surface_q * s),
            clearance: q(200) * s,
            clearance2: q(204) * s,
            depth: -q(201) * s,
            feed: q(206) * fs,
            mode: FeedMode::PerMinute,
            peck: 0.0,
            decrement: 0.0,
            least: 0.0,
            dwell_top: 0.0,
            dwell_depth: q(211),
            retract,
            peck_retract: None,
            breaks: 0,
            break_retract: 0.0,
            break_depth: 0.0,
            stops: None,
        };
        // Q208 = 0: out at the plunging feed.
        let q208 = if q(208) > 0.0 {
            q(208) * fs
        } else {
            q(206) * fs
        };
        let mut d = match num {
            200 => Drill {
                peck: q(202) * s,
                dwell_top: q(210),
                ..drill(q(203), None)
            },
            201 | 202 => drill(q(203), Some(q208)),
            203 | 205 => Drill {
                peck: q(202) * s,
                decrement: q(212) * s,
                least: q(205) * s,
                dwell_top: if num == 203 { q(210) } else { 0.0 },
                peck_retract: (num == 203).then_some(q208),
                breaks: if num == 203 {
                    q(213).clamp(0.0, 1e4) as u32
                } else {
                    0
                },
                break_retract: if q(256) > 0.0 { q(256) * s } else { 0.2 * s },
                break_depth: if num == 205 { q(257).max(0.0) * s } else { 0.0 },
                stops: (num == 205).then(|| (q(258).max(0.0) * s, q(259).max(0.0) * s)),
                ..drill(q(203), Some(q208))
            },
            206 => {
                let f = q(206) * fs;
                drill(q(203), Some(f))
            }
            207 | 209 => {
                let lead = q(239).abs() * s;
                Drill {
                    feed: lead,
                    mode: FeedMode::SpindleSynchronised,
                    ..drill(q(203), Some(lead))
                }
            }
            240 => {
                let mut d = drill(q(203), None);
                if q(343) == 1.0 {
                    d.depth = q(344).abs() * s / 2.0;
                }
                d
            }
            1 | 2 | 17 => {
                let v = |m| self.old_cycle.get(&m).copied().unwrap_or(0.0);
                let clearance = v(1).abs() * s;
                let (peck, dwell, feed) = match num {
                    1 => (v(3).abs() * s, v(4), v(5) * fs),
                    2 => (0.0, v(3), v(4) * fs),
                    _ => (0.0, 0.0, v(3).abs() * s),
                };
                let mode = if num == 17 {
                    FeedMode::SpindleSynchronised
                } else {
                    FeedMode::PerMinute
                };
                Drill {
                    surface: here - clearance,
                    clearance,
                    clearance2: 0.0,
                    depth: -v(2) * s,
                    feed,
                    mode,
                    peck,
                    decrement: 0.0,
                    least: 0.0,
                    dwell_top: 0.0,
                    dwell_depth: dwell,
                    retract: (num != 1).then_some(feed),
                    peck_retract: None,
                    breaks: 0,
                    break_retract: 0.0,
                    break_depth: 0.0,
                    stops: None,
                }
            }
            _ => {
                return Err(Fault::at(
                    at,
                    PathErrorKind::Unsupported,
                    format!(
                        "cycle {num} is not read: swarf runs the drilling and tapping cycles \
                         (200–203, 205–207, 209, 240, 1, 2, 17); a pocket, contour or \
                         thread-milling cycle's path is the control's"
                    ),
                    "a drilling cycle",
                ))
            }
        };
        if num == 240 && self.qd(343) == 1.0 {
            self.warn_once(
                "cycle240",
                at.line,
                at.col,
                "cycle 240 by diameter: the depth is taken for a 90° point (half the diameter)"
                    .into(),
            );
        }
        if d.depth == 0.0 {
            return Ok(());
        }
        if d.depth < 0.0 {
            return Err(Fault::at(
                at,
                PathErrorKind::Semantic,
                "the cycle's depth is positive: it would drill upwards",
                "a negative depth (Q201)",
            ));
        }
        if d.feed <= 0.0 {
            return Err(Fault::at(
                at,
                PathErrorKind::Semantic,
                "the cycle's feed (or thread pitch) is zero",
                "a positive feed",
            ));
        }
        // The least plunging depth a decrement leaves (1 µm at the least).
        let least = if d.decrement > 0.0 {
            d.least.max(1e-3).min(d.peck)
        } else {
            d.peck
        };
        if (d.peck > 0.0 && d.depth / least > MAX_PECKS)
            || (d.break_depth > 0.0 && d.depth / d.break_depth > MAX_PECKS)
        {
            return Err(Fault::at(
                at,
                PathErrorKind::Limit,
                "the plunging depth makes more than 10,000 pecks",
                "a larger plunging depth",
            ));
        }
        if d.peck >= d.depth {
            d.peck = 0.0;
        }
        self.drill(at.line, &d);
        Ok(())
    }

    fn axis_to(&mut self, line: u32, to: f64, feed: Option<(FeedMode, f64)>) {
        let (_, _, n) = self.c.plane.axes();
        let mut end = self.c.pos;
        end[n] = to;
        if let Some((mode, f)) = feed {
            let events: Vec<Canon<'static>> = self.c.feed(mode, f).collect();
            for e in events {
                self.emit(line, e);
            }
        }
        self.line_to(line, end, feed.is_none());
    }

    /// Runs drilling cycle `d` along the tool axis. Cycle 205 follows the TNC 640 / iTNC 530
    /// cycle manuals' run of cycle 205: plunges of Q202 (less Q212 each time, not below Q205);
    /// with a depth for chip breaking Q257 the tool goes back Q256 after each Q257 of a plunge
    /// and feeds on, and after each plunge goes out to the set-up clearance Q200, then at rapid
    /// down to the advanced stop distance above the depth reached: Q258 before the first
    /// re-entry, Q259 before the last, the distance changing "at the same rate" between them
    /// (read here as linear in the depth reached; with equal plunges the same as linear in the
    /// plunge's count; with a decrement the manual is not exact). The manuals give no feed
    /// for the Q256 retract, and differ on the full one between plunges (the iTNC 530 rapid,
    /// the TNC 640 Q208): both stay at rapid as swarf had them.
    fn drill(&mut self, line: u32, d: &Drill) {
        let top = d.surface + d.clearance;
        let dwell = |r: &mut Self, t: f64| {
            if t > 0.0 {
                r.emit(line, Canon::Dwell(t));
            }
        };
        self.axis_to(line, top, None);
        let feed = Some((d.mode, d.feed));
        // The plunges' ends, below the surface (the caller bounds their count).
        let mut ends = Vec::new();
        let mut reached = 0.0;
        let mut peck = d.peck;
        loop {
            let next = if peck > 0.0 {
                (reached + peck).min(d.depth)
            } else {
                d.depth
            };
            ends.push(next);
            reached = next;
            if reached >= d.depth {
                break;
            }
            if d.decrement > 0.0 {
                peck = (peck - d.decrement).max(d.least.max(1e-3));
            }
        }
        // The depths re-entered first and last (the ends of the first and the last but one
        // plunges).
        let (low_first, low_last) = (ends[0], ends[ends.len().saturating_sub(2)]);
        let mut reached = 0.0;
        let mut out = true;
        let mut broken = 0;
        for (i, &next) in ends.iter().enumerate() {
            if out && reached > 0.0 {
                // Back down at rapid to the advanced stop distance (or the set-up clearance)
                // above the depth reached.
                let stop = match d.stops {
                    Some((upper, lower)) if low_last > low_first => {
                        upper + (lower - upper) * (reached - low_first) / (low_last - low_first)
                    }
                    Some((upper, _)) => upper,
                    None => d.clearance,
                };
                self.axis_to(line, (d.surface - reached + stop).min(top), None);
            }
            if d.break_depth > 0.0 {
                // Chip breaking within the plunge: back a little after each break depth.
                let mut k = 1.0;
                while reached + k * d.break_depth < next - 1e-9 {
                    let at = reached + k * d.break_depth;
                    self.axis_to(line, d.surface - at, feed);
                    self.axis_to(line, d.surface - at + d.break_retract, None);
                    k += 1.0;
                }
            }
            self.axis_to(line, d.surface - next, feed);
            reached = next;
            if i + 1 == ends.len() {
                break;
            }
            out = broken >= d.breaks;
            if out {
                broken = 0;
                self.axis_to(line, top, d.peck_retract.map(|f| (d.mode, f)));
                dwell(self, d.dwell_top);
            } else {
                // Chip breaking (cycle 203): back a little, and on.
                broken += 1;
                self.axis_to(line, d.surface - reached + d.break_retract, None);
            }
        }
        dwell(self, d.dwell_depth);
        self.axis_to(line, top, d.retract.map(|f| (d.mode, f)));
        if d.clearance2 > d.clearance {
            self.axis_to(line, d.surface + d.clearance2, None);
        }
    }

    /// `PLANE SPATIAL | EULER | VECTOR | POINTS | RELATIV | RESET …`.
    pub(super) fn plane_function(&mut self, b: &Block) -> Res<()> {
        let Some(kind) = b.toks.get(1) else {
            return Err(Fault::at(
                &b.toks[0],
                PathErrorKind::Syntax,
                "PLANE without a function",
                "PLANE SPATIAL, EULER, VECTOR, POINTS, RELATIV or RESET",
            ));
        };
        let mut vals: Vec<(&str, f64)> = Vec::new();
        let mut mb = None;
        let mut mb_max = false;
        let mut stay = false;
        let toks = &b.toks[2..];
        let mut i = 0;
        while i < toks.len() {
            let t = &toks[i];
            let (name, v) = plane_word(t);
            match (name, v) {
                ("MB", None) if toks.get(i + 1).is_some_and(|n| n.text == "MAX") => {
                    mb_max = true;
                    i += 1;
                }
                ("MB", None) => {
                    mb = toks
                        .get(i + 1)
                        .and_then(|n| lexer::number(&n.text))
                        .map(|v| v * self.scale);
                    i += 1;
                }
                ("MB", Some(v)) => mb = Some(v * self.scale),
                ("STAY", _) => stay = true,
                (n, Some(v)) => vals.push((n, v)),
                // `SPB+Q5`: a parameter as the value; other words (`SEQ-`, `TABLE ROT`,
                // `COORD ROT`, `FMAX`, `F…`) say how the axes move, not where the plane is.
                (n, None) => {
                    let at = t.text.find(['+', '-']).unwrap_or(t.text.len());
                    if let Some(q) = lexer::qref(&t.text[at..]) {
                        vals.push((n, self.qv(q)));
                    }
                }
            }
            i += 1;
        }
        let get = |n: &str| vals.iter().rev().find(|(k, _)| *k == n).map(|(_, v)| *v);
        let g0 = |n: &str| get(n).unwrap_or(0.0);
        let bad = |what: &str| {
            Fault::at(
                kind,
                PathErrorKind::Semantic,
                what.to_string(),
                "a valid plane",
            )
        };
        let tilt = match kind.text.as_str() {
            "RESET" => None,
            "SPATIAL" => Some(spatial(g0("SPA"), g0("SPB"), g0("SPC"))),
            "EULER" => Some(mat(
                &rz(g0("EULPR")),
                &mat(&rx(g0("EULNU")), &rz(g0("EULROT"))),
            )),
            "VECTOR" => Some(
                frame(
                    [g0("BX"), g0("BY"), g0("BZ")],
                    [g0("NX"), g0("NY"), g0("NZ")],
                )
                .ok_or_else(|| bad("the base and normal vectors are zero or parallel"))?,
            ),
            "POINTS" => {
                let p = |k: &str| {
                    [
                        g0(&format!("{k}X")),
                        g0(&format!("{k}Y")),
                        g0(&format!("{k}Z")),
                    ]
                };
                let (p1, p2, p3) = (p("P1"), p("P2"), p("P3"));
                let x = [p2[0] - p1[0], p2[1] - p1[1], p2[2] - p1[2]];
                let v = [p3[0] - p1[0], p3[1] - p1[1], p3[2] - p1[2]];
                Some(frame(x, cross(x, v)).ok_or_else(|| bad("the three points lie on a line"))?)
            }
            "RELATIV" => {
                let r = match (get("SPA"), get("SPB"), get("SPC")) {
                    (Some(a), _, _) => rx(a),
                    (None, Some(b), _) => ry(b),
                    (None, None, Some(c)) => rz(c),
                    _ => return Err(bad("PLANE RELATIV without an angle")),
                };
                Some(match self.frame.tilt {
                    Some(t) => mat(&t, &r),
                    None => r,
                })
            }
            "AXIAL" | "PROJECTED" => {
                return Err(Fault::at(
                    kind,
                    PathErrorKind::Unsupported,
                    format!(
                        "PLANE {} is not read (the plane it gives depends on the machine's \
                         axes)",
                        kind.text
                    ),
                    "PLANE SPATIAL, EULER, VECTOR, POINTS, RELATIV or RESET",
                ))
            }
            _ => {
                return Err(Fault::at(
                    kind,
                    PathErrorKind::Syntax,
                    "unknown PLANE function",
                    "PLANE SPATIAL, EULER, VECTOR, POINTS, RELATIV or RESET",
                ))
            }
        };
        if stay && tilt.is_some() {
            self.warn_once(
                "stay",
                b.line,
                kind.col,
                "PLANE … STAY is read as TURN: the tool is turned normal to the plane".into(),
            );
        }
        // The retract before the axes turn.
        let w = super::Words {
            named: mb.map(|d| vec![("MB", d)]).unwrap_or_default(),
            mb_max,
            ..super::Words::default()
        };
        self.retract(&w, b)?;
        self.set_tilt(b.line, tilt);
        if tilt.is_none() && !stay {
            // RESET TURN (or MOVE) turns the rotary axes back: the machine gives the axis.
            self.emit(b.line, Canon::MachineAxis);
        }
        Ok(())
    }
}
