//! The allowable size for a **general tool axis**, and the 4-axis rotary angle that maximises it
//! (Liu 2007, §2.4.2 eq. 2.2 and ch. 5).
//!
//! # One mechanism: solve in the tool frame
//! The 3-axis solver ([`allowable_certified`]) assumes the tool axis is `+Z`. For a tool axis `a`
//! (unit, in the part frame) the part is moved by a rotation `Q` with `Q·a = +Z`, and the same
//! solver answers unchanged. A rotation is linear, so the homogeneous control points
//! `(w·x, w·y, w·z, w)` of every rational Bézier piece are rotated as `(Q·(w·p), w)`: weights,
//! the convex-hull property and therefore the certificate survive exactly. The contact point and
//! normal are rotated with the part; principal curvatures are invariant under rigid motions. The
//! limiting point is rotated back. The cutter is a solid of revolution about its axis, so the
//! result does not depend on which rotation with `Q·a = +Z` is used. Cost: one pass over the
//! control points per axis (negligible beside the branch-and-bound).
//!
//! # 4-axis convention
//! The rotary axis `e` is `Y` (the thesis's horizontal machine, §1.2.3) or `X`. At table angle
//! `B` the tool axis, seen in the part frame, is `+Z` turned by `B` about `e` (right-hand rule):
//!
//! * `e = Y`: `a(B) = (sin B, 0, cos B)`;
//! * `e = X`: `a(B) = (0, −sin B, cos B)`.
//!
//! (The table turns the part by `−B`.) `B = 0` is the 3-axis set-up. For each CC point the
//! search maximises `L(B) = allowable size with axis a(B)` (eq. 2.2) over `B ∈ [0°, 360°)`.
//!
//! # The search and its tolerance
//! `L(B)` is not continuous: it drops to `0` where the cutter cannot be tangent (`n·a(B)` below
//! `sin θ` for a side taper `θ`, an undercut), and it jumps where the placement switches (a flat
//! bottom standing on a point whose normal is `a`). No Lipschitz bound holds in general, so the
//! search is (documented, not certified in `B`):
//!
//! 1. *Coarse sampling*: `B = k·step` for `k = 0 … ⌈360°/step⌉ − 1` ([`Axis4Options::step_deg`]),
//!    which includes the 3-axis seed `B = 0`, plus the angle `B_n` at which `a(B)` is the
//!    projection of the normal onto the plane of the tool axes (the most reachable axis);
//! 2. *Refinement*: a golden-section search for the maximum on `[B_k − step, B_k + step]`
//!    around each of the [`Axis4Options::refine`] best distinct samples, down to a bracket of
//!    [`Axis4Options::tol_deg`].
//!
//! The result is the best size met, with its angle: it is an exact (certified) allowable size at
//! that angle, and never below the 3-axis size (`B = 0` is always evaluated first, and a later
//! angle replaces the best only when it gains more than the certificate's tolerance, so ties
//! keep the 3-axis angle). It is the global
//! maximum whenever `L` is unimodal on the `2·step` bracket around the best sample.
//!
//! *Pruning.* Before solving at an angle, a cheap upper bound of `L` is taken (the curvature
//! bound and the imaginary sizes of the corners of every Bézier piece: surface points, so each
//! is ≥ the minimum); when it cannot beat the best size so far the solve is skipped and the
//! bound stands for the value (it only steers the refinement, never the result). Solves and
//! skipped angles are counted ([`Orientation4::solves`], [`Orientation4::pruned`]) and the
//! evaluations and nodes of all of it are summed in the returned [`AllowableSize`].

use swarf_geom::math::{Quat, Vec3};
use swarf_geom::search::golden_max;

use super::{allowable_certified, AllowableSize, CertifiedOptions, Contact, CutterFamily, Regime};
use super::{PreparedSurface, SizeError};
use swarf_surface::Curvature;

/// The allowable size with tool axis `axis` (part frame; normalised here) by the certified
/// solver in the tool frame (see the module docs). `axis = +Z` is exactly
/// [`allowable_certified`].
///
/// # Panics
/// When `axis` is zero or not finite.
pub fn allowable_along(
    prep: &PreparedSurface,
    family: &CutterFamily,
    c: &Contact,
    axis: Vec3,
    opts: &CertifiedOptions,
) -> AllowableSize {
    let a = axis.normalize();
    assert!(a.is_finite(), "tool axis {axis} is not a direction");
    allowable_in_frame(prep, family, c, axis_rotation(a), opts)
}

/// A rotation taking the unit axis `a` to `+Z` (the identity when `a` is `+Z` exactly).
pub(crate) fn axis_rotation(a: Vec3) -> Quat {
    if a == Vec3::Z {
        Quat::IDENTITY
    } else {
        Quat::from_rotation_arc(a, Vec3::Z)
    }
}

/// The allowable size after moving the part by `q` (which must take the tool axis to `+Z`).
pub(crate) fn allowable_in_frame(
    prep: &PreparedSurface,
    family: &CutterFamily,
    c: &Contact,
    q: Quat,
    opts: &CertifiedOptions,
) -> AllowableSize {
    if q == Quat::IDENTITY {
        return allowable_certified(prep, family, c, opts);
    }
    let rotated = prep.rotated(q);
    let rc = rotate_contact(c, q);
    let mut a = allowable_certified(&rotated, family, &rc, opts);
    let back = q.inverse();
    a.limit_point = a
        .limit_point
        .map(|p| if p == rc.point { c.point } else { back * p });
    a
}

/// The contact moved by the rotation `q`: point, normal and principal directions rotated
/// (curvatures are invariant under a rigid motion).
pub(crate) fn rotate_contact(c: &Contact, q: Quat) -> Contact {
    Contact {
        point: q * c.point,
        normal: (q * c.normal).normalize(),
        curvature: c.curvature.map(|k| Curvature {
            dir1: q * k.dir1,
            dir2: q * k.dir2,
            ..k
        }),
    }
}

/// The part moved by `q`: the prepared surface and the contact (for checks in the tool frame).
pub(crate) fn in_tool_frame(
    prep: &PreparedSurface,
    c: &Contact,
    q: Quat,
) -> (PreparedSurface, Contact) {
    let rc = rotate_contact(c, q);
    (prep.rotated(q), rc)
}

/// A cheap upper bound of the allowable size after moving the part by `q`, and the imaginary
/// sizes evaluated: the curvature bound and the imaginary sizes of the corners of every Bézier
/// piece (surface points) outside the solver's excluded neighbourhood, raised by the
/// certificate's tolerance (the solver may report the curvature bound when a test point ties
/// with it within that tolerance). `0` when the contact is unreachable.
pub(crate) fn quick_upper_bound(
    prep: &PreparedSurface,
    family: &CutterFamily,
    c: &Contact,
    q: Quat,
    opts: &CertifiedOptions,
) -> (f64, u64) {
    let rc = rotate_contact(c, q);
    let regime = family.regime(&rc, &opts.model);
    if regime == Regime::Unreachable {
        return (0.0, 0);
    }
    let mut ub = family.local_bound(&rc, &regime);
    let mut n = 0;
    for pc in &prep.pieces {
        let (p, qd) = (pc.p, pc.q);
        for (i, j) in [(0, 0), (p, 0), (0, qd), (p, qd)] {
            if !pc.corner_on_part(i, j) {
                continue;
            }
            let x = q * pc.point(i, j);
            if (x - rc.point).length() >= opts.neighbourhood {
                n += 1;
                ub = ub.min(family.imaginary(&rc, &regime, x, &opts.model));
            }
        }
    }
    (ub + opts.tol_abs.max(opts.tol_rel * ub), n)
}

/// The rotary axis of a 4-axis machine.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RotaryAxis {
    /// Rotation about `X` (an A axis).
    X,
    /// Rotation about `Y` (a B axis; the thesis's set-up, the default).
    #[default]
    Y,
}

impl RotaryAxis {
    /// The unit vector of the axis.
    pub fn direction(self) -> Vec3 {
        match self {
            RotaryAxis::X => Vec3::X,
            RotaryAxis::Y => Vec3::Y,
        }
    }

    /// The tool axis in the part frame at table angle `b_deg` (module docs).
    pub fn tool_axis(self, b_deg: f64) -> Vec3 {
        let (s, c) = b_deg.to_radians().sin_cos();
        match self {
            RotaryAxis::X => Vec3::new(0.0, -s, c),
            RotaryAxis::Y => Vec3::new(s, 0.0, c),
        }
    }

    /// The rotation of the part that takes `tool_axis(b_deg)` to `+Z` (the identity at 0).
    pub fn part_rotation(self, b_deg: f64) -> Quat {
        if b_deg == 0.0 {
            Quat::IDENTITY
        } else {
            Quat::from_axis_angle(self.direction(), -b_deg.to_radians())
        }
    }

    /// The angle in `[0°, 360°)` whose tool axis is closest to `n` (the projection of `n` onto
    /// the plane of the tool axes); `None` when `n` is along the rotary axis.
    pub fn angle_towards(self, n: Vec3) -> Option<f64> {
        let (s, c) = match self {
            RotaryAxis::X => (-n.y, n.z),
            RotaryAxis::Y => (n.x, n.z),
        };
        (s.hypot(c) > 1e-12).then(|| wrap_deg(s.atan2(c).to_degrees()))
    }
}

/// `x` wrapped into `[0, 360)`.
pub(crate) fn wrap_deg(x: f64) -> f64 {
    let w = x.rem_euclid(360.0);
    if w >= 360.0 {
        0.0
    } else {
        w
    }
}

/// Options of the 4-axis search (builder style, documented defaults).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axis4Options {
    /// The rotary axis. Default [`RotaryAxis::Y`].
    pub rotary: RotaryAxis,
    /// Coarse sampling step, degrees. Default `10°` (36 samples).
    pub step_deg: f64,
    /// Width (degrees) of the final golden-section bracket. Default `1e-3°`.
    pub tol_deg: f64,
    /// How many of the best distinct samples are refined. Default `2`.
    pub refine: usize,
    /// Options of the certified solver run at each angle.
    pub certified: CertifiedOptions,
}

impl Axis4Options {
    /// The documented defaults.
    pub const DEFAULT: Axis4Options = Axis4Options {
        rotary: RotaryAxis::Y,
        step_deg: 10.0,
        tol_deg: 1e-3,
        refine: 2,
        certified: CertifiedOptions::DEFAULT,
    };

    /// With another rotary axis.
    pub fn with_rotary(mut self, rotary: RotaryAxis) -> Self {
        self.rotary = rotary;
        self
    }

    /// With another coarse step and final bracket, degrees.
    pub fn with_resolution(mut self, step_deg: f64, tol_deg: f64) -> Self {
        self.step_deg = step_deg;
        self.tol_deg = tol_deg;
        self
    }

    /// Checks the ranges.
    ///
    /// # Errors
    /// When the step is not in `(0°, 180°]`, the tolerance not positive, or the solver options
    /// are invalid.
    pub fn validate(&self) -> Result<(), SizeError> {
        if !(self.step_deg > 0.0 && self.step_deg <= 180.0) {
            return Err(SizeError::Option {
                what: "step_deg",
                value: self.step_deg,
                range: "(0, 180]",
            });
        }
        if !(self.tol_deg > 0.0 && self.tol_deg.is_finite()) {
            return Err(SizeError::Option {
                what: "tol_deg",
                value: self.tol_deg,
                range: "> 0",
            });
        }
        self.certified.validate()
    }
}

impl Default for Axis4Options {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// The best 4-axis orientation at a CC point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orientation4 {
    /// The table angle, degrees in `[0, 360)`.
    pub b_deg: f64,
    /// The tool axis at that angle, part frame.
    pub axis: Vec3,
    /// The allowable size at that angle (limit point in the part frame); `evaluations` and
    /// `nodes` are the totals over all solves.
    pub size: AllowableSize,
    /// Certified solves spent.
    pub solves: u32,
    /// Angles skipped without a solve: their cheap upper bound (curvature bound and the
    /// imaginary sizes of the Bézier pieces' corners) could not beat the best size.
    pub pruned: u32,
}

/// Keeps the best (angle, size) over a 1-D or 2-D search and the totals.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Best<T: Copy> {
    pub at: T,
    /// The certificate's tolerances: a size must beat the best by more than
    /// `max(abs, rel·best)` to replace it (ties keep the earlier, e.g. the 3-axis, angle).
    pub margin: (f64, f64),
    pub size: AllowableSize,
    pub evaluations: u64,
    pub nodes: u64,
    pub solves: u32,
    pub pruned: u32,
}

impl<T: Copy> Best<T> {
    pub(crate) fn new(at: T, size: AllowableSize, opts: &CertifiedOptions) -> Self {
        Self {
            at,
            margin: (opts.tol_abs, opts.tol_rel),
            size,
            evaluations: size.evaluations,
            nodes: size.nodes,
            solves: 1,
            pruned: 0,
        }
    }

    /// Solves at `at` only when the cheap upper bound `ub` (with its evaluation count) could
    /// beat the best; returns the size, or `ub` when pruned (then no larger than the best).
    pub(crate) fn offer_bounded(
        &mut self,
        at: T,
        (ub, n): (f64, u64),
        solve: impl FnOnce() -> AllowableSize,
    ) -> f64 {
        self.evaluations += n;
        if ub <= self.size.size + self.gain(self.size.size) && !(self.size.size == 0.0 && ub > 0.0)
        {
            self.pruned += 1;
            return ub;
        }
        self.offer(at, solve())
    }

    /// The least gain over `size` that counts as an improvement (the certificate's tolerance).
    pub(crate) fn gain(&self, size: f64) -> f64 {
        self.margin.0.max(self.margin.1 * size)
    }

    /// Records a solve; returns its size.
    pub(crate) fn offer(&mut self, at: T, size: AllowableSize) -> f64 {
        self.evaluations += size.evaluations;
        self.nodes += size.nodes;
        self.solves += 1;
        if size.size > self.size.size + self.gain(self.size.size)
            || (self.size.size == 0.0 && size.size > 0.0)
        {
            self.at = at;
            self.size = size;
        }
        size.size
    }

    pub(crate) fn totals(&self) -> AllowableSize {
        AllowableSize {
            evaluations: self.evaluations,
            nodes: self.nodes,
            ..self.size
        }
    }
}

/// The 4-axis table angle that maximises the allowable size at `c`, and that size (module
/// docs: coarse sampling, then golden-section refinement).
///
/// # Panics
/// When the options are invalid ([`Axis4Options::validate`]).
pub fn best_rotary_angle(
    prep: &PreparedSurface,
    family: &CutterFamily,
    c: &Contact,
    opts: &Axis4Options,
) -> Orientation4 {
    opts.validate().expect("valid 4-axis options");
    let rot = opts.rotary;
    let solve = |b: f64| allowable_in_frame(prep, family, c, rot.part_rotation(b), &opts.certified);
    let bound = |b: f64| quick_upper_bound(prep, family, c, rot.part_rotation(b), &opts.certified);
    let mut best = Best::new(0.0, solve(0.0), &opts.certified);
    let count = (360.0 / opts.step_deg).ceil() as usize;
    let mut samples: Vec<(f64, f64)> = vec![(0.0, best.size.size)];
    let mut angles: Vec<f64> = (1..count).map(|k| k as f64 * opts.step_deg).collect();
    if let Some(bn) = rot.angle_towards(c.normal) {
        if bn != 0.0 {
            angles.push(bn);
        }
    }
    for b in angles {
        if best.size.size.is_infinite() {
            break;
        }
        let s = best.offer_bounded(b, bound(b), || solve(b));
        samples.push((b, s));
    }
    if best.size.size.is_finite() {
        // The best distinct samples (farther apart than one step), best first.
        samples.sort_by(|x, y| y.1.total_cmp(&x.1).then(x.0.total_cmp(&y.0)));
        let mut seeds: Vec<f64> = Vec::new();
        for (b, s) in samples {
            if seeds.len() >= opts.refine || s <= 0.0 {
                break;
            }
            if seeds
                .iter()
                .all(|&t| angle_gap(t, b) > opts.step_deg * (1.0 - 1e-9))
            {
                seeds.push(b);
            }
        }
        for b0 in seeds {
            golden_max(
                &mut |b| {
                    let b = wrap_deg(b);
                    best.offer_bounded(b, bound(b), || solve(b))
                },
                b0 - opts.step_deg,
                b0 + opts.step_deg,
                opts.tol_deg,
            );
            if best.size.size.is_infinite() {
                break;
            }
        }
    }
    Orientation4 {
        b_deg: best.at,
        axis: rot.tool_axis(best.at),
        size: best.totals(),
        solves: best.solves,
        pruned: best.pruned,
    }
}

/// Angular distance in degrees, in `[0, 180]`.
fn angle_gap(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    d.min(360.0 - d)
}
