//! Sphere-arc profile elements (ball corners): the sphere band (caps) and the cylinder about
//! the centre's path on which the grazing great circle travels (the side of a capsule).

use super::{Acc, DirConsts, BAND_EPS};
use swarf_geom::math::Vec3;

/// Crossings of the line `o + t·d` (unit `d`) with the sphere of radius `r` centred at
/// `(0, 0, f)`, kept within the band `z ∈ [z0, z1]`.
#[inline]
pub(crate) fn cap(f: f64, r: f64, z0: f64, z1: f64, o: Vec3, d: Vec3, acc: &mut Acc) {
    let q = o - Vec3::new(0.0, 0.0, f);
    let b = q.dot(d);
    let c = q.length_squared() - r * r;
    let (rts, nr) = super::quad(1.0, 2.0 * b, c);
    for &t in &rts[..nr] {
        let z = o.z + t * d.z;
        if z >= z0 - BAND_EPS && z <= z1 + BAND_EPS {
            acc.add(t);
        }
    }
}

/// Crossings with the extrusion of the sphere's grazing great circle (normal ⊥ `v`): the
/// cylinder of radius `r` about the line `c + s·v`, kept where `s ∈ [0, 1]` and the grazing
/// point lies in the band.
#[inline]
pub(crate) fn envelope(f: f64, r: f64, z0: f64, z1: f64, o: Vec3, dc: &DirConsts, acc: &mut Acc) {
    let c = Vec3::new(0.0, 0.0, f);
    let q = o - c;
    let vn = dc.v / dc.vv.sqrt();
    let qp = q - vn * q.dot(vn);
    let dp = dc.d - vn * dc.d.dot(vn);
    let qa = dp.length_squared();
    if qa <= 1e-20 {
        return;
    }
    let qb = 2.0 * qp.dot(dp);
    let qc = qp.length_squared() - r * r;
    let se = BAND_EPS / dc.vv.sqrt();
    let (rts, nr) = super::quad(qa, qb, qc);
    for &t in &rts[..nr] {
        let p = o + dc.d * t;
        let s = (p - c).dot(dc.v) / dc.vv;
        if s < -se || s > 1.0 + se {
            continue;
        }
        let gz = p.z - s * dc.v.z;
        if gz >= z0 - BAND_EPS && gz <= z1 + BAND_EPS {
            acc.add(t);
        }
    }
}
