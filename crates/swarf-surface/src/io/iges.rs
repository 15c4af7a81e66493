//! IGES 5.3 surfaces: entity 128 (rational B-spline surface) as patches (restricted to its
//! parameter range U0–U1 × V0–V1 within the knots' domain, exactly, by knot insertion —
//! [`NurbsSurface::restricted`]; a range that leaves nothing is an error), trimmed by 144
//! (trimmed parametric surface) and 142 (curve on a parametric surface); entity 126 (rational
//! B-spline curve) parsed into [`IgesDocument::curves`].
//!
//! **Trims.** A 144 on a 128 gives the patch a [`Trim`]: the outer boundary is the patch's
//! parameter box when PTO = 0, else the 142 at PTO; the inner boundaries are the 142s listed.
//! Each 142 is read through its parameter-space curve (BPTR), in the surface's parameters
//! (never scaled by the units), which may be a 126 (x and y of its control points are u and v),
//! a 110 line, a 100 circular arc or a 102 composite of these (nested up to 8 deep), each with
//! its 124 transformation if it names one. Curves are sampled to a chord of 1e-6 of the patch's
//! parameter box diagonal, at least 4 segments per knot span (and per quarter turn of an arc),
//! into closed polygons; a [`ReadNote::Trimmed`] says how many loops and points. Once every
//! trim is made and placed, a patch with an outer boundary has its parameter box cut down to
//! that boundary's box ([`crate::Patch::fit_domain_to_trim`]), so that its grids fall on the
//! part.
//!
//! **Model-space boundaries.** A 142 without a parameter-space curve (BPTR = 0, as exporters
//! write with PREF = 2), or whose parameter-space curve is (or holds) a kind not evaluated
//! (104, 106, 112, 130), is read through its model-space curve (CPTR) instead: the same kinds
//! (126 in 3-D, 110, 100 at its ZT, 102 of these, with their 124s), scaled to mm like the
//! surface, mapped onto the 128. The curve is sampled from 4 steps per knot span (per quarter
//! turn of an arc, per line), halved until the surface point at the middle of each chord in
//! parameters lies within min(1e-3 mm, 1e-5 of the surface's size) of the curve's own point
//! there; every sample is mapped to the patch's parameters by point inversion (Newton seeded by
//! the previous sample, the first from a coarse grid; at most 256 grid searches per 144). A
//! sample farther than 1e-4 of the surface's size + 0.01 mm (or the G section's minimum
//! resolution, when coarser) from the surface, a curve that does
//! not map to a continuous closed loop (a jump across a seam), fewer than 3 distinct points, or
//! a model-space curve of a kind not read leaves the patch untrimmed with a
//! [`ReadNote::TrimNotHonoured`] saying why (`model-space curve of 142 at D5 lies 1.000e0 mm
//! off the surface …`). The [`ReadNote::Trimmed`] of a trim with such loops says so
//! (`IGES 144 at D1, the loop of the 142 at D5 mapped from its model-space curve`).
//!
//! A 142 with neither curve, a parameter-space curve type not listed (and no model-space
//! curve), or a trim needing more than 200 000 points leaves the patch untrimmed with a
//! [`ReadNote::TrimNotHonoured`] saying why. A second 144 on the same 128 gets its own copy of
//! the patch (at the end of the list). A boundary pointer that names no entry, or an entry of
//! the wrong type, is an error at that parameter (in a model-space curve: a note, the patch
//! untrimmed); so is a 144's surface pointer (PTS) that names no entry or an entry that is not a
//! surface (one on a surface kind not read is skipped with that surface). [`IgesDocument::trims`]
//! still lists every 144 as found. A 144's own transformation (124) places the patch it trims
//! (its boundaries are in the surface's parameters or in the space the surface is defined in).
//!
//! **Other bounds.** A 143 (bounded surface) on a 128 trims it as a 144 does, through its 141
//! boundaries: each 141 is a chain of curves, each read from its parameter-space curves when the
//! boundary has them (TYPE 1), else from its model-space curve mapped onto the patch as above,
//! reversed where its SENSE is 2; the loop enclosing the largest area in the parameters is the
//! outer boundary, the others holes (the 143 does not say which is which). The faces (510) of a
//! manifold solid B-rep (186) leave their surfaces untrimmed with a
//! [`ReadNote::TrimNotHonoured`] each (their 508 loops are not read); a subfigure instance (408)
//! is not applied, with a [`ReadNote::PlacementNotApplied`] (its subfigure's surfaces are read
//! where it defines them).
//!
//! **Swept surfaces and planes** (module `swept`). A 120 (surface of revolution; u the
//! generatrix's parameter, v the turn from SA to TA, counter-clockwise about the axis line's
//! direction), a 122 (tabulated cylinder; u the directrix's, v from 0 to 1 along the generatrix)
//! and a 118 (ruled surface; u along the curves, v from the first to the second) are exact
//! rational B-splines of their curves (110, 100, 126 within its range, 102 of these joined)
//! built by `crate::sweep`. A 118 is read where its rulings can be made exactly: form 0 (equal
//! relative arc length) between two lines or two circular arcs of one sweep, form 1 (equal
//! relative parameter) between lines, 126s and 102s of them, or two arcs of one sweep (an arc's
//! B-spline parameter is not its angle); otherwise, as for curves of other kinds, it is skipped
//! with a [`ReadNote::UnsupportedSurface`] that says why. DEVFLG is not needed. A 190 (plane
//! surface: its 116 point, 123 normal and, form 1, 123 reference direction along u) and a 108
//! (plane Ax + By + Cz = D, about the foot of its display symbol) are planes over
//! [`crate::io::step::DEFAULT_LINEAR_RANGE`]² with a [`ReadNote::DefaultParameterBox`]; a 108 of
//! form 1 with a curve spans the box of the curve's control points and is trimmed by the curve
//! (form −1: holed by it), mapped from model space as a 142's model-space curve is. Each is
//! moved by its own 124 and scaled to mm as a 128. A 144 or 143 on one of them reads its
//! boundaries through their model-space curves (the patch is not parametrised as the IGES
//! surface is); a boundary with only a parameter-space curve leaves the patch untrimmed with a
//! [`ReadNote::TrimNotHonoured`].
//!
//! The fixed-column format: 80-column records (ending in LF, CRLF or a lone CR, or with no line
//! ends at all, every 80 bytes), section letter in column 73 (S, G, D, P, T),
//! sequence number in 74–80 (directory entries listed out of order are put in the order of
//! their sequence numbers, which pointers name). Columns are bytes: text that is not ASCII (accents in the Start
//! section and in strings of European files) is read one byte a column (Latin-1), or one UTF-8
//! character a column when the record was padded to 80 characters (the layout that puts the
//! section letter in column 73 wins); such columns read as `?` in strings, so they never
//! refuse a file. [`parse_bytes`] reads a file's bytes; [`parse`] takes text.
//!
//! The G section gives the parameter and record delimiters (defaults `,` and `;`), the units
//! flag and unit name (field 14/15: inch, mm, foot, mile, metre, km, mil, micron, cm,
//! microinch), converted to mm; its later fields are not used, and a string among them that
//! does not parse (a Hollerith count that overruns) is no error. The model-space scale
//! (field 13) is not applied. Directory entries are two records of 8-column fields; parameter
//! data lives in columns 1–64 of the P records. Transformation matrices (entity 124) referenced
//! by a 128 or a curve are applied. Hollerith strings (`5HHello`) and `D` exponents are
//! understood.

mod swept;

use std::borrow::Cow;
use std::collections::{HashMap, HashSet};
use std::sync::Arc;

use swarf_geom::math::Vec3;

use super::{
    skipped_detail, Format, IgesBoundary, ReadError, TrimFailure, Uv, MAX_GRID_SEARCHES,
    MAX_HALVINGS, MAX_TRIM_POINTS,
};
use crate::compound::{CompoundSurface, EntityRef, Patch, PatchSource, ReadNote, UnhonouredTrim};
use crate::curve::{BSplineCurve, CurveError};
use crate::surface::invert::{InvertError, Inverter};
use crate::surface::{NurbsSurface, ParamBox, ParametricSurface, PlaneSurface, Surface};
use crate::trim::{sample_curve, Trim, TrimError};

/// A rational B-spline curve (entity 126), in mm (model-space curves) or in the surface's
/// parameter space (curves referenced as a 142's parameter-space curve).
#[derive(Clone, Debug, PartialEq)]
pub struct IgesCurve {
    /// Directory entry (D sequence number).
    pub de: usize,
    /// Degree.
    pub degree: usize,
    /// Knot vector (`K + M + 2` values).
    pub knots: Vec<f64>,
    /// Weights, one per control point.
    pub weights: Vec<f64>,
    /// Control points (model-space curves scaled to mm and transformed; parameter-space ones
    /// as written).
    pub points: Vec<Vec3>,
    /// Parameter range `[V0, V1]`.
    pub range: [f64; 2],
}

impl IgesCurve {
    /// The curve as a [`BSplineCurve`] (in the coordinates of its `points`), for evaluation.
    ///
    /// # Errors
    /// When its numbers do not make a curve (the reader refuses those before).
    pub fn spline(&self) -> Result<BSplineCurve, CurveError> {
        BSplineCurve::new(self.degree, self.knots.clone(), &self.points, &self.weights)
    }
}

/// A trimmed surface (entity 144) as found in the file.
#[derive(Clone, Debug, PartialEq)]
pub struct IgesTrim {
    /// Directory entry of the 144.
    pub de: usize,
    /// Index of the trimmed patch in [`IgesDocument::surface`].
    pub patch: Option<usize>,
    /// DE of the outer boundary (a 142), `None` when the outer boundary is the patch's own.
    pub outer: Option<usize>,
    /// DEs of the inner boundaries (142s).
    pub inner: Vec<usize>,
}

/// Everything read from an IGES file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct IgesDocument {
    /// The 128 patches.
    pub surface: CompoundSurface,
    /// Every 126 curve.
    pub curves: Vec<IgesCurve>,
    /// Every 144 trimmed surface.
    pub trims: Vec<IgesTrim>,
}

/// Parse IGES text to its patches.
pub fn parse(text: &str) -> Result<CompoundSurface, ReadError> {
    parse_bytes(text.as_bytes())
}

/// Parse the bytes of an IGES file to its patches (text that is not ASCII, as in Start
/// sections and strings of European files, is read one byte per column).
pub fn parse_bytes(bytes: &[u8]) -> Result<CompoundSurface, ReadError> {
    parse_document_bytes(bytes).map(|d| d.surface)
}

/// Parse IGES text to patches, curves and trims.
pub fn parse_document(text: &str) -> Result<IgesDocument, ReadError> {
    parse_document_bytes(text.as_bytes())
}

/// Parse the bytes of an IGES file to patches, curves and trims.
pub fn parse_document_bytes(bytes: &[u8]) -> Result<IgesDocument, ReadError> {
    let mut file = Sections::split(bytes)?;
    let global = file.global()?;
    let entries = file.directory()?;
    let mut doc = IgesDocument::default();
    let mut patch_of_de = HashMap::new();
    let mut skipped = Vec::new();
    // 108 planes with a bounding curve to map onto them: the entry, the patch, a hole.
    let mut bounded = Vec::new();
    for e in &entries {
        match e.kind {
            128 => {
                let s = file.surface128(e, &entries, global.factor)?;
                patch_of_de.insert(e.de, doc.surface.patches.len());
                doc.surface.patches.push(Patch {
                    name: e.label.clone(),
                    surface: Surface::Nurbs(s),
                    flipped: false,
                    source: PatchSource {
                        file: None,
                        entity: EntityRef::Iges {
                            de: e.de,
                            entity_type: 128,
                        },
                    },
                    trim: None,
                });
            }
            126 => doc.curves.push(file.curve126(e, &entries, global.factor)?),
            k if swept::READ.contains(&k) => {
                match file.swept_surface(e, &entries, global.factor)? {
                    Ok(m) => {
                        let index = doc.surface.patches.len();
                        patch_of_de.insert(e.de, index);
                        if let Some(what) = m.defaulted {
                            doc.surface.notes.push(ReadNote::DefaultParameterBox {
                                patch: index,
                                what: what.into(),
                            });
                        }
                        if let Some(hole) = m.bound {
                            bounded.push((e, index, hole));
                        }
                        doc.surface.patches.push(Patch {
                            name: e.label.clone(),
                            surface: m.surface,
                            flipped: false,
                            source: PatchSource {
                                file: None,
                                entity: EntityRef::Iges {
                                    de: e.de,
                                    entity_type: e.kind,
                                },
                            },
                            trim: None,
                        });
                    }
                    Err(why) => skipped.push(ReadNote::UnsupportedSurface {
                        entity: format!("D{}", e.de),
                        kind: format!("IGES {} ({why})", e.kind),
                    }),
                }
            }
            k if SKIPPED_SURFACES.contains(&k) => skipped.push(ReadNote::UnsupportedSurface {
                entity: format!("D{}", e.de),
                kind: format!("IGES {}", e.kind),
            }),
            _ => {}
        }
    }
    // Curves used in a surface's parameter space are not in model units: undo the scaling.
    if global.factor != 1.0 {
        let mut param_space = HashSet::new();
        for e in entries.iter().filter(|e| e.kind == 142) {
            let p = file.params(e)?;
            let bptr = p.int(3, "BPTR")?;
            file.curves_126_under(&entries, bptr, 0, &mut param_space);
        }
        for c in doc.curves.iter_mut() {
            if param_space.contains(&c.de) {
                c.points.iter_mut().for_each(|q| *q /= global.factor);
            }
        }
    }
    // A 128 trimmed by a 144 becomes a trimmed patch; a second 144 on the same 128 gets a copy
    // (of the surface as the 128 gives it: a 144's own transformation moves only its patch).
    let mut claimed = vec![false; doc.surface.patches.len()];
    // Each trimming entity's own transformation, applied once every trim is made: a copy of a
    // patch another entity trimmed then starts from the surface as the 128 gives it.
    let mut placements: Vec<Placement<'_>> = Vec::new();
    let mut points_left = MAX_FILE_TRIM_POINTS;
    // A 108's bounding curve (form 1) or hole (form −1), in model space, mapped onto its plane.
    for (e, k, hole) in bounded {
        let p = file.params(e)?;
        let t = file.transform(&entries, e)?;
        let result = {
            let surface = &doc.surface.patches[k].surface;
            let mut sampler = Sampler::new(&file, &entries, surface, global.factor, points_left);
            let budget = sampler.points_left;
            let result = sampler.bound108(e, &p, t, hole, &surface.domain())?;
            points_left -= budget - sampler.points_left;
            result
        };
        let by = format!(
            "IGES 108 at D{}, its {} mapped from its model-space curve",
            e.de,
            if hole { "hole" } else { "boundary" }
        );
        settle_trim(&mut doc, &mut claimed, (k, false), result, by, |why| {
            UnhonouredTrim::Iges {
                kind: 108,
                de: e.de,
                why,
            }
        });
    }
    for e in entries.iter().filter(|e| e.kind == 144) {
        let p = file.params(e)?;
        let pts = p.int(1, "PTS")?;
        let n2 = p.int(3, "N2")?;
        let pto = p.int(4, "PTO")?;
        if !(0..=p.values.len() as i64).contains(&n2) {
            return Err(p.error(3, format!("N2 = {n2} inner boundaries is impossible here")));
        }
        let inner = (0..n2 as usize)
            .map(|k| p.int(5 + k, "PTI").map(|v| v as usize))
            .collect::<Result<Vec<_>, _>>()?;
        check_surface_pointer(&entries, &p, 1, "PTS", pts)?;
        let mut patch = usize::try_from(pts)
            .ok()
            .and_then(|d| patch_of_de.get(&d).copied());
        if let Some(k) = patch {
            let target = trim_patch(
                (&file, &entries, global.factor),
                (&mut doc, &mut claimed, &mut placements, &mut points_left),
                (e, k),
                |sampler, domain| sampler.trim144(e, &p, domain),
            )?;
            patch = Some(target);
        }
        doc.trims.push(IgesTrim {
            de: e.de,
            patch,
            outer: usize::try_from(pto).ok().filter(|&d| d > 0),
            inner,
        });
    }
    // A 128 bounded by a 143 (its boundaries 141s) becomes a trimmed patch, as a 144's does.
    for e in entries.iter().filter(|e| e.kind == 143) {
        let p = file.params(e)?;
        let sptr = p.int(2, "SPTR")?;
        p.count(3, "N")?;
        check_surface_pointer(&entries, &p, 2, "SPTR", sptr)?;
        let Some(k) = usize::try_from(sptr)
            .ok()
            .and_then(|d| patch_of_de.get(&d).copied())
        else {
            continue;
        };
        trim_patch(
            (&file, &entries, global.factor),
            (&mut doc, &mut claimed, &mut placements, &mut points_left),
            (e, k),
            |sampler, domain| sampler.trim143(e, &p, domain),
        )?;
    }
    for (target, t, e) in placements {
        let placed = transformed(&doc.surface.patches[target].surface, &t, global.factor).map_err(
            |reason| ReadError::Surface {
                format: Format::Iges,
                line: e.line,
                entity: format!("entity {} at D{}", e.kind, e.de),
                reason,
            },
        )?;
        doc.surface.patches[target].surface = placed;
    }
    // The faces (510) of a manifold solid B-rep: their loops (508 of 504 edge lists) are not
    // read, so the surface of each stands whole, said per face.
    for e in entries.iter().filter(|e| e.kind == 510) {
        let p = file.params(e)?;
        let surf = p.int(1, "SURF")?;
        if let Some(&k) = usize::try_from(surf).ok().and_then(|d| patch_of_de.get(&d)) {
            claimed[k] = true;
            doc.surface.notes.push(ReadNote::TrimNotHonoured {
                patch: k,
                by: UnhonouredTrim::Iges {
                    kind: 510,
                    de: e.de,
                    why: Arc::new(TrimFailure::FaceLoopsNotRead),
                },
            });
        }
    }
    // Subfigure instances (408) place the entities of a subfigure definition (308) elsewhere:
    // not applied, so the geometry is read once, where it is defined.
    for e in entries.iter().filter(|e| e.kind == 408) {
        let p = file.params(e)?;
        let def = p.int(1, "DE")?;
        doc.surface.notes.push(ReadNote::PlacementNotApplied {
            entity: format!("IGES 408 at D{}", e.de),
            why: format!(
                "subfigure instances are not applied: the surfaces of the subfigure D{def} are \
                 read once, where it defines them"
            ),
        });
    }
    // Each trimmed face gridded over its own part (after the placements, which keep the
    // parameters).
    doc.surface.fit_domains_to_trims();
    if doc.surface.patches.is_empty() {
        return Err(ReadError::Empty {
            format: Format::Iges,
            detail: if skipped.is_empty() {
                "; no entity 128".into()
            } else {
                skipped_detail(&skipped)
            },
        });
    }
    if global.factor != 1.0 {
        doc.surface.notes.insert(
            0,
            ReadNote::UnitsConverted {
                unit: global.unit,
                factor: global.factor,
            },
        );
    }
    doc.surface.notes.extend(skipped);
    Ok(doc)
}

/// The surface pointer (parameter `i`, named `what`, value `de`) of a trimming entity: a 128
/// read above, or a surface of a kind not read (skipped with its note); anything
/// else is a broken pointer, as a boundary's would be.
fn check_surface_pointer(
    entries: &[Entry],
    p: &Params,
    i: usize,
    what: &str,
    de: i64,
) -> Result<(), ReadError> {
    match entry_at(entries, de) {
        None => Err(p.error(
            i,
            format!("surface {what} points at D{de}, which is not a directory entry"),
        )),
        Some(s)
            if s.kind != 128
                && !swept::READ.contains(&s.kind)
                && !SKIPPED_SURFACES.contains(&s.kind) =>
        {
            Err(p.error(
            i,
            format!(
                    "surface {what} points at D{de}, an entity {}; expected a surface (128, 108, 118, 120, 122 or 190)",
                    s.kind
                ),
            ))
        }
        Some(_) => Ok(()),
    }
}

/// A trimming entity's own transformation, to move the patch that stands for its face: the
/// patch, the matrix, the entity.
type Placement<'e> = (usize, [f64; 12], &'e Entry);

/// The trim that the trimming entity `e` (a 144 or a 143) gives patch `k`, made by `build`
/// with a sampler on the patch's surface as the file gives it, recorded (`settle_trim`), and
/// `e`'s own transformation listed in `placements` for the patch that stands for the face
/// (applied once every trim is made). Returns that patch.
fn trim_patch<'e>(
    (file, entries, factor): (&Sections<'_>, &[Entry], f64),
    (doc, claimed, placements, points_left): (
        &mut IgesDocument,
        &mut [bool],
        &mut Vec<Placement<'e>>,
        &mut usize,
    ),
    (e, k): (&'e Entry, usize),
    build: impl FnOnce(&mut Sampler<'_, '_>, &ParamBox) -> Result<Built<Trim>, ReadError>,
) -> Result<usize, ReadError> {
    let surface = &doc.surface.patches[k].surface;
    let mut sampler = Sampler::new(file, entries, surface, factor, *points_left);
    if let EntityRef::Iges { entity_type, .. } = doc.surface.patches[k].source.entity {
        sampler.foreign = (entity_type != 128).then_some(entity_type);
    }
    let budget = sampler.points_left;
    let result = build(&mut sampler, &surface.domain())?;
    *points_left -= budget - sampler.points_left;
    let by = match sampler.from_model.as_slice() {
        [] => format!("IGES {} at D{}", e.kind, e.de),
        des => format!(
            "IGES {} at D{}, the loop{s} of the {}{s} at {} mapped from {} model-space curve{s}",
            e.kind,
            e.de,
            des[0].kind,
            des.iter()
                .map(|d| format!("D{}", d.de))
                .collect::<Vec<_>>()
                .join(", "),
            if des.len() == 1 { "its" } else { "their" },
            s = if des.len() == 1 { "" } else { "s" },
        ),
    };
    let (kind, de) = (e.kind, e.de);
    let transform = file.transform(entries, e)?;
    let placed = transform.is_some();
    let target = settle_trim(doc, claimed, (k, placed), result, by, |why| match kind {
        144 => UnhonouredTrim::Iges144 { de, why },
        _ => UnhonouredTrim::Iges { kind, de, why },
    });
    // The entity's own transformation places the trimmed surface (its boundaries are in the
    // surface's parameters, or in the space the surface is defined in).
    if let Some(t) = transform {
        placements.push((target, t, e));
    }
    Ok(target)
}

/// Records what a trimming entity made of patch `k` (still as the file gives it: placements
/// come after every trim): the trimmed patch (the patch itself the first time, a copy of it
/// after), or the whole patch with the note saying why not; `placed` when the entity moves its
/// face by a transformation of its own. Returns the patch that stands for the face.
fn settle_trim(
    doc: &mut IgesDocument,
    claimed: &mut [bool],
    (k, placed): (usize, bool),
    result: Built<Trim>,
    by: String,
    unhonoured: impl FnOnce(Arc<TrimFailure>) -> UnhonouredTrim,
) -> usize {
    // A patch another entity has claimed is copied (from the surface as the file gives it, with
    // no trim): the entity's face is its own, whatever became of the other's.
    let own = |doc: &mut IgesDocument, claimed: &mut [bool]| {
        if claimed[k] {
            let mut copy = doc.surface.patches[k].clone();
            copy.trim = None;
            doc.surface.patches.push(copy);
            doc.surface.patches.len() - 1
        } else {
            claimed[k] = true;
            k
        }
    };
    match result {
        Ok(trim) => {
            let target = own(doc, claimed);
            doc.surface.notes.push(ReadNote::Trimmed {
                patch: target,
                by,
                loops: trim.loops().len(),
                points: trim.loops().iter().map(Vec::len).sum(),
            });
            doc.surface.patches[target].trim = Some(trim);
            target
        }
        Err(why) => {
            // The whole patch stands for this face: once, however many unplaced entities leave
            // it whole; a placed one (its own 124) or one after a trimmed face gets a copy.
            let whole_already = claimed[k] && doc.surface.patches[k].trim.is_none() && !placed;
            let target = if whole_already { k } else { own(doc, claimed) };
            doc.surface.notes.push(ReadNote::TrimNotHonoured {
                patch: target,
                by: unhonoured(Arc::new(why)),
            });
            target
        }
    }
}

/// `s` moved by the transformation matrix `t` (file units; `s` is in mm, `factor` mm per file
/// unit).
fn transformed(
    s: &Surface,
    t: &[f64; 12],
    factor: f64,
) -> Result<Surface, crate::surface::NurbsError> {
    let plane;
    let n = match s {
        Surface::Nurbs(n) => n,
        Surface::Plane(pl) => {
            // A rigid motion (or reflection) keeps it a plane; another map makes it a bilinear
            // B-spline over its box, moved below.
            let lin = |v: Vec3| apply(&Some(*t), v) - apply(&Some(*t), Vec3::ZERO);
            let (x, y) = (lin(pl.frame.x), lin(pl.frame.y));
            let unit = |a: f64| (a - 1.0).abs() <= 1e-9;
            if unit(x.length()) && unit(y.length()) && x.dot(y).abs() <= 1e-9 {
                let origin = apply(&Some(*t), pl.frame.origin / factor) * factor;
                let frame = swarf_geom::Frame {
                    origin,
                    x,
                    y,
                    z: x.cross(y),
                };
                return Ok(Surface::Plane(PlaneSurface::new(frame, pl.domain)));
            }
            let d = pl.domain;
            let corner = |u: f64, v: f64| pl.point(u, v);
            plane = NurbsSurface::new(
                1,
                1,
                vec![d.u[0], d.u[0], d.u[1], d.u[1]],
                vec![d.v[0], d.v[0], d.v[1], d.v[1]],
                &[
                    vec![corner(d.u[0], d.v[0]), corner(d.u[0], d.v[1])],
                    vec![corner(d.u[1], d.v[0]), corner(d.u[1], d.v[1])],
                ],
                None,
            )?;
            &plane
        }
        _ => return Ok(s.clone()),
    };
    let (nu, nv) = n.net_size();
    let points: Vec<Vec<Vec3>> = (0..nu)
        .map(|i| {
            (0..nv)
                .map(|j| apply(&Some(*t), n.control_point(i, j) / factor) * factor)
                .collect()
        })
        .collect();
    let weights: Vec<Vec<f64>> = (0..nu)
        .map(|i| (0..nv).map(|j| n.weight(i, j)).collect())
        .collect();
    NurbsSurface::new(
        n.degree_u(),
        n.degree_v(),
        n.knots_u().to_vec(),
        n.knots_v().to_vec(),
        &points,
        Some(&weights),
    )
    .map(Surface::Nurbs)
}

/// Surface entities that are not read: a patch on one is skipped with a
/// [`ReadNote::UnsupportedSurface`].
const SKIPPED_SURFACES: [u32; 6] = [114, 140, 192, 194, 196, 198];

/// Most points of all the trims of a file (a guard against files that repeat a costly trim).
const MAX_FILE_TRIM_POINTS: usize = 4_000_000;
/// Most curve entities visited for one trim (a composite may list one curve many times).
const MAX_TRIM_CURVES: usize = 20_000;
/// Share of the parameter box's sides by which a trimming curve may stray outside it.
const BOX_MARGIN: f64 = 0.01;
/// Composite curves (102) nest at most this deep in a trimming curve.
const MAX_NESTING: usize = 8;
/// Curve samples per knot span (and per quarter turn of an arc, per line), at least.
const SEGMENTS_PER_SPAN: usize = 4;

/// The directory entry with sequence number `de`, if there is one.
fn entry_at(entries: &[Entry], de: i64) -> Option<&Entry> {
    let d = usize::try_from(de).ok().filter(|d| d % 2 == 1)?;
    entries.get((d - 1) / 2).filter(|e| e.de == d)
}

/// `outer ∘ inner`, either possibly the identity (`None`).
fn compose_opt(outer: &Option<[f64; 12]>, inner: &Option<[f64; 12]>) -> Option<[f64; 12]> {
    match (outer, inner) {
        (None, t) | (t, None) => *t,
        (Some(a), Some(b)) => Some(compose(a, b)),
    }
}

fn uv(p: Vec3) -> Uv {
    [p.x, p.y]
}

/// Appends `more` to `out`, dropping the first point of `more` when it repeats the last of
/// `out` (the junction of two members or spans).
fn append(out: &mut Vec<Uv>, more: Vec<Uv>) {
    let skip = usize::from(out.last().is_some() && out.last() == more.first());
    out.extend(more.into_iter().skip(skip));
}

/// Builds the trims of 144s: samples their 142s' parameter-space curves into loops, or maps
/// their model-space curves onto the patch.
struct Sampler<'s, 'a> {
    file: &'s Sections<'a>,
    entries: &'s [Entry],
    /// Chord tolerance in the patch's parameters.
    tol: f64,
    points_left: usize,
    /// Curve entities this trim may still visit.
    curves_left: usize,
    /// The patch's parameter box with a margin, `[u0, u1, v0, v1]`: a trimming curve that
    /// leaves it is not in the patch's parameters.
    bounds: [f64; 4],
    /// Set when a curve met is of a kind that is not evaluated (104, 106, 112, 130).
    unsupported: bool,
    /// Maps model-space curves onto the patch.
    model: ModelSpace<'s>,
    /// The boundaries (142s, 141s) whose loops came from their model-space curves.
    from_model: Vec<IgesBoundary>,
    /// The kind of surface whose parameters the patch does not share (its B-spline is not
    /// parametrised as the IGES entity is: a 108, 118, 120, 122 or 190), if it is one: its
    /// boundaries are read from their model-space curves.
    foreign: Option<u32>,
}

impl<'s, 'a> Sampler<'s, 'a> {
    /// A sampler for the trims of a patch on `surface`, with `points_left` of the file's
    /// budget of trim points.
    fn new(
        file: &'s Sections<'a>,
        entries: &'s [Entry],
        surface: &'s Surface,
        factor: f64,
        points_left: usize,
    ) -> Self {
        let domain = surface.domain();
        let bb = surface.bounding_box();
        let size = (bb.max - bb.min).length();
        let size = if size.is_finite() { size } else { 1e3 };
        let tol_on = crate::io::on_surface_tolerance(size, file.resolution);
        let (mu, mv) = (
            BOX_MARGIN * (domain.u[1] - domain.u[0]),
            BOX_MARGIN * (domain.v[1] - domain.v[0]),
        );
        Sampler {
            file,
            entries,
            tol: 1e-6 * (domain.u[1] - domain.u[0]).hypot(domain.v[1] - domain.v[0]),
            points_left: points_left.min(MAX_TRIM_POINTS),
            curves_left: MAX_TRIM_CURVES,
            bounds: [
                domain.u[0] - mu,
                domain.u[1] + mu,
                domain.v[0] - mv,
                domain.v[1] + mv,
            ],
            unsupported: false,
            model: ModelSpace {
                inverter: Inverter::new(surface, tol_on, MAX_GRID_SEARCHES),
                factor,
                tol: (1e-5 * size).clamp(1e-9, 1e-3),
                tol_on,
                de: IgesBoundary { kind: 142, de: 0 },
                last: None,
            },
            from_model: Vec::new(),
            foreign: None,
        }
    }
}

/// Where a curve lives: in the patch's parameters (a 142's BPTR) or in model space (CPTR).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Space {
    Parameter,
    Model,
}

impl Space {
    fn name(self) -> &'static str {
        match self {
            Space::Parameter => "parameter-space",
            Space::Model => "model-space",
        }
    }
}

/// Maps samples of a model-space curve to the patch's parameters.
struct ModelSpace<'s> {
    /// Point inversion onto the patch's surface.
    inverter: Inverter<'s>,
    /// File units to mm.
    factor: f64,
    /// Chord tolerance (mm): the surface point at the middle of a chord in parameters stays
    /// this close to the curve's own point there.
    tol: f64,
    /// Farthest a sample may lie from the surface (mm).
    tol_on: f64,
    /// The 142 being mapped.
    de: IgesBoundary,
    /// The parameters of the loop's latest sample (the seed of the next).
    last: Option<Uv>,
}

impl ModelSpace<'_> {
    /// Samples `f` (in the file's coordinates, transforms applied) over `[a, b]`, from `n`
    /// equal steps halved until the chords, in parameters, stay within [`ModelSpace::tol`] of
    /// the curve on the surface; each sample mapped to the patch's parameters, seeded by the
    /// previous one. `budget`: points that may still be mapped.
    fn sample(
        &mut self,
        f: &impl Fn(f64) -> Vec3,
        a: f64,
        b: f64,
        n: usize,
        budget: &mut usize,
    ) -> Built<Vec<Uv>> {
        let n = n.max(1);
        let mut out = Vec::new();
        let mut prev: Option<(f64, Uv)> = None;
        for k in 0..=n {
            let t = if k == n {
                b
            } else {
                a + (b - a) * k as f64 / n as f64
            };
            let seed = prev.map(|p| p.1).or(self.last);
            let q = self.map(f(t), seed, budget)?;
            match prev {
                None => out.push(q),
                Some(p) => self.refine(f, p, (t, q), 0, &mut out, budget)?,
            }
            prev = Some((t, q));
        }
        self.last = out.last().copied();
        Ok(out)
    }

    fn refine(
        &mut self,
        f: &impl Fn(f64) -> Vec3,
        (ta, qa): (f64, Uv),
        (tb, qb): (f64, Uv),
        depth: u32,
        out: &mut Vec<Uv>,
        budget: &mut usize,
    ) -> Built<()> {
        let tm = 0.5 * (ta + tb);
        let qm = self.map(f(tm), Some(qa), budget)?;
        let dev = self.chord_gap(qa, qb, qm);
        if dev.is_nan() || dev > self.tol {
            if depth < MAX_HALVINGS {
                self.refine(f, (ta, qa), (tm, qm), depth + 1, out, budget)?;
                return self.refine(f, (tm, qm), (tb, qb), depth + 1, out, budget);
            }
            if dev.is_nan() || dev > self.tol_on {
                return Err(self.jumps());
            }
        }
        out.push(qb);
        Ok(())
    }

    /// How far the surface point at the middle of the chord `qa`–`qb` lies from that at `qm`.
    fn chord_gap(&self, qa: Uv, qb: Uv, qm: Uv) -> f64 {
        let s = self.inverter.surface();
        let mid = s.point(0.5 * (qa[0] + qb[0]), 0.5 * (qa[1] + qb[1]));
        (mid - s.point(qm[0], qm[1])).length()
    }

    fn jumps(&self) -> TrimFailure {
        TrimFailure::ModelJumps { de: self.de }
    }

    /// The parameters of the surface point nearest `x` (file units), or why not.
    fn map(&mut self, x: Vec3, seed: Option<Uv>, budget: &mut usize) -> Built<Uv> {
        if *budget == 0 {
            return Err(TrimFailure::ModelTooManyPoints {
                de: self.de,
                trim: MAX_TRIM_POINTS,
                file: MAX_FILE_TRIM_POINTS,
            });
        }
        *budget -= 1;
        let x = x * self.factor;
        let inv = self.inverter.invert(x, seed).map_err(|e| match e {
            InvertError::GridSearchesSpent { limit } => {
                TrimFailure::ModelSearchesSpent { de: self.de, limit }
            }
        })?;
        if inv.dist.is_nan() || inv.dist > self.tol_on {
            return Err(TrimFailure::ModelOffSurface {
                de: self.de,
                distance: inv.dist,
                point: x,
                tolerance: self.tol_on,
            });
        }
        if !(inv.uv[0].is_finite() && inv.uv[1].is_finite()) {
            return Err(TrimFailure::ModelNonFinite { de: self.de });
        }
        Ok(inv.uv)
    }

    /// Checks a mapped loop: it closes without a jump and has at least 3 distinct points.
    fn check_loop(&self, l: &[Uv]) -> Built<()> {
        let (Some(&first), Some(&last)) = (l.first(), l.last()) else {
            return Err(TrimFailure::ModelNoPoint { de: self.de });
        };
        // A curve closed in model space closes in the parameters: the closing chord's middle,
        // on the surface, lies near its ends (not across the surface, past a seam).
        let s = self.inverter.surface();
        let (a, b) = (s.point(first[0], first[1]), s.point(last[0], last[1]));
        let mid = s.point(0.5 * (first[0] + last[0]), 0.5 * (first[1] + last[1]));
        let gap = (mid - 0.5 * (a + b)).length();
        if (a - b).length() <= 2.0 * self.tol_on && (gap.is_nan() || gap > self.tol_on) {
            return Err(self.jumps());
        }
        let mut d = l.to_vec();
        d.dedup();
        if d.len() > 1 && d.first() == d.last() {
            d.pop();
        }
        if d.len() < 3 {
            return Err(TrimFailure::ModelTooFewPoints {
                de: self.de,
                points: d.len(),
            });
        }
        Ok(())
    }
}

/// A trim, or why it cannot be honoured.
type Built<T> = Result<T, TrimFailure>;

impl Sampler<'_, '_> {
    /// The trim of the 144 `e` (parameters `p`) on a patch over `domain`. `Ok(Err(why))` when it
    /// cannot be honoured; `Err` when the file is wrong.
    fn trim144(
        &mut self,
        e: &Entry,
        p: &Params,
        domain: &ParamBox,
    ) -> Result<Built<Trim>, ReadError> {
        let n2 = p.int(3, "N2")?.max(0) as usize;
        let pto = p.int(4, "PTO")?;
        let outer = if pto == 0 {
            None
        } else {
            match self.boundary142(p, 4, "outer boundary PTO")? {
                Ok(l) => Some(l),
                Err(why) => return Ok(Err(why)),
            }
        };
        let mut holes = Vec::with_capacity(n2);
        for k in 0..n2 {
            match self.boundary142(p, 5 + k, "inner boundary PTI")? {
                Ok(l) => holes.push(l),
                Err(why) => return Ok(Err(why)),
            }
        }
        let boxed = outer.is_none();
        Trim::new(domain, outer, holes).map(Ok).map_err(|err| {
            // The 142 whose loop is refused: the outer boundary's, then the inner ones'.
            let index = match err {
                TrimError::TooFewPoints { index, .. } | TrimError::NotFinite { index, .. } => index,
            };
            let at = if boxed {
                5 + index
            } else if index == 0 {
                4
            } else {
                4 + index
            };
            let c = p
                .int(at, "boundary")
                .ok()
                .and_then(|de| entry_at(self.entries, de));
            match c {
                Some(c) => syntax(
                    c.line,
                    1,
                    format!(
                        "entity 142 at D{} (a boundary of the 144 at D{}): {err}",
                        c.de, e.de
                    ),
                ),
                None => syntax(e.line, 1, format!("entity 144 at D{}: {err}", e.de)),
            }
        })
    }

    /// The trim of the 143 `e` (parameters `p`: TYPE, SPTR, N, then the N 141 boundaries) on a
    /// patch over `domain`: the loop enclosing the largest area in the parameters is the outer
    /// boundary, the others are holes (the 143 does not say which is which).
    fn trim143(
        &mut self,
        e: &Entry,
        p: &Params,
        domain: &ParamBox,
    ) -> Result<Built<Trim>, ReadError> {
        let n = p.count(3, "N")?;
        let mut loops = Vec::with_capacity(n);
        for k in 0..n {
            match self.boundary141(p, 4 + k)? {
                Ok(l) => loops.push(l),
                Err(why) => return Ok(Err(why)),
            }
        }
        let area = |l: &[Uv]| {
            l.iter()
                .zip(l.iter().cycle().skip(1))
                .map(|(a, b)| a[0] * b[1] - b[0] * a[1])
                .sum::<f64>()
                .abs()
        };
        let outer = (0..loops.len())
            .max_by(|&a, &b| area(&loops[a]).total_cmp(&area(&loops[b])))
            .map(|i| loops.remove(i));
        Trim::new(domain, outer, loops)
            .map(Ok)
            .map_err(|err| syntax(e.line, 1, format!("entity 143 at D{}: {err}", e.de)))
    }

    /// The loop of the 141 named by parameter `i` of `p`: its curves in order (TYPE, PREF,
    /// SPTR, N, then per curve CRVPT, SENSE, K and K parameter-space curves), each from its
    /// parameter-space curves when the boundary has them (TYPE 1), else from its model-space
    /// curve mapped onto the patch, reversed where SENSE is 2.
    fn boundary141(&mut self, p: &Params, i: usize) -> Result<Built<Vec<Uv>>, ReadError> {
        let de = p.int(i, "boundary BDPT")?;
        let Some(e) = entry_at(self.entries, de).filter(|e| e.kind == 141) else {
            return Err(p.error(
                i,
                match entry_at(self.entries, de) {
                    Some(e) => format!(
                        "boundary BDPT points at D{de}, an entity {}; expected a 141 (boundary)",
                        e.kind
                    ),
                    None => {
                        format!("boundary BDPT points at D{de}, which is not a directory entry")
                    }
                },
            ));
        };
        let q = self.file.params(e)?;
        let kind = q.int(1, "TYPE")?;
        let n = q.count(4, "N")?;
        let b141 = IgesBoundary {
            kind: 141,
            de: e.de,
        };
        self.model.de = b141;
        self.model.last = None;
        let mut out = Vec::new();
        let mut at = 5;
        let mut mapped = false;
        for _ in 0..n {
            let sense = q.int(at + 1, "SENSE")?;
            let k = q.count(at + 2, "K")?;
            let mut piece = None;
            let mut failed = None;
            if kind == 1 && k > 0 && self.foreign.is_none() {
                self.unsupported = false;
                let mut pts = Vec::new();
                for c in 0..k {
                    match self.curve(&q, at + 3 + c, "PSCPT", None, 0, Space::Parameter)? {
                        Ok(v) => append(&mut pts, v),
                        Err(why) => {
                            failed = Some(why);
                            break;
                        }
                    }
                }
                if failed.is_none() {
                    piece = Some(pts);
                }
            }
            let piece = match (piece, failed) {
                (Some(piece), _) => piece,
                (None, Some(why)) if !self.unsupported => {
                    return Ok(Err(TrimFailure::Boundary {
                        de: b141,
                        reason: Box::new(why),
                    }))
                }
                (None, _) if q.int(at, "CRVPT")? == 0 && k > 0 && self.foreign.is_some() => {
                    return Ok(Err(TrimFailure::Boundary {
                        de: b141,
                        reason: Box::new(self.foreign_parameters(e, q.int(at + 3, "PSCPT")?)),
                    }))
                }
                (None, _) if q.int(at, "CRVPT")? == 0 => {
                    return Ok(Err(TrimFailure::NoCurve { de: b141 }))
                }
                (None, _) => {
                    mapped = true;
                    match self.curve(&q, at, "CRVPT", None, 0, Space::Model) {
                        Ok(Ok(v)) => v,
                        Ok(Err(why)) if why.names_its_boundary() => return Ok(Err(why)),
                        Ok(Err(why)) => {
                            return Ok(Err(TrimFailure::Boundary {
                                de: b141,
                                reason: Box::new(why),
                            }))
                        }
                        Err(err) => {
                            return Ok(Err(TrimFailure::ModelUnreadable {
                                de: b141,
                                reason: Box::new(err),
                            }))
                        }
                    }
                }
            };
            let piece = if sense == 2 {
                piece.into_iter().rev().collect()
            } else {
                piece
            };
            append(&mut out, piece);
            at += 3 + k;
        }
        if mapped {
            if let Err(why) = self.model.check_loop(&out) {
                return Ok(Err(why));
            }
            self.from_model.push(b141);
        }
        Ok(Ok(out))
    }

    /// Why the parameter-space curve `de` of the boundary `e` is not used: the patch is not
    /// parametrised as the IGES surface is.
    fn foreign_parameters(&self, e: &Entry, de: i64) -> TrimFailure {
        TrimFailure::Entity(Box::new(ReadError::Entity {
            format: Format::Iges,
            line: e.line,
            entity: format!("its parameter-space curve D{de}"),
            message: format!(
                "it is in the parameters of the IGES {} surface, which its B-spline or plane here \
                 does not share, and the boundary has no model-space curve",
                self.foreign.unwrap_or(0)
            ),
        }))
    }

    /// The trim of the 108 `e` (parameters `p`, its own transformation `t`) by its bounding
    /// curve PTR, in model space, mapped onto its plane over `domain`: the outer boundary, or a
    /// hole (form −1).
    fn bound108(
        &mut self,
        e: &Entry,
        p: &Params,
        t: Option<[f64; 12]>,
        hole: bool,
        domain: &ParamBox,
    ) -> Result<Built<Trim>, ReadError> {
        let b = IgesBoundary {
            kind: 108,
            de: e.de,
        };
        self.model.de = b;
        self.model.last = None;
        let l = match self.curve(p, 5, "PTR", t, 0, Space::Model) {
            Ok(Ok(l)) => match self.model.check_loop(&l) {
                Ok(()) => l,
                Err(why) => return Ok(Err(why)),
            },
            Ok(Err(why)) if why.names_its_boundary() => return Ok(Err(why)),
            Ok(Err(why)) => {
                return Ok(Err(TrimFailure::Boundary {
                    de: b,
                    reason: Box::new(why),
                }))
            }
            Err(err) => {
                return Ok(Err(TrimFailure::ModelUnreadable {
                    de: b,
                    reason: Box::new(err),
                }))
            }
        };
        self.from_model.push(b);
        let (outer, holes) = if hole {
            (None, vec![l])
        } else {
            (Some(l), Vec::new())
        };
        Ok(Trim::new(domain, outer, holes).map_err(TrimFailure::Trim))
    }

    /// The loop of the 142 named by parameter `i` of `p`: from its parameter-space curve
    /// (BPTR), or, when it has none or one of a kind not evaluated, from its model-space curve
    /// (CPTR) mapped onto the patch.
    fn boundary142(
        &mut self,
        p: &Params,
        i: usize,
        what: &str,
    ) -> Result<Built<Vec<Uv>>, ReadError> {
        let de = p.int(i, what)?;
        let Some(e) = entry_at(self.entries, de).filter(|e| e.kind == 142) else {
            return Err(p.error(
                i,
                match entry_at(self.entries, de) {
                    Some(e) => format!(
                        "{what} points at D{de}, an entity {}; expected a 142 (curve on a parametric surface)",
                        e.kind
                    ),
                    None => format!("{what} points at D{de}, which is not a directory entry"),
                },
            ));
        };
        let q = self.file.params(e)?;
        let bptr = q.int(3, "BPTR")?;
        let cptr = q.int(4, "CPTR")?;
        let b142 = IgesBoundary {
            kind: 142,
            de: e.de,
        };
        let mut failed = None;
        if bptr != 0 && cptr == 0 && self.foreign.is_some() {
            return Ok(Err(TrimFailure::Boundary {
                de: b142,
                reason: Box::new(self.foreign_parameters(e, bptr)),
            }));
        }
        if bptr != 0 && self.foreign.is_none() {
            self.unsupported = false;
            match self.curve(&q, 3, "BPTR", None, 0, Space::Parameter)? {
                Ok(l) => return Ok(Ok(l)),
                Err(why) if self.unsupported && cptr != 0 => failed = Some(why),
                Err(why) => {
                    return Ok(Err(TrimFailure::Boundary {
                        de: b142,
                        reason: Box::new(why),
                    }))
                }
            }
        } else if cptr == 0 {
            return Ok(Err(TrimFailure::NoCurve { de: b142 }));
        }
        self.model.de = b142;
        self.model.last = None;
        // A model-space curve that cannot be read leaves the patch untrimmed (as it was before
        // such curves were read), not the file unread.
        let mapped = match self.curve(&q, 4, "CPTR", None, 0, Space::Model) {
            Ok(Ok(l)) => self.model.check_loop(&l).map(|()| l),
            Ok(Err(why)) if why.names_its_boundary() => Err(why),
            Ok(Err(why)) => Err(TrimFailure::Boundary {
                de: b142,
                reason: Box::new(why),
            }),
            Err(err) => Err(TrimFailure::ModelUnreadable {
                de: b142,
                reason: Box::new(err),
            }),
        };
        Ok(match (mapped, failed) {
            (Ok(l), _) => {
                self.from_model.push(b142);
                Ok(l)
            }
            (Err(why), None) => Err(why),
            (Err(why), Some(first)) => Err(TrimFailure::BothCurves {
                de: b142,
                parameter: Box::new(first),
                model: Box::new(why),
            }),
        })
    }

    /// The curve named by parameter `i` of `p`, mapped by `outer` (the transforms of the
    /// entities holding it), sampled: a parameter-space curve as it is, a model-space one mapped
    /// onto the patch.
    fn curve(
        &mut self,
        p: &Params,
        i: usize,
        what: &str,
        outer: Option<[f64; 12]>,
        depth: usize,
        space: Space,
    ) -> Result<Built<Vec<Uv>>, ReadError> {
        let de = p.int(i, what)?;
        let Some(e) = entry_at(self.entries, de) else {
            return Err(p.error(
                i,
                format!("{what} points at D{de}, which is not a directory entry"),
            ));
        };
        if self.curves_left == 0 {
            return Ok(Err(TrimFailure::TooManyCurves {
                max: MAX_TRIM_CURVES,
            }));
        }
        self.curves_left -= 1;
        let t = compose_opt(&outer, &self.file.transform(self.entries, e)?);
        let pts = match e.kind {
            126 => {
                // `curve126` applies the curve's own transform; the outer ones are left.
                let mut c = self.file.curve126(e, self.entries, 1.0)?;
                c.points.iter_mut().for_each(|q| *q = apply(&outer, *q));
                let (m, n) = (c.degree, c.points.len());
                let lo = c.range[0].max(c.knots[m]);
                let hi = c.range[1].min(c.knots[n]);
                // Knots and range are finite (read as such).
                if lo >= hi {
                    return Err(self.file.params(e)?.error(
                        7 + c.knots.len() + 4 * n,
                        format!(
                            "entity 126 at D{}: its range [{}, {}] leaves nothing of the knots' [{}, {}]",
                            e.de, c.range[0], c.range[1], c.knots[m], c.knots[n]
                        ),
                    ));
                }
                let spline = match c.spline() {
                    Ok(spline) => spline,
                    Err(reason) => return Ok(Err(TrimFailure::Curve126 { de: e.de, reason })),
                };
                let mut out = Vec::new();
                for s in m..n {
                    let (a, b) = (c.knots[s].max(lo), c.knots[s + 1].min(hi));
                    if a < b {
                        let piece = match self.piece(
                            space,
                            &|x| spline.point(x),
                            a,
                            b,
                            SEGMENTS_PER_SPAN,
                        ) {
                            Ok(piece) => piece,
                            Err(why) => return Ok(Err(why)),
                        };
                        append(&mut out, piece);
                        if space == Space::Parameter {
                            if out.len() > self.points_left {
                                return Ok(Err(self.too_many()));
                            }
                            if let Some(why) = self.outside(&out, de) {
                                return Ok(Err(why));
                            }
                        }
                    }
                }
                Ok(out)
            }
            110 => {
                let q = self.file.params(e)?;
                let mut v = [0.0; 6];
                for (k, x) in v.iter_mut().enumerate() {
                    *x = q.real(1 + k, "line coordinate")?;
                }
                let (a, b) = (
                    apply(&t, Vec3::new(v[0], v[1], v[2])),
                    apply(&t, Vec3::new(v[3], v[4], v[5])),
                );
                match space {
                    Space::Parameter => Ok(vec![uv(a), uv(b)]),
                    Space::Model => {
                        self.piece(space, &|s| a + (b - a) * s, 0.0, 1.0, SEGMENTS_PER_SPAN)
                    }
                }
            }
            100 => {
                let q = self.file.params(e)?;
                let mut v = [0.0; 7];
                for (k, x) in v.iter_mut().enumerate() {
                    *x = q.real(1 + k, "arc parameter")?;
                }
                let [zt, cx, cy, x0, y0, x1, y1] = v;
                let r = (x0 - cx).hypot(y0 - cy);
                let a0 = (y0 - cy).atan2(x0 - cx);
                let mut a1 = (y1 - cy).atan2(x1 - cx);
                if a1 <= a0 || (x0, y0) == (x1, y1) {
                    a1 += std::f64::consts::TAU;
                }
                if !r.is_finite() || r == 0.0 {
                    return Err(q.error(
                        2,
                        format!("entity 100 at D{}: the arc has no radius", e.de),
                    ));
                }
                let quarters = ((a1 - a0) / std::f64::consts::FRAC_PI_2).ceil().max(1.0) as usize;
                self.piece(
                    space,
                    &|a| apply(&t, Vec3::new(cx + r * a.cos(), cy + r * a.sin(), zt)),
                    a0,
                    a1,
                    SEGMENTS_PER_SPAN * quarters,
                )
            }
            102 => {
                if depth >= MAX_NESTING {
                    return Err(p.error(
                        i,
                        format!(
                            "{what} D{de}: composite curves nest more than {MAX_NESTING} deep (a cycle?)"
                        ),
                    ));
                }
                let q = self.file.params(e)?;
                let n = q.count(1, "N")?;
                let mut out = Vec::new();
                for k in 0..n {
                    match self.curve(&q, 2 + k, "composite member", t, depth + 1, space)? {
                        Ok(piece) => append(&mut out, piece),
                        Err(why) => return Ok(Err(why)),
                    }
                }
                Ok(out)
            }
            104 | 106 | 112 | 130 => {
                self.unsupported = true;
                Err(TrimFailure::UnsupportedCurve {
                    space: space.name(),
                    de,
                    kind: e.kind,
                })
            }
            k => {
                return Err(p.error(
                    i,
                    format!("{what} points at D{de}, an entity {k}; expected a curve (100, 102, 110 or 126)"),
                ))
            }
        };
        if space == Space::Model {
            // Points were counted as they were mapped; the patch's box holds them all.
            return Ok(pts);
        }
        let outside = match &pts {
            Ok(v) if e.kind != 102 => self.outside(v, de),
            _ => None,
        };
        Ok(match (pts, outside) {
            (Ok(v), _) if v.len() > self.points_left => Err(self.too_many()),
            (Ok(_), Some(why)) | (Err(why), _) => Err(why),
            (Ok(v), None) => {
                self.points_left -= v.len();
                Ok(v)
            }
        })
    }

    /// Samples one piece of a curve, `f` over `[a, b]` from at least `n` steps: in parameter
    /// space its x and y to the chord tolerance, in model space mapped onto the patch.
    fn piece(
        &mut self,
        space: Space,
        f: &impl Fn(f64) -> Vec3,
        a: f64,
        b: f64,
        n: usize,
    ) -> Built<Vec<Uv>> {
        match space {
            Space::Parameter => Ok(sample_curve(|x| uv(f(x)), a, b, n, self.tol)),
            Space::Model => self.model.sample(f, a, b, n, &mut self.points_left),
        }
    }

    /// Why `pts`, sampled from the curve at `de`, are not in the patch's parameters, if they
    /// are not.
    fn outside(&self, pts: &[Uv], de: i64) -> Option<TrimFailure> {
        let [u0, u1, v0, v1] = self.bounds;
        let p = pts
            .iter()
            .find(|p| !(p[0] >= u0 && p[0] <= u1 && p[1] >= v0 && p[1] <= v1))?;
        Some(TrimFailure::OutsideBox {
            de,
            u: p[0],
            v: p[1],
        })
    }

    fn too_many(&self) -> TrimFailure {
        TrimFailure::LoopsTooManyPoints {
            trim: MAX_TRIM_POINTS,
            file: MAX_FILE_TRIM_POINTS,
        }
    }
}

/// One physical record: its 1-based line number and columns 1–72, one byte per column (a
/// column that is not ASCII is `?` here; `text` keeps it).
struct Record<'a> {
    line: usize,
    /// The sequence number (columns 74–80), if it is one.
    seq: Option<usize>,
    data: Cow<'a, str>,
    /// The columns as characters, for a record that is not all ASCII (labels keep their
    /// accents).
    text: Option<Vec<char>>,
}

/// The sequence number in columns 74–80, if they hold one.
fn sequence(cols: &[u8]) -> Option<usize> {
    std::str::from_utf8(cols).ok()?.trim().parse().ok()
}

/// A record's columns, or `None` when it has no section letter in column 73. An ASCII record
/// is its bytes. Any other is read by bytes (Latin-1: each byte one column, as the fixed
/// 80-column format counts them) when that puts a section letter in column 73 and digits or
/// spaces after it, else by UTF-8 characters when that does (files written by character count).
fn columns(raw: &[u8]) -> Option<Vec<char>> {
    let good = |c: &[char]| {
        c.len() >= 73
            && c[72].is_ascii_uppercase()
            && c[73..c.len().min(80)]
                .iter()
                .all(|x| x.is_ascii_digit() || *x == ' ')
    };
    let bytes: Vec<char> = raw.iter().map(|&b| char::from(b)).collect();
    if good(&bytes) {
        return Some(bytes);
    }
    std::str::from_utf8(raw)
        .ok()
        .map(|t| t.chars().collect::<Vec<char>>())
        .filter(|c| good(c))
}

struct Sections<'a> {
    g: Vec<Record<'a>>,
    d: Vec<Record<'a>>,
    p: Vec<Record<'a>>,
    pdelim: u8,
    rdelim: u8,
    /// The G section's minimum resolution, mm (0 when not given), once it is read.
    resolution: f64,
}

fn syntax(line: usize, column: usize, message: impl Into<String>) -> ReadError {
    ReadError::Syntax {
        format: Format::Iges,
        line,
        column,
        message: message.into(),
    }
}

struct Global {
    factor: f64,
    unit: String,
}

struct Entry {
    de: usize,
    line: usize,
    kind: u32,
    pointer: usize,
    lines: usize,
    transform: usize,
    /// The form number (DE field 15).
    form: i64,
    label: Option<String>,
}

impl<'a> Sections<'a> {
    fn split(text: &'a [u8]) -> Result<Self, ReadError> {
        let mut s = Sections {
            g: Vec::new(),
            d: Vec::new(),
            p: Vec::new(),
            pdelim: b',',
            rdelim: b';',
            resolution: 0.0,
        };
        let mut seen_any = false;
        // Records end in LF or CRLF; in a file with neither, in a lone CR (old Macs) or — a
        // file of 80-byte records and no line ends at all, as some mainframe-era writers made
        // them — every 80 bytes.
        let records: Box<dyn Iterator<Item = &[u8]>> = if text.contains(&b'\n') {
            Box::new(text.split(|&b| b == b'\n'))
        } else if text.contains(&b'\r') {
            Box::new(text.split(|&b| b == b'\r'))
        } else if text.len() > 80 && text.len() % 80 == 0 {
            Box::new(text.chunks(80))
        } else {
            Box::new(std::iter::once(text))
        };
        for (i, raw) in records.enumerate() {
            let line = i + 1;
            let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
            if raw.iter().all(u8::is_ascii_whitespace) {
                continue;
            }
            let (rec, letter) = if raw.is_ascii() && raw.len() >= 73 {
                // ASCII (and so UTF-8) throughout.
                let data = std::str::from_utf8(&raw[..72]).unwrap_or_default();
                let rec = Record {
                    line,
                    seq: sequence(&raw[73..raw.len().min(80)]),
                    data: Cow::Borrowed(data),
                    text: None,
                };
                (rec, raw[72])
            } else {
                // Text in the Start section or in strings need not be ASCII (accents in
                // European files): such columns are read as one column each.
                let Some(cols) = columns(raw).filter(|_| !raw.is_ascii()) else {
                    return Err(syntax(
                        line,
                        raw.len().min(72) + 1,
                        format!(
                            "found a {}-column record, expected 80 columns with the section letter in column 73",
                            raw.len()
                        ),
                    ));
                };
                let data = cols[..72]
                    .iter()
                    .map(|&c| if c.is_ascii() { c } else { '?' })
                    .collect();
                let letter = cols[72] as u8;
                let seq: String = cols[73..cols.len().min(80)].iter().collect();
                let rec = Record {
                    line,
                    seq: sequence(seq.as_bytes()),
                    data: Cow::Owned(data),
                    text: Some(cols),
                };
                (rec, letter)
            };
            seen_any = true;
            match letter {
                b'S' | b'T' => {}
                b'G' => s.g.push(rec),
                b'D' => s.d.push(rec),
                b'P' => s.p.push(rec),
                b'C' => {
                    return Err(syntax(
                        line,
                        73,
                        "compressed IGES (section C) is not supported",
                    ))
                }
                b'B' | b'F' => return Err(syntax(line, 73, "binary IGES is not supported")),
                c => {
                    return Err(syntax(
                        line,
                        73,
                        format!(
                            "found section letter `{}`, expected S, G, D, P or T",
                            c as char
                        ),
                    ))
                }
            }
        }
        if !seen_any {
            return Err(syntax(1, 1, "found no records, expected an IGES file"));
        }
        if s.g.is_empty() {
            return Err(syntax(1, 73, "no global (G) section"));
        }
        Ok(s)
    }

    fn global(&mut self) -> Result<Global, ReadError> {
        let text: String = self.g.iter().map(|r| &*r.data).collect();
        let b = text.as_bytes();
        let line = self.g[0].line;
        let mut pos = 0;
        // Field 1: "1Hc" or empty (default ','); field 2 likewise with default ';'.
        let mut pd = b',';
        if b.starts_with(b"1H") && b.len() > 2 {
            pd = b[2];
            pos = 3;
        }
        if b.get(pos) != Some(&pd) {
            return Err(syntax(
                line,
                pos + 1,
                "expected the parameter delimiter after field 1 of the G section",
            ));
        }
        pos += 1;
        let mut rd = b';';
        if b[pos..].starts_with(b"1H") && b.len() > pos + 2 {
            rd = b[pos + 2];
            pos += 3;
        }
        if pd == rd || pd.is_ascii_digit() || rd.is_ascii_digit() || pd == b' ' || rd == b' ' {
            return Err(syntax(
                line,
                1,
                "invalid parameter/record delimiters in the G section",
            ));
        }
        self.pdelim = pd;
        self.rdelim = rd;
        let rest = &text[pos..];
        // Fields 3 onwards, after the delimiter that ends field 2. Only fields 14 and 15 are
        // used: a string after them that does not parse (a Hollerith count that overruns, as
        // when a file's accents were counted in another encoding) is no error.
        let fields = match rest.as_bytes().first() {
            Some(&c) if c == pd => match tokenize_prefix(&rest[1..], pd, rd) {
                (fields, Some((at, m))) if fields.len() < 13 => {
                    // The record and column of the offset in the G section's data.
                    let o = pos + 1 + at;
                    let r = self.g.get(o / 72).map_or(line, |r| r.line);
                    return Err(syntax(r, o % 72 + 1, m));
                }
                (fields, _) => fields,
            },
            _ => Vec::new(),
        };
        // Fields 3.. are at index 0..; units flag is field 14 → index 11, name field 15 → 12.
        let flag = fields
            .get(11)
            .and_then(|t| t.trim().parse::<f64>().ok())
            .map_or(1, |f| f as i64);
        let name = fields.get(12).map(|t| hollerith(t).to_ascii_uppercase());
        let by_name = |n: &str| -> Option<(f64, &'static str)> {
            Some(match n {
                "IN" | "INCH" => (25.4, "inch"),
                "MM" => (1.0, "mm"),
                "FT" => (304.8, "foot"),
                "MI" => (1_609_344.0, "mile"),
                "M" => (1000.0, "metre"),
                "KM" => (1e6, "km"),
                "MIL" => (0.0254, "mil"),
                "UM" => (0.001, "micron"),
                "CM" => (10.0, "cm"),
                "UIN" => (2.54e-5, "microinch"),
                _ => return None,
            })
        };
        let (factor, unit) = match flag {
            1 => (25.4, "inch"),
            2 => (1.0, "mm"),
            3 => name.as_deref().and_then(by_name).ok_or_else(|| {
                syntax(
                    line,
                    1,
                    format!(
                        "units flag 3 with unknown unit name {:?}",
                        name.as_deref().unwrap_or("")
                    ),
                )
            })?,
            4 => (304.8, "foot"),
            5 => (1_609_344.0, "mile"),
            6 => (1000.0, "metre"),
            7 => (1e6, "km"),
            8 => (0.0254, "mil"),
            9 => (0.001, "micron"),
            10 => (10.0, "cm"),
            11 => (2.54e-5, "microinch"),
            f => {
                return Err(syntax(
                    line,
                    1,
                    format!("units flag {f} in the G section; expected 1 to 11"),
                ))
            }
        };
        // Field 19 → index 16, the minimum user-intended resolution: the distance below
        // which the file's points are one (a trimming curve may lie that far off its surface).
        let resolution = fields
            .get(16)
            .and_then(|t| t.trim().replace(['D', 'd'], "E").parse::<f64>().ok())
            .filter(|r| r.is_finite() && *r > 0.0)
            .map_or(0.0, |r| r * factor);
        self.resolution = resolution;
        Ok(Global {
            factor,
            unit: unit.into(),
        })
    }

    fn directory(&self) -> Result<Vec<Entry>, ReadError> {
        if self.d.len() % 2 != 0 {
            let l = self.d.last().map_or(1, |r| r.line);
            return Err(syntax(
                l,
                1,
                "odd number of directory (D) records; entries take two",
            ));
        }
        let mut out = Vec::with_capacity(self.d.len() / 2);
        for (k, pair) in self.d.chunks(2).enumerate() {
            let (a, b) = (&pair[0], &pair[1]);
            let int = |r: &Record, i: usize, what: &str| -> Result<usize, ReadError> {
                let f = field(r, i);
                if f.is_empty() {
                    return Ok(0);
                }
                f.parse::<i64>().map(|v| v.max(0) as usize).map_err(|_| {
                    syntax(
                        r.line,
                        8 * i + 1,
                        format!("found `{f}`, expected an integer {what}"),
                    )
                })
            };
            let kind = int(a, 0, "entity type")?;
            if int(b, 0, "entity type")? != kind {
                return Err(syntax(
                    b.line,
                    1,
                    "the two directory records of an entry disagree on the entity type",
                ));
            }
            let label = match &b.text {
                // A label with accents keeps them.
                Some(cols) => cols[56..64].iter().collect::<String>().trim().to_string(),
                None => field(b, 7).to_string(),
            };
            out.push(Entry {
                de: 2 * k + 1,
                line: a.line,
                kind: kind as u32,
                pointer: int(a, 1, "parameter data pointer")?,
                lines: int(b, 3, "parameter line count")?,
                transform: int(a, 6, "transformation matrix pointer")?,
                form: field(b, 4).parse::<i64>().unwrap_or(0),
                label: (!label.is_empty()).then_some(label),
            });
        }
        // Pointers name entries by sequence number. Entries out of order whose sequence
        // numbers are those of the positions (1, 3, 5…, each pair n, n + 1) are put in order;
        // otherwise the positions count.
        let seqs: Option<Vec<usize>> = self
            .d
            .chunks(2)
            .map(|pair| match (pair[0].seq, pair[1].seq) {
                (Some(a), Some(b)) if b == a + 1 => Some(a),
                _ => None,
            })
            .collect();
        if let Some(seqs) = seqs {
            let mut sorted = seqs.clone();
            sorted.sort_unstable();
            if sorted.iter().enumerate().all(|(k, &s)| s == 2 * k + 1) && sorted != seqs {
                let mut order: Vec<(usize, Entry)> = seqs.into_iter().zip(out).collect();
                order.sort_unstable_by_key(|(s, _)| *s);
                out = order
                    .into_iter()
                    .map(|(s, e)| Entry { de: s, ..e })
                    .collect();
            }
        }
        Ok(out)
    }

    /// The parameters of an entity, with their record positions.
    fn params(&self, e: &Entry) -> Result<Params, ReadError> {
        let start = e.pointer;
        let n = e.lines.max(1);
        if start == 0 || start > self.p.len() || start - 1 + n > self.p.len() {
            return Err(syntax(
                e.line,
                9,
                format!(
                    "entity {} at D{}: parameter data at P{start} ({n} records) is outside the P section ({} records)",
                    e.kind,
                    e.de,
                    self.p.len()
                ),
            ));
        }
        let recs = &self.p[start - 1..start - 1 + n];
        let mut text = String::new();
        let mut starts = Vec::with_capacity(n);
        for r in recs {
            starts.push((text.len(), r.line));
            text.push_str(&r.data[..64]);
        }
        let toks = tokenize(&text, self.pdelim, self.rdelim).map_err(|(at, m)| {
            let (line, col) = locate(&starts, at);
            syntax(line, col, m)
        })?;
        let mut values = Vec::with_capacity(toks.len());
        let mut offset = 0;
        for t in toks {
            let at = text[offset..].find(t).map_or(offset, |i| offset + i);
            offset = at + t.len();
            values.push((t.trim().to_string(), locate(&starts, at)));
        }
        let kind = values
            .first()
            .and_then(|(t, _)| t.parse::<u32>().ok())
            .unwrap_or(u32::MAX);
        if kind != e.kind {
            let (l, c) = values.first().map_or((recs[0].line, 1), |v| v.1);
            return Err(syntax(
                l,
                c,
                format!(
                    "parameter data of D{} starts with `{}`, expected entity type {}",
                    e.de,
                    values.first().map_or("", |v| v.0.as_str()),
                    e.kind
                ),
            ));
        }
        Ok(Params {
            values,
            end: recs.last().map_or((0, 0), |r| (r.line, 65)),
        })
    }

    fn transform(&self, entries: &[Entry], owner: &Entry) -> Result<Option<[f64; 12]>, ReadError> {
        let mut total: Option<[f64; 12]> = None;
        let mut depth = 0;
        let mut ptr = owner.transform;
        while ptr != 0 {
            depth += 1;
            let e = entries
                .get((ptr.saturating_sub(1)) / 2)
                .filter(|e| e.de == ptr && e.kind == 124);
            let Some(e) = e.filter(|_| depth <= 8) else {
                return Err(syntax(
                    owner.line,
                    49,
                    format!("D{}: transformation pointer D{ptr} is not an entity 124 (or chains too deep)", owner.de),
                ));
            };
            let p = self.params(e)?;
            let mut m = [0.0; 12];
            for (k, x) in m.iter_mut().enumerate() {
                *x = p.real(1 + k, "matrix element")?;
            }
            // Outer transforms apply after inner ones: total = m ∘ total.
            total = Some(match total {
                None => m,
                Some(t) => compose(&m, &t),
            });
            ptr = e.transform;
        }
        Ok(total)
    }

    /// Adds to `seen` the DEs of the 126 curves at `de` or among the members of the composite
    /// curve (102) at `de`, nested up to [`MAX_NESTING`] deep, and of the composites visited
    /// (each once); what cannot be read is passed over.
    fn curves_126_under(
        &self,
        entries: &[Entry],
        de: i64,
        depth: usize,
        seen: &mut HashSet<usize>,
    ) {
        let Some(e) = entry_at(entries, de) else {
            return;
        };
        if !matches!(e.kind, 102 | 126) || depth > MAX_NESTING || !seen.insert(e.de) {
            return;
        }
        if e.kind == 102 {
            let Ok(q) = self.params(e) else {
                return;
            };
            let n = q.count(1, "N").unwrap_or(0);
            for k in 0..n {
                if let Ok(m) = q.int(2 + k, "member") {
                    self.curves_126_under(entries, m, depth + 1, seen);
                }
            }
        }
    }

    fn surface128(
        &self,
        e: &Entry,
        entries: &[Entry],
        factor: f64,
    ) -> Result<NurbsSurface, ReadError> {
        let p = self.params(e)?;
        let k1 = p.count(1, "K1")?;
        let k2 = p.count(2, "K2")?;
        let m1 = p.count(3, "M1")?;
        let m2 = p.count(4, "M2")?;
        let (nu, nv) = (k1 + 1, k2 + 1);
        let (a, b) = (k1 + m1 + 2, k2 + m2 + 2);
        let need = 10 + a + b + 4 * nu * nv + 4;
        if p.values.len() < need {
            return Err(p.error(p.values.len(), format!(
                "entity 128 at D{} has {} parameters; K1 = {k1}, K2 = {k2}, M1 = {m1}, M2 = {m2} need {need}",
                e.de,
                p.values.len()
            )));
        }
        let mut i = 10;
        let mut take = |n: usize, what: &str| -> Result<Vec<f64>, ReadError> {
            let v = (i..i + n).map(|k| p.real(k, what)).collect();
            i += n;
            v
        };
        let ku = take(a, "u knot")?;
        let kv = take(b, "v knot")?;
        let w = take(nu * nv, "weight")?;
        let c = take(3 * nu * nv, "control point coordinate")?;
        let t = self.transform(entries, e)?;
        // The file lists u fastest: index (j·nu + i).
        let points: Vec<Vec<Vec3>> = (0..nu)
            .map(|iu| {
                (0..nv)
                    .map(|jv| {
                        let k = 3 * (jv * nu + iu);
                        apply(&t, Vec3::new(c[k], c[k + 1], c[k + 2])) * factor
                    })
                    .collect()
            })
            .collect();
        let weights: Vec<Vec<f64>> = (0..nu)
            .map(|iu| (0..nv).map(|jv| w[jv * nu + iu]).collect())
            .collect();
        let surface_error = |reason| ReadError::Surface {
            format: Format::Iges,
            line: e.line,
            entity: format!("entity 128 at D{}", e.de),
            reason,
        };
        let s =
            NurbsSurface::new(m1, m2, ku, kv, &points, Some(&weights)).map_err(surface_error)?;
        // The parameter range U0, U1, V0, V1 (the last four values) bounds the surface within
        // its knots, as a 126's V0, V1 bound its curve: the surface is what both allow. Bounds
        // within 1e-9 of the domain's span of its ends are the ends (rounding, not a cut).
        let at = 10 + a + b + 4 * nu * nv;
        let range = [
            take(2, "parameter range U0, U1")?,
            take(2, "parameter range V0, V1")?,
        ];
        let d = s.domain();
        let cut = |r: &[f64], dd: [f64; 2]| {
            let eps = 1e-9 * (dd[1] - dd[0]);
            [
                if r[0] <= dd[0] + eps { dd[0] } else { r[0] },
                if r[1] >= dd[1] - eps { dd[1] } else { r[1] },
            ]
        };
        let (u, v) = (cut(&range[0], d.u), cut(&range[1], d.v));
        if (u, v) == (d.u, d.v) {
            return Ok(s);
        }
        for (k, r, dd, dir) in [(at, &range[0], d.u, "U"), (at + 2, &range[1], d.v, "V")] {
            let c = cut(r, dd);
            if c[0] >= c[1] {
                return Err(p.error(
                    k,
                    format!(
                        "entity 128 at D{}: its parameter range {dir}0, {dir}1 = [{}, {}] leaves nothing of the knots' [{}, {}]",
                        e.de, r[0], r[1], dd[0], dd[1]
                    ),
                ));
            }
        }
        s.restricted(u, v).map_err(surface_error)
    }

    fn curve126(&self, e: &Entry, entries: &[Entry], factor: f64) -> Result<IgesCurve, ReadError> {
        let p = self.params(e)?;
        let k = p.count(1, "K")?;
        let m = p.count(2, "M")?;
        let n = k + 1;
        let a = k + m + 2;
        let need = 7 + a + 4 * n + 2;
        if p.values.len() < need || m == 0 || m > k {
            return Err(p.error(p.values.len().min(2), format!(
                "entity 126 at D{}: K = {k}, M = {m} with {} parameters (needs M ≥ 1, K ≥ M and {need} parameters)",
                e.de,
                p.values.len()
            )));
        }
        let knots = (7..7 + a)
            .map(|i| p.real(i, "knot"))
            .collect::<Result<Vec<_>, _>>()?;
        if knots.windows(2).any(|w| w[1] < w[0]) {
            return Err(p.error(7, format!("entity 126 at D{}: knots decrease", e.de)));
        }
        let weights = (7 + a..7 + a + n)
            .map(|i| p.real(i, "weight"))
            .collect::<Result<Vec<_>, _>>()?;
        if let Some(j) = weights.iter().position(|w| w.is_nan() || *w <= 0.0) {
            return Err(p.error(
                7 + a + j,
                format!("entity 126 at D{}: weight {j} is not positive", e.de),
            ));
        }
        let t = self.transform(entries, e)?;
        let base = 7 + a + n;
        let points = (0..n)
            .map(|j| {
                Ok(apply(
                    &t,
                    Vec3::new(
                        p.real(base + 3 * j, "x")?,
                        p.real(base + 3 * j + 1, "y")?,
                        p.real(base + 3 * j + 2, "z")?,
                    ),
                ) * factor)
            })
            .collect::<Result<Vec<_>, ReadError>>()?;
        let range = [p.real(base + 3 * n, "V0")?, p.real(base + 3 * n + 1, "V1")?];
        Ok(IgesCurve {
            de: e.de,
            degree: m,
            knots,
            weights,
            points,
            range,
        })
    }
}

fn field<'r>(r: &'r Record<'_>, i: usize) -> &'r str {
    r.data[8 * i..8 * i + 8].trim()
}

fn apply(t: &Option<[f64; 12]>, p: Vec3) -> Vec3 {
    match t {
        None => p,
        Some(m) => Vec3::new(
            m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3],
            m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
            m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11],
        ),
    }
}

/// `a ∘ b` for 3×4 affine matrices (rows R | T).
fn compose(a: &[f64; 12], b: &[f64; 12]) -> [f64; 12] {
    let mut out = [0.0; 12];
    for r in 0..3 {
        for c in 0..4 {
            let mut s = if c == 3 { a[4 * r + 3] } else { 0.0 };
            for k in 0..3 {
                s += a[4 * r + k] * b[4 * k + c];
            }
            out[4 * r + c] = s;
        }
    }
    out
}

fn locate(starts: &[(usize, usize)], at: usize) -> (usize, usize) {
    let k = starts.partition_point(|&(s, _)| s <= at).saturating_sub(1);
    starts
        .get(k)
        .map_or((0, 0), |&(s, line)| (line, at - s + 1))
}

/// Split parameter text into fields up to the record delimiter, keeping Hollerith strings
/// whole. Errors carry the byte offset.
fn tokenize(text: &str, pd: u8, rd: u8) -> Result<Vec<&str>, (usize, String)> {
    match tokenize_prefix(text, pd, rd) {
        (fields, None) => Ok(fields),
        (_, Some(e)) => Err(e),
    }
}

/// [`tokenize`], and the fields read before an error with the error.
fn tokenize_prefix(text: &str, pd: u8, rd: u8) -> (Vec<&str>, Option<(usize, String)>) {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut start = 0;
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c == pd || c == rd {
            out.push(&text[start..i]);
            if c == rd {
                return (out, None);
            }
            i += 1;
            start = i;
            continue;
        }
        if c.is_ascii_digit() && text[start..i].trim().is_empty() {
            // A Hollerith string `nH…` or a number.
            let mut j = i;
            while j < b.len() && b[j].is_ascii_digit() {
                j += 1;
            }
            if j < b.len() && b[j] == b'H' {
                let Ok(n) = text[i..j].parse::<usize>() else {
                    return (out, Some((i, "Hollerith length too large".to_string())));
                };
                // (Checked: a count near usize::MAX must not wrap past the test below.)
                let end = (j + 1).saturating_add(n);
                if end > b.len() {
                    return (
                        out,
                        Some((
                            i,
                            format!(
                                "Hollerith string of {n} characters runs past the end of the data"
                            ),
                        )),
                    );
                }
                i = end;
                continue;
            }
            i = j;
            continue;
        }
        i += 1;
    }
    let e = format!(
        "found the end of the data, expected the record delimiter `{}`",
        rd as char
    );
    (out, Some((b.len(), e)))
}

/// The text of a Hollerith field (`3HABC` → `ABC`), or the field itself.
fn hollerith(t: &str) -> String {
    let t = t.trim();
    match t.find('H') {
        Some(i) if i > 0 && t[..i].bytes().all(|c| c.is_ascii_digit()) => t[i + 1..].to_string(),
        _ => t.to_string(),
    }
}

struct Params {
    values: Vec<(String, (usize, usize))>,
    end: (usize, usize),
}

impl Params {
    fn error(&self, i: usize, message: String) -> ReadError {
        let (line, column) = self.values.get(i).map_or(self.end, |v| v.1);
        syntax(line, column, message)
    }

    fn real(&self, i: usize, what: &str) -> Result<f64, ReadError> {
        let Some((t, _)) = self.values.get(i) else {
            return Err(self.error(i, format!("missing {what} (parameter {i})")));
        };
        if t.is_empty() {
            return Ok(0.0);
        }
        t.replace(['D', 'd'], "E")
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| self.error(i, format!("found `{t}`, expected a real number ({what})")))
    }

    fn int(&self, i: usize, what: &str) -> Result<i64, ReadError> {
        let Some((t, _)) = self.values.get(i) else {
            return Err(self.error(i, format!("missing {what} (parameter {i})")));
        };
        if t.is_empty() {
            return Ok(0);
        }
        t.parse::<i64>()
            .map_err(|_| self.error(i, format!("found `{t}`, expected an integer ({what})")))
    }

    /// A non-negative count no larger than the number of parameters (a guard against absurd
    /// allocations).
    fn count(&self, i: usize, what: &str) -> Result<usize, ReadError> {
        let v = self.int(i, what)?;
        if v < 0 || v as usize > self.values.len() {
            return Err(self.error(
                i,
                format!(
                    "{what} = {v} is impossible with {} parameters",
                    self.values.len()
                ),
            ));
        }
        Ok(v as usize)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokenize_hollerith_and_delimiters() {
        let t = tokenize("3HA,B,1.5D2,,7;junk", b',', b';').unwrap();
        assert_eq!(t, vec!["3HA,B", "1.5D2", "", "7"]);
        assert!(tokenize("5HAB", b',', b';').is_err());
        assert!(tokenize("1,2", b',', b';').is_err());
        assert_eq!(hollerith("2HMM"), "MM");
    }

    #[test]
    fn compose_is_matrix_product() {
        let shift = [1.0, 0.0, 0.0, 5.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];
        let rot = [0.0, -1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];
        let p = Vec3::X;
        let both = compose(&shift, &rot);
        assert_eq!(
            apply(&Some(both), p),
            apply(&Some(shift), apply(&Some(rot), p))
        );
        assert_eq!(apply(&Some(both), p), Vec3::new(5.0, 1.0, 0.0));
    }
}
