//! A design given as surfaces (swarf JSON, STEP, IGES through `swarf-surface`): the certified
//! point–surface distance by branch-and-bound over the rational Bézier pieces of the patches.
//!
//! A piece lies in the convex hull of its control net (positive weights), so the distance
//! from the query point to the net's box — and to the slab the net spans along the piece's
//! corner normal — bounds the distance to the piece from below; the piece's corners (surface
//! points on the part) bound it from above. Pieces are halved (de Casteljau, trims honoured as
//! `swarf-surface` cuts them) until the smallest lower bound is within the accuracy of the best
//! corner (and the Gauss–Newton foot point on the starting pieces): the distance `d` is
//! certified to [`DEFAULT_SURFACE_ACCURACY_MM`] (or the caller's accuracy), or to
//! [`RELATIVE_ACCURACY`]·`d` where that is larger (far from the design); the nearest point itself is a surface point within `√(2·d·accuracy)` of the true
//! one along the surface. Nothing off a trimmed part counts.
//!
//! Orientation follows `swarf-surface`: the normal `S_u × S_v` (negated on flipped patches)
//! points to the side the cutter comes from, the outside. A surface bounds no solid, so:
//! * a point whose nearest surface point is on the boundary of the design (not straight along
//!   the normal: the angle to it above 18°) is beyond the design, and not compared;
//! * the answer's sign is the side of the normal at the nearest point.
//!
//! Volumes of excess and gouges are then surface integrals (no solid to cast rays through).

use std::collections::BinaryHeap;

use glam::DVec4;
use smallvec::SmallVec;
use swarf_geom::math::Vec3;
use swarf_geom::Aabb;
use swarf_stock::Dexel;
use swarf_surface::bezier::{OnPart, Piece};
use swarf_surface::{CompoundSurface, PreparedSurface};

use crate::design::{Design, Projection};

/// Default accuracy of the certified distance, mm.
pub const DEFAULT_SURFACE_ACCURACY_MM: f64 = 1e-4;

/// Relative accuracy of distances far from the design (see [`SurfaceDesign::tolerance_at`]).
pub const RELATIVE_ACCURACY: f64 = 1e-3;

/// Pieces smaller than this (mm, box diagonal) are not split further (a guard; their corners
/// are within it of every point of them).
const MIN_PIECE_MM: f64 = 1e-7;

/// Cosine of the largest angle between the normal and the direction to a point for the point
/// to count as facing the surface (18°: the nearest point of an interior point is straight
/// along the normal, up to the search's accuracy; past the design's edge the angle grows).
const FACING_COS: f64 = 0.95;

/// Compound surfaces as the design.
#[derive(Clone, Debug)]
pub struct SurfaceDesign {
    prepared: PreparedSurface,
    /// The pieces the search starts from (on the part, not check geometry) and the boxes of
    /// their control nets.
    roots: Vec<(Aabb, usize)>,
    flipped: Vec<bool>,
    bbox: Aabb,
    accuracy: f64,
    patches: usize,
}

impl SurfaceDesign {
    /// The design bounded (on its outer side) by `surface`, distances certified to `accuracy`
    /// mm (non-positive or non-finite: the default).
    pub fn new(surface: &CompoundSurface, accuracy: f64) -> Option<Self> {
        let prepared = PreparedSurface::new(surface);
        let bbox = prepared.bounding_box()?;
        let mut scratch = Vec::new();
        let roots = prepared
            .pieces
            .iter()
            .enumerate()
            .filter(|(_, pc)| !pc.check && pc.on_part())
            .filter_map(|(i, pc)| {
                scratch.clear();
                pc.euclidean(&mut scratch);
                Aabb::from_points(scratch.iter().copied()).map(|b| (b, i))
            })
            .collect();
        Some(Self {
            roots,
            flipped: surface.patches.iter().map(|p| p.flipped).collect(),
            patches: surface.patches.len(),
            prepared,
            bbox,
            accuracy: if accuracy > 0.0 && accuracy.is_finite() {
                accuracy
            } else {
                DEFAULT_SURFACE_ACCURACY_MM
            },
        })
    }
}

/// A piece in the search, ordered by its lower bound (smallest first from the max-heap).
struct Node {
    lb: f64,
    piece: Piece,
}

impl PartialEq for Node {
    fn eq(&self, o: &Self) -> bool {
        self.lb == o.lb
    }
}
impl Eq for Node {}
impl PartialOrd for Node {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Node {
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        o.lb.total_cmp(&self.lb)
    }
}

/// The unit normal `S_u × S_v` of a piece at its corner `(i, j)` (`i ∈ {0, p}`, `j ∈ {0, q}`)
/// from the net's edges there; the diagonals where those degenerate (a pole).
fn corner_normal(pc: &Piece, i: usize, j: usize) -> Option<Vec3> {
    let (p, q) = (pc.p, pc.q);
    let c = pc.point(i, j);
    let du = if i == 0 {
        pc.point(1.min(p), j) - c
    } else {
        c - pc.point(i - 1, j)
    };
    let dv = if j == 0 {
        pc.point(i, 1.min(q)) - c
    } else {
        c - pc.point(i, j - 1)
    };
    let n = du.cross(dv);
    if n.length() > 1e-12 * (du.length() * dv.length()).max(1e-300) && n.length() > 0.0 {
        return Some(n.normalize());
    }
    let n = (pc.point(p, q) - pc.point(0, 0)).cross(pc.point(0, q) - pc.point(p, 0));
    (n.length() > 0.0).then(|| n.normalize())
}

/// Lower bound of the distance from `x` to the piece: its net's box, and the slab the net
/// spans along the corner normal.
fn lower_bound(pc: &Piece, x: Vec3, scratch: &mut Vec<Vec3>) -> f64 {
    scratch.clear();
    pc.euclidean(scratch);
    let Some(b) = Aabb::from_points(scratch.iter().copied()) else {
        return f64::INFINITY;
    };
    let d = x - x.clamp(b.min, b.max);
    let mut lb = d.length();
    if let Some(n) = corner_normal(pc, 0, 0) {
        let (lo, hi) = scratch
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
                let s = n.dot(*p);
                (l.min(s), h.max(s))
            });
        let s = n.dot(x);
        lb = lb.max(lo - s).max(s - hi);
    }
    lb
}

fn diagonal(scratch: &[Vec3]) -> f64 {
    Aabb::from_points(scratch.iter().copied()).map_or(0.0, |b| b.size().length())
}

/// The best surface point found so far.
struct Foot {
    distance: f64,
    point: Vec3,
    /// Unit `S_u × S_v` there (not yet flipped for the patch).
    normal: Vec3,
    patch: usize,
}

/// The rational Bézier piece at local parameters `(u, v)` ∈ [0, 1]² (de Casteljau on the
/// homogeneous net).
fn eval(pc: &Piece, u: f64, v: f64) -> Vec3 {
    let (p, q) = (pc.p, pc.q);
    let mut col: SmallVec<[DVec4; 8]> = SmallVec::with_capacity(p + 1);
    let mut row: SmallVec<[DVec4; 8]> = SmallVec::with_capacity(q + 1);
    for i in 0..=p {
        row.clear();
        row.extend_from_slice(&pc.net[i * (q + 1)..(i + 1) * (q + 1)]);
        for r in 1..=q {
            for j in 0..=q - r {
                row[j] = row[j] * (1.0 - v) + row[j + 1] * v;
            }
        }
        col.push(row[0]);
    }
    for r in 1..=p {
        for i in 0..=p - r {
            col[i] = col[i] * (1.0 - u) + col[i + 1] * u;
        }
    }
    let h = col[0];
    Vec3::new(h.x, h.y, h.z) / h.w
}

/// Point, `S_u` and `S_v` (central differences, one-sided at the box's edges).
fn eval_d(pc: &Piece, u: f64, v: f64) -> (Vec3, Vec3, Vec3) {
    const E: f64 = 1e-6;
    let s = eval(pc, u, v);
    let (u0, u1) = ((u - E).max(0.0), (u + E).min(1.0));
    let (v0, v1) = ((v - E).max(0.0), (v + E).min(1.0));
    let su = (eval(pc, u1, v) - eval(pc, u0, v)) / (u1 - u0);
    let sv = (eval(pc, u, v1) - eval(pc, u, v0)) / (v1 - v0);
    (s, su, sv)
}

/// Updates `best` with the piece's on-part corners and, with `newton` on a piece wholly on the
/// part, the foot of `x` found by damped Gauss–Newton from the nearest corner: every candidate
/// is a true surface point, so each is an upper bound.
fn consider(pc: &Piece, x: Vec3, newton: bool, best: &mut Option<Foot>) {
    let (p, q) = (pc.p, pc.q);
    let mut near: Option<(f64, f64, f64)> = None;
    for (i, j) in [(0, 0), (p, 0), (0, q), (p, q)] {
        if !pc.corner_on_part(i, j) {
            continue;
        }
        let c = pc.point(i, j);
        let d = c.distance(x);
        let uv = (
            if i == 0 { 0.0 } else { 1.0 },
            if j == 0 { 0.0 } else { 1.0 },
        );
        if near.map_or(true, |n| d < n.0) {
            near = Some((d, uv.0, uv.1));
        }
        if best.as_ref().map_or(true, |b| d < b.distance) {
            if let Some(n) = corner_normal(pc, i, j) {
                *best = Some(Foot {
                    distance: d,
                    point: c,
                    normal: n,
                    patch: pc.patch,
                });
            }
        }
    }
    if !newton || pc.on != OnPart::Whole {
        return;
    }
    let Some((mut d, mut u, mut v)) = near else {
        return;
    };
    for _ in 0..8 {
        let (s, su, sv) = eval_d(pc, u, v);
        let r = x - s;
        let (a, b, c) = (su.dot(su), su.dot(sv), sv.dot(sv));
        let det = a * c - b * b;
        if det.is_nan() || det.abs() <= 1e-300 {
            break;
        }
        let (gu, gv) = (su.dot(r), sv.dot(r));
        let (mut du, mut dv) = ((c * gu - b * gv) / det, (a * gv - b * gu) / det);
        let mut moved = false;
        for _ in 0..6 {
            let (nu, nv) = ((u + du).clamp(0.0, 1.0), (v + dv).clamp(0.0, 1.0));
            let nd = eval(pc, nu, nv).distance(x);
            if nd < d {
                (u, v, d) = (nu, nv, nd);
                moved = true;
                break;
            }
            du *= 0.5;
            dv *= 0.5;
        }
        if !moved {
            break;
        }
    }
    if best.as_ref().map_or(true, |b| d < b.distance) {
        let (s, su, sv) = eval_d(pc, u, v);
        let n = su.cross(sv);
        if n.length() > 0.0 {
            *best = Some(Foot {
                distance: s.distance(x),
                point: s,
                normal: n.normalize(),
                patch: pc.patch,
            });
        }
    }
}

impl SurfaceDesign {
    /// The certified accuracy at distance `d`: the absolute accuracy, or [`RELATIVE_ACCURACY`]
    /// of `d` when larger (far from the design, where no tolerance is in question).
    fn tolerance_at(&self, d: f64) -> f64 {
        self.accuracy.max(RELATIVE_ACCURACY * d)
    }
}

impl Design for SurfaceDesign {
    fn project(&self, x: Vec3) -> Option<Projection> {
        if !x.is_finite() {
            return None;
        }
        let mut scratch = Vec::new();
        let mut heap = BinaryHeap::new();
        let mut best: Option<Foot> = None;
        // Start from the piece whose box is nearest (its foot point bounds the distance from
        // above), then search only the pieces whose boxes come closer than that.
        let box_distance = |b: &Aabb| (x - x.clamp(b.min, b.max)).length();
        let (_, first) = self
            .roots
            .iter()
            .map(|(b, i)| (box_distance(b), *i))
            .min_by(|a, b| a.0.total_cmp(&b.0))?;
        consider(&self.prepared.pieces[first], x, true, &mut best);
        let ub = best.as_ref().map_or(f64::INFINITY, |b| b.distance);
        for (b, i) in &self.roots {
            if box_distance(b) < ub - self.accuracy {
                let pc = &self.prepared.pieces[*i];
                let lb = lower_bound(pc, x, &mut scratch);
                if lb < best.as_ref().map_or(f64::INFINITY, |b| b.distance) - self.accuracy {
                    if *i != first {
                        consider(pc, x, true, &mut best);
                    }
                    heap.push(Node {
                        lb,
                        piece: pc.clone(),
                    });
                }
            }
        }
        while let Some(Node { lb, piece }) = heap.pop() {
            let ub = best.as_ref().map_or(f64::INFINITY, |b| b.distance);
            if lb >= ub - self.tolerance_at(ub) {
                break;
            }
            scratch.clear();
            piece.euclidean(&mut scratch);
            if diagonal(&scratch) < MIN_PIECE_MM {
                continue;
            }
            for child in piece.children() {
                if !child.on_part() {
                    continue;
                }
                consider(&child, x, false, &mut best);
                let clb = lower_bound(&child, x, &mut scratch);
                let ub = best.as_ref().map_or(f64::INFINITY, |b| b.distance);
                if clb < ub - self.tolerance_at(ub) {
                    heap.push(Node {
                        lb: clb,
                        piece: child,
                    });
                }
            }
        }
        let foot = best?;
        let mut n = foot.normal;
        if self.flipped.get(foot.patch).copied().unwrap_or(false) {
            n = -n;
        }
        let s = (x - foot.point).dot(n);
        if foot.distance > self.accuracy && s.abs() < FACING_COS * foot.distance {
            return None; // nearest to the design's boundary: beyond it
        }
        let sign = if s < 0.0 { -1.0 } else { 1.0 };
        Some(Projection {
            distance: sign * foot.distance,
            closest: foot.point,
            normal: n,
        })
    }

    fn solid_intervals(&self, _: usize, _: f64, _: f64, _: (f64, f64), _: &mut Dexel) -> bool {
        false
    }

    fn bounds_solid(&self) -> bool {
        false
    }

    fn follow_rays_below(&self) -> f64 {
        // One patch is taken as smooth: a ray behind it meets it where its nearest point's
        // normal is the one to weigh by, to first order in the depth (a crease inside a patch is
        // weighed by the nearest point's normal too). Several may meet at edges.
        if self.patches > 1 {
            0.5
        } else {
            0.0
        }
    }

    fn bounding_box(&self) -> Aabb {
        self.bbox
    }

    fn describe(&self) -> String {
        format!(
            "{} surface patches, {} Bézier pieces, distances certified to {} mm",
            self.patches,
            self.prepared.piece_count(),
            self.accuracy
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bilinear NURBS patch over `[0, 10]²` at height `z`, normal +Z unless `flip`.
    fn plane(z: f64) -> CompoundSurface {
        let json = format!(
            r#"{{"units": "mm", "patches": [{{"name": "top", "degree_u": 1, "degree_v": 1,
            "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
            "control_points": [[[0, 0, {z}, 1], [0, 10, {z}, 1]], [[10, 0, {z}, 1], [10, 10, {z}, 1]]]}}]}}"#
        );
        swarf_surface::io::parse(swarf_surface::io::Format::Json, &json).unwrap()
    }

    #[test]
    fn plane_distances_are_exact_and_signed() {
        let d = SurfaceDesign::new(&plane(5.0), 0.0).unwrap();
        let p = d.project(Vec3::new(3.0, 4.0, 5.7)).unwrap();
        assert!((p.distance - 0.7).abs() < 1e-4, "{p:?}");
        // The distance is certified; the point only to √(2·d·accuracy) along the surface.
        assert!((p.closest - Vec3::new(3.0, 4.0, 5.0)).length() < (2.0 * 0.7 * 1e-4f64).sqrt());
        let p = d.project(Vec3::new(7.0, 2.0, 4.2)).unwrap();
        assert!((p.distance + 0.8).abs() < 1e-4, "{p:?}");
        // Beyond the edge: nothing to compare with.
        assert!(d.project(Vec3::new(20.0, 5.0, 5.1)).is_none());
        let mut flipped = plane(5.0);
        flipped.flip_all();
        let f = SurfaceDesign::new(&flipped, 0.0).unwrap();
        assert!((f.project(Vec3::new(3.0, 4.0, 5.7)).unwrap().distance + 0.7).abs() < 1e-4);
    }
}
