//! `ContourOptions::simplify`: 2 × 2 × 2 blocks of cells merged into one vertex. The merged
//! mesh must stay closed, manifold and oriented, keep the topology of the unmerged one (same
//! Euler characteristic and components, also where two solids are a cell apart), keep sharp
//! edges and flat faces exact, stay within the stated distance of curved surfaces, and have
//! about a quarter of the triangles where the surface is smooth.

mod common;
use common::*;
use proptest::prelude::*;
use swarf_geom::math::Vec3;
use swarf_geom::Aabb;
use swarf_io::{dual_contour_with_stats, ContourOptions, FnGrid, Lattice, TriMesh};

/// Euler characteristic `V − E + F` of a closed mesh (its used vertices) and its number of
/// connected components.
fn euler_and_components(m: &TriMesh) -> (i64, usize) {
    let n = m.vertices.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(p: &mut [usize], mut x: usize) -> usize {
        while p[x] != x {
            p[x] = p[p[x]];
            x = p[x];
        }
        x
    }
    let mut used = vec![false; n];
    for t in &m.triangles {
        for &v in t {
            used[v as usize] = true;
        }
        let a = find(&mut parent, t[0] as usize);
        for &v in &t[1..] {
            let b = find(&mut parent, v as usize);
            parent[b] = a;
        }
    }
    let v = used.iter().filter(|&&u| u).count() as i64;
    let f = m.triangles.len() as i64;
    let components = (0..n)
        .filter(|&i| used[i] && find(&mut parent, i) == i)
        .count();
    (v - 3 * f / 2 + f, components)
}

/// Asserts that `merged` is clean (`assert_clean`) and has the Euler characteristic and the
/// components of `fine`.
fn assert_same_topology(merged: &TriMesh, fine: &TriMesh, what: &str) {
    assert_clean(merged, what);
    assert_eq!(
        euler_and_components(merged),
        euler_and_components(fine),
        "{what}"
    );
}

fn contour(lattice: Lattice, sdf: impl Fn(Vec3) -> f64 + Sync, tol: Option<f64>) -> TriMesh {
    let (m, _) = dual_contour_with_stats(
        &FnGrid::new(lattice, sdf),
        &ContourOptions::default().with_simplify(tol),
    );
    m
}

#[test]
fn a_sphere_merges_to_about_a_quarter_within_the_tolerance() {
    let (r, h) = (1.0, 0.04);
    let lattice = Lattice::covering(Aabb::new(Vec3::splat(-1.2), Vec3::splat(1.2)), h);
    let sdf = sphere_sdf(Vec3::ZERO, r);
    let fine = contour(lattice, sdf, None);
    // The planes of a block of side 2h on a sphere of radius r spread about (2h)²/(8r) = 8e-4.
    let tol = 2e-3;
    let (merged, stats) = dual_contour_with_stats(
        &FnGrid::new(lattice, sdf),
        &ContourOptions::default().with_simplify(Some(tol)),
    );
    assert_clean(&merged, "merged sphere");
    let ratio = merged.len() as f64 / fine.len() as f64;
    assert!(ratio < 0.3, "{} of {} triangles", merged.len(), fine.len());
    assert!(stats.merged_blocks > 0);
    assert_eq!(euler_and_components(&merged), (2, 1));
    // Vertices where the QEF puts them: within the tolerance of the sphere (beyond the fine
    // mesh's own error); facets a chord of a block's width (2h√3) inside it at most.
    let vertex_error = vertex_to_surface(&merged, sdf);
    let fine_error = vertex_to_surface(&fine, sdf);
    assert!(
        vertex_error <= fine_error + tol,
        "{vertex_error} vs {fine_error}"
    );
    let chord = (2.0 * h * 3f64.sqrt()).powi(2) / (8.0 * r);
    let facet_error = mesh_to_surface(&merged, sdf);
    assert!(facet_error <= vertex_error + chord, "{facet_error}");
    let exact = 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
    let area = 4.0 * std::f64::consts::PI * r * r;
    assert!(
        (merged.volume() - exact).abs() <= area * (vertex_error + chord),
        "{} vs {exact}",
        merged.volume()
    );
    // A tolerance no block meets merges nothing: the fine mesh itself.
    let none = contour(lattice, sdf, Some(1e-9));
    assert_eq!(none.triangles, fine.triangles);
    assert_eq!(none.vertices, fine.vertices);
}

#[test]
fn flat_faces_and_sharp_edges_stay_exact() {
    // A turned box: every block on a face, an edge or a corner has planes meeting in a point.
    let h = 0.05;
    let lattice = Lattice::covering(Aabb::new(Vec3::splat(-1.3), Vec3::splat(1.3)), h);
    let sdf = box_sdf(
        Vec3::new(0.013, -0.021, 0.007),
        Vec3::new(0.9, 0.7, 0.55),
        0.4,
    );
    let fine = contour(lattice, sdf, None);
    let merged = contour(lattice, sdf, Some(1e-6));
    assert_clean(&merged, "merged box");
    assert!(
        (merged.len() as f64) < 0.4 * fine.len() as f64,
        "{} of {}",
        merged.len(),
        fine.len()
    );
    assert_eq!(euler_and_components(&merged), (2, 1));
    // Every vertex on the box (faces, edges, corners: planes that meet in a point). Facets
    // folding across a turned edge cut it by a chord, as the fine mesh's do.
    let vertex_error = vertex_to_surface(&merged, sdf);
    assert!(vertex_error < 1e-9, "{vertex_error}");
    let (err, fine_err) = (mesh_to_surface(&merged, sdf), mesh_to_surface(&fine, sdf));
    assert!(err <= fine_err, "{err} vs {fine_err}");
    // The volume no further off than the fine mesh's (whose facets cut the turned edges by
    // chords: 2.2e-5 of it).
    let exact = 8.0 * 0.9 * 0.7 * 0.55;
    let (err, fine_err) = (
        (merged.volume() - exact).abs(),
        (fine.volume() - exact).abs(),
    );
    assert!(
        err <= fine_err && fine_err < 3e-5 * exact,
        "{err} vs {fine_err}"
    );
}

#[test]
fn faces_on_the_domain_boundary_merge_on_every_side() {
    // A solid filling its lattice (an uncut stock): its faces lie on the domain's boundary.
    // With an even or odd number of points per axis, each face merges as its opposite does —
    // the top face too, which lies in a slab left without a partner when the slabs are odd
    // in number — and the mesh is a quarter of the fine one, but for the blocks at the
    // faces' rims.
    for n in [[12, 13, 10], [13, 12, 11]] {
        let lattice = Lattice::new(Vec3::ZERO, Vec3::splat(0.1), n);
        let fine = contour(lattice, |_| -1.0, None);
        let merged = contour(lattice, |_| -1.0, Some(1e-6));
        assert_same_topology(&merged, &fine, "a filled lattice");
        let facing = |m: &TriMesh, axis: usize, sign: f64| {
            m.triangles
                .iter()
                .filter(|t| {
                    let [a, b, c] = t.map(|i| m.vertices[i as usize]);
                    let normal = (b - a).cross(c - a);
                    normal[axis] * sign > 0.9 * normal.length()
                })
                .count()
        };
        for axis in 0..3 {
            let (up, down) = (facing(&merged, axis, 1.0), facing(&merged, axis, -1.0));
            let fine_up = facing(&fine, axis, 1.0);
            assert!(
                up.abs_diff(down) * 10 <= fine_up && 3 * up <= fine_up,
                "{n:?}, axis {axis}: {up} and {down} of {fine_up}"
            );
        }
        let ratio = merged.len() as f64 / fine.len() as f64;
        assert!(ratio < 0.32, "{n:?}: {} of {}", merged.len(), fine.len());
        let exact = n.iter().map(|&k| 0.1 * k as f64).product::<f64>();
        assert!(
            (merged.volume() - exact).abs() < 1e-9,
            "{}",
            merged.volume()
        );
    }
}

#[test]
fn topology_below_a_block_is_kept() {
    // Two spheres and two slabs a little more than a cell apart: resolved by the fine cells,
    // not by a block of two. The merged mesh keeps both components (and a thin plate keeps
    // its two faces).
    let h = 0.05;
    for gap in [1.2 * h, 1.6 * h, 2.5 * h] {
        let (spheres, d) = two_spheres_sdf(0.6, gap);
        let lattice = Lattice::covering(Aabb::new(Vec3::splat(-0.8), Vec3::splat(d + 0.8)), h);
        let fine = contour(lattice, spheres, None);
        let merged = contour(lattice, spheres, Some(5e-3));
        assert_same_topology(&merged, &fine, &format!("spheres, gap {gap}"));
        assert!(merged.len() < fine.len() / 2);
        let e = Vec3::new(0.7, 0.8, 0.6);
        let sa = box_sdf(Vec3::new(-0.71 - 0.5 * gap, 0.0, 0.0), e, 0.0);
        let sb = box_sdf(Vec3::new(0.71 + 0.5 * gap, 0.0, 0.0), e, 0.3);
        let slabs = move |p: Vec3| sa(p).min(sb(p));
        let lattice = Lattice::covering(Aabb::new(Vec3::splat(-1.6), Vec3::splat(1.6)), h);
        let fine = contour(lattice, slabs, None);
        let merged = contour(lattice, slabs, Some(1e-6));
        assert_same_topology(&merged, &fine, &format!("slabs, gap {gap}"));
    }
    let plate = box_sdf(Vec3::ZERO, Vec3::new(1.0, 0.8, 0.04), 0.3);
    let lattice = Lattice::covering(Aabb::new(Vec3::splat(-1.2), Vec3::splat(1.2)), h);
    let fine = contour(lattice, plate, None);
    let merged = contour(lattice, plate, Some(1e-6));
    assert_same_topology(&merged, &fine, "thin plate");
}

fn blob_strategy() -> impl Strategy<Value = (Vec<Blob>, f64, f64)> {
    (
        prop::collection::vec(
            (
                -1.0..1.0f64,
                -1.0..1.0f64,
                -1.0..1.0f64,
                0.1..0.9f64,
                any::<bool>(),
            ),
            1..5,
        ),
        0.05..0.2f64,
        prop_oneof![Just(1e-6), Just(1e-3), Just(1e-2)],
    )
}

proptest! {
    #![proptest_config(swarf_testdata::proptest_config(256))]
    #[test]
    fn random_unions_keep_their_topology((blobs, h, tol) in blob_strategy()) {
        let sdf = &blobs_sdf(blobs);
        let lattice = Lattice::covering(Aabb::new(Vec3::splat(-1.5), Vec3::splat(1.5)), h);
        let fine = contour(lattice, sdf, None);
        let merged = contour(lattice, sdf, Some(tol));
        let r = merged.edge_report();
        prop_assert!(r.is_clean(), "{} open {} non-manifold {} misoriented: {:?}", r.open, r.non_manifold, r.misoriented, r.examples);
        prop_assert_eq!(euler_and_components(&merged), euler_and_components(&fine));
        prop_assert!(merged.len() <= fine.len());
        // Each merged vertex solves its block's QEF: within the tolerance of the planes, so
        // of the surface up to the fine cells' own error and the block's size.
        let (fine_error, err) = (vertex_to_surface(&fine, sdf), vertex_to_surface(&merged, sdf));
        prop_assert!(err <= fine_error + tol + 0.5 * h, "{} vs {}", err, fine_error);
        let area = fine.area();
        prop_assert!((merged.volume() - fine.volume()).abs() <= area * (tol + 0.25 * h) + 1e-9,
            "{} vs {}", merged.volume(), fine.volume());
    }
}

#[test]
fn a_corner_two_cells_put_their_vertices_on_stays_manifold() {
    // Two turned cubes (a shrunk case of the property test below): two cells' QEFs put their
    // vertices on one corner of the second cube, one point in f32. With merged blocks around
    // it, merging the two made an edge of four triangles; the repair now keeps them apart.
    let sdf = &blobs_sdf(vec![
        (
            -0.2732597379481262,
            -0.9234169497009213,
            0.6090404284932487,
            0.870869179870048,
            true,
        ),
        (
            0.2283764191468182,
            -0.9592491214504739,
            0.0,
            0.5954347790855747,
            true,
        ),
    ]);
    let h = 0.12775644970312736;
    let lattice = Lattice::covering(Aabb::new(Vec3::splat(-1.5), Vec3::splat(1.5)), h);
    let fine = contour(lattice, sdf, None);
    let (merged, stats) = dual_contour_with_stats(
        &FnGrid::new(lattice, sdf),
        &ContourOptions::default().with_simplify(Some(1e-6)),
    );
    assert!(stats.merged_blocks > 0);
    assert_same_topology(&merged, &fine, "two turned cubes");
}
