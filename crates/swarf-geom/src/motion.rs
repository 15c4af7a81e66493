//! Rigid motions (rotation then translation) of points and vectors.

use crate::math::{Quat, Vec3};

/// A proper rigid motion `p ↦ rotation·p + translation`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RigidMotion {
    /// Unit quaternion (normalised by the constructors).
    pub rotation: Quat,
    /// Translation applied after the rotation.
    pub translation: Vec3,
}

impl Default for RigidMotion {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl RigidMotion {
    /// The motion that moves nothing.
    pub const IDENTITY: RigidMotion = RigidMotion {
        rotation: Quat::IDENTITY,
        translation: Vec3::ZERO,
    };

    /// Rotation (normalised here) followed by translation.
    pub fn new(rotation: Quat, translation: Vec3) -> Self {
        Self {
            rotation: rotation.normalize(),
            translation,
        }
    }

    /// A pure translation.
    pub fn from_translation(t: Vec3) -> Self {
        Self::new(Quat::IDENTITY, t)
    }

    /// A rotation by `angle` radians about the line through `point` with direction `axis`.
    pub fn from_axis_angle(point: Vec3, axis: Vec3, angle: f64) -> Self {
        let q = Quat::from_axis_angle(axis.normalize(), angle);
        // p ↦ q(p - point) + point
        Self::new(q, point - q * point)
    }

    /// Moves a point.
    pub fn apply_point(&self, p: Vec3) -> Vec3 {
        self.rotation * p + self.translation
    }

    /// Moves a vector (rotation only).
    pub fn apply_vector(&self, v: Vec3) -> Vec3 {
        self.rotation * v
    }

    /// `self ∘ other`: first `other`, then `self`.
    pub fn compose(&self, other: &RigidMotion) -> RigidMotion {
        RigidMotion::new(
            self.rotation * other.rotation,
            self.rotation * other.translation + self.translation,
        )
    }

    /// The motion undoing this one.
    pub fn inverse(&self) -> RigidMotion {
        let inv = self.rotation.conjugate();
        RigidMotion::new(inv, -(inv * self.translation))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn rotation_about_offset_axis() {
        let m = RigidMotion::from_axis_angle(
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::Z,
            std::f64::consts::FRAC_PI_2,
        );
        let p = m.apply_point(Vec3::new(2.0, 0.0, 5.0));
        assert!((p - Vec3::new(1.0, 1.0, 5.0)).length() < 1e-15);
        assert!((m.apply_vector(Vec3::X) - Vec3::Y).length() < 1e-15);
    }

    proptest! {
        #![proptest_config(swarf_testdata::proptest_config(256))]
        #[test]
        fn compose_and_inverse(a in -3.0f64..3.0, b in -3.0f64..3.0, tx in -10.0f64..10.0,
                               px in -10.0f64..10.0, py in -10.0f64..10.0, pz in -10.0f64..10.0) {
            let m1 = RigidMotion::from_axis_angle(Vec3::new(tx, 1.0, 0.0), Vec3::new(1.0, 2.0, 3.0), a);
            let m2 = RigidMotion::from_axis_angle(Vec3::new(0.0, tx, 2.0), Vec3::new(-1.0, 0.5, 0.2), b);
            let p = Vec3::new(px, py, pz);
            let c = m1.compose(&m2);
            prop_assert!((c.apply_point(p) - m1.apply_point(m2.apply_point(p))).length() < 1e-12);
            prop_assert!((m1.inverse().apply_point(m1.apply_point(p)) - p).length() < 1e-12);
            // Distances are preserved.
            let q = Vec3::new(py, pz, px);
            prop_assert!(((c.apply_point(p) - c.apply_point(q)).length() - (p - q).length()).abs() < 1e-12);
        }
    }
}
