//! IGES 5.3 surfaces: entity 128 (rational B-spline surface) as patches; entity 126
//! (rational B-spline curve) parsed for trims; 142 (curve on a parametric surface) and 144
//! (trimmed parametric surface) parsed and reported — **trims are not honoured**: each trimmed
//! 128 is used whole, with a [`ReadNote::TrimNotHonoured`], and the trim structure is returned in
//! [`IgesDocument::trims`] for a later stage.
//!
//! The fixed-column format: 80-column records, section letter in column 73 (S, G, D, P, T),
//! sequence number in 74–80. The G section gives the parameter and record delimiters (defaults
//! `,` and `;`), the units flag and unit name (field 14/15: inch, mm, foot, mile, metre, km,
//! mil, micron, cm, microinch), converted to mm. The model-space scale (field 13) is not
//! applied. Directory entries are two records of 8-column fields; parameter data lives in
//! columns 1–64 of the P records. Transformation matrices (entity 124) referenced by a 128 or
//! 126 are applied. Hollerith strings (`5HHello`) and `D` exponents are understood.

use std::collections::HashMap;

use swarf_geom::math::Vec3;

use super::{Format, ReadError};
use crate::compound::{CompoundSurface, EntityRef, Patch, PatchSource, ReadNote};
use crate::surface::{NurbsSurface, Surface};

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
    parse_document(text).map(|d| d.surface)
}

/// Parse IGES text to patches, curves and trims.
pub fn parse_document(text: &str) -> Result<IgesDocument, ReadError> {
    let mut file = Sections::split(text)?;
    let global = file.global()?;
    let entries = file.directory()?;
    let mut doc = IgesDocument::default();
    let mut patch_of_de = HashMap::new();
    let mut skipped = Vec::new();
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
            114 | 118 | 120 | 122 | 140 | 190 | 192 | 194 | 196 | 198 => {
                skipped.push(ReadNote::UnsupportedSurface {
                    entity: format!("D{}", e.de),
                    kind: format!("IGES {}", e.kind),
                })
            }
            _ => {}
        }
    }
    // Curves used in a surface's parameter space are not in model units: undo the scaling.
    for e in entries.iter().filter(|e| e.kind == 142) {
        let p = file.params(e)?;
        let bptr = p.int(3, "BPTR")?;
        if let Some(c) = doc.curves.iter_mut().find(|c| c.de as i64 == bptr) {
            if global.factor != 1.0 {
                c.points.iter_mut().for_each(|q| *q /= global.factor);
            }
        }
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
        let patch = usize::try_from(pts)
            .ok()
            .and_then(|d| patch_of_de.get(&d).copied());
        if let Some(k) = patch {
            doc.surface.notes.push(ReadNote::TrimNotHonoured {
                patch: k,
                by: format!(
                    "IGES 144 at D{} (outer boundary {}, {} inner)",
                    e.de,
                    if pto > 0 {
                        format!("142 at D{pto}")
                    } else {
                        "the patch's own".into()
                    },
                    inner.len()
                ),
            });
        }
        doc.trims.push(IgesTrim {
            de: e.de,
            patch,
            outer: usize::try_from(pto).ok().filter(|&d| d > 0),
            inner,
        });
    }
    if doc.surface.patches.is_empty() {
        return Err(ReadError::Empty {
            format: Format::Iges,
            detail: if skipped.is_empty() {
                "; no entity 128".into()
            } else {
                format!(
                    "; skipped: {}",
                    skipped
                        .iter()
                        .map(ToString::to_string)
                        .collect::<Vec<_>>()
                        .join("; ")
                )
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

/// One physical record: its 1-based line number, section letter, columns 1–72.
struct Record<'a> {
    line: usize,
    data: &'a str,
}

struct Sections<'a> {
    g: Vec<Record<'a>>,
    d: Vec<Record<'a>>,
    p: Vec<Record<'a>>,
    pdelim: u8,
    rdelim: u8,
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
    label: Option<String>,
}

impl<'a> Sections<'a> {
    fn split(text: &'a str) -> Result<Self, ReadError> {
        let mut s = Sections {
            g: Vec::new(),
            d: Vec::new(),
            p: Vec::new(),
            pdelim: b',',
            rdelim: b';',
        };
        let mut seen_any = false;
        for (i, raw) in text.lines().enumerate() {
            let line = i + 1;
            let raw = raw.trim_end_matches('\r');
            if raw.trim().is_empty() {
                continue;
            }
            if !raw.is_ascii() || raw.len() < 73 {
                return Err(syntax(
                    line,
                    raw.len().min(72) + 1,
                    format!(
                        "found a {}-character{} record, expected 80 ASCII columns with the section letter in column 73",
                        raw.chars().count(),
                        if raw.is_ascii() { "" } else { " non-ASCII" }
                    ),
                ));
            }
            seen_any = true;
            let rec = Record {
                line,
                data: &raw[..72],
            };
            match raw.as_bytes()[72] {
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
        let text: String = self.g.iter().map(|r| r.data).collect();
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
        // Fields 3 onwards, after the delimiter that ends field 2.
        let fields = match rest.as_bytes().first() {
            Some(&c) if c == pd => {
                tokenize(&rest[1..], pd, rd).map_err(|(at, m)| syntax(line, pos + 2 + at, m))?
            }
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
            let label = field(b, 7);
            out.push(Entry {
                de: 2 * k + 1,
                line: a.line,
                kind: kind as u32,
                pointer: int(a, 1, "parameter data pointer")?,
                lines: int(b, 3, "parameter line count")?,
                transform: int(a, 6, "transformation matrix pointer")?,
                label: (!label.is_empty()).then(|| label.to_string()),
            });
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
        NurbsSurface::new(m1, m2, ku, kv, &points, Some(&weights)).map_err(|source| {
            ReadError::Surface {
                format: Format::Iges,
                line: e.line,
                entity: format!("entity 128 at D{}", e.de),
                source,
            }
        })
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

fn field<'a>(r: &Record<'a>, i: usize) -> &'a str {
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
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut start = 0;
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c == pd || c == rd {
            out.push(&text[start..i]);
            if c == rd {
                return Ok(out);
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
                let n: usize = text[i..j]
                    .parse()
                    .map_err(|_| (i, "Hollerith length too large".to_string()))?;
                let end = j + 1 + n;
                if end > b.len() {
                    return Err((
                        i,
                        format!("Hollerith string of {n} characters runs past the end of the data"),
                    ));
                }
                i = end;
                continue;
            }
            i = j;
            continue;
        }
        i += 1;
    }
    Err((
        b.len(),
        format!(
            "found the end of the data, expected the record delimiter `{}`",
            rd as char
        ),
    ))
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
