//! Ray intersections of whole cutters against brute-force sampling of `contains` along the
//! ray, for named cutters and random valid APT parameter sets (proptest); joints of random
//! cutters are continuous and tangent.

use proptest::prelude::*;
use swarf_geom::math::Vec3;
use swarf_geom::Ray;
use swarf_tool::cutter::joint_errors;
use swarf_tool::Cutter;

/// Checks, along `ray` over `[t0, t1]`:
/// * between consecutive hits, `contains` at the midpoint equals the parity (inside after an
///   odd number of crossings);
/// * every change of `contains` found by dense sampling has a reported hit within one step.
fn check(c: &Cutter, ray: &Ray, t0: f64, t1: f64) -> Result<(), String> {
    let mut hits = Vec::new();
    c.ray_intersections(ray, &mut hits);
    if hits.windows(2).any(|w| w[0] > w[1]) {
        return Err(format!("unsorted {hits:?}"));
    }
    let mut inside = false;
    let mut prev = f64::NEG_INFINITY;
    for (i, &t) in hits
        .iter()
        .chain(std::iter::once(&f64::INFINITY))
        .enumerate()
    {
        let mid = if prev.is_infinite() {
            t - 1.0
        } else if t.is_infinite() {
            prev + 1.0
        } else {
            0.5 * (prev + t)
        };
        // Skip slivers where the midpoint is within rounding of the boundary.
        let long_enough =
            prev.is_infinite() || t.is_infinite() || (t - prev) * ray.dir.length() > 1e-6;
        if long_enough && c.contains(ray.at(mid)) != inside {
            return Err(format!(
                "parity broken in interval {i} (t = {mid}); hits {hits:?}"
            ));
        }
        inside = !inside;
        prev = t;
    }
    let n = 4000;
    let step = (t1 - t0) / n as f64;
    let mut was = c.contains(ray.at(t0));
    for k in 1..=n {
        let t = t0 + step * k as f64;
        let now = c.contains(ray.at(t));
        if now != was && !hits.iter().any(|&h| h >= t - step - 1e-9 && h <= t + 1e-9) {
            return Err(format!(
                "containment changes in [{}, {t}] but no hit there; hits {hits:?}",
                t - step
            ));
        }
        was = now;
    }
    Ok(())
}

fn rays_through(c: &Cutter) -> Vec<Ray> {
    let h = c.apt_params().h;
    let r = c.max_diameter() / 2.0;
    let mut rays = Vec::new();
    for i in 0..40 {
        let a = i as f64 * 0.37;
        let z = h * (i as f64 / 39.0) * 1.1 - 0.05 * h;
        let target = Vec3::new(0.3 * r * a.cos(), 0.2 * r * a.sin(), z);
        let dir = Vec3::new(a.cos(), a.sin(), 0.6 * (a * 1.7).sin());
        rays.push(Ray::new(target - dir * 3.0 * (r + h), dir));
    }
    // Axis-aligned rays, as the tri-dexel workpiece casts them.
    for k in 0..10 {
        let x = r * (k as f64 / 9.0) * 1.05 + 1e-3;
        rays.push(Ray::new(Vec3::new(x, 0.1, -5.0), Vec3::Z));
        rays.push(Ray::new(
            Vec3::new(-2.0 * r, 0.05, h * k as f64 / 10.0 + 1e-3),
            Vec3::X,
        ));
    }
    rays
}

#[test]
fn named_cutters_agree_with_containment() {
    let cutters = [
        Cutter::flat(12.0).unwrap(),
        Cutter::ball(10.0).unwrap(),
        Cutter::bull(16.0, 2.0).unwrap(),
        Cutter::taper_flat(10.0, 5.0).unwrap(),
        Cutter::taper_ball(6.0, 3.0).unwrap(),
        Cutter::chamfer(10.0, 90.0).unwrap(),
        Cutter::drill(8.0, 118.0).unwrap(),
    ];
    for c in &cutters {
        for ray in rays_through(c) {
            let span = 6.0 * (c.max_diameter() + c.apt_params().h) / ray.dir.length();
            if let Err(e) = check(c, &ray, 0.0, span) {
                panic!("{}: ray {ray:?}: {e}", c.spec());
            }
        }
    }
}

#[test]
fn bull_nose_hits_analytic() {
    // Horizontal ray at z = 1 through the axis: torus crossings at x = ±(6 + √3).
    let c = Cutter::bull(16.0, 2.0).unwrap();
    let mut h = Vec::new();
    c.ray_intersections(&Ray::new(Vec3::new(-20.0, 0.0, 1.0), Vec3::X), &mut h);
    let x = 6.0 + 3f64.sqrt();
    assert_eq!(h.len(), 2, "{h:?}");
    assert!(
        (h[0] - (20.0 - x)).abs() < 1e-9 && (h[1] - (20.0 + x)).abs() < 1e-9,
        "{h:?}"
    );
    // Vertical ray at ρ = 7: the torus bottom at z = 2 − √3, then the top cap at 48.
    h.clear();
    c.ray_intersections(&Ray::new(Vec3::new(7.0, 0.0, -1.0), Vec3::Z), &mut h);
    assert_eq!(h.len(), 2, "{h:?}");
    assert!(
        (h[0] - (1.0 + 2.0 - 3f64.sqrt())).abs() < 1e-9 && (h[1] - 49.0).abs() < 1e-12,
        "{h:?}"
    );
}

/// Random valid APT parameters: (d, r, e, f, α°, β°, h).
fn apt_params() -> impl Strategy<Value = (f64, f64, f64, f64, f64, f64, f64)> {
    (
        1.0f64..30.0,
        0.0f64..1.0,
        0.0f64..60.0,
        -20.0f64..40.0,
        0.05f64..3.0,
    )
        .prop_map(|(d, rf, a, b, hx)| {
            let b = b.min(90.0 - a);
            let r = rf * d / 2.0;
            let (al, be) = (a.to_radians(), b.to_radians());
            let e = (d / 2.0 - r * be.cos()).max(0.0);
            let f = (r + e * al.sin()) / al.cos();
            let h = f - r * be.sin() + hx * d;
            (d, r, e, f, a, b, h)
        })
}

proptest! {
    #![proptest_config(swarf_testdata::proptest_config(200))]

    #[test]
    fn random_apt_cutters_join_and_agree(p in apt_params(), ox in -1.0f64..1.0, oy in -1.0f64..1.0,
                                         oz in -0.2f64..1.2, dx in -1.0f64..1.0, dy in -1.0f64..1.0,
                                         dz in -1.0f64..1.0) {
        let (d, r, e, f, a, b, h) = p;
        let c = match Cutter::apt(d, r, e, f, a, b, h) {
            Ok(c) => c,
            Err(swarf_tool::ToolError::SideReachesAxis { .. }) => return Ok(()),
            Err(err) => return Err(TestCaseError::fail(format!("valid parameters rejected: {err}"))),
        };
        let (gap, ang) = joint_errors(&c);
        prop_assert!(gap < 1e-12 * d.max(1.0), "gap {}", gap);
        prop_assert!(ang < 1e-9, "angle {}", ang);
        // The profile is continuous: radius from both sides of each joint agree.
        let dir = Vec3::new(dx, dy, dz);
        prop_assume!(dir.length() > 0.1);
        let rmax = c.max_diameter() / 2.0;
        let target = Vec3::new(ox * rmax, oy * rmax, oz * h);
        let span = 4.0 * (rmax + h) / dir.length();
        let ray = Ray::new(target - dir * span / 2.0, dir);
        let res = check(&c, &ray, 0.0, span);
        prop_assert!(res.is_ok(), "{}: {}", c.spec(), res.unwrap_err());
    }
}
