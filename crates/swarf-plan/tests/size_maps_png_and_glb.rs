//! The pictures of a map: one PNG per patch that decodes with the expected size, cells in the
//! colours of their radii and distinct colours for `inf`, unreachable and undefined; the part
//! as a glb with one colour per vertex.

use std::path::Path;

use swarf_geom::math::Vec3;
use swarf_plan::plot::{
    map_layout, part_mesh, patch_png_name, standard_rgb, write_part_glb, write_patch_maps,
    write_standard_maps, PlotOptions, RadiusScale, INF_RGB, UNDEFINED_RGB, UNREACHABLE_RGB,
};
use swarf_plan::size::StandardCutters;
use swarf_plan::size::{allowable_map, CutterFamily, MapOptions, ToolSizeMap};
use swarf_surface::{CompoundSurface, NurbsSurface, Patch, Surface, Tolerances};

fn bilinear(p00: Vec3, p10: Vec3, p01: Vec3, p11: Vec3) -> Patch {
    Patch::new(Surface::Nurbs(
        NurbsSurface::new(
            1,
            1,
            vec![0.0, 0.0, 1.0, 1.0],
            vec![0.0, 0.0, 1.0, 1.0],
            &[vec![p00, p01], vec![p10, p11]],
            None,
        )
        .unwrap(),
    ))
}

fn quad(x: [f64; 2], y: [f64; 2], z: f64) -> Patch {
    bilinear(
        Vec3::new(x[0], y[0], z),
        Vec3::new(x[1], y[0], z),
        Vec3::new(x[0], y[1], z),
        Vec3::new(x[1], y[1], z),
    )
}

/// A floor next to a wall (finite radii), a plateau above everything (`inf`), a ceiling facing
/// down (unreachable, `0`) and a patch collapsed onto a line (no normal).
fn part() -> CompoundSurface {
    let mut floor = quad([-10.0, 10.0], [-10.0, 10.0], 0.0);
    floor.name = Some("floor".into());
    let mut wall = bilinear(
        Vec3::new(10.0, -10.0, 0.0),
        Vec3::new(10.0, 10.0, 0.0),
        Vec3::new(10.0, -10.0, 5.0),
        Vec3::new(10.0, 10.0, 5.0),
    );
    wall.flipped = true;
    let mut plateau = quad([-60.0, -50.0], [0.0, 10.0], 100.0);
    plateau.name = Some("plateau top".into());
    let mut ceiling = quad([-60.0, -50.0], [20.0, 30.0], 50.0);
    ceiling.flipped = true;
    let needle = bilinear(
        Vec3::new(-20.0, 0.0, 0.0),
        Vec3::new(-15.0, 0.0, 0.0),
        Vec3::new(-20.0, 0.0, 0.0),
        Vec3::new(-15.0, 0.0, 0.0),
    );
    CompoundSurface::new(vec![floor, wall, plateau, ceiling, needle])
}

fn map(part: &CompoundSurface, n: usize) -> ToolSizeMap {
    allowable_map(
        part,
        &CutterFamily::flat(),
        &part.grid(n),
        &MapOptions::default(),
    )
}

fn decode(path: &Path) -> (usize, usize, Vec<u8>) {
    let dec = png::Decoder::new(std::fs::File::open(path).unwrap());
    let mut reader = dec.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb);
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    buf.truncate(info.buffer_size());
    (info.width as usize, info.height as usize, buf)
}

fn out_dir(name: &str) -> std::path::PathBuf {
    let d = swarf_testdata::scratch_dir(&format!("maps-{name}"));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn one_png_per_patch_with_the_cells_in_their_colours() {
    let part = part();
    let n = 5;
    let m = map(&part, n);
    let class = |k: usize| m.points[k * n * n + n * n / 2].radius_mm;
    assert!(
        class(0).is_some_and(|r| r.is_finite() && r > 0.0),
        "floor {:?}",
        class(0)
    );
    assert_eq!(class(2), Some(f64::INFINITY), "plateau");
    assert_eq!(class(3), Some(0.0), "ceiling");
    assert_eq!(class(4), None, "needle");

    let dir = out_dir("png");
    let opts = PlotOptions::default();
    let paths = write_patch_maps(&part, &m, n, &dir, &opts).unwrap();
    assert_eq!(paths.len(), part.patches.len());
    assert_eq!(paths[0].file_name().unwrap(), "patch_floor.png");
    assert_eq!(paths[1].file_name().unwrap(), "patch_1.png");
    assert_eq!(paths[2].file_name().unwrap(), "patch_plateau_top.png");
    assert_eq!(patch_png_name(&part, 4), "patch_4.png");

    let scale = RadiusScale::from_radii(m.points.iter().map(|p| p.radius_mm));
    let lay = map_layout(n, &scale, &opts);
    assert_eq!(lay.cell, 64); // 320 / 5
    let mut seen = Vec::new();
    for (k, path) in paths.iter().enumerate() {
        let (w, h, px) = decode(path);
        assert_eq!((w, h), (lay.width, lay.height), "{}", path.display());
        assert!(w >= n * lay.cell && h >= n * lay.cell);
        for i in 0..n {
            for j in 0..n {
                let (x, y) = lay.cell_origin(i, j);
                let (cx, cy) = (x + lay.cell / 2, y + lay.cell / 2);
                let at = 3 * (cy * w + cx);
                let got = [px[at], px[at + 1], px[at + 2]];
                let want = scale.rgb(m.points[k * n * n + i * n + j].radius_mm);
                assert_eq!(got, want, "patch {k} cell ({i}, {j})");
                seen.push(got);
            }
        }
    }
    for special in [INF_RGB, UNREACHABLE_RGB, UNDEFINED_RGB] {
        assert!(seen.contains(&special), "{special:?} drawn");
    }
    assert_ne!(INF_RGB, UNREACHABLE_RGB);
    assert_ne!(INF_RGB, UNDEFINED_RGB);
    assert_ne!(UNREACHABLE_RGB, UNDEFINED_RGB);
    // The floor's finite cells are viridis, i.e. none of the special colours.
    let floor_finite = scale.rgb(class(0));
    assert!(![INF_RGB, UNREACHABLE_RGB, UNDEFINED_RGB].contains(&floor_finite));
    // Keep a copy for looking at.
    if let Ok(keep) = std::env::var("SWARF_KEEP_MAPS") {
        std::fs::copy(&paths[0], Path::new(&keep).join("patch_floor.png")).unwrap();
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn glb_has_one_colour_per_vertex() {
    let part = part();
    let n = 4;
    let m = map(&part, n);
    let tol = Tolerances::DEFAULT;
    let mesh = part_mesh(&part, &m, n, &tol).unwrap();
    let colors = mesh.colors.as_ref().unwrap();
    assert_eq!(mesh.vertices.len(), part.patches.len() * n * n);
    assert_eq!(colors.len(), mesh.vertices.len());
    // Vertex k is CC point k, coloured by its radius.
    let scale = RadiusScale::from_radii(m.points.iter().map(|p| p.radius_mm));
    for (k, p) in m.points.iter().enumerate() {
        assert!((mesh.vertices[k] - p.point).length() < 1e-12);
        assert_eq!(colors[k], scale.rgba(p.radius_mm));
    }

    let dir = out_dir("glb");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("part.glb");
    write_part_glb(&path, &part, &m, n, &tol).unwrap();
    let glb = swarf_io::read_glb(&path).unwrap();
    let prim = &glb.root.meshes[0].primitives[0];
    let count = |sem: gltf_json::mesh::Semantic| {
        let idx = prim
            .attributes
            .get(&gltf_json::validation::Checked::Valid(sem))
            .expect("attribute present");
        glb.root.accessors[idx.value()].count.0
    };
    let positions = count(gltf_json::mesh::Semantic::Positions);
    let colours = count(gltf_json::mesh::Semantic::Colors(0));
    assert_eq!(colours, positions);
    assert!(positions >= mesh.vertices.len() as u64);
    // Not the grid: refused.
    assert!(part_mesh(&part, &m, n + 1, &tol).is_err());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn standard_maps_colour_cells_by_the_largest_fitting_cutter() {
    let part = part();
    let n = 5;
    let m = map(&part, n);
    let cutters = StandardCutters::new(&[4.0, 10.0, 40.0]).unwrap();
    let dir = out_dir("std");
    let opts = PlotOptions::default();
    let paths = write_standard_maps(&part, &m, n, &cutters, &dir, &opts).unwrap();
    assert_eq!(paths[0].file_name().unwrap(), "standard_patch_floor.png");
    let lay = map_layout(n, &RadiusScale::from_radii([]), &opts);
    let mut seen = Vec::new();
    for (k, path) in paths.iter().enumerate() {
        let (w, _, px) = decode(path);
        for i in 0..n {
            for j in 0..n {
                let (x, y) = lay.cell_origin(i, j);
                let at = 3 * ((y + lay.cell / 2) * w + x + lay.cell / 2);
                let got = [px[at], px[at + 1], px[at + 2]];
                let r = m.points[k * n * n + i * n + j].radius_mm;
                let want = match (r, cutters.largest_fitting(r)) {
                    (None, _) => UNDEFINED_RGB,
                    (Some(_), None) => UNREACHABLE_RGB,
                    (Some(_), Some(d)) => {
                        let idx = cutters.diameters_mm().iter().position(|x| *x == d).unwrap();
                        standard_rgb(idx, 3)
                    }
                };
                assert_eq!(got, want, "patch {k} cell ({i}, {j}) radius {r:?}");
                seen.push(got);
            }
        }
    }
    // The plateau (inf) takes the largest cutter; the floor uses more than one.
    assert!(seen.contains(&standard_rgb(0, 3)));
    assert!(seen.contains(&UNREACHABLE_RGB) && seen.contains(&UNDEFINED_RGB));
    let distinct: std::collections::HashSet<[u8; 3]> = (0..3).map(|k| standard_rgb(k, 3)).collect();
    assert_eq!(distinct.len(), 3);
    if let Ok(keep) = std::env::var("SWARF_KEEP_MAPS") {
        std::fs::copy(&paths[0], Path::new(&keep).join("standard_patch_floor.png")).unwrap();
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
