//! Analytic solids and measurements shared by the integration tests.
#![allow(dead_code, unreachable_pub)]

use swarf_geom::math::Vec3;
use swarf_io::TriMesh;

/// Signed distance to a box with centre `c`, half sizes `e`, turned by `angle` (rad) about Z.
pub fn box_sdf(c: Vec3, e: Vec3, angle: f64) -> impl Fn(Vec3) -> f64 + Sync + Send + Copy {
    let (s, co) = angle.sin_cos();
    move |p: Vec3| {
        let d = p - c;
        let l = Vec3::new(co * d.x + s * d.y, -s * d.x + co * d.y, d.z);
        let q = l.abs() - e;
        q.max(Vec3::ZERO).length() + q.max_element().min(0.0)
    }
}

/// Sphere.
pub fn sphere_sdf(c: Vec3, r: f64) -> impl Fn(Vec3) -> f64 + Sync + Send + Copy {
    move |p: Vec3| (p - c).length() - r
}

/// Two spheres of radius `r`, the second's centre on the first's diagonal `(d, d, d)` so that
/// `gap` separates them; returns the union's distance and `d`.
pub fn two_spheres_sdf(r: f64, gap: f64) -> (impl Fn(Vec3) -> f64 + Sync + Send + Copy, f64) {
    let d = (2.0 * r + gap) / 3f64.sqrt();
    let (a, b) = (sphere_sdf(Vec3::ZERO, r), sphere_sdf(Vec3::splat(d), r));
    (move |p: Vec3| a(p).min(b(p)), d)
}

/// Capped cylinder along Z: centre of the base `c`, radius `r`, height `h`.
pub fn cylinder_sdf(c: Vec3, r: f64, h: f64) -> impl Fn(Vec3) -> f64 + Sync + Send + Copy {
    move |p: Vec3| {
        let d = p - c;
        let radial = (d.x * d.x + d.y * d.y).sqrt() - r;
        let axial = (d.z - 0.5 * h).abs() - 0.5 * h;
        let q = [radial, axial];
        let outside = (radial.max(0.0).powi(2) + axial.max(0.0).powi(2)).sqrt();
        outside + q[0].max(q[1]).min(0.0)
    }
}

/// Central-difference gradient of `f`.
pub fn gradient(f: impl Fn(Vec3) -> f64) -> impl Fn(Vec3) -> Vec3 {
    move |p: Vec3| {
        let e = 1e-7;
        Vec3::new(
            f(p + Vec3::X * e) - f(p - Vec3::X * e),
            f(p + Vec3::Y * e) - f(p - Vec3::Y * e),
            f(p + Vec3::Z * e) - f(p - Vec3::Z * e),
        ) / (2.0 * e)
    }
}

/// Distance from `p` to triangle `abc`.
pub fn point_triangle_distance(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> f64 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return ap.length();
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return bp.length();
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (p - (a + v * ab)).length();
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return cp.length();
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (p - (a + w * ac)).length();
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (p - (b + w * (c - b))).length();
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    (p - (a + ab * v + ac * w)).length()
}

/// Distance from `p` to the mesh (brute force).
pub fn distance_to_mesh(m: &TriMesh, p: Vec3) -> f64 {
    (0..m.len())
        .map(|t| {
            let [a, b, c] = m.corners(t);
            point_triangle_distance(p, a, b, c)
        })
        .fold(f64::INFINITY, f64::min)
}

/// Largest |sdf| over the mesh's vertices.
pub fn vertex_to_surface(m: &TriMesh, sdf: impl Fn(Vec3) -> f64) -> f64 {
    m.vertices.iter().map(|&p| sdf(p).abs()).fold(0.0, f64::max)
}

/// A blob of the property tests: centre x, y, z, size, and whether it is a cube (turned about
/// Z by its size in radians) rather than a sphere.
pub type Blob = (f64, f64, f64, f64, bool);

/// Signed distance to the union of `blobs`.
pub fn blobs_sdf(blobs: Vec<Blob>) -> impl Fn(Vec3) -> f64 + Sync + Send {
    move |p: Vec3| {
        blobs
            .iter()
            .map(|&(x, y, z, r, cube)| {
                let c = Vec3::new(x, y, z);
                if cube {
                    box_sdf(c, Vec3::splat(r), r)(p)
                } else {
                    (p - c).length() - r
                }
            })
            .fold(f64::INFINITY, f64::min)
    }
}

/// Largest |sdf| over vertices, edge midpoints and centroids: the mesh-to-surface half of the
/// Hausdorff distance (sampled).
pub fn mesh_to_surface(m: &TriMesh, sdf: impl Fn(Vec3) -> f64) -> f64 {
    let mut worst = 0.0f64;
    for t in 0..m.len() {
        let [a, b, c] = m.corners(t);
        for p in [
            a,
            b,
            c,
            0.5 * (a + b),
            0.5 * (b + c),
            0.5 * (c + a),
            (a + b + c) / 3.0,
        ] {
            worst = worst.max(sdf(p).abs());
        }
    }
    worst
}

/// Points spread over the unit sphere (Fibonacci lattice).
pub fn fibonacci_sphere(n: usize) -> Vec<Vec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let y = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let r = (1.0 - y * y).sqrt();
            let t = golden * i as f64;
            Vec3::new(r * t.cos(), y, r * t.sin())
        })
        .collect()
}

/// Asserts that the mesh is closed, manifold, consistently oriented and has positive volume.
pub fn assert_clean(m: &TriMesh, what: &str) {
    let r = m.edge_report();
    assert!(
        r.is_clean(),
        "{what}: {} open, {} non-manifold, {} misoriented edges, e.g. {:?}",
        r.open,
        r.non_manifold,
        r.misoriented,
        r.examples
    );
    assert!(m.volume() > 0.0, "{what}: volume {}", m.volume());
    assert!(m.validate().is_ok());
}
