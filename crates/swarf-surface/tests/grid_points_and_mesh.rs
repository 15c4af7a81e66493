//! CC-point grids and lists, flipping, bounding boxes and the viewing mesh.

mod common;

use common::*;
use swarf_geom::math::Vec3;
use swarf_surface::{
    tessellate, CcPointError, CompoundSurface, ParametricSurface, Patch, Surface, Tolerances,
};

const TOL: Tolerances = Tolerances::DEFAULT;

fn part() -> CompoundSurface {
    CompoundSurface::new(vec![
        Patch::new(Surface::Nurbs(sphere_octant(5.0))),
        Patch::new(Surface::Nurbs(quarter_cylinder(2.0, 3.0))),
    ])
}

#[test]
fn grid_is_iso_parametric_and_covers_the_corners() {
    let s = part();
    let g = s.grid(21);
    assert_eq!(g.len(), 2 * 21 * 21);
    assert_eq!((g[0].patch, g[0].u, g[0].v), (0, 0.0, 0.0));
    assert_eq!((g[1].u, g[1].v), (0.0, 0.05));
    assert_eq!((g[21].u, g[21].v), (0.05, 0.0));
    let last = g[21 * 21 - 1];
    assert_eq!((last.patch, last.u, last.v), (0, 1.0, 1.0));
    assert_eq!(g[21 * 21].patch, 1);
    assert_eq!(s.grid(41).len(), 2 * 41 * 41);
    assert_eq!(s.grid(0).len(), 2 * 4, "n < 2 is taken as 2");
}

#[test]
fn point_lists_are_checked() {
    let s = part();
    let p = s.points(&[(1, 0.5, 0.5), (0, 1.0, 0.0)]).unwrap();
    assert_eq!(p.len(), 2);
    assert!(matches!(
        s.points(&[(0, 0.5, 0.5), (2, 0.0, 0.0)]),
        Err(CcPointError::NoPatch {
            index: 1,
            patch: 2,
            count: 2
        })
    ));
    let e = s.points(&[(0, 1.5, 0.5)]).unwrap_err();
    assert!(
        e.to_string()
            .contains("outside patch 0's parameter box [0, 1] × [0, 1]"),
        "{e}"
    );
}

#[test]
fn flip_all_reverses_normals_and_curvature_signs() {
    let mut s = part();
    let cc = s.points(&[(1, 0.4, 0.5)]).unwrap()[0];
    let a = s.local(&cc, &TOL);
    s.flip_all();
    let b = s.local(&cc, &TOL);
    assert_eq!(a.normal.vector().unwrap(), -b.normal.vector().unwrap());
    let (ca, cb) = (a.curvature.unwrap(), b.curvature.unwrap());
    assert_eq!((ca.k1, ca.k2), (-cb.k2, -cb.k1));
    s.flip_all();
    assert_eq!(s.local(&cc, &TOL), a);
}

#[test]
fn point_normal_agrees_with_local_everywhere_including_the_pole() {
    let mut s = part();
    s.patches[0].flipped = true;
    for cc in s.grid(11) {
        let p = &s.patches[cc.patch];
        let g = p.local(cc.u, cc.v, &TOL);
        let (q, n) = p.point_normal(cc.u, cc.v, &TOL);
        assert_eq!((q, n), (g.point(), g.normal));
    }
}

#[test]
fn boxes_hold_their_patches() {
    let s = part();
    let boxes = s.patch_boxes();
    assert_eq!(boxes[0].max, Vec3::splat(5.0));
    assert_eq!(boxes[1].min, Vec3::ZERO);
    let all = s.bounding_box().unwrap();
    assert_eq!(all.max, Vec3::splat(5.0));
    assert!(CompoundSurface::default().bounding_box().is_none());
}

#[test]
fn mesh_has_consistent_triangles_and_cutter_side_normals() {
    let mut s = part();
    s.patches[1].flipped = true;
    let n = 9;
    let m = tessellate(&s, n, &TOL);
    assert_eq!(m.mesh.vertices.len(), 2 * n * n);
    assert_eq!(m.normals.len(), m.mesh.vertices.len());
    assert_eq!(m.mesh.triangles.len(), 2 * 2 * (n - 1) * (n - 1));
    assert_eq!(m.triangle_patch.len(), m.mesh.triangles.len());
    assert_eq!(m.mesh.len(), m.mesh.triangles.len());
    for (t, &k) in m.mesh.triangles.iter().zip(&m.triangle_patch) {
        let p = t.map(|i| m.mesh.vertices[i as usize]);
        let face = (p[1] - p[0]).cross(p[2] - p[0]);
        if face.length() < 1e-9 {
            continue; // collapsed at the pole
        }
        let vn = m.normals[t[0] as usize] + m.normals[t[1] as usize] + m.normals[t[2] as usize];
        assert!(
            face.dot(vn) > 0.0,
            "winding agrees with the normals (patch {k})"
        );
        if k == 1 {
            // The flipped cylinder's normals point to the axis.
            let c = (p[0] + p[1] + p[2]) / 3.0;
            assert!(vn.dot(Vec3::new(c.x, c.y, 0.0)) < 0.0);
        }
    }
    for nv in &m.normals {
        assert!((nv.length() - 1.0).abs() < 1e-12);
    }
    // Every vertex is on its patch's surface.
    assert!((m.mesh.vertices[0] - s.patches[0].surface.point(0.0, 0.0)).length() < 1e-15);
}

#[test]
fn patches_without_a_grid_point_on_the_part_are_named() {
    // The octant's parameters are [0, 1]²; a triangle of the trim between the 5 × 5 grid's
    // rows and columns (0.25 apart) holds none of its points, at 9 × 9 (0.125 apart) it holds
    // (0.375, 0.375).
    let mut s = part();
    let d = s.patches[0].surface.domain();
    let sliver = vec![[0.3, 0.3], [0.46, 0.3], [0.3, 0.46]];
    s.patches[0].trim = Some(swarf_surface::Trim::new(&d, Some(sliver), Vec::new()).unwrap());
    assert_eq!(s.patches_off_grid(5), vec![0]);
    assert!(s.grid(5).iter().all(|c| c.patch == 1));
    assert!(s.patches_off_grid(9).is_empty());
    assert_eq!(s.grid(9).iter().filter(|c| c.patch == 0).count(), 1);
}
