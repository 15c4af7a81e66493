//! Boxes, axis-aligned and turned 30° about Z: volume, area, distance of every vertex to the
//! surface, and vertices near edges lying on the edges (crisp edges and corners), with normals
//! estimated from the crossings (as for a tri-dexel) and given exactly.

mod common;
use common::*;
use swarf_geom::math::Vec3;
use swarf_geom::Aabb;
use swarf_io::{dual_contour_with_stats, ContourOptions, FnGrid, Lattice, TriMesh};

const C: Vec3 = Vec3::new(0.31, -0.17, 0.05);
const E: Vec3 = Vec3::new(1.6, 1.1, 0.7);

fn contour(angle: f64, h: f64, exact: bool) -> TriMesh {
    let sdf = box_sdf(C, E, angle);
    let lattice = Lattice::covering(Aabb::new(C - 2.0 * E, C + 2.0 * E), h);
    let grid = FnGrid::new(lattice, sdf);
    let grid = if exact {
        grid.with_gradient(gradient(sdf))
    } else {
        grid
    };
    let (m, stats) = dual_contour_with_stats(&grid, &ContourOptions::default());
    assert_eq!(stats.fallback_crossings, 0, "{stats:?}");
    assert_clean(&m, &format!("box at {angle} rad, h = {h}"));
    m
}

#[test]
fn axis_aligned_box_is_exact_with_crisp_edges_and_corners() {
    let h = 0.137;
    let sdf = box_sdf(C, E, 0.0);
    for exact in [false, true] {
        let m = contour(0.0, h, exact);
        let volume = 8.0 * E.x * E.y * E.z;
        let area = 8.0 * (E.x * E.y + E.y * E.z + E.z * E.x);
        assert!(
            (m.volume() / volume - 1.0).abs() < 1e-12,
            "volume {} vs {volume}",
            m.volume()
        );
        assert!(
            (m.area() / area - 1.0).abs() < 1e-12,
            "area {} vs {area}",
            m.area()
        );
        // Every vertex on the surface.
        let worst = m.vertices.iter().map(|&v| sdf(v).abs()).fold(0.0, f64::max);
        assert!(
            worst < 1e-12 * E.length(),
            "vertex off the surface by {worst}"
        );
        // Crisp edges: every point of the box's twelve edges lies on the mesh (a chamfer would
        // be about h/2 away), and the eight corners are vertices.
        let lo = C - E;
        let hi = C + E;
        let corner = |c: usize| {
            Vec3::new(
                [lo.x, hi.x][c & 1],
                [lo.y, hi.y][c >> 1 & 1],
                [lo.z, hi.z][c >> 2],
            )
        };
        let mut worst_edge = 0.0f64;
        for a in 0..8 {
            for k in 0..3 {
                let b = a | (1 << k);
                if b == a {
                    continue;
                }
                for s in 0..=40 {
                    let p = corner(a).lerp(corner(b), s as f64 / 40.0);
                    worst_edge = worst_edge.max(distance_to_mesh(&m, p));
                }
            }
            let d = m
                .vertices
                .iter()
                .map(|v| v.distance(corner(a)))
                .fold(f64::INFINITY, f64::min);
            assert!(
                d < 1e-9 * h,
                "corner {:?} is {d} from the nearest vertex",
                corner(a)
            );
        }
        assert!(worst_edge < 1e-6 * h, "box edge {worst_edge} from the mesh");
    }
}

#[test]
fn box_turned_30_degrees_about_z() {
    let angle = 30f64.to_radians();
    let sdf = box_sdf(C, E, angle);
    let volume = 8.0 * E.x * E.y * E.z;
    let area = 8.0 * (E.x * E.y + E.y * E.z + E.z * E.x);
    for (h, exact, vol_tol, area_tol, dist_tol) in [
        (0.137, true, 1e-4, 5e-4, 1e-8),
        (0.137, false, 1e-4, 1e-3, 1e-9),
        (0.0685, false, 4e-5, 4e-4, 1e-9),
    ] {
        let m = contour(angle, h, exact);
        let dv = (m.volume() / volume - 1.0).abs();
        let da = (m.area() / area - 1.0).abs();
        let worst = m.vertices.iter().map(|&v| sdf(v).abs()).fold(0.0, f64::max);
        println!("h {h} exact normals {exact}: volume error {dv:.2e}, area error {da:.2e}, worst vertex {:.2e} h", worst / h);
        // Edges: the largest distance from a point of the box's edges to the mesh (a
        // chamfered edge would be ~h/2 away everywhere; DC misses the edge only in the odd cell
        // where no lattice edge crosses one of the two faces).
        let (s30, c30) = angle.sin_cos();
        let corner = |c: usize| {
            let l = Vec3::new(
                [-E.x, E.x][c & 1],
                [-E.y, E.y][c >> 1 & 1],
                [-E.z, E.z][c >> 2],
            );
            C + Vec3::new(c30 * l.x - s30 * l.y, s30 * l.x + c30 * l.y, l.z)
        };
        let mut edge_dists = Vec::new();
        for a in 0..8 {
            for k in 0..3 {
                let b = a | (1 << k);
                if b != a {
                    for s in 0..=40 {
                        let p = corner(a).lerp(corner(b), s as f64 / 40.0);
                        edge_dists.push(distance_to_mesh(&m, p) / h);
                    }
                }
            }
        }
        edge_dists.sort_by(f64::total_cmp);
        let median = edge_dists[edge_dists.len() / 2];
        let max = edge_dists[edge_dists.len() - 1];
        println!("   box edges to mesh: median {median:.2e} h, max {max:.2e} h");
        assert!(
            median < 1e-6,
            "box edges are not crisp: median distance {median} h"
        );
        assert!(max < 0.2, "box edge up to {max} h from the mesh");
        assert!(dv < vol_tol, "volume error {dv}");
        assert!(da < area_tol, "area error {da}");
        assert!(
            worst < dist_tol * h,
            "vertex off the surface by {} h",
            worst / h
        );
    }
}
