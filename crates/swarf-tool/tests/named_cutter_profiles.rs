//! Profile radius, pieces and joints of every named constructor against hand-derived values.

use swarf_tool::cutter::joint_errors;
use swarf_tool::{AnyPiece, Cutter, CutterKind, Piece};

fn close(a: f64, b: f64, tol: f64) {
    assert!((a - b).abs() <= tol, "{a} vs {b} (tol {tol})");
}

fn shapes(c: &Cutter) -> Vec<&'static str> {
    c.pieces().iter().map(AnyPiece::shape_name).collect()
}

#[test]
fn flat_end_mill() {
    let c = Cutter::flat(12.0).unwrap();
    assert_eq!(shapes(&c), ["disc", "cylinder", "disc"]);
    for z in [0.0, 1e-9, 5.0, 36.0] {
        close(c.profile_radius(z).unwrap(), 6.0, 1e-15);
    }
    assert_eq!(c.profile_radius(-1e-9), None);
    assert_eq!(c.profile_radius(36.0 + 1e-9), None);
    assert_eq!(c.flute_length(), 36.0);
    assert_eq!(c.shank_diameter(), 12.0);
    assert_eq!(c.overall_length(), 60.0);
    assert_eq!(c.max_diameter(), 12.0);
}

#[test]
fn ball_end_mill_centre_at_half_diameter() {
    let c = Cutter::ball(10.0).unwrap();
    assert_eq!(shapes(&c), ["sphere", "cylinder", "disc"]);
    close(c.corner_center().y, 5.0, 0.0);
    close(c.corner_center().x, 0.0, 0.0);
    // ρ(z) = √(z(d − z)) on the ball.
    for z in [0.0, 0.5, 1.0, 2.5, 4.0, 4.999] {
        close(c.profile_radius(z).unwrap(), (z * (10.0 - z)).sqrt(), 1e-12);
    }
    close(c.profile_radius(5.0).unwrap(), 5.0, 1e-12);
    close(c.profile_radius(20.0).unwrap(), 5.0, 0.0);
    let (gap, ang) = joint_errors(&c);
    assert!(gap < 1e-14 && ang < 1e-12, "{gap} {ang}");
}

#[test]
fn bull_nose_torus_joints_tangent() {
    let c = Cutter::bull(16.0, 2.0).unwrap();
    assert_eq!(shapes(&c), ["disc", "torus", "cylinder", "disc"]);
    let a = c.apt_params();
    close(a.e, 6.0, 0.0);
    close(a.f, 2.0, 0.0);
    close(c.profile_radius(0.0).unwrap(), 6.0, 1e-15);
    close(c.profile_radius(1.0).unwrap(), 6.0 + 3f64.sqrt(), 1e-12);
    close(c.profile_radius(2.0).unwrap(), 8.0, 1e-12);
    // The torus normal at its ends equals the disc normal (down) and the cylinder normal (out).
    let t = &c.pieces()[1];
    assert!((t.profile_normal(0.0) - c.pieces()[0].profile_normal(1.0)).length() < 1e-15);
    assert!((t.profile_normal(1.0) - c.pieces()[2].profile_normal(0.0)).length() < 1e-15);
    let (gap, ang) = joint_errors(&c);
    assert!(gap < 1e-14 && ang < 1e-12, "{gap} {ang}");
    // Point evaluation on the torus at s = 0.5 (φ = 45°), θ = 90°.
    let p = t.point(0.5, std::f64::consts::FRAC_PI_2);
    let h = 2f64.sqrt();
    assert!(
        (p - swarf_geom::math::Vec3::new(0.0, 6.0 + h, 2.0 - h)).length() < 1e-12,
        "{p}"
    );
}

#[test]
fn taper_flat_widens_at_taper_angle() {
    let c = Cutter::taper_flat(10.0, 5.0).unwrap();
    assert_eq!(shapes(&c), ["disc", "cone", "disc"]);
    let t = 5f64.to_radians().tan();
    for z in [0.0, 3.0, 30.0] {
        close(c.profile_radius(z).unwrap(), 5.0 + z * t, 1e-12);
    }
    close(c.shank_diameter(), 10.0 + 60.0 * t, 1e-12);
}

#[test]
fn taper_ball_ball_diameter_and_tangent_taper() {
    let c = Cutter::taper_ball(6.0, 3.0).unwrap();
    assert_eq!(c.kind(), CutterKind::TaperBall);
    assert_eq!(shapes(&c), ["sphere", "cone", "disc"]);
    let b = 3f64.to_radians();
    let a = c.apt_params();
    close(a.d, 6.0 * b.cos(), 1e-12);
    close(a.r, 3.0, 0.0);
    // On the ball below the tangent height 3 − 3·sin β the radius is that of the ball.
    let zt = 3.0 - 3.0 * b.sin();
    for z in [0.0, 1.0, 2.0, zt - 1e-9] {
        close(c.profile_radius(z).unwrap(), (z * (6.0 - z)).sqrt(), 1e-9);
    }
    // Above it the side is tangent to the ball: radius = 3·cos β + (z − zt)·tan β.
    for z in [zt + 1e-9, 5.0, 18.0] {
        close(
            c.profile_radius(z).unwrap(),
            3.0 * b.cos() + (z - zt) * b.tan(),
            1e-9,
        );
    }
    let (gap, ang) = joint_errors(&c);
    assert!(gap < 1e-14 && ang < 1e-12, "{gap} {ang}");
}

#[test]
fn chamfer_and_drill_cones() {
    let c = Cutter::chamfer(10.0, 90.0).unwrap();
    assert_eq!(shapes(&c), ["cone", "cylinder", "disc"]);
    close(c.profile_radius(2.0).unwrap(), 2.0, 1e-12);
    close(c.profile_radius(5.0).unwrap(), 5.0, 1e-12);
    close(c.profile_radius(7.0).unwrap(), 5.0, 1e-12);
    assert_eq!(c.helix_deg(), 0.0);
    let d = Cutter::drill(8.0, 118.0).unwrap();
    let cone_h = 4.0 / 59f64.to_radians().tan();
    close(d.apt_params().f, cone_h, 1e-12);
    close(d.apt_params().alpha_deg, 31.0, 1e-12);
    close(d.profile_radius(cone_h / 2.0).unwrap(), 2.0, 1e-12);
    // A very sharp V is taller than 3·d: h grows to the cone height.
    let v = Cutter::chamfer(2.0, 10.0).unwrap();
    close(v.apt_params().h, 1.0 / 5f64.to_radians().tan(), 1e-12);
    assert_eq!(shapes(&v), ["cone", "disc"]);
}

#[test]
fn general_apt_with_every_piece() {
    // α = 10°, β = 5°, r = 2, d = 20: lower cone, torus, upper cone, cap.
    let (d, r, al, be) = (20.0f64, 2.0f64, 10f64.to_radians(), 5f64.to_radians());
    let e = d / 2.0 - r * be.cos();
    let f = (r + e * al.sin()) / al.cos();
    let c = Cutter::apt(d, r, e, f, 10.0, 5.0, 40.0).unwrap();
    assert_eq!(shapes(&c), ["cone", "torus", "cone", "disc"]);
    // Lower cone: ρ = z / tan α.
    close(c.profile_radius(0.5).unwrap(), 0.5 / al.tan(), 1e-12);
    // Diameter d where the corner meets the side.
    let z2 = f - r * be.sin();
    close(c.profile_radius(z2).unwrap(), d / 2.0, 1e-9);
    let (gap, ang) = joint_errors(&c);
    assert!(gap < 1e-13 && ang < 1e-12, "{gap} {ang}");
    // Back taper: β = −2°.
    let be = -2f64.to_radians();
    let e = d / 2.0 - r * be.cos();
    let c = Cutter::apt(d, r, e, r, 0.0, -2.0, 30.0).unwrap();
    assert!(c.profile_radius(30.0).unwrap() < c.profile_radius(5.0).unwrap());
    close(c.max_diameter(), 2.0 * (e + r), 1e-12);
}
