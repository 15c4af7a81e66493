//! Compound surfaces: ordered sets of patches with their orientation and provenance, and the
//! cutter-contact (CC) points the planner visits on them.

use std::fmt;
use std::sync::Arc;

use swarf_geom::Aabb;

use swarf_geom::math::Vec3;

use crate::io::TrimFailure;
use crate::surface::{
    differential, LocalGeometry, ParametricSurface, Surface, SurfaceNormal, Tolerances,
};
use crate::trim::Trim;

/// Most grid points a command asks [`CompoundSurface::grid`] for (see
/// [`CompoundSurface::lattice_len`]): four million, a 2000 × 2000 grid on one patch.
pub const MAX_GRID_POINTS: u64 = 4_000_000;

/// Where a patch came from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum EntityRef {
    /// Index of the patch in a swarf JSON file's `patches` array.
    Json {
        /// 0-based index.
        index: usize,
    },
    /// A STEP surface instance, and the `ADVANCED_FACE` (or `FACE_SURFACE`) it bounds.
    Step {
        /// `#id` of the surface.
        surface: u64,
        /// `#id` of the face, when it belongs to one.
        face: Option<u64>,
    },
    /// An IGES entity, by the sequence number of its first directory-entry line.
    Iges {
        /// Directory entry (the `D` sequence number).
        de: usize,
        /// Entity type (128).
        entity_type: u32,
    },
    /// Built in code.
    Built,
}

impl fmt::Display for EntityRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EntityRef::Json { index } => write!(f, "patches[{index}]"),
            EntityRef::Step {
                surface,
                face: Some(face),
            } => write!(f, "#{surface} (face #{face})"),
            EntityRef::Step {
                surface,
                face: None,
            } => write!(f, "#{surface}"),
            EntityRef::Iges { de, entity_type } => write!(f, "entity {entity_type} at D{de}"),
            EntityRef::Built => write!(f, "built in code"),
        }
    }
}

/// Provenance of a patch: the file (when read from one) and the entity.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PatchSource {
    /// The file path as given to the reader, if any.
    pub file: Option<String>,
    /// The entity in that file.
    pub entity: EntityRef,
}

impl PatchSource {
    /// A patch made in code.
    pub const BUILT: PatchSource = PatchSource {
        file: None,
        entity: EntityRef::Built,
    };
}

/// One patch of a compound surface.
#[derive(Clone, Debug, PartialEq)]
pub struct Patch {
    /// Name from the file (JSON `name`, STEP face or surface name, IGES label), if any.
    pub name: Option<String>,
    /// The geometry, in millimetres.
    pub surface: Surface,
    /// When true the cutter comes from the side of `−(S_u × S_v)`.
    pub flipped: bool,
    /// Where it came from.
    pub source: PatchSource,
    /// The part of the parameter box that is on the part, when the file trims the patch
    /// (`None`: all of it), in the patch's own parameters (radians for angles of elementary
    /// surfaces).
    pub trim: Option<Trim>,
}

impl Patch {
    /// An unnamed, unflipped patch made in code.
    pub fn new(surface: Surface) -> Self {
        Self {
            name: None,
            surface,
            flipped: false,
            source: PatchSource::BUILT,
            trim: None,
        }
    }

    /// The differential geometry at `(u, v)`, with the normal pointing to the cutter side and
    /// curvatures signed accordingly (see [`crate::surface::Curvature`]).
    #[inline]
    pub fn local(&self, u: f64, v: f64, tol: &Tolerances) -> LocalGeometry {
        differential(&self.surface, u, v, self.flipped, tol)
    }

    /// Point and unit normal (towards the cutter) only — the cheaper query for solvers that do
    /// not need curvature. Same normal as [`Patch::local`], including at degenerate points.
    #[inline]
    pub fn point_normal(&self, u: f64, v: f64, tol: &Tolerances) -> (Vec3, SurfaceNormal) {
        let d = self.surface.derivs(u, v);
        let cross = d.su.cross(d.sv);
        let len = cross.length();
        let scale = d.su.length_squared().max(d.sv.length_squared());
        if len > tol.degenerate * scale && len.is_finite() {
            let n = cross / len;
            (
                d.point,
                SurfaceNormal::Regular(if self.flipped { -n } else { n }),
            )
        } else {
            let g = self.local(u, v, tol);
            (g.point(), g.normal)
        }
    }

    /// True when `(u, v)` is on the part: always for an untrimmed patch, inside the trim for a
    /// trimmed one (the parameter box is not checked).
    #[inline]
    pub fn on_part(&self, u: f64, v: f64) -> bool {
        self.trim.as_ref().map_or(true, |t| t.contains(u, v))
    }

    /// Cuts the parameter box down to the box of the trim's outer boundary (a side the
    /// boundary runs along, within 1e-9 of the box's extent, or beyond, stays), so that the
    /// grid of [`CompoundSurface::grid`] spends its `n × n` points on the part rather than on
    /// the surface the trim cuts away (a face that is a sliver of a large surface got a few
    /// points, or none). A B-spline surface is cut exactly,
    /// its parameters kept; the trim is made again on the new box (the same loops: only its
    /// tolerances, relative to the box, change), as if the file had given that box. Nothing
    /// changes without an outer boundary. The STEP reader fits its faces' boxes as it reads
    /// them (across seams, in angles); the IGES and JSON readers call this on every patch.
    pub fn fit_domain_to_trim(&mut self) {
        let Some((t, outer)) = self.trim.as_ref().and_then(|t| Some((t, t.outer()?))) else {
            return;
        };
        let d = self.surface.domain();
        let fitted = crate::trim::fitted_to_loop(d, outer);
        if fitted == d {
            return;
        }
        self.surface.set_domain(fitted);
        // (The loops were accepted on the old box: they are on any box.)
        if let Ok(t) = Trim::new(
            &self.surface.domain(),
            Some(outer.to_vec()),
            t.holes().to_vec(),
        ) {
            self.trim = Some(t);
        }
    }

    /// A box containing the patch.
    pub fn bounding_box(&self) -> Aabb {
        self.surface.bounding_box()
    }

    /// The patch's name, or its index as text (the CSV convention of the planner).
    pub fn label(&self, index: usize) -> String {
        self.name.clone().unwrap_or_else(|| index.to_string())
    }
}

/// Something a reader noticed but did not treat as an error.
#[derive(Clone, Debug, PartialEq)]
pub enum ReadNote {
    /// A surface kind this crate does not evaluate was skipped.
    UnsupportedSurface {
        /// Entity (`#12` or `D7`).
        entity: String,
        /// Its type (`SURFACE_OF_REVOLUTION`, `IGES 118`, …).
        kind: String,
    },
    /// The patch is trimmed in the file, but the trim is not honoured (a trimming curve the
    /// reader does not evaluate, a face trim of a format that is not read): the whole
    /// untrimmed patch is used.
    TrimNotHonoured {
        /// Index of the patch.
        patch: usize,
        /// The trimming entity and why it is not honoured (shown as `IGES 144 at D1 (142 at
        /// D5 has neither a parameter-space nor a model-space curve)`, …).
        by: UnhonouredTrim,
    },
    /// The patch is trimmed in the file and the trim is honoured: [`Patch::trim`] holds it.
    Trimmed {
        /// Index of the patch.
        patch: usize,
        /// The trimming entity (`IGES 144 at D1`, …).
        by: String,
        /// Loops of the trim: the outer boundary (when the file gives one, not the parameter
        /// box) and the holes.
        loops: usize,
        /// Points of the loops' polygons, all together.
        points: usize,
    },
    /// The file declares no length unit; millimetres were assumed.
    UnitsAssumed,
    /// Lengths were scaled to millimetres by this factor.
    UnitsConverted {
        /// Declared unit.
        unit: String,
        /// Millimetres per file unit.
        factor: f64,
    },
    /// Representations of the file declare different length units; each face (surface) is
    /// read in its own representation's, scaled to millimetres.
    UnitsMixed {
        /// The length units, smallest first.
        units: Vec<String>,
        /// The unit of the first context, used for what no single representation holds.
        first: String,
        /// Faces (surfaces) in no representation, or in several of different units, read in
        /// `first`.
        defaulted: usize,
    },
    /// The file places parts by assembly instances (`MAPPED_ITEM`s, representation
    /// relationships with a transformation: `CONTEXT_DEPENDENT_SHAPE_REPRESENTATION`s of
    /// `NEXT_ASSEMBLY_USAGE_OCCURRENCE`s) and the placements were applied: the faces of a part
    /// are read once per placed instance of it, moved into the frame of the assembly's root
    /// (through nested sub-assemblies). Any placement that could not be applied has its own
    /// [`ReadNote::PlacementNotApplied`].
    PlacementsApplied {
        /// Placed instances of representations that hold faces (a part used twice counts
        /// twice, a part in a sub-assembly used twice also twice).
        instances: usize,
        /// The distinct representations (parts) so placed.
        parts: usize,
    },
    /// An assembly placement that could not be applied: an unsupported transformation (a
    /// mirror, a scale out of range, an entity of another kind), a chain that cannot be
    /// resolved (a missing representation, a cycle), an assembly occurrence that nothing
    /// places. Its component is read without it (unmoved by it, as a CAD kernel does), so its
    /// geometry may be misplaced.
    PlacementNotApplied {
        /// The placing entity (`MAPPED_ITEM #31`, `NEXT_ASSEMBLY_USAGE_OCCURRENCE #43`, …).
        entity: String,
        /// Why, and what was read instead.
        why: String,
    },
    /// An analytic patch's parameter box came from a default instead of the face bounds.
    DefaultParameterBox {
        /// Index of the patch.
        patch: usize,
        /// Which parameter(s).
        what: String,
    },
}

impl ReadNote {
    /// This note about a patch, told of patch `index` instead (a note about no patch is
    /// returned as it is).
    pub fn for_patch(mut self, index: usize) -> ReadNote {
        if let ReadNote::TrimNotHonoured { patch, .. }
        | ReadNote::Trimmed { patch, .. }
        | ReadNote::DefaultParameterBox { patch, .. } = &mut self
        {
            *patch = index;
        }
        self
    }
}

/// A trim in a file that a reader does not honour, and why: the entity that trims the patch
/// and the [`TrimFailure`] its loops gave.
#[derive(Clone, Debug)]
pub enum UnhonouredTrim {
    /// The bounds of a STEP face (`STEP face #12 (why)`).
    StepFace {
        /// The face's instance number.
        face: u64,
        /// Why its bounds are not a trim.
        why: Arc<TrimFailure>,
    },
    /// The boundaries of a STEP `CURVE_BOUNDED_SURFACE` (`STEP curve-bounded surface #12
    /// (why)`).
    StepBounded {
        /// The curve-bounded surface's instance number.
        surface: u64,
        /// Why its boundaries are not a trim.
        why: Arc<TrimFailure>,
    },
    /// An IGES 144 trimmed surface (`IGES 144 at D7 (why)`).
    Iges144 {
        /// The 144's directory entry.
        de: usize,
        /// Why its boundaries are not a trim.
        why: Arc<TrimFailure>,
    },
    /// Another IGES entity that bounds the patch: a 143 bounded surface, a 510 face of a
    /// manifold solid B-rep (`IGES 143 at D7 (why)`).
    Iges {
        /// The entity type.
        kind: u32,
        /// Its directory entry.
        de: usize,
        /// Why its boundaries are not a trim.
        why: Arc<TrimFailure>,
    },
}

impl UnhonouredTrim {
    /// Why the trim is not honoured.
    pub fn why(&self) -> &TrimFailure {
        match self {
            UnhonouredTrim::StepFace { why, .. }
            | UnhonouredTrim::StepBounded { why, .. }
            | UnhonouredTrim::Iges144 { why, .. }
            | UnhonouredTrim::Iges { why, .. } => why,
        }
    }
}

impl PartialEq for UnhonouredTrim {
    /// The same entity, not honoured for the same reason (told by its text: a failure may hold
    /// an I/O error, which has no equality).
    fn eq(&self, other: &Self) -> bool {
        let same_entity = match (self, other) {
            (
                UnhonouredTrim::StepFace { face: a, .. },
                UnhonouredTrim::StepFace { face: b, .. },
            ) => a == b,
            (
                UnhonouredTrim::StepBounded { surface: a, .. },
                UnhonouredTrim::StepBounded { surface: b, .. },
            ) => a == b,
            (UnhonouredTrim::Iges144 { de: a, .. }, UnhonouredTrim::Iges144 { de: b, .. }) => {
                a == b
            }
            (
                UnhonouredTrim::Iges { kind: k, de: a, .. },
                UnhonouredTrim::Iges { kind: l, de: b, .. },
            ) => (k, a) == (l, b),
            _ => false,
        };
        same_entity && self.why().to_string() == other.why().to_string()
    }
}

impl fmt::Display for UnhonouredTrim {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            UnhonouredTrim::StepFace { face, why } => write!(f, "STEP face #{face} ({why})"),
            UnhonouredTrim::StepBounded { surface, why } => {
                write!(f, "STEP curve-bounded surface #{surface} ({why})")
            }
            UnhonouredTrim::Iges144 { de, why } => write!(f, "IGES 144 at D{de} ({why})"),
            UnhonouredTrim::Iges { kind, de, why } => write!(f, "IGES {kind} at D{de} ({why})"),
        }
    }
}

impl fmt::Display for ReadNote {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReadNote::UnsupportedSurface { entity, kind } => {
                write!(f, "{entity}: surface type {kind} is not supported; skipped")
            }
            ReadNote::TrimNotHonoured { patch, by } => write!(
                f,
                "patch {patch} is trimmed by {by}; the trim is not honoured (the whole patch is used)"
            ),
            ReadNote::Trimmed {
                patch,
                by,
                loops,
                points,
            } => write!(
                f,
                "patch {patch} is trimmed by {by}: {loops} loop(s), {points} point(s)"
            ),
            ReadNote::UnitsAssumed => write!(f, "no length unit declared; millimetres assumed"),
            ReadNote::UnitsConverted { unit, factor } => {
                write!(f, "lengths in {unit}, scaled by {factor} to millimetres")
            }
            ReadNote::UnitsMixed {
                units,
                first,
                defaulted,
            } => {
                write!(
                    f,
                    "representations declare different length units ({}); each face is scaled \
                     to millimetres by its own",
                    units.join(", ")
                )?;
                if *defaulted > 0 {
                    write!(
                        f,
                        "; {defaulted} face(s) in no single representation read in {first}"
                    )?;
                }
                Ok(())
            }
            ReadNote::PlacementsApplied { instances, parts } => write!(
                f,
                "assembly placements applied: {instances} placed instance(s) of {parts} \
                 part(s), each part's faces read once per instance"
            ),
            ReadNote::PlacementNotApplied { entity, why } => {
                write!(f, "{entity}: placement not applied: {why}")
            }
            ReadNote::DefaultParameterBox { patch, what } => {
                write!(f, "patch {patch}: default parameter range for {what}")
            }
        }
    }
}

/// A cutter-contact point: a patch index and parameters on it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CcPoint {
    /// Index into [`CompoundSurface::patches`].
    pub patch: usize,
    /// u parameter.
    pub u: f64,
    /// v parameter.
    pub v: f64,
}

/// Why a list of CC points is rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CcPointError {
    /// No such patch.
    #[error("point {index}: patch {patch} does not exist ({count} patches)")]
    NoPatch {
        /// Position in the list.
        index: usize,
        /// Patch asked for.
        patch: usize,
        /// Patches there are.
        count: usize,
    },
    /// Parameters outside the patch's box.
    #[error("point {index}: (u, v) = ({u}, {v}) is outside patch {patch}'s parameter box [{u0}, {u1}] × [{v0}, {v1}]")]
    OutsideDomain {
        /// Position in the list.
        index: usize,
        /// Patch.
        patch: usize,
        /// u.
        u: f64,
        /// v.
        v: f64,
        /// Box u0.
        u0: f64,
        /// Box u1.
        u1: f64,
        /// Box v0.
        v0: f64,
        /// Box v1.
        v1: f64,
    },
    /// Parameters inside the box but off the patch's trimmed region.
    #[error("point {index}: (u, v) = ({u}, {v}) is off patch {patch}'s trimmed region")]
    OffPart {
        /// Position in the list.
        index: usize,
        /// Patch.
        patch: usize,
        /// u.
        u: f64,
        /// v.
        v: f64,
    },
}

/// A surface made of patches, in millimetres, each with the side the cutter comes from.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CompoundSurface {
    /// The patches, in file order.
    pub patches: Vec<Patch>,
    /// What the reader noticed (units, skipped entities, trims).
    pub notes: Vec<ReadNote>,
}

/// A label's file-name form: ASCII letters, digits, `_` and `-` kept, anything else `_`.
pub fn file_safe(label: &str) -> String {
    label
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// What a surface's reader could not carry over, by kind, with the reader's note on each:
/// what a check on the surface cannot vouch for.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Caveats {
    /// Faces (or surfaces) skipped, of kinds the reader does not evaluate: nothing is known
    /// of them.
    pub skipped_faces: usize,
    /// The notes on them.
    pub skipped_face_notes: Vec<String>,
    /// Faces whose trim the reader could not honour, used on their whole surface.
    pub untrimmed_faces: usize,
    /// The notes on them.
    pub untrimmed_face_notes: Vec<String>,
    /// Assembly placements the reader could not apply (their parts may be misplaced).
    pub unapplied_placements: usize,
    /// The notes on them.
    pub unapplied_placement_notes: Vec<String>,
}

impl Caveats {
    /// Nothing was left out or approximated.
    pub fn is_empty(&self) -> bool {
        self.skipped_faces == 0 && self.untrimmed_faces == 0 && self.unapplied_placements == 0
    }
}

impl CompoundSurface {
    /// What the reader could not carry over ([`Caveats`]), from its notes.
    pub fn caveats(&self) -> Caveats {
        let of = |keep: fn(&ReadNote) -> bool| -> Vec<String> {
            self.notes
                .iter()
                .filter(|n| keep(n))
                .map(ToString::to_string)
                .collect()
        };
        let skipped = of(|n| matches!(n, ReadNote::UnsupportedSurface { .. }));
        let untrimmed = of(|n| matches!(n, ReadNote::TrimNotHonoured { .. }));
        let unplaced = of(|n| matches!(n, ReadNote::PlacementNotApplied { .. }));
        Caveats {
            skipped_faces: skipped.len(),
            skipped_face_notes: skipped,
            untrimmed_faces: untrimmed.len(),
            untrimmed_face_notes: untrimmed,
            unapplied_placements: unplaced.len(),
            unapplied_placement_notes: unplaced,
        }
    }

    /// The surface moved by the rigid motion `m` (a part placed in the program's frame): every
    /// patch's geometry moved, its parameters — and so its trim, name, orientation and source —
    /// as they are, the notes kept.
    ///
    /// # Errors
    /// A patch that cannot be rebuilt moved (a non-finite motion), naming it.
    pub fn moved(&self, m: &swarf_geom::RigidMotion) -> Result<CompoundSurface, String> {
        let p = crate::placement::Placement::rigid(m);
        let patches = self
            .patches
            .iter()
            .enumerate()
            .map(|(n, patch)| {
                let (surface, trim) =
                    crate::placement::place(&patch.surface, patch.trim.as_ref(), &p)
                        .map_err(|why| format!("patch {n}: {why}"))?;
                Ok(Patch {
                    surface,
                    trim,
                    ..patch.clone()
                })
            })
            .collect::<Result<Vec<_>, String>>()?;
        Ok(CompoundSurface {
            patches,
            notes: self.notes.clone(),
        })
    }

    /// One label per patch, unique even in file-name form: the patch's name, or its index when
    /// it has none; a name several patches share (CAD systems give every face the product's
    /// name) gets the index appended, `PartBody#3`.
    pub fn patch_labels(&self) -> Vec<String> {
        use std::collections::HashMap;
        let first: Vec<String> = self
            .patches
            .iter()
            .enumerate()
            .map(|(k, p)| p.label(k))
            .collect();
        let count = |labels: &[String]| {
            let mut c: HashMap<String, usize> = HashMap::new();
            for l in labels {
                *c.entry(file_safe(l)).or_default() += 1;
            }
            c
        };
        let seen = count(&first);
        let second: Vec<String> = first
            .iter()
            .enumerate()
            .map(|(k, l)| {
                if seen[&file_safe(l)] > 1 {
                    format!("{l}#{k}")
                } else {
                    l.clone()
                }
            })
            .collect();
        // A name that happens to equal another's `name#k` form: the bare index settles it.
        let seen = count(&second);
        second
            .into_iter()
            .enumerate()
            .map(|(k, l)| {
                if seen[&file_safe(&l)] > 1 {
                    format!("#{k}")
                } else {
                    l
                }
            })
            .collect()
    }

    /// The unique label of patch `k` ([`CompoundSurface::patch_labels`]); its index when out of
    /// range.
    pub fn patch_label(&self, k: usize) -> String {
        if k < self.patches.len() {
            self.patch_labels().swap_remove(k)
        } else {
            k.to_string()
        }
    }

    /// A compound surface of these patches.
    pub fn new(patches: Vec<Patch>) -> Self {
        Self {
            patches,
            notes: Vec::new(),
        }
    }

    /// Reverse the side the cutter comes from on every patch (the CLI's `--flip`).
    pub fn flip_all(&mut self) {
        for p in &mut self.patches {
            p.flipped = !p.flipped;
        }
    }

    /// [`Patch::fit_domain_to_trim`] on every patch: the IGES and JSON readers' last step. A
    /// note that a patch's box was a default one ([`ReadNote::DefaultParameterBox`]) is
    /// dropped when an outer boundary gives the patch its box, as the STEP reader drops it.
    pub fn fit_domains_to_trims(&mut self) {
        self.patches.iter_mut().for_each(Patch::fit_domain_to_trim);
        let patches = &self.patches;
        self.notes.retain(|n| match n {
            ReadNote::DefaultParameterBox { patch, .. } => patches
                .get(*patch)
                .and_then(|p| p.trim.as_ref())
                .map_or(true, |t| t.outer().is_none()),
            _ => true,
        });
    }

    /// One box per patch.
    pub fn patch_boxes(&self) -> Vec<Aabb> {
        self.patches.iter().map(Patch::bounding_box).collect()
    }

    /// A box containing every patch; `None` when there are none.
    pub fn bounding_box(&self) -> Option<Aabb> {
        self.patches
            .iter()
            .map(Patch::bounding_box)
            .reduce(|a, b| a.union(&b))
    }

    /// The iso-parametric `n × n` grid of CC points of every patch (`n ≥ 2`; smaller `n` is
    /// taken as 2): `u_i = u0 + i/(n−1)·(u1 − u0)`, likewise v, patch by patch, u outer, v
    /// inner — the thesis's 21×21 and 41×41 grids. Points off a trimmed patch are left out
    /// ([`Self::lattice`] has them all).
    pub fn grid(&self, n: usize) -> Vec<CcPoint> {
        self.lattice(n)
            .into_iter()
            .filter(|(_, on)| *on)
            .map(|(c, _)| c)
            .collect()
    }

    /// The number of points of [`Self::lattice`] for `n` (saturating): compare it with
    /// [`MAX_GRID_POINTS`] before asking for a grid a user chose.
    pub fn lattice_len(&self, n: usize) -> u64 {
        let n = n.max(2) as u64;
        (self.patches.len() as u64).saturating_mul(n.saturating_mul(n))
    }

    /// Every point of the `n × n` grid of every patch, in [`Self::grid`]'s order, each with
    /// whether it is on the part (the layout maps and meshes are drawn on).
    pub fn lattice(&self, n: usize) -> Vec<(CcPoint, bool)> {
        let n = n.max(2);
        let len = usize::try_from(self.lattice_len(n)).unwrap_or(usize::MAX);
        let mut out = Vec::with_capacity(len.min(MAX_GRID_POINTS as usize));
        for (k, p) in self.patches.iter().enumerate() {
            let d = p.surface.domain();
            for i in 0..n {
                let u = d.u_at(i as f64 / (n - 1) as f64);
                for j in 0..n {
                    let v = d.v_at(j as f64 / (n - 1) as f64);
                    out.push((CcPoint { patch: k, u, v }, p.on_part(u, v)));
                }
            }
        }
        out
    }

    /// The patches none of whose points of [`Self::grid`]`(n)` is on the part: a trimmed
    /// region that lies between the grid's rows and columns (the readers fit each face's
    /// parameter box to its trim, so this takes a sliver, or a region far from convex). A
    /// caller that samples the surface on the grid gets no point on them, and should say so.
    pub fn patches_off_grid(&self, n: usize) -> Vec<usize> {
        self.patches_without(&self.grid(n))
    }

    /// The patches that none of `points` (a [`Self::grid`] already made) is on, in order.
    pub fn patches_without(&self, points: &[CcPoint]) -> Vec<usize> {
        let mut has = vec![false; self.patches.len()];
        for c in points {
            if let Some(h) = has.get_mut(c.patch) {
                *h = true;
            }
        }
        (0..has.len()).filter(|&k| !has[k]).collect()
    }

    /// CC points from a list of `(patch, u, v)`, checked against the patches and their boxes.
    pub fn points(&self, list: &[(usize, f64, f64)]) -> Result<Vec<CcPoint>, CcPointError> {
        list.iter()
            .enumerate()
            .map(|(index, &(patch, u, v))| {
                let p = self.patches.get(patch).ok_or(CcPointError::NoPatch {
                    index,
                    patch,
                    count: self.patches.len(),
                })?;
                let d = p.surface.domain();
                if !d.contains(u, v) {
                    return Err(CcPointError::OutsideDomain {
                        index,
                        patch,
                        u,
                        v,
                        u0: d.u[0],
                        u1: d.u[1],
                        v0: d.v[0],
                        v1: d.v[1],
                    });
                }
                if !p.on_part(u, v) {
                    return Err(CcPointError::OffPart { index, patch, u, v });
                }
                Ok(CcPoint { patch, u, v })
            })
            .collect()
    }

    /// The differential geometry at a CC point (normal towards the cutter).
    ///
    /// # Panics
    /// If `cc.patch` is not a patch index (points from [`Self::grid`] and [`Self::points`]
    /// always are).
    #[inline]
    pub fn local(&self, cc: &CcPoint, tol: &Tolerances) -> LocalGeometry {
        self.patches[cc.patch].local(cc.u, cc.v, tol)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_trim_not_honoured_reads_as_the_readers_always_wrote_it() {
        let iges = ReadNote::TrimNotHonoured {
            patch: 3,
            by: UnhonouredTrim::Iges144 {
                de: 7,
                why: Arc::new(TrimFailure::NoCurve {
                    de: crate::io::IgesBoundary { kind: 142, de: 5 },
                }),
            },
        };
        assert_eq!(
            iges.to_string(),
            "patch 3 is trimmed by IGES 144 at D7 (142 at D5 has neither a parameter-space nor a \
             model-space curve); the trim is not honoured (the whole patch is used)"
        );
        let step = ReadNote::TrimNotHonoured {
            patch: 0,
            by: UnhonouredTrim::StepFace {
                face: 12,
                why: Arc::new(TrimFailure::NoArea),
            },
        };
        assert_eq!(
            step.to_string(),
            "patch 0 is trimmed by STEP face #12 (the loops span no area); the trim is not \
             honoured (the whole patch is used)"
        );
        assert_eq!(step.clone(), step);
        assert_ne!(step, iges);
    }
}
