//! The closed-form kernels (slab, ball-end and bull-nose profiles, tool axis along a world axis,
//! rays along world axes) against the general exact candidates of the same sweep, on random
//! moves of random cutters, special moves included (plunge and retract along the axis, moves
//! along and across each ray family, zero length): the two agree to 1e-9 mm.

use swarf_geom::math::Vec3;
use swarf_sweep::{ConvexProfile, SweepShape, SweptConvex};
use swarf_tool::Cutter;

mod common;
use common::{both_answers, Rng};

/// Worst disagreement, and the count of compared hits, between the two paths on `rays`
/// random axis-aligned rays near the sweep of `prof`.
fn compare(
    prof: &ConvexProfile,
    tip: Vec3,
    axis: Vec3,
    delta: Vec3,
    rng: &mut Rng,
    rays: usize,
) -> (f64, usize) {
    let sw = SweptConvex::new(prof, tip, axis, delta);
    assert!(sw.has_closed_form(), "{:?} axis {axis}", prof.elements());
    let bb = sw.bbox();
    let (mut worst, mut hits) = (0.0f64, 0);
    for _ in 0..rays {
        let k = rng.pick(3);
        let p = rng.point_in(&bb, 0.1);
        let (fast, general, e) = both_answers(&sw, p, k);
        assert!(
            e.is_some_and(|e| e <= 1e-9),
            "{:?}: tip {tip} axis {axis} delta {delta}, ray along {k} through {p}: fast {fast:?} vs general {general:?}",
            prof.elements()
        );
        if fast.is_some() && general.is_some() {
            worst = worst.max(e.unwrap_or(0.0));
            hits += 1;
        }
    }
    (worst, hits)
}

fn cutters(rng: &mut Rng) -> Vec<Cutter> {
    let d = rng.range(1.0, 20.0);
    let fl = rng.range(1.0, 4.0) * d;
    let r = rng.range(0.05, 0.45) * d;
    [
        "ball".to_string(),
        "flat".to_string(),
        format!("bull:r={r}"),
    ]
    .iter()
    .flat_map(|kind| {
        let (kind, extra) = kind.split_once(':').unwrap_or((kind, ""));
        let extra = if extra.is_empty() {
            String::new()
        } else {
            format!(",{extra}")
        };
        [
            format!("{kind}:d={d}{extra}"),
            format!("{kind}:d={d},flute-length={fl}{extra}"),
        ]
    })
    .map(|spec| Cutter::from_spec(&spec).unwrap())
    .collect()
}

#[test]
fn closed_form_matches_general_candidates() {
    let mut rng = Rng(0xfa57_2026);
    let (mut worst, mut hits) = (0.0f64, 0);
    for round in 0..40 {
        for cutter in cutters(&mut rng) {
            let mut profiles = vec![ConvexProfile::from_solid(cutter.cutting_solid()).unwrap()];
            profiles.extend(
                SweepShape::from_solid(cutter.shank_solid())
                    .parts()
                    .iter()
                    .cloned(),
            );
            let kt = round % 3;
            let axis = Vec3::AXES[kt];
            let len = rng.range(0.01, 30.0);
            let mut across = Vec3::ZERO;
            across[(kt + 1 + rng.pick(2)) % 3] = 1.0;
            let deltas = [
                Vec3::new(
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                ) * len,
                axis * -len,
                axis * len,
                across * len,
                (across + axis * 0.02) * len,
                (across * 0.6 + Vec3::AXES[3 - kt - across.abs().max_position()] * 0.8) * len,
                Vec3::ZERO,
            ];
            for delta in deltas {
                let tip = Vec3::new(
                    rng.range(-50.0, 50.0),
                    rng.range(-50.0, 50.0),
                    rng.range(-50.0, 50.0),
                );
                for prof in &profiles {
                    let (w, n) = compare(prof, tip, axis, delta, &mut rng, 300);
                    worst = worst.max(w);
                    hits += n;
                }
            }
        }
    }
    println!("compared {hits} hits; worst disagreement {worst:.3e} mm");
    assert!(hits > 50_000, "{hits}");
}

#[test]
fn other_profiles_and_tilted_axes_use_the_general_path() {
    let bull = Cutter::bull(10.0, 2.0).unwrap();
    let prof = ConvexProfile::from_solid(bull.cutting_solid()).unwrap();
    // A bull-nose with its axis along a world axis takes the fast kernels on every move
    // (across its axis, along it, still, on a ramp).
    for delta in [
        Vec3::X,
        Vec3::new(0.6, -0.8, 0.0),
        -Vec3::Z,
        Vec3::ZERO,
        Vec3::new(1.0, 0.0, -0.1),
    ] {
        assert!(SweptConvex::new(&prof, Vec3::ZERO, Vec3::Z, delta).has_closed_form());
    }
    let sw = SweptConvex::new(&prof, Vec3::ZERO, Vec3::new(0.0, 0.6, 0.8), Vec3::X);
    assert!(!sw.has_closed_form());
    let ball = Cutter::ball(10.0).unwrap();
    let prof = ConvexProfile::from_solid(ball.cutting_solid()).unwrap();
    let sw = SweptConvex::new(&prof, Vec3::ZERO, Vec3::new(0.0, 0.6, 0.8), Vec3::X);
    assert!(!sw.has_closed_form());
    let sw = SweptConvex::new(&prof, Vec3::ZERO, Vec3::Z, Vec3::X);
    assert!(sw.has_closed_form());
}
