//! What the mesh fuzz targets do with a mesh they read, as the commands do: check it, measure
//! it, take it as a design part (`swarf verify --design`: accepted or refused with a message),
//! weld it, and sample it as a stock (`--stock part.stl`, on about 16 rays across its largest
//! side). Nothing may panic.

use swarf_io::TriMesh;

/// Exercises `mesh` (see the crate docs).
pub fn exercise(mut mesh: TriMesh) {
    let _ = mesh.validate();
    let _ = mesh.edge_report();
    let _ = (mesh.volume(), mesh.area(), mesh.manifold_defect());
    let _ = swarf_verify::MeshDesign::new(&mesh);
    if let Some(b) = mesh.aabb() {
        let s = b.size();
        let h = s.x.max(s.y).max(s.z) / 16.0;
        let open = swarf_stock::MeshOptions { allow_open: true };
        let _ = swarf_stock::TriDexel::from_mesh(&mesh, h, open);
    }
    mesh.weld(1e-6);
    let _ = mesh.vertex_normals();
}
