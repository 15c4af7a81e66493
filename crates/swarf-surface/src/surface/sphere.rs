//! STEP `SPHERICAL_SURFACE`: `S(u, v) = C + R·cos v·(cos u·x + sin u·y) + R·sin v·z`, u the
//! longitude and v the latitude in radians; `S_u × S_v` points outwards. The poles
//! (`v = ±π/2`) are degenerate points with a limit normal.

use swarf_geom::math::Vec3;
use swarf_geom::{Aabb, Frame};

use super::{Derivs, ParamBox, ParametricSurface};

/// A sphere of radius `radius` centred at `frame.origin`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphericalSurface {
    /// Centre and axes (`z` through the poles, `x` at `u = 0`).
    pub frame: Frame,
    /// Radius, mm (> 0).
    pub radius: f64,
    /// Parameter box in radians, within `[−π/2, π/2]` for v.
    pub domain: ParamBox,
}

impl SphericalSurface {
    /// The whole sphere: `u ∈ [0, 2π]`, `v ∈ [−π/2, π/2]`.
    pub const FULL: ParamBox = ParamBox {
        u: [0.0, std::f64::consts::TAU],
        v: [-std::f64::consts::FRAC_PI_2, std::f64::consts::FRAC_PI_2],
    };

    /// A sphere patch; `None` unless the radius is positive and finite.
    pub fn new(frame: Frame, radius: f64, domain: ParamBox) -> Option<Self> {
        (radius > 0.0 && radius.is_finite()).then_some(Self {
            frame,
            radius,
            domain,
        })
    }
}

impl ParametricSurface for SphericalSurface {
    fn domain(&self) -> ParamBox {
        self.domain
    }
    fn point(&self, u: f64, v: f64) -> Vec3 {
        self.derivs(u, v).point
    }
    fn derivs(&self, u: f64, v: f64) -> Derivs {
        let (u, v) = self.domain.clamp(u, v);
        let f = &self.frame;
        let (su_, cu) = u.sin_cos();
        let (sv_, cv) = v.sin_cos();
        let e = cu * f.x + su_ * f.y;
        let e1 = -su_ * f.x + cu * f.y;
        let r = self.radius;
        Derivs {
            point: f.origin + r * cv * e + r * sv_ * f.z,
            su: r * cv * e1,
            sv: -r * sv_ * e + r * cv * f.z,
            suu: -r * cv * e,
            suv: -r * sv_ * e1,
            svv: -r * cv * e - r * sv_ * f.z,
        }
    }
    fn bounding_box(&self) -> Aabb {
        let c = self.frame.origin;
        Aabb::new(c - Vec3::splat(self.radius), c + Vec3::splat(self.radius))
    }
}
