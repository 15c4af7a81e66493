//! The exact swept interval against an independent brute-force reference: the same lines
//! against many sampled tool instances along the move (`Cutter::ray_intersections`, the
//! swarf-tool implementation), for every cutter type, 3-axis and 3+2 axes, and the special
//! moves (plunge along the axis, horizontal, pure vertical, zero length).
//!
//! With `N` samples, the continuous sweep is within `δ = |v|/(2N)` of the sampled union, so
//! (1) every sampled interval must lie inside the exact one, and (2) both exact end points
//! must lie within `δ` of some sampled instance.

mod common;

use common::{boundary_distance, every_cutter_kind, general_apt, Lcg};
use swarf_geom::math::Vec3;
use swarf_geom::{Frame, Ray};
use swarf_sweep::{ConvexProfile, Element, SweptConvex};
use swarf_tool::Cutter;

/// Distance from `(ρ, z)` to the closed profile region (0 inside).
fn profile_distance(c: &Cutter, els: &[Element], rho: f64, z: f64) -> f64 {
    if c.contains(Vec3::new(rho, 0.0, z)) {
        0.0
    } else {
        boundary_distance(els, rho, z)
    }
}

struct Case {
    cutter: Cutter,
    tip: Vec3,
    axis: Vec3,
    delta: Vec3,
}

fn check_case(case: &Case, rng: &mut Lcg, rays: usize, samples: usize) -> (usize, f64) {
    let prof = ConvexProfile::from_solid(case.cutter.cutting_solid()).unwrap();
    let els = prof.elements().to_vec();
    let sw = SweptConvex::new(&prof, case.tip, case.axis, case.delta);
    let frame = Frame::from_axis(Vec3::ZERO, case.axis);
    let delta_bound = case.delta.length() / (2.0 * samples as f64);
    let h = case.cutter.apt_params().h;
    let rmax = case.cutter.max_diameter() / 2.0;
    let mut hits = Vec::new();
    let mut checked = 0;
    let mut worst_excess: f64 = 0.0;
    for ri in 0..rays {
        // A line through a random point near the swept region, axis-aligned (the dexel case)
        // for a third of the rays, arbitrary otherwise.
        let s0 = rng.next_f64();
        let anchor = case.tip
            + case.delta * s0
            + case.axis * rng.range(-0.2 * h, 1.1 * h)
            + rng.unit() * rng.range(0.0, 1.2 * rmax);
        let dir = if ri % 3 == 0 {
            Vec3::AXES[ri / 3 % 3]
        } else {
            rng.unit()
        };
        let origin = anchor - dir * 100.0;
        let exact = sw.ray_interval(origin, dir);
        // Sampled union.
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for i in 0..=samples {
            let s = i as f64 / samples as f64;
            let tip = case.tip + case.delta * s;
            let ray = Ray::new(
                frame.vector_to_local(origin - tip),
                frame.vector_to_local(dir),
            );
            hits.clear();
            case.cutter.ray_intersections(&ray, &mut hits);
            if hits.len() >= 2 {
                lo = lo.min(hits[0]);
                hi = hi.max(*hits.last().unwrap());
            }
        }
        let sampled = (lo <= hi).then_some((lo, hi));
        let tol = 1e-7;
        match (exact, sampled) {
            (None, Some(s)) => panic!(
                "exact misses, samples hit {s:?}: cutter {}, tip {}, axis {}, delta {}, origin {origin}, dir {dir}",
                case.cutter.spec(), case.tip, case.axis, case.delta
            ),
            (Some((a, b)), s) => {
                if let Some((sa, sb)) = s {
                    assert!(
                        a <= sa + tol && b >= sb - tol,
                        "exact [{a}, {b}] does not contain sampled [{sa}, {sb}]: cutter {}, tip {}, axis {}, delta {}, origin {origin}, dir {dir}",
                        case.cutter.spec(), case.tip, case.axis, case.delta
                    );
                    worst_excess = worst_excess.max(sa - a).max(b - sb);
                }
                for t in [a, b] {
                    let p = origin + dir * t;
                    let mut best = f64::INFINITY;
                    for i in 0..=samples {
                        let s = i as f64 / samples as f64;
                        let q = frame.vector_to_local(p - (case.tip + case.delta * s));
                        best = best.min(profile_distance(&case.cutter, &els, q.x.hypot(q.y), q.z));
                        if best <= delta_bound {
                            break;
                        }
                    }
                    assert!(
                        best <= delta_bound + tol,
                        "exact end {t} is {best} from every sample (bound {delta_bound}): cutter {}, tip {}, axis {}, delta {}, origin {origin}, dir {dir}, exact [{a}, {b}], sampled {s:?}",
                        case.cutter.spec(), case.tip, case.axis, case.delta
                    );
                }
                checked += 1;
            }
            (None, None) => {}
        }
    }
    (checked, worst_excess)
}

fn cutters(rng: &mut Lcg) -> Vec<Cutter> {
    every_cutter_kind(rng, 3.0, 16.0, general_apt(10.0, 2.0, 25.0))
}

#[test]
fn exact_interval_brackets_sampled_sweep() {
    let mut rng = Lcg(0x5eed_2026);
    let mut total = 0;
    let mut worst: f64 = 0.0;
    for round in 0..6 {
        for cutter in cutters(&mut rng) {
            let axis = if round % 2 == 0 { Vec3::Z } else { rng.unit() };
            let frame = Frame::from_axis(Vec3::ZERO, axis);
            let len = rng.range(0.5, 30.0);
            let general = rng.unit() * len;
            let deltas = [
                general,
                axis * -len,                           // plunge along the axis
                axis * len,                            // retract along the axis
                (frame.x * 0.6 + frame.y * 0.8) * len, // horizontal (⊥ axis)
                (frame.x + axis * 1e-3) * len,         // nearly horizontal
                Vec3::Z * -len,                        // pure vertical
                Vec3::ZERO,                            // zero length
            ];
            for delta in deltas {
                let case = Case {
                    cutter: cutter.clone(),
                    tip: Vec3::new(
                        rng.range(-5.0, 5.0),
                        rng.range(-5.0, 5.0),
                        rng.range(-5.0, 5.0),
                    ),
                    axis,
                    delta,
                };
                let (n, w) = check_case(&case, &mut rng, 24, 300);
                total += n;
                worst = worst.max(w);
            }
        }
    }
    println!(
        "checked {total} intersecting lines; largest excess over the sampled union {worst:.3e} mm"
    );
    assert!(total > 2000, "too few lines met the sweeps: {total}");
}
