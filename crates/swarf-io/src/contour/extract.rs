//! The extraction proper, slab by slab along Z: the sign-changing lattice edges of each point
//! level along X and Y are found from its X lines (runs of inside points; X edges at the runs'
//! ends, Y edges where neighbouring lines' runs differ) with their crossings and normals, once
//! per level — a level is the top of one slab and the bottom of the next; phase 1 adds a slab's
//! Z edges (where the runs of its two levels differ), groups its edges by cell and places one
//! vertex per cell patch; phase 2 emits one quad per sign-changing edge, looking up the four
//! vertices around it. Levels and slabs run in parallel, in batches that bound the edges held
//! at once; scratch buffers are reused per worker, nothing is allocated per cell.

use super::lines::{boundary_in, in_runs, runs, xor_runs, Run, Store};
use super::normal::estimate;
use super::qef::Qef;
use super::table::{cases, joined_faces, NONE};
use super::{ContourOptions, ContourStats, HermiteGrid, QuadSplit};
use crate::mesh::TriMesh;
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
    /// Edges whose quads this slab emits: Z edges from its low level, X and Y edges on its top level.
    owned: Vec<Edge>,
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
            owned,
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

/// Index of slab `k` (cells with z index `k ∈ −1..n2`) in the slab list.
fn slab_index(k: i32) -> usize {
    (k + 1) as usize
}

fn vertex_of(slabs: &[SlabOut], base: &[u32], stride: u32, k: i32, key: u32, local: usize) -> u32 {
    let s = slab_index(k);
    let slab = &slabs[s];
    let row = (key / stride) as usize;
    let (a, b) = (slab.rows[row] as usize, slab.rows[row + 1] as usize);
    let c = a + slab.cells[a..b].partition_point(|c| c.key < key);
    let rec = slab.cells[c];
    debug_assert_eq!(rec.key, key);
    let p = cases()[rec.case as usize].patch[local];
    debug_assert!(p != NONE);
    base[s] + rec.first + p as u32
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

pub(crate) fn extract<G: HermiteGrid + ?Sized>(
    store: Store,
    grid: &G,
    opt: &ContourOptions,
) -> (TriMesh, ContourStats) {
    let n = store.lattice.n.map(|x| x as i32);
    let ctx = Ctx {
        store: &store,
        grid,
        opt,
        n,
    };
    // Slabs in batches: the levels a batch needs first (its bottom level kept from the batch
    // before), then its slabs, both in parallel; only a batch's levels are held at once.
    let batch = (LEVELS_PER_THREAD * rayon::current_num_threads()) as i32;
    let mut slabs: Vec<SlabOut> = Vec::with_capacity(n[2] as usize + 1);
    let mut level_stats = ContourStats::default();
    let mut bottom: Option<LevelEdges> = None;
    let mut k0 = -1;
    while k0 < n[2] {
        let k1 = (k0 + batch).min(n[2]);
        let first = k0 + i32::from(bottom.is_some());
        let fresh: Vec<LevelEdges> = (first..=k1)
            .into_par_iter()
            .map_init(Scratch::default, |s, lev| ctx.level_edges(lev, s))
            .collect();
        for l in &fresh {
            level_stats = level_stats.add(l.stats);
        }
        let levels: Vec<LevelEdges> = bottom.take().into_iter().chain(fresh).collect();
        slabs.par_extend((k0..k1).into_par_iter().map_init(Scratch::default, |s, k| {
            let at = (k - k0) as usize;
            ctx.phase1(k, s, &levels[at], &levels[at + 1])
        }));
        bottom = levels.into_iter().last();
        k0 = k1;
    }
    // The triangles need only the slabs: the lines go before the mesh's arrays are made.
    let (lines, spans) = (store.line_count(), store.span_count());
    drop(store);
    let mut base = Vec::with_capacity(slabs.len() + 1);
    base.push(0u32);
    for s in &slabs {
        base.push(base.last().copied().unwrap_or(0) + s.vertices.len() as u32);
    }
    // The slabs' vertices moved into one array, each slab's freed as it is copied (the peak
    // of a large mesh is here).
    let mut vertices: Vec<Vec3> = Vec::with_capacity(base[slabs.len()] as usize);
    for s in &mut slabs {
        vertices.append(&mut s.vertices);
        s.vertices = Vec::new();
    }
    let key = |ci: i32, cj: i32| ((ci + 1) + (n[0] + 1) * (cj + 1)) as u32;
    let stride = (n[0] + 1) as u32;
    const AROUND: [(i32, i32); 4] = [(-1, -1), (0, -1), (0, 0), (-1, 0)];
    // Two triangles per owned edge, written in place: slab by slab into its own stretch of
    // the one array.
    let mut triangles: Vec<[u32; 3]> =
        vec![[0; 3]; 2 * slabs.iter().map(|s| s.owned.len()).sum::<usize>()];
    let mut stretches: Vec<(i32, &mut [[u32; 3]])> = Vec::with_capacity(slabs.len());
    let mut rest = &mut triangles[..];
    for k in -1..n[2] {
        let (mine, after) = rest.split_at_mut(2 * slabs[slab_index(k)].owned.len());
        stretches.push((k, mine));
        rest = after;
    }
    stretches.into_par_iter().for_each(|(k, out)| {
        let owned = &slabs[slab_index(k)].owned;
        for (&e, pair) in owned.iter().zip(out.chunks_exact_mut(2)) {
            let q = AROUND.map(|(db, dc)| match e.axis {
                0 => vertex_of(
                    &slabs,
                    &base,
                    stride,
                    e.k + dc,
                    key(e.i, e.j + db),
                    (-db - 2 * dc) as usize,
                ),
                1 => vertex_of(
                    &slabs,
                    &base,
                    stride,
                    e.k + db,
                    key(e.i + dc, e.j),
                    (4 - dc - 2 * db) as usize,
                ),
                _ => vertex_of(
                    &slabs,
                    &base,
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
            pair.copy_from_slice(&split_quad(q, &vertices, opt.split));
        }
    });
    let mut stats = slabs.iter().fold(level_stats, |a, s| a.add(s.stats));
    drop(slabs);
    stats.triangles = triangles.len();
    stats.lines = lines;
    stats.spans = spans;
    (TriMesh::from_parts(vertices, triangles), stats)
}
