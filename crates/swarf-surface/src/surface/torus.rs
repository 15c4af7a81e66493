//! STEP `TOROIDAL_SURFACE`: `S(u, v) = C + (R + r·cos v)(cos u·x + sin u·y) + r·sin v·z`, both
//! angles in radians; `S_u × S_v` points away from the tube's centre circle.

use swarf_geom::math::Vec3;
use swarf_geom::{Aabb, Frame};

use super::{Derivs, ParamBox, ParametricSurface};

/// A torus around `frame.z`: major radius `major`, tube radius `minor`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToroidalSurface {
    /// Centre and axes.
    pub frame: Frame,
    /// Major radius R, mm (> 0).
    pub major: f64,
    /// Minor (tube) radius r, mm (> 0).
    pub minor: f64,
    /// Parameter box in radians.
    pub domain: ParamBox,
}

impl ToroidalSurface {
    /// The whole torus: `u, v ∈ [0, 2π]`.
    pub const FULL: ParamBox = ParamBox {
        u: [0.0, std::f64::consts::TAU],
        v: [0.0, std::f64::consts::TAU],
    };

    /// A torus patch; `None` unless both radii are positive and finite.
    pub fn new(frame: Frame, major: f64, minor: f64, domain: ParamBox) -> Option<Self> {
        let ok = major > 0.0 && minor > 0.0 && major.is_finite() && minor.is_finite();
        ok.then_some(Self {
            frame,
            major,
            minor,
            domain,
        })
    }
}

impl ParametricSurface for ToroidalSurface {
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
        let (big, r) = (self.major, self.minor);
        let rho = big + r * cv;
        Derivs {
            point: f.origin + rho * e + r * sv_ * f.z,
            su: rho * e1,
            sv: -r * sv_ * e + r * cv * f.z,
            suu: -rho * e,
            suv: -r * sv_ * e1,
            svv: -r * cv * e - r * sv_ * f.z,
        }
    }
    fn bounding_box(&self) -> Aabb {
        let f = &self.frame;
        let axis = f.z;
        let ext = Vec3::new(
            (self.major + self.minor) * (1.0 - axis.x * axis.x).max(0.0).sqrt()
                + self.minor * axis.x.abs(),
            (self.major + self.minor) * (1.0 - axis.y * axis.y).max(0.0).sqrt()
                + self.minor * axis.y.abs(),
            (self.major + self.minor) * (1.0 - axis.z * axis.z).max(0.0).sqrt()
                + self.minor * axis.z.abs(),
        );
        Aabb::new(f.origin - ext, f.origin + ext)
    }
}
