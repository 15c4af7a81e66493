//! Which 2 × 2 × 2 blocks of cells become one vertex ([`super::ContourOptions::simplify`]),
//! decided for a pair of slabs before any cell is made — what a dual contouring of the lattice
//! twice as coarse would compute, checked against the fine lattice: the sides of each block's
//! 27 lattice points (the topology), the Hermite data of the crossings on the block's own
//! edges (those of the coarse lattice of block corners) for its vertex, and the positions of
//! all crossings on its 54 lattice edges against that vertex's planes (the shape). The
//! extraction then makes cells — records, normals, QEFs, vertices — only for the blocks left as
//! they are, and a merged block's lattice edges give quads only where they lie on the coarse
//! lattice's edges: the work of a merged region is reading its crossings' positions and a
//! quarter of their normals, not making its cells.
//!
//! Why normals at all: positions alone cannot tell a sharp edge from a chamfer. Where a box's
//! edge runs along a block, one row of crossings on each face, each as far from the edge, lie
//! on one plane across it; the coarse crossings' normals are the faces' own, and their planes
//! meet on the edge. Every block that passes the topology test has a sign change among its
//! corners, so a crossing on a coarse edge.
//!
//! Blocks are aligned on cells `2b − 1, 2b` along X and Y and on a pair of slabs `k, k + 1`
//! with `k` odd (slab `k` lies between point levels `k` and `k + 1`): block `(b, c)` of the
//! pair spans lattice points `2b − 1 ..= 2b + 1`, `2c − 1 ..= 2c + 1` and levels
//! `k ..= k + 2`, and its corners are the points with odd indices.

use super::extract::{Edge, Hermite};
use super::lines::{xor_runs, LevelRuns, Store};
use super::qef::Qef;
use super::table::{cases, has_ambiguous_face};
use swarf_geom::math::Vec3;

/// The merged blocks of one pair of slabs and their vertices.
pub(crate) struct BlockMap {
    /// Blocks per row (along X).
    width: usize,
    /// Per block `b + width · c`: the index of its vertex in `vertices`, or `u32::MAX`.
    ids: Vec<u32>,
    /// The merged blocks' vertices.
    pub(crate) vertices: Vec<Vec3>,
}

impl BlockMap {
    /// The vertex (index in `vertices`) of the merged block holding cell `(ci, cj)` of either
    /// slab of the pair, if that block is merged.
    #[inline]
    pub(crate) fn vertex(&self, ci: i32, cj: i32) -> Option<u32> {
        let (b, c) = (((ci + 1) >> 1) as usize, ((cj + 1) >> 1) as usize);
        let id = *self
            .ids
            .get(b + self.width * c)
            .filter(|_| b < self.width)?;
        (id != u32::MAX).then_some(id)
    }

    /// True when cell `(ci, cj)` lies in a merged block.
    #[inline]
    pub(crate) fn merged(&self, ci: i32, cj: i32) -> bool {
        self.vertex(ci, cj).is_some()
    }
}

/// What one block's crossings add up to: the QEF of the planes of those on coarse edges with
/// the mass point of all (relative to the block's low corner), and the box of all.
#[derive(Clone, Copy)]
struct Gathered {
    qef: Qef,
    lo: Vec3,
    hi: Vec3,
}

impl Default for Gathered {
    fn default() -> Self {
        Self {
            qef: Qef::default(),
            lo: Vec3::splat(f64::INFINITY),
            hi: Vec3::splat(f64::NEG_INFINITY),
        }
    }
}

/// Buffers reused from pair to pair.
#[derive(Default)]
pub(crate) struct BlockScratch {
    /// Runs of the X lines at levels `k`, `k + 1`, `k + 2`.
    levels: [LevelRuns; 3],
    /// Per block of the row being read: what its crossings add up to, and their positions
    /// (relative to its low corner) and the unit normals of its coarse ones.
    gathered: Vec<Gathered>,
    points: Vec<Vec<Vec3>>,
    normals: Vec<Vec<Vec3>>,
    touched: Vec<u32>,
    found: Vec<(i32, bool)>,
    /// The crossings of the coarse X and Z edges on the last line of the row before (shared
    /// with this row: its first line), in the order they were met, and how many of them this
    /// row has used; those of this row's last line.
    carried: Vec<Hermite>,
    cursor: usize,
    carry: Vec<Hermite>,
    /// Per level slot, the lattice points inside along each X line: bit `i + 1` for point
    /// `i`, `words` words a line.
    inside: [Vec<u64>; 3],
    /// The topology tests' verdicts on the sides met so far (a few hundred distinct ones
    /// make up a surface): `1 << 63 | sides << 1 | verdict`, at a hash of the sides.
    verdicts: Vec<u64>,
}

/// Entries of [`BlockScratch::verdicts`].
const VERDICTS: usize = 1 << 12;

impl BlockScratch {
    /// Whether a block with these sides (bit `x + 3y + 9z` for point `(x, y, z)`) may merge
    /// as far as its topology goes ([`cells_merge`] and [`topology_safe`]).
    fn topology_allows(&mut self, sides: u32) -> bool {
        if self.verdicts.len() != VERDICTS {
            self.verdicts = vec![0; VERDICTS];
        }
        let slot = (sides.wrapping_mul(0x9e37_79b1) >> 20) as usize % VERDICTS;
        let entry = self.verdicts[slot];
        if entry >> 63 == 1 && (entry >> 1) as u32 == sides {
            return entry & 1 == 1;
        }
        let mut array = [[[false; 3]; 3]; 3];
        for (index, v) in array.iter_mut().flatten().flatten().enumerate() {
            // `array[x][y][z]` in this order is index `9x + 3y + z`.
            let (x, y, z) = (index / 9, (index / 3) % 3, index % 3);
            *v = sides >> (x + 3 * y + 9 * z) & 1 == 1;
        }
        let verdict = cells_merge(&array) && topology_safe(&array);
        self.verdicts[slot] = 1 << 63 | (sides as u64) << 1 | u64::from(verdict);
        verdict
    }
}

/// Sets bits `from..to`, a word at a time.
fn set_bits(bits: &mut [u64], from: usize, to: usize) {
    let mut at = from;
    while at < to {
        let (w, o) = (at / 64, at % 64);
        let n = (64 - o).min(to - at);
        let ones = if n == 64 { u64::MAX } else { (1u64 << n) - 1 };
        bits[w] |= ones << o;
        at += n;
    }
}

/// Three bits of a line's inside points from bit `at` on.
fn three_bits(line: &[u64], at: usize) -> u32 {
    let (w, o) = (at / 64, at % 64);
    let mut v = line[w] >> o;
    if o > 61 && w + 1 < line.len() {
        v |= line[w + 1] << (64 - o);
    }
    (v & 7) as u32
}

/// The blocks of the pair of slabs `k` (odd) and `k + 1` merged at tolerance `tol`, with the
/// extraction's `eigen_threshold` and clamping (`clamp`): those with at least two cells
/// crossed, each crossed cell one patch with no ambiguous face, that pass Ju et al.'s
/// topology-safety test ([`topology_safe`]), and whose vertex — the minimiser of the QEF of
/// the planes at the crossings on the block's coarse edges, regularised towards the mean of
/// all its crossings, clamped to the block — (1) lies within `tol` of those planes and (2) of
/// every crossing of the block, each measured from the nearest of those planes moved through
/// the vertex (both root mean square; planes weighted as the QEF weighs them), and (3) lies
/// within `tol` of the crossings' bounding box (planes that meet in a line or a point far
/// from the crossings — a surface crossed too sparsely: two planes always meet — do not make
/// a vertex of the surface). Crossings are found as the extraction finds them
/// (`Ctx::hermite`): an interval end of the edge's own line within `slack` of the edge, else
/// the edge's middle; `hermite` gives a coarse edge's crossing with its normal (the crossing
/// along an X edge known from its run).
pub(crate) fn decide(
    store: &Store,
    k: i32,
    (tol, slack, eigen_threshold, clamp): (f64, f64, f64, bool),
    s: &mut BlockScratch,
    mut hermite: impl FnMut(Edge, Option<f64>) -> Hermite,
) -> BlockMap {
    let lat = &store.lattice;
    let n = lat.n.map(|x| x as i32);
    for (slot, lev) in (k..k + 3).enumerate() {
        s.levels[slot].read(store, lev);
    }
    let words = (n[0] as usize + 3).div_ceil(64);
    for slot in 0..3 {
        let mut inside = std::mem::take(&mut s.inside[slot]);
        inside.clear();
        inside.resize(words * n[1] as usize, 0);
        for j in 0..n[1] {
            let bits = &mut inside[j as usize * words..(j as usize + 1) * words];
            for r in s.levels[slot].line(j) {
                set_bits(bits, (r.lo + 1) as usize, (r.hi + 2) as usize);
            }
        }
        s.inside[slot] = inside;
    }
    let width = n[0] as usize / 2 + 1;
    let rows = n[1] as usize / 2 + 1;
    let mut map = BlockMap {
        width,
        ids: vec![u32::MAX; width * rows],
        vertices: Vec::new(),
    };
    s.gathered.clear();
    s.gathered.resize(width, Gathered::default());
    s.points.resize(width, Vec::new());
    s.normals.resize(width, Vec::new());
    let size = 2.0 * lat.spacing;
    // The crossing of an edge, as `Ctx::hermite` finds it.
    let crossing = |e: Edge| -> Vec3 {
        e.point_at(
            lat,
            e.crossing(store, slack).unwrap_or_else(|| e.middle(lat)),
        )
    };
    s.carry.clear();
    for c in 0..rows as i32 {
        let j0 = 2 * c - 1;
        s.touched.clear();
        std::mem::swap(&mut s.carried, &mut s.carry);
        s.carry.clear();
        s.cursor = 0;
        // The crossing of edge `e` (at `t` along it when known), filed in each block holding
        // one of its cells: those with X index `i − 1` and `i` (Y and Z edges) or `i` only (X
        // edges); with its tangent plane where the edge lies on a coarse one.
        let mut file = |s: &mut BlockScratch, e: Edge, t: Option<f64>| {
            let (first, last) = if e.axis == 0 {
                ((e.i + 1) >> 1, (e.i + 1) >> 1)
            } else {
                (e.i >> 1, (e.i + 1) >> 1)
            };
            let (p, plane) = if e.halves_coarse_edge() {
                // X and Z edges of the row's first line were its last in the row before.
                let shared = e.axis != 1 && c > 0 && e.j == j0;
                let known = s
                    .carried
                    .get(s.cursor)
                    .filter(|h| shared && same(h.edge, e));
                let h = match known {
                    Some(&h) => {
                        s.cursor += 1;
                        h
                    }
                    None => hermite(e, t),
                };
                if e.axis != 1 && e.j == j0 + 2 {
                    s.carry.push(h);
                }
                (h.p, Some((h.n, h.w)))
            } else {
                let p = match t {
                    Some(t) => e.point_at(lat, t),
                    None => crossing(e),
                };
                (p, None)
            };
            for b in first.max(0)..=last.min(width as i32 - 1) {
                let corner = lat.point(2 * b as isize - 1, j0 as isize, k as isize);
                let at = b as usize;
                let g = &mut s.gathered[at];
                if g.qef.is_empty() {
                    s.touched.push(b as u32);
                    s.points[at].clear();
                    s.normals[at].clear();
                }
                let (n, w) = plane.unwrap_or((Vec3::ZERO, 0.0));
                g.qef.add(p - corner, n, w);
                (g.lo, g.hi) = (g.lo.min(p), g.hi.max(p));
                s.points[at].push(p - corner);
                if w > 0.0 {
                    s.normals[at].push(n);
                }
            }
        };
        for dz in 0..3usize {
            let lev = k + dz as i32;
            for dy in 0..3 {
                let j = j0 + dy;
                // X edges: at both ends of every run.
                for ri in 0..s.levels[dz].line(j).len() {
                    let run = s.levels[dz].line(j)[ri];
                    for (i, inside_low, t) in
                        [(run.lo - 1, false, run.t_lo), (run.hi, true, run.t_hi)]
                    {
                        let e = Edge {
                            axis: 0,
                            inside_low,
                            i,
                            j,
                            k: lev,
                        };
                        file(s, e, Some(t));
                    }
                }
                // Y edges to the next line of the block, Z edges to the next level.
                let mut found = std::mem::take(&mut s.found);
                let next = [
                    (dy < 2).then(|| (1usize, dz, j + 1)),
                    (dz < 2).then(|| (2, dz + 1, j)),
                ];
                for (axis, slot, jj) in next.into_iter().flatten() {
                    found.clear();
                    xor_runs(s.levels[dz].line(j), s.levels[slot].line(jj), |i, in_a| {
                        found.push((i, in_a))
                    });
                    for &(i, inside_low) in &found {
                        let e = Edge {
                            axis: axis as u8,
                            inside_low,
                            i,
                            j,
                            k: lev,
                        };
                        file(s, e, None);
                    }
                }
                s.found = found;
            }
        }
        let touched = std::mem::take(&mut s.touched);
        for &b in &touched {
            let at = b as usize;
            let g = std::mem::take(&mut s.gathered[at]);
            let i0 = 2 * b as i32 - 1;
            // Points i0..=i0 + 2 are bits 2b..=2b + 2 of each line.
            let mut sides = 0u32;
            for z in 0..3 {
                for y in 0..3 {
                    let j = j0 + y as i32;
                    if (0..n[1]).contains(&j) {
                        let line = &s.inside[z][j as usize * words..(j as usize + 1) * words];
                        sides |= three_bits(line, 2 * b as usize) << (3 * y + 9 * z);
                    }
                }
            }
            if !s.topology_allows(sides) {
                continue;
            }
            let x = g.qef.solve(eigen_threshold);
            let x = if clamp { x.clamp(Vec3::ZERO, size) } else { x };
            if !g.qef.rms_distance(x).is_some_and(|d| d <= tol) {
                continue;
            }
            let normals = &s.normals[at];
            let squares: f64 = s.points[at]
                .iter()
                .map(|&p| {
                    normals
                        .iter()
                        .map(|n| n.dot(p - x).powi(2))
                        .fold(f64::INFINITY, f64::min)
                })
                .sum();
            if squares > tol * tol * s.points[at].len() as f64 {
                continue;
            }
            let corner = lat.point(i0 as isize, j0 as isize, k as isize);
            let x = corner + x;
            let margin = Vec3::splat(tol);
            if x.cmplt(g.lo - margin).any() || x.cmpgt(g.hi + margin).any() {
                continue;
            }
            map.ids[at + width * c as usize] = map.vertices.len() as u32;
            map.vertices.push(x);
        }
        s.touched = touched;
    }
    map
}

/// True when `a` and `b` are one edge.
fn same(a: Edge, b: Edge) -> bool {
    (a.axis, a.inside_low, a.i, a.j, a.k) == (b.axis, b.inside_low, b.i, b.j, b.k)
}

/// True when at least two of the block's eight cells are crossed and each crossed one has a
/// single patch and no ambiguous face.
fn cells_merge(sides: &[[[bool; 3]; 3]; 3]) -> bool {
    let mut crossed = 0;
    for cell in 0..8usize {
        let (cx, cy, cz) = (cell & 1, (cell >> 1) & 1, cell >> 2);
        let mask = (0..8usize).fold(0u8, |m, c| {
            let (dx, dy, dz) = (c & 1, (c >> 1) & 1, c >> 2);
            m | u8::from(sides[cx + dx][cy + dy][cz + dz]) << c
        });
        if mask == 0 || mask == 0xff {
            continue;
        }
        if cases()[mask as usize].count != 1 || has_ambiguous_face(mask) {
            return false;
        }
        crossed += 1;
    }
    crossed >= 2
}

/// Ju et al.'s (2002) test that a 2 × 2 × 2 block's contour may be one vertex: the corners
/// (`sides[x][y][z]` at even coordinates) make a single patch with no ambiguous face, and every
/// other lattice point of the block — the middles of its edges and faces, its centre — has the
/// side of at least one of the corners around it (those with each of its middle coordinates
/// set to either end). The cells' own test (one patch each) is [`cells_merge`].
pub(crate) fn topology_safe(sides: &[[[bool; 3]; 3]; 3]) -> bool {
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
