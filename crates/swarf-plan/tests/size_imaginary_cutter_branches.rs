//! Every branch of the imaginary cutter size, checked against geometry: the cutter of the
//! computed size, placed tangent at the CC point, passes through the test point (to 1e-9 mm),
//! touches the CC point with the surface normal, and is the *smallest* such cutter (a slightly
//! smaller one leaves the point outside, a slightly larger one swallows it). The placed profile
//! itself is checked against swarf-tool's independent APT cutter.

use swarf_geom::math::Vec3;
use swarf_plan::size::{Contact, CutterFamily, PlacedCutter, Regime, SizeTolerances};

const TOL: SizeTolerances = SizeTolerances::DEFAULT;

fn contact(point: Vec3, normal: Vec3) -> Contact {
    Contact {
        point,
        normal: normal.normalize(),
        curvature: None,
    }
}

/// Checks a finite, positive imaginary size against the placed cutter; returns it.
fn check_finite(f: &CutterFamily, c: &Contact, p: Vec3) -> f64 {
    let reg = f.regime(c, &TOL);
    let l = f.imaginary(c, &reg, p, &TOL);
    assert!(
        l.is_finite() && l > 0.0,
        "expected a finite size, got {l} for {p:?}"
    );
    let k = f.placed(c, &reg, l).unwrap();
    let scale = 1.0 + l;
    assert!(
        k.signed_distance(p).abs() < 1e-9 * scale,
        "P is {} from the cutter of size {l}",
        k.signed_distance(p)
    );
    assert!(
        k.signed_distance(c.point).abs() < 1e-9 * scale,
        "C is {} from the cutter",
        k.signed_distance(c.point)
    );
    if k.r == 0.0 && k.big_r > 0.0 {
        // A sharp edge touches C: −n must lie in the edge's normal cone, between the bottom's
        // (−z) and the side's normals in the meridian plane.
        let m = -c.normal;
        let (_, _, e) = k.meridian(c.point);
        let off_plane = m - m.dot(e) * e - m.z * Vec3::Z;
        assert!(off_plane.length() < 1e-9 && m.dot(e) >= -1e-12 && m.z <= 1e-12);
    } else if !matches!(reg, Regime::Bottom) || c.normal.z > 1.0 - 1e-12 {
        let m = k.outward_normal(c.point);
        assert!(
            (m + c.normal).length() < 1e-7,
            "cutter normal {m:?} at C, surface normal {:?}",
            c.normal
        );
    }
    let smaller = f.placed(c, &reg, l * (1.0 - 1e-6)).unwrap();
    let larger = f.placed(c, &reg, l * (1.0 + 1e-6)).unwrap();
    assert!(
        !smaller.contains(p, 0.0),
        "a smaller cutter already contains P"
    );
    assert!(
        larger.contains(p, 0.0),
        "a larger cutter does not contain P"
    );
    l
}

fn assert_zero(f: &CutterFamily, c: &Contact, p: Vec3) {
    let reg = f.regime(c, &TOL);
    assert_eq!(f.imaginary(c, &reg, p, &TOL), 0.0);
    if let Some(k) = f.placed(c, &reg, 1e-12) {
        assert!(
            k.contains(p, 0.0),
            "size 0 but the smallest cutter misses P"
        );
    }
}

fn assert_infinite(f: &CutterFamily, c: &Contact, p: Vec3) {
    let reg = f.regime(c, &TOL);
    assert_eq!(f.imaginary(c, &reg, p, &TOL), f64::INFINITY);
    let k = f.placed(c, &reg, 1e6).unwrap();
    assert!(!k.contains(p, 0.0), "size ∞ but a huge cutter contains P");
}

#[test]
fn bare_sphere_closed_form() {
    let f = CutterFamily::ball();
    assert_eq!(f, CutterFamily::Sphere);
    let c = contact(Vec3::new(1.0, 0.0, -2.0), Vec3::new(0.1, 0.5, 1.0));
    let p = Vec3::new(-3.0, 2.0, 6.0);
    let l = check_finite(&f, &c, p);
    let d = p - c.point;
    assert!((l - d.length_squared() / (2.0 * c.normal.dot(d))).abs() < 1e-12);
    // High above the ball: the sphere alone reaches it (the side would be sooner).
    let side = CutterFamily::ball_with_side();
    let reg = side.regime(&c, &TOL);
    assert!(side.imaginary(&c, &reg, p, &TOL) < l);
    assert_infinite(&f, &c, c.point - c.normal + Vec3::new(0.5, 0.0, 0.0));
}

#[test]
fn ball_sphere_and_cylinder_branches() {
    let f = CutterFamily::ball_with_side();
    let c = contact(Vec3::ZERO, Vec3::new(0.3, -0.2, 1.0));
    // Sphere branch (eq. 2.35): below the centre.
    let l = check_finite(&f, &c, Vec3::new(3.0, 1.0, 1.0));
    let d = Vec3::new(3.0, 1.0, 1.0);
    assert!((l - d.length_squared() / (2.0 * c.normal.dot(d))).abs() < 1e-12);
    // Cylinder branch: high above, beside the ball.
    let p = Vec3::new(-6.0, 0.0, 30.0);
    let l = check_finite(&f, &c, p);
    let k = f.placed(&c, &f.regime(&c, &TOL), l).unwrap();
    assert!(p.z > k.corner_z, "the point should be met by the cylinder");
    // Behind the tangent plane and under the ball: ∞ (eq. 2.32).
    assert_infinite(&f, &c, Vec3::new(-3.0, 2.0, -1.0));
    // Vertical normal: a plain sphere formula.
    let c = contact(Vec3::new(1.0, 2.0, 3.0), Vec3::Z);
    let l = check_finite(&f, &c, Vec3::new(5.0, 2.0, 5.0));
    assert!((l - 5.0).abs() < 1e-12);
}

#[test]
fn taper_ball_sphere_cone_zero_infinite_and_linear_branches() {
    let f = CutterFamily::taper_ball(10.0).unwrap();
    let c = contact(Vec3::ZERO, Vec3::new(0.2, 0.1, 1.0));
    check_finite(&f, &c, Vec3::new(2.0, 0.5, 0.5)); // sphere
    let p = Vec3::new(-8.0, 1.0, 25.0);
    let l = check_finite(&f, &c, p); // side cone
    let k = f.placed(&c, &f.regime(&c, &TOL), l).unwrap();
    assert!(p.z - k.corner_z > -l * 10f64.to_radians().sin());
    // Inside the cone with apex C (eq. 2.33): 0.
    assert_zero(&f, &c, Vec3::new(0.1, 0.0, 5.0));
    // Behind the tangent plane, low: ∞.
    assert_infinite(&f, &c, Vec3::new(-2.0, -1.0, -3.0));
    // n_z = sin θ: the quadratic is linear (eq. 2.45).
    let th = 10f64.to_radians();
    let n = Vec3::new(th.cos(), 0.0, th.sin());
    let c = contact(Vec3::ZERO, n);
    let reg = f.regime(&c, &TOL);
    assert_eq!(reg, Regime::Ball);
    check_finite(&f, &c, Vec3::new(3.0, 0.5, 10.0));
    // Steeper than the taper: unreachable, 0.
    let c = contact(Vec3::ZERO, Vec3::new(1.0, 0.0, 0.1));
    assert_eq!(f.regime(&c, &TOL), Regime::Unreachable);
    assert_eq!(f.imaginary(&c, &Regime::Unreachable, Vec3::X, &TOL), 0.0);
}

#[test]
fn bull_nose_corner_branches() {
    let f = CutterFamily::bull(2.0).unwrap();
    let c = contact(Vec3::ZERO, Vec3::new(0.5, 0.0, 1.0));
    let reg = f.regime(&c, &TOL);
    let Regime::Corner { q, .. } = reg else {
        panic!("corner regime expected")
    };
    // Side (condition 1, eq. 2.11): above the corner plane.
    let p = Vec3::new(10.0, 1.0, q.z + 3.0);
    check_finite(&f, &c, p);
    // Corner torus (condition 2, eq. 2.22).
    let p = Vec3::new(12.0, -2.0, q.z - 1.0);
    check_finite(&f, &c, p);
    // Inside the smallest cutter (the ball of radius r at Q): 0 (eq. 2.12).
    assert_zero(&f, &c, q + Vec3::new(0.3, 0.2, -0.5));
    // Below the flat bottom: ∞ (ψ = 0, the plane limit of condition 3).
    assert_infinite(&f, &c, Vec3::new(5.0, 0.0, q.z - 2.5));
    // Behind: d·u + t ≤ 0 (eqs. 2.18–2.20): ∞.
    assert_infinite(&f, &c, q + Vec3::new(-5.0, 0.0, -1.0));
}

#[test]
fn apt_with_taper_and_cone_all_three_portions() {
    let f = CutterFamily::apt(1.5, 5.0, 12.0).unwrap();
    let c = contact(Vec3::new(1.0, 1.0, 1.0), Vec3::new(-0.6, 0.3, 1.0));
    let Regime::Corner { q, u } = f.regime(&c, &TOL) else {
        panic!("corner regime expected")
    };
    let side = Vec3::new(0.0, 0.0, 1.0);
    let out = Vec3::new(u.y, -u.x, 0.0); // sideways
    check_finite(&f, &c, q + 6.0 * u + 2.0 * out + 3.0 * side); // tapered side
    check_finite(&f, &c, q + 6.0 * u + 2.0 * out - 1.0 * side); // torus
                                                                // Conical bottom (condition 3, eq. 2.30 with the erratum r/sin ψ): below −r·cos ψ.
    let p = q + 8.0 * u + 1.0 * out - 2.0 * side;
    let l = check_finite(&f, &c, p);
    let k = f.placed(&c, &f.regime(&c, &TOL), l).unwrap();
    assert!(p.z - k.corner_z <= -1.5 * 12f64.to_radians().cos());
    // The same point must NOT satisfy Liu's printed step 12 (2·r·sin ψ): the erratum matters.
    let (r, ps) = (1.5f64, 12f64.to_radians());
    let d = Vec3::new(p.x - q.x, p.y - q.y, 0.0);
    let dz = p.z - q.z;
    let printed = dz / ps.tan() + 2.0 * r * ps.sin();
    let r_printed = (d.length_squared() - printed * printed) / (2.0 * d.dot(u) + 2.0 * printed);
    assert!(
        (r_printed - l).abs() > 1e-3,
        "printed eq. 2.30 agrees: {r_printed} vs {l}"
    );
    assert_zero(&f, &c, q + Vec3::new(0.2, 0.1, -0.3));
    assert_infinite(&f, &c, q - 5.0 * u - 1.0 * side);
}

#[test]
fn flat_end_mill_bottom_convention_and_corner() {
    let f = CutterFamily::flat();
    // Vertical normal: the axis through C (documented convention); R = ρ − t.
    let c = contact(Vec3::new(2.0, 3.0, 0.0), Vec3::Z);
    assert_eq!(f.regime(&c, &TOL), Regime::Bottom);
    let l = check_finite(&f, &c, Vec3::new(7.0, 3.0, 4.0));
    assert!((l - 5.0).abs() < 1e-12);
    // On the floor's plane: touching, never gouged.
    assert_infinite(&f, &c, Vec3::new(9.0, 3.0, 0.0));
    // Below: never.
    assert_infinite(&f, &c, Vec3::new(9.0, 3.0, -1.0));
    // Tilted: the sharp corner touches C; the axis is at C + R·u.
    let c = contact(Vec3::ZERO, Vec3::new(0.3, 0.4, 1.0));
    check_finite(&f, &c, Vec3::new(6.0, 6.0, 2.0));
    // A vertical wall (n horizontal): still reachable by the side.
    let c = contact(Vec3::ZERO, Vec3::X);
    let reg = f.regime(&c, &TOL);
    assert!(matches!(reg, Regime::Corner { .. }));
    check_finite(&f, &c, Vec3::new(4.0, 3.0, 1.0));
    // Tapered flat end mill on a floor: R = ρ − z·tan θ.
    let f = CutterFamily::apt(0.0, 3.0, 0.0).unwrap();
    let c = contact(Vec3::ZERO, Vec3::Z);
    let l = check_finite(&f, &c, Vec3::new(10.0, 0.0, 5.0));
    assert!((l - (10.0 - 5.0 * 3f64.to_radians().tan())).abs() < 1e-12);
}

#[test]
fn conical_bottom_tip_contact_by_bisection() {
    let f = CutterFamily::apt(1.0, 0.0, 20.0).unwrap();
    // A normal 10° from vertical is within ψ = 20°: the tip touches, the axis through C.
    let c = contact(Vec3::ZERO, Vec3::new(10f64.to_radians().tan(), 0.0, 1.0));
    assert_eq!(f.regime(&c, &TOL), Regime::Bottom);
    let p = Vec3::new(6.0, 1.0, 5.0);
    let reg = f.regime(&c, &TOL);
    let l = f.imaginary(&c, &reg, p, &TOL);
    let k = f.placed(&c, &reg, l).unwrap();
    assert!(k.signed_distance(p).abs() < 1e-9);
    assert!((k.tip() - c.point).length() < 1e-12, "the tip sits on C");
    assert!(!f
        .placed(&c, &reg, l * (1.0 - 1e-6))
        .unwrap()
        .contains(p, 0.0));
    // Under the bottom cone: ∞.
    assert_infinite(&f, &c, Vec3::new(6.0, 0.0, 1.0));
}

/// Independent check of the placed profile: swarf-tool's APT cutter with Liu's mapping
/// (e = R, f = R·tan ψ + r·sec ψ, α = ψ, β = θ), tip at the origin.
#[test]
fn placed_profile_matches_swarf_tool_cutter() {
    for &(big_r, r, th_deg, ps_deg) in &[
        (4.0, 2.0, 0.0, 0.0),
        (5.0, 0.0, 0.0, 0.0),
        (0.0, 3.0, 0.0, 0.0),
        (3.0, 1.0, 5.0, 10.0),
        (0.0, 2.0, 8.0, 0.0),
    ] {
        let (th, ps) = (f64::to_radians(th_deg), f64::to_radians(ps_deg));
        let f_h = big_r * ps.tan() + r / ps.cos();
        let d = 2.0 * (big_r + r * th.cos());
        let h = 40.0;
        let tool = swarf_tool::Cutter::apt(d, r, big_r, f_h, ps_deg, th_deg, h).unwrap();
        let mine = PlacedCutter {
            axis: Vec3::ZERO,
            corner_z: f_h,
            big_r,
            r,
            taper: th,
            cone: ps,
            sphere_only: false,
        };
        assert!(mine.tip().length() < 1e-12);
        let mut s = 12345u64;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut checked = 0;
        for _ in 0..4000 {
            let p = Vec3::new(
                (rnd() - 0.5) * 3.0 * d,
                (rnd() - 0.5) * 3.0 * d,
                rnd() * 30.0 - 2.0,
            );
            if mine.signed_distance(p).abs() < 1e-6 {
                continue;
            }
            assert_eq!(
                mine.contains(p, 0.0),
                tool.contains(p),
                "R={big_r} r={r} θ={th_deg} ψ={ps_deg} at {p:?}"
            );
            checked += 1;
        }
        assert!(checked > 3000);
    }
}
