//! Swept envelopes, grazing curves and feasible contact surfaces of the APT generic cutter.
//!
//! # Model
//! The cutter (`swarf_tool::Cutter`: tip at the origin, axis +Z, a stack of surface-of-revolution
//! pieces) moves rigidly along a program's moves (`swarf_path`). At an instant the motion is a
//! [`MotionState`]: tip `F`, unit axis `n`, tip velocity `V_F` and angular velocity `ω`, so a
//! tool point `P` moves at `V(P) = V_F + ω × (P − F)` ([`kinematics`]). With `N` the outward
//! normal at `P`, the **tangency function** `f = N·V` (Aras 2008, eq. 5.18) splits every piece
//! into forward (`f > 0`), envelope (`f = 0`) and backward (`f < 0`) sets ([`mod@tangency`]); the
//! forward set closed by the envelope is the kinematically feasible engagement set `CWE_K`
//! (Aras ch. 5, Tables 5.1–5.2). The envelope set — the **grazing** or characteristic curves —
//! is found in closed form for every piece ([`grazing`]): cones and spheres as canal surfaces
//! (a one-parameter family of spheres along the axis; two roots `θ₁,₂` per parallel, Aras
//! ch. 3), cylinders and tori as pipe surfaces (`N = m_t × m_u`), discs by their affine
//! tangency and their rims as edges.
//!
//! The **swept envelope** of moves and programs ([`mod@envelope`]) is the boundary of the union of
//! exact fixed-axis sweeps, sampled along the lines of a cubic lattice in X, Y and Z and
//! contoured into a closed mesh; arcs and 5-axis moves are split into fixed-axis pieces within
//! a chordal tolerance. Where the envelope of a move folds into its own sweep (tight turns) the
//! [`fold`] test reports the move.
//!
//! # Conventions
//! Millimetres and radians; the workpiece frame of `swarf_path`; the tool axis points from the
//! tip to the spindle; velocities are per unit of the move parameter `s ∈ [0, 1]` (grazing
//! curves depend only on directions). Accuracy parameters are named in [`tolerance`].
//!
//! # Errata of the source
//! Re-deriving Aras (2008) found, besides those in `seeds/ERRATA.md`: eq. 3.27 and 3.38 have the
//! sign of the `(P − F)·n_u` term flipped (expanding `(P − F − t n)·(F_u + t n_u)` gives
//! `−t{F_u·n − (P − F)·n_u}`, which is also `−½ ∂f/∂u` of eq. 3.26/3.37); eq. 5.1's first case
//! `y_L = x_L × z_L` makes a left-handed frame (`y_L = z_L × x_L` is meant, and only then do
//! 5.24–5.39 hold); eq. 5.33's `A_T` lost the major radius, `(h_c sin φ + R cos φ)(ω·y_L)`;
//! eq. 5.41's second root reads `C_T` for `C_L`; eq. 3.23 writes `F(t)` for `F(u)`.
//!
//! # Example
//! A 10 mm ball-nose moving along +X: its grazing curve is the great circle of the ball normal
//! to the feed (and the cylinder's two side lines), every point with `N·V = 0`.
//!
//! ```
//! use swarf_geom::math::Vec3;
//! use swarf_sweep::{grazing_points, tangency, MotionState};
//! use swarf_tool::Cutter;
//!
//! let ball = Cutter::ball(10.0).unwrap();
//! let state = MotionState::translation(Vec3::ZERO, Vec3::Z, Vec3::X);
//! let set = grazing_points(ball.pieces(), &state, 9);
//! assert!(!set.points.is_empty());
//! for g in &set.points {
//!     assert!(tangency(&state, g.point, g.normal).abs() < 1e-12);
//!     if !g.edge {
//!         assert!(g.point.x.abs() < 1e-12); // the plane through the axis normal to the feed
//!     }
//! }
//! ```

pub mod envelope;
pub mod error;
pub mod fold;
pub mod grazing;
pub mod kinematics;
pub mod tangency;
pub mod tolerance;

pub use envelope::{
    envelope, fixed_axis_pieces, Envelope, EnvelopeGrid, EnvelopeOptions, EnvelopeReport,
    FixedAxisPiece,
};
pub use error::SweepError;
pub use fold::{fold_check, SelfIntersection};
pub use grazing::{grazing_points, GrazingPoint, GrazingSet, Harmonic, Roots};
pub use kinematics::MotionState;
pub use tangency::{
    aras_angles, feasible_contact, feed_angle, feed_range, motion_class, roles, tangency,
    Feasibility, FeedRange, MotionClass, PieceEngagement, PieceRole, Side,
};
pub use tolerance::*;
