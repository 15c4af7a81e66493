//! The closed-form kernels (slab, ball-end and bull-nose profiles, tool axis along a world axis,
//! rays along world axes) against the general exact candidates of the same sweep, on random
//! moves of random cutters, special moves included (plunge and retract along the axis, moves
//! along and across each ray family, zero length): the two agree to 1e-9 mm, and the stock
//! update's query through each family's kernel removes the closed form's chord of the material.

use swarf_geom::math::Vec3;
use swarf_sweep::swept::{Interval, Scratch};
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
    let family = [0, 1, 2].map(|k| sw.dexel_rays(k));
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
        // The stock update's query, through the family's kernel as the tile loop resolves it
        // (`SweptConvex::with_kernel`), against the closed form's chord held to the general
        // one above.
        cuts_what_the_chord_holds(&sw, &family[k], p, k, fast, 1e-12, rng);
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
    // Tilted and moving, a bull-nose, a ball end or a slab takes the tilted closed form
    // (`tilted_closed_form_matches_general_candidates`); a taper the general path.
    for cutter in [
        bull,
        Cutter::ball(10.0).unwrap(),
        Cutter::flat(10.0).unwrap(),
    ] {
        let prof = ConvexProfile::from_solid(cutter.cutting_solid()).unwrap();
        let sw = SweptConvex::new(&prof, Vec3::ZERO, Vec3::new(0.0, 0.6, 0.8), Vec3::X);
        assert!(sw.has_closed_form());
        let sw = SweptConvex::new(&prof, Vec3::ZERO, Vec3::Z, Vec3::X);
        assert!(sw.has_closed_form());
    }
    let taper = Cutter::taper_flat(4.0, 8.0).unwrap();
    let prof = ConvexProfile::from_solid(taper.cutting_solid()).unwrap();
    let sw = SweptConvex::new(&prof, Vec3::ZERO, Vec3::new(0.0, 0.6, 0.8), Vec3::X);
    assert!(!sw.has_closed_form());
}

/// Whether a chord's ends lie within the spread of the general candidates' ends on the rays
/// 10⁻⁸ mm beside it (a neighbour that misses allows either end anywhere): the test of a ray
/// grazing a side it runs nearly parallel to, where an end moves along the ray by 10⁻⁸ mm
/// divided by the sine of the angle — far more than rounding makes two exact paths differ.
fn within_neighbours(sw: &SweptConvex<'_>, p: Vec3, k: usize, chord: Option<(f64, f64)>) -> bool {
    let (u, w) = ((k + 1) % 3, (k + 2) % 3);
    let (mut lo, mut hi) = (
        (f64::INFINITY, f64::NEG_INFINITY),
        (f64::INFINITY, f64::NEG_INFINITY),
    );
    let mut misses = false;
    for (du, dw) in [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0), (0.0, 0.0)] {
        let mut o = p;
        o[u] += 1e-8 * du;
        o[w] += 1e-8 * dw;
        o[k] = 0.0;
        match sw.ray_interval(o, Vec3::AXES[k]) {
            Some((a, b)) => {
                lo = (lo.0.min(a), lo.1.max(a));
                hi = (hi.0.min(b), hi.1.max(b));
            }
            None => misses = true,
        }
    }
    let Some((a, b)) = chord else {
        return misses;
    };
    let inside = |x: f64, (l, h): (f64, f64)| misses || (l - 1e-9..=h + 1e-9).contains(&x);
    inside(a, lo) && inside(b, hi)
}

/// The stock update's query (`SweptConvex::dexel_cut`: the box prefilter, and the bull-nose's
/// lozenge left out where the slab's chord already holds the material) on material ending
/// inside the chord, beyond it, or clear of it on either side: what it removes of the material
/// is `chord`'s part of it, within `tol`.
fn cuts_what_the_chord_holds(
    sw: &SweptConvex<'_>,
    rays: &swarf_sweep::swept::DexelRays,
    p: Vec3,
    k: usize,
    chord: Option<(f64, f64)>,
    tol: f64,
    rng: &mut Rng,
) {
    let (u, w) = ((k + 1) % 3, (k + 2) % 3);
    let (lo, hi) = chord.unwrap_or((p[k] - 1.0, p[k] + 1.0));
    let len = hi - lo;
    let at = |f: f64| lo + f * len;
    let mut scratch = Scratch::new();
    for _ in 0..4 {
        let (a, b) = (rng.range(-1.5, 2.5), rng.range(-1.5, 2.5));
        let mut material = vec![Interval {
            enter: at(a.min(b)),
            exit: at(a.max(b)) + 1e-6,
        }];
        if rng.pick(2) == 0 {
            // A second interval beyond the first, as after a cut through the ray.
            let c = a.max(b) + rng.range(0.05, 1.0);
            material.push(Interval {
                enter: at(c),
                exit: at(c + rng.range(0.05, 2.0)),
            });
        }
        let (_, hit) = sw.dexel_cut((p[u], p[w]), k, &material, rays, &mut scratch);
        for m in &material {
            let want = chord.map(|(lo, hi)| (lo.max(m.enter), hi.min(m.exit)));
            let got = hit.map(|(a, b)| (a.max(m.enter), b.min(m.exit)));
            let len = |x: Option<(f64, f64)>| x.map_or(0.0, |(a, b)| (b - a).max(0.0));
            match (want.filter(|_| len(want) > 1e-7), got.filter(|_| len(got) > 1e-7)) {
                (None, None) => {}
                (Some(w), Some(g)) => assert!(
                    (w.0 - g.0).abs() <= tol && (w.1 - g.1).abs() <= tol,
                    "ray along {k} through {p}, material {m:?}: removes {g:?}, the chord holds {w:?}"
                ),
                (w, g) => assert!(
                    len(w).max(len(g)) <= 1e-6,
                    "ray along {k} through {p}, material {m:?}: removes {g:?}, the chord holds {w:?}"
                ),
            }
        }
    }
}

/// Flat, ball and bull-nose end mills (cutting parts, shanks, and the bands a 5-axis move cuts
/// them into) moving with a fixed axis off the world axes: the closed form of `tilted.rs` against
/// the general candidates, on random axes (some within 10⁻⁶ rad of a world axis or of the
/// plane of two), random moves and the special ones (along the axis, across it, along each
/// ray family, in the plane of the axis and a ray family), rays through the sweep's box and
/// rays grazing its two end instances.
#[test]
fn tilted_closed_form_matches_general_candidates() {
    let mut rng = Rng(0x7117_2026);
    let (mut worst, mut hits, mut grazing) = (0.0f64, 0, 0u32);
    for round in 0..60 {
        let d = rng.range(1.0, 20.0);
        let fl = rng.range(1.0, 4.0) * d;
        let r = rng.range(0.05, 0.45) * d;
        for spec in [
            format!("flat:d={d}"),
            format!("ball:d={d},flute-length={fl}"),
            format!("bull:d={d},r={r},flute-length={fl}"),
        ] {
            let cutter = Cutter::from_spec(&spec).unwrap();
            let mut profiles: Vec<ConvexProfile> = SweepShape::from_solid(cutter.cutting_solid())
                .bands(0.5 * d)
                .parts()
                .to_vec();
            let bands = profiles.len();
            profiles.push(ConvexProfile::from_solid(cutter.cutting_solid()).unwrap());
            profiles.extend(
                SweepShape::from_solid(cutter.shank_solid())
                    .parts()
                    .iter()
                    .cloned(),
            );
            let axis = match round % 4 {
                0 => rng.unit(),
                // Nearly a world axis, nearly in the plane of two.
                1 => (Vec3::AXES[rng.pick(3)] + rng.unit() * 1e-6).normalize(),
                2 => {
                    let mut a = rng.unit();
                    a[rng.pick(3)] = 1e-7 * rng.range(-1.0, 1.0);
                    a.normalize()
                }
                _ => {
                    let mut a = rng.unit();
                    a[rng.pick(3)] = 0.0;
                    a.normalize()
                }
            };
            let len = rng.range(0.001, 30.0);
            let across = axis.any_orthonormal_pair().0;
            let deltas = [
                rng.unit() * len,
                axis * len,
                axis * -len,
                across * len,
                (across + axis * 0.02) * len,
                Vec3::AXES[rng.pick(3)] * len,
                (Vec3::AXES[rng.pick(3)] * 0.5 + axis).normalize() * len,
            ];
            for delta in deltas {
                let tip = Vec3::new(
                    rng.range(-50.0, 50.0),
                    rng.range(-50.0, 50.0),
                    rng.range(-50.0, 50.0),
                );
                for (i, prof) in profiles.iter().enumerate() {
                    // A round end's band below its spine is a sphere cap or a torus band: no
                    // closed form (5-axis moves cut round tools as instances). Every other part
                    // has one.
                    if !SweptConvex::new(prof, tip, axis, delta).has_closed_form() {
                        assert!(!spec.starts_with("flat") && i < bands, "{spec}: part {i}");
                        continue;
                    }
                    let sw = SweptConvex::new(prof, tip, axis, delta);
                    let bb = sw.bbox();
                    // Rays through the sweep's box, and near the end instances' axes, where
                    // the caps decide.
                    let ends = [tip, tip + delta];
                    for i in 0..190 {
                        let k = rng.pick(3);
                        let p = if i < 150 {
                            rng.point_in(&bb, 0.1)
                        } else {
                            let z = rng.range(prof.z_min(), prof.z_max());
                            rng.across(ends[i % 2] + axis * z, k, 1.2 * prof.r_max())
                        };
                        let (fast, general, e) = both_answers(&sw, p, k);
                        // A ray nearly parallel to the caps' planes (`axis[k]` tiny) ends
                        // where it crosses one, a point that rounding of 10⁻¹³ mm across the
                        // plane moves by 10⁻¹³ / |axis[k]| along the ray (in both paths); one
                        // exactly parallel never ends on them.
                        let tol = if axis[k] == 0.0 {
                            1e-9
                        } else {
                            1e-9 + 1e-13 / axis[k].abs()
                        };
                        let close = e.is_some_and(|e| e <= tol);
                        assert!(
                            close || within_neighbours(&sw, p, k, fast),
                            "{spec}: tip {tip} axis {axis} delta {delta}, ray along {k} through {p}: fast {fast:?} vs general {general:?}"
                        );
                        grazing += u32::from(!close);
                        if fast.is_some() && general.is_some() {
                            if close && axis[k].abs() >= 0.01 {
                                worst = worst.max(e.unwrap_or(0.0));
                            }
                            hits += 1;
                        }
                        let rays = sw.dexel_rays(k);
                        // (Against the closed form's own chord, held to the general one above.)
                        cuts_what_the_chord_holds(&sw, &rays, p, k, fast, 1e-12, &mut rng);
                    }
                }
            }
        }
    }
    println!(
        "tilted: compared {hits} hits; worst disagreement {worst:.3e} mm (rays at least 0.01 rad \
         off the caps' planes); {grazing} grazing rays agree with their neighbours 1e-8 mm away"
    );
    assert!(grazing < 100, "{grazing}");
    assert!(hits > 50_000, "{hits}");
}
