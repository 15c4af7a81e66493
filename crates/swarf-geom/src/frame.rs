//! Right-handed orthonormal frames: where a local coordinate system sits in the world.

use crate::math::{Mat3, Quat, Vec3};
use crate::motion::RigidMotion;

/// A right-handed orthonormal coordinate system placed in the world.
///
/// `to_world(p) = origin + p.x·x + p.y·y + p.z·z`. Primitives and cutters are described in a
/// local frame whose `z` axis is their axis of revolution.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Frame {
    /// Origin of the frame, in world coordinates.
    pub origin: Vec3,
    /// Unit x axis.
    pub x: Vec3,
    /// Unit y axis (`z × x`).
    pub y: Vec3,
    /// Unit z axis.
    pub z: Vec3,
}

impl Default for Frame {
    fn default() -> Self {
        Self::WORLD
    }
}

impl Frame {
    /// The world frame itself.
    pub const WORLD: Frame = Frame {
        origin: Vec3::ZERO,
        x: Vec3::X,
        y: Vec3::Y,
        z: Vec3::Z,
    };

    /// A frame at `origin` whose z axis is `z` (normalised here; must be non-zero and finite).
    ///
    /// The x and y axes come from Duff et al.'s branchless construction ("Building an
    /// orthonormal basis, revisited", 2017, via glam's `any_orthonormal_pair`), which is accurate
    /// for every direction, including `z = ±Z`, unlike "cross with a fixed helper vector"
    /// schemes that degenerate when the axis is parallel to the helper.
    pub fn from_axis(origin: Vec3, z: Vec3) -> Frame {
        let z = z.normalize();
        let (x, y) = z.any_orthonormal_pair();
        Frame { origin, x, y, z }
    }

    /// A frame at `origin` with z axis `z` and x axis as close to `x_hint` as possible
    /// (Gram–Schmidt). Falls back to [`Frame::from_axis`] when `x_hint` is parallel to `z`.
    pub fn from_axis_and_x(origin: Vec3, z: Vec3, x_hint: Vec3) -> Frame {
        let z = z.normalize();
        let x = x_hint - z * z.dot(x_hint);
        if x.length_squared() <= 1e-24 * x_hint.length_squared().max(1e-300) {
            return Frame::from_axis(origin, z);
        }
        let x = x.normalize();
        Frame {
            origin,
            x,
            y: z.cross(x),
            z,
        }
    }

    /// The world frame moved to `origin` (axes unchanged).
    pub fn at(origin: Vec3) -> Frame {
        Frame {
            origin,
            ..Frame::WORLD
        }
    }

    /// Rotation matrix whose columns are the axes (local → world for vectors).
    pub fn matrix(&self) -> Mat3 {
        Mat3::from_cols(self.x, self.y, self.z)
    }

    /// Rotation part as a unit quaternion.
    pub fn rotation(&self) -> Quat {
        Quat::from_mat3(&self.matrix()).normalize()
    }

    /// The rigid motion mapping local coordinates to world coordinates.
    pub fn to_motion(&self) -> RigidMotion {
        RigidMotion::new(self.rotation(), self.origin)
    }

    /// This frame moved by `m` (origin and axes).
    pub fn transformed(&self, m: &RigidMotion) -> Frame {
        Frame {
            origin: m.apply_point(self.origin),
            x: m.apply_vector(self.x),
            y: m.apply_vector(self.y),
            z: m.apply_vector(self.z),
        }
    }

    /// World point → local coordinates.
    pub fn to_local(&self, p: Vec3) -> Vec3 {
        self.vector_to_local(p - self.origin)
    }

    /// Local coordinates → world point.
    pub fn to_world(&self, p: Vec3) -> Vec3 {
        self.origin + self.vector_to_world(p)
    }

    /// World vector → local components (no translation).
    pub fn vector_to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.x), v.dot(self.y), v.dot(self.z))
    }

    /// Local components → world vector (no translation).
    pub fn vector_to_world(&self, v: Vec3) -> Vec3 {
        self.x * v.x + self.y * v.y + self.z * v.z
    }

    /// Largest deviation from orthonormality and right-handedness (0 for a perfect frame).
    pub fn orthonormality_error(&self) -> f64 {
        let e = [
            (self.x.length() - 1.0).abs(),
            (self.y.length() - 1.0).abs(),
            (self.z.length() - 1.0).abs(),
            self.x.dot(self.y).abs(),
            self.y.dot(self.z).abs(),
            self.z.dot(self.x).abs(),
            (self.x.cross(self.y) - self.z).length(),
        ];
        e.into_iter().fold(0.0, f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn axis_parallel_to_world_axes() {
        for z in [Vec3::Z, -Vec3::Z, Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y] {
            let f = Frame::from_axis(Vec3::new(1.0, 2.0, 3.0), z);
            assert!(f.orthonormality_error() < 1e-15, "{z}");
            assert!((f.z - z).length() < 1e-15);
        }
    }

    #[test]
    fn axis_and_x_hint() {
        let f = Frame::from_axis_and_x(
            Vec3::ZERO,
            Vec3::new(0.0, 0.0, 2.0),
            Vec3::new(1.0, 0.0, 5.0),
        );
        assert!((f.x - Vec3::X).length() < 1e-15 && (f.y - Vec3::Y).length() < 1e-15);
        let g = Frame::from_axis_and_x(Vec3::ZERO, Vec3::Z, Vec3::Z);
        assert!(g.orthonormality_error() < 1e-15);
    }

    proptest! {
        #![proptest_config(swarf_testdata::proptest_config(256))]
        #[test]
        fn round_trip(zx in -1.0f64..1.0, zy in -1.0f64..1.0, zz in -1.0f64..1.0,
                      px in -100.0f64..100.0, py in -100.0f64..100.0, pz in -100.0f64..100.0) {
            let z = Vec3::new(zx, zy, zz);
            prop_assume!(z.length() > 1e-3);
            let f = Frame::from_axis(Vec3::new(3.0, -2.0, 7.0), z);
            prop_assert!(f.orthonormality_error() < 1e-14);
            let p = Vec3::new(px, py, pz);
            prop_assert!((f.to_world(f.to_local(p)) - p).length() < 1e-12);
            prop_assert!((f.vector_to_world(f.vector_to_local(p)) - p).length() < 1e-12);
            // The motion of the frame agrees with to_world.
            let m = f.to_motion();
            prop_assert!((m.apply_point(p) - f.to_world(p)).length() < 1e-11);
        }
    }
}
