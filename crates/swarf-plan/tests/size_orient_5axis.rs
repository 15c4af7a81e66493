//! 5-axis orientation: lead and tilt within machine limits that maximise the allowable size.
//!
//! * A slot: floor `z = 0` for `x ∈ [−20, 10]`, walls at `x = 10` and `x = −20` (20 mm high),
//!   feed along `+Y`, CC point at the origin. 3-axis: the flat end mill stands on the floor with
//!   its axis through the CC point: `R = 10` (the near wall). Tilted by `τ` towards the near wall
//!   its bottom disc rises away from the contact towards the far wall, whose rim reaches
//!   `x = −2R·cos τ`: `R = 10 / cos τ`, best at the tilt limit.
//! * Consistency: zero limits give the normal as the axis (the 3-axis answer where the normal is
//!   `+Z`); the optimum is never below 3-axis when `+Z` is admissible.
//! * Against brute force: a dense grid of lead and tilt on a random compound surface.

mod common;

use common::Rng;

use swarf_geom::math::Vec3;
use swarf_plan::size::{
    allowable_along, allowable_certified, best_lead_tilt, Axis5Options, CertifiedOptions, Contact,
    CutterFamily, LeadTiltFrame,
};
use swarf_surface::PreparedSurface;
use swarf_surface::{CompoundSurface, NurbsSurface, Patch, Surface, Tolerances};

fn bilinear(p00: Vec3, p10: Vec3, p01: Vec3, p11: Vec3) -> Patch {
    let k = vec![0.0, 0.0, 1.0, 1.0];
    let s = NurbsSurface::new(1, 1, k.clone(), k, &[vec![p00, p01], vec![p10, p11]], None).unwrap();
    Patch::new(Surface::Nurbs(s))
}

/// The slot of the module docs (u along +Y on every patch).
fn slot() -> CompoundSurface {
    let v = Vec3::new;
    CompoundSurface::new(vec![
        // Floor: v from x = 10 to x = −20, so S_u × S_v = +Z.
        bilinear(
            v(10.0, -30.0, 0.0),
            v(10.0, 30.0, 0.0),
            v(-20.0, -30.0, 0.0),
            v(-20.0, 30.0, 0.0),
        ),
        // Near wall x = 10, normal −X: v from z = 20 down to 0.
        bilinear(
            v(10.0, -30.0, 20.0),
            v(10.0, 30.0, 20.0),
            v(10.0, -30.0, 0.0),
            v(10.0, 30.0, 0.0),
        ),
        // Far wall x = −20, normal +X.
        bilinear(
            v(-20.0, -30.0, 0.0),
            v(-20.0, 30.0, 0.0),
            v(-20.0, -30.0, 20.0),
            v(-20.0, 30.0, 20.0),
        ),
    ])
}

fn contact_and_frame(part: &CompoundSurface, k: usize, u: f64, v: f64) -> (Contact, LeadTiltFrame) {
    let cc = part.points(&[(k, u, v)]).unwrap()[0];
    let c = Contact::at(part, &cc, &Tolerances::DEFAULT).unwrap();
    let su = part.local(&cc, &Tolerances::DEFAULT).derivs.su;
    (c, LeadTiltFrame::new(c.normal, su).unwrap())
}

#[test]
fn slot_normals_and_frame() {
    let part = slot();
    for (k, n) in [(0, Vec3::Z), (1, -Vec3::X), (2, Vec3::X)] {
        let (c, _) = contact_and_frame(&part, k, 0.5, 0.5);
        assert!((c.normal - n).length() < 1e-12, "patch {k}: {}", c.normal);
    }
    let (_, f) = contact_and_frame(&part, 0, 0.5, 2.0 / 3.0);
    assert!((f.feed - Vec3::Y).length() < 1e-12);
    assert!((f.side + Vec3::X).length() < 1e-12);
    // Positive lead leans forward, positive tilt towards the side.
    assert!((f.axis(90.0, 0.0) - Vec3::Y).length() < 1e-12);
    assert!((f.axis(0.0, 90.0) + Vec3::X).length() < 1e-12);
    let (l, t) = f.angles_of(f.axis(12.0, -7.0));
    assert!((l - 12.0).abs() < 1e-12 && (t + 7.0).abs() < 1e-12);
}

#[test]
fn tilting_towards_the_near_wall_grows_the_flat_end_mill_to_10_over_cos_tilt() {
    let part = slot();
    let prep = PreparedSurface::new(&part);
    // The origin: v = 1/3 of the way from x = 10 to x = −20.
    let (c, frame) = contact_and_frame(&part, 0, 0.5, 1.0 / 3.0);
    assert!(c.point.length() < 1e-12, "{}", c.point);
    let fam = CutterFamily::flat();
    let three = allowable_certified(&prep, &fam, &c, &CertifiedOptions::DEFAULT);
    assert!((three.size - 10.0).abs() < 1e-6, "{}", three.size);
    let t_max: f64 = 10.0;
    let opts = Axis5Options::DEFAULT.with_limits(0.0, t_max);
    let best = best_lead_tilt(&prep, &fam, &c, &frame, &opts);
    let expected = 10.0 / t_max.to_radians().cos();
    assert!(
        (best.size.size - expected).abs() < 1e-6,
        "{best:?} vs {expected}"
    );
    assert!(best.size.certified);
    assert_eq!((best.lead_deg, best.tilt_deg), (0.0, -t_max));
    // Leaning the axis towards +X (the near wall), s = −X.
    assert!(best.axis.x > 0.0);
    // The limit is the rim on the far wall, at height 2R·sin τ.
    let p = best.size.limit_point.unwrap();
    let rim = Vec3::new(-20.0, 0.0, 20.0 * t_max.to_radians().tan());
    assert!((p - rim).length() < 1e-3, "{p}");
    // Tilting the other way (towards the far wall) halves it: R = 5 / cos τ.
    let away = allowable_along(&prep, &fam, &c, frame.axis(0.0, 5.0), &opts.certified);
    assert!(
        (away.size - 5.0 / 5f64.to_radians().cos()).abs() < 1e-6,
        "{}",
        away.size
    );
    // Zero limits: the axis is the normal, +Z here: exactly the 3-axis answer.
    let zero = best_lead_tilt(
        &prep,
        &fam,
        &c,
        &frame,
        &Axis5Options::DEFAULT.with_limits(0.0, 0.0),
    );
    assert_eq!(zero.size.size, three.size);
    assert_eq!((zero.lead_deg, zero.tilt_deg), (0.0, 0.0));
}

/// 2×2 bicubic Bézier height fields of 10 × 10 mm with random heights (amplitude 6 mm).
fn random_surface(seed: u64) -> CompoundSurface {
    let mut rng = Rng(seed);
    let knots = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
    let h: Vec<Vec<f64>> = (0..7)
        .map(|_| (0..7).map(|_| 6.0 * rng.f()).collect())
        .collect();
    let mut patches = Vec::new();
    for (a, b) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
        let pts: Vec<Vec<Vec3>> = (0..4)
            .map(|i| {
                (0..4)
                    .map(|j| {
                        let (gi, gj) = (3 * a + i, 3 * b + j);
                        Vec3::new(10.0 * gi as f64 / 3.0, 10.0 * gj as f64 / 3.0, h[gi][gj])
                    })
                    .collect()
            })
            .collect();
        let s = NurbsSurface::new(3, 3, knots.clone(), knots.clone(), &pts, None).unwrap();
        patches.push(Patch::new(Surface::Nurbs(s)));
    }
    CompoundSurface::new(patches)
}

const POINTS: [(usize, f64, f64); 3] = [(0, 0.5, 0.5), (1, 0.3, 0.6), (3, 0.4, 0.4)];

#[test]
fn zero_limits_use_the_normal_and_wide_limits_never_lose_to_3_axis() {
    let part = random_surface(11);
    let prep = PreparedSurface::new(&part);
    for fam in [CutterFamily::flat(), CutterFamily::bull(1.0).unwrap()] {
        for &(k, u, v) in &POINTS {
            let (c, frame) = contact_and_frame(&part, k, u, v);
            let zero = best_lead_tilt(
                &prep,
                &fam,
                &c,
                &frame,
                &Axis5Options::DEFAULT.with_limits(0.0, 0.0),
            );
            let along_n = allowable_along(&prep, &fam, &c, c.normal, &CertifiedOptions::DEFAULT);
            assert!((zero.axis - c.normal).length() < 1e-15);
            assert!(
                (zero.size.size - along_n.size).abs() <= 1e-9 * along_n.size.max(1.0),
                "{} vs {}",
                zero.size.size,
                along_n.size
            );
            assert_eq!(zero.solves, 1);
            let opts = Axis5Options::DEFAULT.with_limits(40.0, 40.0);
            let (lz, tz) = frame.angles_of(Vec3::Z);
            assert!(lz.abs() <= 40.0 && tz.abs() <= 40.0, "+Z admissible here");
            let three = allowable_certified(&prep, &fam, &c, &opts.certified);
            let best = best_lead_tilt(&prep, &fam, &c, &frame, &opts);
            assert!(
                best.size.size >= three.size,
                "{} < {}",
                best.size.size,
                three.size
            );
            assert!(best.lead_deg.abs() <= 40.0 && best.tilt_deg.abs() <= 40.0);
        }
    }
}

#[test]
fn search_matches_a_dense_grid_of_lead_and_tilt() {
    let part = random_surface(5);
    let prep = PreparedSurface::new(&part);
    let opts = Axis5Options::DEFAULT.with_limits(20.0, 20.0);
    for fam in [CutterFamily::flat(), CutterFamily::ball_with_side()] {
        for &(k, u, v) in &POINTS {
            let (c, frame) = contact_and_frame(&part, k, u, v);
            let best = best_lead_tilt(&prep, &fam, &c, &frame, &opts);
            let n = 24;
            let mut dense: f64 = 0.0;
            for i in 0..=n {
                for j in 0..=n {
                    let l = -20.0 + 40.0 * i as f64 / n as f64;
                    let t = -20.0 + 40.0 * j as f64 / n as f64;
                    let a = allowable_along(&prep, &fam, &c, frame.axis(l, t), &opts.certified);
                    dense = dense.max(a.size);
                }
            }
            let tol = 1e-3 * dense.max(1.0);
            assert!(
                best.size.size >= dense - tol || best.size.size == dense,
                "{fam:?} at {k},{u},{v}: search {} at ({}, {}), dense {dense}",
                best.size.size,
                best.lead_deg,
                best.tilt_deg
            );
            eprintln!(
                "{fam:?} {k},{u},{v}: best {:.6} at lead {:.4} tilt {:.4} (dense {:.6}), {} solves, {} pruned, {} evaluations",
                best.size.size, best.lead_deg, best.tilt_deg, dense, best.solves, best.pruned, best.size.evaluations
            );
        }
    }
}
