//! Cutter radius compensation (G40, G41, G42, G41.1, G42.1) as LinuxCNC's interpreter does it
//! (`convert_straight_comp1/2`, `convert_arc_comp1/2`, `move_endpoint_and_flush` in
//! `interp_convert.cc`), in the G17 (XY) and G18 (ZX) planes.
//!
//! The tool runs at the compensation radius `r` to the left (G41) or right (G42) of the
//! programmed contour, looking along the motion; a negative radius swaps the sides.
//!
//! * **Entry**: the first move with an XY (plane) component after G41/G42 ends `r` from its
//!   programmed end: a straight line perpendicular to it, and must be longer than `r`; an arc
//!   (`convert_arc_comp1`) keeps its centre (found from the current point: I J K, or R through
//!   the current point and the programmed end) and ends on the ray from the centre through
//!   the programmed end, `r` nearer the centre (tool inside) or farther; its end must be more
//!   than `r` from its start ("radius of cutter compensation entry arc is not greater than the
//!   tool radius"), and I J K must give an end radius, less or plus `r`, within the arc
//!   tolerance of the start radius (`arc_data_comp_ijk`).
//! * **Zero radius** (`G41 D0`, `G41.1 D0`): compensation is on (the side is set: G20, another
//!   G41, G92 … are refused as with any radius) but moves are not offset.
//! * **Corners**: the compensated move is held back (queued with every event that follows it)
//!   until the next move shows the corner. With `θ` the direction from the programmed corner to
//!   the tool, `α` the new move's start direction and `β` the angle between them less 90°
//!   (LinuxCNC's quantities), a convex corner (`β > small`) gets an arc about the programmed
//!   corner from the tool to the new move's offset start; a concave corner (`β < −small`,
//!   `β > π + small`, or the "h" shape after an arc) moves the held move's end back to where it
//!   meets the new offset move and flushes it; a near-tangent corner is flushed as it is.
//!   `small` is LinuxCNC's `TOLERANCE_CONCAVE_CORNER`, 0.05 rad.
//! * **Arcs** keep their centre; the tool runs on the radius `R + r` (outside) or `R − r`
//!   (inside, an error when `R ≤ r`).
//! * **Exit**: after G40 the held move is flushed, the interpreter's position is the
//!   programmed one, and the next move (straight: an arc is an error) goes from the
//!   compensated position to its programmed end.
//!
//! The interpreter's position (`Interp::p`) stays the *programmed* one while compensation is
//! on, so incremental words, arc centres and parameters read as LinuxCNC's do; the tool's
//! position in the plane is kept here.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use super::block::{group, slot, Block};
use super::interp::Interp;
use super::{Fault, Res, Span};
use crate::canon::OwnedCanon;
use crate::{Axes, Canon, CanonSink, PathErrorKind, Plane};

/// LinuxCNC's `TOLERANCE_CONCAVE_CORNER` (radians): corners within this of tangent get neither
/// an arc nor a cut-back.
const SMALL: f64 = 0.05;

/// Which side of the contour the tool runs on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Side {
    /// G41: left of the contour, looking along the motion.
    Left,
    /// G42: right.
    Right,
}

/// The compensated move held back until the next one shows its corner.
#[derive(Clone, Copy, Debug)]
struct Held {
    /// Where the tool starts it (plane coordinates, mm).
    start: [f64; 2],
    /// Where it ends now (moved back at a concave corner).
    end: [f64; 2],
    /// Its centre and turn (positive counter-clockwise), for an arc.
    arc: Option<([f64; 2], i32)>,
    /// A rapid (LinuxCNC words its error differently).
    rapid: bool,
    /// For a line, its programmed direction: a cut-back retreats along it (for the entry move
    /// it is not the direction the tool moves in).
    dir: [f64; 2],
}

/// Compensation state.
#[derive(Debug, Default)]
pub(crate) struct Comp {
    /// On, and on which side.
    pub(crate) side: Option<Side>,
    /// The radius, mm, positive.
    radius: f64,
    /// The next plane move is the entry move.
    first: bool,
    /// The tool's position in the plane (compensated), mm.
    tool: [f64; 2],
    /// The held move, if any (it is `queue[0]`).
    held: Option<Held>,
    /// Events held back behind the held move, with their lines.
    pub(crate) queue: Vec<(u32, OwnedCanon)>,
    /// The frames (G5x offset, G92 offset, XY rotation) the queued events were made in, one
    /// per change of frame since the held move (G10 L2/L20 of the active system): the events
    /// up to the first [`Canon::Offsets`] are in the first, and so on; those after the last in
    /// the current one.
    queue_frames: Vec<Frame>,
}

/// A frame: G5x offset, G92 offset, XY rotation (degrees).
pub(crate) type Frame = ([f64; 6], [f64; 6], f64);

fn angle(v: [f64; 2]) -> f64 {
    v[1].atan2(v[0])
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

fn polar(c: [f64; 2], r: f64, a: f64) -> [f64; 2] {
    [c[0] + r * a.cos(), c[1] + r * a.sin()]
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// Intersections of the line through `p` along `d` with the circle (`c`, `r`).
fn line_circle(p: [f64; 2], d: [f64; 2], c: [f64; 2], r: f64) -> Vec<[f64; 2]> {
    let len = d[0].hypot(d[1]);
    if len == 0.0 {
        return Vec::new();
    }
    let u = [d[0] / len, d[1] / len];
    let w = sub(p, c);
    let b = w[0] * u[0] + w[1] * u[1];
    let disc = b * b - (w[0] * w[0] + w[1] * w[1] - r * r);
    if disc < 0.0 {
        return Vec::new();
    }
    let s = disc.sqrt();
    [-b - s, -b + s]
        .iter()
        .map(|t| [p[0] + t * u[0], p[1] + t * u[1]])
        .collect()
}

/// Intersections of two circles.
fn circle_circle(c1: [f64; 2], r1: f64, c2: [f64; 2], r2: f64) -> Vec<[f64; 2]> {
    let d = dist(c1, c2);
    if d == 0.0 || d > r1 + r2 || d < (r1 - r2).abs() {
        return Vec::new();
    }
    let a = (r1 * r1 - r2 * r2 + d * d) / (2.0 * d);
    let h = (r1 * r1 - a * a).max(0.0).sqrt();
    let u = [(c2[0] - c1[0]) / d, (c2[1] - c1[1]) / d];
    let m = [c1[0] + a * u[0], c1[1] + a * u[1]];
    vec![
        [m[0] - h * u[1], m[1] + h * u[0]],
        [m[0] + h * u[1], m[1] - h * u[0]],
    ]
}

/// The sweep (radians, in `0..2π`, in the arc's own direction) from `from` to `to` about `c`.
fn sweep(c: [f64; 2], from: [f64; 2], to: [f64; 2], turn: i32) -> f64 {
    let d = angle(sub(to, c)) - angle(sub(from, c));
    let d = if turn > 0 { d } else { -d };
    d.rem_euclid(TAU)
}

/// A new compensated move in plane coordinates: programmed start and end, and for an arc its
/// centre and turn.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PlaneMove {
    pub(crate) start: [f64; 2],
    pub(crate) end: [f64; 2],
    pub(crate) arc: Option<([f64; 2], i32)>,
}

impl PlaneMove {
    /// The direction of motion at the start (radians).
    fn start_direction(&self) -> f64 {
        match self.arc {
            None => angle(sub(self.end, self.start)),
            Some((c, turn)) => {
                angle(sub(self.start, c)) + if turn > 0 { FRAC_PI_2 } else { -FRAC_PI_2 }
            }
        }
    }
}

impl Comp {
    /// True when compensation is on (with any radius, 0 included: LinuxCNC's
    /// `cutter_comp_side`, which the refusals of G20, G92, G54 … test).
    pub(crate) fn on(&self) -> bool {
        self.side.is_some()
    }
    /// True when moves are compensated: on, with a radius above zero (LinuxCNC's
    /// `cutter_comp_side && cutter_comp_radius > 0.0` in `convert_straight`/`convert_arc`).
    pub(crate) fn moving(&self) -> bool {
        self.side.is_some() && self.radius > 0.0
    }
    /// The radius when the next move is the entry move of a compensation with a radius.
    pub(crate) fn entry_radius(&self) -> Option<f64> {
        (self.moving() && self.first).then_some(self.radius)
    }
    /// True when no move is held.
    #[inline]
    pub(crate) fn held_none(&self) -> bool {
        self.held.is_none()
    }
}

impl Interp<'_, '_> {
    /// The plane's two coordinates of a position.
    fn plane_of(&self, p: &[f64; 6]) -> [f64; 2] {
        let (f, s, _) = self.plane.axes();
        [p[f], p[s]]
    }

    fn with_plane(&self, p: &[f64; 6], q: [f64; 2]) -> [f64; 6] {
        let (f, s, _) = self.plane.axes();
        let mut out = *p;
        out[f] = q[0];
        out[s] = q[1];
        out
    }

    /// G40/G41/G42/G41.1/G42.1 of a block (the cutter-compensation group).
    pub(crate) fn comp_mode(&mut self, b: &Block, g: u16) -> Res<()> {
        let span = b.g_span(group::CUTTER_COMP);
        if g == 400 {
            if self.comp.on() {
                // As LinuxCNC's `convert_cutter_compensation_off`: the current point becomes
                // the programmed one (the tool stays where it is until the next move, which
                // goes from there to its programmed end, so incremental words and parameters
                // count from the contour), and that move must be straight — once a compensated
                // move was made (LinuxCNC leaves the rest alone before the first one).
                self.comp_flush();
                self.comp.side = None;
                self.arc_not_allowed = !self.comp.first && self.comp.radius > 0.0;
            }
            return Ok(());
        }
        if self.comp.on() {
            return Err(Fault::semantic(
                span,
                "cannot turn cutter radius compensation on when it is already on",
            ));
        }
        if self.plane == Plane::YZ {
            return Err(Fault::semantic(
                span,
                "cutter radius compensation works in the XY (G17) and XZ (G18) planes only",
            ));
        }
        let radius = if g == 411 || g == 421 {
            // G41.1/G42.1: D is the diameter.
            b.get(b'd').ok_or_else(|| {
                Fault::new(
                    PathErrorKind::Semantic,
                    span,
                    "G41.1/G42.1 need a D word (the tool diameter)",
                    "D<diameter>",
                )
            })? * self.scale
                / 2.0
        } else {
            // G41/G42: D names a tool of the table (default: the tool in the spindle).
            let tool = match b.get(b'd') {
                Some(d) if d < 0.0 || d.fract() != 0.0 || d > f64::from(u32::MAX) => {
                    return Err(Fault::new(
                        PathErrorKind::Semantic,
                        b.span(b'd'),
                        "bad tool number in D",
                        "D<tool number>",
                    ))
                }
                Some(d) => d as u32,
                None => self.read_only.loaded_tool,
            };
            // A Fanuc control's D registers are the control's own: only the program sets
            // them (G10). The tool library's cutters are the simulation's, not registers:
            // taking their radius compensated a wear-compensation path a second time.
            let known = if self.fanuc {
                self.tool_radii.get(&tool).map(|r| 2.0 * r)
            } else {
                self.tool_diameter(tool)
            };
            if tool == 0 {
                0.0
            } else {
                match known {
                    Some(d) => d / 2.0,
                    None if self.fanuc => {
                        if !self.comp_registers_told.contains(&tool) {
                            self.comp_registers_told.push(tool);
                            let (at, named) = if b.has(b'd') {
                                (b.at[slot(b'd')], format!("D{tool}"))
                            } else {
                                (
                                    b.g_at[group::CUTTER_COMP],
                                    format!("(register D{tool}, the loaded tool's)"),
                                )
                            };
                            self.later.push((
                                at as usize,
                                format!(
                                    "G{} {named}: the offset in register D{tool} is the \
                                     control's, not in the program: the path is read as the \
                                     tool centre's, as CAM systems write it for wear \
                                     compensation (a G10 in the program sets a register; \
                                     --dialect linuxcnc reads D{tool} as tool {tool}, whose \
                                     radius --tool or --tools gives)",
                                    g / 10
                                ),
                            ));
                        }
                        0.0
                    }
                    None => {
                        return Err(Fault::new(
                            PathErrorKind::Semantic,
                            if b.has(b'd') { b.span(b'd') } else { span },
                            format!(
                                "cutter radius compensation needs the diameter of tool {tool}, \
                                 which the tool table does not give"
                            ),
                            "a tool table with the tool (--tools), G10 L1 P<tool> R<radius>, \
                             G41.1/G42.1 D<diameter>, or --dialect fanuc (D registers the \
                             control's: the path read as the tool centre's)",
                        ))
                    }
                }
            }
        };
        // A zero radius leaves the path as programmed, but compensation is on (LinuxCNC sets
        // the side whatever the radius: G20, another G41, G92 … are refused until G40).
        let left = g == 410 || g == 411;
        let side = if (radius < 0.0) == left {
            Side::Right
        } else {
            Side::Left
        };
        self.comp.side = Some(side);
        self.comp.radius = radius.abs();
        self.comp.first = true;
        self.comp.tool = self.plane_of(&self.p);
        self.comp.held = None;
        Ok(())
    }

    /// The compensation's points (the tool, the held move's start, end, centre and a point
    /// along its direction from its start) as machine positions, before a change of frame:
    /// [`Self::comp_reframe`] re-expresses them in the new one. `None` when moves are not
    /// compensated.
    pub(crate) fn comp_points(&self) -> Option<[[f64; 6]; 5]> {
        if !self.comp.moving() {
            return None;
        }
        let h = self.comp.held.unwrap_or(Held {
            start: self.comp.tool,
            end: self.comp.tool,
            arc: None,
            rapid: false,
            dir: [0.0; 2],
        });
        let c = h.arc.map_or(h.start, |(c, _)| c);
        let d = [h.start[0] + h.dir[0], h.start[1] + h.dir[1]];
        Some(
            [self.comp.tool, h.start, h.end, c, d]
                .map(|q| self.machine_of(&self.with_plane(&self.p, q))),
        )
    }

    /// The frame changed under compensation (G10 L2/L20 of the active system, which LinuxCNC
    /// accepts): the tool's point and the held move, `pts` from [`Self::comp_points`], are
    /// re-expressed in the new frame, as the programmed point is, so the next corner is
    /// judged between the two in one frame. (LinuxCNC's `convert_setup` moves its current
    /// point, the tool's, and leaves the programmed point in the old frame, which makes the
    /// next corner from points in two frames; swarf keeps both in step instead.) `old` is the
    /// frame the queued events were made in.
    pub(crate) fn comp_reframe(&mut self, pts: [[f64; 6]; 5], old: Frame) {
        let q = pts.map(|m| self.plane_of(&self.program_of(&m, &self.off, &self.g92, self.rot)));
        self.comp.tool = q[0];
        if let Some(h) = &mut self.comp.held {
            h.start = q[1];
            h.end = q[2];
            if let Some((c, _)) = &mut h.arc {
                *c = q[3];
            }
            h.dir = sub(q[4], q[1]);
            self.comp.queue_frames.push(old);
        }
    }

    /// Emits the held move and everything queued behind it.
    pub(crate) fn comp_flush(&mut self) {
        self.comp.held = None;
        self.comp.queue_frames.clear();
        let queue = std::mem::take(&mut self.comp.queue);
        for (line, e) in &queue {
            self.sink.emit(*line, e);
        }
        self.comp.queue = queue;
        self.comp.queue.clear();
    }

    /// A straight (`rapid`) or arc move to `end` (programmed) with compensation on.
    pub(crate) fn comp_move(
        &mut self,
        b: &Block,
        end: [f64; 6],
        rapid: bool,
        arc: Option<([f64; 2], i32)>,
    ) -> Res<()> {
        // The motion word, or the first axis word of a modal move.
        let span = match b.g(group::MOTION) {
            Some(_) => b.g_span(group::MOTION),
            None => b"xyzabc"
                .iter()
                .find(|&&c| b.has(c))
                .map_or(Span::Line, |&c| b.span(c)),
        };
        let mv = PlaneMove {
            start: self.plane_of(&self.p),
            end: self.plane_of(&end),
            arc,
        };
        let side = self.comp.side.expect("called with compensation on");
        let r = self.comp.radius;
        if arc.is_none() && mv.start == mv.end {
            // No motion in the plane: the tool moves along the plane's normal (and rotary
            // axes) where it is; corners are judged without it.
            let p = self.with_plane(&end, self.comp.tool);
            let e = if rapid {
                Canon::Traverse {
                    end: Axes::from_array(p),
                }
            } else {
                Canon::Feed {
                    end: Axes::from_array(p),
                }
            };
            self.emit(e);
            self.p = end;
            return Ok(());
        }
        let normal = if side == Side::Left {
            FRAC_PI_2
        } else {
            -FRAC_PI_2
        };
        if self.comp.first {
            if let Some((c, turn)) = arc {
                return self.comp_entry_arc(end, span, c, turn);
            }
            let from = self.comp.tool;
            let length = dist(from, mv.end);
            if self.fanuc && length > 0.0 && length <= r {
                // Fanuc starts up on any entry move (the offset vector normal to it at its
                // end); LinuxCNC refuses one no longer than the radius.
                if let Span::Code(at, _) = span {
                    self.later.push((
                        at,
                        format!(
                            "cutter compensation entry move ({length:.4} mm) not longer than the \
                             tool radius ({r:.4} mm): the tool may cut back into the part"
                        ),
                    ));
                }
            } else if length <= r {
                return Err(Fault::semantic(
                    span,
                    "length of cutter compensation entry move is not greater than the tool radius",
                ));
            }
            let a = angle(sub(mv.end, from)) + normal;
            let to = polar(mv.end, r, a);
            self.comp.first = false;
            self.comp_hold(end, to, from, None, rapid, sub(mv.end, from));
            return Ok(());
        }
        let corner = mv.start;
        let tool = self.comp.tool;
        let mut alpha = mv.start_direction();
        let mut theta = angle(sub(tool, corner));
        let beta = if side == Side::Left {
            if theta < alpha {
                theta += TAU;
            }
            theta - alpha - FRAC_PI_2
        } else {
            if alpha < theta {
                alpha += TAU;
            }
            alpha - theta - FRAC_PI_2
        };
        let held = self.comp.held;
        let h_shape = beta > PI - SMALL
            && held.is_some_and(|h| {
                h.arc.is_some_and(|(_, turn)| {
                    (side == Side::Right && turn > 0) || (side == Side::Left && turn < 0)
                })
            });
        let concave = !(-SMALL..=PI + SMALL).contains(&beta) || h_shape;
        let offset_start = polar(corner, r, alpha + normal);
        // The new move's offset geometry: a line through its offset start, or a circle.
        let new_circle = match arc {
            None => None,
            Some((c, turn)) => {
                let inside = (side == Side::Left) == (turn > 0);
                let rad = dist(mv.start, c);
                if inside && rad <= r {
                    return Err(Fault::semantic(
                        span,
                        format!(
                            "tool radius ({r:.4} mm) not less than the arc radius ({rad:.4} mm) \
                             with cutter radius compensation"
                        ),
                    ));
                }
                // The compensated arc is the circle through its end (its canonical form).
                let rad_end = dist(mv.end, c);
                Some((
                    c,
                    if inside { rad_end - r } else { rad_end + r },
                    turn,
                    inside,
                ))
            }
        };
        let start = if !concave && beta > SMALL {
            // Convex corner: an arc about the programmed corner.
            self.comp_flush();
            // The corner arc keeps the other axes where the tool is (LinuxCNC: current Z).
            let p = self.with_plane(&self.p, offset_start);
            let turn = if side == Side::Left { -1 } else { 1 };
            let e = Canon::Arc {
                end: Axes::from_array(p),
                center: corner,
                rotation: turn,
                plane: self.plane,
            };
            self.emit(e);
            offset_start
        } else if concave {
            let Some(h) = held else {
                self.comp_flush();
                return self.comp_continue(end, tool, new_circle, mv, r, normal, rapid);
            };
            let hits = match (h.arc, new_circle) {
                (None, None) => {
                    let d1 = h.dir;
                    let d2 = sub(mv.end, mv.start);
                    let den = d1[0] * d2[1] - d1[1] * d2[0];
                    if den == 0.0 {
                        vec![h.end]
                    } else {
                        let w = sub(offset_start, h.end);
                        let s = (w[0] * d2[1] - w[1] * d2[0]) / den;
                        vec![[h.end[0] + s * d1[0], h.end[1] + s * d1[1]]]
                    }
                }
                (None, Some((c, rad, ..))) => line_circle(h.end, h.dir, c, rad),
                (Some((c, _)), None) => {
                    line_circle(offset_start, sub(mv.end, mv.start), c, dist(h.end, c))
                }
                (Some((c1, _)), Some((c2, rad2, ..))) => {
                    circle_circle(c1, dist(h.end, c1), c2, rad2)
                }
            };
            if hits.is_empty() {
                let what = match (h.arc.is_some(), arc.is_some()) {
                    (false, true) => "straight to arc",
                    (true, false) => "arc to straight",
                    (true, true) => "arc to arc",
                    (false, false) => "straight to straight",
                };
                return Err(Fault::semantic(
                    span,
                    format!(
                        "{what} motion makes a corner the compensated tool can't fit in \
                         without gouging"
                    ),
                ));
            }
            // The held move must still go the same way after it is cut back: of the
            // meeting points, the nearest to its end that it reaches going forward.
            let forward = |x: [f64; 2]| match h.arc {
                None => {
                    let a = sub(x, h.start);
                    a[0] * h.dir[0] + a[1] * h.dir[1] >= 0.0
                }
                Some((c, turn)) => {
                    // A full circle (its compensated ends apart by rounding: the sweep from
                    // start to end would read ≈ 0, not 2π) reaches every point.
                    let full = dist(h.start, h.end) <= 1e-9 * (1.0 + dist(h.start, c));
                    full || sweep(c, h.start, x, turn) <= sweep(c, h.start, h.end, turn) + 1e-9
                }
            };
            let Some(x) = hits
                .into_iter()
                .filter(|&x| forward(x))
                .min_by(|a, b| dist(*a, h.end).total_cmp(&dist(*b, h.end)))
            else {
                let what = match (h.arc, h.rapid) {
                    (Some(_), _) => "arc move",
                    (None, true) => "straight traverse",
                    (None, false) => "straight feed",
                };
                return Err(Fault::semantic(
                    span,
                    format!(
                        "{what} in concave corner cannot be reached by the tool without gouging"
                    ),
                ));
            };
            self.comp_move_held_end(x);
            self.comp_flush();
            x
        } else {
            self.comp_flush();
            tool
        };
        self.comp_continue(end, start, new_circle, mv, r, normal, rapid)
    }

    /// An arc as the entry move (LinuxCNC's `convert_arc_comp1`): its centre `c` is the one
    /// found from the current point ([`Self::comp_entry_arc_checks`] ran before it was), it
    /// ends `r` from its programmed end along the ray from the centre (towards the centre when
    /// the tool is inside the arc), and goes from the current point there about `c`: with an
    /// R word the two radii differ by `r` (a spiral, as LinuxCNC makes it).
    fn comp_entry_arc(&mut self, end: [f64; 6], span: Span, c: [f64; 2], turn: i32) -> Res<()> {
        if self.fanuc {
            // Fanuc alarm PS0034: no start-up in a circular block.
            return Err(Fault::new(
                PathErrorKind::Semantic,
                span,
                "the first move after G41/G42 (the compensation start-up) cannot be an arc on \
                 a Fanuc control (alarm 034)",
                "a G0 or G1 start-up move (or --dialect linuxcnc, whose entry arc ends the \
                 radius from its programmed end)",
            ));
        }
        let side = self.comp.side.expect("called with compensation on");
        let r = self.comp.radius;
        let from = self.comp.tool;
        let end2 = self.plane_of(&end);
        let inside = (side == Side::Left) == (turn > 0);
        let rad = dist(from, c);
        if inside && rad <= r {
            return Err(Fault::semantic(
                span,
                format!(
                    "tool radius ({r:.4} mm) not less than the arc radius ({rad:.4} mm) with \
                     cutter radius compensation"
                ),
            ));
        }
        let gamma = if inside {
            angle(sub(c, end2))
        } else {
            angle(sub(end2, c))
        };
        let to = polar(end2, r, gamma);
        self.comp.first = false;
        self.comp_hold(end, to, from, Some((c, turn)), false, [0.0; 2]);
        Ok(())
    }

    /// The entry arc's own checks, made before its centre is found (LinuxCNC's order in
    /// `convert_arc_comp1`): its programmed end must be more than the tool radius from the
    /// current point. Returns what the I J K check adds to the end radius (`−r` with the tool
    /// inside the arc, `+r` outside: `arc_data_comp_ijk` compares the start radius with the
    /// offset end's), `None` when the arc is not an entry move.
    pub(crate) fn comp_entry_arc_checks(
        &self,
        span: Span,
        end: [f64; 2],
        clockwise: bool,
    ) -> Res<Option<f64>> {
        let Some(r) = self.comp.entry_radius() else {
            return Ok(None);
        };
        if self.fanuc {
            return Ok(None);
        }
        if dist(self.comp.tool, end) <= r {
            return Err(Fault::semantic(
                span,
                "radius of cutter compensation entry arc is not greater than the tool radius",
            ));
        }
        let inside = (self.comp.side == Some(Side::Left)) != clockwise;
        Ok(Some(if inside { -r } else { r }))
    }

    /// LinuxCNC's `arc_data_comp_r` check, before the centre of an R arc under compensation
    /// is found: with the tool inside the arc, |R| must exceed the tool radius.
    pub(crate) fn comp_r_check(&self, span: Span, radius: f64, clockwise: bool) -> Res<()> {
        if !self.comp.moving() {
            return Ok(());
        }
        let r = self.comp.radius;
        let inside = (self.comp.side == Some(Side::Left)) != clockwise;
        if inside && radius.abs() <= r {
            return Err(Fault::semantic(
                span,
                format!(
                    "tool radius ({r:.4} mm) not less than the arc radius ({:.4} mm) with \
                     cutter radius compensation",
                    radius.abs()
                ),
            ));
        }
        Ok(())
    }

    /// Holds the new move: from `start` (plane) to its offset end.
    #[allow(clippy::too_many_arguments)]
    fn comp_continue(
        &mut self,
        end: [f64; 6],
        start: [f64; 2],
        circle: Option<([f64; 2], f64, i32, bool)>,
        mv: PlaneMove,
        r: f64,
        normal: f64,
        rapid: bool,
    ) -> Res<()> {
        match circle {
            None => {
                let a = angle(sub(mv.end, mv.start)) + normal;
                let to = polar(mv.end, r, a);
                self.comp_hold(end, to, start, None, rapid, sub(mv.end, mv.start));
            }
            Some((c, _, turn, inside)) => {
                let rad_end = dist(mv.end, c);
                let rad_end = if inside { rad_end - r } else { rad_end + r };
                let to = polar(c, rad_end, angle(sub(mv.end, c)));
                self.comp_hold(end, to, start, Some((c, turn)), rapid, [0.0; 2]);
            }
        }
        Ok(())
    }

    /// Emits (into the queue) the compensated move ending at `to` and holds it.
    #[allow(clippy::too_many_arguments)]
    fn comp_hold(
        &mut self,
        end: [f64; 6],
        to: [f64; 2],
        from: [f64; 2],
        arc: Option<([f64; 2], i32)>,
        rapid: bool,
        dir: [f64; 2],
    ) {
        let p = Axes::from_array(self.with_plane(&end, to));
        let e = match arc {
            Some((center, rotation)) => Canon::Arc {
                end: p,
                center,
                rotation,
                plane: self.plane,
            },
            None if rapid => Canon::Traverse { end: p },
            None => Canon::Feed { end: p },
        };
        debug_assert!(self.comp.queue.is_empty());
        // Through `emit` (tool bookkeeping), then into the queue.
        self.comp.held = Some(Held {
            start: from,
            end: to,
            arc,
            rapid,
            dir,
        });
        self.emit(e);
        self.comp.tool = to;
        self.p = end;
    }

    /// Moves the held move's end in the plane to `x`, and that of every move queued behind it
    /// (moves along the plane's normal made where the held move ended: LinuxCNC's
    /// `move_endpoint_and_flush` changes them all — "moving into a concave corner, then up and
    /// back down, then continuing on: three moves to change").
    ///
    /// `x` is in the current frame; events made before a change of frame take it in theirs.
    fn comp_move_held_end(&mut self, x: [f64; 2]) {
        let (f, s, _) = self.plane.axes();
        let m = self.machine_of(&self.with_plane(&self.p, x));
        let xs: Vec<[f64; 2]> = self
            .comp
            .queue_frames
            .iter()
            .map(|(off, g92, rot)| self.plane_of(&self.program_of(&m, off, g92, *rot)))
            .collect();
        let mut segment = 0;
        for (_, e) in self.comp.queue.iter_mut() {
            if let Canon::Offsets { .. } = e {
                segment += 1;
            }
            let x = xs.get(segment).copied().unwrap_or(x);
            if let Canon::Traverse { end } | Canon::Feed { end } | Canon::Arc { end, .. } = e {
                let mut a = end.to_array();
                a[f] = x[0];
                a[s] = x[1];
                *end = Axes::from_array(a);
            }
        }
        if let Some(h) = &mut self.comp.held {
            h.end = x;
        }
    }
}
