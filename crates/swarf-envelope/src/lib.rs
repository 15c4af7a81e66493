//! The swept envelope of moves and programs as a closed mesh.
//!
//! # Model
//! The envelope of a range of feed moves is the boundary of the union of the volumes the whole
//! tool (cutting part, shank, holder) sweeps along them. Each move is split into fixed-axis
//! straight pieces (`swarf_sweep`: a line as it is, arcs as chords, 5-axis moves as constant-axis
//! sub-moves with a proven Hausdorff bound) whose exact sweeps are sampled along the lines of a
//! tri-dexel (`swarf_stock`'s ray grid, starting empty) in X, Y and Z; the union of their
//! intervals on every ray is contoured into a
//! closed, outward-oriented mesh (`swarf_io`'s dual contouring). Where the envelope of a move
//! folds into its own sweep (tight turns) the fold test of `swarf_sweep` reports the move; the
//! union resolves it.
//!
//! # Conventions
//! Millimetres; the workpiece frame of `swarf_path`; the tool axis points from the tip to the
//! spindle. Accuracy parameters are named in [`tolerance`] and reported in [`EnvelopeReport`].
//!
//! # Example
//! ```
//! use swarf_envelope::{envelope, EnvelopeOptions};
//! use swarf_path::load::{read_program_str, ReadOptions};
//! use swarf_path::Machine;
//! use swarf_tool::{Cutter, ToolSet};
//!
//! let program = read_program_str(
//!     "G21 G90\nG0 X0 Y0 Z0\nG1 X20 F300\n",
//!     "line.ngc",
//!     Machine::three_axis(),
//!     &ReadOptions::default(),
//! )
//! .unwrap();
//! let tools = ToolSet::single(Cutter::ball(10.0).unwrap());
//! let options = EnvelopeOptions::default().with_resolution(0.5);
//! let env = envelope(&program, &tools, 0..program.moves.len(), &options).unwrap();
//! assert!(env.mesh.is_closed());
//! ```

pub mod envelope;
pub mod error;
mod project;
pub mod tolerance;

pub use envelope::{
    envelope, envelope_rays, fixed_axis_pieces, Envelope, EnvelopeOptions, EnvelopeReport,
    FixedAxisPiece,
};
pub use error::EnvelopeError;
pub use tolerance::*;
