//! Smooth and curved solids: a sphere and a capped cylinder at halving spacings. The volume
//! error must fall as the spacing halves (a convergence table is printed), and the two-sided
//! Hausdorff distance between mesh and analytic surface must stay below c·h.

mod common;
use common::*;
use std::f64::consts::PI;
use swarf_geom::math::Vec3;
use swarf_geom::Aabb;
use swarf_io::{dual_contour_with_stats, ContourOptions, FnGrid, Lattice, TriMesh};

fn contour(sdf: impl Fn(Vec3) -> f64 + Sync, bounds: Aabb, h: f64) -> TriMesh {
    let lattice = Lattice::covering(bounds.inflated(1.5 * h), h);
    let (m, stats) =
        dual_contour_with_stats(&FnGrid::new(lattice, sdf), &ContourOptions::default());
    assert_eq!(stats.fallback_crossings, 0);
    m
}

/// Hausdorff distance, both ways: mesh → surface sampled on the mesh, surface → mesh from
/// `samples` points on the surface.
fn hausdorff(m: &TriMesh, sdf: impl Fn(Vec3) -> f64, samples: &[Vec3]) -> f64 {
    let to_surface = mesh_to_surface(m, sdf);
    let to_mesh = samples
        .iter()
        .map(|&p| distance_to_mesh(m, p))
        .fold(0.0, f64::max);
    to_surface.max(to_mesh)
}

fn table(name: &str, exact: f64, rows: &[(f64, f64, f64)]) {
    println!("{name}: exact volume {exact:.6}");
    println!(
        "  {:>8} {:>14} {:>10} {:>8} {:>12}",
        "h", "volume", "rel.err", "ratio", "hausdorff/h"
    );
    let mut prev: Option<f64> = None;
    for &(h, v, d) in rows {
        let e = (v / exact - 1.0).abs();
        let ratio = prev.map_or(String::new(), |p| format!("{:.2}", p / e));
        println!("  {h:>8.4} {v:>14.6} {e:>10.2e} {ratio:>8} {:>12.4}", d / h);
        prev = Some(e);
    }
}

#[test]
fn sphere_volume_converges_and_hausdorff_is_order_h() {
    let (c, r) = (Vec3::new(0.123, -0.045, 0.077), 3.0);
    let sdf = sphere_sdf(c, r);
    let exact = 4.0 / 3.0 * PI * r.powi(3);
    let samples: Vec<Vec3> = fibonacci_sphere(300).iter().map(|&d| c + r * d).collect();
    let bounds = Aabb::new(c - Vec3::splat(r), c + Vec3::splat(r));
    let mut rows = Vec::new();
    for h in [0.4, 0.2, 0.1, 0.05] {
        let m = contour(sdf, bounds, h);
        assert_clean(&m, &format!("sphere h = {h}"));
        rows.push((h, m.volume(), hausdorff(&m, sdf, &samples)));
    }
    table("sphere r = 3", exact, &rows);
    let errs: Vec<f64> = rows.iter().map(|r| (r.1 / exact - 1.0).abs()).collect();
    for w in errs.windows(2) {
        assert!(
            w[1] < 0.6 * w[0],
            "volume error does not fall with h: {errs:?}"
        );
    }
    assert!(errs[3] < 1e-4, "{errs:?}");
    for &(h, _, d) in &rows {
        assert!(d < 0.1 * h, "Hausdorff {d} > 0.1 h at h = {h}");
    }
}

#[test]
fn cylinder_volume_converges_and_hausdorff_is_order_h() {
    let (c, r, height) = (Vec3::new(0.05, 0.11, -1.93), 2.0, 3.7);
    let sdf = cylinder_sdf(c, r, height);
    let exact = PI * r * r * height;
    // Samples on the side, both caps and both circular edges.
    let mut samples = Vec::new();
    for i in 0..60 {
        let t = 2.0 * PI * i as f64 / 60.0;
        let rim = Vec3::new(t.cos(), t.sin(), 0.0);
        for z in [0.0, 0.3, 0.5, 0.9, 1.0] {
            samples.push(c + r * rim + Vec3::Z * (z * height));
        }
        for f in [0.3, 0.7] {
            samples.push(c + f * r * rim);
            samples.push(c + f * r * rim + Vec3::Z * height);
        }
    }
    let bounds = Aabb::new(c - Vec3::new(r, r, 0.0), c + Vec3::new(r, r, height));
    let mut rows = Vec::new();
    for h in [0.4, 0.2, 0.1, 0.05] {
        let m = contour(sdf, bounds, h);
        assert_clean(&m, &format!("cylinder h = {h}"));
        rows.push((h, m.volume(), hausdorff(&m, sdf, &samples)));
    }
    table("cylinder r = 2, height 3.7", exact, &rows);
    let errs: Vec<f64> = rows.iter().map(|r| (r.1 / exact - 1.0).abs()).collect();
    for w in errs.windows(2) {
        assert!(
            w[1] < 0.6 * w[0],
            "volume error does not fall with h: {errs:?}"
        );
    }
    for &(h, _, d) in &rows {
        assert!(d < 0.1 * h, "Hausdorff {d} > 0.1 h at h = {h}");
    }
}
