//! Zeros and minimum of a convex function along a line — where a line enters and leaves a
//! convex solid given by a convex "outside" function `F` (`F ≤ 0` inside): the one mechanism of
//! the torus caps (`torus.rs`) and the swept lozenge (`lozenge.rs`).
//!
//! `F` being convex, its tangent lies below it: Newton steps from a point where `F ≥ 0` land
//! short of the nearest zero that way and close in on it from one side, never overshooting
//! ([`walk`]). Where that cannot settle (a vertical tangent, a line grazing the solid), the zero
//! or the minimum is found in a bracket by Newton steps that bisection takes over when they
//! leave it ([`zero_between`], [`min_between`]).

/// A convex function of the line parameter `t`.
pub(crate) trait ConvexLine {
    /// `(F(t), F′(t))`; `F′` may be `±∞` where `F` has a vertical tangent.
    fn value_slope(&self, t: f64) -> (f64, f64);

    /// `(F(t), F′(t), −F(t)/F′(t))`: the Newton step too, for a line that can have it
    /// without waiting for `F′` (the division by `F′` then leaves the walk's chain of
    /// dependent operations).
    #[inline]
    fn value_slope_step(&self, t: f64) -> (f64, f64, f64) {
        let (f, g) = self.value_slope(t);
        (f, g, -f / g)
    }

    /// `F(t)` (when cheaper alone).
    fn value(&self, t: f64) -> f64 {
        self.value_slope(t).0
    }

    /// `F′(t)`.
    fn slope(&self, t: f64) -> f64 {
        self.value_slope(t).1
    }

    /// `F″(t) ≥ 0` when known (Newton steps for the minimum); `None`: bisection on the slope.
    fn curvature(&self, _t: f64) -> Option<f64> {
        None
    }

    /// A bound `K ≥ F″` wherever `F ≥ 0`, when known: [`walk`] then stops as soon as the
    /// step it takes is proven to land within [`T_TOL`] of the zero, one evaluation earlier.
    fn curvature_bound(&self) -> Option<f64> {
        None
    }
}

/// Zeros are located to this (in `t`, mm).
pub(crate) const T_TOL: f64 = 1e-12;

/// Newton steps at most in [`walk`] before it hands over to the bracketed search.
const WALK_STEPS: usize = 40;

/// Steps at most per zero or minimum (bisection takes over when a step leaves the bracket;
/// convergence is quadratic, so this is only a guard).
const MAX_STEPS: usize = 100;

/// Where [`walk`] ends.
pub(crate) enum Walk {
    /// At the zero.
    Zero(f64),
    /// There is no zero between the start and the end it walked towards.
    NoZero,
    /// It could not tell: bracket instead.
    Stuck,
}

/// Newton steps from `t` (where `F(t) = f ≥ 0`, its slope `g` if known) towards `toward`:
/// [`Walk::Stuck`] where a slope is infinite or the steps do not settle.
pub(crate) fn walk<F: ConvexLine + ?Sized>(
    line: &F,
    mut t: f64,
    (mut f, g): (f64, Option<f64>),
    toward: f64,
) -> Walk {
    let dir = if toward > t { 1.0 } else { -1.0 };
    // The slope at `t` (known with the value after the first step), and the step.
    let mut slope = g;
    let mut known_step = None;
    for _ in 0..WALK_STEPS {
        if f <= 0.0 {
            return Walk::Zero(t);
        }
        let g = slope.take().unwrap_or_else(|| line.slope(t));
        if !g.is_finite() {
            return Walk::Stuck;
        }
        if g * dir >= 0.0 {
            // Rising the way it walks while above zero: no zero that way.
            return Walk::NoZero;
        }
        let step = known_step.take().unwrap_or_else(|| -f / g);
        let next = t + step;
        if (next - toward) * dir > 0.0 {
            return Walk::NoZero;
        }
        if step.abs() <= T_TOL {
            return Walk::Zero(next);
        }
        if let Some(k) = line.curvature_bound() {
            // Past `next` the zero is at most F(next)/|F′| away, with F(next) ≤ K·s²/2
            // (Taylor: the tangent's zero) and |F′| ≥ |g| − 2·K·s on the way (F″ ≤ K; the
            // zero lies within s of next while this holds).
            let s = step.abs();
            let slope = g.abs() - 2.0 * k * s;
            if slope > 0.0 && 0.5 * k * s * s <= T_TOL * slope {
                return Walk::Zero(next);
            }
        }
        t = next;
        let (fv, gv, sv) = line.value_slope_step(t);
        (f, slope, known_step) = (fv, Some(gv), Some(sv));
    }
    Walk::Stuck
}

/// The zero of `F` in `[a, b]`, where `F` changes sign once, `F(a) = fa`.
pub(crate) fn zero_between<F: ConvexLine + ?Sized>(
    line: &F,
    mut a: f64,
    mut b: f64,
    fa: f64,
) -> f64 {
    let rising = fa < 0.0;
    let mut t = 0.5 * (a + b);
    for _ in 0..MAX_STEPS {
        let (v, g) = line.value_slope(t);
        if v == 0.0 {
            return t;
        }
        if (v < 0.0) == rising {
            a = t;
        } else {
            b = t;
        }
        let newton = g.is_finite() && g != 0.0;
        let step = v / g;
        if newton && step.abs() <= T_TOL {
            // Confirmed by a change of sign around it (a tiny step may also come from a huge
            // slope near a vertical tangent, far from the zero).
            let x = (t - step).clamp(a, b);
            let w = 2.0 * T_TOL;
            let (l, r) = (line.value((x - w).max(a)), line.value((x + w).min(b)));
            if l == 0.0 || r == 0.0 || (l < 0.0) != (r < 0.0) {
                return x;
            }
        }
        let next = t - step;
        t = if newton && next > a && next < b && step.abs() > T_TOL {
            next
        } else {
            0.5 * (a + b)
        };
        if b - a <= T_TOL {
            break;
        }
    }
    t
}

/// The zero of `F′` in `[a, b]` (`F′(a) < 0 < F′(b)`): the minimum.
pub(crate) fn min_between<F: ConvexLine + ?Sized>(line: &F, mut a: f64, mut b: f64) -> f64 {
    let mut t = 0.5 * (a + b);
    for _ in 0..MAX_STEPS {
        let g = line.slope(t);
        if g == 0.0 {
            return t;
        }
        if g < 0.0 {
            a = t;
        } else {
            b = t;
        }
        let h = line.curvature(t).unwrap_or(0.0);
        let step = g / h;
        if h > 0.0 && step.abs() <= T_TOL {
            // Confirmed by the slope's sign on both sides (a tiny step may also come from a
            // huge curvature near a vertical tangent, far from the minimum).
            let x = (t - step).clamp(a, b);
            let w = 2.0 * T_TOL;
            if line.slope((x - w).max(a)) <= 0.0 && line.slope((x + w).min(b)) >= 0.0 {
                return x;
            }
        }
        let next = t - step;
        t = if h > 0.0 && next > a && next < b && step.abs() > T_TOL {
            next
        } else {
            0.5 * (a + b)
        };
        if b - a <= T_TOL {
            break;
        }
    }
    t
}
