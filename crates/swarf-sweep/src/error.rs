//! Errors of the sweep kernel: profiles that cannot be swept exactly and 5-axis moves that
//! cannot be split within a tolerance.

use thiserror::Error;

/// What can stop a shape from being swept or a move from being split into fixed-axis pieces.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SweepError {
    /// A profile that does not close or join.
    #[error("bad profile: {why}")]
    BadProfile {
        /// What is wrong.
        why: String,
    },
    /// A profile that turns inwards at `(rho, z)`: the solid is not convex.
    #[error("profile is not convex at rho = {rho} mm, z = {z} mm")]
    NotConvex {
        /// Radius of the offending joint.
        rho: f64,
        /// Height of the offending joint.
        z: f64,
    },
    /// A move that cannot be cut within the tolerance (a 5-axis move with a non-positive
    /// tolerance, or needing more than [`crate::five_axis::MAX_SUB_MOVES`] sub-moves).
    #[error("move {index} (line {line}): {why}")]
    Unsupported {
        /// Move index in the program.
        index: usize,
        /// Source line.
        line: u32,
        /// Why.
        why: String,
    },
}
