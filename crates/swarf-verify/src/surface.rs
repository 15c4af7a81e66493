//! A design given as surfaces (swarf JSON, STEP, IGES through `swarf-surface`): the certified
//! point–surface distance by branch-and-bound over the rational Bézier pieces of the patches.
//!
//! A piece lies in the convex hull of its control net (positive weights), so the distance
//! from the query point to the net's box — and to the slab the net spans along the piece's
//! corner normal — bounds the distance to the piece from below; the piece's corners (surface
//! points on the part) bound it from above. Pieces are halved (de Casteljau, trims honoured as
//! `swarf-surface` cuts them) until the smallest lower bound is within the accuracy of the best
//! corner: the distance is certified to [`DEFAULT_SURFACE_ACCURACY_MM`] (or the caller's
//! accuracy); the nearest point itself is a surface point within `√(2·d·accuracy)` of the true
//! one along the surface. Nothing off a trimmed part counts.
//!
//! Orientation follows `swarf-surface`: the normal `S_u × S_v` (negated on flipped patches)
//! points to the side the cutter comes from, the outside. A surface bounds no solid, so:
//! * a point whose nearest surface point is on the boundary of the design (not straight along
//!   the normal: the angle to it above 60°) is beyond the design, and not compared;
//! * the answer's sign is the side of the normal at the nearest point.
//!
//! Volumes of excess and gouges are then surface integrals (no solid to cast rays through).

use std::collections::BinaryHeap;

use swarf_geom::math::Vec3;
use swarf_geom::Aabb;
use swarf_stock::Dexel;
use swarf_surface::bezier::Piece;
use swarf_surface::{CompoundSurface, PreparedSurface};

use crate::design::{Design, Projection};

/// Default accuracy of the certified distance, mm.
pub const DEFAULT_SURFACE_ACCURACY_MM: f64 = 1e-4;

/// Pieces smaller than this (mm, box diagonal) are not split further (a guard; their corners
/// are within it of every point of them).
const MIN_PIECE_MM: f64 = 1e-7;

/// Cosine of the largest angle between the normal and the direction to a point for the point
/// to count as facing the surface (60°).
const FACING_COS: f64 = 0.5;

/// Compound surfaces as the design.
#[derive(Clone, Debug)]
pub struct SurfaceDesign {
    prepared: PreparedSurface,
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
        Some(Self {
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

impl Design for SurfaceDesign {
    fn project(&self, x: Vec3) -> Option<Projection> {
        if !x.is_finite() {
            return None;
        }
        let mut scratch = Vec::new();
        let mut heap = BinaryHeap::new();
        // Best corner: distance, point, piece and corner.
        let mut best: Option<(f64, Vec3, Piece, usize, usize)> = None;
        let consider = |pc: &Piece, best: &mut Option<(f64, Vec3, Piece, usize, usize)>| {
            let (p, q) = (pc.p, pc.q);
            for (i, j) in [(0, 0), (p, 0), (0, q), (p, q)] {
                if !pc.corner_on_part(i, j) {
                    continue;
                }
                let c = pc.point(i, j);
                let d = c.distance(x);
                if best.as_ref().map_or(true, |b| d < b.0) {
                    *best = Some((d, c, pc.clone(), i, j));
                }
            }
        };
        for pc in self
            .prepared
            .pieces
            .iter()
            .filter(|pc| !pc.check && pc.on_part())
        {
            consider(pc, &mut best);
            heap.push(Node {
                lb: lower_bound(pc, x, &mut scratch),
                piece: pc.clone(),
            });
        }
        while let Some(Node { lb, piece }) = heap.pop() {
            let ub = best.as_ref().map_or(f64::INFINITY, |b| b.0);
            if lb >= ub - self.accuracy {
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
                consider(&child, &mut best);
                let clb = lower_bound(&child, x, &mut scratch);
                let ub = best.as_ref().map_or(f64::INFINITY, |b| b.0);
                if clb < ub - self.accuracy {
                    heap.push(Node {
                        lb: clb,
                        piece: child,
                    });
                }
            }
        }
        let (dist, q, pc, i, j) = best?;
        let mut n = corner_normal(&pc, i, j)?;
        if self.flipped.get(pc.patch).copied().unwrap_or(false) {
            n = -n;
        }
        let s = (x - q).dot(n);
        if dist > self.accuracy && s.abs() < FACING_COS * dist {
            return None; // nearest to the design's boundary: beyond it
        }
        let sign = if s < 0.0 { -1.0 } else { 1.0 };
        Some(Projection {
            distance: sign * dist,
            closest: q,
            normal: n,
        })
    }

    fn solid_intervals(&self, _: usize, _: f64, _: f64, _: (f64, f64), _: &mut Dexel) -> bool {
        false
    }

    fn bounds_solid(&self) -> bool {
        false
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
