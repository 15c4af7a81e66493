//! The moving cutter: exact swept solids, grazing curves and feasible contact surfaces of the APT
//! generic cutter.
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
//! The **exact swept solid** of a straight move with a fixed tool axis ([`swept`]) is what the
//! stock (`swarf-stock`), the envelope mesh (`swarf-envelope`) and the engagement cut and query:
//! for a line, the one interval inside the sweep of a convex solid of revolution (caps and
//! grazing-curve extrusions in closed form, the torus by guaranteed root isolation), with
//! closed-form kernels for the common ball, flat and bull-nose cutters (a bull-nose's ramps
//! keep one Newton search for the corner), for flat, ball and bull-nose instances at any axis (the 5-axis
//! cuts), and for flat, ball and bull-nose end mills moving at any fixed axis (3+2 moves, a
//! 5-axis flat end mill's pieces). A cutter is swept as the union of
//! its convex parts ([`ToolShape`]: cutting part; shank and holder). Arcs and helices are cut as
//! chords ([`arc_chords`]), and 5-axis moves as constant-axis sub-moves with a proven Hausdorff
//! bound ([`five_axis`]), both within a chordal tolerance. Where the envelope of a move folds
//! into its own sweep (tight turns) the [`fold`] test reports the move.
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

pub mod chords;
pub mod error;
pub mod five_axis;
pub mod fold;
pub mod grazing;
pub mod kinematics;
pub mod swept;
pub mod tangency;
pub mod tolerance;
pub mod tool_shape;

pub use chords::{arc_chords, too_many_chords, MAX_CHORDS};
pub use error::SweepError;
pub use five_axis::{MotionBound, Reach, SubMove};
pub use fold::{fold_check, SelfIntersection};
pub use grazing::{grazing_points, GrazingPoint, GrazingSet, Harmonic, Roots};
pub use kinematics::MotionState;
pub use swept::{
    ConvexProfile, DexelKernel, Element, Front, FrontBlock, InstanceSet, KernelTask, KeyBound,
    LineBatch, PlanarMember, Progress, SignedDistance, SweepBound, SweepShape, SweptConvex,
};
pub use tangency::{
    aras_angles, feasible_contact, feed_angle, feed_range, motion_class, roles, tangency,
    Feasibility, FeedRange, MotionClass, PieceEngagement, PieceRole, Side,
};
pub use tolerance::*;
pub use tool_shape::{InstanceBand, ToolShape};
