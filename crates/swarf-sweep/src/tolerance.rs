//! Every accuracy parameter of the sweep kernel, with its default, in one place.
//!
//! The exact fixed-axis sweep has no discretisation of its own. Arcs become chords and 5-axis
//! moves fixed-axis sub-moves within a chordal tolerance ([`DEFAULT_CHORDAL_TOLERANCE_MM`], a
//! proven Hausdorff bound, [`crate::five_axis`]). The other constants are floating-point guards
//! and finite-difference steps.

/// Default chordal tolerance for arcs, helices and 5-axis moves, mm (what the stock cuts with).
pub const DEFAULT_CHORDAL_TOLERANCE_MM: f64 = 0.001;

/// Step in the move parameter `s ∈ [0, 1]` of the central differences used where a pose is
/// not differentiated analytically (rotary motion interpolated through machine kinematics).
/// The truncation error is `O(step²)` relative; 1e-5 keeps the rounding error (≈ ε/step) and
/// the truncation error (≈ step²) both near 1e-10 relative.
pub const KINEMATICS_FD_STEP: f64 = 1e-5;

/// Step in `s` of the second difference of the distance from a grazing point to the tool at
/// nearby instants (the fold test, [`crate::fold`]). Large enough that rounding (≈ ε·size/step²)
/// stays below 1e-8 of the curvature term, small enough that the O(step²) truncation does.
pub const FOLD_FD_STEP: f64 = 1e-3;

/// A grazing point is folded into the sweep when the second derivative of its distance to the
/// tool is below `−FOLD_REL_TOL · |v|² / L` (`v` its velocity, `L` the tool's reach): the
/// scale of the curvature term of a tool of size `L`.
pub const FOLD_REL_TOL: f64 = 1e-6;

/// Instants per move sampled by the fold test.
pub const FOLD_SAMPLES: usize = 12;

/// Parallels per piece sampled by the fold test.
pub const FOLD_PARALLELS: usize = 12;

/// Relative tolerance of the tangency function: `|f| ≤ TANGENCY_REL_EPS · speed` counts as
/// zero (speed: the largest point speed over the piece). Rounding of the closed forms is near
/// 1e-15 relative, so this only absorbs floating point.
pub const TANGENCY_REL_EPS: f64 = 1e-9;
