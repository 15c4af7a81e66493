//! Arcs and helices as chords: how many equal chords keep the tip path within a tolerance.

/// Number of equal chords for an arc of radius `radius` sweeping `sweep` radians so that the
/// sagitta `radius·(1 − cos(Δ/2))` is at most `tol`. For a helix or spiral, the axial travel
/// is linear in the parameter on both the arc and the chord, so the distance between points of
/// equal parameter is the in-plane sagitta of the larger radius (a bound). At most
/// [`MAX_CHORDS`]` + 1`: a caller refuses an arc that needs more (a tolerance far below the
/// radius's rounding made the count infinite, and a vector of `usize::MAX` chords).
pub fn arc_chords(radius: f64, sweep: f64, tol: f64) -> usize {
    let cap = (MAX_CHORDS + 1) as f64;
    if !(radius > tol && tol > 0.0 && sweep.is_finite()) {
        return 1.max((sweep / std::f64::consts::FRAC_PI_2).ceil().min(cap) as usize);
    }
    let step = 2.0 * (1.0 - tol / radius).acos();
    let n = (sweep.abs() / step).ceil().max(1.0);
    // Never coarser than quarter turns (keeps each chord's sweep convex-hull argument simple).
    n.max((sweep.abs() / std::f64::consts::FRAC_PI_2).ceil())
        .min(cap) as usize
}

/// The most chords one arc is cut as (the 5-axis sub-move limit): about a million, 1.4 ms of a
/// full circle each at 1 µm on a 10 m radius.
pub const MAX_CHORDS: usize = crate::five_axis::MAX_SUB_MOVES;

/// The error for an arc of radius `radius` mm that needs more than [`MAX_CHORDS`] chords
/// within `tol` mm, as move `index` on `line`.
pub fn too_many_chords(index: usize, line: u32, radius: f64, tol: f64) -> crate::SweepError {
    crate::SweepError::Unsupported {
        index,
        line,
        why: format!(
            "the arc of radius {radius} mm needs more than {MAX_CHORDS} chords to stay within \
             {tol:e} mm of it; give a larger tolerance"
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tolerance_below_the_radius_s_rounding_is_capped() {
        for tol in [1e-300, 1e-17, 0.0] {
            let n = arc_chords(10.0, 4.0 * std::f64::consts::PI, tol);
            assert!((4..=MAX_CHORDS + 1).contains(&n), "{tol}: {n}");
        }
        assert_eq!(arc_chords(10.0, 1.0, 1e-300), MAX_CHORDS + 1);
    }

    #[test]
    fn chord_count_honours_tolerance() {
        for (r, sweep, tol) in [
            (10.0, std::f64::consts::PI, 0.001),
            (3.0, 7.0, 0.01),
            (50.0, 0.1, 1e-4),
        ] {
            let n = arc_chords(r, sweep, tol);
            let d = sweep / n as f64;
            assert!(
                r * (1.0 - (d / 2.0).cos()) <= tol * (1.0 + 1e-12),
                "{r} {sweep} {tol} {n}"
            );
            // And not wastefully fine: one chord fewer would break it (when not capped).
            if n > (sweep / std::f64::consts::FRAC_PI_2).ceil() as usize {
                let d1 = sweep / (n - 1) as f64;
                assert!(r * (1.0 - (d1 / 2.0).cos()) > tol);
            }
        }
    }
}
