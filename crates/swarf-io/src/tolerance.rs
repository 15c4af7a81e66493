//! Every tolerance and limit of this crate, named and documented in one place. The option
//! structs ([`crate::ContourOptions`], [`crate::GlbOptions`]) take their defaults from here.

/// How many offending edges an [`crate::EdgeReport`] lists.
pub const MAX_EDGE_EXAMPLES: usize = 8;

/// Largest binary STL accepted by the reader, in triangles (about 2.5 GB of file): a header
/// claiming more is treated as garbage rather than trusted with an allocation.
pub const MAX_STL_TRIANGLES: u64 = 50_000_000;

/// Dual contouring: eigenvalues of the QEF's normal matrix below this fraction of the largest
/// are truncated (treated as zero), so nearly parallel planes do not throw the vertex far away;
/// the position along the truncated directions comes from the mass point. Two planes at 90°
/// from a handful of crossings each stay well above it; tangent planes of a smooth surface
/// within one cell fall below it, which keeps those vertices near the crossings.
pub const DEFAULT_EIGEN_THRESHOLD: f64 = 0.02;

/// Dual contouring, normal estimation: a crossing on a neighbouring line is taken as the
/// continuation of the same surface only if it lies within `max_slope × spacing × lines apart`
/// along the ray (a surface steeper than this relative to the ray is left to the other two
/// ray families, whose crossings see it at a better angle).
pub const DEFAULT_MAX_SLOPE: f64 = 4.0;

/// Dual contouring, normal estimation: weight of a crossing's plane in the QEF is
/// `|n · ray axis|^power` (1 for exact normals given by the grid). Crossings that graze their
/// ray have the least reliable estimated normals.
pub const DEFAULT_WEIGHT_POWER: f64 = 1.0;

/// [`crate::FnGrid`]: crossings are refined until their bracket is below this fraction of the
/// spacing.
pub const DEFAULT_ROOT_TOLERANCE: f64 = 1e-13;

/// Dual contouring: an interval end of a lattice edge's own line found up to this fraction of
/// the spacing beyond the edge still counts as the edge's crossing (clamped onto it). Ray
/// families computed independently can disagree by rounding where the surface passes through
/// a lattice point; anything farther is a real disagreement and falls back to the midpoint.
pub const DEFAULT_CROSSING_SLACK: f64 = 1e-6;

/// Dual contouring, normal estimation: the central difference's second difference is scaled by
/// this factor before it is compared with the one-sided ones, so a one-sided stencil replaces
/// the (second-order) central one only where it is clearly smoother: next to a kink, where
/// the central second difference is O(h) and the one-sided one O(h²) or zero.
pub const ENO_ONE_SIDED_FACTOR: f64 = 0.25;

/// [`crate::TriMesh::merge_coplanar`]: triangles whose corners lie within this of one plane are
/// merged, and boundary vertices within this of a straight line between their neighbours are
/// taken out (mm). The merged surface lies within it of the input's.
pub const PLANAR_TOLERANCE_MM: f64 = 1e-6;
