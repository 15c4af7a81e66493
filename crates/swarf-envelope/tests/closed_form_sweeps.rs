//! Sweeps with closed forms: a ball-nose along a line sweeps a capsule (below the ball's
//! centre), a flat end mill along a horizontal line a stadium prism (two planes, two
//! half-cylinders, floor and top); mesh vertices lie within a fraction of the lattice spacing of
//! the exact surface and the volume converges as the spacing falls.

mod common;

use std::f64::consts::PI;

use swarf_envelope::{envelope, EnvelopeOptions};
use swarf_geom::math::Vec3;
use swarf_sweep::{grazing_points, MotionState};
use swarf_tool::{AnyPiece, Cutter};

/// Distance from `p` to the segment `a`–`b`.
fn seg_dist(p: Vec3, a: Vec3, b: Vec3) -> f64 {
    let d = b - a;
    let t = ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0);
    (p - (a + d * t)).length()
}

/// Signed distance to the envelope of a ball end mill of radius `r` and overall length `top`
/// whose tip moves along `a`–`b` in the plane z = 0: the capsule of its ball centres, united
/// with the slab of its cylinder up to `top`.
fn ball_line_signed(p: Vec3, r: f64, top: f64, a: Vec3, b: Vec3) -> f64 {
    let d = seg_dist(Vec3::new(p.x, p.y, 0.0), a, b);
    let disc = d.hypot(p.z - r) - r;
    let (qx, qz) = (d - r, (r - p.z).max(p.z - top));
    let rect = qx.max(0.0).hypot(qz.max(0.0)) + qx.max(qz).min(0.0);
    disc.min(rect)
}

#[test]
fn ball_along_a_line_sweeps_a_capsule() {
    let r = 5.0;
    let ball = Cutter::ball(2.0 * r).unwrap();
    let (len, height) = (ball.overall_length(), ball.overall_length() - r);
    // Diagonal in XY so no wall is aligned with the lattice, and the start off the lattice's
    // grid: from (1, 2), the Z lines at Pythagorean offsets ((3, 4), (1.4, 4.8), …) were
    // tangent to the shank's cylinder, each a 25 mm segment of measure zero that rounding
    // either counted in the rays' volume or not (1 mm³ each at h = 0.2).
    let (a, b) = (Vec3::new(1.013, 2.029, 0.0), Vec3::new(21.0, 13.0, 0.0));
    let program = common::gcode(&format!(
        "G21 G90\nG0 X{} Y{} Z0\nG1 X{} Y{} F500\n",
        a.x, a.y, b.x, b.y
    ));
    let d = (b - a).length();
    // Whole tool: hemisphere + cylinder of the same radius to the shank's top.
    let exact = 2.0 / 3.0 * PI * r.powi(3)
        + PI * r * r * height
        + d * (0.5 * PI * r * r + 2.0 * r * height);
    assert!((ball.shank_diameter() - 2.0 * r).abs() < 1e-12 && len > r);
    let mut errors = Vec::new();
    for h in [0.8, 0.4, 0.2] {
        let env = envelope(
            &program,
            &common::tools(&ball),
            0..program.moves.len(),
            &EnvelopeOptions::default().with_resolution(h),
        )
        .unwrap();
        assert!(env.mesh.is_closed());
        assert_eq!(env.report.moves, vec![1]);
        let (ca, cb) = (a + Vec3::Z * r, b + Vec3::Z * r);
        let mut worst = 0.0f64;
        for &v in &env.mesh.vertices {
            if v.z < r - 0.5 * h {
                worst = worst.max((seg_dist(v, ca, cb) - r).abs());
            }
        }
        assert!(worst < 1e-9, "h = {h}: capsule vertex error {worst}");
        let err = (env.report.volume_mm3 - exact).abs() / exact;
        let ray_err = (env.report.volume_xyz_mm3[2] - exact).abs() / exact;
        eprintln!("capsule h = {h}: vertex error {worst:.4} mm, volume error mesh {err:.2e}, rays {ray_err:.2e}");
        errors.push((err, ray_err));
    }
    assert!(
        errors[2].0 < errors[0].0,
        "mesh volume converges: {errors:?}"
    );
    // The rays' volume is a midpoint sum whose boundary is jagged at h: 1.5·10⁻³ at h = 0.2.
    assert!(errors[2].0 < 5e-4 && errors[2].1 < 2e-3, "{errors:?}");
}

#[test]
fn flat_end_mill_along_a_horizontal_line_gives_planes_and_half_cylinders() {
    let r = 4.0;
    let flat = Cutter::flat(2.0 * r).unwrap();
    let top = flat.overall_length();
    let (a, b) = (Vec3::new(0.3, 0.7, -1.0), Vec3::new(18.3, 0.7, -1.0));
    let program = common::gcode("G21 G90\nG0 X0.3 Y0.7 Z-1\nG1 X18.3 F300\n");
    // Grazing set: the two side lines at y = ±r (the two planes), the whole bottom and top.
    let st = MotionState::translation(a, Vec3::Z, b - a);
    let set = grazing_points(flat.pieces(), &st, 9);
    for g in set
        .points
        .iter()
        .filter(|g| matches!(flat.pieces()[g.piece], AnyPiece::Cylinder(_)))
    {
        assert!(((g.point.y - a.y).abs() - r).abs() < 1e-12 && (g.point.x - a.x).abs() < 1e-12);
    }
    let h = 0.25;
    let env = envelope(
        &program,
        &common::tools(&flat),
        0..2,
        &EnvelopeOptions::default().with_resolution(h),
    )
    .unwrap();
    // Signed distance to the stadium prism: stadium of radius r about a–b in XY, z in [a.z, a.z + top].
    let sdf = |p: Vec3| {
        let qxy = seg_dist(
            Vec3::new(p.x, p.y, 0.0),
            Vec3::new(a.x, a.y, 0.0),
            Vec3::new(b.x, b.y, 0.0),
        ) - r;
        let qz = (a.z - p.z).max(p.z - a.z - top);
        let out = qxy.max(0.0).hypot(qz.max(0.0));
        out + qxy.max(qz).min(0.0)
    };
    let worst = env
        .mesh
        .vertices
        .iter()
        .map(|&v| sdf(v).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "stadium prism h = {h}: vertex error {worst:.2e} mm, volume {} vs {}",
        env.report.volume_mm3,
        (PI * r * r + 2.0 * r * (b - a).length()) * top
    );
    // Every vertex is put on the exact envelope, sharp edges included.
    assert!(worst < 1e-9, "stadium prism vertex error {worst}");
    // The side walls are planes: their vertices lie on y = a.y ± r to rounding.
    let walls: Vec<f64> = env
        .mesh
        .vertices
        .iter()
        .filter(|v| v.x > a.x + 1.0 && v.x < b.x - 1.0 && v.z > a.z + 1.0 && v.z < a.z + top - 1.0)
        .map(|v| ((v.y - a.y).abs() - r).abs())
        .collect();
    assert!(
        !walls.is_empty() && walls.iter().all(|&e| e < 1e-6),
        "{:?}",
        walls.iter().cloned().fold(0.0, f64::max)
    );
    let exact = (PI * r * r + 2.0 * r * (b - a).length()) * top;
    assert!(
        (env.report.volume_mm3 - exact).abs() / exact < 2e-3,
        "{} vs {exact}",
        env.report.volume_mm3
    );
}

/// The case: one 36 mm line of a 10 mm ball end mill (shank of the same diameter), at
/// the default resolution. The swept solid of a tool of revolution with a vertical axis along
/// a horizontal segment is `{d ≤ ρ(z)}` with `d` the horizontal distance to the segment
/// (`d` is 1-Lipschitz and an isometry across the segment), so the distance of a point to the
/// envelope is the plane distance of `(d, z)` to the tool's half-profile: a rectangle
/// `[−r, r] × [r, top]` united with the disc of radius `r` about `(0, r)`. For a point near the
/// boundary the smaller of the two signed distances is never below the true distance.
#[test]
fn envelope_vertices_lie_on_the_exact_envelope_at_the_default_resolution() {
    let r = 5.0;
    let ball = Cutter::ball(2.0 * r).unwrap();
    let top = ball.overall_length();
    assert!((ball.shank_diameter() - 2.0 * r).abs() < 1e-12);
    let (a, b) = (Vec3::new(0.0, 0.0, 0.0), Vec3::new(36.0, 0.0, 0.0));
    let program = common::gcode("G21 G90\nG0 X0 Y0 Z0\nG1 X36 F300\n");
    let distance = |p: Vec3| ball_line_signed(p, r, top, a, b).abs();
    let worst = |exact: bool| {
        let opts = EnvelopeOptions::default().with_exact_vertices(exact);
        let env = envelope(&program, &common::tools(&ball), 0..2, &opts).unwrap();
        assert!(env.report.closed);
        let w = env
            .mesh
            .vertices
            .iter()
            .map(|&v| distance(v))
            .fold(0.0, f64::max);
        (w, env.report.exact_vertices, env.mesh.vertices.len())
    };
    let (on, moved, n) = worst(true);
    let (off, _, _) = worst(false);
    eprintln!(
        "36 mm ball line, h = {}: vertex error {on:.1e} mm exact ({moved} of {n} vertices \
         moved), {off:.1e} mm as contoured",
        swarf_envelope::DEFAULT_RESOLUTION_MM
    );
    assert_eq!(moved, n, "every vertex finds the envelope within a spacing");
    assert!(on < 1e-9, "{on}");
    // What the contouring alone gives: micrometres off on the curved parts.
    assert!(off > 1e-4, "{off}");
}

#[test]
fn merged_blocks_keep_the_vertices_exact_and_the_facets_within_a_chord() {
    // The 36 mm line of a 10 mm ball at h = 0.1, blocks merged within 1 µm:
    // a quarter of the triangles, every vertex still on the exact envelope, every facet within
    // the chord of a merged block's diagonal (2h√3) on the ball's radius of it.
    let r = 5.0;
    let ball = Cutter::ball(2.0 * r).unwrap();
    let top = ball.overall_length();
    let (a, b) = (Vec3::new(0.0, 0.0, 0.0), Vec3::new(36.0, 0.0, 0.0));
    let program = common::gcode("G21 G90\nG0 X0 Y0 Z0\nG1 X36 F300\n");
    let signed = |p: Vec3| ball_line_signed(p, r, top, a, b);
    let h = 0.1;
    let run = |simplify| {
        let opts = EnvelopeOptions::default()
            .with_resolution(h)
            .with_simplify(simplify);
        envelope(&program, &common::tools(&ball), 0..2, &opts).unwrap()
    };
    let (plain, merged) = (run(None), run(Some(1e-3)));
    assert!(merged.report.closed);
    assert!(merged.report.merged_blocks.unwrap() > 0);
    assert_eq!(plain.report.merged_blocks, None);
    let ratio = merged.report.triangles as f64 / plain.report.triangles as f64;
    assert!(ratio < 0.3, "{ratio}");
    let vertex_error = merged
        .mesh
        .vertices
        .iter()
        .map(|&v| signed(v).abs())
        .fold(0.0, f64::max);
    assert_eq!(merged.report.exact_vertices, merged.mesh.vertices.len());
    assert!(vertex_error < 1e-9, "{vertex_error}");
    // Facets: their centroids and edge midpoints (a chord lies inside a convex surface).
    let facet_error = |env: &swarf_envelope::Envelope| {
        (0..env.mesh.len())
            .flat_map(|t| {
                let [p, q, s] = env.mesh.corners(t);
                [
                    (p + q + s) / 3.0,
                    0.5 * (p + q),
                    0.5 * (q + s),
                    0.5 * (s + p),
                ]
            })
            .map(|x| signed(x).abs())
            .fold(0.0, f64::max)
    };
    let chord = (2.0 * h * 3f64.sqrt()).powi(2) / (8.0 * r);
    let (fe, pe) = (facet_error(&merged), facet_error(&plain));
    eprintln!(
        "ball line, h = {h}: {} → {} triangles with blocks merged; facets within {fe:.1e} mm \
         ({pe:.1e} unmerged), chord bound {chord:.1e}",
        plain.report.triangles, merged.report.triangles
    );
    assert!(fe <= chord, "{fe} vs {chord}");
    // Inscribed facets take volume off the convex parts: at most the chord over the area.
    let area = merged.mesh.area();
    let dv = (merged.report.volume_mm3 - plain.report.volume_mm3).abs();
    assert!(dv <= area * chord, "{dv}");
}
