//! From instances to surfaces: entity access with positioned errors, the file's units, faces
//! and their surfaces (B-spline and elementary), the parameter boxes of elementary surfaces.

use std::collections::{HashMap, HashSet};
use std::sync::Arc;

use swarf_geom::math::Vec3;
use swarf_geom::Frame;

use super::assembly::{place, Assembly, MAX_PLACED_CONTROL_POINTS, MAX_PLACED_TRIM_POINTS};
use super::lex::{refs, show, Instance, Param};
use super::swept::is_swept;
use super::trims::MAX_FILE_TRIM_POINTS;
use super::trims::{Built, FaceTrim};
use super::DEFAULT_LINEAR_RANGE;
use crate::compound::{CompoundSurface, EntityRef, Patch, PatchSource, ReadNote, UnhonouredTrim};
use crate::io::{line_col, skipped_detail, Format, ReadError};
use crate::surface::{
    ConicalSurface, CylindricalSurface, NurbsSurface, ParamBox, PlaneSurface, SphericalSurface,
    Surface, ToroidalSurface,
};

/// The instances of a file and the units they are read in.
pub(super) struct Model<'a> {
    pub(super) text: &'a str,
    pub(super) map: HashMap<u64, Instance>,
    /// Millimetres per file length unit.
    pub(super) length: f64,
    /// Radians per file plane-angle unit.
    pub(super) angle: f64,
    /// The distance accuracy the file declares (its `UNCERTAINTY_MEASURE_WITH_UNIT`), mm; 0
    /// when it declares none.
    pub(super) accuracy: f64,
}

pub(super) const SURFACES: [&str; 9] = [
    "B_SPLINE_SURFACE_WITH_KNOTS",
    "UNIFORM_SURFACE",
    "QUASI_UNIFORM_SURFACE",
    "BEZIER_SURFACE",
    "PLANE",
    "CYLINDRICAL_SURFACE",
    "CONICAL_SURFACE",
    "SPHERICAL_SURFACE",
    "TOROIDAL_SURFACE",
];

/// The B-spline surface kinds: with its knots, or with knots the kind implies.
const BSPLINE_KINDS: [&str; 4] = [
    "B_SPLINE_SURFACE_WITH_KNOTS",
    "UNIFORM_SURFACE",
    "QUASI_UNIFORM_SURFACE",
    "BEZIER_SURFACE",
];

pub(super) const OTHER_SURFACES: [&str; 7] = [
    "B_SPLINE_SURFACE",
    "SURFACE_OF_REVOLUTION",
    "SURFACE_OF_LINEAR_EXTRUSION",
    "OFFSET_SURFACE",
    "RECTANGULAR_TRIMMED_SURFACE",
    "CURVE_BOUNDED_SURFACE",
    "DEGENERATE_TOROIDAL_SURFACE",
];

pub(super) fn supported(inst: &Instance) -> bool {
    SURFACES.iter().any(|s| inst.part(s).is_some())
}

pub(super) fn is_surface(inst: &Instance) -> bool {
    supported(inst) || OTHER_SURFACES.iter().any(|s| inst.part(s).is_some())
}

/// The surface kind an instance is, by its most specific part: a complex B-spline surface is
/// named by its subtype (`QUASI_UNIFORM_SURFACE`), not by `B_SPLINE_SURFACE`.
pub(super) fn kind_name(inst: &Instance) -> String {
    let named = |n: &&str| SURFACES.contains(n) || OTHER_SURFACES.contains(n);
    let names = || inst.parts.iter().map(|(n, _)| n.as_str());
    names()
        .filter(named)
        .find(|n| *n != "B_SPLINE_SURFACE")
        .or_else(|| names().find(named))
        .unwrap_or(inst.first_name())
        .to_string()
}

pub(super) type R<T> = Result<T, ReadError>;

impl Model<'_> {
    pub(super) fn line(&self, id: u64) -> usize {
        self.map
            .get(&id)
            .map_or(0, |i| line_col(self.text, i.offset).0)
    }

    pub(super) fn bad(&self, id: u64, message: impl Into<String>) -> ReadError {
        ReadError::Entity {
            format: Format::Step,
            line: self.line(id),
            entity: format!("#{id}"),
            message: message.into(),
        }
    }

    pub(super) fn get(&self, from: u64, id: u64) -> R<&Instance> {
        self.map
            .get(&id)
            .ok_or_else(|| self.bad(from, format!("refers to #{id}, which is not defined")))
    }

    pub(super) fn num(&self, id: u64, p: Option<&Param>, what: &str) -> R<f64> {
        match p {
            Some(Param::Num(v)) => Ok(*v),
            Some(Param::Typed(_, inner)) if inner.len() == 1 => self.num(id, inner.first(), what),
            other => Err(self.bad(
                id,
                format!("{what}: found {}, expected a number", show(other)),
            )),
        }
    }

    pub(super) fn reference(&self, id: u64, p: Option<&Param>, what: &str) -> R<u64> {
        match p {
            Some(Param::Ref(r)) => Ok(*r),
            other => Err(self.bad(
                id,
                format!("{what}: found {}, expected a reference #n", show(other)),
            )),
        }
    }

    pub(super) fn list<'p>(&self, id: u64, p: Option<&'p Param>, what: &str) -> R<&'p [Param]> {
        match p {
            Some(Param::List(l)) => Ok(l),
            other => Err(self.bad(
                id,
                format!("{what}: found {}, expected a list", show(other)),
            )),
        }
    }

    pub(super) fn logical(&self, id: u64, p: Option<&Param>, what: &str) -> R<bool> {
        match p {
            Some(Param::Enum(e)) if e == "T" => Ok(true),
            Some(Param::Enum(e)) if e == "F" => Ok(false),
            other => Err(self.bad(
                id,
                format!("{what}: found {}, expected .T. or .F.", show(other)),
            )),
        }
    }

    pub(super) fn name(p: Option<&Param>) -> Option<String> {
        match p {
            Some(Param::Str(s)) if !s.trim().is_empty() => Some(s.clone()),
            _ => None,
        }
    }

    /// A CARTESIAN_POINT's coordinates (file units).
    pub(super) fn raw_point(&self, from: u64, id: u64) -> R<Vec3> {
        let inst = self.get(from, id)?;
        let p = inst.part("CARTESIAN_POINT").ok_or_else(|| {
            self.bad(
                id,
                format!("found {}, expected CARTESIAN_POINT", inst.first_name()),
            )
        })?;
        let c = self.list(id, p.get(1), "coordinates")?;
        if c.len() != 3 {
            return Err(self.bad(id, format!("{} coordinates, expected 3", c.len())));
        }
        Ok(Vec3::new(
            self.num(id, c.first(), "x")?,
            self.num(id, c.get(1), "y")?,
            self.num(id, c.get(2), "z")?,
        ))
    }

    pub(super) fn point(&self, from: u64, id: u64) -> R<Vec3> {
        Ok(self.raw_point(from, id)? * self.length)
    }

    pub(super) fn direction(&self, from: u64, p: Option<&Param>, default: Vec3) -> R<Vec3> {
        let id = match p {
            Some(Param::Null) | None => return Ok(default),
            other => self.reference(from, other, "direction")?,
        };
        let inst = self.get(from, id)?;
        let d = inst.part("DIRECTION").ok_or_else(|| {
            self.bad(
                id,
                format!("found {}, expected DIRECTION", inst.first_name()),
            )
        })?;
        let c = self.list(id, d.get(1), "direction ratios")?;
        if c.len() != 3 {
            return Err(self.bad(id, format!("{} direction ratios, expected 3", c.len())));
        }
        let v = Vec3::new(
            self.num(id, c.first(), "x")?,
            self.num(id, c.get(1), "y")?,
            self.num(id, c.get(2), "z")?,
        );
        if v.length() == 0.0 || !v.is_finite() {
            return Err(self.bad(id, "zero-length direction"));
        }
        Ok(v.normalize())
    }

    pub(super) fn placement(&self, from: u64, p: Option<&Param>) -> R<Frame> {
        let id = self.reference(from, p, "position")?;
        self.axis_in(from, id, self.length)
    }

    /// Conversion factor of a unit: mm per length unit, or radians per angle unit.
    pub(super) fn unit_factor(&self, from: u64, id: u64, depth: usize) -> R<(f64, String)> {
        if depth > 8 {
            return Err(self.bad(id, "unit definitions nest too deeply"));
        }
        let inst = self.get(from, id)?;
        if let Some(si) = inst.part("SI_UNIT") {
            let prefix = match si.first() {
                Some(Param::Enum(p)) => {
                    si_prefix(p).ok_or_else(|| self.bad(id, format!("unknown SI prefix .{p}.")))?
                }
                _ => 1.0,
            };
            let (base, name) = match si.get(1) {
                Some(Param::Enum(n)) if n == "METRE" => (1000.0, n.clone()),
                Some(Param::Enum(n)) => (1.0, n.clone()),
                other => return Err(self.bad(id, format!("SI unit name: found {}", show(other)))),
            };
            // ISO 10303-41's si_unit_name: a name outside it (`.METER.`) is no unit at all, and
            // a length or plane-angle unit must be the metre or the radian.
            let wanted = if inst.part("LENGTH_UNIT").is_some() {
                Some("METRE")
            } else if inst.part("PLANE_ANGLE_UNIT").is_some() {
                Some("RADIAN")
            } else {
                None
            };
            if !SI_UNIT_NAMES.contains(&name.as_str()) || wanted.is_some_and(|w| w != name) {
                let expected = match wanted {
                    Some(w) => format!(
                        ".{w}. (the SI name of a {})",
                        if w == "METRE" {
                            "length unit"
                        } else {
                            "plane angle unit"
                        }
                    ),
                    None => format!(
                        "one of ISO 10303-41's SI unit names (.{}.)",
                        SI_UNIT_NAMES.join("., .")
                    ),
                };
                return Err(self.bad(
                    id,
                    format!("SI_UNIT name .{name}. is not {expected}; refused (the file's lengths or angles would be read in a unit it does not declare)"),
                ));
            }
            let label = match si.first() {
                Some(Param::Enum(p)) => format!("{p} {name}"),
                _ => name,
            };
            return Ok((prefix * base, label));
        }
        if let Some(cb) = inst.part("CONVERSION_BASED_UNIT") {
            let label = Self::name(cb.first()).unwrap_or_else(|| "conversion-based unit".into());
            let m = self.reference(id, cb.get(1), "conversion factor")?;
            let mi = self.get(id, m)?;
            // The part that holds (value, unit): in the complex form `(LENGTH_MEASURE_WITH_UNIT()
            // MEASURE_WITH_UNIT(LENGTH_MEASURE(25.4),#1))` the subtype's part comes first and
            // is empty, the supertype's holds them.
            let mp = mi
                .parts
                .iter()
                .find(|(n, p)| n.ends_with("MEASURE_WITH_UNIT") && p.len() >= 2)
                .map(|(_, p)| p.as_slice())
                .ok_or_else(|| {
                    self.bad(
                        m,
                        format!(
                            "found {}, expected a …_MEASURE_WITH_UNIT with a value and a unit",
                            mi.first_name()
                        ),
                    )
                })?;
            let v = self.num(m, mp.first(), "value")?;
            let u = self.reference(m, mp.get(1), "unit")?;
            let (f, _) = self.unit_factor(m, u, depth + 1)?;
            if (v * f).is_nan() || v * f <= 0.0 || !(v * f).is_finite() {
                return Err(self.bad(m, "unit conversion factor is not positive"));
            }
            return Ok((v * f, label));
        }
        Err(self.bad(
            id,
            format!(
                "found {}, expected SI_UNIT or CONVERSION_BASED_UNIT",
                inst.first_name()
            ),
        ))
    }

    /// Reads the units of every unit context, sets the file's (the first length and the first
    /// plane-angle unit, by instance number) and returns each context's, by the context's
    /// instance number: `(mm per length unit, its name, radians per angle unit)`, the file's
    /// where a context declares none.
    pub(super) fn units(&mut self, notes: &mut Vec<ReadNote>) -> R<Contexts> {
        let mut ids: Vec<u64> = self.map.keys().copied().collect();
        ids.sort_unstable();
        let mut length = None;
        let mut angle = None;
        let mut contexts = Vec::new();
        for id in ids {
            let Some(g) = self.map[&id].part("GLOBAL_UNIT_ASSIGNED_CONTEXT") else {
                continue;
            };
            let units = self.list(id, g.first(), "units")?.to_vec();
            let (mut own_length, mut own_angle) = (None, None);
            for u in &units {
                let uid = self.reference(id, Some(u), "unit")?;
                let ui = self.get(id, uid)?;
                if own_length.is_none() && ui.part("LENGTH_UNIT").is_some() {
                    own_length = Some(self.unit_factor(id, uid, 0)?);
                } else if own_angle.is_none() && ui.part("PLANE_ANGLE_UNIT").is_some() {
                    own_angle = Some(self.unit_factor(id, uid, 0)?.0);
                }
            }
            length = length.or_else(|| own_length.clone());
            angle = angle.or(own_angle);
            contexts.push((id, own_length, own_angle));
        }
        let (first, label) = length.clone().unwrap_or((1.0, "mm".into()));
        self.angle = angle.unwrap_or(1.0);
        let contexts: Contexts = contexts
            .into_iter()
            .map(|(id, l, a)| {
                let (f, name) = l.unwrap_or_else(|| (first, label.clone()));
                (id, (f, name, a.unwrap_or(self.angle)))
            })
            .collect();
        let mut distinct: Vec<(f64, String)> = Vec::new();
        for (f, name, _) in contexts.values() {
            if !distinct.iter().any(|(g, _)| g == f) {
                distinct.push((*f, name.clone()));
            }
        }
        match length {
            None => notes.push(ReadNote::UnitsAssumed),
            Some((f, label)) => {
                if distinct.len() > 1 {
                    distinct.sort_by(|a, b| a.0.total_cmp(&b.0));
                    notes.push(ReadNote::UnitsMixed {
                        units: distinct.into_iter().map(|(_, n)| n).collect(),
                        first: label,
                        defaulted: 0,
                    });
                } else if f != 1.0 {
                    notes.push(ReadNote::UnitsConverted {
                        unit: label,
                        factor: f,
                    });
                }
                self.length = f;
            }
        }
        Ok(contexts)
    }

    /// The unit context of each face (or, in a file without faces, each surface) that one
    /// representation holds: its items are followed through shells and models to the faces,
    /// not into other representations (a `MAPPED_ITEM`'s representation holds its own). A face
    /// held by representations of different length units maps to `None`.
    pub(super) fn face_contexts(&self, contexts: &Contexts) -> HashMap<u64, Option<u64>> {
        let mut ids: Vec<u64> = self.map.keys().copied().collect();
        ids.sort_unstable();
        let mut out: HashMap<u64, Option<u64>> = HashMap::new();
        for id in ids {
            // A representation: (name, items, context), its context one of the unit contexts.
            let Some((items, ctx)) =
                self.map[&id]
                    .parts
                    .iter()
                    .find_map(|(_, p)| match p.as_slice() {
                        [_, Param::List(items), Param::Ref(c)] if contexts.contains_key(c) => {
                            Some((items, *c))
                        }
                        _ => None,
                    })
            else {
                continue;
            };
            let mut stack = Vec::new();
            for item in items {
                refs(item, &mut stack);
            }
            let mut seen = HashSet::new();
            while let Some(i) = stack.pop() {
                let Some(inst) = self.map.get(&i) else {
                    continue;
                };
                if !seen.insert(i) || is_representation(inst, contexts) {
                    continue;
                }
                let face =
                    inst.part("ADVANCED_FACE").is_some() || inst.part("FACE_SURFACE").is_some();
                if face || is_surface(inst) {
                    let unit = |c: Option<u64>| c.and_then(|c| contexts.get(&c)).map(|u| u.0);
                    out.entry(i)
                        .and_modify(|c| {
                            if unit(*c) != unit(Some(ctx)) {
                                *c = None;
                            }
                        })
                        .or_insert(Some(ctx));
                    continue;
                }
                if not_entered(inst.first_name()) {
                    continue;
                }
                for (_, ps) in &inst.parts {
                    for p in ps {
                        refs(p, &mut stack);
                    }
                }
            }
        }
        out
    }

    /// The surfaces of a file with faces that are read on their own, by instance number:
    /// those a shape representation's items reach (through sets, shells and surface models;
    /// not into faces, curves, mapped items, styled items or other representations) — never a
    /// face's geometry (`geometry`), nor the basis of another surface (`bases`), which are read
    /// through the face or that surface. A surface nothing refers to is in no shape (left-over
    /// construction geometry beside a B-rep): not read.
    fn free_surfaces(&self, geometry: &HashSet<u64>, bases: &HashSet<u64>) -> Vec<u64> {
        let mut stack = Vec::new();
        let mut reached = HashSet::new();
        for inst in self.map.values() {
            let Some((items, _)) = super::assembly::shape_rep(inst) else {
                continue;
            };
            let mut seen = HashSet::new();
            for item in items {
                refs(item, &mut stack);
            }
            while let Some(i) = stack.pop() {
                let Some(inst) = self.map.get(&i) else {
                    continue;
                };
                if !seen.insert(i) || super::assembly::shape_rep(inst).is_some() {
                    continue;
                }
                if inst.part("ADVANCED_FACE").is_some() || inst.part("FACE_SURFACE").is_some() {
                    continue;
                }
                if is_surface(inst) {
                    reached.insert(i);
                    continue;
                }
                let name = inst.first_name();
                let curve = inst.parts.iter().any(|(n, _)| n.ends_with("CURVE"));
                if curve || name.contains("STYLED_ITEM") || not_entered(name) {
                    continue;
                }
                for (_, ps) in &inst.parts {
                    for p in ps {
                        refs(p, &mut stack);
                    }
                }
            }
        }
        let mut out: Vec<u64> = self
            .map
            .iter()
            .filter(|(id, inst)| {
                is_surface(inst)
                    && reached.contains(*id)
                    && !geometry.contains(*id)
                    && !bases.contains(*id)
            })
            .map(|(id, _)| *id)
            .collect();
        out.sort_unstable();
        out
    }

    pub(super) fn read(mut self) -> R<CompoundSurface> {
        let mut out = CompoundSurface::default();
        let contexts = self.units(&mut out.notes)?;
        let mut ids: Vec<u64> = self.map.keys().copied().collect();
        ids.sort_unstable();
        let faces: Vec<u64> = ids
            .iter()
            .copied()
            .filter(|id| {
                let i = &self.map[id];
                i.part("ADVANCED_FACE").is_some() || i.part("FACE_SURFACE").is_some()
            })
            .collect();
        let bases = self.bases();
        // Surfaces read on their own: in a file without faces every surface that is no other
        // surface's basis; in a file with faces, the free ones besides them.
        let free: Vec<u64> = if faces.is_empty() {
            ids.iter()
                .copied()
                .filter(|id| is_surface(&self.map[id]) && !bases.contains(id))
                .collect()
        } else {
            let geometry: HashSet<u64> = faces
                .iter()
                .filter_map(|f| {
                    let i = &self.map[f];
                    match i
                        .part("ADVANCED_FACE")
                        .or_else(|| i.part("FACE_SURFACE"))?
                        .get(2)
                    {
                        Some(Param::Ref(s)) => Some(*s),
                        _ => None,
                    }
                })
                .collect();
            self.free_surfaces(&geometry, &bases)
        };
        let readable =
            |i: &Instance| supported(i) || is_swept(i) || i.part("CURVE_BOUNDED_SURFACE").is_some();
        // Assembly placements, in the file's units (each representation's, when they differ).
        let items: Vec<u64> = faces
            .iter()
            .copied()
            .chain(free.iter().copied().filter(|id| readable(&self.map[id])))
            .collect();
        let assembly = self.assembly(&contexts, &items)?;
        let reversals = self.face_reversals()?;
        // Representations in different length units: each face is read in its own's.
        let units = matches!(out.notes.last(), Some(ReadNote::UnitsMixed { .. })).then(|| {
            let by_face = self.face_contexts(&contexts);
            (contexts, by_face)
        });
        let file_units = (self.length, self.angle);
        let mut defaulted = 0;
        let mut skipped = Vec::new();
        let mut budget = MAX_FILE_TRIM_POINTS;
        let mut placed = [0; 2];
        for &fid in &faces {
            let f = &self.map[&fid];
            let p = f
                .part("ADVANCED_FACE")
                .or_else(|| f.part("FACE_SURFACE"))
                .unwrap_or(&[]);
            let sid = self.reference(fid, p.get(2), "face geometry")?;
            let same_sense = self.logical(fid, p.get(3), "same_sense")?;
            let sinst = self.get(fid, sid)?;
            let skind = kind_name(sinst);
            if !supported(sinst) && !is_swept(sinst) {
                skipped.push(ReadNote::UnsupportedSurface {
                    entity: format!("#{sid} (face #{fid})"),
                    kind: kind_name(sinst),
                });
                continue;
            }
            let index = out.patches.len();
            let bounds = p.get(1).cloned();
            (self.length, self.angle) = units_of(fid, &units, &mut defaulted, file_units);
            let mut notes = Vec::new();
            let face = bounds.as_ref().map(|b| (fid, b));
            let (mut surface, sname, reversed) =
                match self.any_surface(sid, face, index, &mut notes)? {
                    Ok(s) => s,
                    Err(why) => {
                        skipped.push(ReadNote::UnsupportedSurface {
                            entity: format!("#{sid} (face #{fid})"),
                            kind: format!("{skind} ({why})"),
                        });
                        continue;
                    }
                };
            // A surface whose normal is the other way (a reversed rectangular trim): the
            // face agrees with it the other way.
            let same_sense = same_sense != reversed;
            let trim = self.face_trim(fid, bounds.as_ref(), same_sense, &surface, &mut budget);
            let trim = trimmed(
                trim,
                &mut surface,
                &mut notes,
                index,
                format!("STEP face #{fid}"),
                |why| UnhonouredTrim::StepFace { face: fid, why },
            );
            let patch = Patch {
                name: Self::name(p.first()).or(sname),
                surface,
                flipped: !same_sense,
                source: PatchSource {
                    file: None,
                    entity: EntityRef::Step {
                        surface: sid,
                        face: Some(fid),
                    },
                },
                trim,
            };
            // An oriented face or shell that reverses the face flips its material side
            // only: the region its bounds enclose is the same (it reverses the bounds too),
            // so the trim above is read with the face's own same_sense. A face its holders
            // use both ways (two solids sharing it) is read once each way.
            let ways = reversals.get(&fid).map_or(&[false][..], Vec::as_slice);
            for &reversed in ways {
                let first = out.patches.len();
                let patch = Patch {
                    flipped: patch.flipped != reversed,
                    ..patch.clone()
                };
                let notes = notes.iter().map(|n| n.clone().for_patch(first)).collect();
                self.push_placed(&mut out, patch, notes, &assembly, fid, &mut placed)?;
            }
        }
        for &id in &free {
            let inst = &self.map[&id];
            if !readable(inst) {
                skipped.push(ReadNote::UnsupportedSurface {
                    entity: format!("#{id}"),
                    kind: kind_name(inst),
                });
                continue;
            }
            let index = out.patches.len();
            (self.length, self.angle) = units_of(id, &units, &mut defaulted, file_units);
            let mut notes = Vec::new();
            let read = match inst.part("CURVE_BOUNDED_SURFACE") {
                Some(p) => self
                    .bounded(id, p, index, &mut notes, &mut budget)?
                    .map(|(s, t)| (s, Some(t))),
                None => self
                    .any_surface(id, None, index, &mut notes)?
                    .map(|s| (s, None)),
            };
            let ((mut surface, name, reversed), trim) = match read {
                Ok(s) => s,
                Err(why) => {
                    skipped.push(ReadNote::UnsupportedSurface {
                        entity: format!("#{id}"),
                        kind: format!("{} ({why})", kind_name(inst)),
                    });
                    continue;
                }
            };
            let trim = match trim {
                Some(t) => trimmed(
                    t,
                    &mut surface,
                    &mut notes,
                    index,
                    format!("STEP curve-bounded surface #{id}"),
                    |why| UnhonouredTrim::StepBounded { surface: id, why },
                ),
                None => None,
            };
            let patch = Patch {
                name,
                surface,
                flipped: reversed,
                source: PatchSource {
                    file: None,
                    entity: EntityRef::Step {
                        surface: id,
                        face: None,
                    },
                },
                trim,
            };
            self.push_placed(&mut out, patch, notes, &assembly, id, &mut placed)?;
        }
        if out.patches.is_empty() {
            let detail = if skipped.is_empty() {
                String::new()
            } else {
                skipped_detail(&skipped)
            };
            return Err(ReadError::Empty {
                format: Format::Step,
                detail,
            });
        }
        if let Some(ReadNote::UnitsMixed { defaulted: d, .. }) = out
            .notes
            .iter_mut()
            .find(|n| matches!(n, ReadNote::UnitsMixed { .. }))
        {
            *d = defaulted;
        }
        out.notes.extend(assembly.notes);
        out.notes.extend(skipped);
        Ok(out)
    }

    /// Adds the patch of face (or surface) `id`, read in its own frame with its `notes`, once
    /// per placed instance of it (moved by the instance's placement, named with the instance's
    /// path when there are several, each note repeated for each patch), or once as it is when
    /// no placement reaches it.
    ///
    /// `placed` counts the control points and the trim points of the placed patches so far; a
    /// face whose instances would take either past its cap ([`MAX_PLACED_CONTROL_POINTS`],
    /// [`MAX_PLACED_TRIM_POINTS`]) refuses the file before they are made.
    fn push_placed(
        &self,
        out: &mut CompoundSurface,
        patch: Patch,
        notes: Vec<ReadNote>,
        assembly: &Assembly,
        id: u64,
        placed: &mut [usize; 2],
    ) -> R<()> {
        let Some(instances) = assembly.by_item.get(&id) else {
            out.patches.push(patch);
            out.notes.extend(notes);
            return Ok(());
        };
        let control = match &patch.surface {
            Surface::Nurbs(n) => n.net_size().0 * n.net_size().1,
            _ => 0,
        };
        let trim = patch
            .trim
            .as_ref()
            .map_or(0, |t| t.loops().iter().map(Vec::len).sum());
        for (k, (own, cap, what)) in [
            (control, MAX_PLACED_CONTROL_POINTS, "control points"),
            (trim, MAX_PLACED_TRIM_POINTS, "trim points"),
        ]
        .into_iter()
        .enumerate()
        {
            placed[k] = placed[k].saturating_add(own.saturating_mul(instances.len()));
            if placed[k] > cap {
                return Err(self.bad(
                    id,
                    format!(
                        "placed {} times by the assembly, its {own} {what} take the file's \
                         placed patches past {cap} {what} (each placed instance copies them); \
                         refused: read the parts on their own, or export the assembly with \
                         fewer instances",
                        instances.len()
                    ),
                ));
            }
        }
        for (placement, path) in instances {
            let index = out.patches.len();
            let (surface, trim) =
                place(&patch.surface, patch.trim.as_ref(), placement).map_err(|why| {
                    self.bad(
                        id,
                        format!("placed by {path} (the assembly placement): {why}"),
                    )
                })?;
            let name = match &patch.name {
                Some(n) if instances.len() > 1 && !path.is_empty() => Some(format!("{n}@{path}")),
                other => other.clone(),
            };
            out.patches.push(Patch {
                name,
                surface,
                trim,
                ..patch.clone()
            });
            out.notes
                .extend(notes.iter().map(|n| n.clone().for_patch(index)));
        }
        Ok(())
    }

    /// The surface `id`, bounded (for elementary kinds) by the face bounds when given.
    pub(super) fn surface(
        &self,
        id: u64,
        face: Option<(u64, &Param)>,
        index: usize,
        notes: &mut Vec<ReadNote>,
    ) -> R<(Surface, Option<String>)> {
        let inst = &self.map[&id];
        if BSPLINE_KINDS.iter().any(|k| inst.part(k).is_some()) {
            return self.bspline(id, inst);
        }
        let (kind, p) = inst
            .parts
            .iter()
            .find(|(n, _)| SURFACES.contains(&n.as_str()))
            .map(|(n, p)| (n.as_str(), p.as_slice()))
            .unwrap_or(("", &[]));
        let name = Self::name(p.first());
        let frame = self.placement(id, p.get(1))?;
        let pts = match face {
            Some((fid, bounds)) => self.boundary_points(fid, bounds)?,
            None => Vec::new(),
        };
        let tau = std::f64::consts::TAU;
        let mut range = |f: &dyn Fn(Vec3) -> f64, what: &str| {
            let lo = pts.iter().map(|&q| f(q)).fold(f64::INFINITY, f64::min);
            let hi = pts.iter().map(|&q| f(q)).fold(f64::NEG_INFINITY, f64::max);
            if hi - lo > 1e-9 * (1.0 + hi.abs().max(lo.abs())) {
                [lo, hi]
            } else {
                notes.push(ReadNote::DefaultParameterBox {
                    patch: index,
                    what: what.into(),
                });
                DEFAULT_LINEAR_RANGE
            }
        };
        let along = |a: Vec3| move |q: Vec3| (q - frame.origin).dot(a);
        let bad_radius = || self.bad(id, format!("{kind}: radius must be positive and finite"));
        let surface = match kind {
            "PLANE" => {
                let u = range(&along(frame.x), "u");
                let v = range(&along(frame.y), "v");
                Surface::Plane(PlaneSurface::new(
                    frame,
                    ParamBox::new(u[0], u[1], v[0], v[1]),
                ))
            }
            "CYLINDRICAL_SURFACE" => {
                let r = self.num(id, p.get(2), "radius")? * self.length;
                let v = range(&along(frame.z), "v");
                Surface::Cylinder(
                    CylindricalSurface::new(frame, r, ParamBox::new(0.0, tau, v[0], v[1]))
                        .ok_or_else(bad_radius)?,
                )
            }
            "CONICAL_SURFACE" => {
                let r = self.num(id, p.get(2), "radius")? * self.length;
                let a = self.num(id, p.get(3), "semi_angle")? * self.angle;
                let v = range(&along(frame.z), "v");
                Surface::Cone(
                    ConicalSurface::new(frame, r, a, ParamBox::new(0.0, tau, v[0], v[1]))
                        .ok_or_else(|| {
                            self.bad(
                                id,
                                "CONICAL_SURFACE: needs radius ≥ 0 and 0 < semi_angle < 90°",
                            )
                        })?,
                )
            }
            "SPHERICAL_SURFACE" => {
                let r = self.num(id, p.get(2), "radius")? * self.length;
                Surface::Sphere(
                    SphericalSurface::new(frame, r, SphericalSurface::FULL)
                        .ok_or_else(bad_radius)?,
                )
            }
            "TOROIDAL_SURFACE" => {
                let big = self.num(id, p.get(2), "major_radius")? * self.length;
                let r = self.num(id, p.get(3), "minor_radius")? * self.length;
                Surface::Torus(
                    ToroidalSurface::new(frame, big, r, ToroidalSurface::FULL)
                        .ok_or_else(bad_radius)?,
                )
            }
            _ => return Err(self.bad(id, format!("unsupported surface {}", inst.first_name()))),
        };
        Ok((surface, name))
    }

    pub(super) fn bspline(&self, id: u64, inst: &Instance) -> R<(Surface, Option<String>)> {
        // Simple entity: all attributes in one part; complex: split over parts. A uniform,
        // quasi-uniform or Bézier surface has no knots of its own: its kind implies them.
        let (kind, k) = BSPLINE_KINDS
            .iter()
            .find_map(|n| inst.part(n).map(|p| (*n, p)))
            .unwrap_or(("B_SPLINE_SURFACE_WITH_KNOTS", &[]));
        let with_knots = kind == "B_SPLINE_SURFACE_WITH_KNOTS";
        let (name, head, knots): (Option<String>, &[Param], &[Param]) =
            if let Some(b) = inst.part("B_SPLINE_SURFACE") {
                let name = inst
                    .part("REPRESENTATION_ITEM")
                    .and_then(|r| Self::name(r.first()));
                (name, b, if with_knots { k } else { &[] })
            } else {
                let expected = if with_knots { 13 } else { 8 };
                if k.len() < expected {
                    return Err(self.bad(
                        id,
                        format!("{kind} has {} attributes, expected {expected}", k.len()),
                    ));
                }
                (Self::name(k.first()), &k[1..8], &k[8..])
            };
        let degree = |p: Option<&Param>, what: &str| -> R<usize> {
            let d = self.num(id, p, what)?;
            if d >= 1.0 && d <= NurbsSurface::MAX_DEGREE as f64 && d.fract() == 0.0 {
                Ok(d as usize)
            } else {
                Err(self.bad(
                    id,
                    format!("{what} is {d}; expected 1 to {}", NurbsSurface::MAX_DEGREE),
                ))
            }
        };
        let du = degree(head.first(), "u_degree")?;
        let dv = degree(head.get(1), "v_degree")?;
        let rows = self.list(id, head.get(2), "control_points_list")?;
        let mut points = Vec::with_capacity(rows.len());
        for r in rows {
            let row = self.list(id, Some(r), "control point row")?;
            let mut out = Vec::with_capacity(row.len());
            for c in row {
                out.push(self.point(id, self.reference(id, Some(c), "control point")?)?);
            }
            points.push(out);
        }
        let nu = points.len();
        let nv = points.first().map_or(0, Vec::len);
        let (knots_u, knots_v) = if with_knots {
            (
                self.knots(id, knots.first(), knots.get(2), "u", nu + du + 1)?,
                self.knots(id, knots.get(1), knots.get(3), "v", nv + dv + 1)?,
            )
        } else {
            let implied = |n: usize, d: usize, dir: &str| {
                implied_knots(kind, n, d)
                    .ok_or_else(|| self.bad(id, format!("{kind}: {n} {dir} control points do not make pieces of degree {d} (a Bézier surface needs a multiple of the degree, plus one)")))
            };
            (implied(nu, du, "u")?, implied(nv, dv, "v")?)
        };
        let weights = match inst.part("RATIONAL_B_SPLINE_SURFACE") {
            Some(w) => {
                let rows = self.list(id, w.first(), "weights_data")?;
                let mut ws = Vec::with_capacity(rows.len());
                for r in rows {
                    let row = self.list(id, Some(r), "weights row")?;
                    ws.push(
                        row.iter()
                            .map(|x| self.num(id, Some(x), "weight"))
                            .collect::<R<Vec<f64>>>()?,
                    );
                }
                Some(ws)
            }
            None => None,
        };
        let s = NurbsSurface::new(du, dv, knots_u, knots_v, &points, weights.as_deref()).map_err(
            |reason| ReadError::Surface {
                format: Format::Step,
                line: self.line(id),
                entity: format!("#{id}"),
                reason,
            },
        )?;
        Ok((Surface::Nurbs(s), name))
    }

    /// Expand (multiplicities, knots) into a knot vector, refusing a total other than `expected`
    /// before allocating it.
    pub(super) fn knots(
        &self,
        id: u64,
        mult: Option<&Param>,
        vals: Option<&Param>,
        dir: &str,
        expected: usize,
    ) -> R<Vec<f64>> {
        let m = self.list(id, mult, &format!("{dir}_multiplicities"))?;
        let k = self.list(id, vals, &format!("{dir}_knots"))?;
        if m.len() != k.len() {
            return Err(self.bad(
                id,
                format!(
                    "{} {dir} multiplicities for {} {dir} knots",
                    m.len(),
                    k.len()
                ),
            ));
        }
        let mut total = 0.0;
        let mut ms = Vec::with_capacity(m.len());
        for x in m {
            let v = self.num(id, Some(x), "multiplicity")?;
            if v.is_nan() || v < 1.0 || v.fract() != 0.0 {
                return Err(self.bad(
                    id,
                    format!("{dir} multiplicity {v} is not a positive integer"),
                ));
            }
            total += v;
            ms.push(v as usize);
        }
        if total != expected as f64 {
            return Err(self.bad(
                id,
                format!("{dir} multiplicities add up to {total}; expected {expected} (control points + degree + 1)"),
            ));
        }
        let mut out = Vec::with_capacity(expected);
        for (x, &n) in k.iter().zip(&ms) {
            let v = self.num(id, Some(x), "knot")?;
            out.extend(std::iter::repeat(v).take(n));
        }
        Ok(out)
    }

    /// The placement and the semi-axes (mm) of the `CIRCLE` or `ELLIPSE` `id` with attributes
    /// `c` (a circle's second semi-axis is its radius).
    pub(super) fn conic(&self, id: u64, c: &[Param]) -> R<(Frame, f64, f64)> {
        let f = self.placement(id, c.get(1))?;
        let a = self.num(id, c.get(2), "radius")? * self.length;
        let b = match c.get(3) {
            Some(p) => self.num(id, Some(p), "semi_axis_2")? * self.length,
            None => a,
        };
        Ok((f, a, b))
    }

    /// Points (mm) that bound a face: vertices, B-spline edge control points, circle and ellipse
    /// samples reachable from its bounds (not through placements, lines or pcurves).
    pub(super) fn boundary_points(&self, face: u64, bounds: &Param) -> R<Vec<Vec3>> {
        const LIMIT: usize = 200_000;
        let mut out = Vec::new();
        let mut seen = HashSet::new();
        let mut stack = Vec::new();
        refs(bounds, &mut stack);
        while let Some(id) = stack.pop() {
            if !seen.insert(id) || seen.len() > LIMIT {
                continue;
            }
            let inst = self.get(face, id)?;
            let name = inst.first_name();
            if is_surface(inst)
                || matches!(
                    name,
                    "PCURVE"
                        | "DEFINITIONAL_REPRESENTATION"
                        | "AXIS2_PLACEMENT_3D"
                        | "LINE"
                        | "DIRECTION"
                        | "VECTOR"
                )
            {
                continue;
            }
            if let Some(c) = inst.part("CARTESIAN_POINT") {
                if matches!(c.get(1), Some(Param::List(l)) if l.len() == 3) {
                    out.push(self.point(face, id)?);
                }
                continue;
            }
            if let Some(c) = inst.part("CIRCLE").or_else(|| inst.part("ELLIPSE")) {
                let (f, a, b) = self.conic(id, c)?;
                for k in 0..32 {
                    let t = k as f64 / 32.0 * std::f64::consts::TAU;
                    out.push(f.origin + a * t.cos() * f.x + b * t.sin() * f.y);
                }
                continue;
            }
            for (_, ps) in &inst.parts {
                for p in ps {
                    refs(p, &mut stack);
                }
            }
        }
        Ok(out)
    }
}

/// The knots ISO 10303-42 implies for `n` control points of degree `d` (`n > d`) of a
/// `UNIFORM_SURFACE` (every knot once, a unit apart, the parameter range `[0, n − d]`: knots
/// −d, −d + 1, …, n), a `QUASI_UNIFORM_SURFACE` (0 and n − d each d + 1 times, the integers
/// between once) or a `BEZIER_SURFACE` (pieces of degree d: 0 and m = (n − 1)/d each d + 1
/// times, 1 … m − 1 each d times; `None` when d does not divide n − 1).
fn implied_knots(kind: &str, n: usize, d: usize) -> Option<Vec<f64>> {
    if n <= d {
        return None;
    }
    let mut k = Vec::with_capacity(n + d + 1);
    match kind {
        "UNIFORM_SURFACE" => k.extend((0..n + d + 1).map(|i| i as f64 - d as f64)),
        "QUASI_UNIFORM_SURFACE" => {
            let last = (n - d) as f64;
            k.extend(std::iter::repeat(0.0).take(d + 1));
            k.extend((1..n - d).map(|i| i as f64));
            k.extend(std::iter::repeat(last).take(d + 1));
        }
        "BEZIER_SURFACE" => {
            if (n - 1) % d != 0 {
                return None;
            }
            let m = (n - 1) / d;
            k.extend(std::iter::repeat(0.0).take(d + 1));
            for i in 1..m {
                k.extend(std::iter::repeat(i as f64).take(d));
            }
            k.extend(std::iter::repeat(m as f64).take(d + 1));
        }
        _ => return None,
    }
    Some(k)
}

/// A face's (or a curve-bounded surface's) trim as read: `Some(trim)`, the surface's box set
/// to the trim's and a [`ReadNote::Trimmed`] by `by`; `None` without one, or with a
/// [`ReadNote::TrimNotHonoured`] (`unhonoured`) when it cannot be honoured.
fn trimmed(
    trim: Built<Option<FaceTrim>>,
    surface: &mut Surface,
    notes: &mut Vec<ReadNote>,
    index: usize,
    by: String,
    unhonoured: impl FnOnce(Arc<crate::io::TrimFailure>) -> UnhonouredTrim,
) -> Option<crate::trim::Trim> {
    match trim {
        Ok(Some(t)) => {
            notes.push(ReadNote::Trimmed {
                patch: index,
                by,
                loops: t.trim.loops().len(),
                points: t.trim.loops().iter().map(Vec::len).sum(),
            });
            surface.set_domain(t.domain);
            Some(t.trim)
        }
        Ok(None) => None,
        Err(why) => {
            notes.push(ReadNote::TrimNotHonoured {
                patch: index,
                by: unhonoured(Arc::new(why)),
            });
            None
        }
    }
}

/// The units (mm per length unit, radians per angle unit) to read face or surface `id` in:
/// its representation's context's, or the file's (`file`) where it has none or is ambiguous
/// (counted in `defaulted`).
fn units_of(
    id: u64,
    units: &Option<(Contexts, HashMap<u64, Option<u64>>)>,
    defaulted: &mut usize,
    file: (f64, f64),
) -> (f64, f64) {
    let Some((contexts, by_face)) = units else {
        return file;
    };
    match by_face
        .get(&id)
        .copied()
        .flatten()
        .and_then(|c| contexts.get(&c))
    {
        Some(&(length, _, angle)) => (length, angle),
        None => {
            *defaulted += 1;
            file
        }
    }
}

/// The unit contexts of a file by instance number: mm per length unit, the unit's name,
/// radians per plane-angle unit.
pub(super) type Contexts = HashMap<u64, (f64, String, f64)>;

/// True for a representation (name, items, one of the unit contexts), whose items belong to
/// its own context.
fn is_representation(inst: &Instance, contexts: &Contexts) -> bool {
    inst.parts.iter().any(|(_, p)| {
        matches!(p.as_slice(), [_, Param::List(_), Param::Ref(c)] if contexts.contains_key(c))
    })
}

/// ISO 10303-41's `si_unit_name`: the names an `SI_UNIT` may have.
const SI_UNIT_NAMES: [&str; 28] = [
    "METRE",
    "GRAM",
    "SECOND",
    "AMPERE",
    "KELVIN",
    "MOLE",
    "CANDELA",
    "RADIAN",
    "STERADIAN",
    "HERTZ",
    "NEWTON",
    "PASCAL",
    "JOULE",
    "WATT",
    "COULOMB",
    "VOLT",
    "FARAD",
    "OHM",
    "SIEMENS",
    "WEBER",
    "TESLA",
    "HENRY",
    "DEGREE_CELSIUS",
    "LUMEN",
    "LUX",
    "BECQUEREL",
    "GRAY",
    "SIEVERT",
];

pub(super) fn si_prefix(p: &str) -> Option<f64> {
    Some(match p {
        "EXA" => 1e18,
        "PETA" => 1e15,
        "TERA" => 1e12,
        "GIGA" => 1e9,
        "MEGA" => 1e6,
        "KILO" => 1e3,
        "HECTO" => 1e2,
        "DECA" => 1e1,
        "DECI" => 1e-1,
        "CENTI" => 1e-2,
        "MILLI" => 1e-3,
        "MICRO" => 1e-6,
        "NANO" => 1e-9,
        "PICO" => 1e-12,
        "FEMTO" => 1e-15,
        "ATTO" => 1e-18,
        _ => return None,
    })
}

/// Entities a walk from a representation's items down to its faces does not enter: mapped
/// items (their faces belong to the representation they place) and the points, directions and
/// axes of placements.
pub(super) fn not_entered(name: &str) -> bool {
    matches!(
        name,
        "MAPPED_ITEM"
            | "REPRESENTATION_MAP"
            | "CARTESIAN_POINT"
            | "DIRECTION"
            | "AXIS2_PLACEMENT_3D"
    )
}
