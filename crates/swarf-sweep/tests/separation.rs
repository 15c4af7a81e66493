//! The separating-plane skip of the stock update's general query (`SweptConvex::dexel_cut`,
//! `separation.rs`): a ray whose material the sweep would cut is never skipped — checked by
//! brute force against the exact interval, for every cutter kind (APT's generic one too), moves level, rising,
//! oblique, along the axis and on tilted axes, and material ending at many distances from the
//! sweep on either side, with one scratch shared by all the rays (and by two sweeps queried in
//! turn, as the workers of a cut do), so the planes kept from earlier rays are put to the test
//! too. And the skip must be worth having: most rays whose material stays clear of the sweep
//! by a tenth of a millimetre are skipped (counted on the sweeps that take the general query).

mod common;

use swarf_geom::math::Vec3;
use swarf_sweep::swept::{Interval, Scratch};
use swarf_sweep::{SweptConvex, ToolShape};

/// `(axis, move)` pairs: tilted axes (the general query's own case), a world axis with an
/// oblique move, a static instance.
fn moves() -> Vec<(Vec3, Vec3)> {
    let tilted = Vec3::new(0.3, -0.2, 1.0).normalize();
    let steep = Vec3::new(-0.7, 0.4, 0.6).normalize();
    vec![
        (tilted, Vec3::new(0.6, 0.1, -0.2)),
        (tilted, Vec3::new(0.02, -0.01, 0.0)),
        (steep, Vec3::new(-0.3, -0.5, 0.4)),
        (steep, Vec3::ZERO),
        (Vec3::Z, Vec3::new(0.5, 0.2, 0.3)),
        (Vec3::Z, Vec3::new(0.0, 0.0, -0.6)),
    ]
}

/// Where the material ends relative to the exact chord's end (mm; negative: short of it, i.e.
/// inside the sweep).
const OFFSETS: [f64; 10] = [-0.5, -1e-3, -1e-6, 1e-9, 1e-6, 1e-4, 1e-3, 0.05, 0.3, 2.0];

/// (rays whose material stays at least 0.1 mm clear of the sweep, of those skipped).
fn check(sweeps: [&SweptConvex<'_>; 2], k: usize, h: f64, scratch: &mut Scratch) -> (u32, u32) {
    let rays = sweeps.map(|s| s.dexel_rays(k));
    let bb = sweeps[0].bbox();
    let (u, w) = ((k + 1) % 3, (k + 2) % 3);
    let (mut clear, mut skipped) = (0, 0);
    let steps = |a: usize| ((bb.max[a] - bb.min[a]) / h).ceil() as usize;
    for i in 0..=steps(u) {
        for j in 0..=steps(w) {
            // The two sweeps in turn on one scratch.
            for (sweep, rays) in sweeps.iter().zip(&rays) {
                let mut o = Vec3::ZERO;
                o[u] = bb.min[u] + i as f64 * h;
                o[w] = bb.min[w] + j as f64 * h;
                let Some((lo, hi)) = sweep.axis_ray_interval(o, k) else {
                    continue;
                };
                let far = bb.max[k] - bb.min[k] + 10.0;
                for (n, off) in OFFSETS.iter().enumerate() {
                    // Material below the chord, above it, or both (ending `off` short of or
                    // beyond its ends).
                    let below = Interval {
                        enter: lo - far,
                        exit: lo - off,
                    };
                    let above = Interval {
                        enter: hi + off,
                        exit: hi + far,
                    };
                    let material: Vec<Interval> = match n % 3 {
                        0 => vec![below],
                        1 => vec![above],
                        _ => vec![below, above],
                    }
                    .into_iter()
                    .filter(|iv| iv.exit > iv.enter)
                    .collect();
                    if material.is_empty() {
                        continue;
                    }
                    let meets = material
                        .iter()
                        .any(|iv| iv.exit.min(hi) - iv.enter.max(lo) > 1e-7);
                    let (_, hit) = sweep.dexel_cut((o[u], o[w]), k, &material, rays, scratch);
                    if meets {
                        let cuts = hit.is_some_and(|(a, b)| {
                            material
                                .iter()
                                .any(|iv| iv.exit.min(b) - iv.enter.max(a) > 1e-7)
                        });
                        assert!(
                            cuts,
                            "family {k}, ray ({}, {}): chord ({lo}, {hi}) meets the material \
                             {material:?}, the query gave {hit:?}",
                            o[u], o[w]
                        );
                    }
                    if *off >= 0.1 {
                        clear += 1;
                        skipped += u32::from(hit.is_none());
                    }
                }
            }
        }
    }
    (clear, skipped)
}

#[test]
fn no_ray_the_sweep_cuts_is_skipped_and_most_clear_ones_are() {
    let tip = Vec3::new(1.0, 2.0, 3.0);
    let (mut clear, mut skipped) = (0, 0);
    let mut scratch = Scratch::new();
    for (_, c) in common::cutters() {
        let tool = ToolShape::new(&c);
        for (axis, v) in moves() {
            for shape in [tool.cutting(), tool.non_cutting()] {
                for p in shape.parts() {
                    let sweep = SweptConvex::new(p, tip, axis, v);
                    // A second sweep a little further along, queried in turn with the first.
                    let next = SweptConvex::new(p, tip + v, axis, v);
                    for k in 0..3 {
                        let (c, s) = check([&sweep, &next], k, 0.23, &mut scratch);
                        // The skip is the general query's: a closed form answers every ray
                        // (its chord, which the stock update then finds clear of the material).
                        if !sweep.has_closed_form() {
                            clear += c;
                            skipped += s;
                        }
                    }
                }
            }
        }
    }
    assert!(clear > 10_000, "{clear}");
    let share = f64::from(skipped) / f64::from(clear);
    assert!(
        share > 0.8,
        "{skipped} of {clear} clear rays skipped ({share:.3})"
    );
}
