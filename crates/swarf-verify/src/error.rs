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
         triangles (e.g. {examples}); a design part must be the closed boundary of one or more \
         solid bodies"
    )]
    OpenMesh {
        /// The design file (or `<mesh>`).
        path: PathBuf,
        /// Edges used by other than two triangles.
        count: usize,
        /// The first few, as coordinates.
        examples: String,
    },
    /// The design mesh is empty, not finite, or bounds no volume.
    #[error(
        "design {path}: {what}; expected a closed triangle mesh bounding one or more solid bodies"
    )]
    BadMesh {
        /// The design file (or `<mesh>`).
        path: PathBuf,
        /// What is wrong.
        what: String,
    },
    /// The design mesh reaches beyond the machine range
    /// ([`swarf_geom::math::MACHINE_RANGE_MM`] from the origin), as stock meshes may not.
    #[error(
        "design {path}: the mesh's box from {min:?} to {max:?} mm reaches {reach:e} mm from the \
         origin, beyond the machine range of {range:e} mm"
    )]
    OutOfRange {
        /// The design file (or `<mesh>`).
        path: PathBuf,
        /// The bounding box's corners, mm.
        min: [f64; 3],
        /// Upper corner, mm.
        max: [f64; 3],
        /// The largest coordinate's magnitude, mm.
        reach: f64,
        /// The machine range, mm.
        range: f64,
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
