//! Assembly placements: the tree of shape representations placed in one another by
//! `MAPPED_ITEM`s and by representation relationships with a transformation (the
//! `CONTEXT_DEPENDENT_SHAPE_REPRESENTATION`s of assembly occurrences), walked from its roots
//! down so that every face (every surface, in a file without faces) gets the placements of the
//! instances that hold it; and the surfaces moved by them.

use std::collections::{HashMap, HashSet};

use swarf_geom::math::{Mat3, Vec3};
use swarf_geom::Frame;

use super::entities::{is_surface, not_entered, Contexts, Model, R};
use super::lex::{refs, show, Instance, Param};
use crate::compound::ReadNote;
pub(super) use crate::placement::{place, Placement};

/// Most placed instances of representations (each path from a root to a representation counts
/// once) a file may expand to; beyond, the file is refused.
pub(super) const MAX_INSTANCES: usize = 100_000;

/// Most patches the placed faces of a file may give, each once per placed instance.
pub(super) const MAX_PLACED_PATCHES: usize = 500_000;

/// Most control points of B-spline surfaces that the placed faces (surfaces) of a file may
/// hold, counted once per placed instance (each instance copies its surface); beyond, the file
/// is refused before they are made. The instance and patch caps above do not bound this: one
/// 30×30 B-spline surface placed 16 384 times (7 levels of 4 mapped items, an 88 KB file) is
/// 14.7 million control points, and took the toolsize command past 14 GB. The reader holds 56
/// bytes a control point (the homogeneous and the given coordinates), but the commands that
/// decompose the surface into Bézier pieces and search them (`toolsize`, `gouge`) take about
/// 1.5 KB a control point (measured: 0.92 million took `toolsize` to 1.4 GB), so the cap is 2
/// million — about 3 GB there, on the 2-core, 24 GB machines the project is measured on. A
/// machined part stays far below: 2 000 faces at 25 control points a face on average (most faces
/// are planes, cylinders and cones without any; B-spline faces of ordinary size have 4×4 to 8×8)
/// is 50 000, and may be placed 40 times; a part of 5 000 B-spline faces of 10×10 four times.
pub(super) const MAX_PLACED_CONTROL_POINTS: usize = 2_000_000;

/// Most points of trims' loops that the placed faces of a file may hold, counted once per
/// placed instance (each instance copies its face's trim): what the trims of
/// [`MAX_PLACED_PATCHES`] faces of 100 points each hold (an ordinary face's loops have tens to
/// a few hundred points; one face may have 200 000, placed up to [`MAX_INSTANCES`] times).
/// About 60 bytes a point, 3 GB at the cap.
pub(super) const MAX_PLACED_TRIM_POINTS: usize = 50_000_000;

/// Deepest nesting of placements (sub-assemblies in sub-assemblies) followed.
pub(super) const MAX_NESTING: usize = 64;

/// One placed instance of a representation: its motion into the root's frame and the path of
/// placing entities (`#43/#57`) that gives it.
pub(super) type Placed = (Placement, String);

/// A placement of one shape representation in another.
struct Edge {
    parent: u64,
    child: u64,
    /// The motion, or why it cannot be read (then the child is placed without it).
    motion: Result<Placement, String>,
    /// The placing entity, as `MAPPED_ITEM #31`.
    entity: String,
    /// Its part of an instance's path (`#43`: the assembly occurrence, or the placing entity).
    label: u64,
}

/// Union–find over representation ids (representations joined by relationships without a
/// transformation share a frame).
#[derive(Default)]
struct Classes(HashMap<u64, u64>);

impl Classes {
    fn find(&mut self, x: u64) -> u64 {
        let mut r = x;
        while let Some(&p) = self.0.get(&r) {
            if p == r {
                break;
            }
            r = p;
        }
        // Path compression.
        let mut y = x;
        while let Some(&p) = self.0.get(&y) {
            if p == r {
                break;
            }
            self.0.insert(y, r);
            y = p;
        }
        r
    }

    fn union(&mut self, a: u64, b: u64) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            // The smaller id is the class's name, for a stable order.
            let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
            self.0.insert(hi, lo);
            self.0.insert(lo, lo);
        }
    }
}

/// The items and the context of a shape representation (`…SHAPE_REPRESENTATION(name, items,
/// context)`, simple or complex).
pub(super) fn shape_rep(inst: &Instance) -> Option<(&[Param], u64)> {
    if !inst
        .parts
        .iter()
        .any(|(n, _)| n.ends_with("SHAPE_REPRESENTATION"))
    {
        return None;
    }
    inst.parts.iter().find_map(|(_, p)| match p.as_slice() {
        [_, Param::List(items), Param::Ref(c)] => Some((items.as_slice(), *c)),
        _ => None,
    })
}

/// The x axis of a placement whose z axis is the unit `z`, from its reference direction
/// `arg` (`None`: omitted, `$`): ISO 10303-42's `first_proj_axis(z_axis, arg)`, which both
/// `build_axes` (an `AXIS2_PLACEMENT_3D`'s axes) and `base_axis` (a
/// `CARTESIAN_TRANSFORMATION_OPERATOR_3D`'s) call. The standard's function: without `arg`,
/// v = (1, 0, 0) unless z is (1, 0, 0) or (−1, 0, 0), then v = (0, 1, 0); with it, v = arg
/// (undefined when arg is parallel to z); the result is v less its component along z,
/// normalised. So an axis along ±X with its reference direction omitted has x = (0, 1, 0).
/// The standard compares z with ±(1, 0, 0) exactly; here z within 1e-12 of it counts as
/// along it (there the exact rule would normalise a difference of length ~1e-12, whose
/// direction is rounding). `None` when the given direction is parallel to z.
pub(super) fn first_proj_axis(z: Vec3, arg: Option<Vec3>) -> Option<Vec3> {
    let v = arg.unwrap_or(if z.y.abs() <= 1e-12 && z.z.abs() <= 1e-12 {
        Vec3::Y
    } else {
        Vec3::X
    });
    let x = v - z * z.dot(v);
    (x.length() > 1e-12 * v.length()).then(|| x.normalize())
}

/// What the walk from the roots found.
pub(super) struct Assembly {
    /// The placed instances of each face (or surface) that a placement reaches; the others
    /// are read once, in their own frame.
    pub(super) by_item: HashMap<u64, Vec<Placed>>,
    /// Notes: placements applied, placements not applied.
    pub(super) notes: Vec<ReadNote>,
}

impl Model<'_> {
    /// mm per length unit of representation `rep`: its context's, or the file's.
    fn rep_length(&self, rep: u64, contexts: &Contexts) -> f64 {
        self.map
            .get(&rep)
            .and_then(shape_rep)
            .and_then(|(_, c)| contexts.get(&c))
            .map_or(self.length, |c| c.0)
    }

    /// The AXIS2_PLACEMENT_3D `id` as a frame, its location scaled by `length` (mm per unit).
    pub(super) fn axis_in(&self, from: u64, id: u64, length: f64) -> R<Frame> {
        let inst = self.get(from, id)?;
        let a = inst.part("AXIS2_PLACEMENT_3D").ok_or_else(|| {
            self.bad(
                id,
                format!("found {}, expected AXIS2_PLACEMENT_3D", inst.first_name()),
            )
        })?;
        let loc = self.reference(id, a.get(1), "location")?;
        let origin = self.raw_point(id, loc)? * length;
        let z = self.direction(id, a.get(2), Vec3::Z)?;
        let given = match a.get(3) {
            Some(Param::Null) | None => None,
            other => Some(self.direction(id, other, Vec3::X)?),
        };
        Ok(match first_proj_axis(z, given) {
            Some(x) => Frame::from_axis_and_x(origin, z, x),
            // A reference direction along the axis: the standard leaves the placement
            // undefined; any x square to the axis.
            None => Frame::from_axis(origin, z),
        })
    }

    /// A CARTESIAN_TRANSFORMATION_OPERATOR_3D (simple, its attributes `name, axis1, axis2,
    /// local_origin, scale, axis3` after one name or after name, name and description; or
    /// complex) as a placement, its origin scaled by `length`: the axes by the standard's
    /// `base_axis` (axis3 or +Z; axis1 or +X made normal to it; axis2 or z × x made normal to
    /// both). `Ok(Err(why))` when it mirrors or scales out of range.
    fn operator(&self, id: u64, length: f64) -> R<Result<Placement, String>> {
        let inst = self.get(id, id)?;
        let head: Vec<Param> = if let Some(c) = inst.part("CARTESIAN_TRANSFORMATION_OPERATOR") {
            let mut h = c.to_vec();
            h.push(
                inst.part("CARTESIAN_TRANSFORMATION_OPERATOR_3D")
                    .and_then(|p| p.first().cloned())
                    .unwrap_or(Param::Null),
            );
            h
        } else {
            let p = inst
                .part("CARTESIAN_TRANSFORMATION_OPERATOR_3D")
                .unwrap_or(&[]);
            match p.len() {
                6 => p[1..].to_vec(),
                8 => p[3..].to_vec(),
                n => {
                    return Err(self.bad(
                        id,
                        format!(
                        "CARTESIAN_TRANSFORMATION_OPERATOR_3D has {n} attributes, expected 6 or 8"
                    ),
                    ))
                }
            }
        };
        if head.len() != 5 {
            return Err(self.bad(
                id,
                "CARTESIAN_TRANSFORMATION_OPERATOR needs axis1, axis2, local_origin, scale",
            ));
        }
        let z = self.direction(id, head.get(4), Vec3::Z)?;
        let given = match head.first() {
            Some(Param::Null) | None => None,
            other => Some(self.direction(id, other, Vec3::X)?),
        };
        let Some(x) = first_proj_axis(z, given) else {
            return Ok(Err("its axis1 is parallel to its axis3".into()));
        };
        let right = z.cross(x);
        let y = match head.get(1) {
            Some(Param::Null) | None => right,
            other => self.direction(id, other, right)?,
        };
        let y = y - x * x.dot(y) - z * z.dot(y);
        if y.length() <= 1e-12 {
            return Ok(Err("its axis2 is parallel to its axis1 or axis3".into()));
        }
        if y.dot(right) < 0.0 {
            return Ok(Err("it mirrors (its axes are left-handed)".into()));
        }
        let origin = self.raw_point(id, self.reference(id, head.get(2), "local_origin")?)? * length;
        let scale = match head.get(3) {
            Some(Param::Null) | None => 1.0,
            other => self.num(id, other, "scale")?,
        };
        let p = Placement {
            rot: Mat3::from_cols(x, right, z),
            scale,
            shift: origin,
        };
        Ok(match p.insane() {
            Some(why) => Err(why),
            None => Ok(p),
        })
    }

    /// The motion of a relationship's transformation `t`: an ITEM_DEFINED_TRANSFORMATION
    /// between two AXIS2_PLACEMENT_3Ds (item 1 in `rep1`'s units, item 2 in `rep2`'s; the
    /// motion takes item 1 onto item 2) or a CARTESIAN_TRANSFORMATION_OPERATOR_3D.
    fn transformation(&self, from: u64, t: &Param, l1: f64, l2: f64) -> Result<Placement, String> {
        let id = match t {
            Param::Ref(r) => *r,
            other => return Err(format!("its transformation is {}", show(Some(other)))),
        };
        let inst = self.get(from, id).map_err(|e| e.to_string())?;
        let motion = if let Some(d) = inst.part("ITEM_DEFINED_TRANSFORMATION") {
            let item = |k: usize, l: f64| -> Result<Frame, String> {
                let r = self
                    .reference(id, d.get(k), "transform item")
                    .map_err(|e| e.to_string())?;
                if self
                    .map
                    .get(&r)
                    .and_then(|i| i.part("AXIS2_PLACEMENT_3D"))
                    .is_none()
                {
                    let kind = self.map.get(&r).map_or("nothing", |i| i.first_name());
                    return Err(format!(
                        "ITEM_DEFINED_TRANSFORMATION #{id}: its item #{r} is {kind}, not an \
                         AXIS2_PLACEMENT_3D"
                    ));
                }
                self.axis_in(id, r, l).map_err(|e| e.to_string())
            };
            let (a, b) = (item(2, l1)?, item(3, l2)?);
            Placement::between(&a, &b)
        } else if inst.part("CARTESIAN_TRANSFORMATION_OPERATOR_3D").is_some() {
            self.operator(id, l2).map_err(|e| e.to_string())??
        } else {
            return Err(format!(
                "its transformation #{id} is a {}, not an ITEM_DEFINED_TRANSFORMATION or a \
                 CARTESIAN_TRANSFORMATION_OPERATOR_3D",
                inst.first_name()
            ));
        };
        match motion.insane() {
            Some(why) => Err(why),
            None => Ok(motion),
        }
    }

    /// A MAPPED_ITEM's motion: its REPRESENTATION_MAP's origin (an AXIS2_PLACEMENT_3D, in the
    /// mapped representation's units `lc`) onto its target (an AXIS2_PLACEMENT_3D or a
    /// CARTESIAN_TRANSFORMATION_OPERATOR_3D, in the holding representation's units `lp`).
    fn mapping(
        &self,
        id: u64,
        origin: &Param,
        target: Option<&Param>,
        lc: f64,
        lp: f64,
    ) -> Result<Placement, String> {
        let err = |e: crate::io::ReadError| e.to_string();
        let o = self
            .reference(id, Some(origin), "mapping_origin")
            .map_err(err)?;
        let oi = self.get(id, o).map_err(err)?;
        if oi.part("AXIS2_PLACEMENT_3D").is_none() {
            return Err(format!(
                "its mapping origin #{o} is a {}, not an AXIS2_PLACEMENT_3D",
                oi.first_name()
            ));
        }
        let from = self.axis_in(id, o, lc).map_err(err)?;
        let t = self.reference(id, target, "mapping_target").map_err(err)?;
        let ti = self.get(id, t).map_err(err)?;
        let to = if ti.part("AXIS2_PLACEMENT_3D").is_some() {
            Placement::of_frame(&self.axis_in(id, t, lp).map_err(err)?)
        } else if ti.part("CARTESIAN_TRANSFORMATION_OPERATOR_3D").is_some() {
            self.operator(t, lp).map_err(err)??
        } else {
            return Err(format!(
                "its mapping target #{t} is a {}, not an AXIS2_PLACEMENT_3D or a \
                 CARTESIAN_TRANSFORMATION_OPERATOR_3D",
                ti.first_name()
            ));
        };
        let m = to.after(&Placement::of_frame(&from).inverse());
        match m.insane() {
            Some(why) => Err(why),
            None => Ok(m),
        }
    }

    /// The faces (and the surfaces outside faces) a representation's items hold, followed
    /// through shells, solids and models, not into other representations, mapped items or
    /// styled items.
    fn held(&self, items: &[Param]) -> Vec<u64> {
        let mut stack = Vec::new();
        for item in items {
            refs(item, &mut stack);
        }
        let mut seen = HashSet::new();
        let mut out = Vec::new();
        while let Some(i) = stack.pop() {
            let Some(inst) = self.map.get(&i) else {
                continue;
            };
            if !seen.insert(i) || shape_rep(inst).is_some() {
                continue;
            }
            let name = inst.first_name();
            if inst.part("ADVANCED_FACE").is_some()
                || inst.part("FACE_SURFACE").is_some()
                || is_surface(inst)
            {
                out.push(i);
                continue;
            }
            if name.contains("STYLED_ITEM") || not_entered(name) {
                continue;
            }
            for (_, ps) in &inst.parts {
                for p in ps {
                    refs(p, &mut stack);
                }
            }
        }
        out
    }

    /// The file's assembly structure applied to `items` (its faces, or its surfaces in a file
    /// without faces): which placed instances each gets, and the notes. Nothing (no notes, no
    /// placements) for a file without placements.
    ///
    /// Direction: a relationship `(rep_1, rep_2)` with a transformation places `rep_1` (the
    /// component) in `rep_2` (the assembly) by the motion taking its item 1 onto its item 2
    /// (`item_2 ∘ item_1⁻¹`; rep 1 the child is OCCT's convention, see the module docs); when the
    /// assembly occurrence of its `CONTEXT_DEPENDENT_SHAPE_REPRESENTATION` says the other way
    /// round (`rep_1` is the assembly's representation, `rep_2` the component's), `rep_2` is
    /// placed in `rep_1` by the inverse.
    pub(super) fn assembly(&self, contexts: &Contexts, items: &[u64]) -> R<Assembly> {
        let mut notes = Vec::new();
        let mut ids: Vec<u64> = self.map.keys().copied().collect();
        ids.sort_unstable();
        let nodes: Vec<u64> = ids
            .iter()
            .copied()
            .filter(|id| shape_rep(&self.map[id]).is_some())
            .collect();
        let is_node = |r: u64| self.map.get(&r).and_then(shape_rep).is_some();
        let mut classes = Classes::default();
        for &n in &nodes {
            classes.union(n, n);
        }
        // Relationships referenced by a CONTEXT_DEPENDENT_SHAPE_REPRESENTATION: (cdsr, pds).
        let mut cdsr: HashMap<u64, (u64, Option<u64>)> = HashMap::new();
        for &id in &ids {
            if let Some(p) = self.map[&id].part("CONTEXT_DEPENDENT_SHAPE_REPRESENTATION") {
                if let Some(Param::Ref(rel)) = p.first() {
                    let pds = match p.get(1) {
                        Some(Param::Ref(d)) => Some(*d),
                        _ => None,
                    };
                    cdsr.entry(*rel).or_insert((id, pds));
                }
            }
        }
        // Placements between representations (not yet their classes), with their assembly
        // occurrences.
        let mut raw: Vec<(Edge, Option<u64>)> = Vec::new();
        let mut not_applied = |entity: String, why: String| {
            notes.push(ReadNote::PlacementNotApplied { entity, why });
        };
        for &id in &ids {
            let inst = &self.map[&id];
            let shape = inst.part("SHAPE_REPRESENTATION_RELATIONSHIP");
            let wt = inst.part("REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION");
            let placing = cdsr.get(&id).copied();
            if shape.is_none() && wt.is_none() && placing.is_none() {
                continue;
            }
            let base = inst
                .part("REPRESENTATION_RELATIONSHIP")
                .or(shape)
                .or(wt)
                .filter(|p| p.len() >= 4);
            let transform = wt.and_then(|p| if p.len() >= 5 { p.get(4) } else { p.first() });
            let entity = format!("{} #{id}", inst.first_name());
            let reps = base.and_then(|b| match (&b[2], &b[3]) {
                (Param::Ref(a), Param::Ref(b)) => Some((*a, *b)),
                _ => None,
            });
            let Some((rep1, rep2)) = reps.filter(|&(a, b)| is_node(a) && is_node(b)) else {
                // Worth a note when it places in an assembly or touches a shape
                // representation: relationships between other representations (presentation,
                // annotation) place no shape.
                let shape_side = reps.is_some_and(|(a, b)| is_node(a) || is_node(b));
                if (wt.is_some() && (shape_side || reps.is_none())) || placing.is_some() {
                    not_applied(
                        entity,
                        "it does not relate two shape representations; its placement cannot \
                         be resolved"
                            .into(),
                    );
                }
                continue;
            };
            if wt.is_none() && placing.is_none() {
                // Same frame: the product's shape representation and its geometry's.
                classes.union(rep1, rep2);
                continue;
            }
            let motion = match transform {
                Some(t) => self.transformation(
                    id,
                    t,
                    self.rep_length(rep1, contexts),
                    self.rep_length(rep2, contexts),
                ),
                None => Ok(Placement::IDENTITY),
            };
            // The assembly occurrence, through the CDSR's PRODUCT_DEFINITION_SHAPE.
            let nauo = placing
                .and_then(|(_, pds)| pds)
                .and_then(|d| self.map.get(&d))
                .and_then(|d| d.part("PRODUCT_DEFINITION_SHAPE"))
                .and_then(|p| match p.get(2) {
                    Some(Param::Ref(n)) => Some(*n),
                    _ => None,
                })
                .filter(|n| {
                    self.map
                        .get(n)
                        .is_some_and(|i| i.part("NEXT_ASSEMBLY_USAGE_OCCURRENCE").is_some())
                });
            let edge = Edge {
                parent: rep2,
                child: rep1,
                motion,
                entity,
                label: nauo.unwrap_or(id),
            };
            raw.push((edge, nauo));
        }
        // Product definitions' shape representations (SHAPE_DEFINITION_REPRESENTATION).
        let mut pd_reps: HashMap<u64, Vec<u64>> = HashMap::new();
        for &id in &ids {
            let Some(p) = self.map[&id].part("SHAPE_DEFINITION_REPRESENTATION") else {
                continue;
            };
            let (Some(Param::Ref(pds)), Some(Param::Ref(rep))) = (p.first(), p.get(1)) else {
                continue;
            };
            let pd = self
                .map
                .get(pds)
                .and_then(|d| d.part("PRODUCT_DEFINITION_SHAPE"))
                .and_then(|d| match d.get(2) {
                    Some(Param::Ref(x)) => Some(*x),
                    _ => None,
                });
            if let Some(pd) = pd.filter(|_| is_node(*rep)) {
                pd_reps.entry(pd).or_default().push(*rep);
            }
        }
        let occurrence = |n: u64| -> Option<(u64, u64)> {
            match self.map.get(&n)?.part("NEXT_ASSEMBLY_USAGE_OCCURRENCE")? {
                [_, _, _, Param::Ref(relating), Param::Ref(related), ..] => {
                    Some((*relating, *related))
                }
                _ => None,
            }
        };
        let class_of = |classes: &mut Classes, pd: u64| -> Vec<u64> {
            let mut v: Vec<u64> = pd_reps
                .get(&pd)
                .map(|r| r.iter().map(|&x| classes.find(x)).collect())
                .unwrap_or_default();
            v.sort_unstable();
            v.dedup();
            v
        };
        let mut edges: Vec<Edge> = Vec::new();
        for (mut e, nauo) in raw {
            let (mut parent, mut child) = (classes.find(e.parent), classes.find(e.child));
            if let Some((relating, related)) = nauo.and_then(occurrence) {
                let (asm, comp) = (
                    class_of(&mut classes, relating),
                    class_of(&mut classes, related),
                );
                let normal = comp.contains(&child) && asm.contains(&parent);
                let reversed = comp.contains(&parent) && asm.contains(&child);
                if reversed && !normal {
                    std::mem::swap(&mut parent, &mut child);
                    e.motion = e.motion.map(|m| m.inverse());
                }
            }
            (e.parent, e.child) = (parent, child);
            edges.push(e);
        }
        // MAPPED_ITEMs in the items of shape representations.
        let mut held_mapped = HashSet::new();
        for &n in &nodes {
            let (items, _) = shape_rep(&self.map[&n]).unwrap_or((&[], 0));
            for item in items {
                let Param::Ref(m) = item else { continue };
                let Some(mp) = self.map.get(m).and_then(|i| i.part("MAPPED_ITEM")) else {
                    continue;
                };
                held_mapped.insert(*m);
                let entity = format!("MAPPED_ITEM #{m}");
                let source = match mp.get(1) {
                    Some(Param::Ref(s)) => self
                        .map
                        .get(s)
                        .and_then(|i| i.part("REPRESENTATION_MAP"))
                        .filter(|r| r.len() >= 2),
                    _ => None,
                };
                let Some(source) = source else {
                    not_applied(
                        entity,
                        format!(
                            "its source {} is not a REPRESENTATION_MAP; its placement cannot be \
                             resolved",
                            show(mp.get(1))
                        ),
                    );
                    continue;
                };
                let child = match &source[1] {
                    Param::Ref(r) if is_node(*r) => *r,
                    other => {
                        not_applied(
                            entity,
                            format!(
                                "its representation map maps {}, not a shape representation; its \
                                 placement cannot be resolved",
                                show(Some(other))
                            ),
                        );
                        continue;
                    }
                };
                let motion = self.mapping(
                    *m,
                    &source[0],
                    mp.get(2),
                    self.rep_length(child, contexts),
                    self.rep_length(n, contexts),
                );
                edges.push(Edge {
                    parent: classes.find(n),
                    child: classes.find(child),
                    motion,
                    entity,
                    label: *m,
                });
            }
        }
        for &id in &ids {
            let Some(mp) = self.map[&id].part("MAPPED_ITEM") else {
                continue;
            };
            // One that maps something other than a shape representation (an annotation's)
            // places no shape.
            let maps_shape = match mp.get(1) {
                Some(Param::Ref(s)) => self
                    .map
                    .get(s)
                    .and_then(|i| i.part("REPRESENTATION_MAP"))
                    .and_then(|r| match r.get(1) {
                        Some(Param::Ref(rep)) => Some(is_node(*rep)),
                        _ => None,
                    })
                    .unwrap_or(true),
                _ => true,
            };
            if maps_shape && !held_mapped.contains(&id) {
                not_applied(
                    format!("MAPPED_ITEM #{id}"),
                    "no shape representation holds it among its items; it places nothing".into(),
                );
            }
        }
        // Assembly occurrences that no placement accounts for.
        let cdsr_nauos: HashSet<u64> = cdsr
            .values()
            .filter_map(|&(_, pds)| pds)
            .filter_map(|d| {
                self.map
                    .get(&d)?
                    .part("PRODUCT_DEFINITION_SHAPE")?
                    .get(2)
                    .cloned()
            })
            .filter_map(|p| match p {
                Param::Ref(n) => Some(n),
                _ => None,
            })
            .collect();
        for &id in &ids {
            let Some((relating, related)) = occurrence(id) else {
                continue;
            };
            if cdsr_nauos.contains(&id) {
                continue;
            }
            let comp = class_of(&mut classes, related);
            if comp.is_empty() {
                continue;
            }
            let asm = class_of(&mut classes, relating);
            let mapped = edges
                .iter()
                .any(|e| asm.contains(&e.parent) && comp.contains(&e.child));
            if !mapped {
                not_applied(
                    format!("NEXT_ASSEMBLY_USAGE_OCCURRENCE #{id}"),
                    "no CONTEXT_DEPENDENT_SHAPE_REPRESENTATION or MAPPED_ITEM places its \
                     component; the component is read where its own representation puts it"
                        .into(),
                );
            }
        }
        if edges.is_empty() {
            return Ok(Assembly {
                by_item: HashMap::new(),
                notes,
            });
        }
        for e in &mut edges {
            if let Err(why) = &e.motion {
                notes.push(ReadNote::PlacementNotApplied {
                    entity: e.entity.clone(),
                    why: format!("{why}; the component is placed without it"),
                });
                e.motion = Ok(Placement::IDENTITY);
            }
        }
        edges.sort_by_key(|e| (e.parent, e.label, e.child));
        let mut children: HashMap<u64, Vec<usize>> = HashMap::new();
        let mut has_parent = HashSet::new();
        for (k, e) in edges.iter().enumerate() {
            children.entry(e.parent).or_default().push(k);
            has_parent.insert(e.child);
        }
        let mut all: Vec<u64> = nodes.iter().map(|&n| classes.find(n)).collect();
        all.sort_unstable();
        all.dedup();
        let roots: Vec<u64> = all
            .iter()
            .copied()
            .filter(|c| !has_parent.contains(c))
            .collect();
        let mut walk = Walk {
            edges: &edges,
            children: &children,
            placed: HashMap::new(),
            count: 0,
            used: vec![false; edges.len()],
            cyclic: HashSet::new(),
            out_of_range: HashMap::new(),
            too_deep: false,
        };
        for &r in &roots {
            let mut path = Vec::new();
            if !walk.visit(r, Placement::IDENTITY, &mut path) {
                return Err(self.bad(
                    r,
                    format!(
                        "the assembly places more than {MAX_INSTANCES} instances of \
                         representations; refused"
                    ),
                ));
            }
        }
        for (k, e) in edges.iter().enumerate() {
            if walk.cyclic.contains(&k) {
                notes.push(ReadNote::PlacementNotApplied {
                    entity: e.entity.clone(),
                    why: format!(
                        "it would place #{} inside itself (a cycle of placements); not followed",
                        e.child
                    ),
                });
            } else if !walk.used[k] && !walk.placed.contains_key(&e.parent) {
                let reason = if walk.too_deep {
                    format!("placements nest more than {MAX_NESTING} levels deep, or form a cycle")
                } else {
                    "a cycle of placements".into()
                };
                notes.push(ReadNote::PlacementNotApplied {
                    entity: e.entity.clone(),
                    why: format!(
                        "it places #{} in #{}, which no root representation reaches ({reason}); \
                         not applied",
                        e.child, e.parent
                    ),
                });
            }
        }
        let mut far: Vec<(&usize, &String)> = walk.out_of_range.iter().collect();
        far.sort();
        for (&k, why) in far {
            notes.push(ReadNote::PlacementNotApplied {
                entity: edges[k].entity.clone(),
                why: format!(
                    "composed with the placements above it, {why}; the instance(s) it would \
                     place there are left out"
                ),
            });
        }
        if walk.too_deep {
            notes.push(ReadNote::PlacementNotApplied {
                entity: format!("#{}", roots.first().copied().unwrap_or(0)),
                why: format!(
                    "placements nest more than {MAX_NESTING} levels deep; the deeper ones are \
                     not applied"
                ),
            });
        }
        // The faces each class holds.
        let mut holders: HashMap<u64, Vec<u64>> = HashMap::new();
        let wanted: HashSet<u64> = items.iter().copied().collect();
        let mut holding = HashSet::new();
        for &n in &nodes {
            let (its, _) = shape_rep(&self.map[&n]).unwrap_or((&[], 0));
            let c = classes.find(n);
            for f in self.held(its) {
                if wanted.contains(&f) {
                    let h = holders.entry(f).or_default();
                    if !h.contains(&c) {
                        h.push(c);
                    }
                    holding.insert(c);
                }
            }
        }
        let mut by_item: HashMap<u64, Vec<Placed>> = HashMap::new();
        let mut total = 0usize;
        let mut unplaced = 0usize;
        for &f in items {
            let mut list: Vec<Placed> = Vec::new();
            let hs = holders.get(&f).map(Vec::as_slice).unwrap_or(&[]);
            for (k, c) in hs.iter().enumerate() {
                for p in walk.placed.get(c).map(Vec::as_slice).unwrap_or(&[]) {
                    if k > 0 && list.iter().any(|q| q.0 == p.0) {
                        continue;
                    }
                    list.push(p.clone());
                }
            }
            if list.iter().any(|p| !p.1.is_empty()) {
                total += list.len();
                by_item.insert(f, list);
            } else {
                unplaced += 1;
            }
            if total > MAX_PLACED_PATCHES {
                return Err(self.bad(
                    f,
                    format!(
                        "the assembly's placed faces, once per instance, make more than \
                         {MAX_PLACED_PATCHES} patches; refused"
                    ),
                ));
            }
        }
        // Placements whose component holds no face (below it) while some faces are read
        // unplaced: what they should have placed may be there.
        if unplaced > 0 {
            let mut below: HashSet<u64> = holding.clone();
            let mut stack: Vec<u64> = holding.iter().copied().collect();
            let mut parents: HashMap<u64, Vec<u64>> = HashMap::new();
            for e in &edges {
                parents.entry(e.child).or_default().push(e.parent);
            }
            while let Some(c) = stack.pop() {
                for &p in parents.get(&c).map(Vec::as_slice).unwrap_or(&[]) {
                    if below.insert(p) {
                        stack.push(p);
                    }
                }
            }
            for (k, e) in edges.iter().enumerate() {
                if walk.used[k] && !below.contains(&e.child) {
                    notes.push(ReadNote::PlacementNotApplied {
                        entity: e.entity.clone(),
                        why: format!(
                            "it places #{}, which holds no faces, while {unplaced} face(s) are \
                             in no placed representation and are read in their own frame",
                            e.child
                        ),
                    });
                }
            }
        }
        let mut instances = 0;
        let mut parts = 0;
        for c in &holding {
            let n = walk
                .placed
                .get(c)
                .map_or(0, |v| v.iter().filter(|p| !p.1.is_empty()).count());
            if n > 0 {
                instances += n;
                parts += 1;
            }
        }
        if instances > 0 {
            notes.insert(0, ReadNote::PlacementsApplied { instances, parts });
        }
        Ok(Assembly { by_item, notes })
    }
}

/// The walk from the roots down the placements.
struct Walk<'e> {
    edges: &'e [Edge],
    children: &'e HashMap<u64, Vec<usize>>,
    /// The placed instances of each class.
    placed: HashMap<u64, Vec<Placed>>,
    count: usize,
    /// Edges followed at least once.
    used: Vec<bool>,
    /// Edges that close a cycle.
    cyclic: HashSet<usize>,
    /// Edges whose motion, composed with the chain above, is out of range (why).
    out_of_range: HashMap<usize, String>,
    too_deep: bool,
}

impl Walk<'_> {
    /// Places `class` by `at` (reached through the edges `path`) and its components below it;
    /// false when the instances run past [`MAX_INSTANCES`].
    fn visit(&mut self, class: u64, at: Placement, path: &mut Vec<usize>) -> bool {
        self.count += 1;
        if self.count > MAX_INSTANCES {
            return false;
        }
        let label = path
            .iter()
            .map(|&k| format!("#{}", self.edges[k].label))
            .collect::<Vec<_>>()
            .join("/");
        self.placed.entry(class).or_default().push((at, label));
        if path.len() >= MAX_NESTING {
            self.too_deep |= self.children.contains_key(&class);
            return true;
        }
        let kids = self.children.get(&class).cloned().unwrap_or_default();
        for k in kids {
            let e = &self.edges[k];
            let child = e.child;
            let on_path = child == class || path.iter().any(|&j| self.edges[j].parent == child);
            if on_path {
                self.cyclic.insert(k);
                continue;
            }
            self.used[k] = true;
            let m = at.after(e.motion.as_ref().unwrap_or(&Placement::IDENTITY));
            if let Some(why) = m.insane() {
                self.out_of_range.entry(k).or_insert(why);
                continue;
            }
            path.push(k);
            let ok = self.visit(child, m, path);
            path.pop();
            if !ok {
                return false;
            }
        }
        true
    }
}
