//! Trimmed patches: the part of a patch's parameter box that belongs to the part.
//!
//! A [`Trim`] is an outer boundary (the patch's own parameter box when the file gives none) and
//! holes, closed polygons in the patch's `(u, v)` parameters, as a reader sampled them from the
//! file's trimming curves (IGES 144 and 142, a JSON patch's `trim`). A parameter point is on the
//! part when it lies in the parameter box and a ray from it crosses the outer loop and the holes
//! an odd number of times — without an outer loop, the holes an even number of times (the
//! even–odd rule, so loops need no particular orientation). The region is closed: a point on a
//! loop (within a relative 1e-12) is on the part, so the corners of pieces along a boundary
//! count; the box itself is no loop, so a hole may run off the patch's edge.
//!
//! The queries the planner asks are point containment (a CC point, a corner of a Bézier piece)
//! and the [`Coverage`] of a parameter rectangle (a piece: wholly on the part, wholly off it, or
//! crossing the boundary). Both are exact for the polygons; a uniform grid of cells, each
//! listing the edges that may pass through it and, when none does, whether it is on the part,
//! keeps them cheap: a rectangle far from the boundary is answered from one cell.
//!
//! The polygons stand for curves: a reader samples them to a chord tolerance, and the solvers
//! treat a piece smaller than [`Trim::resolution`] that still crosses the boundary as on the
//! part, so the boundary is honoured to within that resolution (on the conservative side: a
//! point that close outside still limits the cutter).

use crate::surface::ParamBox;

/// Where a parameter rectangle lies relative to the trimmed region.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Coverage {
    /// Every point of it is on the part.
    Inside,
    /// No point of it is on the part.
    Outside,
    /// The boundary passes through it.
    Crossing,
}

/// Why a trim is refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TrimError {
    /// A loop with fewer than three distinct points encloses nothing.
    #[error("trim loop {index} has {points} point(s); a loop needs at least 3")]
    TooFewPoints {
        /// Index of the loop.
        index: usize,
        /// Points it has (the closing repeat of the first not counted).
        points: usize,
    },
    /// A coordinate is NaN or infinite.
    #[error("trim loop {index}, point {point} is not finite")]
    NotFinite {
        /// Index of the loop.
        index: usize,
        /// Index of the point in the loop.
        point: usize,
    },
}

type Uv = [f64; 2];

/// The trimmed region of a patch (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct Trim {
    loops: Vec<Vec<Uv>>,
    /// Whether `loops[0]` is an outer boundary (else every loop is a hole).
    outer: bool,
    /// Distance to a loop within which a point counts as on it.
    on_edge: f64,
    /// Every edge of every loop, `[a, b]`.
    edges: Vec<[Uv; 2]>,
    /// The box holding the region, `[u0, u1, v0, v1]`: the parameter box, cut down to the outer
    /// loop's box.
    bbox: [f64; 4],
    /// Cells per side.
    n: usize,
    /// Edge indices per cell (compressed rows: cell `c` owns `cell_edges[start[c]..start[c+1]]`).
    start: Vec<u32>,
    cell_edges: Vec<u32>,
    /// For cells without edges: on the part or not (meaningless for the others).
    cell_inside: Vec<bool>,
    resolution: f64,
}

/// The box `dom` cut down to the box of the loop `outer` (a side that would move by less than
/// 1e-9 of the box's extent stays: the loop runs along it, a point inversion or a rounding a
/// hair inside; a loop beyond a side leaves it). The readers fit a trimmed patch's parameter
/// box with it: the STEP reader as it reads a face, [`crate::Patch::fit_domain_to_trim`] for the
/// others.
pub(crate) fn fitted_to_loop(dom: ParamBox, outer: &[Uv]) -> ParamBox {
    let mut out = dom;
    for d in 0..2 {
        let r = if d == 0 { dom.u } else { dom.v };
        let (lo, hi) = outer
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(p[d]), b.max(p[d]))
            });
        let keep = 1e-9 * (r[1] - r[0]);
        let cut = [
            if lo > r[0] + keep { lo } else { r[0] },
            if hi < r[1] - keep { hi } else { r[1] },
        ];
        if cut[0] >= cut[1] || cut[0].is_nan() || cut[1].is_nan() {
            continue;
        }
        if d == 0 {
            out.u = cut;
        } else {
            out.v = cut;
        }
    }
    out
}

impl Trim {
    /// Relative resolution of the boundary: a rectangle whose larger side is below this share of
    /// the patch's parameter box diagonal counts as on the part even when the boundary crosses
    /// it.
    pub const RELATIVE_RESOLUTION: f64 = 1e-7;

    /// The region inside `outer` (the whole of `domain` when `None`) and outside every hole, on
    /// a patch whose parameter box is `domain`. A loop is a closed polygon; the closing repeat
    /// of its first point is optional.
    ///
    /// # Errors
    /// When a loop has fewer than 3 points or a coordinate is not finite. Loops are numbered
    /// outer first (when given), then the holes.
    pub fn new(
        domain: &ParamBox,
        outer: Option<Vec<Uv>>,
        holes: Vec<Vec<Uv>>,
    ) -> Result<Self, TrimError> {
        let has_outer = outer.is_some();
        let loops: Vec<Vec<Uv>> = outer.into_iter().chain(holes).collect();
        let mut clean = Vec::with_capacity(loops.len());
        for (index, mut l) in loops.into_iter().enumerate() {
            if let Some(point) = l
                .iter()
                .position(|p| !p[0].is_finite() || !p[1].is_finite())
            {
                return Err(TrimError::NotFinite { index, point });
            }
            l.dedup();
            if l.len() > 1 && l.first() == l.last() {
                l.pop();
            }
            if l.len() < 3 {
                return Err(TrimError::TooFewPoints {
                    index,
                    points: l.len(),
                });
            }
            clean.push(l);
        }
        let edges: Vec<[Uv; 2]> = clean
            .iter()
            .flat_map(|l| (0..l.len()).map(move |i| [l[i], l[(i + 1) % l.len()]]))
            .collect();
        let dom = [domain.u[0], domain.u[1], domain.v[0], domain.v[1]];
        let mut bbox = dom;
        if has_outer {
            let mut lb = [
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
            ];
            for p in &clean[0] {
                lb = [
                    lb[0].min(p[0]),
                    lb[1].max(p[0]),
                    lb[2].min(p[1]),
                    lb[3].max(p[1]),
                ];
            }
            bbox = [
                dom[0].max(lb[0]),
                dom[1].min(lb[1]),
                dom[2].max(lb[2]),
                dom[3].min(lb[3]),
            ];
        }
        let diag = (dom[1] - dom[0]).hypot(dom[3] - dom[2]);
        // About two edges per cell row: a cell near the boundary lists a handful of edges.
        let n = ((edges.len() as f64).sqrt() * 2.0).clamp(8.0, 256.0) as usize;
        let mut t = Trim {
            loops: clean,
            outer: has_outer,
            on_edge: 1e-12 * diag,
            edges,
            bbox,
            n,
            start: Vec::new(),
            cell_edges: Vec::new(),
            cell_inside: Vec::new(),
            resolution: Self::RELATIVE_RESOLUTION * diag,
        };
        t.build_cells();
        Ok(t)
    }

    /// Lists the edges through every cell (each edge walks the columns it spans and, in each,
    /// the rows its clipped piece spans: linear in the cells it meets) and the state of the
    /// cells without edges (one sweep per row of cell centres), so hostile loops of many long
    /// edges cost no more than their length in cells.
    fn build_cells(&mut self) {
        let n = self.n;
        let (du, dv) = self.cell_size();
        let pad = 1e-9 * du.max(dv);
        let mut lists: Vec<Vec<u32>> = vec![Vec::new(); n * n];
        for (k, &[a, b]) in self.edges.iter().enumerate() {
            let (lo, hi) = if a[0] <= b[0] { (a, b) } else { (b, a) };
            let (i0, i1) = self.cols(lo[0], hi[0]);
            for i in i0..=i1 {
                let r = self.cell_rect(i, 0);
                // The piece of the edge over this column (padded: a cell it only grazes is
                // listed too, which costs a test, never an answer).
                let (x0, x1) = (lo[0].max(r[0] - pad), hi[0].min(r[1] + pad));
                let at = |x: f64| {
                    if hi[0] > lo[0] {
                        lo[1] + (x.clamp(lo[0], hi[0]) - lo[0]) * (hi[1] - lo[1]) / (hi[0] - lo[0])
                    } else {
                        lo[1]
                    }
                };
                let (y0, y1) = if hi[0] > lo[0] {
                    (at(x0), at(x1))
                } else {
                    (lo[1], hi[1])
                };
                let (j0, j1) = self.rows(y0.min(y1) - pad, y0.max(y1) + pad);
                for j in j0..=j1 {
                    lists[i * n + j].push(k as u32);
                }
            }
        }
        self.start = Vec::with_capacity(n * n + 1);
        self.start.push(0);
        for l in &lists {
            self.cell_edges.extend_from_slice(l);
            self.start.push(self.cell_edges.len() as u32);
        }
        self.cell_inside = vec![false; n * n];
        let mut xs = Vec::new();
        for j in 0..n {
            let r = self.cell_rect(0, j);
            let v = 0.5 * (r[2] + r[3]);
            xs.clear();
            for [a, b] in &self.edges {
                if (a[1] > v) != (b[1] > v) {
                    xs.push(a[0] + (v - a[1]) * (b[0] - a[0]) / (b[1] - a[1]));
                }
            }
            xs.sort_by(f64::total_cmp);
            for i in 0..n {
                let c = i * n + j;
                if lists[c].is_empty() {
                    let r = self.cell_rect(i, j);
                    let u = 0.5 * (r[0] + r[1]);
                    // Crossings right of the centre: those after the first x > u.
                    let right = xs.len() - xs.partition_point(|&x| x <= u);
                    self.cell_inside[c] = (right % 2 == 1) == self.outer;
                }
            }
        }
    }

    /// The loops, the outer boundary first when there is one (closing repeat dropped).
    pub fn loops(&self) -> &[Vec<[f64; 2]>] {
        &self.loops
    }

    /// The outer boundary, `None` when it is the parameter box.
    pub fn outer(&self) -> Option<&[[f64; 2]]> {
        self.outer.then(|| &self.loops[0][..])
    }

    /// The box holding the part, `[u0, u1, v0, v1]`: the parameter box the trim was made on,
    /// cut down to the outer boundary's box.
    pub fn region_box(&self) -> [f64; 4] {
        self.bbox
    }

    /// The holes.
    pub fn holes(&self) -> &[Vec<[f64; 2]>] {
        &self.loops[usize::from(self.outer)..]
    }

    /// Below this size (parameter units) a rectangle crossing the boundary counts as on the
    /// part (see the module docs).
    pub fn resolution(&self) -> f64 {
        self.resolution
    }

    /// True when `(u, v)` is on the part (exact for the polygons; a point on a loop is on it).
    pub fn contains(&self, u: f64, v: f64) -> bool {
        let [u0, u1, v0, v1] = self.bbox;
        if !(u >= u0 && u <= u1 && v >= v0 && v <= v1) {
            return false;
        }
        let c = self.cell_of(u, v);
        let list = &self.cell_edges[self.start[c] as usize..self.start[c + 1] as usize];
        if list.is_empty() {
            return self.cell_inside[c];
        }
        let near = |&k: &u32| {
            let [a, b] = self.edges[k as usize];
            segment_distance([u, v], a, b) <= self.on_edge
        };
        list.iter().any(near) || self.parity_inside(u, v)
    }

    /// On the part by the even–odd rule alone (see the module docs).
    fn parity_inside(&self, u: f64, v: f64) -> bool {
        self.crossings_odd(u, v) == self.outer
    }

    /// Where the rectangle `[u0, u1] × [v0, v1]` lies (exact for the polygons).
    pub fn coverage(&self, rect: [f64; 4]) -> Coverage {
        let [bu0, bu1, bv0, bv1] = self.bbox;
        if rect[1] < bu0 || rect[0] > bu1 || rect[3] < bv0 || rect[2] > bv1 {
            return Coverage::Outside;
        }
        // Only the inside counts: a loop along the rectangle's side leaves its inside in one
        // region (the points on that side are on the part, and so in the neighbour's cover too).
        let e = self.on_edge;
        let inner = [rect[0] + e, rect[1] - e, rect[2] + e, rect[3] - e];
        let (cu, cv) = (0.5 * (rect[0] + rect[1]), 0.5 * (rect[2] + rect[3]));
        if inner[0] > inner[1] || inner[2] > inner[3] {
            return if self.contains(cu, cv) {
                Coverage::Inside
            } else {
                Coverage::Outside
            };
        }
        let (i0, i1) = self.cols(rect[0], rect[1]);
        let (j0, j1) = self.rows(rect[2], rect[3]);
        for i in i0..=i1 {
            for j in j0..=j1 {
                let c = i * self.n + j;
                for &k in &self.cell_edges[self.start[c] as usize..self.start[c + 1] as usize] {
                    let [a, b] = self.edges[k as usize];
                    if segment_meets_rect(a, b, inner) {
                        return Coverage::Crossing;
                    }
                }
            }
        }
        // No loop passes through the inside: it lies in one region, that of its centre (inside
        // the box). What reaches past the box is off the part.
        let (ku, kv) = (cu.clamp(bu0, bu1), cv.clamp(bv0, bv1));
        let c = self.cell_of(ku, kv);
        let inside = if self.start[c] == self.start[c + 1] {
            self.cell_inside[c]
        } else {
            self.parity_inside(ku, kv)
        };
        let past_box = rect[0] < bu0 || rect[1] > bu1 || rect[2] < bv0 || rect[3] > bv1;
        match (inside, past_box) {
            (true, false) => Coverage::Inside,
            (true, true) => Coverage::Crossing,
            (false, _) => Coverage::Outside,
        }
    }

    /// A boundary edge along a parameter line through the inside of `rect` (not within 1 % of its
    /// sides): `(0, u)` for an edge along `u = const`, `(1, v)` for `v = const`, the one nearest
    /// the middle of the rectangle.
    pub(crate) fn aligned_cut(&self, rect: [f64; 4]) -> Option<(usize, f64)> {
        let (i0, i1) = self.cols(rect[0], rect[1]);
        let (j0, j1) = self.rows(rect[2], rect[3]);
        let mut best: Option<(f64, usize, f64)> = None;
        for i in i0..=i1 {
            for j in j0..=j1 {
                let c = i * self.n + j;
                for &k in &self.cell_edges[self.start[c] as usize..self.start[c + 1] as usize] {
                    let [a, b] = self.edges[k as usize];
                    if !segment_meets_rect(a, b, rect) {
                        continue;
                    }
                    for dir in 0..2 {
                        if (a[dir] - b[dir]).abs() > self.on_edge {
                            continue;
                        }
                        let (lo, hi) = (rect[2 * dir], rect[2 * dir + 1]);
                        let t = (a[dir] - lo) / (hi - lo);
                        if t > 0.01 && t < 0.99 {
                            let off = (t - 0.5).abs();
                            if best.map_or(true, |(o, _, _)| off < o) {
                                best = Some((off, dir, a[dir]));
                            }
                        }
                    }
                }
            }
        }
        best.map(|(_, dir, at)| (dir, at))
    }

    /// Even–odd count of the edges crossed by the ray from `(u, v)` towards `+u`.
    fn crossings_odd(&self, u: f64, v: f64) -> bool {
        let mut odd = false;
        for [a, b] in &self.edges {
            if (a[1] > v) != (b[1] > v) {
                let x = a[0] + (v - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
                if x > u {
                    odd = !odd;
                }
            }
        }
        odd
    }

    fn cell_size(&self) -> (f64, f64) {
        let [u0, u1, v0, v1] = self.bbox;
        (
            ((u1 - u0) / self.n as f64).max(f64::MIN_POSITIVE),
            ((v1 - v0) / self.n as f64).max(f64::MIN_POSITIVE),
        )
    }

    fn index(&self, x: f64, origin: f64, size: f64) -> usize {
        (((x - origin) / size).floor().max(0.0) as usize).min(self.n - 1)
    }

    fn cols(&self, a: f64, b: f64) -> (usize, usize) {
        let (du, _) = self.cell_size();
        (
            self.index(a, self.bbox[0], du),
            self.index(b, self.bbox[0], du),
        )
    }

    fn rows(&self, a: f64, b: f64) -> (usize, usize) {
        let (_, dv) = self.cell_size();
        (
            self.index(a, self.bbox[2], dv),
            self.index(b, self.bbox[2], dv),
        )
    }

    fn cell_of(&self, u: f64, v: f64) -> usize {
        let (du, dv) = self.cell_size();
        self.index(u, self.bbox[0], du) * self.n + self.index(v, self.bbox[2], dv)
    }

    /// Cell `(i, j)` as `[u0, u1, v0, v1]`; the last row and column reach the box exactly.
    fn cell_rect(&self, i: usize, j: usize) -> [f64; 4] {
        let (du, dv) = self.cell_size();
        let [u0, u1, v0, v1] = self.bbox;
        let end = |k: usize, o: f64, d: f64, hi: f64| {
            if k + 1 == self.n {
                hi
            } else {
                o + (k + 1) as f64 * d
            }
        };
        [
            u0 + i as f64 * du,
            end(i, u0, du, u1),
            v0 + j as f64 * dv,
            end(j, v0, dv, v1),
        ]
    }
}

/// Distance from `p` to the segment `ab`.
fn segment_distance(p: Uv, a: Uv, b: Uv) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1]];
    let len2 = d[0] * d[0] + d[1] * d[1];
    let t = if len2 > 0.0 {
        (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p[0] - a[0] - t * d[0]).hypot(p[1] - a[1] - t * d[1])
}

/// True when the closed segment `ab` meets the closed rectangle `[u0, u1] × [v0, v1]`
/// (Liang–Barsky clipping).
fn segment_meets_rect(a: Uv, b: Uv, r: [f64; 4]) -> bool {
    let d = [b[0] - a[0], b[1] - a[1]];
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-d[0], a[0] - r[0]),
        (d[0], r[1] - a[0]),
        (-d[1], a[1] - r[2]),
        (d[1], r[3] - a[1]),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return false;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
            if t0 > t1 {
                return false;
            }
        }
    }
    true
}

/// Samples a parameter-space curve `f` over `[t0, t1]` into a polyline whose chords stay within
/// `tol` of the curve at their midpoints (adaptive halving from `min_segments` equal steps, at
/// most 2¹² segments per step); the first point is `f(t0)`, the last `f(t1)`.
pub fn sample_curve(
    f: impl Fn(f64) -> [f64; 2],
    t0: f64,
    t1: f64,
    min_segments: usize,
    tol: f64,
) -> Vec<[f64; 2]> {
    fn refine(
        f: &impl Fn(f64) -> [f64; 2],
        (ta, pa): (f64, Uv),
        (tb, pb): (f64, Uv),
        tol: f64,
        depth: u32,
        out: &mut Vec<Uv>,
    ) {
        let tm = 0.5 * (ta + tb);
        let pm = f(tm);
        let chord = [0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])];
        let dev = (pm[0] - chord[0]).hypot(pm[1] - chord[1]);
        if depth < 12 && dev > tol {
            refine(f, (ta, pa), (tm, pm), tol, depth + 1, out);
            refine(f, (tm, pm), (tb, pb), tol, depth + 1, out);
        } else {
            out.push(pb);
        }
    }
    let n = min_segments.max(1);
    let mut out = vec![f(t0)];
    let mut prev = (t0, out[0]);
    for k in 1..=n {
        let t = if k == n {
            t1
        } else {
            t0 + (t1 - t0) * k as f64 / n as f64
        };
        let next = (t, f(t));
        refine(&f, prev, next, tol, 0, &mut out);
        prev = next;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit() -> ParamBox {
        ParamBox {
            u: [0.0, 1.0],
            v: [0.0, 1.0],
        }
    }

    /// The unit square with a square hole `[0.4, 0.6]²` and a disc of radius 0.1 around
    /// (0.2, 0.2) (a polygon within 1e-5 of the circle) removed.
    fn holed() -> Trim {
        let outer = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let hole = vec![[0.4, 0.4], [0.4, 0.6], [0.6, 0.6], [0.6, 0.4], [0.4, 0.4]];
        let disc = sample_curve(
            |t| [0.2 + 0.1 * t.cos(), 0.2 + 0.1 * t.sin()],
            0.0,
            std::f64::consts::TAU,
            16,
            1e-5,
        );
        Trim::new(&unit(), Some(outer), vec![hole, disc]).unwrap()
    }

    /// The plain even–odd count over every edge, no cells (points exactly on edges aside).
    fn brute_contains(t: &Trim, u: f64, v: f64) -> bool {
        t.parity_inside(u, v)
            && u >= t.bbox[0]
            && u <= t.bbox[1]
            && v >= t.bbox[2]
            && v <= t.bbox[3]
    }

    #[test]
    fn containment_matches_the_geometry_and_the_plain_crossing_count() {
        let t = holed();
        assert!(t.contains(0.9, 0.9));
        assert!(!t.contains(0.5, 0.5));
        assert!(!t.contains(0.2, 0.2));
        assert!(t.contains(0.2, 0.32));
        assert!(!t.contains(0.2, 0.29));
        assert!(!t.contains(1.5, 0.5) && !t.contains(-0.1, 0.5));
        for i in 0..200 {
            for j in 0..200 {
                let (u, v) = (i as f64 / 199.0 * 1.2 - 0.1, j as f64 / 199.0 * 1.2 - 0.1);
                assert_eq!(t.contains(u, v), brute_contains(&t, u, v), "({u}, {v})");
            }
        }
    }

    #[test]
    fn coverage_agrees_with_dense_samples_of_the_rectangle() {
        let t = holed();
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut seen = [0; 3];
        for _ in 0..2000 {
            let (u, v) = (rnd() * 1.2 - 0.1, rnd() * 1.2 - 0.1);
            let (w, h) = (rnd() * rnd() * 0.5, rnd() * rnd() * 0.5);
            let rect = [u, u + w, v, v + h];
            let c = t.coverage(rect);
            let mut ins = 0;
            let mut outs = 0;
            for a in 0..=20 {
                for b in 0..=20 {
                    let (x, y) = (u + w * a as f64 / 20.0, v + h * b as f64 / 20.0);
                    if brute_contains(&t, x, y) {
                        ins += 1;
                    } else {
                        outs += 1;
                    }
                }
            }
            match c {
                Coverage::Inside => {
                    seen[0] += 1;
                    assert_eq!(outs, 0, "{rect:?}")
                }
                Coverage::Outside => {
                    seen[1] += 1;
                    assert_eq!(ins, 0, "{rect:?}")
                }
                // Samples may all fall on one side of a thin sliver, so nothing to assert but
                // that the boundary really is near: some edge meets the rectangle.
                Coverage::Crossing => {
                    seen[2] += 1;
                    assert!(t
                        .edges
                        .iter()
                        .any(|[a, b]| segment_meets_rect(*a, *b, rect)));
                }
            }
        }
        assert!(seen.iter().all(|&s| s > 100), "{seen:?}");
    }

    #[test]
    fn bad_loops_are_refused() {
        assert_eq!(
            Trim::new(
                &unit(),
                Some(vec![[0.0, 0.0], [1.0, 0.0], [0.0, 0.0]]),
                vec![]
            ),
            Err(TrimError::TooFewPoints {
                index: 0,
                points: 2
            })
        );
        assert_eq!(
            Trim::new(
                &unit(),
                None,
                vec![vec![[0.0, 0.0], [1.0, f64::NAN], [0.0, 1.0]]]
            ),
            Err(TrimError::NotFinite { index: 0, point: 1 })
        );
        // No outer loop: the parameter box.
        let t = Trim::new(&unit(), None, vec![]).unwrap();
        assert!(t.contains(0.5, 0.5) && !t.contains(1.01, 0.5));
        assert_eq!(t.coverage([0.1, 0.9, 0.1, 0.9]), Coverage::Inside);
        assert_eq!(t.coverage([0.5, 1.5, 0.1, 0.9]), Coverage::Crossing);
    }

    #[test]
    fn the_region_is_closed_and_a_hole_may_run_off_the_box() {
        // A slot through the box, overhanging it on both sides.
        let slot = vec![[-0.1, 0.25], [1.1, 0.25], [1.1, 0.75], [-0.1, 0.75]];
        let t = Trim::new(&unit(), None, vec![slot]).unwrap();
        for u in [0.0, 0.5, 1.0] {
            assert!(!t.contains(u, 0.5), "{u}");
            assert!(t.contains(u, 0.25) && t.contains(u, 0.75) && t.contains(u, 0.1));
        }
        assert!(t.contains(0.0, 0.0) && t.contains(1.0, 1.0) && t.contains(1.0, 0.0));
        assert_eq!(t.coverage([0.0, 1.0, 0.3, 0.7]), Coverage::Outside);
        assert_eq!(t.coverage([0.0, 1.0, 0.0, 0.2]), Coverage::Inside);
        assert_eq!(t.coverage([0.0, 1.0, 0.0, 0.5]), Coverage::Crossing);
        // An outer loop on the box's edges: every edge point is on the part.
        let square = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let t = Trim::new(&unit(), Some(square), vec![]).unwrap();
        for (u, v) in [(0.0, 0.5), (1.0, 0.5), (0.5, 0.0), (0.5, 1.0), (1.0, 1.0)] {
            assert!(t.contains(u, v), "({u}, {v})");
        }
        // Its sides lie on the loop: the inside is on the part.
        assert_eq!(t.coverage([0.0, 1.0, 0.0, 1.0]), Coverage::Inside);
        assert_eq!(t.coverage([0.0, 0.5, 0.5, 1.0]), Coverage::Inside);
    }

    #[test]
    fn many_long_edges_build_in_linear_time() {
        // A star of 40 000 spikes across the whole box: every edge is long. The build lists each
        // edge in the cells it meets, about its length in cells (the time is measured by the
        // `trim_build` bench: about 0.1 s).
        let pts: Vec<[f64; 2]> = (0..40_000)
            .map(|k| {
                let a = k as f64 / 40_000.0 * std::f64::consts::TAU;
                let r = if k % 2 == 0 { 0.5 } else { 0.01 };
                [0.5 + r * a.cos(), 0.5 + r * a.sin()]
            })
            .collect();
        let t = Trim::new(&unit(), Some(pts), vec![]).unwrap();
        assert!(t.contains(0.5, 0.5) && !t.contains(0.02, 0.02));
        let (du, dv) = t.cell_size();
        let (mut length, mut boxes) = (0.0, 0.0);
        for [a, b] in &t.edges {
            let (cu, cv) = ((b[0] - a[0]).abs() / du, (b[1] - a[1]).abs() / dv);
            // The cells a segment meets: about the columns and rows it crosses, plus one (and
            // the padding at either end).
            length += cu.ceil() + cv.ceil() + 3.0;
            // What the walk over each edge's bounding box it replaced tested.
            boxes += (cu.ceil() + 1.0) * (cv.ceil() + 1.0);
        }
        let listed = t.cell_edges.len() as f64;
        // Measured: 6.42e6 listings, 6.55e6 cells of length, 2.1e8 bounding-box cells.
        assert!(
            listed <= 1.5 * length,
            "{listed} listings for {length} cells of edge length"
        );
        assert!(
            20.0 * listed < boxes,
            "{listed} listings, {boxes} bounding-box cells"
        );
    }

    #[test]
    fn sampled_circle_keeps_within_the_tolerance() {
        let tol = 1e-6;
        let pts = sample_curve(|t| [t.cos(), t.sin()], 0.0, std::f64::consts::PI, 2, tol);
        assert_eq!(pts[0], [1.0, 0.0]);
        for w in pts.windows(2) {
            let m = [(w[0][0] + w[1][0]) / 2.0, (w[0][1] + w[1][1]) / 2.0];
            // The sagitta of a chord of the unit circle is 1 − |midpoint|.
            assert!(1.0 - m[0].hypot(m[1]) <= tol * 1.0001);
        }
        // The sagitta of a chord of angle a is a²/8: about π/sqrt(8 tol) chords are needed.
        let need = std::f64::consts::PI / (8.0 * tol).sqrt();
        assert!((pts.len() as f64) < 2.5 * need, "{} vs {need}", pts.len());
    }
}
