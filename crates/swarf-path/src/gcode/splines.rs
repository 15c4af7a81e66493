//! G5 (cubic), G5.1 (quadratic) and G5.2/G5.3 (NURBS) spline feeds, read as LinuxCNC's manual
//! defines them, in the XY plane:
//!
//! * `G5 X Y I J P Q`: I J is the first control point's offset from the start, P Q the second
//!   one's offset from the end. I J may be left out after a G5: the first control point is then
//!   the previous G5's second one mirrored about its end (a smooth continuation).
//! * `G5.1 X Y I J`: I J is the control point's offset from the start.
//! * `G5.2 X Y P L` opens a NURBS (the current position is its first control point; P the
//!   weight, default 1; L the order, default 3); each following `X Y P` line adds a control
//!   point; `G5.3` closes it and the curve is fed.
//!
//! The curve is stated exactly ([`Canon::Spline`]); the move stream flattens it.

use std::borrow::Cow;

use super::block::{group, Block};
use super::interp::Interp;
use super::{Fault, Res, Span};
use crate::spline::SplineKind;
use crate::{Axes, Canon, PathErrorKind, Plane};

/// Most control points one NURBS may collect.
const MAX_NURBS_POINTS: usize = 100_000;

impl Interp<'_, '_> {
    /// A block in spline mode `m` (G code × 10: 50, 51, 52, 53).
    pub(crate) fn spline(&mut self, b: &Block, m: u16, explicit: bool) -> Res<()> {
        let span = b
            .g(group::MOTION)
            .map_or(Span::Line, |_| b.g_span(group::MOTION));
        if self.plane != Plane::XY {
            return Err(Fault::semantic(
                span,
                "splines (G5, G5.1, G5.2) need the XY plane (G17)",
            ));
        }
        if self.comp.on() {
            return Err(Fault::semantic(
                span,
                "splines cannot be used with cutter radius compensation on",
            ));
        }
        for c in [b'z', b'a', b'b', b'c', b'@', b'^'] {
            if b.has(c) {
                return Err(Fault::semantic(b.span(c), "a spline moves X and Y only"));
            }
        }
        let xy = |me: &Self| -> Res<[f64; 2]> {
            let e = me.find_ends(b, false)?;
            Ok([e[0], e[1]])
        };
        let start = [self.p[0], self.p[1]];
        let off = |me: &Self, c: u8| b.get(c).map(|v| me.mm_from_units(0, v));
        match m {
            50 | 51 => {
                if !(b.has(b'x') || b.has(b'y')) {
                    // (`G05.1 Q1` is Fanuc's AI contour control, which that dialect reads.)
                    let fanuc_mode = m == 51 && b.has(b'q');
                    return Err(Fault::new(
                        PathErrorKind::Semantic,
                        span,
                        if fanuc_mode {
                            "a spline needs its end point (`G05.1 Q…` is Fanuc's AI contour \
                             control: --dialect fanuc reads it)"
                        } else {
                            "a spline needs its end point"
                        },
                        "X and/or Y",
                    ));
                }
                self.check_feed(b)?;
                let end = xy(self)?;
                let (kind, controls) = if m == 50 {
                    let c1 = match (off(self, b'i'), off(self, b'j'), self.g5_last) {
                        (None, None, Some(prev)) => {
                            [2.0 * start[0] - prev[0], 2.0 * start[1] - prev[1]]
                        }
                        (i, j, _) if i.is_some() && j.is_some() => {
                            [start[0] + i.unwrap_or(0.0), start[1] + j.unwrap_or(0.0)]
                        }
                        _ => {
                            return Err(Fault::new(
                                PathErrorKind::Semantic,
                                span,
                                "G5 needs I and J unless it follows a G5",
                                "I J (the first control point from the start)",
                            ))
                        }
                    };
                    let (Some(p), Some(q)) = (off(self, b'p'), off(self, b'q')) else {
                        return Err(Fault::new(
                            PathErrorKind::Semantic,
                            span,
                            "G5 needs P and Q",
                            "P Q (the second control point from the end)",
                        ));
                    };
                    let c2 = [end[0] + p, end[1] + q];
                    self.g5_last = Some(c2);
                    (
                        SplineKind::Cubic,
                        vec![
                            [c1[0], c1[1], 1.0],
                            [c2[0], c2[1], 1.0],
                            [end[0], end[1], 1.0],
                        ],
                    )
                } else {
                    let (Some(i), Some(j)) = (off(self, b'i'), off(self, b'j')) else {
                        return Err(Fault::new(
                            PathErrorKind::Semantic,
                            span,
                            "G5.1 needs I and J",
                            "I J (the control point from the start)",
                        ));
                    };
                    if i == 0.0 && j == 0.0 {
                        // The control point at the start: LinuxCNC refuses it.
                        return Err(Fault::new(
                            PathErrorKind::Semantic,
                            b.span(b'i'),
                            "G5.1 with I0 J0: the control point is the start point",
                            "I J, not both 0 (the control point from the start)",
                        ));
                    }
                    self.g5_last = None;
                    (
                        SplineKind::Quadratic,
                        vec![[start[0] + i, start[1] + j, 1.0], [end[0], end[1], 1.0]],
                    )
                };
                self.emit_spline(end, kind, controls)?;
            }
            52 => {
                self.g5_last = None;
                if !(b.has(b'x') || b.has(b'y')) {
                    if explicit {
                        return Err(Fault::new(
                            PathErrorKind::Semantic,
                            span,
                            "G5.2 needs its first control point",
                            "X Y",
                        ));
                    }
                    return Ok(());
                }
                if b.has(b'x') != b.has(b'y') {
                    let (given, missing) = if b.has(b'x') {
                        (b'x', 'Y')
                    } else {
                        (b'y', 'X')
                    };
                    return Err(Fault::new(
                        PathErrorKind::Semantic,
                        b.span(given),
                        format!(
                            "a NURBS control point needs both X and Y ({missing} is missing; \
                             LinuxCNC: \"You must specify both X and Y coordinates for Control \
                             Points\")"
                        ),
                        "X and Y",
                    ));
                }
                let p = xy(self)?;
                let w = b.get(b'p').unwrap_or(1.0);
                if !(w > 0.0 && w.is_finite()) {
                    return Err(Fault::semantic(
                        b.span(b'p'),
                        "a NURBS weight must be positive",
                    ));
                }
                if explicit {
                    let order = match b.get(b'l') {
                        None => 3,
                        Some(l) if (2.0..=32.0).contains(&l) && l.fract() == 0.0 => l as u32,
                        Some(_) => {
                            return Err(Fault::new(
                                PathErrorKind::Semantic,
                                b.span(b'l'),
                                "bad NURBS order",
                                "L, an integer from 2 to 32",
                            ))
                        }
                    };
                    self.check_feed(b)?;
                    self.nurbs = Some((Vec::new(), order));
                }
                let Some((pts, _)) = self.nurbs.as_mut() else {
                    return Err(Fault::semantic(
                        span,
                        "NURBS control point outside G5.2 … G5.3",
                    ));
                };
                if pts.len() >= MAX_NURBS_POINTS {
                    return Err(Fault::new(
                        PathErrorKind::Limit,
                        span,
                        format!("more than {MAX_NURBS_POINTS} NURBS control points"),
                        "",
                    ));
                }
                pts.push([p[0], p[1], w]);
                // The interpreter's position follows the control points (LinuxCNC reads
                // incremental words from the last one).
                self.p[0] = p[0];
                self.p[1] = p[1];
            }
            _ => {
                // G5.3: the NURBS is complete.
                self.motion = None;
                let Some((pts, order)) = self.nurbs.take() else {
                    return Err(Fault::semantic(span, "G5.3 without an open G5.2"));
                };
                // The start is the first control point (LinuxCNC's list holds it too).
                let count = pts.len() + 1;
                if count < order as usize {
                    return Err(Fault::new(
                        PathErrorKind::Semantic,
                        span,
                        format!(
                            "the NURBS has {count} control points (the start and {} given) for \
                             its order L = {order}: it needs at least as many as its order",
                            pts.len(),
                        ),
                        format!(
                            "at least {} control points (G5.2 X Y lines) before G5.3",
                            order - 1
                        ),
                    ));
                }
                let Some(last) = pts.last().copied() else {
                    return Ok(());
                };
                self.p[0] = self.nurbs_start[0];
                self.p[1] = self.nurbs_start[1];
                self.emit_spline([last[0], last[1]], SplineKind::Nurbs { order }, pts)?;
            }
        }
        Ok(())
    }

    fn emit_spline(&mut self, end: [f64; 2], kind: SplineKind, controls: Vec<[f64; 3]>) -> Res<()> {
        if controls.iter().flatten().any(|v| !v.is_finite()) {
            return Err(Fault::semantic(
                Span::Line,
                "a spline control point is out of range (not a finite number)",
            ));
        }
        let mut e = self.p;
        e[0] = end[0];
        e[1] = end[1];
        self.emit(Canon::Spline {
            end: Axes::from_array(e),
            kind,
            controls: Cow::Owned(controls),
        });
        self.p = e;
        Ok(())
    }
}
