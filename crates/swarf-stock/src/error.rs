//! Errors of stock construction and simulation.

use thiserror::Error;

/// What can go wrong building a stock or simulating a program on it.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum StockError {
    /// The run was stopped by its observer ([`swarf_geom::progress::Observer`], e.g. on
    /// Ctrl-C) after `done` moves.
    #[error("stopped after {done} moves")]
    Cancelled {
        /// Moves completed.
        done: usize,
    },
    /// A stock spec string that cannot be read.
    #[error("stock spec column {column}: found {found}, expected {expected}")]
    Spec {
        /// 1-based column in the spec.
        column: usize,
        /// What was found.
        found: String,
        /// What would have been accepted.
        expected: String,
    },
    /// A stock file that cannot be read, or whose mesh makes no stock (the message says why).
    #[error("{file}: {message}")]
    Io {
        /// File name.
        file: String,
        /// The system's message.
        message: String,
    },
    /// A resolution that is not a positive finite number.
    #[error("resolution must be a positive finite number of mm, got {0:?}")]
    BadResolution(f64),
    /// A stock shape with non-positive or non-finite dimensions.
    #[error("bad stock dimensions: {0}")]
    BadDimensions(String),
    /// The grid would hold more rays than [`crate::MAX_RAYS`].
    #[error(
        "resolution {h:?} mm over a {size} mm stock needs {rays:.3e} rays, more than the limit \
         {limit}; give a coarser resolution"
    )]
    TooManyRays {
        /// Requested resolution.
        h: f64,
        /// Stock size, mm, as text.
        size: String,
        /// Rays needed (counted in floating point: it may exceed every integer type).
        rays: f64,
        /// The limit.
        limit: u64,
    },
    /// The mesh has boundary edges (it is not closed).
    #[error(
        "the mesh is not closed: {open} open edge(s), {non_manifold} non-manifold edge(s), e.g. \
         {examples}"
    )]
    OpenMesh {
        /// Number of edges used by only one triangle or more than two.
        count: usize,
        /// Edges used by one triangle.
        open: usize,
        /// Edges used by more than two triangles.
        non_manifold: usize,
        /// The first few edges' end points, as text.
        examples: String,
    },
    /// An open mesh (allowed by [`crate::MeshOptions::allow_open`]) that encloses no material.
    #[error(
        "the open mesh ({count} open edge(s)) encloses no material: no ray enters and leaves \
         it; close the mesh"
    )]
    EmptyOpenMesh {
        /// Number of open edges.
        count: usize,
    },
    /// The mesh has no triangles, or a triangle with a non-finite coordinate.
    #[error("bad mesh: {0}")]
    BadMesh(String),
    /// A move whose tool number has no cutter.
    #[error("move {index} (line {line}): no cutter for tool {tool}")]
    UnknownTool {
        /// Move index in the program.
        index: usize,
        /// Source line.
        line: u32,
        /// Tool number.
        tool: u32,
    },
    /// A shape that cannot be swept exactly or a 5-axis move that cannot be split within the
    /// tolerance (from the sweep kernel).
    #[error(transparent)]
    Sweep(#[from] swarf_sweep::SweepError),
    /// A non-finite pose.
    #[error("move {index} (line {line}): non-finite tool position or axis")]
    NonFinite {
        /// Move index in the program.
        index: usize,
        /// Source line.
        line: u32,
    },
}
