//! The benchmarks' part: a compound surface of 24 bicubic patches (a 6 × 4 mould-like height
//! field with pockets, a rib and a gentle wave, 60 × 40 mm).
#![allow(dead_code, unreachable_pub)]

use swarf_geom::math::Vec3;
use swarf_surface::{CompoundSurface, NurbsSurface, Patch, Surface};

/// The height field: two pockets, a rib and a gentle wave (mm).
pub fn height(x: f64, y: f64) -> f64 {
    let pocket = |cx: f64, cy: f64, r: f64, d: f64| {
        let q = ((x - cx).powi(2) + (y - cy).powi(2)) / (r * r);
        -d * (-q).exp()
    };
    8.0 + pocket(20.0, 15.0, 9.0, 6.0)
        + pocket(45.0, 25.0, 7.0, 5.0)
        + 4.0 * (-((x - 33.0) / 2.5).powi(2)).exp()
        + 0.8 * (x / 9.0).sin() * (y / 7.0).cos()
}

/// 6 × 4 patches of 10 × 10 mm, each a bicubic Bézier through the height field; patch
/// `4a + b` covers `[10a, 10a + 10] × [10b, 10b + 10]` with `x = 10a + 10u`, `y = 10b + 10v`.
pub fn mould() -> CompoundSurface {
    let knots = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
    let mut patches = Vec::new();
    for a in 0..6 {
        for b in 0..4 {
            let (x0, y0) = (10.0 * a as f64, 10.0 * b as f64);
            let pts: Vec<Vec<Vec3>> = (0..4)
                .map(|i| {
                    (0..4)
                        .map(|j| {
                            let (x, y) = (x0 + 10.0 * i as f64 / 3.0, y0 + 10.0 * j as f64 / 3.0);
                            Vec3::new(x, y, height(x, y))
                        })
                        .collect()
                })
                .collect();
            let s = NurbsSurface::new(3, 3, knots.clone(), knots.clone(), &pts, None).unwrap();
            patches.push(Patch::new(Surface::Nurbs(s)));
        }
    }
    CompoundSurface::new(patches)
}
