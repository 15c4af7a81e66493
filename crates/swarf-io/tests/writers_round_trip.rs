//! Writers and readers: STL (binary and ASCII), glb and PLY round trips of a contoured solid;
//! atomic writes (no temporary left behind, a failed write leaves no file); the third-party STL
//! files of `SWARF_TEST_DATA` (skipped, saying so, without them); garbage never panics a reader.

mod common;
use common::*;
use proptest::prelude::*;
use std::path::{Path, PathBuf};
use swarf_geom::math::Vec3;
use swarf_geom::Aabb;
use swarf_io::glb::{glb_bytes, parse_glb};
use swarf_io::ply::parse_ply;
use swarf_io::stl::parse_stl;
use swarf_io::{
    dual_contour, read_glb, read_ply, read_stl, write_glb, write_ply, write_stl, write_stl_ascii,
    ColorMap, ContourOptions, FnGrid, GlbOptions, IoError, Lattice, Shading, TriMesh,
};

fn temp_dir(name: &str) -> PathBuf {
    swarf_testdata::fresh_scratch_dir(&format!("io-{name}"))
}

fn files_in(d: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// A coloured, contoured rounded solid (cylinder ∪ sphere), coloured by height.
fn part() -> TriMesh {
    let cyl = cylinder_sdf(Vec3::new(0.0, 0.0, -1.0), 1.0, 2.0);
    let sph = sphere_sdf(Vec3::new(0.6, 0.2, 1.0), 0.8);
    let lattice = Lattice::covering(Aabb::new(Vec3::splat(-2.0), Vec3::splat(2.0)), 0.2);
    let mut m = dual_contour(
        &FnGrid::new(lattice, move |p| cyl(p).min(sph(p))),
        &ContourOptions::default(),
    );
    let z: Vec<f64> = m.vertices.iter().map(|v| v.z).collect();
    m.colors = Some(ColorMap::Viridis.map(&z, -1.0, 1.8));
    m
}

fn same_to_f32(a: &TriMesh, b: &TriMesh) {
    assert_eq!(a.triangles.len(), b.triangles.len());
    assert!((a.volume() - b.volume()).abs() < 1e-5 * a.volume().abs());
    assert!((a.area() - b.area()).abs() < 1e-5 * a.area());
}

#[test]
fn stl_binary_and_ascii_round_trip() {
    let d = temp_dir("stl");
    let m = part();
    write_stl(&d.join("p.stl"), &m).unwrap();
    write_stl_ascii(&d.join("a.stl"), &m, "swarf part").unwrap();
    assert_eq!(
        files_in(&d),
        vec!["a.stl", "p.stl"],
        "temporary files left behind"
    );
    let size = std::fs::metadata(d.join("p.stl")).unwrap().len();
    assert_eq!(size, 84 + 50 * m.triangles.len() as u64);
    for f in ["p.stl", "a.stl"] {
        let back = read_stl(&d.join(f)).unwrap();
        same_to_f32(&m, &back);
        assert!(back.edge_report().is_clean(), "{f}");
        assert_eq!(
            back.vertices.len(),
            m.vertices.len(),
            "{f}: welding restores the indexing"
        );
        // Positions are the f32 roundings of the originals.
        let bb = back.aabb().unwrap();
        let ba = m.aabb().unwrap();
        assert!((bb.min - ba.min).length() < 1e-6 && (bb.max - ba.max).length() < 1e-6);
    }
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn glb_extras_are_written_and_only_when_asked() {
    let m = TriMesh::from_parts(
        vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
        vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
    );
    let plain = glb_bytes(&m, &GlbOptions::default()).unwrap();
    let legend = serde_json::json!({"range_mm": [-0.5, 0.5], "note": "<b>"});
    let with = glb_bytes(&m, &GlbOptions::default().with_extras(legend.clone())).unwrap();
    let json_of = |b: &[u8]| -> serde_json::Value {
        let n = u32::from_le_bytes([b[12], b[13], b[14], b[15]]) as usize;
        serde_json::from_slice(&b[20..20 + n]).unwrap()
    };
    assert!(json_of(&plain).get("extras").is_none());
    assert_eq!(json_of(&with)["extras"], legend);
    // Still a valid glb, and the geometry is untouched.
    let (a, b) = (
        parse_glb(&plain, Path::new("a")).unwrap(),
        parse_glb(&with, Path::new("b")).unwrap(),
    );
    assert_eq!(a.bin, b.bin);
}

/// A mesh with no triangles (a stock machined away) is a glb of its asset alone, no BIN chunk:
/// glTF forbids the empty accessor, view and buffer it was written with.
#[test]
fn an_empty_mesh_is_a_valid_glb_without_geometry() {
    let m = TriMesh::from_parts(Vec::new(), Vec::new());
    let legend = serde_json::json!({"note": "machined away"});
    let bytes = glb_bytes(&m, &GlbOptions::default().with_extras(legend.clone())).unwrap();
    assert_eq!(
        swarf_io::glb::GlbFile::new(&m, &GlbOptions::default())
            .unwrap()
            .len(),
        glb_bytes(&m, &GlbOptions::default()).unwrap().len()
    );
    let g = parse_glb(&bytes, Path::new("empty.glb")).unwrap();
    assert!(g.bin.is_empty());
    assert!(g.root.accessors.is_empty() && g.root.buffers.is_empty());
    assert!(g.root.buffer_views.is_empty() && g.root.meshes.is_empty());
    let n = u32::from_le_bytes([bytes[12], bytes[13], bytes[14], bytes[15]]) as usize;
    assert_eq!(bytes.len(), 20 + n);
    let doc: serde_json::Value = serde_json::from_slice(&bytes[20..20 + n]).unwrap();
    assert_eq!(doc["asset"]["version"], "2.0");
    assert_eq!(doc["extras"], legend);
}

/// The file written as it goes (`write_glb`) holds exactly the bytes built in memory, and its
/// size is the one announced, for every shading and with colours.
#[test]
fn glb_written_as_it_goes_equals_the_one_in_memory() {
    let d = temp_dir("glb_stream");
    let mut coloured = part();
    coloured.colors = Some(
        (0..coloured.vertices.len())
            .map(|i| [i as f32 / 7.0, 0.5, 0.25, 1.0])
            .collect(),
    );
    for m in [part(), coloured] {
        for shading in [Shading::Flat, Shading::Smooth] {
            let opts = GlbOptions::default().with_shading(shading);
            let path = d.join(format!("{shading:?}.glb"));
            write_glb(&path, &m, &opts).unwrap();
            let bytes = glb_bytes(&m, &opts).unwrap();
            assert_eq!(std::fs::read(&path).unwrap(), bytes);
            let file = swarf_io::glb::GlbFile::new(&m, &opts).unwrap();
            assert_eq!(file.len(), bytes.len());
            parse_glb(&bytes, &path).unwrap();
        }
    }
}

#[test]
fn a_glb_naming_missing_accessors_is_an_error_not_a_panic() {
    // Found by the `glb` fuzz target: gltf-json's validation indexed the POSITION accessor
    // before checking it exists. A document whose `accessors` key is misspelt (same length,
    // so the chunk stays well-formed) has none.
    let bytes = glb_bytes(&part(), &GlbOptions::default()).unwrap();
    let at = bytes
        .windows(11)
        .position(|w| w == b"\"accessors\"")
        .unwrap();
    let mut bad = bytes.clone();
    bad[at + 1..at + 10].copy_from_slice(b"aYwessors");
    let e = parse_glb(&bad, Path::new("bad.glb")).unwrap_err();
    let s = e.to_string();
    assert!(
        s.contains("bad.glb") && s.contains("POSITION accessor 0 of 0"),
        "{s}"
    );
    assert!(parse_glb(&bytes, Path::new("good.glb")).is_ok());
}

#[test]
fn glb_reparses_with_consistent_accessors() {
    let d = temp_dir("glb");
    let m = part();
    for shading in [Shading::Flat, Shading::Smooth] {
        let path = d.join(format!("{shading:?}.glb"));
        write_glb(&path, &m, &GlbOptions::default().with_shading(shading)).unwrap();
        let glb = read_glb(&path).unwrap();
        let root = &glb.root;
        assert_eq!(root.meshes.len(), 1);
        let prim = &root.meshes[0].primitives[0];
        let get = |name: &str| {
            let (_, idx) = prim
                .attributes
                .iter()
                .find(|(k, _)| format!("{:?}", k).contains(name))
                .unwrap_or_else(|| panic!("no {name}"));
            &root.accessors[idx.value()]
        };
        // Indexed, each vertex once; normals only for smooth shading (viewers compute flat
        // ones, as glTF requires).
        let verts = m.vertices.len() as u64;
        for name in ["Positions", "Colors"] {
            assert_eq!(get(name).count.0, verts, "{name}");
        }
        let has_normals = prim
            .attributes
            .keys()
            .any(|k| format!("{k:?}").contains("Normals"));
        assert_eq!(has_normals, shading == Shading::Smooth);
        if has_normals {
            assert_eq!(get("Normals").count.0, verts);
        }
        let bytes = std::fs::metadata(&path).unwrap().len();
        let bound =
            swarf_io::glb::glb_size_bound(m.vertices.len(), m.triangles.len(), true, shading);
        assert!(
            bytes <= bound && bound - bytes <= 4096,
            "{bytes} vs bound {bound}"
        );
        let indices = &root.accessors[prim.indices.unwrap().value()];
        assert_eq!(indices.count.0, 3 * m.triangles.len() as u64);
        // POSITION min/max are those of the f32 positions written.
        let b = m.aabb().unwrap();
        let pos = get("Positions");
        let min: Vec<f64> = serde_json::from_value(pos.min.clone().unwrap()).unwrap();
        let max: Vec<f64> = serde_json::from_value(pos.max.clone().unwrap()).unwrap();
        for k in 0..3 {
            assert_eq!(min[k] as f32, b.min[k] as f32);
            assert_eq!(max[k] as f32, b.max[k] as f32);
        }
        // Buffer views lie within the BIN chunk, 4-byte aligned.
        assert_eq!(root.buffers[0].byte_length.0, glb.bin.len() as u64);
        assert_eq!(glb.bin.len() % 4, 0);
        for v in &root.buffer_views {
            let off = v.byte_offset.unwrap().0;
            assert_eq!(off % 4, 0);
            assert!(off + v.byte_length.0 <= glb.bin.len() as u64);
        }
        // The index buffer reproduces the triangles' positions.
        let iv = &root.buffer_views[indices.buffer_view.unwrap().value()];
        let pv = &root.buffer_views[pos.buffer_view.unwrap().value()];
        let rd = |o: usize| u32::from_le_bytes(glb.bin[o..o + 4].try_into().unwrap());
        let rf = |o: usize| f32::from_le_bytes(glb.bin[o..o + 4].try_into().unwrap());
        let ib = iv.byte_offset.unwrap().0 as usize;
        let pb = pv.byte_offset.unwrap().0 as usize;
        for t in [0, m.triangles.len() / 2, m.triangles.len() - 1] {
            for c in 0..3 {
                let i = rd(ib + 4 * (3 * t + c)) as usize;
                let p = Vec3::new(
                    rf(pb + 12 * i) as f64,
                    rf(pb + 12 * i + 4) as f64,
                    rf(pb + 12 * i + 8) as f64,
                );
                assert!((p - m.vertices[m.triangles[t][c] as usize]).length() < 1e-6);
            }
        }
    }
    // A corrupted container is an error, not a panic.
    let mut bytes = glb_bytes(&m, &GlbOptions::default()).unwrap();
    bytes[12] ^= 0x55;
    assert!(parse_glb(&bytes, Path::new("x.glb")).is_err());
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn ply_round_trip_with_colours() {
    let d = temp_dir("ply");
    let m = part();
    write_ply(&d.join("p.ply"), &m).unwrap();
    let back = read_ply(&d.join("p.ply")).unwrap();
    same_to_f32(&m, &back);
    assert_eq!(back.triangles, m.triangles);
    let (a, b) = (m.colors.as_ref().unwrap(), back.colors.as_ref().unwrap());
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(b) {
        for k in 0..4 {
            assert!((x[k] - y[k]).abs() <= 0.5 / 255.0 + 1e-6);
        }
    }
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn failed_writes_leave_nothing_behind() {
    let d = temp_dir("atomic");
    let m = part();
    // The target is a directory: the final rename fails; the temporary is removed.
    std::fs::create_dir(d.join("taken.stl")).unwrap();
    let e = write_stl(&d.join("taken.stl"), &m).unwrap_err();
    assert!(matches!(e, IoError::Io { .. }), "{e}");
    assert_eq!(files_in(&d), vec!["taken.stl"]);
    assert!(d.join("taken.stl").is_dir());
    // An invalid mesh is refused before any file is created.
    let mut bad = m.clone();
    bad.triangles.push([0, 1, u32::MAX]);
    for r in [
        write_stl(&d.join("b.stl"), &bad),
        write_ply(&d.join("b.ply"), &bad),
        write_glb(&d.join("b.glb"), &bad, &GlbOptions::default()),
    ] {
        assert!(matches!(r, Err(IoError::InvalidMesh(_))));
    }
    // A body that fails half-way: the old file survives untouched, no temporary remains.
    std::fs::write(d.join("keep.txt"), b"old").unwrap();
    let r = swarf_io::write_atomic(&d.join("keep.txt"), |w| {
        use std::io::Write;
        w.write_all(b"new and partial")?;
        Err(std::io::Error::other("interrupted"))
    });
    assert!(r.is_err());
    assert_eq!(std::fs::read(d.join("keep.txt")).unwrap(), b"old");
    assert_eq!(files_in(&d), vec!["keep.txt", "taken.stl"]);
    // A name as long as a file system takes (255 bytes): its temporary's name is shortened
    // to fit too; one longer is refused by `check_writable` as by the writer, nothing left.
    let long = format!("{}.stl", "é".repeat(125));
    assert_eq!(long.len(), 254);
    swarf_io::atomic::check_writable(&d.join(&long)).unwrap();
    write_stl(&d.join(&long), &m).unwrap();
    assert!(d.join(&long).is_file());
    std::fs::remove_file(d.join(&long)).unwrap();
    let too_long = d.join(format!("{}.stl", "x".repeat(300)));
    assert!(swarf_io::atomic::check_writable(&too_long).is_err());
    assert!(write_stl(&too_long, &m).is_err());
    assert_eq!(files_in(&d), vec!["keep.txt", "taken.stl"]);
    // A folder that does not exist: an error naming it.
    let e = write_stl(&d.join("nope/x.stl"), &m)
        .unwrap_err()
        .to_string();
    assert!(e.contains("nope"), "{e}");
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn shared_stl_files_read_closed_with_known_volumes() {
    let Some([ocl, swcam]) =
        swarf_testdata::paths(["stl/ocl_ktoolcor.stl", "stl/swcam_Paralelipipedo.stl"])
    else {
        return;
    };
    // Binary, although its header starts with "solid".
    let m = read_stl(&ocl).unwrap();
    assert_eq!(m.triangles.len(), 3802);
    assert!(m.edge_report().is_clean(), "{:?}", m.edge_report());
    assert!((m.volume() - 12.01).abs() < 0.01, "{}", m.volume());
    let m = read_stl(&swcam).unwrap();
    assert_eq!(m.triangles.len(), 3170);
    println!("swcam: volume {} closed {:?}", m.volume(), m.edge_report());
    assert!((m.volume() / 3.006e7 - 1.0).abs() < 1e-3, "{}", m.volume());
}

#[test]
fn a_missing_stl_file_is_named() {
    let e = read_stl(Path::new("/nonexistent/x.stl"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("/nonexistent/x.stl"), "{e}");
}

#[test]
fn truncated_binary_stl_is_reported() {
    // A binary STL whose 80-byte header starts with "solid", as some exporters write them.
    let d = temp_dir("truncated");
    let file = d.join("part.stl");
    write_stl(&file, &part()).unwrap();
    let mut bytes = std::fs::read(&file).unwrap();
    std::fs::remove_dir_all(&d).unwrap();
    bytes[..10].copy_from_slice(b"solid part");
    assert_eq!(
        parse_stl(&bytes, Path::new("whole.stl"))
            .unwrap()
            .triangles
            .len(),
        part().triangles.len()
    );
    let e = parse_stl(&bytes[..bytes.len() - 7], Path::new("cut.stl"))
        .unwrap_err()
        .to_string();
    // Starts with "solid" but is not text; the size does not match the count.
    assert!(e.contains("cut.stl"), "{e}");
    let mut nan = bytes.clone();
    nan[84 + 12..84 + 16].copy_from_slice(&f32::NAN.to_le_bytes());
    let e = parse_stl(&nan, Path::new("nan.stl"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("triangle 0") && e.contains("non-finite"), "{e}");
}

proptest! {
    #![proptest_config(swarf_testdata::proptest_config(400))]
    #[test]
    fn garbage_never_panics(bytes in prop::collection::vec(any::<u8>(), 0..600), solid in any::<bool>(), count in 0u32..20) {
        let mut b = bytes.clone();
        if solid {
            b.splice(0..0, b"solid x\nfacet normal 0 0 1\nouter loop\nvertex".iter().copied());
        }
        let _ = parse_stl(&b, Path::new("g.stl"));
        // Binary with a header count that matches or nearly matches the size.
        let mut bin = vec![0u8; 80];
        bin.extend_from_slice(&count.to_le_bytes());
        bin.extend_from_slice(&bytes);
        let _ = parse_stl(&bin, Path::new("g.stl"));
        let _ = parse_ply(&b, Path::new("g.ply"));
        let mut ply = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 2\nproperty list uchar uint vertex_indices\nend_header\n".to_vec();
        ply.extend_from_slice(&bytes);
        let _ = parse_ply(&ply, Path::new("g.ply"));
        let _ = parse_glb(&b, Path::new("g.glb"));
    }
}
