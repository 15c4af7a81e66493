//! Coplanar triangles of a closed mesh merged into few: [`TriMesh::merge_coplanar`].
//!
//! Dual contouring puts two triangles in every lattice cell the surface crosses, flat or not:
//! a block's face of 40 × 40 mm at h = 0.05 mm is 1.3 M triangles, and so is every face of a
//! machined part, every wall of a swept envelope. The merge keeps the mesh's vertices where
//! they are and only takes out those that no longer bound anything, so it changes the surface
//! by at most the coplanarity tolerance (10⁻⁶ mm by default, [`PLANAR_TOLERANCE_MM`]):
//!
//! 1. **Regions.** Triangles are grown into regions across shared edges while every corner of a
//!    new triangle lies within the tolerance of the region's first triangle's plane (so a region
//!    never drifts along a gently curved surface) and it faces the same way.
//! 2. **Loops.** A region of two or more triangles is a polygon: its boundary edges (those
//!    whose other triangle is in another region) chained into loops — one outer loop and any
//!    holes. A region whose boundary passes twice through a vertex is left as it is.
//! 3. **Straight boundaries.** Along the boundary shared by two merged regions, vertices that
//!    lie within the tolerance of the straight line through the vertices kept either side are
//!    taken out of both polygons at once (one region decides for both), so the two still meet
//!    edge to edge: no T-junction, the mesh stays closed. A vertex on the boundary of three
//!    regions, or of a region left as it is, always stays. This is what turns a column of
//!    quads on a cylinder along a lattice axis — coplanar, bounded by two straight lines of
//!    vertices — into two triangles.
//! 4. **Triangles.** Each polygon (with its holes) is cut into triangles by ear clipping
//!    (`earcutr`) in its plane, oriented as the region was. The triangles of one polygon must
//!    number `vertices − 2 + 2·holes` and cover its area once, and every edge they make must
//!    end in exactly two triangles of the result, once each way. Contouring leaves the odd
//!    triangle folded flat onto a face, facing the other way across a notch of its polygon: the
//!    ear clipped there is that triangle again, and the two, enclosing nothing, are both left
//!    out. A region whose polygon still fails is left as it is and the rest merged again
//!    (four rounds at most, then the input is returned).
//!
//! The result is closed when the input is (every edge between two regions is one straight
//! segment in both polygons) and encloses the same volume within `tolerance × area`; both are
//! checked at the end, and a result that fails is not returned.

use crate::mesh::{TriMesh, VertexTriangles};
use crate::tolerance::PLANAR_TOLERANCE_MM;
use rayon::prelude::*;
use std::collections::HashMap;
use swarf_geom::math::Vec3;

/// Rounds of [`Merge::run`] at most (each leaves out the regions whose polygons failed).
const MAX_ROUNDS: usize = 4;

/// Vertices at most in one straight stretch of a boundary that is not straight as a whole
/// (bounds the search, quadratic in it).
const MAX_STRAIGHT: usize = 64;

/// No neighbour (an open edge) or no region.
const NONE: u32 = u32::MAX;

/// What [`TriMesh::merge_coplanar`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PlanarMerge {
    /// Triangles before.
    pub triangles_before: usize,
    /// Triangles after.
    pub triangles_after: usize,
    /// Vertices before.
    pub vertices_before: usize,
    /// Vertices after.
    pub vertices_after: usize,
    /// Regions of two or more triangles made into polygons.
    pub polygons: usize,
    /// Triangles of the result flat once written (`f32`) that the repair could not take out
    /// (`TriMesh::repair_degenerate_f32`; the contouring leaves such too).
    pub flat_triangles: usize,
    /// True when the merge was given up and the mesh is the input: not a closed manifold, with
    /// per-vertex colours, polygons still failing after the last round, or a result that fails
    /// its closedness or volume check.
    pub given_up: bool,
}

impl TriMesh {
    /// This mesh with its coplanar triangles merged, within [`PLANAR_TOLERANCE_MM`] (module
    /// documentation, `crate::planar`); see [`TriMesh::merge_coplanar_within`].
    pub fn merge_coplanar(&self) -> (TriMesh, PlanarMerge) {
        self.merge_coplanar_within(PLANAR_TOLERANCE_MM)
    }

    /// This mesh with the triangles that lie in one plane within `tolerance` mm merged into
    /// few, its vertices a subset of this mesh's. The result is checked closed and of the same
    /// volume (within `2·tolerance·area`); a mesh that is not a closed manifold, that has
    /// per-vertex colours, or whose merge would fail those checks, is returned as it is
    /// (`given_up`). The input is expected closed: it is what the check compares against.
    pub fn merge_coplanar_within(&self, tolerance: f64) -> (TriMesh, PlanarMerge) {
        let mut stats = PlanarMerge {
            triangles_before: self.triangles.len(),
            vertices_before: self.vertices.len(),
            ..Default::default()
        };
        let unchanged = |mut stats: PlanarMerge| {
            stats.triangles_after = stats.triangles_before;
            stats.vertices_after = stats.vertices_before;
            stats.given_up = true;
            (self.clone(), stats)
        };
        if self.colors.is_some() || self.triangles.is_empty() {
            return unchanged(stats);
        }
        let Some(m) = Merge::new(self, tolerance) else {
            return unchanged(stats);
        };
        let Some((mut mesh, polygons)) = m.run() else {
            return unchanged(stats);
        };
        // Ear clipping may cut a triangle of three points nearly on a line (a vertex kept on a
        // straight stretch, beside a region left as it is), flat once written as `f32`: the
        // contouring's own repair splits a neighbour to take it out where it can.
        stats.flat_triangles = mesh.repair_degenerate_f32().remaining_flat;
        // What the construction promises, checked: still closed and consistently oriented,
        // the same volume within the tolerance over the surface.
        let slack = 2.0 * tolerance * self.area() + 1e-9 * self.volume().abs();
        if !mesh.edge_report().is_clean() || (mesh.volume() - self.volume()).abs() > slack {
            return unchanged(stats);
        }
        stats.triangles_after = mesh.triangles.len();
        stats.vertices_after = mesh.vertices.len();
        stats.polygons = polygons;
        (mesh, stats)
    }
}

/// A polygon's triangles, and the folded triangles of other regions they cancel.
struct Fitted {
    triangles: Vec<[u32; 3]>,
    cancelled: Vec<u32>,
}

/// The merge's working state.
struct Merge<'m> {
    mesh: &'m TriMesh,
    tol: f64,
    /// Per triangle and edge `i` (from corner `i` to `i + 1`), the triangle across it.
    across: Vec<[u32; 3]>,
    /// Per vertex, its triangles.
    fans: VertexTriangles,
}

impl<'m> Merge<'m> {
    /// The adjacency of `mesh`; `None` when an edge has no twin or several (not a closed
    /// manifold: nothing is merged).
    fn new(mesh: &'m TriMesh, tol: f64) -> Option<Self> {
        let (nv, tris) = (mesh.vertices.len(), &mesh.triangles);
        if tris.iter().flatten().any(|&v| v as usize >= nv) {
            return None;
        }
        let fans = VertexTriangles::new(nv, tris);
        // The triangle across each edge a → b: the one of a's fan with the edge b → a.
        let across: Vec<[u32; 3]> = tris
            .par_iter()
            .map(|t| {
                let mut out = [NONE; 3];
                for i in 0..3 {
                    let (a, b) = (t[i], t[(i + 1) % 3]);
                    let mut twins = fans.of(a).iter().filter(|&&u| {
                        let s = &tris[u as usize];
                        (0..3).any(|j| s[j] == b && s[(j + 1) % 3] == a)
                    });
                    match (twins.next(), twins.next()) {
                        (Some(&u), None) => out[i] = u,
                        _ => return None,
                    }
                }
                Some(out)
            })
            .collect::<Option<Vec<_>>>()?;
        Some(Self {
            mesh,
            tol,
            across,
            fans,
        })
    }

    /// The triangles around vertex `v`.
    fn fan(&self, v: u32) -> &[u32] {
        self.fans.of(v)
    }

    /// Triangle `t`'s unit normal (zero for a degenerate one).
    fn normal(&self, t: u32) -> Vec3 {
        let [a, b, c] = [0, 1, 2].map(|i| self.corner(t, i));
        (b - a).cross(c - a).normalize_or_zero()
    }

    fn corner(&self, t: u32, i: usize) -> Vec3 {
        self.mesh.vertices[self.mesh.triangles[t as usize][i] as usize]
    }

    /// Each triangle's region, grown from each unassigned triangle in order (deterministic),
    /// and each region's size and first triangle.
    fn regions(&self) -> (Vec<u32>, Vec<u32>, Vec<u32>) {
        let n = self.mesh.triangles.len();
        let mut region = vec![NONE; n];
        let (mut sizes, mut seeds) = (Vec::new(), Vec::new());
        let mut stack = Vec::new();
        for seed in 0..n as u32 {
            if region[seed as usize] != NONE {
                continue;
            }
            let r = sizes.len() as u32;
            region[seed as usize] = r;
            let mut size = 1u32;
            let normal = self.normal(seed);
            if normal != Vec3::ZERO {
                let offset = normal.dot(self.corner(seed, 0));
                stack.push(seed);
                while let Some(t) = stack.pop() {
                    for &u in &self.across[t as usize] {
                        // The corners first (cheap, and where most neighbours part), then the
                        // side it faces: a triangle folded back onto the plane faces the other
                        // way. (Its normal's direction is not compared: that of a small
                        // triangle within the tolerance of the plane may lean far more.)
                        if region[u as usize] != NONE
                            || (0..3)
                                .any(|i| (normal.dot(self.corner(u, i)) - offset).abs() > self.tol)
                            || normal.dot(self.normal(u)) <= 0.0
                        {
                            continue;
                        }
                        region[u as usize] = r;
                        size += 1;
                        stack.push(u);
                    }
                }
            }
            sizes.push(size);
            seeds.push(seed);
        }
        (region, sizes, seeds)
    }

    /// The merged mesh and the number of polygons. A region whose polygon would not cut into
    /// triangles that fit the mesh is left as it is, and the rest merged again without it (a
    /// few rounds at most); `None` if that does not settle.
    fn run(self) -> Option<(TriMesh, usize)> {
        let regions = self.regions();
        let mut excluded = vec![false; regions.1.len()];
        for _ in 0..MAX_ROUNDS {
            match self.build(&regions, &excluded) {
                Ok(done) => return Some(done),
                Err(bad) => {
                    for r in bad {
                        excluded[r as usize] = true;
                    }
                }
            }
        }
        None
    }

    /// One round of [`Merge::run`] with the regions `excluded` left as they are: the merged
    /// mesh, or the regions whose polygons failed.
    fn build(
        &self,
        (region, sizes, seeds): &(Vec<u32>, Vec<u32>, Vec<u32>),
        excluded: &[bool],
    ) -> Result<(TriMesh, usize), Vec<u32>> {
        let tris = &self.mesh.triangles;
        // The regions of two or more triangles, the polygons to be: each one's slot.
        let mut slot = vec![NONE; sizes.len()];
        let mut polys: Vec<u32> = Vec::new();
        for (r, &n) in sizes.iter().enumerate() {
            if n >= 2 && !excluded[r] {
                slot[r] = polys.len() as u32;
                polys.push(r as u32);
            }
        }
        // Per polygon, twice its area and its boundary edges in the region's orientation.
        let mut own = vec![0.0; polys.len()];
        let mut boundary: Vec<Vec<(u32, u32)>> = vec![Vec::new(); polys.len()];
        for (t, tri) in tris.iter().enumerate() {
            let r = region[t];
            let p = slot[r as usize];
            if p == NONE {
                continue;
            }
            let [a, b, c] = [0, 1, 2].map(|i| self.corner(t as u32, i));
            own[p as usize] += (b - a).cross(c - a).length();
            for i in 0..3 {
                if region[self.across[t][i] as usize] != r {
                    boundary[p as usize].push((tri[i], tri[(i + 1) % 3]));
                }
            }
        }
        // The loops of each polygon, as vertex sequences; a region whose boundary passes twice
        // through a vertex is left as it is (not `merged`).
        let loops: Vec<Option<Vec<Vec<u32>>>> = boundary
            .into_par_iter()
            .map(|mut edges| {
                if edges.is_empty() {
                    return None;
                }
                edges.sort_unstable();
                if edges.windows(2).any(|w| w[0].0 == w[1].0) {
                    return None;
                }
                let mut used = vec![false; edges.len()];
                let mut loops = Vec::new();
                for start in 0..edges.len() {
                    if used[start] {
                        continue;
                    }
                    let mut ring = Vec::new();
                    let mut e = start;
                    loop {
                        used[e] = true;
                        ring.push(edges[e].0);
                        let next = edges[e].1;
                        match edges.binary_search_by_key(&next, |x| x.0) {
                            Ok(f) if f == start => break,
                            Ok(f) if !used[f] => e = f,
                            _ => return None,
                        }
                    }
                    loops.push(ring);
                }
                Some(loops)
            })
            .collect();
        let merged = |r: u32| {
            let p = slot[r as usize];
            p != NONE && loops[p as usize].is_some()
        };
        // Straight stretches of the boundary between two merged regions: the vertices to take
        // out (`removed`), decided by the region of lower index along its own loop.
        let nv = self.mesh.vertices.len();
        let pair_of = |v: u32| -> Option<(u32, u32)> {
            let mut pair = (NONE, NONE);
            for &t in self.fan(v) {
                let r = region[t as usize];
                if r == pair.0 || r == pair.1 {
                    continue;
                }
                if pair.0 == NONE {
                    pair.0 = r;
                } else if pair.1 == NONE {
                    pair.1 = r;
                } else {
                    return None;
                }
            }
            (pair.1 != NONE && merged(pair.0) && merged(pair.1))
                .then(|| (pair.0.min(pair.1), pair.0.max(pair.1)))
        };
        let mut removed = vec![false; nv];
        for (&r, l) in polys.iter().zip(&loops) {
            let Some(l) = l else { continue };
            for ring in l {
                self.straighten(r, ring, &pair_of, &mut removed);
            }
        }
        // The polygons cut into triangles; every other triangle kept.
        let polygons: Vec<(usize, Vec<Vec<u32>>)> = loops
            .iter()
            .enumerate()
            .filter_map(|(p, l)| {
                let l = l.as_ref()?;
                let rings = l
                    .iter()
                    .map(|ring| {
                        ring.iter()
                            .copied()
                            .filter(|&v| !removed[v as usize])
                            .collect()
                    })
                    .collect();
                Some((p, rings))
            })
            .collect();
        let cut: Vec<Option<Fitted>> = polygons
            .par_iter()
            .map(|(p, rings)| {
                let r = polys[*p];
                let tri = self.triangulate(self.normal(seeds[r as usize]), rings, own[*p])?;
                self.fit(r, region, &merged, tri)
            })
            .collect();
        let failed: Vec<u32> = polygons
            .iter()
            .zip(&cut)
            .filter(|(_, c)| c.is_none())
            .map(|((p, _), _)| polys[*p])
            .collect();
        if !failed.is_empty() {
            return Err(failed);
        }
        let mut cancelled = vec![false; tris.len()];
        for c in cut.iter().flatten() {
            for &u in &c.cancelled {
                cancelled[u as usize] = true;
            }
        }
        // Every edge of a new triangle must end up in exactly two triangles, once each way:
        // counted over the new triangles and the kept ones around it (the edges of kept
        // triangles only are as they were).
        let mut uses: HashMap<(u32, u32), u32> = HashMap::new();
        for c in cut.iter().flatten() {
            for t in &c.triangles {
                for i in 0..3 {
                    *uses.entry((t[i], t[(i + 1) % 3])).or_default() += 1;
                }
            }
        }
        let kept_uses = |a: u32, b: u32| {
            self.fan(a)
                .iter()
                .filter(|&&u| {
                    let t = &tris[u as usize];
                    !merged(region[u as usize])
                        && !cancelled[u as usize]
                        && (0..3).any(|i| t[i] == a && t[(i + 1) % 3] == b)
                })
                .count() as u32
        };
        let count = |a: u32, b: u32| uses.get(&(a, b)).copied().unwrap_or(0) + kept_uses(a, b);
        let failed: Vec<u32> = polygons
            .iter()
            .zip(&cut)
            .filter(|(_, c)| {
                c.as_ref().is_some_and(|c| {
                    c.triangles.iter().any(|t| {
                        (0..3).any(|i| {
                            let (a, b) = (t[i], t[(i + 1) % 3]);
                            count(a, b) != 1 || count(b, a) != 1
                        })
                    })
                })
            })
            .map(|((p, _), _)| polys[*p])
            .collect();
        if !failed.is_empty() {
            return Err(failed);
        }
        let mut out_tris: Vec<[u32; 3]> = tris
            .iter()
            .zip(region.iter())
            .zip(&cancelled)
            .filter(|&((_, &r), &c)| !merged(r) && !c)
            .map(|((t, _), _)| *t)
            .collect();
        for c in cut.into_iter().flatten() {
            out_tris.extend(c.triangles);
        }
        // Only the vertices still used, in their order.
        let mut map = vec![NONE; nv];
        for t in &out_tris {
            for &v in t {
                map[v as usize] = 0;
            }
        }
        let mut vertices = Vec::new();
        for (v, m) in map.iter_mut().enumerate() {
            if *m == 0 {
                *m = vertices.len() as u32;
                vertices.push(self.mesh.vertices[v]);
            }
        }
        for t in &mut out_tris {
            *t = t.map(|v| map[v as usize]);
        }
        let n_polygons = polygons.len();
        Ok((
            TriMesh {
                vertices,
                triangles: out_tris,
                colors: None,
            },
            n_polygons,
        ))
    }

    /// Region `r`'s new triangles `tri`, less those that a triangle of an unmerged region
    /// (`merged` false) cancels: one folded flat onto the plane, facing the other way, across a
    /// notch of the polygon, whose three vertices are consecutive on the polygon's loop — the
    /// ear clipped there is that triangle again, the two enclose nothing, and both are left
    /// out. `None` when such a fold belongs to a merged region (its triangles are replaced).
    fn fit(
        &self,
        r: u32,
        region: &[u32],
        merged: &(impl Fn(u32) -> bool + Sync),
        tri: Vec<[u32; 3]>,
    ) -> Option<Fitted> {
        let mut out = Fitted {
            triangles: Vec::with_capacity(tri.len()),
            cancelled: Vec::new(),
        };
        for t in tri {
            // The fold: a triangle of the same three vertices elsewhere.
            let mut sorted = t;
            sorted.sort_unstable();
            let fold = self.fan(t[0]).iter().copied().find(|&u| {
                let mut s = self.mesh.triangles[u as usize];
                s.sort_unstable();
                s == sorted && region[u as usize] != r
            });
            match fold {
                Some(u) if !merged(region[u as usize]) => {
                    out.cancelled.push(u);
                    continue;
                }
                Some(_) => return None,
                None => {}
            }
            out.triangles.push(t);
        }
        Some(out)
    }

    /// Marks in `removed` the vertices of `ring` (a loop of region `r`) that lie on straight
    /// stretches shared with one other merged region of higher index: from each vertex kept,
    /// the next kept one is the farthest of the stretch such that every vertex between lies
    /// within the tolerance of the segment joining them.
    fn straighten(
        &self,
        r: u32,
        ring: &[u32],
        pair_of: &impl Fn(u32) -> Option<(u32, u32)>,
        removed: &mut [bool],
    ) {
        let n = ring.len();
        // A vertex may go when it lies between exactly this region and one of higher index.
        let candidate = |v: u32| pair_of(v).is_some_and(|(a, b)| a == r && b != r);
        // The whole loop may lie on one other region: then start from its least vertex.
        let Some(anchor) = (0..n)
            .find(|&i| !candidate(ring[i]))
            .or_else(|| (0..n).min_by_key(|&i| ring[i]))
        else {
            return;
        };
        let at = |i: usize| ring[(anchor + i) % n];
        let pos = |v: u32| self.mesh.vertices[v as usize];
        let mut i = 0;
        while i < n {
            // From kept vertex `at(i)`, through candidates of one pair.
            let pair = pair_of(at((i + 1) % n));
            // The stretch: candidates of one pair after `from`, `i + 1..stretch`.
            let mut stretch = i + 1;
            while stretch < n && candidate(at(stretch)) && pair_of(at(stretch)) == pair {
                stretch += 1;
            }
            let within = |a: usize, b: usize| {
                let (p, q) = (pos(at(a)), pos(at(b % n)));
                (a + 1..b).all(|k| distance_to_segment(pos(at(k)), p, q) <= self.tol)
            };
            // Usually the whole stretch is straight (two planes meet on a line); else the
            // farthest end from `from`, searched over at most `MAX_STRAIGHT` vertices.
            let best = if within(i, stretch) {
                stretch
            } else {
                let mut best = i + 1;
                for j in i + 1..stretch.min(i + MAX_STRAIGHT) {
                    if !within(i, j + 1) {
                        break;
                    }
                    best = j + 1;
                }
                best
            };
            for k in i + 1..best {
                removed[at(k) as usize] = true;
            }
            i = best;
        }
    }

    /// A region's polygon (`rings`: its loops, vertices taken out removed; `normal` the
    /// region's, `own` twice its area) cut into triangles oriented as the region; `None` when
    /// ear clipping does not give a full cover.
    fn triangulate(&self, normal: Vec3, rings: &[Vec<u32>], own: f64) -> Option<Vec<[u32; 3]>> {
        // Drop the axis the normal leans on most; (u, v) counter-clockwise seen from outside.
        let k = normal.abs().max_position();
        let (mut u, mut v) = ((k + 1) % 3, (k + 2) % 3);
        if normal[k] < 0.0 {
            std::mem::swap(&mut u, &mut v);
        }
        let area2 = |ring: &[u32]| {
            let m = ring.len();
            (0..m)
                .map(|i| {
                    let (a, b) = (
                        self.mesh.vertices[ring[i] as usize],
                        self.mesh.vertices[ring[(i + 1) % m] as usize],
                    );
                    a[u] * b[v] - b[u] * a[v]
                })
                .sum::<f64>()
        };
        // The outer loop turns counter-clockwise in (u, v), holes clockwise.
        let (outer, holes): (Vec<&Vec<u32>>, Vec<&Vec<u32>>) =
            rings.iter().partition(|ring| area2(ring) > 0.0);
        if outer.len() != 1 || rings.iter().any(|ring| ring.len() < 3) {
            return None;
        }
        let mut ids: Vec<u32> = Vec::new();
        let mut coords: Vec<f64> = Vec::new();
        let mut hole_starts = Vec::new();
        for (h, ring) in std::iter::once(outer[0])
            .chain(holes.iter().copied())
            .enumerate()
        {
            if h > 0 {
                hole_starts.push(ids.len());
            }
            for &id in ring {
                let p = self.mesh.vertices[id as usize];
                ids.push(id);
                coords.extend([p[u], p[v]]);
            }
        }
        let idx = earcutr::earcut(&coords, &hole_starts, 2).ok()?;
        let expected = ids.len() - 2 + 2 * holes.len();
        if idx.len() != 3 * expected {
            return None;
        }
        // Ear clipping winds all its triangles one way: the polygon's own, turned to the
        // region's normal as a whole (a triangle of three collinear corners has no side of its
        // own to tell).
        let mut out: Vec<[u32; 3]> = Vec::with_capacity(expected);
        let (mut signed, mut covered) = (0.0, 0.0);
        for t in idx.chunks_exact(3) {
            let [a, b, c] = [ids[t[0]], ids[t[1]], ids[t[2]]];
            let [pa, pb, pc] = [a, b, c].map(|i| self.mesh.vertices[i as usize]);
            let d = (pb - pa).cross(pc - pa).dot(normal);
            signed += d;
            covered += d.abs();
            out.push([a, b, c]);
        }
        if signed < 0.0 {
            for t in &mut out {
                t.swap(1, 2);
            }
        }
        if (covered - signed.abs()) > 1e-9 * covered {
            // Triangles of both windings: overlapping, not a cut of the polygon.
            return None;
        }
        // The new triangles cover the region's area, once.
        ((covered - own).abs() <= 1e-9 * own.max(1e-300) + 4.0 * self.tol * perimeter(self, rings))
            .then_some(out)
    }
}

/// The total length of `rings`' edges.
fn perimeter(m: &Merge<'_>, rings: &[Vec<u32>]) -> f64 {
    rings
        .iter()
        .map(|ring| {
            let n = ring.len();
            (0..n)
                .map(|i| {
                    (m.mesh.vertices[ring[(i + 1) % n] as usize]
                        - m.mesh.vertices[ring[i] as usize])
                        .length()
                })
                .sum::<f64>()
        })
        .sum()
}

/// Distance from `x` to the segment `p`–`q`.
fn distance_to_segment(x: Vec3, p: Vec3, q: Vec3) -> f64 {
    let d = q - p;
    let dd = d.dot(d);
    let t = if dd > 0.0 {
        ((x - p).dot(d) / dd).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (x - (p + d * t)).length()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{dual_contour, ContourOptions, FnGrid, Lattice};
    use parry3d_f64::query::PointQuery;
    use std::collections::HashSet;
    use swarf_geom::Aabb;

    /// The closed mesh of a signed distance function over `[lo, hi]`, contoured every `h`.
    fn contoured(sdf: impl Fn(Vec3) -> f64 + Sync, lo: Vec3, hi: Vec3, h: f64) -> TriMesh {
        let lattice = Lattice::covering(Aabb::new(lo, hi).inflated(0.3), h);
        let mesh = dual_contour(&FnGrid::new(lattice, sdf), &ContourOptions::default());
        assert!(mesh.edge_report().is_clean());
        mesh
    }

    fn boxed(lo: Vec3, hi: Vec3) -> impl Fn(Vec3) -> f64 + Sync {
        move |p: Vec3| {
            let q = (p - 0.5 * (lo + hi)).abs() - 0.5 * (hi - lo);
            q.max(Vec3::ZERO).length() + q.max_element().min(0.0)
        }
    }

    /// A cylinder of radius `r` about the Z axis, `|z| ≤ half`.
    fn cylinder(r: f64, half: f64) -> impl Fn(Vec3) -> f64 + Sync {
        move |p: Vec3| {
            let d = (p.x.hypot(p.y) - r, p.z.abs() - half);
            d.0.max(0.0).hypot(d.1.max(0.0)) + d.0.max(d.1).min(0.0)
        }
    }

    /// What every merge must keep: closed, the same volume within `2·tol·area`, vertices a
    /// subset of the input's, and every input vertex within `tol` of the merged surface.
    fn check_merge(input: &TriMesh, out: &TriMesh, tol: f64) {
        let report = out.edge_report();
        assert!(report.is_clean(), "{report:?}");
        // Hardly more triangles flat once written (`f32`) than the contouring left.
        let flat = |m: &TriMesh| {
            (0..m.triangles.len())
                .filter(|&t| {
                    let [a, b, c] = m.corners(t).map(|p| p.as_vec3());
                    let n = (b - a).cross(c - a);
                    n.x == 0.0 && n.y == 0.0 && n.z == 0.0
                })
                .count()
        };
        assert!(
            flat(out) <= flat(input) + 2,
            "{} flat triangles as written, {} before",
            flat(out),
            flat(input)
        );
        let slack = 2.0 * tol * input.area() + 1e-9 * input.volume();
        assert!(
            (out.volume() - input.volume()).abs() <= slack,
            "{} vs {}",
            out.volume(),
            input.volume()
        );
        let key = |p: Vec3| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
        let kept: HashSet<[u64; 3]> = input.vertices.iter().map(|&p| key(p)).collect();
        assert!(out.vertices.iter().all(|&p| kept.contains(&key(p))));
        // Distances to the merged surface by parry's point–mesh query (an independent code).
        let merged = parry3d_f64::shape::TriMesh::new(out.vertices.clone(), out.triangles.clone())
            .expect("a mesh parry takes");
        let worst = input
            .vertices
            .iter()
            .map(|&p| merged.distance_to_local_point(p, true))
            .fold(0.0, f64::max);
        assert!(
            worst <= tol,
            "an input vertex {worst} mm off the merged surface"
        );
    }

    #[test]
    fn a_box_is_twelve_triangles() {
        let (lo, hi) = (Vec3::new(-1.0, -0.7, -0.5), Vec3::new(1.0, 0.7, 0.5));
        let input = contoured(boxed(lo, hi), lo, hi, 0.13);
        let (out, stats) = input.merge_coplanar();
        assert!(!stats.given_up);
        assert_eq!(
            (out.triangles.len(), out.vertices.len()),
            (12, 8),
            "{stats:?}"
        );
        assert_eq!(stats.polygons, 6);
        check_merge(&input, &out, PLANAR_TOLERANCE_MM);
        assert!((out.volume() - 2.0 * 1.4).abs() < 1e-9);
    }

    #[test]
    fn a_cylinder_along_an_axis_becomes_strips_and_two_discs() {
        let (r, half) = (1.0, 0.8);
        let lo = Vec3::new(-r, -r, -half);
        let input = contoured(cylinder(r, half), lo, -lo, 0.1);
        let (out, stats) = input.merge_coplanar();
        assert!(!stats.given_up);
        // The side's vertices stand in columns (one per cell around the axis, 63 of them at
        // this spacing): each column's quads lie in one plane, one polygon each. (The cells at
        // the rims, whose vertices sit on the sharp edge, are not in a column's plane.)
        assert!(stats.polygons >= 63, "{stats:?}");
        assert!(
            out.triangles.len() * 5 < input.triangles.len(),
            "{} of {}",
            out.triangles.len(),
            input.triangles.len()
        );
        check_merge(&input, &out, PLANAR_TOLERANCE_MM);
    }

    #[test]
    fn a_sphere_stays_within_the_tolerance() {
        let sphere = |p: Vec3| p.length() - 1.0;
        let input = contoured(sphere, Vec3::splat(-1.0), Vec3::splat(1.0), 0.15);
        let (out, stats) = input.merge_coplanar();
        assert!(!stats.given_up);
        check_merge(&input, &out, PLANAR_TOLERANCE_MM);
        // A looser tolerance merges more of a curved surface, and still holds it.
        let (loose, _) = input.merge_coplanar_within(1e-3);
        assert!(loose.triangles.len() <= out.triangles.len());
        check_merge(&input, &loose, 1e-3);
    }

    #[test]
    fn a_block_with_a_pocket_and_a_boss_keeps_its_holes() {
        // A plate with a through hole (its top and bottom faces are polygons with a hole) and
        // a boss on top.
        let plate = boxed(Vec3::new(-2.0, -2.0, -0.5), Vec3::new(2.0, 2.0, 0.5));
        let hole = boxed(Vec3::new(-0.6, -0.6, -1.0), Vec3::new(0.6, 0.6, 1.0));
        let boss = boxed(Vec3::new(0.9, 0.9, 0.0), Vec3::new(1.6, 1.6, 1.2));
        let solid = move |p: Vec3| plate(p).max(-hole(p)).min(boss(p));
        let (lo, hi) = (Vec3::new(-2.0, -2.0, -0.5), Vec3::new(2.0, 2.0, 1.2));
        let input = contoured(solid, lo, hi, 0.1);
        let (out, stats) = input.merge_coplanar();
        assert!(!stats.given_up);
        assert!(out.triangles.len() < 200, "{stats:?}");
        check_merge(&input, &out, PLANAR_TOLERANCE_MM);
    }

    proptest::proptest! {
        #![proptest_config(swarf_testdata::proptest_config(24))]
        /// Unions of up to three boxes, turned as a whole about a random axis (so their faces
        /// lie across the lattice): every merge keeps the solid (`check_merge`), and a union
        /// of boxes, all faces flat, shrinks to a small share of its triangles.
        #[test]
        fn unions_of_turned_boxes_keep_their_solid(
            boxes in proptest::collection::vec(
                ((-0.6f64..0.6, -0.6f64..0.6, -0.6f64..0.6), (0.2f64..0.7, 0.2f64..0.7, 0.2f64..0.7)),
                1..4,
            ),
            axis in (-1.0f64..1.0, -1.0f64..1.0, 0.1f64..1.0),
            angle in 0.0f64..1.5,
        ) {
            let boxes: Vec<(Vec3, Vec3)> = boxes
                .into_iter()
                .map(|((x, y, z), (a, b, c))| {
                    let (centre, half) = (Vec3::new(x, y, z), Vec3::new(a, b, c));
                    (centre - half, centre + half)
                })
                .collect();
            let turn = swarf_geom::math::Quat::from_axis_angle(
                Vec3::new(axis.0, axis.1, axis.2).normalize(),
                angle,
            );
            let sdf = move |p: Vec3| {
                let q = turn.inverse() * p;
                boxes.iter().map(|&(lo, hi)| boxed(lo, hi)(q)).fold(f64::INFINITY, f64::min)
            };
            let input = contoured(sdf, Vec3::splat(-1.5), Vec3::splat(1.5), 0.11);
            let (out, stats) = input.merge_coplanar();
            proptest::prop_assert!(!stats.given_up);
            check_merge(&input, &out, PLANAR_TOLERANCE_MM);
        }
    }

    #[test]
    fn a_turned_box_keeps_its_solid() {
        // Faces across the lattice: the contouring places its vertices from estimated normals,
        // near the faces but not within 10⁻⁶ mm of them, so little merges; what does still
        // holds the solid. (Where vertices are put on the exact surface, as `swarf envelope`
        // does, such faces merge as the level ones do.)
        let (lo, hi) = (Vec3::new(-1.0, -0.7, -0.5), Vec3::new(1.0, 0.7, 0.5));
        let turn =
            swarf_geom::math::Quat::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
        let sdf = move |p: Vec3| boxed(lo, hi)(turn.inverse() * p);
        let input = contoured(sdf, Vec3::splat(-1.4), Vec3::splat(1.4), 0.09);
        let (out, stats) = input.merge_coplanar();
        assert!(!stats.given_up);
        check_merge(&input, &out, PLANAR_TOLERANCE_MM);
    }

    #[test]
    fn coloured_and_open_meshes_are_returned_as_they_are() {
        let (lo, hi) = (Vec3::splat(-1.0), Vec3::splat(1.0));
        let mut input = contoured(boxed(lo, hi), lo, hi, 0.25);
        input.colors = Some(vec![[1.0; 4]; input.vertices.len()]);
        let (out, stats) = input.merge_coplanar();
        assert!(stats.given_up);
        assert_eq!(out, input);
        input.colors = None;
        input.triangles.pop();
        let (out, stats) = input.merge_coplanar();
        assert!(stats.given_up);
        assert_eq!(out, input);
        assert_eq!(stats.triangles_after, stats.triangles_before);
    }
}
