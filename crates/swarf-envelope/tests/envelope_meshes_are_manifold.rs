//! Every envelope mesh as its files store it (`f32` positions, welded by position when read
//! back) is a 2-manifold: each edge in exactly two triangles, consistently oriented, no
//! triangle with two corners at one point or three on a line — on many random programs of
//! lines, arcs, full circles, helices and plunges, for every cutter type, with and without
//! blocks of cells merged (`EnvelopeOptions::with_simplify`). `closed` in the report is that
//! of the mesh written.

mod common;

use common::{cutters, gcode, tools, Rng};
use swarf_envelope::{envelope, EnvelopeOptions};
use swarf_io::TriMesh;

/// The mesh as an STL file stores it, read back (the reader welds equal positions).
fn as_written(mesh: &TriMesh) -> TriMesh {
    let mut bytes = Vec::new();
    swarf_io::write_stl_to(&mut bytes, mesh).unwrap();
    swarf_io::stl::parse_stl(&bytes, std::path::Path::new("envelope.stl")).unwrap()
}

/// Panics unless `written` is a 2-manifold without degenerate triangles
/// (`TriMesh::manifold_defect`).
fn check(written: &TriMesh, what: &str) {
    if let Some(defect) = written.manifold_defect() {
        panic!("{what}: {defect}");
    }
}

fn run(text: &str, name: &str, cutter: &swarf_tool::Cutter, h: f64, simplify: Option<f64>) {
    let program = gcode(text);
    let options = EnvelopeOptions::default()
        .with_resolution(h)
        .with_simplify(simplify);
    let env = envelope(&program, &tools(cutter), 0..program.moves.len(), &options).unwrap();
    let written = as_written(&env.mesh);
    let what = format!("{name} at h = {h}, merging blocks within {simplify:?} mm:\n{text}");
    check(&written, &what);
    assert!(env.report.closed, "{what}");
    assert_eq!(env.report.triangles, written.triangles.len(), "{what}");
    assert_eq!(env.mesh.vertices.len(), written.vertices.len(), "{what}");
}

#[test]
fn a_full_circle_with_a_flat_end_mill_is_a_2_manifold() {
    // Before: 456 collapsed and 4 flat triangles, 221 edges in six triangles, "closed": true.
    let text = "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG2 X0 Y0 I5 J0\nM30\n";
    for (name, c) in cutters() {
        run(text, name, &c, 0.25, None);
        run(text, name, &c, 0.25, Some(1e-3));
    }
}

#[test]
fn random_programs_give_2_manifolds() {
    let mut rng = Rng(0x5EED_2026_0015);
    let all = cutters();
    for case in 0..40 {
        let mut text = String::from("G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F200\n");
        let (mut x, mut y, mut z) = (0.0f64, 0.0f64, -1.0f64);
        let moves = 1 + (rng.next() * 3.0) as usize;
        for _ in 0..moves {
            let kind = (rng.next() * 5.0) as u32;
            let (nx, ny) = (
                (rng.range(-8.0, 8.0) * 4.0).round() / 4.0,
                (rng.range(-8.0, 8.0) * 4.0).round() / 4.0,
            );
            let nz = (rng.range(-3.0, 0.0) * 2.0).round() / 2.0;
            match kind {
                0 => text.push_str(&format!("G1 X{nx} Y{ny} Z{nz}\n")),
                1 => text.push_str(&format!("G1 Z{nz}\n")),
                2 => {
                    // A full circle, maybe helical.
                    let r = (rng.range(1.0, 6.0) * 4.0).round() / 4.0;
                    text.push_str(&format!("G2 X{x} Y{y} I{r} J0 Z{nz}\n"));
                }
                _ => {
                    let r = (nx - x).hypot(ny - y) / 2.0 + rng.range(0.5, 5.0);
                    let g = if kind == 3 { 2 } else { 3 };
                    text.push_str(&format!("G{g} X{nx} Y{ny} R{r:.3}\n"));
                }
            }
            match kind {
                0 => (x, y, z) = (nx, ny, nz),
                1 | 2 => z = nz,
                _ => (x, y) = (nx, ny),
            }
        }
        let _ = z;
        text.push_str("M30\n");
        let (name, c) = &all[case % all.len()];
        let h = [0.25, 0.3, 0.2][case % 3];
        // Every other case with 2 × 2 × 2 blocks of cells merged (`--simplify`).
        let simplify = [None, Some(1e-3)][case % 2];
        run(&text, name, c, h, simplify);
    }
}
