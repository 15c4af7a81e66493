//! Stock from a closed triangle mesh (an STL part or casting): every ray of the three families
//! is cast against the mesh through parry's BVH, **all** crossings along it are collected and
//! the material is where the shells' crossings, counted by their orientation, do not cancel:
//! the union of the mesh's bodies ([`axis_line_intervals`]).
//!
//! Rays parallel to the axes pass through mesh vertices and edges often (meshes have round
//! coordinates too); each cast is therefore made at the ray's position nudged by a tiny fixed
//! offset ([`NUDGE`] of the cell size, the same for every ray) so that no crossing is counted
//! twice or missed; a ray that still finds an odd number of crossings is cast again with a
//! different nudge. The stored intervals belong to the ray at the cell centre; the nudge shifts
//! the sampled surface by at most `NUDGE·h` (far below the grid's own error).

use crate::dexel::Interval;
use crate::error::StockError;
use crate::tridexel::TriDexel;
use parry3d_f64::shape::TriMesh;
use swarf_geom::math::Vec3;
use swarf_geom::Aabb;

/// Relative nudges (fractions of the cell size along u and v) tried in turn.
pub const NUDGE: [(f64, f64); 3] = [
    (3.183_098_861e-6, 7.071_067_812e-6),
    (-5.772_156_649e-6, 2.718_281_828e-6),
    (1.414_213_562e-6, -4.669_201_609e-6),
];

/// How to treat meshes.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct MeshOptions {
    /// Build even when the mesh is not closed (a ray whose crossings do not balance pairs them
    /// by parity).
    pub allow_open: bool,
}

impl TriDexel {
    /// A stock from the bytes of an STL file (binary or ASCII, read by `swarf-io`),
    /// resolution `h`. The errors do not name a file (the bytes have none): the caller that
    /// read them names it, once ([`StockSpec::build`](crate::StockSpec::build) does).
    pub fn from_stl_bytes(bytes: &[u8], h: f64, opts: MeshOptions) -> Result<Self, StockError> {
        let mesh = swarf_io::stl::parse_stl(bytes, std::path::Path::new("")).map_err(|e| {
            StockError::BadMesh(match e {
                swarf_io::IoError::Malformed { what, expected, .. } => {
                    format!("{what} (expected {expected})")
                }
                other => other.to_string(),
            })
        })?;
        Self::from_mesh(&mesh, h, opts)
    }

    /// A stock from a closed triangle soup (identical vertices are welded), resolution `h`.
    ///
    /// Errors with [`StockError::OpenMesh`] (count and the first edges' coordinates) when some
    /// edge is not shared by exactly two triangles, unless `opts.allow_open`.
    pub fn from_triangles(
        triangles: &[[Vec3; 3]],
        h: f64,
        opts: MeshOptions,
    ) -> Result<Self, StockError> {
        let mut mesh = swarf_io::TriMesh::new();
        for t in triangles {
            let base = mesh.vertices.len() as u32;
            mesh.vertices.extend_from_slice(t);
            mesh.triangles.push([base, base + 1, base + 2]);
        }
        mesh.weld(0.0);
        Self::from_mesh(&mesh, h, opts)
    }

    /// A stock from a closed indexed mesh, resolution `h`.
    ///
    /// Errors with [`StockError::OpenMesh`] (count and the first edges' coordinates) when some
    /// edge is not shared by exactly two triangles, unless `opts.allow_open`.
    pub fn from_mesh(
        mesh: &swarf_io::TriMesh,
        h: f64,
        opts: MeshOptions,
    ) -> Result<Self, StockError> {
        if mesh.triangles.is_empty() {
            return Err(StockError::BadMesh("no triangles".into()));
        }
        mesh.validate()
            .map_err(|e| StockError::BadMesh(e.to_string()))?;
        let report = mesh.edge_report();
        if report.boundary_count() > 0 && !opts.allow_open {
            let examples = report
                .examples
                .iter()
                .take(3)
                .map(|e| {
                    let [a, b] = e.points;
                    format!("({}, {}, {})-({}, {}, {})", a.x, a.y, a.z, b.x, b.y, b.z)
                })
                .collect::<Vec<_>>()
                .join(", ");
            return Err(StockError::OpenMesh {
                count: report.boundary_count(),
                open: report.open,
                non_manifold: report.non_manifold,
                examples,
            });
        }
        let (verts, idx) = (&mesh.vertices, &mesh.triangles);
        let mesh = TriMesh::new(verts.clone(), idx.clone())
            .map_err(|e| StockError::BadMesh(format!("{e:?}")))?;
        let bounds = Aabb::from_points(verts.iter().copied())
            .ok_or_else(|| StockError::BadMesh("no vertices".into()))?;
        let hk = Self::empty(bounds, h)?.grid().h;
        let stock = Self::from_fn(bounds, h, |k, u, v, d| {
            let (ku, kv) = ((k + 1) % 3, (k + 2) % 3);
            axis_line_intervals(&mesh, k, u, v, (hk[ku], hk[kv]), &mut Vec::new(), d);
        })?;
        // An open mesh whose rays find no way in and out (a box without its top) would be a
        // stock of no material, reported as "-0.000 mm³" and cut by nothing.
        if report.boundary_count() > 0 && stock.volumes().iter().any(|&v| v <= 0.0) {
            return Err(StockError::EmptyOpenMesh {
                count: report.boundary_count(),
            });
        }
        Ok(stock)
    }

    /// A stock from a closed parry triangle mesh.
    pub fn from_trimesh(mesh: &TriMesh, h: f64, opts: MeshOptions) -> Result<Self, StockError> {
        let tris: Vec<[Vec3; 3]> = mesh.triangles().map(|t| [t.a, t.b, t.c]).collect();
        Self::from_triangles(&tris, h, opts)
    }
}

/// Pushes onto `out` the intervals of the closed mesh's solid along the line parallel to axis
/// `k` through cross coordinates `(u, v)` (along `(k+1)%3` and `(k+2)%3`): every crossing
/// found through the BVH, the line nudged by [`NUDGE`] times `cell` (the grid's cell sizes
/// along the cross axes) and nudged again while the count is odd. `hits` is scratch space.
///
/// The solid is the **union** of the mesh's bodies: each crossing counts +1 where the line
/// enters a shell and −1 where it leaves it (by its triangle's orientation), and the material
/// is where the count is not zero — bodies that overlap or nest (a multi-body export) are one
/// solid, not their parity (which made an overlap a void). Either orientation of the whole mesh
/// serves. Where the orientations along the line are inconsistent (a flipped triangle: the
/// count does not come back to zero, or changes sign), the crossings are paired by parity.
pub fn axis_line_intervals(
    mesh: &TriMesh,
    k: usize,
    u: f64,
    v: f64,
    cell: (f64, f64),
    hits: &mut Vec<(f64, i32)>,
    out: &mut crate::Dexel,
) {
    let (ku, kv) = ((k + 1) % 3, (k + 2) % 3);
    let (verts, idx) = (mesh.vertices(), mesh.indices());
    for &(nu, nv) in &NUDGE {
        let (pu, pv) = (u + nu * cell.0, v + nv * cell.1);
        hits.clear();
        for leaf in mesh.bvh().leaves(|node| {
            let (lo, hi) = (node.mins(), node.maxs());
            lo[ku] <= pu && pu <= hi[ku] && lo[kv] <= pv && pv <= hi[kv]
        }) {
            let t = idx[leaf as usize].map(|i| verts[i as usize]);
            if let Some(x) = axis_line_triangle(k, pu, pv, &t) {
                hits.push(x);
            }
        }
        if hits.len() % 2 == 0 {
            break;
        }
    }
    // Crossings at one position count together: bodies that touch (a face shared, either
    // orientation of the mesh) make one interval, not two that meet.
    hits.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (mut w, mut pos, mut neg) = (0i32, false, false);
    for (_, s) in groups(hits) {
        w += s;
        pos |= w > 0;
        neg |= w < 0;
    }
    if w != 0 || (pos && neg) {
        for pair in hits.chunks_exact(2) {
            if pair[1].0 > pair[0].0 {
                out.push(Interval {
                    enter: pair[0].0,
                    exit: pair[1].0,
                });
            }
        }
        return;
    }
    let mut start = 0.0;
    for (t, s) in groups(hits) {
        let before = w;
        w += s;
        if before == 0 && w != 0 {
            start = t;
        } else if before != 0 && w == 0 && t > start {
            out.push(Interval {
                enter: start,
                exit: t,
            });
        }
    }
}

/// The crossings `hits` (sorted) with those at one position — within
/// [`crate::dexel::MIN_INTERVAL_MM`], as two faces at one place are computed a rounding apart —
/// counted together.
fn groups(hits: &[(f64, i32)]) -> impl Iterator<Item = (f64, i32)> + '_ {
    let mut i = 0;
    std::iter::from_fn(move || {
        let t = hits.get(i)?.0;
        let mut s = 0;
        while i < hits.len() && hits[i].0 - t <= crate::dexel::MIN_INTERVAL_MM {
            s += hits[i].1;
            i += 1;
        }
        Some((t, s))
    })
}

/// Where the line along axis `k` through cross coordinates `(pu, pv)` crosses triangle `t`
/// (strictly inside its projection; the nudge keeps the line off edges), as the coordinate
/// along `k`.
fn axis_line_triangle(k: usize, pu: f64, pv: f64, t: &[Vec3; 3]) -> Option<(f64, i32)> {
    let (ku, kv) = ((k + 1) % 3, (k + 2) % 3);
    let p2 = |p: Vec3| (p[ku] - pu, p[kv] - pv);
    let (a, b, c) = (p2(t[0]), p2(t[1]), p2(t[2]));
    let cross = |p: (f64, f64), q: (f64, f64)| p.0 * q.1 - p.1 * q.0;
    let (wa, wb, wc) = (cross(b, c), cross(c, a), cross(a, b));
    let pos = wa > 0.0 && wb > 0.0 && wc > 0.0;
    let neg = wa < 0.0 && wb < 0.0 && wc < 0.0;
    if !(pos || neg) {
        return None;
    }
    let sum = wa + wb + wc;
    // `sum` is twice the triangle's area projected across the line, signed as its normal's
    // component along +k ((k, ku, kv) is right-handed): positive where an outward-facing
    // triangle lets the line out.
    let side = if pos { -1 } else { 1 };
    Some(((wa * t[0][k] + wb * t[1][k] + wc * t[2][k]) / sum, side))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 12 triangles of a box.
    fn box_tris(min: Vec3, max: Vec3) -> Vec<[Vec3; 3]> {
        let m = swarf_io::TriMesh::cuboid(min, max);
        m.triangles
            .iter()
            .map(|t| t.map(|i| m.vertices[i as usize]))
            .collect()
    }

    #[test]
    fn box_mesh_matches_box_stock() {
        let (a, b) = (Vec3::new(0.0, 0.0, 0.0), Vec3::new(10.0, 6.0, 4.0));
        let s = TriDexel::from_triangles(&box_tris(a, b), 0.5, MeshOptions::default()).unwrap();
        for v in s.volumes() {
            assert!((v - 240.0).abs() < 1e-9, "{v}");
        }
    }

    /// Bodies that overlap or nest are one solid (their union), whichever way the mesh is
    /// oriented; a flipped triangle falls back to parity along the rays it crosses.
    #[test]
    fn overlapping_and_nested_bodies_are_their_union() {
        let v = |tris: &[[Vec3; 3]]| {
            TriDexel::from_triangles(tris, 0.5, MeshOptions::default())
                .unwrap()
                .volumes()
        };
        let close = |got: [f64; 3], want: f64| {
            for g in got {
                assert!((g - want).abs() < 1e-6, "{got:?} want {want}");
            }
        };
        // 25·20·10 + 25·16·9 − 10·16·9 = 5000 + 3600 − 1440 (the overlap counted once).
        let mut two = box_tris(Vec3::new(0.0, 0.0, -10.0), Vec3::new(25.0, 20.0, 0.0));
        two.extend(box_tris(
            Vec3::new(15.0, 2.0, -9.0),
            Vec3::new(40.0, 18.0, 0.0),
        ));
        close(v(&two), 7160.0);
        // Inside out: the same solid.
        let flipped: Vec<[Vec3; 3]> = two.iter().map(|t| [t[0], t[2], t[1]]).collect();
        close(v(&flipped), 7160.0);
        // A box inside a box: the outer one (parity made the inner one a void).
        let mut nested = box_tris(Vec3::new(0.0, 0.0, -10.0), Vec3::new(40.0, 20.0, 0.0));
        nested.extend(box_tris(
            Vec3::new(10.0, 5.0, -8.0),
            Vec3::new(30.0, 15.0, -3.0),
        ));
        close(v(&nested), 8000.0);
        // Two boxes sharing a face, inside out: one interval a ray across the face, as with
        // the mesh the right way out (entries and exits at the face count together).
        let mut touch = box_tris(Vec3::ZERO, Vec3::new(10.0, 6.0, 4.0));
        touch.extend(box_tris(
            Vec3::new(10.0, 0.0, 0.0),
            Vec3::new(20.0, 6.0, 4.0),
        ));
        for tris in [
            touch.clone(),
            touch.iter().map(|t| [t[0], t[2], t[1]]).collect::<Vec<_>>(),
        ] {
            // (The shared face's edges are used four times, half each way: closed bodies
            // that touch, taken without `allow_open`.)
            let closed = MeshOptions { allow_open: false };
            let s = TriDexel::from_triangles(&tris, 0.5, closed).unwrap();
            let x = s.family(0);
            let (nu, nv) = x.dims();
            assert_eq!(x.interval_count(), nu * nv, "one interval on every X ray");
            close(s.volumes(), 480.0);
        }
        // One flipped triangle of a single box: the rays through it pair by parity.
        let mut one = box_tris(Vec3::ZERO, Vec3::new(10.0, 6.0, 4.0));
        one[0] = [one[0][0], one[0][2], one[0][1]];
        close(v(&one), 240.0);
    }

    #[test]
    fn stl_binary_and_ascii() {
        let tris = box_tris(Vec3::ZERO, Vec3::new(2.0, 3.0, 4.0));
        let mut bin = vec![0u8; 80];
        bin.extend_from_slice(&(tris.len() as u32).to_le_bytes());
        let mut ascii = String::from("solid b\n");
        for t in &tris {
            bin.extend_from_slice(&[0u8; 12]);
            ascii.push_str("facet normal 0 0 0\nouter loop\n");
            for v in t {
                for c in [v.x, v.y, v.z] {
                    bin.extend_from_slice(&(c as f32).to_le_bytes());
                }
                ascii.push_str(&format!("vertex {} {} {}\n", v.x, v.y, v.z));
            }
            bin.extend_from_slice(&[0u8; 2]);
            ascii.push_str("endloop\nendfacet\n");
        }
        ascii.push_str("endsolid b\n");
        for bytes in [bin.as_slice(), ascii.as_bytes()] {
            let s = TriDexel::from_stl_bytes(bytes, 0.25, MeshOptions::default()).unwrap();
            assert!((s.volume() - 24.0).abs() < 1e-9);
        }
        assert!(
            TriDexel::from_stl_bytes(b"solid x\nendsolid\n", 0.25, MeshOptions::default()).is_err()
        );
    }

    #[test]
    fn open_mesh_rejected_with_edges() {
        let mut t = box_tris(Vec3::ZERO, Vec3::ONE);
        t.pop();
        let e = TriDexel::from_triangles(&t, 0.1, MeshOptions::default()).unwrap_err();
        let msg = e.to_string();
        assert!(matches!(e, StockError::OpenMesh { count: 3, .. }), "{msg}");
        assert!(
            msg.contains("3 open edge(s), 0 non-manifold edge(s)"),
            "{msg}"
        );
        // An edge shared by four triangles, two each way (a box's copy along one edge): closed
        // bodies that touch, a stock of both.
        let mut t = box_tris(Vec3::ZERO, Vec3::ONE);
        t.extend(box_tris(Vec3::new(1.0, 1.0, 0.0), Vec3::new(2.0, 2.0, 1.0)));
        let s = TriDexel::from_triangles(&t, 0.1, MeshOptions::default()).unwrap();
        assert!((s.volume() - 2.0).abs() < 1e-9, "{}", s.volume());
        // A fin (a third triangle on an edge of a closed box): non-manifold, not open.
        let mut t = box_tris(Vec3::ZERO, Vec3::ONE);
        let fin = [t[0][0], t[0][1], Vec3::new(-1.0, -1.0, -1.0)];
        t.push(fin);
        let msg = TriDexel::from_triangles(&t, 0.1, MeshOptions::default())
            .unwrap_err()
            .to_string();
        assert!(msg.contains("non-manifold edge(s)"), "{msg}");
        assert!(!msg.contains(" 0 non-manifold"), "{msg}");
    }

    #[test]
    fn an_open_mesh_enclosing_nothing_is_an_error_even_when_allowed() {
        // A box without its top: rays along Z cross only the bottom. Was a stock of
        // "-0.000 mm³" with no word said.
        let mut t = box_tris(Vec3::ZERO, Vec3::new(10.0, 10.0, 5.0));
        t.drain(2..4);
        let e = TriDexel::from_triangles(&t, 0.5, MeshOptions { allow_open: true }).unwrap_err();
        assert!(matches!(e, StockError::EmptyOpenMesh { count: 4 }), "{e:?}");
        assert!(e.to_string().contains("encloses no material"), "{e}");
    }
}
