//! swarf's JSON surface format (part of the CLI contract):
//!
//! ```json
//! {"units": "mm", "patches": [{"name": "floor", "degree_u": 1, "degree_v": 1,
//!   "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
//!   "control_points": [[[0, 0, 0, 1], [0, 10, 0, 1]], [[10, 0, 0, 1], [10, 10, 0, 1]]]}]}
//! ```
//!
//! `control_points[i][j]` is indexed along u then v; each is `[x, y, z, w]` with x y z **not**
//! multiplied by the weight w; `S_u × S_v` points to the side the cutter comes from. `units` is
//! `"mm"` (the default when absent), `"inch"` or `"in"`; inches are converted to mm. `name` is
//! optional. Unknown keys are errors (they are usually typos).
//!
//! A patch may be trimmed: `"trim": {"outer": [[u, v], ...], "holes": [[[u, v], ...], ...]}`,
//! closed polygons in the patch's parameters (not lengths: `units` does not scale them; the
//! closing repeat of the first point is optional). Both keys are optional: without `outer` the
//! outer boundary is the patch's parameter box. A point is on the part when a ray from it
//! crosses the loops an odd number of times (the even–odd rule), so loops need no particular
//! orientation. See [`crate::trim::Trim`]. A patch with an outer boundary is read with its
//! parameter box cut down to that boundary's box ([`crate::Patch::fit_domain_to_trim`]: the
//! B-spline cut exactly by knot insertion, its parameters kept), so that its grids fall on the
//! part; written back, it is written so cut. A CC point `(patch, u, v)` beyond that box is
//! refused as outside the patch's parameter box (it is off the part either way).

use std::cell::Cell;
use std::fmt;

use serde::de::{self, Deserializer, SeqAccess, Visitor};
use serde::{Deserialize, Serialize};
use swarf_geom::math::Vec3;

use super::{Format, ReadError};
use crate::compound::{CompoundSurface, EntityRef, Patch, PatchSource, ReadNote};
use crate::surface::{NurbsError, NurbsSurface, ParametricSurface, Surface};
use crate::trim::{Trim, TrimError};

/// Millimetres per inch.
pub const MM_PER_INCH: f64 = 25.4;

#[derive(Deserialize, Serialize, Clone, Copy, Debug, PartialEq)]
enum Units {
    #[serde(rename = "mm")]
    Mm,
    #[serde(rename = "inch", alias = "in")]
    Inch,
}

#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct JsonPatch {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    name: Option<String>,
    degree_u: usize,
    degree_v: usize,
    knots_u: Vec<f64>,
    knots_v: Vec<f64>,
    control_points: Vec<Vec<[f64; 4]>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    trim: Option<JsonTrim>,
}

/// A patch's `trim`: loops of `[u, v]`.
#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct JsonTrim {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    outer: Option<Vec<[f64; 2]>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    holes: Vec<Vec<[f64; 2]>>,
}

/// A validated patch; validation runs inside the deserializer so that errors carry the
/// position (the end of the offending patch object).
struct Checked {
    name: Option<String>,
    surface: NurbsSurface,
    trim: Option<Trim>,
}

thread_local! {
    /// Index of the patch being read while `patches` is read (`None` outside it, and once a
    /// patch's validation has named it), so that `parse` can name the patch of a syntax error.
    static READING_PATCH: Cell<Option<usize>> = const { Cell::new(None) };
}

/// `patches`, each patch validated knowing its index.
fn checked_patches<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<Checked>, D::Error> {
    struct Patches;
    impl<'de> Visitor<'de> for Patches {
        type Value = Vec<Checked>;
        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            f.write_str("an array of patches")
        }
        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<Checked>, A::Error> {
            let mut out = Vec::new();
            loop {
                let index = out.len();
                READING_PATCH.set(Some(index));
                let Some(p) = seq.next_element::<JsonPatch>()? else {
                    break;
                };
                READING_PATCH.set(None);
                out.push(Checked::new(p, index).map_err(de::Error::custom)?);
            }
            READING_PATCH.set(None);
            Ok(out)
        }
    }
    d.deserialize_seq(Patches)
}

impl Checked {
    /// Validates patch `index`; errors name it.
    fn new(p: JsonPatch, index: usize) -> Result<Self, PatchError> {
        let who = match &p.name {
            Some(n) => format!("patch {index} \"{n}\""),
            None => format!("patch {index}"),
        };
        let points: Vec<Vec<Vec3>> = p
            .control_points
            .iter()
            .map(|r| r.iter().map(|c| Vec3::new(c[0], c[1], c[2])).collect())
            .collect();
        let weights: Vec<Vec<f64>> = p
            .control_points
            .iter()
            .map(|r| r.iter().map(|c| c[3]).collect())
            .collect();
        let surface = NurbsSurface::new(
            p.degree_u,
            p.degree_v,
            p.knots_u,
            p.knots_v,
            &points,
            Some(&weights),
        )
        .map_err(|reason| PatchError::Surface {
            who: who.clone(),
            reason,
        })?;
        let trim = match p.trim {
            None => None,
            Some(t) => {
                let given_outer = t.outer.is_some();
                let loop_name = |index: usize| match (given_outer, index) {
                    (true, 0) => "trim.outer".to_string(),
                    (true, k) => format!("trim.holes[{}]", k - 1),
                    (false, k) => format!("trim.holes[{k}]"),
                };
                let trim = Trim::new(&surface.domain(), t.outer, t.holes).map_err(|e| {
                    let index = match e {
                        TrimError::TooFewPoints { index, .. }
                        | TrimError::NotFinite { index, .. } => index,
                    };
                    PatchError::Trim {
                        who,
                        what: loop_name(index),
                        reason: e,
                    }
                })?;
                Some(trim)
            }
        };
        Ok(Checked {
            name: p.name,
            surface,
            trim,
        })
    }
}

/// Why a JSON patch is refused (the reader reports it at the patch's position).
#[derive(Debug, thiserror::Error)]
enum PatchError {
    /// Its numbers do not make a NURBS.
    #[error("{who}: {reason}")]
    Surface {
        /// `patch 3 "floor"`.
        who: String,
        /// Why (in the message, not a separate source).
        reason: NurbsError,
    },
    /// Its trim is refused.
    #[error("{who}: {what} {}", trim_problem(.reason))]
    Trim {
        /// `patch 3 "floor"`.
        who: String,
        /// `trim.outer`, `trim.holes[2]`.
        what: String,
        /// Why (in the message, not a separate source).
        reason: TrimError,
    },
}

/// The trim error's words after the loop's name.
fn trim_problem(e: &TrimError) -> String {
    match e {
        TrimError::TooFewPoints { points, .. } => {
            format!("has {points} distinct point(s); a loop needs at least 3")
        }
        TrimError::NotFinite { point, .. } => format!("point {point} is not finite"),
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CheckedFile {
    #[serde(default)]
    units: Option<Units>,
    #[serde(deserialize_with = "checked_patches")]
    patches: Vec<Checked>,
}

/// Parse swarf JSON.
pub fn parse(text: &str) -> Result<CompoundSurface, ReadError> {
    let syntax = |e: serde_json::Error| ReadError::Syntax {
        format: Format::Json,
        line: e.line(),
        column: e.column(),
        message: match READING_PATCH.take() {
            Some(index) => format!("patch {index}: {}", strip_position(&e)),
            None => strip_position(&e),
        },
    };
    READING_PATCH.set(None);
    let file: CheckedFile = serde_json::from_str(text).map_err(syntax)?;
    let factor = match file.units {
        Some(Units::Inch) => MM_PER_INCH,
        _ => 1.0,
    };
    let mut out = CompoundSurface::default();
    match file.units {
        None => out.notes.push(ReadNote::UnitsAssumed),
        Some(Units::Inch) => out.notes.push(ReadNote::UnitsConverted {
            unit: "inch".into(),
            factor,
        }),
        Some(Units::Mm) => {}
    }
    if file.patches.is_empty() {
        return Err(ReadError::Empty {
            format: Format::Json,
            detail: "; \"patches\" is empty".into(),
        });
    }
    for (index, c) in file.patches.into_iter().enumerate() {
        let surface = if factor == 1.0 {
            c.surface
        } else {
            scaled(&c.surface, factor)
        };
        out.patches.push(Patch {
            name: c.name,
            surface: Surface::Nurbs(surface),
            flipped: false,
            source: PatchSource {
                file: None,
                entity: EntityRef::Json { index },
            },
            trim: c.trim,
        });
    }
    out.fit_domains_to_trims();
    Ok(out)
}

/// A copy of `s` with every control point scaled by `factor` (weights kept).
pub(crate) fn scaled(s: &NurbsSurface, factor: f64) -> NurbsSurface {
    let (nu, nv) = s.net_size();
    let points: Vec<Vec<Vec3>> = (0..nu)
        .map(|i| (0..nv).map(|j| s.control_point(i, j) * factor).collect())
        .collect();
    let weights: Vec<Vec<f64>> = (0..nu)
        .map(|i| (0..nv).map(|j| s.weight(i, j)).collect())
        .collect();
    // Scaling a valid surface by a positive finite factor keeps it valid.
    NurbsSurface::new(
        s.degree_u(),
        s.degree_v(),
        s.knots_u().to_vec(),
        s.knots_v().to_vec(),
        &points,
        Some(&weights),
    )
    .unwrap_or_else(|_| s.clone())
}

fn strip_position(e: &serde_json::Error) -> String {
    let s = e.to_string();
    match s.rfind(" at line ") {
        Some(i) => s[..i].to_string(),
        None => s,
    }
}

/// Why a compound surface cannot be written as swarf JSON.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    /// Only NURBS patches have a JSON form.
    #[error("patch {index} is a {kind}; swarf JSON holds NURBS patches only")]
    NotNurbs {
        /// Patch index.
        index: usize,
        /// Its kind.
        kind: &'static str,
    },
    /// serde_json failed (it does not for these types, but the error is not hidden).
    #[error(transparent)]
    Json(#[from] serde_json::Error),
}

#[derive(Serialize)]
struct OutFile {
    units: Units,
    patches: Vec<JsonPatch>,
}

/// Write swarf JSON (units mm). A flipped patch is written with its u direction reversed, so
/// that `S_u × S_v` points to the cutter side as the format requires (its trim, mirrored to
/// match). A trim without an outer loop (the parameter box) is written without `outer`.
pub fn to_string(surface: &CompoundSurface) -> Result<String, WriteError> {
    let mut patches = Vec::with_capacity(surface.patches.len());
    for (index, p) in surface.patches.iter().enumerate() {
        let Surface::Nurbs(s) = &p.surface else {
            return Err(WriteError::NotNurbs {
                index,
                kind: p.surface.kind(),
            });
        };
        let s = if p.flipped { s.reversed_u() } else { s.clone() };
        // Reversing u maps u to a + b − u (the ends of the knot vector); the trim follows.
        let (a, b) = (s.knots_u()[0], s.knots_u()[s.knots_u().len() - 1]);
        let mirrored = |l: &[[f64; 2]]| -> Vec<[f64; 2]> {
            l.iter()
                .map(|&[u, v]| if p.flipped { [a + b - u, v] } else { [u, v] })
                .collect()
        };
        let trim = p.trim.as_ref().map(|t| JsonTrim {
            outer: t.outer().map(mirrored),
            holes: t.holes().iter().map(|l| mirrored(l)).collect(),
        });
        let (nu, nv) = s.net_size();
        let control_points = (0..nu)
            .map(|i| {
                (0..nv)
                    .map(|j| {
                        let c = s.control_point(i, j);
                        [c.x, c.y, c.z, s.weight(i, j)]
                    })
                    .collect()
            })
            .collect();
        patches.push(JsonPatch {
            name: p.name.clone(),
            degree_u: s.degree_u(),
            degree_v: s.degree_v(),
            knots_u: s.knots_u().to_vec(),
            knots_v: s.knots_v().to_vec(),
            control_points,
            trim,
        });
    }
    Ok(serde_json::to_string_pretty(&OutFile {
        units: Units::Mm,
        patches,
    })?)
}
