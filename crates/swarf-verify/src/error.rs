//! What can go wrong: a design that is not a solid, tolerances that make no sense.

use std::path::PathBuf;

/// Errors of the verification.
#[derive(Debug, thiserror::Error)]
pub enum VerifyError {
    /// The observer ([`swarf_geom::progress::Observer`]) stopped the verification after `done`
    /// of `total` rows of rays; nothing is reported.
    #[error("stopped after {done} of {total} rows of rays")]
    Cancelled {
        /// Rows of rays compared.
        done: u64,
        /// Rows of rays in the three families.
        total: u64,
    },
    /// The design file could not be read (the reader's error names the file and what it
    /// expected).
    #[error(transparent)]
    Read(#[from] swarf_io::IoError),
    /// The design mesh is not a closed solid boundary.
    #[error(
        "design {path}: not a closed mesh: {count} edges are not shared by exactly two \
         triangles (e.g. {examples}); a design part must be a closed, consistently oriented solid"
    )]
    OpenMesh {
        /// The design file (or `<mesh>`).
        path: PathBuf,
        /// Edges used by other than two triangles.
        count: usize,
        /// The first few, as coordinates.
        examples: String,
    },
    /// The design mesh is empty, not finite, or inconsistently oriented.
    #[error("design {path}: {what}; expected a closed, consistently oriented triangle mesh")]
    BadMesh {
        /// The design file (or `<mesh>`).
        path: PathBuf,
        /// What is wrong.
        what: String,
    },
    /// A tolerance is negative or not finite.
    #[error("{name} must be a finite number of mm ≥ 0, got {value}")]
    BadTolerance {
        /// Which tolerance.
        name: &'static str,
        /// Its value.
        value: f64,
    },
}
