//! The indexed triangle mesh every writer takes and every reader returns, with the queries that
//! prove a mesh is a valid solid boundary: signed volume, area, open or non-manifold edges,
//! orientation, and the welding and merging that build one.
//!
//! Convention: a triangle's vertices are counter-clockwise seen from outside, so the right-hand
//! normal `(b − a) × (c − a)` points out of the solid and the signed volume of a closed mesh is
//! positive.

use crate::error::IoError;
use crate::tolerance::MAX_EDGE_EXAMPLES;
use std::collections::HashMap;

use rayon::prelude::*;
use swarf_geom::math::Vec3;
use swarf_geom::Aabb;

/// What [`TriMesh::repair_degenerate_f32`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DegenerateRepair {
    /// Vertices merged into another at the same `f32` position.
    pub merged_vertices: usize,
    /// Triangles dropped because two of their corners merged.
    pub collapsed_triangles: usize,
    /// Zero-area triangles removed by splitting their neighbour.
    pub split_caps: usize,
    /// Zero-area triangles left (no neighbour could be split without a non-manifold edge).
    pub remaining_flat: usize,
    /// Vertices at another's `f32` position moved one `f32` step in X instead of merged (the
    /// merge would have made an edge of more than two triangles).
    pub moved_vertices: usize,
}

/// True when the vertices `members` (all at one `f32` position, merged into the first by
/// `remap` with every other merge) make one manifold vertex: the far edges of its triangles
/// (those that do not collapse) chain into one loop — or one path, at a mesh's open border —
/// so each of its edges is used once each way and its triangles are one fan, not two fans
/// meeting at a point.
fn merge_keeps_manifold(
    tris: &[[u32; 3]],
    around: &VertexTriangles,
    remap: &[u32],
    members: &[u32],
) -> bool {
    let first = members[0];
    let mut seen: Vec<u32> = members
        .iter()
        .flat_map(|&m| around.of(m).iter().copied())
        .collect();
    seen.sort_unstable();
    seen.dedup();
    // The far edge (b, c) of each triangle (first, b, c).
    let mut link: Vec<(u32, u32)> = Vec::new();
    for &t in &seen {
        let t = tris[t as usize].map(|v| remap[v as usize]);
        if t[0] == t[1] || t[1] == t[2] || t[2] == t[0] {
            continue;
        }
        if let Some(k) = t.iter().position(|&v| v == first) {
            link.push((t[(k + 1) % 3], t[(k + 2) % 3]));
        }
    }
    if link.is_empty() {
        return true;
    }
    link.sort_unstable();
    let mut ends: Vec<u32> = link.iter().map(|e| e.1).collect();
    ends.sort_unstable();
    if link.windows(2).any(|w| w[0].0 == w[1].0) || ends.windows(2).any(|w| w[0] == w[1]) {
        return false;
    }
    // Start where the path starts (a start that is no edge's end), else anywhere on the loop.
    let start = link
        .iter()
        .map(|e| e.0)
        .find(|s| ends.binary_search(s).is_err())
        .unwrap_or(link[0].0);
    let (mut at, mut steps) = (start, 0);
    while let Ok(i) = link.binary_search_by_key(&at, |e| e.0) {
        at = link[i].1;
        steps += 1;
        if at == start || steps > link.len() {
            break;
        }
    }
    steps == link.len()
}

/// The next `f32` value after `x` (away from zero; from zero, the smallest positive), as `f64`.
fn f32_step(x: f64) -> f64 {
    let f = x as f32;
    let next = if f == 0.0 {
        f32::from_bits(1)
    } else {
        f32::from_bits(f.to_bits() + 1)
    };
    next as f64
}

/// An indexed triangle mesh: positions in mm, triangles counter-clockwise seen from outside,
/// optional linear RGBA colour per vertex.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriMesh {
    /// Vertex positions.
    pub vertices: Vec<Vec3>,
    /// Triangles as indices into `vertices`, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
    /// One RGBA colour (components in `[0, 1]`) per vertex, if any.
    pub colors: Option<Vec<[f32; 4]>>,
}

/// An edge of a mesh used by other than exactly two triangles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BadEdge {
    /// Vertex indices (smaller first).
    pub indices: [u32; 2],
    /// The end points.
    pub points: [Vec3; 2],
    /// How many triangles use it (1: open; 3 or more: non-manifold).
    pub uses: u32,
}

/// The edges of a mesh that keep it from being a closed 2-manifold, and those whose two
/// triangles disagree on orientation.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EdgeReport {
    /// Edges used by exactly one triangle.
    pub open: usize,
    /// Edges used by three or more triangles, not half of them each way.
    pub non_manifold: usize,
    /// Edges used by four, six… triangles, half of them each way: closed bodies that touch
    /// along an edge or a face (each body closed, the union's boundary well defined), not a
    /// 2-manifold but no hole either.
    pub touching: usize,
    /// Edges used by exactly two triangles that traverse it in the same direction (the two
    /// triangles are inconsistently oriented).
    pub misoriented: usize,
    /// The first few offending edges (at most [`MAX_EDGE_EXAMPLES`]), open and non-manifold
    /// ones first.
    pub examples: Vec<BadEdge>,
}

impl EdgeReport {
    /// Open plus non-manifold edges: those that leave the mesh without a well-defined inside
    /// (edges where closed bodies touch do not).
    pub fn boundary_count(&self) -> usize {
        self.open + self.non_manifold
    }

    /// True when the mesh is closed, manifold at every edge and consistently oriented.
    pub fn is_clean(&self) -> bool {
        self.open == 0 && self.non_manifold == 0 && self.misoriented == 0 && self.touching == 0
    }
}

/// The unit normal of a triangle with corners `[a, b, c]` (right-hand rule; zero when
/// degenerate).
pub(crate) fn facet_normal([a, b, c]: [Vec3; 3]) -> Vec3 {
    (b - a).cross(c - a).normalize_or_zero()
}

impl TriMesh {
    /// An empty mesh.
    pub fn new() -> Self {
        Self::default()
    }

    /// A mesh from positions and triangles, without colours.
    pub fn from_parts(vertices: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> Self {
        Self {
            vertices,
            triangles,
            colors: None,
        }
    }

    /// The closed, outward-oriented 12-triangle mesh of the box `min`–`max` (tests, examples,
    /// simple designs and stocks).
    pub fn cuboid(min: Vec3, max: Vec3) -> Self {
        let c = |i: usize| {
            Vec3::new(
                if i & 1 == 0 { min.x } else { max.x },
                if i & 2 == 0 { min.y } else { max.y },
                if i & 4 == 0 { min.z } else { max.z },
            )
        };
        // Each face counter-clockwise seen from outside.
        let quads: [[u32; 4]; 6] = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let triangles = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        Self::from_parts((0..8).map(c).collect(), triangles)
    }

    /// Checks that every index is in range, every coordinate finite, and that the colour count
    /// matches the vertex count.
    pub fn validate(&self) -> Result<(), IoError> {
        let n = self.vertices.len();
        if n > u32::MAX as usize {
            return Err(IoError::InvalidMesh(format!(
                "{n} vertices, more than u32 indices can address"
            )));
        }
        if let Some(i) = self
            .triangles
            .par_iter()
            .position_first(|t| t.iter().any(|&v| v as usize >= n))
        {
            return Err(IoError::InvalidMesh(format!(
                "triangle {i} has indices {:?} but there are only {n} vertices",
                self.triangles[i]
            )));
        }
        if let Some(i) = self.vertices.par_iter().position_first(|v| !v.is_finite()) {
            return Err(IoError::InvalidMesh(format!(
                "vertex {i} is not finite: {:?}",
                self.vertices[i]
            )));
        }
        if let Some(c) = &self.colors {
            if c.len() != n {
                return Err(IoError::InvalidMesh(format!(
                    "{} colours for {n} vertices",
                    c.len()
                )));
            }
        }
        Ok(())
    }

    /// Number of triangles.
    pub fn len(&self) -> usize {
        self.triangles.len()
    }

    /// True when there are no triangles.
    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }

    /// The three corners of triangle `t`.
    #[inline]
    pub fn corners(&self, t: usize) -> [Vec3; 3] {
        self.triangles[t].map(|i| self.vertices[i as usize])
    }

    /// Unit normal of triangle `t` (zero for a degenerate triangle).
    pub fn triangle_normal(&self, t: usize) -> Vec3 {
        facet_normal(self.corners(t))
    }

    /// Signed volume enclosed (divergence theorem; positive for a closed, outward-oriented
    /// mesh). Computed about the bounding-box centre, which keeps it accurate far from the origin.
    pub fn volume(&self) -> f64 {
        let o = self.aabb().map_or(Vec3::ZERO, |b| b.center());
        // Summed in fixed chunks, then the chunks in order: the same value on any number of
        // threads.
        let parts: Vec<f64> = self
            .triangles
            .par_chunks(SUM_CHUNK)
            .map(|chunk| {
                chunk
                    .iter()
                    .map(|t| {
                        let [a, b, c] = t.map(|i| self.vertices[i as usize] - o);
                        a.dot(b.cross(c))
                    })
                    .sum::<f64>()
            })
            .collect();
        parts.iter().sum::<f64>() / 6.0
    }

    /// Total surface area.
    pub fn area(&self) -> f64 {
        (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.corners(t);
                0.5 * (b - a).cross(c - a).length()
            })
            .sum()
    }

    /// Bounding box of the vertices used by triangles (of all vertices when there are no
    /// triangles), or `None` when there are none.
    pub fn aabb(&self) -> Option<Aabb> {
        if self.triangles.is_empty() {
            return Aabb::from_points(self.vertices.iter().copied());
        }
        self.triangles
            .par_chunks(SUM_CHUNK)
            .filter_map(|chunk| {
                Aabb::from_points(
                    chunk
                        .iter()
                        .flat_map(|t| t.iter().map(|&i| self.vertices[i as usize])),
                )
            })
            .reduce_with(|a, b| a.union(&b))
    }

    /// Open, non-manifold and misoriented edges (by vertex index: weld first if the mesh
    /// repeats positions).
    pub fn edge_report(&self) -> EdgeReport {
        self.edge_report_in_passes(EDGE_USES_PER_PASS)
    }

    /// [`TriMesh::edge_report`] filing at most `per_pass` edge uses at once.
    fn edge_report_in_passes(&self, per_pass: usize) -> EdgeReport {
        // Every edge filed under its smaller vertex (compressed rows, two counting passes: no
        // sort of the 3·T edge uses, whose keys took as much memory as the mesh): the larger
        // vertex, and one bit for the direction the triangle runs it in.
        let n = self.vertices.len();
        let ends = |t: &[u32; 3]| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])];
        let mut start = vec![0u32; n + 1];
        for t in &self.triangles {
            for (a, b) in ends(t) {
                start[a.min(b) as usize + 1] += 1;
            }
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        // The uses are filed in passes over ranges of smaller vertices holding at most
        // `per_pass` uses each (one pass up to ≈ 1.4 M triangles): a 5-million-triangle
        // mesh's 15.5 M uses held at once were 60 MB on top of the mesh, the peak of a whole
        // `swarf envelope` run; each further pass reads the triangles once more.
        let chunk = (n / (4 * rayon::current_num_threads()).max(1)).clamp(1024, 1 << 16);
        let mut parts: Vec<(EdgeReport, Vec<BadEdge>)> = Vec::new();
        let mut v0 = 0;
        while v0 < n {
            let limit = (start[v0] as usize).saturating_add(per_pass);
            let v1 = (start.partition_point(|&s| s as usize <= limit) - 1).clamp(v0 + 1, n);
            let base = start[v0] as usize;
            let uses = start[v1] as usize - base;
            let mut fill: Vec<u32> = start[v0..v1].to_vec();
            let mut other = vec![0u32; uses];
            let mut backward = vec![0u64; uses.div_ceil(64)];
            for t in &self.triangles {
                for (a, b) in ends(t) {
                    let lo = a.min(b) as usize;
                    if !(v0..v1).contains(&lo) {
                        continue;
                    }
                    let slot = &mut fill[lo - v0];
                    let at = *slot as usize - base;
                    *slot += 1;
                    other[at] = a.max(b);
                    backward[at / 64] |= u64::from(a > b) << (at % 64);
                }
            }
            drop(fill);
            // Vertices in chunks, each chunk's edges in (smaller, larger) order: the examples
            // come in the order of the edges' vertex indices.
            parts.par_extend((0..(v1 - v0).div_ceil(chunk)).into_par_iter().map(|c| {
                let mut rep = EdgeReport::default();
                let mut misoriented: Vec<BadEdge> = Vec::new();
                let mut local: Vec<u64> = Vec::new();
                for lo in v0 + c * chunk..(v0 + (c + 1) * chunk).min(v1) {
                    let (s, e) = (start[lo] as usize - base, start[lo + 1] as usize - base);
                    local.clear();
                    local.extend((s..e).map(|at| {
                        (u64::from(other[at]) << 1) | ((backward[at / 64] >> (at % 64)) & 1)
                    }));
                    local.sort_unstable();
                    for edge in local.chunk_by(|x, y| x >> 1 == y >> 1) {
                        let hi = (edge[0] >> 1) as u32;
                        let forward = edge.iter().filter(|&&k| k & 1 == 0).count();
                        let e = || BadEdge {
                            indices: [lo as u32, hi],
                            points: [self.vertices[lo], self.vertices[hi as usize]],
                            uses: edge.len() as u32,
                        };
                        match edge.len() {
                            2 if forward != 1 => {
                                rep.misoriented += 1;
                                if misoriented.len() < MAX_EDGE_EXAMPLES {
                                    misoriented.push(e());
                                }
                            }
                            2 => {}
                            n if n % 2 == 0 && 2 * forward == n => rep.touching += 1,
                            uses => {
                                if uses == 1 {
                                    rep.open += 1;
                                } else {
                                    rep.non_manifold += 1;
                                }
                                if rep.examples.len() < MAX_EDGE_EXAMPLES {
                                    rep.examples.push(e());
                                }
                            }
                        }
                    }
                }
                (rep, misoriented)
            }));
            v0 = v1;
        }
        let mut rep = EdgeReport::default();
        let mut misoriented: Vec<BadEdge> = Vec::new();
        for (r, m) in parts {
            rep.open += r.open;
            rep.non_manifold += r.non_manifold;
            rep.touching += r.touching;
            rep.misoriented += r.misoriented;
            rep.examples.extend(r.examples);
            misoriented.extend(m);
        }
        // Open and non-manifold edges first, then misoriented ones.
        rep.examples.truncate(MAX_EDGE_EXAMPLES);
        rep.examples.extend(misoriented);
        rep.examples.truncate(MAX_EDGE_EXAMPLES);
        rep
    }

    /// Edges not shared by exactly two triangles (open or non-manifold): their count and the
    /// first few.
    pub fn boundary_edges(&self) -> (usize, Vec<BadEdge>) {
        let rep = self.edge_report();
        let ex = rep
            .examples
            .iter()
            .filter(|e| e.uses != 2)
            .copied()
            .collect();
        (rep.boundary_count(), ex)
    }

    /// True when every edge is shared by exactly two triangles.
    pub fn is_closed(&self) -> bool {
        self.edge_report().boundary_count() == 0
    }

    /// The mesh as its files store it and a reader sees it: positions rounded to `f32`, equal
    /// positions one vertex; every triangle kept, even one that collapses.
    pub fn as_written(&self) -> TriMesh {
        let key = |p: Vec3| [p.x as f32, p.y as f32, p.z as f32].map(f32::to_bits);
        let mut order: Vec<u32> = (0..self.vertices.len() as u32).collect();
        order.sort_unstable_by_key(|&i| (key(self.vertices[i as usize]), i));
        let mut remap = vec![0u32; self.vertices.len()];
        let mut vertices: Vec<Vec3> = Vec::new();
        let mut last = None;
        for &i in &order {
            let k = key(self.vertices[i as usize]);
            if last != Some(k) {
                last = Some(k);
                vertices.push(Vec3::from(k.map(|b| f64::from(f32::from_bits(b)))));
            }
            remap[i as usize] = vertices.len() as u32 - 1;
        }
        let triangles = self
            .triangles
            .iter()
            .map(|t| t.map(|v| remap[v as usize]))
            .collect();
        TriMesh::from_parts(vertices, triangles)
    }

    /// Why the mesh is not a 2-manifold, or `None` when it is one: every edge in exactly two
    /// triangles in opposite directions, no triangle with two corners at one point or three on
    /// a line, and the triangles around every vertex a single fan (no two cones touching at a
    /// point). Check [`TriMesh::as_written`] to judge a file.
    pub fn manifold_defect(&self) -> Option<String> {
        let rep = self.edge_report();
        if !rep.is_clean() {
            return Some(format!(
                "{} open, {} non-manifold ({} where bodies touch), {} misoriented edges, e.g. {:?}",
                rep.open,
                rep.non_manifold + rep.touching,
                rep.touching,
                rep.misoriented,
                rep.examples.first()
            ));
        }
        // Around each vertex v, a triangle (v, b, c) leads to the one whose edge out of v is
        // (v, c): on a 2-manifold those links close into one cycle through all of them.
        let mut links: Vec<(u32, u32, u32)> = Vec::with_capacity(3 * self.triangles.len());
        for (i, t) in self.triangles.iter().enumerate() {
            let [a, b, c] = t.map(|v| self.vertices[v as usize]);
            if t[0] == t[1] || t[1] == t[2] || t[2] == t[0] || (b - a).cross(c - a) == Vec3::ZERO {
                return Some(format!("triangle {i} is degenerate: {a} {b} {c}"));
            }
            for r in 0..3 {
                links.push((t[r], t[(r + 1) % 3], t[(r + 2) % 3]));
            }
        }
        links.par_sort_unstable();
        for fan in links.chunk_by(|x, y| x.0 == y.0) {
            let mut at = fan[0].2;
            let mut steps = 1;
            while at != fan[0].1 && steps <= fan.len() {
                // The edge report guarantees exactly one triangle with each outgoing edge.
                let Ok(k) = fan.binary_search_by_key(&at, |l| l.1) else {
                    break;
                };
                at = fan[k].2;
                steps += 1;
            }
            if steps != fan.len() || at != fan[0].1 {
                return Some(format!(
                    "vertex {} ({}) joins {} triangles that are not one fan",
                    fan[0].0,
                    self.vertices[fan[0].0 as usize],
                    fan.len()
                ));
            }
        }
        None
    }

    /// Merges vertices closer than `tolerance` (mm; `0` merges identical positions only),
    /// drops triangles that collapse, and any vertex no longer used. Returns the number of
    /// vertices removed. Each cluster keeps its first vertex (and its colour).
    pub fn weld(&mut self, tolerance: f64) -> usize {
        let n = self.vertices.len();
        let mut remap = vec![u32::MAX; n];
        let mut kept: Vec<u32> = Vec::new();
        if tolerance > 0.0 {
            let inv = 1.0 / tolerance;
            let cell = |p: Vec3| -> [i64; 3] { [p.x, p.y, p.z].map(|c| (c * inv).floor() as i64) };
            let mut buckets: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
            for (i, &p) in self.vertices.iter().enumerate() {
                let c = cell(p);
                let mut found = None;
                'search: for dx in -1..=1 {
                    for dy in -1..=1 {
                        for dz in -1..=1 {
                            // (Saturating: a coordinate far beyond the tolerance's range
                            // lands in the last cell, where the distances still decide.)
                            let near = [
                                c[0].saturating_add(dx),
                                c[1].saturating_add(dy),
                                c[2].saturating_add(dz),
                            ];
                            if let Some(list) = buckets.get(&near) {
                                for &k in list {
                                    if self.vertices[kept[k as usize] as usize].distance(p)
                                        <= tolerance
                                    {
                                        found = Some(k);
                                        break 'search;
                                    }
                                }
                            }
                        }
                    }
                }
                remap[i] = found.unwrap_or_else(|| {
                    let k = kept.len() as u32;
                    kept.push(i as u32);
                    buckets.entry(c).or_default().push(k);
                    k
                });
            }
        } else {
            let mut map: HashMap<[u64; 3], u32> = HashMap::new();
            for (i, p) in self.vertices.iter().enumerate() {
                // -0.0 and 0.0 are the same point.
                let key = [p.x + 0.0, p.y + 0.0, p.z + 0.0].map(f64::to_bits);
                remap[i] = *map.entry(key).or_insert_with(|| {
                    kept.push(i as u32);
                    kept.len() as u32 - 1
                });
            }
        }
        let triangles: Vec<[u32; 3]> = self
            .triangles
            .iter()
            .map(|t| t.map(|i| remap[i as usize]))
            .filter(|t| t[0] != t[1] && t[1] != t[2] && t[2] != t[0])
            .collect();
        // Compact: drop vertices no triangle uses any more.
        let mut used = vec![u32::MAX; kept.len()];
        let mut order: Vec<u32> = Vec::with_capacity(kept.len());
        for t in &triangles {
            for &v in t {
                if used[v as usize] == u32::MAX {
                    used[v as usize] = order.len() as u32;
                    order.push(v);
                }
            }
        }
        let vertices: Vec<Vec3> = order
            .iter()
            .map(|&k| self.vertices[kept[k as usize] as usize])
            .collect();
        let colors = self.colors.as_ref().map(|c| {
            order
                .iter()
                .map(|&k| c[kept[k as usize] as usize])
                .collect()
        });
        self.triangles = triangles
            .into_iter()
            .map(|t| t.map(|v| used[v as usize]))
            .collect();
        let removed = n - vertices.len();
        self.vertices = vertices;
        self.colors = colors;
        removed
    }

    /// Makes the mesh the files store (`f32` positions) free of degenerate triangles without
    /// opening it: vertices whose `f32` positions coincide are merged (a file cannot tell them
    /// apart: its readers weld them, and edges of a closed mesh became shared by four or six
    /// triangles), triangles that collapse are dropped, and each remaining triangle with zero
    /// area at `f32` positions — three distinct corners on a line — is removed by splitting
    /// the triangle across its longest edge at its middle corner (which keeps every edge in
    /// two triangles). Positions stay `f64`; vertices no triangle uses any more are dropped
    /// (the others keep their order). A mesh with nothing to repair is left exactly as it was.
    pub fn repair_degenerate_f32(&mut self) -> DegenerateRepair {
        let mut rep = DegenerateRepair::default();
        let key = |p: Vec3| [p.x, p.y, p.z].map(|c| (c as f32 + 0.0).to_bits());
        // Each vertex to the first vertex at its `f32` position: sorted by (position, index),
        // each run of one position maps to its first index.
        let mut order: Vec<([u32; 3], u32)> = self
            .vertices
            .iter()
            .enumerate()
            .map(|(i, &p)| (key(p), i as u32))
            .collect();
        order.par_sort_unstable();
        let mut remap: Vec<u32> = vec![0; self.vertices.len()];
        // The runs of two vertices or more (rare), as ranges of `members`: listed only they,
        // and without the sort, which is dropped before the tables below are built.
        let mut runs: Vec<std::ops::Range<usize>> = Vec::new();
        let mut members: Vec<u32> = Vec::new();
        let mut start = 0;
        for (n, &(k, i)) in order.iter().enumerate() {
            if n > 0 && order[n - 1].0 != k {
                start = n;
            }
            remap[i as usize] = order[start].1;
            let ends = order.get(n + 1).map_or(true, |next| next.0 != k);
            if ends && n > start {
                let at = members.len();
                members.extend(order[start..=n].iter().map(|&(_, i)| i));
                runs.push(at..members.len());
            }
        }
        drop(order);
        // Two vertices at one position are one in a file. Merged, an edge from it to a
        // neighbour of both is used by four triangles where each had its own closed fan (two
        // cells' vertices clamped to one point): the vertices of such a run are moved one `f32`
        // step apart instead, so that the file keeps them apart. Judged with every other merge
        // made (a cluster of merges can close up only together), again after each round of
        // moves. (Runs are rare: the triangles around each vertex are listed only for them.)
        if !runs.is_empty() {
            let around = VertexTriangles::of_some(self.vertices.len(), &self.triangles, &members);
            for _round in 0..4 {
                let mut moved = false;
                for r in runs.iter_mut().filter(|r| r.start < r.end) {
                    let run = &members[r.clone()];
                    if merge_keeps_manifold(&self.triangles, &around, &remap, run) {
                        continue;
                    }
                    for &m in &run[1..] {
                        remap[m as usize] = m;
                        let p = &mut self.vertices[m as usize];
                        p.x = f32_step(p.x);
                        rep.moved_vertices += 1;
                    }
                    *r = 0..0;
                    moved = true;
                }
                if !moved {
                    break;
                }
            }
        }
        rep.merged_vertices = remap
            .iter()
            .enumerate()
            .filter(|&(i, &r)| r != i as u32)
            .count();
        drop(members);
        // Remapped in place (a mesh with nothing merged keeps its triangles as they were);
        // collapsed triangles become `GONE` until the end.
        let mut tris = std::mem::take(&mut self.triangles);
        rep.collapsed_triangles = tris
            .par_iter_mut()
            .map(|t| {
                *t = t.map(|i| remap[i as usize]);
                let collapsed = t[0] == t[1] || t[1] == t[2] || t[2] == t[0];
                if collapsed {
                    *t = GONE;
                }
                usize::from(collapsed)
            })
            .sum();
        drop(remap);
        let live = |t: [u32; 3]| (t != GONE).then_some(t);
        let f = |p: Vec3| Vec3::new(p.x as f32 as f64, p.y as f32 as f64, p.z as f32 as f64);
        let verts = &self.vertices;
        let flat = |t: [u32; 3]| {
            let [a, b, c] = t.map(|i| f(verts[i as usize]));
            (b - a).cross(c - a) == Vec3::ZERO
        };
        let mut work: Vec<usize> = (0..tris.len())
            .into_par_iter()
            .filter(|&i| live(tris[i]).is_some_and(flat))
            .collect();
        if !work.is_empty() {
            // Directed edge → triangle, for the few triangles around the flat ones only: a
            // vertex's triangles (from `around`, built once without hashing) enter the map
            // the first time an edge at that vertex is looked up; triangles made by a split
            // enter it when they are made. (A map of every edge of a large mesh cost more
            // than the contouring itself.)
            let around = VertexTriangles::new(self.vertices.len(), &tris);
            let mut loaded = vec![false; self.vertices.len()];
            let mut edges: HashMap<(u32, u32), usize> = HashMap::new();
            let mut load = |v: u32, edges: &mut HashMap<(u32, u32), usize>, tris: &[[u32; 3]]| {
                if std::mem::replace(&mut loaded[v as usize], true) {
                    return;
                }
                for &i in around.of(v) {
                    if let Some(t) = live(tris[i as usize]) {
                        for k in 0..3 {
                            edges.insert((t[k], t[(k + 1) % 3]), i as usize);
                        }
                    }
                }
            };
            let mut budget = 4 * tris.len() + 16;
            while let Some(i) = work.pop() {
                budget = budget.saturating_sub(1);
                let Some(t) = live(tris[i]) else { continue };
                if !flat(t) || budget == 0 {
                    continue;
                }
                // The longest side (a, b) in the triangle's order; c lies between a and b.
                let len = |k: usize| {
                    (f(verts[t[k] as usize]) - f(verts[t[(k + 1) % 3] as usize])).length_squared()
                };
                let k = (0..3)
                    .max_by(|&x, &y| len(x).total_cmp(&len(y)))
                    .unwrap_or(0);
                let (a, b, c) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
                for v in [a, b, c] {
                    load(v, &mut edges, &tris);
                }
                let Some(&j) = edges.get(&(b, a)) else {
                    continue;
                };
                let Some(n) = live(tris[j]) else { continue };
                let d = n.iter().copied().find(|&v| v != a && v != b).unwrap_or(c);
                load(d, &mut edges, &tris);
                if j == i || d == c || edges.contains_key(&(c, d)) || edges.contains_key(&(d, c)) {
                    continue;
                }
                for old in [t, n] {
                    for k in 0..3 {
                        edges.remove(&(old[k], old[(k + 1) % 3]));
                    }
                }
                tris[i] = [b, c, d];
                tris[j] = [c, a, d];
                for idx in [i, j] {
                    let nt = tris[idx];
                    for k in 0..3 {
                        edges.insert((nt[k], nt[(k + 1) % 3]), idx);
                    }
                    work.push(idx);
                }
                rep.split_caps += 1;
            }
            rep.remaining_flat = tris.iter().filter(|&&t| t != GONE && flat(t)).count();
        }
        if rep.merged_vertices == 0
            && rep.collapsed_triangles == 0
            && rep.split_caps == 0
            && rep.moved_vertices == 0
        {
            self.triangles = tris;
            return rep;
        }
        tris.retain(|&t| t != GONE);
        self.triangles = tris;
        // Drop unused vertices, keeping the order of the others.
        let mut used = vec![u32::MAX; self.vertices.len()];
        for t in &self.triangles {
            for &v in t {
                used[v as usize] = 0;
            }
        }
        let mut next = 0u32;
        for u in used.iter_mut() {
            if *u == 0 {
                *u = next;
                next += 1;
            }
        }
        // Compacted in place, in order.
        fn keep_used<T: Copy>(items: &mut Vec<T>, used: &[u32]) {
            let mut w = 0;
            for i in 0..items.len() {
                if used.get(i).is_some_and(|&u| u != u32::MAX) {
                    items[w] = items[i];
                    w += 1;
                }
            }
            items.truncate(w);
        }
        keep_used(&mut self.vertices, &used);
        if let Some(c) = &mut self.colors {
            keep_used(c, &used);
        }
        for t in &mut self.triangles {
            *t = t.map(|v| used[v as usize]);
        }
        rep
    }

    /// Appends `other` (its indices shifted). Colours are kept when both meshes have them or
    /// the result would otherwise have none; a mesh without colours contributes opaque white.
    pub fn merge(&mut self, other: &TriMesh) {
        let offset = self.vertices.len() as u32;
        match (&mut self.colors, &other.colors) {
            (Some(a), Some(b)) => a.extend_from_slice(b),
            (Some(a), None) => a.resize(a.len() + other.vertices.len(), [1.0; 4]),
            (None, Some(b)) => {
                let mut c = vec![[1.0f32; 4]; self.vertices.len()];
                c.extend_from_slice(b);
                self.colors = Some(c);
            }
            (None, None) => {}
        }
        self.vertices.extend_from_slice(&other.vertices);
        self.triangles
            .extend(other.triangles.iter().map(|t| t.map(|i| i + offset)));
    }

    /// Area-weighted unit vertex normals (zero for unused vertices).
    pub fn vertex_normals(&self) -> Vec<Vec3> {
        // One pass (a parallel sum over chunks needs a partial array per chunk: measured, as
        // much memory again as the normals for no time gained on a 5-million-triangle mesh).
        let mut n = area_vectors_at(&self.vertices, &self.triangles, 0..self.vertices.len());
        n.par_iter_mut().for_each(|v| *v = v.normalize_or_zero());
        n
    }

    /// Reverses every triangle (turns the mesh inside out).
    pub fn flip(&mut self) {
        for t in &mut self.triangles {
            t.swap(1, 2);
        }
    }
}

/// The area vectors (twice the area along the normal) of `triangles` summed, in their order,
/// at each vertex in `range` (entry `i − range.start`): the vertex normals before they are made
/// unit, for a whole mesh or for the vertices a run of its triangles surrounds (the streamed
/// contouring's slabs), with the same sums either way.
pub(crate) fn area_vectors_at(
    vertices: &[Vec3],
    triangles: &[[u32; 3]],
    range: std::ops::Range<usize>,
) -> Vec<Vec3> {
    let mut sum = vec![Vec3::ZERO; range.len()];
    for t in triangles {
        let [a, b, c] = t.map(|i| vertices[i as usize]);
        let w = (b - a).cross(c - a);
        for &i in t {
            if range.contains(&(i as usize)) {
                sum[i as usize - range.start] += w;
            }
        }
    }
    sum
}

/// Edge uses filed at once by [`TriMesh::edge_report`] (16 MB of them).
const EDGE_USES_PER_PASS: usize = 1 << 22;

/// Triangles per chunk of the parallel sums and scans over a mesh's triangles (fixed, so that
/// a sum is the same on any number of threads).
const SUM_CHUNK: usize = 1 << 14;

/// A triangle removed while a mesh is repaired in place.
const GONE: [u32; 3] = [u32::MAX; 3];

/// The triangles around each vertex, as one array per mesh (compressed rows: counts, then
/// offsets, then indices), built in two passes without hashing.
pub(crate) struct VertexTriangles {
    start: Vec<u32>,
    index: Vec<u32>,
    /// The vertices listed, sorted, when only some are (`start` is then per entry of this
    /// list); `None`: every vertex, `start` per vertex.
    only: Option<Vec<u32>>,
}

impl VertexTriangles {
    /// Each vertex's triangles (corner indices below `vertices`; `GONE` triangles skipped).
    pub(crate) fn new(vertices: usize, tris: &[[u32; 3]]) -> Self {
        Self::build(vertices, tris, |v| Some(v as usize))
    }

    /// The triangles of the vertices in `wanted` only (any order, repeats allowed): for a few
    /// vertices of a large mesh, a table the size of their fans rather than of the mesh.
    pub(crate) fn of_some(vertices: usize, tris: &[[u32; 3]], wanted: &[u32]) -> Self {
        let mut only = wanted.to_vec();
        only.sort_unstable();
        only.dedup();
        // A bit per vertex rejects the corners of almost every triangle without a search.
        let mut marked = vec![0u64; vertices.div_ceil(64)];
        for &v in &only {
            marked[v as usize / 64] |= 1 << (v % 64);
        }
        let slot = |v: u32| {
            (marked[v as usize / 64] >> (v % 64) & 1 == 1)
                .then(|| only.binary_search(&v).ok())
                .flatten()
        };
        let built = Self::build(only.len(), tris, slot);
        Self {
            only: Some(only),
            ..built
        }
    }

    /// The table of `slots` entries, vertex `v` filed under `slot(v)` (none: not listed).
    fn build(slots: usize, tris: &[[u32; 3]], slot: impl Fn(u32) -> Option<usize>) -> Self {
        let mut start = vec![0u32; slots + 1];
        for t in tris.iter().filter(|&&t| t != GONE) {
            for &v in t {
                if let Some(s) = slot(v) {
                    start[s + 1] += 1;
                }
            }
        }
        for i in 0..slots {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut index = vec![0u32; start[slots] as usize];
        for (i, t) in tris.iter().enumerate().filter(|(_, &t)| t != GONE) {
            for &v in t {
                if let Some(s) = slot(v) {
                    index[fill[s] as usize] = i as u32;
                    fill[s] += 1;
                }
            }
        }
        Self {
            start,
            index,
            only: None,
        }
    }

    /// The triangles that had `v` as a corner when this was built (none for a vertex not
    /// listed by [`VertexTriangles::of_some`]).
    pub(crate) fn of(&self, v: u32) -> &[u32] {
        let s = match &self.only {
            None => v as usize,
            Some(only) => match only.binary_search(&v) {
                Ok(s) => s,
                Err(_) => return &[],
            },
        };
        &self.index[self.start[s] as usize..self.start[s + 1] as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetra() -> TriMesh {
        TriMesh::from_parts(
            vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
            vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        )
    }

    #[test]
    fn manifold_defects_are_named() {
        assert_eq!(tetra().manifold_defect(), None);
        // Two tetrahedra touching at one vertex: every edge is fine, the vertex is not.
        let mut two = tetra();
        let far = tetra();
        let offset = two.vertices.len() as u32;
        two.vertices
            .extend(far.vertices.iter().map(|&p| Vec3::splat(1.0) - p));
        // Their shared corner: (1, 1, 1) − Z = (1, 1, 0) is not a corner of the first, so
        // weld the second's vertex 0, (1, 1, 1), onto a new shared point instead.
        two.vertices[offset as usize] = Vec3::ZERO;
        two.triangles.extend(
            far.triangles
                .iter()
                .map(|t| t.map(|v| if v == 0 { 0 } else { v + offset })),
        );
        let defect = two.manifold_defect().unwrap();
        assert!(defect.contains("not one fan"), "{defect}");
        // A triangle with three corners on a line.
        let mut flat = tetra();
        flat.vertices[3] = Vec3::new(0.5, 0.5, 0.0);
        let defect = flat.manifold_defect().unwrap();
        assert!(defect.contains("degenerate"), "{defect}");
        // Two vertices one f32 apart become one when written.
        let mut near = tetra();
        near.vertices.push(Vec3::Z + Vec3::new(0.0, 0.0, 1e-12));
        near.triangles[1] = [0, 1, 4];
        assert!(!near.edge_report().is_clean());
        let w = near.as_written();
        assert_eq!(w.vertices.len(), 4);
        assert_eq!(w.manifold_defect(), None);
    }

    #[test]
    fn a_table_of_some_vertices_lists_their_fans_as_the_full_one_does() {
        // A contoured sphere: the wanted vertices (repeats and an unused index among them)
        // get exactly the full table's triangles, the others none.
        use crate::contour::{dual_contour, ContourOptions, FnGrid, Lattice};
        let lattice = Lattice::new(Vec3::splat(-1.2), Vec3::splat(0.1), [25, 25, 25]);
        let mesh = dual_contour(
            &FnGrid::new(lattice, |p: Vec3| p.length() - 1.0),
            &ContourOptions::default(),
        );
        let nv = mesh.vertices.len() as u32;
        let mut tris = mesh.triangles.clone();
        tris[5] = GONE;
        let full = VertexTriangles::new(mesh.vertices.len(), &tris);
        let wanted = [7, 3, nv - 1, 7, tris[5 + 1][0]];
        let some = VertexTriangles::of_some(mesh.vertices.len(), &tris, &wanted);
        for v in 0..nv {
            let expected = if wanted.contains(&v) { full.of(v) } else { &[] };
            assert_eq!(some.of(v), expected, "vertex {v}");
        }
        assert!(wanted.iter().all(|&v| !full.of(v).is_empty()));
    }

    #[test]
    fn parallel_sums_match_one_pass_over_the_triangles() {
        // A contoured sphere (tens of thousands of triangles: several chunks), in its own
        // triangle order and shuffled (every chunk reaching over all vertices), against one
        // serial pass; and the same bits on one thread and on three.
        use crate::contour::{dual_contour, ContourOptions, FnGrid, Lattice};
        let lattice = Lattice::new(Vec3::splat(-1.2), Vec3::splat(0.02), [121, 121, 121]);
        let sphere = FnGrid::new(lattice, |p: Vec3| p.length() - 1.0);
        let ordered = dual_contour(&sphere, &ContourOptions::default());
        assert!(ordered.triangles.len() > 4 * SUM_CHUNK, "{}", ordered.len());
        let mut shuffled = ordered.clone();
        let t = shuffled.triangles.len();
        shuffled.triangles = (0..t).map(|i| ordered.triangles[(i * 7919) % t]).collect();
        for m in [&ordered, &shuffled] {
            let mut normals = vec![Vec3::ZERO; m.vertices.len()];
            let (mut volume, mut lo, mut hi) = (0.0, Vec3::INFINITY, Vec3::NEG_INFINITY);
            let o = Vec3::ZERO; // the sphere's box centre, to rounding
            for tri in &m.triangles {
                let [a, b, c] = tri.map(|i| m.vertices[i as usize]);
                for &i in tri {
                    normals[i as usize] += (b - a).cross(c - a);
                }
                volume += (a - o).dot((b - o).cross(c - o)) / 6.0;
                for p in [a, b, c] {
                    (lo, hi) = (lo.min(p), hi.max(p));
                }
            }
            let got = m.vertex_normals();
            for (g, n) in got.iter().zip(&normals) {
                assert!((*g - n.normalize()).length() < 1e-12, "{g} vs {n}");
            }
            assert!(
                (m.volume() - volume).abs() < 1e-12 * volume,
                "{} vs {volume}",
                m.volume()
            );
            assert!((m.volume() - 4.0 / 3.0 * std::f64::consts::PI).abs() < 2e-3);
            let b = m.aabb().unwrap();
            assert_eq!((b.min, b.max), (lo, hi));
            let a = swarf_testdata::on_threads(1, || (m.vertex_normals(), m.volume()));
            let b = swarf_testdata::on_threads(3, || (m.vertex_normals(), m.volume()));
            assert_eq!(a.0, b.0);
            assert_eq!(a.1.to_bits(), b.1.to_bits());
        }
    }

    #[test]
    fn edge_reports_in_several_passes_are_the_same() {
        // A contoured sphere with defects of every kind (a triangle dropped: open edges; one
        // repeated: non-manifold; some turned: misoriented), filed in one pass and in passes of
        // a few hundred uses (a vertex with more uses than a pass gets a pass of its own).
        use crate::contour::{dual_contour, ContourOptions, FnGrid, Lattice};
        let lattice = Lattice::new(Vec3::splat(-1.2), Vec3::splat(0.1), [25, 25, 25]);
        let mut m = dual_contour(
            &FnGrid::new(lattice, |p: Vec3| p.length() - 1.0),
            &ContourOptions::default(),
        );
        let whole = m.edge_report_in_passes(usize::MAX);
        assert!(whole.is_clean());
        m.triangles.remove(10);
        let again = m.triangles[200];
        m.triangles.push(again);
        // Misoriented edges all over (every seventh triangle turned), so that every pass has
        // some to count.
        for t in m.triangles.iter_mut().step_by(7) {
            t.swap(1, 2);
        }
        let whole = m.edge_report_in_passes(usize::MAX);
        assert!(whole.open > 0 && whole.non_manifold > 0 && whole.misoriented > 1000);
        for per_pass in [1, 7, 300, 1000] {
            let parts = m.edge_report_in_passes(per_pass);
            assert_eq!(
                (parts.open, parts.non_manifold, parts.misoriented),
                (whole.open, whole.non_manifold, whole.misoriented),
                "{per_pass} uses per pass"
            );
            let key = |r: &EdgeReport| {
                r.examples
                    .iter()
                    .map(|e| (e.indices, e.uses))
                    .collect::<Vec<_>>()
            };
            assert_eq!(key(&parts), key(&whole), "{per_pass} uses per pass");
        }
    }

    #[test]
    fn closed_bodies_touching_along_an_edge_leave_no_boundary() {
        // Two tetrahedra sharing the edge 0–1, the second the first turned half a turn about
        // X (its vertices 2, 3 at −Y, −Z, the same triangles): the shared edge is used four
        // times, twice each way. Closed bodies that touch: no boundary, no 2-manifold either.
        let mut two = tetra();
        two.vertices
            .extend([Vec3::new(0.0, -1.0, 0.0), Vec3::new(0.0, 0.0, -1.0)]);
        two.triangles
            .extend([[0, 4, 1], [0, 1, 5], [0, 5, 4], [1, 4, 5]]);
        let r = two.edge_report();
        assert_eq!((r.open, r.non_manifold, r.touching), (0, 0, 1), "{r:?}");
        assert_eq!(r.boundary_count(), 0);
        assert!(!r.is_clean());
        assert!((two.volume() - 2.0 / 6.0).abs() < 1e-15);
        // Three triangles on one edge (a fin) stay non-manifold.
        let mut fin = tetra();
        fin.vertices.push(Vec3::new(0.0, -1.0, 0.0));
        fin.triangles.push([0, 1, 4]);
        let r = fin.edge_report();
        assert!(r.non_manifold > 0 && r.touching == 0, "{r:?}");
    }

    #[test]
    fn tetra_volume_area_closed() {
        let m = tetra();
        assert!((m.volume() - 1.0 / 6.0).abs() < 1e-15);
        let area = 1.5 + 0.5 * 3f64.sqrt();
        assert!((m.area() - area).abs() < 1e-14);
        assert!(m.edge_report().is_clean());
        let mut f = m.clone();
        f.triangles[3].swap(1, 2);
        let r = f.edge_report();
        assert_eq!((r.open, r.non_manifold, r.misoriented), (0, 0, 3));
        let mut o = m.clone();
        o.triangles.pop();
        let (count, ex) = o.boundary_edges();
        assert_eq!(count, 3);
        assert_eq!(ex.len(), 3);
        assert!(ex.iter().all(|e| e.uses == 1));
    }

    #[test]
    fn degenerate_triangles_are_repaired_without_opening_the_mesh() {
        // A tetrahedron whose edge 0-1 carries a midpoint on one side only: closed, with a
        // zero-area cap (0, 1, m) and a vertex 1e-12 mm from vertex 3 (one point in f32).
        let m = tetra();
        let mut v = m.vertices.clone();
        v.push(0.5 * (v[0] + v[1])); // 4 = m
        v.push(v[3] + Vec3::new(0.0, 0.0, 1e-12)); // 5 ~ 3 (1 + 1e-12 is 1 in f32)
        let t = vec![
            [0, 2, 1],
            [0, 4, 5],
            [4, 1, 3],
            [0, 1, 4],
            [0, 3, 2],
            [1, 2, 3],
        ];
        let mut mesh = TriMesh::from_parts(v, t);
        assert!(
            !mesh.edge_report().is_clean(),
            "vertex 5 is not vertex 3 yet"
        );
        let rep = mesh.repair_degenerate_f32();
        assert_eq!(
            rep,
            DegenerateRepair {
                merged_vertices: 1,
                collapsed_triangles: 0,
                split_caps: 1,
                remaining_flat: 0,
                moved_vertices: 0,
            }
        );
        assert!(mesh.edge_report().is_clean(), "{:?}", mesh.edge_report());
        assert_eq!((mesh.vertices.len(), mesh.triangles.len()), (5, 6));
        assert!((mesh.volume() - 1.0 / 6.0).abs() < 1e-12);
        for i in 0..mesh.len() {
            let [a, b, c] = mesh.corners(i);
            assert!((b - a).cross(c - a).length() > 1e-3, "triangle {i} is flat");
        }
        // Nothing to repair: nothing changes.
        let before = mesh.clone();
        assert_eq!(mesh.repair_degenerate_f32(), DegenerateRepair::default());
        assert_eq!(mesh, before);
    }

    #[test]
    fn coincident_vertices_that_would_pinch_are_moved_apart() {
        // Two closed tetrahedra about (1, 1, 1), the second mirrored through the plane x = 1
        // so that it has the first's face 0–2–3 (its vertices 1e-12 mm off: one point each in
        // f32). Merged, the face's edges would each be used by four triangles: the three
        // pairs are moved one f32 step apart instead, the two solids kept as they were.
        let shift = Vec3::splat(1.0);
        let mut two = tetra();
        two.vertices.iter_mut().for_each(|p| *p += shift);
        let mirrored = TriMesh::from_parts(
            two.vertices
                .iter()
                .map(|&p| Vec3::new(2.0 - p.x, p.y, p.z) + Vec3::splat(1e-12))
                .collect(),
            two.triangles.iter().map(|t| [t[0], t[2], t[1]]).collect(),
        );
        let first = two.clone();
        two.merge(&mirrored);
        assert!(two.edge_report().is_clean());
        let rep = two.repair_degenerate_f32();
        assert_eq!((rep.merged_vertices, rep.moved_vertices), (0, 3), "{rep:?}");
        assert!(two.edge_report().is_clean(), "{:?}", two.edge_report());
        assert_eq!(two.vertices.len(), 8);
        // What a file stores: eight distinct f32 positions, still two closed solids.
        let mut keys: Vec<[u32; 3]> = two
            .vertices
            .iter()
            .map(|p| [p.x, p.y, p.z].map(|c| (c as f32).to_bits()))
            .collect();
        keys.sort_unstable();
        keys.dedup();
        assert_eq!(keys.len(), 8);
        assert!((two.volume() - 2.0 / 6.0).abs() < 1e-6);
        // Merging every coincident pair, as before, makes edges of four triangles (two each
        // way: bodies touching).
        let mut pinched = first;
        pinched.merge(&mirrored);
        for v in pinched.triangles.iter_mut().flatten() {
            if [4, 6, 7].contains(v) {
                *v -= 4;
            }
        }
        assert_eq!(pinched.edge_report().touching, 3);
    }

    #[test]
    fn weld_and_merge() {
        let m = tetra();
        // Unweld: every triangle its own vertices, nudged by 1e-9.
        let mut soup = TriMesh::new();
        for t in 0..m.len() {
            let c = m.corners(t);
            let base = soup.vertices.len() as u32;
            soup.vertices
                .extend(c.iter().map(|&p| p + Vec3::splat(1e-9 * t as f64)));
            soup.triangles.push([base, base + 1, base + 2]);
        }
        assert!(!soup.is_closed());
        let mut exact = soup.clone();
        assert_eq!(exact.weld(0.0), 0);
        assert_eq!(soup.weld(1e-6), 8);
        assert_eq!(soup.vertices.len(), 4);
        assert!(soup.edge_report().is_clean());
        let mut two = m.clone();
        let mut moved = m.clone();
        moved
            .vertices
            .iter_mut()
            .for_each(|v| *v += Vec3::splat(5.0));
        moved.colors = Some(vec![[1.0, 0.0, 0.0, 1.0]; 4]);
        two.merge(&moved);
        assert_eq!(two.vertices.len(), 8);
        assert_eq!(two.colors.as_ref().unwrap()[0], [1.0; 4]);
        assert!((two.volume() - 2.0 / 6.0).abs() < 1e-14);
        assert!(two.validate().is_ok());
        two.triangles.push([0, 1, 8]);
        assert!(two.validate().is_err());
    }

    #[test]
    fn weld_takes_coordinates_beyond_its_cells() {
        // Found by the `stl` and `ply` fuzz targets: 1e300 / 1e-6 saturates the cell index at
        // i64::MAX, whose neighbour overflowed (a panic where overflow is checked: debug and
        // fuzz builds; `cargo test` without `--release` fails here without the fix). Points
        // there are still welded by distance.
        let far = 1e300;
        let mut m = TriMesh::from_parts(
            vec![
                Vec3::new(far, 0.0, 0.0),
                Vec3::new(far, 1.0, 0.0),
                Vec3::new(far, 0.0, 1.0),
                Vec3::new(far, 0.0, 1.0),
                Vec3::new(-far, -far, 0.0),
            ],
            vec![[0, 1, 2], [0, 3, 4]],
        );
        assert_eq!(m.weld(1e-6), 1);
        assert_eq!(m.vertices.len(), 4);
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    }

    /// The edge uses sorted whole, as a plain reference for [`TriMesh::edge_report`].
    fn edge_report_by_sorting(m: &TriMesh) -> EdgeReport {
        let mut keys: Vec<u64> = m
            .triangles
            .iter()
            .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
            .map(|(a, b)| {
                (u64::from(a.min(b)) << 33) | (u64::from(a.max(b)) << 1) | u64::from(a > b)
            })
            .collect();
        keys.sort_unstable();
        let mut rep = EdgeReport::default();
        let (mut bad, mut mis) = (Vec::new(), Vec::new());
        for edge in keys.chunk_by(|x, y| x >> 1 == y >> 1) {
            let (a, b) = (
                (edge[0] >> 33) as u32,
                ((edge[0] >> 1) & 0xffff_ffff) as u32,
            );
            let forward = edge.iter().filter(|&&k| k & 1 == 0).count();
            let e = BadEdge {
                indices: [a, b],
                points: [m.vertices[a as usize], m.vertices[b as usize]],
                uses: edge.len() as u32,
            };
            match (edge.len(), forward) {
                (2, 1) => {}
                (2, _) => {
                    rep.misoriented += 1;
                    mis.push(e);
                }
                (1, _) => {
                    rep.open += 1;
                    bad.push(e);
                }
                (n, f) if n % 2 == 0 && 2 * f == n => rep.touching += 1,
                _ => {
                    rep.non_manifold += 1;
                    bad.push(e);
                }
            }
        }
        bad.truncate(MAX_EDGE_EXAMPLES);
        mis.truncate(MAX_EDGE_EXAMPLES);
        bad.extend(mis);
        bad.truncate(MAX_EDGE_EXAMPLES);
        rep.examples = bad;
        rep
    }

    proptest::proptest! {
        /// Random triangle soups over few vertices (every kind of defect, many of each, across
        /// the chunks the report works in): the same counts and the same examples, in the
        /// same order, as sorting every edge use.
        #[test]
        fn edge_report_equals_sorting_every_edge(
            n in 1usize..5000,
            raw in proptest::collection::vec((0u32..5000, 0u32..5000, 0u32..5000), 0..3000),
        ) {
            let vertices = (0..n).map(|i| Vec3::new(i as f64, 0.5 * i as f64, 0.0)).collect();
            let triangles = raw
                .into_iter()
                .map(|(a, b, c)| [a, b, c].map(|v| v % n as u32))
                .collect();
            let m = TriMesh::from_parts(vertices, triangles);
            let want = edge_report_by_sorting(&m);
            let got = m.edge_report();
            proptest::prop_assert_eq!(
                (got.open, got.non_manifold, got.misoriented),
                (want.open, want.non_manifold, want.misoriented)
            );
            proptest::prop_assert_eq!(got.examples, want.examples);
        }
    }
}
