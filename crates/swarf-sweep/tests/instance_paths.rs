//! The closed-form kernels of a tool instance (no motion; flat, ball and bull-nose profiles and
//! shank slabs at any axis, rays along world axes) against the general exact candidates of the
//! same instance: the whole chords agree to 1e-9 mm, and with a ray's material given, the part
//! of the cut that meets the material is the same as the general path's.

use swarf_geom::math::Vec3;
use swarf_sweep::swept::{DexelRays, Interval, Scratch};
use swarf_sweep::{ConvexProfile, InstanceSet, SweepShape, SweptConvex};
use swarf_tool::Cutter;

mod common;
use common::{both_answers, Rng};

/// Cutting parts and shank slabs of random flat, ball and bull-nose cutters.
fn profiles(rng: &mut Rng) -> Vec<ConvexProfile> {
    let d = rng.range(1.0, 20.0);
    let r = rng.range(0.05, 0.5) * d;
    let fl = rng.range(1.0, 4.0) * d;
    let mut out = Vec::new();
    for spec in [
        format!("ball:d={d}"),
        format!("flat:d={d},flute-length={fl}"),
        format!("bull:d={d},r={r}"),
        format!("bull:d={d},r={r},flute-length={fl}"),
    ] {
        let c = Cutter::from_spec(&spec).unwrap();
        out.push(ConvexProfile::from_solid(c.cutting_solid()).unwrap());
        out.extend(
            SweepShape::from_solid(c.shank_solid())
                .parts()
                .iter()
                .cloned(),
        );
    }
    out
}

/// Random unit axes: any direction, near a world axis, in a coordinate plane.
fn axis(rng: &mut Rng) -> Vec3 {
    let a = match rng.pick(4) {
        0 => Vec3::new(1e-7, rng.range(-1e-7, 1e-7), 1.0),
        1 => Vec3::new(rng.range(-1.0, 1.0), 0.0, rng.range(-1.0, 1.0)),
        _ => Vec3::new(
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        ),
    };
    if a.length() < 1e-3 {
        Vec3::Z
    } else {
        a.normalize()
    }
}

/// Calls `f` with the generator and random instances: `rounds` rounds of [`profiles`], each at
/// a random [`axis`] with its tip within `spread` of the origin.
fn for_instances(
    seed: u64,
    rounds: usize,
    spread: f64,
    mut f: impl FnMut(&mut Rng, &ConvexProfile, Vec3, Vec3),
) {
    let mut rng = Rng(seed);
    for _ in 0..rounds {
        for prof in profiles(&mut rng) {
            let axis = axis(&mut rng);
            let tip = Vec3::new(
                rng.range(-spread, spread),
                rng.range(-spread, spread),
                rng.range(-spread, spread),
            );
            f(&mut rng, &prof, tip, axis);
        }
    }
}

#[test]
fn instance_chords_match_general_candidates() {
    let (mut worst, mut hits, mut corner) = (0.0f64, 0usize, 0usize);
    for_instances(0x1257_2026, 60, 80.0, |rng, prof, tip, axis| {
        let sw = SweptConvex::new(prof, tip, axis, Vec3::ZERO);
        assert!(sw.has_closed_form(), "{:?}", prof.elements());
        let bb = sw.bbox();
        for _ in 0..400 {
            let k = rng.pick(3);
            let o = rng.point_in(&bb, 0.1);
            let (fast, general, e) = both_answers(&sw, o, k);
            assert!(
                e.is_some_and(|e| e <= 1e-9),
                "{:?}: tip {tip} axis {axis}, ray along {k} through {o}: \
                 instance {fast:?} vs general {general:?}",
                prof.elements()
            );
            if let (Some(f), Some(_)) = (fast, general) {
                worst = worst.max(e.unwrap_or(0.0));
                hits += 1;
                // Ends below the slab of a rounded end (the lozenge's part).
                let low = |t: f64| {
                    let mut q = o;
                    q[k] = t;
                    (q - tip).dot(axis)
                };
                if low(f.0).min(low(f.1)) < 0.5 * bb.size().min_element() {
                    corner += 1;
                }
            }
        }
    });
    println!("compared {hits} hits ({corner} near the end); worst {worst:.3e} mm");
    assert!(hits > 80_000 && corner > 10_000, "{hits} {corner}");
}

/// The stock's query: with the ray's material given, the removed part of the material is the
/// general chord's (the kernel may stop at an end beyond the material), a ray whose material
/// misses the instance is left without an exact query, and cutting the same instance again
/// removes nothing.
#[test]
fn instance_cuts_are_exact_on_the_material() {
    let (mut compared, mut skipped, mut recut) = (0usize, 0usize, 0usize);
    for_instances(0xc07_2026, 40, 30.0, |rng, prof, tip, axis| {
        let sw = SweptConvex::new(prof, tip, axis, Vec3::ZERO);
        let bb = sw.bbox();
        let rays: Vec<_> = (0..3).map(|k| sw.dexel_rays(k)).collect();
        let mut scratch = Scratch::new();
        for _ in 0..300 {
            let k = rng.pick(3);
            let p = rng.point_in(&bb, 0.1);
            let (cu, cv) = (p[(k + 1) % 3], p[(k + 2) % 3]);
            // One or two material intervals anywhere along the box.
            let (lo, hi) = (bb.min[k] - 5.0, bb.max[k] + 5.0);
            let mut ts: Vec<f64> = (0..2 * (1 + rng.pick(2)))
                .map(|_| rng.range(lo, hi))
                .collect();
            ts.sort_by(f64::total_cmp);
            let dex: Vec<Interval> = ts
                .chunks(2)
                .map(|c| Interval {
                    enter: c[0],
                    exit: c[1],
                })
                .collect();
            let mut o = p;
            o[k] = 0.0;
            let general = sw.ray_interval(o, Vec3::AXES[k]);
            let (tested, cut) = sw.dexel_cut((cu, cv), k, &dex, &rays[k], &mut scratch);
            let on_material = |c: Option<(f64, f64)>| -> Vec<(f64, f64)> {
                c.map(|(a, b)| {
                    dex.iter()
                        .map(|iv| (iv.enter.max(a), iv.exit.min(b)))
                        .filter(|(x, y)| x < y)
                        .collect()
                })
                .unwrap_or_default()
            };
            let (want, got) = (on_material(general), on_material(cut));
            if !tested {
                skipped += 1;
                assert!(
                    want.iter().all(|(a, b)| b - a <= 1e-6),
                    "skipped a ray the instance cuts: {want:?}"
                );
                continue;
            }
            let close = |x: &[(f64, f64)], y: &[(f64, f64)]| {
                x.len() == y.len()
                    && x.iter()
                        .zip(y)
                        .all(|(a, b)| (a.0 - b.0).abs() <= 1e-9 && (a.1 - b.1).abs() <= 1e-9)
            };
            // (A tangent line may leave a sliver in one and not the other.)
            let slivers = |x: &[(f64, f64)]| -> Vec<(f64, f64)> {
                x.iter().copied().filter(|(a, b)| b - a > 1e-6).collect()
            };
            assert!(
                close(&want, &got) || close(&slivers(&want), &slivers(&got)),
                "{:?}: tip {tip} axis {axis} ray {k} ({cu}, {cv}) material {dex:?}: \
                 general {want:?} vs instance {got:?}",
                prof.elements()
            );
            compared += 1;
            // Cutting the same instance again removes nothing more (not even a sliver).
            if let Some((a, b)) = cut {
                let mut left = Vec::new();
                for iv in &dex {
                    for (x, y) in [(iv.enter, iv.exit.min(a)), (iv.enter.max(b), iv.exit)] {
                        if x < y {
                            left.push(Interval { enter: x, exit: y });
                        }
                    }
                }
                let (_, again) = sw.dexel_cut((cu, cv), k, &left, &rays[k], &mut scratch);
                if let Some((a2, b2)) = again {
                    for iv in &left {
                        assert!(
                            iv.enter.max(a2) >= iv.exit.min(b2),
                            "{:?}: tip {tip} axis {axis} ray {k} ({cu}, {cv}): the second \
                             cut {again:?} meets {iv:?} (first {cut:?})",
                            prof.elements()
                        );
                    }
                }
                recut += 1;
            }
        }
    });
    println!("compared {compared} cuts ({recut} cut again), {skipped} rays left without a query");
    assert!(
        compared > 20_000 && skipped > 5_000 && recut > 10_000,
        "{compared} {skipped} {recut}"
    );
}

/// The tile test's range for a square block of rays holds the chord of every ray of the block
/// (a tile skipped by it holds no ray the instance meets).
#[test]
fn block_range_holds_every_ray_of_the_block() {
    let mut checked = 0usize;
    for_instances(0xb10c_2026, 30, 30.0, |rng, prof, tip, axis| {
        let sw = SweptConvex::new(prof, tip, axis, Vec3::ZERO);
        let bb = sw.bbox();
        for _ in 0..40 {
            let k = rng.pick(3);
            let half = rng.range(0.05, 3.0);
            let centre = rng.point_in(&bb, 0.2);
            let range = sw.block_range(k, centre, half);
            for _ in 0..25 {
                let o = rng.across(centre, k, half);
                let Some((lo, hi)) = sw.axis_ray_interval(o, k) else {
                    continue;
                };
                let (a, b) = range.unwrap_or_else(|| {
                    panic!("block at {centre} ±{half} along {k}: none, ray {o} has {lo}..{hi}")
                });
                assert!(
                    a <= lo + 1e-9 && hi <= b + 1e-9,
                    "block {a}..{b} misses the ray's {lo}..{hi}"
                );
                // (The bounding box holds it too: an axis within 1e-7 of a world axis
                // once made it 1e-8 mm short.)
                assert!(
                    bb.min[k] <= lo + 1e-12 && hi <= bb.max[k] + 1e-12,
                    "box {}..{} misses the ray's {lo}..{hi} (axis {axis})",
                    bb.min[k],
                    bb.max[k]
                );
                checked += 1;
            }
        }
    });
    assert!(checked > 5_000, "{checked}");
}

/// A set of instances (a few poses of one profile, near each other or apart) answers a ray
/// with the union of what each instance's own query gives it: the chords joined where they
/// overlap or touch, disjoint and ascending otherwise (the material along the whole ray, so
/// that every chord is exact).
#[test]
fn an_instance_set_joins_its_instances_chords() {
    let mut rng = Rng(0x2026_1128_1107);
    let mut scratch = Scratch::new();
    let (mut joined, mut apart) = (0usize, 0usize);
    let d = [Interval {
        enter: -1e4,
        exit: 1e4,
    }];
    for _ in 0..30 {
        for prof in profiles(&mut rng) {
            let n = 2 + rng.pick(InstanceSet::MAX - 1);
            let a = axis(&mut rng);
            let tip = Vec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            );
            // Steps from a tenth of a millimetre to beyond the tool's size.
            let reach = prof.r_max() * rng.range(0.0, 3.0);
            let step = Vec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            ) * reach
                / 3f64.sqrt();
            let sweeps: Vec<SweptConvex<'_>> = (0..n)
                .map(|i| SweptConvex::new(&prof, tip + step * i as f64, a, Vec3::ZERO))
                .collect();
            let bb = sweeps
                .iter()
                .map(SweptConvex::bbox)
                .reduce(|x, y| x.union(&y))
                .unwrap();
            for k in 0..3 {
                let rays: Vec<DexelRays> = sweeps.iter().map(|s| s.dexel_rays(k)).collect();
                let mut set = InstanceSet::new();
                for r in &rays {
                    assert!(set.push(r), "an instance's rays have its closed form");
                }
                for _ in 0..100 {
                    let o = rng.point_in(&bb, 0.1);
                    let (cu, cv) = (o[(k + 1) % 3], o[(k + 2) % 3]);
                    let mut out = [(0.0, 0.0); InstanceSet::MAX];
                    let (_, m) = set.cut(cu, cv, &d, &mut out);
                    let mut chords: Vec<(f64, f64)> = sweeps
                        .iter()
                        .zip(&rays)
                        .filter_map(|(s, r)| s.dexel_cut((cu, cv), k, &d, r, &mut scratch).1)
                        .collect();
                    chords.sort_by(|x, y| x.0.total_cmp(&y.0));
                    let mut union: Vec<(f64, f64)> = Vec::new();
                    for c in chords {
                        match union.last_mut() {
                            Some(l) if c.0 <= l.1 => l.1 = l.1.max(c.1),
                            _ => union.push(c),
                        }
                    }
                    assert_eq!(&out[..m], &union[..], "ray along {k} through {o}");
                    match m {
                        1 => joined += 1,
                        2.. => apart += 1,
                        _ => {}
                    }
                }
            }
        }
    }
    assert!(
        joined > 5_000 && apart > 500,
        "{joined} joined, {apart} apart"
    );
}

/// Rays grazing the side of a tool whose axis is within 10⁻⁷–5·10⁻² rad of theirs (closer, the
/// axis is taken as theirs): the nearly parallel ones cross the side far from where their
/// quadratic's other root lies (up to 10⁸ mm away), and the nearer root must keep its
/// precision — the division-free roots are taken only up to `DIRECT_ROOTS_MM`, which the
/// steeper ones (tilts of 10⁻² and more) are within.
#[test]
fn rays_nearly_along_the_axis_cross_the_side_where_the_general_path_does() {
    let mut rng = Rng(0x9a2e_2026);
    let (mut worst, mut side) = (0.0f64, 0usize);
    for spec in ["flat:d=10,flute-length=30", "bull:d=10,r=2,flute-length=30"] {
        let c = Cutter::from_spec(spec).unwrap();
        let prof = ConvexProfile::from_solid(c.cutting_solid()).unwrap();
        for tilt in [1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 5e-2] {
            let axis = Vec3::new(tilt, 0.0, 1.0).normalize();
            let sw = SweptConvex::new(&prof, Vec3::ZERO, axis, Vec3::ZERO);
            for _ in 0..400 {
                // At a height z up the side, the side is at x ≈ 5 + tilt·z (φ = 0).
                let z = rng.range(1.0, 29.0);
                let p = Vec3::new(5.0 + tilt * z + rng.range(-1e-3, 1e-3) * tilt, 0.0, 0.0);
                let (fast, general, e) = both_answers(&sw, p, 2);
                assert!(
                    e.is_some_and(|e| e <= 1e-11),
                    "{spec} tilted {tilt}: ray through {p}: instance {fast:?} vs general {general:?}"
                );
                if let (Some(f), Some(_)) = (fast, general) {
                    worst = worst.max(e.unwrap_or(0.0));
                    side += usize::from(f.0 > 0.5);
                }
            }
        }
    }
    println!("{side} chords entering through the side; worst {worst:.3e} mm");
    assert!(side > 4_000, "{side}");
}
