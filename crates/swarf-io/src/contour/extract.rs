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

use super::lines::{boundary_in, in_runs, runs, xor_runs, Run, Store};
use super::normal::estimate;
use super::qef::Qef;
use super::table::{cases, has_ambiguous_face, joined_faces, NONE};
use super::{ContourOptions, ContourStats, HermiteGrid, Projection, QuadSplit};
use crate::mesh::{area_vectors_at, TriMesh};
use rayon::prelude::*;
use swarf_geom::math::Vec3;

/// A sign-changing lattice edge from point `(i, j, k)` along `axis`.
#[derive(Clone, Copy, Debug)]
struct Edge {
    axis: u8,
    inside_low: bool,
    i: i32,
    j: i32,
    k: i32,
}

/// An edge with its crossing.
#[derive(Clone, Copy, Debug)]
struct Hermite {
    edge: Edge,
    p: Vec3,
    n: Vec3,
    w: f64,
}

/// A cell with vertices: key `(ci + 1) + (n0 + 1)(cj + 1)`, case (corner mask and face rule
/// flips, see `table`), first vertex (slab-local; the mesh's own index when `global`: a cell of
/// a merged block whose vertex is in the slab below).
#[derive(Clone, Copy, Debug)]
struct CellRec {
    key: u32,
    case: u16,
    global: bool,
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
    /// With [`ContourOptions::simplify`], until the slab's blocks are merged: per cell, its
    /// patch's QEF (relative to the cell's low corner) when the cell may join a merged block
    /// (one patch, no ambiguous face).
    qefs: Vec<Option<Qef>>,
    stats: ContourStats,
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
    /// neighbours across ambiguous faces), and their offsets per line.
    runs: [Vec<Run>; 4],
    roff: [Vec<usize>; 4],
    edges: Vec<Hermite>,
    pairs: Vec<u64>,
    found: Vec<(i32, bool)>,
}

impl Scratch {
    /// Where the runs `a` and `b` (a slot and a range of its runs each) differ: the points
    /// inside one and not the other, and whether inside `a` (the edges between two lines).
    /// The list is the scratch's own, taken: hand it back to `found` when done.
    fn differing(
        &mut self,
        (sa, ra): (usize, std::ops::Range<usize>),
        (sb, rb): (usize, std::ops::Range<usize>),
    ) -> Vec<(i32, bool)> {
        let mut found = std::mem::take(&mut self.found);
        found.clear();
        xor_runs(&self.runs[sa][ra], &self.runs[sb][rb], |i, in_a| {
            found.push((i, in_a))
        });
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
        let lo = lat.coord(a, idx[a] as isize);
        let hi = lat.coord(a, idx[a] as isize + 1);
        let spans = self.store.fam[a].get(u, v);
        let slack = self.opt.crossing_slack * lat.spacing[a];
        let t = t_known
            .or_else(|| boundary_in(spans, lo - slack, hi + slack, exit).map(|t| t.clamp(lo, hi)));
        let mut p = lat.point(e.i as isize, e.j as isize, e.k as isize);
        let Some(t) = t else {
            stats.fallback_crossings += 1;
            p[a] = 0.5 * (lo + hi);
            return Hermite {
                edge: e,
                p,
                n: Vec3::ZERO,
                w: 0.0,
            };
        };
        p[a] = t;
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

    /// The X and Y edges of point level `lev` with their crossings (none outside the lattice),
    /// in the order the slabs take them: X edges line by line, then Y edges.
    fn level_edges(&self, lev: i32, s: &mut Scratch) -> LevelEdges {
        let [_, n1, n2] = self.n;
        let mut out = LevelEdges::default();
        if !(0..n2).contains(&lev) {
            return out;
        }
        let lat = &self.store.lattice;
        s.runs[0].clear();
        s.roff[0].clear();
        s.roff[0].push(0);
        for j in 0..n1 {
            runs(
                self.store.fam[0].get(j as isize, lev as isize),
                lat,
                0,
                &mut s.runs[0],
            );
            s.roff[0].push(s.runs[0].len());
        }
        let line = |s: &Scratch, j: i32| -> std::ops::Range<usize> {
            if j < 0 || j >= n1 {
                0..0
            } else {
                s.roff[0][j as usize]..s.roff[0][j as usize + 1]
            }
        };
        // X edges: at both ends of every run.
        for j in 0..n1 {
            for ri in line(s, j) {
                let run = s.runs[0][ri];
                for (i, inside_low, t) in [(run.lo - 1, false, run.t_lo), (run.hi, true, run.t_hi)]
                {
                    let e = Edge {
                        axis: 0,
                        inside_low,
                        i,
                        j,
                        k: lev,
                    };
                    out.edges.push(self.hermite(e, Some(t), &mut out.stats));
                }
            }
        }
        // Y edges: where the runs of neighbouring X lines differ.
        for j in -1..n1 {
            let (ra, rb) = (line(s, j), line(s, j + 1));
            let found = s.differing((0, ra), (0, rb));
            for &(i, inside_low) in &found {
                let e = Edge {
                    axis: 1,
                    inside_low,
                    i,
                    j,
                    k: lev,
                };
                out.edges.push(self.hermite(e, None, &mut out.stats));
            }
            s.found = found;
        }
        out
    }

    /// The cells and vertices of slab `k`, between point levels `k` and `k + 1` whose X and Y
    /// edges are `below` and `above`.
    fn phase1(&self, k: i32, s: &mut Scratch, below: &LevelEdges, above: &LevelEdges) -> SlabOut {
        let [n0, n1, n2] = self.n;
        let lat = &self.store.lattice;
        let mut stats = ContourStats::default();
        // Runs of the X lines at levels k (slot 0), k + 1 (slot 1), k − 1 (2) and k + 2 (3).
        for (slot, &dk) in LEVEL_OFFSET.iter().enumerate() {
            let lev = k + dk;
            s.runs[slot].clear();
            s.roff[slot].clear();
            s.roff[slot].push(0);
            for j in 0..n1 {
                if (0..n2).contains(&lev) {
                    runs(
                        self.store.fam[0].get(j as isize, lev as isize),
                        lat,
                        0,
                        &mut s.runs[slot],
                    );
                }
                s.roff[slot].push(s.runs[slot].len());
            }
        }
        let line = |s: &Scratch, slot: usize, j: i32| -> std::ops::Range<usize> {
            if j < 0 || j >= n1 {
                0..0
            } else {
                s.roff[slot][j as usize]..s.roff[slot][j as usize + 1]
            }
        };
        s.edges.clear();
        s.pairs.clear();
        let mut owned = Vec::new();
        let push = |s: &mut Scratch, h: Hermite, cells: &[(i32, i32)]| {
            let id = s.edges.len() as u64;
            s.edges.push(h);
            for &(ci, cj) in cells {
                s.pairs.push((self.key(ci, cj) as u64) << 32 | id);
            }
        };
        // X and Y edges of both levels, computed once per level; this slab emits the quads of
        // its top level's.
        for (slot, level) in [below, above].into_iter().enumerate() {
            for &h in &level.edges {
                let e = h.edge;
                let cells = if e.axis == 0 {
                    [(e.i, e.j - 1), (e.i, e.j)]
                } else {
                    [(e.i - 1, e.j), (e.i, e.j)]
                };
                push(s, h, &cells);
                if slot == 1 {
                    owned.push(e);
                }
            }
        }
        // Z edges: where the runs of the two levels differ.
        for j in 0..n1 {
            let (ra, rb) = (line(s, 0, j), line(s, 1, j));
            let found = s.differing((0, ra), (1, rb));
            for &(i, inside_low) in &found {
                let e = Edge {
                    axis: 2,
                    inside_low,
                    i,
                    j,
                    k,
                };
                let h = self.hermite(e, None, &mut stats);
                push(s, h, &[(i - 1, j - 1), (i, j - 1), (i - 1, j), (i, j)]);
                owned.push(e);
            }
            s.found = found;
        }
        s.pairs.sort_unstable();
        // Vertices, cell by cell.
        let table = cases();
        let mut cells = Vec::new();
        let mut vertices = Vec::new();
        let mut qef_of_cell = Vec::new();
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
                    let r = line(s, slot, cj + dy);
                    if in_runs(&s.runs[slot][r], ci + dx) {
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
            if self.opt.simplify.is_some() {
                let may_merge = case.count == 1 && flips == 0 && !has_ambiguous_face(mask);
                qef_of_cell.push(may_merge.then_some(qefs[0]));
            }
            cells.push(CellRec {
                key,
                case: case_index,
                global: false,
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
            qefs: qef_of_cell,
            stats,
        }
    }

    /// Merges the 2 × 2 × 2 blocks of cells of slabs `k` (`lo`) and `k + 1` (`hi`) that pass
    /// the tests of [`ContourOptions::simplify`] (tolerance `tol`) into one vertex each, kept
    /// in `lo`'s list; `hi`'s cells of a merged block point to it with the index `lo`'s base
    /// will add to (`global`, see `extract`). `s` is `phase1(k)`'s scratch: the X lines' runs
    /// of point levels `k`, `k + 1` and `k + 2` (slots 0, 1, 3). Blocks are aligned on cells
    /// `2b − 1, 2b` along each axis (`k` is odd).
    fn merge_pair(&self, k: i32, s: &Scratch, lo: &mut SlabOut, hi: &mut SlabOut, tol: f64) {
        let [n0, n1, _] = self.n;
        let lat = &self.store.lattice;
        let stride = (n0 + 1) as u32;
        let bstride = (n0 + 3) as u64;
        // Each cell of the two slabs filed under its block: block key, slab, index.
        let mut members: Vec<u64> = Vec::with_capacity(lo.cells.len() + hi.cells.len());
        for (si, slab) in [&*lo, &*hi].into_iter().enumerate() {
            for (at, c) in slab.cells.iter().enumerate() {
                let (ip, jp) = ((c.key % stride) as u64, (c.key / stride) as u64);
                let b = (ip >> 1) + bstride * (jp >> 1);
                members.push(b << 33 | (si as u64) << 32 | at as u64);
            }
        }
        members.sort_unstable();
        const SLOT: [usize; 3] = [0, 1, 3];
        let inside = |i: i32, j: i32, dl: usize| -> bool {
            if j < 0 || j >= n1 {
                return false;
            }
            let slot = SLOT[dl];
            let r = s.roff[slot][j as usize]..s.roff[slot][j as usize + 1];
            in_runs(&s.runs[slot][r], i)
        };
        // Per slab and cell: the merged vertex it takes (index in `merged`), if any.
        let mut redirect = [
            vec![u32::MAX; lo.cells.len()],
            vec![u32::MAX; hi.cells.len()],
        ];
        let mut merged: Vec<Vec3> = Vec::new();
        let size = 2.0 * lat.spacing;
        let mut g = 0;
        while g < members.len() {
            let block = members[g] >> 33;
            let mut end = g + 1;
            while end < members.len() && members[end] >> 33 == block {
                end += 1;
            }
            let group = &members[g..end];
            g = end;
            // One cell alone gains nothing; every cell must have one patch.
            let cell = |m: u64| ((m >> 32 & 1) as usize, (m & 0xffff_ffff) as usize);
            let qef_of = |m: u64| {
                let (si, at) = cell(m);
                [&*lo, &*hi][si].qefs[at]
            };
            if group.len() < 2 || group.iter().any(|&m| qef_of(m).is_none()) {
                continue;
            }
            let (bi, bj) = ((block % bstride) as i32, (block / bstride) as i32);
            let (i0, j0) = (2 * bi - 1, 2 * bj - 1);
            // Sides of the block's 27 lattice points, (x, y, z) ∈ {0, 1, 2}³.
            let side = |x: usize, y: usize, z: usize| inside(i0 + x as i32, j0 + y as i32, z);
            let mut sides = [[[false; 3]; 3]; 3];
            for (x, plane) in sides.iter_mut().enumerate() {
                for (y, line) in plane.iter_mut().enumerate() {
                    for (z, v) in line.iter_mut().enumerate() {
                        *v = side(x, y, z);
                    }
                }
            }
            if !topology_safe(&sides) {
                continue;
            }
            let corner = lat.point(i0 as isize, j0 as isize, k as isize);
            let mut q = Qef::default();
            for &m in group {
                let (si, at) = cell(m);
                let key = [&*lo, &*hi][si].cells[at].key;
                let (ci, cj) = ((key % stride) as i32 - 1, (key / stride) as i32 - 1);
                let own = lat.point(ci as isize, cj as isize, (k + si as i32) as isize);
                q.merge(&qef_of(m).expect("checked above").shifted(own - corner));
            }
            let x = q.solve(self.opt.eigen_threshold);
            let x = if self.opt.clamp_to_cell {
                x.clamp(Vec3::ZERO, size)
            } else {
                x
            };
            if !q.rms_distance(x).is_some_and(|d| d <= tol) {
                continue;
            }
            // Planes that meet in a line or a point far from the cells' own vertices (a
            // surface sampled by too few crossings for a block: two planes always meet) do not
            // make a vertex of the surface: it must lie among theirs.
            let x = corner + x;
            let (mut lo_v, mut hi_v) = (Vec3::splat(f64::INFINITY), Vec3::splat(f64::NEG_INFINITY));
            for &m in group {
                let (si, at) = cell(m);
                let slab = [&*lo, &*hi][si];
                let v = slab.vertices[slab.cells[at].first as usize];
                (lo_v, hi_v) = (lo_v.min(v), hi_v.max(v));
            }
            if x.cmplt(lo_v - Vec3::splat(tol)).any() || x.cmpgt(hi_v + Vec3::splat(tol)).any() {
                continue;
            }
            for &m in group {
                let (si, at) = cell(m);
                redirect[si][at] = merged.len() as u32;
            }
            merged.push(x);
        }
        lo.stats.merged_blocks += merged.len();
        // Each slab's list: the vertices of its cells that were not merged, then (in `lo`)
        // the merged ones.
        let table = cases();
        let [lo_to, hi_to] = redirect;
        for (slab, to) in [(&mut *lo, &lo_to), (&mut *hi, &hi_to)] {
            let mut kept = Vec::with_capacity(slab.vertices.len());
            for (c, &t) in slab.cells.iter_mut().zip(to) {
                if t == u32::MAX {
                    let count = table[c.case as usize].count as usize;
                    let first = c.first as usize;
                    c.first = kept.len() as u32;
                    kept.extend_from_slice(&slab.vertices[first..first + count]);
                }
            }
            slab.vertices = kept;
        }
        let at = lo.vertices.len() as u32;
        lo.vertices.extend_from_slice(&merged);
        lo.vertices.shrink_to_fit();
        hi.vertices.shrink_to_fit();
        for (c, &t) in lo.cells.iter_mut().zip(&lo_to) {
            if t != u32::MAX {
                c.first = at + t;
            }
        }
        for (c, &t) in hi.cells.iter_mut().zip(&hi_to) {
            if t != u32::MAX {
                c.first = at + t;
                c.global = true;
            }
        }
        lo.qefs = Vec::new();
        hi.qefs = Vec::new();
    }
}

/// Ju et al.'s (2002) test that a 2 × 2 × 2 block's contour may be one vertex: the corners
/// (`sides[x][y][z]` at even coordinates) make a single patch with no ambiguous face, and every
/// other lattice point of the block — the middles of its edges and faces, its centre — has the
/// side of at least one of the corners around it (those with each of its middle coordinates
/// set to either end). The cells' own test (one patch each) is the caller's.
fn topology_safe(sides: &[[[bool; 3]; 3]; 3]) -> bool {
    let at = |p: [usize; 3]| sides[p[0]][p[1]][p[2]];
    let mask = (0..8usize).fold(0u8, |m, c| {
        let p = [2 * (c & 1), 2 * ((c >> 1) & 1), 2 * (c >> 2)];
        m | u8::from(at(p)) << c
    });
    if cases()[mask as usize].count != 1 || has_ambiguous_face(mask) {
        return false;
    }
    for index in 0..27usize {
        let p = [index % 3, (index / 3) % 3, index / 9];
        let middle: [bool; 3] = p.map(|v| v == 1);
        if !middle.contains(&true) {
            continue;
        }
        let side = at(p);
        // The corners around `p`: each middle coordinate at 0 or 2, the others as they are.
        let agrees = (0..8usize).any(|bits| {
            let mut q = p;
            for axis in 0..3 {
                if middle[axis] {
                    q[axis] = 2 * (bits >> axis & 1);
                } else if bits >> axis & 1 == 1 {
                    return false; // the same corner as with this bit clear
                }
            }
            at(q) == side
        });
        if !agrees {
            return false;
        }
    }
    true
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

/// Global index of the vertex of patch `local`'s edge in cell `key` of slab `k`; `window`
/// holds the slabs from `first_k` on.
fn vertex_of(window: &[SlabOut], first_k: i32, stride: u32, k: i32, key: u32, local: usize) -> u32 {
    let slab = &window[(k - first_k) as usize];
    let row = (key / stride) as usize;
    let (a, b) = (slab.rows[row] as usize, slab.rows[row + 1] as usize);
    let c = a + slab.cells[a..b].partition_point(|c| c.key < key);
    let rec = slab.cells[c];
    debug_assert_eq!(rec.key, key);
    let p = cases()[rec.case as usize].patch[local];
    debug_assert!(p != NONE);
    if rec.global {
        // A merged block's single vertex (its cells have one patch each: `p` is 0).
        return rec.first;
    }
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
    // Slabs made whose triangles are not (the last of the batch before), from slab `first_k`.
    let mut window: Vec<SlabOut> = Vec::new();
    let mut first_k = -1;
    let mut k0 = -1;
    while k0 < n[2] {
        let k1 = (k0 + batch).min(n[2]);
        let first = k0 + i32::from(bottom.is_some());
        let fresh: Vec<LevelEdges> = (first..=k1)
            .into_par_iter()
            .map_init(Scratch::default, |s, lev| ctx.level_edges(lev, s))
            .collect();
        for l in &fresh {
            stats = stats.add(l.stats);
        }
        let levels: Vec<LevelEdges> = bottom.take().into_iter().chain(fresh).collect();
        let made: Vec<SlabOut> = match opt.simplify {
            None => (k0..k1)
                .into_par_iter()
                .map_init(Scratch::default, |s, k| {
                    let at = (k - k0) as usize;
                    ctx.phase1(k, s, &levels[at], &levels[at + 1])
                })
                .collect(),
            // Slabs in pairs (a batch starts at an odd slab and holds an even number but for
            // the last), each pair's blocks merged as soon as both are made.
            Some(tol) => {
                let pairs: Vec<Vec<SlabOut>> = (k0..k1)
                    .step_by(2)
                    .collect::<Vec<i32>>()
                    .into_par_iter()
                    .map_init(
                        || (Scratch::default(), Scratch::default()),
                        |(sa, sb), k| {
                            let at = (k - k0) as usize;
                            let mut lo = ctx.phase1(k, sa, &levels[at], &levels[at + 1]);
                            if k + 1 == k1 {
                                // The top slab, alone when the slabs are odd in number: paired
                                // with the empty one above the lattice, so that its blocks
                                // merge too (a stock's uncut top face lies in it).
                                let empty = LevelEdges::default();
                                let mut above = ctx.phase1(k + 1, sb, &levels[at + 1], &empty);
                                ctx.merge_pair(k, sa, &mut lo, &mut above, tol);
                                debug_assert!(above.cells.is_empty());
                                return vec![lo];
                            }
                            let mut hi = ctx.phase1(k + 1, sb, &levels[at + 1], &levels[at + 2]);
                            ctx.merge_pair(k, sa, &mut lo, &mut hi, tol);
                            vec![lo, hi]
                        },
                    )
                    .collect();
                pairs.into_iter().flatten().collect()
            }
        };
        bottom = levels.into_iter().last();
        let mut below_base = 0;
        for mut slab in made {
            stats = stats.add(slab.stats);
            slab.base = mesh.vertices.len() as u32;
            // A merged block's cells in the upper slab of a pair point into the lower slab's
            // list, the slab just before.
            for c in slab.cells.iter_mut().filter(|c| c.global) {
                c.first += below_base;
            }
            below_base = slab.base;
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
