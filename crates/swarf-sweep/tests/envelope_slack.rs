//! Leaving a torus band's envelope out of a short fixed-axis sweep
//! (`SweptConvex::with_envelope_slack`) moves the swept solid by at most `|v|²/(8r)`: on random
//! rays near random short moves of bull-noses with random axes, the interval without the
//! envelope lies inside the exact one, and every point of the exact interval it leaves out is
//! within that distance of the start or end instance of the cutter. Long moves, sharp joints
//! and slack below the bound keep the exact envelope.

mod common;

use common::Rng;
use swarf_geom::math::Vec3;
use swarf_sweep::{ConvexProfile, SweptConvex};
use swarf_tool::Cutter;

fn torus_index(prof: &ConvexProfile) -> usize {
    (0..prof.elements().len())
        .find(|&i| prof.smooth_torus_radius(i).is_some())
        .expect("a bull-nose has a smooth torus band")
}

#[test]
fn a_bull_noses_band_is_smooth_and_a_clipped_one_is_not() {
    let c = Cutter::bull(10.0, 2.0).unwrap();
    let prof = ConvexProfile::from_solid(c.cutting_solid()).unwrap();
    let i = torus_index(&prof);
    assert_eq!(prof.smooth_torus_radius(i), Some(2.0));
    // Cut through the torus at z = 1: the band now meets a disc at an angle.
    let clipped = prof.clipped(1.0, 20.0).unwrap();
    assert!((0..clipped.elements().len()).all(|k| clipped.smooth_torus_radius(k).is_none()));
    // A ball end has no torus band (its arc is on the axis).
    let ball = ConvexProfile::from_solid(Cutter::ball(10.0).unwrap().cutting_solid()).unwrap();
    assert!((0..ball.elements().len()).all(|k| ball.smooth_torus_radius(k).is_none()));
}

#[test]
fn leaving_the_envelope_out_moves_the_sweep_by_at_most_the_bound() {
    let mut rng = Rng(0x5eed_2026_1126);
    let (mut differing, mut compared, mut worst_seen) = (0usize, 0usize, 0.0f64);
    for case in 0..40 {
        let r = rng.range(0.5, 3.0);
        let d = rng.range(2.0 * r + 1.0, 16.0);
        let c = Cutter::bull(d, r).unwrap();
        let prof = ConvexProfile::from_solid(c.cutting_solid()).unwrap();
        let tip = Vec3::new(
            rng.range(-2.0, 2.0),
            rng.range(-2.0, 2.0),
            rng.range(-2.0, 2.0),
        );
        let axis = rng.unit();
        // Short moves, as 5-axis pieces are (0.01–0.2 mm).
        let delta = rng.unit() * rng.range(0.01, 0.2);
        let bound = delta.length_squared() / (8.0 * r);
        let exact = SweptConvex::new(&prof, tip, axis, delta);
        let (slack, moved) =
            SweptConvex::new(&prof, tip, axis, delta).with_envelope_slack(bound * (1.0 + 1e-12));
        assert!(
            (moved - bound).abs() <= 1e-12 * bound,
            "case {case}: {moved} vs {bound}"
        );
        let bb = exact.bbox();
        for _ in 0..400 {
            let o = Vec3::new(
                rng.range(bb.min.x, bb.max.x),
                rng.range(bb.min.y, bb.max.y),
                rng.range(bb.min.z, bb.max.z),
            );
            let dir = rng.unit();
            let Some((lo, hi)) = exact.ray_interval(o, dir) else {
                assert!(slack.ray_interval(o, dir).is_none());
                continue;
            };
            // Points of [lo, hi] the slack sweep leaves out: all of it on a miss.
            let (a, b) = slack.ray_interval(o, dir).unwrap_or((hi, hi));
            assert!(
                a >= lo - 1e-9 && b <= hi + 1e-9,
                "case {case}: {a} {b} in {lo} {hi}"
            );
            compared += 1;
            for (from, to) in [(lo, a), (b, hi)] {
                if to - from <= 1e-12 {
                    continue;
                }
                differing += 1;
                for k in 0..=8 {
                    let x = o + dir * (from + (to - from) * k as f64 / 8.0);
                    let near = prof
                        .signed_distance(tip, axis, x)
                        .distance
                        .min(prof.signed_distance(tip + delta, axis, x).distance);
                    assert!(
                        near <= bound + 1e-9,
                        "case {case}: a point left out is {near} mm from both instances \
                         (bound {bound})"
                    );
                    worst_seen = worst_seen.max(near);
                }
            }
        }
    }
    eprintln!(
        "{compared} rays hit, {differing} ends moved; farthest point left out {worst_seen:.3e} mm"
    );
    assert!(compared > 5000 && differing > 0, "{compared} {differing}");
}

#[test]
fn long_moves_and_tight_slack_keep_the_envelope() {
    let c = Cutter::bull(10.0, 2.0).unwrap();
    let prof = ConvexProfile::from_solid(c.cutting_solid()).unwrap();
    let delta = Vec3::new(0.5, 0.0, 0.1);
    let need = delta.length_squared() / 16.0;
    let (_, moved) =
        SweptConvex::new(&prof, Vec3::ZERO, Vec3::Z, delta).with_envelope_slack(need * 0.99);
    assert_eq!(moved, 0.0);
    let (_, moved) = SweptConvex::new(&prof, Vec3::ZERO, Vec3::Z, delta)
        .with_envelope_slack(need * (1.0 + 1e-12));
    assert!((moved - need).abs() < 1e-12 * need);
}
