//! Fuzz target `stl`: any bytes read as an STL file (binary or ASCII) give a mesh or an error
//! naming the file — never a panic, a hang or an allocation the bytes do not justify — and a
//! mesh that is read survives what `swarf verify --design`, `swarf gouge --check`, `swarf
//! toolsize --check` and a mesh stock (`--stock part.stl`, sampled on about 16 rays across
//! its largest side) do with it. Run with `cargo +nightly fuzz run stl` from `crates/swarf-io`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;

/// What the commands do with a mesh they read: check it, measure it, weld it, and take it as a
/// design part (accepted or refused with a message). None of it may panic.
fn exercise(mut mesh: swarf_io::TriMesh) {
    let _ = mesh.validate();
    let _ = mesh.edge_report();
    let _ = (mesh.volume(), mesh.area(), mesh.aabb(), mesh.manifold_defect());
    let _ = swarf_verify::MeshDesign::new(&mesh);
    mesh.weld(1e-6);
    let _ = mesh.vertex_normals();
}

fuzz_target!(|data: &[u8]| {
    if let Ok(mesh) = swarf_io::stl::parse_stl(data, Path::new("fuzz.stl")) {
        if let Some(b) = mesh.aabb() {
            let s = b.size();
            let h = s.x.max(s.y).max(s.z) / 16.0;
            let open = swarf_stock::MeshOptions { allow_open: true };
            let _ = swarf_stock::TriDexel::from_mesh(&mesh, h, open);
        }
        exercise(mesh);
    }
});
