//! Every accuracy parameter of the envelope, with its default, in one place.
//!
//! The envelope mesh has three error sources, each a named parameter reported in
//! [`crate::EnvelopeReport`]: the lattice spacing `h` of the ray grid
//! ([`DEFAULT_RESOLUTION_MM`]), the chordal tolerance with which arcs become chords and 5-axis
//! moves become fixed-axis sub-moves ([`DEFAULT_CHORDAL_TOLERANCE_MM`], a proven Hausdorff bound
//! from `swarf_sweep::five_axis`), and the contouring of the union of exact ray intervals
//! (vertices put on the exact surface of the pieces; triangles within `h²κ/8` of it, or chords
//! of blocks of 2 × 2 × 2 cells where those are merged: [`DEFAULT_SIMPLIFY_MM`]).

/// Default ray spacing of the envelope lattice, mm.
pub const DEFAULT_RESOLUTION_MM: f64 = 0.25;

/// Default chordal tolerance for arcs and 5-axis sub-moves, mm: a tenth of
/// [`DEFAULT_RESOLUTION_MM`]. Lines are swept exactly; on arcs and 5-axis moves this bound,
/// not the contouring, is the envelope's error. The number of
/// 5-axis sub-moves, and the envelope time of 5-axis moves, grows like `1/tolerance` (their
/// error is first order in the sub-move length).
pub const DEFAULT_CHORDAL_TOLERANCE_MM: f64 = 0.025;

/// Default tolerance of the contouring's merged blocks (`ContourOptions::simplify`), mm: a
/// 2 × 2 × 2 block of cells gets one vertex where its crossings lie within this of the planes
/// that meet at it. The envelope's vertices are then put on the exact surface, so a merged
/// block's facets are chords of exact points twice as far apart: on a 36 mm line of a 10 mm
/// ball the facets lie within 5.5·10⁻⁴ mm of the exact envelope at h = 0.05 (1.8·10⁻³ with
/// every cell, whose facets cut the shank's rim), 2.1·10⁻³ at h = 0.1 (3.6·10⁻³), 9.7·10⁻³ at
/// the default h = 0.25 (5.9·10⁻³; under [`DEFAULT_CHORDAL_TOLERANCE_MM`] either way), with
/// a quarter to a half of the triangles, and the contouring takes about half the time (it
/// decides the blocks before it makes cells). Cost then grows with the surface's detail, not
/// with its area over `h²`.
pub const DEFAULT_SIMPLIFY_MM: f64 = 1e-3;

/// Largest number of lattice points of an envelope grid (a guard against runaway memory).
pub const MAX_LATTICE_POINTS: u64 = 400_000_000;
