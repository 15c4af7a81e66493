//! Triangle meshes of patch sets, for viewing: swarf-io's [`TriMesh`] (the one triangle-mesh
//! type of the workspace, which its writers take) with the surface's normals and the patch of
//! every triangle beside it.

use swarf_geom::math::Vec3;
use swarf_io::TriMesh;

use crate::compound::CompoundSurface;
use crate::surface::{ParametricSurface, Tolerances};

/// A tessellated compound surface, in mm.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SurfaceMesh {
    /// Vertices and triangles, counter-clockwise seen from the normal side (the cutter's).
    pub mesh: TriMesh,
    /// Unit vertex normals (towards the cutter side), one per vertex.
    pub normals: Vec<Vec3>,
    /// The patch each triangle belongs to.
    pub triangle_patch: Vec<u32>,
}

/// Tessellate every patch on its `n × n` iso-parametric grid (`n ≥ 2`) into `2·(n−1)²`
/// triangles. Vertex normals are the surface normals (limit normals at degenerate points);
/// where the normal is undefined, the average of the adjacent triangles' normals is used.
/// Triangles collapsed to a point or a segment (at poles) are kept, with zero area. On a trimmed
/// patch only triangles whose three corners are on the part are kept (the boundary is drawn to
/// the grid's resolution); every grid point stays a vertex, so vertex `k·n² + i·n + j` is always
/// grid point `(u_i, v_j)` of patch `k`.
pub fn tessellate(surface: &CompoundSurface, n: usize, tol: &Tolerances) -> SurfaceMesh {
    let n = n.max(2);
    let mut m = SurfaceMesh::default();
    let (positions, triangles) = (&mut m.mesh.vertices, &mut m.mesh.triangles);
    for (k, patch) in surface.patches.iter().enumerate() {
        let base = positions.len();
        let dom = patch.surface.domain();
        let mut undefined = Vec::new();
        let mut on = Vec::with_capacity(n * n);
        for i in 0..n {
            let u = dom.u_at(i as f64 / (n - 1) as f64);
            for j in 0..n {
                let v = dom.v_at(j as f64 / (n - 1) as f64);
                on.push(patch.on_part(u, v));
                let g = patch.local(u, v, tol);
                positions.push(g.point());
                match g.normal.vector() {
                    Some(nv) => m.normals.push(nv),
                    None => {
                        undefined.push(m.normals.len());
                        m.normals.push(Vec3::ZERO);
                    }
                }
            }
        }
        let idx = |i: usize, j: usize| (base + i * n + j) as u32;
        let first_tri = triangles.len();
        for i in 0..n - 1 {
            for j in 0..n - 1 {
                let (a, b, c, d) = (idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1));
                let kept = |t: &[u32; 3]| t.iter().all(|&x| on[x as usize - base]);
                // u along the first edge, v along the second: S_u × S_v is counter-clockwise.
                let (t1, t2) = if patch.flipped {
                    ([a, c, b], [a, d, c])
                } else {
                    ([a, b, c], [a, c, d])
                };
                for t in [t1, t2] {
                    if kept(&t) {
                        triangles.push(t);
                        m.triangle_patch.push(k as u32);
                    }
                }
            }
        }
        if !undefined.is_empty() {
            let mut acc = vec![Vec3::ZERO; positions.len() - base];
            for t in &triangles[first_tri..] {
                let p = t.map(|i| positions[i as usize]);
                let fnorm = (p[1] - p[0]).cross(p[2] - p[0]);
                for &i in t {
                    acc[i as usize - base] += fnorm;
                }
            }
            for i in undefined {
                m.normals[i] = acc[i - base].normalize_or_zero();
            }
        }
    }
    m
}
