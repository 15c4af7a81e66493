//! The union of a mesh's bodies as the design's boundary: a design exported as several bodies
//! that overlap or nest (a multi-body export) is the solid they fill together, so its surface
//! is the part of each body's surface that lies inside no other body.
//!
//! Each triangle is cut where another body's surface crosses it: by the plane of every
//! triangle that truly crosses it (its pieces near the crossing segment only), and by the
//! edges of every triangle lying on its plane over a common area (a face two bodies share, or
//! two faces flush with each other). Each piece then lies wholly inside or outside every other
//! body, and is classified at its centre by the rule the stock uses for a mesh
//! ([`swarf_stock::axis_line_intervals`]: along the axis line nearest the piece's normal, the
//! crossings counted by orientation, paired by parity where they do not balance — a flipped
//! triangle): a piece whose two sides are both solid (inside another body, or on a face two
//! bodies share) or both empty is left out, one whose solid side is its front is turned
//! outwards, and of pieces that lie flush on one another the first triangle's stands for all.
//! The pieces left bound the union, outward; its volume is theirs (divergence theorem),
//! exact.
//!
//! Faces of different bodies closer than [`UNION_GAP_MM`] count as touching.

use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::shape::TriMesh;
use rayon::prelude::*;
use swarf_geom::math::Vec3;
use swarf_stock::{axis_line_intervals, Dexel};

/// How far on either side of a piece of surface its sides are looked at, mm: faces of
/// different bodies closer than this count as touching, and a body thinner than this is not
/// seen.
pub const UNION_GAP_MM: f64 = 1e-6;

/// The boundary of the union of a mesh's bodies.
#[derive(Clone, Debug, Default)]
pub(crate) struct Union {
    /// The boundary's triangles, counter-clockwise seen from outside.
    pub(crate) triangles: Vec<[Vec3; 3]>,
    /// The union's volume, mm³.
    pub(crate) volume: f64,
    /// Input triangles wholly or partly left out: inside another body, on a face two bodies
    /// share, or flush under another body's face.
    pub(crate) inside: usize,
    /// Input triangles cut where another body's surface crosses or overlaps them.
    pub(crate) cut: usize,
    /// Input triangles (or pieces of them) turned outwards.
    pub(crate) turned: usize,
    /// The first input triangle turned outwards, if any: its index and centre.
    pub(crate) first_turned: Option<(usize, Vec3)>,
}

impl Union {
    /// True when the union's boundary is not the input mesh as it is: some of it is left out or
    /// turned.
    pub(crate) fn changed(&self) -> bool {
        self.inside > 0 || self.turned > 0
    }
}

/// What became of one input triangle.
#[derive(Default)]
struct Pieces {
    kept: Vec<[Vec3; 3]>,
    inside: bool,
    cut: bool,
    turned: bool,
}

/// The boundary of the union of the bodies of `mesh` (its triangles in `mesh`'s order of
/// indices; any orientation of each body, a flipped triangle repaired). `tol` is the distance
/// within which points count as on a plane, mm (a billionth of the mesh's reach is right).
pub(crate) fn union_boundary(mesh: &TriMesh, tol: f64) -> Union {
    let n = mesh.indices().len();
    let per: Vec<Pieces> = (0..n)
        .into_par_iter()
        .map_init(
            || (Vec::new(), Dexel::new()),
            |(hits, dexel), t| triangle_pieces(mesh, t, tol, hits, dexel),
        )
        .collect();
    // Volumes about a point near the mesh: fewer digits lost than about the origin.
    let centre = {
        let b = mesh.local_aabb();
        (b.mins + b.maxs) * 0.5
    };
    let mut u = Union::default();
    for (t, p) in per.into_iter().enumerate() {
        u.inside += usize::from(p.inside);
        u.cut += usize::from(p.cut);
        u.turned += usize::from(p.turned);
        if p.turned && u.first_turned.is_none() {
            let [a, b, c] = corners(mesh, t);
            u.first_turned = Some((t, (a + b + c) / 3.0));
        }
        for [a, b, c] in p.kept {
            u.volume += (a - centre).dot((b - centre).cross(c - centre)) / 6.0;
            u.triangles.push([a, b, c]);
        }
    }
    u
}

/// The unit normal and plane offset of a triangle, or `None` when it is degenerate.
fn plane(t: &[Vec3; 3]) -> Option<(Vec3, f64)> {
    let n = (t[1] - t[0]).cross(t[2] - t[0]);
    let len = n.length();
    (len > 0.0 && len.is_finite()).then(|| {
        let n = n / len;
        (n, n.dot(t[0]))
    })
}

fn corners(mesh: &TriMesh, t: usize) -> [Vec3; 3] {
    let tri = mesh.triangle(t as u32);
    [tri.a, tri.b, tri.c]
}

/// The box of `points`, grown by `pad`.
fn bounds(points: &[Vec3], pad: f64) -> (Vec3, Vec3) {
    let lo = points
        .iter()
        .copied()
        .fold(Vec3::splat(f64::INFINITY), Vec3::min);
    let hi = points
        .iter()
        .copied()
        .fold(Vec3::splat(f64::NEG_INFINITY), Vec3::max);
    (lo - Vec3::splat(pad), hi + Vec3::splat(pad))
}

fn boxes_meet(a: (Vec3, Vec3), b: (Vec3, Vec3)) -> bool {
    a.0.cmple(b.1).all() && b.0.cmple(a.1).all()
}

/// Whether two triangles on one plane share an area (not just an edge or a corner): no edge
/// of either separates them by more than `tol`.
fn overlap_on_plane(a: &[Vec3; 3], b: &[Vec3; 3], tol: f64) -> bool {
    let separates = |x: &[Vec3; 3], y: &[Vec3; 3]| {
        let nx = (x[1] - x[0]).cross(x[2] - x[0]);
        (0..3).any(|i| {
            let (p, r) = (x[i], x[(i + 1) % 3]);
            // Inward, in the plane: towards x's third corner.
            let w = nx.cross(r - p).normalize_or_zero();
            y.iter().all(|q| w.dot(*q - p) <= tol)
        })
    };
    !separates(a, b) && !separates(b, a)
}

/// Whether `q` (on the triangle's plane) lies inside triangle `t`.
fn inside_triangle(t: &[Vec3; 3], q: Vec3) -> bool {
    let n = (t[1] - t[0]).cross(t[2] - t[0]);
    (0..3).all(|i| {
        let (p, r) = (t[i], t[(i + 1) % 3]);
        (r - p).cross(q - p).dot(n) >= 0.0
    })
}

/// The ends of the segment where the plane with signed distances `d` of the corners crosses
/// triangle `t`, ordered along `dir`: corners on the plane (within `tol`) and edges that cross
/// it.
fn crossing(t: &[Vec3; 3], d: [f64; 3], dir: Vec3, tol: f64) -> Option<(Vec3, Vec3)> {
    let mut pts: smallvec::SmallVec<[Vec3; 4]> = smallvec::SmallVec::new();
    for i in 0..3 {
        let (p, dp) = (t[i], d[i]);
        let (q, dq) = (t[(i + 1) % 3], d[(i + 1) % 3]);
        if dp.abs() <= tol {
            pts.push(p);
        }
        if (dp > tol && dq < -tol) || (dp < -tol && dq > tol) {
            pts.push(p + (q - p) * (dp / (dp - dq)));
        }
    }
    let lo = pts
        .iter()
        .copied()
        .min_by(|a, b| dir.dot(*a).total_cmp(&dir.dot(*b)))?;
    let hi = pts
        .iter()
        .copied()
        .max_by(|a, b| dir.dot(*a).total_cmp(&dir.dot(*b)))?;
    Some((lo, hi))
}

/// Splits the convex polygon `poly` by the plane `m·x = o` into the parts on either side, or
/// `None` when no corner lies farther than `tol` on each side.
fn split(poly: &[Vec3], m: Vec3, o: f64, tol: f64) -> Option<(Vec<Vec3>, Vec<Vec3>)> {
    let d: Vec<f64> = poly.iter().map(|p| m.dot(*p) - o).collect();
    if !(d.iter().any(|&x| x > tol) && d.iter().any(|&x| x < -tol)) {
        return None;
    }
    let (mut pos, mut neg) = (Vec::new(), Vec::new());
    for i in 0..poly.len() {
        let j = (i + 1) % poly.len();
        let (p, dp, dq) = (poly[i], d[i], d[j]);
        if dp > tol {
            pos.push(p);
        } else if dp < -tol {
            neg.push(p);
        } else {
            pos.push(p);
            neg.push(p);
        }
        if (dp > tol && dq < -tol) || (dp < -tol && dq > tol) {
            let x = p + (poly[j] - p) * (dp / (dp - dq));
            pos.push(x);
            neg.push(x);
        }
    }
    (pos.len() >= 3 && neg.len() >= 3).then_some((pos, neg))
}

/// The pieces of triangle `t` on the union's boundary, outward.
fn triangle_pieces(
    mesh: &TriMesh,
    t: usize,
    tol: f64,
    hits: &mut Vec<(f64, i32)>,
    dexel: &mut Dexel,
) -> Pieces {
    let tri = corners(mesh, t);
    let mut out = Pieces::default();
    // A triangle of no area bounds nothing (and is left out of the boundary unremarked).
    let Some((n, off)) = plane(&tri) else {
        return out;
    };
    let (lo, hi) = bounds(&tri, tol);
    // Planes to cut along: (normal, offset, where the cut is wanted).
    let mut cuts: Vec<(Vec3, f64, (Vec3, Vec3))> = Vec::new();
    // Triangles lying on this one's plane over a common area, by index.
    let mut flush: Vec<(usize, [Vec3; 3])> = Vec::new();
    for s in mesh.bvh().intersect_aabb(&Aabb::new(lo, hi)) {
        let s = s as usize;
        if s == t {
            continue;
        }
        let q = corners(mesh, s);
        let ds = q.map(|p| n.dot(p) - off);
        if ds.iter().all(|d| d.abs() <= tol) {
            if plane(&q).is_some() && overlap_on_plane(&tri, &q, tol) {
                for i in 0..3 {
                    let (p, r) = (q[i], q[(i + 1) % 3]);
                    let m = n.cross(r - p).normalize_or_zero();
                    if m != Vec3::ZERO {
                        cuts.push((m, m.dot(p), bounds(&q, tol)));
                    }
                }
                flush.push((s, q));
            }
            continue;
        }
        if ds.iter().all(|&d| d >= -tol) || ds.iter().all(|&d| d <= tol) {
            continue;
        }
        let Some((ns, os)) = plane(&q) else { continue };
        let dt = tri.map(|p| ns.dot(p) - os);
        if dt.iter().all(|&d| d >= -tol) || dt.iter().all(|&d| d <= tol) {
            continue;
        }
        // Both cross the other's plane: the segments on the planes' common line overlap
        // where the triangles cross.
        let dir = n.cross(ns).normalize_or_zero();
        if dir == Vec3::ZERO {
            continue;
        }
        let (Some((t0, t1)), Some((s0, s1))) =
            (crossing(&tri, dt, dir, tol), crossing(&q, ds, dir, tol))
        else {
            continue;
        };
        let a = if dir.dot(t0) > dir.dot(s0) { t0 } else { s0 };
        let b = if dir.dot(t1) < dir.dot(s1) { t1 } else { s1 };
        if dir.dot(b) - dir.dot(a) > tol {
            cuts.push((ns, os, bounds(&[a, b], tol)));
        }
    }
    let mut pieces: Vec<Vec<Vec3>> = vec![tri.to_vec()];
    for (m, o, near) in &cuts {
        let mut next = Vec::with_capacity(pieces.len() + 1);
        for poly in pieces {
            if !boxes_meet(bounds(&poly, 0.0), *near) {
                next.push(poly);
                continue;
            }
            match split(&poly, *m, *o, tol) {
                Some((p, q)) => {
                    next.push(p);
                    next.push(q);
                }
                None => next.push(poly),
            }
        }
        pieces = next;
    }
    out.cut = pieces.len() > 1;
    let k = (0..3)
        .max_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs()))
        .unwrap_or(2);
    let (ku, kv) = ((k + 1) % 3, (k + 2) % 3);
    for poly in pieces {
        let c = poly.iter().copied().sum::<Vec3>() / poly.len() as f64;
        // The line through the centre, nudged (by the stock's rule) far less than the
        // piece's inner size so that it still crosses the piece.
        let inner = (0..poly.len())
            .map(|i| {
                let (p, r) = (poly[i], poly[(i + 1) % poly.len()]);
                let e = r - p;
                e.cross(c - p).length() / e.length().max(f64::MIN_POSITIVE)
            })
            .fold(f64::INFINITY, f64::min);
        if !(inner > 0.0 && inner.is_finite()) {
            continue;
        }
        let cell = inner * 1e-2;
        dexel.clear();
        axis_line_intervals(mesh, k, c[ku], c[kv], (cell, cell), hits, dexel);
        let solid = |x: f64| dexel.iter().any(|iv| iv.enter < x && x < iv.exit);
        let (below, above) = (solid(c[k] - UNION_GAP_MM), solid(c[k] + UNION_GAP_MM));
        if below == above {
            out.inside = true;
            continue;
        }
        // Flush under another body's face: that triangle's piece here stands for both.
        if flush.iter().any(|(s, q)| *s < t && inside_triangle(q, c)) {
            out.inside = true;
            continue;
        }
        // Outward is +k where the solid lies below along the line.
        let outward = (n[k] > 0.0) == below;
        out.turned |= !outward;
        for i in 1..poly.len() - 1 {
            out.kept.push(if outward {
                [poly[0], poly[i], poly[i + 1]]
            } else {
                [poly[0], poly[i + 1], poly[i]]
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn raw(m: &swarf_io::TriMesh) -> TriMesh {
        TriMesh::new(m.vertices.clone(), m.triangles.clone()).unwrap()
    }

    #[test]
    fn splitting_a_square_by_a_diagonal_plane() {
        let sq = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(2.0, 2.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
        ];
        // x = 0.5: a 0.5 × 2 and a 1.5 × 2 rectangle.
        let (p, q) = split(&sq, Vec3::X, 0.5, 1e-12).unwrap();
        assert_eq!(p.len(), 4);
        assert_eq!(q.len(), 4);
        // Through two corners (the diagonal): two triangles, the corners in both.
        let m = Vec3::new(1.0, -1.0, 0.0).normalize();
        let (p, q) = split(&sq, m, 0.0, 1e-12).unwrap();
        assert_eq!((p.len(), q.len()), (3, 3));
        // Along an edge: no split.
        assert!(split(&sq, Vec3::X, 0.0, 1e-12).is_none());
    }

    #[test]
    fn a_body_inside_another_is_left_out_and_a_crossing_one_cut() {
        // 20 × 20 × 9 with a 10 × 10 × 5 box inside: the outer box alone.
        let v = Vec3::new;
        let mut m = swarf_io::TriMesh::cuboid(v(0.0, 0.0, -10.0), v(20.0, 20.0, -1.0));
        m.merge(&swarf_io::TriMesh::cuboid(
            v(5.0, 5.0, -8.0),
            v(15.0, 15.0, -3.0),
        ));
        let u = union_boundary(&raw(&m), 1e-9);
        assert_eq!((u.inside, u.cut, u.turned), (12, 0, 0));
        assert_eq!(u.triangles.len(), 12);
        assert!((u.volume - 3600.0).abs() < 1e-9, "{}", u.volume);
        // Boxes x 0–12 and 8–20 (y 0–20, z −10…−1): 20 × 20 × 9, tops flush.
        let mut m = swarf_io::TriMesh::cuboid(v(0.0, 0.0, -10.0), v(12.0, 20.0, -1.0));
        m.merge(&swarf_io::TriMesh::cuboid(
            v(8.0, 0.0, -10.0),
            v(20.0, 20.0, -1.0),
        ));
        let u = union_boundary(&raw(&m), 1e-9);
        assert!((u.volume - 3600.0).abs() < 1e-9, "{}", u.volume);
        assert_eq!(u.turned, 0);
        // Area: that of the 20 × 20 × 9 box, each flush face counted once.
        let area: f64 = u
            .triangles
            .iter()
            .map(|t| 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length())
            .sum();
        assert!((area - (2.0 * 400.0 + 4.0 * 180.0)).abs() < 1e-9, "{area}");
    }
}
