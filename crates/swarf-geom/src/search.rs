//! One-dimensional searches shared by the planner and the surface readers.

/// Golden-section search for a maximum of `f` on `[lo, hi]`, down to a bracket of `tol` (or 200
/// steps, a bracket of 1e-42 of the start: a `tol` below the doubles' resolution cannot hang it).
/// Stops early where `f` is infinite. Returns nothing: the caller keeps the best value `f` was
/// asked for (so it may also remember where, or stop on its own criterion).
///
/// For a unimodal `f` the bracket keeps the maximum; otherwise it finds a local one.
///
/// ```
/// use swarf_geom::search::golden_max;
/// let mut best = (f64::NEG_INFINITY, 0.0);
/// golden_max(
///     &mut |x: f64| {
///         let y = -(x - 0.3) * (x - 0.3);
///         if y > best.0 {
///             best = (y, x);
///         }
///         y
///     },
///     0.0,
///     1.0,
///     1e-10,
/// );
/// assert!((best.1 - 0.3).abs() < 1e-9);
/// ```
pub fn golden_max(f: &mut impl FnMut(f64) -> f64, lo: f64, hi: f64, tol: f64) {
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut a, mut b) = (lo, hi);
    let mut x1 = b - g * (b - a);
    let mut x2 = a + g * (b - a);
    let mut f1 = f(x1);
    let mut f2 = f(x2);
    for _ in 0..200 {
        if b - a <= tol {
            break;
        }
        if f1.is_infinite() || f2.is_infinite() {
            return;
        }
        if f1 >= f2 {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - g * (b - a);
            f1 = f(x1);
        } else {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + g * (b - a);
            f2 = f(x2);
        }
    }
}
