//! Real roots of low-degree polynomials, with a guarantee.
//!
//! Ray queries on quadrics reduce to quadratics and on the torus to a quartic. The quadratic is
//! solved in closed form with the cancellation-free formula (`q = -(b + sign(b)·√Δ)/2`, roots
//! `q/a` and `c/q`). Higher degrees are solved by **recursive derivative bracketing**: the real
//! roots of `p'` split the search interval into pieces on which `p` is monotone, so each piece
//! holds at most one root, present exactly when `p` changes sign across it; that root is then
//! found by Newton's method safeguarded by bisection. Roots of `p'` come from the same procedure
//! one degree lower, down to a linear polynomial. Unlike closed-form quartic formulas (Ferrari)
//! this never loses a root to cancellation, and unlike plain Newton it never converges to the
//! wrong root or misses one: every root of odd multiplicity in the interval is found.
//!
//! Roots of even multiplicity (a ray tangent to a surface) do not change the sign of `p`; they
//! sit at a critical point where `|p|` is below the rounding error of evaluating `p` there, and
//! are reported once.
//!
//! Accuracy is a parameter: [`RootTolerance::x_tol`] is the absolute width below which a
//! bracket is accepted; [`RootTolerance::DEFAULT`] is 1e-12 (in the unit of the variable, mm for
//! ray parameters of unit direction).
//!
//! Coefficients are given in **ascending** order: `c[0] + c[1]·x + c[2]·x² + …`.

use crate::math::Real;

/// Highest polynomial degree [`real_roots_in`] accepts (the torus needs 4).
pub const MAX_DEGREE: usize = 8;

/// How precisely [`real_roots_in`] locates roots.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RootTolerance {
    /// Absolute width of the final bracket around a root (unit of the variable).
    pub x_tol: Real,
    /// Maximum number of Newton/bisection steps per root (bisection alone halves the bracket
    /// each step, so 200 steps reach any `x_tol` from any finite `f64` interval).
    pub max_iter: u32,
}

impl RootTolerance {
    /// The default: 1e-12 absolute, 200 iterations.
    pub const DEFAULT: RootTolerance = RootTolerance {
        x_tol: 1e-12,
        max_iter: 200,
    };

    /// The default with another absolute tolerance.
    pub fn with_x_tol(mut self, x_tol: Real) -> Self {
        self.x_tol = x_tol;
        self
    }
}

impl Default for RootTolerance {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// A short list of real roots held on the stack (at most [`MAX_DEGREE`]), sorted ascending.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Roots {
    buf: [Real; MAX_DEGREE],
    len: usize,
}

impl Roots {
    /// No roots.
    pub const EMPTY: Roots = Roots {
        buf: [0.0; MAX_DEGREE],
        len: 0,
    };

    fn push(&mut self, x: Real) {
        if self.len < MAX_DEGREE {
            self.buf[self.len] = x;
            self.len += 1;
        }
    }

    /// The roots, ascending.
    pub fn as_slice(&self) -> &[Real] {
        &self.buf[..self.len]
    }

    /// Number of roots.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when there is no root.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
}

/// Real roots of `a·x² + b·x + c`, ascending; a double root is reported once.
///
/// Uses the cancellation-free form. When `a == 0` the equation is linear; when `a == b == 0`
/// there is no isolated root and the result is empty (also for the identically zero polynomial).
pub fn quadratic_roots(a: Real, b: Real, c: Real) -> Roots {
    let mut r = Roots::EMPTY;
    if a == 0.0 {
        if b != 0.0 {
            r.push(-c / b);
        }
        return r;
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 || !disc.is_finite() {
        return r;
    }
    if disc == 0.0 {
        r.push(-b / (2.0 * a));
        return r;
    }
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    // b == 0 gives signum 1, fine: q = -√Δ/2 ≠ 0 since Δ > 0.
    let (x1, x2) = (q / a, c / q);
    if x1 <= x2 {
        r.push(x1);
        r.push(x2);
    } else {
        r.push(x2);
        r.push(x1);
    }
    r
}

/// Evaluates `c[0] + c[1]·x + …` by Horner's rule.
pub fn eval(c: &[Real], x: Real) -> Real {
    c.iter().rev().fold(0.0, |acc, &ci| acc * x + ci)
}

/// Value and a bound on the rounding error of Horner evaluation (Higham, §5.1: the error is at
/// most `γ_{2n} · Σ|c_i|·|x|^i`).
fn eval_with_error(c: &[Real], x: Real) -> (Real, Real) {
    let ax = x.abs();
    let mut v = 0.0;
    let mut m = 0.0;
    for &ci in c.iter().rev() {
        v = v * x + ci;
        m = m * ax + ci.abs();
    }
    let n = c.len() as Real;
    (v, 4.0 * n * Real::EPSILON * m)
}

/// All real roots of the polynomial `c` (ascending coefficients, degree ≤ [`MAX_DEGREE`]) in the
/// closed interval `[lo, hi]`, ascending, appended to `out`.
///
/// Each root of odd multiplicity is found (to `tol.x_tol`); a root of even multiplicity is
/// reported once, at the critical point where `p` touches zero within its rounding error. Leading
/// zero coefficients are dropped (the degree falls). The identically zero polynomial has no
/// isolated roots and yields none. Non-finite coefficients or bounds yield none.
///
/// # Panics
/// Never; a degree above [`MAX_DEGREE`] yields no roots (and a debug assertion).
pub fn real_roots_in(c: &[Real], lo: Real, hi: Real, tol: RootTolerance, out: &mut Vec<Real>) {
    let mut deg = c.len();
    while deg > 0 && c[deg - 1] == 0.0 {
        deg -= 1;
    }
    if deg == 0 || !lo.is_finite() || !hi.is_finite() || lo > hi {
        return;
    }
    if c[..deg].iter().any(|v| !v.is_finite()) {
        return;
    }
    debug_assert!(deg - 1 <= MAX_DEGREE, "degree above MAX_DEGREE");
    if deg - 1 > MAX_DEGREE {
        return;
    }
    let mut coeffs = [0.0; MAX_DEGREE + 1];
    coeffs[..deg].copy_from_slice(&c[..deg]);
    let roots = roots_rec(&coeffs[..deg], lo, hi, tol);
    out.extend_from_slice(roots.as_slice());
}

/// Recursive derivative bracketing on `[lo, hi]`; `c` has a non-zero leading coefficient.
fn roots_rec(c: &[Real], lo: Real, hi: Real, tol: RootTolerance) -> Roots {
    let mut roots = Roots::EMPTY;
    let deg = c.len() - 1;
    if deg == 0 {
        return roots;
    }
    if deg == 1 {
        let x = -c[0] / c[1];
        if x >= lo && x <= hi {
            roots.push(x);
        }
        return roots;
    }
    // Critical points split [lo, hi] into monotone pieces.
    let mut d = [0.0; MAX_DEGREE];
    for i in 1..=deg {
        d[i - 1] = c[i] * i as Real;
    }
    let crit = roots_rec(&d[..deg], lo, hi, tol);
    let mut xs = [0.0; MAX_DEGREE + 2];
    let mut n = 0;
    xs[n] = lo;
    n += 1;
    for &x in crit.as_slice() {
        if x > xs[n - 1] && x < hi {
            xs[n] = x;
            n += 1;
        }
    }
    xs[n] = hi;
    n += 1;
    if hi == lo {
        n = 1;
    }
    // Values at the breakpoints; a value within rounding error of zero counts as a root there.
    let mut vs = [0.0; MAX_DEGREE + 2];
    let mut zero = [false; MAX_DEGREE + 2];
    for i in 0..n {
        let (v, err) = eval_with_error(c, xs[i]);
        vs[i] = v;
        zero[i] = v.abs() <= err;
    }
    for i in 0..n {
        if zero[i] {
            roots.push(xs[i]);
        }
        if i + 1 < n && !zero[i] && !zero[i + 1] && (vs[i] < 0.0) != (vs[i + 1] < 0.0) {
            roots.push(bracketed_root(c, xs[i], xs[i + 1], vs[i], tol));
        }
    }
    roots
}

/// Newton's method safeguarded by bisection on a bracket `[a, b]` with `p(a)`, `p(b)` of
/// opposite signs (`fa = p(a)`).
fn bracketed_root(c: &[Real], mut a: Real, mut b: Real, fa: Real, tol: RootTolerance) -> Real {
    let neg_at_a = fa < 0.0;
    let mut x = 0.5 * (a + b);
    for _ in 0..tol.max_iter {
        let (f, df) = eval_and_derivative(c, x);
        if f == 0.0 {
            return x;
        }
        // Shrink the bracket, keeping the sign change inside.
        if (f < 0.0) == neg_at_a {
            a = x;
        } else {
            b = x;
        }
        let width = b - a;
        if width <= tol.x_tol.max(4.0 * Real::EPSILON * x.abs()) {
            break;
        }
        let newton = x - f / df;
        // Accept the Newton step only inside the bracket; otherwise bisect. Monotonicity on the
        // piece means Newton converges quadratically once close, and bisection keeps the
        // worst case linear.
        x = if df != 0.0 && newton > a && newton < b {
            newton
        } else {
            0.5 * (a + b)
        };
        if x == a || x == b {
            break;
        }
    }
    x
}

fn eval_and_derivative(c: &[Real], x: Real) -> (Real, Real) {
    let mut f = 0.0;
    let mut df = 0.0;
    for &ci in c.iter().rev() {
        df = df * x + f;
        f = f * x + ci;
    }
    (f, df)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn from_roots(rs: &[Real]) -> Vec<Real> {
        // Ascending coefficients of Π (x - r).
        let mut c = vec![1.0];
        for &r in rs {
            let mut n = vec![0.0; c.len() + 1];
            for (i, &ci) in c.iter().enumerate() {
                n[i + 1] += ci;
                n[i] -= r * ci;
            }
            c = n;
        }
        c
    }

    #[test]
    fn quadratic_stable_for_tiny_root() {
        // x² - 1e8 x + 1 : roots ≈ 1e-8 and 1e8; the naive formula loses the small one.
        let r = quadratic_roots(1.0, -1e8, 1.0);
        assert_eq!(r.len(), 2);
        assert!((r.as_slice()[0] - 1e-8).abs() < 1e-22);
        assert!((r.as_slice()[1] - 1e8).abs() < 1e-6);
    }

    #[test]
    fn quadratic_degenerate_cases() {
        assert!(quadratic_roots(1.0, 0.0, 1.0).is_empty());
        assert_eq!(quadratic_roots(1.0, -2.0, 1.0).as_slice(), &[1.0]);
        assert_eq!(quadratic_roots(0.0, 2.0, -4.0).as_slice(), &[2.0]);
        assert!(quadratic_roots(0.0, 0.0, 1.0).is_empty());
        assert_eq!(quadratic_roots(1.0, 0.0, -4.0).as_slice(), &[-2.0, 2.0]);
    }

    #[test]
    fn quartic_four_simple_roots() {
        let rs = [-3.0, -0.5, 1.25, 7.0];
        let c = from_roots(&rs);
        let mut out = Vec::new();
        real_roots_in(&c, -10.0, 10.0, RootTolerance::DEFAULT, &mut out);
        assert_eq!(out.len(), 4, "{out:?}");
        for (a, b) in out.iter().zip(rs) {
            assert!((a - b).abs() < 1e-11, "{a} vs {b}");
        }
    }

    #[test]
    fn interval_clips_roots() {
        let c = from_roots(&[-3.0, -0.5, 1.25, 7.0]);
        let mut out = Vec::new();
        real_roots_in(&c, -1.0, 2.0, RootTolerance::DEFAULT, &mut out);
        assert_eq!(out.len(), 2);
        assert!((out[0] + 0.5).abs() < 1e-12 && (out[1] - 1.25).abs() < 1e-12);
    }

    #[test]
    fn double_root_reported_once() {
        // (x-1)²(x+2)(x-4): the double root is a tangency.
        let c = from_roots(&[1.0, 1.0, -2.0, 4.0]);
        let mut out = Vec::new();
        real_roots_in(&c, -5.0, 5.0, RootTolerance::DEFAULT, &mut out);
        assert_eq!(out.len(), 3, "{out:?}");
        assert!((out[1] - 1.0).abs() < 1e-7, "{out:?}");
    }

    #[test]
    fn close_roots_separated() {
        let rs = [0.3, 0.3 + 1e-6, 2.0, 5.0];
        let c = from_roots(&rs);
        let mut out = Vec::new();
        real_roots_in(&c, -1.0, 6.0, RootTolerance::DEFAULT, &mut out);
        assert_eq!(out.len(), 4, "{out:?}");
        assert!((out[0] - 0.3).abs() < 1e-9 && (out[1] - 0.3 - 1e-6).abs() < 1e-9);
    }

    #[test]
    fn no_real_roots() {
        // (x² + 1)(x² + 4)
        let c = [4.0, 0.0, 5.0, 0.0, 1.0];
        let mut out = Vec::new();
        real_roots_in(&c, -100.0, 100.0, RootTolerance::DEFAULT, &mut out);
        assert!(out.is_empty());
    }

    #[test]
    fn wilkinson_like_degree_eight() {
        let rs: Vec<Real> = (1..=8).map(|i| i as Real).collect();
        let c = from_roots(&rs);
        let mut out = Vec::new();
        real_roots_in(&c, 0.0, 9.0, RootTolerance::DEFAULT, &mut out);
        assert_eq!(out.len(), 8, "{out:?}");
        for (a, b) in out.iter().zip(&rs) {
            assert!((a - b).abs() < 1e-9, "{a} vs {b}");
        }
    }

    #[test]
    fn garbage_input_yields_nothing() {
        let mut out = Vec::new();
        real_roots_in(
            &[Real::NAN, 1.0],
            -1.0,
            1.0,
            RootTolerance::DEFAULT,
            &mut out,
        );
        real_roots_in(&[1.0, 1.0], 1.0, -1.0, RootTolerance::DEFAULT, &mut out);
        real_roots_in(&[0.0, 0.0], -1.0, 1.0, RootTolerance::DEFAULT, &mut out);
        assert!(out.is_empty());
    }

    proptest::proptest! {
        #![proptest_config(swarf_testdata::proptest_config(256))]
        #[test]
        fn finds_all_planted_roots(mut rs in proptest::collection::vec(-10.0f64..10.0, 1..=4)) {
            rs.sort_by(f64::total_cmp);
            // Keep roots separated so each must be found individually.
            for w in rs.windows(2) {
                proptest::prop_assume!(w[1] - w[0] > 1e-3);
            }
            let c = from_roots(&rs);
            let mut out = Vec::new();
            real_roots_in(&c, -11.0, 11.0, RootTolerance::DEFAULT, &mut out);
            proptest::prop_assert_eq!(out.len(), rs.len(), "{:?} vs {:?}", out, rs);
            for (a, b) in out.iter().zip(&rs) {
                // Clustered roots are ill-conditioned: rounding the coefficients' products by
                // ε moves a root by about ε·Σ|c_i||r|^i / |p'(r)| (Horner's error is within 2n
                // times that), whatever the solver does.
                let spread: f64 = c.iter().enumerate().map(|(i, ci)| ci.abs() * b.abs().powi(i as i32)).sum();
                let slope: f64 = rs.iter().filter(|r| *r != b).map(|r| (b - r).abs()).product();
                let cond = 2.0 * c.len() as f64 * f64::EPSILON * spread / slope;
                proptest::prop_assert!((a - b).abs() < 1e-8 + cond, "{} vs {} (conditioning {:e})", a, b, cond);
            }
        }
    }
}
