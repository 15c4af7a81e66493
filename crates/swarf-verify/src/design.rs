//! The design part the machined stock is compared with, and the one question verification asks
//! of it: the signed distance from a point, exact to the design's own geometry.
//!
//! [`MeshDesign`] is a closed triangle mesh (an STL part), read as the union of its bodies
//! ([`crate::union`]: faces inside another body are left out, faces that cross are cut where
//! they cross, flipped triangles turned outwards): the nearest point is the exact
//! point–triangle projection found through parry's BVH, and the sign comes from the
//! angle-weighted pseudo-normal of the nearest feature (face, edge or vertex; Bærentzen &
//! Aanæs 2005), which is exact for a closed, consistently oriented mesh — or, for the pieces
//! of a union, which share no edges, from the nearest face's normal when the nearest point lies
//! inside it, else from the crossings of the Z line through the point. Its solid also answers
//! where an axis-parallel line crosses it, so volumes of excess and gouges are measured ray by
//! ray like the stock's own volume.

use std::path::Path;

use parry3d_f64::query::{PointQueryWithLocation, Ray, RayCast};
use parry3d_f64::shape::{TriMesh, TriMeshFlags, TrianglePointLocation};
use swarf_geom::math::{Vec3, MACHINE_RANGE_MM};
use swarf_geom::{Aabb, RigidMotion};
use swarf_stock::Dexel;

use crate::error::VerifyError;

/// The nearest point of the design to a query point.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Projection {
    /// Signed distance, mm: positive outside the design's solid, negative inside.
    pub distance: f64,
    /// The nearest point of the design.
    pub closest: Vec3,
    /// Unit outward normal of the design there (for a point off the design: the direction
    /// from the nearest point to it, flipped inside; on it: the face's normal).
    pub normal: Vec3,
}

/// A design part: what verification asks of it.
pub trait Design: Sync {
    /// The nearest point of the design to `p` and the signed distance, or `None` where the
    /// design says nothing about `p` (beyond the edge of an open surface).
    fn project(&self, p: Vec3) -> Option<Projection>;

    /// Pushes onto `out` the intervals of the design's solid along the line parallel to axis
    /// `k` through cross coordinates `(u, v)` (along `(k+1)%3`, `(k+2)%3`; `cell` the grid's
    /// cell sizes there) and returns true; returns false when the design bounds no solid.
    fn solid_intervals(&self, k: usize, u: f64, v: f64, cell: (f64, f64), out: &mut Dexel) -> bool;

    /// True when the design bounds a solid (a closed mesh); false for a surface, which only
    /// says which side is outside near it.
    fn bounds_solid(&self) -> bool;

    /// Where the line through `p` along axis `k` (0 = X, 1 = Y, 2 = Z), followed in the
    /// direction `towards` (±1), first meets the design within `reach` mm: the design's
    /// outward normal there (up to sign), or `None` when it does not meet it that near.
    ///
    /// The default steps along the line by the distance to the design each time (sphere
    /// tracing: a step cannot pass through it), up to [`MEET_STEPS`] steps, and takes the
    /// nearest point's normal once closer than a thousandth of the reach.
    fn meet_along(&self, p: Vec3, k: usize, towards: f64, reach: f64) -> Option<Vec3> {
        let eps = (reach * 1e-3).max(1e-6);
        let (mut q, mut gone) = (p, 0.0);
        for _ in 0..MEET_STEPS {
            let pr = self.project(q)?;
            let step = pr.distance.abs();
            if step <= eps {
                return Some(pr.normal);
            }
            gone += step;
            if gone > reach {
                return None;
            }
            q[k] += towards * step;
        }
        None
    }

    /// A defect end's area weight ([`DefectEnd::area`](crate::DefectEnd::area)) is the
    /// normal's component along its ray where the ray meets the design; the nearest point's
    /// normal stands for it when its component is at least this (default ½: a ray crossing the
    /// nearest point's face within 60° of its normal meets that face, but beside an edge the
    /// nearest point may lie on another face — a convex edge's side face, component 0 — and
    /// the ray is followed with [`Design::meet_along`]). A design whose rays are cheap and
    /// exact follows every one (above 1); one smooth face never needs to (0).
    fn follow_rays_below(&self) -> f64 {
        0.5
    }

    /// The design's bounding box.
    fn bounding_box(&self) -> Aabb;

    /// A short description for reports ("closed mesh, 12 triangles, 1000 mm³").
    fn describe(&self) -> String;
}

/// Steps [`Design::meet_along`]'s default takes before it gives up.
pub const MEET_STEPS: usize = 64;

/// A closed triangle mesh as the design: the union of its bodies (bodies that overlap, nest
/// or touch are the solid they fill together; [`crate::union`]), outward.
#[derive(Clone)]
pub struct MeshDesign {
    /// The union's boundary: the input mesh itself when it already is that, consistently
    /// oriented (then `pseudo_normals`), else the pieces of it that bound the union.
    mesh: TriMesh,
    /// The side of a point is told by the nearest feature's angle-weighted pseudo-normal
    /// (exact for a closed, consistently oriented mesh); otherwise — pieces of several bodies,
    /// which share no edges — by the nearest face's normal where the nearest point lies inside
    /// a face, else by the crossings of the Z line through the point.
    pseudo_normals: bool,
    bbox: Aabb,
    volume: f64,
    /// Triangles of the input mesh.
    input_triangles: usize,
    /// What making the union changed, when it did.
    union: Option<crate::union::Union>,
}

impl std::fmt::Debug for MeshDesign {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "MeshDesign({})", self.describe())
    }
}

/// Cell size handed to [`swarf_stock::axis_line_intervals`] when a point's side is told by
/// the crossings of the Z line through it, mm: the line is nudged by a few millionths of it.
const SIDE_LINE_CELL_MM: f64 = 1e-3;

impl MeshDesign {
    /// Reads a closed STL part (binary or ASCII). Errors name the file.
    pub fn read_stl(path: &Path) -> Result<Self, VerifyError> {
        Self::read_stl_at(path, None)
    }

    /// [`MeshDesign::read_stl`], the mesh moved by `at` first (a part exported in another
    /// frame than the program's).
    pub fn read_stl_at(path: &Path, at: Option<&RigidMotion>) -> Result<Self, VerifyError> {
        let mut mesh = swarf_io::read_stl(path)?;
        if let Some(m) = at {
            for v in &mut mesh.vertices {
                *v = m.apply_point(*v);
            }
        }
        Self::named(&mesh, path)
    }

    /// The design bounded by `mesh`, which must be closed (every edge shared by exactly two
    /// triangles, or by four, six… half of them each way where closed bodies touch). The
    /// design is the union of its bodies, as for the stock: bodies that overlap or nest are
    /// one solid (the faces inside it are left out, faces that cross are cut where they cross),
    /// an inward-oriented mesh is turned outwards, and so is a triangle whose neighbours
    /// disagree with it (a flipped triangle; the stock's rule: along a line whose crossings do
    /// not balance they are paired by parity).
    pub fn new(mesh: &swarf_io::TriMesh) -> Result<Self, VerifyError> {
        Self::named(mesh, Path::new("<mesh>"))
    }

    fn named(mesh: &swarf_io::TriMesh, path: &Path) -> Result<Self, VerifyError> {
        let bad = |what: String| VerifyError::BadMesh {
            path: path.to_path_buf(),
            what,
        };
        if mesh.triangles.is_empty() {
            return Err(bad("no triangles".into()));
        }
        mesh.validate().map_err(|e| bad(e.to_string()))?;
        let report = mesh.edge_report();
        if report.boundary_count() > 0 {
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
            return Err(VerifyError::OpenMesh {
                path: path.to_path_buf(),
                count: report.boundary_count(),
                examples,
            });
        }
        let mut m = mesh.clone();
        if m.volume() < 0.0 {
            m.flip();
        }
        let bbox = m.aabb().ok_or_else(|| bad("no vertices".into()))?;
        // The stock is held to the machine range; a design beyond it could be compared with
        // no stock (and its distances lose their digits).
        let reach = bbox.min.abs().max(bbox.max.abs()).max_element();
        if reach > MACHINE_RANGE_MM {
            return Err(VerifyError::OutOfRange {
                path: path.to_path_buf(),
                min: bbox.min.to_array(),
                max: bbox.max.to_array(),
                reach,
                range: MACHINE_RANGE_MM,
            });
        }
        let input_triangles = m.triangles.len();
        let raw = TriMesh::new(m.vertices.clone(), m.triangles.clone())
            .map_err(|e| bad(format!("{e:?}")))?;
        let mut union = crate::union::union_boundary(&raw, 1e-9 * reach.max(1.0));
        let (mesh, pseudo_normals, volume, union) = if union.changed() || report.misoriented > 0 {
            let volume = union.volume;
            // The triangles live on in the mesh only.
            let boundary = std::mem::take(&mut union.triangles);
            let vertices: Vec<Vec3> = boundary.iter().flatten().copied().collect();
            let indices: Vec<[u32; 3]> = (0..boundary.len() as u32)
                .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
                .collect();
            if indices.is_empty() {
                return Err(bad("no triangle bounds the union of its bodies".into()));
            }
            let mesh = TriMesh::new(vertices, indices).map_err(|e| bad(format!("{e:?}")))?;
            (mesh, false, volume, Some(union))
        } else {
            let volume = m.volume();
            let mesh = TriMesh::with_flags(m.vertices, m.triangles, TriMeshFlags::ORIENTED)
                .map_err(|e| bad(format!("{e:?}")))?;
            (mesh, true, volume, None)
        };
        if !(volume > 0.0 && volume.is_finite()) {
            return Err(bad(format!("encloses no volume ({volume} mm³)")));
        }
        Ok(Self {
            mesh,
            pseudo_normals,
            bbox,
            volume,
            input_triangles,
            union,
        })
    }

    /// The enclosed volume, mm³: that of the union of the mesh's bodies.
    pub fn volume(&self) -> f64 {
        self.volume
    }

    /// What reading the mesh as the union of its bodies changed, in words (`None` when the
    /// mesh already bounded it, consistently oriented): how many triangles lie inside another
    /// body (or on a face two bodies share) and are left out, how many are cut where another
    /// body crosses them, and how many were turned outwards (the first by index and place).
    pub fn repairs(&self) -> Option<String> {
        let u = self.union.as_ref()?;
        let mut said = Vec::new();
        if u.inside > 0 {
            said.push(format!(
                "{} left out (wholly or partly inside another body, or on a face two bodies \
                 share)",
                u.inside
            ));
        }
        if u.cut > 0 {
            said.push(format!(
                "{} cut where another body's surface crosses or lies on them",
                u.cut
            ));
        }
        if let Some((t, c)) = u.first_turned {
            said.push(format!(
                "{} turned outwards, their neighbours disagreeing on the inside (the first: \
                 triangle {t}, centred at ({}, {}, {}))",
                u.turned, c.x, c.y, c.z
            ));
        }
        Some(format!(
            "read as the union of its bodies; of its {} triangles {}",
            self.input_triangles,
            if said.is_empty() {
                "none changed".to_string()
            } else {
                said.join(", ")
            }
        ))
    }

    /// True when `p` lies inside the union: the Z line through it, its crossings counted by
    /// orientation ([`swarf_stock::axis_line_intervals`]).
    fn contains(&self, p: Vec3) -> bool {
        let mut line = Dexel::new();
        swarf_stock::axis_line_intervals(
            &self.mesh,
            2,
            p.x,
            p.y,
            (SIDE_LINE_CELL_MM, SIDE_LINE_CELL_MM),
            &mut Vec::new(),
            &mut line,
        );
        line.iter().any(|iv| iv.enter < p.z && p.z < iv.exit)
    }
}

impl Design for MeshDesign {
    fn project(&self, p: Vec3) -> Option<Projection> {
        if !p.is_finite() {
            return None;
        }
        let (proj, (tri, loc)) = self.mesh.project_local_point_and_get_location(p, false);
        let d = p - proj.point;
        let len = d.length();
        let face = self.mesh.triangle(tri).normal();
        let inside = if self.pseudo_normals {
            proj.is_inside
        } else {
            match (loc, face) {
                (TrianglePointLocation::OnFace(..), Some(n)) => d.dot(n) < 0.0,
                _ => self.contains(p),
            }
        };
        let sign = if inside { -1.0 } else { 1.0 };
        let normal = if len > 1e-12 {
            d / len * sign
        } else {
            face.unwrap_or(Vec3::Z)
        };
        Some(Projection {
            distance: sign * len,
            closest: proj.point,
            normal,
        })
    }

    fn solid_intervals(&self, k: usize, u: f64, v: f64, cell: (f64, f64), out: &mut Dexel) -> bool {
        swarf_stock::axis_line_intervals(&self.mesh, k, u, v, cell, &mut Vec::new(), out);
        true
    }

    fn meet_along(&self, p: Vec3, k: usize, towards: f64, reach: f64) -> Option<Vec3> {
        // Exact, through the BVH: the first triangle the ray crosses.
        let mut dir = Vec3::ZERO;
        dir[k] = towards;
        let hit = self
            .mesh
            .cast_local_ray_and_get_normal(&Ray::new(p, dir), reach, false)?;
        Some(hit.normal)
    }

    fn follow_rays_below(&self) -> f64 {
        // Every ray: a cast costs about a projection.
        f64::INFINITY
    }

    fn bounds_solid(&self) -> bool {
        true
    }

    fn bounding_box(&self) -> Aabb {
        self.bbox
    }

    fn describe(&self) -> String {
        match &self.union {
            None => format!(
                "closed mesh, {} triangles, {:.3} mm³",
                self.input_triangles, self.volume
            ),
            Some(_) => format!(
                "closed mesh, {} triangles, {:.3} mm³ as the union of its bodies (bounded by {} \
                 triangles)",
                self.input_triangles,
                self.volume,
                self.mesh.indices().len()
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use swarf_geom::math::Vec3;

    #[test]
    fn closed_bodies_touching_along_an_edge_or_a_face_are_one_design() {
        // Two boxes sharing a vertical edge, and two sharing a face, welded as an STL reader
        // welds them: each body closed, the shared edges used four times (half each way).
        let v = Vec3::new;
        for (b, volume) in [
            (
                (v(20.0, 20.0, -20.0), v(40.0, 40.0, -1.0)),
                2.0 * 400.0 * 19.0,
            ),
            (
                (v(20.0, 0.0, -20.0), v(40.0, 20.0, -1.0)),
                2.0 * 400.0 * 19.0,
            ),
        ] {
            let mut m = swarf_io::TriMesh::cuboid(v(0.0, 0.0, -20.0), v(20.0, 20.0, -1.0));
            m.merge(&swarf_io::TriMesh::cuboid(b.0, b.1));
            let m = m.as_written();
            assert!(m.edge_report().touching > 0);
            let d = MeshDesign::new(&m).unwrap_or_else(|e| panic!("{e}"));
            assert!((d.volume() - volume).abs() < 1e-9, "{}", d.volume());
        }
        // The face two boxes share is inside their union: no distance finds it. A point 1 mm
        // inside the union, 0.5 mm from the shared face, is 1 mm from the design's boundary.
        let mut m = swarf_io::TriMesh::cuboid(v(0.0, 0.0, 0.0), v(20.0, 20.0, 10.0));
        m.merge(&swarf_io::TriMesh::cuboid(
            v(20.0, 0.0, 0.0),
            v(40.0, 20.0, 10.0),
        ));
        let d = MeshDesign::new(&m.as_written()).unwrap();
        assert_eq!(
            d.mesh.indices().len(),
            20,
            "the 4 shared triangles left out"
        );
        let p = d.project(v(20.5, 10.0, 9.0)).unwrap();
        assert!((p.distance.abs() - 1.0).abs() < 1e-12, "{p:?}");
        // The same with the second box's shared face split along its other diagonal
        // (exporters triangulate each body on its own).
        let mut b = swarf_io::TriMesh::cuboid(v(20.0, 0.0, 0.0), v(40.0, 20.0, 10.0));
        let on_face: Vec<usize> = (0..b.triangles.len())
            .filter(|&t| b.corners(t).iter().all(|c| c.x == 20.0))
            .collect();
        assert_eq!(on_face.len(), 2);
        let corner =
            |y: f64, z: f64| b.vertices.iter().position(|c| *c == v(20.0, y, z)).unwrap() as u32;
        let [p00, p10, p01, p11] = [
            corner(0.0, 0.0),
            corner(20.0, 0.0),
            corner(0.0, 10.0),
            corner(20.0, 10.0),
        ];
        // Facing −x, the other diagonal than the cuboid's, the same turn.
        let first = b.corners(on_face[0]);
        let diagonal_00_11 =
            first.contains(&v(20.0, 0.0, 0.0)) && first.contains(&v(20.0, 20.0, 10.0));
        let (t0, t1) = if diagonal_00_11 {
            ([p00, p01, p10], [p10, p01, p11])
        } else {
            ([p00, p11, p10], [p00, p01, p11])
        };
        b.triangles[on_face[0]] = t0;
        b.triangles[on_face[1]] = t1;
        let mut m = swarf_io::TriMesh::cuboid(v(0.0, 0.0, 0.0), v(20.0, 20.0, 10.0));
        m.merge(&b);
        let m = m.as_written();
        assert_eq!(m.edge_report().boundary_count(), 0, "{:?}", m.edge_report());
        assert_eq!(m.edge_report().misoriented, 0, "{:?}", m.edge_report());
        let d = MeshDesign::new(&m).unwrap();
        assert_eq!(
            d.mesh.indices().len(),
            20,
            "the 4 shared triangles left out"
        );
        assert!((d.volume() - 8000.0).abs() < 1e-9);
        let p = d.project(v(20.5, 10.0, 9.0)).unwrap();
        assert!((p.distance.abs() - 1.0).abs() < 1e-12, "{p:?}");
        // An open box is still refused.
        let mut open = swarf_io::TriMesh::cuboid(Vec3::ZERO, Vec3::splat(1.0));
        open.triangles.pop();
        assert!(MeshDesign::new(&open).is_err());
    }
}
