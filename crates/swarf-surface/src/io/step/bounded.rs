//! `CURVE_BOUNDED_SURFACE` (ISO 10303-42): a basis surface and closed curves on it that bound
//! the part of it the surface is, read as the basis's patch with the boundaries as its trim.
//!
//! A boundary is a `BOUNDARY_CURVE` or `OUTER_BOUNDARY_CURVE` (`(name, segments,
//! self_intersect)`), its segments `COMPOSITE_CURVE_SEGMENT`s (`(transition, same_sense,
//! parent_curve)`) run along or against their parent curve. A parent curve is either a `PCURVE`
//! on the basis — its curve in the basis's parameters, given by a `DEFINITIONAL_REPRESENTATION`
//! (a `POLYLINE`, `LINE`, `CIRCLE` or `ELLIPSE` on an `AXIS2_PLACEMENT_2D`, B-spline, or a
//! `TRIMMED_CURVE` of one), the parameters scaled by the file's units (lengths to mm, angles to
//! radians) on the surfaces whose parameters the reader keeps as the file's (planes, cylinders,
//! cones, spheres, tori, B-splines, rectangular trims of them) — or a curve in model space (a
//! `SURFACE_CURVE` or any edge curve the face bounds read, bounded: a B-spline, a polyline, a
//! trimmed curve, a whole circle or ellipse), mapped onto the basis as a face's edges are. The
//! loops are assembled as a face's bounds are: the `OUTER_BOUNDARY_CURVE` is the outer loop,
//! else, when `implicit_outer` is `.F.`, the loop with the largest parameter box; with
//! `implicit_outer` `.T.` the basis's own boundary is the outer one and every loop a hole.

use super::curves::{Curve, Space, MAX_CURVE_DEPTH};
use super::entities::{kind_name, supported, Model, R};
use super::lex::Param;
use super::swept::Sensed;
use super::trims::{assemble, Bound, Built, FaceTrim, Mapper, Sample};
use crate::compound::ReadNote;
use crate::io::{TrimFailure, Uv};

/// A curve-bounded surface read: its basis (with its name and sense) and its boundaries as a
/// trim (`Ok(None)`: no boundary; `Err`: not honoured, the whole basis used).
pub(super) type BoundedRead = (Sensed, Built<Option<FaceTrim>>);

impl Model<'_> {
    /// The `CURVE_BOUNDED_SURFACE` `id` with attributes `p` (name, basis_surface, boundaries,
    /// implicit_outer). `Ok(Err(why))` when its basis is of a kind not read.
    pub(super) fn bounded(
        &self,
        id: u64,
        p: &[Param],
        index: usize,
        notes: &mut Vec<ReadNote>,
        budget: &mut usize,
    ) -> R<Result<BoundedRead, String>> {
        let basis = self.reference(id, p.get(1), "basis_surface")?;
        // (A basis that is no instance is this surface's error, at its line.)
        self.get(id, basis)?;
        let implicit_outer = self.logical(id, p.get(3), "implicit_outer")?;
        let boundaries = self.list(id, p.get(2), "boundaries")?;
        let mut own = Vec::new();
        let (surface, name, reversed) = match self.any_surface(basis, None, index, &mut own)? {
            Ok(s) => s,
            Err(why) => return Ok(Err(format!("its basis surface #{basis}: {why}"))),
        };
        let mut m = Mapper::new(&surface, self.accuracy, *budget);
        let start = m.points_left();
        let trim = self.boundaries(id, basis, boundaries, &mut m);
        *budget -= start - m.points_left();
        let period = m.period();
        let trim = trim.and_then(|bounds| {
            if bounds.is_empty() {
                return Ok(None);
            }
            assemble(&surface, period, bounds, implicit_outer).map(Some)
        });
        // An outer boundary gives the box: the basis's default one is not the surface's then.
        let outer = matches!(&trim, Ok(Some(t)) if t.trim.outer().is_some());
        notes.extend(
            own.into_iter()
                .filter(|n| !outer || !matches!(n, ReadNote::DefaultParameterBox { .. })),
        );
        let name = Self::name(p.first()).or(name);
        Ok(Ok(((surface, name, reversed), trim)))
    }

    /// The sampled loops of the boundaries of curve-bounded surface `id` on its basis `basis`.
    fn boundaries(
        &self,
        id: u64,
        basis: u64,
        boundaries: &[Param],
        m: &mut Mapper,
    ) -> Built<Vec<Bound>> {
        let scale = self.parameter_scale(basis);
        let mut out = Vec::new();
        for b in boundaries {
            let bid = self.reference(id, Some(b), "boundary")?;
            let bi = self.get(id, bid)?;
            let outer = bi.part("OUTER_BOUNDARY_CURVE").is_some();
            let Some(bp) = ["OUTER_BOUNDARY_CURVE", "BOUNDARY_CURVE"]
                .iter()
                .find_map(|n| bi.part(n))
            else {
                return Err(TrimFailure::BoundaryKind {
                    boundary: bid,
                    kind: bi.first_name().to_string(),
                });
            };
            let samples = self
                .boundary_loop(bid, basis, bp, scale.as_ref(), m)
                .map_err(|why| TrimFailure::InBoundary {
                    boundary: bid,
                    reason: Box::new(why),
                })?;
            // The surface on the boundary's left, as on a face's bound run its way.
            out.push(Bound::new(outer, true, samples, m.period()));
        }
        Ok(out)
    }

    /// One boundary curve's segments, sampled in order, their angles continuous.
    fn boundary_loop(
        &self,
        bid: u64,
        basis: u64,
        bp: &[Param],
        scale: Result<&[f64; 2], &String>,
        m: &mut Mapper,
    ) -> Built<Vec<Sample>> {
        let segments = self.list(bid, bp.get(1), "segments")?;
        let mut out: Vec<Sample> = Vec::new();
        for sref in segments {
            let sid = self.reference(bid, Some(sref), "segment")?;
            let si = self.get(bid, sid)?;
            let Some(sp) = [
                "COMPOSITE_CURVE_SEGMENT",
                "REPARAMETRISED_COMPOSITE_CURVE_SEGMENT",
            ]
            .iter()
            .find_map(|n| si.part(n)) else {
                return Err(TrimFailure::SegmentKind {
                    segment: sid,
                    kind: si.first_name().to_string(),
                });
            };
            let same = self.logical(sid, sp.get(1), "same_sense")?;
            let parent = self.reference(sid, sp.get(2), "parent_curve")?;
            let near = out.last().map(|q| q.uv);
            let mut s = self.segment(sid, basis, parent, scale, m, near)?;
            if !same {
                s.reverse();
            }
            // Angles continuous with the loop so far.
            if let (Some(prev), Some(first)) = (out.last().map(|q| q.uv), s.first().map(|q| q.uv)) {
                for d in 0..2 {
                    if let Some(t) = m.period()[d] {
                        let k = ((prev[d] - first[d]) / t).round() * t;
                        if k != 0.0 {
                            s.iter_mut().for_each(|q| q.uv[d] += k);
                        }
                    }
                }
            }
            out.extend(s);
        }
        Ok(out)
    }

    /// A segment's parent curve `parent`, sampled from its start to its end in the basis's
    /// parameters: a pcurve on `basis` in its own parameters (scaled by `scale`), any other
    /// curve in model space mapped onto the basis.
    fn segment(
        &self,
        from: u64,
        basis: u64,
        parent: u64,
        scale: Result<&[f64; 2], &String>,
        m: &mut Mapper,
        near: Option<Uv>,
    ) -> Built<Vec<Sample>> {
        let pi = self.get(from, parent)?;
        if let Some(pp) = pi.part("PCURVE") {
            let on = self.reference(parent, pp.get(1), "basis_surface")?;
            if on != basis {
                return Err(TrimFailure::PcurveElsewhere {
                    pcurve: parent,
                    surface: on,
                    basis,
                });
            }
            let [fu, fv] = *scale.map_err(|kind| TrimFailure::PcurveParameters {
                pcurve: parent,
                kind: kind.clone(),
            })?;
            let dr = self.reference(parent, pp.get(2), "reference_to_curve")?;
            let di = self.get(parent, dr)?;
            let Some(dp) = di.part("DEFINITIONAL_REPRESENTATION") else {
                return Err(TrimFailure::PcurveRepresentation {
                    pcurve: parent,
                    kind: di.first_name().to_string(),
                });
            };
            let items = self.list(dr, dp.get(1), "items")?;
            let cid = self.reference(dr, items.first(), "curve")?;
            let (curve, (a, b)) = self.bounded_curve(dr, cid, Space::Parameter, 0)?;
            let f = |t: f64| {
                let q = curve.point(t);
                [q.x * fu, q.y * fv]
            };
            return m.sample_parameters(&f, &curve.steps(a, b));
        }
        let (curve, (a, b)) = self.bounded_curve(from, parent, Space::Model, 0)?;
        m.sample(&curve, &[(a, b)], near)
    }

    /// The curve `id` in `space` and the run of its parameter it bounds, from start to end: a
    /// trimmed curve's kept part (backwards when it runs against its basis), a bounded
    /// curve's own range, a conic's whole turn; a surface curve's 3-D curve's.
    fn bounded_curve(
        &self,
        from: u64,
        id: u64,
        space: Space,
        depth: usize,
    ) -> Built<(Curve, (f64, f64))> {
        let inst = self.get(from, id)?;
        if depth <= MAX_CURVE_DEPTH {
            for name in ["SURFACE_CURVE", "SEAM_CURVE", "INTERSECTION_CURVE"] {
                if let Some(p) = inst.part(name) {
                    let c = self.reference(id, p.get(1), "curve_3d")?;
                    return self.bounded_curve(id, c, space, depth + 1);
                }
            }
        }
        if let Some(p) = inst.part("TRIMMED_CURVE") {
            let k = self
                .kept(id, p, space)
                .map_err(|why| TrimFailure::TrimmedCurve { why })?;
            let [lo, hi] = k.range;
            return Ok((k.curve, if k.against { (hi, lo) } else { (lo, hi) }));
        }
        let curve = self.curve_in(from, id, depth, space)?;
        let run = match (&curve, curve.range()) {
            (_, Some(r)) => r,
            (Curve::Conic { .. }, None) => (0.0, std::f64::consts::TAU),
            _ => return Err(TrimFailure::UnboundedLine { curve: id }),
        };
        Ok((curve, run))
    }

    /// What a `PCURVE`'s coordinates on surface `basis` are multiplied by to give the reader's
    /// parameters (mm and radians); `Err(kind)` for a basis whose parameters the reader does
    /// not keep as the file's (swept and offset surfaces).
    fn parameter_scale(&self, basis: u64) -> Result<[f64; 2], String> {
        let Some(b) = self.map.get(&basis) else {
            return Err(format!("#{basis}, which is not defined"));
        };
        if let Some(Param::Ref(inner)) =
            b.part("RECTANGULAR_TRIMMED_SURFACE").and_then(|p| p.get(1))
        {
            return self.parameter_scale(*inner);
        }
        if supported(b) || b.part("DEGENERATE_TOROIDAL_SURFACE").is_some() {
            let [(fu, _), (fv, _)] = self.parameter_units(b);
            Ok([fu, fv])
        } else {
            Err(kind_name(b))
        }
    }
}
