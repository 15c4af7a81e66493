//! The contouring computes each point level's X and Y edges once and shares them between the
//! two slabs beside it, level and slab work running in batches whose size follows the number
//! of worker threads: the mesh and its statistics must not depend on that. A tall solid (many
//! batches, ending at different levels in each pool) is contoured in pools of 1, 2 and 3
//! threads, with every cell and with blocks of cells merged; the meshes must be equal to the
//! bit, closed, and on the solid's surface.

mod common;
use common::*;
use swarf_geom::math::Vec3;
use swarf_io::{dual_contour_with_stats, ContourOptions, FnGrid, Lattice};

/// Five overlapping spheres up a column, over 150 point levels (batches of 16 levels per
/// thread: 16, 32 and 48 levels): its lattice and signed distance.
fn stacked_spheres() -> (Lattice, impl Fn(Vec3) -> f64 + Sync + Copy) {
    let lattice = Lattice::new(Vec3::new(-2.0, -2.0, -1.0), Vec3::splat(0.1), [41, 41, 150]);
    let sdf = |p: Vec3| {
        (0..5)
            .map(|i| {
                let c = Vec3::new(0.3 * i as f64 - 0.6, 0.1 * i as f64, 1.0 + 2.6 * i as f64);
                sphere_sdf(c, 1.4)(p)
            })
            .fold(f64::INFINITY, f64::min)
    };
    (lattice, sdf)
}

#[test]
fn the_mesh_does_not_depend_on_the_threads() {
    // With every cell, and with 2 × 2 × 2 blocks merged (decided a pair of slabs at a time,
    // the pair above a batch before the batch).
    let (lattice, sdf) = stacked_spheres();
    for simplify in [None, Some(2e-3)] {
        let options = ContourOptions::default().with_simplify(simplify);
        let run = |threads: usize| {
            swarf_testdata::on_threads(threads, || {
                dual_contour_with_stats(&FnGrid::new(lattice, sdf), &options)
            })
        };
        let (one, stats) = run(1);
        assert_clean(&one, "stacked spheres");
        assert_eq!(stats.merged_blocks > 0, simplify.is_some());
        // Within half a cell of the spheres (the creases where they meet are the farthest).
        let off = mesh_to_surface(&one, sdf);
        assert!(off < 0.05, "{off} mm off the spheres");
        for threads in [2, 3] {
            let (m, st) = run(threads);
            assert_eq!(m.vertices, one.vertices, "{threads} threads, {simplify:?}");
            assert_eq!(
                m.triangles, one.triangles,
                "{threads} threads, {simplify:?}"
            );
            assert_eq!(st, stats, "{threads} threads, {simplify:?}");
        }
    }
}

#[test]
fn vertices_are_projected_with_the_whole_mesh_normals() {
    // The extraction projects each slab's vertices as soon as the triangles around them are
    // made, with normals summed over those triangles alone: the same vertices, to the bit, as
    // projecting the finished mesh with `TriMesh::vertex_normals`, in pools of 1, 2 and 3
    // threads (batches ending at different slabs).
    let (lattice, sdf) = stacked_spheres();
    let grid = FnGrid::new(lattice, sdf);
    let options = ContourOptions::default();
    // A move along the normal that depends on the position too, so that a normal summed over
    // other triangles or a vertex moved too early would show.
    let nudge = |p: Vec3, n: Vec3| Some(p + n * (1e-3 * (1.0 + p.z.sin())));
    let (plain, _) = dual_contour_with_stats(&grid, &options);
    let normals = plain.vertex_normals();
    let expected: Vec<Vec3> = plain
        .vertices
        .iter()
        .zip(&normals)
        .map(|(&p, &n)| nudge(p, n).unwrap())
        .collect();
    for threads in [1, 2, 3] {
        let (m, stats) = swarf_testdata::on_threads(threads, || {
            swarf_io::dual_contour_projected(&grid, &options, nudge)
        });
        assert_eq!(m.triangles, plain.triangles, "{threads} threads");
        assert_eq!(m.vertices, expected, "{threads} threads");
        assert_eq!(
            stats.projected_vertices,
            expected.len(),
            "{threads} threads"
        );
    }
}
