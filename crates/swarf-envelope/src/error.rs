//! Errors of envelope construction, each naming the move (index and source line) it concerns.

use thiserror::Error;

/// What can stop an envelope from being built.
#[derive(Debug, Error)]
pub enum EnvelopeError {
    /// A move uses a tool number no cutter was given for.
    #[error("move {index} (line {line}) uses tool T{tool}, for which no cutter was given")]
    UnknownTool {
        /// Move index in the program.
        index: usize,
        /// Source line of the move.
        line: u32,
        /// The tool number.
        tool: u32,
    },
    /// The selected move range is empty or outside the program.
    #[error("move range {start}..{end} selects no feed move of the {len} moves of the program")]
    NoMoves {
        /// First index asked for.
        start: usize,
        /// One past the last index asked for.
        end: usize,
        /// Number of moves in the program.
        len: usize,
    },
    /// An accuracy parameter is not a positive finite number.
    #[error("{name} must be a positive finite number, got {value}")]
    BadParameter {
        /// The parameter's name.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// The swept box needs more lattice points than [`crate::MAX_LATTICE_POINTS`].
    #[error("the envelope lattice would hold {points:.3e} points (more than {max}); use a coarser resolution than {h} mm")]
    TooFine {
        /// Points needed (counted in floating point: it may exceed every integer type).
        points: f64,
        /// The limit.
        max: u64,
        /// The resolution asked for, mm.
        h: f64,
    },
    /// The ray grid could not be made (from `swarf-stock`).
    #[error(transparent)]
    Stock(#[from] swarf_stock::StockError),
    /// A 5-axis move could not be split into fixed-axis sub-moves (from `swarf-sweep`).
    #[error(transparent)]
    Sweep(#[from] swarf_sweep::SweepError),
}
