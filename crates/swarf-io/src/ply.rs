//! PLY, binary little-endian: `float x y z` per vertex, optional `uchar red green blue alpha`,
//! and `list uchar uint vertex_indices` per face. MeshLab, CloudCompare and Blender read it,
//! and unlike STL it keeps the mesh indexed and carries colours. The reader accepts what the
//! writer produces (and `float`/`double` positions, `int`/`uint` indices) for round trips.

use crate::atomic::write_atomic;
use crate::error::IoError;
use crate::mesh::TriMesh;
use std::io::Write;
use std::path::Path;
use swarf_geom::math::Vec3;

/// Writes `mesh` as binary little-endian PLY (colours as 8-bit RGBA when present), atomically.
pub fn write_ply(path: &Path, mesh: &TriMesh) -> Result<(), IoError> {
    mesh.validate()?;
    write_atomic(path, |w| {
        writeln!(
            w,
            "ply\nformat binary_little_endian 1.0\ncomment written by swarf-io"
        )?;
        writeln!(w, "element vertex {}", mesh.vertices.len())?;
        writeln!(w, "property float x\nproperty float y\nproperty float z")?;
        if mesh.colors.is_some() {
            writeln!(
                w,
                "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha"
            )?;
        }
        writeln!(w, "element face {}", mesh.triangles.len())?;
        writeln!(w, "property list uchar uint vertex_indices\nend_header")?;
        for (i, v) in mesh.vertices.iter().enumerate() {
            for c in [v.x, v.y, v.z] {
                w.write_all(&(c as f32).to_le_bytes())?;
            }
            if let Some(colors) = &mesh.colors {
                let c = colors[i].map(|x| (x.clamp(0.0, 1.0) * 255.0).round() as u8);
                w.write_all(&c)?;
            }
        }
        for t in &mesh.triangles {
            w.write_all(&[3u8])?;
            for &i in t {
                w.write_all(&i.to_le_bytes())?;
            }
        }
        Ok(())
    })
}

#[derive(Clone, Copy, PartialEq)]
enum Scalar {
    U8,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(s: &str) -> Option<Scalar> {
        Some(match s {
            "uchar" | "uint8" => Scalar::U8,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::U8 => 1,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    fn read(self, b: &[u8]) -> f64 {
        match self {
            Scalar::U8 => b[0] as f64,
            Scalar::I32 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F64 => f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]),
        }
    }
}

/// Reads a binary little-endian PLY with triangle faces (as written by [`write_ply`]).
pub fn read_ply(path: &Path) -> Result<TriMesh, IoError> {
    let bytes = std::fs::read(path).map_err(|e| IoError::io(path, e))?;
    parse_ply(&bytes, path)
}

/// Parses binary little-endian PLY bytes; `path` only names the source in errors.
pub fn parse_ply(bytes: &[u8], path: &Path) -> Result<TriMesh, IoError> {
    let bad = |what: String, expected: &str| IoError::malformed(path, what, expected);
    let end = b"end_header\n";
    let hend = bytes
        .windows(end.len())
        .position(|w| w == end)
        .ok_or_else(|| bad("no `end_header` line".into(), "a PLY header"))?
        + end.len();
    let header = std::str::from_utf8(&bytes[..hend])
        .map_err(|_| bad("a header that is not text".into(), "an ASCII PLY header"))?;
    let mut lines = header.lines();
    if lines.next() != Some("ply") {
        return Err(bad("first line is not `ply`".into(), "`ply`"));
    }
    let (mut nv, mut nf) = (None, None);
    let mut vprops: Vec<(String, Scalar)> = Vec::new();
    let mut face_list: Option<(Scalar, Scalar)> = None;
    let mut current = "";
    for (l, line) in lines.enumerate() {
        let w: Vec<&str> = line.split_whitespace().collect();
        let count = |s: &str| {
            s.parse::<usize>().map_err(|_| {
                bad(
                    format!("header line {}: `{line}`", l + 2),
                    "an element count",
                )
            })
        };
        match w.as_slice() {
            ["format", "binary_little_endian", "1.0"] | ["end_header"] => {}
            ["format", ..] => {
                return Err(bad(
                    format!("header line {}: `{line}`", l + 2),
                    "`format binary_little_endian 1.0`",
                ))
            }
            ["comment", ..] | ["obj_info", ..] => {}
            ["element", "vertex", n] => {
                nv = Some(count(n)?);
                current = "vertex";
            }
            ["element", "face", n] => {
                nf = Some(count(n)?);
                current = "face";
            }
            ["property", "list", c, i, _] if current == "face" => {
                face_list = Scalar::parse(c).zip(Scalar::parse(i));
            }
            ["property", t, name] if current == "vertex" => {
                let s = Scalar::parse(t).ok_or_else(|| {
                    bad(format!("header line {}: `{line}`", l + 2), "a scalar type")
                })?;
                vprops.push((name.to_string(), s));
            }
            _ => {
                return Err(bad(
                    format!("header line {}: `{line}`", l + 2),
                    "vertex and face elements of a triangle mesh",
                ))
            }
        }
    }
    let (nv, nf) = nv.zip(nf).ok_or_else(|| {
        bad(
            "no vertex or no face element".into(),
            "both `element vertex` and `element face`",
        )
    })?;
    let (lc, li) = face_list.ok_or_else(|| {
        bad(
            "no face index list".into(),
            "`property list uchar uint vertex_indices`",
        )
    })?;
    let find = |n: &str| vprops.iter().position(|(p, _)| p == n);
    let xyz = [find("x"), find("y"), find("z")];
    let [Some(ix), Some(iy), Some(iz)] = xyz else {
        return Err(bad("vertex without x, y and z".into(), "x y z properties"));
    };
    let rgba = [find("red"), find("green"), find("blue"), find("alpha")];
    let stride: usize = vprops.iter().map(|(_, s)| s.size()).sum();
    let mut offsets = Vec::with_capacity(vprops.len());
    let mut o = 0;
    for (_, s) in &vprops {
        offsets.push(o);
        o += s.size();
    }
    let body = &bytes[hend..];
    let need = nv
        .checked_mul(stride)
        .filter(|&n| n <= body.len())
        .ok_or_else(|| {
            bad(
                format!("{} bytes after the header", body.len()),
                &format!("{nv} vertices of {stride} bytes"),
            )
        })?;
    let get = |v: usize, p: usize| vprops[p].1.read(&body[v * stride + offsets[p]..]);
    let mut mesh = TriMesh::new();
    mesh.vertices = (0..nv)
        .map(|v| Vec3::new(get(v, ix), get(v, iy), get(v, iz)))
        .collect();
    if let [Some(r), Some(g), Some(b)] = [rgba[0], rgba[1], rgba[2]] {
        let scale = |p: usize, v: usize| {
            let x = get(v, p);
            (if vprops[p].1 == Scalar::U8 {
                x / 255.0
            } else {
                x
            }) as f32
        };
        mesh.colors = Some(
            (0..nv)
                .map(|v| {
                    let a = rgba[3].map_or(1.0, |a| scale(a, v));
                    [scale(r, v), scale(g, v), scale(b, v), a]
                })
                .collect(),
        );
    }
    let mut at = need;
    for f in 0..nf {
        let short = || {
            bad(
                format!("file ends in face {f} of {nf}"),
                "a complete face list",
            )
        };
        let c = body.get(at..at + lc.size()).ok_or_else(short)?;
        let c = lc.read(c);
        if c != 3.0 {
            return Err(bad(format!("face {f} has {c} vertices"), "triangles (3)"));
        }
        at += lc.size();
        let mut t = [0u32; 3];
        for v in &mut t {
            let b = body.get(at..at + li.size()).ok_or_else(short)?;
            let x = li.read(b);
            if !(x >= 0.0 && (x as usize) < nv) {
                return Err(bad(
                    format!("face {f} refers to vertex {x}"),
                    &format!("an index below {nv}"),
                ));
            }
            *v = x as u32;
            at += li.size();
        }
        mesh.triangles.push(t);
    }
    Ok(mesh)
}
