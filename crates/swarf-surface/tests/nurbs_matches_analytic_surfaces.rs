//! Analytic surfaces written exactly as NURBS: points, normals and principal curvatures agree
//! with the closed forms; derivatives agree with finite differences.

mod common;

use common::*;
use swarf_geom::math::Vec3;
use swarf_geom::Frame;
use swarf_surface::{
    ConicalSurface, CylindricalSurface, ParamBox, ParametricSurface, Patch, PlaneSurface,
    SphericalSurface, Surface, SurfaceNormal, Tolerances, ToroidalSurface,
};

const TOL: Tolerances = Tolerances::DEFAULT;

fn grid(n: usize) -> impl Iterator<Item = (f64, f64)> {
    (0..=n).flat_map(move |i| (0..=n).map(move |j| (i as f64 / n as f64, j as f64 / n as f64)))
}

fn regular(n: SurfaceNormal) -> Vec3 {
    match n {
        SurfaceNormal::Regular(v) => v,
        other => panic!("expected a regular normal, got {other:?}"),
    }
}

#[test]
fn quarter_cylinder_points_normals_and_curvatures() {
    let (r, h) = (7.5, 20.0);
    let s = Surface::Nurbs(quarter_cylinder(r, h));
    for (u, v) in grid(20) {
        let g = s.local(u, v, &TOL);
        let p = g.point();
        assert!(
            (p.x.hypot(p.y) - r).abs() < 1e-12,
            "off the cylinder at ({u}, {v})"
        );
        assert!(p.x >= -1e-12 && p.y >= -1e-12 && (p.z - v * h).abs() < 1e-12);
        let n = regular(g.normal);
        let radial = Vec3::new(p.x, p.y, 0.0) / r;
        assert!(
            (n - radial).length() < 1e-12,
            "normal not radial at ({u}, {v})"
        );
        let c = g.curvature.unwrap();
        // Outward normal: the surface bends away from it along the arc.
        assert!(
            c.k1.abs() < 1e-12 && (c.k2 + 1.0 / r).abs() < 1e-12,
            "{c:?}"
        );
        assert!(
            c.dir1.cross(Vec3::Z).length() < 1e-9,
            "zero-curvature direction is the axis"
        );
    }
    // Seen from inside (flipped), the cylinder is concave: k1 = +1/R.
    let mut p = Patch::new(s.clone());
    p.flipped = true;
    let c = p.local(0.3, 0.6, &TOL).curvature.unwrap();
    assert!((c.k1 - 1.0 / r).abs() < 1e-12 && c.k2.abs() < 1e-12);
    assert!(max_fd_error(&s, 8) < 1e-6);
}

#[test]
fn sphere_octant_points_normals_and_umbilic_curvature() {
    let r = 5.0;
    let s = Surface::Nurbs(sphere_octant(r));
    for (u, v) in grid(20) {
        if v == 1.0 {
            continue; // the pole, see degenerate_points.rs
        }
        let g = s.local(u, v, &TOL);
        let p = g.point();
        assert!(
            (p.length() - r).abs() < 1e-12,
            "off the sphere at ({u}, {v})"
        );
        let n = regular(g.normal);
        assert!((n - p / r).length() < 1e-11, "normal at ({u}, {v})");
        let c = g.curvature.unwrap();
        assert!(
            (c.k1 + 1.0 / r).abs() < 1e-12 && (c.k2 + 1.0 / r).abs() < 1e-12,
            "{c:?}"
        );
    }
    assert!(max_fd_error(&s, 8) < 1e-6);
}

#[test]
fn torus_quarter_curvatures_at_the_equators() {
    let (big, r) = (10.0, 3.0);
    let s = Surface::Nurbs(torus_quarter(big, r));
    for (u, v) in grid(16) {
        let g = s.local(u, v, &TOL);
        let p = g.point();
        let rho = p.x.hypot(p.y);
        assert!(
            ((rho - big).hypot(p.z) - r).abs() < 1e-12,
            "off the torus at ({u}, {v})"
        );
        let centre = Vec3::new(p.x, p.y, 0.0) * (big / rho);
        assert!((regular(g.normal) - (p - centre) / r).length() < 1e-11);
    }
    // Outer equator (v = 0): both curvatures negative (convex), −1/(R+r) and −1/r.
    let c = s.local(0.37, 0.0, &TOL).curvature.unwrap();
    assert!((c.k1 + 1.0 / (big + r)).abs() < 1e-12, "{c:?}");
    assert!((c.k2 + 1.0 / r).abs() < 1e-12, "{c:?}");
    // Inner equator (v = 0.5): a saddle, +1/(R−r) around the axis and −1/r around the tube.
    let g = s.local(0.37, 0.5, &TOL);
    let c = g.curvature.unwrap();
    assert!((c.k1 - 1.0 / (big - r)).abs() < 1e-12, "{c:?}");
    assert!((c.k2 + 1.0 / r).abs() < 1e-12, "{c:?}");
    // The +1/(R−r) direction is horizontal (around the axis).
    assert!(c.dir1.z.abs() < 1e-9 && c.dir2.z.abs() > 1.0 - 1e-9);
    assert!(max_fd_error(&s, 8) < 1e-6);
}

#[test]
fn bilinear_plane_has_zero_curvature_and_constant_normal() {
    let s = Surface::Nurbs(bilinear_plane());
    let expected = Vec3::new(-2.0, -3.0, 1.0).normalize();
    for (u, v) in grid(10) {
        let g = s.local(u, v, &TOL);
        let p = g.point();
        assert!((p.z - 2.0 * p.x - 3.0 * p.y).abs() < 1e-12);
        assert!((regular(g.normal) - expected).length() < 1e-12);
        let c = g.curvature.unwrap();
        assert!(c.k1.abs() < 1e-12 && c.k2.abs() < 1e-12, "{c:?}");
    }
    assert!(max_fd_error(&s, 6) < 1e-6);
}

#[test]
fn elementary_surfaces_have_their_closed_form_curvatures() {
    let f = Frame::from_axis_and_x(Vec3::new(1.0, -2.0, 3.0), Vec3::new(0.3, 0.4, 1.0), Vec3::X);
    let cyl = Surface::Cylinder(
        CylindricalSurface::new(f, 4.0, ParamBox::new(0.0, 6.0, -5.0, 5.0)).unwrap(),
    );
    let sph = Surface::Sphere(SphericalSurface::new(f, 5.0, SphericalSurface::FULL).unwrap());
    let tor = Surface::Torus(ToroidalSurface::new(f, 10.0, 3.0, ToroidalSurface::FULL).unwrap());
    let alpha: f64 = 0.4;
    let cone = Surface::Cone(
        ConicalSurface::new(f, 2.0, alpha, ParamBox::new(0.0, 6.0, 0.0, 8.0)).unwrap(),
    );
    let plane = Surface::Plane(PlaneSurface::new(f, ParamBox::new(-3.0, 3.0, -2.0, 2.0)));
    for (u, v) in grid(12) {
        let (uu, vv) = (cyl.domain().u_at(u), cyl.domain().v_at(v));
        let c = cyl.local(uu, vv, &TOL).curvature.unwrap();
        assert!(c.k1.abs() < 1e-12 && (c.k2 + 0.25).abs() < 1e-12);
        if v > 0.0 && v < 1.0 {
            let d = sph.domain();
            let g = sph.local(d.u_at(u), d.v_at(v), &TOL);
            let c = g.curvature.unwrap();
            assert!((c.k1 + 0.2).abs() < 1e-12 && (c.k2 + 0.2).abs() < 1e-12);
            assert!((regular(g.normal) - (g.point() - f.origin) / 5.0).length() < 1e-12);
        }
        let d = tor.domain();
        let (tu, tv) = (d.u_at(u), d.v_at(v));
        let c = tor.local(tu, tv, &TOL).curvature.unwrap();
        // Around the tube −1/r; around the axis −cos v/(R + r cos v).
        let k_par = -tv.cos() / (10.0 + 3.0 * tv.cos());
        let (hi, lo) = (k_par.max(-1.0 / 3.0), k_par.min(-1.0 / 3.0));
        assert!(
            (c.k1 - hi).abs() < 1e-12 && (c.k2 - lo).abs() < 1e-12,
            "{c:?} at v = {tv}"
        );
        let d = cone.domain();
        let (cu, cv) = (d.u_at(u), d.v_at(v));
        let c = cone.local(cu, cv, &TOL).curvature.unwrap();
        let rad = 2.0 + cv * alpha.tan();
        assert!(
            c.k1.abs() < 1e-12 && (c.k2 + alpha.cos() / rad).abs() < 1e-12,
            "{c:?}"
        );
        let c = plane
            .local(plane.domain().u_at(u), plane.domain().v_at(v), &TOL)
            .curvature
            .unwrap();
        assert!(c.k1 == 0.0 && c.k2 == 0.0);
        assert!((regular(plane.local(0.0, 0.0, &TOL).normal) - f.z).length() < 1e-15);
    }
    for s in [&cyl, &sph, &tor, &cone, &plane] {
        assert!(max_fd_error(s, 8) < 1e-6, "{}", s.kind());
        // Every point lies in the bounding box.
        let b = s.bounding_box().inflated(1e-9);
        for (u, v) in grid(10) {
            let d = s.domain();
            assert!(b.contains(s.point(d.u_at(u), d.v_at(v))), "{}", s.kind());
        }
    }
}

#[test]
fn nurbs_control_net_box_holds_the_surface() {
    for s in [
        quarter_cylinder(3.0, 2.0),
        sphere_octant(4.0),
        torus_quarter(6.0, 2.0),
        bilinear_plane(),
    ] {
        let b = s.bounding_box().inflated(1e-12);
        for (u, v) in grid(25) {
            assert!(b.contains(s.point(u, v)));
        }
    }
}

#[test]
fn reversing_u_negates_the_normal_and_keeps_the_points() {
    let s = torus_quarter(10.0, 3.0);
    let r = s.reversed_u();
    for (u, v) in grid(10) {
        let a = Surface::Nurbs(s.clone()).local(u, v, &TOL);
        let b = Surface::Nurbs(r.clone()).local(1.0 - u, v, &TOL);
        assert!((a.point() - b.point()).length() < 1e-12);
        assert!((a.normal.vector().unwrap() + b.normal.vector().unwrap()).length() < 1e-12);
    }
}
