//! `CompoundSurface::moved`: a part placed in the program's frame. Every patch kind moved by a
//! rigid motion evaluates, at the same parameters, to the moved points of the original, and its
//! trim, name and orientation stay.

use swarf_geom::math::{Quat, Vec3};
use swarf_geom::{Frame, RigidMotion};
use swarf_surface::compound::{CompoundSurface, Patch};
use swarf_surface::surface::{
    CylindricalSurface as Cylinder, NurbsSurface, ParamBox, ParametricSurface,
    PlaneSurface as Plane, SphericalSurface as Sphere, Surface,
};
use swarf_surface::trim::Trim;

fn part() -> CompoundSurface {
    let frame = Frame::from_axis_and_x(Vec3::new(1.0, 2.0, 3.0), Vec3::new(0.2, 0.1, 1.0), Vec3::X);
    let points: Vec<Vec<Vec3>> = (0..4)
        .map(|i| {
            (0..3)
                .map(|j| Vec3::new(i as f64, j as f64, ((i * j) as f64).sin()))
                .collect()
        })
        .collect();
    let weights: Vec<Vec<f64>> = (0..4)
        .map(|i| (0..3).map(|j| 1.0 + 0.1 * (i + j) as f64).collect())
        .collect();
    let nurbs = NurbsSurface::new(
        3,
        2,
        vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0],
        vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
        &points,
        Some(&weights),
    )
    .unwrap();
    let plane_box = ParamBox::new(-5.0, 5.0, -2.0, 2.0);
    let mut plane = Patch::new(Surface::Plane(Plane::new(frame, plane_box)));
    plane.trim = Some(
        Trim::new(
            &plane_box,
            Some(vec![[-1.0, -1.0], [1.0, -1.0], [0.0, 1.0]]),
            vec![],
        )
        .unwrap(),
    );
    plane.name = Some("floor".into());
    plane.flipped = true;
    CompoundSurface {
        patches: vec![
            Patch::new(Surface::Nurbs(nurbs)),
            plane,
            Patch::new(Surface::Cylinder(
                Cylinder::new(frame, 4.0, ParamBox::new(0.0, 6.0, -1.0, 3.0)).unwrap(),
            )),
            Patch::new(Surface::Sphere(
                Sphere::new(frame, 2.5, ParamBox::new(0.0, 6.0, -1.5, 1.5)).unwrap(),
            )),
        ],
        notes: Vec::new(),
    }
}

#[test]
fn every_patch_moves_with_the_motion_and_keeps_its_parameters() {
    let m = RigidMotion::new(
        Quat::from_axis_angle(Vec3::new(1.0, -2.0, 0.5).normalize(), 0.7),
        Vec3::new(100.0, -40.0, 12.5),
    );
    let a = part();
    let b = a.moved(&m).unwrap();
    assert_eq!(a.patches.len(), b.patches.len());
    for (p, q) in a.patches.iter().zip(&b.patches) {
        assert_eq!(p.surface.domain(), q.surface.domain());
        assert_eq!((&p.name, p.flipped, &p.trim), (&q.name, q.flipped, &q.trim));
        let d = p.surface.domain();
        for i in 0..=8 {
            for j in 0..=8 {
                let u = d.u[0] + (d.u[1] - d.u[0]) * i as f64 / 8.0;
                let v = d.v[0] + (d.v[1] - d.v[0]) * j as f64 / 8.0;
                let want = m.apply_point(p.surface.point(u, v));
                let got = q.surface.point(u, v);
                assert!(
                    (got - want).length() < 1e-9 * (1.0 + want.length()),
                    "{got} vs {want} at ({u}, {v})"
                );
            }
        }
    }
    // Moving back gives the part again.
    let back = b.moved(&m.inverse()).unwrap();
    for (p, q) in a.patches.iter().zip(&back.patches) {
        let d = p.surface.domain();
        let (u, v) = (0.3 * d.u[0] + 0.7 * d.u[1], 0.6 * d.v[0] + 0.4 * d.v[1]);
        assert!((p.surface.point(u, v) - q.surface.point(u, v)).length() < 1e-9);
    }
}
