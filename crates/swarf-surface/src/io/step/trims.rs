//! Face bounds as trims: edge loops sampled on the face's surface, mapped to its parameters,
//! through poles and seams, and assembled into the patch's [`Trim`] and parameter box.

use crate::io::on_surface_tolerance;
use std::collections::HashMap;

use swarf_geom::math::Vec3;
use swarf_geom::Frame;

use super::curves::{Curve, MAX_CURVE_POINTS};
use super::entities::{Model, R};
use super::lex::Param;
use crate::io::{TrimFailure, Uv, MAX_GRID_SEARCHES, MAX_HALVINGS, MAX_TRIM_POINTS};
use crate::surface::invert::Inverter;
use crate::surface::{ParamBox, ParametricSurface, Surface};
use crate::trim::{fitted_to_loop, Trim};

/// Most points in all the trims of a file.
pub(super) const MAX_FILE_TRIM_POINTS: usize = 2_000_000;

/// A trim (or a part of one), or why it cannot be honoured.
pub(super) type Built<T> = Result<T, TrimFailure>;

/// A trim loop point: its parameters, and whether its u (the angle around the axis) is free
/// (a pole of a sphere, a cone's apex).
#[derive(Clone, Copy, Debug)]
pub(super) struct Sample {
    pub(super) uv: Uv,
    pub(super) free: bool,
}

/// Maps model-space points of a face's edges to its surface's parameters.
pub(super) struct Mapper<'s> {
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

impl<'s> Mapper<'s> {
    /// A mapper onto `surface` for a file declaring the distance accuracy `accuracy` (mm, 0
    /// when none), allowed `points` points: chords within min(1e-3 mm, 1e-5 of the surface's
    /// size), points within [`on_surface_tolerance`] of it.
    pub(super) fn new(surface: &'s Surface, accuracy: f64, points: usize) -> Self {
        let tau = std::f64::consts::TAU;
        let period = match surface {
            Surface::Cylinder(_) | Surface::Cone(_) | Surface::Sphere(_) => [Some(tau), None],
            Surface::Torus(_) => [Some(tau), Some(tau)],
            _ => [None, None],
        };
        let bb = surface.bounding_box();
        let size = (bb.max - bb.min).length();
        let size = if size.is_finite() { size } else { 1e3 };
        let tol_on = on_surface_tolerance(size, accuracy);
        Mapper {
            surface,
            period,
            tol: (1e-5 * size).clamp(1e-9, 1e-3),
            tol_on,
            points_left: points.min(MAX_TRIM_POINTS),
            inverter: Inverter::new(surface, tol_on, MAX_GRID_SEARCHES),
        }
    }

    /// Points it may still map.
    pub(super) fn points_left(&self) -> usize {
        self.points_left
    }

    /// Period of u and v (the angles of elementary surfaces).
    pub(super) fn period(&self) -> [Option<f64>; 2] {
        self.period
    }

    /// Samples a curve given in the surface's parameters, `f(t)`, at the parameters `ts` and
    /// between them to the chord tolerance (as [`Mapper::sample`] does a model-space curve: the
    /// chord between neighbouring samples, on the surface, stays within the tolerance of the
    /// curve's own point there).
    pub(super) fn sample_parameters(
        &mut self,
        f: &dyn Fn(f64) -> Uv,
        ts: &[f64],
    ) -> Built<Vec<Sample>> {
        fn refine(
            m: &mut Mapper,
            f: &dyn Fn(f64) -> Uv,
            (ta, a): (f64, Uv),
            (tb, b): (f64, Uv),
            depth: u32,
            out: &mut Vec<Sample>,
        ) -> Built<()> {
            m.take_point()?;
            let tm = 0.5 * (ta + tb);
            let mid = f(tm);
            let chord = m.eval([0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]);
            let dev = (chord - m.eval(mid)).length();
            if depth < MAX_HALVINGS && (dev.is_nan() || dev > m.tol) {
                refine(m, f, (ta, a), (tm, mid), depth + 1, out)?;
                refine(m, f, (tm, mid), (tb, b), depth + 1, out)?;
            } else {
                out.push(Sample { uv: b, free: false });
            }
            Ok(())
        }
        let mut out = Vec::new();
        let mut prev: Option<(f64, Uv)> = None;
        for &t in ts {
            let uv = f(t);
            if !(uv[0].is_finite() && uv[1].is_finite()) {
                return Err(TrimFailure::NonFiniteParameters);
            }
            match prev {
                None => {
                    self.take_point()?;
                    out.push(Sample { uv, free: false });
                }
                Some(p) => refine(self, f, p, (t, uv), 0, &mut out)?,
            }
            prev = Some((t, uv));
        }
        Ok(out)
    }

    /// Counts one more point against the budget.
    fn take_point(&mut self) -> Built<()> {
        if self.points_left == 0 {
            return Err(TrimFailure::TooManyPoints {
                trim: MAX_TRIM_POINTS,
                file: MAX_FILE_TRIM_POINTS,
            });
        }
        self.points_left -= 1;
        Ok(())
    }

    /// S(u, v), without clamping the angles into the parameter box.
    pub(super) fn eval(&self, [u, v]: Uv) -> Vec3 {
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
    pub(super) fn map(&mut self, p: Vec3, near: Option<Uv>) -> Built<Sample> {
        if self.points_left == 0 {
            return Err(TrimFailure::TooManyPoints {
                trim: MAX_TRIM_POINTS,
                file: MAX_FILE_TRIM_POINTS,
            });
        }
        self.points_left -= 1;
        let inv = self.inverter.invert(p, near)?;
        let (mut uv, free, off) = (inv.uv, inv.pole, inv.dist);
        if off.is_nan() || off > self.tol_on {
            return Err(TrimFailure::OffSurface {
                point: p,
                distance: off,
            });
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
            return Err(TrimFailure::NonFiniteParameters);
        }
        Ok(Sample { uv, free })
    }

    /// Samples `curve` over the runs `(a, b)` (in that direction) to the chord tolerance: the
    /// chord between neighbouring samples, in parameters, stays within `tol` of the curve's own
    /// parameters on the surface. Each sample's angles are unwrapped to lie near the previous
    /// one's.
    pub(super) fn sample(
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

    pub(super) fn refine(
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
pub(super) struct FaceTrim {
    pub(super) trim: Trim,
    pub(super) domain: ParamBox,
}

/// One bound of a face, sampled.
pub(super) struct Bound {
    /// `FACE_OUTER_BOUND`.
    outer: bool,
    /// Its orientation, times the face's `same_sense`.
    sense: bool,
    samples: Vec<Sample>,
}

impl Bound {
    /// A bound of its samples: the outer one or not, the face on its left (`sense`) or its
    /// right; on a surface of a periodic u only (`period`), run along the box's edge through
    /// a pole ([`through_poles`]).
    pub(super) fn new(
        outer: bool,
        sense: bool,
        samples: Vec<Sample>,
        period: [Option<f64>; 2],
    ) -> Bound {
        let samples = match period {
            [Some(t), None] => through_poles(samples, sense, t),
            _ => samples,
        };
        Bound {
            outer,
            sense,
            samples,
        }
    }
}

impl Model<'_> {
    /// The largest length uncertainty the file declares (`UNCERTAINTY_MEASURE_WITH_UNIT` of a
    /// `LENGTH_MEASURE`, in its unit), mm; 0 when none reads.
    pub(super) fn declared_accuracy(&self) -> f64 {
        let mut best: f64 = 0.0;
        for (&id, inst) in &self.map {
            let Some(p) = inst.part("UNCERTAINTY_MEASURE_WITH_UNIT") else {
                continue;
            };
            let length = matches!(p.first(), Some(Param::Typed(t, _)) if t == "LENGTH_MEASURE");
            let (Ok(v), Ok(u)) = (
                self.num(id, p.first(), "uncertainty"),
                self.reference(id, p.get(1), "unit"),
            ) else {
                continue;
            };
            if let (true, Ok((f, _))) = (length, self.unit_factor(id, u, 0)) {
                if (v * f).is_finite() && v * f > 0.0 {
                    best = best.max(v * f);
                }
            }
        }
        best
    }

    /// The trim of face `fid` on `surface` from its bounds, `None` when they hold no loop (only
    /// vertex loops), `Err(why)` when it cannot be honoured.
    pub(super) fn face_trim(
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
        let mut m = Mapper::new(surface, self.accuracy, *budget);
        let start_budget = m.points_left;
        let result = self.face_loops(fid, bounds, same_sense, &mut m);
        *budget -= start_budget - m.points_left;
        let loops = result?;
        if loops.is_empty() {
            return Ok(None);
        }
        assemble(surface, m.period, loops, false).map(Some)
    }

    /// The sampled loops of a face's bounds (vertex loops left out).
    pub(super) fn face_loops(
        &self,
        fid: u64,
        bounds: &[Param],
        same_sense: bool,
        m: &mut Mapper,
    ) -> Built<Vec<Bound>> {
        let mut out = Vec::new();
        for b in bounds {
            let bid = self.reference(fid, Some(b), "bound")?;
            let bi = self.get(fid, bid)?;
            let (outer, bp) = match (bi.part("FACE_OUTER_BOUND"), bi.part("FACE_BOUND")) {
                (Some(p), _) => (true, p),
                (None, Some(p)) => (false, p),
                _ => {
                    return Err(TrimFailure::BoundKind {
                        bound: bid,
                        kind: bi.first_name().to_string(),
                    })
                }
            };
            let lid = self.reference(bid, bp.get(1), "bound")?;
            let orientation = self.logical(bid, bp.get(2), "orientation")?;
            let li = self.get(bid, lid)?;
            let samples = if li.part("VERTEX_LOOP").is_some() {
                continue;
            } else if let Some(p) = li.part("POLY_LOOP") {
                let pts = self.list(lid, p.get(1), "polygon")?;
                if pts.len() > MAX_CURVE_POINTS {
                    return Err(TrimFailure::PolyLoopTooLong { lp: lid });
                }
                let mut pts = pts
                    .iter()
                    .map(|q| {
                        let r = self.reference(lid, Some(q), "point")?;
                        self.point(lid, r)
                    })
                    .collect::<R<Vec<Vec3>>>()?;
                if let Some(&first) = pts.first() {
                    pts.push(first);
                }
                if pts.len() < 4 {
                    return Err(TrimFailure::PolyLoopTooShort { lp: lid });
                }
                let c = Curve::Polyline(pts);
                let (a, b) = c.range().unwrap_or((0.0, 1.0));
                m.sample(&c, &[(a, b)], None)
                    .map_err(|why| TrimFailure::InPolyLoop {
                        lp: lid,
                        reason: Box::new(why),
                    })?
            } else if let Some(p) = li.part("EDGE_LOOP") {
                let edges = self.list(lid, p.get(1), "edge_list")?;
                self.edge_loop(lid, edges, m)?
            } else {
                return Err(TrimFailure::LoopKind {
                    lp: lid,
                    kind: li.first_name().to_string(),
                });
            };
            let sense = orientation == same_sense;
            out.push(Bound::new(outer, sense, samples, m.period));
        }
        Ok(out)
    }

    /// An EDGE_LOOP's samples in order, angles continuous; a seam edge met a second time on the
    /// same parameters (through a pole) is moved a period over when that closes the loop.
    pub(super) fn edge_loop(
        &self,
        lid: u64,
        edges: &[Param],
        m: &mut Mapper,
    ) -> Built<Vec<Sample>> {
        let mut out: Vec<Sample> = Vec::new();
        let mut first_pass: HashMap<u64, (Sample, Sample)> = HashMap::new();
        let mut split: Option<usize> = None;
        let mut last_point: Option<Vec3> = None;
        let join = m.tol_on * 10.0;
        for e in edges {
            let oid = self.reference(lid, Some(e), "oriented edge")?;
            let oi = self.get(lid, oid)?;
            let op = oi
                .part("ORIENTED_EDGE")
                .ok_or_else(|| TrimFailure::EdgeKind {
                    edge: oid,
                    found: oi.first_name().to_string(),
                    expected: "ORIENTED_EDGE",
                })?;
            let eid = self.reference(oid, op.get(3), "edge_element")?;
            let orientation = self.logical(oid, op.get(4), "orientation")?;
            let ei = self.get(oid, eid)?;
            let ep = ei.part("EDGE_CURVE").ok_or_else(|| TrimFailure::EdgeKind {
                edge: eid,
                found: ei.first_name().to_string(),
                expected: "EDGE_CURVE",
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
            let (vs, ps) = vertex(ep.get(1))?;
            let (ve, pe) = vertex(ep.get(2))?;
            let gid = self.reference(eid, ep.get(3), "edge_geometry")?;
            let same = self.logical(eid, ep.get(4), "same_sense")?;
            let curve = self.curve(eid, gid, 0)?;
            let (ts, ds) = curve.param_of(ps);
            let (te, de) = curve.param_of(pe);
            if ds.is_nan() || de.is_nan() || ds.max(de) > join {
                return Err(TrimFailure::VertexOffCurve {
                    edge: eid,
                    distance: ds.max(de),
                });
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
                        return Err(TrimFailure::OpenCurveOnOneVertex { edge: eid });
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
                .map_err(|why| TrimFailure::InEdge {
                    edge: eid,
                    reason: Box::new(why),
                })?;
            // From the edge's start to its end, then as the loop uses it.
            if !orientation {
                s.reverse();
            }
            let (from, to) = if orientation { (ps, pe) } else { (pe, ps) };
            if let Some(lp) = last_point {
                if (lp - from).length() > join {
                    return Err(TrimFailure::EdgesDoNotJoin { edge: eid });
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
pub(super) fn through_poles(s: Vec<Sample>, sense: bool, t: f64) -> Vec<Sample> {
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
/// loop the face's outer bound (else the loop with the largest box; none when `holes_only`).
/// The parameter box returned is cut down to the outer loop's (on every parameter, the seam
/// handled: the box's angle range starts where the loop lies), so that a grid over the box
/// covers the face, not its whole surface.
pub(super) fn assemble(
    surface: &Surface,
    period: [Option<f64>; 2],
    bounds: Vec<Bound>,
    holes_only: bool,
) -> Built<FaceTrim> {
    let mut dom = surface.domain();
    let span = [dom.u[1] - dom.u[0], dom.v[1] - dom.v[0]];
    let close = [1e-6 * span[0].max(1e-300), 1e-6 * span[1].max(1e-300)];
    // Closed loops, and loops winding around angle d (their direction times the bound's sense).
    let mut closed: Vec<(bool, Vec<Uv>)> = Vec::new();
    let mut winding: [Vec<(bool, Vec<Uv>)>; 2] = [Vec::new(), Vec::new()];
    for (k, b) in bounds.into_iter().enumerate() {
        let s = &b.samples;
        let (Some(first), Some(last)) = (s.first(), s.last()) else {
            return Err(TrimFailure::EmptyLoop { index: k });
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
            return Err(TrimFailure::LoopNotClosed { index: k });
        }
        let pts: Vec<Uv> = s.iter().map(|q| q.uv).collect();
        match turns {
            [0.0, 0.0] => closed.push((b.outer, pts)),
            [t, 0.0] if t.abs() == 1.0 => winding[0].push(((t > 0.0) == b.sense, pts)),
            [0.0, t] if t.abs() == 1.0 => winding[1].push(((t > 0.0) == b.sense, pts)),
            _ => return Err(TrimFailure::LoopWindsTwice { index: k }),
        }
    }
    let wound = winding.iter().map(Vec::len).sum::<usize>();
    if wound > 0
        && (winding[0].len() > 2
            || winding[1].len() > 2
            || (!winding[0].is_empty() && !winding[1].is_empty()))
    {
        return Err(TrimFailure::WindingNotRead);
    }
    // The outer closed loop (when no loop winds).
    let outer_at = if wound > 0 || holes_only {
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
                _ => return Err(TrimFailure::BandEdgesAlike),
            },
            _ => return Err(TrimFailure::LoopAroundBothAngles),
        };
        let mean = |l: &[Uv]| l.iter().map(|p| p[e]).sum::<f64>() / l.len().max(1) as f64;
        let (ma, mb) = (mean(&w[a].1), mean(&w[b].1));
        let k = (((ma - mb) / te).floor() + 1.0) * te;
        w[b].1.iter_mut().for_each(|p| p[e] += k);
        let lo = range(&w[a].1, e).0;
        let hi = range(&w[b].1, e).1;
        if hi - lo > te + close[e] || (hi - lo).is_nan() {
            return Err(TrimFailure::BandTooWide);
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
    if let Some(o) = &outer {
        dom = fitted_to_loop(dom, o);
    }
    if !(dom.u[0] < dom.u[1] && dom.v[0] < dom.v[1]) {
        return Err(TrimFailure::NoArea);
    }
    let trim = Trim::new(&dom, outer, holes)?;
    Ok(FaceTrim { trim, domain: dom })
}

/// `p` with coordinate `d` set to `x`.
pub(super) fn with(mut p: Uv, d: usize, x: f64) -> Uv {
    p[d] = x;
    p
}

/// A loop winding once around angle `d` (period `t`, last point = first ± t) as a polyline from
/// `d = s` to `d = s + t`: cut where it crosses `s` (mod t), going up.
pub(super) fn unroll(l: &[Uv], d: usize, s: f64, t: f64) -> Vec<Uv> {
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
