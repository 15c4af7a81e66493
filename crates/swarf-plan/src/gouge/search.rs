//! The deepest surface point inside a convex tool part over a stretch of a fixed-axis straight
//! move: best-first branch-and-bound over (Bézier sub-patch × parameter interval) with the
//! support-plane bound of the module docs ([`super`]).

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use parry3d_f64::bounding_volume::Aabb as PAabb;
use parry3d_f64::math::Vector as PVec;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy};
use smallvec::SmallVec;
use swarf_geom::math::Vec3;
use swarf_geom::Aabb;
use swarf_sweep::{ConvexProfile, SweptConvex};

use swarf_surface::bezier::Piece;
use swarf_surface::PreparedSurface;

/// The surface (and check geometry) prepared for the gouge search: its rational Bézier pieces
/// and a bounding-volume hierarchy over their control-net boxes.
pub struct GougeSurface {
    pieces: Vec<Piece>,
    bvh: Bvh,
}

impl std::fmt::Debug for GougeSurface {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GougeSurface")
            .field("pieces", &self.pieces.len())
            .finish()
    }
}

impl GougeSurface {
    /// The pieces of `prep` (surface patches and check triangles) with their hierarchy.
    pub fn new(prep: &PreparedSurface) -> Self {
        let pieces = prep.pieces.clone();
        let boxes: Vec<PAabb> = pieces
            .iter()
            .map(|pc| {
                let b = net_box(pc);
                PAabb::new(
                    PVec::new(b.min.x, b.min.y, b.min.z),
                    PVec::new(b.max.x, b.max.y, b.max.z),
                )
            })
            .collect();
        let bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &boxes);
        Self { pieces, bvh }
    }

    /// Number of root pieces (Bézier pieces and check triangles).
    pub fn piece_count(&self) -> usize {
        self.pieces.len()
    }

    /// Root pieces whose control-net box meets `b`.
    fn candidates(&self, b: &Aabb, out: &mut Vec<usize>) {
        out.clear();
        if self.pieces.is_empty() {
            return;
        }
        let q = PAabb::new(
            PVec::new(b.min.x, b.min.y, b.min.z),
            PVec::new(b.max.x, b.max.y, b.max.z),
        );
        out.extend(self.bvh.intersect_aabb(&q).map(|i| i as usize));
    }
}

fn net_box(pc: &Piece) -> Aabb {
    Aabb::from_points(pc.net.iter().map(|h| Vec3::new(h.x, h.y, h.z) / h.w))
        .unwrap_or_else(|| Aabb::new(Vec3::ZERO, Vec3::ZERO))
}

/// A fixed-axis straight motion of one convex tool part: the tip runs from `tip0` to
/// `tip0 + delta` as `t` goes from 0 to 1, the unit axis stays `axis`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Segment<'a> {
    pub part: &'a ConvexProfile,
    pub tip0: Vec3,
    pub delta: Vec3,
    pub axis: Vec3,
}

impl Segment<'_> {
    fn tip(&self, t: f64) -> Vec3 {
        self.tip0 + t * self.delta
    }
}

/// Which pieces a search looks at.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Pieces {
    /// The machined surface and the check geometry.
    All,
    /// The machined surface only.
    Surface,
    /// The check geometry only.
    Check,
}

impl Pieces {
    fn admits(self, pc: &Piece) -> bool {
        match self {
            Pieces::All => true,
            Pieces::Surface => !pc.check,
            Pieces::Check => pc.check,
        }
    }
}

/// What the search asks.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Query {
    /// Parameter interval of the segment.
    pub t0: f64,
    /// End of it.
    pub t1: f64,
    /// The pieces searched.
    pub pieces: Pieces,
    /// Depths at or below this do not matter (the reporting tolerance).
    pub floor: f64,
    /// Stop as soon as a point deeper than this is found (the caller will split anyway).
    pub stop_above: f64,
    /// Certificate gap on the depth, mm, or `relative_accuracy` times the depth if larger.
    pub accuracy: f64,
    /// The relative part of the gap.
    pub relative_accuracy: f64,
    /// Node budget.
    pub max_nodes: u64,
}

/// The deepest point found and the bound on anything deeper.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Deepest {
    /// Depth of the deepest point found inside the part (negative: the clearance of the nearest
    /// point evaluated, not certified), mm; `-inf` when nothing was near.
    pub depth: f64,
    /// No point of the surface is deeper than this over the interval (certified unless the
    /// budget ran out, see `certified`).
    pub upper: f64,
    /// The point, its parameter on the segment, and its piece.
    pub point: Vec3,
    pub t: f64,
    pub patch: usize,
    pub check: bool,
    /// Nodes expanded.
    pub nodes: u64,
    /// False when the budget ran out (`upper` is still a valid bound).
    pub certified: bool,
}

struct Node {
    ub: f64,
    /// The part of `ub − depth` due to the motion over `[t0, t1]`, and the evidence depth.
    gap_t: f64,
    depth: f64,
    t0: f64,
    t1: f64,
    piece: Piece,
    /// Whether `ub` is already [`pair_bound`]'s.
    tight: bool,
}

impl PartialEq for Node {
    fn eq(&self, o: &Self) -> bool {
        self.ub == o.ub
    }
}
impl Eq for Node {}
impl PartialOrd for Node {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Node {
    fn cmp(&self, o: &Self) -> Ordering {
        self.ub.total_cmp(&o.ub)
    }
}

/// A node's bound and evidence.
struct Assessed {
    ub: f64,
    /// Share of the bound's gap due to the motion over the interval.
    gap_t: f64,
    depth: f64,
    point: Vec3,
    tm: f64,
}

/// Box of the part swept over `[t0, t1]`, grown by `grow`.
fn sweep_box(seg: &Segment, t0: f64, t1: f64, grow: f64) -> Aabb {
    let a = seg.tip(t0);
    let b = SweptConvex::new(seg.part, a, seg.axis, seg.tip(t1) - a).bbox();
    Aabb::new(b.min - Vec3::splat(grow), b.max + Vec3::splat(grow))
}

fn assess(seg: &Segment, pc: &Piece, t0: f64, t1: f64) -> Assessed {
    let pts: SmallVec<[Vec3; 16]> = pc
        .net
        .iter()
        .map(|h| Vec3::new(h.x, h.y, h.z) / h.w)
        .collect();
    let tm = 0.5 * (t0 + t1);
    let tip = seg.tip(tm);
    // Evidence: the corners on the part are surface points (A, B, C for a check triangle).
    let corners = pc.corners_on_part();
    let mut depth = f64::NEG_INFINITY;
    let mut point = pts[0];
    let mut n_corner = seg.axis;
    for &c in &corners {
        let sd = seg.part.signed_distance(tip, seg.axis, c);
        if -sd.distance > depth {
            depth = -sd.distance;
            point = c;
            n_corner = sd.normal;
        }
    }
    let centroid = pts.iter().copied().sum::<Vec3>() / pts.len() as f64;
    let n_centre = seg.part.signed_distance(tip, seg.axis, centroid).normal;
    let dt = 0.5 * (t1 - t0);
    let mut best = (f64::INFINITY, 0.0);
    for n in [n_centre, n_corner] {
        let lo = pts.iter().map(|p| n.dot(*p)).fold(f64::INFINITY, f64::min);
        let nd = n.dot(seg.delta);
        let gap_t = dt * nd.abs();
        let ub = seg.part.support(tip, seg.axis, n) + gap_t - lo;
        if ub < best.0 {
            best = (ub, gap_t);
        }
    }
    Assessed {
        ub: best.0,
        gap_t: best.1,
        depth,
        point,
        tm,
    }
}

/// Expansions after which a search also tries [`pair_bound`] on every node it would expand: a
/// search that has come this far is likely grinding through ties along a ridge, and the easy
/// searches (nearly all) never pay for the pair.
const PAIR_AFTER: u64 = 512;

/// Cosine of the angle between two normals of the part beyond which their pair of planes is
/// tried (30°: the ridges where two faces meet at an edge — a flat bottom's rim, 90°).
const PAIR_COS: f64 = 0.866;

/// The bound of a pair of planes over the node, when its corners are nearest to faces of the
/// part with normals more than 30° apart. A node across the ridge where two faces are equally
/// near (a flat bottom's rim, where a flat end mill sunk into a slope has a line of near-ties) is
/// bounded loosely by either plane alone, but the depth is at most the smaller of the two plane
/// gaps at every point, and the largest such minimum over the hull is reached at a control
/// point or where the two gaps cross on a segment between two.
fn pair_bound(seg: &Segment, pc: &Piece, t0: f64, t1: f64) -> Option<f64> {
    let tip = seg.tip(0.5 * (t0 + t1));
    let pts: SmallVec<[Vec3; 16]> = pc
        .net
        .iter()
        .map(|h| Vec3::new(h.x, h.y, h.z) / h.w)
        .collect();
    let centroid = pts.iter().copied().sum::<Vec3>() / pts.len() as f64;
    let n1 = seg.part.signed_distance(tip, seg.axis, centroid).normal;
    let n2 = pc
        .corners_on_part()
        .iter()
        .map(|&c| seg.part.signed_distance(tip, seg.axis, c).normal)
        .min_by(|a, b| a.dot(n1).total_cmp(&b.dot(n1)))?;
    if n2.dot(n1) >= PAIR_COS {
        return None;
    }
    let dt = 0.5 * (t1 - t0);
    let plane = |n: Vec3| seg.part.support(tip, seg.axis, n) + dt * n.dot(seg.delta).abs();
    let (h1, h2) = (plane(n1), plane(n2));
    let gaps: SmallVec<[(f64, f64); 16]> = pts
        .iter()
        .map(|p| (h1 - n1.dot(*p), h2 - n2.dot(*p)))
        .collect();
    let mut pair = f64::NEG_INFINITY;
    for (i, &(a1, a2)) in gaps.iter().enumerate() {
        pair = pair.max(a1.min(a2));
        let da = a1 - a2;
        for &(b1, b2) in &gaps[i + 1..] {
            let db = b1 - b2;
            if da * db < 0.0 {
                pair = pair.max(a1 + da / (da - db) * (b1 - a1));
            }
        }
    }
    Some(pair)
}

/// Scratch reused between searches (one per thread).
#[derive(Default)]
pub(crate) struct SearchScratch {
    heap: BinaryHeap<Node>,
    roots: Vec<usize>,
}

/// Runs the search of the module docs for one segment and query.
pub(crate) fn deepest(
    surface: &GougeSurface,
    seg: &Segment,
    q: &Query,
    scratch: &mut SearchScratch,
) -> Deepest {
    let mut out = Deepest {
        depth: f64::NEG_INFINITY,
        upper: f64::NEG_INFINITY,
        point: seg.tip(q.t0),
        t: q.t0,
        patch: 0,
        check: false,
        nodes: 0,
        certified: true,
    };
    // Pieces farther than the floor from the swept part cannot reach deeper than the floor.
    let grow = (-q.floor).max(0.0) + 1e-9;
    surface.candidates(&sweep_box(seg, q.t0, q.t1, grow), &mut scratch.roots);
    let heap = &mut scratch.heap;
    heap.clear();
    let travel = seg.delta.length();
    let push = |out: &mut Deepest, heap: &mut BinaryHeap<Node>, pc: Piece, t0: f64, t1: f64| {
        let a = assess(seg, &pc, t0, t1);
        if a.depth > out.depth {
            out.depth = a.depth;
            out.point = a.point;
            out.t = a.tm;
            out.patch = pc.patch;
            out.check = pc.check;
        }
        if a.ub > q.floor {
            heap.push(Node {
                ub: a.ub,
                gap_t: a.gap_t,
                depth: a.depth,
                t0,
                t1,
                piece: pc,
                tight: false,
            });
        }
    };
    for &i in &scratch.roots {
        let pc = &surface.pieces[i];
        if q.pieces.admits(pc) {
            push(&mut out, heap, pc.clone(), q.t0, q.t1);
        }
    }
    while let Some(mut node) = heap.pop() {
        let gap = q.accuracy.max(q.relative_accuracy * out.depth);
        let prune = (out.depth + gap).max(q.floor);
        if node.ub <= prune || out.depth > q.stop_above {
            out.upper = out.upper.max(node.ub).max(out.depth);
            heap.clear();
            return out;
        }
        if out.nodes > PAIR_AFTER && !node.tight {
            node.tight = true;
            if let Some(ub) = pair_bound(seg, &node.piece, node.t0, node.t1) {
                if ub <= prune {
                    // Pruned after all; its bound still counts towards the certificate.
                    out.upper = out.upper.max(ub);
                    continue;
                }
                if ub < node.ub {
                    // Back in line at its tighter bound.
                    node.ub = ub;
                    heap.push(node);
                    continue;
                }
            }
        }
        out.nodes += 1;
        if out.nodes > q.max_nodes {
            out.upper = node.ub;
            out.certified = false;
            heap.clear();
            return out;
        }
        // Split the motion when it holds most of the gap, else the piece.
        let span = node.t1 - node.t0;
        let split_t = span * travel > 1e-9 && node.gap_t >= 0.5 * (node.ub - node.depth).max(0.0);
        if split_t {
            let tm = 0.5 * (node.t0 + node.t1);
            push(&mut out, heap, node.piece.clone(), node.t0, tm);
            push(&mut out, heap, node.piece, tm, node.t1);
        } else {
            for child in node.piece.children().into_iter().filter(Piece::on_part) {
                push(&mut out, heap, child, node.t0, node.t1);
            }
        }
    }
    // Everything was pruned against the floor (or by the pair bound, recorded above).
    out.upper = out.upper.max(out.depth).max(q.floor);
    out
}
