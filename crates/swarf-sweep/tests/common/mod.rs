//! Helpers shared by the integration tests (here and in `swarf-envelope`): a tiny deterministic
//! generator and the cutters of every type.
#![allow(dead_code, unreachable_pub)]

use swarf_geom::math::Vec3;
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
