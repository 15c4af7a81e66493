//! STEP (ISO 10303-21, AP203/AP214) surfaces.
//!
//! Read: `B_SPLINE_SURFACE_WITH_KNOTS` (simple, and the complex rational form with
//! `RATIONAL_B_SPLINE_SURFACE`), `PLANE`, `CYLINDRICAL_SURFACE`, `CONICAL_SURFACE`,
//! `SPHERICAL_SURFACE`, `TOROIDAL_SURFACE`.
//!
//! * **Patches**: when the file has faces (`ADVANCED_FACE`, `FACE_SURFACE`), one patch per face,
//!   named after the face (or its surface), flipped when the face's `same_sense` is `.F.`;
//!   faces on other surface kinds are skipped with a [`ReadNote::UnsupportedSurface`]. A file
//!   without faces gives one patch per surface instance.
//! * **Face trims**: a face's bounds become the patch's [`Trim`] (in the surface's own
//!   parameters), with a [`ReadNote::Trimmed`]: the `FACE_OUTER_BOUND` is the outer loop (no
//!   such bound: the loop with the largest parameter box), the other bounds are holes;
//!   `VERTEX_LOOP`s (a pole, an apex) enclose nothing and are left out, so a face bounded only
//!   by them is untrimmed. An `EDGE_LOOP` is walked through its `ORIENTED_EDGE`s and their
//!   `EDGE_CURVE`s (from the start to the end `VERTEX_POINT`, along or against the curve as
//!   `same_sense` says); a `POLY_LOOP` is a polygon. Edge curves read: `LINE`, `CIRCLE`,
//!   `ELLIPSE` (between the vertices' angles, a full turn when they are one vertex),
//!   `B_SPLINE_CURVE_WITH_KNOTS` (simple or rational complex; between the vertices' parameters,
//!   found by point inversion), `POLYLINE`, and through `SURFACE_CURVE`, `SEAM_CURVE`,
//!   `INTERSECTION_CURVE` and `TRIMMED_CURVE` their 3-D curve (run backwards for a trimmed
//!   curve whose `sense_agreement` is `.F.`). Each edge is sampled so that
//!   the chords, in parameters, stay within min(1e-3 mm, 1e-5 of the surface's size) of the
//!   curve on the surface (at least 4 steps per quarter turn, 8 per knot span), and each
//!   sample is mapped to the surface's parameters: in closed form on the elementary surfaces,
//!   by Newton inversion seeded from the previous sample (first: the nearest point of a grid)
//!   on B-spline surfaces. Angles are unwrapped along a loop; a loop is moved whole turns to
//!   lie in the parameter box (whose angle range may then start at the outer loop's), a hole
//!   across the box's edge is copied to the other side, a seam edge met twice on the same
//!   angle (through a pole or an apex) is moved a turn. Through a pole or an apex a loop runs
//!   along the box's edge there the way the face's side says (left of the loop, by the bound's
//!   orientation and the face's `same_sense`: towards −u along the top edge, +u along the
//!   bottom, up to a whole turn), so lunes wider than a half turn and their complements are
//!   told apart. A loop that winds once around the axis (a circle bounding a cylinder) is cut
//!   at the box's edge: two of them make the outer loop (the band between them; on a torus, of
//!   the two bands the one on the loops' face side, the box's other angle starting at it when
//!   it does not fit), one is closed along the box's far edge on the face's side. The outer
//!   loop's points on the box's edges across an angle sit a hair (1e-9 of a turn) outside it,
//!   so points on the seam inside a hole across it are off the part. Linear parameter ranges grow to
//!   hold the loops. An edge curve of another kind, a sample more than 1e-4 of the surface's
//!   size (+ 1e-3 mm) off the surface, edges that do not join, a loop that does not close in
//!   the parameters or winds otherwise, or more than 200 000 points for a face (2 000 000 for
//!   the file) leave the patch untrimmed with a [`ReadNote::TrimNotHonoured`] saying why.
//! * **Units**: the length unit of the `GLOBAL_UNIT_ASSIGNED_CONTEXT` (`SI_UNIT` with any prefix,
//!   or a `CONVERSION_BASED_UNIT` such as INCH or FOOT, resolved through its
//!   `LENGTH_MEASURE_WITH_UNIT`) scales lengths to mm; the plane-angle unit scales cone angles.
//!   No unit: mm, with a [`ReadNote::UnitsAssumed`].
//! * **Parameter boxes of elementary surfaces**: angles take their full range (u ∈ [0, 2π];
//!   sphere v ∈ [−π/2, π/2]; torus v ∈ [0, 2π]); linear parameters (plane u, v; cylinder and
//!   cone v) span the face's boundary: its vertices, the control points of its B-spline edges
//!   and its circles and ellipses, projected — a range that holds the face, possibly larger.
//!   Without a face, or with a boundary of zero extent, they take [`DEFAULT_LINEAR_RANGE`] and
//!   a [`ReadNote::DefaultParameterBox`] says so.

use std::collections::{HashMap, HashSet};

use swarf_geom::math::Vec3;
use swarf_geom::Frame;

use super::{line_col, Format, ReadError, Uv, MAX_GRID_SEARCHES, MAX_HALVINGS, MAX_TRIM_POINTS};
use crate::compound::{CompoundSurface, EntityRef, Patch, PatchSource, ReadNote};
use crate::surface::invert::Inverter;
use crate::surface::{
    ConicalSurface, CylindricalSurface, NurbsSurface, ParamBox, ParametricSurface, PlaneSurface,
    SphericalSurface, Surface, ToroidalSurface,
};
use crate::trim::Trim;

/// Range (mm) of a linear parameter of an elementary surface when no face bounds it.
pub const DEFAULT_LINEAR_RANGE: [f64; 2] = [-100.0, 100.0];

/// Deepest nesting of parameter lists accepted (real files use 3).
const MAX_DEPTH: usize = 32;

/// A parameter value.
#[derive(Clone, Debug, PartialEq)]
enum Param {
    Ref(u64),
    Num(f64),
    Str(String),
    Enum(String),
    List(Vec<Param>),
    Typed(String, Vec<Param>),
    Null,
    Derived,
}

#[derive(Debug)]
struct Instance {
    offset: usize,
    parts: Vec<(String, Vec<Param>)>,
}

impl Instance {
    fn part(&self, name: &str) -> Option<&[Param]> {
        self.parts
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, p)| p.as_slice())
    }
    fn first_name(&self) -> &str {
        self.parts.first().map_or("", |(n, _)| n.as_str())
    }
}

/// Parse STEP text.
pub fn parse(text: &str) -> Result<CompoundSurface, ReadError> {
    let map = Lexer::new(text).instances()?;
    Model {
        text,
        map,
        length: 1.0,
        angle: 1.0,
    }
    .read()
}

// ---------------------------------------------------------------------------------------------
// Lexing and parsing of the exchange structure.

struct Lexer<'a> {
    text: &'a str,
    b: &'a [u8],
    pos: usize,
}

impl<'a> Lexer<'a> {
    fn new(text: &'a str) -> Self {
        Self {
            text,
            b: text.as_bytes(),
            pos: 0,
        }
    }

    fn err(&self, at: usize, message: String) -> ReadError {
        let (line, column) = line_col(self.text, at);
        ReadError::Syntax {
            format: Format::Step,
            line,
            column,
            message,
        }
    }

    fn found(&self) -> String {
        match self.b.get(self.pos) {
            None => "end of file".into(),
            Some(_) => {
                let s: String = self
                    .text
                    .get(self.pos..)
                    .unwrap_or("")
                    .chars()
                    .take(12)
                    .collect();
                format!("`{}`", s.split_whitespace().next().unwrap_or(""))
            }
        }
    }

    fn skip_ws(&mut self) -> Result<(), ReadError> {
        loop {
            while self.pos < self.b.len() && self.b[self.pos].is_ascii_whitespace() {
                self.pos += 1;
            }
            if self.b[self.pos..].starts_with(b"/*") {
                let start = self.pos;
                match self.text[self.pos + 2..].find("*/") {
                    Some(i) => self.pos += 2 + i + 2,
                    None => return Err(self.err(start, "unterminated comment `/*`".into())),
                }
            } else {
                return Ok(());
            }
        }
    }

    fn peek(&mut self) -> Result<Option<u8>, ReadError> {
        self.skip_ws()?;
        Ok(self.b.get(self.pos).copied())
    }

    fn expect(&mut self, c: u8, what: &str) -> Result<(), ReadError> {
        if self.peek()? == Some(c) {
            self.pos += 1;
            Ok(())
        } else {
            Err(self.err(self.pos, format!("found {}, expected {what}", self.found())))
        }
    }

    fn keyword(&mut self) -> Option<String> {
        let start = self.pos;
        if !self
            .b
            .get(self.pos)
            .is_some_and(|c| c.is_ascii_alphabetic() || *c == b'_' || *c == b'!')
        {
            return None;
        }
        self.pos += 1;
        while self
            .b
            .get(self.pos)
            .is_some_and(|c| c.is_ascii_alphanumeric() || *c == b'_' || *c == b'-')
        {
            self.pos += 1;
        }
        Some(self.text[start..self.pos].to_ascii_uppercase())
    }

    fn integer(&mut self) -> Option<u64> {
        let start = self.pos;
        while self.b.get(self.pos).is_some_and(u8::is_ascii_digit) {
            self.pos += 1;
        }
        self.text[start..self.pos].parse().ok()
    }

    /// Every instance of every DATA section.
    fn instances(mut self) -> Result<HashMap<u64, Instance>, ReadError> {
        let mut map = HashMap::new();
        let mut saw_data = false;
        loop {
            // Skip to the next `DATA ;` (headers and other sections hold no geometry).
            match self.next_data()? {
                false => break,
                true => saw_data = true,
            }
            loop {
                self.skip_ws()?;
                let at = self.pos;
                match self.b.get(at).copied() {
                    Some(b'#') => {
                        self.pos += 1;
                        let id = self.integer().ok_or_else(|| {
                            self.err(
                                at,
                                format!(
                                    "found {}, expected an instance name like #12",
                                    self.found()
                                ),
                            )
                        })?;
                        self.expect(b'=', "`=` after the instance name")?;
                        let parts = self.record()?;
                        self.expect(b';', "`;` at the end of the instance")?;
                        if map.insert(id, Instance { offset: at, parts }).is_some() {
                            return Err(self.err(at, format!("instance #{id} is defined twice")));
                        }
                    }
                    Some(_) => {
                        let kw = self.keyword();
                        if kw.as_deref() == Some("ENDSEC") {
                            self.expect(b';', "`;` after ENDSEC")?;
                            break;
                        }
                        self.pos = at;
                        return Err(self.err(
                            at,
                            format!(
                                "found {}, expected an instance `#n = …;` or ENDSEC",
                                self.found()
                            ),
                        ));
                    }
                    None => {
                        return Err(self.err(at, "found end of file, expected ENDSEC".into()));
                    }
                }
            }
        }
        if !saw_data {
            let (line, column) = line_col(self.text, self.pos);
            return Err(ReadError::Syntax {
                format: Format::Step,
                line,
                column,
                message: "found end of file, expected a DATA section (is this a STEP file?)".into(),
            });
        }
        Ok(map)
    }

    /// Advance past the next `DATA;` (or `DATA(…);`); false at end of file.
    fn next_data(&mut self) -> Result<bool, ReadError> {
        loop {
            match self.peek()? {
                None => return Ok(false),
                Some(b'\'') => {
                    self.string()?;
                }
                Some(c) if c.is_ascii_alphabetic() => {
                    let kw = self.keyword();
                    if kw.as_deref() == Some("DATA") {
                        if self.peek()? == Some(b'(') {
                            self.param(0)?;
                        }
                        self.expect(b';', "`;` after DATA")?;
                        return Ok(true);
                    }
                }
                Some(_) => self.pos += 1,
            }
        }
    }

    /// `KEYWORD(params)` or `(KEYWORD(params) KEYWORD(params) …)`.
    fn record(&mut self) -> Result<Vec<(String, Vec<Param>)>, ReadError> {
        if self.peek()? == Some(b'(') {
            self.pos += 1;
            let mut parts = Vec::new();
            while self.peek()? != Some(b')') {
                parts.push(self.simple()?);
            }
            self.pos += 1;
            if parts.is_empty() {
                return Err(self.err(self.pos - 1, "empty complex instance `()`".into()));
            }
            Ok(parts)
        } else {
            Ok(vec![self.simple()?])
        }
    }

    fn simple(&mut self) -> Result<(String, Vec<Param>), ReadError> {
        self.skip_ws()?;
        let at = self.pos;
        let kw = self.keyword().ok_or_else(|| {
            self.err(
                at,
                format!("found {}, expected an entity name", self.found()),
            )
        })?;
        let params = self.list(0)?;
        Ok((kw, params))
    }

    fn list(&mut self, depth: usize) -> Result<Vec<Param>, ReadError> {
        if depth > MAX_DEPTH {
            return Err(self.err(self.pos, format!("lists nested deeper than {MAX_DEPTH}")));
        }
        self.expect(b'(', "`(`")?;
        let mut out = Vec::new();
        if self.peek()? == Some(b')') {
            self.pos += 1;
            return Ok(out);
        }
        loop {
            out.push(self.param(depth + 1)?);
            match self.peek()? {
                Some(b',') => self.pos += 1,
                Some(b')') => {
                    self.pos += 1;
                    return Ok(out);
                }
                _ => {
                    return Err(self.err(
                        self.pos,
                        format!(
                            "found {}, expected `,` or `)` in a parameter list",
                            self.found()
                        ),
                    ))
                }
            }
        }
    }

    fn string(&mut self) -> Result<String, ReadError> {
        let start = self.pos;
        self.pos += 1;
        let mut s = String::new();
        loop {
            let rest = &self.text[self.pos..];
            match rest.find('\'') {
                None => return Err(self.err(start, "unterminated string".into())),
                Some(i) => {
                    s.push_str(&rest[..i]);
                    self.pos += i + 1;
                    if self.b.get(self.pos) == Some(&b'\'') {
                        s.push('\'');
                        self.pos += 1;
                    } else {
                        return Ok(s);
                    }
                }
            }
        }
    }

    fn param(&mut self, depth: usize) -> Result<Param, ReadError> {
        let at = self.pos;
        match self.peek()? {
            Some(b'#') => {
                self.pos += 1;
                self.integer().map(Param::Ref).ok_or_else(|| {
                    self.err(at, "found `#`, expected an instance name like #12".into())
                })
            }
            Some(b'$') => {
                self.pos += 1;
                Ok(Param::Null)
            }
            Some(b'*') => {
                self.pos += 1;
                Ok(Param::Derived)
            }
            Some(b'\'') => self.string().map(Param::Str),
            Some(b'"') => {
                let rest = &self.text[self.pos + 1..];
                let i = rest
                    .find('"')
                    .ok_or_else(|| self.err(at, "unterminated binary `\"`".into()))?;
                self.pos += i + 2;
                Ok(Param::Str(rest[..i].to_string()))
            }
            Some(b'.') => {
                let start = self.pos;
                self.pos += 1;
                let kw = self.keyword().unwrap_or_default();
                if self.b.get(self.pos) != Some(&b'.') {
                    return Err(self.err(
                        start,
                        format!("found {}, expected an enumeration like .T.", self.found()),
                    ));
                }
                self.pos += 1;
                Ok(Param::Enum(kw))
            }
            Some(b'(') => self.list(depth).map(Param::List),
            Some(c) if c == b'+' || c == b'-' || c.is_ascii_digit() => {
                let start = self.pos;
                self.pos += 1;
                while self.b.get(self.pos).is_some_and(|c| {
                    c.is_ascii_digit() || matches!(c, b'.' | b'E' | b'e' | b'+' | b'-')
                }) {
                    self.pos += 1;
                }
                let s = &self.text[start..self.pos];
                let v = s
                    .parse::<f64>()
                    .ok()
                    .or_else(|| s.strip_suffix('.').and_then(|t| t.parse().ok()))
                    .or_else(|| s.replace(".E", "E").replace(".e", "e").parse().ok())
                    .filter(|v: &f64| v.is_finite())
                    .ok_or_else(|| self.err(start, format!("found `{s}`, expected a number")))?;
                Ok(Param::Num(v))
            }
            Some(c) if c.is_ascii_alphabetic() || c == b'_' => {
                let kw = self.keyword().unwrap_or_default();
                let inner = self.list(depth)?;
                Ok(Param::Typed(kw, inner))
            }
            _ => Err(self.err(at, format!("found {}, expected a parameter", self.found()))),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// From instances to surfaces.

struct Model<'a> {
    text: &'a str,
    map: HashMap<u64, Instance>,
    /// Millimetres per file length unit.
    length: f64,
    /// Radians per file plane-angle unit.
    angle: f64,
}

const SURFACES: [&str; 6] = [
    "B_SPLINE_SURFACE_WITH_KNOTS",
    "PLANE",
    "CYLINDRICAL_SURFACE",
    "CONICAL_SURFACE",
    "SPHERICAL_SURFACE",
    "TOROIDAL_SURFACE",
];

const OTHER_SURFACES: [&str; 10] = [
    "B_SPLINE_SURFACE",
    "BEZIER_SURFACE",
    "UNIFORM_SURFACE",
    "QUASI_UNIFORM_SURFACE",
    "SURFACE_OF_REVOLUTION",
    "SURFACE_OF_LINEAR_EXTRUSION",
    "OFFSET_SURFACE",
    "RECTANGULAR_TRIMMED_SURFACE",
    "CURVE_BOUNDED_SURFACE",
    "DEGENERATE_TOROIDAL_SURFACE",
];

fn supported(inst: &Instance) -> bool {
    SURFACES.iter().any(|s| inst.part(s).is_some())
}

fn is_surface(inst: &Instance) -> bool {
    supported(inst) || OTHER_SURFACES.iter().any(|s| inst.part(s).is_some())
}

fn kind_name(inst: &Instance) -> String {
    inst.parts
        .iter()
        .map(|(n, _)| n.as_str())
        .find(|n| SURFACES.contains(n) || OTHER_SURFACES.contains(n))
        .unwrap_or(inst.first_name())
        .to_string()
}

type R<T> = Result<T, ReadError>;

impl Model<'_> {
    fn line(&self, id: u64) -> usize {
        self.map
            .get(&id)
            .map_or(0, |i| line_col(self.text, i.offset).0)
    }

    fn bad(&self, id: u64, message: impl Into<String>) -> ReadError {
        ReadError::Entity {
            format: Format::Step,
            line: self.line(id),
            entity: format!("#{id}"),
            message: message.into(),
        }
    }

    fn get(&self, from: u64, id: u64) -> R<&Instance> {
        self.map
            .get(&id)
            .ok_or_else(|| self.bad(from, format!("refers to #{id}, which is not defined")))
    }

    fn num(&self, id: u64, p: Option<&Param>, what: &str) -> R<f64> {
        match p {
            Some(Param::Num(v)) => Ok(*v),
            Some(Param::Typed(_, inner)) if inner.len() == 1 => self.num(id, inner.first(), what),
            other => Err(self.bad(
                id,
                format!("{what}: found {}, expected a number", show(other)),
            )),
        }
    }

    fn reference(&self, id: u64, p: Option<&Param>, what: &str) -> R<u64> {
        match p {
            Some(Param::Ref(r)) => Ok(*r),
            other => Err(self.bad(
                id,
                format!("{what}: found {}, expected a reference #n", show(other)),
            )),
        }
    }

    fn list<'p>(&self, id: u64, p: Option<&'p Param>, what: &str) -> R<&'p [Param]> {
        match p {
            Some(Param::List(l)) => Ok(l),
            other => Err(self.bad(
                id,
                format!("{what}: found {}, expected a list", show(other)),
            )),
        }
    }

    fn logical(&self, id: u64, p: Option<&Param>, what: &str) -> R<bool> {
        match p {
            Some(Param::Enum(e)) if e == "T" => Ok(true),
            Some(Param::Enum(e)) if e == "F" => Ok(false),
            other => Err(self.bad(
                id,
                format!("{what}: found {}, expected .T. or .F.", show(other)),
            )),
        }
    }

    fn name(p: Option<&Param>) -> Option<String> {
        match p {
            Some(Param::Str(s)) if !s.trim().is_empty() => Some(s.clone()),
            _ => None,
        }
    }

    /// A CARTESIAN_POINT's coordinates (file units).
    fn raw_point(&self, from: u64, id: u64) -> R<Vec3> {
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

    fn point(&self, from: u64, id: u64) -> R<Vec3> {
        Ok(self.raw_point(from, id)? * self.length)
    }

    fn direction(&self, from: u64, p: Option<&Param>, default: Vec3) -> R<Vec3> {
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

    fn placement(&self, from: u64, p: Option<&Param>) -> R<Frame> {
        let id = self.reference(from, p, "position")?;
        let inst = self.get(from, id)?;
        let a = inst.part("AXIS2_PLACEMENT_3D").ok_or_else(|| {
            self.bad(
                id,
                format!("found {}, expected AXIS2_PLACEMENT_3D", inst.first_name()),
            )
        })?;
        let loc = self.reference(id, a.get(1), "location")?;
        let origin = self.point(id, loc)?;
        let z = self.direction(id, a.get(2), Vec3::Z)?;
        let x = self.direction(id, a.get(3), Vec3::X)?;
        Ok(Frame::from_axis_and_x(origin, z, x))
    }

    /// Conversion factor of a unit: mm per length unit, or radians per angle unit.
    fn unit_factor(&self, from: u64, id: u64, depth: usize) -> R<(f64, String)> {
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
            let mp = mi
                .parts
                .iter()
                .find(|(n, _)| n.ends_with("MEASURE_WITH_UNIT"))
                .map(|(_, p)| p.as_slice())
                .filter(|p| p.len() >= 2)
                .ok_or_else(|| self.bad(m, "expected a …_MEASURE_WITH_UNIT"))?;
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

    fn units(&mut self, notes: &mut Vec<ReadNote>) -> R<()> {
        let mut ids: Vec<u64> = self.map.keys().copied().collect();
        ids.sort_unstable();
        let mut length = None;
        let mut angle = None;
        for id in ids {
            let Some(g) = self.map[&id].part("GLOBAL_UNIT_ASSIGNED_CONTEXT") else {
                continue;
            };
            let units = self.list(id, g.first(), "units")?.to_vec();
            for u in &units {
                let uid = self.reference(id, Some(u), "unit")?;
                let ui = self.get(id, uid)?;
                if length.is_none() && ui.part("LENGTH_UNIT").is_some() {
                    length = Some(self.unit_factor(id, uid, 0)?);
                } else if angle.is_none() && ui.part("PLANE_ANGLE_UNIT").is_some() {
                    angle = Some(self.unit_factor(id, uid, 0)?.0);
                }
            }
        }
        match length {
            None => notes.push(ReadNote::UnitsAssumed),
            Some((f, label)) => {
                if f != 1.0 {
                    notes.push(ReadNote::UnitsConverted {
                        unit: label,
                        factor: f,
                    });
                }
                self.length = f;
            }
        }
        self.angle = angle.unwrap_or(1.0);
        Ok(())
    }

    fn read(mut self) -> R<CompoundSurface> {
        let mut out = CompoundSurface::default();
        self.units(&mut out.notes)?;
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
        let mut skipped = Vec::new();
        let mut budget = MAX_FILE_TRIM_POINTS;
        if faces.is_empty() {
            for &id in &ids {
                let inst = &self.map[&id];
                if !is_surface(inst) {
                    continue;
                }
                if !supported(inst) {
                    skipped.push(ReadNote::UnsupportedSurface {
                        entity: format!("#{id}"),
                        kind: kind_name(inst),
                    });
                    continue;
                }
                let index = out.patches.len();
                let (surface, name) = self.surface(id, None, index, &mut out.notes)?;
                out.patches.push(Patch {
                    name,
                    surface,
                    flipped: false,
                    source: PatchSource {
                        file: None,
                        entity: EntityRef::Step {
                            surface: id,
                            face: None,
                        },
                    },
                    trim: None,
                });
            }
        } else {
            for &fid in &faces {
                let f = &self.map[&fid];
                let p = f
                    .part("ADVANCED_FACE")
                    .or_else(|| f.part("FACE_SURFACE"))
                    .unwrap_or(&[]);
                let sid = self.reference(fid, p.get(2), "face geometry")?;
                let same_sense = self.logical(fid, p.get(3), "same_sense")?;
                let sinst = self.get(fid, sid)?;
                if !supported(sinst) {
                    skipped.push(ReadNote::UnsupportedSurface {
                        entity: format!("#{sid} (face #{fid})"),
                        kind: kind_name(sinst),
                    });
                    continue;
                }
                let index = out.patches.len();
                let bounds = p.get(1).cloned();
                let (mut surface, sname) = self.surface(
                    sid,
                    bounds.as_ref().map(|b| (fid, b)),
                    index,
                    &mut out.notes,
                )?;
                let by = format!("STEP face #{fid}");
                let trim =
                    match self.face_trim(fid, bounds.as_ref(), same_sense, &surface, &mut budget) {
                        Ok(Some(t)) => {
                            out.notes.push(ReadNote::Trimmed {
                                patch: index,
                                by,
                                loops: t.trim.loops().len(),
                                points: t.trim.loops().iter().map(Vec::len).sum(),
                            });
                            set_domain(&mut surface, t.domain);
                            Some(t.trim)
                        }
                        Ok(None) => None,
                        Err(why) => {
                            out.notes.push(ReadNote::TrimNotHonoured {
                                patch: index,
                                by: format!("{by} ({why})"),
                            });
                            None
                        }
                    };
                out.patches.push(Patch {
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
                });
            }
        }
        if out.patches.is_empty() {
            let detail = if skipped.is_empty() {
                String::new()
            } else {
                format!(
                    "; skipped: {}",
                    skipped
                        .iter()
                        .map(ToString::to_string)
                        .collect::<Vec<_>>()
                        .join("; ")
                )
            };
            return Err(ReadError::Empty {
                format: Format::Step,
                detail,
            });
        }
        out.notes.extend(skipped);
        Ok(out)
    }

    /// The surface `id`, bounded (for elementary kinds) by the face bounds when given.
    fn surface(
        &self,
        id: u64,
        face: Option<(u64, &Param)>,
        index: usize,
        notes: &mut Vec<ReadNote>,
    ) -> R<(Surface, Option<String>)> {
        let inst = &self.map[&id];
        if inst.part("B_SPLINE_SURFACE_WITH_KNOTS").is_some() {
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

    fn bspline(&self, id: u64, inst: &Instance) -> R<(Surface, Option<String>)> {
        // Simple entity: all attributes in one part; complex: split over parts.
        let k = inst.part("B_SPLINE_SURFACE_WITH_KNOTS").unwrap_or(&[]);
        let (name, head, knots): (Option<String>, &[Param], &[Param]) =
            if let Some(b) = inst.part("B_SPLINE_SURFACE") {
                let name = inst
                    .part("REPRESENTATION_ITEM")
                    .and_then(|r| Self::name(r.first()));
                (name, b, k)
            } else {
                if k.len() < 13 {
                    return Err(self.bad(
                        id,
                        format!(
                            "B_SPLINE_SURFACE_WITH_KNOTS has {} attributes, expected 13",
                            k.len()
                        ),
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
        let knots_u = self.knots(id, knots.first(), knots.get(2), "u", nu + du + 1)?;
        let knots_v = self.knots(id, knots.get(1), knots.get(3), "v", nv + dv + 1)?;
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
            |source| ReadError::Surface {
                format: Format::Step,
                line: self.line(id),
                entity: format!("#{id}"),
                source,
            },
        )?;
        Ok((Surface::Nurbs(s), name))
    }

    /// Expand (multiplicities, knots) into a knot vector, refusing a total other than `expected`
    /// before allocating it.
    fn knots(
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

    /// Points (mm) that bound a face: vertices, B-spline edge control points, circle and ellipse
    /// samples reachable from its bounds (not through placements, lines or pcurves).
    fn boundary_points(&self, face: u64, bounds: &Param) -> R<Vec<Vec3>> {
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
                let f = self.placement(id, c.get(1))?;
                let a = self.num(id, c.get(2), "radius")? * self.length;
                let b = match c.get(3) {
                    Some(p) => self.num(id, Some(p), "semi_axis_2")? * self.length,
                    None => a,
                };
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

// ---------------------------------------------------------------------------------------------
// Face bounds as trims.

/// Most points in all the trims of a file.
const MAX_FILE_TRIM_POINTS: usize = 2_000_000;
/// Deepest nesting of curves (a SURFACE_CURVE of a TRIMMED_CURVE of …) and of edges.
const MAX_CURVE_DEPTH: usize = 8;
/// Most control points of a B-spline edge curve, and most points of a POLYLINE or POLY_LOOP.
const MAX_CURVE_POINTS: usize = 100_000;

/// A trim (or a part of one), or why it cannot be honoured.
type Built<T> = Result<T, String>;

/// A model-space edge curve (mm).
enum Curve {
    /// `p + t·d`.
    Line { p: Vec3, d: Vec3 },
    /// `origin + a·cos t·x + b·sin t·y` (a circle when `a = b`).
    Conic { f: Frame, a: f64, b: f64 },
    Spline {
        degree: usize,
        knots: Vec<f64>,
        /// Control points times weights, and the weights.
        points: Vec<(Vec3, f64)>,
    },
    /// Vertices; `t ∈ [0, n − 1]`, vertex `k` at `t = k`.
    Polyline(Vec<Vec3>),
}

impl Curve {
    fn point(&self, t: f64) -> Vec3 {
        match self {
            Curve::Line { p, d } => *p + t * *d,
            Curve::Conic { f, a, b } => f.origin + a * t.cos() * f.x + b * t.sin() * f.y,
            Curve::Spline {
                degree,
                knots,
                points,
            } => {
                let (m, n, k) = (*degree, points.len(), knots);
                let t = t.clamp(k[m], k[n]);
                let mut s = k[..n].partition_point(|&x| x <= t).saturating_sub(1).max(m);
                while s > m && k[s] == k[s + 1] {
                    s -= 1;
                }
                let mut d: Vec<(Vec3, f64)> = points[s - m..=s].to_vec();
                for r in 1..=m {
                    for j in (r..=m).rev() {
                        let i = j + s - m;
                        let den = k[i + m + 1 - r] - k[i];
                        let a = if den > 0.0 { (t - k[i]) / den } else { 0.0 };
                        let prev = d[j - 1];
                        d[j] = (
                            prev.0 * (1.0 - a) + d[j].0 * a,
                            prev.1 * (1.0 - a) + d[j].1 * a,
                        );
                    }
                }
                d[m].0 / d[m].1
            }
            Curve::Polyline(p) => {
                let last = p.len() - 1;
                let t = t.clamp(0.0, last as f64);
                let i = (t.floor() as usize).min(last.saturating_sub(1));
                let s = t - i as f64;
                if i + 1 > last {
                    p[last]
                } else {
                    p[i] * (1.0 - s) + p[i + 1] * s
                }
            }
        }
    }

    /// The same points run the other way (`t → −t`).
    fn reversed(self) -> Curve {
        match self {
            Curve::Line { p, d } => Curve::Line { p, d: -d },
            Curve::Conic { f, a, b } => Curve::Conic {
                f: Frame {
                    y: -f.y,
                    z: -f.z,
                    ..f
                },
                a,
                b,
            },
            Curve::Spline {
                degree,
                knots,
                points,
            } => Curve::Spline {
                degree,
                knots: knots.iter().rev().map(|k| -k).collect(),
                points: points.into_iter().rev().collect(),
            },
            Curve::Polyline(p) => Curve::Polyline(p.into_iter().rev().collect()),
        }
    }

    /// The parameter range of a bounded curve.
    fn range(&self) -> Option<(f64, f64)> {
        match self {
            Curve::Line { .. } | Curve::Conic { .. } => None,
            Curve::Spline {
                degree,
                knots,
                points,
            } => Some((knots[*degree], knots[points.len()])),
            Curve::Polyline(p) => Some((0.0, (p.len() - 1) as f64)),
        }
    }

    /// The parameter of the curve point nearest `q`, and its distance.
    fn param_of(&self, q: Vec3) -> (f64, f64) {
        let t = match self {
            Curve::Line { p, d } => (q - *p).dot(*d) / d.length_squared(),
            Curve::Conic { f, a, b } => {
                let l = q - f.origin;
                (l.dot(f.y) / b).atan2(l.dot(f.x) / a)
            }
            Curve::Polyline(p) => {
                let mut best = (f64::INFINITY, 0.0);
                for (i, w) in p.windows(2).enumerate() {
                    let d = w[1] - w[0];
                    let len2 = d.length_squared();
                    let s = if len2 > 0.0 {
                        ((q - w[0]).dot(d) / len2).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    let dist = (w[0] + s * d - q).length();
                    if dist < best.0 {
                        best = (dist, i as f64 + s);
                    }
                }
                best.1
            }
            Curve::Spline { knots, .. } => {
                let (t0, t1) = self.range().unwrap_or((0.0, 1.0));
                let dist = |t: f64| (self.point(t) - q).length();
                // Samples over the spans (at most 512), then golden-section search around the
                // nearest.
                let spans = knots.windows(2).filter(|w| w[1] > w[0]).count().max(1);
                let n = (8 * spans).clamp(16, 512);
                let mut best = (f64::INFINITY, t0);
                for k in 0..=n {
                    let t = t0 + (t1 - t0) * k as f64 / n as f64;
                    let d = dist(t);
                    if d < best.0 {
                        best = (d, t);
                    }
                }
                let h = (t1 - t0) / n as f64;
                let (a, b) = ((best.1 - h).max(t0), (best.1 + h).min(t1));
                let mut near = best;
                swarf_geom::search::golden_max(
                    &mut |t| {
                        let d = dist(t);
                        if d < near.0 {
                            near = (d, t);
                        }
                        -d
                    },
                    a,
                    b,
                    1e-12 * (b - a) + 1e-15 * a.abs().max(b.abs()),
                );
                let t = near.1;
                // The ends exactly, when they are as near.
                [t0, t1, t]
                    .into_iter()
                    .min_by(|x, y| dist(*x).total_cmp(&dist(*y)))
                    .unwrap_or(t)
            }
        };
        (t, (self.point(t) - q).length())
    }

    /// Initial steps over `[a, b]`: 4 per quarter turn of a conic, 8 per knot span of a spline
    /// (what the range covers of it), 1 per polyline segment, 4 for a line.
    fn steps(&self, a: f64, b: f64) -> Vec<f64> {
        let (lo, hi) = (a.min(b), a.max(b));
        let mut ts: Vec<f64> = match self {
            Curve::Line { .. } => (0..=4).map(|k| a + (b - a) * k as f64 / 4.0).collect(),
            Curve::Conic { .. } => {
                let n = ((hi - lo) / std::f64::consts::FRAC_PI_2 * 4.0)
                    .ceil()
                    .clamp(4.0, 1024.0) as usize;
                (0..=n).map(|k| a + (b - a) * k as f64 / n as f64).collect()
            }
            Curve::Spline { knots, .. } => {
                let mut breaks = vec![lo];
                breaks.extend(knots.iter().copied().filter(|&k| k > lo && k < hi));
                breaks.push(hi);
                breaks.dedup();
                let mut out = Vec::new();
                for w in breaks.windows(2).take(MAX_CURVE_POINTS) {
                    for k in 0..8 {
                        out.push(w[0] + (w[1] - w[0]) * k as f64 / 8.0);
                    }
                }
                out.push(hi);
                if a > b {
                    out.reverse();
                }
                out
            }
            Curve::Polyline(_) => {
                let mut out = vec![lo];
                let mut k = lo.floor() + 1.0;
                while k < hi && out.len() < MAX_CURVE_POINTS {
                    out.push(k);
                    k += 1.0;
                }
                out.push(hi);
                if a > b {
                    out.reverse();
                }
                out
            }
        };
        ts.dedup();
        if ts.len() < 2 {
            ts = vec![a, b];
        }
        ts
    }
}

/// A trim loop point: its parameters, and whether its u (the angle around the axis) is free
/// (a pole of a sphere, a cone's apex).
#[derive(Clone, Copy, Debug)]
struct Sample {
    uv: Uv,
    free: bool,
}

/// Maps model-space points of a face's edges to its surface's parameters.
struct Mapper<'s> {
    surface: &'s Surface,
    /// Period of u and v (angles of elementary surfaces).
    period: [Option<f64>; 2],
    /// Chord tolerance (mm).
    tol: f64,
    /// Farthest a point may lie from the surface (mm).
    tol_on: f64,
    points_left: usize,
    /// Point inversion onto the surface (at most [`MAX_GRID_SEARCHES`] grid searches).
    inverter: Inverter<'s>,
}

impl Mapper<'_> {
    /// S(u, v), without clamping the angles into the parameter box.
    fn eval(&self, [u, v]: Uv) -> Vec3 {
        let e = |f: &Frame, u: f64| u.cos() * f.x + u.sin() * f.y;
        match self.surface {
            Surface::Nurbs(n) => n.point(u, v),
            Surface::Plane(p) => p.frame.origin + u * p.frame.x + v * p.frame.y,
            Surface::Cylinder(c) => c.frame.origin + c.radius * e(&c.frame, u) + v * c.frame.z,
            Surface::Cone(c) => {
                c.frame.origin
                    + (c.radius + v * c.semi_angle.tan()) * e(&c.frame, u)
                    + v * c.frame.z
            }
            Surface::Sphere(s) => {
                s.frame.origin
                    + s.radius * v.cos() * e(&s.frame, u)
                    + s.radius * v.sin() * s.frame.z
            }
            Surface::Torus(t) => {
                t.frame.origin
                    + (t.major + t.minor * v.cos()) * e(&t.frame, u)
                    + t.minor * v.sin() * t.frame.z
            }
        }
    }

    /// The parameters of `p` (the angles unwrapped to lie near `near`), or why not.
    fn map(&mut self, p: Vec3, near: Option<Uv>) -> Built<Sample> {
        if self.points_left == 0 {
            return Err(format!(
                "the trim needs more than {MAX_TRIM_POINTS} points (or the file more than {MAX_FILE_TRIM_POINTS})"
            ));
        }
        self.points_left -= 1;
        let inv = self.inverter.invert(p, near).map_err(|e| e.to_string())?;
        let (mut uv, free, off) = (inv.uv, inv.pole, inv.dist);
        if off.is_nan() || off > self.tol_on {
            return Err(format!(
                "the point ({:.6}, {:.6}, {:.6}) is {off:.3e} mm off the surface",
                p.x, p.y, p.z
            ));
        }
        if let Some(near) = near {
            if free {
                uv[0] = near[0];
            }
            for d in 0..2 {
                if let Some(t) = self.period[d] {
                    uv[d] += t * ((near[d] - uv[d]) / t).round();
                }
            }
        }
        if !(uv[0].is_finite() && uv[1].is_finite()) {
            return Err("a point maps to non-finite parameters".into());
        }
        Ok(Sample { uv, free })
    }

    /// Samples `curve` over the runs `(a, b)` (in that direction) to the chord tolerance: the
    /// chord between neighbouring samples, in parameters, stays within `tol` of the curve's own
    /// parameters on the surface. Each sample's angles are unwrapped to lie near the previous
    /// one's.
    fn sample(
        &mut self,
        curve: &Curve,
        runs: &[(f64, f64)],
        near: Option<Uv>,
    ) -> Built<Vec<Sample>> {
        let mut out: Vec<Sample> = Vec::new();
        for &(a, b) in runs {
            let ts = curve.steps(a, b);
            let mut prev: Option<(f64, Sample)> = None;
            for t in ts {
                let seed = prev.map(|p| p.1.uv).or(out.last().map(|s| s.uv)).or(near);
                let s = self.map(curve.point(t), seed)?;
                match prev {
                    None => {
                        if out.is_empty() {
                            out.push(s);
                        }
                    }
                    Some(p) => {
                        self.refine(curve, p, (t, s), 0, &mut out)?;
                    }
                }
                prev = Some((t, s));
            }
        }
        // A free first point takes the u of the next.
        if out.len() > 1 && out[0].free {
            out[0].uv[0] = out[1].uv[0];
        }
        Ok(out)
    }

    fn refine(
        &mut self,
        curve: &Curve,
        (ta, sa): (f64, Sample),
        (tb, sb): (f64, Sample),
        depth: u32,
        out: &mut Vec<Sample>,
    ) -> Built<()> {
        let tm = 0.5 * (ta + tb);
        let sm = self.map(curve.point(tm), Some(sa.uv))?;
        let chord = self.eval([0.5 * (sa.uv[0] + sb.uv[0]), 0.5 * (sa.uv[1] + sb.uv[1])]);
        let dev = (chord - self.eval(sm.uv)).length();
        if depth < MAX_HALVINGS && (dev.is_nan() || dev > self.tol) {
            self.refine(curve, (ta, sa), (tm, sm), depth + 1, out)?;
            self.refine(curve, (tm, sm), (tb, sb), depth + 1, out)?;
        } else {
            out.push(sb);
        }
        Ok(())
    }
}

/// What a face's bounds give: the trim and the parameter box it needs (angles may start
/// elsewhere than 0, linear ranges may grow to hold the loops).
struct FaceTrim {
    trim: Trim,
    domain: ParamBox,
}

/// One bound of a face, sampled.
struct Bound {
    /// `FACE_OUTER_BOUND`.
    outer: bool,
    /// Its orientation, times the face's `same_sense`.
    sense: bool,
    samples: Vec<Sample>,
}

impl Model<'_> {
    /// A curve for the edge geometry `id`.
    fn curve(&self, from: u64, id: u64, depth: usize) -> Built<Curve> {
        let wrap = |e: ReadError| e.to_string();
        if depth > MAX_CURVE_DEPTH {
            return Err(format!(
                "#{id}: curves nest more than {MAX_CURVE_DEPTH} deep"
            ));
        }
        let inst = self.get(from, id).map_err(wrap)?;
        for name in ["SURFACE_CURVE", "SEAM_CURVE", "INTERSECTION_CURVE"] {
            if let Some(p) = inst.part(name) {
                let c = self.reference(id, p.get(1), "curve_3d").map_err(wrap)?;
                return self.curve(id, c, depth + 1);
            }
        }
        if let Some(p) = inst.part("TRIMMED_CURVE") {
            // The edge's vertices bound it; its sense_agreement .F. runs it against the basis
            // curve (the way round a conic between the vertices).
            let c = self.reference(id, p.get(1), "basis_curve").map_err(wrap)?;
            let curve = self.curve(id, c, depth + 1)?;
            let against = matches!(p.get(4), Some(Param::Enum(e)) if e == "F");
            return Ok(if against { curve.reversed() } else { curve });
        }
        if let Some(p) = inst.part("LINE") {
            let origin = self.reference(id, p.get(1), "pnt").map_err(wrap)?;
            let origin = self.point(id, origin).map_err(wrap)?;
            let vid = self.reference(id, p.get(2), "dir").map_err(wrap)?;
            let vi = self.get(id, vid).map_err(wrap)?;
            let vp = vi
                .part("VECTOR")
                .ok_or_else(|| format!("#{vid}: found {}, expected VECTOR", vi.first_name()))?;
            let dir = self.direction(vid, vp.get(1), Vec3::X).map_err(wrap)?;
            let mag = self.num(vid, vp.get(2), "magnitude").map_err(wrap)? * self.length;
            if !(mag.abs() > 0.0 && mag.is_finite()) {
                return Err(format!("#{vid}: a line's vector has no length"));
            }
            return Ok(Curve::Line {
                p: origin,
                d: dir * mag.abs(),
            });
        }
        if let Some(c) = inst.part("CIRCLE").or_else(|| inst.part("ELLIPSE")) {
            let f = self.placement(id, c.get(1)).map_err(wrap)?;
            let a = self.num(id, c.get(2), "radius").map_err(wrap)? * self.length;
            let b = match c.get(3) {
                Some(p) => self.num(id, Some(p), "semi_axis_2").map_err(wrap)? * self.length,
                None => a,
            };
            if !(a > 0.0 && b > 0.0 && a.is_finite() && b.is_finite()) {
                return Err(format!("#{id}: a conic's radii must be positive"));
            }
            return Ok(Curve::Conic { f, a, b });
        }
        if let Some(p) = inst.part("POLYLINE") {
            let pts = self.list(id, p.get(1), "points").map_err(wrap)?;
            if pts.len() < 2 || pts.len() > MAX_CURVE_POINTS {
                return Err(format!(
                    "#{id}: a polyline needs 2 to {MAX_CURVE_POINTS} points"
                ));
            }
            let pts = pts
                .iter()
                .map(|q| {
                    let r = self.reference(id, Some(q), "point")?;
                    self.point(id, r)
                })
                .collect::<R<Vec<Vec3>>>()
                .map_err(wrap)?;
            return Ok(Curve::Polyline(pts));
        }
        if let Some(k) = inst.part("B_SPLINE_CURVE_WITH_KNOTS") {
            let (head, knots): (&[Param], &[Param]) = match inst.part("B_SPLINE_CURVE") {
                Some(b) => (b, k),
                None if k.len() >= 9 => (&k[1..6], &k[6..]),
                None => {
                    return Err(format!(
                        "#{id}: B_SPLINE_CURVE_WITH_KNOTS has {} attributes, expected 9",
                        k.len()
                    ))
                }
            };
            let degree = self.num(id, head.first(), "degree").map_err(wrap)?;
            if !(degree >= 1.0
                && degree <= NurbsSurface::MAX_DEGREE as f64
                && degree.fract() == 0.0)
            {
                return Err(format!(
                    "#{id}: curve degree {degree} is not 1 to {}",
                    NurbsSurface::MAX_DEGREE
                ));
            }
            let degree = degree as usize;
            let cps = self
                .list(id, head.get(1), "control_points_list")
                .map_err(wrap)?;
            if cps.len() < degree + 1 || cps.len() > MAX_CURVE_POINTS {
                return Err(format!(
                    "#{id}: {} control points for degree {degree}",
                    cps.len()
                ));
            }
            let pts = cps
                .iter()
                .map(|q| {
                    let r = self.reference(id, Some(q), "control point")?;
                    self.point(id, r)
                })
                .collect::<R<Vec<Vec3>>>()
                .map_err(wrap)?;
            let kv = self
                .knots(
                    id,
                    knots.first(),
                    knots.get(1),
                    "curve",
                    pts.len() + degree + 1,
                )
                .map_err(wrap)?;
            if kv.iter().any(|k| !k.is_finite())
                || kv.windows(2).any(|w| w[1] < w[0])
                || kv[pts.len()] <= kv[degree]
            {
                return Err(format!("#{id}: knots are not increasing"));
            }
            let weights = match inst.part("RATIONAL_B_SPLINE_CURVE") {
                Some(w) => {
                    let ws = self.list(id, w.first(), "weights_data").map_err(wrap)?;
                    if ws.len() != pts.len() {
                        return Err(format!(
                            "#{id}: {} weights for {} control points",
                            ws.len(),
                            pts.len()
                        ));
                    }
                    ws.iter()
                        .map(|x| self.num(id, Some(x), "weight"))
                        .collect::<R<Vec<f64>>>()
                        .map_err(wrap)?
                }
                None => vec![1.0; pts.len()],
            };
            if weights.iter().any(|w| !(*w > 0.0 && w.is_finite())) {
                return Err(format!("#{id}: weights must be positive"));
            }
            return Ok(Curve::Spline {
                degree,
                knots: kv,
                points: pts
                    .into_iter()
                    .zip(weights)
                    .map(|(p, w)| (p * w, w))
                    .collect(),
            });
        }
        Err(format!(
            "edge curve #{id} is a {}, which is not evaluated",
            inst.first_name()
        ))
    }

    /// The trim of face `fid` on `surface` from its bounds, `None` when they hold no loop (only
    /// vertex loops), `Err(why)` when it cannot be honoured.
    fn face_trim(
        &self,
        fid: u64,
        bounds: Option<&Param>,
        same_sense: bool,
        surface: &Surface,
        budget: &mut usize,
    ) -> Built<Option<FaceTrim>> {
        let Some(Param::List(bounds)) = bounds else {
            return Ok(None);
        };
        let tau = std::f64::consts::TAU;
        let period = match surface {
            Surface::Cylinder(_) | Surface::Cone(_) | Surface::Sphere(_) => [Some(tau), None],
            Surface::Torus(_) => [Some(tau), Some(tau)],
            _ => [None, None],
        };
        let bb = surface.bounding_box();
        let size = (bb.max - bb.min).length();
        let size = if size.is_finite() { size } else { 1e3 };
        let tol_on = 1e-4 * size + 1e-3;
        let mut m = Mapper {
            surface,
            period,
            tol: (1e-5 * size).clamp(1e-9, 1e-3),
            tol_on,
            points_left: (*budget).min(MAX_TRIM_POINTS),
            inverter: Inverter::new(surface, tol_on, MAX_GRID_SEARCHES),
        };
        let start_budget = m.points_left;
        let result = self.face_loops(fid, bounds, same_sense, &mut m);
        *budget -= start_budget - m.points_left;
        let loops = result?;
        if loops.is_empty() {
            return Ok(None);
        }
        assemble(surface, period, loops).map(Some)
    }

    /// The sampled loops of a face's bounds (vertex loops left out).
    fn face_loops(
        &self,
        fid: u64,
        bounds: &[Param],
        same_sense: bool,
        m: &mut Mapper,
    ) -> Built<Vec<Bound>> {
        let wrap = |e: ReadError| e.to_string();
        let mut out = Vec::new();
        for b in bounds {
            let bid = self.reference(fid, Some(b), "bound").map_err(wrap)?;
            let bi = self.get(fid, bid).map_err(wrap)?;
            let (outer, bp) = match (bi.part("FACE_OUTER_BOUND"), bi.part("FACE_BOUND")) {
                (Some(p), _) => (true, p),
                (None, Some(p)) => (false, p),
                _ => return Err(format!("bound #{bid} is a {}", bi.first_name())),
            };
            let lid = self.reference(bid, bp.get(1), "bound").map_err(wrap)?;
            let orientation = self.logical(bid, bp.get(2), "orientation").map_err(wrap)?;
            let li = self.get(bid, lid).map_err(wrap)?;
            let samples = if li.part("VERTEX_LOOP").is_some() {
                continue;
            } else if let Some(p) = li.part("POLY_LOOP") {
                let pts = self.list(lid, p.get(1), "polygon").map_err(wrap)?;
                if pts.len() > MAX_CURVE_POINTS {
                    return Err(format!("poly loop #{lid} has too many points"));
                }
                let mut pts = pts
                    .iter()
                    .map(|q| {
                        let r = self.reference(lid, Some(q), "point")?;
                        self.point(lid, r)
                    })
                    .collect::<R<Vec<Vec3>>>()
                    .map_err(wrap)?;
                if let Some(&first) = pts.first() {
                    pts.push(first);
                }
                if pts.len() < 4 {
                    return Err(format!("poly loop #{lid} has fewer than 3 points"));
                }
                let c = Curve::Polyline(pts);
                let (a, b) = c.range().unwrap_or((0.0, 1.0));
                m.sample(&c, &[(a, b)], None)
                    .map_err(|why| format!("poly loop #{lid}: {why}"))?
            } else if let Some(p) = li.part("EDGE_LOOP") {
                let edges = self.list(lid, p.get(1), "edge_list").map_err(wrap)?;
                self.edge_loop(lid, edges, m)?
            } else {
                return Err(format!(
                    "loop #{lid} is a {}, which is not read",
                    li.first_name()
                ));
            };
            let sense = orientation == same_sense;
            let samples = match m.period {
                [Some(t), None] => through_poles(samples, sense, t),
                _ => samples,
            };
            out.push(Bound {
                outer,
                sense,
                samples,
            });
        }
        Ok(out)
    }

    /// An EDGE_LOOP's samples in order, angles continuous; a seam edge met a second time on the
    /// same parameters (through a pole) is moved a period over when that closes the loop.
    fn edge_loop(&self, lid: u64, edges: &[Param], m: &mut Mapper) -> Built<Vec<Sample>> {
        let wrap = |e: ReadError| e.to_string();
        let mut out: Vec<Sample> = Vec::new();
        let mut first_pass: HashMap<u64, (Sample, Sample)> = HashMap::new();
        let mut split: Option<usize> = None;
        let mut last_point: Option<Vec3> = None;
        let join = m.tol_on * 10.0;
        for e in edges {
            let oid = self
                .reference(lid, Some(e), "oriented edge")
                .map_err(wrap)?;
            let oi = self.get(lid, oid).map_err(wrap)?;
            let op = oi.part("ORIENTED_EDGE").ok_or_else(|| {
                format!(
                    "edge #{oid} is a {}, expected ORIENTED_EDGE",
                    oi.first_name()
                )
            })?;
            let eid = self
                .reference(oid, op.get(3), "edge_element")
                .map_err(wrap)?;
            let orientation = self.logical(oid, op.get(4), "orientation").map_err(wrap)?;
            let ei = self.get(oid, eid).map_err(wrap)?;
            let ep = ei.part("EDGE_CURVE").ok_or_else(|| {
                format!("edge #{eid} is a {}, expected EDGE_CURVE", ei.first_name())
            })?;
            let vertex = |p: Option<&Param>| -> R<(u64, Vec3)> {
                let vid = self.reference(eid, p, "vertex")?;
                let vi = self.get(eid, vid)?;
                let vp = vi.part("VERTEX_POINT").ok_or_else(|| {
                    self.bad(
                        vid,
                        format!("found {}, expected VERTEX_POINT", vi.first_name()),
                    )
                })?;
                let cid = self.reference(vid, vp.get(1), "vertex_geometry")?;
                Ok((vid, self.point(vid, cid)?))
            };
            let (vs, ps) = vertex(ep.get(1)).map_err(wrap)?;
            let (ve, pe) = vertex(ep.get(2)).map_err(wrap)?;
            let gid = self
                .reference(eid, ep.get(3), "edge_geometry")
                .map_err(wrap)?;
            let same = self.logical(eid, ep.get(4), "same_sense").map_err(wrap)?;
            let curve = self.curve(eid, gid, 0)?;
            let (ts, ds) = curve.param_of(ps);
            let (te, de) = curve.param_of(pe);
            if ds.is_nan() || de.is_nan() || ds.max(de) > join {
                return Err(format!(
                    "a vertex of edge #{eid} is {:.3e} mm off its curve",
                    ds.max(de)
                ));
            }
            let closed = vs == ve || (ps - pe).length() <= 1e-9 * (1.0 + ps.length());
            let tau = std::f64::consts::TAU;
            let runs: Vec<(f64, f64)> = match curve.range() {
                None if matches!(curve, Curve::Conic { .. }) => {
                    let mut te = te;
                    if same {
                        while te <= ts + if closed { 1e-12 } else { 0.0 } {
                            te += tau;
                        }
                        while te > ts + tau + 1e-12 {
                            te -= tau;
                        }
                    } else {
                        while te >= ts - if closed { 1e-12 } else { 0.0 } {
                            te -= tau;
                        }
                        while te < ts - tau - 1e-12 {
                            te += tau;
                        }
                    }
                    vec![(ts, te)]
                }
                None => vec![(ts, te)],
                Some((t0, t1)) if closed => {
                    let near = |a: f64, b: f64| (a - b).abs() <= 1e-9 * (t1 - t0);
                    let ring = (curve.point(t0) - curve.point(t1)).length() <= join;
                    if !ring {
                        return Err(format!(
                            "edge #{eid} starts and ends at one vertex, but its curve is open"
                        ));
                    }
                    let forward = if near(ts, t0) || near(ts, t1) {
                        vec![(t0, t1)]
                    } else {
                        vec![(ts, t1), (t0, ts)]
                    };
                    if same {
                        forward
                    } else {
                        forward.iter().rev().map(|&(a, b)| (b, a)).collect()
                    }
                }
                Some(_) => vec![(ts, te)],
            };
            let mut s = m
                .sample(&curve, &runs, out.last().map(|s| s.uv))
                .map_err(|why| format!("edge #{eid}: {why}"))?;
            // From the edge's start to its end, then as the loop uses it.
            if !orientation {
                s.reverse();
            }
            let (from, to) = if orientation { (ps, pe) } else { (pe, ps) };
            if let Some(lp) = last_point {
                if (lp - from).length() > join {
                    return Err(format!(
                        "edge #{eid} does not start where the previous edge ends"
                    ));
                }
            }
            last_point = Some(to);
            // Angles continuous with the loop so far.
            if let (Some(&prev), Some(&first)) = (out.last(), s.first()) {
                for d in 0..2 {
                    if let Some(t) = m.period[d] {
                        let k = ((prev.uv[d] - first.uv[d]) / t).round() * t;
                        if k != 0.0 {
                            s.iter_mut().for_each(|q| q.uv[d] += k);
                        }
                    }
                }
            }
            let at = out.len();
            if let (Some(&(a, b)), Some(&f), Some(&l)) = (first_pass.get(&eid), s.first(), s.last())
            {
                let same_uv = |x: Sample, y: Sample| {
                    (x.free || y.free || (x.uv[0] - y.uv[0]).abs() <= 1e-6)
                        && (x.uv[1] - y.uv[1]).abs() <= 1e-6
                };
                if split.is_none()
                    && m.period.iter().any(Option::is_some)
                    && same_uv(f, b)
                    && same_uv(l, a)
                {
                    split = Some(at);
                }
            } else if let (Some(&f), Some(&l)) = (s.first(), s.last()) {
                first_pass.insert(eid, (f, l));
            }
            out.extend(s);
        }
        if let (Some(at), Some(&first)) = (split, out.first()) {
            // Move the second pass over the seam (and what follows it) a period either way:
            // whichever closes the loop.
            let d = usize::from(m.period[0].is_none());
            let t = m.period[d].unwrap_or(std::f64::consts::TAU);
            for k in [-t, t] {
                let last = out[out.len() - 1];
                let moved = last.uv[d] + k;
                let closes = (moved - first.uv[d]).abs() <= 1e-6 || (last.free && first.free);
                if closes {
                    out[at..].iter_mut().for_each(|q| q.uv[d] += k);
                    break;
                }
            }
        }
        Ok(out)
    }
}

/// A loop through a pole or an apex (a run of free samples, where every u is the same point):
/// there it runs along the parameter box's edge at that v, from the u it arrives at to the u it
/// leaves at. Whole turns either way reach the same points; which is meant follows from the
/// face's side. The face lies on the loop's left in (u, v) (on its right when `sense` is false),
/// so along the box's top edge the loop runs towards −u, along its bottom edge towards +u, by
/// more than nothing and at most a turn (a seam met twice through the pole: a whole turn). The
/// loop is rotated to start off the pole (its last sample repeats its first point).
fn through_poles(s: Vec<Sample>, sense: bool, t: f64) -> Vec<Sample> {
    let Some(a) = s.iter().position(|q| !q.free) else {
        return s;
    };
    if !s.iter().any(|q| q.free) {
        return s;
    }
    let seq: Vec<Sample> = if a == 0 {
        s
    } else {
        // Off the pole to the end (less the last sample, the first's point), then round to
        // where it started, continuing from the head's own angles (the passage below moves
        // them).
        let mut v = s[a..s.len() - 1].to_vec();
        v.extend_from_slice(&s[..=a]);
        v
    };
    let mut out: Vec<Sample> = Vec::with_capacity(seq.len() + 2);
    let mut shift = 0.0;
    let mut i = 0;
    while i < seq.len() {
        let Some(&before) = out.last().filter(|_| seq[i].free) else {
            let mut q = seq[i];
            q.uv[0] += shift;
            out.push(q);
            i += 1;
            continue;
        };
        let mut j = i;
        while j < seq.len() && seq[j].free {
            j += 1;
        }
        let vf = seq[i].uv[1];
        let Some(after) = seq.get(j) else {
            // Ends on the pole: it stays at the u it arrives at.
            out.extend(seq[i..].iter().map(|q| Sample {
                uv: [before.uv[0], q.uv[1]],
                free: true,
            }));
            break;
        };
        let u_out = after.uv[0] + shift;
        let top = before.uv[1] < vf;
        let r = (u_out - before.uv[0]).rem_euclid(t);
        let r = if r <= 1e-9 * t || t - r <= 1e-9 * t {
            0.0
        } else {
            r
        };
        let jump = match (top != sense, r == 0.0) {
            (true, true) => t,
            (true, false) => r,
            (false, true) => -t,
            (false, false) => r - t,
        };
        let u_new = before.uv[0] + jump;
        shift += u_new - u_out;
        out.push(Sample {
            uv: [before.uv[0], vf],
            free: true,
        });
        out.push(Sample {
            uv: [u_new, vf],
            free: true,
        });
        i = j;
    }
    out
}

/// The trim from a face's sampled bounds: closed loops moved a period to lie in the parameter
/// box (holes across its edge copied to the other side), loops winding once around an angle
/// paired into one outer loop (or closed along the box edge on the face's side), the outer
/// loop the face's outer bound (else the loop with the largest box).
fn assemble(surface: &Surface, period: [Option<f64>; 2], bounds: Vec<Bound>) -> Built<FaceTrim> {
    let mut dom = surface.domain();
    let span = [dom.u[1] - dom.u[0], dom.v[1] - dom.v[0]];
    let close = [1e-6 * span[0].max(1e-300), 1e-6 * span[1].max(1e-300)];
    // Closed loops, and loops winding around angle d (their direction times the bound's sense).
    let mut closed: Vec<(bool, Vec<Uv>)> = Vec::new();
    let mut winding: [Vec<(bool, Vec<Uv>)>; 2] = [Vec::new(), Vec::new()];
    for (k, b) in bounds.into_iter().enumerate() {
        let s = &b.samples;
        let (Some(first), Some(last)) = (s.first(), s.last()) else {
            return Err(format!("loop {k} has no points"));
        };
        let mut turns = [0.0; 2];
        let mut ok = true;
        for d in 0..2 {
            let gap = last.uv[d] - first.uv[d];
            if d == 0 && (first.free || last.free) {
                continue;
            }
            if let Some(t) = period[d] {
                turns[d] = (gap / t).round();
                if (gap - turns[d] * t).abs() > close[d] {
                    ok = false;
                }
            } else if gap.abs() > close[d] {
                ok = false;
            }
        }
        if !ok {
            return Err(format!(
                "loop {k} does not close in the surface's parameters"
            ));
        }
        let pts: Vec<Uv> = s.iter().map(|q| q.uv).collect();
        match turns {
            [0.0, 0.0] => closed.push((b.outer, pts)),
            [t, 0.0] if t.abs() == 1.0 => winding[0].push(((t > 0.0) == b.sense, pts)),
            [0.0, t] if t.abs() == 1.0 => winding[1].push(((t > 0.0) == b.sense, pts)),
            _ => return Err(format!("loop {k} winds around the surface more than once")),
        }
    }
    let wound = winding.iter().map(Vec::len).sum::<usize>();
    if wound > 0
        && (winding[0].len() > 2
            || winding[1].len() > 2
            || (!winding[0].is_empty() && !winding[1].is_empty()))
    {
        return Err("the loops wind around the surface in a way not read".into());
    }
    // The outer closed loop (when no loop winds).
    let outer_at = if wound > 0 {
        None
    } else {
        closed.iter().position(|c| c.0).or_else(|| {
            let area = |l: &Vec<Uv>| {
                let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
                for p in l {
                    for d in 0..2 {
                        lo[d] = lo[d].min(p[d]);
                        hi[d] = hi[d].max(p[d]);
                    }
                }
                (hi[0] - lo[0]) * (hi[1] - lo[1])
            };
            (0..closed.len()).max_by(|&a, &b| area(&closed[a].1).total_cmp(&area(&closed[b].1)))
        })
    };
    let range = |l: &[Uv], d: usize| {
        l.iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(p[d]), b.max(p[d]))
            })
    };
    let mut starts = [dom.u[0], dom.v[0]];
    // Loops winding around angle d where the other parameter e is an angle too (a torus): of
    // the two bands between them the face is the one on their face side (going +u it lies at
    // +v, going +v at −u), from the loop with the face above it (in e) up to the other, less
    // than a turn; the box starts at it when it does not fit. One such loop bounds nothing.
    let mut band_start: [Option<f64>; 2] = [None, None];
    for (d, w) in winding.iter_mut().enumerate() {
        let e = 1 - d;
        let Some(te) = period[e] else { continue };
        if w.is_empty() {
            continue;
        }
        let face_above = |up: bool| up == (d == 0);
        let (a, b) = match w.as_slice() {
            [(x, _), (y, _)] => match (face_above(*x), face_above(*y)) {
                (true, false) => (0, 1),
                (false, true) => (1, 0),
                _ => return Err("the two loops around the surface face the same way".into()),
            },
            _ => return Err("one loop around both angles of the surface bounds nothing".into()),
        };
        let mean = |l: &[Uv]| l.iter().map(|p| p[e]).sum::<f64>() / l.len().max(1) as f64;
        let (ma, mb) = (mean(&w[a].1), mean(&w[b].1));
        let k = (((ma - mb) / te).floor() + 1.0) * te;
        w[b].1.iter_mut().for_each(|p| p[e] += k);
        let lo = range(&w[a].1, e).0;
        let hi = range(&w[b].1, e).1;
        if hi - lo > te + close[e] || (hi - lo).is_nan() {
            return Err(
                "the band between the loops around the surface is wider than a turn".into(),
            );
        }
        let s = starts[e];
        let k = ((s + 0.5 * te - 0.5 * (lo + hi)) / te).round() * te;
        for (_, l) in w.iter_mut() {
            l.iter_mut().for_each(|p| p[e] += k);
        }
        let fits = lo + k >= s - close[e] && hi + k <= s + te + close[e];
        band_start[e] = Some(if fits { s } else { lo + k });
    }
    for d in 0..2 {
        let Some(t) = period[d] else { continue };
        let mut s = band_start[d].unwrap_or(starts[d]);
        // Shift the outer loop in; when it still crosses the box's edge, start the box at it.
        if let Some(o) = outer_at {
            let (lo, hi) = range(&closed[o].1, d);
            let k = ((s + 0.5 * t - 0.5 * (lo + hi)) / t).round() * t;
            closed[o].1.iter_mut().for_each(|p| p[d] += k);
            if lo + k < s - close[d] || hi + k > s + t + close[d] {
                s = lo + k;
            }
        }
        // Every closed loop into [s, s + t] by its middle; holes across an edge copied over.
        let mut copies = Vec::new();
        for (i, (_, l)) in closed.iter_mut().enumerate() {
            let (lo, hi) = range(l, d);
            let k = ((s + 0.5 * t - 0.5 * (lo + hi)) / t).round() * t;
            l.iter_mut().for_each(|p| p[d] += k);
            if Some(i) != outer_at {
                if lo + k < s - close[d] {
                    copies.push(l.iter().map(|p| with(*p, d, p[d] + t)).collect::<Vec<_>>());
                }
                if hi + k > s + t + close[d] {
                    copies.push(l.iter().map(|p| with(*p, d, p[d] - t)).collect::<Vec<_>>());
                }
            }
        }
        closed.extend(copies.into_iter().map(|l| (false, l)));
        starts[d] = s;
        let r = [s, s + t];
        if d == 0 {
            dom.u = r;
        } else {
            dom.v = r;
        }
    }
    // Linear parameters: snap to the box's edges, then grow the box to hold the loops.
    for d in 0..2 {
        if period[d].is_some() {
            continue;
        }
        let (mut lo, mut hi) = if d == 0 {
            (dom.u[0], dom.u[1])
        } else {
            (dom.v[0], dom.v[1])
        };
        let snap = 1e-9 * (hi - lo).abs().max(1e-300);
        let all = closed.iter_mut().map(|c| &mut c.1).chain(
            winding
                .iter_mut()
                .flat_map(|w| w.iter_mut().map(|c| &mut c.1)),
        );
        for l in all {
            for p in l.iter_mut() {
                if (p[d] - lo).abs() <= snap {
                    p[d] = lo;
                } else if (p[d] - hi).abs() <= snap {
                    p[d] = hi;
                }
            }
            let (a, b) = range(l, d);
            lo = lo.min(a);
            hi = hi.max(b);
        }
        if !matches!(surface, Surface::Nurbs(_) | Surface::Sphere(_)) {
            if d == 0 {
                dom.u = [lo, hi];
            } else {
                dom.v = [lo, hi];
            }
        }
    }
    // Winding loops: cut where they cross the box's edge, from one edge to the other.
    let mut outer: Option<Vec<Uv>> = outer_at.map(|o| closed[o].1.clone());
    for d in 0..2 {
        if winding[d].is_empty() {
            continue;
        }
        let t = period[d].unwrap_or(std::f64::consts::TAU);
        let s = starts[d];
        let cut: Vec<(bool, Vec<Uv>)> = winding[d]
            .iter()
            .map(|(up, l)| (*up, unroll(l, d, s, t)))
            .collect();
        let e = 1 - d;
        let (lo, hi) = if e == 0 {
            (dom.u[0], dom.u[1])
        } else {
            (dom.v[0], dom.v[1])
        };
        let poly = if cut.len() == 2 {
            let mut p = cut[0].1.clone();
            p.extend(cut[1].1.iter().rev());
            p
        } else {
            // One loop: the face lies on its left (u right, v up); going +u that is +v, going
            // +v it is −u.
            let (up, l) = &cut[0];
            let far = match (d, *up) {
                (0, true) | (1, false) => hi,
                _ => lo,
            };
            let mut p = l.clone();
            p.push(with(with([0.0; 2], d, s + t), e, far));
            p.push(with(with([0.0; 2], d, s), e, far));
            p
        };
        outer = Some(poly);
    }
    // The outer loop's points on the box's edges across an angle (where a band is cut, where a
    // seam runs) moved a little outside it: the box clips the region there, and a hole across
    // the seam keeps its points on the seam off the part (on a loop they would count as on).
    if let Some(o) = outer.as_mut() {
        let diag = (dom.u[1] - dom.u[0]).hypot(dom.v[1] - dom.v[0]);
        for d in 0..2 {
            let Some(t) = period[d] else { continue };
            let out = (1e-9 * t).max(1e-10 * diag);
            let s = starts[d];
            for p in o.iter_mut() {
                if (p[d] - s).abs() <= close[d] {
                    p[d] = s - out;
                } else if (p[d] - s - t).abs() <= close[d] {
                    p[d] = s + t + out;
                }
            }
        }
    }
    let holes: Vec<Vec<Uv>> = closed
        .into_iter()
        .enumerate()
        .filter(|(i, _)| Some(*i) != outer_at)
        .map(|(_, c)| c.1)
        .collect();
    if !(dom.u[0] < dom.u[1] && dom.v[0] < dom.v[1]) {
        return Err("the loops span no area".into());
    }
    let trim = Trim::new(&dom, outer, holes).map_err(|e| e.to_string())?;
    Ok(FaceTrim { trim, domain: dom })
}

/// Sets the parameter box of an elementary surface (a B-spline surface keeps its knots').
fn set_domain(surface: &mut Surface, domain: ParamBox) {
    match surface {
        Surface::Nurbs(_) => {}
        Surface::Plane(s) => s.domain = domain,
        Surface::Cylinder(s) => s.domain = domain,
        Surface::Cone(s) => s.domain = domain,
        Surface::Sphere(s) => s.domain = domain,
        Surface::Torus(s) => s.domain = domain,
    }
}

/// `p` with coordinate `d` set to `x`.
fn with(mut p: Uv, d: usize, x: f64) -> Uv {
    p[d] = x;
    p
}

/// A loop winding once around angle `d` (period `t`, last point = first ± t) as a polyline from
/// `d = s` to `d = s + t`: cut where it crosses `s` (mod t), going up.
fn unroll(l: &[Uv], d: usize, s: f64, t: f64) -> Vec<Uv> {
    let n = l.len();
    let turn = ((l[n - 1][d] - l[0][d]) / t).round() * t;
    let mut seq: Vec<Uv> = if turn < 0.0 {
        l.iter().rev().copied().collect()
    } else {
        l.to_vec()
    };
    if turn == 0.0 {
        return seq;
    }
    let g = |x: f64| (x - s) / t;
    for i in 0..n - 1 {
        let (a, b) = (seq[i], seq[i + 1]);
        let (ga, gb) = (g(a[d]), g(b[d]));
        let m = ga.min(gb).ceil();
        if m <= ga.max(gb) {
            let c = s + m * t;
            let f = if b[d] != a[d] {
                (c - a[d]) / (b[d] - a[d])
            } else {
                0.0
            };
            let e = 1 - d;
            let cp = with(with([0.0; 2], d, c), e, a[e] + f * (b[e] - a[e]));
            let mut out = vec![cp];
            out.extend_from_slice(&seq[i + 1..]);
            out.extend(seq[1..=i].iter().map(|p| with(*p, d, p[d] + t)));
            out.push(with(cp, d, c + t));
            let shift = -m * t;
            out.iter_mut().for_each(|p| p[d] += shift);
            let last = out.len() - 1;
            out[0][d] = s;
            out[last][d] = s + t;
            seq = out;
            return seq;
        }
    }
    seq
}

fn refs(p: &Param, out: &mut Vec<u64>) {
    match p {
        Param::Ref(r) => out.push(*r),
        Param::List(l) | Param::Typed(_, l) => l.iter().for_each(|q| refs(q, out)),
        _ => {}
    }
}

fn si_prefix(p: &str) -> Option<f64> {
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

fn show(p: Option<&Param>) -> String {
    match p {
        None => "nothing (too few attributes)".into(),
        Some(Param::Ref(r)) => format!("#{r}"),
        Some(Param::Num(v)) => format!("{v}"),
        Some(Param::Str(s)) => format!("'{s}'"),
        Some(Param::Enum(e)) => format!(".{e}."),
        Some(Param::List(_)) => "a list".into(),
        Some(Param::Typed(t, _)) => format!("{t}(…)"),
        Some(Param::Null) => "$".into(),
        Some(Param::Derived) => "*".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lexer_handles_strings_comments_and_complex_instances() {
        let t = "ISO-10303-21;\nHEADER;FILE_NAME('a''b;','x');ENDSEC;\nDATA;\n/* c */ #1=( A(1,2.5E1) B('it''s',.T.,$,*,(#2,-3.)) );\n#2=C(LENGTH_MEASURE(1.));\nENDSEC;END-ISO-10303-21;";
        let m = Lexer::new(t).instances().unwrap();
        assert_eq!(m.len(), 2);
        let i = &m[&1];
        assert_eq!(i.parts.len(), 2);
        assert_eq!(i.part("A").unwrap(), &[Param::Num(1.0), Param::Num(25.0)]);
        assert_eq!(i.part("B").unwrap()[0], Param::Str("it's".into()));
        assert_eq!(i.part("B").unwrap()[1], Param::Enum("T".into()));
        assert_eq!(
            m[&2].part("C").unwrap()[0],
            Param::Typed("LENGTH_MEASURE".into(), vec![Param::Num(1.0)])
        );
    }

    #[test]
    fn syntax_errors_have_positions() {
        let t = "ISO-10303-21;\nDATA;\n#1=A(1,2;\nENDSEC;";
        match Lexer::new(t).instances() {
            Err(ReadError::Syntax {
                line,
                column,
                message,
                ..
            }) => {
                assert_eq!((line, column), (3, 9), "{message}");
                assert!(message.contains("expected `,` or `)`"), "{message}");
            }
            other => panic!("{other:?}"),
        }
    }
}
