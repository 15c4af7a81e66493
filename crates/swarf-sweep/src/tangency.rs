//! The tangency function `f = N·V` (Aras eq. 5.18) and the kinematically feasible engagement
//! set `CWE_K = {f ≥ 0}` of each cutter piece (Aras §5.3–5.4).
//!
//! At an instant every surface point is **forward** (`f > 0`, egress: it moves out of the
//! tool's current volume into material ahead), on the **envelope** (`f = 0`, grazing) or
//! **backward** (`f < 0`, ingress). `CWE_K` — the points that can touch the workpiece — is the
//! forward set closed by the envelope. Per piece we report whether `CWE_K` has area
//! ([`Feasibility::Area`]), only touches the piece along a curve or a point
//! ([`Feasibility::Touch`], `{ }` in Table 5.2) or misses it ([`Feasibility::Empty`]), and
//! whether it reaches the **front** or the **back** face (the half-spaces `x > 0`, `x < 0` of
//! the feed frame, [`MotionState::feed_frame`]: `x` along the feed's component across the axis).
//!
//! On each parallel `f(θ) = A cos θ + B sin θ − C` ([`Harmonic`]), so the largest `f` over a
//! piece is `max_s (√(A² + B²) − C)` in closed form per parallel. A piece whose `f` vanishes on
//! a whole band (a cylinder under a plunge along the axis) is all envelope ([`Feasibility::Sliding`]).
//!
//! # Motion classes (Aras Table 5.1)
//! In 3-axis motion (`ω = 0`) the feed angle `ψ = ∠(V_F, n)` classifies the motion:
//! ascending `ψ < 90°` (F1 `ψ = β`, F2 `(β, α)`, F3 `α`, F4 `(α, 90°)`), horizontal (F5, 90°)
//! and descending (B1 `(90°, 180° − α)`, B2 `180° − α`, B3 `(180° − α, 180° − β)`, B4
//! `180° − β`), with Aras's angles: `α` between the axis and the bottom surface (90° for a flat
//! bottom; `90° −` the APT bottom angle) and `β` between the axis and the side.

use std::f64::consts::FRAC_PI_2;

use serde::Serialize;
use swarf_geom::math::{Vec2, Vec3};
use swarf_tool::{AnyPiece, Piece};

use crate::grazing::{parameters, Harmonic};
use crate::kinematics::MotionState;
use crate::tolerance::TANGENCY_REL_EPS;

/// `f = N·V(P)` for the tool point `p` with unit outward normal `n` (workpiece frame).
#[inline]
pub fn tangency(state: &MotionState, p: Vec3, n: Vec3) -> f64 {
    n.dot(state.velocity_at(p))
}

/// Where a surface point is with respect to the motion.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// `f > 0`: egress, moving into what lies ahead.
    Forward,
    /// `f = 0` (within the tolerance): grazing.
    Envelope,
    /// `f < 0`: ingress, leaving space behind.
    Backward,
}

impl Side {
    /// The side of a tangency value `f`, `|f| ≤ eps` being the envelope.
    pub fn of(f: f64, eps: f64) -> Self {
        if f > eps {
            Side::Forward
        } else if f < -eps {
            Side::Backward
        } else {
            Side::Envelope
        }
    }
}

/// The role of a piece in Aras's generic cutter (Fig. 5.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PieceRole {
    /// Flat bottom disc (Aras's lower cone with `α = 90°`).
    Bottom,
    /// Cone through the tip below the corner.
    LowerCone,
    /// Corner torus or sphere.
    Corner,
    /// Side above the corner (cylinder when `β = 0`).
    UpperCone,
    /// Top cap (not a cutting surface).
    Top,
}

/// The role of every piece of a cutting part, bottom to top.
pub fn roles(pieces: &[AnyPiece]) -> Vec<PieceRole> {
    let corner = pieces
        .iter()
        .position(|p| matches!(p, AnyPiece::Torus(_) | AnyPiece::Sphere(_)));
    pieces
        .iter()
        .enumerate()
        .map(|(i, p)| match p {
            AnyPiece::Torus(_) | AnyPiece::Sphere(_) => PieceRole::Corner,
            AnyPiece::Disc(d) if d.facing_up => PieceRole::Top,
            AnyPiece::Disc(_) => PieceRole::Bottom,
            AnyPiece::Cone(c) => {
                let below = corner.map_or(c.bottom.x == 0.0 && c.bottom.y == 0.0, |k| i < k);
                if below {
                    PieceRole::LowerCone
                } else {
                    PieceRole::UpperCone
                }
            }
            AnyPiece::Cylinder(_) => PieceRole::UpperCone,
        })
        .collect()
}

/// Aras's angles `(α, β)` in radians from the cutting part's pieces: `α` between the axis and
/// the bottom surface, `β` between the axis and the side (from their outward normals
/// `(cos α, −sin α)`, `(cos β, −sin β)`); `None` when a piece of either role is missing.
pub fn aras_angles(pieces: &[AnyPiece]) -> Option<(f64, f64)> {
    let rs = roles(pieces);
    let angle = |want: &[PieceRole], s: f64| {
        pieces.iter().zip(&rs).find_map(|(p, r)| {
            want.contains(r).then(|| {
                let n = piece_normal(p, s);
                (-n.y).atan2(n.x)
            })
        })
    };
    Some((
        angle(&[PieceRole::Bottom, PieceRole::LowerCone], 0.5)?,
        angle(&[PieceRole::UpperCone], 0.5)?,
    ))
}

/// How much of a piece `CWE_K` covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Feasibility {
    /// No point has `f ≥ 0`.
    Empty,
    /// `f ≥ 0` only on a curve or a point (`{ }` in Aras Table 5.2).
    Touch,
    /// `f ≡ 0` on a band and `f ≤ 0` elsewhere: the piece slides along the surface it leaves
    /// (the flat bottom in horizontal motion, a cylinder in a plunge) and removes nothing.
    /// Aras counts it as `{ }` for the bottom in 2½-axis motion but as `CWE_K` for a cylinder
    /// in B4 (`β = 0`); swarf names it apart.
    Sliding,
    /// `f ≥ 0` on a region of positive area.
    Area,
}

/// `CWE_K` on one piece.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PieceEngagement {
    /// Index of the piece.
    pub piece: usize,
    /// Its role in the generic cutter.
    pub role: PieceRole,
    /// How much of it can engage.
    pub feasibility: Feasibility,
    /// `CWE_K` has area on the front face (`x > 0` in the feed frame).
    pub front: bool,
    /// `CWE_K` has area on the back face (`x < 0`).
    pub back: bool,
    /// Largest `f` over the piece, relative to the motion's speed scale.
    pub max_tangency: f64,
}

/// The profile point of `p` at `s` (a disc by its radius from inner to outer).
fn piece_point(p: &AnyPiece, s: f64) -> Vec2 {
    match p {
        AnyPiece::Disc(d) => Vec2::new(d.inner + s * (d.outer - d.inner), d.z),
        _ => p.profile_point(s),
    }
}

fn piece_normal(p: &AnyPiece, s: f64) -> Vec2 {
    match p {
        AnyPiece::Disc(d) => crate::grazing::disc::normal(d),
        _ => p.profile_normal(s),
    }
}

/// Whether `{θ : f(θ) > eps}` on one parallel reaches the front (`cos θ > 0`) and the back
/// (`cos θ < 0`) face. The set is the arc `|θ − θ₀| < d`, `θ₀ = atan2(b, a)`,
/// `cos d = (c + eps)/√(a² + b²)`; the extremes of `cos θ` over it are at its ends unless it
/// holds 0 or π.
fn faces(h: &Harmonic, eps: f64) -> (bool, bool) {
    use std::f64::consts::PI;
    let amp = h.a.hypot(h.b);
    let q = (h.c + eps) / amp;
    if amp == 0.0 || q >= 1.0 {
        return (false, false);
    }
    if q < -1.0 {
        return (true, true);
    }
    let (t0, d) = (h.b.atan2(h.a), q.acos());
    // Angular distance from the arc's centre to 0 and to π.
    let dist = |x: f64| ((t0 - x + PI).rem_euclid(2.0 * PI) - PI).abs();
    let ends = [(t0 - d).cos(), (t0 + d).cos()];
    let max = if dist(0.0) < d {
        1.0
    } else {
        ends[0].max(ends[1])
    };
    let min = if dist(PI) < d {
        -1.0
    } else {
        ends[0].min(ends[1])
    };
    (max > 0.0, min < 0.0)
}

/// `CWE_K` of every piece of `pieces` under `state`, from `samples` parallels per piece.
pub fn feasible_contact(
    pieces: &[AnyPiece],
    state: &MotionState,
    samples: usize,
) -> Vec<PieceEngagement> {
    let frame = state.feed_frame();
    let v = frame.vector_to_local(state.v_tip);
    let w = frame.vector_to_local(state.omega);
    let rs = roles(pieces);
    pieces
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let reach = (0..=1)
                .map(|s| piece_point(p, s as f64).length())
                .fold(0.0, f64::max);
            let speed = v.length() + w.length() * reach;
            let eps = TANGENCY_REL_EPS * speed.max(f64::MIN_POSITIVE);
            let (mut max, mut run, mut whole_band) = (f64::NEG_INFINITY, 0usize, false);
            let (mut front, mut back) = (false, false);
            for s in parameters(samples) {
                let h = Harmonic::on_parallel(piece_point(p, s), piece_normal(p, s), v, w);
                max = max.max(h.max());
                if h.a.abs() <= eps && h.b.abs() <= eps && h.c.abs() <= eps {
                    run += 1;
                    whole_band |= run >= 2;
                } else {
                    run = 0;
                }
                let (f, b) = faces(&h, eps);
                front |= f;
                back |= b;
            }
            let feasibility = if max > eps {
                Feasibility::Area
            } else if whole_band {
                Feasibility::Sliding
            } else if max >= -eps {
                Feasibility::Touch
            } else {
                Feasibility::Empty
            };
            if whole_band {
                (front, back) = (true, true);
            }
            PieceEngagement {
                piece: i,
                role: rs[i],
                feasibility,
                front,
                back,
                max_tangency: max / speed.max(f64::MIN_POSITIVE),
            }
        })
        .collect()
}

/// The motion classes of Aras §5.4, and the general 5-axis instant.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MotionClass {
    /// `ψ < 90°`: the tip rises along the axis.
    Ascending,
    /// `ψ = 90°`.
    Horizontal,
    /// `ψ > 90°`: the tip descends along the axis.
    Descending,
    /// The axis turns (`ω ≠ 0`): the feed angle differs from point to point.
    FiveAxis,
    /// No motion.
    Rest,
}

/// The feed angle `ψ = ∠(V_F, n)`, radians (Aras eq. 5.42).
pub fn feed_angle(state: &MotionState) -> f64 {
    let v = state.v_tip;
    v.cross(state.axis).length().atan2(v.dot(state.axis))
}

/// The class of `state`; `angle_eps` (radians) is the band counted as horizontal.
pub fn motion_class(state: &MotionState, angle_eps: f64) -> MotionClass {
    if state.is_turning() {
        return MotionClass::FiveAxis;
    }
    if state.v_tip.length() == 0.0 {
        return MotionClass::Rest;
    }
    let psi = feed_angle(state);
    if (psi - FRAC_PI_2).abs() <= angle_eps {
        MotionClass::Horizontal
    } else if psi < FRAC_PI_2 {
        MotionClass::Ascending
    } else {
        MotionClass::Descending
    }
}

/// The feed-angle ranges of Aras Table 5.1, with the two ranges the table leaves out.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[allow(missing_docs)]
pub enum FeedRange {
    /// `ψ < β`: the top circle of the side leads (excluded by Aras).
    BelowF1,
    F1,
    F2,
    F3,
    F4,
    F5,
    B1,
    B2,
    B3,
    B4,
    /// `ψ > 180° − β` (excluded by Aras).
    BeyondB4,
}

/// The Table 5.1 range of feed angle `psi` for Aras angles `alpha`, `beta` (radians); angles
/// within `eps` of a boundary are on it.
pub fn feed_range(psi: f64, alpha: f64, beta: f64, eps: f64) -> FeedRange {
    use std::f64::consts::PI;
    let on = |x: f64| (psi - x).abs() <= eps;
    if on(beta) {
        FeedRange::F1
    } else if on(alpha) {
        FeedRange::F3
    } else if on(FRAC_PI_2) {
        FeedRange::F5
    } else if on(PI - alpha) {
        FeedRange::B2
    } else if on(PI - beta) {
        FeedRange::B4
    } else if psi < beta {
        FeedRange::BelowF1
    } else if psi < alpha {
        FeedRange::F2
    } else if psi < FRAC_PI_2 {
        FeedRange::F4
    } else if psi < PI - alpha {
        FeedRange::B1
    } else if psi < PI - beta {
        FeedRange::B3
    } else {
        FeedRange::BeyondB4
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_5_1_ranges() {
        let (a, b) = (70f64.to_radians(), 10f64.to_radians());
        let r = |deg: f64| feed_range(deg.to_radians(), a, b, 1e-9);
        assert_eq!(
            [5.0, 10.0, 40.0, 70.0, 80.0, 90.0, 100.0, 110.0, 150.0, 170.0, 175.0].map(r),
            [
                FeedRange::BelowF1,
                FeedRange::F1,
                FeedRange::F2,
                FeedRange::F3,
                FeedRange::F4,
                FeedRange::F5,
                FeedRange::B1,
                FeedRange::B2,
                FeedRange::B3,
                FeedRange::B4,
                FeedRange::BeyondB4
            ]
        );
    }

    #[test]
    fn faces_of_a_parallel() {
        // f = cos θ − 0.5: positive on |θ| < 60°, front only.
        let h = Harmonic {
            a: 1.0,
            b: 0.0,
            c: 0.5,
        };
        assert_eq!(faces(&h, 0.0), (true, false));
        // f = −cos θ + 0.9 > 0 almost everywhere: both faces.
        let h = Harmonic {
            a: -1.0,
            b: 0.0,
            c: -0.9,
        };
        assert_eq!(faces(&h, 0.0), (true, true));
        // f = sin θ − 0.99: a thin arc about 90°, reaching both sides of the y axis.
        let h = Harmonic {
            a: 0.0,
            b: 1.0,
            c: 0.99,
        };
        assert_eq!(faces(&h, 0.0), (true, true));
        // Never positive.
        let h = Harmonic {
            a: 1.0,
            b: 0.0,
            c: 1.0,
        };
        assert_eq!(faces(&h, 1e-12), (false, false));
    }
}
