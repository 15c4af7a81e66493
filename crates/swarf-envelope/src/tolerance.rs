//! Every accuracy parameter of the envelope, with its default, in one place.
//!
//! The envelope mesh has three error sources, each a named parameter reported in
//! [`crate::EnvelopeReport`]: the lattice spacing `h` of the ray grid
//! ([`DEFAULT_RESOLUTION_MM`]), the chordal tolerance with which arcs become chords and 5-axis
//! moves become fixed-axis sub-moves ([`DEFAULT_CHORDAL_TOLERANCE_MM`], a proven Hausdorff bound
//! from `swarf_sweep::five_axis`), and the contouring of the union of exact ray intervals
//! (vertices put on the exact surface of the pieces; triangles within `h²κ/8` of it).

/// Default ray spacing of the envelope lattice, mm.
pub const DEFAULT_RESOLUTION_MM: f64 = 0.25;

/// Default chordal tolerance for arcs and 5-axis sub-moves, mm: a tenth of
/// [`DEFAULT_RESOLUTION_MM`]. Lines are swept exactly; on arcs and 5-axis moves this bound,
/// not the contouring, is the envelope's error. The number of
/// 5-axis sub-moves, and the envelope time of 5-axis moves, grows like `1/tolerance` (their
/// error is first order in the sub-move length).
pub const DEFAULT_CHORDAL_TOLERANCE_MM: f64 = 0.025;

/// Largest number of lattice points of an envelope grid (a guard against runaway memory).
pub const MAX_LATTICE_POINTS: u64 = 400_000_000;
