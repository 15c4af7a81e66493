//! Orientation of faces by the topology that holds them: `ORIENTED_FACE`,
//! `ORIENTED_OPEN_SHELL` and `ORIENTED_CLOSED_SHELL` (`(name, *, element, orientation)`) with
//! orientation `.F.` reverse their element — a face, or every face of a shell — so that its
//! material side is the other one, as if its `same_sense` were the opposite. Reversals compose
//! along the chain from the top (a solid or a surface model, or a shell or a face that nothing
//! holds) down to the face: a reversed face in a reversed shell is not reversed. `BREP_WITH_VOIDS` lists
//! its voids as `ORIENTED_CLOSED_SHELL(…, .F.)`, so their faces come out reversed.
//!
//! Only the topology that holds faces is followed (solids, surface models, shells, connected
//! face sets, oriented faces and shells): a styled item, a layer or a shape aspect that names a
//! face says nothing about its side.

use std::collections::{HashMap, HashSet};

use super::entities::{Model, R};
use super::lex::{refs, Instance, Param};

/// Entities that reverse their element when their orientation is `.F.`.
const ORIENTED: [&str; 3] = [
    "ORIENTED_FACE",
    "ORIENTED_OPEN_SHELL",
    "ORIENTED_CLOSED_SHELL",
];

/// Entities that hold faces, shells or solids as they are (their orientation passes on
/// unchanged).
const HOLDERS: [&str; 8] = [
    "OPEN_SHELL",
    "CLOSED_SHELL",
    "CONNECTED_FACE_SET",
    "MANIFOLD_SOLID_BREP",
    "BREP_WITH_VOIDS",
    "FACETED_BREP",
    "SHELL_BASED_SURFACE_MODEL",
    "FACE_BASED_SURFACE_MODEL",
];

fn is_face(inst: &Instance) -> bool {
    inst.part("ADVANCED_FACE").is_some() || inst.part("FACE_SURFACE").is_some()
}

fn oriented(inst: &Instance) -> Option<(&str, &[Param])> {
    ORIENTED.iter().find_map(|&n| inst.part(n).map(|p| (n, p)))
}

/// A face, an oriented face or shell, or a holder of them: what the walk goes down through.
fn is_topology(inst: &Instance) -> bool {
    is_face(inst) || oriented(inst).is_some() || HOLDERS.iter().any(|&n| inst.part(n).is_some())
}

impl Model<'_> {
    /// What the instance `id` holds, each with whether it reverses it: an oriented face or
    /// shell its element (reversed when its orientation is `.F.`), a face nothing (its bounds
    /// are not faces), the others the faces, shells and solids among their attributes.
    fn held_topology(&self, id: u64) -> R<Vec<(u64, bool)>> {
        let inst = &self.map[&id];
        if let Some((name, p)) = oriented(inst) {
            let element = self.reference(id, p.get(2), &format!("{name} element"))?;
            let orientation = self.logical(id, p.get(3), &format!("{name} orientation"))?;
            self.get(id, element)?;
            return Ok(vec![(element, !orientation)]);
        }
        if is_face(inst) {
            return Ok(Vec::new());
        }
        let mut found = Vec::new();
        for (_, ps) in &inst.parts {
            for p in ps {
                refs(p, &mut found);
            }
        }
        Ok(found
            .into_iter()
            .filter(|r| self.map.get(r).is_some_and(is_topology))
            .map(|r| (r, false))
            .collect())
    }

    /// For each face (`ADVANCED_FACE`, `FACE_SURFACE`) that the topology reaches reversed,
    /// whether it is reached reversed and whether also as it is: `[true]`, or `[false, true]`
    /// for a face that two holders use with opposite sides (two solids sharing it). A face
    /// missing from the map is read as it is.
    pub(super) fn face_reversals(&self) -> R<HashMap<u64, Vec<bool>>> {
        let mut ids: Vec<u64> = self.map.keys().copied().collect();
        ids.sort_unstable();
        let mut below: HashMap<u64, Vec<(u64, bool)>> = HashMap::new();
        let mut held = HashSet::new();
        for &id in &ids {
            let inst = &self.map[&id];
            if !is_topology(inst) {
                continue;
            }
            let kids = self.held_topology(id)?;
            held.extend(kids.iter().map(|&(k, _)| k));
            below.insert(id, kids);
        }
        // From the tops (what no other topology holds: the solids and surface models of
        // representations, and whatever stands alone), each face gets the reversals composed on
        // the way down to it. A representation reverses nothing, so it need not be a top.
        let mut out: HashMap<u64, Vec<bool>> = HashMap::new();
        let mut seen = HashSet::new();
        for &top in ids.iter().filter(|&&id| below.contains_key(&id)) {
            if held.contains(&top) {
                continue;
            }
            let mut stack = vec![(top, false)];
            while let Some((id, reversed)) = stack.pop() {
                if !seen.insert((id, reversed)) {
                    continue;
                }
                if self.map.get(&id).is_some_and(is_face) {
                    let r = out.entry(id).or_default();
                    if !r.contains(&reversed) {
                        r.push(reversed);
                        r.sort_unstable();
                    }
                }
                for &(k, flip) in below.get(&id).map(Vec::as_slice).unwrap_or(&[]) {
                    stack.push((k, reversed != flip));
                }
            }
        }
        // Faces reached only as they are need no entry.
        out.retain(|_, r| r.as_slice() != [false]);
        Ok(out)
    }
}
