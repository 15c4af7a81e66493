//! Cutter radius compensation (G40, G41, G42, G41.1, G42.1) as LinuxCNC's interpreter does it
//! (`convert_straight_comp1/2`, `convert_arc_comp1/2`, `move_endpoint_and_flush` in
//! `interp_convert.cc`), in the G17 (XY) and G18 (ZX) planes.
//!
//! The tool runs at the compensation radius `r` to the left (G41) or right (G42) of the
//! programmed contour, looking along the motion; a negative radius swaps the sides.
//!
//! * **Entry**: the first move after G41/G42 ends `r` from its programmed end. A straight
//!   one (which must move in the plane, and be longer than `r`) ends on the normal to it. An
//!   arc (`convert_arc_comp1`; its end must be more than `r` from its start, and its I J K are
//!   checked as any arc's, programmed radius against programmed radius) ends on the radius
//!   through its programmed end, `r` nearer the centre (tool inside) or farther, and its
//!   centre moves along that radius to where it is as far from the start as from the new end,
//!   so the entry arc is round. (Fanuc: the entry starts at the first move in the plane; an
//!   entry arc is alarm 034.)
//! * **Zero radius** (`G41 D0`, `G41.1 D0`): compensation is on (the side is set: G20, another
//!   G41, G92 … are refused as with any radius) but moves are not offset.
//! * **Corners**: the compensated move is held back (queued with every event that follows it)
//!   until the next move shows the corner (`convert_straight_comp2`, `convert_arc_comp2`),
//!   with LinuxCNC's quantities: `θ` from the programmed corner to the tool, `α` the new move's
//!   start direction, `β` the turn between them less 90°. A convex corner (`β > small`) gets
//!   an arc about the programmed corner to the new move's offset start (a straight traverse
//!   before a rapid); at a concave corner (`β < −small`, `β > π + small`, an "h" after an arc
//!   with the tool outside, or a tangent arc with the tool outside) the held move's end moves
//!   back to where LinuxCNC's formulas put it — line to line by the half corner's cotangent,
//!   arc to line, line to arc and arc to arc by its triangles, the first two of which take
//!   the tool to sit square to the programmed corner, `r` along the held arc's radius or
//!   normal to the held line (not so after an entry move, whose tool path is not parallel to
//!   its programmed one: the cut-back then lands off the exact crossing, as LinuxCNC's does);
//!   of two crossings the turns choose, not the distance (a full circle keeps its turn). The
//!   moved end is checked as `move_endpoint_and_flush` checks it: a line must not turn against
//!   the direction it was queued with (the entry line's is its normal), an arc not sweep
//!   farther than it was made to. A near-tangent corner is flushed as it is. `small` is
//!   LinuxCNC's `TOLERANCE_CONCAVE_CORNER`, 0.05 rad.
//! * **Arcs** keep their centre; the tool runs on the radius `R + r` (outside) or `R − r`
//!   (inside, an error when the end radius `R < r`: equal is taken, see [`EQUAL_RADIUS_MM`]).
//! * **Exit**: after G40 the held move is flushed (checked as a moved end), the interpreter's
//!   position is the programmed one, and the next move (straight: an arc is an error) goes
//!   from the compensated position to its programmed end — unless a tool change comes first,
//!   after which the position is re-read where the tool stands, as LinuxCNC's task does.
//!
//! The interpreter's position (`Interp::p`) stays the *programmed* one while compensation is
//! on, so incremental words, arc centres and parameters read as LinuxCNC's do; the tool's
//! position in the plane is kept here.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// How much shorter than a tool table's radius an entry move, an entry arc's radius or an arc
/// the tool runs inside may be and still be taken as equal to it. rs274 refuses `distance <= radius`, but its radius comes through
/// unit conversions of the tool table (inch to mm and back) that leave it a rounding under the
/// nominal value, so an entry exactly as long as the radius runs on LinuxCNC (nc_files'
/// useful-subroutines.ngc enters by one tool radius; rs274 2.9 takes a 0.25 in entry with a
/// 0.5 in tool, and a 1.5875 mm one with a 0.125 in tool). A tolerance far under any
/// machining quantity keeps that equality where swarf's millimetres compute it exactly.
const EQUAL_RADIUS_MM: f64 = 1e-9;

use super::block::{group, slot, Block};
use super::interp::Interp;
use super::{Fault, Res, Span};
use crate::canon::OwnedCanon;
use crate::{Axes, Canon, CanonSink, PathErrorKind, Plane, Units};

/// LinuxCNC's `TOLERANCE_CONCAVE_CORNER` (radians): corners within this of tangent get neither
/// an arc nor a cut-back.
const SMALL: f64 = 0.05;

/// LinuxCNC's `TOLERANCE_EQUAL`: below this the cosine of the entry arc's triangle angle reads
/// as zero (`convert_arc_comp1`).
const TOLERANCE_EQUAL: f64 = 0.0001;

/// Which side of the contour the tool runs on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Side {
    /// G41: left of the contour, looking along the motion.
    Left,
    /// G42: right.
    Right,
}

/// The compensated move held back until the next one shows its corner (LinuxCNC's queue front,
/// with its `endpoint`).
#[derive(Clone, Copy, Debug)]
struct Held {
    /// Where the tool starts it (plane coordinates, mm): LinuxCNC's `endpoint`.
    start: [f64; 2],
    /// False when LinuxCNC's `endpoint` is not valid (the entry arc's: `convert_arc_comp1` sets
    /// none), which skips the checks of a moved end.
    start_known: bool,
    /// Where it ends now (moved back at a concave corner).
    end: [f64; 2],
    /// Its centre and turn (positive counter-clockwise), for an arc.
    arc: Option<([f64; 2], i32)>,
    /// For an arc, its sweep (radians, signed) as queued: `original_turns`, from the
    /// programmed start and end (from the tool's start and end for the entry arc).
    sweep: f64,
    /// A rapid (LinuxCNC words its error differently).
    rapid: bool,
    /// For a line, the direction LinuxCNC queues with it (the programmed direction; for the
    /// entry move the normal to it, towards the tool): a moved end that goes against it is a
    /// gouge.
    dir: [f64; 2],
}

/// Compensation state.
#[derive(Debug, Default)]
pub(crate) struct Comp {
    /// On, and on which side.
    pub(crate) side: Option<Side>,
    /// The radius, mm, positive.
    radius: f64,
    /// The radius is the tool table's, which reaches rs274 a rounding under its nominal value
    /// (see [`EQUAL_RADIUS_MM`]); a G41.1/G42.1 `D` is taken as written.
    from_table: bool,
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

/// LinuxCNC's `find_turn`: the signed sweep (radians) of an arc of `turn` turns from `p1` to
/// `p2` about `c` (a whole turn when they coincide).
fn find_turn(p1: [f64; 2], c: [f64; 2], turn: i32, p2: [f64; 2]) -> f64 {
    if turn == 0 {
        return 0.0;
    }
    let mut alpha = angle(sub(p1, c));
    let mut beta = angle(sub(p2, c));
    if turn > 0 {
        if beta <= alpha {
            beta += TAU;
        }
        beta - alpha + f64::from(turn - 1) * TAU
    } else {
        if alpha <= beta {
            alpha += TAU;
        }
        beta - alpha + f64::from(turn + 1) * TAU
    }
}

/// LinuxCNC's `TOOL_INSIDE_ARC`: the tool on the side of the arc's centre.
fn tool_inside(side: Side, turn: i32) -> bool {
    (side == Side::Left && turn > 0) || (side == Side::Right && turn < 0)
}

/// A new compensated move's programmed start and end in plane coordinates.
#[derive(Clone, Copy, Debug)]
struct PlaneMove {
    start: [f64; 2],
    end: [f64; 2],
}

impl Comp {
    /// How far under the radius a length still passes as longer than it: [`EQUAL_RADIUS_MM`]
    /// for a tool table's radius (rs274 takes the equality), and for a G41.1/G42.1 `D`, which
    /// rs274 takes as written and so refuses at equality, minus that (an equality that the
    /// conversion to mm leaves a rounding over the radius is still refused).
    fn equal_within(&self) -> f64 {
        if self.from_table {
            EQUAL_RADIUS_MM
        } else {
            -EQUAL_RADIUS_MM
        }
    }

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

    /// After a block with a tool change under LinuxCNC's rules: rs274 ends the block
    /// (INTERP_EXECUTE_FINISH) and the task re-reads the position, which right after G40 (no
    /// straight move since: `arc_not_allowed`) is where the tool stands, the compensated point,
    /// not the programmed one (nc_files' useful-subroutines.ngc: the next `G0 Z` goes straight
    /// up there). The move after G40 must still be straight.
    pub(crate) fn comp_resync_after_change(&mut self) {
        if self.arc_not_allowed {
            self.p = self.with_plane(&self.p, self.comp.tool);
        }
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
                // move was made (LinuxCNC leaves the rest alone before the first one). The held
                // move is flushed where it ends, checked as a moved end is.
                self.comp_move_end_and_flush(self.comp.tool, span)?;
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
        self.comp.from_table = !(g == 411 || g == 421);
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
            start_known: false,
            end: self.comp.tool,
            arc: None,
            sweep: 0.0,
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
        };
        let side = self.comp.side.expect("called with compensation on");
        let r = self.comp.radius;
        let plane_still = arc.is_none() && mv.start == mv.end;
        if plane_still && (self.fanuc || !self.comp.first) {
            // No motion in the plane: the tool moves along the plane's normal (and rotary
            // axes) where it is; corners are judged without it. (A LinuxCNC entry move must
            // move in the plane: `convert_straight_comp1` refuses it below; a Fanuc control
            // starts up at the first block that does.)
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
            } else if length <= r - self.comp.equal_within() {
                return Err(Fault::semantic(
                    span,
                    "length of cutter compensation entry move is not greater than the tool radius",
                ));
            }
            // LinuxCNC's `convert_straight_comp1`: the move queues the normal (towards the
            // tool) as its direction, which a later cut-back is tested against.
            let a = angle(sub(mv.end, from))
                + if side == Side::Left {
                    FRAC_PI_2
                } else {
                    -FRAC_PI_2
                };
            let to = polar(mv.end, r, a);
            self.comp.first = false;
            self.comp_hold(
                end,
                Held {
                    start: from,
                    start_known: true,
                    end: to,
                    arc: None,
                    sweep: 0.0,
                    rapid,
                    dir: [a.cos(), a.sin()],
                },
            );
            return Ok(());
        }
        match arc {
            None => self.comp_straight(end, span, mv, rapid),
            Some((c, turn)) => self.comp_arc(end, span, mv, c, turn),
        }
    }

    /// A straight move after the entry move: LinuxCNC's `convert_straight_comp2`, its
    /// quantities and formulas (`θ` the direction from the programmed corner to the tool, `α`
    /// the move's, `β` the turn between the previous move and this one less 90°).
    fn comp_straight(&mut self, end: [f64; 6], span: Span, mv: PlaneMove, rapid: bool) -> Res<()> {
        let side = self.comp.side.expect("called with compensation on");
        let r = self.comp.radius;
        let op = mv.start;
        let tool = self.comp.tool;
        let mut theta = angle(sub(tool, op));
        let mut alpha = angle(sub(mv.end, op));
        let (beta, gamma) = if side == Side::Left {
            if theta < alpha {
                theta += TAU;
            }
            (theta - alpha - FRAC_PI_2, FRAC_PI_2)
        } else {
            if alpha < theta {
                alpha += TAU;
            }
            (alpha - theta - FRAC_PI_2, -FRAC_PI_2)
        };
        let to = polar(mv.end, r, alpha + gamma);
        let mid = polar(op, r, alpha + gamma);
        let held = self.comp.held;
        // The "h" shape: round an arc with the tool outside it, then straight on alongside;
        // LinuxCNC stays above and beside rather than loop around.
        let h_shape = beta > PI - SMALL
            && held.is_some_and(|h| {
                h.arc.is_some_and(|(_, turn)| {
                    (side == Side::Right && turn > 0) || (side == Side::Left && turn < 0)
                })
            });
        let concave = !(-SMALL..=PI + SMALL).contains(&beta) || h_shape;
        let start = if !concave && beta > SMALL {
            // Convex: around the programmed corner to the new move's offset start (a rapid
            // goes there straight: there is no arc traverse).
            self.comp_move_end_and_flush(tool, span)?;
            let p = self.corner_point(&end, mid);
            let e = if rapid {
                Canon::Traverse { end: p }
            } else {
                Canon::Arc {
                    end: p,
                    center: op,
                    rotation: if side == Side::Left { -1 } else { 1 },
                    plane: self.plane,
                }
            };
            self.emit(e);
            mid
        } else if concave {
            let x = match held {
                None => {
                    // Nothing held (LinuxCNC reads an empty queue here): flushed as it is.
                    self.comp_flush();
                    tool
                }
                Some(Held { arc: None, .. }) => {
                    // Line to line: back along the held move by the half corner's cotangent.
                    let half = (beta + PI) / 2.0;
                    if half == 0.0 {
                        return Err(Fault::semantic(
                            span,
                            "zero degree inside corner is invalid for cutter compensation",
                        ));
                    }
                    polar(tool, r / half.tan(), theta + gamma)
                }
                Some(Held {
                    arc: Some((pc, pturn)),
                    end: pe,
                    ..
                }) => {
                    // Arc to line: the held arc (compensated) meets the new offset line where
                    // LinuxCNC's triangle puts it (taking the programmed corner `r` from the
                    // tool's end, along its radius).
                    let oldrad = dist(pc, pe);
                    let base = angle(sub(mv.end, op));
                    let th = if pturn > 0 {
                        base + FRAC_PI_2
                    } else {
                        base - FRAC_PI_2
                    };
                    let phi = angle(sub(pc, op));
                    let inside = tool_inside(side, pturn);
                    let uncomp = if inside { oldrad + r } else { oldrad - r };
                    let d = uncomp * (th - phi).cos();
                    let l = if inside { d - r } else { d + r } / oldrad;
                    if !(-1.0..=1.0).contains(&l) {
                        return Err(Fault::semantic(
                            span,
                            "arc to straight motion makes a corner the compensated tool can't fit \
                             in without gouging",
                        ));
                    }
                    let a = if inside == (pturn > 0) {
                        -l.acos()
                    } else {
                        l.acos()
                    };
                    polar(pc, oldrad, a + th + PI)
                }
            };
            if held.is_some() {
                self.comp_move_end_and_flush(x, span)?;
            }
            x
        } else {
            // Tangent, or colinear.
            self.comp_flush();
            tool
        };
        self.comp_hold(
            end,
            Held {
                start,
                start_known: true,
                end: to,
                arc: None,
                sweep: 0.0,
                rapid,
                dir: sub(mv.end, op),
            },
        );
        Ok(())
    }

    /// An arc after the entry move, about the programmed centre `c`: LinuxCNC's
    /// `convert_arc_comp2`.
    fn comp_arc(
        &mut self,
        end: [f64; 6],
        span: Span,
        mv: PlaneMove,
        c: [f64; 2],
        turn: i32,
    ) -> Res<()> {
        let side = self.comp.side.expect("called with compensation on");
        let r = self.comp.radius;
        let op = mv.start;
        let tool = self.comp.tool;
        let arc_radius = dist(c, mv.end);
        let theta = angle(sub(tool, op))
            + if side == Side::Left {
                -FRAC_PI_2
            } else {
                FRAC_PI_2
            };
        let mut delta = angle(sub(c, op));
        let alpha = if turn > 0 {
            delta - FRAC_PI_2
        } else {
            delta + FRAC_PI_2
        };
        let mut beta = if side == Side::Left {
            theta - alpha
        } else {
            alpha - theta
        };
        if beta > 1.5 * PI {
            beta -= TAU;
        } else if beta < -FRAC_PI_2 {
            beta += TAU;
        }
        let inside = tool_inside(side, turn);
        let gamma = if inside {
            if arc_radius <= r - self.comp.equal_within() {
                return Err(Fault::semantic(
                    span,
                    format!(
                        "tool radius ({r:.4} mm) not less than the arc radius ({arc_radius:.4} \
                         mm) with cutter radius compensation"
                    ),
                ));
            }
            angle(sub(c, mv.end))
        } else {
            delta += PI;
            angle(sub(mv.end, c))
        };
        let to = polar(mv.end, r, gamma);
        let concave = !(-SMALL..=PI + SMALL).contains(&beta)
            // A tangent reversal onto an arc with the tool outside it (atop the middle of an
            // "m", or of an "h"): LinuxCNC takes it as concave.
            || ((beta - PI).abs() < SMALL && !inside);
        let start = if concave {
            let x = match self.comp.held {
                None => {
                    // Nothing held (LinuxCNC reads an empty queue here): flushed as it is.
                    self.comp_flush();
                    tool
                }
                Some(Held { arc: None, .. }) => {
                    // Line to arc.
                    let cy = arc_radius * (beta - FRAC_PI_2).sin();
                    let (d, toward) = if inside {
                        (arc_radius - r, cy + r)
                    } else {
                        (arc_radius + r, cy - r)
                    };
                    let l = toward / d;
                    if !(-1.0..=1.0).contains(&l) {
                        return Err(Fault::semantic(
                            span,
                            "arc move in concave corner cannot be reached by the tool without \
                             gouging",
                        ));
                    }
                    let a = match (inside, turn > 0) {
                        (true, true) => theta + l.asin(),
                        (true, false) => theta - l.asin(),
                        (false, true) => theta + PI - l.asin(),
                        (false, false) => theta + PI + l.asin(),
                    };
                    polar(c, d, a)
                }
                Some(Held {
                    arc: Some((pc, pturn)),
                    end: pe,
                    ..
                }) => {
                    // Arc to arc: where the two compensated circles meet, on the side the
                    // turns give.
                    let oldrad = dist(pc, pe);
                    let newrad = if inside {
                        arc_radius - r
                    } else {
                        arc_radius + r
                    };
                    let cc = dist(pc, c);
                    if oldrad == 0.0 || cc == 0.0 {
                        return Err(Fault::semantic(
                            span,
                            "arc to arc motion is invalid because the arcs have the same center",
                        ));
                    }
                    let a = (oldrad * oldrad + cc * cc - newrad * newrad) / (2.0 * oldrad * cc);
                    if !(-1.0..=1.0).contains(&a) {
                        return Err(Fault::semantic(
                            span,
                            "arc to arc motion makes a corner the compensated tool can't fit in \
                             without gouging",
                        ));
                    }
                    let pullback = a.acos();
                    let cc_dir = angle(sub(c, pc));
                    let dir = if tool_inside(side, pturn) == (turn > 0) {
                        cc_dir + pullback
                    } else {
                        cc_dir - pullback
                    };
                    polar(pc, oldrad, dir)
                }
            };
            if self.comp.held.is_some() {
                self.comp_move_end_and_flush(x, span)?;
            }
            x
        } else if beta > SMALL {
            // Convex: around the programmed corner to the arc's offset start.
            let mid = polar(op, r, delta);
            self.comp_flush();
            let e = Canon::Arc {
                end: self.corner_point(&end, mid),
                center: op,
                rotation: if side == Side::Left { -1 } else { 1 },
                plane: self.plane,
            };
            self.emit(e);
            mid
        } else {
            self.comp_flush();
            tool
        };
        self.comp_hold(
            end,
            Held {
                start,
                start_known: true,
                end: to,
                arc: Some((c, turn)),
                sweep: find_turn(op, c, turn, mv.end),
                rapid: false,
                dir: [0.0; 2],
            },
        );
        Ok(())
    }

    /// The end of a corner's arc (or rapid) at `mid` in the plane: the axis along the plane's
    /// normal where the tool is, the others (rotary, U V W) at the block's end, as LinuxCNC
    /// enqueues it.
    fn corner_point(&self, end: &[f64; 6], mid: [f64; 2]) -> Axes {
        let (_, _, n) = self.plane.axes();
        let mut p = self.with_plane(end, mid);
        p[n] = self.p[n];
        Axes::from_array(p)
    }

    /// An arc as the entry move (LinuxCNC's `convert_arc_comp1`): `c` is the centre found from
    /// the current point ([`Self::comp_entry_arc_checks`] ran before it was). The tool ends `r`
    /// from the programmed end along the ray from `c` (towards `c` when the tool is inside the
    /// arc), and the arc is made round again: its centre moves along the line from that end
    /// towards `c` to where it is as far from the start as from the end (the perpendicular
    /// bisector of the two), so the entry arc is a true arc, not a spiral.
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
        if inside && rad <= r - self.comp.equal_within() {
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
        // LinuxCNC's triangle: A the tool's end, B the new centre, C the midpoint of the chord
        // from the start to A; the angle at A is between the chord and the line from A to `c`.
        let b_len = dist(from, to) / 2.0;
        let ab = angle(sub(c, to));
        let a_ang = angle(sub(from, to)) - ab;
        if a_ang.cos().abs() < TOLERANCE_EQUAL {
            // The chord is square to that line: no centre on it is as far from both ends.
            return Err(Fault::semantic(
                span,
                format!(
                    "tool radius ({r:.4} mm) not less than the arc radius with cutter radius \
                     compensation: the entry arc's offset end ({:.4}, {:.4}) is square to its \
                     start and centre, so no arc through both has its centre on the end's radius",
                    to[0], to[1]
                ),
            ));
        }
        let centre = polar(to, b_len / a_ang.cos(), ab);
        self.comp.first = false;
        self.comp_hold(
            end,
            Held {
                start: from,
                start_known: false,
                end: to,
                arc: Some((centre, turn)),
                sweep: find_turn(from, centre, turn, to),
                rapid: false,
                dir: [0.0; 2],
            },
        );
        Ok(())
    }

    /// The entry arc's own checks, made before its centre is found (LinuxCNC's order in
    /// `convert_arc_comp1`): its programmed end must be more than the tool radius from the
    /// current point. (Its I J K are checked as any arc's: `arc_data_comp_ijk` compares the
    /// programmed radii, from the current point and from the programmed end.)
    pub(crate) fn comp_entry_arc_checks(&self, span: Span, end: [f64; 2]) -> Res<()> {
        let Some(r) = self.comp.entry_radius() else {
            return Ok(());
        };
        if self.fanuc {
            return Ok(());
        }
        if dist(self.comp.tool, end) <= r - self.comp.equal_within() {
            return Err(Fault::semantic(
                span,
                "radius of cutter compensation entry arc is not greater than the tool radius",
            ));
        }
        Ok(())
    }

    /// LinuxCNC's `arc_data_comp_r` check, before the centre of an R arc under compensation
    /// is found: with the tool inside the arc, |R| must exceed the tool radius.
    pub(crate) fn comp_r_check(&self, span: Span, radius: f64, clockwise: bool) -> Res<()> {
        if !self.comp.moving() {
            return Ok(());
        }
        let r = self.comp.radius;
        let inside = (self.comp.side == Some(Side::Left)) != clockwise;
        if inside && radius.abs() <= r - self.comp.equal_within() {
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

    /// Emits (into the queue) the compensated move `h` and holds it; `end` is the block's
    /// programmed end (the other axes go there).
    fn comp_hold(&mut self, end: [f64; 6], h: Held) {
        let p = Axes::from_array(self.with_plane(&end, h.end));
        let e = match h.arc {
            Some((center, rotation)) => Canon::Arc {
                end: p,
                center,
                rotation,
                plane: self.plane,
            },
            None if h.rapid => Canon::Traverse { end: p },
            None => Canon::Feed { end: p },
        };
        debug_assert!(self.comp.queue.is_empty());
        // Through `emit` (tool bookkeeping), then into the queue.
        self.comp.held = Some(h);
        self.emit(e);
        self.comp.tool = h.end;
        self.p = end;
    }

    /// LinuxCNC's `move_endpoint_and_flush`: the held move now ends at `x`, checked first: an
    /// arc must not sweep farther than it was made to (by more than 0.0254 rad in a millimetre
    /// program, 0.001 in an inch one: LinuxCNC's length tolerance read as an angle), nor change
    /// its radius by more than 0.01 program units; a line must not turn against its queued
    /// direction.
    fn comp_move_end_and_flush(&mut self, x: [f64; 2], span: Span) -> Res<()> {
        let Some(h) = self.comp.held else {
            return Ok(());
        };
        match h.arc {
            Some((c, turn)) => {
                let unit = if self.units == Units::Inch { 25.4 } else { 1.0 };
                let (r1, r2) = (dist(h.end, c), dist(x, c));
                if (r1 - r2).abs() > 0.01 * unit {
                    return Err(Fault::semantic(
                        span,
                        format!(
                            "cutter compensation made an arc with mismatched radii ({r1:.4} mm and \
                             {r2:.4} mm)"
                        ),
                    ));
                }
                let tolerance = if self.units == Units::Inch {
                    0.001
                } else {
                    0.0254
                };
                let swept = find_turn(h.start, c, turn, x);
                if h.sweep != 0.0 && h.start_known && swept.abs() > h.sweep.abs() + tolerance {
                    return Err(Fault::semantic(
                        span,
                        "arc move in concave corner cannot be reached by the tool without gouging",
                    ));
                }
            }
            None => {
                let moved = sub(x, h.start);
                if h.start_known && h.dir[0] * moved[0] + h.dir[1] * moved[1] < 0.0 {
                    return Err(Fault::semantic(
                        span,
                        format!(
                            "{} in concave corner cannot be reached by the tool without gouging",
                            if h.rapid {
                                "straight traverse"
                            } else {
                                "straight feed"
                            }
                        ),
                    ));
                }
            }
        }
        self.comp_move_held_end(x);
        self.comp_flush();
        Ok(())
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
