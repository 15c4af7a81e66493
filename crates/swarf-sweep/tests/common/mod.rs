//! Helpers shared by the integration tests (here and in `swarf-envelope`): a tiny deterministic
//! generator and the cutters of every type.
#![allow(dead_code, unreachable_pub)]

use swarf_geom::math::Vec3;
use swarf_geom::Aabb;
use swarf_sweep::SweptConvex;
use swarf_tool::Cutter;

/// xorshift64*: deterministic, no dependency.
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
    /// One of `0..n`.
    pub fn pick(&mut self, n: usize) -> usize {
        ((self.next() * n as f64) as usize).min(n - 1)
    }
    /// A point of the box `bb` grown by `margin` times its size on every side.
    pub fn point_in(&mut self, bb: &Aabb, margin: f64) -> Vec3 {
        let (a, b) = (-margin, 1.0 + margin);
        bb.min + (bb.max - bb.min) * Vec3::new(self.range(a, b), self.range(a, b), self.range(a, b))
    }
    /// A point within `half` of `centre` across world axis `k`.
    pub fn across(&mut self, centre: Vec3, k: usize, half: f64) -> Vec3 {
        let mut o = centre;
        o[(k + 1) % 3] += self.range(-half, half);
        o[(k + 2) % 3] += self.range(-half, half);
        o
    }
    pub fn unit(&mut self) -> Vec3 {
        loop {
            let v = Vec3::new(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            if v.length() > 0.1 && v.length() < 1.0 {
                return v.normalize();
            }
        }
    }
}

/// One cutter of every type, named.
pub fn cutters() -> Vec<(&'static str, Cutter)> {
    vec![
        ("flat", Cutter::flat(6.0).unwrap()),
        ("ball", Cutter::ball(6.0).unwrap()),
        ("bull", Cutter::bull(8.0, 1.5).unwrap()),
        ("taper_flat", Cutter::taper_flat(4.0, 8.0).unwrap()),
        ("taper_ball", Cutter::taper_ball(4.0, 8.0).unwrap()),
        ("chamfer", Cutter::chamfer(8.0, 90.0).unwrap()),
        ("drill", Cutter::drill(6.0, 118.0).unwrap()),
        ("generic", generic()),
    ]
}

/// Aras's generic cutter: lower cone, corner torus and an upper cone (APT α = 20°, β = 10°).
pub fn generic() -> Cutter {
    let (d, r, a, b) = (10.0f64, 2.0f64, 20f64.to_radians(), 10f64.to_radians());
    let e = d / 2.0 - r * b.cos();
    let f = (r + e * a.sin()) / a.cos();
    Cutter::apt(d, r, e, f, 20.0, 10.0, 25.0).unwrap()
}

/// A line's interval inside a solid, `None` when it misses.
pub type Chord = Option<(f64, f64)>;

/// How far two answers for one line (its interval inside a solid, or a miss) differ: the larger
/// difference of their ends, 0 when both miss; `None` when one misses and the other holds more
/// than a tangent's 1e-6 mm (only a tangent line may be seen by one and not the other).
pub fn chord_difference(a: Chord, b: Chord) -> Option<f64> {
    match (a, b) {
        (None, None) => Some(0.0),
        (Some(x), Some(y)) => Some((x.0 - y.0).abs().max((x.1 - y.1).abs())),
        (Some(x), None) | (None, Some(x)) => (x.1 - x.0 <= 1e-6).then_some(0.0),
    }
}

/// The ray along world axis `k` through `p` against `sw`: the closed-form answer
/// ([`SweptConvex::axis_ray_interval`]), the general candidates' ([`SweptConvex::ray_interval`])
/// and how far they differ ([`chord_difference`]).
pub fn both_answers(sw: &SweptConvex<'_>, p: Vec3, k: usize) -> (Chord, Chord, Option<f64>) {
    let fast = sw.axis_ray_interval(p, k);
    let mut o = p;
    o[k] = 0.0;
    let general = sw.ray_interval(o, Vec3::AXES[k]);
    (fast, general, chord_difference(fast, general))
}
