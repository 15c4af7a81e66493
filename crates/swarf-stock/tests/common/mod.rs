//! Helpers shared by the scenario tests.
#![allow(dead_code, unreachable_pub)]

use swarf_geom::math::{Vec2, Vec3};
use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::{Axes, FeedMode, Machine, Move, MoveKind, Pose, Program};
use swarf_sweep::Element;
use swarf_tool::Cutter;

/// Reads G-code text on a 3-axis machine.
pub fn gcode(text: &str) -> Program {
    read_program_str(
        text,
        "test.ngc",
        Machine::three_axis(),
        &ReadOptions::default(),
    )
    .unwrap()
}

/// A program of straight feed moves (or rapids) through `tips` with a fixed `axis`, one
/// move per line starting at line 1.
pub fn moves(tips: &[Vec3], axis: Vec3, rapid: bool) -> Program {
    let mut p = Program {
        files: vec!["test.cl".into()],
        ..Program::default()
    };
    for (i, w) in tips.windows(2).enumerate() {
        p.moves.push(Move {
            kind: if rapid {
                MoveKind::Rapid
            } else {
                MoveKind::Linear
            },
            start: Pose { tip: w[0], axis },
            end: Pose { tip: w[1], axis },
            start_joints: Axes::default(),
            end_joints: Axes::default(),
            feed: 100.0,
            feed_mode: FeedMode::PerMinute,
            spindle_rpm: 10000.0,
            spindle_dir: swarf_path::SpindleDir::Clockwise,
            tool: 1,
            file: 0,
            line: i as u32 + 1,
            axis_source: Default::default(),
            tcp: false,
            rotary_feed_combined: None,
        });
    }
    p
}

/// Relative error.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// A tiny deterministic generator (keeps the tests reproducible without extra crates).
pub struct Lcg(pub u64);

impl Lcg {
    /// Uniform in [0, 1).
    pub fn next_f64(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64) / ((1u64 << 53) as f64)
    }

    /// Uniform in [a, b).
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next_f64()
    }

    /// A uniformly distributed unit vector.
    pub fn unit(&mut self) -> Vec3 {
        loop {
            let v = Vec3::new(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            let l = v.length();
            if l > 0.1 && l <= 1.0 {
                return v / l;
            }
        }
    }

    /// A unit vector within `max_deg` of +Z.
    pub fn axis(&mut self, max_deg: f64) -> Vec3 {
        let tilt = self.range(0.0, max_deg).to_radians();
        let az = self.range(0.0, std::f64::consts::TAU);
        Vec3::new(tilt.sin() * az.cos(), tilt.sin() * az.sin(), tilt.cos())
    }
}

/// Distance from `(ρ, z)` to a cutter's profile curve (the solid's boundary in the meridian
/// plane): the reference the brute-force tests measure sampled tools with.
pub fn boundary_distance(els: &[Element], rho: f64, z: f64) -> f64 {
    let p = Vec2::new(rho, z);
    let mut best = f64::INFINITY;
    for el in els {
        let d = match *el {
            Element::Line { p: a, q: b } => {
                let ab = b - a;
                let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
                (a + ab * t - p).length()
            }
            Element::Arc {
                e,
                f,
                r,
                phi0,
                phi1,
            } => {
                let c0 = Vec2::new(e, f);
                let q = p - c0;
                // Polar angle measured from straight down, towards +ρ.
                let phi = q.x.atan2(-q.y);
                if phi >= phi0 && phi <= phi1 {
                    (q.length() - r).abs()
                } else {
                    let pt = |a: f64| c0 + Vec2::new(r * a.sin(), -r * a.cos());
                    (pt(phi0) - p).length().min((pt(phi1) - p).length())
                }
            }
        };
        best = best.min(d);
    }
    best
}

/// A general APT cutter of diameter `d`, corner `r` and height `h`: bottom cone α = 10°, torus
/// corner, back-tapered side β = −5° (e and f as the APT relations imply).
pub fn general_apt(d: f64, r: f64, h: f64) -> Cutter {
    let (a, b) = (10f64.to_radians(), -5f64.to_radians());
    let e = d / 2.0 - r * b.cos();
    let f = (r + e * a.sin()) / a.cos();
    Cutter::apt(d, r, e, f, 10.0, -5.0, h).unwrap()
}

/// One cutter of every kind, diameter drawn in `[d_lo, d_hi)`, then `general`.
pub fn every_cutter_kind(rng: &mut Lcg, d_lo: f64, d_hi: f64, general: Cutter) -> Vec<Cutter> {
    let d = rng.range(d_lo, d_hi);
    vec![
        Cutter::flat(d).unwrap(),
        Cutter::ball(d).unwrap(),
        Cutter::bull(d, rng.range(0.1, 0.45) * d).unwrap(),
        Cutter::taper_flat(d, rng.range(1.0, 15.0)).unwrap(),
        Cutter::taper_ball(d, rng.range(1.0, 15.0)).unwrap(),
        Cutter::chamfer(d, rng.range(60.0, 120.0)).unwrap(),
        Cutter::drill(d, rng.range(100.0, 140.0)).unwrap(),
        general,
    ]
}
