//! The scalar and vector types of swarf, chosen once for the whole workspace.
//!
//! glam's `DVec3` is the same type parry3d-f64 uses, so meshes and ray casts from parry need no
//! conversion.

/// The scalar type: every computation in swarf is double precision.
pub type Real = f64;
/// A vector or a point in 3-D space (millimetres when it is a position).
pub type Vec3 = glam::DVec3;
/// A 3×3 matrix (rotations, frames).
pub type Mat3 = glam::DMat3;
/// A unit quaternion (rotations).
pub type Quat = glam::DQuat;
/// A vector in 2-D (profiles, arcs in their plane).
pub type Vec2 = glam::DVec2;

/// Default absolute tolerance for geometric equality of lengths, in millimetres.
pub const LENGTH_EPS: Real = 1e-9;
/// Default tolerance for comparing unit vectors and angles, in radians.
pub const ANGLE_EPS: Real = 1e-12;

/// The machine range: no coordinate of a program, a stock or a tool position in swarf lies
/// farther than this from the origin, in millimetres (a kilometre; the largest machining
/// centres travel a few tens of metres). Readers refuse coordinates beyond it with their
/// position, so that no later stage meets an infinite or absurd length.
pub const MACHINE_RANGE_MM: Real = 1e6;

/// The lesser of `a` and `b` in one comparison (`b` when they compare equal, or when either is
/// NaN). `f64::min` also orders NaN, which costs several instructions a call on the baseline
/// x86-64 target; the per-ray kernels, whose operands are never NaN, use this.
#[inline(always)]
pub fn lesser(a: Real, b: Real) -> Real {
    if a < b {
        a
    } else {
        b
    }
}

/// The greater of `a` and `b` in one comparison (`b` when they compare equal, or when either
/// is NaN); see [`lesser`].
#[inline(always)]
pub fn greater(a: Real, b: Real) -> Real {
    if a > b {
        a
    } else {
        b
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Away from NaN and from a tie of ±0 (where `f64::min` may return either), `lesser` and
    /// `greater` are `f64::min` and `f64::max`; with a NaN they return the second operand,
    /// which is why callers put the value that may be NaN first only where `f64::min` would
    /// also have dropped it.
    #[test]
    fn lesser_and_greater_are_min_and_max_without_nan() {
        let xs = [
            f64::NEG_INFINITY,
            -3.5,
            -1e-300,
            -0.0,
            0.0,
            1e-300,
            2.0,
            f64::INFINITY,
        ];
        for a in xs {
            for b in xs {
                if a == b {
                    continue;
                }
                assert_eq!(lesser(a, b), a.min(b), "{a} {b}");
                assert_eq!(greater(a, b), a.max(b), "{a} {b}");
            }
        }
        assert_eq!(lesser(f64::NAN, 1.0), 1.0);
        assert_eq!(greater(f64::NAN, 1.0), 1.0);
        assert!(lesser(1.0, f64::NAN).is_nan());
        assert!(greater(1.0, f64::NAN).is_nan());
    }
}
