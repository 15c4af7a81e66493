//! The extraction proper, slab by slab along Z: the sign-changing lattice edges of each point
//! level along X and Y are found from its X lines (runs of inside points; X edges at the runs'
//! ends, Y edges where neighbouring lines' runs differ) with their crossings and normals, once
//! per level — a level is the top of one slab and the bottom of the next; phase 1 adds a slab's
//! Z edges (where the runs of its two levels differ), groups its edges by cell and places one
//! vertex per cell patch; phase 2 emits one quad per sign-changing edge, looking up the four
//! vertices around it. Levels and slabs run in parallel, in batches that bound the edges held
//! at once; scratch buffers are reused per worker, nothing is allocated per cell.
//!
//! The mesh is streamed: each batch's vertices join the mesh's array as its slabs are made,
//! a slab's triangles are made as soon as the slab above it exists (its quads reach into it)
//! and the slab is then dropped, and a projection onto an exact surface moves a slab's
//! vertices once no triangle still to come is split or given normals from their unprojected
//! positions. So besides the mesh itself only the line store and a batch of slabs (and the one
//! carried to the next batch) are held, not every slab's cells and edges until the end (the
//! peak of a large envelope was there).
//!
//! With merged blocks ([`ContourOptions::simplify`], module `blocks`), each batch first
//! decides the merged blocks of its pairs of slabs and of the pair above it (whose slab the
//! batch's top level reaches), then makes levels and slabs as above, skipping the cells of
//! merged blocks: an edge all of whose cells are merged is dropped, or kept without a crossing
//! where it gives a quad of four blocks. A pair's block vertices follow its lower slab's own,
//! and a vertex lookup asks the pair's map first.

use super::blocks::{decide, BlockMap, BlockScratch};
use super::lines::{boundary_in, in_runs, xor_runs, LevelRuns, Store};
use super::normal::estimate;
use super::qef::Qef;
use super::table::{cases, joined_faces, NONE};
use super::{ContourOptions, ContourStats, HermiteGrid, Lattice, Projection, QuadSplit};
use crate::mesh::{area_vectors_at, TriMesh};
use rayon::prelude::*;
use std::sync::Arc;
use swarf_geom::math::Vec3;

/// A sign-changing lattice edge from point `(i, j, k)` along `axis`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Edge {
    pub(crate) axis: u8,
    pub(crate) inside_low: bool,
    pub(crate) i: i32,
    pub(crate) j: i32,
    pub(crate) k: i32,
}

impl Edge {
    /// Where the edge's own line crosses the surface: the first interval end of the kind the
    /// edge needs (an exit when inside at its low end) within `slack` × the spacing of the
    /// edge, clamped onto it; `None` when the line has none there.
    pub(crate) fn crossing(&self, store: &Store, slack: f64) -> Option<f64> {
        let lat = &store.lattice;
        let a = self.axis as usize;
        let idx = [self.i, self.j, self.k];
        let (u, v) = (idx[(a + 1) % 3] as isize, idx[(a + 2) % 3] as isize);
        let lo = lat.coord(a, idx[a] as isize);
        let hi = lat.coord(a, idx[a] as isize + 1);
        let slack = slack * lat.spacing[a];
        boundary_in(
            store.fam[a].get(u, v),
            lo - slack,
            hi + slack,
            self.inside_low,
        )
        .map(|t| t.clamp(lo, hi))
    }

    /// The edge's middle, as a coordinate along its axis.
    pub(crate) fn middle(&self, lat: &Lattice) -> f64 {
        let a = self.axis as usize;
        let i = [self.i, self.j, self.k][a] as isize;
        0.5 * (lat.coord(a, i) + lat.coord(a, i + 1))
    }

    /// The (X, Y) indices of the cells around the edge in a slab it borders, and how many:
    /// the four of a Z edge's slab, two of an X or Y edge's in each slab beside its level.
    pub(crate) fn cells(&self) -> ([(i32, i32); 4], usize) {
        let (i, j) = (self.i, self.j);
        match self.axis {
            0 => ([(i, j - 1), (i, j), (i, j), (i, j)], 2),
            1 => ([(i - 1, j), (i, j), (i, j), (i, j)], 2),
            _ => ([(i - 1, j - 1), (i, j - 1), (i - 1, j), (i, j)], 4),
        }
    }

    /// True when the edge halves an edge of the coarse lattice of block corners (both its
    /// indices across its axis odd, see `blocks`).
    pub(crate) fn halves_coarse_edge(&self) -> bool {
        let (a, b) = match self.axis {
            0 => (self.j, self.k),
            1 => (self.i, self.k),
            _ => (self.i, self.j),
        };
        a & 1 == 1 && b & 1 == 1
    }

    /// The point at coordinate `t` along the edge's line.
    pub(crate) fn point_at(&self, lat: &Lattice, t: f64) -> Vec3 {
        let mut p = lat.point(self.i as isize, self.j as isize, self.k as isize);
        p[self.axis as usize] = t;
        p
    }
}

/// An edge with its crossing.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Hermite {
    pub(crate) edge: Edge,
    pub(crate) p: Vec3,
    pub(crate) n: Vec3,
    pub(crate) w: f64,
}

/// A cell with vertices: key `(ci + 1) + (n0 + 1)(cj + 1)`, case (corner mask and face rule
/// flips, see `table`), first vertex (slab-local).
#[derive(Clone, Copy, Debug)]
struct CellRec {
    key: u32,
    case: u16,
    first: u32,
}

struct SlabOut {
    cells: Vec<CellRec>,
    /// Where each row of cells (`cj + 1`) starts in `cells` (sorted by key, so by row), and
    /// the end: a vertex is looked up in its row only.
    rows: Vec<u32>,
    vertices: Vec<Vec3>,
    /// Index in the mesh of the slab's first vertex (set when its vertices join the mesh).
    base: u32,
    /// Edges whose quads this slab emits: Z edges from its low level, X and Y edges on its top level.
    owned: Vec<Edge>,
    /// With [`ContourOptions::simplify`]: the merged blocks of the slab's pair (their cells
    /// have no record in `cells`), and the mesh index of the pair's first block vertex (set
    /// when the pair's vertices join the mesh; they follow the cells' in the pair's lower
    /// slab, from `block_offset` in its list).
    blocks: Option<Arc<BlockMap>>,
    block_base: u32,
    block_offset: u32,
    stats: ContourStats,
}

/// The block maps of consecutive pairs of slabs, the first pair's lower slab `first` (odd).
struct Pairs {
    first: i32,
    maps: Vec<Arc<BlockMap>>,
}

impl Pairs {
    /// The map of the pair holding slab `k`.
    fn of(&self, k: i32) -> &BlockMap {
        &self.maps[((k - self.first) >> 1) as usize]
    }

    /// What becomes of edge `e`: `None` while a cell around it is not merged (its crossing
    /// is needed); once all are, `Some(true)` where it halves a coarse edge (kept, without a
    /// crossing, for its quad of four blocks) and `Some(false)` where it gives nothing.
    fn merged_edge(&self, e: Edge) -> Option<bool> {
        let (cells, n) = e.cells();
        let slabs = if e.axis == 2 {
            e.k..=e.k
        } else {
            e.k - 1..=e.k
        };
        let all = slabs.into_iter().all(|k| {
            let map = self.of(k);
            cells[..n].iter().all(|&(ci, cj)| map.merged(ci, cj))
        });
        all.then(|| e.halves_coarse_edge())
    }
}

/// The X and Y edges of one point level with their crossings: the top of one slab and the
/// bottom of the next, so computed once for both.
#[derive(Default)]
struct LevelEdges {
    edges: Vec<Hermite>,
    stats: ContourStats,
}

#[derive(Default)]
struct Scratch {
    /// Runs of the X lines at levels k, k + 1 (the slab's), k − 1 and k + 2 (for the
    /// neighbours across ambiguous faces).
    levels: [LevelRuns; 4],
    edges: Vec<Hermite>,
    pairs: Vec<u64>,
    found: Vec<(i32, bool)>,
}

impl Scratch {
    /// Where line `ja` of level slot `sa` and line `jb` of slot `sb` differ: the points
    /// inside one and not the other, and whether inside the first (the edges between two
    /// lines). The list is the scratch's own, taken: hand it back to `found` when done.
    fn differing(&mut self, (sa, ja): (usize, i32), (sb, jb): (usize, i32)) -> Vec<(i32, bool)> {
        let mut found = std::mem::take(&mut self.found);
        found.clear();
        xor_runs(
            self.levels[sa].line(ja),
            self.levels[sb].line(jb),
            |i, in_a| found.push((i, in_a)),
        );
        found
    }
}

struct Ctx<'a, G: ?Sized> {
    store: &'a Store,
    grid: &'a G,
    opt: &'a ContourOptions,
    n: [i32; 3],
}

impl<G: HermiteGrid + ?Sized> Ctx<'_, G> {
    fn key(&self, ci: i32, cj: i32) -> u32 {
        ((ci + 1) + (self.n[0] + 1) * (cj + 1)) as u32
    }

    /// Crossing point, unit normal (or zero) and weight of a sign-changing edge; `None` for the
    /// point when the edge's own line has no matching interval end.
    fn hermite(&self, e: Edge, t_known: Option<f64>, stats: &mut ContourStats) -> Hermite {
        let lat = &self.store.lattice;
        let a = e.axis as usize;
        let idx = [e.i, e.j, e.k];
        let exit = e.inside_low;
        let (u, v) = (idx[(a + 1) % 3] as isize, idx[(a + 2) % 3] as isize);
        let t = t_known.or_else(|| e.crossing(self.store, self.opt.crossing_slack));
        let Some(t) = t else {
            stats.fallback_crossings += 1;
            return Hermite {
                edge: e,
                p: e.point_at(lat, e.middle(lat)),
                n: Vec3::ZERO,
                w: 0.0,
            };
        };
        let p = e.point_at(lat, t);
        let mut axis_dir = Vec3::ZERO;
        axis_dir[a] = 1.0;
        let (n, w) = if !exit && t <= self.store.lo[a] {
            (-axis_dir, 1.0)
        } else if exit && t >= self.store.hi[a] {
            (axis_dir, 1.0)
        } else if let Some(n) = self
            .grid
            .normal(a, p)
            .filter(|n| n.is_finite() && n.length() > 0.0)
        {
            (n.normalize(), 1.0)
        } else if let Some(n) = estimate(self.store, a, u, v, t, exit, self.opt.max_slope) {
            let c = n[a].abs();
            let w = if self.opt.weight_power == 1.0 {
                c
            } else {
                c.powf(self.opt.weight_power)
            };
            (n, w)
        } else {
            stats.unknown_normals += 1;
            (Vec3::ZERO, 0.0)
        };
        Hermite { edge: e, p, n, w }
    }

    /// An X or Y edge of a point level: with its crossing, or (every cell around it merged)
    /// without one where it gives a quad of four blocks, or nothing.
    fn level_edge(
        &self,
        e: Edge,
        t: Option<f64>,
        pairs: Option<&Pairs>,
        stats: &mut ContourStats,
    ) -> Option<Hermite> {
        match pairs.and_then(|p| p.merged_edge(e)) {
            Some(keep) => keep.then(|| no_crossing(e)),
            None => Some(self.hermite(e, t, stats)),
        }
    }

    /// The X and Y edges of point level `lev` with their crossings (none outside the lattice),
    /// in the order the slabs take them: X edges line by line, then Y edges. With merged
    /// blocks (`pairs`), an edge all of whose cells are merged has no crossing computed and is
    /// kept only where it gives a quad: on an edge of the coarse lattice of block corners.
    fn level_edges(&self, lev: i32, s: &mut Scratch, pairs: Option<&Pairs>) -> LevelEdges {
        let [_, n1, n2] = self.n;
        let mut out = LevelEdges::default();
        if !(0..n2).contains(&lev) {
            return out;
        }
        s.levels[0].read(self.store, lev);
        // X edges: at both ends of every run.
        for j in 0..n1 {
            for &run in s.levels[0].line(j) {
                for (i, inside_low, t) in [(run.lo - 1, false, run.t_lo), (run.hi, true, run.t_hi)]
                {
                    let e = Edge {
                        axis: 0,
                        inside_low,
                        i,
                        j,
                        k: lev,
                    };
                    if let Some(h) = self.level_edge(e, Some(t), pairs, &mut out.stats) {
                        out.edges.push(h);
                    }
                }
            }
        }
        // Y edges: where the runs of neighbouring X lines differ.
        for j in -1..n1 {
            let found = s.differing((0, j), (0, j + 1));
            for &(i, inside_low) in &found {
                let e = Edge {
                    axis: 1,
                    inside_low,
                    i,
                    j,
                    k: lev,
                };
                if let Some(h) = self.level_edge(e, None, pairs, &mut out.stats) {
                    out.edges.push(h);
                }
            }
            s.found = found;
        }
        out
    }

    /// The cells and vertices of slab `k`, between point levels `k` and `k + 1` whose X and Y
    /// edges are `below` and `above`.
    fn phase1(
        &self,
        k: i32,
        s: &mut Scratch,
        below: &LevelEdges,
        above: &LevelEdges,
        pairs: Option<&Pairs>,
    ) -> SlabOut {
        let map = pairs.map(|p| p.of(k));
        let [n0, n1, _] = self.n;
        let lat = &self.store.lattice;
        let mut stats = ContourStats::default();
        // Runs of the X lines at levels k (slot 0), k + 1 (slot 1), k − 1 (2) and k + 2 (3).
        for (slot, &dk) in LEVEL_OFFSET.iter().enumerate() {
            s.levels[slot].read(self.store, k + dk);
        }
        s.edges.clear();
        s.pairs.clear();
        let mut owned = Vec::new();
        // Cells of merged blocks have no vertex of their own: no record, no QEF.
        let push = |s: &mut Scratch, h: Hermite, cells: &[(i32, i32)]| {
            let id = s.edges.len() as u64;
            s.edges.push(h);
            for &(ci, cj) in cells {
                if !map.is_some_and(|m| m.merged(ci, cj)) {
                    s.pairs.push((self.key(ci, cj) as u64) << 32 | id);
                }
            }
        };
        // X and Y edges of both levels, computed once per level; this slab emits the quads of
        // its top level's.
        for (slot, level) in [below, above].into_iter().enumerate() {
            for &h in &level.edges {
                let e = h.edge;
                let (cells, n) = e.cells();
                push(s, h, &cells[..n]);
                if slot == 1 {
                    owned.push(e);
                }
            }
        }
        // Z edges: where the runs of the two levels differ.
        for j in 0..n1 {
            let found = s.differing((0, j), (1, j));
            for &(i, inside_low) in &found {
                let e = Edge {
                    axis: 2,
                    inside_low,
                    i,
                    j,
                    k,
                };
                if let Some(keep) = pairs.and_then(|p| p.merged_edge(e)) {
                    // A quad of four blocks on a coarse edge, else nothing.
                    if keep {
                        owned.push(e);
                    }
                    continue;
                }
                let h = self.hermite(e, None, &mut stats);
                push(s, h, &e.cells().0);
                owned.push(e);
            }
            s.found = found;
        }
        s.pairs.sort_unstable();
        // Vertices, cell by cell.
        let table = cases();
        let mut cells = Vec::new();
        let mut vertices = Vec::new();
        let mut g = 0;
        while g < s.pairs.len() {
            let key = (s.pairs[g] >> 32) as u32;
            let mut end = g;
            while end < s.pairs.len() && (s.pairs[end] >> 32) as u32 == key {
                end += 1;
            }
            let ci = (key as i32) % (n0 + 1) - 1;
            let cj = (key as i32) / (n0 + 1) - 1;
            let mask_at = |s: &Scratch, ci: i32, cj: i32, dk: i32| -> u8 {
                let mut mask = 0u8;
                for c in 0..8usize {
                    let (dx, dy, dz) = ((c & 1) as i32, ((c >> 1) & 1) as i32, (c >> 2) as i32);
                    let slot = slot_of(dk + dz);
                    if in_runs(s.levels[slot].line(cj + dy), ci + dx) {
                        mask |= 1 << c;
                    }
                }
                mask
            };
            let mask = mask_at(s, ci, cj, 0);
            // Ambiguous faces whose crossings one patch joins here: use the other pairing on
            // them where the neighbour across joins them too (else the shared mesh edge would
            // be used by four triangles).
            let mut flips = 0u16;
            let joins = joined_faces(mask);
            if joins != 0 {
                for f in 0..3 {
                    for side in 0..2 {
                        let bit = 1u8 << (2 * f + side);
                        if joins & bit == 0 {
                            continue;
                        }
                        let step = 2 * side - 1;
                        let (mut ni, mut nj, mut nk) = (ci, cj, 0);
                        match f {
                            0 => ni += step,
                            1 => nj += step,
                            _ => nk += step,
                        }
                        let nmask = mask_at(s, ni, nj, nk);
                        let opposite = 1u8 << (2 * f + 1 - side);
                        if joined_faces(nmask) & opposite != 0 {
                            flips |= bit as u16;
                        }
                    }
                }
            }
            let case_index = mask as u16 | flips << 8;
            let case = &table[case_index as usize];
            let mut qefs = [Qef::default(); 4];
            let corner = lat.point(ci as isize, cj as isize, k as isize);
            for &pair in &s.pairs[g..end] {
                let h = &s.edges[(pair & 0xffff_ffff) as usize];
                let e = h.edge;
                let (dx, dy, dz) = (e.i - ci, e.j - cj, e.k - k);
                let local = match e.axis {
                    0 => dy + 2 * dz,
                    1 => 4 + dx + 2 * dz,
                    _ => 8 + dx + 2 * dy,
                } as usize;
                let patch = case.patch[local];
                debug_assert!(
                    patch != NONE,
                    "edge {e:?} not crossed in cell mask {mask:#b}"
                );
                if patch != NONE {
                    qefs[patch as usize].add(h.p - corner, h.n, h.w);
                }
            }
            cells.push(CellRec {
                key,
                case: case_index,
                first: vertices.len() as u32,
            });
            let size = lat.spacing;
            for q in &qefs[..case.count as usize] {
                let x = q.solve(self.opt.eigen_threshold);
                let inside_cell = x.cmpge(Vec3::ZERO).all() && x.cmple(size).all();
                if !inside_cell {
                    stats.clamped_vertices += 1;
                }
                let x = if self.opt.clamp_to_cell && !inside_cell {
                    x.clamp(Vec3::ZERO, size)
                } else {
                    x
                };
                vertices.push(corner + x);
            }
            g = end;
        }
        let mut rows = vec![0u32; n1 as usize + 3];
        for c in &cells {
            rows[(c.key / (n0 + 1) as u32) as usize + 1] += 1;
        }
        for r in 1..rows.len() {
            rows[r] += rows[r - 1];
        }
        stats.cells = cells.len();
        stats.vertices = vertices.len();
        // Thousands of slabs are held at once: no growth slack kept.
        cells.shrink_to_fit();
        vertices.shrink_to_fit();
        owned.shrink_to_fit();
        SlabOut {
            cells,
            rows,
            vertices,
            base: 0,
            owned,
            blocks: None,
            block_base: 0,
            block_offset: 0,
            stats,
        }
    }
}

/// Point levels computed at once per worker thread (a batch's edges are held until its slabs
/// are done).
const LEVELS_PER_THREAD: usize = 16;

/// Level of each run slot relative to the slab's `k`.
const LEVEL_OFFSET: [i32; 4] = [0, 1, -1, 2];

/// Slot of the runs of level `k + dk`, `dk ∈ −1..=2`.
fn slot_of(dk: i32) -> usize {
    match dk {
        0 => 0,
        1 => 1,
        -1 => 2,
        _ => 3,
    }
}

/// An edge kept for its quad of merged blocks only: its crossing is never read.
fn no_crossing(edge: Edge) -> Hermite {
    Hermite {
        edge,
        p: Vec3::ZERO,
        n: Vec3::ZERO,
        w: 0.0,
    }
}

/// Global index of the vertex of patch `local`'s edge in cell `key` of slab `k`; `window`
/// holds the slabs from `first_k` on.
fn vertex_of(window: &[SlabOut], first_k: i32, stride: u32, k: i32, key: u32, local: usize) -> u32 {
    let slab = &window[(k - first_k) as usize];
    if let Some(map) = &slab.blocks {
        let (ci, cj) = ((key % stride) as i32 - 1, (key / stride) as i32 - 1);
        if let Some(v) = map.vertex(ci, cj) {
            return slab.block_base + v;
        }
    }
    let row = (key / stride) as usize;
    let (a, b) = (slab.rows[row] as usize, slab.rows[row + 1] as usize);
    let c = a + slab.cells[a..b].partition_point(|c| c.key < key);
    let rec = slab.cells[c];
    debug_assert_eq!(rec.key, key);
    let p = cases()[rec.case as usize].patch[local];
    debug_assert!(p != NONE);
    slab.base + rec.first + p as u32
}

/// The triangles of the polygon around a sign-changing edge, written to `out`: the quad `q`
/// of the four cells' vertices as two triangles, or where merged blocks give two cells one
/// vertex, the triangle of the three distinct ones (none when fewer: the edge lies inside a
/// merged block or on the face between two). Returns how many.
fn polygon(q: [u32; 4], v: &[Vec3], mode: QuadSplit, out: &mut [[u32; 3]]) -> usize {
    if q[0] != q[1] && q[1] != q[2] && q[2] != q[3] && q[3] != q[0] {
        // Cells diagonal about an edge never share a block without the other two.
        debug_assert!(q[0] != q[2] && q[1] != q[3], "{q:?}");
        out[..2].copy_from_slice(&split_quad(q, v, mode));
        return 2;
    }
    let mut t = [0u32; 4];
    let mut n = 0;
    for i in 0..4 {
        if q[i] != q[(i + 3) % 4] {
            t[n] = q[i];
            n += 1;
        }
    }
    if n == 3 {
        out[0] = [t[0], t[1], t[2]];
        1
    } else {
        0
    }
}

/// The two triangles of quad `q`.
fn split_quad(q: [u32; 4], v: &[Vec3], mode: QuadSplit) -> [[u32; 3]; 2] {
    let p = q.map(|i| v[i as usize]);
    let first = || {
        let n1 = (p[1] - p[0]).cross(p[2] - p[0]);
        let n2 = (p[2] - p[0]).cross(p[3] - p[0]);
        n1.normalize_or_zero().dot(n2.normalize_or_zero())
    };
    let second = || {
        let n1 = (p[1] - p[0]).cross(p[3] - p[0]);
        let n2 = (p[2] - p[1]).cross(p[3] - p[1]);
        n1.normalize_or_zero().dot(n2.normalize_or_zero())
    };
    if mode == QuadSplit::Fixed || first() >= second() {
        [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
    } else {
        [[q[0], q[1], q[3]], [q[1], q[2], q[3]]]
    }
}

/// The mesh of the lines in `store`, slab by slab (see the module docs), with every vertex
/// moved by `project` (given its unit normal, area-weighted over its triangles) when there is
/// one. The mesh's arrays are filled as the slabs come: a slab's vertices join the mesh as it
/// is made, its triangles once the slab above it is made (their quads reach into it), and its
/// vertices are projected once the slab above it has its triangles (the last whose normals
/// use their unprojected positions); each slab is dropped as soon as its triangles are made,
/// so only a batch of slabs is held at once, not all of them.
pub(crate) fn extract<G: HermiteGrid + ?Sized>(
    store: Store,
    grid: &G,
    opt: &ContourOptions,
    project: Option<Projection<'_>>,
) -> (TriMesh, ContourStats) {
    let n = store.lattice.n.map(|x| x as i32);
    let ctx = Ctx {
        store: &store,
        grid,
        opt,
        n,
    };
    let mut mesh = Stream {
        vertices: Vec::new(),
        triangles: Vec::new(),
        tri_start: Vec::with_capacity(n[2] as usize + 2),
        vert_start: Vec::with_capacity(n[2] as usize + 2),
        normals: Vec::new(),
        with_normals: 0,
        projected_slabs: 0,
        projected: 0,
        stride: (n[0] + 1) as u32,
        n0: n[0],
    };
    // Slabs in batches: the levels a batch needs first (its bottom level kept from the batch
    // before), then its slabs, both in parallel; only a batch's levels are held at once.
    let batch = (LEVELS_PER_THREAD * rayon::current_num_threads()) as i32;
    let mut stats = ContourStats::default();
    let mut bottom: Option<LevelEdges> = None;
    // With merged blocks: the map of the pair above the last batch (its bottom level's edges
    // were kept or dropped by it), carried to the next.
    let mut ahead: Option<Arc<BlockMap>> = None;
    // Slabs made whose triangles are not (the last of the batch before), from slab `first_k`.
    let mut window: Vec<SlabOut> = Vec::new();
    let mut first_k = -1;
    let mut k0 = -1;
    while k0 < n[2] {
        let k1 = (k0 + batch).min(n[2]);
        let first = k0 + i32::from(bottom.is_some());
        // The batch's pairs of slabs (a batch starts at an odd slab and holds an even number
        // but for the last, whose top slab pairs with the empty one above the lattice) and the
        // pair above it, whose slab `k1` the top level's edges reach: their merged blocks,
        // decided before any level or slab is made.
        let pairs = opt.simplify.map(|tol| {
            let mut maps: Vec<Arc<BlockMap>> = ahead.take().into_iter().collect();
            let from = k0 + 2 * maps.len() as i32;
            let fresh: Vec<Arc<BlockMap>> = (from..=k1.min(n[2] - 1))
                .step_by(2)
                .collect::<Vec<i32>>()
                .into_par_iter()
                .map_init(BlockScratch::default, |s, k| {
                    // Crossings counted by the cells that use them: none here.
                    let mut uncounted = ContourStats::default();
                    let options = (
                        tol,
                        opt.crossing_slack,
                        opt.eigen_threshold,
                        opt.clamp_to_cell,
                    );
                    Arc::new(decide(&store, k, options, s, |e, t| {
                        ctx.hermite(e, t, &mut uncounted)
                    }))
                })
                .collect();
            maps.extend(fresh);
            Pairs { first: k0, maps }
        });
        let fresh: Vec<LevelEdges> = (first..=k1)
            .into_par_iter()
            .map_init(Scratch::default, |s, lev| {
                ctx.level_edges(lev, s, pairs.as_ref())
            })
            .collect();
        for l in &fresh {
            stats = stats.add(l.stats);
        }
        let levels: Vec<LevelEdges> = bottom.take().into_iter().chain(fresh).collect();
        let made: Vec<SlabOut> = (k0..k1)
            .into_par_iter()
            .map_init(Scratch::default, |s, k| {
                let at = (k - k0) as usize;
                let mut slab = ctx.phase1(k, s, &levels[at], &levels[at + 1], pairs.as_ref());
                if let Some(p) = &pairs {
                    let map = p.maps[((k - k0) >> 1) as usize].clone();
                    // The pair's block vertices follow its lower slab's own.
                    if (k - k0) % 2 == 0 {
                        slab.block_offset = slab.vertices.len() as u32;
                        slab.vertices.extend_from_slice(&map.vertices);
                        slab.stats.merged_blocks += map.vertices.len();
                        slab.stats.vertices = slab.vertices.len();
                    }
                    slab.blocks = Some(map);
                }
                slab
            })
            .collect();
        if let Some(p) = pairs.filter(|_| k1 < n[2]) {
            // The pair above the batch: the next batch's first.
            ahead = p.maps.into_iter().nth(((k1 - k0) >> 1) as usize);
        }
        bottom = levels.into_iter().last();
        let mut pair_block_base = 0;
        for (at, mut slab) in made.into_iter().enumerate() {
            stats = stats.add(slab.stats);
            slab.base = mesh.vertices.len() as u32;
            if at % 2 == 0 {
                pair_block_base = slab.base + slab.block_offset;
            }
            slab.block_base = pair_block_base;
            mesh.vert_start.push(mesh.vertices.len());
            mesh.vertices.append(&mut slab.vertices);
            slab.vertices = Vec::new();
            window.push(slab);
        }
        // A slab's quads reach into the slab above it: all but the last slab made have them
        // now, and the last too once it is the top one.
        let ready = if k1 == n[2] {
            window.len()
        } else {
            window.len() - 1
        };
        mesh.triangles_of(&window[..], first_k, ready, opt.split);
        // Merged blocks put a vertex into triangles of three slabs, not two: their meshes
        // are projected whole, at the end (with `TriMesh::vertex_normals`).
        if let (Some(project), None) = (project, opt.simplify) {
            mesh.normals_and_projection(k1 == n[2], project);
        }
        window.drain(..ready);
        first_k += ready as i32;
        k0 = k1;
    }
    stats.lines = store.line_count();
    stats.spans = store.span_count();
    stats.triangles = mesh.triangles.len();
    stats.projected_vertices = mesh.projected;
    drop(store);
    let Stream {
        mut vertices,
        mut triangles,
        ..
    } = mesh;
    vertices.shrink_to_fit();
    triangles.shrink_to_fit();
    let mut mesh = TriMesh::from_parts(vertices, triangles);
    if let (Some(project), Some(_)) = (project, opt.simplify) {
        let normals = mesh.vertex_normals();
        stats.projected_vertices += project_vertices(&mut mesh.vertices, &normals, project);
    }
    (mesh, stats)
}

/// The mesh as the slabs fill it.
struct Stream {
    vertices: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    /// Where each slab's triangles start in `triangles` (slab order; one entry per slab whose
    /// triangles are made).
    tri_start: Vec<usize>,
    /// Where each slab's vertices start in `vertices` (one entry per slab made).
    vert_start: Vec<usize>,
    /// Unit normals of the vertices of the slabs from `projected_slabs` to `with_normals`.
    normals: Vec<Vec3>,
    with_normals: usize,
    /// Slabs whose vertices are projected, and the vertices moved.
    projected_slabs: usize,
    projected: usize,
    stride: u32,
    n0: i32,
}

impl Stream {
    /// Appends the triangles of the first `ready` slabs of `window` (which starts at slab
    /// `first_k` and holds the slab above each of them), each slab's in parallel into its own
    /// stretch (two triangles an edge at most: fewer where merged blocks share vertices).
    fn triangles_of(&mut self, window: &[SlabOut], first_k: i32, ready: usize, split: QuadSplit) {
        let (n0, stride) = (self.n0, self.stride);
        let key = |ci: i32, cj: i32| ((ci + 1) + (n0 + 1) * (cj + 1)) as u32;
        const AROUND: [(i32, i32); 4] = [(-1, -1), (0, -1), (0, 0), (-1, 0)];
        let start = self.triangles.len();
        let added: usize = window[..ready].iter().map(|s| 2 * s.owned.len()).sum();
        self.triangles.resize(start + added, [0; 3]);
        let mut stretches: Vec<(i32, &mut [[u32; 3]])> = Vec::with_capacity(ready);
        let mut rest = &mut self.triangles[start..];
        for (at, slab) in window[..ready].iter().enumerate() {
            let (mine, after) = rest.split_at_mut(2 * slab.owned.len());
            stretches.push((first_k + at as i32, mine));
            rest = after;
        }
        let vertices = &self.vertices;
        let made: Vec<usize> = stretches
            .into_par_iter()
            .map(|(k, out)| {
                let owned = &window[(k - first_k) as usize].owned;
                let mut made = 0;
                for &e in owned {
                    let q = AROUND.map(|(db, dc)| match e.axis {
                        0 => vertex_of(
                            window,
                            first_k,
                            stride,
                            e.k + dc,
                            key(e.i, e.j + db),
                            (-db - 2 * dc) as usize,
                        ),
                        1 => vertex_of(
                            window,
                            first_k,
                            stride,
                            e.k + db,
                            key(e.i + dc, e.j),
                            (4 - dc - 2 * db) as usize,
                        ),
                        _ => vertex_of(
                            window,
                            first_k,
                            stride,
                            k,
                            key(e.i + db, e.j + dc),
                            (8 - db - 2 * dc) as usize,
                        ),
                    });
                    let q = if e.inside_low {
                        q
                    } else {
                        [q[3], q[2], q[1], q[0]]
                    };
                    made += polygon(q, vertices, split, &mut out[made..]);
                }
                made
            })
            .collect();
        // Each slab's triangles moved down over the room its stretch did not use.
        let mut to = start;
        let mut from = start;
        for (slab, n) in window[..ready].iter().zip(made) {
            self.tri_start.push(to);
            if from != to {
                self.triangles.copy_within(from..from + n, to);
            }
            to += n;
            from += 2 * slab.owned.len();
        }
        self.triangles.truncate(to);
    }

    /// Normals of the vertices of the slabs that have their triangles now, then the
    /// projection of those vertices that no triangle still to come is made from (all of them
    /// when `all`). A slab's vertices are used by its own triangles and the slab below's:
    /// their normals sum those triangles' area vectors in mesh order, as
    /// `TriMesh::vertex_normals` does with every vertex still where the contouring put it —
    /// so a slab is projected only once the slab above it has its normals (its triangles
    /// reach into it).
    fn normals_and_projection(&mut self, all: bool, project: Projection<'_>) {
        let with_triangles = self.tri_start.len();
        // Slab `s`'s stretch of an array whose slabs start at `starts` and end at `len`.
        let stretch = |starts: &[usize], len: usize, s: usize| {
            starts[s]..starts.get(s + 1).copied().unwrap_or(len)
        };
        let slab_vertices = |st: &Stream, s: usize| stretch(&st.vert_start, st.vertices.len(), s);
        let slab_triangles = |st: &Stream, s: usize| stretch(&st.tri_start, st.triangles.len(), s);
        let fresh: Vec<Vec<Vec3>> = (self.with_normals..with_triangles)
            .into_par_iter()
            .map(|s| {
                let below = if s > 0 {
                    slab_triangles(self, s - 1).start
                } else {
                    0
                };
                let around = &self.triangles[below..slab_triangles(self, s).end];
                let mut sum = area_vectors_at(&self.vertices, around, slab_vertices(self, s));
                for v in &mut sum {
                    *v = v.normalize_or_zero();
                }
                sum
            })
            .collect();
        self.normals.extend(fresh.into_iter().flatten());
        self.with_normals = with_triangles;
        // Every slab with normals but the last, whose positions the next slab's normals use.
        let upto = if all {
            with_triangles
        } else {
            with_triangles.saturating_sub(1)
        };
        if upto <= self.projected_slabs {
            return;
        }
        let from = self.vert_start[self.projected_slabs];
        let to = slab_vertices(self, upto - 1).end;
        let normals = self.normals.drain(..to - from);
        self.projected +=
            project_vertices(&mut self.vertices[from..to], normals.as_slice(), project);
        drop(normals);
        self.projected_slabs = upto;
    }
}

/// Moves each vertex where `project` says, given its unit normal (none moved without one);
/// returns how many moved.
fn project_vertices(vertices: &mut [Vec3], normals: &[Vec3], project: Projection<'_>) -> usize {
    vertices
        .par_iter_mut()
        .zip(normals.par_iter())
        .map(|(v, &n)| match project(*v, n) {
            Some(p) if n != Vec3::ZERO => {
                *v = p;
                1
            }
            _ => 0,
        })
        .sum()
}
