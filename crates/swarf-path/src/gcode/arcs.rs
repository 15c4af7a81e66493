//! Arc centres as LinuxCNC computes them (`arc_data_ijk`, `arc_data_r`), in the plane's first
//! and second coordinates, millimetres.
//!
//! LinuxCNC works in program units; the tolerances here are LinuxCNC's converted to mm, so a
//! program is accepted or rejected the same way in either unit system.

use crate::Units;

/// `RADIUS_TOLERANCE_INCH` (0.00005 in; the mm constant is the same length): arcs with a radius
/// below this are rejected.
pub(crate) const ZERO_RADIUS_MM: f64 = 0.00005 * 25.4;

/// `TOLERANCE_INCH` / `TOLERANCE_MM`: how far an R-format end point may be beyond the diameter.
pub(crate) fn r_tolerance_mm(units: Units) -> f64 {
    match units {
        Units::Inch => 0.0005 * 25.4,
        Units::Mm => 0.005,
    }
}

/// Checks a centre-format arc: both radii above zero, and the end radius within tolerance of
/// the start radius (LinuxCNC's rule: reject when the difference exceeds `100 × abs`, or when
/// it exceeds `abs` and the relative difference exceeds `rel`). A cutter compensation entry
/// arc is checked so too, on its programmed ends (rs274 2.9).
pub(crate) fn check_ijk(
    start: [f64; 2],
    end: [f64; 2],
    center: [f64; 2],
    abs: f64,
    rel: f64,
) -> Result<(), String> {
    let r1 = (center[0] - start[0]).hypot(center[1] - start[1]);
    let r2 = (center[0] - end[0]).hypot(center[1] - end[1]);
    if r1 < ZERO_RADIUS_MM || r2 < ZERO_RADIUS_MM {
        return Err("zero-radius arc".into());
    }
    let abs_err = (r1 - r2).abs();
    let rel_err = abs_err / r1.max(r2);
    if abs_err > abs * 100.0 || (rel_err > rel && abs_err > abs) {
        return Err(format!(
            "radius to end of arc differs from radius to start: r1={r1:.4} mm r2={r2:.4} mm abs_err={abs_err:.4} mm \
             rel_err={:.4}%",
            rel_err * 100.0
        ));
    }
    Ok(())
}

/// Centre of an R-format arc from `start` to `end` (LinuxCNC's `arc_data_r`). A negative radius
/// asks for the arc of more than 180°.
pub(crate) fn center_r(
    start: [f64; 2],
    end: [f64; 2],
    radius: f64,
    clockwise: bool,
    tolerance: f64,
) -> Result<[f64; 2], String> {
    if start == end {
        return Err("current point is the same as the end point of the arc; an R-format arc cannot be a full circle".into());
    }
    let abs_r = radius.abs();
    let mid = [(start[0] + end[0]) / 2.0, (start[1] + end[1]) / 2.0];
    let mut half = (mid[0] - end[0]).hypot(mid[1] - end[1]);
    if half - abs_r > tolerance {
        return Err(format!(
            "arc radius {abs_r:.4} mm is too small to reach the end point ({:.4} mm away)",
            2.0 * half
        ));
    }
    if half / abs_r > 1.0 - 1e-12 {
        // Allow a small error for a semicircle.
        half = abs_r;
    }
    let chord = (end[1] - start[1]).atan2(end[0] - start[0]);
    let theta = if clockwise == (radius > 0.0) {
        chord - std::f64::consts::FRAC_PI_2
    } else {
        chord + std::f64::consts::FRAC_PI_2
    };
    let turn2 = (half / abs_r).asin();
    let offset = abs_r * turn2.cos();
    Ok([mid[0] + offset * theta.cos(), mid[1] + offset * theta.sin()])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f64; 2], b: [f64; 2]) -> bool {
        (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12
    }

    #[test]
    fn r_format_centres() {
        // Quarter circle from (1,0) to (0,1): CCW small arc centre (0,0), CW small arc centre (1,1).
        assert!(close(
            center_r([1.0, 0.0], [0.0, 1.0], 1.0, false, 0.005).unwrap(),
            [0.0, 0.0]
        ));
        assert!(close(
            center_r([1.0, 0.0], [0.0, 1.0], 1.0, true, 0.005).unwrap(),
            [1.0, 1.0]
        ));
        // Negative radius: the large arc, centre on the other side.
        assert!(close(
            center_r([1.0, 0.0], [0.0, 1.0], -1.0, false, 0.005).unwrap(),
            [1.0, 1.0]
        ));
        assert!(close(
            center_r([1.0, 0.0], [0.0, 1.0], -1.0, true, 0.005).unwrap(),
            [0.0, 0.0]
        ));
        // Semicircle, within tolerance.
        assert!(close(
            center_r([0.0, 0.0], [2.0, 0.0], 1.0, true, 0.005).unwrap(),
            [1.0, 0.0]
        ));
        assert!(center_r([0.0, 0.0], [2.02, 0.0], 1.0, true, 0.005).is_err());
        assert!(center_r([1.0, 1.0], [1.0, 1.0], 1.0, true, 0.005).is_err());
    }

    #[test]
    fn ijk_tolerance() {
        assert!(check_ijk([1.0, 0.0], [0.0, 1.0], [0.0, 0.0], 0.02, 0.001).is_ok());
        // 0.015 mm off on a 10 mm radius: under abs.
        assert!(check_ijk([10.0, 0.0], [0.0, 10.015], [0.0, 0.0], 0.02, 0.001).is_ok());
        // 0.05 mm off on a 10 mm radius: over abs and over 0.1 %.
        assert!(check_ijk([10.0, 0.0], [0.0, 10.05], [0.0, 0.0], 0.02, 0.001).is_err());
        // 0.05 mm off on a 1000 mm radius: relative 0.005 % passes.
        assert!(check_ijk([1000.0, 0.0], [0.0, 1000.05], [0.0, 0.0], 0.02, 0.001).is_ok());
        // 2.5 mm off is over 100 × abs whatever the radius.
        assert!(check_ijk([10000.0, 0.0], [0.0, 10002.5], [0.0, 0.0], 0.02, 0.001).is_err());
        assert!(check_ijk([0.0, 0.0], [0.0, 0.0], [0.0, 0.0], 0.02, 0.001).is_err());
    }
}
