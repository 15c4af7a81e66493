//! Degenerate points (poles, collapsed edges, apices) give limit normals, never NaN.

mod common;

use common::*;
use swarf_geom::math::Vec3;
use swarf_geom::Frame;
use swarf_surface::{
    ConicalSurface, NurbsSurface, ParamBox, ParametricSurface, Patch, SphericalSurface, Surface,
    SurfaceNormal, Tolerances,
};

const TOL: Tolerances = Tolerances::DEFAULT;

#[test]
fn nurbs_sphere_pole_has_the_limit_normal() {
    let r = 5.0;
    let s = Surface::Nurbs(sphere_octant(r));
    for k in 0..=10 {
        let u = k as f64 / 10.0;
        let d = s.derivs(u, 1.0);
        assert!(d.su.length() < 1e-12, "the pole edge is collapsed");
        let g = s.local(u, 1.0, &TOL);
        assert!((g.point() - Vec3::new(0.0, 0.0, r)).length() < 1e-12);
        match g.normal {
            SurfaceNormal::Limit(n) => assert!((n - Vec3::Z).length() < 1e-12, "{n:?} at u = {u}"),
            other => panic!("expected a limit normal at the pole, got {other:?}"),
        }
        // The curvature sampled just inside is the sphere's.
        let c = g.curvature.expect("curvature near the pole");
        assert!(
            (c.k1 + 1.0 / r).abs() < 1e-7 && (c.k2 + 1.0 / r).abs() < 1e-7,
            "{c:?}"
        );
        assert!(c.k1.is_finite() && c.dir1.is_finite() && c.dir2.is_finite());
    }
    // Flipped (machining the inside), the limit normal points to the centre.
    let mut p = Patch::new(s);
    p.flipped = true;
    assert_eq!(
        p.local(0.5, 1.0, &TOL).normal.vector().map(|n| n.z.round()),
        Some(-1.0)
    );
}

#[test]
fn analytic_sphere_poles_and_cone_apex() {
    let f = Frame::from_axis(Vec3::new(1.0, 2.0, 3.0), Vec3::new(0.0, 1.0, 1.0));
    let s = Surface::Sphere(SphericalSurface::new(f, 2.0, SphericalSurface::FULL).unwrap());
    let half_pi = std::f64::consts::FRAC_PI_2;
    for (v, sign) in [(half_pi, 1.0), (-half_pi, -1.0)] {
        for u in [0.0, 1.0, 4.0] {
            let g = s.local(u, v, &TOL);
            match g.normal {
                SurfaceNormal::Limit(n) => assert!((n - sign * f.z).length() < 1e-12, "{n:?}"),
                other => panic!("pole: {other:?}"),
            }
        }
    }
    // A cone with its apex at v = 0: the limit normal along each generator.
    let alpha: f64 = 0.5;
    let c = Surface::Cone(
        ConicalSurface::new(Frame::WORLD, 0.0, alpha, ParamBox::new(0.0, 6.0, 0.0, 5.0)).unwrap(),
    );
    for u in [0.0, 1.0, 2.5] {
        let g = c.local(u, 0.0, &TOL);
        let expected = Vec3::new(alpha.cos() * u.cos(), alpha.cos() * u.sin(), -alpha.sin());
        match g.normal {
            SurfaceNormal::Limit(n) => {
                assert!((n - expected).length() < 1e-12, "{n:?} vs {expected:?}")
            }
            other => panic!("apex: {other:?}"),
        }
    }
}

#[test]
fn fully_collapsed_patch_is_flagged_undefined() {
    // Every control point the same: no normal anywhere, and no NaN either.
    let p = Vec3::new(1.0, 2.0, 3.0);
    let pts = vec![vec![p, p], vec![p, p]];
    let k = vec![0.0, 0.0, 1.0, 1.0];
    let s = Surface::Nurbs(NurbsSurface::new(1, 1, k.clone(), k, &pts, None).unwrap());
    let g = s.local(0.3, 0.4, &TOL);
    assert_eq!(g.normal, SurfaceNormal::Undefined);
    assert!(g.curvature.is_none());
    assert!((g.point() - p).length() < 1e-14);
}

#[test]
fn parameters_outside_the_domain_are_clamped() {
    let s = Surface::Nurbs(quarter_cylinder(2.0, 1.0));
    let g = s.local(-3.0, 7.0, &TOL);
    assert_eq!(g.uv, (0.0, 1.0));
    assert!((g.point() - Vec3::new(2.0, 0.0, 1.0)).length() < 1e-12);
}
