//! Segment profile elements — discs (horizontal), cylinders (vertical) and cones — against a
//! line: the surface itself (caps) and its grazing generator lines extruded along the move
//! (parallelograms).

use super::{Acc, DirConsts, BAND_EPS};
use swarf_geom::math::{Vec2, Vec3};

/// Crossings of the line `o + t·d` with the surface of revolution of the segment `p → q`.
#[inline]
pub(crate) fn cap(p: Vec2, q: Vec2, o: Vec3, d: Vec3, acc: &mut Acc) {
    if p.y == q.y {
        // Disc or annulus in the plane z = p.y.
        if d.z == 0.0 {
            return;
        }
        let t = (p.y - o.z) / d.z;
        let (x, y) = (o.x + t * d.x, o.y + t * d.y);
        let rr = x * x + y * y;
        let (r0, r1) = (p.x.min(q.x), p.x.max(q.x));
        if rr <= (r1 + BAND_EPS) * (r1 + BAND_EPS) && (r0 == 0.0 || rr >= (r0 - BAND_EPS).powi(2)) {
            acc.add(t);
        }
        return;
    }
    let (lo, hi) = if p.y < q.y { (p, q) } else { (q, p) };
    // ρ(z) = lo.x + k·(z − lo.y) along the segment; on the line z = o.z + t·d.z.
    let k = (hi.x - lo.x) / (hi.y - lo.y);
    let a0 = lo.x + k * (o.z - lo.y);
    let kd = k * d.z;
    let qa = d.x * d.x + d.y * d.y - kd * kd;
    let qb = 2.0 * (o.x * d.x + o.y * d.y - kd * a0);
    let qc = o.x * o.x + o.y * o.y - a0 * a0;
    let (rts, nr) = super::quad(qa, qb, qc);
    for &t in &rts[..nr] {
        let z = o.z + t * d.z;
        if z >= lo.y - BAND_EPS && z <= hi.y + BAND_EPS && a0 + kd * t >= -BAND_EPS {
            acc.add(t);
        }
    }
}

/// Crossings of the line with the generator lines of the segment's surface whose normal is
/// perpendicular to the move `v = (a, 0, b)`, extruded along `v`.
#[inline]
pub(crate) fn envelope(p: Vec2, q: Vec2, o: Vec3, dc: &DirConsts, acc: &mut Acc) {
    let (a, b) = (dc.v.x, dc.v.z);
    let e = q - p;
    if e.y <= 0.0 || a == 0.0 {
        // Discs: covered by their edge circles. Plunges: cones have no grazing generator and
        // cylinders' extrusions are covered by their end circles and the caps.
        return;
    }
    // Outward normal (n_ρ, n_z) ∝ (Δz, −Δρ); grazing where n_ρ·a·cos θ + n_z·b = 0.
    let c = e.x * b / (e.y * a);
    if c.abs() > 1.0 {
        return;
    }
    let sn = (1.0 - c * c).sqrt();
    for y in [sn, -sn] {
        let g0 = Vec3::new(p.x * c, p.x * y, p.y);
        let ev = Vec3::new(e.x * c, e.x * y, e.y);
        // o + t·d = g0 + λ·ev + s·v, by Cramer's rule.
        let exv = ev.cross(dc.v);
        let det = dc.d.dot(exv);
        if det.abs() <= 1e-14 * ev.length() * dc.vv.sqrt() {
            continue;
        }
        let rhs = g0 - o;
        let t = rhs.dot(exv) / det;
        let lam = -dc.d.dot(rhs.cross(dc.v)) / det;
        let s = -dc.d.dot(ev.cross(rhs)) / det;
        let (le, se) = (BAND_EPS / e.length(), BAND_EPS / dc.vv.sqrt());
        if (-le..=1.0 + le).contains(&lam) && (-se..=1.0 + se).contains(&s) {
            acc.add(t);
        }
        if sn == 0.0 {
            break;
        }
    }
}
