//! Swept surfaces written exactly as NURBS: a curve (a rational B-spline; lines and conic arcs
//! written as such) revolved about an axis, extruded along a vector, or ruled to a second curve.
//! The STEP (`SURFACE_OF_REVOLUTION`, `SURFACE_OF_LINEAR_EXTRUSION`) and IGES (120, 122, 118)
//! readers build their patches here.
//!
//! * A **revolution** has u the angle (rational quadratic arcs of at most a quarter turn, their
//!   knots at the angles, so a knot's point is the curve turned by exactly that angle), v the
//!   curve's parameter: `S(u, v) = C + R_z(u)(λ(v) − C)`, turned the right-hand way about `z`.
//! * An **extrusion** has u the curve's parameter and v the length along the vector in units of
//!   it: `S(u, v) = λ(u) + v·V`.
//! * A **ruled** surface joins the two curves' points of equal (normalised) parameter by
//!   straight lines, v from the first curve (0) to the second (1); its control net is the two
//!   curves' (made of one degree and one knot vector), so each ruling is a straight segment.

use glam::DVec4;
use swarf_geom::math::Vec3;
use swarf_geom::Frame;

use crate::curve::BSplineCurve;
use crate::surface::{NurbsError, NurbsSurface};

/// The segment `p + t·d`, `t ∈ [t0, t1]`, as a degree-1 B-spline with the same parameter.
pub(crate) fn line(p: Vec3, d: Vec3, t0: f64, t1: f64) -> Option<BSplineCurve> {
    BSplineCurve::new(
        1,
        vec![t0, t0, t1, t1],
        &[p + t0 * d, p + t1 * d],
        &[1.0, 1.0],
    )
    .ok()
}

/// Quarter-turn (at most) pieces of `[t0, t1]`: their count and angle.
fn pieces(t0: f64, t1: f64) -> (usize, f64) {
    let n = ((t1 - t0) / std::f64::consts::FRAC_PI_2 - 1e-9)
        .ceil()
        .clamp(1.0, 4096.0) as usize;
    (n, (t1 - t0) / n as f64)
}

/// Knots of `n` rational quadratic pieces of width `step` from `t0` (each inner knot twice).
fn arc_knots(t0: f64, t1: f64, n: usize, step: f64) -> Vec<f64> {
    let mut k = vec![t0; 3];
    for i in 1..n {
        let t = t0 + step * i as f64;
        k.extend([t, t]);
    }
    k.extend([t1; 3]);
    k
}

/// The conic `origin + a·cos t·x + b·sin t·y`, `t ∈ [t0, t1]` (`t0 < t1`), exactly, as rational
/// quadratic pieces of at most a quarter turn with their knots at the angles (the point at a
/// knot is the conic's at that angle; between knots the parameter is not the angle).
pub(crate) fn conic(f: &Frame, a: f64, b: f64, t0: f64, t1: f64) -> Option<BSplineCurve> {
    if !(t1 > t0 && (t1 - t0).is_finite()) {
        return None;
    }
    let (n, step) = pieces(t0, t1);
    let half = 0.5 * step;
    let at = |t: f64, s: f64| f.origin + s * (a * t.cos() * f.x + b * t.sin() * f.y);
    let mut pts = vec![at(t0, 1.0)];
    let mut ws = vec![1.0];
    for i in 0..n {
        let t = t0 + step * i as f64;
        pts.push(at(t + half, 1.0 / half.cos()));
        ws.push(half.cos());
        pts.push(at(if i + 1 == n { t1 } else { t + step }, 1.0));
        ws.push(1.0);
    }
    BSplineCurve::new(2, arc_knots(t0, t1, n, step), &pts, &ws).ok()
}

fn split(h: DVec4) -> (Vec3, f64) {
    (Vec3::new(h.x / h.w, h.y / h.w, h.z / h.w), h.w)
}

/// The curve `c` turned about the axis through `o` along the unit `z` from angle `a0` to `a1`
/// (`a0 < a1`, radians, right-hand about `z`).
pub(crate) fn revolve(
    c: &BSplineCurve,
    o: Vec3,
    z: Vec3,
    a0: f64,
    a1: f64,
) -> Result<NurbsSurface, NurbsError> {
    let (n, step) = pieces(a0, a1);
    let half = 0.5 * step;
    let mut pts = vec![Vec::new(); 2 * n + 1];
    let mut ws = vec![Vec::new(); 2 * n + 1];
    for &h in c.homogeneous() {
        let (p, w) = split(h);
        let q = p - o;
        let axial = o + q.dot(z) * z;
        let perp = q - q.dot(z) * z;
        let perp2 = z.cross(perp);
        let turned = |t: f64, s: f64| axial + s * (t.cos() * perp + t.sin() * perp2);
        for i in 0..=2 * n {
            let k = i / 2;
            let (t, s, wi) = if i % 2 == 0 {
                let t = if k == n { a1 } else { a0 + step * k as f64 };
                (t, 1.0, w)
            } else {
                let t = a0 + step * k as f64 + half;
                (t, 1.0 / half.cos(), w * half.cos())
            };
            pts[i].push(turned(t, s));
            ws[i].push(wi);
        }
    }
    NurbsSurface::new(
        2,
        c.degree(),
        arc_knots(a0, a1, n, step),
        c.knots().to_vec(),
        &pts,
        Some(&ws),
    )
}

/// The curve `c` moved along `vector` times `v ∈ [v0, v1]`.
pub(crate) fn extrude(
    c: &BSplineCurve,
    vector: Vec3,
    v0: f64,
    v1: f64,
) -> Result<NurbsSurface, NurbsError> {
    let mut pts = Vec::new();
    let mut ws = Vec::new();
    for &h in c.homogeneous() {
        let (p, w) = split(h);
        pts.push(vec![p + v0 * vector, p + v1 * vector]);
        ws.push(vec![w, w]);
    }
    NurbsSurface::new(
        c.degree(),
        1,
        c.knots().to_vec(),
        vec![v0, v0, v1, v1],
        &pts,
        Some(&ws),
    )
}

/// `c` with its domain mapped linearly onto `[0, 1]`.
fn normalised(c: &BSplineCurve) -> (usize, Vec<f64>, Vec<DVec4>) {
    let (t0, t1) = c.domain();
    let knots = c
        .knots()
        .iter()
        .map(|&k| ((k - t0) / (t1 - t0)).clamp(0.0, 1.0))
        .collect();
    (c.degree(), knots, c.homogeneous().to_vec())
}

/// Inserts knot `t` once (Boehm) into the homogeneous curve of degree `p`.
fn insert(p: usize, knots: &mut Vec<f64>, pw: &mut Vec<DVec4>, t: f64) {
    let k = knots.partition_point(|&x| x <= t) - 1;
    let mut q = Vec::with_capacity(pw.len() + 1);
    for i in 0..=pw.len() {
        if i + p <= k {
            q.push(pw[i]);
        } else if i > k {
            q.push(pw[i - 1]);
        } else {
            let a = (t - knots[i]) / (knots[i + p] - knots[i]);
            q.push(a * pw[i] + (1.0 - a) * pw[i - 1]);
        }
    }
    knots.insert(k + 1, t);
    *pw = q;
}

/// A degree-1 curve of one span raised to degree `p` (its points spread evenly along it).
fn raised_line(pw: &[DVec4], p: usize) -> Option<(Vec<f64>, Vec<DVec4>)> {
    if pw.len() != 2 || pw[0].w != pw[1].w {
        return None;
    }
    let pts = (0..=p)
        .map(|i| {
            let s = i as f64 / p as f64;
            (1.0 - s) * pw[0] + s * pw[1]
        })
        .collect();
    let mut knots = vec![0.0; p + 1];
    knots.extend(vec![1.0; p + 1]);
    Some((knots, pts))
}

/// The curves joined end to end into one (IGES 102): each member's parameters shifted to
/// follow on from the last's, its weights scaled to meet the last's end weight (a rational
/// curve is unchanged by scaling all its weights), a single line segment of a lower degree
/// raised. `None` when the members differ in degree otherwise, one is not clamped (its ends
/// not its end points), or one does not start within `tol` of where the last ends.
pub(crate) fn join(curves: &[BSplineCurve], tol: f64) -> Option<BSplineCurve> {
    let p = curves.iter().map(BSplineCurve::degree).max()?;
    let mut knots: Vec<f64> = Vec::new();
    let mut pw: Vec<DVec4> = Vec::new();
    for c in curves {
        let (t0, t1) = c.domain();
        let (k, h) = if c.degree() < p {
            let (k, h) = raised_line(c.homogeneous(), p)?;
            (k.iter().map(|x| t0 + x * (t1 - t0)).collect(), h)
        } else {
            (c.knots().to_vec(), c.homogeneous().to_vec())
        };
        let n = h.len();
        if k[..=p].iter().any(|&x| x != k[0]) || k[n..].iter().any(|&x| x != k[n]) {
            return None;
        }
        match pw.last().copied() {
            None => {
                knots = k;
                pw = h;
            }
            Some(last) => {
                let (a, _) = split(last);
                let (b, wb) = split(h[0]);
                if (a - b).length().is_nan() || (a - b).length() > tol {
                    return None;
                }
                let scale = last.w / wb;
                let shift = knots[knots.len() - 1] - k[0];
                knots.truncate(knots.len() - 1); // the joint: p copies
                knots.extend(k[p + 1..].iter().map(|x| x + shift));
                pw.extend(h[1..].iter().map(|q| *q * scale));
            }
        }
    }
    let (pts, ws): (Vec<Vec3>, Vec<f64>) = pw.iter().map(|&h| split(h)).unzip();
    BSplineCurve::new(p, knots, &pts, &ws).ok()
}

/// The ruled surface from `c1` (v = 0) to `c2` (v = 1), joining the points of equal
/// normalised parameter, `c2` run backwards when `reverse`. `None` when the two cannot be made
/// of one degree exactly (they differ in degree and the lower is not a single line segment).
pub(crate) fn ruled(
    c1: &BSplineCurve,
    c2: &BSplineCurve,
    reverse: bool,
) -> Option<Result<NurbsSurface, NurbsError>> {
    let c2 = if reverse {
        c2.clone().reversed()
    } else {
        c2.clone()
    };
    let (mut p1, mut k1, mut w1) = normalised(c1);
    let (mut p2, mut k2, mut w2) = normalised(&c2);
    if p1 < p2 {
        (k1, w1) = raised_line(&w1, p2)?;
        p1 = p2;
    } else if p2 < p1 {
        (k2, w2) = raised_line(&w2, p1)?;
        p2 = p1;
    }
    let p = p1.max(p2);
    // Merge the inner knots: each to the larger multiplicity of the two.
    let inner = |k: &[f64]| k[p + 1..k.len() - p - 1].to_vec();
    let (i1, i2) = (inner(&k1), inner(&k2));
    let count = |v: &[f64], t: f64| v.iter().filter(|&&x| x == t).count();
    let mut all: Vec<f64> = i1.iter().chain(&i2).copied().collect();
    all.sort_by(f64::total_cmp);
    all.dedup();
    for t in all {
        for _ in count(&i1, t)..count(&i2, t) {
            insert(p, &mut k1, &mut w1, t);
        }
        for _ in count(&i2, t)..count(&i1, t) {
            insert(p, &mut k2, &mut w2, t);
        }
    }
    if k1 != k2 || w1.len() != w2.len() {
        return None;
    }
    let mut pts = Vec::new();
    let mut ws = Vec::new();
    for (a, b) in w1.iter().zip(&w2) {
        let ((pa, wa), (pb, wb)) = (split(*a), split(*b));
        pts.push(vec![pa, pb]);
        ws.push(vec![wa, wb]);
    }
    Some(NurbsSurface::new(
        p,
        1,
        k1,
        vec![0.0, 0.0, 1.0, 1.0],
        &pts,
        Some(&ws),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::ParametricSurface;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn arcs_revolutions_extrusions_and_rulings_are_exact() {
        let f = Frame::WORLD;
        let c = conic(&f, 3.0, 3.0, 0.2, 5.0).unwrap();
        assert_eq!(c.domain(), (0.2, 5.0));
        for k in 0..=50 {
            let t = 0.2 + 4.8 * k as f64 / 50.0;
            assert!((c.point(t).length() - 3.0).abs() < 1e-12);
        }
        assert!(
            (c.point(5.0) - Vec3::new(3.0 * 5f64.cos(), 3.0 * 5f64.sin(), 0.0)).length() < 1e-12
        );
        // A line parallel to z at radius 10, revolved: a cylinder.
        let l = line(Vec3::new(10.0, 0.0, 0.0), Vec3::Z, -2.0, 7.0).unwrap();
        let s = revolve(&l, Vec3::ZERO, Vec3::Z, 0.0, std::f64::consts::TAU).unwrap();
        for i in 0..=20 {
            for j in 0..=10 {
                let d = s.domain();
                let q = s.point(d.u_at(i as f64 / 20.0), d.v_at(j as f64 / 10.0));
                assert!((q.x.hypot(q.y) - 10.0).abs() < 1e-12, "{q}");
                assert!(q.z >= -2.0 - 1e-12 && q.z <= 7.0 + 1e-12);
            }
        }
        // At a knot (a quarter turn) the point is turned by exactly that angle.
        let q = s.point(FRAC_PI_2, 3.0);
        assert!((q - Vec3::new(0.0, 10.0, 3.0)).length() < 1e-12, "{q}");
        // An arc extruded: a cylinder piece.
        let e = extrude(&c, Vec3::new(0.0, 0.0, 2.0), 0.0, 5.0).unwrap();
        let q = e.point(1.4, 2.5);
        let a: f64 = 1.4; // a knot: four pieces of 1.2
        assert!(
            (q - Vec3::new(3.0 * a.cos(), 3.0 * a.sin(), 5.0)).length() < 1e-12,
            "{q}"
        );
        // Ruled from a line to an arc (raised and knots merged): every ruling straight.
        let r = ruled(&l, &c, false).unwrap().unwrap();
        for t in [0.0, 0.3, 0.77, 1.0] {
            let (a, b, m) = (r.point(t, 0.0), r.point(t, 1.0), r.point(t, 0.4));
            assert!((b - a).cross(m - a).length() < 1e-9 * (b - a).length_squared());
        }
        assert!((r.point(0.0, 1.0) - c.point(0.2)).length() < 1e-12);
        assert!((r.point(1.0, 0.0) - l.point(7.0)).length() < 1e-12);
    }
}
