//! A cheap outer bound of a fixed-axis sweep along world-axis lines: what a line query can skip.

use swarf_geom::math::Vec3;

use super::ConvexProfile;

/// A cheap outer bound of a fixed-axis sweep: the part's bounding cylinder about the axis at
/// the start (radius `ρ_max`, heights `[z_min, z_max]`) grown by the move's length, which holds
/// every point of the sweep (each is within `|δ|` of the start instance).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweepBound {
    tip: Vec3,
    axis: Vec3,
    radius: f64,
    z0: f64,
    z1: f64,
}

impl SweepBound {
    /// The bound of `prof` placed at `tip` with unit `axis`, moving by `delta`.
    pub fn new(prof: &ConvexProfile, tip: Vec3, axis: Vec3, delta: Vec3) -> Self {
        let g = delta.length() + BOUND_SLACK_MM;
        Self {
            tip,
            axis: axis.normalize(),
            radius: prof.r_max() + g,
            z0: prof.z_min() - g,
            z1: prof.z_max() + g,
        }
    }

    /// The range of world coordinate along axis `k` of the line through `o` (`o[k]` = 0)
    /// inside the bound, `None` when it misses.
    pub fn range(&self, o: Vec3, k: usize) -> Option<(f64, f64)> {
        let p0 = o - self.tip;
        let ak = self.axis[k];
        let zo = p0.dot(self.axis);
        // Slab of heights.
        let (mut lo, mut hi) = if ak.abs() < 1e-12 {
            if zo < self.z0 || zo > self.z1 {
                return None;
            }
            (f64::NEG_INFINITY, f64::INFINITY)
        } else {
            let (a, b) = ((self.z0 - zo) / ak, (self.z1 - zo) / ak);
            (a.min(b), a.max(b))
        };
        // Infinite cylinder: |q0 + t w|² ≤ r² with w the line direction across the axis.
        let q0 = p0 - self.axis * zo;
        let mut w = Vec3::ZERO;
        w[k] = 1.0;
        let w = w - self.axis * ak;
        let (aa, bb, cc) = (w.dot(w), q0.dot(w), q0.dot(q0) - self.radius * self.radius);
        if aa < 1e-12 {
            if cc > 0.0 {
                return None;
            }
        } else {
            let disc = bb * bb - aa * cc;
            if disc < 0.0 {
                return None;
            }
            let sq = disc.sqrt();
            lo = lo.max((-bb - sq) / aa);
            hi = hi.min((-bb + sq) / aa);
        }
        (lo <= hi).then_some((lo, hi))
    }
}

/// Growth (mm) of [`SweepBound`] beyond the exact bound, against rounding.
const BOUND_SLACK_MM: f64 = 1e-6;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SweptConvex;

    #[test]
    fn bound_holds_the_sweep() {
        let c = swarf_tool::Cutter::bull(8.0, 2.0).unwrap();
        let shape = crate::ToolShape::new(&c);
        let prof = &shape.cutting().parts()[0];
        let tip = Vec3::new(1.0, -2.0, 0.5);
        let axis = Vec3::new(0.3, 0.2, 1.0).normalize();
        let delta = Vec3::new(0.4, 0.1, -0.2);
        let sw = SweptConvex::new(prof, tip, axis, delta);
        let b = SweepBound::new(prof, tip, axis, delta);
        let mut hits = 0;
        for k in 0..3 {
            for i in 0..40 {
                for j in 0..40 {
                    let mut o = Vec3::ZERO;
                    o[(k + 1) % 3] = -10.0 + 0.5 * i as f64;
                    o[(k + 2) % 3] = -10.0 + 0.5 * j as f64;
                    if let Some((lo, hi)) = sw.axis_ray_interval(o, k) {
                        let (blo, bhi) = b.range(o, k).expect("the bound holds the sweep");
                        assert!(blo <= lo && bhi >= hi);
                        hits += 1;
                    }
                }
            }
        }
        assert!(hits > 500);
    }
}
