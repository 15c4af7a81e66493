//! The swept front of a chained move's start instance (`SweptConvex::front`): every line
//! whose chord through the sweep reaches beyond its chord through the start instance must be
//! let through, over the very range where it does — checked by brute force on dense rays of
//! the three families for every cutter kind, moves level, rising, falling, oblique and along
//! a tilted axis. And the test must be worth having: on a level move of a ball it rejects a
//! good part of the rays across the tool.

use swarf_geom::math::Vec3;
use swarf_sweep::{SweptConvex, ToolShape};
use swarf_tool::Cutter;

fn cutters() -> Vec<Cutter> {
    vec![
        Cutter::flat(6.0).unwrap(),
        Cutter::ball(6.0).unwrap(),
        Cutter::bull(6.0, 1.5).unwrap(),
        Cutter::taper_flat(6.0, 10.0).unwrap(),
        Cutter::taper_ball(6.0, 8.0).unwrap(),
        Cutter::chamfer(6.0, 90.0).unwrap(),
        Cutter::drill(6.0, 118.0).unwrap(),
    ]
}

/// `(axis, move)` pairs: level, rising, falling, oblique, along the axis, a tilted axis.
fn moves() -> Vec<(Vec3, Vec3)> {
    let tilted = Vec3::new(0.3, -0.2, 1.0).normalize();
    vec![
        (Vec3::Z, Vec3::new(0.7, 0.0, 0.0)),
        (Vec3::Z, Vec3::new(0.5, 0.2, 0.3)),
        (Vec3::Z, Vec3::new(-0.4, 0.3, -0.35)),
        (Vec3::Z, Vec3::new(0.0, 0.0, -0.6)),
        (Vec3::Z, Vec3::new(0.05, 0.0, 0.8)),
        (tilted, Vec3::new(0.6, 0.1, -0.2)),
        (Vec3::X, Vec3::new(0.1, 0.6, 0.0)),
    ]
}

/// Counts of rays crossing the sweep and of those the front lets through (with all their
/// material), for one family of one part; fails on a ray the move changes that it rejects.
fn check_family(sweep: &SweptConvex<'_>, start: &SweptConvex<'_>, k: usize, h: f64) -> (u32, u32) {
    let front = sweep.front();
    let bb = sweep.bbox();
    let (u, w) = ((k + 1) % 3, (k + 2) % 3);
    let (mut crossing, mut passed) = (0, 0);
    let steps = |a: usize| ((bb.max[a] - bb.min[a]) / h).ceil() as usize;
    for i in 0..=steps(u) {
        for j in 0..=steps(w) {
            let mut o = Vec3::ZERO;
            o[u] = bb.min[u] + i as f64 * h;
            o[w] = bb.min[w] + j as f64 * h;
            let Some((lo, hi)) = sweep.axis_ray_interval(o, k) else {
                continue;
            };
            crossing += 1;
            let reached = |material: (f64, f64)| {
                front
                    .block(k, o, 0.0, material)
                    .is_some_and(|b| b.reaches(o[u], o[w]))
            };
            if reached((f64::NEG_INFINITY, f64::INFINITY)) {
                passed += 1;
            }
            // Where the sweep reaches beyond the start instance (the material a cut start
            // instance leaves that the move removes).
            let beyond: Vec<(f64, f64)> = match start.axis_ray_interval(o, k) {
                None => vec![(lo, hi)],
                Some((a, b)) => [(lo, a), (b, hi)]
                    .into_iter()
                    .filter(|(x, y)| y - x > 1e-7)
                    .collect(),
            };
            for m in beyond {
                assert!(
                    reached(m),
                    "family {k}, ray ({}, {}): the move removes {m:?} but the front rejects it",
                    o[u],
                    o[w]
                );
            }
        }
    }
    (crossing, passed)
}

#[test]
fn the_front_lets_through_every_ray_a_chained_move_changes() {
    let tip = Vec3::new(1.0, 2.0, 3.0);
    for c in cutters() {
        let tool = ToolShape::new(&c);
        for (axis, v) in moves() {
            for shape in [tool.cutting(), tool.non_cutting()] {
                for p in shape.parts() {
                    let sweep = SweptConvex::new(p, tip, axis, v);
                    let start = SweptConvex::new(p, tip, axis, Vec3::ZERO);
                    for k in 0..3 {
                        check_family(&sweep, &start, k, 0.11);
                    }
                }
            }
        }
    }
}

#[test]
fn a_level_ball_move_needs_only_the_rays_ahead() {
    let tool = ToolShape::new(&Cutter::ball(10.0).unwrap());
    let p = &tool.cutting().parts()[0];
    let tip = Vec3::new(0.0, 0.0, 0.0);
    let sweep = SweptConvex::new(p, tip, Vec3::Z, Vec3::new(0.5, 0.0, 0.0));
    let start = SweptConvex::new(p, tip, Vec3::Z, Vec3::ZERO);
    // Rays along Y and Z: the half behind the tip cannot change (the front is the half-space
    // ahead of it); rays along X all cross the front.
    for (k, at_most) in [(0, 1.0), (1, 0.56), (2, 0.56)] {
        let (crossing, passed) = check_family(&sweep, &start, k, 0.1);
        let share = passed as f64 / crossing as f64;
        assert!(
            share <= at_most,
            "family {k}: {passed} of {crossing} rays let through ({share:.3})"
        );
        if k == 0 {
            assert_eq!(passed, crossing);
        }
    }
}
