//! The swept envelope of moves and programs as a closed mesh.
//!
//! # Method
//! The swept volume of the whole tool (cutting part, shank, holder) over the selected feed
//! moves is sampled exactly along the rays of a tri-dexel with cubic cells in three directions
//! (X, Y, Z), then contoured: the tri-dexel ([`envelope_rays`], `swarf_stock`'s own type) starts
//! **empty** over the swept bounding box and each ray accumulates the **union**
//! ([`TriDexel::unite_swept`]) of its exact intervals inside the sweeps of fixed-axis
//! straight (sub-)moves — the closed-form grazing-curve kernels of `swarf_sweep::swept` that the
//! stock also cuts with. Arcs and helices become chords through exact arc points
//! (`swarf_sweep::arc_chords`), and 5-axis moves constant-axis sub-moves with a proven Hausdorff
//! bound (`swarf_sweep::five_axis::subdivide`), both within the chordal tolerance. Dual
//! contouring (`swarf_io`, as for the stock) turns the rays' Hermite data into a closed, outward-oriented mesh:
//! ingress, envelope and egress surfaces alike, and self-intersecting envelopes are resolved by
//! the union itself (the fold test, `swarf_sweep::fold`, reports where they occur).
//!
//! # Accuracy
//! Interval ends are exact to floating point for each fixed-axis piece; arcs and 5-axis moves
//! are within the chordal tolerance. Contouring alone leaves vertices micrometres off a curved
//! envelope (6 µm on a 10 mm ball's line at h = 0.25); each vertex is then moved along the
//! world axis nearest to its normal onto the exact union of the pieces' intervals on that line
//! (`crate::project`), so the vertices lie on the envelope of the fixed-axis pieces to rounding,
//! and the triangles within `h²κ/8` of it. The volume converges as the spacing falls. Both
//! parameters are reported.

use std::collections::BTreeMap;
use std::ops::Range;

use serde::Serialize;
use swarf_geom::math::Vec3;
use swarf_geom::Aabb;
use swarf_io::{ContourOptions, Lattice, TriMesh};
use swarf_path::{MoveKind, Program};
use swarf_stock::{Grid, TriDexel};
use swarf_sweep::five_axis::{subdivide, Reach};
use swarf_sweep::{
    arc_chords, fold_check, SelfIntersection, SweepBound, SweepShape, SweptConvex, ToolShape,
};
use swarf_tool::{Cutter, ToolSet};

use crate::error::EnvelopeError;
use crate::project::{onto_envelope, SweepIndex};
use crate::tolerance::{
    DEFAULT_CHORDAL_TOLERANCE_MM, DEFAULT_RESOLUTION_MM, DEFAULT_SIMPLIFY_MM, MAX_LATTICE_POINTS,
};

/// Parameters of [`envelope`]; defaults from [`crate::tolerance`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvelopeOptions {
    /// Lattice spacing, mm ([`DEFAULT_RESOLUTION_MM`]).
    pub resolution: f64,
    /// Chordal tolerance of arcs and 5-axis sub-moves, mm ([`DEFAULT_CHORDAL_TOLERANCE_MM`]).
    pub tolerance: f64,
    /// Run the fold test on arcs and moves whose axis turns (`swarf_sweep::fold`).
    pub check_folds: bool,
    /// Contouring parameters; blocks of cells merged within [`DEFAULT_SIMPLIFY_MM`] by default.
    pub contour: ContourOptions,
    /// Move every mesh vertex onto the exact envelope (along the world axis nearest to its
    /// normal; `crate::project`). On by default; off leaves the contouring's placement.
    pub exact_vertices: bool,
    /// Merge the mesh's coplanar triangles (`TriMesh::merge_coplanar`): a wall, a floor or a
    /// column of cells on a cylinder along a lattice axis becomes a few triangles, the
    /// vertices stay where they were. Off by default.
    pub merge_planar: bool,
}

impl Default for EnvelopeOptions {
    fn default() -> Self {
        Self {
            resolution: DEFAULT_RESOLUTION_MM,
            tolerance: DEFAULT_CHORDAL_TOLERANCE_MM,
            check_folds: true,
            contour: ContourOptions::default().with_simplify(Some(DEFAULT_SIMPLIFY_MM)),
            exact_vertices: true,
            merge_planar: false,
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

    /// With or without vertices moved onto the exact envelope.
    pub fn with_exact_vertices(mut self, on: bool) -> Self {
        self.exact_vertices = on;
        self
    }

    /// With or without the coplanar triangles merged.
    pub fn with_merge_planar(mut self, on: bool) -> Self {
        self.merge_planar = on;
        self
    }

    /// With the contouring's 2 × 2 × 2 blocks of cells merged where their crossings lie within
    /// `tol` mm of the planes that meet at one point (`ContourOptions::simplify`; the merged
    /// vertices are then put on the exact envelope like the others). `None` keeps every cell;
    /// the default is [`DEFAULT_SIMPLIFY_MM`].
    pub fn with_simplify(mut self, tol: Option<f64>) -> Self {
        self.contour.simplify = tol;
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

/// An empty tri-dexel on the envelope's ray grid: cubic cells of side `h` centred on `bounds`
/// grown by two spacings (the lattice of [`Lattice::covering`]), so the envelope's surface never
/// touches the grid's border.
///
/// # Errors
/// [`EnvelopeError::BadParameter`] for a spacing that is not positive and finite,
/// [`EnvelopeError::TooFine`] beyond [`MAX_LATTICE_POINTS`], and the stock's own limits.
pub fn envelope_rays(bounds: Aabb, h: f64) -> Result<TriDexel, EnvelopeError> {
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
    let grid = Grid::cubic(lattice.origin - Vec3::splat(0.5 * h), h, lattice.n)?;
    Ok(TriDexel::on_grid(grid))
}

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
            if n > swarf_sweep::MAX_CHORDS {
                return Err(swarf_sweep::too_many_chords(index, m.line, r, tol).into());
            }
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
    /// Vertices put on the exact envelope ([`EnvelopeOptions::exact_vertices`]); the others
    /// are where the contouring placed them.
    pub exact_vertices: usize,
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
    /// With [`EnvelopeOptions::merge_planar`], the triangles before the merge (the same as
    /// `triangles` where the merge was given up: `TriMesh::merge_coplanar_within`).
    pub triangles_before_merge: Option<usize>,
    /// With `ContourOptions::simplify`, the blocks of cells merged into one vertex.
    pub merged_blocks: Option<usize>,
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
/// of `program`, each swept by the whole tool (the cutter `tools` gives the move's tool: cutting part, shank and
/// holder).
///
/// # Errors
/// [`EnvelopeError::NoMoves`] when the range selects no feed move, [`EnvelopeError::UnknownTool`],
/// [`EnvelopeError::BadParameter`], [`EnvelopeError::TooFine`], and 5-axis subdivision failures.
pub fn envelope(
    program: &Program,
    tools: &ToolSet,
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
    if let Some(s) = options
        .contour
        .simplify
        .filter(|s| !(*s > 0.0 && s.is_finite()))
    {
        return Err(EnvelopeError::BadParameter {
            name: "simplify",
            value: s,
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
        let Some(c) = tools.get(m.tool) else {
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
    let mut rays = envelope_rays(bounds, options.resolution)?;
    rays.unite_swept(&sweeps, &outer);
    let h = options.resolution;
    // What the report needs of the rays, taken before the contouring consumes them.
    let (volume_xyz_mm3, lattice) = (rays.volumes(), rays.grid().n);
    let (mesh, stats) = if options.exact_vertices {
        let boxes: Vec<Aabb> = sweeps.iter().map(SweptConvex::bbox).collect();
        // Cells about half the narrowest extent of a typical sweep: each sweep is filed in a
        // few cells, each cell holds the few sweeps around it.
        let typical = boxes
            .iter()
            .map(|b| {
                let s = b.size();
                s.x.min(s.y).min(s.z)
            })
            .sum::<f64>()
            / boxes.len() as f64;
        let index = SweepIndex::new(boxes, h, (0.5 * typical).max(8.0 * h));
        rays.into_mesh_projected(&options.contour, |p, n| {
            onto_envelope(&sweeps, &index, p, n, h)
        })
    } else {
        rays.to_mesh(&options.contour)
    };
    let (mesh, merged) = if options.merge_planar {
        let (merged, stats) = mesh.merge_coplanar();
        (merged, Some(stats))
    } else {
        (mesh, None)
    };
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
        exact_vertices: stats.projected_vertices,
        // Of the mesh as written: contouring leaves no two vertices at one `f32` position.
        closed: mesh.edge_report().is_clean(),
        volume_mm3: mesh.volume(),
        volume_xyz_mm3,
        resolution_mm: options.resolution,
        tolerance_mm: tol,
        max_piece_error_mm: max_err,
        lattice,
        self_intersections,
        triangles_before_merge: merged.map(|m| m.triangles_before),
        merged_blocks: options.contour.simplify.map(|_| stats.merged_blocks),
    };
    Ok(Envelope { mesh, report })
}
