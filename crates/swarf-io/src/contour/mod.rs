//! Dual contouring of Hermite data on a regular lattice: the bridge from a tri-dexel stock (or
//! any solid that can answer "where along this lattice line is material?") to a closed,
//! outward-oriented triangle mesh with sharp edges and corners.
//!
//! # Input: a [`HermiteGrid`]
//! The solid is sampled on the lines of a regular [`Lattice`] (points `origin + (i, j, k) ∘
//! spacing`). For each axis `a` and each lattice line parallel to it, the grid reports the
//! solid's intervals along that line ([`Span`]s, world coordinate along `a`). That is exactly
//! what a tri-dexel stores: the X, Y and Z rays through the cell centres *are* the lattice
//! lines, so [`HermiteGrid::line_spans`] copies a dexel's intervals and nothing else is needed.
//! Lines are indexed like the stock's ray families: the line of axis `a` through lattice
//! indices `(u, v)` on the axes `(a + 1) % 3` and `(a + 2) % 3`.
//!
//! From the spans:
//! - **membership** of lattice point `(i, j, k)` is read on the X line through it (closed
//!   intervals: a point on an interval's end is inside). Points outside the lattice are outside,
//!   and the solid is clipped to the *domain* `[origin − spacing/2, origin + (n − ½)·spacing]`
//!   (for a tri-dexel: exactly the stock's grid box), so the mesh is closed even where the
//!   solid fills the lattice to its boundary;
//! - the **crossing** on a lattice edge along `a` whose ends differ is the interval end on that
//!   edge's own line (so X rays place the surface along X, Y rays along Y, Z rays along Z: a
//!   vertical wall is positioned by the horizontal rays that hit it square). Where the three
//!   families disagree (a Y or Z line with no matching interval end on an edge where the X
//!   lines change), the edge midpoint is used and counted in [`ContourStats::fallback_crossings`];
//! - the **normal** at a crossing is [`HermiteGrid::normal`] if the grid knows it, otherwise it
//!   is estimated from the same family's neighbouring lines (module `normal`): the crossings of
//!   the matching interval ends on the lines ±1, ±2 apart in each cross direction give the
//!   surface as a height field over the line; its slope in each direction is the one-sided or
//!   central difference whose second difference is smallest (an ENO stencil), so a flat face
//!   gives an exactly flat normal right up to a 90° edge, where the stencil looks away from the
//!   edge. Estimated normals enter the QEF weighted by `|n · axis|^p`
//!   ([`ContourOptions::weight_power`]): crossings that graze their ray count least.
//!
//! # Output
//! One vertex per *surface patch* of each lattice cell with a sign change — usually one per
//! cell; a cell whose corners make several separate patches (two solids closer than a cell,
//! a thin slot) gets one vertex per patch, resolving ambiguous faces by keeping inside
//! corners apart (inside is 6-connected). The vertex minimises the patch's QEF
//! `Σ wᵢ (nᵢ · (x − pᵢ))²` through an eigen-decomposition of its normal matrix, with
//! eigenvalues below [`ContourOptions::eigen_threshold`] × the largest truncated and the
//! missing directions taken from the mass point (the mean of the crossings), then clamped to
//! the cell. Each lattice edge with a sign change gives a quad over the four cells around it,
//! oriented so that its normal points from inside to outside, split into two triangles along
//! the diagonal that keeps them flattest.
//!
//! With [`ContourOptions::simplify`], each 2 × 2 × 2 block of cells whose contour is one patch
//! of the same topology (Ju et al. 2002's test on the block's 27 lattice points) and whose
//! crossings lie within the tolerance of the planes met at the block's own edges gets one
//! vertex (where those planes meet) instead of its cells' own. The blocks of a pair of slabs
//! are decided first (module `blocks`), then only the cells of blocks left as they are are
//! made; an edge whose four cells share a merged vertex gives one triangle (two cells in one
//! block) or none (the edge inside a block, or on the face between two), and an edge all of
//! whose cells are merged has no crossing computed unless it halves an edge of the coarse
//! lattice of block corners, whose quad it gives.
//!
//! Every mesh edge is shared by exactly two triangles with opposite directions. The one
//! configuration that could break this — a lattice face with all four edges crossed whose
//! crossings one patch joins in *both* cells beside it (a tunnel narrower than a cell through
//! the face) — is detected from the two cells' corner masks, and both cells then pair that
//! face's edges around its outside corners instead, which provably never joins them (an
//! exhaustive check over all 256 masks and face choices is in the tests). What this costs is
//! topology below the lattice's resolution: such a tunnel is closed off in that face. The work
//! is parallel over Z slabs of cells (rayon) and sparse: it
//! touches the lattice only near the surface (cost ∝ lines + crossings, not cells).

mod blocks;
mod extract;
mod fn_grid;
mod lines;
mod normal;
mod qef;
mod table;

pub use fn_grid::FnGrid;

use crate::mesh::TriMesh;
use crate::tolerance::{
    DEFAULT_CROSSING_SLACK, DEFAULT_EIGEN_THRESHOLD, DEFAULT_MAX_SLOPE, DEFAULT_WEIGHT_POWER,
};
use swarf_geom::math::Vec3;
use swarf_geom::Aabb;

/// A regular lattice of points `origin + (i, j, k) ∘ spacing` for `i < n[0]`, `j < n[1]`,
/// `k < n[2]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lattice {
    /// Position of point `(0, 0, 0)`, mm.
    pub origin: Vec3,
    /// Distance between neighbouring points along X, Y, Z, mm (each `> 0`).
    pub spacing: Vec3,
    /// Number of points along X, Y, Z.
    pub n: [usize; 3],
}

impl Lattice {
    /// The lattice with the given origin, spacing and counts.
    pub fn new(origin: Vec3, spacing: Vec3, n: [usize; 3]) -> Self {
        Self { origin, spacing, n }
    }

    /// The lattice of the centres of `n` cells dividing `bounds` evenly — the points where a
    /// tri-dexel's rays meet. Its domain is `bounds`.
    pub fn cell_centres(bounds: Aabb, n: [usize; 3]) -> Self {
        let size = bounds.size();
        let spacing = Vec3::new(
            size.x / n[0] as f64,
            size.y / n[1] as f64,
            size.z / n[2] as f64,
        );
        Self {
            origin: bounds.min + 0.5 * spacing,
            spacing,
            n,
        }
    }

    /// A cubic lattice of spacing `h` whose domain covers `bounds` (at least), centred on it.
    pub fn covering(bounds: Aabb, h: f64) -> Self {
        let size = bounds.size();
        let n = [size.x, size.y, size.z].map(|s| ((s / h).ceil() as usize).max(1));
        let extent = Vec3::new(n[0] as f64, n[1] as f64, n[2] as f64) * h;
        let min = bounds.center() - 0.5 * extent;
        Self {
            origin: min + Vec3::splat(0.5 * h),
            spacing: Vec3::splat(h),
            n,
        }
    }

    /// Coordinate along `axis` of lattice index `i` (negative or `≥ n` for the virtual,
    /// always-outside points around the lattice).
    #[inline]
    pub fn coord(&self, axis: usize, i: isize) -> f64 {
        self.origin[axis] + i as f64 * self.spacing[axis]
    }

    /// Position of lattice point `(i, j, k)`.
    #[inline]
    pub fn point(&self, i: isize, j: isize, k: isize) -> Vec3 {
        Vec3::new(self.coord(0, i), self.coord(1, j), self.coord(2, k))
    }

    /// The box the solid is clipped to: half a spacing beyond the outermost points.
    pub fn domain(&self) -> Aabb {
        let n = Vec3::new(self.n[0] as f64, self.n[1] as f64, self.n[2] as f64);
        Aabb::new(
            self.origin - 0.5 * self.spacing,
            self.origin + (n - Vec3::splat(0.5)) * self.spacing,
        )
    }

    /// Number of lattice cells `(n − 1)` per axis, multiplied (a size measure for benchmarks).
    pub fn cell_count(&self) -> usize {
        self.n.iter().map(|&k| k.saturating_sub(1)).product()
    }

    fn is_valid(&self) -> bool {
        // Cell keys of a Z slab, (n0 + 1)(n1 + 1), are u32.
        self.n.iter().all(|&k| k > 0 && k < i32::MAX as usize / 2)
            && ((self.n[0] + 1) as u64) * ((self.n[1] + 1) as u64) < u32::MAX as u64
            && self.spacing.cmpgt(Vec3::ZERO).all()
            && self.spacing.is_finite()
            && self.origin.is_finite()
    }
}

/// A closed interval `[enter, exit]` of solid along a lattice line, in the world coordinate
/// along the line's axis (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Span {
    /// Where the line enters the solid (going towards +axis).
    pub enter: f64,
    /// Where it leaves (`≥ enter`).
    pub exit: f64,
}

/// A solid sampled along the lines of a regular lattice (see the [module docs](self)).
///
/// For a tri-dexel whose rays pass through the centres of an `n[0] × n[1] × n[2]` grid of cells
/// over a box `B`: `lattice()` is `Lattice::cell_centres(B, n)`; `line_spans(a, u, v, out)` appends
/// the intervals of the ray of family `a` at cross indices `(u, v)` (the stock's
/// `family(a).ray(u, v)`); `normal` keeps its default (`None`) unless normals are stored.
pub trait HermiteGrid: Sync {
    /// The lattice whose lines are sampled.
    fn lattice(&self) -> Lattice;

    /// Appends to `out` the solid intervals along the lattice line parallel to `axis` through
    /// the lattice indices `u` on axis `(axis + 1) % 3` and `v` on axis `(axis + 2) % 3`:
    /// sorted, disjoint, world coordinates along `axis`. They may extend beyond the lattice
    /// (they are clipped to [`Lattice::domain`]); unsorted or overlapping input is sorted and
    /// merged, non-finite ends are dropped.
    fn line_spans(&self, axis: usize, u: usize, v: usize, out: &mut Vec<Span>);

    /// The outward unit normal of the solid at `p`, a boundary point found on a line of
    /// `axis`, if the grid knows it. The default (`None`) lets the contouring estimate it.
    fn normal(&self, axis: usize, p: Vec3) -> Option<Vec3> {
        let _ = (axis, p);
        None
    }
}

/// How a quad is split into two triangles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum QuadSplit {
    /// Along the diagonal whose two triangles have the most nearly parallel normals (keeps
    /// flat faces flat and folds along edges).
    #[default]
    Flattest,
    /// Always along the diagonal from the quad's first vertex.
    Fixed,
}

/// Parameters of [`dual_contour`]; defaults from [`crate::tolerance`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContourOptions {
    /// Relative eigenvalue truncation of the QEF ([`DEFAULT_EIGEN_THRESHOLD`]).
    pub eigen_threshold: f64,
    /// Steepest surface slope, relative to a line, that normal estimation follows across
    /// neighbouring lines ([`DEFAULT_MAX_SLOPE`]).
    pub max_slope: f64,
    /// Exponent of the weight `|n · axis|` of an estimated normal ([`DEFAULT_WEIGHT_POWER`]).
    pub weight_power: f64,
    /// How far beyond a lattice edge (fraction of the spacing) an interval end of the edge's
    /// own line is still taken as its crossing, clamped onto the edge: absorbs rounding
    /// differences between the ray families where the surface passes through a lattice point
    /// ([`DEFAULT_CROSSING_SLACK`]).
    pub crossing_slack: f64,
    /// Clamp each vertex to its cell (recommended; otherwise a vertex may leave its cell
    /// where the planes of its crossings meet far away).
    pub clamp_to_cell: bool,
    /// Quad triangulation.
    pub split: QuadSplit,
    /// Merge each 2 × 2 × 2 block of cells into one vertex where that changes neither the
    /// surface's topology nor, beyond this distance (mm), its shape: `None` (the default)
    /// keeps one vertex per cell patch. A block is merged when every cell of it with a
    /// crossing has a single patch and no ambiguous face (one with two diagonal inside
    /// corners), the block's own corners make a single patch with no ambiguous face, the lattice
    /// points at its edges' and faces' middles and at its centre each have the side of one of
    /// the corners around them (Ju et al. 2002's topology-safety test: the merged contour is
    /// the fine one's, face by face), and its vertex — where the planes of the crossings on
    /// the block's own edges meet (their QEF's minimiser, clamped to the block), as a lattice
    /// twice as coarse would place it — lies within this distance of those planes and of
    /// every crossing of the block, each measured from the nearest of those planes moved
    /// through the vertex (both root mean square), and within it of the box of the block's
    /// crossings (planes that meet far from the crossings do not make a vertex of the
    /// surface). The mesh then has about a quarter of the triangles where the surface is
    /// smooth at the block's scale; sharp edges keep their place (the planes meet on them),
    /// and fine detail keeps its cells. The blocks are decided before the cells are made, so
    /// a merged block costs reading its crossings, not making its cells: the contouring runs
    /// in about half the time.
    pub simplify: Option<f64>,
}

impl Default for ContourOptions {
    fn default() -> Self {
        Self {
            eigen_threshold: DEFAULT_EIGEN_THRESHOLD,
            max_slope: DEFAULT_MAX_SLOPE,
            weight_power: DEFAULT_WEIGHT_POWER,
            crossing_slack: DEFAULT_CROSSING_SLACK,
            clamp_to_cell: true,
            split: QuadSplit::Flattest,
            simplify: None,
        }
    }
}

impl ContourOptions {
    /// With the given eigenvalue truncation.
    pub fn with_eigen_threshold(mut self, t: f64) -> Self {
        self.eigen_threshold = t;
        self
    }

    /// With the given maximum slope for normal estimation.
    pub fn with_max_slope(mut self, s: f64) -> Self {
        self.max_slope = s;
        self
    }

    /// With the given quad split.
    pub fn with_split(mut self, s: QuadSplit) -> Self {
        self.split = s;
        self
    }

    /// With 2 × 2 × 2 blocks of cells merged where their crossings lie within `tol` mm of the
    /// planes that meet at one point ([`ContourOptions::simplify`]); `None` keeps every cell.
    pub fn with_simplify(mut self, tol: Option<f64>) -> Self {
        self.simplify = tol;
        self
    }
}

/// What [`dual_contour_with_stats`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ContourStats {
    /// Lattice lines read (all three families).
    pub lines: usize,
    /// Spans kept after clipping to the domain.
    pub spans: usize,
    /// Cells with at least one vertex.
    pub cells: usize,
    /// Vertices (one per surface patch per cell).
    pub vertices: usize,
    /// Triangles.
    pub triangles: usize,
    /// Sign-changing edges whose own line had no matching interval end (midpoint used); with
    /// merged blocks, of the edges of the cells not merged.
    pub fallback_crossings: usize,
    /// Crossings whose normal could be neither read nor estimated (they only move the mass
    /// point).
    pub unknown_normals: usize,
    /// Vertices the QEF placed outside their cell (clamped when clamping is on).
    pub clamped_vertices: usize,
    /// Vertices moved onto the exact surface ([`dual_contour_projected`]).
    pub projected_vertices: usize,
    /// 2 × 2 × 2 blocks of cells merged into one vertex ([`ContourOptions::simplify`]).
    pub merged_blocks: usize,
}

impl ContourStats {
    fn add(mut self, o: ContourStats) -> Self {
        self.cells += o.cells;
        self.vertices += o.vertices;
        self.triangles += o.triangles;
        self.fallback_crossings += o.fallback_crossings;
        self.unknown_normals += o.unknown_normals;
        self.clamped_vertices += o.clamped_vertices;
        self.merged_blocks += o.merged_blocks;
        self
    }
}

/// The closed, outward-oriented boundary mesh of the solid sampled by `grid`. A lattice
/// without points, with a spacing that is not positive and finite, or wider than 65 535
/// points in X × Y gives an empty mesh.
pub fn dual_contour<G: HermiteGrid + ?Sized>(grid: &G, options: &ContourOptions) -> TriMesh {
    dual_contour_with_stats(grid, options).0
}

/// [`dual_contour`] with counts of what was done and of every fallback taken.
pub fn dual_contour_with_stats<G: HermiteGrid + ?Sized>(
    grid: &G,
    options: &ContourOptions,
) -> (TriMesh, ContourStats) {
    contour(grid, options, None)
}

/// [`dual_contour_with_stats`] for a solid whose surface is known exactly: every vertex is
/// handed to `project` with its unit normal (area-weighted over its triangles) before the
/// mesh is made safe for `f32` storage, and moved where `project` says (`None`: left where the
/// QEF put it). The Hermite data only places vertices within a fraction of the lattice
/// spacing of a curved surface; a caller that can intersect lines with the true surface puts
/// them on it. Moves are expected to be small against the spacing (the projection must not
/// fold triangles over).
pub fn dual_contour_projected<G, P>(
    grid: &G,
    options: &ContourOptions,
    project: P,
) -> (TriMesh, ContourStats)
where
    G: HermiteGrid + ?Sized,
    P: Fn(Vec3, Vec3) -> Option<Vec3> + Sync,
{
    contour(grid, options, Some(&project))
}

/// [`dual_contour_projected`] that takes the grid and drops it as soon as its lines are read,
/// before the extraction (where a large mesh peaks): for a grid that leaves its normals to the
/// contouring (the default [`HermiteGrid::normal`]: a tri-dexel's), the same mesh without the
/// grid's memory at the peak.
pub fn dual_contour_projected_owned<G, P>(
    grid: G,
    options: &ContourOptions,
    project: P,
) -> (TriMesh, ContourStats)
where
    G: HermiteGrid,
    P: Fn(Vec3, Vec3) -> Option<Vec3> + Sync,
{
    let Some((lattice, store)) = lines_of(&grid) else {
        return (TriMesh::new(), ContourStats::default());
    };
    drop(grid);
    finish(store, &LinesRead(lattice), options, Some(&project))
}

/// The grid's lattice and its lines read into a store; `None` for a lattice with no mesh.
fn lines_of<G: HermiteGrid + ?Sized>(grid: &G) -> Option<(Lattice, lines::Store)> {
    let lattice = grid.lattice();
    lattice
        .is_valid()
        .then(|| (lattice, lines::Store::build(grid, lattice)))
}

/// What the extraction sees of a grid whose lines are in the store and which has been
/// dropped: its lattice, and no normals.
struct LinesRead(Lattice);

impl HermiteGrid for LinesRead {
    fn lattice(&self) -> Lattice {
        self.0
    }

    fn line_spans(&self, _axis: usize, _u: usize, _v: usize, _out: &mut Vec<Span>) {}
}

pub(crate) type Projection<'a> = &'a (dyn Fn(Vec3, Vec3) -> Option<Vec3> + Sync);

fn contour<G: HermiteGrid + ?Sized>(
    grid: &G,
    options: &ContourOptions,
    project: Option<Projection<'_>>,
) -> (TriMesh, ContourStats) {
    let Some((_, store)) = lines_of(grid) else {
        return (TriMesh::new(), ContourStats::default());
    };
    finish(store, grid, options, project)
}

/// The extraction from the lines in `store` (normals asked of `grid` first), the projection
/// and the `f32` repair.
fn finish<G: HermiteGrid + ?Sized>(
    store: lines::Store,
    grid: &G,
    options: &ContourOptions,
    project: Option<Projection<'_>>,
) -> (TriMesh, ContourStats) {
    let (mut mesh, mut stats) = extract::extract(store, grid, options, project);
    // Cells whose vertices are clamped to a shared corner or edge can place two vertices at one
    // point, or three on a line: what a file stores must stay a 2-manifold without them.
    mesh.repair_degenerate_f32();
    stats.vertices = mesh.vertices.len();
    stats.triangles = mesh.triangles.len();
    (mesh, stats)
}
