//! The force model on given engagements, against closed forms and an independent numeric
//! integration of the same model.
//!
//! Closed forms: ../shared/data/forces/REFERENCE.md (Altintas, Manufacturing Automation, ch. 2).

// Components are indexed by number, as in the formulas.
#![allow(clippy::needless_range_loop)]

use std::f64::consts::{PI, TAU};

use swarf_engage::{CircleEngagement, EngageOptions, Engagement, PhiInterval};
use swarf_force::{unit_forces, Coefficients, CutterEdges, UnitForces};
use swarf_geom::math::Vec3;
use swarf_tool::{Cutter, CutterOptions};

const K: Coefficients = Coefficients {
    ktc: 796.0,
    krc: 168.8,
    kac: 222.0,
    kte: 27.7,
    kre: 30.8,
    kae: 1.8,
};

fn cutter(kind: &str, flutes: u32, helix: f64) -> Cutter {
    let c = match kind {
        "flat" => Cutter::flat(10.0),
        "ball" => Cutter::ball(10.0),
        _ => Cutter::bull(10.0, 2.0),
    }
    .unwrap();
    c.with_options(&CutterOptions {
        flutes: Some(flutes),
        helix_deg: Some(helix),
        ..CutterOptions::default()
    })
    .unwrap()
}

/// An engagement with the discs of `opts` whose centres lie in `(z0, z1)` engaged over
/// `[start, end]` degrees, feed along +X, axis +Z.
fn engagement(z0: f64, z1: f64, start: f64, end: f64, opts: &EngageOptions) -> Engagement {
    let dz = opts.dz_mm;
    let discs = (0..10_000)
        .map(|k| (k as f64 + 0.5) * dz)
        .filter(|&z| z > z0 && z < z1)
        .map(|z| CircleEngagement {
            at_mm: z,
            intervals: vec![PhiInterval {
                start_deg: start,
                end_deg: end,
            }],
        })
        .collect();
    Engagement {
        location: 0,
        move_index: 0,
        file: "t.ngc".into(),
        line: 1,
        tool: 1,
        s: 1.0,
        tip: Vec3::ZERO,
        axis: Vec3::Z,
        x_l: Vec3::X,
        y_l: Vec3::Y,
        tip_direction: Vec3::X,
        axis_rate: Vec3::ZERO,
        feed_mm_min: 0.0,
        spindle_rpm: 0.0,
        spindle_dir: swarf_path::SpindleDir::Clockwise,
        discs,
        bottom: vec![],
        area_mm2: 1.0,
        ap_mm: z1 - z0,
        side_extent_mm: Some((z0, z1)),
        phi_entry_deg: None,
        phi_exit_deg: None,
        removed_mm3: 0.0,
        mrr_mm3_min: 0.0,
    }
}

fn unit(c: &Cutter, e: &Engagement, samples: usize) -> UnitForces {
    let opts = EngageOptions::default();
    let edges = CutterEdges::new(c, &opts, "test").unwrap();
    unit_forces(e, &edges, samples)
}

/// REFERENCE.md's closed-form means of a cylindrical end mill.
fn closed_form(n: f64, a: f64, c: f64, st: f64, ex: f64) -> [f64; 3] {
    let br = |f: &dyn Fn(f64) -> f64| f(ex) - f(st);
    let fx = n * a * c / (8.0 * PI)
        * br(&|p| K.ktc * (2.0 * p).cos() - K.krc * (2.0 * p - (2.0 * p).sin()))
        + n * a / (2.0 * PI) * br(&|p| -K.kte * p.sin() + K.kre * p.cos());
    let fy = n * a * c / (8.0 * PI)
        * br(&|p| K.ktc * (2.0 * p - (2.0 * p).sin()) + K.krc * (2.0 * p).cos())
        - n * a / (2.0 * PI) * br(&|p| K.kte * p.cos() + K.kre * p.sin());
    let fz = n * a / (2.0 * PI) * br(&|p| -K.kac * c * p.cos() + K.kae * p);
    [fx, fy, fz]
}

#[test]
fn mean_forces_match_the_closed_forms() {
    let opts = EngageOptions::default();
    let r = 5.0f64;
    let a = 4.0;
    let mut cases = vec![("full slot", 0.0, PI)];
    for ae in [0.5, 1.0, 2.5, 4.0] {
        let w = (1.0 - ae / r).acos();
        cases.push(("up-milling", 0.0, w));
        cases.push(("down-milling", PI - w, PI));
    }
    for flutes in [2, 3, 4] {
        for helix in [0.0, 30.0] {
            let c = cutter("flat", flutes, helix);
            for &(name, st, ex) in &cases {
                let e = engagement(0.0, a, st.to_degrees(), ex.to_degrees(), &opts);
                let u = unit(&c, &e, 360);
                for feed in [0.05, 0.1] {
                    let f = u.combine(K.as_array(), feed);
                    let want = closed_form(flutes as f64, a, feed, st, ex);
                    for o in 0..3 {
                        let err = (f.means[o] - want[o]).abs();
                        assert!(
                            err <= 1e-9 * want[o].abs().max(1.0),
                            "{name} N={flutes} i={helix} c={feed}: F{o} {} vs {}",
                            f.means[o],
                            want[o]
                        );
                    }
                }
                // The full slot's special values.
                if name == "full slot" {
                    let f = u.combine(K.as_array(), 0.1);
                    let n = flutes as f64;
                    let want = [
                        -n * a * (0.1 * K.krc / 4.0 + K.kre / PI),
                        n * a * (0.1 * K.ktc / 4.0 + K.kte / PI),
                        n * a * (0.1 * K.kac / PI + K.kae / 2.0),
                    ];
                    for o in 0..3 {
                        assert!((f.means[o] - want[o]).abs() < 1e-9 * want[o].abs(), "{o}");
                    }
                }
            }
        }
    }
}

#[test]
fn sampled_mean_agrees_with_the_exact_mean() {
    // A continuous curve (helix on): the 3600-sample average is within O(1/N²) of the exact mean.
    let opts = EngageOptions::default();
    let c = cutter("flat", 3, 30.0);
    let e = engagement(0.0, 4.0, 20.0, 140.0, &opts);
    let u = unit(&c, &e, 3600);
    let f = u.combine(K.as_array(), 0.1);
    for o in 0..4 {
        let avg = (0..3600).map(|j| f.at(o, j)).sum::<f64>() / 3600.0;
        assert!(
            (avg - f.means[o]).abs() < 1e-4 * f.means[o].abs().max(1.0),
            "{o}: {avg} vs {}",
            f.means[o]
        );
    }
}

/// Independent reference: the force of all flutes at spindle angle θ, integrating over z by
/// Gauss–Legendre on the pieces where each flute is inside `[st, ex]`, straight from
/// REFERENCE.md's elemental forces (cylinder: κ = 90°, lag z·tan i/R).
fn reference(theta: f64, n: usize, helix: f64, a: f64, st: f64, ex: f64, c: f64) -> [f64; 4] {
    const X: [f64; 8] = [
        -0.960_289_856_497_536_3,
        -0.796_666_477_413_626_7,
        -0.525_532_409_916_329,
        -0.183_434_642_495_649_8,
        0.183_434_642_495_649_8,
        0.525_532_409_916_329,
        0.796_666_477_413_626_7,
        0.960_289_856_497_536_3,
    ];
    const W: [f64; 8] = [
        0.101_228_536_290_376_3,
        0.222_381_034_453_374_5,
        0.313_706_645_877_887_3,
        0.362_683_783_378_362,
        0.362_683_783_378_362,
        0.313_706_645_877_887_3,
        0.222_381_034_453_374_5,
        0.101_228_536_290_376_3,
    ];
    let r = 5.0;
    let k = helix.to_radians().tan() / r;
    let mut out = [0.0; 4];
    for m in 0..n {
        let phi0 = theta + TAU * m as f64 / n as f64;
        let phi = |z: f64| phi0 - k * z;
        // Heights where the edge crosses an interval end (any turn).
        let mut cuts = vec![0.0, a];
        if k > 0.0 {
            for end in [st, ex] {
                let lo = ((phi(a) - end) / TAU).floor() as i64 - 1;
                let hi = ((phi(0.0) - end) / TAU).ceil() as i64 + 1;
                for t in lo..=hi {
                    let z = (phi0 - end - TAU * t as f64) / k;
                    if z > 0.0 && z < a {
                        cuts.push(z);
                    }
                }
            }
        }
        cuts.sort_by(f64::total_cmp);
        for w in cuts.windows(2) {
            let (z0, z1) = (w[0], w[1]);
            let mid = phi(0.5 * (z0 + z1)).rem_euclid(TAU);
            if !(mid >= st && mid <= ex) || z1 <= z0 {
                continue;
            }
            // 64 panels of 8-point Gauss–Legendre.
            let panels = 64;
            let hpan = (z1 - z0) / panels as f64;
            for p in 0..panels {
                for (x, wt) in X.iter().zip(W) {
                    let z = z0 + hpan * (p as f64 + 0.5 + 0.5 * x);
                    let f = phi(z);
                    let h = c * f.sin();
                    let ft = K.ktc * h + K.kte;
                    let fr = K.krc * h + K.kre;
                    let fa = K.kac * h + K.kae;
                    let dz = 0.5 * hpan * wt;
                    out[0] += dz * (-ft * f.cos() - fr * f.sin());
                    out[1] += dz * (ft * f.sin() - fr * f.cos());
                    out[2] += dz * fa;
                    out[3] += dz * ft * r * 1e-3;
                }
            }
        }
    }
    out
}

#[test]
fn instantaneous_curves_match_an_independent_integration() {
    let opts = EngageOptions::default();
    for (flutes, helix, st, ex, a) in [
        (3, 30.0, 30.0, 150.0, 4.0),
        (4, 45.0, 0.0, 180.0, 6.0),
        (2, 10.0, 120.0, 180.0, 3.0),
        // Without a helix the force jumps at the interval ends: ends off the sample grid.
        (3, 0.0, 0.5, 60.5, 2.0),
    ] {
        let c = cutter("flat", flutes, helix);
        let e = engagement(0.0, a, st, ex, &opts);
        let samples = 360;
        let u = unit(&c, &e, samples);
        let f = u.combine(K.as_array(), 0.08);
        let mut worst = 0.0f64;
        let scale = f.peaks().iter().cloned().fold(0.0, f64::max);
        for j in 0..samples {
            let theta = TAU * j as f64 / samples as f64;
            let want = reference(
                theta,
                flutes as usize,
                helix,
                a,
                st.to_radians(),
                ex.to_radians(),
                0.08,
            );
            for o in 0..4 {
                let rel = (f.at(o, j) - want[o]).abs() / scale.max(1e-12);
                worst = worst.max(rel);
            }
        }
        assert!(
            worst < 1e-6,
            "N={flutes} i={helix}: worst relative {worst:e}"
        );
    }
}

#[test]
fn symmetries_and_limits() {
    let opts = EngageOptions::default();
    // No engagement: zero.
    let c = cutter("flat", 4, 30.0);
    let mut e = engagement(0.0, 4.0, 0.0, 180.0, &opts);
    e.discs.clear();
    let u = unit(&c, &e, 360);
    let f = u.combine(K.as_array(), 0.1);
    assert!(!u.engaged && f.peaks() == [0.0; 4] && f.means == [0.0; 4]);

    // An even flute count (≥ 4) in a full slot: shear forces Fx, Fy constant at every angle,
    // −N·a·c·Krc/4 and N·a·c·Ktc/4, with or without a helix.
    for (flutes, helix) in [(4, 0.0), (4, 30.0), (6, 45.0)] {
        let c = cutter("flat", flutes, helix);
        let e = engagement(0.0, 4.0, 0.0, 180.0, &opts);
        let u = unit(&c, &e, 360);
        let shear = [K.ktc, K.krc, K.kac, 0.0, 0.0, 0.0];
        let f = u.combine(shear, 0.1);
        let n = flutes as f64;
        for j in 0..360 {
            assert!(
                (f.at(0, j) + n * 4.0 * 0.1 * K.krc / 4.0).abs() < 1e-9 * n * K.krc,
                "N={flutes} i={helix} j={j}: {} vs {}",
                f.at(0, j),
                -n * 4.0 * 0.1 * K.krc / 4.0
            );
            assert!(
                (f.at(1, j) - n * 4.0 * 0.1 * K.ktc / 4.0).abs() < 1e-9 * n * K.ktc,
                "N={flutes} i={helix} j={j}: {} vs {}",
                f.at(1, j),
                n * 4.0 * 0.1 * K.ktc / 4.0
            );
        }
    }

    // Doubling the feed per tooth doubles the shear part only.
    let c = cutter("flat", 3, 30.0);
    let e = engagement(0.0, 4.0, 40.0, 170.0, &opts);
    let u = unit(&c, &e, 360);
    let edge = u.combine(K.as_array(), 0.0);
    let f1 = u.combine(K.as_array(), 0.1);
    let f2 = u.combine(K.as_array(), 0.2);
    for o in 0..4 {
        for j in 0..360 {
            let s1 = f1.at(o, j) - edge.at(o, j);
            let s2 = f2.at(o, j) - edge.at(o, j);
            assert!((s2 - 2.0 * s1).abs() < 1e-9 * s1.abs().max(1.0));
        }
    }
    assert!(edge.peaks().iter().any(|&p| p > 1.0));

    // Ball and bull-nose reduce to the flat end mill where κ = 90° (their cylinder): the same
    // discs give the same means, and without a helix the same curves.
    for kind in ["ball", "bull"] {
        for helix in [0.0, 30.0] {
            let flat = cutter("flat", 3, helix);
            let other = cutter(kind, 3, helix);
            let e = engagement(6.0, 9.0, 10.0, 160.0, &opts);
            let (uf, uo) = (unit(&flat, &e, 360), unit(&other, &e, 360));
            let (ff, fo) = (uf.combine(K.as_array(), 0.1), uo.combine(K.as_array(), 0.1));
            for o in 0..4 {
                assert!((ff.means[o] - fo.means[o]).abs() < 1e-9 * ff.means[o].abs().max(1.0));
                if helix == 0.0 {
                    for j in 0..360 {
                        assert!(
                            (ff.at(o, j) - fo.at(o, j)).abs() < 1e-9 * ff.peaks()[o].max(1.0),
                            "{kind} {o} {j}: {} vs {}",
                            ff.at(o, j),
                            fo.at(o, j)
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn ball_end_chip_thins_towards_the_tip() {
    // On the ball, h = c·sin φ·sin κ, κ = θ the polar angle, ds = R dθ: the mean Fz of the disc
    // whose slab is z ∈ [1, 1.1], engaged on φ ∈ [0, π], which only the axial components carry,
    // is F̄z = N/2π·∫∫(Kac·c·sin φ·sin²κ + Kae·sin κ + (Krc·c·sin φ·sin κ + Kre)·cos κ) dφ ds,
    // integrated along the profile over the slab (not at its circle):
    // ∫sin²θ R dθ = R·[θ/2 − sin 2θ/4], ∫sin θ cos θ R dθ = R·[sin²θ/2], ∫sin θ R dθ = Δz,
    // ∫cos θ R dθ = R·[sin θ].
    let opts = EngageOptions::default();
    let c = cutter("ball", 2, 0.0);
    let z = 1.05;
    let e = engagement(z - 0.01, z + 0.01, 0.0, 180.0, &opts);
    let mut e = e;
    e.side_extent_mm = None;
    let u = unit(&c, &e, 360);
    let f = u.combine(K.as_array(), 0.1);
    let r = 5.0f64;
    let (a, b) = (1.0f64, 1.1f64);
    let theta = |z: f64| (1.0 - z / r).acos();
    let (ta, tb) = (theta(a), theta(b));
    let br = |g: &dyn Fn(f64) -> f64| g(tb) - g(ta);
    let sin2 = r * br(&|t| t / 2.0 - (2.0 * t).sin() / 4.0);
    let sin_cos = r * br(&|t| t.sin() * t.sin() / 2.0);
    let sin = b - a;
    let cos = r * br(&f64::sin);
    // ∫_0^π sin φ = 2, ∫ 1 = π.
    let want = 2.0 / TAU
        * (K.kac * 0.1 * 2.0 * sin2
            + K.kae * PI * sin
            + K.krc * 0.1 * 2.0 * sin_cos
            + K.kre * PI * cos);
    assert!(
        (f.means[2] - want).abs() < 1e-9 * want,
        "{} vs {want}",
        f.means[2]
    );
}
