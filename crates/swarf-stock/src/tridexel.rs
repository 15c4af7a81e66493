//! The tri-dexel stock: three families of parallel rays (along X, Y and Z) on a grid, each ray
//! holding its material intervals; construction from simple shapes, volume, statistics and the
//! localised, parallel subtraction of swept volumes.

use crate::dexel::{dexel_length, overlaps, subtract, Dexel, Interval};
use crate::error::StockError;
use crate::sweep::{Scratch, SweptConvex};
use rayon::prelude::*;
use smallvec::SmallVec;
use swarf_geom::math::Vec3;
use swarf_geom::Aabb;

/// Side of the square tiles of rays (tiles are stored contiguously and carry a conservative
/// bound of their material along the ray, so whole tiles are skipped without touching rays).
pub const TILE: usize = 8;
const TILE_RAYS: usize = TILE * TILE;

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
        if !(size.min_element() > 0.0 && size.is_finite() && bounds.min.is_finite()) {
            return Err(StockError::BadDimensions(format!(
                "bounding box {:?} .. {:?} is empty or not finite",
                bounds.min, bounds.max
            )));
        }
        let n = [0, 1, 2].map(|k| ((size[k] / h) * (1.0 - 1e-12)).ceil().max(1.0) as usize);
        let rays = (n[1] * n[2] + n[2] * n[0] + n[0] * n[1]) as u64;
        if rays > MAX_RAYS {
            return Err(StockError::TooManyRays {
                h,
                size: format!("{} x {} x {}", size.x, size.y, size.z),
                rays,
                limit: MAX_RAYS,
            });
        }
        let hk = [0, 1, 2].map(|k| size[k] / n[k] as f64);
        Ok(Grid {
            min: bounds.min,
            max: bounds.max,
            n,
            h: hk,
        })
    }

    /// Coordinate of the centre of cell `i` along axis `k`.
    #[inline]
    pub fn center(&self, k: usize, i: usize) -> f64 {
        self.min[k] + (i as f64 + 0.5) * self.h[k]
    }

    /// Indices of the cell centres along axis `k` within `[a, b]`, if any.
    fn centers_in(&self, k: usize, a: f64, b: f64) -> Option<(usize, usize)> {
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
    axis: usize,
    /// Rays along the first cross axis `(axis+1) % 3` and the second `(axis+2) % 3`.
    nu: usize,
    nv: usize,
    /// Tiles along u.
    ntu: usize,
    /// Tile-major storage: tile `(ti, tj)` holds rays `(tj·ntu + ti)·TILE² ..`, row-major inside.
    rays: Vec<Dexel>,
    /// Per tile, `[lowest enter, highest exit]` of its material (conservative: may be wider than
    /// the material after cuts until the tile is next visited).
    bounds: Vec<[f64; 2]>,
}

const EMPTY_BOUND: [f64; 2] = [f64::INFINITY, f64::NEG_INFINITY];

impl DexelFamily {
    fn new(axis: usize, grid: &Grid) -> Self {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        let (nu, nv) = (grid.n[u], grid.n[v]);
        let (ntu, ntv) = (nu.div_ceil(TILE), nv.div_ceil(TILE));
        Self {
            axis,
            nu,
            nv,
            ntu,
            rays: vec![Dexel::new(); ntu * ntv * TILE_RAYS],
            bounds: vec![EMPTY_BOUND; ntu * ntv],
        }
    }

    #[inline]
    fn index(&self, i: usize, j: usize) -> usize {
        ((j / TILE) * self.ntu + i / TILE) * TILE_RAYS + (j % TILE) * TILE + i % TILE
    }

    /// Ray direction: 0 = X, 1 = Y, 2 = Z.
    pub fn axis(&self) -> usize {
        self.axis
    }

    /// Number of rays (along the two cross axes).
    pub fn dims(&self) -> (usize, usize) {
        (self.nu, self.nv)
    }

    /// The intervals of ray `(i, j)` (indices along the cross axes `(axis+1)%3`, `(axis+2)%3`).
    pub fn ray(&self, i: usize, j: usize) -> &[Interval] {
        &self.rays[self.index(i, j)]
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
            + self.bounds.capacity() * std::mem::size_of::<[f64; 2]>()
    }

    fn refresh_bounds(&mut self) {
        for (t, b) in self.bounds.iter_mut().enumerate() {
            *b = tile_bound(&self.rays[t * TILE_RAYS..(t + 1) * TILE_RAYS]);
        }
    }
}

fn tile_bound(rays: &[Dexel]) -> [f64; 2] {
    let mut b = EMPTY_BOUND;
    for d in rays {
        if let (Some(f), Some(l)) = (d.first(), d.last()) {
            b[0] = b[0].min(f.enter);
            b[1] = b[1].max(l.exit);
        }
    }
    b
}

/// Counts and lengths from one subtraction.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct CutStats {
    /// Material length removed per family (X, Y, Z rays), mm.
    pub removed_length: [f64; 3],
    /// Rays whose exact interval was computed (after the material-first rejection).
    pub rays_tested: u64,
    /// Rays whose intervals changed.
    pub updates: u64,
    /// Rays visited per family (X, Y, Z): in a tile that survived the tile test, with material
    /// in the sweep's bounding range.
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
    families: [DexelFamily; 3],
}

impl TriDexel {
    /// An empty stock (no material) on the grid over `bounds` with resolution `h` (mm).
    pub fn empty(bounds: Aabb, h: f64) -> Result<Self, StockError> {
        let grid = Grid::new(bounds, h)?;
        Ok(Self {
            families: [0, 1, 2].map(|k| DexelFamily::new(k, &grid)),
            grid,
        })
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

    /// The grid.
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// The ray family along axis `k` (0 = X, 1 = Y, 2 = Z).
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
        self.families[k].total_length() * self.ray_area(k)
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

    /// Removes the union of the swept volumes `parts` (all sharing one move) from every ray
    /// that crosses their bounding box; returns what was removed.
    pub fn subtract_swept(&mut self, parts: &[SweptConvex<'_>]) -> CutStats {
        if parts.is_empty() {
            return CutStats::default();
        }
        let bb = parts
            .iter()
            .skip(1)
            .fold(parts[0].bbox(), |b, p| b.union(&p.bbox()));
        let grid = self.grid;
        let mut items: Vec<Work<'_>> = Vec::new();
        for fam in self.families.iter_mut() {
            let k = fam.axis;
            let (u, v) = ((k + 1) % 3, (k + 2) % 3);
            let (Some((i0, i1)), Some((j0, j1))) = (
                grid.centers_in(u, bb.min[u], bb.max[u]),
                grid.centers_in(v, bb.min[v], bb.max[v]),
            ) else {
                continue;
            };
            let (tmin, tmax) = (bb.min[k], bb.max[k]);
            let dir = Vec3::AXES[k];
            let (ti0, ti1) = (i0 / TILE, i1 / TILE);
            let ntu = fam.ntu;
            let mut rest_r: &mut [Dexel] = &mut fam.rays[..];
            let mut rest_b: &mut [[f64; 2]] = &mut fam.bounds[..];
            let mut consumed = 0;
            for tj in j0 / TILE..=j1 / TILE {
                let start = tj * ntu + ti0;
                let end = tj * ntu + ti1 + 1;
                let (_, r) =
                    std::mem::take(&mut rest_r).split_at_mut((start - consumed) * TILE_RAYS);
                let (mine_r, r) = r.split_at_mut((end - start) * TILE_RAYS);
                rest_r = r;
                let (_, b) = std::mem::take(&mut rest_b).split_at_mut(start - consumed);
                let (mine_b, b) = b.split_at_mut(end - start);
                rest_b = b;
                consumed = end;
                items.push(Work {
                    k,
                    u,
                    v,
                    tj,
                    ti0,
                    i: (i0, i1),
                    j: (j0, j1),
                    t: (tmin, tmax),
                    dir,
                    rays: mine_r,
                    bounds: mine_b,
                });
            }
        }
        let run = |w: Work<'_>| -> CutStats { w.run(&grid, parts) };
        if items.len() <= 2 {
            items
                .into_iter()
                .map(run)
                .fold(CutStats::default(), CutStats::merged)
        } else {
            items
                .into_par_iter()
                .map(run)
                .reduce(CutStats::default, CutStats::merged)
        }
    }
}

/// One row of tiles of one family, to be cut by one task.
struct Work<'a> {
    k: usize,
    u: usize,
    v: usize,
    tj: usize,
    ti0: usize,
    i: (usize, usize),
    j: (usize, usize),
    t: (f64, f64),
    dir: Vec3,
    rays: &'a mut [Dexel],
    bounds: &'a mut [[f64; 2]],
}

impl Work<'_> {
    fn run(self, grid: &Grid, parts: &[SweptConvex<'_>]) -> CutStats {
        let mut st = CutStats::default();
        let mut scratch = Scratch::new();
        let dcs: SmallVec<[_; 4]> = parts.iter().map(|p| p.dir_consts(self.dir)).collect();
        let (tmin, tmax) = self.t;
        for (tn, (tile, bound)) in self
            .rays
            .chunks_mut(TILE_RAYS)
            .zip(self.bounds.iter_mut())
            .enumerate()
        {
            if !(bound[0] < tmax && bound[1] > tmin) {
                continue;
            }
            let ti = self.ti0 + tn;
            // Material-first at tile level: skip the tile when no part's sweep can reach its
            // material range.
            let half = 0.5 * TILE as f64 * grid.h[self.u].max(grid.h[self.v]);
            let mut centre = Vec3::ZERO;
            centre[self.u] = grid.min[self.u]
                + (ti * TILE) as f64 * grid.h[self.u]
                + 0.5 * TILE as f64 * grid.h[self.u];
            centre[self.v] = grid.min[self.v]
                + (self.tj * TILE) as f64 * grid.h[self.v]
                + 0.5 * TILE as f64 * grid.h[self.v];
            let reach = parts.iter().any(|p| {
                p.block_range(self.k, centre, half)
                    .is_some_and(|(a, b)| bound[0] < b && bound[1] > a)
            });
            if !reach {
                continue;
            }
            let mut changed = false;
            for jj in 0..TILE {
                let j = self.tj * TILE + jj;
                if j < self.j.0 || j > self.j.1 {
                    continue;
                }
                let cv = grid.center(self.v, j);
                for ii in 0..TILE {
                    let i = ti * TILE + ii;
                    if i < self.i.0 || i > self.i.1 {
                        continue;
                    }
                    let d = &mut tile[jj * TILE + ii];
                    if !overlaps(d, tmin, tmax) {
                        continue;
                    }
                    st.visited_per_family[self.k] += 1;
                    let mut origin = Vec3::ZERO;
                    origin[self.u] = grid.center(self.u, i);
                    origin[self.v] = cv;
                    let mut removed = 0.0;
                    let mut tested = false;
                    for (p, dc) in parts.iter().zip(&dcs) {
                        // Material-first: a cheap range that holds the ray's part of this
                        // sweep; no overlap with the material, no geometry.
                        let Some((a, b)) = p.dexel_range(origin, self.k) else {
                            continue;
                        };
                        if d.is_empty() || !overlaps(d, a, b) {
                            continue;
                        }
                        tested = true;
                        let (m_lo, m_hi) = (d[0].enter.max(a), d[d.len() - 1].exit.min(b));
                        if let Some((lo, hi)) =
                            p.line_interval(origin, dc, Some((self.k, m_lo, m_hi)), &mut scratch)
                        {
                            removed += subtract(d, lo, hi);
                        }
                    }
                    if tested {
                        st.rays_tested += 1;
                        st.tested_per_family[self.k] += 1;
                    }
                    if removed > 0.0 {
                        st.updates += 1;
                        st.updates_per_family[self.k] += 1;
                        st.removed_length[self.k] += removed;
                        changed = true;
                    }
                }
            }
            if changed {
                *bound = tile_bound(tile);
            }
        }
        st
    }
}
