//! IGES surfaces made of curves and planes: 120 (surface of revolution), 122 (tabulated
//! cylinder) and 118 (ruled surface) as exact rational B-splines of their curves
//! ([`crate::sweep`], as the STEP reader builds its swept surfaces), 190 (plane surface) and
//! 108 (plane) as planes.
//!
//! Their curves are read in model space: a 110 line, a 100 circular arc (a rational quadratic
//! of at most a quarter turn a piece), a 126 (within its range V0–V1) or a 102 composite of
//! these joined end to end (one degree; a line raised to the others'), each with its own 124.
//! The surface is built in its definition space, then moved by its own 124, as a 128 is.

use std::f64::consts::TAU;

use swarf_geom::math::Vec3;
use swarf_geom::Frame;

use super::{apply, entry_at, transformed, Entry, Params, Sections, MAX_NESTING};
use crate::curve::BSplineCurve;
use crate::io::step::DEFAULT_LINEAR_RANGE;
use crate::io::{Format, ReadError};
use crate::surface::{NurbsError, NurbsSurface, ParamBox, PlaneSurface, Surface};
use crate::sweep;

/// The surface kinds read here.
pub(super) const READ: [u32; 5] = [108, 118, 120, 122, 190];

/// A result, or why the surface is not read (said in the skip note).
type Made<T> = Result<Result<T, String>, ReadError>;

/// A model-space curve as a B-spline (mm, in the definition space of the entity naming it),
/// and what its parameter is.
struct ModelCurve {
    spline: BSplineCurve,
    /// The B-spline's parameter is the IGES curve's own (a 110's 0–1, a 126's, a 102 of these).
    exact: bool,
    /// A 100 circular arc of this sweep (radians) that its transformation keeps circular: its
    /// parameter is the rational one of [`sweep::conic`], the same for arcs of one sweep.
    arc: Option<f64>,
    /// A straight segment whose parameter runs in proportion to its length.
    uniform: bool,
}

/// What a surface entity makes.
pub(super) struct Made3 {
    /// The surface, placed by the entity's own 124, in mm.
    pub(super) surface: Surface,
    /// The parameters given the default box ([`DEFAULT_LINEAR_RANGE`]), if any.
    pub(super) defaulted: Option<&'static str>,
    /// A 108's bounding curve to map onto the plane: `Some(true)` for a hole (form −1).
    pub(super) bound: Option<bool>,
}

fn made(surface: Surface) -> Made3 {
    Made3 {
        surface,
        defaulted: None,
        bound: None,
    }
}

impl Sections<'_> {
    /// The surface of the 108, 118, 120, 122 or 190 `e`, or why it is not read.
    pub(super) fn swept_surface(&self, e: &Entry, entries: &[Entry], factor: f64) -> Made<Made3> {
        let p = self.params(e)?;
        let out = match e.kind {
            120 => self.revolution(e, &p, entries, factor)?,
            122 => self.tabulated(e, &p, entries, factor)?,
            118 => self.ruled(e, &p, entries, factor)?,
            190 => self.plane190(e, &p, entries, factor)?,
            _ => self.plane108(e, &p, entries, factor)?,
        };
        let mut out = match out {
            Ok(m) => m,
            Err(why) => return Ok(Err(why)),
        };
        if let Some(t) = self.transform(entries, e)? {
            out.surface = transformed(&out.surface, &t, factor).map_err(|r| surface_error(e, r))?;
        }
        Ok(Ok(out))
    }

    /// 120: the generatrix C turned about the line L from SA to TA (radians, counter-clockwise
    /// about L's direction, start to end point); u the generatrix's parameter, v the turn (so
    /// the normal is `S_u × S_v`, as IGES parametrises it: a line out from the axis turned
    /// counter-clockwise faces along the axis).
    fn revolution(&self, e: &Entry, p: &Params, entries: &[Entry], factor: f64) -> Made<Made3> {
        let l = p.int(1, "L")?;
        if let Some(k) = entry_at(entries, l).map(|x| x.kind).filter(|&k| k != 110) {
            return Ok(Err(format!(
                "its axis L = D{l} is an entity {k}, not a line (110)"
            )));
        }
        let axis = match self.model_curve(entries, p, 1, "axis L", factor, 0)? {
            Ok(c) => c.spline,
            Err(why) => return Ok(Err(why)),
        };
        let c = match self.model_curve(entries, p, 2, "generatrix C", factor, 0)? {
            Ok(c) => c.spline,
            Err(why) => return Ok(Err(why)),
        };
        let (sa, ta) = (p.real(3, "SA")?, p.real(4, "TA")?);
        if !(ta > sa && ta - sa <= TAU * (1.0 + 1e-12)) {
            return Ok(Err(format!(
                "start angle SA = {sa}, terminate angle TA = {ta}: expected SA < TA ≤ SA + 2π"
            )));
        }
        let (a, b) = (axis.point(0.0), axis.point(1.0));
        let s = sweep::revolve(&c, a, (b - a).normalize(), sa, ta.min(sa + TAU))
            .and_then(|s| swapped(&s))
            .map_err(|r| surface_error(e, r))?;
        Ok(Ok(made(Surface::Nurbs(s))))
    }

    /// 122: the directrix moved by the generatrix, the vector from its start point to
    /// (LX, LY, LZ).
    fn tabulated(&self, e: &Entry, p: &Params, entries: &[Entry], factor: f64) -> Made<Made3> {
        let c = match self.model_curve(entries, p, 1, "directrix DE", factor, 0)? {
            Ok(c) => c.spline,
            Err(why) => return Ok(Err(why)),
        };
        let l = Vec3::new(p.real(2, "LX")?, p.real(3, "LY")?, p.real(4, "LZ")?) * factor;
        let v = l - c.point(c.domain().0);
        if v.length().is_nan() || v.length() <= 0.0 {
            return Ok(Err(
                "its generatrix has no length (LX, LY, LZ is the directrix's start point)".into(),
            ));
        }
        let s = sweep::extrude(&c, v, 0.0, 1.0).map_err(|r| surface_error(e, r))?;
        Ok(Ok(made(Surface::Nurbs(s))))
    }

    /// 118: rulings from DE1 to DE2 (DIRFLG 1: the first point of one to the last of the other)
    /// at equal relative arc length (form 0) or parameter (form 1); made exactly where the
    /// curves' B-spline parameters follow that rule.
    fn ruled(&self, e: &Entry, p: &Params, entries: &[Entry], factor: f64) -> Made<Made3> {
        let c1 = match self.model_curve(entries, p, 1, "DE1", factor, 0)? {
            Ok(c) => c,
            Err(why) => return Ok(Err(why)),
        };
        let c2 = match self.model_curve(entries, p, 2, "DE2", factor, 0)? {
            Ok(c) => c,
            Err(why) => return Ok(Err(why)),
        };
        let dirflg = p.int(3, "DIRFLG")?;
        if !(0..=1).contains(&dirflg) {
            return Ok(Err(format!("DIRFLG = {dirflg}; expected 0 or 1")));
        }
        let same_arc =
            matches!((c1.arc, c2.arc), (Some(a), Some(b)) if (a - b).abs() <= 1e-12 * a.max(1.0));
        let exact = match e.form {
            0 => (c1.uniform && c2.uniform) || same_arc,
            1 => (c1.exact && c2.exact) || same_arc,
            f => return Ok(Err(format!("form {f}; expected 0 or 1"))),
        };
        if !exact {
            return Ok(Err(if e.form == 0 {
                "form 0 joins points of equal relative arc length, which the curves' B-spline \
                 parameters do not follow (exact here: two lines, or two circular arcs of one \
                 sweep)"
                    .into()
            } else {
                "form 1 joins points of equal relative parameter, and a circular arc's (100) \
                 parameter is its angle, which its rational B-spline does not follow (exact \
                 here: lines, 126 and composites of them, or two arcs of one sweep)"
                    .into()
            }));
        }
        match sweep::ruled(&c1.spline, &c2.spline, dirflg == 1) {
            Some(s) => Ok(Ok(made(Surface::Nurbs(
                s.map_err(|r| surface_error(e, r))?,
            )))),
            None => Ok(Err(format!(
                "its curves (degrees {} and {}, the lower not one line segment) cannot be made of \
                 one degree exactly",
                c1.spline.degree(),
                c2.spline.degree()
            ))),
        }
    }

    /// 190: the plane through the 116 point DELOC with the 123 normal DENRML (form 1: u along
    /// the 123 reference direction DEREFD), over the default box.
    fn plane190(&self, e: &Entry, p: &Params, entries: &[Entry], factor: f64) -> Made<Made3> {
        let o = match self.vector(entries, p, 1, "DELOC", 116)? {
            Ok(v) => v * factor,
            Err(why) => return Ok(Err(why)),
        };
        let n = match self.vector(entries, p, 2, "DENRML", 123)? {
            Ok(v) => v,
            Err(why) => return Ok(Err(why)),
        };
        if n.length().is_nan() || n.length() <= 0.0 {
            return Ok(Err("its normal DENRML has no length".into()));
        }
        let frame = if e.form == 1 {
            match self.vector(entries, p, 3, "DEREFD", 123)? {
                Ok(r) if r.cross(n).length() > 0.0 => Frame::from_axis_and_x(o, n, r),
                Ok(_) => {
                    return Ok(Err(
                        "its reference direction DEREFD is along its normal (or has no length)"
                            .into(),
                    ))
                }
                Err(why) => return Ok(Err(why)),
            }
        } else {
            Frame::from_axis(o, n)
        };
        Ok(Ok(default_plane(frame)))
    }

    /// 108: the plane Ax + By + Cz = D, centred at the foot of its display symbol (X, Y, Z);
    /// form 1 bounded by the curve PTR (over the box of its control points), form −1 holed by
    /// it, form 0 (or no curve) over the default box.
    fn plane108(&self, e: &Entry, p: &Params, entries: &[Entry], factor: f64) -> Made<Made3> {
        let (a, b, c, d) = (
            p.real(1, "A")?,
            p.real(2, "B")?,
            p.real(3, "C")?,
            p.real(4, "D")?,
        );
        let n = Vec3::new(a, b, c);
        if n.length().is_nan() || n.length() <= 0.0 {
            return Ok(Err("its coefficients A, B, C are all zero".into()));
        }
        let ptr = if p.values.len() > 5 {
            p.int(5, "PTR")?
        } else {
            0
        };
        let opt = |i: usize, what: &str| {
            if p.values.len() > i {
                p.real(i, what)
            } else {
                Ok(0.0)
            }
        };
        let sym = Vec3::new(opt(6, "X")?, opt(7, "Y")?, opt(8, "Z")?);
        let o = (sym - (n.dot(sym) - d) / n.length_squared() * n) * factor;
        let frame = Frame::from_axis(o, n);
        if !(e.form == 1 || e.form == -1) || ptr == 0 {
            return Ok(Ok(default_plane(frame)));
        }
        let hole = e.form == -1;
        // A bounded plane spans its curve: the box of its control points (which hold it).
        let bounds = match self.model_curve(entries, p, 5, "PTR", factor, 0)? {
            Ok(c) if !hole => {
                let pts: Vec<[f64; 2]> = c
                    .spline
                    .homogeneous()
                    .iter()
                    .map(|h| {
                        let q = Vec3::new(h.x / h.w, h.y / h.w, h.z / h.w) - o;
                        [q.dot(frame.x), q.dot(frame.y)]
                    })
                    .collect();
                let lo = |k: usize| pts.iter().map(|q| q[k]).fold(f64::INFINITY, f64::min);
                let hi = |k: usize| pts.iter().map(|q| q[k]).fold(f64::NEG_INFINITY, f64::max);
                let (u, v) = ([lo(0), hi(0)], [lo(1), hi(1)]);
                let m = 1e-9 * (1.0 + (u[1] - u[0]).max(v[1] - v[0]));
                (u[1] - u[0] > m && v[1] - v[0] > m)
                    .then(|| ParamBox::new(u[0] - m, u[1] + m, v[0] - m, v[1] + m))
            }
            _ => None,
        };
        let mut out = match bounds {
            Some(b) => made(Surface::Plane(PlaneSurface::new(frame, b))),
            None => default_plane(frame),
        };
        out.bound = Some(hole);
        Ok(Ok(out))
    }

    /// The coordinates of the 116 point or 123 direction named by parameter `i` (its own 124
    /// applied; a direction's without the translation), in file units.
    fn vector(&self, entries: &[Entry], p: &Params, i: usize, what: &str, kind: u32) -> Made<Vec3> {
        let de = p.int(i, what)?;
        let Some(e) = entry_at(entries, de) else {
            return Err(p.error(
                i,
                format!("{what} points at D{de}, which is not a directory entry"),
            ));
        };
        if e.kind != kind {
            return Ok(Err(format!(
                "its {what} D{de} is an entity {}, expected a {kind}",
                e.kind
            )));
        }
        let q = self.params(e)?;
        let v = Vec3::new(q.real(1, "x")?, q.real(2, "y")?, q.real(3, "z")?);
        let t = self.transform(entries, e)?;
        Ok(Ok(if kind == 123 {
            apply(&t, v) - apply(&t, Vec3::ZERO)
        } else {
            apply(&t, v)
        }))
    }

    /// The curve named by parameter `i` of `p` as a B-spline in mm, its own 124 applied.
    fn model_curve(
        &self,
        entries: &[Entry],
        p: &Params,
        i: usize,
        what: &str,
        factor: f64,
        depth: usize,
    ) -> Made<ModelCurve> {
        let de = p.int(i, what)?;
        let Some(e) = entry_at(entries, de) else {
            return Err(p.error(
                i,
                format!("{what} points at D{de}, which is not a directory entry"),
            ));
        };
        let t = self.transform(entries, e)?;
        let at = |q: Vec3| apply(&t, q) * factor;
        let bad = || format!("its {what} D{de} (an entity {}) makes no curve", e.kind);
        match e.kind {
            110 => {
                let q = self.params(e)?;
                let v = (1..=6)
                    .map(|k| q.real(k, "line coordinate"))
                    .collect::<Result<Vec<_>, _>>()?;
                let (a, b) = (
                    at(Vec3::new(v[0], v[1], v[2])),
                    at(Vec3::new(v[3], v[4], v[5])),
                );
                if a == b {
                    return Ok(Err(format!("its {what} D{de} is a line of no length")));
                }
                Ok(sweep::line(a, b - a, 0.0, 1.0)
                    .map(|spline| ModelCurve {
                        spline,
                        exact: true,
                        arc: None,
                        uniform: true,
                    })
                    .ok_or_else(bad))
            }
            100 => {
                let q = self.params(e)?;
                let v = (1..=7)
                    .map(|k| q.real(k, "arc parameter"))
                    .collect::<Result<Vec<_>, _>>()?;
                let [zt, cx, cy, x0, y0, x1, y1] = [v[0], v[1], v[2], v[3], v[4], v[5], v[6]];
                let r = (x0 - cx).hypot(y0 - cy);
                let a0 = (y0 - cy).atan2(x0 - cx);
                let mut a1 = (y1 - cy).atan2(x1 - cx);
                if a1 <= a0 || (x0, y0) == (x1, y1) {
                    a1 += TAU;
                }
                if !(r.is_finite() && r > 0.0) {
                    return Ok(Err(format!("its {what} D{de} is an arc of no radius")));
                }
                let f = Frame::at(Vec3::new(cx, cy, zt));
                let spline = sweep::conic(&f, r, r, a0, a1).and_then(|c| mapped(&c, at));
                let round = t.map_or(true, |m| similarity(&m));
                Ok(spline
                    .map(|spline| ModelCurve {
                        spline,
                        exact: false,
                        arc: round.then_some(a1 - a0),
                        uniform: false,
                    })
                    .ok_or_else(bad))
            }
            126 => {
                let c = self.curve126(e, entries, factor)?;
                let spline = match c.spline() {
                    Ok(s) => s,
                    Err(why) => return Ok(Err(format!("its {what}, the 126 at D{de}: {why}"))),
                };
                let (t0, t1) = spline.domain();
                let (lo, hi) = (c.range[0].max(t0), c.range[1].min(t1));
                if lo >= hi {
                    return Ok(Err(format!(
                        "its {what}, the 126 at D{de}: its range [{}, {}] leaves nothing of the knots' [{t0}, {t1}]",
                        c.range[0], c.range[1]
                    )));
                }
                let spline = if (lo, hi) == (t0, t1) {
                    Some(spline)
                } else {
                    clip(&spline, lo, hi)
                };
                let uniform = c.degree == 1 && c.points.len() == 2 && c.weights[0] == c.weights[1];
                Ok(spline
                    .map(|spline| ModelCurve {
                        spline,
                        exact: true,
                        arc: None,
                        uniform,
                    })
                    .ok_or_else(bad))
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
                let q = self.params(e)?;
                let n = q.count(1, "N")?;
                let mut members = Vec::with_capacity(n);
                for k in 0..n {
                    match self.model_curve(
                        entries,
                        &q,
                        2 + k,
                        "composite member",
                        factor,
                        depth + 1,
                    )? {
                        Ok(m) => members.push(m),
                        Err(why) => return Ok(Err(format!("its {what} D{de}: {why}"))),
                    }
                }
                // The members are in the composite's definition space: its 124 moves them.
                let splines: Option<Vec<BSplineCurve>> = members
                    .iter()
                    .map(|m| mapped(&m.spline, |x| apply(&t, x / factor) * factor))
                    .collect();
                let Some(splines) = splines.filter(|s| !s.is_empty()) else {
                    return Ok(Err(bad()));
                };
                let size = splines
                    .iter()
                    .flat_map(|s| {
                        s.homogeneous()
                            .iter()
                            .map(|h| (h.truncate() / h.w).abs().max_element())
                    })
                    .fold(0.0, f64::max);
                let tol = self.resolution.max(1e-9 * (1.0 + size));
                let Some(spline) = sweep::join(&splines, tol) else {
                    return Ok(Err(format!(
                        "its {what}, the composite D{de}: its members do not join end to end in one degree (a gap, or curves of different degrees)"
                    )));
                };
                let one = members.len() == 1;
                Ok(Ok(ModelCurve {
                    spline,
                    exact: members.iter().all(|m| m.exact),
                    arc: if one { members[0].arc } else { None },
                    uniform: one && members[0].uniform,
                }))
            }
            k => Ok(Err(format!(
                "its {what} D{de} is an entity {k}, not a curve read here (100, 102, 110 or 126)"
            ))),
        }
    }
}

/// A plane over the default box.
fn default_plane(frame: Frame) -> Made3 {
    let [a, b] = DEFAULT_LINEAR_RANGE;
    Made3 {
        surface: Surface::Plane(PlaneSurface::new(frame, ParamBox::new(a, b, a, b))),
        defaulted: Some("u and v (an unbounded plane)"),
        bound: None,
    }
}

fn surface_error(e: &Entry, reason: NurbsError) -> ReadError {
    ReadError::Surface {
        format: Format::Iges,
        line: e.line,
        entity: format!("entity {} at D{}", e.kind, e.de),
        reason,
    }
}

/// Whether the matrix's rotation part is a rotation (or reflection) times a scale: it keeps
/// circles circles.
fn similarity(m: &[f64; 12]) -> bool {
    let col = |c: usize| Vec3::new(m[c], m[4 + c], m[8 + c]);
    let (a, b, c) = (col(0), col(1), col(2));
    let s = a.length_squared();
    let tol = 1e-9 * s.max(1e-300);
    (b.length_squared() - s).abs() <= tol
        && (c.length_squared() - s).abs() <= tol
        && a.dot(b).abs() <= tol
        && b.dot(c).abs() <= tol
        && a.dot(c).abs() <= tol
}

/// `c` with its control points moved by the affine map `f` (exact for a rational B-spline).
fn mapped(c: &BSplineCurve, f: impl Fn(Vec3) -> Vec3) -> Option<BSplineCurve> {
    let (pts, ws): (Vec<Vec3>, Vec<f64>) = c
        .homogeneous()
        .iter()
        .map(|h| (f(h.truncate() / h.w), h.w))
        .unzip();
    BSplineCurve::new(c.degree(), c.knots().to_vec(), &pts, &ws).ok()
}

/// `c` over `[lo, hi]` within its domain, exactly (knot insertion, through a surface's).
fn clip(c: &BSplineCurve, lo: f64, hi: f64) -> Option<BSplineCurve> {
    let s = sweep::extrude(c, Vec3::X, 0.0, 1.0).ok()?;
    let r = s.restricted([lo, hi], [0.0, 1.0]).ok()?;
    let n = r.net_size().0;
    let pts: Vec<Vec3> = (0..n).map(|i| r.control_point(i, 0)).collect();
    let ws: Vec<f64> = (0..n).map(|i| r.weight(i, 0)).collect();
    BSplineCurve::new(r.degree_u(), r.knots_u().to_vec(), &pts, &ws).ok()
}

/// `s` with u and v exchanged (its normal reversed).
fn swapped(s: &NurbsSurface) -> Result<NurbsSurface, NurbsError> {
    let (nu, nv) = s.net_size();
    let pts: Vec<Vec<Vec3>> = (0..nv)
        .map(|j| (0..nu).map(|i| s.control_point(i, j)).collect())
        .collect();
    let ws: Vec<Vec<f64>> = (0..nv)
        .map(|j| (0..nu).map(|i| s.weight(i, j)).collect())
        .collect();
    NurbsSurface::new(
        s.degree_v(),
        s.degree_u(),
        s.knots_v().to_vec(),
        s.knots_u().to_vec(),
        &pts,
        Some(&ws),
    )
}
