//! Model-space edge curves of face bounds: lines, conics, B-splines (the shared
//! [`BSplineCurve`]) and polylines, read through surface, seam, intersection and trimmed curves.

use swarf_geom::math::Vec3;
use swarf_geom::Frame;

use super::entities::{Model, R};
use super::lex::{show, Param};
use super::trims::Built;
use crate::curve::BSplineCurve;
use crate::io::TrimFailure;
use crate::surface::NurbsSurface;

/// Deepest nesting of curves (a SURFACE_CURVE of a TRIMMED_CURVE of …) and of edges.
pub(super) const MAX_CURVE_DEPTH: usize = 8;
/// Most control points of a B-spline edge curve, and most points of a POLYLINE or POLY_LOOP.
pub(super) const MAX_CURVE_POINTS: usize = 100_000;

/// A model-space edge curve (mm).
pub(super) enum Curve {
    /// `p + t·d`.
    Line { p: Vec3, d: Vec3 },
    /// `origin + a·cos t·x + b·sin t·y` (a circle when `a = b`).
    Conic { f: Frame, a: f64, b: f64 },
    /// A rational B-spline.
    Spline(BSplineCurve),
    /// Vertices; `t ∈ [0, n − 1]`, vertex `k` at `t = k`.
    Polyline(Vec<Vec3>),
}

impl Curve {
    pub(super) fn point(&self, t: f64) -> Vec3 {
        match self {
            Curve::Line { p, d } => *p + t * *d,
            Curve::Conic { f, a, b } => f.origin + a * t.cos() * f.x + b * t.sin() * f.y,
            Curve::Spline(c) => c.point(t),
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
    pub(super) fn reversed(self) -> Curve {
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
            Curve::Spline(c) => Curve::Spline(c.reversed()),
            Curve::Polyline(p) => Curve::Polyline(p.into_iter().rev().collect()),
        }
    }

    /// The parameter range of a bounded curve.
    pub(super) fn range(&self) -> Option<(f64, f64)> {
        match self {
            Curve::Line { .. } | Curve::Conic { .. } => None,
            Curve::Spline(c) => Some(c.domain()),
            Curve::Polyline(p) => Some((0.0, (p.len() - 1) as f64)),
        }
    }

    /// The parameter of the curve point nearest `q`, and its distance.
    pub(super) fn param_of(&self, q: Vec3) -> (f64, f64) {
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
            Curve::Spline(c) => {
                let knots = c.knots();
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
    pub(super) fn steps(&self, a: f64, b: f64) -> Vec<f64> {
        let (lo, hi) = (a.min(b), a.max(b));
        let mut ts: Vec<f64> = match self {
            Curve::Line { .. } => (0..=4).map(|k| a + (b - a) * k as f64 / 4.0).collect(),
            Curve::Conic { .. } => {
                let n = ((hi - lo) / std::f64::consts::FRAC_PI_2 * 4.0)
                    .ceil()
                    .clamp(4.0, 1024.0) as usize;
                (0..=n).map(|k| a + (b - a) * k as f64 / n as f64).collect()
            }
            Curve::Spline(c) => {
                let mut breaks = vec![lo];
                breaks.extend(c.knots().iter().copied().filter(|&k| k > lo && k < hi));
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

/// Where a curve lies: in model space, or in a surface's parameters (a `PCURVE`'s curve).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Space {
    Model,
    Parameter,
}

/// The part of its basis curve a `TRIMMED_CURVE` keeps.
pub(super) struct Kept {
    /// The basis curve (itself, not run backwards).
    pub(super) curve: Curve,
    /// The basis's parameters kept, increasing (a conic's may pass 2π: the part from the
    /// first to the second across the seam).
    pub(super) range: [f64; 2],
    /// True when the trimmed curve runs against its basis (`sense_agreement` `.F.`): from
    /// `range[1]` down to `range[0]`.
    pub(super) against: bool,
}

impl Model<'_> {
    /// The frame and semi-axes of a parameter-space `CIRCLE` or `ELLIPSE` `id` with attributes
    /// `c`: its `AXIS2_PLACEMENT_2D(name, location, ref_direction)` (x the reference
    /// direction, or (1, 0) when omitted; y a quarter turn on), its radii as written.
    fn conic_2d(&self, id: u64, c: &[Param]) -> R<(Frame, f64, f64)> {
        let pid = self.reference(id, c.get(1), "position")?;
        let pi = self.get(id, pid)?;
        let ap = pi.part("AXIS2_PLACEMENT_2D").ok_or_else(|| {
            self.bad(
                pid,
                format!("found {}, expected AXIS2_PLACEMENT_2D", pi.first_name()),
            )
        })?;
        let o = self.reference(pid, ap.get(1), "location")?;
        let origin = self.curve_point(pid, o, Space::Parameter)?;
        let x = self.curve_direction(pid, ap.get(2), Vec3::X, Space::Parameter)?;
        let f = Frame {
            origin,
            x,
            y: Vec3::Z.cross(x),
            z: Vec3::Z,
        };
        let a = self.num(id, c.get(2), "radius")?;
        let b = match c.get(3) {
            Some(p) => self.num(id, Some(p), "semi_axis_2")?,
            None => a,
        };
        Ok((f, a, b))
    }

    /// The `TRIMMED_CURVE` `id` (attributes `p`: name, basis_curve, trim_1, trim_2,
    /// sense_agreement, master_representation) as the part of its basis it keeps (ISO 10303-42
    /// `trimmed_curve`): each trim is a `PARAMETER_VALUE` of the basis's parameter or a
    /// `CARTESIAN_POINT` on it (both given: the one `master_representation` names, the
    /// parameter when it names neither); with `sense_agreement` `.T.` the curve runs from
    /// trim 1 up to trim 2, with `.F.` from trim 1 down to trim 2, across the seam of a conic
    /// where it must (a conic's parameter is an angle, in the file's angle unit; equal trims
    /// on a conic keep the whole turn). `Err(why)` for a basis or trims not read.
    pub(super) fn kept(&self, id: u64, p: &[Param], space: Space) -> Result<Kept, String> {
        let bid = self
            .reference(id, p.get(1), "basis_curve")
            .map_err(|e| e.to_string())?;
        if self
            .map
            .get(&bid)
            .and_then(|b| b.part("TRIMMED_CURVE"))
            .is_some()
        {
            return Err(format!(
                "#{id}: a trimmed curve of a trimmed curve (#{bid}) is not read"
            ));
        }
        let curve = self
            .curve_in(id, bid, 1, space)
            .map_err(|e| format!("#{id}: {e}"))?;
        let conic = matches!(curve, Curve::Conic { .. });
        let master = match p.get(5) {
            Some(Param::Enum(m)) => m.as_str(),
            _ => "UNSPECIFIED",
        };
        let size = match &curve {
            Curve::Conic { a, b, .. } => a.max(*b),
            Curve::Spline(c) => {
                let (t0, t1) = c.domain();
                (c.point(t1) - c.point(t0)).length().max(
                    c.homogeneous()
                        .iter()
                        .map(|h| (h.truncate() / h.w).length())
                        .fold(0.0, f64::max),
                )
            }
            Curve::Polyline(pts) => pts.iter().map(|q| q.length()).fold(0.0, f64::max),
            Curve::Line { p, d } => p.length().max(d.length()),
        };
        let tol = match space {
            Space::Model => crate::io::on_surface_tolerance(size, self.accuracy),
            Space::Parameter => 1e-6 * size.max(1.0),
        };
        let trim = |k: usize| -> Result<f64, String> {
            let list: Vec<&Param> = match p.get(k) {
                Some(Param::List(l)) => l.iter().collect(),
                Some(other) => vec![other],
                None => Vec::new(),
            };
            let value = list.iter().find_map(|q| match q {
                Param::Typed(t, v) if t == "PARAMETER_VALUE" => {
                    self.num(id, v.first(), "parameter value").ok()
                }
                _ => None,
            });
            let point = list.iter().find_map(|q| match q {
                Param::Ref(r) => Some(*r),
                _ => None,
            });
            let by_point = |r: u64| -> Result<f64, String> {
                let q = self.curve_point(id, r, space).map_err(|e| e.to_string())?;
                let (t, off) = curve.param_of(q);
                if off.is_nan() || off > tol {
                    return Err(format!(
                        "#{id}: its trim point #{r} is {off:.3e} off its basis curve"
                    ));
                }
                Ok(t)
            };
            let scaled = |v: f64| if conic { v * self.angle } else { v };
            match (value, point) {
                (Some(v), Some(r)) if master == "CARTESIAN" => by_point(r).or(Ok(scaled(v))),
                (Some(v), _) => Ok(scaled(v)),
                (None, Some(r)) => by_point(r),
                (None, None) => Err(format!(
                    "#{id}: trim {} is neither a parameter value nor a point",
                    k - 1
                )),
            }
        };
        let (t1, t2) = (trim(2)?, trim(3)?);
        let sense = match p.get(4) {
            Some(Param::Enum(e)) if e == "F" => false,
            Some(Param::Enum(e)) if e == "T" => true,
            other => {
                return Err(format!(
                    "#{id}: sense_agreement is {}, expected .T. or .F.",
                    show(other)
                ))
            }
        };
        // Increasing: from the lower end of the run to its upper.
        let (lo, mut hi) = if sense { (t1, t2) } else { (t2, t1) };
        let tau = std::f64::consts::TAU;
        if conic {
            // Up from lo to hi, less than a turn; trims a whole number of turns apart (to
            // rounding: 360° in a file's degrees is not 2π exactly) keep the whole turn.
            let d = (hi - lo).rem_euclid(tau);
            hi = lo
                + if d <= 1e-9 * tau || tau - d <= 1e-9 * tau {
                    tau
                } else {
                    d
                };
        }
        if !(lo < hi && (hi - lo).is_finite()) {
            return Err(format!(
                "#{id}: its trims keep nothing of its basis (from {t1} to {t2}, {})",
                if sense { "forwards" } else { "backwards" }
            ));
        }
        if let Some((a, b)) = curve.range() {
            let slack = 1e-9 * (b - a).abs().max(1.0);
            if lo < a - slack || hi > b + slack {
                return Err(format!(
                    "#{id}: its trims {t1} and {t2} lie outside its basis's parameters [{a}, {b}]"
                ));
            }
        }
        Ok(Kept {
            curve,
            range: [lo, hi],
            against: !sense,
        })
    }

    /// A curve for the edge geometry `id`.
    pub(super) fn curve(&self, from: u64, id: u64, depth: usize) -> Built<Curve> {
        self.curve_in(from, id, depth, Space::Model)
    }

    /// A point of a curve in `space`: a model-space `CARTESIAN_POINT` in mm, or a
    /// parameter-space one's two coordinates as they are written (z = 0).
    fn curve_point(&self, from: u64, id: u64, space: Space) -> R<Vec3> {
        match space {
            Space::Model => self.point(from, id),
            Space::Parameter => self.pair(
                from,
                id,
                "CARTESIAN_POINT",
                "coordinates",
                "a CARTESIAN_POINT of two coordinates (a point in a surface's parameters)",
                ["u", "v"],
            ),
        }
    }

    /// The two numbers of instance `id`'s `entity` (its list `what`) as (x, y, 0): a point or
    /// direction in a surface's parameters; `expected` says what else was found.
    fn pair(
        &self,
        from: u64,
        id: u64,
        entity: &str,
        what: &str,
        expected: &str,
        names: [&str; 2],
    ) -> R<Vec3> {
        let inst = self.get(from, id)?;
        let c = inst
            .part(entity)
            .map(|p| self.list(id, p.get(1), what))
            .transpose()?
            .filter(|c| c.len() == 2)
            .ok_or_else(|| {
                self.bad(
                    id,
                    format!("found {}, expected {expected}", inst.first_name()),
                )
            })?;
        Ok(Vec3::new(
            self.num(id, c.first(), names[0])?,
            self.num(id, c.get(1), names[1])?,
            0.0,
        ))
    }

    /// A direction of a curve in `space` (`default` when `$`): three ratios, or two (z = 0).
    fn curve_direction(
        &self,
        from: u64,
        p: Option<&Param>,
        default: Vec3,
        space: Space,
    ) -> R<Vec3> {
        if space == Space::Model || matches!(p, Some(Param::Null) | None) {
            return self.direction(from, p, default);
        }
        let id = self.reference(from, p, "direction")?;
        let v = self.pair(
            from,
            id,
            "DIRECTION",
            "direction ratios",
            "a DIRECTION of two ratios",
            ["x", "y"],
        )?;
        if v.length() == 0.0 || !v.is_finite() {
            return Err(self.bad(id, "zero-length direction"));
        }
        Ok(v.normalize())
    }

    /// A curve for the geometry `id` in `space`: model space (mm), or a surface's parameters
    /// (the `(u, v)` of a `PCURVE`'s definitional representation as written, z = 0; conics on
    /// an `AXIS2_PLACEMENT_2D`).
    pub(super) fn curve_in(&self, from: u64, id: u64, depth: usize, space: Space) -> Built<Curve> {
        if depth > MAX_CURVE_DEPTH {
            return Err(TrimFailure::CurveNesting {
                curve: id,
                max: MAX_CURVE_DEPTH,
            });
        }
        let inst = self.get(from, id)?;
        for name in ["SURFACE_CURVE", "SEAM_CURVE", "INTERSECTION_CURVE"] {
            if let Some(p) = inst.part(name) {
                let c = self.reference(id, p.get(1), "curve_3d")?;
                return self.curve_in(id, c, depth + 1, space);
            }
        }
        if let Some(p) = inst.part("TRIMMED_CURVE") {
            // The edge's vertices bound it; its sense_agreement .F. runs it against the basis
            // curve (the way round a conic between the vertices).
            let c = self.reference(id, p.get(1), "basis_curve")?;
            let curve = self.curve_in(id, c, depth + 1, space)?;
            let against = matches!(p.get(4), Some(Param::Enum(e)) if e == "F");
            return Ok(if against { curve.reversed() } else { curve });
        }
        if let Some(p) = inst.part("LINE") {
            let origin = self.reference(id, p.get(1), "pnt")?;
            let origin = self.curve_point(id, origin, space)?;
            let vid = self.reference(id, p.get(2), "dir")?;
            let vi = self.get(id, vid)?;
            let vp = vi.part("VECTOR").ok_or_else(|| TrimFailure::NotVector {
                vector: vid,
                found: vi.first_name().to_string(),
            })?;
            let dir = self.curve_direction(vid, vp.get(1), Vec3::X, space)?;
            let unit = if space == Space::Model {
                self.length
            } else {
                1.0
            };
            let mag = self.num(vid, vp.get(2), "magnitude")? * unit;
            if !(mag.abs() > 0.0 && mag.is_finite()) {
                return Err(TrimFailure::ZeroLine { vector: vid });
            }
            return Ok(Curve::Line {
                p: origin,
                d: dir * mag.abs(),
            });
        }
        if let Some(c) = inst.part("CIRCLE").or_else(|| inst.part("ELLIPSE")) {
            let (f, a, b) = match space {
                Space::Model => self.conic(id, c)?,
                Space::Parameter => self.conic_2d(id, c)?,
            };
            if !(a > 0.0 && b > 0.0 && a.is_finite() && b.is_finite()) {
                return Err(TrimFailure::ConicRadii { curve: id });
            }
            return Ok(Curve::Conic { f, a, b });
        }
        if let Some(p) = inst.part("POLYLINE") {
            let pts = self.list(id, p.get(1), "points")?;
            if pts.len() < 2 || pts.len() > MAX_CURVE_POINTS {
                return Err(TrimFailure::PolylinePoints {
                    curve: id,
                    max: MAX_CURVE_POINTS,
                });
            }
            let pts = pts
                .iter()
                .map(|q| {
                    let r = self.reference(id, Some(q), "point")?;
                    self.curve_point(id, r, space)
                })
                .collect::<R<Vec<Vec3>>>()?;
            return Ok(Curve::Polyline(pts));
        }
        if let Some(k) = inst.part("B_SPLINE_CURVE_WITH_KNOTS") {
            let (head, knots): (&[Param], &[Param]) = match inst.part("B_SPLINE_CURVE") {
                Some(b) => (b, k),
                None if k.len() >= 9 => (&k[1..6], &k[6..]),
                None => {
                    return Err(TrimFailure::SplineAttributes {
                        curve: id,
                        count: k.len(),
                    })
                }
            };
            let degree = self.num(id, head.first(), "degree")?;
            if !(degree >= 1.0
                && degree <= NurbsSurface::MAX_DEGREE as f64
                && degree.fract() == 0.0)
            {
                return Err(TrimFailure::SplineDegree {
                    curve: id,
                    degree,
                    max: NurbsSurface::MAX_DEGREE,
                });
            }
            let degree = degree as usize;
            let cps = self.list(id, head.get(1), "control_points_list")?;
            if cps.len() < degree + 1 || cps.len() > MAX_CURVE_POINTS {
                return Err(TrimFailure::SplinePoints {
                    curve: id,
                    points: cps.len(),
                    degree,
                });
            }
            let pts = cps
                .iter()
                .map(|q| {
                    let r = self.reference(id, Some(q), "control point")?;
                    self.curve_point(id, r, space)
                })
                .collect::<R<Vec<Vec3>>>()?;
            let kv = self.knots(
                id,
                knots.first(),
                knots.get(1),
                "curve",
                pts.len() + degree + 1,
            )?;
            if kv.iter().any(|k| !k.is_finite())
                || kv.windows(2).any(|w| w[1] < w[0])
                || kv[pts.len()] <= kv[degree]
            {
                return Err(TrimFailure::SplineKnots { curve: id });
            }
            let weights = match inst.part("RATIONAL_B_SPLINE_CURVE") {
                Some(w) => {
                    let ws = self.list(id, w.first(), "weights_data")?;
                    if ws.len() != pts.len() {
                        return Err(TrimFailure::SplineWeightCount {
                            curve: id,
                            weights: ws.len(),
                            points: pts.len(),
                        });
                    }
                    ws.iter()
                        .map(|x| self.num(id, Some(x), "weight"))
                        .collect::<R<Vec<f64>>>()?
                }
                None => vec![1.0; pts.len()],
            };
            if weights.iter().any(|w| !(*w > 0.0 && w.is_finite())) {
                return Err(TrimFailure::SplineWeights { curve: id });
            }
            // Checked above with the reader's own messages; the curve checks the same.
            return BSplineCurve::new(degree, kv, &pts, &weights)
                .map(Curve::Spline)
                .map_err(|reason| TrimFailure::SplineCurve { curve: id, reason });
        }
        Err(TrimFailure::CurveKind {
            curve: id,
            kind: inst.first_name().to_string(),
        })
    }
}
