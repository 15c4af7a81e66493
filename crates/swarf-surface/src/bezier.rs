//! Every patch as rational Bézier pieces in homogeneous form, for rigorous bounds: a piece lies
//! in the convex hull of its control points (weights are positive), and halving a piece by de
//! Casteljau gives the control nets of its halves, which converge to the surface.
//!
//! NURBS are cut at their knots by knot insertion (Boehm); the elementary surfaces are written
//! exactly as rational Bézier pieces (circular arcs of at most 90° as rational quadratics, the
//! sphere and torus as tensor products of two arcs), so the certified solver sees every patch
//! kind through the same representation.
//!
//! A trimmed patch ([`crate::Trim`]) keeps only the pieces that reach the part: each piece
//! knows its rectangle in the Bézier parameters of the piece it was cut from, and that root
//! piece's map to the patch's parameters (`Axis`: affine over a knot span, or the angle of a
//! rational quadratic arc, `θ = m + 2·atan(tan(h/2)·(2t − 1))`, both increasing, so rectangles map
//! to rectangles exactly); whether the trim boundary crosses it ([`OnPart`]); halves of a
//! crossing piece are classified again (dropped when off the part), and only corners on the part
//! count as surface points. Bounds computed from a crossing piece's whole control net stay
//! valid (they bound a superset).
//!
//! Check geometry (a closed triangle mesh: fixtures, neighbouring parts) enters the same way:
//! a triangle `ABC` is the degenerate bilinear piece with control net `A A / B C` (one edge
//! collapsed to the point `A`), `S(u, v) = (1 − u)·A + u·((1 − v)·B + v·C)`, whose control
//! points' convex hull is the triangle itself. Check triangles are subdivided into triangles of
//! the same form, so every node stays a triangle whose hull is exact: bisected through an edge
//! midpoint ([`Piece::bisect_triangle`], the certified search, which picks the edge) or cut at
//! all three edge midpoints into four ([`Piece::split_triangle`], the shank check). Such pieces
//! are flagged [`Piece::check`]: a point found on them is never the CC point's own surface, so
//! it always limits the size as interference.

use std::f64::consts::FRAC_PI_2;
use std::sync::Arc;

use glam::DVec4;
use smallvec::SmallVec;
use swarf_geom::math::{Quat, Vec3};
use swarf_geom::Aabb;
use swarf_io::TriMesh;

use crate::trim::{Coverage, Trim};
use crate::{CompoundSurface, NurbsSurface, ParametricSurface, Surface};

/// A rational Bézier patch of degrees `(p, q)` with homogeneous control points `(w·x, w·y,
/// w·z, w)`, row-major `i·(q+1) + j`.
#[derive(Clone, Debug, PartialEq)]
pub struct Piece {
    /// Index of the patch it belongs to (of the triangle, for check geometry).
    pub patch: usize,
    /// True for a triangle of the check geometry (not the machined surface).
    pub check: bool,
    /// Degree in u.
    pub p: usize,
    /// Degree in v.
    pub q: usize,
    /// Homogeneous control points `(w·x, w·y, w·z, w)`, `(p + 1)·(q + 1)` of them, row-major.
    pub net: Vec<DVec4>,
    /// How much of the piece is on the part.
    pub on: OnPart,
}

/// How much of a piece lies on the (trimmed) part.
#[derive(Clone, Debug, PartialEq)]
pub enum OnPart {
    /// All of it: untrimmed patches, check triangles, pieces inside the trim.
    Whole,
    /// The trim boundary crosses it: halves are classified again, corners tested. (Boxed: few
    /// pieces cross, and every piece is cloned and moved in the searches' heaps.)
    Partly(Box<Crossing>),
    /// None of it (a half of a crossing piece): callers drop it.
    Off,
}

impl OnPart {
    /// The state of the rectangle `local` (root Bézier parameters) of a piece of a trimmed
    /// patch: crossing rectangles smaller than the trim's resolution count as on the part (the
    /// boundary is honoured to that size).
    fn of(root: &Arc<TrimmedRoot>, uv: [f64; 4]) -> OnPart {
        let rect = root.rect(uv);
        match root.trim.coverage(rect) {
            Coverage::Inside => OnPart::Whole,
            Coverage::Outside => OnPart::Off,
            Coverage::Crossing => {
                if (rect[1] - rect[0]).max(rect[3] - rect[2]) < root.trim.resolution() {
                    OnPart::Whole
                } else {
                    OnPart::Partly(Box::new(Crossing {
                        root: root.clone(),
                        uv,
                    }))
                }
            }
        }
    }
}

/// A root piece's Bézier parameter mapped to its patch's parameter, one direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Axis {
    /// `a + t·(b − a)`: a knot span of a NURBS, a linear parameter of an elementary surface.
    Affine(f64, f64),
    /// The angle of the rational quadratic arc from `m − h` to `m + h` (weight `cos h` in the
    /// middle): `m + 2·atan(tan(h/2)·(2t − 1))`.
    Arc { m: f64, h: f64 },
}

impl Axis {
    fn at(self, t: f64) -> f64 {
        match self {
            Axis::Affine(a, b) => a + t * (b - a),
            Axis::Arc { m, h } => m + 2.0 * ((0.5 * h).tan() * (2.0 * t - 1.0)).atan(),
        }
    }

    /// The inverse of [`Axis::at`].
    fn local(self, x: f64) -> f64 {
        match self {
            Axis::Affine(a, b) => (x - a) / (b - a),
            Axis::Arc { m, h } => 0.5 * ((0.5 * (x - m)).tan() / (0.5 * h).tan() + 1.0),
        }
    }
}

/// A piece the trim boundary crosses: its root, and the rectangle `[t0, t1, s0, s1]` it covers in
/// the root's Bézier parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct Crossing {
    root: Arc<TrimmedRoot>,
    uv: [f64; 4],
}

/// A root piece of a trimmed patch: the patch's trim and the piece's parameter map.
#[derive(Debug, PartialEq)]
pub(crate) struct TrimmedRoot {
    trim: Arc<Trim>,
    u: Axis,
    v: Axis,
}

impl TrimmedRoot {
    /// The patch-parameter rectangle of a rectangle of root Bézier parameters.
    fn rect(&self, l: [f64; 4]) -> [f64; 4] {
        [
            self.u.at(l[0]),
            self.u.at(l[1]),
            self.v.at(l[2]),
            self.v.at(l[3]),
        ]
    }
}

/// A compound surface cut into rational Bézier pieces, prepared once and shared by all CC
/// points (the certified solver's input).
#[derive(Clone, Debug, PartialEq)]
pub struct PreparedSurface {
    /// The pieces: every patch's in patch order (those off a trimmed part dropped), then the
    /// check mesh's triangles. The searches walk them; [`PreparedSurface::piece_count`] counts
    /// them.
    pub pieces: Vec<Piece>,
    pub(crate) bbox: Option<Aabb>,
}

impl PreparedSurface {
    /// Cut every patch of `surface` into rational Bézier pieces.
    pub fn new(surface: &CompoundSurface) -> Self {
        let mut pieces = Vec::new();
        let mut maps = Vec::new();
        for (k, patch) in surface.patches.iter().enumerate() {
            let first = pieces.len();
            maps.clear();
            match &patch.surface {
                Surface::Nurbs(s) => nurbs_pieces(k, s, &mut pieces, &mut maps),
                other => analytic_pieces(k, other, &mut pieces, &mut maps),
            }
            if let Some(trim) = &patch.trim {
                let trim = Arc::new(trim.clone());
                let mut kept = first;
                for (i, &(u, v)) in (first..pieces.len()).zip(&maps) {
                    let root = Arc::new(TrimmedRoot {
                        trim: trim.clone(),
                        u,
                        v,
                    });
                    pieces[i].on = OnPart::of(&root, [0.0, 1.0, 0.0, 1.0]);
                    if pieces[i].on != OnPart::Off {
                        pieces.swap(kept, i);
                        kept += 1;
                    }
                }
                pieces.truncate(kept);
            }
        }
        Self {
            pieces,
            bbox: surface.bounding_box(),
        }
    }

    /// This surface with a closed triangle mesh added as check geometry (fixtures, neighbouring
    /// parts): every point of it limits the allowable size like a point of the surface, and
    /// always as interference. `name` (the file, say) is only used in the error.
    ///
    /// # Errors
    /// [`CheckMeshError::Open`] when the mesh has open or non-manifold edges: a mesh that is
    /// not closed does not bound a solid, so it is refused rather than half-checked;
    /// [`CheckMeshError::Empty`] when it has no triangles.
    pub fn with_check_mesh(mut self, name: &str, mesh: &TriMesh) -> Result<Self, CheckMeshError> {
        if mesh.is_empty() {
            return Err(CheckMeshError::Empty {
                name: name.to_string(),
            });
        }
        let report = mesh.edge_report();
        if report.boundary_count() > 0 {
            return Err(CheckMeshError::Open {
                name: name.to_string(),
                open: report.open,
                non_manifold: report.non_manifold,
            });
        }
        for t in 0..mesh.len() {
            let [a, b, c] = mesh.corners(t);
            self.pieces.push(triangle_piece(t, a, b, c));
        }
        self.bbox = match (self.bbox, mesh.aabb()) {
            (Some(s), Some(m)) => Aabb::from_points([s.min, s.max, m.min, m.max]),
            (s, m) => s.or(m),
        };
        Ok(self)
    }

    /// Number of triangles of check geometry among the pieces.
    pub fn check_triangle_count(&self) -> usize {
        self.pieces.iter().filter(|pc| pc.check).count()
    }

    /// Number of Bézier pieces (check triangles included).
    pub fn piece_count(&self) -> usize {
        self.pieces.len()
    }

    /// A box around the whole surface.
    pub fn bounding_box(&self) -> Option<Aabb> {
        self.bbox
    }

    /// The prepared surface moved by the rotation `q` (homogeneous control points rotated,
    /// weights kept; the box recomputed from the rotated control points, which enclose the
    /// surface).
    #[must_use]
    pub fn rotated(&self, q: Quat) -> PreparedSurface {
        let mut pieces = self.pieces.clone();
        for pc in &mut pieces {
            for h in &mut pc.net {
                let v = q * Vec3::new(h.x, h.y, h.z);
                h.x = v.x;
                h.y = v.y;
                h.z = v.z;
            }
        }
        let bbox = Aabb::from_points(
            pieces
                .iter()
                .flat_map(|pc| pc.net.iter().map(|h| Vec3::new(h.x, h.y, h.z) / h.w)),
        );
        PreparedSurface { pieces, bbox }
    }
}

/// Why check geometry is refused.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum CheckMeshError {
    /// The mesh has no triangles (an empty `solid`, a binary file with a count of 0).
    #[error("check mesh {name} is empty: it has no triangles")]
    Empty {
        /// The mesh's name (its file).
        name: String,
    },
    /// The mesh is not a closed 2-manifold.
    #[error(
        "check mesh {name} is not closed: {open} open edge(s), {non_manifold} non-manifold edge(s)"
    )]
    Open {
        /// The mesh's name (its file).
        name: String,
        /// Edges used by one triangle only.
        open: usize,
        /// Edges used by three or more triangles.
        non_manifold: usize,
    },
}

/// The triangle `ABC` as a degenerate bilinear piece (net `A A / B C`, weights 1): its control
/// points' hull is the triangle (see the module docs).
fn triangle_piece(index: usize, a: Vec3, b: Vec3, c: Vec3) -> Piece {
    let h = |p: Vec3| DVec4::new(p.x, p.y, p.z, 1.0);
    Piece {
        patch: index,
        check: true,
        p: 1,
        q: 1,
        net: vec![h(a), h(a), h(b), h(c)],
        on: OnPart::Whole,
    }
}

impl Piece {
    /// Euclidean control point `(i, j)`.
    #[inline]
    pub fn point(&self, i: usize, j: usize) -> Vec3 {
        let h = self.net[i * (self.q + 1) + j];
        Vec3::new(h.x, h.y, h.z) / h.w
    }

    /// True unless the piece is a half of a crossing piece that lies off the part.
    #[inline]
    pub fn on_part(&self) -> bool {
        self.on != OnPart::Off
    }

    /// True when corner `(i, j)` of the net (`i ∈ {0, p}`, `j ∈ {0, q}`), a surface point, is on
    /// the part.
    pub fn corner_on_part(&self, i: usize, j: usize) -> bool {
        match &self.on {
            OnPart::Whole => true,
            OnPart::Off => false,
            OnPart::Partly(c) => c.root.trim.contains(
                c.root.u.at(if i == 0 { c.uv[0] } else { c.uv[1] }),
                c.root.v.at(if j == 0 { c.uv[2] } else { c.uv[3] }),
            ),
        }
    }

    /// The corners of the net that are surface points on the part (a check triangle's `A, B,
    /// C`; a patch piece's four corners, those on the trimmed part).
    #[inline]
    pub fn corners_on_part(&self) -> SmallVec<[Vec3; 4]> {
        if self.check {
            return SmallVec::from_slice(&self.triangle());
        }
        let (p, q) = (self.p, self.q);
        let corners = [(0, 0), (p, 0), (0, q), (p, q)];
        if self.on == OnPart::Whole {
            // The hot case (every piece of an untrimmed patch): no filter, no iterator.
            return SmallVec::from_buf(corners.map(|(i, j)| self.point(i, j)));
        }
        corners
            .into_iter()
            .filter(|&(i, j)| self.corner_on_part(i, j))
            .map(|(i, j)| self.point(i, j))
            .collect()
    }

    /// Euclidean control points.
    #[inline]
    pub fn euclidean(&self, out: &mut Vec<Vec3>) {
        out.clear();
        out.extend(self.net.iter().map(|h| Vec3::new(h.x, h.y, h.z) / h.w));
    }

    /// A check triangle's four children, cut at the edge midpoints (see the module docs), each
    /// again `A A / B C`, and the three new points (the midpoints).
    ///
    /// # Panics
    /// In debug builds, when the piece is not a check triangle.
    pub fn split_triangle(&self) -> ([Piece; 4], [Vec3; 3]) {
        debug_assert!(self.check && self.p == 1 && self.q == 1);
        let (a, b, c) = (self.point(0, 0), self.point(1, 0), self.point(1, 1));
        let (ab, bc, ca) = ((a + b) / 2.0, (b + c) / 2.0, (c + a) / 2.0);
        let t = |x, y, z| triangle_piece(self.patch, x, y, z);
        (
            [t(a, ab, ca), t(ab, b, bc), t(ca, bc, c), t(ab, bc, ca)],
            [ab, bc, ca],
        )
    }

    /// The corners `A, B, C` of a check triangle.
    #[inline]
    pub fn triangle(&self) -> [Vec3; 3] {
        [self.point(0, 0), self.point(1, 0), self.point(1, 1)]
    }

    /// A check triangle's two children, cut through the midpoint of edge `edge` (`0`: `AB`,
    /// `1`: `BC`, `2`: `CA`) and the opposite corner, and that midpoint (the new point).
    pub fn bisect_triangle(&self, edge: usize) -> ([Piece; 2], Vec3) {
        debug_assert!(self.check && edge < 3);
        let t = self.triangle();
        let (x, y, z) = (t[edge], t[(edge + 1) % 3], t[(edge + 2) % 3]);
        let m = (x + y) / 2.0;
        (
            [
                triangle_piece(self.patch, x, m, z),
                triangle_piece(self.patch, m, y, z),
            ],
            m,
        )
    }

    /// Where to cut a piece the trim boundary crosses along a boundary edge that runs along a
    /// parameter line through it: `(dir, t)` for [`Piece::split_at`]. Halving such a piece
    /// would leave the boundary inside one half at every level; cutting along it puts each
    /// side in a child of its own, on or off the part.
    pub fn trim_cut(&self) -> Option<(usize, f64)> {
        let OnPart::Partly(c) = &self.on else {
            return None;
        };
        let root = &c.root;
        let (dir, at) = root.trim.aligned_cut(root.rect(c.uv))?;
        let at = if dir == 0 { root.u } else { root.v }.local(at);
        let (lo, hi) = (c.uv[2 * dir], c.uv[2 * dir + 1]);
        Some((dir, ((at - lo) / (hi - lo)).clamp(0.0, 1.0)))
    }

    /// Children covering the piece for searches that do not choose a direction: cut along the
    /// trim boundary where [`Piece::trim_cut`] finds a line to cut along, otherwise
    /// [`Piece::quarters`].
    pub fn children(&self) -> SmallVec<[Piece; 4]> {
        match self.trim_cut() {
            Some((dir, t)) => {
                let (a, b) = self.split_at(dir, t);
                smallvec::smallvec![a, b]
            }
            None => SmallVec::from_buf(self.quarters()),
        }
    }

    /// Four children covering the piece: a check triangle's midpoint triangles, otherwise the
    /// halves in u each halved in v.
    pub fn quarters(&self) -> [Piece; 4] {
        if self.check {
            return self.split_triangle().0;
        }
        let (a, b) = self.split(0);
        let (a0, a1) = a.split(1);
        let (b0, b1) = b.split(1);
        [a0, a1, b0, b1]
    }

    /// The halves in u (`dir = 0`) or v (`dir = 1`) at the parameter midpoint, each classified
    /// against the trim when the piece crosses it (a half may be [`OnPart::Off`]).
    pub fn split(&self, dir: usize) -> (Piece, Piece) {
        self.split_at(dir, 0.5)
    }

    /// The parts before and after the local parameter `t ∈ (0, 1)` in u (`dir = 0`) or v
    /// (`dir = 1`) (de Casteljau), classified like [`Piece::split`]'s halves.
    pub fn split_at(&self, dir: usize, t: f64) -> (Piece, Piece) {
        let (p, q) = (self.p, self.q);
        let mut a = self.clone();
        let mut b = self.clone();
        let (len, count) = if dir == 0 {
            (p + 1, q + 1)
        } else {
            (q + 1, p + 1)
        };
        let idx = |line: usize, k: usize| {
            if dir == 0 {
                k * (q + 1) + line
            } else {
                line * (q + 1) + k
            }
        };
        let mut tmp = [DVec4::ZERO; 16];
        let mut buf: Vec<DVec4> = Vec::new();
        let work: &mut [DVec4] = if len <= 16 {
            &mut tmp[..len]
        } else {
            buf.resize(len, DVec4::ZERO);
            &mut buf[..]
        };
        for line in 0..count {
            for (k, w) in work.iter_mut().enumerate() {
                *w = self.net[idx(line, k)];
            }
            a.net[idx(line, 0)] = work[0];
            b.net[idx(line, len - 1)] = work[len - 1];
            for level in 1..len {
                if t == 0.5 {
                    // The common halving: one multiply per coordinate, and exact.
                    for k in 0..len - level {
                        work[k] = 0.5 * (work[k] + work[k + 1]);
                    }
                } else {
                    for k in 0..len - level {
                        work[k] = (1.0 - t) * work[k] + t * work[k + 1];
                    }
                }
                a.net[idx(line, level)] = work[0];
                b.net[idx(line, len - 1 - level)] = work[len - 1 - level];
            }
        }
        let (lo, hi) = (2 * dir, 2 * dir + 1);
        if let OnPart::Partly(c) = &self.on {
            let mid = c.uv[lo] + t * (c.uv[hi] - c.uv[lo]);
            let (mut ua, mut ub) = (c.uv, c.uv);
            ua[hi] = mid;
            ub[lo] = mid;
            a.on = OnPart::of(&c.root, ua);
            b.on = OnPart::of(&c.root, ub);
        }
        (a, b)
    }
}

/// Boehm insertion of every distinct knot in the domain until it has multiplicity `p`, then the
/// Bézier segments (each `p + 1` homogeneous points) of a curve, with their knot spans.
fn curve_segments(p: usize, knots: &[f64], pts: &[DVec4]) -> Vec<(Vec<DVec4>, [f64; 2])> {
    let mut u = knots.to_vec();
    let mut cp = pts.to_vec();
    let n = pts.len();
    let (a, b) = (knots[p], knots[n]);
    let mut distinct: Vec<f64> = knots[p..=n].to_vec();
    distinct.dedup();
    for &t in &distinct {
        loop {
            let mult = u.iter().filter(|&&k| k == t).count();
            if mult >= p {
                break;
            }
            // Span k: u[k] ≤ t < u[k+1] (for t = b, the last non-empty span).
            let m = cp.len();
            let k = if t >= u[m] {
                m - 1
            } else {
                (p..m).rev().find(|&k| u[k] <= t).unwrap_or(p)
            };
            let mut q = Vec::with_capacity(m + 1);
            for i in 0..=m {
                if i + p <= k {
                    q.push(cp[i]);
                } else if i > k {
                    q.push(cp[i - 1]);
                } else {
                    let den = u[i + p] - u[i];
                    let al = if den > 0.0 { (t - u[i]) / den } else { 0.0 };
                    q.push(al * cp[i] + (1.0 - al) * cp[i - 1]);
                }
            }
            u.insert(k + 1, t);
            cp = q;
        }
    }
    // Segments: for each span [u[k], u[k+1]) with a ≤ u[k] < b, points k−p..=k.
    let mut out = Vec::new();
    for k in p..cp.len() {
        if u[k] < u[k + 1] && u[k] >= a && u[k + 1] <= b {
            out.push((cp[k - p..=k].to_vec(), [u[k], u[k + 1]]));
        }
    }
    out
}

fn nurbs_pieces(
    patch: usize,
    s: &NurbsSurface,
    out: &mut Vec<Piece>,
    maps: &mut Vec<(Axis, Axis)>,
) {
    let (p, q) = (s.degree_u(), s.degree_v());
    let (nu, nv) = s.net_size();
    let h = |i: usize, j: usize| {
        let w = s.weight(i, j);
        let c = s.control_point(i, j);
        DVec4::new(w * c.x, w * c.y, w * c.z, w)
    };
    // Along u for every column j.
    let cols: Vec<Vec<(Vec<DVec4>, [f64; 2])>> = (0..nv)
        .map(|j| {
            let col: Vec<DVec4> = (0..nu).map(|i| h(i, j)).collect();
            curve_segments(p, s.knots_u(), &col)
        })
        .collect();
    let nseg_u = cols.first().map_or(0, Vec::len);
    for a in 0..nseg_u {
        // Rows i = 0..=p of u-segment a, decomposed along v.
        let rows: Vec<Vec<(Vec<DVec4>, [f64; 2])>> = (0..=p)
            .map(|i| {
                let row: Vec<DVec4> = cols.iter().map(|col| col[a].0[i]).collect();
                curve_segments(q, s.knots_v(), &row)
            })
            .collect();
        for bseg in 0..rows[0].len() {
            let mut net = Vec::with_capacity((p + 1) * (q + 1));
            for row in &rows {
                net.extend_from_slice(&row[bseg].0);
            }
            let (su, sv) = (cols[0][a].1, rows[0][bseg].1);
            out.push(Piece {
                patch,
                check: false,
                p,
                q,
                net,
                on: OnPart::Whole,
            });
            maps.push((Axis::Affine(su[0], su[1]), Axis::Affine(sv[0], sv[1])));
        }
    }
}

/// A control point `(x, y, w)` of a rational quadratic arc of the unit circle.
type ArcPoint = (f64, f64, f64);

/// Rational quadratic arcs of the unit circle over `[a, b]`, each ≤ 90°: `(x, y, w)` triples
/// and the map of each arc's parameter to the angle.
fn arcs(a: f64, b: f64) -> Vec<([ArcPoint; 3], Axis)> {
    let n = ((b - a) / FRAC_PI_2 - 1e-12).ceil().max(1.0) as usize;
    let step = (b - a) / n as f64;
    (0..n)
        .map(|k| {
            let (t0, t1) = (a + k as f64 * step, a + (k + 1) as f64 * step);
            let h = 0.5 * (t1 - t0);
            let m = 0.5 * (t0 + t1);
            (
                [
                    (t0.cos(), t0.sin(), 1.0),
                    (m.cos() / h.cos(), m.sin() / h.cos(), h.cos()),
                    (t1.cos(), t1.sin(), 1.0),
                ],
                Axis::Arc { m, h },
            )
        })
        .collect()
}

/// The tensor product of two point lists (arcs or degree-1 segments) through `f`, and its
/// parameter maps.
fn push_tensor(
    patch: usize,
    (us, mu): (&[(f64, f64, f64)], Axis),
    (vs, mv): (&[(f64, f64, f64)], Axis),
    f: impl Fn((f64, f64), (f64, f64)) -> Vec3,
    (out, maps): (&mut Vec<Piece>, &mut Vec<(Axis, Axis)>),
) {
    let mut net = Vec::with_capacity(us.len() * vs.len());
    for &(ux, uy, uw) in us {
        for &(vx, vy, vw) in vs {
            let w = uw * vw;
            let c = f((ux, uy), (vx, vy));
            net.push(DVec4::new(w * c.x, w * c.y, w * c.z, w));
        }
    }
    out.push(Piece {
        patch,
        check: false,
        p: us.len() - 1,
        q: vs.len() - 1,
        net,
        on: OnPart::Whole,
    });
    maps.push((mu, mv));
}

fn analytic_pieces(patch: usize, s: &Surface, out: &mut Vec<Piece>, maps: &mut Vec<(Axis, Axis)>) {
    let d = s.domain();
    let lu = [(d.u[0], 0.0, 1.0), (d.u[1], 0.0, 1.0)];
    let lv = [(d.v[0], 0.0, 1.0), (d.v[1], 0.0, 1.0)];
    let line_u = (&lu[..], Axis::Affine(d.u[0], d.u[1]));
    let line_v = (&lv[..], Axis::Affine(d.v[0], d.v[1]));
    let sink = (out, maps);
    match s {
        Surface::Plane(pl) => {
            let f = pl.frame;
            push_tensor(
                patch,
                line_u,
                line_v,
                |(u, _), (v, _)| f.origin + u * f.x + v * f.y,
                sink,
            );
        }
        Surface::Cylinder(c) => {
            let (f, r) = (c.frame, c.radius);
            for (arc, m) in arcs(d.u[0], d.u[1]) {
                push_tensor(
                    patch,
                    (&arc, m),
                    line_v,
                    |(x, y), (v, _)| f.origin + r * (x * f.x + y * f.y) + v * f.z,
                    (&mut *sink.0, &mut *sink.1),
                );
            }
        }
        Surface::Cone(c) => {
            let (f, r, ta) = (c.frame, c.radius, c.semi_angle.tan());
            for (arc, m) in arcs(d.u[0], d.u[1]) {
                push_tensor(
                    patch,
                    (&arc, m),
                    line_v,
                    // Bilinear in (arc point, v): (r + v tan α)(x, y) is linear in each.
                    |(x, y), (v, _)| f.origin + (r + v * ta) * (x * f.x + y * f.y) + v * f.z,
                    (&mut *sink.0, &mut *sink.1),
                );
            }
        }
        Surface::Sphere(sp) => {
            let (f, r) = (sp.frame, sp.radius);
            for (au, mu) in arcs(d.u[0], d.u[1]) {
                for (av, mv) in arcs(d.v[0], d.v[1]) {
                    push_tensor(
                        patch,
                        (&au, mu),
                        (&av, mv),
                        |(x, y), (cv, sv)| f.origin + r * cv * (x * f.x + y * f.y) + r * sv * f.z,
                        (&mut *sink.0, &mut *sink.1),
                    );
                }
            }
        }
        Surface::Torus(t) => {
            let (f, big, r) = (t.frame, t.major, t.minor);
            for (au, mu) in arcs(d.u[0], d.u[1]) {
                for (av, mv) in arcs(d.v[0], d.v[1]) {
                    push_tensor(
                        patch,
                        (&au, mu),
                        (&av, mv),
                        |(x, y), (cv, sv)| {
                            f.origin + (big + r * cv) * (x * f.x + y * f.y) + r * sv * f.z
                        },
                        (&mut *sink.0, &mut *sink.1),
                    );
                }
            }
        }
        Surface::Nurbs(_) => unreachable!("NURBS are cut by nurbs_pieces"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Patch, SphericalSurface};
    use swarf_geom::Frame;

    /// Evaluate a rational Bézier piece by de Casteljau at (s, t).
    fn eval(pc: &Piece, s: f64, t: f64) -> Vec3 {
        let mut rows = Vec::new();
        for i in 0..=pc.p {
            let mut w: Vec<DVec4> = pc.net[i * (pc.q + 1)..(i + 1) * (pc.q + 1)].to_vec();
            for l in 1..w.len() {
                for k in 0..w.len() - l {
                    w[k] = (1.0 - t) * w[k] + t * w[k + 1];
                }
            }
            rows.push(w[0]);
        }
        for l in 1..rows.len() {
            for k in 0..rows.len() - l {
                rows[k] = (1.0 - s) * rows[k] + s * rows[k + 1];
            }
        }
        Vec3::new(rows[0].x, rows[0].y, rows[0].z) / rows[0].w
    }

    #[test]
    fn nurbs_pieces_reproduce_the_surface() {
        let knots_u = vec![0.0, 0.0, 0.0, 0.0, 0.3, 0.7, 0.7, 1.0, 1.0, 1.0, 1.0];
        let knots_v = vec![0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0];
        let mut k = 7u64;
        let mut r = || {
            k = k
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (k >> 11) as f64 / (1u64 << 53) as f64
        };
        let pts: Vec<Vec<Vec3>> = (0..7)
            .map(|i| {
                (0..4)
                    .map(|j| Vec3::new(i as f64, j as f64, 3.0 * r()))
                    .collect()
            })
            .collect();
        let w: Vec<Vec<f64>> = (0..7)
            .map(|_| (0..4).map(|_| 0.5 + r()).collect())
            .collect();
        let s = NurbsSurface::new(3, 2, knots_u, knots_v, &pts, Some(&w)).unwrap();
        let mut out = Vec::new();
        let mut maps = Vec::new();
        nurbs_pieces(0, &s, &mut out, &mut maps);
        assert_eq!(out.len(), 3 * 2);
        let us = [0.0, 0.3, 0.7, 1.0];
        let vs = [0.0, 0.5, 1.0];
        for (a, pc) in out.iter().enumerate() {
            let (iu, iv) = (a / 2, a % 2);
            assert_eq!(
                maps[a],
                (
                    Axis::Affine(us[iu], us[iu + 1]),
                    Axis::Affine(vs[iv], vs[iv + 1])
                )
            );
            for &(x, y) in &[(0.0, 0.0), (0.25, 0.6), (1.0, 1.0), (0.5, 0.1)] {
                let u = us[iu] + x * (us[iu + 1] - us[iu]);
                let v = vs[iv] + y * (vs[iv + 1] - vs[iv]);
                assert!(
                    (eval(pc, x, y) - s.point(u, v)).length() < 1e-12,
                    "piece {a}"
                );
            }
        }
    }

    #[test]
    fn sphere_pieces_lie_on_the_sphere_and_split_preserves_points() {
        let s = SphericalSurface::new(Frame::WORLD, 5.0, SphericalSurface::FULL).unwrap();
        let cs = CompoundSurface::new(vec![Patch::new(Surface::Sphere(s))]);
        let prep = PreparedSurface::new(&cs);
        assert_eq!(prep.piece_count(), 4 * 2);
        for pc in &prep.pieces {
            for &(a, b) in &[(0.0, 0.0), (0.3, 0.7), (1.0, 0.5), (0.5, 0.5)] {
                assert!((eval(pc, a, b).length() - 5.0).abs() < 1e-12);
            }
            let (l, r) = pc.split(0);
            assert!((eval(&l, 1.0, 0.3) - eval(pc, 0.5, 0.3)).length() < 1e-12);
            assert!((eval(&r, 0.5, 0.3) - eval(pc, 0.75, 0.3)).length() < 1e-12);
            let (l, _) = pc.split(1);
            assert!((eval(&l, 0.2, 0.5) - eval(pc, 0.2, 0.25)).length() < 1e-12);
        }
    }

    #[test]
    fn arc_maps_give_the_angle_of_every_bezier_parameter() {
        // A torus patch over uneven angle ranges: arcs of several sizes in both directions.
        let dom = crate::ParamBox {
            u: [0.3, 4.0],
            v: [-1.0, 2.5],
        };
        let t = crate::ToroidalSurface::new(Frame::WORLD, 7.0, 2.0, dom).unwrap();
        let s = Surface::Torus(t);
        let (mut out, mut maps) = (Vec::new(), Vec::new());
        analytic_pieces(0, &s, &mut out, &mut maps);
        assert_eq!(out.len(), maps.len());
        assert!(out.len() >= 6);
        for (pc, &(mu, mv)) in out.iter().zip(&maps) {
            for &(a, b) in &[
                (0.0, 0.0),
                (0.13, 0.77),
                (0.5, 0.5),
                (1.0, 0.31),
                (0.9, 1.0),
            ] {
                let want = s.point(mu.at(a), mv.at(b));
                assert!((eval(pc, a, b) - want).length() < 1e-12, "{a} {b}");
                assert!((mu.local(mu.at(a)) - a).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn a_check_triangle_is_its_own_hull_and_splits_into_four_triangles() {
        let (a, b, c) = (
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(4.0, -1.0, 0.5),
            Vec3::new(-2.0, 0.0, 5.0),
        );
        let pc = triangle_piece(7, a, b, c);
        // S(u, v) = (1 − u)·A + u·((1 − v)·B + v·C): the triangle.
        for &(u, v) in &[(0.0, 0.3), (1.0, 0.0), (1.0, 1.0), (0.4, 0.7)] {
            let want = (1.0 - u) * a + u * ((1.0 - v) * b + v * c);
            assert!((eval(&pc, u, v) - want).length() < 1e-12);
        }
        let area = |t: &Piece| {
            let (x, y, z) = (t.point(0, 0), t.point(1, 0), t.point(1, 1));
            0.5 * (y - x).cross(z - x).length()
        };
        let (kids, mids) = pc.split_triangle();
        assert_eq!(mids, [(a + b) / 2.0, (b + c) / 2.0, (c + a) / 2.0]);
        let total: f64 = kids.iter().map(area).sum();
        assert!((total - area(&pc)).abs() < 1e-12);
        for k in &kids {
            assert!(k.check && k.patch == 7 && k.point(0, 0) == k.point(0, 1));
            assert!((area(k) - area(&pc) / 4.0).abs() < 1e-12);
        }
        assert_eq!(pc.quarters(), kids);
    }
}
