//! 4-axis orientation: the allowable size as a function of the table angle `B`, maximised.
//!
//! * A concave half-cylinder (a trough) lying along `Y`, open towards `+X`: in 3-axis the ball
//!   end mill with its side is limited by its own shank hitting the trough; about `Y` the best
//!   `B` points the tool axis along the normal and the size is the radius of curvature. The same
//!   part turned by 90° about `Z` and machined about `X` gives the same size at the turned angle.
//! * Consistency: `B = 0` is the 3-axis solve; a rigidly rotated part solved along the rotated
//!   axis gives the 3-axis answer of the original part; the optimum is never below 3-axis.
//! * Against brute force: dense sampling of `B` on a random compound surface.

mod common;

use common::Rng;

use std::f64::consts::FRAC_1_SQRT_2;

use swarf_geom::math::{Quat, Vec3};
use swarf_plan::size::{
    allowable_along, allowable_certified, best_rotary_angle, Axis4Options, CertifiedOptions,
    Contact, CutterFamily, RotaryAxis,
};
use swarf_surface::PreparedSurface;
use swarf_surface::{CompoundSurface, NurbsSurface, Patch, Surface, Tolerances};

const R: f64 = 5.0;

/// The trough: `(−R cos α, y, R sin α)` for `α ∈ [−90°, 90°]`, `y ∈ [−20, 20]`, as one rational
/// quadratic NURBS (two 90° arcs), mapped by `m`; normal towards the cylinder's axis.
fn trough(m: impl Fn(Vec3) -> Vec3) -> CompoundSurface {
    let w = FRAC_1_SQRT_2;
    let arc = [
        (Vec3::new(0.0, 0.0, -R), 1.0),
        (Vec3::new(-R, 0.0, -R), w),
        (Vec3::new(-R, 0.0, 0.0), 1.0),
        (Vec3::new(-R, 0.0, R), w),
        (Vec3::new(0.0, 0.0, R), 1.0),
    ];
    let pts: Vec<Vec<Vec3>> = arc
        .iter()
        .map(|(p, _)| {
            vec![
                m(*p + Vec3::new(0.0, -20.0, 0.0)),
                m(*p + Vec3::new(0.0, 20.0, 0.0)),
            ]
        })
        .collect();
    let ws: Vec<Vec<f64>> = arc.iter().map(|(_, w)| vec![*w, *w]).collect();
    let s = NurbsSurface::new(
        2,
        1,
        vec![0.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0],
        vec![0.0, 0.0, 1.0, 1.0],
        &pts,
        Some(&ws),
    )
    .unwrap();
    let mut part = CompoundSurface::new(vec![Patch::new(Surface::Nurbs(s))]);
    let cc = part.points(&[(0, 0.5, 0.5)]).unwrap()[0];
    let n = part
        .local(&cc, &Tolerances::DEFAULT)
        .normal
        .vector()
        .unwrap();
    if n.dot(m(Vec3::X) - m(Vec3::ZERO)) < 0.0 {
        part.flip_all();
    }
    part
}

fn contact(part: &CompoundSurface, patch: usize, u: f64, v: f64) -> Contact {
    let cc = part.points(&[(patch, u, v)]).unwrap()[0];
    Contact::at(part, &cc, &Tolerances::DEFAULT).unwrap()
}

#[test]
fn trough_about_y_gives_the_curvature_radius_with_the_axis_along_the_normal() {
    let part = trough(|p| p);
    let prep = PreparedSurface::new(&part);
    let c = contact(&part, 0, 0.5, 0.5);
    assert!((c.normal - Vec3::X).length() < 1e-12, "{}", c.normal);
    let fam = CutterFamily::ball_with_side();
    let three = allowable_certified(&prep, &fam, &c, &CertifiedOptions::DEFAULT);
    // The shank, standing up from the centre of the ball, meets the upper half of the trough.
    assert!(three.size < 0.5 * R, "3-axis size {}", three.size);
    let best = best_rotary_angle(&prep, &fam, &c, &Axis4Options::DEFAULT);
    assert!((best.size.size - R).abs() < 1e-6, "{:?}", best);
    assert!(best.size.certified);
    assert!((best.b_deg - 90.0).abs() < 1e-3, "B = {}", best.b_deg);
    assert!((best.axis - c.normal).length() < 1e-5);
    // Every coarse angle is solved or pruned by its cheap upper bound.
    assert!(best.solves + best.pruned >= 36, "{best:?}");
    assert!(best.pruned > 0 && best.solves >= 2, "{best:?}");
    assert!(best.size.evaluations >= three.evaluations);
}

#[test]
fn upper_half_of_the_trough_is_unreachable_in_3_axis_and_reached_in_4_axis() {
    let part = trough(|p| p);
    let prep = PreparedSurface::new(&part);
    // α = 45°: the normal points down, (cos 45°, 0, −sin 45°).
    let c = contact(&part, 0, 0.75, 0.5);
    assert!(c.normal.z < -0.5, "{}", c.normal);
    let fam = CutterFamily::ball();
    let three = allowable_certified(&prep, &fam, &c, &CertifiedOptions::DEFAULT);
    assert_eq!(three.size, 0.0);
    let best = best_rotary_angle(&prep, &fam, &c, &Axis4Options::DEFAULT);
    assert!((best.size.size - R).abs() < 1e-6, "{:?}", best);
    // Any reachable axis gives the sphere its curvature radius; the one found is reachable.
    assert!(best.axis.dot(c.normal) > 0.0);
    let with_side = best_rotary_angle(
        &prep,
        &CutterFamily::ball_with_side(),
        &c,
        &Axis4Options::DEFAULT,
    );
    // With its shank the ball fits only when every point of the trough lies below its equator:
    // trough points lie in directions (−cos α', 0, sin α') from the centre, α' ∈ [−90°, 90°],
    // so the axis must be +X (the trough's opening, not this point's normal): B = 90°.
    assert!((with_side.size.size - R).abs() < 1e-6, "{:?}", with_side);
    assert!((with_side.b_deg - 90.0).abs() < 1e-3, "{}", with_side.b_deg);
    let at_normal = allowable_along(
        &prep,
        &CutterFamily::ball_with_side(),
        &c,
        c.normal,
        &CertifiedOptions::DEFAULT,
    );
    assert!(at_normal.size < R - 0.1, "{}", at_normal.size);
}

#[test]
fn the_part_turned_about_z_and_machined_about_x_gives_the_same_size() {
    // Turn by +90° about Z: the trough lies along −X, open towards +Y.
    let q = Quat::from_rotation_z(std::f64::consts::FRAC_PI_2);
    let part = trough(|p| q * p);
    let prep = PreparedSurface::new(&part);
    let c = contact(&part, 0, 0.5, 0.5);
    assert!((c.normal - Vec3::Y).length() < 1e-12, "{}", c.normal);
    let opts = Axis4Options::DEFAULT.with_rotary(RotaryAxis::X);
    let best = best_rotary_angle(&prep, &CutterFamily::ball_with_side(), &c, &opts);
    assert!((best.size.size - R).abs() < 1e-6, "{:?}", best);
    // a(B) = (0, −sin B, cos B) = +Y at B = 270°.
    assert!((best.b_deg - 270.0).abs() < 1e-3, "{}", best.b_deg);
    assert!((RotaryAxis::X.tool_axis(270.0) - Vec3::Y).length() < 1e-12);
    assert!((RotaryAxis::Y.tool_axis(90.0) - Vec3::X).length() < 1e-12);
}

/// 2×2 bicubic Bézier height fields of 10 × 10 mm with random heights (amplitude 6 mm), mapped
/// by `m`.
fn random_surface(seed: u64, m: impl Fn(Vec3) -> Vec3) -> CompoundSurface {
    let mut rng = Rng(seed);
    let knots = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
    let mut patches = Vec::new();
    // Shared heights on a 7 × 7 lattice so that neighbouring patches meet.
    let h: Vec<Vec<f64>> = (0..7)
        .map(|_| (0..7).map(|_| 6.0 * rng.f()).collect())
        .collect();
    for (a, b) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
        let pts: Vec<Vec<Vec3>> = (0..4)
            .map(|i| {
                (0..4)
                    .map(|j| {
                        let (gi, gj) = (3 * a + i, 3 * b + j);
                        m(Vec3::new(
                            10.0 * gi as f64 / 3.0,
                            10.0 * gj as f64 / 3.0,
                            h[gi][gj],
                        ))
                    })
                    .collect()
            })
            .collect();
        let s = NurbsSurface::new(3, 3, knots.clone(), knots.clone(), &pts, None).unwrap();
        patches.push(Patch::new(Surface::Nurbs(s)));
    }
    CompoundSurface::new(patches)
}

const POINTS: [(usize, f64, f64); 4] = [(0, 0.5, 0.5), (1, 0.3, 0.6), (2, 0.7, 0.2), (3, 0.4, 0.4)];

#[test]
fn a_rotated_part_along_the_rotated_axis_is_the_3_axis_answer() {
    let q = Quat::from_euler(glam::EulerRot::XYZ, 0.4, -0.7, 1.1);
    for (seed, fam) in [
        (1, CutterFamily::ball()),
        (2, CutterFamily::flat()),
        (3, CutterFamily::bull(1.0).unwrap()),
    ] {
        let part = random_surface(seed, |p| p);
        let turned = random_surface(seed, |p| q * p);
        let (prep, prep_t) = (PreparedSurface::new(&part), PreparedSurface::new(&turned));
        for &(k, u, v) in &POINTS {
            let c = contact(&part, k, u, v);
            let ct = contact(&turned, k, u, v);
            let a = allowable_certified(&prep, &fam, &c, &CertifiedOptions::DEFAULT);
            let b = allowable_along(&prep_t, &fam, &ct, q * Vec3::Z, &CertifiedOptions::DEFAULT);
            let tol = 1e-6 * a.size.max(1.0);
            assert!(
                (a.size - b.size).abs() <= tol || a.size == b.size,
                "{fam:?} at {k},{u},{v}: {} vs {}",
                a.size,
                b.size
            );
            if let (Some(p), Some(pt)) = (a.limit_point, b.limit_point) {
                if a.size.is_finite() && a.size > 0.0 {
                    assert!((q * p - pt).length() < 1e-3, "{p} vs {pt}");
                }
            }
            // Axis +Z is exactly the 3-axis solve.
            let z = allowable_along(&prep, &fam, &c, Vec3::Z, &CertifiedOptions::DEFAULT);
            assert_eq!(z, a);
        }
    }
}

#[test]
fn search_matches_dense_sampling_and_never_loses_to_3_axis() {
    let opts = Axis4Options::DEFAULT;
    for (seed, fam) in [
        (7, CutterFamily::flat()),
        (8, CutterFamily::ball_with_side()),
    ] {
        let part = random_surface(seed, |p| p);
        let prep = PreparedSurface::new(&part);
        for &(k, u, v) in &POINTS {
            let c = contact(&part, k, u, v);
            let three = allowable_certified(&prep, &fam, &c, &opts.certified);
            let best = best_rotary_angle(&prep, &fam, &c, &opts);
            // Ties keep B = 0, where the answer is the 3-axis solve itself.
            if best.size.size <= three.size {
                assert_eq!((best.b_deg, best.size.size), (0.0, three.size));
            }
            assert!(
                best.size.size >= three.size,
                "{} < {}",
                best.size.size,
                three.size
            );
            // The size reported is the size at the angle reported.
            let again = allowable_along(
                &prep,
                &fam,
                &c,
                opts.rotary.tool_axis(best.b_deg),
                &opts.certified,
            );
            assert!(
                (again.size - best.size.size).abs() <= 1e-6 * again.size.max(1.0)
                    || again.size == best.size.size,
                "{} vs {}",
                again.size,
                best.size.size
            );
            // Dense sampling every 0.5°.
            let dense = (0..720)
                .map(|i| {
                    allowable_along(
                        &prep,
                        &fam,
                        &c,
                        opts.rotary.tool_axis(0.5 * i as f64),
                        &opts.certified,
                    )
                    .size
                })
                .fold(0.0, f64::max);
            let tol = 1e-3 * dense.max(1.0);
            assert!(
                best.size.size >= dense - tol || best.size.size == dense,
                "{fam:?} at {k},{u},{v}: search {} at B = {}, dense {}",
                best.size.size,
                best.b_deg,
                dense
            );
            eprintln!(
                "{fam:?} {k},{u},{v}: 3-axis {:.6} best {:.6} at B = {:.4} (dense {:.6}), {} solves, {} pruned, {} evaluations",
                three.size, best.size.size, best.b_deg, dense, best.solves, best.pruned, best.size.evaluations
            );
        }
    }
}
