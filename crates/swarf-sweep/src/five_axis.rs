//! 5-axis simultaneous moves: adaptive subdivision into constant-axis straight sub-moves whose
//! geometric error is **bounded** by the chordal tolerance, then cut exactly.
//!
//! # What is approximated
//! Along a move the machine puts the tool at poses `P(s) = (T(s), a(s))`, `s ∈ [0, 1]`: tip `T`
//! and unit axis `a`, as [`Program::pose_at`] computes them (joints linear in `s` through the
//! machine kinematics for G-code; a straight or circular tip and a slerped axis for CL data).
//! The cutter instance at `s` is `C(s) = T(s) + R(s)·K`, with `K` the tool in its own frame (tip
//! at the origin, axis +Z) and `R(s)` any rotation taking +Z to `a(s)` (`K` is a solid of
//! revolution, so which one does not matter). The true swept volume of `[s0, s1]` is
//! `S = ∪ C(s)`.
//!
//! A sub-move replaces it by the swept volume `S̃` of a fixed-axis straight move (cut exactly by
//! [`crate::swept`]). It keeps a **pivot**, the point `c(s) = T(s) + λ·a(s)` at height `λ` on
//! the tool axis, on the chord `L(t) = c(s0) + t·(c(s1) − c(s0))` with the fixed axis
//! `ā = a(s_m)` of the middle parameter `s_m = (s0 + s1)/2` (so its tip runs from
//! `c(s0) − λ·ā` to `c(s1) − λ·ā`). Aras (2008, §4.2.4) pivots on the tip (`λ = 0`), takes the
//! average of the end axes and assumes the error small; here it is bounded, and the pivot sits
//! half-way up the shape, which halves the reach of a long tool (below).
//!
//! # The bound
//! Pair `s` with `t = (s − s0)/(s1 − s0)` and let `Q(s)` be the smallest rotation taking `a(s)`
//! to `ā`. The map `φ(x) = L(t) + Q(s)·(x − c(s))` is rigid and takes `C(s)` onto the
//! approximating instance at `t` (`Q·R(s)` takes +Z to `ā`, and the pivot to the chord). A point
//! `x = c(s) + p` of `C(s)`, `|p| ≤ ρ_λ`, moves by
//!
//! ```text
//! |φ(x) − x| ≤ |L(t) − c(s)| + |Q·p − p| ≤ |L(t) − c(s)| + 2·sin(θ/2)·|p| ≤ e_chord + θ·ρ_λ
//! ```
//!
//! with `θ = ∠(a(s), ā)`; `|φ⁻¹(x) − x| ≤ |Qᵀp − p| + |c(s) − L(t)|` obeys the same bound.
//! So every point of `S` is within `ε` of `S̃` and every point of `S̃` within `ε` of `S`
//! (Hausdorff distance `≤ ε`), and a point deeper than `ε` inside some `C(s)` is inside `S̃`
//! (its preimage is still in `C(s)`): the cut leaves no material deeper than `ε` in the true
//! sweep and removes none farther than `ε` from it. Here
//!
//! ```text
//! ε = (M₂ + |λ|·V₂)·Δ²/8 + ρ_λ·W·Δ/2,      Δ = s1 − s0,
//! ```
//!
//! * `ρ_λ` = the largest distance of a point of the shape from the pivot, bounded by
//!   `sqrt(ρ_max² + max(|z_min − λ|, |z_max − λ|)²)` over its parts ([`Reach`]); with
//!   `λ = (z_min + z_max)/2` it is `sqrt((d/2)² + (h/2)²)` for the cutting part instead of
//!   `sqrt((d/2)² + h²)` about the tip, and the shank's is its own half length, not its top's
//!   distance from the tip;
//! * `M₂ ≥ |T''(s)|` and `V₂ ≥ |a''(s)|` on the sub-interval, so `|c''| ≤ M₂ + |λ|·V₂`, and the
//!   chord error of a C² curve vanishing at both ends is at most
//!   `|c''|·(s − s0)(s1 − s)/2 ≤ |c''|·Δ²/8` (apply the scalar bound to `u·(c − L)` with `u` the
//!   unit error direction);
//! * `W ≥ |a'(s)|` on the sub-interval, so `θ(s) ≤ W·|s − s_m| ≤ W·Δ/2`.
//!
//! `M₂` and `W` come from the motion, never from sampling:
//! * **CL data** ([`AxisSource::Program`]): the slerp turns along a great circle at the constant
//!   rate `W = ∠(a0, a1)` (`π` for opposite axes), so `V₂ = W²`; a straight tip has `M₂ = 0`, an
//!   arc, helix or spiral of radius `ρ(s)` linear in `s` and sweep `ψ` has
//!   `|T''| ≤ ρ_max·ψ² + 2·|ρ1 − ρ0|·ψ`.
//! * **Machine joints** ([`AxisSource::Machine`]): the tip is the controlled point carried by
//!   the head joints (inner to outer), translated by the slides `X(s)` (straight, or the arc
//!   mapped rigidly into joint space), then by the inverse table joints (outer to inner); the
//!   axis is +Z through the same rotations. Each joint turns about a fixed line at the constant
//!   rate `w = |Δ joint|` (radians per unit `s`). For `y(s) = c + R(w·s)(x(s) − c)`:
//!   `|y'| ≤ w·ρ + |x'|` and `|y''| ≤ w²·ρ + 2w·|x'| + |x''|`, with `ρ` the largest distance of
//!   `x` from the joint line on the sub-interval (`≤` its distance at `s_m` plus `|x'|·Δ/2`); for
//!   a direction `v`, `|v'_new| ≤ w·σ + |v'|` and `|v''_new| ≤ w²·σ + 2w·|v'| + |v''|` with
//!   `σ ≥ |d × v| ≤ |d × v(s_m)| + |v'|·Δ/2` (a rotation about `d` moves a vector in proportion
//!   to its sine to `d`, so turning C about a vertical tool axis costs nothing). These propagate
//!   through the chain; with TCP the tip is `X(s)` itself. The bounds are local to the
//!   sub-interval, so bisection is adaptive.
//!
//! The interval `[0, 1]` is bisected until `ε ≤` the tolerance ([`subdivide`]); the cutting part
//! and the shank/holder are subdivided separately with their own pivot and reach. The error is
//! first order in `Δ` (a fixed axis cannot follow a turning one), so the count grows like
//! `ρ_λ·W/(2·tol)`. Sweeping the convex hull of the start and end instances would make it
//! second order, but needs line queries against the hull of two differently oriented solids,
//! which the exact fixed-axis kernel does not provide; the sub-moves are cheap (each touches only
//! the rays near it), so the simple bounded scheme is used. (The stock screens a move against its
//! material at a coarse tolerance before the fine bisection, `swarf_stock::cut`; that changes
//! the time, not the result.)
//!
//! # Instances
//! A round tool needs far fewer cuts as a union of exact **instances** `C(s_i)`, second order
//! in their spacing. Where every point of the tool lies in a ball of radius `ρ` inside the tool
//! (a ball or bull-nose end mill and a shank of its diameter, up to `2ρ` below the first sharp
//! edge: `ToolShape::round_region`), write the tool as the union of those balls, centres `p`
//! (`|p| ≤ r_c` from the tip). Take `R(s)` the rotation that carries +Z to `a(s)` by parallel
//! transport (angular velocity `ω = a × a'`, so `|ω| ≤ W` and `|ω'| ≤ |a''| ≤ V₂`; any rotation
//! taking +Z to `a` gives the same solid of revolution). A centre moves on
//! `x(s) = T(s) + R(s)·p`, with
//!
//! ```text
//! |x'| ≤ M₁ + W·r_c,      |x''| ≤ M₂ + (V₂ + W²)·r_c.
//! ```
//!
//! Over `[s0, s1]` the centre stays within `e = |x''|max·Δ²/8` of the chord between its ends,
//! which are `d ≤ |x'|max·Δ` apart. Two balls of radius `ρ` at the ends of a segment of length
//! `d` contain the ball of radius `√(ρ² − d²/4)` about any point of it; so the ball about
//! `x(s)` lies within
//!
//! ```text
//! g = e + ρ − √(ρ² − d²/4)       (≈ e + d²/(8ρ))
//! ```
//!
//! of `C(s0) ∪ C(s1)` ([`MotionBound::instance_gap`]), and a point deeper than `g` inside
//! `C(s)` is inside the union (it lies in the ball of radius `ρ − depth` about the centre of the
//! ball touching its nearest boundary point). The instances are the true tool, so they never
//! remove anything outside the true sweep. `g` is second order in `Δ`: the count grows as
//! `1/√T` where constant-axis pieces grow as `1/T`, and a short move that turns (a 5-axis
//! finishing path) needs a few instances where it needs tens of pieces; a long move that barely
//! turns is still cheaper as pieces (they follow the translation exactly), and the stock takes
//! whichever is fewer. [`instance_times`] splits a range into equal parts, as many as the whole
//! range's rates ask for, each checked on its own rates.

use crate::error::SweepError;
use crate::swept::SweepShape;
use swarf_geom::math::{Mat3, Vec3};
use swarf_path::{AxisSource, Move, MoveKind, Program};

/// Most sub-moves one bisection may make; beyond it the move is refused (a tolerance far below
/// what the rays can resolve, or a huge rotation) rather than run for hours.
pub const MAX_SUB_MOVES: usize = 1 << 20;

/// One constant-axis straight piece of a 5-axis move.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SubMove {
    /// Parameter range of the move it replaces.
    pub s0: f64,
    /// End of the range.
    pub s1: f64,
    /// Tip at the start: the true pivot at `s0` minus the pivot height along `axis`, mm.
    pub tip0: Vec3,
    /// Tip at the end, mm.
    pub tip1: Vec3,
    /// The fixed unit axis: the true axis at the middle parameter.
    pub axis: Vec3,
    /// The bound `ε` on the Hausdorff distance between this piece's swept volume and the true
    /// one, for the [`Reach`] it was made for, mm.
    pub error_bound: f64,
}

/// Where a shape is pivoted and how far it reaches from the pivot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reach {
    /// Height of the pivot on the tool axis above the tip, mm.
    pub pivot: f64,
    /// Largest distance of a point of the shape from the pivot, mm.
    pub radius: f64,
}

impl Reach {
    /// The pivot half-way up `shape` (tool frame) and `sqrt(ρ_max² + z²)` over its parts, `z`
    /// the farther end of each part's height range from the pivot; `None` for an empty shape.
    pub fn of(shape: &SweepShape) -> Option<Reach> {
        let parts = shape.parts();
        let lo = parts.iter().map(|p| p.z_min()).reduce(f64::min)?;
        let hi = parts.iter().map(|p| p.z_max()).reduce(f64::max)?;
        Some(Self::about(shape, 0.5 * (lo + hi)))
    }

    /// The reach of `shape` about the pivot at height `pivot`.
    pub fn about(shape: &SweepShape, pivot: f64) -> Reach {
        let radius = shape
            .parts()
            .iter()
            .map(|p| {
                p.r_max()
                    .hypot((p.z_min() - pivot).abs().max((p.z_max() - pivot).abs()))
            })
            .fold(0.0, f64::max);
        Reach { pivot, radius }
    }
}

/// The tip (or, on a machine, the slides' X Y Z) as a function of `s`, with bounds on its first
/// and second derivatives over the whole move.
#[derive(Clone, Copy, Debug)]
struct Path {
    /// Bound on `|x'(s)|`, mm per unit `s`.
    d1: f64,
    /// Bound on `|x''(s)|`.
    d2: f64,
}

impl Path {
    /// A straight path from `a` to `b`.
    fn line(a: Vec3, b: Vec3) -> Self {
        Path {
            d1: (b - a).length(),
            d2: 0.0,
        }
    }

    /// An arc of `m` (helix and spiral included): `x = c + e_r(s)·ρ(s) + n·(h0 + s·helix)` gives
    /// `x' = e_t·ψ·ρ + e_r·Δρ + n·helix` and `x'' = −e_r·ψ²·ρ + 2·e_t·ψ·Δρ`.
    fn arc(g: &swarf_path::ArcGeom) -> Self {
        let rho = g.start_radius.max(g.end_radius);
        let drho = (g.end_radius - g.start_radius).abs();
        let psi = g.sweep.abs();
        Path {
            d1: psi * rho + drho + g.helix.abs(),
            d2: psi * psi * rho + 2.0 * psi * drho,
        }
    }
}

/// One rotary joint turning about a fixed line, its angle linear in `s`.
#[derive(Clone, Copy, Debug)]
struct Turn {
    centre: Vec3,
    dir: Vec3,
    /// Signed angles at `s = 0` and `s = 1`, radians (joint sign, `reverse` and table inversion
    /// applied).
    a0: f64,
    a1: f64,
}

/// A step of the kinematic chain from the head's zero pose to the workpiece frame.
#[derive(Clone, Copy, Debug)]
enum Step {
    Turn(Turn),
    /// The slides: translation by the joint X Y Z.
    Slides,
}

/// How a move's pose varies with `s`, reduced to what the error bound needs.
#[derive(Clone, Debug)]
enum Motion {
    /// CL data: the tip along `tip`, the axis slerped at the constant rate `rate` (radians).
    Program { tip: Path, rate: f64 },
    /// Joints linear in `s` through the machine.
    Machine {
        steps: Vec<Step>,
        /// The slides' path (joint X Y Z).
        slides: Path,
        /// Slides at parameter `s` (exactly as [`Program::pose_at`] interpolates them).
        slides_at: Box<SlidesAt>,
        tcp: bool,
    },
}

/// The joint X Y Z of a move at `s`.
#[derive(Clone, Copy, Debug)]
enum SlidesAt {
    Line(Vec3, Vec3),
    /// The arc, given in the workpiece frame at the start's rotary position, carried into joint
    /// space by `x = R·(p − t)` (R, t: the start's joint-space-to-workpiece map, R transposed).
    Arc {
        g: swarf_path::ArcGeom,
        start: Vec3,
        r: Mat3,
        t: Vec3,
    },
}

impl SlidesAt {
    fn at(&self, s: f64) -> Vec3 {
        match *self {
            SlidesAt::Line(a, b) => a.lerp(b, s),
            SlidesAt::Arc { g, start, r, t } => r * (g.point_at(start, s) - t),
        }
    }
}

/// The error bound of a move: see the module documentation.
#[derive(Clone, Debug)]
pub struct MotionBound {
    motion: Motion,
}

impl MotionBound {
    /// The bound for move `m` of `program`.
    pub fn new(program: &Program, m: &Move) -> Self {
        let cl = m.axis_source == AxisSource::Program;
        let tip_path = |m: &Move| match m.kind {
            MoveKind::Arc(g) => Path::arc(&g),
            _ => Path::line(m.start.tip, m.end.tip),
        };
        if cl || !(program.machine.has_rotary() && m.start_joints.rotary_differs(&m.end_joints)) {
            let (a, b) = (m.start.axis.normalize(), m.end.axis.normalize());
            let rate = if cl {
                a.cross(b).length().atan2(a.dot(b))
            } else {
                0.0
            };
            return Self {
                motion: Motion::Program {
                    tip: tip_path(m),
                    rate,
                },
            };
        }
        let mach = &program.machine;
        let value = |w: swarf_path::kinematics::RotaryWord, j: &swarf_path::Axes| match w {
            swarf_path::kinematics::RotaryWord::A => j.a,
            swarf_path::kinematics::RotaryWord::B => j.b,
            swarf_path::kinematics::RotaryWord::C => j.c,
        };
        let turn = |j: &swarf_path::kinematics::RotaryJoint, inverse: bool| {
            let sign = if j.reverse != inverse { -1.0 } else { 1.0 };
            Step::Turn(Turn {
                centre: j.center,
                dir: j.direction,
                a0: sign * value(j.word, &m.start_joints).to_radians(),
                a1: sign * value(j.word, &m.end_joints).to_radians(),
            })
        };
        // Head joints are listed outermost first and act inner first; the inverse table
        // motion undoes the outermost table joint first.
        let mut steps: Vec<Step> = mach.head.iter().rev().map(|j| turn(j, false)).collect();
        steps.push(Step::Slides);
        steps.extend(mach.table.iter().map(|j| turn(j, true)));
        let (js, je) = (m.start_joints, m.end_joints);
        let (slides, slides_at) = match m.kind {
            MoveKind::Arc(g) => {
                let (r, t) = mach.joint_space_to_workpiece_with(&js, m.tcp);
                (
                    Path::arc(&g),
                    SlidesAt::Arc {
                        g,
                        start: m.start.tip,
                        r: r.transpose(),
                        t,
                    },
                )
            }
            _ => {
                let (a, b) = (Vec3::new(js.x, js.y, js.z), Vec3::new(je.x, je.y, je.z));
                (Path::line(a, b), SlidesAt::Line(a, b))
            }
        };
        Self {
            motion: Motion::Machine {
                steps,
                slides,
                slides_at: Box::new(slides_at),
                tcp: m.tcp,
            },
        }
    }

    /// Bound on the Hausdorff distance between the volume a shape of reach `reach` sweeps over
    /// `[s0, s1]` and the sweep of its sub-move (axis at the middle, pivot along the chord), mm.
    pub fn error_bound(&self, s0: f64, s1: f64, reach: Reach) -> f64 {
        let (_, m2, w, v2) = self.rates(s0, s1);
        let d = s1 - s0;
        (m2 + reach.pivot.abs() * v2) * d * d / 8.0 + reach.radius * w * d / 2.0
    }

    /// Bound on how deep material the union of the true instances at `s0` and `s1` can leave
    /// inside the true sweep of `[s0, s1]` of a tool region whose every point lies in a ball of
    /// radius `rho` inside the tool, the balls' centres within `centre_reach` of the tip, mm
    /// (module documentation, "Instances"); infinite when the instances are too far apart.
    pub fn instance_gap(&self, s0: f64, s1: f64, rho: f64, centre_reach: f64) -> f64 {
        gap_with(self.rates(s0, s1), s1 - s0, rho, centre_reach)
    }

    /// `(M₁, M₂, W, V₂)` on `[s0, s1]`: bounds on the tip's first and second derivatives, the
    /// axis' speed and the axis' second derivative.
    fn rates(&self, s0: f64, s1: f64) -> (f64, f64, f64, f64) {
        match &self.motion {
            Motion::Program { tip, rate } => (tip.d1, tip.d2, *rate, rate * rate),
            Motion::Machine {
                steps,
                slides,
                slides_at,
                tcp,
            } => {
                let (sm, half) = (0.5 * (s0 + s1), 0.5 * (s1 - s0));
                // Point x (the tip, from the head's zero pose) and its derivative bounds; axis
                // v and its speed bound.
                let (mut x, mut b1, mut b2) = (Vec3::ZERO, 0.0f64, 0.0f64);
                let (mut v, mut w, mut v2) = (Vec3::Z, 0.0f64, 0.0f64);
                for step in steps {
                    match *step {
                        Step::Slides => {
                            x += slides_at.at(sm);
                            b1 += slides.d1;
                            b2 += slides.d2;
                        }
                        Step::Turn(t) => {
                            let rate = (t.a1 - t.a0).abs();
                            let rot = Mat3::from_axis_angle(t.dir, t.a0 + sm * (t.a1 - t.a0));
                            let rel = x - t.centre;
                            let rho = t.dir.cross(rel).length() + b1 * half;
                            b2 += rate * rate * rho + 2.0 * rate * b1;
                            b1 += rate * rho;
                            x = t.centre + rot * rel;
                            let sine = (t.dir.cross(v).length() + w * half).min(1.0);
                            v2 += rate * rate * sine + 2.0 * rate * w;
                            w += rate * sine;
                            v = rot * v;
                        }
                    }
                }
                if *tcp {
                    (slides.d1, slides.d2, w, v2)
                } else {
                    (b1, b2, w, v2)
                }
            }
        }
    }

    /// The pose the bound's own chain gives at `s` (tip, axis): equal to
    /// [`Program::pose_at`] up to rounding; exposed so tests can check the chain.
    pub fn chain_pose(&self, s: f64) -> Option<(Vec3, Vec3)> {
        let Motion::Machine {
            steps,
            slides_at,
            tcp,
            ..
        } = &self.motion
        else {
            return None;
        };
        let (mut x, mut v) = (Vec3::ZERO, Vec3::Z);
        for step in steps {
            match *step {
                Step::Slides => x += slides_at.at(s),
                Step::Turn(t) => {
                    let rot = Mat3::from_axis_angle(t.dir, t.a0 + s * (t.a1 - t.a0));
                    x = t.centre + rot * (x - t.centre);
                    v = rot * v;
                }
            }
        }
        Some((if *tcp { slides_at.at(s) } else { x }, v))
    }
}

/// Splits move `index` of `program` into constant-axis straight sub-moves, each within `tol`
/// (mm) of the true sweep of a shape with reach `reach`, by bisecting `[0, 1]` until
/// [`MotionBound::error_bound`] `≤ tol`. In order of `s`.
///
/// # Errors
/// [`SweepError::Unsupported`] (naming the move) when `tol` is not a positive finite number or
/// more than [`MAX_SUB_MOVES`] would be needed.
pub fn subdivide(
    program: &Program,
    index: usize,
    reach: Reach,
    tol: f64,
) -> Result<Vec<SubMove>, SweepError> {
    let mut out = Vec::new();
    subdivide_range(program, index, reach, tol, (0.0, 1.0), &mut out)?;
    Ok(out)
}

/// [`subdivide`] on the parameter range `range` only, appending to `out`.
///
/// # Errors
/// As [`subdivide`].
pub fn subdivide_range(
    program: &Program,
    index: usize,
    reach: Reach,
    tol: f64,
    range: (f64, f64),
    out: &mut Vec<SubMove>,
) -> Result<(), SweepError> {
    check_tolerance(program, index, tol)?;
    let m = &program.moves[index];
    let bound = MotionBound::new(program, m);
    // Depth-first, right half pushed first, so the pieces come out in order of s.
    let mut stack = vec![range];
    while let Some((s0, s1)) = stack.pop() {
        let e = bound.error_bound(s0, s1, reach);
        if e <= tol {
            let pose = |s: f64| stated_pose(program, m, s);
            let pivot = |s: f64| {
                let p = pose(s);
                p.tip + p.axis.normalize() * reach.pivot
            };
            let axis = pose(0.5 * (s0 + s1)).axis.normalize();
            out.push(SubMove {
                s0,
                s1,
                tip0: pivot(s0) - axis * reach.pivot,
                tip1: pivot(s1) - axis * reach.pivot,
                axis,
                error_bound: e,
            });
        } else if !e.is_finite() || out.len() + stack.len() >= MAX_SUB_MOVES {
            return Err(SweepError::Unsupported {
                index,
                line: m.line,
                why: format!(
                    "the 5-axis move needs more than {MAX_SUB_MOVES} constant-axis sub-moves to stay within {tol} mm (error bound {e:.3e} mm on [{s0}, {s1}])"
                ),
            });
        } else {
            let sm = 0.5 * (s0 + s1);
            stack.push((sm, s1));
            stack.push((s0, sm));
        }
    }
    Ok(())
}

/// The pose of move `m` at parameter `s`: its end poses as the program states them
/// ([`Program::pose_at`] reproduces them only to rounding), else interpolated.
pub fn stated_pose(program: &Program, m: &Move, s: f64) -> swarf_path::Pose {
    if s == 0.0 {
        m.start
    } else if s == 1.0 {
        m.end
    } else {
        program.pose_at(m, s)
    }
}

/// [`MotionBound::instance_gap`] for the rates `(M₁, M₂, W, V₂)` and a part of length `d`.
fn gap_with((m1, m2, w, v2): (f64, f64, f64, f64), d: f64, rho: f64, centre_reach: f64) -> f64 {
    let travel = (m1 + w * centre_reach) * d;
    let chord = (m2 + (v2 + w * w) * centre_reach) * d * d / 8.0;
    let half = 0.5 * travel;
    // (NaN rates fail too.)
    if half.partial_cmp(&rho) != Some(std::cmp::Ordering::Less) {
        return f64::INFINITY;
    }
    // ρ − √(ρ² − (d/2)²), written without cancellation.
    chord + half * half / (rho + (rho * rho - half * half).sqrt())
}

/// The parameters in `range` of move `index` of `program` at which exact instances of a tool
/// region of rolling radius `rho` (balls' centres within `centre_reach` of the tip) leave no
/// material deeper than `tol` (mm) inside the region's true sweep, by bisecting `range` until
/// [`MotionBound::instance_gap`] `≤ tol` on every part; appended to `times` in increasing order,
/// both ends of `range` included. Returns the largest gap of any part.
///
/// # Errors
/// As [`subdivide`].
pub fn instance_times(
    program: &Program,
    index: usize,
    (rho, centre_reach): (f64, f64),
    tol: f64,
    range: (f64, f64),
    times: &mut Vec<f64>,
) -> Result<f64, SweepError> {
    check_tolerance(program, index, tol)?;
    let m = &program.moves[index];
    let bound = MotionBound::new(program, m);
    let mut worst = 0.0f64;
    let first = times.len();
    times.push(range.0);
    // Equal parts, as many as the whole range's rates ask for (fewer than bisection's powers
    // of two); each is then checked on its own rates, and bisected if need be.
    let (len, rates) = (range.1 - range.0, bound.rates(range.0, range.1));
    let fits = |n: f64| gap_with(rates, len / n, rho, centre_reach) <= tol;
    let too_many = |g: f64, (s0, s1): (f64, f64)| {
        SweepError::Unsupported {
        index,
        line: m.line,
        why: format!(
            "the 5-axis move needs more than {MAX_SUB_MOVES} tool instances to stay within {tol} mm (gap bound {g:.3e} mm on [{s0}, {s1}])"
        ),
    }
    };
    let mut n = 1.0f64;
    while !fits(n) {
        if n >= MAX_SUB_MOVES as f64 {
            // Refused before any part is made.
            let g = gap_with(rates, len / n, rho, centre_reach);
            return Err(too_many(g, (range.0, range.0 + len / n)));
        }
        n *= 2.0;
    }
    let (mut lo, mut hi) = (0.5 * n, n);
    while hi - lo > 1.0 {
        let mid = (0.5 * (lo + hi)).floor();
        if fits(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let n = hi.max(1.0) as usize;
    let at = |i: usize| {
        if i == n {
            range.1
        } else {
            range.0 + len * i as f64 / n as f64
        }
    };
    let mut stack: Vec<(f64, f64)> = (0..n).rev().map(|i| (at(i), at(i + 1))).collect();
    while let Some((s0, s1)) = stack.pop() {
        let g = bound.instance_gap(s0, s1, rho, centre_reach);
        if g <= tol {
            worst = worst.max(g);
            times.push(s1);
        } else if times.len() - first + stack.len() >= MAX_SUB_MOVES || s1 - s0 < 1e-12 {
            return Err(too_many(g, (s0, s1)));
        } else {
            let sm = 0.5 * (s0 + s1);
            stack.push((sm, s1));
            stack.push((s0, sm));
        }
    }
    Ok(worst)
}

/// `Ok` when `tol` is a positive finite chordal tolerance for move `index`.
///
/// # Errors
/// [`SweepError::Unsupported`] naming the move otherwise.
pub fn check_tolerance(program: &Program, index: usize, tol: f64) -> Result<(), SweepError> {
    if tol.is_finite() && tol > 0.0 {
        return Ok(());
    }
    Err(SweepError::Unsupported {
        index,
        line: program.moves[index].line,
        why: format!("a 5-axis move needs a positive chordal tolerance, got {tol} mm"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use swarf_path::{Axes, FeedMode, Machine, Pose};

    fn machine_move(machine: &str, j0: Axes, j1: Axes) -> Program {
        let mach = Machine::from_name(machine).unwrap();
        let mv = Move {
            kind: MoveKind::Linear,
            start: mach.pose(&j0),
            end: mach.pose(&j1),
            start_joints: j0,
            end_joints: j1,
            feed: 100.0,
            feed_mode: FeedMode::PerMinute,
            spindle_rpm: 1000.0,
            spindle_dir: swarf_path::SpindleDir::Clockwise,
            tool: 1,
            file: 0,
            line: 1,
            axis_source: AxisSource::Machine,
            tcp: mach.tcp,
            rotary_feed_combined: None,
        };
        Program {
            moves: vec![mv],
            machine: mach,
            ..Program::default()
        }
    }

    #[test]
    fn chain_reproduces_custom_machines() {
        use swarf_path::kinematics::{RotaryJoint, RotaryWord};
        let joint = |word, direction: Vec3, center: Vec3, reverse| RotaryJoint {
            word,
            direction: direction.normalize(),
            center,
            reverse,
        };
        let machines = [
            Machine::new(
                "trunnion",
                false,
                vec![
                    joint(RotaryWord::B, Vec3::Y, Vec3::new(10.0, 0.0, -50.0), true),
                    joint(RotaryWord::C, Vec3::Z, Vec3::new(3.0, -2.0, 0.0), false),
                ],
                vec![],
            )
            .unwrap(),
            Machine::new(
                "nutating",
                false,
                vec![joint(
                    RotaryWord::C,
                    Vec3::Z,
                    Vec3::new(-4.0, 1.0, 0.0),
                    true,
                )],
                vec![joint(
                    RotaryWord::B,
                    Vec3::new(0.0, 1.0, 1.0),
                    Vec3::new(0.0, 5.0, 120.0),
                    true,
                )],
            )
            .unwrap(),
        ];
        for mach in machines {
            let (j0, j1) = (
                joints(3.0, -7.0, 12.0, 0.0, -25.0, 40.0),
                joints(-5.0, 4.0, 2.0, 0.0, 30.0, -110.0),
            );
            let mut p = machine_move("3axis", j0, j1);
            p.moves[0].start = mach.pose(&j0);
            p.moves[0].end = mach.pose(&j1);
            p.moves[0].tcp = mach.tcp;
            p.machine = mach;
            let m = &p.moves[0];
            let b = MotionBound::new(&p, m);
            for i in 0..=10 {
                let s = i as f64 / 10.0;
                let want = p.pose_at(m, s);
                let (tip, axis) = b.chain_pose(s).unwrap();
                assert!((tip - want.tip).length() < 1e-9, "{} s={s}", p.machine.name);
                assert!(
                    (axis - want.axis).length() < 1e-12,
                    "{} s={s}",
                    p.machine.name
                );
            }
            assert_bound_holds(&p, 0.02);
        }
    }

    fn joints(x: f64, y: f64, z: f64, a: f64, b: f64, c: f64) -> Axes {
        Axes { x, y, z, a, b, c }
    }

    #[test]
    fn chain_reproduces_the_machine() {
        for name in swarf_path::kinematics::BUILTIN_NAMES {
            for tcp in ["", "-tcp"] {
                let p = machine_move(
                    &format!("{name}{tcp}"),
                    joints(3.0, -7.0, 12.0, 10.0, -25.0, 40.0),
                    joints(-5.0, 4.0, 2.0, -35.0, 20.0, -110.0),
                );
                let m = &p.moves[0];
                let b = MotionBound::new(&p, m);
                for i in 0..=10 {
                    let s = i as f64 / 10.0;
                    let want = p.pose_at(m, s);
                    let Some((tip, axis)) = b.chain_pose(s) else {
                        assert!(!p.is_five_axis(m), "{name}{tcp}");
                        continue;
                    };
                    assert!((tip - want.tip).length() < 1e-9, "{name}{tcp} s={s}");
                    assert!((axis - want.axis).length() < 1e-12, "{name}{tcp} s={s}");
                }
            }
        }
    }

    /// The bound must hold: the largest displacement of a tool point under the sub-move's
    /// pairing (pivot deviation from the chord + 2·sin(θ/2)·radius), measured on a fine grid of
    /// `s`, stays within each piece's bound, and the bounds within the tolerance. For the pivot
    /// at the tip and half-way up a 30 mm tool.
    fn assert_bound_holds(p: &Program, tol: f64) {
        let m = &p.moves[0];
        let name = &p.machine.name;
        for reach in [
            Reach {
                pivot: 0.0,
                radius: 30.0,
            },
            Reach {
                pivot: 15.0,
                radius: 16.0,
            },
        ] {
            let pieces = subdivide(p, 0, reach, tol).unwrap();
            assert!(pieces.len() > 4, "{name}: {}", pieces.len());
            for sm in &pieces {
                let mut worst: f64 = 0.0;
                for i in 0..=64 {
                    let s = sm.s0 + (sm.s1 - sm.s0) * i as f64 / 64.0;
                    let t = (s - sm.s0) / (sm.s1 - sm.s0);
                    let Pose { tip, axis } = p.pose_at(m, s);
                    let theta = axis.angle_between(sm.axis);
                    let chord = sm.tip0.lerp(sm.tip1, t) + sm.axis * reach.pivot;
                    let dev = (chord - (tip + axis * reach.pivot)).length()
                        + 2.0 * (theta / 2.0).sin() * reach.radius;
                    worst = worst.max(dev);
                }
                assert!(
                    worst <= sm.error_bound * (1.0 + 1e-9) + 1e-12,
                    "{name}: measured {worst} > bound {} on [{}, {}]",
                    sm.error_bound,
                    sm.s0,
                    sm.s1
                );
                assert!(sm.error_bound <= tol);
            }
            for w in pieces.windows(2) {
                assert_eq!(w[0].s1, w[1].s0);
            }
            assert_eq!((pieces[0].s0, pieces[pieces.len() - 1].s1), (0.0, 1.0));
        }
    }

    #[test]
    fn bound_holds_on_sampled_motion() {
        let cases = [
            (
                "table-ac",
                joints(40.0, -20.0, 10.0, 5.0, 0.0, 0.0),
                joints(-30.0, 25.0, 0.0, 40.0, 0.0, 170.0),
            ),
            (
                "head-bc",
                joints(0.0, 0.0, 0.0, 0.0, -30.0, 10.0),
                joints(10.0, 5.0, -5.0, 0.0, 45.0, 95.0),
            ),
            (
                "head-table-ac",
                joints(20.0, 0.0, 5.0, 30.0, 0.0, 0.0),
                joints(-20.0, 10.0, 0.0, -10.0, 0.0, 90.0),
            ),
            (
                "table-bc-tcp",
                joints(5.0, 5.0, 5.0, 0.0, 10.0, 0.0),
                joints(-5.0, 0.0, 0.0, 0.0, 60.0, -200.0),
            ),
        ];
        for (name, j0, j1) in cases {
            assert_bound_holds(&machine_move(name, j0, j1), 0.05);
        }
    }

    #[test]
    fn turning_about_the_tool_axis_costs_no_subdivision() {
        // C turns a table whose A is 0: the axis stays +Z and, with TCP, the tip stays straight.
        let p = machine_move(
            "table-ac-tcp",
            joints(0.0, 0.0, 5.0, 0.0, 0.0, 0.0),
            joints(10.0, 0.0, 5.0, 0.0, 0.0, 270.0),
        );
        assert!(p.is_five_axis(&p.moves[0]));
        let reach = Reach {
            pivot: 20.0,
            radius: 25.0,
        };
        assert_eq!(subdivide(&p, 0, reach, 1e-6).unwrap().len(), 1);
        // Without TCP the tip follows a spiral about the table centre: subdivided.
        let p = machine_move(
            "table-ac",
            joints(0.0, 0.0, 5.0, 0.0, 0.0, 0.0),
            joints(10.0, 0.0, 5.0, 0.0, 0.0, 270.0),
        );
        assert!(subdivide(&p, 0, reach, 1e-3).unwrap().len() > 10);
        assert!(subdivide(&p, 0, reach, 0.0).is_err());
    }
}
