//! Rays (half-lines or full lines parameterised by `t`).

use crate::math::Vec3;

/// The line `origin + t·dir`.
///
/// Queries return **all** parameters `t` (negative ones included: callers such as the
/// tri-dexel update treat rays as lines and clip to their own interval). `dir` need not be a
/// unit vector; `t` is then in units of `|dir|`. `dir` must be non-zero and finite.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Ray {
    /// A point of the line (`t = 0`).
    pub origin: Vec3,
    /// Direction (`t = 1` is `origin + dir`).
    pub dir: Vec3,
}

impl Ray {
    /// The line through `origin` with direction `dir`.
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Self { origin, dir }
    }

    /// The point at parameter `t`.
    pub fn at(&self, t: f64) -> Vec3 {
        self.origin + self.dir * t
    }
}
