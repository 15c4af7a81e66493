//! The swept envelope of moves and programs as a closed mesh.
//!
//! # Method
//! The swept volume of the whole tool (cutting part, shank, holder) over the selected feed
//! moves is sampled exactly along the lines of a cubic lattice in three directions (X, Y, Z),
//! then contoured: an [`EnvelopeGrid`] starts **empty** over the swept bounding box and each
//! line accumulates the **union** of its exact intervals inside the sweeps of fixed-axis
//! straight (sub-)moves — the closed-form grazing-curve kernels of `swarf_sweep::swept` that the
//! stock also cuts with. Arcs and helices become chords through exact arc points
//! (`swarf_sweep::arc_chords`), and 5-axis moves constant-axis sub-moves with a proven Hausdorff
//! bound (`swarf_sweep::five_axis::subdivide`), both within the chordal tolerance. Dual
//! contouring (`swarf_io`) turns the lines' Hermite data into a closed, outward-oriented mesh:
//! ingress, envelope and egress surfaces alike, and self-intersecting envelopes are resolved by
//! the union itself (the fold test, `swarf_sweep::fold`, reports where they occur).
//!
//! # Accuracy
//! Interval ends are exact to floating point for each fixed-axis piece; arcs and 5-axis moves
//! are within the chordal tolerance; the mesh vertices are within about one lattice spacing of
//! the true surface (sharp edges are kept by the contouring's QEF) and the volume converges as
//! the spacing falls. Both parameters are reported.

use std::collections::BTreeMap;
use std::ops::Range;

use rayon::prelude::*;
use serde::Serialize;
use swarf_geom::math::Vec3;
use swarf_geom::Aabb;
use swarf_io::{dual_contour, ContourOptions, HermiteGrid, Lattice, Span, TriMesh};
use swarf_path::{MoveKind, Program};
use swarf_sweep::five_axis::{subdivide, Reach};
use swarf_sweep::{
    arc_chords, fold_check, ConvexProfile, SelfIntersection, SweepShape, SweptConvex, ToolShape,
};
use swarf_tool::Cutter;

use crate::error::EnvelopeError;
use crate::tolerance::{DEFAULT_CHORDAL_TOLERANCE_MM, DEFAULT_RESOLUTION_MM, MAX_LATTICE_POINTS};

/// Parameters of [`envelope`]; defaults from [`crate::tolerance`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvelopeOptions {
    /// Lattice spacing, mm ([`DEFAULT_RESOLUTION_MM`]).
    pub resolution: f64,
    /// Chordal tolerance of arcs and 5-axis sub-moves, mm ([`DEFAULT_CHORDAL_TOLERANCE_MM`]).
    pub tolerance: f64,
    /// Run the fold test on arcs and moves whose axis turns (`swarf_sweep::fold`).
    pub check_folds: bool,
    /// Contouring parameters.
    pub contour: ContourOptions,
}

impl Default for EnvelopeOptions {
    fn default() -> Self {
        Self {
            resolution: DEFAULT_RESOLUTION_MM,
            tolerance: DEFAULT_CHORDAL_TOLERANCE_MM,
            check_folds: true,
            contour: ContourOptions::default(),
        }
    }
}

impl EnvelopeOptions {
    /// With lattice spacing `h` mm.
    pub fn with_resolution(mut self, h: f64) -> Self {
        self.resolution = h;
        self
    }

    /// With chordal tolerance `tol` mm.
    pub fn with_tolerance(mut self, tol: f64) -> Self {
        self.tolerance = tol;
        self
    }

    /// With or without the fold test.
    pub fn with_fold_check(mut self, on: bool) -> Self {
        self.check_folds = on;
        self
    }
}

/// A straight piece of motion with a fixed tool axis: the unit the exact kernels sweep.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FixedAxisPiece {
    /// Tip at the start, mm.
    pub tip0: Vec3,
    /// Tip at the end, mm.
    pub tip1: Vec3,
    /// Unit tool axis.
    pub axis: Vec3,
}

/// The lines of a cubic lattice holding the union of swept intervals (Hermite data for
/// [`swarf_io::dual_contour`]).
#[derive(Clone, Debug)]
pub struct EnvelopeGrid {
    lattice: Lattice,
    /// Per family `k`, lines indexed `v·n_u + u` (u along `(k+1)%3`, v along `(k+2)%3`).
    lines: [Vec<Vec<Span>>; 3],
}

impl EnvelopeGrid {
    /// An empty grid of spacing `h` covering `bounds` with a margin of two spacings.
    ///
    /// # Errors
    /// [`EnvelopeError::BadParameter`] for a spacing that is not positive and finite,
    /// [`EnvelopeError::TooFine`] beyond [`MAX_LATTICE_POINTS`].
    pub fn new(bounds: Aabb, h: f64) -> Result<Self, EnvelopeError> {
        if !(h > 0.0 && h.is_finite()) {
            return Err(EnvelopeError::BadParameter {
                name: "resolution",
                value: h,
            });
        }
        let box_ = bounds.inflated(2.0 * h);
        // Counted in f64 before the lattice is made or anything allocated: no count can wrap,
        // and a non-finite box fails the comparison.
        let size = box_.size();
        let points: f64 = [size.x, size.y, size.z]
            .iter()
            .map(|s| (s / h).ceil().max(1.0))
            .product();
        if !points.is_finite() || points > MAX_LATTICE_POINTS as f64 {
            return Err(EnvelopeError::TooFine {
                points,
                max: MAX_LATTICE_POINTS,
                h,
            });
        }
        let lattice = Lattice::covering(box_, h);
        let n = lattice.n;
        let lines = [0, 1, 2].map(|k| vec![Vec::new(); n[(k + 1) % 3] * n[(k + 2) % 3]]);
        Ok(Self { lattice, lines })
    }

    /// The lattice.
    pub fn lattice(&self) -> &Lattice {
        &self.lattice
    }

    /// Adds (unites) the swept volumes `sweeps` to every line. Lines are filled in parallel,
    /// row by row, each keeping its spans merged. A line skips the exact query of a sweep when
    /// a cheap outer bound of that sweep along it ([`SweepBound`]) is already covered — inside
    /// the union, where the many overlapping sub-moves of a 5-axis move put most lines.
    pub fn add(&mut self, sweeps: &[SweptConvex<'_>]) {
        self.add_bounded(sweeps, &vec![None; sweeps.len()]);
    }

    /// [`EnvelopeGrid::add`] with an optional outer bound per sweep.
    pub fn add_bounded(&mut self, sweeps: &[SweptConvex<'_>], bounds: &[Option<SweepBound>]) {
        let lat = self.lattice;
        let boxes: Vec<Aabb> = sweeps.iter().map(SweptConvex::bbox).collect();
        for (k, fam) in self.lines.iter_mut().enumerate() {
            let (ua, va) = ((k + 1) % 3, (k + 2) % 3);
            let nu = lat.n[ua];
            fam.par_chunks_mut(nu).enumerate().for_each(|(v, row)| {
                let cv = lat.coord(va, v as isize);
                for ((sw, b), bound) in sweeps.iter().zip(&boxes).zip(bounds) {
                    if cv < b.min[va] || cv > b.max[va] {
                        continue;
                    }
                    let Some((u0, u1)) = index_range(&lat, ua, b.min[ua], b.max[ua]) else {
                        continue;
                    };
                    let mut batch = None;
                    for (u, line) in row.iter_mut().enumerate().take(u1 + 1).skip(u0) {
                        let mut o = Vec3::ZERO;
                        o[ua] = lat.coord(ua, u as isize);
                        o[va] = cv;
                        if let Some(bd) = bound {
                            match bd.range(o, k) {
                                None => continue,
                                Some((lo, hi)) if covered(line, lo, hi) => continue,
                                Some(_) => {}
                            }
                        }
                        let batch = batch.get_or_insert_with(|| sw.lines(Vec3::AXES[k]));
                        if let Some((lo, hi)) = batch.interval(o) {
                            insert(
                                line,
                                Span {
                                    enter: lo,
                                    exit: hi,
                                },
                            );
                        }
                    }
                }
            });
        }
    }

    /// The intervals of line `(u, v)` of family `k` (sorted, disjoint).
    pub fn line(&self, k: usize, u: usize, v: usize) -> &[Span] {
        &self.lines[k][v * self.lattice.n[(k + 1) % 3] + u]
    }

    /// Volume from the lines of family `k`: `Σ lengths × cell area`, mm³.
    pub fn volume_from(&self, k: usize) -> f64 {
        let s = self.lattice.spacing;
        let area = s[(k + 1) % 3] * s[(k + 2) % 3];
        self.lines[k]
            .iter()
            .flatten()
            .map(|sp| sp.exit - sp.enter)
            .sum::<f64>()
            * area
    }

    /// The closed, outward-oriented boundary mesh of the union.
    pub fn to_mesh(&self, options: &ContourOptions) -> TriMesh {
        dual_contour(self, options)
    }
}

impl HermiteGrid for EnvelopeGrid {
    fn lattice(&self) -> Lattice {
        self.lattice
    }

    fn line_spans(&self, axis: usize, u: usize, v: usize, out: &mut Vec<Span>) {
        out.extend_from_slice(self.line(axis, u, v));
    }
}

/// Lattice indices along `axis` whose coordinates lie in `[lo, hi]`.
fn index_range(lat: &Lattice, axis: usize, lo: f64, hi: f64) -> Option<(usize, usize)> {
    let (o, h) = (lat.origin[axis], lat.spacing[axis]);
    let i0 = ((lo - o) / h).ceil().max(0.0);
    let i1 = ((hi - o) / h).floor().min(lat.n[axis] as f64 - 1.0);
    (i0 <= i1).then_some((i0 as usize, i1 as usize))
}

/// Inserts `s` into the sorted, disjoint spans of `line`, merging what it overlaps.
fn insert(line: &mut Vec<Span>, s: Span) {
    // First span that ends at or after s.enter; last span that starts at or before s.exit.
    let i = line.partition_point(|x| x.exit < s.enter);
    let j = line.partition_point(|x| x.enter <= s.exit);
    if i == j {
        line.insert(i, s);
        return;
    }
    let merged = Span {
        enter: s.enter.min(line[i].enter),
        exit: s.exit.max(line[j - 1].exit),
    };
    line.splice(i..j, std::iter::once(merged));
}

/// True when `[lo, hi]` lies inside one span of the sorted, disjoint `line`.
fn covered(line: &[Span], lo: f64, hi: f64) -> bool {
    let i = line.partition_point(|x| x.exit < hi);
    i < line.len() && line[i].enter <= lo
}

/// A cheap outer bound of a fixed-axis sweep: the part's bounding cylinder about the axis at
/// the start (radius `ρ_max`, heights `[z_min, z_max]`) grown by the move's length, which holds
/// every point of the sweep (each is within `|δ|` of the start instance).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweepBound {
    tip: Vec3,
    axis: Vec3,
    radius: f64,
    z0: f64,
    z1: f64,
}

impl SweepBound {
    /// The bound of `prof` placed at `tip` with unit `axis`, moving by `delta`.
    pub fn new(prof: &ConvexProfile, tip: Vec3, axis: Vec3, delta: Vec3) -> Self {
        let g = delta.length() + BOUND_SLACK_MM;
        Self {
            tip,
            axis: axis.normalize(),
            radius: prof.r_max() + g,
            z0: prof.z_min() - g,
            z1: prof.z_max() + g,
        }
    }

    /// The range of world coordinate along axis `k` of the line through `o` (`o[k]` = 0)
    /// inside the bound, `None` when it misses.
    pub fn range(&self, o: Vec3, k: usize) -> Option<(f64, f64)> {
        let p0 = o - self.tip;
        let ak = self.axis[k];
        let zo = p0.dot(self.axis);
        // Slab of heights.
        let (mut lo, mut hi) = if ak.abs() < 1e-12 {
            if zo < self.z0 || zo > self.z1 {
                return None;
            }
            (f64::NEG_INFINITY, f64::INFINITY)
        } else {
            let (a, b) = ((self.z0 - zo) / ak, (self.z1 - zo) / ak);
            (a.min(b), a.max(b))
        };
        // Infinite cylinder: |q0 + t w|² ≤ r² with w the line direction across the axis.
        let q0 = p0 - self.axis * zo;
        let mut w = Vec3::ZERO;
        w[k] = 1.0;
        let w = w - self.axis * ak;
        let (aa, bb, cc) = (w.dot(w), q0.dot(w), q0.dot(q0) - self.radius * self.radius);
        if aa < 1e-12 {
            if cc > 0.0 {
                return None;
            }
        } else {
            let disc = bb * bb - aa * cc;
            if disc < 0.0 {
                return None;
            }
            let sq = disc.sqrt();
            lo = lo.max((-bb - sq) / aa);
            hi = hi.min((-bb + sq) / aa);
        }
        (lo <= hi).then_some((lo, hi))
    }
}

/// Growth (mm) of [`SweepBound`] beyond the exact bound, against rounding.
const BOUND_SLACK_MM: f64 = 1e-6;

/// The fixed-axis pieces of move `index` for `shape`: the move itself (fixed-axis line),
/// chords of an arc, or 5-axis sub-moves, within `tol`; with the largest error bound.
///
/// # Errors
/// As `swarf_sweep::five_axis::subdivide`.
pub fn fixed_axis_pieces(
    program: &Program,
    index: usize,
    shape: &SweepShape,
    tol: f64,
) -> Result<(Vec<FixedAxisPiece>, f64), EnvelopeError> {
    let m = &program.moves[index];
    if program.is_five_axis(m) {
        let Some(reach) = Reach::of(shape) else {
            return Ok((Vec::new(), 0.0));
        };
        let subs = subdivide(program, index, reach, tol)?;
        let err = subs.iter().map(|p| p.error_bound).fold(0.0, f64::max);
        let pieces = subs
            .into_iter()
            .map(|p| FixedAxisPiece {
                tip0: p.tip0,
                tip1: p.tip1,
                axis: p.axis,
            })
            .collect();
        return Ok((pieces, err));
    }
    let axis = m.start.axis.normalize();
    Ok(match m.kind {
        MoveKind::Rapid | MoveKind::Linear => (
            vec![FixedAxisPiece {
                tip0: m.start.tip,
                tip1: m.end.tip,
                axis,
            }],
            0.0,
        ),
        MoveKind::Arc(g) => {
            let r = g.start_radius.max(g.end_radius);
            let n = arc_chords(r, g.sweep, tol);
            let step = g.sweep / n as f64;
            let sag = r * (1.0 - (0.5 * step).cos());
            let mut prev = m.start.tip;
            let mut out = Vec::with_capacity(n);
            for i in 1..=n {
                let p = if i == n {
                    m.end.tip
                } else {
                    program.pose_at(m, i as f64 / n as f64).tip
                };
                out.push(FixedAxisPiece {
                    tip0: prev,
                    tip1: p,
                    axis,
                });
                prev = p;
            }
            (out, sag)
        }
    })
}

/// What an envelope run did (the JSON summary of `swarf envelope`).
#[derive(Clone, Debug, Serialize)]
pub struct EnvelopeReport {
    /// Indices of the feed moves swept.
    pub moves: Vec<usize>,
    /// Fixed-axis pieces swept (all shapes).
    pub pieces: usize,
    /// Triangles of the mesh.
    pub triangles: usize,
    /// The mesh is closed (every edge shared by exactly two triangles, in opposite
    /// directions), as its files store it (`f32` positions).
    pub closed: bool,
    /// Volume enclosed by the mesh, mm³.
    pub volume_mm3: f64,
    /// Volume from the X, Y and Z lines, mm³ (a cross-check of the discretisation).
    pub volume_xyz_mm3: [f64; 3],
    /// Lattice spacing, mm.
    pub resolution_mm: f64,
    /// Chordal tolerance, mm.
    pub tolerance_mm: f64,
    /// Largest bound of any arc chord or 5-axis sub-move, mm.
    pub max_piece_error_mm: f64,
    /// Lattice points per axis.
    pub lattice: [usize; 3],
    /// Moves whose envelope folds into their own sweep.
    pub self_intersections: Vec<SelfIntersection>,
}

/// An envelope mesh and its report.
#[derive(Clone, Debug)]
pub struct Envelope {
    /// The closed, outward-oriented mesh.
    pub mesh: TriMesh,
    /// What was done.
    pub report: EnvelopeReport,
}

/// The envelope of the feed moves (linear and arc; rapids are skipped) with indices in `moves`
/// of `program`, each swept by the whole tool (`tools[move.tool]`: cutting part, shank and
/// holder).
///
/// # Errors
/// [`EnvelopeError::NoMoves`] when the range selects no feed move, [`EnvelopeError::UnknownTool`],
/// [`EnvelopeError::BadParameter`], [`EnvelopeError::TooFine`], and 5-axis subdivision failures.
pub fn envelope(
    program: &Program,
    tools: &BTreeMap<u32, Cutter>,
    moves: Range<usize>,
    options: &EnvelopeOptions,
) -> Result<Envelope, EnvelopeError> {
    let tol = options.tolerance;
    if !(tol > 0.0 && tol.is_finite()) {
        return Err(EnvelopeError::BadParameter {
            name: "tolerance",
            value: tol,
        });
    }
    let end = moves.end.min(program.moves.len());
    let selected: Vec<usize> = (moves.start.min(end)..end)
        .filter(|&i| !matches!(program.moves[i].kind, MoveKind::Rapid))
        .collect();
    if selected.is_empty() {
        return Err(EnvelopeError::NoMoves {
            start: moves.start,
            end: moves.end,
            len: program.moves.len(),
        });
    }
    let mut shapes: BTreeMap<u32, (ToolShape, &Cutter)> = BTreeMap::new();
    for &i in &selected {
        let m = &program.moves[i];
        let Some(c) = tools.get(&m.tool) else {
            return Err(EnvelopeError::UnknownTool {
                index: i,
                line: m.line,
                tool: m.tool,
            });
        };
        shapes
            .entry(m.tool)
            .or_insert_with(|| (ToolShape::new(c), c));
    }
    // Fixed-axis pieces per (move, shape); the cutting part and shank/holder are subdivided
    // separately (each with its own pivot and reach, as the stock does).
    let mut work: Vec<(&SweepShape, FixedAxisPiece)> = Vec::new();
    let mut max_err = 0.0f64;
    for &i in &selected {
        let (shape, _) = &shapes[&program.moves[i].tool];
        for part in [shape.cutting(), shape.non_cutting()] {
            if part.parts().is_empty() {
                continue;
            }
            let (pieces, err) = fixed_axis_pieces(program, i, part, tol)?;
            max_err = max_err.max(err);
            work.extend(pieces.into_iter().map(|p| (part, p)));
        }
    }
    let sweeps: Vec<SweptConvex<'_>> = work
        .iter()
        .flat_map(|(shape, p)| {
            shape
                .parts()
                .iter()
                .map(move |prof| SweptConvex::new(prof, p.tip0, p.axis, p.tip1 - p.tip0))
        })
        .collect();
    let outer: Vec<Option<SweepBound>> = work
        .iter()
        .flat_map(|(shape, p)| {
            shape
                .parts()
                .iter()
                .map(move |prof| Some(SweepBound::new(prof, p.tip0, p.axis, p.tip1 - p.tip0)))
        })
        .collect();
    let bounds = sweeps
        .iter()
        .map(SweptConvex::bbox)
        .reduce(|a, b| a.union(&b))
        .expect("a selected feed move has a non-empty cutting part");
    let mut grid = EnvelopeGrid::new(bounds, options.resolution)?;
    grid.add_bounded(&sweeps, &outer);
    let mesh = grid.to_mesh(&options.contour);
    let self_intersections = if options.check_folds {
        selected
            .iter()
            .filter_map(|&i| fold_check(program, i, shapes[&program.moves[i].tool].1))
            .collect()
    } else {
        Vec::new()
    };
    let report = EnvelopeReport {
        moves: selected,
        pieces: work.len(),
        triangles: mesh.len(),
        // Of the mesh as written: contouring leaves no two vertices at one `f32` position.
        closed: mesh.edge_report().is_clean(),
        volume_mm3: mesh.volume(),
        volume_xyz_mm3: [0, 1, 2].map(|k| grid.volume_from(k)),
        resolution_mm: options.resolution,
        tolerance_mm: tol,
        max_piece_error_mm: max_err,
        lattice: grid.lattice().n,
        self_intersections,
    };
    Ok(Envelope { mesh, report })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn span(a: f64, b: f64) -> Span {
        Span { enter: a, exit: b }
    }

    #[test]
    fn spans_insert_and_cover() {
        let mut v = Vec::new();
        for s in [
            span(3.0, 4.0),
            span(0.0, 1.0),
            span(0.5, 2.0),
            span(2.0, 2.5),
            span(5.0, 6.0),
        ] {
            insert(&mut v, s);
        }
        assert_eq!(v, vec![span(0.0, 2.5), span(3.0, 4.0), span(5.0, 6.0)]);
        insert(&mut v, span(2.4, 5.5));
        assert_eq!(v, vec![span(0.0, 6.0)]);
        assert!(covered(&v, 1.0, 5.0) && !covered(&v, -1.0, 1.0) && !covered(&v, 5.0, 7.0));
    }

    #[test]
    fn bound_holds_the_sweep() {
        let c = swarf_tool::Cutter::bull(8.0, 2.0).unwrap();
        let shape = ToolShape::new(&c);
        let prof = &shape.cutting().parts()[0];
        let tip = Vec3::new(1.0, -2.0, 0.5);
        let axis = Vec3::new(0.3, 0.2, 1.0).normalize();
        let delta = Vec3::new(0.4, 0.1, -0.2);
        let sw = SweptConvex::new(prof, tip, axis, delta);
        let b = SweepBound::new(prof, tip, axis, delta);
        let mut hits = 0;
        for k in 0..3 {
            for i in 0..40 {
                for j in 0..40 {
                    let mut o = Vec3::ZERO;
                    o[(k + 1) % 3] = -10.0 + 0.5 * i as f64;
                    o[(k + 2) % 3] = -10.0 + 0.5 * j as f64;
                    if let Some((lo, hi)) = sw.axis_ray_interval(o, k) {
                        let (blo, bhi) = b.range(o, k).expect("the bound holds the sweep");
                        assert!(blo <= lo && bhi >= hi);
                        hits += 1;
                    }
                }
            }
        }
        assert!(hits > 500);
    }

    #[test]
    fn index_ranges_are_inside() {
        let lat = Lattice::new(Vec3::ZERO, Vec3::splat(0.5), [10, 10, 10]);
        assert_eq!(index_range(&lat, 0, 0.6, 2.0), Some((2, 4)));
        assert_eq!(index_range(&lat, 0, -3.0, -1.0), None);
        assert_eq!(index_range(&lat, 0, 4.2, 9.0), Some((9, 9)));
    }
}
