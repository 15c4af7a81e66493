//! STEP `PLANE`: `S(u, v) = C + u·x + v·y`, normal `z` (ISO 10303-42).

use swarf_geom::math::Vec3;
use swarf_geom::{Aabb, Frame};

use super::{Derivs, ParamBox, ParametricSurface};

/// A plane through `frame.origin` spanned by `frame.x`, `frame.y`; `S_u × S_v = frame.z`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneSurface {
    /// Position: origin and axes.
    pub frame: Frame,
    /// Parameter box, in millimetres along `x` and `y`.
    pub domain: ParamBox,
}

impl PlaneSurface {
    /// A plane patch over `domain` (u, v are lengths along `frame.x`, `frame.y`).
    pub fn new(frame: Frame, domain: ParamBox) -> Self {
        Self { frame, domain }
    }
}

impl ParametricSurface for PlaneSurface {
    fn domain(&self) -> ParamBox {
        self.domain
    }
    fn point(&self, u: f64, v: f64) -> Vec3 {
        let (u, v) = self.domain.clamp(u, v);
        self.frame.origin + u * self.frame.x + v * self.frame.y
    }
    fn derivs(&self, u: f64, v: f64) -> Derivs {
        Derivs {
            point: self.point(u, v),
            su: self.frame.x,
            sv: self.frame.y,
            suu: Vec3::ZERO,
            suv: Vec3::ZERO,
            svv: Vec3::ZERO,
        }
    }
    fn bounding_box(&self) -> Aabb {
        let d = self.domain;
        let c = [(0, 0), (0, 1), (1, 0), (1, 1)].map(|(i, j)| self.point(d.u[i], d.v[j]));
        Aabb::from_points(c).unwrap_or(Aabb::new(Vec3::ZERO, Vec3::ZERO))
    }
}
