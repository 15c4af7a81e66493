//! glb: binary glTF 2.0, the format of the web and of most 3-D viewers (three.js, Blender,
//! Windows' 3D Viewer). One scene, one node, one mesh with one triangle primitive: `POSITION`
//! and `NORMAL` (`f32` VEC3), optional `COLOR_0` (`f32` VEC4), `u32` indices. The JSON is built
//! with `gltf-json`'s types; the container follows the spec: 12-byte header, a JSON chunk padded
//! with spaces and a BIN chunk padded with zeros to 4 bytes, every accessor 4-byte aligned,
//! `POSITION` with exact `min`/`max` (computed from the `f32` values written).
//!
//! The mesh is written indexed, each vertex once (a machined part's vertices are shared by six
//! triangles on average: a flat-shaded copy per triangle made files six times larger). Flat
//! shading (the default, right for machined parts with sharp edges) writes no `NORMAL`: glTF
//! 2.0 requires viewers to compute flat normals then (§3.7.2.1 "When normals are not specified,
//! client implementations MUST calculate flat normals"). Smooth shading adds area-weighted
//! vertex normals.

use crate::atomic::write_atomic;
use crate::error::IoError;
use crate::mesh::TriMesh;
use gltf_json as json;
use json::validation::{Checked::Valid, USize64};
use std::collections::BTreeMap;
use std::io::Write;
use std::path::Path;

/// How normals are written.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Shading {
    /// No normals: viewers compute one per triangle (glTF's rule), crisp edges.
    #[default]
    Flat,
    /// Area-weighted vertex normals.
    Smooth,
}

/// Options of [`write_glb`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GlbOptions {
    /// Flat or smooth normals.
    pub shading: Shading,
    /// Application data written as the document's top-level `extras` (glTF 2.0 §3.8: any
    /// JSON; viewers ignore it). `None` (the default) writes none.
    pub extras: Option<serde_json::Value>,
}

impl GlbOptions {
    /// With the given shading.
    pub fn with_shading(mut self, shading: Shading) -> Self {
        self.shading = shading;
        self
    }

    /// With `extras` as the document's top-level `extras`.
    pub fn with_extras(mut self, extras: serde_json::Value) -> Self {
        self.extras = Some(extras);
        self
    }
}

const GLB_MAGIC: &[u8; 4] = b"glTF";
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

fn pad4(n: usize) -> usize {
    n.div_ceil(4) * 4
}

/// The glb file of `mesh` in memory.
pub fn glb_bytes(mesh: &TriMesh, options: &GlbOptions) -> Result<Vec<u8>, IoError> {
    let file = GlbFile::new(mesh, options)?;
    let mut out = Vec::with_capacity(file.len());
    file.write_to(&mut out)
        .map_err(|e| IoError::io(Path::new("glb"), e))?;
    Ok(out)
}

/// A glb file of a mesh, ready to be written: its JSON chunk and the layout of its BIN chunk,
/// whose arrays [`GlbFile::write_to`] writes straight from the mesh a block at a time — the
/// file is never held in memory (smooth shading keeps one `f32` array of vertex normals).
#[derive(Debug)]
pub struct GlbFile<'m> {
    mesh: &'m TriMesh,
    normals: Option<Vec<[f32; 3]>>,
    /// The JSON chunk's data, padded with spaces.
    json: Vec<u8>,
    bin_len: usize,
}

impl<'m> GlbFile<'m> {
    /// Checks `mesh` and lays out its file.
    pub fn new(mesh: &'m TriMesh, options: &GlbOptions) -> Result<Self, IoError> {
        mesh.validate()?;
        let count = mesh.vertices.len();
        if count > u32::MAX as usize {
            return Err(IoError::InvalidMesh(format!(
                "{count} glTF vertices exceed u32 indices"
            )));
        }
        let normals: Option<Vec<[f32; 3]>> = (options.shading == Shading::Smooth).then(|| {
            mesh.vertex_normals()
                .iter()
                .map(|v| v.as_vec3().to_array())
                .collect()
        });
        let colors = mesh.colors.as_ref();
        let index_count = 3 * mesh.triangles.len();
        // The BIN chunk's views, in order: positions, normals, colours, indices.
        let mut views: Vec<(usize, usize, json::buffer::Target)> = Vec::new();
        let mut bin_len = 0;
        let mut push_view = |len: usize, target| {
            views.push((bin_len, len, target));
            bin_len = pad4(bin_len + len);
        };
        use json::buffer::Target::{ArrayBuffer, ElementArrayBuffer};
        push_view(12 * count, ArrayBuffer);
        if normals.is_some() {
            push_view(12 * count, ArrayBuffer);
        }
        if colors.is_some() {
            push_view(16 * count, ArrayBuffer);
        }
        push_view(4 * index_count, ElementArrayBuffer);

        let mut min = [f32::INFINITY; 3];
        let mut max = [f32::NEG_INFINITY; 3];
        for v in &mesh.vertices {
            let p = v.as_vec3().to_array();
            for k in 0..3 {
                min[k] = min[k].min(p[k]);
                max[k] = max[k].max(p[k]);
            }
        }
        let mut root = json::Root::default();
        root.asset.generator = Some(format!("swarf-io {}", env!("CARGO_PKG_VERSION")));
        // No triangles (a stock machined away): a document of its asset alone, no BIN chunk —
        // glTF wants at least one element in every accessor, view and buffer it has.
        if mesh.triangles.is_empty() {
            return Self::finish(root, mesh, None, 0, options);
        }
        let buffer = root.push(json::Buffer {
            byte_length: USize64::from(bin_len),
            uri: None,
            extensions: None,
            extras: Default::default(),
        });
        let view_idx: Vec<_> = views
            .iter()
            .map(|&(off, len, target)| {
                root.push(json::buffer::View {
                    buffer,
                    byte_length: USize64::from(len),
                    byte_offset: Some(USize64::from(off)),
                    byte_stride: None,
                    target: Some(Valid(target)),
                    extensions: None,
                    extras: Default::default(),
                })
            })
            .collect();
        let accessor = |root: &mut json::Root,
                        view: usize,
                        n: usize,
                        ct: json::accessor::ComponentType,
                        ty: json::accessor::Type,
                        minmax: Option<([f32; 3], [f32; 3])>| {
            root.push(json::Accessor {
                buffer_view: Some(view_idx[view]),
                byte_offset: Some(USize64(0)),
                count: USize64::from(n),
                component_type: Valid(json::accessor::GenericComponentType(ct)),
                extensions: None,
                extras: Default::default(),
                type_: Valid(ty),
                min: minmax.map(|(a, _)| json::Value::from(a.to_vec())),
                max: minmax.map(|(_, b)| json::Value::from(b.to_vec())),
                normalized: false,
                sparse: None,
            })
        };
        use json::accessor::{ComponentType as C, Type as T};
        let pos = accessor(
            &mut root,
            0,
            count,
            C::F32,
            T::Vec3,
            (count > 0).then_some((min, max)),
        );
        let nor = normals
            .as_ref()
            .map(|_| accessor(&mut root, 1, count, C::F32, T::Vec3, None));
        let col_view = 1 + usize::from(normals.is_some());
        let col = colors.map(|_| accessor(&mut root, col_view, count, C::F32, T::Vec4, None));
        let idx = accessor(
            &mut root,
            views.len() - 1,
            index_count,
            C::U32,
            T::Scalar,
            None,
        );
        let mut attributes = BTreeMap::new();
        attributes.insert(Valid(json::mesh::Semantic::Positions), pos);
        if let Some(n) = nor {
            attributes.insert(Valid(json::mesh::Semantic::Normals), n);
        }
        if let Some(c) = col {
            attributes.insert(Valid(json::mesh::Semantic::Colors(0)), c);
        }
        let mesh_idx = root.push(json::Mesh {
            extensions: None,
            extras: Default::default(),
            primitives: vec![json::mesh::Primitive {
                attributes,
                extensions: None,
                extras: Default::default(),
                indices: Some(idx),
                material: None,
                mode: Valid(json::mesh::Mode::Triangles),
                targets: None,
            }],
            weights: None,
        });
        let node = root.push(json::Node {
            mesh: Some(mesh_idx),
            ..Default::default()
        });
        let scene = root.push(json::Scene {
            extensions: None,
            extras: Default::default(),
            nodes: vec![node],
        });
        root.scene = Some(scene);
        Self::finish(root, mesh, normals, bin_len, options)
    }

    /// The file of the document `root` (its `extras` from `options`) and a BIN chunk of
    /// `bin_len` bytes (none at 0) of `mesh`'s arrays.
    fn finish(
        root: json::Root,
        mesh: &'m TriMesh,
        normals: Option<Vec<[f32; 3]>>,
        bin_len: usize,
        options: &GlbOptions,
    ) -> Result<Self, IoError> {
        let json_error = |e| IoError::Json {
            path: Default::default(),
            reason: e,
        };
        let mut js = root.to_vec().map_err(json_error)?;
        if let Some(extras) = &options.extras {
            let mut doc: serde_json::Value = serde_json::from_slice(&js).map_err(json_error)?;
            if let Some(obj) = doc.as_object_mut() {
                obj.insert("extras".into(), extras.clone());
            }
            js = serde_json::to_vec(&doc).map_err(json_error)?;
        }
        js.resize(pad4(js.len()), b' ');
        let file = GlbFile {
            mesh,
            normals,
            json: js,
            bin_len,
        };
        u32::try_from(file.len()).map_err(|_| {
            IoError::InvalidMesh(format!("{} bytes exceed glb's 4 GiB limit", file.len()))
        })?;
        Ok(file)
    }

    /// The file's size in bytes.
    pub fn len(&self) -> usize {
        12 + 8
            + self.json.len()
            + if self.bin_len > 0 {
                8 + self.bin_len
            } else {
                0
            }
    }

    /// Never: a glb file has at least its header.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Writes the file to `w`, the mesh's arrays a block at a time.
    pub fn write_to<W: Write>(&self, w: &mut W) -> std::io::Result<()> {
        // Both sizes were checked against u32 in `new`.
        let le = |n: usize| (n as u32).to_le_bytes();
        w.write_all(GLB_MAGIC)?;
        w.write_all(&2u32.to_le_bytes())?;
        w.write_all(&le(self.len()))?;
        w.write_all(&le(self.json.len()))?;
        w.write_all(&CHUNK_JSON.to_le_bytes())?;
        w.write_all(&self.json)?;
        if self.bin_len == 0 {
            return Ok(());
        }
        w.write_all(&le(self.bin_len))?;
        w.write_all(&CHUNK_BIN.to_le_bytes())?;
        let mut out = Words::new(w);
        for v in &self.mesh.vertices {
            for x in v.as_vec3().to_array() {
                out.put(x.to_le_bytes())?;
            }
        }
        for n in self.normals.iter().flatten().flatten() {
            out.put(n.to_le_bytes())?;
        }
        for c in self.mesh.colors.iter().flatten().flatten() {
            out.put(c.to_le_bytes())?;
        }
        for i in self.mesh.triangles.iter().flatten() {
            out.put(i.to_le_bytes())?;
        }
        out.finish()
    }
}

/// Four-byte words written through a block buffer (one `write_all` per 64 KiB, not per word).
struct Words<'w, W: Write> {
    w: &'w mut W,
    buf: Vec<u8>,
}

impl<'w, W: Write> Words<'w, W> {
    const BLOCK: usize = 1 << 16;

    fn new(w: &'w mut W) -> Self {
        Self {
            w,
            buf: Vec::with_capacity(Self::BLOCK),
        }
    }

    #[inline]
    fn put(&mut self, word: [u8; 4]) -> std::io::Result<()> {
        self.buf.extend_from_slice(&word);
        if self.buf.len() >= Self::BLOCK {
            self.w.write_all(&self.buf)?;
            self.buf.clear();
        }
        Ok(())
    }

    fn finish(mut self) -> std::io::Result<()> {
        self.w.write_all(&self.buf)?;
        self.buf.clear();
        Ok(())
    }
}

/// The size in bytes of [`glb_bytes`]'s file for a mesh of `vertices` vertices and
/// `triangles` triangles, without building it: exact for the BIN chunk, the JSON chunk
/// bounded above by 4 KiB.
pub fn glb_size_bound(vertices: usize, triangles: usize, colors: bool, shading: Shading) -> u64 {
    let per_vertex = 12 + 12 * u64::from(shading == Shading::Smooth) + 16 * u64::from(colors);
    28 + 4096 + vertices as u64 * per_vertex + triangles as u64 * 12 + 16
}

/// Writes `mesh` as a glb file, atomically, without holding the file in memory.
pub fn write_glb(path: &Path, mesh: &TriMesh, options: &GlbOptions) -> Result<(), IoError> {
    let file = GlbFile::new(mesh, options)?;
    write_atomic(path, |w| file.write_to(w))
}

/// A glb file taken apart: its parsed JSON document and its BIN chunk.
#[derive(Debug)]
pub struct Glb {
    /// The glTF document.
    pub root: json::Root,
    /// The binary buffer.
    pub bin: Vec<u8>,
}

/// Reads and checks a glb container: header, chunk lengths and types, padding; parses the JSON
/// with `gltf-json` and runs its validation (indices in range, required fields).
pub fn read_glb(path: &Path) -> Result<Glb, IoError> {
    let bytes = std::fs::read(path).map_err(|e| IoError::io(path, e))?;
    parse_glb(&bytes, path)
}

/// [`read_glb`] on bytes; `path` only names the source in errors.
pub fn parse_glb(bytes: &[u8], path: &Path) -> Result<Glb, IoError> {
    let bad = |what: String, expected: &str| IoError::malformed(path, what, expected);
    let u32_at = |o: usize| -> Option<u32> {
        bytes
            .get(o..o + 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    if bytes.len() < 20 || &bytes[0..4] != GLB_MAGIC {
        return Err(bad(
            format!("{} bytes without the `glTF` magic", bytes.len()),
            "a glb header",
        ));
    }
    if u32_at(4) != Some(2) || u32_at(8) != Some(bytes.len() as u32) {
        return Err(bad(
            format!(
                "version {:?}, length {:?} for {} bytes",
                u32_at(4),
                u32_at(8),
                bytes.len()
            ),
            "version 2 and the file's length",
        ));
    }
    let jlen = u32_at(12).unwrap_or(0) as usize;
    if u32_at(16) != Some(CHUNK_JSON) || jlen % 4 != 0 || 20 + jlen > bytes.len() {
        return Err(bad(
            format!("JSON chunk of {jlen} bytes"),
            "a JSON chunk padded to 4 bytes",
        ));
    }
    let js = &bytes[20..20 + jlen];
    let mut bin = Vec::new();
    let b0 = 20 + jlen;
    if b0 < bytes.len() {
        let blen = u32_at(b0).unwrap_or(0) as usize;
        if u32_at(b0 + 4) != Some(CHUNK_BIN) || blen % 4 != 0 || b0 + 8 + blen != bytes.len() {
            return Err(bad(
                format!("BIN chunk of {blen} bytes at {b0}"),
                "a BIN chunk padded to 4 bytes ending the file",
            ));
        }
        bin = bytes[b0 + 8..].to_vec();
    }
    let root = json::Root::from_slice(js).map_err(|e| IoError::Json {
        path: path.to_path_buf(),
        reason: e,
    })?;
    // gltf-json's validation indexes a primitive's POSITION accessor before checking that it
    // exists (it panics on an index out of range): checked here first.
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let position = json::validation::Checked::Valid(json::mesh::Semantic::Positions);
            if let Some(a) = prim.attributes.get(&position) {
                if a.value() >= root.accessors.len() {
                    return Err(bad(
                        format!(
                            "meshes[{m}].primitives[{p}] POSITION accessor {} of {}",
                            a.value(),
                            root.accessors.len()
                        ),
                        "accessor indices within the document's accessors",
                    ));
                }
            }
        }
    }
    let mut errors = Vec::new();
    json::validation::Validate::validate(&root, &root, json::Path::new, &mut |p, e| {
        errors.push(format!("{}: {e}", p()))
    });
    if let Some(e) = errors.first() {
        return Err(bad(
            format!("glTF validation: {e} ({} errors)", errors.len()),
            "a valid glTF 2.0 document",
        ));
    }
    Ok(Glb { root, bin })
}
