//! STEP `CONICAL_SURFACE`: `S(u, v) = C + (R + v·tan α)(cos u·x + sin u·y) + v·z`, u the angle
//! in radians, v the height in millimetres along the axis, α the semi-angle; `S_u × S_v` points
//! away from the axis. The apex (`R + v·tan α = 0`) is a degenerate point.

use swarf_geom::math::Vec3;
use swarf_geom::{Aabb, Frame};

use super::{circle_box, Derivs, ParamBox, ParametricSurface};

/// A circular cone around `frame.z` with radius `radius` at `v = 0` and semi-angle
/// `semi_angle`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConicalSurface {
    /// Position: `origin` on the axis where the radius is `radius`, `z` the axis.
    pub frame: Frame,
    /// Radius at `v = 0`, mm (≥ 0).
    pub radius: f64,
    /// Semi-angle α in radians, `0 < α < π/2`.
    pub semi_angle: f64,
    /// Parameter box: u in radians, v in mm along the axis.
    pub domain: ParamBox,
}

impl ConicalSurface {
    /// A cone patch; `None` unless `radius ≥ 0` and `0 < semi_angle < π/2`.
    pub fn new(frame: Frame, radius: f64, semi_angle: f64, domain: ParamBox) -> Option<Self> {
        let ok = radius >= 0.0
            && radius.is_finite()
            && semi_angle > 0.0
            && semi_angle < std::f64::consts::FRAC_PI_2;
        ok.then_some(Self {
            frame,
            radius,
            semi_angle,
            domain,
        })
    }

    fn radius_at(&self, v: f64) -> f64 {
        self.radius + v * self.semi_angle.tan()
    }
}

impl ParametricSurface for ConicalSurface {
    fn domain(&self) -> ParamBox {
        self.domain
    }
    fn point(&self, u: f64, v: f64) -> Vec3 {
        self.derivs(u, v).point
    }
    fn derivs(&self, u: f64, v: f64) -> Derivs {
        let (u, v) = self.domain.clamp(u, v);
        let f = &self.frame;
        let (s, c) = u.sin_cos();
        let e = c * f.x + s * f.y;
        let e1 = -s * f.x + c * f.y;
        let t = self.semi_angle.tan();
        let r = self.radius_at(v);
        Derivs {
            point: f.origin + r * e + v * f.z,
            su: r * e1,
            sv: t * e + f.z,
            suu: -r * e,
            suv: t * e1,
            svv: Vec3::ZERO,
        }
    }
    fn bounding_box(&self) -> Aabb {
        let f = &self.frame;
        let [v0, v1] = self.domain.v;
        let a = circle_box(f.origin + v0 * f.z, f.z, self.radius_at(v0).abs());
        let b = circle_box(f.origin + v1 * f.z, f.z, self.radius_at(v1).abs());
        let mut bb = a.union(&b);
        let apex_v = -self.radius / self.semi_angle.tan();
        if apex_v > v0 && apex_v < v1 {
            bb = bb.extended(f.origin + apex_v * f.z);
        }
        bb
    }
}
