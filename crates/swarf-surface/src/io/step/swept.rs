//! The STEP surfaces built on other geometry: `SURFACE_OF_REVOLUTION` and
//! `SURFACE_OF_LINEAR_EXTRUSION` (exact NURBS of their swept curve, [`crate::sweep`]),
//! `RECTANGULAR_TRIMMED_SURFACE` (its basis over the rectangle), `OFFSET_SURFACE` of an
//! elementary surface (the same kind, moved or with another radius) and
//! `DEGENERATE_TOROIDAL_SURFACE` (a torus whose tube passes the axis: the outer or inner part).

use swarf_geom::math::Vec3;

use super::curves::{Curve, Space};
use super::entities::{kind_name, supported, Model, R};
use super::lex::{Instance, Param};
use super::DEFAULT_LINEAR_RANGE;
use crate::compound::ReadNote;
use crate::curve::BSplineCurve;
use crate::surface::{NurbsSurface, ParamBox, ParametricSurface, Surface, ToroidalSurface};
use crate::sweep;

/// The kinds read here.
pub(super) const SWEPT: [&str; 5] = [
    "SURFACE_OF_REVOLUTION",
    "SURFACE_OF_LINEAR_EXTRUSION",
    "RECTANGULAR_TRIMMED_SURFACE",
    "OFFSET_SURFACE",
    "DEGENERATE_TOROIDAL_SURFACE",
];

/// Deepest chain of basis surfaces (an offset of a trimmed surface of …).
const MAX_BASIS_DEPTH: usize = 8;

pub(super) fn is_swept(inst: &Instance) -> bool {
    SWEPT.iter().any(|s| inst.part(s).is_some())
}

/// A surface, its name, and whether its normal is the opposite of the one `Surface` gives
/// (a `RECTANGULAR_TRIMMED_SURFACE` with one sense `.F.`).
pub(super) type Sensed = (Surface, Option<String>, bool);

/// A swept curve as a B-spline, and the range of its parameter to cut from the swept surface
/// afterwards (a bounded curve's trimmed range).
type SweptCurve = (BSplineCurve, Option<[f64; 2]>);

/// Parameter ranges in the file's own parameters (STEP's), given by a rectangular trim.
type Ranges = Option<([f64; 2], [f64; 2])>;

impl Model<'_> {
    /// Surface `id` of any kind read: `Ok(Err(why))` when it is of a kind (or on a basis or
    /// curve) that is not read.
    pub(super) fn any_surface(
        &self,
        id: u64,
        face: Option<(u64, &Param)>,
        index: usize,
        notes: &mut Vec<ReadNote>,
    ) -> R<Result<Sensed, String>> {
        self.sensed(id, face, index, notes, None, 0)
    }

    fn sensed(
        &self,
        id: u64,
        face: Option<(u64, &Param)>,
        index: usize,
        notes: &mut Vec<ReadNote>,
        ranges: Ranges,
        depth: usize,
    ) -> R<Result<Sensed, String>> {
        let inst = self.get(id, id)?;
        if depth > MAX_BASIS_DEPTH {
            return Ok(Err(format!(
                "basis surfaces nested deeper than {MAX_BASIS_DEPTH}"
            )));
        }
        if supported(inst) {
            // A rectangular trim replaces the parameter box: the reader's notes on a box it
            // chose are not the surface's then.
            let mut own = Vec::new();
            let (mut s, name) = self.surface(id, face, index, &mut own)?;
            notes.extend(own.into_iter().filter(|n| {
                ranges.is_none() || !matches!(n, ReadNote::DefaultParameterBox { .. })
            }));
            if let Some((u, v)) = ranges {
                match restrict(&mut s, u, v, depth == 0) {
                    Ok(()) => {}
                    Err(why) => return Ok(Err(why)),
                }
            }
            return Ok(Ok((s, name, false)));
        }
        let first = |n: &str| inst.part(n);
        if let Some(p) = first("SURFACE_OF_REVOLUTION") {
            return self.revolution(id, p, face, index, notes, ranges);
        }
        if let Some(p) = first("SURFACE_OF_LINEAR_EXTRUSION") {
            return self.extrusion(id, p, face, index, notes, ranges);
        }
        if let Some(p) = first("RECTANGULAR_TRIMMED_SURFACE") {
            if ranges.is_some() {
                return Ok(Err("a trimmed surface of a trimmed surface".into()));
            }
            let basis = self.reference(id, p.get(1), "basis_surface")?;
            let b = self.get(id, basis)?;
            let u1 = self.num(id, p.get(2), "u1")?;
            let u2 = self.num(id, p.get(3), "u2")?;
            let v1 = self.num(id, p.get(4), "v1")?;
            let v2 = self.num(id, p.get(5), "v2")?;
            let us = self.logical(id, p.get(6), "usense")?;
            let vs = self.logical(id, p.get(7), "vsense")?;
            let [(fu, pu), (fv, pv)] = self.parameter_units(b);
            let (Some(u), Some(v)) = (
                sensed_range(u1 * fu, u2 * fu, us, pu),
                sensed_range(v1 * fv, v2 * fv, vs, pv),
            ) else {
                return Ok(Err(format!(
                    "empty or wrapped range u {u1}..{u2}, v {v1}..{v2} on a basis that is not closed"
                )));
            };
            let out = self.sensed(basis, face, index, notes, Some((u, v)), depth + 1)?;
            let name = Self::name(p.first());
            return Ok(out.map(|(s, n, r)| (s, name.or(n), r != (us != vs))));
        }
        if let Some(p) = first("OFFSET_SURFACE") {
            let basis = self.reference(id, p.get(1), "basis_surface")?;
            let d = self.num(id, p.get(2), "distance")? * self.length;
            let out = self.sensed(basis, face, index, notes, ranges, depth + 1)?;
            let name = Self::name(p.first());
            return Ok(match out {
                // Along the basis's own normal: reversed (`r`), the offset goes the other way.
                Ok((s, n, r)) => {
                    offset(s, if r { -d } else { d }).map(|(s, r2)| (s, name.or(n), r != r2))
                }
                Err(why) => Err(why),
            });
        }
        if let Some(p) = first("DEGENERATE_TOROIDAL_SURFACE") {
            let frame = self.placement(id, p.get(1))?;
            let big = self.num(id, p.get(2), "major_radius")? * self.length;
            let r = self.num(id, p.get(3), "minor_radius")? * self.length;
            let outer = self.logical(id, p.get(4), "select_outer")?;
            // Where R + r·cos v = 0 the tube meets the axis: the outer part (an apple) is
            // |v| ≤ c, the inner (a lemon) the rest.
            let c = if r > big && big > 0.0 {
                (-big / r).acos()
            } else {
                std::f64::consts::PI
            };
            let v = if outer {
                [-c, c]
            } else {
                [c, std::f64::consts::TAU - c]
            };
            if !outer && c >= std::f64::consts::PI {
                return Ok(Err(
                    "select_outer .F. on a torus whose tube does not pass its axis".into(),
                ));
            }
            let mut bx = ParamBox::new(0.0, std::f64::consts::TAU, v[0], v[1]);
            if let Some((u, v)) = ranges {
                bx = ParamBox::new(u[0], u[1], v[0].max(bx.v[0]), v[1].min(bx.v[1]));
                if bx.v[0] >= bx.v[1] {
                    return Ok(Err("the rectangle misses the selected part".into()));
                }
            }
            let Some(t) = ToroidalSurface::new(frame, big, r, bx) else {
                return Err(self.bad(id, "DEGENERATE_TOROIDAL_SURFACE: radii must be positive"));
            };
            return Ok(Ok((Surface::Torus(t), Self::name(p.first()), false)));
        }
        Ok(Err(kind_name(inst)))
    }

    /// The surfaces that are the basis of a rectangular trim, an offset or a curve-bounded
    /// surface: read only through those (unless a face has them as its geometry).
    pub(super) fn bases(&self) -> std::collections::HashSet<u64> {
        let mut out = std::collections::HashSet::new();
        for inst in self.map.values() {
            for n in [
                "RECTANGULAR_TRIMMED_SURFACE",
                "OFFSET_SURFACE",
                "CURVE_BOUNDED_SURFACE",
            ] {
                if let Some(Param::Ref(b)) = inst.part(n).and_then(|p| p.get(1)) {
                    out.insert(*b);
                }
            }
        }
        out
    }

    /// Millimetres (or radians) per file unit of the u and v parameters of surface `b`, and
    /// whether each is an angle (closed, a turn).
    pub(super) fn parameter_units(&self, b: &Instance) -> [(f64, bool); 2] {
        let (l, a) = ((self.length, false), (self.angle, true));
        // A conic's parameter is an angle, a trimmed conic's too.
        let conic = |p: Option<&Param>| -> (f64, bool) {
            let is_conic =
                |ci: &Instance| ci.part("CIRCLE").is_some() || ci.part("ELLIPSE").is_some();
            let curve = match p {
                Some(Param::Ref(c)) => self.map.get(c),
                _ => None,
            };
            let basis =
                curve
                    .and_then(|ci| ci.part("TRIMMED_CURVE"))
                    .and_then(|t| match t.get(1) {
                        Some(Param::Ref(b)) => self.map.get(b),
                        _ => None,
                    });
            if curve.is_some_and(is_conic) || basis.is_some_and(is_conic) {
                a
            } else {
                (1.0, false)
            }
        };
        if b.part("PLANE").is_some() {
            [l, l]
        } else if b.part("CYLINDRICAL_SURFACE").is_some() || b.part("CONICAL_SURFACE").is_some() {
            [a, l]
        } else if b.part("SPHERICAL_SURFACE").is_some()
            || b.part("TOROIDAL_SURFACE").is_some()
            || b.part("DEGENERATE_TOROIDAL_SURFACE").is_some()
        {
            [a, a]
        } else if let Some(p) = b.part("SURFACE_OF_REVOLUTION") {
            [a, conic(p.get(1))]
        } else if let Some(p) = b.part("SURFACE_OF_LINEAR_EXTRUSION") {
            [conic(p.get(1)), (1.0, false)]
        } else {
            [(1.0, false), (1.0, false)]
        }
    }

    /// The swept curve `p[1]` of surface `id` as a B-spline over `range` (its STEP parameter)
    /// or, for a line (unbounded) without one, over `line_range(p, d)`; a conic without one
    /// takes a full turn, a bounded curve its own range. A `TRIMMED_CURVE` keeps the part of
    /// its basis its trims keep ([`Model::kept`]), run backwards when its sense disagrees (a
    /// rectangular trim's range, when there is one, is then in the basis's parameter, and
    /// must meet the trimmed part). With the spline, the range to cut from the swept surface
    /// afterwards, in the spline's parameter (a bounded curve's, when it has one).
    fn swept_curve(
        &self,
        id: u64,
        p: &[Param],
        range: Option<[f64; 2]>,
        line_range: &mut dyn FnMut(Vec3, Vec3) -> [f64; 2],
    ) -> R<Result<SweptCurve, String>> {
        let cid = self.reference(id, p.get(1), "swept_curve")?;
        let trimmed = self.get(id, cid)?.part("TRIMMED_CURVE");
        let (curve, range, against) = match trimmed {
            Some(tp) => match self.kept(cid, tp, Space::Model) {
                Ok(k) => {
                    let r = match range {
                        None => k.range,
                        Some(r) if k.against => {
                            return Ok(Err(format!(
                                "swept curve #{cid}: a rectangular trim ({}..{}) of a surface \
                                 swept along a trimmed curve that runs against its basis is not \
                                 read",
                                r[0], r[1]
                            )))
                        }
                        Some(r) => match meet(r, k.range, matches!(k.curve, Curve::Conic { .. })) {
                            Some(m) => m,
                            None => {
                                return Ok(Err(format!(
                                    "swept curve #{cid}: the rectangle's range {}..{} misses \
                                     the trimmed curve's {}..{}",
                                    r[0], r[1], k.range[0], k.range[1]
                                )))
                            }
                        },
                    };
                    (k.curve, Some(r), k.against)
                }
                Err(why) => return Ok(Err(format!("swept curve #{cid}: {why}"))),
            },
            None => match self.curve(id, cid, 0) {
                Ok(c) => (c, range, false),
                Err(why) => return Ok(Err(format!("swept curve #{cid}: {why}"))),
            },
        };
        let tau = std::f64::consts::TAU;
        let bounded = matches!(curve, Curve::Spline(_) | Curve::Polyline(_));
        let spline = match curve {
            Curve::Line { p, d } => {
                let [a, b] = range.unwrap_or_else(|| line_range(p, d));
                sweep::line(p, d, a, b)
            }
            Curve::Conic { f, a, b } => {
                let [t0, t1] = range.unwrap_or([0.0, tau]);
                sweep::conic(&f, a, b, t0, t1)
            }
            Curve::Spline(c) => Some(c),
            Curve::Polyline(pts) => {
                let n = pts.len();
                let mut knots = vec![0.0];
                knots.extend((0..n).map(|k| k as f64));
                knots.push((n - 1) as f64);
                BSplineCurve::new(1, knots, &pts, &vec![1.0; n]).ok()
            }
        };
        let Some(spline) = spline else {
            return Ok(Err(format!("swept curve #{cid}: an empty parameter range")));
        };
        // A bounded curve restricted afterwards (on the surface, exactly); run backwards, its
        // parameter t is the basis's −t.
        let after = range
            .filter(|_| bounded)
            .map(|[a, b]| if against { [-b, -a] } else { [a, b] });
        let spline = if against { spline.reversed() } else { spline };
        Ok(Ok((spline, after)))
    }

    fn revolution(
        &self,
        id: u64,
        p: &[Param],
        face: Option<(u64, &Param)>,
        index: usize,
        notes: &mut Vec<ReadNote>,
        ranges: Ranges,
    ) -> R<Result<Sensed, String>> {
        let aid = self.reference(id, p.get(2), "axis_position")?;
        let ai = self.get(id, aid)?;
        let Some(ap) = ai.part("AXIS1_PLACEMENT") else {
            return Ok(Err(format!(
                "axis_position #{aid} is {}, not an AXIS1_PLACEMENT",
                ai.first_name()
            )));
        };
        let o = self.point(aid, self.reference(aid, ap.get(1), "location")?)?;
        let z = self.direction(aid, ap.get(2), Vec3::Z)?;
        let pts = match face {
            Some((fid, bounds)) => self.boundary_points(fid, bounds)?,
            None => Vec::new(),
        };
        let mut defaulted = false;
        // A line's parameters that turn onto the face's points: by height along the axis, or
        // (a line square to the axis) by the distance from it, on the side of the line's
        // point nearest the axis that holds its origin.
        let mut line_range = |lp: Vec3, d: Vec3| {
            let ts: Vec<f64> = pts
                .iter()
                .map(|&q| {
                    if d.dot(z).abs() > 1e-9 * d.length() {
                        ((q - o).dot(z) - (lp - o).dot(z)) / d.dot(z)
                    } else {
                        let perp = |x: Vec3| x - x.dot(z) * z;
                        let (a, b) = (perp(lp - o), perp(d));
                        let rho2 = perp(q - o).length_squared();
                        let foot = -a.dot(b) / b.length_squared();
                        let disc = foot * foot - (a.length_squared() - rho2) / b.length_squared();
                        foot + if foot <= 0.0 { 1.0 } else { -1.0 } * disc.max(0.0).sqrt()
                    }
                })
                .collect();
            span(&ts).unwrap_or_else(|| {
                defaulted = true;
                DEFAULT_LINEAR_RANGE
            })
        };
        let (u, v) = match ranges {
            Some((u, v)) => (u, Some(v)),
            None => ([0.0, std::f64::consts::TAU], None),
        };
        let (c, restrict_v) = match self.swept_curve(id, p, v, &mut line_range)? {
            Ok(c) => c,
            Err(why) => return Ok(Err(why)),
        };
        if defaulted {
            notes.push(ReadNote::DefaultParameterBox {
                patch: index,
                what: "v (the swept line's parameter)".into(),
            });
        }
        let s =
            sweep::revolve(&c, o, z, u[0], u[1]).map_err(|reason| self.nurbs_error(id, reason))?;
        let s = match restrict_v {
            Some(v) => match clipped(&s, s.domain().u, v) {
                Ok(s) => s,
                Err(why) => return Ok(Err(why)),
            },
            _ => s,
        };
        Ok(Ok((Surface::Nurbs(s), Self::name(p.first()), false)))
    }

    fn extrusion(
        &self,
        id: u64,
        p: &[Param],
        face: Option<(u64, &Param)>,
        index: usize,
        notes: &mut Vec<ReadNote>,
        ranges: Ranges,
    ) -> R<Result<Sensed, String>> {
        let vid = self.reference(id, p.get(2), "extrusion_axis")?;
        let vi = self.get(id, vid)?;
        let Some(vp) = vi.part("VECTOR") else {
            return Err(self.bad(vid, format!("found {}, expected VECTOR", vi.first_name())));
        };
        let dir = self.direction(vid, vp.get(1), Vec3::Z)?;
        let mag = self.num(vid, vp.get(2), "magnitude")? * self.length;
        if !(mag.abs() > 0.0 && mag.is_finite()) {
            return Err(self.bad(vid, "SURFACE_OF_LINEAR_EXTRUSION: zero or infinite vector"));
        }
        let vector = dir * mag;
        let pts = match face {
            Some((fid, bounds)) => self.boundary_points(fid, bounds)?,
            None => Vec::new(),
        };
        let mut defaulted = Vec::new();
        // A line's (u) parameters of the face's points, solving q = p + u·d + v·V.
        let mut line_range = |lp: Vec3, d: Vec3| {
            let (dd, dv, vv) = (d.dot(d), d.dot(vector), vector.dot(vector));
            let det = dd * vv - dv * dv;
            let ts: Vec<f64> = if det > 1e-12 * dd * vv {
                pts.iter()
                    .map(|&q| {
                        let r = q - lp;
                        (r.dot(d) * vv - r.dot(vector) * dv) / det
                    })
                    .collect()
            } else {
                Vec::new()
            };
            span(&ts).unwrap_or_else(|| {
                defaulted.push("u (the swept line's parameter)");
                DEFAULT_LINEAR_RANGE
            })
        };
        let (u, v) = match ranges {
            Some((u, v)) => (Some(u), Some(v)),
            None => (None, None),
        };
        let (c, restrict_u) = match self.swept_curve(id, p, u, &mut line_range)? {
            Ok(c) => c,
            Err(why) => return Ok(Err(why)),
        };
        let v = v.unwrap_or_else(|| {
            // v of the face's points: their height along V less the curve's (whose control
            // points hold it), in units of |V|.
            let along = |x: Vec3| x.dot(vector) / vector.length_squared();
            let cs: Vec<f64> = c
                .homogeneous()
                .iter()
                .map(|h| along(Vec3::new(h.x / h.w, h.y / h.w, h.z / h.w)))
                .collect();
            let (clo, chi) = (
                cs.iter().copied().fold(f64::INFINITY, f64::min),
                cs.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            );
            let qs: Vec<f64> = pts.iter().map(|&q| along(q)).collect();
            match span(&qs) {
                Some([lo, hi]) if (lo - chi) < (hi - clo) => [lo - chi, hi - clo],
                _ => {
                    defaulted.push("v");
                    let d = mag.abs();
                    [DEFAULT_LINEAR_RANGE[0] / d, DEFAULT_LINEAR_RANGE[1] / d]
                }
            }
        });
        for what in defaulted {
            notes.push(ReadNote::DefaultParameterBox {
                patch: index,
                what: what.into(),
            });
        }
        let s = sweep::extrude(&c, vector, v[0], v[1])
            .map_err(|reason| self.nurbs_error(id, reason))?;
        let s = match restrict_u {
            Some(u) => match clipped(&s, u, s.domain().v) {
                Ok(s) => s,
                Err(why) => return Ok(Err(why)),
            },
            _ => s,
        };
        Ok(Ok((Surface::Nurbs(s), Self::name(p.first()), false)))
    }

    fn nurbs_error(&self, id: u64, reason: crate::surface::NurbsError) -> crate::io::ReadError {
        crate::io::ReadError::Surface {
            format: crate::io::Format::Step,
            line: self.line(id),
            entity: format!("#{id}"),
            reason,
        }
    }
}

/// Where the range `r` meets `k`; on an angle (`periodic`) `r` moved whole turns to meet it
/// most.
fn meet(r: [f64; 2], k: [f64; 2], periodic: bool) -> Option<[f64; 2]> {
    let tau = std::f64::consts::TAU;
    // The turn that starts r at or after k's start, and the one before it.
    let shift = if periodic {
        ((k[0] - r[0]) / tau).ceil() * tau
    } else {
        0.0
    };
    let turns: &[f64] = if periodic { &[0.0, -tau] } else { &[0.0] };
    turns
        .iter()
        .map(|t| [(r[0] + shift + t).max(k[0]), (r[1] + shift + t).min(k[1])])
        .filter(|m| m[0] < m[1])
        .max_by(|x, y| (x[1] - x[0]).total_cmp(&(y[1] - y[0])))
}

/// `[min, max]` of values with a positive extent.
fn span(ts: &[f64]) -> Option<[f64; 2]> {
    let lo = ts.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = ts.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (hi - lo > 1e-9 * (1.0 + hi.abs().max(lo.abs())) && (hi - lo).is_finite()).then_some([lo, hi])
}

/// The range a rectangular trim's `t1, t2` with `sense` cover, increasing: from `t1` up to `t2`
/// (sense `.T.`) or down (`.F.`); across the seam (a whole turn added) only on a `periodic`
/// (angle) parameter.
fn sensed_range(t1: f64, t2: f64, sense: bool, periodic: bool) -> Option<[f64; 2]> {
    let (a, b) = if sense { (t1, t2) } else { (t2, t1) };
    if !(a.is_finite() && b.is_finite()) {
        return None;
    }
    if a < b {
        Some([a, b])
    } else if periodic && a > b {
        Some([a, b + std::f64::consts::TAU])
    } else {
        None
    }
}

/// The NURBS `s` over `u × v` (within its domain).
fn clipped(s: &NurbsSurface, u: [f64; 2], v: [f64; 2]) -> Result<NurbsSurface, String> {
    let d = s.domain();
    let cut = |r: [f64; 2], dd: [f64; 2]| [r[0].max(dd[0]), r[1].min(dd[1])];
    s.restricted(cut(u, d.u), cut(v, d.v))
        .map_err(|e| format!("the rectangle leaves nothing of the basis: {e}"))
}

/// Surface `s` restricted to the rectangle `u × v` of its own parameters.
fn restrict(s: &mut Surface, u: [f64; 2], v: [f64; 2], _top: bool) -> Result<(), String> {
    let b = ParamBox::new(u[0], u[1], v[0], v[1]);
    match s {
        Surface::Nurbs(n) => *n = clipped(n, u, v)?,
        Surface::Plane(p) => p.domain = b,
        Surface::Cylinder(p) => p.domain = b,
        Surface::Cone(p) => p.domain = b,
        Surface::Sphere(p) => {
            let h = std::f64::consts::FRAC_PI_2;
            p.domain = ParamBox::new(u[0], u[1], v[0].max(-h), v[1].min(h));
            if p.domain.v[0] >= p.domain.v[1] {
                return Err("the rectangle misses the sphere's latitudes".into());
            }
        }
        Surface::Torus(p) => p.domain = b,
    }
    Ok(())
}

/// The elementary surface `s` offset by `d` along its normal `S_u × S_v`: the same kind
/// (`true` when its normal is then the other way). A B-spline has no exact offset.
fn offset(s: Surface, d: f64) -> Result<(Surface, bool), String> {
    match s {
        Surface::Plane(mut p) => {
            p.frame.origin += d * p.frame.z;
            Ok((Surface::Plane(p), false))
        }
        Surface::Cylinder(mut c) if c.radius + d > 0.0 => {
            c.radius += d;
            Ok((Surface::Cylinder(c), false))
        }
        Surface::Sphere(mut c) if c.radius + d > 0.0 => {
            c.radius += d;
            Ok((Surface::Sphere(c), false))
        }
        Surface::Torus(mut t) if t.minor + d > 0.0 => {
            t.minor += d;
            Ok((Surface::Torus(t), false))
        }
        Surface::Cone(mut c) => {
            // The normal is cos α·e − sin α·z: the point (ρ, v) moves to (ρ + d cos α,
            // v − d sin α), the same cone with radius R + d / cos α at the new v = 0.
            let (sa, ca) = c.semi_angle.sin_cos();
            let r = c.radius + d / ca;
            c.domain.v = [c.domain.v[0] - d * sa, c.domain.v[1] - d * sa];
            if r >= 0.0 {
                c.radius = r;
            } else {
                // The new v = 0 circle lies past the apex: move the origin to the apex.
                let shift = -r / sa * ca;
                c.frame.origin += shift * c.frame.z;
                c.domain.v = [c.domain.v[0] - shift, c.domain.v[1] - shift];
                c.radius = 0.0;
            }
            Ok((Surface::Cone(c), false))
        }
        Surface::Nurbs(_) => Err("an offset of a B-spline surface (no exact B-spline form)".into()),
        other => Err(format!(
            "an offset of a {} through its centre or axis ({d} mm)",
            other.kind()
        )),
    }
}
