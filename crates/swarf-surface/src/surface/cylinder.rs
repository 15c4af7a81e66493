//! STEP `CYLINDRICAL_SURFACE`: `S(u, v) = C + R(cos u·x + sin u·y) + v·z`, u the angle in
//! radians, v the height in millimetres; `S_u × S_v` points away from the axis.

use swarf_geom::math::Vec3;
use swarf_geom::{Aabb, Frame};

use super::{circle_box, Derivs, ParamBox, ParametricSurface};

/// A circular cylinder of radius `radius` around `frame.z`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CylindricalSurface {
    /// Position: `origin` on the axis, `z` the axis, `x` the direction of `u = 0`.
    pub frame: Frame,
    /// Radius, mm (> 0).
    pub radius: f64,
    /// Parameter box: u in radians, v in mm along the axis.
    pub domain: ParamBox,
}

impl CylindricalSurface {
    /// A cylinder patch; `None` unless the radius is positive and finite.
    pub fn new(frame: Frame, radius: f64, domain: ParamBox) -> Option<Self> {
        (radius > 0.0 && radius.is_finite()).then_some(Self {
            frame,
            radius,
            domain,
        })
    }
}

impl ParametricSurface for CylindricalSurface {
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
        let r = self.radius;
        Derivs {
            point: f.origin + r * e + v * f.z,
            su: r * e1,
            sv: f.z,
            suu: -r * e,
            suv: Vec3::ZERO,
            svv: Vec3::ZERO,
        }
    }
    fn bounding_box(&self) -> Aabb {
        let f = &self.frame;
        let a = circle_box(f.origin + self.domain.v[0] * f.z, f.z, self.radius);
        let b = circle_box(f.origin + self.domain.v[1] * f.z, f.z, self.radius);
        a.union(&b)
    }
}
