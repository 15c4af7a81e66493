//! The tri-dexel stock: three families of parallel rays (along X, Y and Z) on a grid, each ray
//! holding its material intervals; construction from simple shapes, volume, statistics and the
//! localised, parallel subtraction of swept volumes.

use crate::dexel::{
    dexel_length, overlaps, subtract, subtract_with, Dexel, DexelTags, EndTags, Interval, MoveTag,
};
use crate::error::StockError;
use rayon::prelude::*;
use smallvec::SmallVec;
use std::sync::OnceLock;
use swarf_geom::math::{greater, lesser, Vec3, MACHINE_RANGE_MM};
use swarf_geom::Aabb;
use swarf_sweep::swept::{DexelRays, Scratch};
use swarf_sweep::{
    DexelKernel, Front, FrontBlock, InstanceSet, KernelTask, KeyBound, PlanarMember, Progress,
    SweepShape, SweptConvex, ToolShape,
};

/// Side of the square tiles of rays (tiles are stored contiguously and carry a conservative
/// bound of their material along the ray, so whole tiles are skipped without touching rays).
/// Tuned on the finishing bench (2,000 moves, one thread, both passes): 8 / 9 / 10 / 11 / 12 /
/// 16 rays ran 6.08 / 6.02 / 5.97 / 6.02 / 6.03 / 6.15 G instructions — a tile's set-up
/// (its reach, the front's half-plane, the separating planes) against the rays a coarser tile
/// lets through — and 10 was also the quickest in alternate timed runs.
pub const TILE: usize = 10;
pub(crate) const TILE_RAYS: usize = TILE * TILE;

/// The most rays a stock may have (about 40 bytes each before any material).
pub const MAX_RAYS: u64 = 60_000_000;

/// The grid: cells of size `h[k]` (≤ the requested resolution, chosen so that an integer
/// number of cells spans the stock's bounding box exactly) from `min`; rays pass through cell
/// centres.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Grid {
    /// Lower corner of the gridded box (the stock's bounding box), mm.
    pub min: Vec3,
    /// Upper corner, mm.
    pub max: Vec3,
    /// Number of cells along X, Y, Z.
    pub n: [usize; 3],
    /// Cell size along X, Y, Z, mm.
    pub h: [f64; 3],
}

impl Grid {
    /// The grid over `bounds` with cells no larger than `h`.
    pub fn new(bounds: Aabb, h: f64) -> Result<Grid, StockError> {
        if !(h.is_finite() && h > 0.0) {
            return Err(StockError::BadResolution(h));
        }
        let size = bounds.size();
        let (lo, hi) = (bounds.min.to_array(), bounds.max.to_array());
        if !(size.min_element() > 0.0 && size.is_finite() && bounds.min.is_finite()) {
            return Err(StockError::BadDimensions(format!(
                "the box from {lo:?} to {hi:?} mm is empty or not finite"
            )));
        }
        let reach = bounds.min.abs().max(bounds.max.abs()).max_element();
        if reach > MACHINE_RANGE_MM {
            return Err(StockError::BadDimensions(format!(
                "the box from {lo:?} to {hi:?} mm reaches {reach:e} mm from the origin, beyond \
                 the machine range of {MACHINE_RANGE_MM:e} mm"
            )));
        }
        // Counted in f64 before anything is converted or allocated: no count can wrap.
        let n = [0, 1, 2].map(|k| ((size[k] / h) * (1.0 - 1e-12)).ceil().max(1.0));
        let rays = n[1] * n[2] + n[2] * n[0] + n[0] * n[1];
        if rays > MAX_RAYS as f64 {
            return Err(StockError::TooManyRays {
                h,
                size: format!("{} x {} x {}", size.x, size.y, size.z),
                rays,
                limit: MAX_RAYS,
            });
        }
        let n = n.map(|c| c as usize);
        let hk = [0, 1, 2].map(|k| size[k] / n[k] as f64);
        Ok(Grid {
            min: bounds.min,
            max: bounds.max,
            n,
            h: hk,
        })
    }

    /// The grid of `n` cubic cells of side `h` from `min` (rays through `min + (i + ½)·h`): for
    /// sampling on a lattice chosen by the caller (the envelope's, centred on what it covers).
    ///
    /// # Errors
    /// As [`Grid::new`].
    pub fn cubic(min: Vec3, h: f64, n: [usize; 3]) -> Result<Grid, StockError> {
        let size = Vec3::new(n[0] as f64, n[1] as f64, n[2] as f64) * h;
        let mut g = Grid::new(Aabb::new(min, min + size), h)?;
        g.n = n.map(|c| c.max(1));
        g.h = [h; 3];
        Ok(g)
    }

    /// Coordinate of the centre of cell `i` along axis `k`.
    #[inline]
    pub fn center(&self, k: usize, i: usize) -> f64 {
        self.min[k] + (i as f64 + 0.5) * self.h[k]
    }

    /// Indices of the cell centres along axis `k` within `[a, b]`, if any.
    pub(crate) fn centers_in(&self, k: usize, a: f64, b: f64) -> Option<(usize, usize)> {
        let lo = ((a - self.min[k]) / self.h[k] - 0.5).ceil().max(0.0);
        let hi = ((b - self.min[k]) / self.h[k] - 0.5).floor();
        let hi = hi.min(self.n[k] as f64 - 1.0);
        (lo <= hi).then_some((lo as usize, hi as usize))
    }
}

/// The rays along one axis.
#[derive(Clone, Debug)]
pub struct DexelFamily {
    /// Ray direction: 0 = X, 1 = Y, 2 = Z.
    pub(crate) axis: usize,
    /// Rays along the first cross axis `(axis+1) % 3` and the second `(axis+2) % 3`.
    pub(crate) nu: usize,
    pub(crate) nv: usize,
    /// Tiles along u.
    pub(crate) ntu: usize,
    /// A ray's index in `rays` is `at_u[i] + at_v[j]`: the tile-major layout's two halves,
    /// tabled (a lookup by a point — the engagement's millions a location — otherwise divides
    /// by `TILE` four times).
    at_u: Box<[u32]>,
    at_v: Box<[u32]>,
    /// Tile-major storage: tile `(ti, tj)` holds rays `(tj·ntu + ti)·TILE² ..`, row-major inside.
    pub(crate) rays: Vec<Dexel>,
    /// Per tile, where its material lies along the rays: always true, exact unless `stale`.
    /// A tile a cut changed keeps its older bound (larger, still true) until a later run finds
    /// nothing to change in it, in this call or a later one ([`TriDexel::refresh_stale_bounds`]
    /// makes them all exact): a caller that cuts one short move per call (the engagement's
    /// locations) would otherwise pay for re-reading every tile each move changed, each move.
    pub(crate) bounds: Vec<TileBound>,
    /// Per tile, whether a cut changed it since its bound was last made exact.
    pub(crate) stale: Vec<bool>,
    /// The bins of [`TileBound::bins`] along this family's rays.
    pub(crate) bins: Bins,
    /// The provenance of every ray's intervals, indexed like `rays` (empty when the stock
    /// does not track provenance).
    pub(crate) tags: Vec<DexelTags>,
}

/// Where a tile's material lies along its rays: `[lo, hi]` spans it, and bit `b` of `bins` is
/// set when some of it lies in bin `b` of the family's 64 equal bins ([`Bins`]). The bins tell a
/// tile whose rays hold material only near their two ends (slivers a finishing pass leaves at
/// the stock's edges) from one with material in the middle, which `[lo, hi]` cannot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TileBound {
    pub(crate) lo: f64,
    pub(crate) hi: f64,
    pub(crate) bins: u64,
}

const EMPTY_BOUND: TileBound = TileBound {
    lo: f64::INFINITY,
    hi: f64::NEG_INFINITY,
    bins: 0,
};

impl TileBound {
    /// Adds material `[lo, hi]`.
    #[inline]
    pub(crate) fn add(&mut self, lo: f64, hi: f64, bins: &Bins) {
        self.lo = lesser(lo, self.lo);
        self.hi = greater(hi, self.hi);
        self.bins |= bins.mask(lo, hi);
    }

    /// Whether the tile may hold material inside the open range `(lo, hi)`.
    #[inline]
    pub(crate) fn meets(&self, lo: f64, hi: f64, bins: &Bins) -> bool {
        self.meets_mask(lo, hi, bins.mask(lo, hi))
    }

    /// [`TileBound::meets`] with the range's bins `mask` (`Bins::mask(lo, hi)`) made once for
    /// many tiles.
    #[inline(always)]
    pub(crate) fn meets_mask(&self, lo: f64, hi: f64, mask: u64) -> bool {
        self.lo < hi && self.hi > lo && self.bins & mask != 0
    }
}

/// 64 equal bins over a family's extent along its rays (coordinates beyond it fall in the end
/// bins).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Bins {
    origin: f64,
    scale: f64,
}

impl Bins {
    fn new(grid: &Grid, k: usize) -> Bins {
        let extent = grid.n[k] as f64 * grid.h[k];
        Bins {
            origin: grid.min[k],
            scale: 64.0 / extent,
        }
    }

    #[inline]
    fn bin(&self, t: f64) -> u32 {
        // NaN (never a stored end) lands in bin 0, as the clamp's lower end would.
        ((t - self.origin) * self.scale).clamp(0.0, 63.0) as u32
    }

    /// The bins that `[lo, hi]` touches.
    #[inline]
    pub(crate) fn mask(&self, lo: f64, hi: f64) -> u64 {
        let (a, b) = (self.bin(lo), self.bin(hi));
        if a > b {
            return 0;
        }
        (u64::MAX >> (63 - b)) & (u64::MAX << a)
    }
}

impl DexelFamily {
    fn new(axis: usize, grid: &Grid) -> Self {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        let (nu, nv) = (grid.n[u], grid.n[v]);
        let (ntu, ntv) = (nu.div_ceil(TILE), nv.div_ceil(TILE));
        // (Fits: `MAX_RAYS` and the tiles' padding stay far below 2³².)
        let at = |i: usize, stride: usize, step: usize| {
            let at = (i / TILE) * stride + (i % TILE) * step;
            debug_assert!(u32::try_from(at).is_ok(), "a ray index beyond u32");
            at as u32
        };
        Self {
            axis,
            nu,
            nv,
            ntu,
            at_u: (0..nu).map(|i| at(i, TILE_RAYS, 1)).collect(),
            at_v: (0..nv).map(|j| at(j, ntu * TILE_RAYS, TILE)).collect(),
            // Made, not cloned: `vec![Dexel::new(); n]` clones each through `SmallVec`'s
            // `extend`, ≈ 75 instructions a ray: more than half of building a box stock.
            rays: std::iter::repeat_with(Dexel::new)
                .take(ntu * ntv * TILE_RAYS)
                .collect(),
            bounds: vec![EMPTY_BOUND; ntu * ntv],
            stale: vec![false; ntu * ntv],
            bins: Bins::new(grid, axis),
            tags: Vec::new(),
        }
    }

    /// True when some ray `(i, j)`, `i ∈ is`, `j ∈ js`, holds material inside the open range
    /// `(lo, hi)` along the rays; tiles whose bound rules it out are not looked into.
    pub(crate) fn material_in(
        &self,
        (i0, i1): (usize, usize),
        (j0, j1): (usize, usize),
        (lo, hi): (f64, f64),
    ) -> bool {
        (j0 / TILE..=j1 / TILE).any(|tj| {
            (i0 / TILE..=i1 / TILE).any(|ti| {
                if !self.bounds[tj * self.ntu + ti].meets(lo, hi, &self.bins) {
                    return false;
                }
                let (ja, jb) = (j0.max(tj * TILE), j1.min(tj * TILE + TILE - 1));
                let (ia, ib) = (i0.max(ti * TILE), i1.min(ti * TILE + TILE - 1));
                (ja..=jb).any(|j| {
                    (ia..=ib).any(|i| {
                        self.ray(i, j)
                            .iter()
                            .any(|iv| iv.enter < hi && iv.exit > lo)
                    })
                })
            })
        })
    }

    #[inline]
    fn index(&self, i: usize, j: usize) -> usize {
        (self.at_u[i] + self.at_v[j]) as usize
    }

    /// The number of tiles along the two cross axes.
    pub(crate) fn tile_dims(&self) -> (usize, usize) {
        (self.ntu, self.bounds.len() / self.ntu)
    }

    /// The highest material end among tile `(ti, tj)`'s rays, or above it (the tile's bound;
    /// −∞ when they hold none).
    #[inline]
    pub(crate) fn tile_hi(&self, ti: usize, tj: usize) -> f64 {
        debug_assert!(ti < self.ntu, "tile {ti} of {}", self.ntu);
        self.bounds[tj * self.ntu + ti].hi
    }

    /// Ray direction: 0 = X, 1 = Y, 2 = Z.
    pub fn axis(&self) -> usize {
        self.axis
    }

    /// Number of rays (along the two cross axes).
    #[inline]
    pub fn dims(&self) -> (usize, usize) {
        (self.nu, self.nv)
    }

    /// The intervals of ray `(i, j)` (indices along the cross axes `(axis+1)%3`, `(axis+2)%3`).
    #[inline]
    pub fn ray(&self, i: usize, j: usize) -> &[Interval] {
        &self.rays[self.index(i, j)]
    }

    /// The four rays `(i, j)`, `(i + 1, j)`, `(i, j + 1)`, `(i + 1, j + 1)` around a point
    /// (`i + 1`, `j + 1` within [`DexelFamily::dims`]): four table reads, across tile borders
    /// as within a tile.
    #[inline]
    pub fn ray_quad(&self, i: usize, j: usize) -> [&[Interval]; 4] {
        let (u0, u1) = (self.at_u[i], self.at_u[i + 1]);
        let (v0, v1) = (self.at_v[j], self.at_v[j + 1]);
        let ray = |a: u32, b: u32| &self.rays[(a + b) as usize][..];
        [ray(u0, v0), ray(u1, v0), ray(u0, v1), ray(u1, v1)]
    }

    /// The provenance of ray `(i, j)`'s intervals (one [`EndTags`] per interval of
    /// [`DexelFamily::ray`], in the same order), or `None` when the stock does not track
    /// provenance ([`TriDexel::track_provenance`]).
    pub fn ray_tags(&self, i: usize, j: usize) -> Option<&[EndTags]> {
        self.tags.get(self.index(i, j)).map(|t| &t[..])
    }

    /// Total material length over all rays, mm.
    pub fn total_length(&self) -> f64 {
        self.rays.iter().map(|d| dexel_length(d)).sum()
    }

    /// Number of intervals.
    pub fn interval_count(&self) -> usize {
        self.rays.iter().map(|d| d.len()).sum()
    }

    fn heap_bytes(&self) -> usize {
        self.rays.capacity() * std::mem::size_of::<Dexel>()
            + self
                .rays
                .iter()
                .filter(|d| d.spilled())
                .map(|d| d.capacity() * std::mem::size_of::<Interval>())
                .sum::<usize>()
            + self.bounds.capacity() * std::mem::size_of::<TileBound>()
            + self.stale.capacity()
            + (self.at_u.len() + self.at_v.len()) * std::mem::size_of::<u32>()
            + self.tags.capacity() * std::mem::size_of::<DexelTags>()
            + self
                .tags
                .iter()
                .filter(|t| t.spilled())
                .map(|t| t.capacity() * std::mem::size_of::<EndTags>())
                .sum::<usize>()
    }

    fn refresh_bounds(&mut self) {
        for (b, rays) in self.bounds.iter_mut().zip(self.rays.chunks(TILE_RAYS)) {
            *b = tile_bound(rays, &self.bins);
        }
        self.stale.fill(false);
    }

    /// Makes the bounds of the tiles changed since their last refresh exact.
    fn refresh_stale(&mut self) {
        let tiles = self.bounds.iter_mut().zip(self.rays.chunks(TILE_RAYS));
        for ((b, rays), stale) in tiles.zip(&mut self.stale).filter(|(_, s)| **s) {
            *b = tile_bound(rays, &self.bins);
            *stale = false;
        }
    }
}

fn tile_bound(rays: &[Dexel], bins: &Bins) -> TileBound {
    // A ray's intervals are sorted and disjoint: its material spans from its first entry to
    // its last exit, and only the bins need every interval.
    let (mut lo, mut hi, mut mask) = (f64::INFINITY, f64::NEG_INFINITY, 0u64);
    for d in rays {
        let ivs: &[Interval] = d;
        if let (Some(first), Some(last)) = (ivs.first(), ivs.last()) {
            if first.enter < lo {
                lo = first.enter;
            }
            if last.exit > hi {
                hi = last.exit;
            }
            for iv in ivs {
                mask |= bins.mask(iv.enter, iv.exit);
            }
        }
    }
    TileBound { lo, hi, bins: mask }
}

/// Counts and lengths from one subtraction.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct CutStats {
    /// Material length removed per family (X, Y, Z rays), mm.
    pub removed_length: [f64; 3],
    /// The most material removed from one ray, per family, mm.
    pub longest_removal: [f64; 3],
    /// Rays whose exact interval was computed (after the material-first rejection). On the
    /// rays normal to the plane of a run of ball-end moves, cut together
    /// ([`swarf_sweep::PlanarMember`]), a move counts the rays whose chord it computed: those
    /// the moves before it in the run had not already cut wider than it could.
    pub rays_tested: u64,
    /// Rays whose intervals changed.
    pub updates: u64,
    /// Rays visited per family (X, Y, Z): in a tile that survived the tile test, with material
    /// in the sweep's bounding range (in a planar run, as [`CutStats::rays_tested`]).
    pub visited_per_family: [u64; 3],
    /// `rays_tested` per family (X, Y, Z).
    pub tested_per_family: [u64; 3],
    /// `updates` per family (X, Y, Z).
    pub updates_per_family: [u64; 3],
}

impl CutStats {
    /// The sum of two.
    pub fn merged(mut self, o: CutStats) -> CutStats {
        for k in 0..3 {
            self.removed_length[k] += o.removed_length[k];
            self.longest_removal[k] = self.longest_removal[k].max(o.longest_removal[k]);
        }
        self.rays_tested += o.rays_tested;
        self.updates += o.updates;
        for k in 0..3 {
            self.tested_per_family[k] += o.tested_per_family[k];
            self.visited_per_family[k] += o.visited_per_family[k];
            self.updates_per_family[k] += o.updates_per_family[k];
        }
        self
    }

    /// True when any family lost more than `eps` mm of material.
    pub fn removed_any(&self, eps: f64) -> bool {
        self.removed_length.iter().any(|&l| l > eps)
    }
}

/// What one move (or straight sub-move) removed.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SegmentCut {
    /// By the cutting part.
    pub cutting: CutStats,
    /// By the shank and holder (non-zero means a holder collision).
    pub non_cutting: CutStats,
    /// Straight fixed-axis pieces the cutting part was cut as: 1 for a line, the chords of an
    /// arc, the constant-axis sub-moves of a 5-axis move ([`swarf_sweep::five_axis`]).
    pub sub_moves: u64,
    /// Largest bound on the distance between the volume cut and the true swept volume of a
    /// 5-axis move, mm (0 for other moves: exact, or arcs within the chordal tolerance).
    pub error_bound_mm: f64,
}

impl SegmentCut {
    pub(crate) fn add(&mut self, o: SegmentCut) {
        self.cutting = self.cutting.merged(o.cutting);
        self.non_cutting = self.non_cutting.merged(o.non_cutting);
        self.sub_moves += o.sub_moves;
        self.error_bound_mm = self.error_bound_mm.max(o.error_bound_mm);
    }
}

/// Size figures of a stock.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct StockStats {
    /// Rays in the three families.
    pub rays: u64,
    /// Intervals in the three families.
    pub intervals: u64,
    /// Bytes held by the dexels (inline slots, spilled intervals, tile bounds).
    pub bytes: u64,
    /// `bytes / intervals`.
    pub bytes_per_interval: f64,
}

/// The tri-dexel stock. See the crate documentation for the model and conventions.
#[derive(Clone, Debug)]
pub struct TriDexel {
    grid: Grid,
    pub(crate) families: [DexelFamily; 3],
    /// The tag the next cut gives the ends it makes ([`TriDexel::set_move_tag`]).
    tag: MoveTag,
    /// The last tool instance a move was cut with (a linear move's end, or a 5-axis move's
    /// last instance, `cut::five_axis`), while nothing has put material back: the next move,
    /// starting there, need not cut it again.
    pub(crate) last_instance: Option<crate::cut::CutInstance>,
    /// Query every ray a move may reach, without the front test ([`TriDexel::set_exhaustive`]).
    exhaustive: bool,
}

impl TriDexel {
    /// An empty stock (no material) on the grid over `bounds` with resolution `h` (mm).
    pub fn empty(bounds: Aabb, h: f64) -> Result<Self, StockError> {
        Ok(Self::on_grid(Grid::new(bounds, h)?))
    }

    /// An empty stock (no material) on `grid`.
    pub fn on_grid(grid: Grid) -> Self {
        Self {
            families: [0, 1, 2].map(|k| DexelFamily::new(k, &grid)),
            grid,
            tag: 0,
            last_instance: None,
            exhaustive: false,
        }
    }

    /// A stock whose ray along axis `k` at cross coordinates `(u, v)` (cell centres; `u` along
    /// `(k+1)%3`, `v` along `(k+2)%3`) holds the intervals `fill` writes (sorted, disjoint).
    pub fn from_fn<F>(bounds: Aabb, h: f64, fill: F) -> Result<Self, StockError>
    where
        F: Fn(usize, f64, f64, &mut Dexel) + Sync,
    {
        let mut s = Self::empty(bounds, h)?;
        let grid = s.grid;
        for fam in &mut s.families {
            let k = fam.axis;
            let (u, v) = ((k + 1) % 3, (k + 2) % 3);
            let (nu, nv, ntu) = (fam.nu, fam.nv, fam.ntu);
            fam.rays
                .par_chunks_mut(TILE_RAYS)
                .enumerate()
                .for_each(|(t, tile)| {
                    let (ti, tj) = (t % ntu, t / ntu);
                    for (r, d) in tile.iter_mut().enumerate() {
                        let (i, j) = (ti * TILE + r % TILE, tj * TILE + r / TILE);
                        if i < nu && j < nv {
                            fill(k, grid.center(u, i), grid.center(v, j), d);
                            d.retain(|iv| iv.exit - iv.enter >= crate::dexel::MIN_INTERVAL_MM);
                        }
                    }
                });
            fam.refresh_bounds();
        }
        Ok(s)
    }

    /// A box from `min` to `max`, resolution `h`.
    pub fn from_box(min: Vec3, max: Vec3, h: f64) -> Result<Self, StockError> {
        if !(min.is_finite() && max.is_finite()) {
            // Checked here: ordering the corners would drop a NaN.
            return Err(StockError::BadDimensions(format!(
                "the box from {:?} to {:?} mm is not finite",
                min.to_array(),
                max.to_array()
            )));
        }
        let b = Aabb::new(min, max);
        Self::from_fn(b, h, |k, _, _, d| {
            d.push(Interval {
                enter: b.min[k],
                exit: b.max[k],
            })
        })
    }

    /// A cylinder with axis +Z: centre `(cx, cy)`, bottom `z0`, radius `r`, height `height`.
    pub fn from_cylinder(
        cx: f64,
        cy: f64,
        z0: f64,
        r: f64,
        height: f64,
        h: f64,
    ) -> Result<Self, StockError> {
        if !(r > 0.0 && height > 0.0 && r.is_finite() && height.is_finite()) {
            return Err(StockError::BadDimensions(format!(
                "cylinder radius {r} and height {height} must be positive"
            )));
        }
        let b = Aabb::new(
            Vec3::new(cx - r, cy - r, z0),
            Vec3::new(cx + r, cy + r, z0 + height),
        );
        let z1 = z0 + height;
        Self::from_fn(b, h, |k, u, v, d| {
            // (u, v) are (y, z) for X rays, (z, x) for Y rays, (x, y) for Z rays.
            let (a, c, ac, cc) = match k {
                0 => (u, v, cy, 0.0),
                1 => (v, u, cx, 0.0),
                _ => (u, v, cx, cy),
            };
            if k == 2 {
                if (a - ac).powi(2) + (c - cc).powi(2) <= r * r {
                    d.push(Interval {
                        enter: z0,
                        exit: z1,
                    });
                }
            } else if (z0..=z1).contains(&c) {
                let off = r * r - (a - ac).powi(2);
                if off > 0.0 {
                    let half = off.sqrt();
                    let centre = if k == 0 { cx } else { cy };
                    d.push(Interval {
                        enter: centre - half,
                        exit: centre + half,
                    });
                }
            }
        })
    }

    /// From now on, keep for every interval end the tag of the move that last cut it (one
    /// [`MoveTag`] per end, beside the intervals; ends that exist now are [`crate::UNCUT`]).
    /// Costs 8 bytes per interval and 24 per ray; a stock that does not track provenance
    /// pays nothing. Idempotent.
    pub fn track_provenance(&mut self) {
        for fam in &mut self.families {
            if fam.tags.len() != fam.rays.len() {
                fam.tags = fam
                    .rays
                    .iter()
                    .map(|d| d.iter().map(|_| EndTags::UNCUT).collect())
                    .collect();
            }
        }
    }

    /// True when the stock keeps the provenance of its interval ends.
    pub fn tracks_provenance(&self) -> bool {
        !self.families[0].tags.is_empty() || self.families[0].rays.is_empty()
    }

    /// With `on`, every move queries every ray it may reach instead of only those the front
    /// of an already cut start instance can reach (`swarf_sweep::Front`), and moves in one
    /// plane are cut one by one, not as runs (`swarf_sweep::PlanarMember`): the stock ends the
    /// same (to rounding), slower. The reference for checking both, and for timing them.
    pub fn set_exhaustive(&mut self, on: bool) {
        self.exhaustive = on;
    }

    /// Sets the tag of the cuts that follow: the ends they make carry it (when provenance is
    /// tracked) and [`Removal`]s report it. [`TriDexel::cut_linear_batch`] gives its `n`-th move
    /// `tag + n`; every other cut (a move's chords, its 5-axis sub-moves, shank and holder)
    /// carries `tag` itself. [`crate::simulate()`] sets the move's index in the program. Default 0.
    pub fn set_move_tag(&mut self, tag: MoveTag) {
        self.tag = tag;
    }

    /// The tag of the cuts that follow.
    pub fn move_tag(&self) -> MoveTag {
        self.tag
    }

    /// The grid.
    #[inline]
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// The ray family along axis `k` (0 = X, 1 = Y, 2 = Z).
    #[inline]
    pub fn family(&self, k: usize) -> &DexelFamily {
        &self.families[k]
    }

    /// Cross-section area a ray of family `k` stands for, mm².
    pub fn ray_area(&self, k: usize) -> f64 {
        self.grid.h[(k + 1) % 3] * self.grid.h[(k + 2) % 3]
    }

    /// Material volume from the Z rays (Σ lengths × cell area), mm³.
    pub fn volume(&self) -> f64 {
        self.volume_from(2)
    }

    /// Material volume estimated from family `k`, mm³ (for cross-checks: the three agree to
    /// the discretisation error).
    pub fn volume_from(&self, k: usize) -> f64 {
        // (+ 0: a sum of no lengths is −0, which a report printed as "-0.0".)
        self.families[k].total_length() * self.ray_area(k) + 0.0
    }

    /// The volume estimates from the X, Y and Z families.
    pub fn volumes(&self) -> [f64; 3] {
        [0, 1, 2].map(|k| self.volume_from(k))
    }

    /// Counts and memory.
    pub fn stats(&self) -> StockStats {
        let rays: u64 = self.families.iter().map(|f| (f.nu * f.nv) as u64).sum();
        let intervals: u64 = self
            .families
            .iter()
            .map(|f| f.interval_count() as u64)
            .sum();
        let bytes: u64 = self.families.iter().map(|f| f.heap_bytes() as u64).sum();
        StockStats {
            rays,
            intervals,
            bytes,
            bytes_per_interval: bytes as f64 / intervals.max(1) as f64,
        }
    }

    /// Makes every tile's bound exact again. Cuts leave the bounds of the tiles they changed
    /// as they were (larger than the material, never smaller) until a later cut visits the
    /// tile and changes nothing in it; the queries below are conservative either way, and
    /// tighter after this.
    pub fn refresh_stale_bounds(&mut self) {
        for fam in &mut self.families {
            fam.refresh_stale();
        }
    }

    /// A conservative range `[lowest, highest]` along family `k`'s rays of the material of the
    /// rays that cross `bbox` (from the tiles' bounds: it may be wider than the material, never
    /// narrower); `None` when those rays hold no material. Cost: one look per tile (`TILE` ×
    /// `TILE` rays).
    pub fn material_range(&self, k: usize, bbox: &Aabb) -> Option<(f64, f64)> {
        let (u, v) = ((k + 1) % 3, (k + 2) % 3);
        let fam = &self.families[k];
        let (i0, i1) = self.grid.centers_in(u, bbox.min[u], bbox.max[u])?;
        let (j0, j1) = self.grid.centers_in(v, bbox.min[v], bbox.max[v])?;
        let mut b = [f64::INFINITY, f64::NEG_INFINITY];
        for tj in j0 / TILE..=j1 / TILE {
            for ti in i0 / TILE..=i1 / TILE {
                let t = fam.bounds[tj * fam.ntu + ti];
                b[0] = b[0].min(t.lo);
                b[1] = b[1].max(t.hi);
            }
        }
        (b[0] <= b[1]).then_some((b[0], b[1]))
    }

    /// Whether some ray of family `k` whose centre lies in `bbox`'s cross section may hold
    /// material inside `bbox`'s open range along the rays, from the tiles' bounds: `false` is
    /// certain, `true` may not be. A few dozen instructions per tile the box meets.
    pub fn may_hold_material(&self, k: usize, bbox: &Aabb) -> bool {
        let (u, v) = ((k + 1) % 3, (k + 2) % 3);
        let g = &self.grid;
        // The rays whose centres `min + (i + ½)·h` may lie in `[a, b]` (a superset: the tiles
        // of a few rays more are looked at, never fewer).
        let span = |axis: usize, a: f64, b: f64| {
            let (lo, hi) = (
                (a - g.min[axis]) / g.h[axis] - 0.5,
                (b - g.min[axis]) / g.h[axis] + 0.5,
            );
            let last = g.n[axis] as f64 - 1.0;
            (hi >= 0.0 && lo <= last).then(|| (lo.max(0.0) as usize, hi.min(last) as usize))
        };
        let (Some((i0, i1)), Some((j0, j1))) = (
            span(u, bbox.min[u], bbox.max[u]),
            span(v, bbox.min[v], bbox.max[v]),
        ) else {
            return false;
        };
        let fam = &self.families[k];
        let (lo, hi) = (bbox.min[k], bbox.max[k]);
        (j0 / TILE..=j1 / TILE).any(|tj| {
            fam.bounds[tj * fam.ntu + i0 / TILE..=tj * fam.ntu + i1 / TILE]
                .iter()
                .any(|b| b.meets(lo, hi, &fam.bins))
        })
    }

    /// Removes the union of the swept volumes `parts` (all sharing one move) from every ray
    /// that crosses their bounding box; returns what was removed.
    pub fn subtract_swept(&mut self, parts: &[SweptConvex<'_>]) -> CutStats {
        self.subtract_moves(&[[parts]])[0][0]
    }

    /// [`TriDexel::subtract_moves`], all moves under the current tag (the pieces of one move).
    pub(crate) fn subtract_pieces<const G: usize>(
        &mut self,
        moves: &[[&[SweptConvex<'_>]; G]],
        visitor: Option<&dyn RemovalVisitor>,
    ) -> Vec<[CutStats; G]> {
        self.subtract_tagged(moves, 0, visitor, &[])
    }

    /// Removes, move after move, the swept volumes of a sequence of moves, each given as `G`
    /// groups of parts (e.g. the cutting part and the shank), and returns what each group of
    /// each move removed. The stock ends as if the moves were subtracted one by one in order,
    /// and each move's figures are the ones it would have had then.
    ///
    /// Parallel without a barrier per move: each tile row of each family that a move reaches
    /// is one unit of work, taken by whichever worker is free, that runs the whole sequence
    /// over its row — every ray still sees the moves in order, and the row's tiles stay in
    /// cache from one move to the next. The figures are summed in row order (deterministic).
    pub fn subtract_moves<const G: usize>(
        &mut self,
        moves: &[[&[SweptConvex<'_>]; G]],
    ) -> Vec<[CutStats; G]> {
        self.subtract_tagged(moves, 1, None, &[])
    }

    /// [`TriDexel::subtract_moves`], telling `visitor` every piece of material removed (see
    /// [`RemovalVisitor`]); the stock and the figures are the same as without it.
    pub fn subtract_moves_visited<const G: usize>(
        &mut self,
        moves: &[[&[SweptConvex<'_>]; G]],
        visitor: &dyn RemovalVisitor,
    ) -> Vec<[CutStats; G]> {
        self.subtract_tagged(moves, 1, Some(visitor), &[])
    }

    /// The subtraction; move `m` of `moves` carries the tag `self.tag + step·m`. A move
    /// with `chained[m]` true (its start instance has already been cut: it starts where the
    /// move before it ended, with the same parts and axis) queries only the rays that can meet
    /// that instance's front swept along the move (`swarf_sweep::Front`); the others it
    /// cannot change. A missing entry is false.
    fn subtract_tagged<const G: usize>(
        &mut self,
        moves: &[[&[SweptConvex<'_>]; G]],
        step: MoveTag,
        visitor: Option<&dyn RemovalVisitor>,
        chained: &[bool],
    ) -> Vec<[CutStats; G]> {
        let grid = self.grid;
        let base = self.tag;
        let exhaustive = self.exhaustive;
        let tracked = self.tracks_provenance();
        let plans: Vec<[Option<Plan>; G]> = par_map(moves, |m, groups| {
            let chained = !exhaustive && chained.get(m).copied().unwrap_or(false);
            groups.map(|parts| Plan::new(&grid, parts, chained))
        });
        // Tiles the sequence may touch: small work stays on the calling thread.
        let tiles: usize = plans.iter().flatten().flatten().map(Plan::tiles).sum();
        let bins = [0, 1, 2].map(|k| self.families[k].bins);
        // What each part's queries along each family share, made once per move, group and
        // family, by the first row that cuts them one by one (a finishing move's rays normal to
        // and along its plane are mostly cut in planar runs, and never need them).
        let shared: Vec<[[LazyRays; 3]; G]> = moves
            .iter()
            .map(|_| std::array::from_fn(|_| std::array::from_fn(|_| OnceLock::new())))
            .collect();
        let shared_rays = |m: usize, g: usize, k: usize| -> &SmallVec<[DexelRays; 2]> {
            shared[m][g][k].get_or_init(|| moves[m][g].iter().map(|p| p.dexel_rays(k)).collect())
        };
        // Per family and move, the tile rows some group of the move reaches (none: an empty
        // range), side by side: a row's loop passes over the moves that miss it on these alone.
        let row_spans: [Vec<(usize, usize)>; 3] = std::array::from_fn(|k| {
            plans
                .iter()
                .map(|p| {
                    hull(
                        p.iter()
                            .flatten()
                            .filter_map(|p| p.fam[k])
                            .map(|r| (r.j.0 / TILE, r.j.1 / TILE)),
                    )
                })
                .collect()
        });
        // The units of work: the tile rows of each family that some move reaches.
        let mut units: Vec<(usize, usize, Row<'_>)> = Vec::new();
        for fam in self.families.iter_mut() {
            let k = fam.axis;
            let (lo, hi) = hull(row_spans[k].iter().copied());
            if lo > hi {
                continue;
            }
            let per_row = fam.ntu * TILE_RAYS;
            let mut tag_rows = fam.tags.chunks_mut(per_row);
            let mut stale_rows = fam.stale.chunks_mut(fam.ntu);
            for (tj, (r, b)) in fam
                .rays
                .chunks_mut(per_row)
                .zip(fam.bounds.chunks_mut(fam.ntu))
                .enumerate()
            {
                let tags = tag_rows.next().unwrap_or_default();
                let stale = stale_rows.next().unwrap_or_default();
                if (lo..=hi).contains(&tj) {
                    let row = Row {
                        rays: r,
                        bounds: b,
                        stale,
                        tags,
                    };
                    units.push((k, tj, row));
                }
            }
        }
        // Moves of a ball end in a plane normal to a family, as that family sees them
        // (`PlanarMember`): their chords nest, and a run of them in one plane is cut together on
        // a row (`cut_planar`); the family along the plane's other axis, parallel to the motion,
        // cuts such a run together too (`cut_along`). Only for a plain cut (no provenance, no
        // visitor: their records are per move and ray), with the front test on (`exhaustive`
        // keeps the move-by-move reference), and where the whole stock lies below the tool's
        // top (where the chords are exact).
        let plain = visitor.is_none() && !tracked;
        let planar: Vec<[Option<PlanarMember>; 3]> = if plain && !exhaustive {
            par_map(moves, |_, groups| {
                std::array::from_fn(|k| match groups.first() {
                    Some([p]) => p.planar(k).filter(|m| m.top() >= grid.max[m.tool_axis()]),
                    _ => None,
                })
            })
        } else {
            Vec::new()
        };
        // Whether group `g` of move `m` reaches row `tj` of family `k`.
        let reaches = |m: usize, g: usize, k: usize, tj: usize| {
            plans[m][g]
                .as_ref()
                .and_then(|p| p.fam[k])
                .is_some_and(|r| r.j.0 / TILE <= tj && tj <= r.j.1 / TILE)
        };
        // Whether group `g` of move `m` may change row `tj` of family `k`: it reaches the row,
        // and its range along the rays meets the stock's.
        let touches = |m: usize, g: usize, k: usize, tj: usize| {
            reaches(m, g, k, tj)
                && plans[m][g]
                    .as_ref()
                    .and_then(|p| p.fam[k])
                    .is_some_and(|r| r.t.0 <= grid.max[k] && r.t.1 >= grid.min[k])
        };
        // Move `m`'s member as family `k`'s rays see it: in a plane normal to them, or (`along`)
        // in a plane parallel to them, the rays along its in-plane axis.
        let member = |m: usize, k: usize, along: bool| -> Option<PlanarMember> {
            let p = planar.get(m)?;
            if along {
                [(k + 1) % 3, (k + 2) % 3]
                    .into_iter()
                    .find_map(|n| p[n].filter(|q| q.in_plane_axis() == k))
            } else {
                p[k]
            }
        };
        // The end of the run of moves from `m` in one plane normal to family `k` (or, `along`,
        // one plane parallel to its rays), of which at least two reach row `tj` (the others
        // touch nothing there) and no other group may change it.
        let planar_run = |m: usize, k: usize, tj: usize, along: bool| -> Option<usize> {
            let first = member(m, k, along)?;
            let alone = |m: usize| (1..G).all(|g| !touches(m, g, k, tj));
            if !reaches(m, 0, k, tj) || !alone(m) {
                return None;
            }
            let (mut end, mut members) = (m + 1, 1);
            while end < moves.len() {
                match member(end, k, along) {
                    Some(p) if p.nests_with(&first) && alone(end) => {}
                    _ => break,
                }
                members += usize::from(reaches(end, 0, k, tj));
                end += 1;
            }
            (members >= 2).then_some(end)
        };
        // One tile row through the whole sequence: every ray sees the moves in order, and the
        // row's tiles stay in cache from one move to the next. Returns what each (move, group)
        // that reached the row removed from it.
        let run = |scratch: &mut Scratch, (k, tj, mut row): (usize, usize, Row<'_>)| {
            // Only what touched the row is kept (a finishing move reaches a row for a few
            // dozen moves of a batch; growing the list one push at a time cost 3 % of a pass).
            let mut out: Vec<(usize, usize, CutStats)> = Vec::with_capacity(moves.len().min(64));
            // The members of the row's planar runs, one run after another in one buffer (a
            // run's list made afresh was copied whole, a few kilobytes a run).
            let mut members: Vec<PlanarCut> = Vec::new();
            let spans = &row_spans[k];
            let mut m = 0;
            while m < moves.len() {
                // (A move that reaches no tile of the row has nothing to cut there, and no run
                // to start.)
                if !(spans[m].0 <= tj && tj <= spans[m].1) {
                    m += 1;
                    continue;
                }
                let run = [false, true]
                    .into_iter()
                    .find_map(|along| Some((planar_run(m, k, tj, along)?, along)));
                if let Some((end, along)) = run {
                    members.clear();
                    members.extend((m..end).filter(|&m| reaches(m, 0, k, tj)).filter_map(|m| {
                        Some(PlanarCut {
                            index: m,
                            member: member(m, k, along)?,
                            range: plans[m][0].as_ref()?.fam[k]?,
                            stats: CutStats::default(),
                        })
                    }));
                    if along {
                        cut_along(&grid, k, tj, &mut row, &bins[k], &mut members);
                    } else {
                        cut_planar(&grid, k, tj, &mut row, &bins[k], &mut members);
                    }
                    // A run counts a member's rays tested and changed in one field each (one
                    // increment where three moved together on every ray); the others follow.
                    for c in members.iter_mut() {
                        let st = &mut c.stats;
                        st.visited_per_family[k] = st.tested_per_family[k];
                        st.rays_tested = st.tested_per_family[k];
                        st.updates = st.updates_per_family[k];
                    }
                    out.extend(
                        members
                            .iter()
                            .filter(|c| c.stats != CutStats::default())
                            .map(|c| (c.index, 0, c.stats)),
                    );
                    m = end;
                    continue;
                }
                let (groups, plans) = (&moves[m], &plans[m]);
                m += 1;
                let m = m - 1;
                let tag = base
                    .saturating_add(step.saturating_mul(m as MoveTag))
                    .min(crate::dexel::UNCUT - 1);
                for (group, (parts, plan)) in groups.iter().zip(plans).enumerate() {
                    let Some(plan) = plan else { continue };
                    let Some(r) = plan.fam[k] else { continue };
                    if tj < r.j.0 / TILE || tj > r.j.1 / TILE {
                        continue;
                    }
                    let cut = TileCut {
                        grid: &grid,
                        k,
                        range: &r,
                        parts,
                        rays: shared_rays(m, group, k),
                        fronts: plan.fronts.as_deref(),
                        bins: &bins[k],
                        tag,
                        visitor: visitor.map(|v| (v, m, group)),
                    };
                    let mut st = CutStats::default();
                    let tiles = r.i.0 / TILE..r.i.1 / TILE + 1;
                    // Tiles without material in the move's range are left here, before the
                    // call (nearly half the tiles of a finishing move: above the material).
                    let mask = bins[k].mask(r.t.0, r.t.1);
                    for (ti, stale) in tiles.clone().zip(&mut row.stale[tiles]) {
                        if !row.bounds[ti].meets_mask(r.t.0, r.t.1, mask) {
                            continue;
                        }
                        let span = ti * TILE_RAYS..(ti + 1) * TILE_RAYS;
                        let tile = &mut row.rays[span.clone()];
                        let tags = row.tags.get_mut(span).unwrap_or_default();
                        let bound = (&mut row.bounds[ti], stale);
                        cut.run(ti, tj, tile, tags, bound, scratch, &mut st);
                    }
                    if st != CutStats::default() {
                        out.push((m, group, st));
                    }
                }
            }
            out
        };
        // Rows are taken by whichever worker is free (a move's rows differ in work), each row
        // a piece of its own: left to itself, rayon runs stretches of neighbouring rows as one
        // piece, and the last stretch kept one thread waiting (the finishing bench's two
        // threads were 1.71 cores busy, now 1.95). Each row starts with fresh scratch (the
        // separating planes kept from ray to ray) and the figures are summed in row order, so
        // none depends on who took what.
        let per_row: Vec<Vec<(usize, usize, CutStats)>> =
            if tiles < PARALLEL_MIN_TILES || rayon::current_num_threads() == 1 {
                units
                    .into_iter()
                    .map(|u| run(&mut Scratch::new(), u))
                    .collect()
            } else {
                units
                    .into_par_iter()
                    .with_max_len(1)
                    .map(|u| run(&mut Scratch::new(), u))
                    .collect()
            };
        let mut total = vec![[CutStats::default(); G]; moves.len()];
        for (m, g, st) in per_row.into_iter().flatten() {
            total[m][g] = total[m][g].merged(st);
        }
        total
    }
}

/// A straight move with a fixed tool axis: the tip from `tip0` to `tip1`, unit `axis`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct LinearMove {
    /// Tip at the start, workpiece frame, mm.
    pub tip0: Vec3,
    /// Tip at the end.
    pub tip1: Vec3,
    /// Tool axis (unit, from the tip towards the spindle).
    pub axis: Vec3,
}

impl LinearMove {
    /// The moves from each point of `tips` to the next, the tool along `axis`.
    pub fn chain(tips: &[Vec3], axis: Vec3) -> Vec<LinearMove> {
        tips.windows(2)
            .map(|w| LinearMove {
                tip0: w[0],
                tip1: w[1],
                axis,
            })
            .collect()
    }
}

/// Moves prepared and subtracted together by [`TriDexel::cut_linear_batch`] (bounds the
/// memory of the prepared sweeps; large enough that the per-call overhead vanishes).
const BATCH_MOVES: usize = 256;

impl TriDexel {
    /// Cuts a sequence of straight fixed-axis moves of one tool, in order, and returns what
    /// each removed (as [`TriDexel::cut_linear`] would, move by move), with the moves of each
    /// batch cut in parallel over disjoint rays (see [`TriDexel::subtract_moves`]).
    pub fn cut_linear_batch(&mut self, tool: &ToolShape, moves: &[LinearMove]) -> Vec<SegmentCut> {
        self.cut_linear_batch_with(tool, moves, None, 1)
    }

    /// [`TriDexel::cut_linear_batch`], telling `visitor` every piece of material removed
    /// ([`Removal::move_index`] is the index in `moves`; group 0 is the cutting part, 1 the
    /// shank and holder).
    pub fn cut_linear_batch_visited(
        &mut self,
        tool: &ToolShape,
        moves: &[LinearMove],
        visitor: &dyn RemovalVisitor,
    ) -> Vec<SegmentCut> {
        self.cut_linear_batch_with(tool, moves, Some(visitor), 1)
    }

    /// The chords of one arc or helix, in order, as [`TriDexel::cut_linear_batch`] cuts a run
    /// of moves — each a move of its own, as chord-by-chord [`TriDexel::cut_linear`] calls
    /// would cut them — but their interval ends all carrying the tag of the one move they make.
    pub(crate) fn cut_chords(
        &mut self,
        tool: &ToolShape,
        chords: &[LinearMove],
    ) -> Vec<SegmentCut> {
        self.cut_linear_batch_with(tool, chords, None, 0)
    }

    /// The batch; move `m` of `moves` carries the tag `self.tag + tag_step·m`.
    fn cut_linear_batch_with(
        &mut self,
        tool: &ToolShape,
        moves: &[LinearMove],
        visitor: Option<&dyn RemovalVisitor>,
        tag_step: MoveTag,
    ) -> Vec<SegmentCut> {
        let tag0 = self.tag;
        let mut out = Vec::with_capacity(moves.len());
        // A move starting where the tool last stood (the previous move's end, or the last
        // instance the stock was cut with) only needs the rays its front can reach.
        let groups = [tool.cutting(), tool.non_cutting()];
        let chained: Vec<bool> = moves
            .iter()
            .enumerate()
            .map(|(i, m)| match i {
                0 => self
                    .last_instance
                    .as_ref()
                    .is_some_and(|l| l.is(groups, m.tip0, m.axis)),
                _ => moves[i - 1].tip1 == m.tip0 && moves[i - 1].axis == m.axis,
            })
            .collect();
        for (chunk, chained) in moves.chunks(BATCH_MOVES).zip(chained.chunks(BATCH_MOVES)) {
            fn sweep<'s>(shape: &'s SweepShape, m: &LinearMove) -> SmallVec<[SweptConvex<'s>; 2]> {
                shape
                    .parts()
                    .iter()
                    .map(|p| SweptConvex::new(p, m.tip0, m.axis, m.tip1 - m.tip0))
                    .collect()
            }
            let prepared: Vec<[SmallVec<[SweptConvex<'_>; 2]>; 2]> = par_map(chunk, |_, m| {
                [sweep(tool.cutting(), m), sweep(tool.non_cutting(), m)]
            });
            let groups: Vec<[&[SweptConvex<'_>]; 2]> =
                prepared.iter().map(|[a, b]| [&a[..], &b[..]]).collect();
            // Moves of later chunks continue the numbering, as one call would give it.
            let first = out.len();
            self.tag = tag0.saturating_add((first as MoveTag).saturating_mul(tag_step));
            let offset = |r: &Removal| Removal {
                move_index: r.move_index + first,
                ..*r
            };
            let shifted = visitor.map(|v| move |r: &Removal| v.removed(&offset(r)));
            let stats = self.subtract_tagged(
                &groups,
                tag_step,
                shifted.as_ref().map(|f| f as &dyn RemovalVisitor),
                chained,
            );
            self.tag = tag0;
            out.extend(stats.into_iter().map(|[cutting, non_cutting]| SegmentCut {
                cutting,
                non_cutting,
                sub_moves: 1,
                error_bound_mm: 0.0,
            }));
        }
        if let Some(m) = moves.last() {
            crate::cut::CutInstance::record(&mut self.last_instance, groups, m.tip1, m.axis);
        }
        out
    }
}

/// Below this many tiles (summed over the moves of a call) the work is not split: about 4,000
/// rays, what 64 tiles of 8 × 8 held when it was tuned.
const PARALLEL_MIN_TILES: usize = 4096 / TILE_RAYS;

/// Below this many moves a call prepares them on the calling thread.
const PARALLEL_MIN_MOVES: usize = 32;

/// `f(index, item)` for every item, in order; in parallel for a long batch, whose preparation
/// would otherwise be the serial part of the call (≈ 7 % of a finishing batch's time on two
/// threads), with the pool's workers waiting.
fn par_map<T: Sync, U: Send>(items: &[T], f: impl Fn(usize, &T) -> U + Sync + Send) -> Vec<U> {
    if items.len() < PARALLEL_MIN_MOVES || rayon::current_num_threads() == 1 {
        items.iter().enumerate().map(|(i, t)| f(i, t)).collect()
    } else {
        items
            .par_iter()
            .enumerate()
            .with_min_len(8)
            .map(|(i, t)| f(i, t))
            .collect()
    }
}

/// The smallest index range holding every range of `ranges` (inclusive ends); `(usize::MAX,
/// 0)`, empty, when there are none.
fn hull(ranges: impl Iterator<Item = (usize, usize)>) -> (usize, usize) {
    ranges.fold((usize::MAX, 0), |a, b| (a.0.min(b.0), a.1.max(b.1)))
}

/// What the parts of one group of a move share along one family (`DexelRays`), made by the
/// first row that needs it.
type LazyRays = OnceLock<SmallVec<[DexelRays; 2]>>;

/// One tile row of one family, owned by the worker that took it.
struct Row<'a> {
    rays: &'a mut [Dexel],
    bounds: &'a mut [TileBound],
    /// Which of the row's bounds a cut changed since they were last made exact.
    stale: &'a mut [bool],
    /// The rays' provenance (empty when not tracked).
    tags: &'a mut [DexelTags],
}

/// One piece of material a cut took from a ray, as [`RemovalVisitor`] hears of it.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Removal {
    /// Index of the move in the call ([`TriDexel::subtract_moves_visited`]'s `moves`, or
    /// [`TriDexel::cut_linear_batch_visited`]'s).
    pub move_index: usize,
    /// The tag the move cut under ([`TriDexel::set_move_tag`]).
    pub tag: MoveTag,
    /// Which group of the move's parts (for a [`swarf_sweep::ToolShape`]: 0 the cutting part, 1 the
    /// shank and holder).
    pub group: usize,
    /// The ray family (0 = X, 1 = Y, 2 = Z).
    pub family: usize,
    /// The ray: indices along the family's cross axes `(k+1)%3` and `(k+2)%3`
    /// ([`DexelFamily::ray`]).
    pub ray: (usize, usize),
    /// The material removed, in the ray's coordinate, mm.
    pub removed: Interval,
}

/// Hears of every piece of material a cut removes, ray by ray. Called from the cutting
/// threads (hence `Sync` and `&self`): for one ray the calls come in the order the moves cut
/// it; across rays in no particular order. A plain `Fn(&Removal) + Sync` closure is one. The
/// cuts that take no visitor pay nothing for this.
pub trait RemovalVisitor: Sync {
    /// `r` was removed.
    fn removed(&self, r: &Removal);
}

impl<F: Fn(&Removal) + Sync> RemovalVisitor for F {
    fn removed(&self, r: &Removal) {
        self(r)
    }
}

/// The rays of one family a move may touch: cross index ranges and the range along the rays.
#[derive(Clone, Copy, Debug)]
struct FamilyRange {
    i: (usize, usize),
    j: (usize, usize),
    t: (f64, f64),
}

/// What a move may touch, per family.
struct Plan {
    fam: [Option<FamilyRange>; 3],
    /// Per part, the front of its start instance swept along the move, when that instance
    /// has been cut already.
    fronts: Option<SmallVec<[Front; 2]>>,
}

impl Plan {
    fn new(grid: &Grid, parts: &[SweptConvex<'_>], chained: bool) -> Option<Plan> {
        let bb = parts
            .iter()
            .map(SweptConvex::bbox)
            .reduce(|a, b| a.union(&b))?;
        let fam = [0, 1, 2].map(|k| {
            let (u, v) = ((k + 1) % 3, (k + 2) % 3);
            let i = grid.centers_in(u, bb.min[u], bb.max[u])?;
            let j = grid.centers_in(v, bb.min[v], bb.max[v])?;
            Some(FamilyRange {
                i,
                j,
                t: (bb.min[k], bb.max[k]),
            })
        });
        let fronts = chained.then(|| parts.iter().map(SweptConvex::front).collect());
        Some(Plan { fam, fronts })
    }

    fn tiles(&self) -> usize {
        self.fam
            .iter()
            .flatten()
            .map(|r| (r.i.1 / TILE - r.i.0 / TILE + 1) * (r.j.1 / TILE - r.j.0 / TILE + 1))
            .sum()
    }
}

/// Which rays of a tile one part's move can change.
enum Gate {
    /// Any ray (the move's start instance may still hold material).
    All,
    /// The rays that can meet the front of the (cut) start instance swept along the move.
    Front(FrontBlock),
    /// None: the swept front misses the tile's material.
    Never,
}

impl Gate {
    /// Whether the ray through `(cu, cv)` may be changed.
    #[inline(always)]
    fn open(&self, cu: f64, cv: f64) -> bool {
        match self {
            Gate::All => true,
            Gate::Front(b) => b.reaches(cu, cv),
            Gate::Never => false,
        }
    }
}

/// The tiles of one family against one group of parts of one move.
struct TileCut<'g, 'p, 'a> {
    grid: &'g Grid,
    k: usize,
    range: &'g FamilyRange,
    parts: &'p [SweptConvex<'a>],
    /// Per part, what its dexel queries along this family share.
    rays: &'g [DexelRays],
    /// The family's bins of the tiles' bounds.
    bins: &'g Bins,
    /// Per part, the front of its start instance swept along the move, when that instance
    /// has been cut already: only the rays that can meet it are queried.
    fronts: Option<&'g [Front]>,
    /// The tag the ends this cut makes get.
    tag: MoveTag,
    /// Who hears of the removed material, with the move's index in the call and the group.
    visitor: Option<(&'g dyn RemovalVisitor, usize, usize)>,
}

impl TileCut<'_, '_, '_> {
    /// Removes `[lo, hi]` from the dexel `d` of ray `ray` (its provenance `tags` kept in
    /// step when tracked), telling the visitor; returns the length removed.
    #[inline(always)]
    fn remove(
        &self,
        d: &mut Dexel,
        tags: Option<&mut DexelTags>,
        ray: (usize, usize),
        lo: f64,
        hi: f64,
    ) -> f64 {
        match (tags, self.visitor) {
            (None, None) => subtract(d, lo, hi),
            (t, v) => {
                let report = |iv: Interval| {
                    if let Some((v, move_index, group)) = v {
                        v.removed(&Removal {
                            move_index,
                            tag: self.tag,
                            group,
                            family: self.k,
                            ray,
                            removed: iv,
                        });
                    }
                };
                match t {
                    Some(t) => subtract_with(d, t, lo, hi, self.tag, report),
                    None => subtract_with(d, &mut (), lo, hi, self.tag, report),
                }
            }
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn run(
        &self,
        ti: usize,
        tj: usize,
        tile: &mut [Dexel],
        tags: &mut [DexelTags],
        (bound, stale): (&mut TileBound, &mut bool),
        scratch: &mut Scratch,
        st: &mut CutStats,
    ) {
        let (grid, k) = (self.grid, self.k);
        let (u, v) = ((k + 1) % 3, (k + 2) % 3);
        // (The caller has checked that the tile's bound meets the move's range.)
        let (tmin, tmax) = self.range.t;
        // Material-first at tile level: skip the tile when no part's sweep can reach its
        // material range, and look at the rays only where some part can reach them.
        let half = 0.5 * TILE as f64 * grid.h[u].max(grid.h[v]);
        let centre = family_point(
            k,
            0.0,
            grid.min[u] + (ti * TILE) as f64 * grid.h[u] + 0.5 * TILE as f64 * grid.h[u],
            grid.min[v] + (tj * TILE) as f64 * grid.h[v] + 0.5 * TILE as f64 * grid.h[v],
        );
        let (mut reach_lo, mut reach_hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for p in self.parts {
            if let Some((a, b)) = p.block_range(k, centre, half) {
                if bound.lo < b && bound.hi > a {
                    (reach_lo, reach_hi) = (reach_lo.min(a), reach_hi.max(b));
                }
            }
        }
        if reach_lo > reach_hi {
            return;
        }
        let (tmin, tmax) = (tmin.max(reach_lo), tmax.min(reach_hi));
        // Per part, which rays of the tile its move can change.
        let mut gates: SmallVec<[Gate; 2]> = match self.fronts {
            None => self.parts.iter().map(|_| Gate::All).collect(),
            Some(fronts) => fronts
                .iter()
                .map(|f| match f.block(k, centre, half, (bound.lo, bound.hi)) {
                    Some(b) => Gate::Front(b),
                    None => Gate::Never,
                })
                .collect(),
        };
        // A plane that separated rays of this family from a part's sweep may clear the whole
        // tile: the box of its rays' material within the move's reach.
        let (lo, hi) = (
            family_point(k, bound.lo.max(tmin), centre[u] - half, centre[v] - half),
            family_point(k, bound.hi.min(tmax), centre[u] + half, centre[v] + half),
        );
        for ((gate, p), rays) in gates.iter_mut().zip(self.parts).zip(self.rays) {
            if !matches!(gate, Gate::Never) && p.box_clear(lo, hi, rays, scratch) {
                *gate = Gate::Never;
            }
        }
        if gates.iter().all(|g| matches!(g, Gate::Never)) {
            return;
        }
        let (i_lo, i_hi) = (
            self.range.i.0.max(ti * TILE) - ti * TILE,
            self.range.i.1.min(ti * TILE + TILE - 1) - ti * TILE,
        );
        let (j_lo, j_hi) = (
            self.range.j.0.max(tj * TILE) - tj * TILE,
            self.range.j.1.min(tj * TILE + TILE - 1) - tj * TILE,
        );
        let (u_min, u_h, v_min, v_h) = (grid.min[u], grid.h[u], grid.min[v], grid.h[v]);
        // Cell centres with the axes resolved once per tile (`Grid::center` per ray costs, and
        // so does an index's conversion to f64): the same values, computed the same way.
        let cus: [f64; TILE] =
            std::array::from_fn(|ii| u_min + ((ti * TILE + ii) as f64 + 0.5) * u_h);
        // Counted here, added to `st` once (the lengths go on as before: their sum's order is
        // the rays').
        let rows = TileRows {
            cut: self,
            tile: &mut *tile,
            tags,
            scratch,
            removed_length: &mut st.removed_length[k],
            longest_removal: &mut st.longest_removal[k],
            ti,
            tj,
            i: (i_lo, i_hi),
            j: (j_lo, j_hi),
            cus: &cus,
            v: (v_min, v_h),
            t: (tmin, tmax),
        };
        let (visited, tested_n, updates) =
            if let ([p], [rays], [gate]) = (self.parts, self.rays, &gates[..]) {
                // One part (the common case): its kernel chosen once for the tile's loop.
                p.with_kernel(k, rays, OnePart { rows, gate })
            } else if let Some(set) = instance_set(self.rays, &gates) {
                // Instances of one band (a 5-axis move): each ray's chords joined, the ray
                // changed once.
                let mut hits = [(0.0, 0.0); InstanceSet::MAX];
                rows.each_ray(
                    |_, _| true,
                    |cut, (cu, cv), ray, d, mut tags, _| {
                        let (tested, n) = set.cut(cu, cv, d, &mut hits);
                        let mut removed = 0.0;
                        for &(lo, hi) in &hits[..n] {
                            removed += cut.remove(d, tags.as_deref_mut(), ray, lo, hi);
                        }
                        (tested, removed)
                    },
                )
            } else {
                let open = |cu, cv| gates.iter().any(|g: &Gate| g.open(cu, cv));
                rows.each_ray(open, |cut, (cu, cv), ray, d, mut tags, scratch| {
                    let (mut tested, mut removed) = (false, 0.0);
                    for ((p, rays), gate) in self.parts.iter().zip(self.rays).zip(&gates) {
                        if !gate.open(cu, cv) {
                            continue;
                        }
                        let (t, hit) = p.dexel_cut((cu, cv), k, d, rays, scratch);
                        tested |= t;
                        if let Some((lo, hi)) = hit {
                            removed += cut.remove(d, tags.as_deref_mut(), ray, lo, hi);
                        }
                    }
                    (tested, removed)
                })
            };
        st.visited_per_family[k] += visited;
        st.rays_tested += tested_n;
        st.tested_per_family[k] += tested_n;
        st.updates += updates;
        st.updates_per_family[k] += updates;
        // The bound only ever shrinks, so one left as it was stays true; it may only keep the
        // tile from being skipped. A refresh reads all the tile's rays, and a finishing pass
        // changes a tile on each of the dozens of moves that cross it: the bound is refreshed
        // when a run finds nothing to change in a tile changed since (the stale bound may be
        // what let the run in), in this call or a later one.
        if updates > 0 {
            *stale = true;
        } else if *stale {
            *bound = tile_bound(tile, self.bins);
            *stale = false;
        }
    }
}

/// One move of a planar run on one row, and what it removed there.
struct PlanarCut {
    /// The move's index in the call.
    index: usize,
    member: PlanarMember,
    range: FamilyRange,
    stats: CutStats,
}

/// The moves of a run in one plane normal to family `k` (`PlanarMember`), in order, cut on row
/// `tj` together: each ray is visited once for the run. The moves' chords are nested and
/// centred on the plane, so move after move the ray changes only where a move's chord is wider
/// than every earlier one's and than the air about the plane (its key, a squared distance,
/// under the ray's `beat`): a move whose bound cannot beat it is passed over, its chord not even
/// computed. Each change is measured on the ray as it was (`within`: the material inside the
/// chord grows by what the move takes) and counted for its move, as the moves cut one by one
/// would count it; the ray is cut once, by the widest chord. (A member's rays tested and
/// changed are counted in `tested_per_family` and `updates_per_family` alone, here and in
/// `cut_along`; the caller fills in the counters that move with them.)
fn cut_planar(
    grid: &Grid,
    k: usize,
    tj: usize,
    row: &mut Row<'_>,
    bins: &Bins,
    members: &mut [PlanarCut],
) {
    let Some(first) = members.first().map(|m| m.member) else {
        return;
    };
    #[cfg(test)]
    tests::count_run(grid, k);
    let (c, r) = (first.plane(), first.radius());
    let rr = r * r;
    let (tlo, thi) = (c - r, c + r);
    let mask = bins.mask(tlo, thi);
    let (u, v) = ((k + 1) % 3, (k + 2) % 3);
    let span = |f: fn(&FamilyRange) -> (usize, usize)| hull(members.iter().map(|m| f(&m.range)));
    let (i0, i1) = span(|r| r.i);
    let (j0, j1) = span(|r| r.j);
    let (j_lo, j_hi) = (
        j0.max(tj * TILE) - tj * TILE,
        j1.min(tj * TILE + TILE - 1) - tj * TILE,
    );
    let cv = |jj: usize| grid.center(v, tj * TILE + jj);
    let vs = (cv(j_lo), cv(j_hi));
    // The members that can reach a tile, and their bounds side by side: most are passed over
    // on their bound alone, ray after ray.
    let mut cand: SmallVec<[usize; 32]> = SmallVec::new();
    let mut bounds: SmallVec<[KeyBound; 32]> = SmallVec::new();
    let mut spans: SmallVec<[(f64, f64); 32]> = SmallVec::new();
    let mut later: SmallVec<[KeyBound; 32]> = SmallVec::new();
    let run_bounds: SmallVec<[(KeyBound, (f64, f64)); 32]> = members
        .iter()
        .map(|m| (m.member.bound(), m.member.span()))
        .collect();
    for ti in i0 / TILE..i1 / TILE + 1 {
        if !row.bounds[ti].meets_mask(tlo, thi, mask) {
            continue;
        }
        let (i_lo, i_hi) = (
            i0.max(ti * TILE) - ti * TILE,
            i1.min(ti * TILE + TILE - 1) - ti * TILE,
        );
        let cu = |ii: usize| grid.center(u, ti * TILE + ii);
        let us = (cu(i_lo), cu(i_hi));
        cand.clear();
        bounds.clear();
        spans.clear();
        for (n, &(b, span)) in run_bounds.iter().enumerate() {
            if b.over(us, vs) < rr {
                cand.push(n);
                bounds.push(b);
                spans.push(span);
            }
        }
        if cand.is_empty() {
            continue;
        }
        // The bound of every candidate from each on (the hull of their ranges): once a ray
        // fails it, no later member can widen its chord. (On a pass that is once the members
        // start `√beat` ahead of the ray, or sooner where the later centres all stand higher
        // than the ray by enough.)
        later.clear();
        for &b in bounds.iter().rev() {
            let h = later.last().map_or(b, |a: &KeyBound| a.hull(b));
            later.push(h);
        }
        later.reverse();
        // On a pass the members a ray can need are one stretch of them (`Progress`): most
        // are left without checking their bounds.
        let progress = Progress::of(&spans);
        let tile = &mut row.rays[ti * TILE_RAYS..(ti + 1) * TILE_RAYS];
        let mut changed = false;
        for jj in j_lo..j_hi + 1 {
            let cv = cv(jj);
            for ii in i_lo..i_hi + 1 {
                let d = &mut tile[jj * TILE + ii];
                // (No material within r of the plane, i.e. none in the open range (tlo, thi):
                // no threshold — one scan of the ray decides both.)
                let cu = cu(ii);
                // (The ray's intervals read through one slice: each look through the `SmallVec`
                // asks again where they live.)
                let ivs: &[Interval] = d;
                let Some(mut beat) = first.threshold(ivs.iter().map(|iv| (iv.enter, iv.exit)))
                else {
                    continue;
                };
                // The moves that widen the chord, in order, with their keys; their chords are
                // made after the loop (square roots independent of one another, not each
                // waiting for the last comparison).
                let mut wider: SmallVec<[(usize, f64); 32]> = SmallVec::new();
                let x = first.point(cu, cv).0;
                let from = progress.first(&spans, x, beat);
                for ((&n, b), rest) in cand[from..].iter().zip(&bounds[from..]).zip(&later[from..])
                {
                    if b.at(cu, cv) >= beat {
                        if rest.at(cu, cv) >= beat {
                            break;
                        }
                        continue;
                    }
                    let pc = &mut members[n];
                    let key = pc.member.key(cu, cv);
                    pc.stats.tested_per_family[k] += 1;
                    if key < beat {
                        beat = key;
                        wider.push((n, key));
                    }
                }
                let Some(&(last, widest)) = wider.last() else {
                    continue;
                };
                let mut taken = 0.0;
                for &(n, key) in &wider {
                    let (lo, hi) = first.chord(key);
                    let now = within(ivs, lo, hi);
                    let removed = now - taken;
                    taken = now;
                    if removed > 0.0 {
                        let st = &mut members[n].stats;
                        st.updates_per_family[k] += 1;
                        st.removed_length[k] += removed;
                        st.longest_removal[k] = greater(removed, st.longest_removal[k]);
                    }
                }
                // What the cut drops beyond the measure (remainders under `MIN_INTERVAL_MM`)
                // goes to the move that cut last.
                let (lo, hi) = first.chord(widest);
                let removed = subtract(d, lo, hi);
                changed |= removed > 0.0;
                if removed > taken {
                    members[last].stats.removed_length[k] += removed - taken;
                }
            }
        }
        // The tile's bound as a move's cut keeps it (`TileCut::run`).
        if changed {
            row.stale[ti] = true;
        } else if row.stale[ti] {
            row.bounds[ti] = tile_bound(tile, bins);
            row.stale[ti] = false;
        }
    }
}

/// The moves of a run in one plane parallel to family `k`'s rays, along the plane's in-plane
/// axis (`PlanarMember::in_plane_axis` is `k`), in order, cut on row `tj` together: each ray is
/// visited once for the run. A ray `δ` from the plane at height `z` meets a move's sweep in
/// `PlanarMember::line_span` at `√(r² − δ²)`; the spans of the moves taken so far are kept as
/// one interval, `taken`, not yet cut from the ray: a move's share is the material of its span
/// outside `taken` (what it would remove, the earlier moves cut one by one), and a span that
/// does not meet `taken` first has `taken` cut. On a pass the members a ray can need are one
/// stretch of them (`Progress`: only those within `√(r² − δ²)` of the ray's material).
fn cut_along(
    grid: &Grid,
    k: usize,
    tj: usize,
    row: &mut Row<'_>,
    bins: &Bins,
    members: &mut [PlanarCut],
) {
    let Some(first) = members.first().map(|m| m.member) else {
        return;
    };
    #[cfg(test)]
    tests::count_run(grid, k + 3);
    let (c, r) = (first.plane(), first.radius());
    let rr = r * r;
    let (u, v) = ((k + 1) % 3, (k + 2) % 3);
    // Which cross coordinate is the height along the tool axis (the other is the offset).
    let height_is_u = u == first.tool_axis();
    let fold = |f: fn(&PlanarCut) -> (usize, usize)| hull(members.iter().map(f));
    let (i0, i1) = fold(|m| m.range.i);
    let (j0, j1) = fold(|m| m.range.j);
    let (tlo, thi) = members
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |a, m| {
            (a.0.min(m.range.t.0), a.1.max(m.range.t.1))
        });
    let mask = bins.mask(tlo, thi);
    let (j_lo, j_hi) = (
        j0.max(tj * TILE) - tj * TILE,
        j1.min(tj * TILE + TILE - 1) - tj * TILE,
    );
    let cv = |jj: usize| grid.center(v, tj * TILE + jj);
    let spans: SmallVec<[(f64, f64); 32]> = members.iter().map(|m| m.member.span()).collect();
    let progress = Progress::of(&spans);
    let mut cand: SmallVec<[usize; 32]> = SmallVec::new();
    let mut cand_spans: SmallVec<[(f64, f64); 32]> = SmallVec::new();
    let mut gains: Vec<(usize, f64)> = Vec::with_capacity(members.len());
    for ti in i0 / TILE..i1 / TILE + 1 {
        if !row.bounds[ti].meets_mask(tlo, thi, mask) {
            continue;
        }
        let (i_lo, i_hi) = (
            i0.max(ti * TILE) - ti * TILE,
            i1.min(ti * TILE + TILE - 1) - ti * TILE,
        );
        let cu = |ii: usize| grid.center(u, ti * TILE + ii);
        // The members that can reach the tile's rays: the lowest centre within `r` of the
        // tile's highest ray, the plane within `r` of its nearest.
        let (us, vs) = ((cu(i_lo), cu(i_hi)), (cv(j_lo), cv(j_hi)));
        let (zs, offs) = if height_is_u { (us, vs) } else { (vs, us) };
        let near = (offs.0 - c).max(c - offs.1).max(0.0);
        if near >= r {
            continue;
        }
        let reach = (rr - near * near).sqrt();
        cand.clear();
        cand_spans.clear();
        for (n, m) in members.iter().enumerate() {
            if m.member.zlow() - zs.1 < reach {
                cand.push(n);
                cand_spans.push(spans[n]);
            }
        }
        if cand.is_empty() {
            continue;
        }
        let (cand, cand_spans) = (&cand[..], &cand_spans[..]);
        let tile = &mut row.rays[ti * TILE_RAYS..(ti + 1) * TILE_RAYS];
        let mut changed = false;
        for jj in j_lo..j_hi + 1 {
            let cv = cv(jj);
            for ii in i_lo..i_hi + 1 {
                let d = &mut tile[jj * TILE + ii];
                if d.is_empty() {
                    continue;
                }
                let (z, off) = if height_is_u {
                    (cu(ii), cv - c)
                } else {
                    (cv, cu(ii) - c)
                };
                let rho2 = rr - off * off;
                if rho2 <= 0.0 {
                    continue;
                }
                let rho = rho2.sqrt();
                // Each interval of material on its own: the members whose spans meet it are a
                // stretch of them (`Progress`), and an earlier member's span matters to a later
                // one's share only where both meet it.
                let mats: SmallVec<[(f64, f64); 8]> =
                    d.iter().map(|iv| (iv.enter, iv.exit)).collect();
                let intervals = mats.len();
                gains.clear();
                // (The ray's intervals read through one slice, made again after each cut.)
                let mut ivs: &[Interval] = d;
                for (e, f) in mats {
                    let x_from = if progress == Progress::Retreating {
                        f
                    } else {
                        e
                    };
                    let from = progress.first(cand_spans, x_from, rho2);
                    // The union of the spans (within the material's interval) since the last
                    // cut, what it holds of the material, and the member that last added to it.
                    let mut taken: Option<(f64, f64)> = None;
                    let (mut measured, mut last) = (0.0, usize::MAX);
                    for (&n, &span) in cand[from..].iter().zip(&cand_spans[from..]) {
                        // Out of reach of the material: on a pass, so is every later member
                        // once it lies ahead of the material in the direction of progress.
                        let (beyond, behind) = (span.0 - rho > f, span.1 + rho < e);
                        if beyond || behind {
                            match progress {
                                Progress::Advancing if beyond => break,
                                Progress::Retreating if behind => break,
                                _ => continue,
                            }
                        }
                        let pc = &mut members[n];
                        let Some((a, b)) = pc.member.line_span(z, rho) else {
                            continue;
                        };
                        pc.stats.tested_per_family[k] += 1;
                        let (a, b) = (greater(a, e), lesser(b, f));
                        if a >= b {
                            continue;
                        }
                        let removed = match taken {
                            Some((ta, tb)) if a <= tb && b >= ta => {
                                taken = Some((lesser(ta, a), greater(tb, b)));
                                within(ivs, a, greater(ta, a)) + within(ivs, lesser(tb, b), b)
                            }
                            _ => {
                                if let Some((ta, tb)) = taken {
                                    let cut = subtract(d, ta, tb);
                                    ivs = d;
                                    changed |= cut > 0.0;
                                    credit_rest(members, last, k, cut - measured);
                                    measured = 0.0;
                                }
                                taken = Some((a, b));
                                within(ivs, a, b)
                            }
                        };
                        // (A sliver under `MIN_INTERVAL_MM` that an earlier move's cut would
                        // drop beside its span is measured here as the later move's: the
                        // lengths agree to 10⁻⁹ mm, the rays changed by a sliver's count.)
                        if removed > 0.0 {
                            gains.push((n, removed));
                            measured += removed;
                            last = n;
                        }
                    }
                    if let Some((ta, tb)) = taken {
                        let cut = subtract(d, ta, tb);
                        ivs = d;
                        changed |= cut > 0.0;
                        credit_rest(members, last, k, cut - measured);
                    }
                }
                // A move's figures count the ray once, with all it took of it. (One interval
                // of material: the gains are in the members' order already.)
                if intervals > 1 {
                    gains.sort_by_key(|g| g.0);
                }
                let mut rest = &gains[..];
                while let Some(&(n, _)) = rest.first() {
                    let same = rest.iter().take_while(|g| g.0 == n).count();
                    let removed: f64 = rest[..same].iter().map(|g| g.1).sum();
                    rest = &rest[same..];
                    let st = &mut members[n].stats;
                    st.updates_per_family[k] += 1;
                    st.removed_length[k] += removed;
                    st.longest_removal[k] = greater(removed, st.longest_removal[k]);
                }
            }
        }
        // The tile's bound as a move's cut keeps it (`TileCut::run`).
        if changed {
            row.stale[ti] = true;
        } else if row.stale[ti] {
            row.bounds[ti] = tile_bound(tile, bins);
            row.stale[ti] = false;
        }
    }
}

/// What a run's cut drops beyond the measure (remainders under `MIN_INTERVAL_MM`) goes to
/// the move that cut last (`usize::MAX`: none did).
#[inline(always)]
fn credit_rest(members: &mut [PlanarCut], last: usize, k: usize, rest: f64) {
    if rest > 0.0 {
        if let Some(m) = members.get_mut(last) {
            m.stats.removed_length[k] += rest;
        }
    }
}

/// The length of the material of `d` within `[lo, hi]`. (`lo` and `hi` first: where one were
/// NaN, `lesser`/`greater` drop it as `f64::min`/`max` would.)
#[inline(always)]
fn within(d: &[Interval], lo: f64, hi: f64) -> f64 {
    d.iter()
        .map(|iv| greater(lesser(hi, iv.exit) - greater(lo, iv.enter), 0.0))
        .sum()
}

/// The point at `t` along the rays of family `k` and `(cu, cv)` across them. (Built from its
/// three coordinates: set through an index, a point is passed on through memory, and its
/// 16-byte reload of two 8-byte stores stalled a tenth of the tile's setup.)
#[inline(always)]
fn family_point(k: usize, t: f64, cu: f64, cv: f64) -> Vec3 {
    match k {
        0 => Vec3::new(t, cu, cv),
        1 => Vec3::new(cv, t, cu),
        _ => Vec3::new(cu, cv, t),
    }
}

/// The parts' instances as one set, when every part that may change the tile's rays is a
/// tool instance with nothing to gate its rays (no chained front).
fn instance_set<'r>(rays: &'r [DexelRays], gates: &[Gate]) -> Option<InstanceSet<'r>> {
    let mut set = InstanceSet::new();
    for (r, g) in rays.iter().zip(gates) {
        match g {
            Gate::Never => {}
            Gate::All if set.push(r) => {}
            _ => return None,
        }
    }
    Some(set)
}

/// The rays of one tile that one group of parts' move may change, and what the loop over
/// them adds to.
struct TileRows<'c, 'g, 'p, 'a, 't> {
    cut: &'c TileCut<'g, 'p, 'a>,
    tile: &'t mut [Dexel],
    tags: &'t mut [DexelTags],
    scratch: &'t mut Scratch,
    /// The family's removed length, added to ray by ray in the rays' order.
    removed_length: &'t mut f64,
    /// The family's longest removal from one ray.
    longest_removal: &'t mut f64,
    ti: usize,
    tj: usize,
    /// The tile's ray columns and rows that the move's range covers (first and last,
    /// inclusive).
    i: (usize, usize),
    j: (usize, usize),
    /// The columns' centres; where the rows' axis starts and their spacing (a row's centre is
    /// `start + (index + ½)·spacing`).
    cus: &'t [f64; TILE],
    v: (f64, f64),
    /// The range along the rays the sweep can reach.
    t: (f64, f64),
}

impl TileRows<'_, '_, '_, '_, '_> {
    /// The loop over the tile's rays: each that `open` lets through and whose material lies
    /// within the sweep's reach is handed to `cut_ray` — with its cross coordinates, its
    /// indices, its dexel and provenance (when tracked) — which says whether an exact query
    /// ran and what length it removed. Returns the rays visited, queried and changed.
    #[inline(always)]
    fn each_ray<G, F>(self, open: G, mut cut_ray: F) -> (u64, u64, u64)
    where
        G: Fn(f64, f64) -> bool,
        F: FnMut(
            &TileCut<'_, '_, '_>,
            (f64, f64),
            (usize, usize),
            &mut Dexel,
            Option<&mut DexelTags>,
            &mut Scratch,
        ) -> (bool, f64),
    {
        let TileRows {
            cut,
            tile,
            tags,
            scratch,
            removed_length,
            longest_removal,
            ti,
            tj,
            i: (i_lo, i_hi),
            j: (j_lo, j_hi),
            cus,
            v: (v_min, v_h),
            t: (tmin, tmax),
        } = self;
        let (mut visited, mut tested, mut updates) = (0u64, 0u64, 0u64);
        // Half-open ranges: an inclusive range's bookkeeping costs in a loop this hot.
        for jj in j_lo..j_hi + 1 {
            let cv = v_min + ((tj * TILE + jj) as f64 + 0.5) * v_h;
            for (ii, &cu) in (i_lo..i_hi + 1).zip(&cus[i_lo..i_hi + 1]) {
                let r = jj * TILE + ii;
                // The gate first: it reads no ray's material (the dexel's header, maybe on the
                // heap).
                let d = &mut tile[r];
                if !open(cu, cv) || !overlaps(d, tmin, tmax) {
                    continue;
                }
                visited += 1;
                let ray = (ti * TILE + ii, tj * TILE + jj);
                let (t, removed) = cut_ray(cut, (cu, cv), ray, d, tags.get_mut(r), scratch);
                tested += u64::from(t);
                if removed > 0.0 {
                    updates += 1;
                    *removed_length += removed;
                    *longest_removal = greater(removed, *longest_removal);
                }
            }
        }
        (visited, tested, updates)
    }
}

/// A tile's rays against one part (the common case), as the work that
/// [`SweptConvex::with_kernel`] runs with the part's kernel for the family: the loop is
/// compiled once per kernel, once per kind of gate, and once with and once without the
/// removal's bookkeeping (provenance, a visitor).
struct OnePart<'c, 'g, 'p, 'a, 't> {
    rows: TileRows<'c, 'g, 'p, 'a, 't>,
    gate: &'t Gate,
}

impl KernelTask for OnePart<'_, '_, '_, '_, '_> {
    /// Rays visited, exact queries, rays changed.
    type Output = (u64, u64, u64);

    fn run<K: DexelKernel>(self, kernel: &K) -> Self::Output {
        let OnePart { rows, gate } = self;
        let plain = rows.tags.is_empty() && rows.cut.visitor.is_none();
        // Written out arm by arm: one closure shared by the arms (a generic helper per gate)
        // compiled the finishing bench's loop 17 % longer (7.41 -> 8.71 G instructions).
        match (gate, plain) {
            (Gate::All, true) => rows.each_ray(
                |_, _| true,
                |c, at, ray, d, t, s| query::<K, true>(kernel, c, at, ray, d, t, s),
            ),
            (Gate::Front(b), true) => {
                let b = *b;
                rows.each_ray(
                    move |cu, cv| b.reaches(cu, cv),
                    |c, at, ray, d, t, s| query::<K, true>(kernel, c, at, ray, d, t, s),
                )
            }
            (Gate::All, false) => rows.each_ray(
                |_, _| true,
                |c, at, ray, d, t, s| query::<K, false>(kernel, c, at, ray, d, t, s),
            ),
            (Gate::Front(b), false) => {
                let b = *b;
                rows.each_ray(
                    move |cu, cv| b.reaches(cu, cv),
                    |c, at, ray, d, t, s| query::<K, false>(kernel, c, at, ray, d, t, s),
                )
            }
            // (Not reached: a tile whose only part can change none of its rays is left
            // before its loop.)
            (Gate::Never, _) => (0, 0, 0),
        }
    }
}

/// One ray's kernel query, and its interval taken from the dexel: by a plain subtraction
/// (`PLAIN`: no provenance, no visitor) or with the cut's bookkeeping.
#[inline(always)]
fn query<K: DexelKernel, const PLAIN: bool>(
    kernel: &K,
    cut: &TileCut<'_, '_, '_>,
    (cu, cv): (f64, f64),
    ray: (usize, usize),
    d: &mut Dexel,
    tags: Option<&mut DexelTags>,
    scratch: &mut Scratch,
) -> (bool, f64) {
    let (tested, hit) = kernel.cut(cu, cv, d, scratch);
    let removed = match hit {
        Some((lo, hi)) if PLAIN => subtract(d, lo, hi),
        Some((lo, hi)) => cut.remove(d, tags, ray, lo, hi),
        None => 0.0,
    };
    (tested, removed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ray_quad_is_the_four_rays() {
        // Every cell, across tile borders too: each ray holds what was filled at its own
        // centre (so the layout's index is the ray's), no two rays share a slot, and the quad
        // is the same slices as four `ray` calls.
        let b = Aabb::new(Vec3::ZERO, Vec3::new(2.1, 1.7, 1.3));
        let stock = TriDexel::from_fn(b, 0.1, |k, cu, cv, d| {
            d.push(Interval {
                enter: cu + 10.0 * cv + 100.0 * k as f64,
                exit: cu + 10.0 * cv + 100.0 * k as f64 + 1.0,
            });
        })
        .unwrap();
        let grid = *stock.grid();
        for k in 0..3 {
            let fam = stock.family(k);
            let (nu, nv) = fam.dims();
            let mut slots = std::collections::HashSet::new();
            for j in 0..nv {
                for i in 0..nu {
                    let (cu, cv) = (grid.center((k + 1) % 3, i), grid.center((k + 2) % 3, j));
                    let want = cu + 10.0 * cv + 100.0 * k as f64;
                    assert_eq!(fam.ray(i, j)[0].enter, want, "family {k}, ray ({i}, {j})");
                    assert!(
                        slots.insert(fam.ray(i, j).as_ptr()),
                        "family {k}, ray ({i}, {j})"
                    );
                }
            }
            for j in 0..nv - 1 {
                for i in 0..nu - 1 {
                    let quad = fam.ray_quad(i, j);
                    let each = [
                        fam.ray(i, j),
                        fam.ray(i + 1, j),
                        fam.ray(i, j + 1),
                        fam.ray(i + 1, j + 1),
                    ];
                    assert_eq!(quad, each, "family {k}, cell ({i}, {j})");
                }
            }
        }
    }

    /// A raster of short chained moves over a wavy floor in a 9 × 7 × 4 mm block: `passes`
    /// passes of `per_pass` moves `step` mm long, alternately along +X and −X, each followed by
    /// a move `over` mm along +Y.
    fn wavy_raster(passes: usize, per_pass: usize, step: f64, over: f64) -> Vec<LinearMove> {
        let mut moves: Vec<LinearMove> = Vec::new();
        let go = |moves: &mut Vec<LinearMove>, next: Vec3| {
            let tip0 = moves.last().map_or(Vec3::new(-2.0, 1.0, 2.2), |m| m.tip1);
            moves.push(LinearMove {
                tip0,
                tip1: next,
                axis: Vec3::Z,
            });
            next
        };
        let mut tip = Vec3::new(-2.0, 1.0, 2.2);
        for pass in 0..passes {
            let dir = if pass % 2 == 0 { step } else { -step };
            for i in 0..per_pass {
                let z = 2.2 + 0.4 * (0.3 * i as f64).sin();
                tip = go(&mut moves, Vec3::new(tip.x + dir, tip.y, z));
            }
            tip = go(&mut moves, tip + Vec3::new(0.0, over, 0.0));
        }
        moves
    }

    /// Every ray of `a` holds `b`'s intervals, ends within 1e-9 mm.
    fn same_rays(a: &TriDexel, b: &TriDexel, what: &str) {
        for k in 0..3 {
            let (nu, nv) = a.family(k).dims();
            for j in 0..nv {
                for i in 0..nu {
                    let (x, y) = (a.family(k).ray(i, j), b.family(k).ray(i, j));
                    assert_eq!(x.len(), y.len(), "{what}: family {k} ray ({i}, {j})");
                    for (p, q) in x.iter().zip(y) {
                        assert!(
                            (p.enter - q.enter).abs() <= 1e-9 && (p.exit - q.exit).abs() <= 1e-9,
                            "{what}: family {k} ray ({i}, {j}): {x:?} vs {y:?}"
                        );
                    }
                }
            }
        }
    }

    /// Runs of `cut_planar` (family `k`) and `cut_along` (`k + 3`), by the grid's cell counts
    /// (a test's own grid tells its runs from those of tests running beside it).
    static PLANAR_RUNS: std::sync::Mutex<Vec<([usize; 3], usize, usize)>> =
        std::sync::Mutex::new(Vec::new());

    pub(super) fn count_run(grid: &Grid, k: usize) {
        let mut runs = PLANAR_RUNS.lock().unwrap_or_else(|e| e.into_inner());
        match runs.iter_mut().find(|r| r.0 == grid.n && r.1 == k) {
            Some(r) => r.2 += 1,
            None => runs.push((grid.n, k, 1)),
        }
    }

    /// The runs counted so far on grids of `n` cells, family `k`.
    fn runs(n: [usize; 3], k: usize) -> usize {
        let runs = PLANAR_RUNS.lock().unwrap_or_else(|e| e.into_inner());
        runs.iter()
            .find(|r| r.0 == n && r.1 == k)
            .map_or(0, |r| r.2)
    }

    /// Moves of a ball end in one plane, cut together on the rows of the family normal to it
    /// (`cut_planar`) and of the family along it (`cut_along`), leave the stock and each move's
    /// figures (lengths and longest removals; not the rays changed, which the reference's
    /// retraced moves inflate by changes of 10⁻¹⁵ mm — on the stretch back and forth below, up
    /// to ten times a run's count for one move, for the same length) as the moves cut one by
    /// one do
    /// (`set_exhaustive` keeps them one by one): passes along X (the Y rays' planes) and along
    /// Y (the X rays'), plunges and lifts in them, step-overs and a diagonal between, a stretch
    /// back and forth in one plane across earlier cuts, in calls of several lengths; a ball
    /// with a short flute, shank and holder in the block, and one whose flute is just too short
    /// for it (both refused, no run at all: the top would cut the chords short).
    #[test]
    fn planar_runs_cut_as_the_moves_one_by_one() {
        use swarf_tool::{Cutter, CutterKind, CutterOptions, Holder, HolderSegment};
        let surface = |x: f64, y: f64| 2.4 + 0.5 * (x / 2.0).sin() * (y / 3.0).cos();
        let mut pts = vec![Vec3::new(-3.0, 1.0, 7.0)];
        for pass in 0..7 {
            let y = 1.0 + 0.45 * pass as f64;
            let x0 = if pass % 2 == 0 { -1.0 } else { 13.0 };
            pts.push(Vec3::new(x0, y, 7.0));
            for i in 0..=28 {
                let x = if pass % 2 == 0 {
                    x0 + 0.5 * i as f64
                } else {
                    x0 - 0.5 * i as f64
                };
                pts.push(Vec3::new(x, y, surface(x, y)));
            }
            let last = *pts.last().unwrap();
            pts.push(Vec3::new(last.x, y, 7.0));
        }
        pts.push(Vec3::new(2.0, 4.0, 5.0));
        for pass in 0..5 {
            let x = 2.0 + 0.6 * pass as f64;
            for i in 0..=20 {
                let y = if pass % 2 == 0 {
                    4.0 + 0.4 * i as f64
                } else {
                    12.0 - 0.4 * i as f64
                };
                pts.push(Vec3::new(x, y, surface(x, y) - 0.3));
            }
        }
        // Back and forth in one plane (neither advancing nor retreating), deeper than the
        // passes before it, whose X rays it crosses where they hold several intervals.
        pts.push(Vec3::new(3.0, 9.5, 6.0));
        for i in 0..16 {
            let x = 3.0 + 0.4 * i as f64 - if i % 2 == 1 { 1.1 } else { 0.0 };
            pts.push(Vec3::new(x, 9.5, surface(x, 9.5) - 0.6));
        }
        let moves = LinearMove::chain(&pts, Vec3::Z);
        let held = CutterOptions {
            flute_length: Some(2.0),
            overall_length: Some(3.0),
            shank_diameter: Some(2.5),
            holder: Some(Holder {
                base_z_mm: 3.0,
                segments: vec![HolderSegment {
                    length_mm: 5.0,
                    bottom_diameter_mm: 5.0,
                    top_diameter_mm: 8.0,
                }],
            }),
            ..CutterOptions::default()
        };
        let short = CutterOptions {
            flute_length: Some(3.2),
            overall_length: Some(3.2),
            ..CutterOptions::default()
        };
        let long = CutterOptions {
            flute_length: Some(12.0),
            ..CutterOptions::default()
        };
        let block = TriDexel::from_box(Vec3::ZERO, Vec3::new(13.0, 13.0, 8.0), 0.11).unwrap();
        for (name, cutter, planar) in [
            (
                "ball",
                Cutter::named(CutterKind::Ball, &[3.0], &long).unwrap(),
                true,
            ),
            (
                "held",
                Cutter::named(CutterKind::Ball, &[3.0], &held).unwrap(),
                false,
            ),
            (
                "short",
                Cutter::named(CutterKind::Ball, &[3.0], &short).unwrap(),
                false,
            ),
        ] {
            let tool = ToolShape::new(&cutter);
            let mut one = block.clone();
            one.set_exhaustive(true);
            let want = one.cut_linear_batch(&tool, &moves);
            if !planar {
                // Nothing of the grid may rely on a chord the top would cut short.
                let grid = block.grid();
                let m = &moves[10];
                let part = &tool.cutting().parts()[0];
                let sw = SweptConvex::new(part, m.tip0, m.axis, m.tip1 - m.tip0);
                let member = sw.planar(1);
                assert!(
                    member.is_none_or(|p| p.top() < grid.max[2]),
                    "{name}: {member:?}"
                );
            }
            for chunk in [moves.len(), 40, 7] {
                let n = block.grid().n;
                let before = [runs(n, 0), runs(n, 1), runs(n, 3), runs(n, 4)];
                let mut together = block.clone();
                let got: Vec<SegmentCut> = moves
                    .chunks(chunk)
                    .flat_map(|c| together.cut_linear_batch(&tool, c))
                    .collect();
                // Both the passes along X (the Y rays across them, the X rays along them) and
                // along Y (the X rays across, the Y rays along) ran as runs; none ran for a
                // tool refused.
                let after = [runs(n, 0), runs(n, 1), runs(n, 3), runs(n, 4)];
                if planar {
                    assert!(
                        after.iter().zip(&before).all(|(a, b)| a > b),
                        "{name}: runs across X, Y, along X, Y {before:?} -> {after:?}"
                    );
                } else {
                    assert_eq!(after, before, "{name}: runs across X, Y, along X, Y");
                }
                for (m, (a, b)) in got.iter().zip(&want).enumerate() {
                    for (x, y) in [(a.cutting, b.cutting), (a.non_cutting, b.non_cutting)] {
                        for k in 0..3 {
                            assert!(
                                (x.removed_length[k] - y.removed_length[k]).abs() < 1e-9
                                    && (x.longest_removal[k] - y.longest_removal[k]).abs() < 1e-9,
                                "{name}, calls of {chunk}: move {m}, family {k}: {x:?} vs {y:?}"
                            );
                        }
                    }
                }
                same_rays(&together, &one, name);
            }
        }
    }

    /// A second group of parts whose sweeps reach a planar run's rows (a part beside the ball,
    /// crossing the Y rays the ball's run cuts) keeps those rows move by move: each group's
    /// figures, the second's included, and the stock are the move-by-move reference's, and the
    /// rows the second group does not reach still ran as runs.
    #[test]
    fn another_group_on_the_rows_keeps_the_moves_one_by_one() {
        use swarf_sweep::ConvexProfile;
        use swarf_tool::{Cutter, CutterKind, CutterOptions};
        let long = CutterOptions {
            flute_length: Some(12.0),
            ..CutterOptions::default()
        };
        let ball = Cutter::named(CutterKind::Ball, &[3.0], &long).unwrap();
        let flat = Cutter::flat(1.0).unwrap();
        let (bp, fp) = (
            ConvexProfile::from_solid(ball.cutting_solid()).unwrap(),
            ConvexProfile::from_solid(flat.cutting_solid()).unwrap(),
        );
        // A pass along X at y = 3 over x 1..11; the flat end, 2 mm to the side (y = 5, its own
        // plane) and 1 mm lower, moves with it over x 1..5 only.
        let tips: Vec<Vec3> = (0..=20)
            .map(|i| {
                Vec3::new(
                    1.0 + 0.5 * i as f64,
                    3.0,
                    2.5 + 0.3 * (i as f64 * 0.7).sin(),
                )
            })
            .collect();
        let balls: Vec<SweptConvex<'_>> = tips
            .windows(2)
            .map(|w| SweptConvex::new(&bp, w[0], Vec3::Z, w[1] - w[0]))
            .collect();
        let flats: Vec<SweptConvex<'_>> = tips
            .windows(2)
            .map(|w| {
                let side = Vec3::new(0.0, 2.0, -1.0);
                SweptConvex::new(&fp, w[0] + side, Vec3::Z, w[1] - w[0])
            })
            .collect();
        let moves: Vec<[&[SweptConvex<'_>]; 2]> = (0..balls.len())
            .map(|i| {
                let second: &[SweptConvex<'_>] = if i < 8 { &flats[i..i + 1] } else { &[] };
                [&balls[i..i + 1], second]
            })
            .collect();
        let block = TriDexel::from_box(Vec3::ZERO, Vec3::new(12.1, 7.1, 4.1), 0.09).unwrap();
        let mut one = block.clone();
        one.set_exhaustive(true);
        let want = one.subtract_moves(&moves);
        let n = block.grid().n;
        let before = runs(n, 1);
        let mut together = block.clone();
        let got = together.subtract_moves(&moves);
        assert!(
            runs(n, 1) > before,
            "no run on the rows the second group leaves"
        );
        let held: f64 = want.iter().map(|m| m[1].removed_length[1]).sum();
        assert!(held > 1.0, "the second group cuts the Y rays: {held} mm");
        for (m, (a, b)) in got.iter().zip(&want).enumerate() {
            for g in 0..2 {
                for k in 0..3 {
                    assert!(
                        (a[g].removed_length[k] - b[g].removed_length[k]).abs() < 1e-9,
                        "move {m}, group {g}, family {k}: {:?} vs {:?}",
                        a[g],
                        b[g]
                    );
                }
            }
        }
        same_rays(&together, &one, "beside");
    }

    /// Every tile's bound holds its material between calls, and is exact unless a cut changed
    /// the tile since it was last made exact (a tile is refreshed when a run finds nothing to
    /// change in it, in the same call or a later one), and exact everywhere after
    /// `refresh_stale_bounds`: a raster of short chained moves (each tile changed by many in a
    /// row, some emptied), in calls of several lengths.
    #[test]
    fn tile_bounds_hold_their_material_and_are_exact_once_refreshed() {
        let tool = ToolShape::new(&swarf_tool::Cutter::ball(3.0).unwrap());
        let moves = wavy_raster(6, 30, 0.37, 0.9);
        for chunk in [1, 7, 64, moves.len()] {
            let b = Aabb::new(Vec3::ZERO, Vec3::new(9.0, 7.0, 4.0));
            let mut stock = TriDexel::from_box(b.min, b.max, 0.1).unwrap();
            let mut stale_seen = 0;
            for part in moves.chunks(chunk) {
                stock.cut_linear_batch(&tool, part);
                for fam in &stock.families {
                    for (t, bound) in fam.bounds.iter().enumerate() {
                        let rays = &fam.rays[t * TILE_RAYS..(t + 1) * TILE_RAYS];
                        let exact = tile_bound(rays, &fam.bins);
                        if fam.stale[t] {
                            stale_seen += 1;
                            // Larger, never smaller: its span and bins hold the exact ones.
                            assert!(
                                exact.lo >= bound.lo
                                    && exact.hi <= bound.hi
                                    && exact.bins & !bound.bins == 0,
                                "chunks of {chunk}, tile {t}: {bound:?} misses {exact:?}"
                            );
                        } else {
                            assert_eq!(*bound, exact, "chunks of {chunk}, tile {t}");
                        }
                    }
                }
            }
            assert!(stale_seen > 0, "chunks of {chunk}: no tile was left stale");
            stock.refresh_stale_bounds();
            for fam in &stock.families {
                assert!(fam.stale.iter().all(|s| !s));
                for (t, bound) in fam.bounds.iter().enumerate() {
                    let rays = &fam.rays[t * TILE_RAYS..(t + 1) * TILE_RAYS];
                    assert_eq!(
                        *bound,
                        tile_bound(rays, &fam.bins),
                        "chunks of {chunk}, tile {t}"
                    );
                }
            }
        }
    }

    /// `may_hold_material` never says no where a ray with its centre in the box holds material
    /// inside the box's range (brute force over every ray, on a block cut by a raster of ball
    /// moves, boxes of many sizes and places, beside the grid too), and says no to some boxes
    /// in the cut-away air.
    #[test]
    fn may_hold_material_never_misses() {
        let tool = ToolShape::new(&swarf_tool::Cutter::ball(3.0).unwrap());
        let b = Aabb::new(Vec3::ZERO, Vec3::new(9.0, 7.0, 4.0));
        let mut stock = TriDexel::from_box(b.min, b.max, 0.1).unwrap();
        stock.cut_linear_batch(&tool, &wavy_raster(5, 26, 0.5, 1.1));
        let (mut said_no, mut boxes) = (0, 0);
        for q in 0..4000 {
            let f = |m: usize, p: usize| ((q * m) % p) as f64 / p as f64;
            let c = Vec3::new(
                11.0 * f(37, 101) - 1.0,
                9.0 * f(53, 103) - 1.0,
                6.0 * f(71, 107) - 1.0,
            );
            let half = Vec3::new(
                0.02 + 0.6 * f(13, 97),
                0.02 + 0.6 * f(17, 89),
                0.02 + 0.6 * f(19, 83),
            );
            let bbox = Aabb::new(c - half, c + half);
            for k in 0..3 {
                boxes += 1;
                let (u, v) = ((k + 1) % 3, (k + 2) % 3);
                let g = stock.grid();
                let fam = stock.family(k);
                let (nu, nv) = fam.dims();
                let centre = |axis: usize, i: usize| g.min[axis] + (i as f64 + 0.5) * g.h[axis];
                let holds = (0..nv).any(|j| {
                    (0..nu).any(|i| {
                        let (cu, cv) = (centre(u, i), centre(v, j));
                        cu >= bbox.min[u]
                            && cu <= bbox.max[u]
                            && cv >= bbox.min[v]
                            && cv <= bbox.max[v]
                            && fam
                                .ray(i, j)
                                .iter()
                                .any(|iv| iv.enter < bbox.max[k] && iv.exit > bbox.min[k])
                    })
                });
                let may = stock.may_hold_material(k, &bbox);
                assert!(may || !holds, "box {bbox:?}, family {k}");
                said_no += usize::from(!may);
            }
        }
        assert!(said_no * 10 > boxes, "{said_no} of {boxes}");
    }

    /// The bins never miss: material `[a, b]` and a range `(lo, hi)` that overlap always share
    /// a bin, over and beyond the family's extent and on bin edges; far apart, they do not.
    #[test]
    fn tile_bins_are_conservative() {
        let grid = Grid::cubic(Vec3::new(-3.0, 0.0, 1.0), 0.5, [40, 8, 8]).unwrap();
        let bins = Bins::new(&grid, 0);
        let at = |i: i32| -3.0 + 20.0 * i as f64 / 256.0 - 2.0;
        let mut apart = 0;
        for i in 0..300 {
            for j in i..300 {
                let mut b = EMPTY_BOUND;
                b.add(at(i), at(j), &bins);
                for (lo, hi) in [(at(j) - 0.01, at(j) + 0.3), (at(i) - 0.7, at(i) + 1e-9)] {
                    assert!(
                        b.meets(lo, hi, &bins),
                        "[{}, {}] vs ({lo}, {hi})",
                        at(i),
                        at(j)
                    );
                }
                let (lo, hi) = (at(j) + 1.0, at(j) + 2.0);
                apart += usize::from(!b.meets(lo, hi, &bins));
            }
        }
        assert!(apart > 20_000, "{apart}");
    }
}
