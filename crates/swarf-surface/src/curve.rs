//! Rational B-spline curves in model space: the edge curves of STEP faces and the trimming
//! curves of IGES surfaces, both readers evaluating them here.

use glam::DVec4;
use swarf_geom::math::Vec3;

/// A rational B-spline (NURBS) curve of degree `p ≥ 1` over knots `t_0 ≤ … ≤ t_{n+p}`, with
/// `n` control points and positive weights, defined on `[t_p, t_n]`.
///
/// ```
/// use swarf_geom::math::Vec3;
/// use swarf_surface::BSplineCurve;
/// // A quarter circle of radius 2 as a rational quadratic.
/// let w = std::f64::consts::FRAC_1_SQRT_2;
/// let pts = [Vec3::new(2.0, 0.0, 0.0), Vec3::new(2.0, 2.0, 0.0), Vec3::new(0.0, 2.0, 0.0)];
/// let c = BSplineCurve::new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0], &pts, &[1.0, w, 1.0]).unwrap();
/// assert_eq!(c.domain(), (0.0, 1.0));
/// assert!((c.point(0.3).length() - 2.0).abs() < 1e-12);
/// assert!((c.clone().reversed().point(-0.3) - c.point(0.3)).length() < 1e-12);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct BSplineCurve {
    degree: usize,
    knots: Vec<f64>,
    /// Control points times weights, and the weights: `(w·x, w·y, w·z, w)`.
    homogeneous: Vec<DVec4>,
}

/// Why numbers do not make a B-spline curve.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CurveError {
    /// Degree 0, or too few control points for the degree.
    #[error("{points} control points for degree {degree}")]
    Degree {
        /// The degree.
        degree: usize,
        /// The number of control points.
        points: usize,
    },
    /// The knot count is not control points + degree + 1.
    #[error("{knots} knots for {points} control points of degree {degree}")]
    KnotCount {
        /// The number of knots.
        knots: usize,
        /// The number of control points.
        points: usize,
        /// The degree.
        degree: usize,
    },
    /// Knots not finite, decreasing, or with an empty domain.
    #[error("knots are not increasing")]
    Knots,
    /// A weight not positive and finite, or not one per control point.
    #[error("weights must be positive, one per control point")]
    Weights,
}

impl BSplineCurve {
    /// The curve of `degree` with `knots`, control `points` and their `weights`.
    ///
    /// # Errors
    /// [`CurveError`] when the numbers do not make a curve (see its variants).
    pub fn new(
        degree: usize,
        knots: Vec<f64>,
        points: &[Vec3],
        weights: &[f64],
    ) -> Result<Self, CurveError> {
        let n = points.len();
        if degree == 0 || n < degree + 1 {
            return Err(CurveError::Degree { degree, points: n });
        }
        if knots.len() != n + degree + 1 {
            return Err(CurveError::KnotCount {
                knots: knots.len(),
                points: n,
                degree,
            });
        }
        if knots.iter().any(|k| !k.is_finite())
            || knots.windows(2).any(|w| w[1] < w[0])
            || knots[n] <= knots[degree]
        {
            return Err(CurveError::Knots);
        }
        if weights.len() != n || weights.iter().any(|w| !(*w > 0.0 && w.is_finite())) {
            return Err(CurveError::Weights);
        }
        let homogeneous = points
            .iter()
            .zip(weights)
            .map(|(p, &w)| DVec4::new(p.x * w, p.y * w, p.z * w, w))
            .collect();
        Ok(Self {
            degree,
            knots,
            homogeneous,
        })
    }

    /// The control points times their weights, and the weights: `(w·x, w·y, w·z, w)`.
    pub fn homogeneous(&self) -> &[DVec4] {
        &self.homogeneous
    }

    /// The degree.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The knots.
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// The parameter range `(t_p, t_n)`.
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[self.degree], self.knots[self.homogeneous.len()])
    }

    /// The point at `t` (clamped to the domain), by de Boor's algorithm on the homogeneous
    /// points.
    pub fn point(&self, t: f64) -> Vec3 {
        let (m, n, k) = (self.degree, self.homogeneous.len(), &self.knots);
        let t = t.clamp(k[m], k[n]);
        // The span [k_s, k_{s+1}) holding t: the last one with k_s ≤ t, moved back off empty
        // spans (t at the end of the domain, which is not empty).
        let mut s = k[..n].partition_point(|&x| x <= t).saturating_sub(1).max(m);
        while s > m && k[s] == k[s + 1] {
            s -= 1;
        }
        let mut d = [DVec4::ZERO; 8];
        let mut buf = Vec::new();
        let d: &mut [DVec4] = if m < 8 {
            &mut d[..=m]
        } else {
            buf.resize(m + 1, DVec4::ZERO);
            &mut buf
        };
        d.copy_from_slice(&self.homogeneous[s - m..=s]);
        for r in 1..=m {
            for j in (r..=m).rev() {
                let i = j + s - m;
                let den = k[i + m + 1 - r] - k[i];
                let a = if den > 0.0 { (t - k[i]) / den } else { 0.0 };
                d[j] = d[j - 1] * (1.0 - a) + d[j] * a;
            }
        }
        let h = d[m];
        Vec3::new(h.x / h.w, h.y / h.w, h.z / h.w)
    }

    /// The same points run the other way: the point at `t` is the old one at `−t`.
    #[must_use]
    pub fn reversed(self) -> Self {
        Self {
            degree: self.degree,
            knots: self.knots.iter().rev().map(|k| -k).collect(),
            homogeneous: self.homogeneous.into_iter().rev().collect(),
        }
    }
}
