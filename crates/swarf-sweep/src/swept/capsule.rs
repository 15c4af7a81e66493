//! A sphere swept along a segment (a capsule) against a line, in closed form: the ball of a
//! ball end mill on a fixed-axis move. One quadratic for the side (the cylinder about the
//! centre's path), one per end sphere when the side's hit falls beyond an end.

use swarf_geom::math::Vec3;

/// The chord `(near, far)` of the line `oc + t·d` (unit `d`) through the sphere of squared
/// radius `rr` centred at the origin.
#[inline(always)]
fn sphere(oc: Vec3, d: Vec3, rr: f64) -> Option<(f64, f64)> {
    let b = oc.dot(d);
    let h = b * b - (oc.dot(oc) - rr);
    (h >= 0.0).then(|| {
        let s = h.sqrt();
        (-b - s, -b + s)
    })
}

/// The interval of the line `o + t·d` (unit `d`) inside the capsule of radius `r` about the
/// segment `c0 → c0 + ba`; `None` when it misses. With `LOW_ONLY` the upper end is not
/// computed (returned equal to the lower one): the drop-cutter of a swept ball, for lines
/// whose upper end another piece provides.
///
/// The line is re-based at its point nearest `c0` first (parameters of a few mm whatever the
/// coordinates). The side is the cylinder about the segment: where its crossing projects
/// beyond an end, that end's sphere holds the capsule's boundary instead (the capsule is
/// convex). A line parallel to the segment meets the two end spheres, and its interval is the
/// hull of their chords.
#[inline]
pub(crate) fn line_capsule<const LOW_ONLY: bool>(
    o: Vec3,
    d: Vec3,
    c0: Vec3,
    ba: Vec3,
    r: f64,
) -> Option<(f64, f64)> {
    let t0 = (c0 - o).dot(d);
    let oa = o + d * t0 - c0;
    let rr = r * r;
    let baba = ba.dot(ba);
    if baba == 0.0 {
        return sphere(oa, d, rr).map(|(l, h)| (l + t0, h + t0));
    }
    let bard = ba.dot(d);
    let baoa = ba.dot(oa);
    let a = baba - bard * bard;
    if a <= 1e-20 * baba {
        // (Nearly) parallel: when both end spheres are met the segment between them lies in
        // the capsule, so the hull is exact; a line meeting one only is within 1e-10·|ba| of
        // tangency and, unless exactly parallel, goes on to the side's quadratic below.
        let s0 = sphere(oa, d, rr);
        let s1 = sphere(oa - ba, d, rr);
        match (s0, s1) {
            (Some(p), Some(q)) => return Some((p.0.min(q.0) + t0, p.1.max(q.1) + t0)),
            (None, None) => return None,
            (Some(p), None) | (None, Some(p)) if a == 0.0 => return Some((p.0 + t0, p.1 + t0)),
            _ => {}
        }
    }
    // |(oa + t·d) × ba|² = r²·|ba|², with d·oa = 0 after re-basing.
    let b = -baoa * bard;
    let c = baba * oa.dot(oa) - baoa * baoa - rr * baba;
    let h = b * b - a * c;
    if h < 0.0 {
        return None;
    }
    // Cancellation-free roots; (b + sign(b)·√h) is never 0 here unless h = b = 0.
    let sh = h.sqrt();
    let (near, far) = if b > 0.0 {
        let q = -(b + sh);
        (q / a, if q != 0.0 { c / q } else { 0.0 })
    } else {
        let q = -b + sh;
        (if q != 0.0 { c / q } else { 0.0 }, q / a)
    };
    let end = |t: f64, low: bool| -> Option<f64> {
        let y = baoa + t * bard;
        if y > 0.0 && y < baba {
            return Some(t);
        }
        let oc = if y <= 0.0 { oa } else { oa - ba };
        sphere(oc, d, rr).map(|(l, h)| if low { l } else { h })
    };
    let lo = end(near, true)?;
    if LOW_ONLY {
        return Some((lo + t0, lo + t0));
    }
    let hi = end(far, false)?;
    Some((lo + t0, hi + t0))
}
