//! STL, binary and ASCII. The binary writer is swarf's own: a binary STL is an 80-byte header,
//! a `u32` count and 50 bytes per triangle (normal and corners as little-endian `f32`, a zero
//! `u16`), which every viewer and slicer opens; swarf encodes it in blocks in parallel (on one
//! thread a 5-million-triangle envelope's STL took 0.4 s to encode, the larger part of its
//! output time). The reader is swarf's own too, so that it can tell binary from ASCII robustly
//! (binary files whose 80-byte header starts with `solid` exist: a file is binary exactly when
//! its size is `84 + 50 × count` for the count in its header), report what it found where, and
//! never panic on garbage. Triangles read are welded on identical positions so that
//! closedness can be checked by index.

use crate::atomic::write_atomic;
use crate::error::IoError;
use crate::mesh::TriMesh;
use crate::tolerance::MAX_STL_TRIANGLES;
use rayon::prelude::*;
use std::io::Write;
use std::path::Path;
use swarf_geom::math::Vec3;

/// Bytes of one binary STL triangle record.
const RECORD: usize = 50;

/// Triangles encoded per block of the binary writer (1.6 MB of output): blocks are encoded in
/// parallel, a few at a time, and written in order.
const BLOCK: usize = 1 << 15;

/// Triangle `t` as STL stores it: its unit normal and its three corners, in `f32`.
fn stl_triangle(mesh: &TriMesh, t: usize) -> [[f32; 3]; 4] {
    let corners = mesh.corners(t);
    let [a, b, c] = corners;
    [crate::mesh::facet_normal(corners), a, b, c]
        .map(|p: Vec3| [p.x as f32, p.y as f32, p.z as f32])
}

/// Replaces `out` with the binary records of `triangles`.
fn encode_binary(mesh: &TriMesh, triangles: std::ops::Range<usize>, out: &mut Vec<u8>) {
    out.clear();
    out.reserve(RECORD * triangles.len());
    for t in triangles {
        // The record assembled whole, then appended once (the attribute stays zero).
        let mut record = [0u8; RECORD];
        for (k, c) in stl_triangle(mesh, t).as_flattened().iter().enumerate() {
            record[4 * k..4 * k + 4].copy_from_slice(&c.to_le_bytes());
        }
        out.extend_from_slice(&record);
    }
}

fn check_binary(mesh: &TriMesh) -> Result<(), IoError> {
    mesh.validate()?;
    if mesh.triangles.len() > u32::MAX as usize {
        return Err(IoError::InvalidMesh(format!(
            "{} triangles do not fit a binary STL",
            mesh.triangles.len()
        )));
    }
    Ok(())
}

/// Writes `mesh` as binary STL (single precision, facet normals from the vertex order),
/// atomically.
pub fn write_stl(path: &Path, mesh: &TriMesh) -> Result<(), IoError> {
    check_binary(mesh)?;
    write_atomic(path, |w| encode_stl(w, mesh))
}

/// Writes `mesh` as binary STL to `w` (what [`write_stl`] puts in its file); for a file of an
/// [`OutputSet`](crate::OutputSet).
///
/// # Errors
/// An invalid mesh (as [`write_stl`]) as [`std::io::ErrorKind::InvalidData`], or the writer's.
pub fn write_stl_to<W: std::io::Write>(w: &mut W, mesh: &TriMesh) -> std::io::Result<()> {
    check_binary(mesh)
        .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidData, e.to_string()))?;
    encode_stl(w, mesh)
}

/// The binary STL of a checked mesh: a zero header, the count, then the records, encoded
/// `2 × threads` blocks at a time.
fn encode_stl<W: std::io::Write>(w: &mut W, mesh: &TriMesh) -> std::io::Result<()> {
    let count = mesh.triangles.len();
    w.write_all(&[0u8; 80])?;
    w.write_all(&(count as u32).to_le_bytes())?;
    let mut buffers: Vec<Vec<u8>> = vec![Vec::new(); 2 * rayon::current_num_threads()];
    let mut first = 0;
    while first < count {
        let batch = buffers.len() * BLOCK;
        buffers.par_iter_mut().enumerate().for_each(|(i, buf)| {
            let start = (first + i * BLOCK).min(count);
            encode_binary(mesh, start..(start + BLOCK).min(count), buf);
        });
        for buf in &buffers {
            w.write_all(buf)?;
        }
        first += batch;
    }
    Ok(())
}

/// Writes `mesh` as ASCII STL (`solid name` … `endsolid name`), atomically. Coordinates are
/// written with enough digits to read back the same `f32` values as the binary form.
pub fn write_stl_ascii(path: &Path, mesh: &TriMesh, name: &str) -> Result<(), IoError> {
    mesh.validate()?;
    let name: String = name.chars().filter(|c| !c.is_whitespace()).collect();
    write_atomic(path, |w| {
        writeln!(w, "solid {name}")?;
        for t in 0..mesh.triangles.len() {
            let [n, corners @ ..] = stl_triangle(mesh, t);
            writeln!(w, "  facet normal {:e} {:e} {:e}", n[0], n[1], n[2])?;
            writeln!(w, "    outer loop")?;
            for v in &corners {
                writeln!(w, "      vertex {:e} {:e} {:e}", v[0], v[1], v[2])?;
            }
            writeln!(w, "    endloop")?;
            writeln!(w, "  endfacet")?;
        }
        writeln!(w, "endsolid {name}")
    })
}

/// Reads a binary or ASCII STL file into a welded [`TriMesh`] (identical positions merged).
pub fn read_stl(path: &Path) -> Result<TriMesh, IoError> {
    let bytes = std::fs::read(path).map_err(|e| IoError::io(path, e))?;
    parse_stl(&bytes, path)
}

/// Parses STL bytes; `path` only names the source in errors.
pub fn parse_stl(bytes: &[u8], path: &Path) -> Result<TriMesh, IoError> {
    let binary_size = (bytes.len() >= 84).then(|| {
        let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
        (count, 84 + 50 * count)
    });
    if let Some((count, size)) = binary_size {
        if size == bytes.len() as u64 {
            return parse_binary(bytes, count, path);
        }
    }
    let start = bytes
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(bytes.len());
    if bytes[start..].starts_with(b"solid") {
        return parse_ascii(bytes, path);
    }
    let what = match binary_size {
        Some((count, size)) => format!(
            "{} bytes, not starting with `solid`; as binary its header claims {count} triangles, \
             which needs {size} bytes",
            bytes.len()
        ),
        None => format!(
            "{} bytes, too short for a binary STL and not starting with `solid`",
            bytes.len()
        ),
    };
    Err(IoError::malformed(
        path,
        what,
        "a binary STL (84 + 50 × triangle count bytes) or an ASCII STL starting with `solid`",
    ))
}

fn parse_binary(bytes: &[u8], count: u64, path: &Path) -> Result<TriMesh, IoError> {
    if count > MAX_STL_TRIANGLES {
        return Err(IoError::malformed(
            path,
            format!("binary header claims {count} triangles"),
            format!("at most {MAX_STL_TRIANGLES} triangles"),
        ));
    }
    let mut soup = Vec::with_capacity(count as usize);
    for t in 0..count as usize {
        let rec = &bytes[84 + 50 * t..84 + 50 * (t + 1)];
        let f = |k: usize| {
            let o = 12 + 4 * k;
            f32::from_le_bytes([rec[o], rec[o + 1], rec[o + 2], rec[o + 3]]) as f64
        };
        let tri = [0, 1, 2].map(|v| Vec3::new(f(3 * v), f(3 * v + 1), f(3 * v + 2)));
        if tri.iter().any(|p| !p.is_finite()) {
            return Err(IoError::malformed(
                path,
                format!(
                    "triangle {t} (byte {}) has a non-finite coordinate",
                    84 + 50 * t
                ),
                "finite vertex coordinates",
            ));
        }
        soup.push(tri);
    }
    Ok(weld_soup(&soup))
}

fn parse_ascii(bytes: &[u8], path: &Path) -> Result<TriMesh, IoError> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        IoError::malformed(
            path,
            format!(
                "invalid UTF-8 at byte {} in a file starting with `solid`",
                e.valid_up_to()
            ),
            "ASCII text (or a binary STL whose size matches its triangle count)",
        )
    })?;
    let mut tokens = text
        .lines()
        .enumerate()
        .flat_map(|(l, line)| line.split_whitespace().map(move |w| (l + 1, w)));
    let mut soup: Vec<[Vec3; 3]> = Vec::new();
    let eof = |expected: &str| IoError::malformed(path, "end of file", format!("`{expected}`"));
    let expect = |tok: Option<(usize, &str)>, want: &str| -> Result<(), IoError> {
        match tok {
            Some((_, w)) if w == want => Ok(()),
            Some((l, w)) => Err(IoError::malformed(
                path,
                format!("line {l}: `{w}`"),
                format!("`{want}`"),
            )),
            None => Err(eof(want)),
        }
    };
    let number = |tok: Option<(usize, &str)>| -> Result<f64, IoError> {
        match tok {
            Some((l, w)) => match w.parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(x),
                _ => Err(IoError::malformed(
                    path,
                    format!("line {l}: `{w}`"),
                    "a finite number",
                )),
            },
            None => Err(eof("a number")),
        }
    };
    let mut in_solid = false;
    while let Some((l, w)) = tokens.next() {
        match w {
            "solid" if !in_solid => {
                in_solid = true;
                // The name runs to the end of the line.
                while tokens.clone().next().is_some_and(|(l2, _)| l2 == l) {
                    tokens.next();
                }
            }
            "endsolid" if in_solid => {
                in_solid = false;
                while tokens.clone().next().is_some_and(|(l2, _)| l2 == l) {
                    tokens.next();
                }
            }
            "facet" if in_solid => {
                expect(tokens.next(), "normal")?;
                for _ in 0..3 {
                    number(tokens.next())?;
                }
                expect(tokens.next(), "outer")?;
                expect(tokens.next(), "loop")?;
                let mut tri = [Vec3::ZERO; 3];
                for p in &mut tri {
                    expect(tokens.next(), "vertex")?;
                    *p = Vec3::new(
                        number(tokens.next())?,
                        number(tokens.next())?,
                        number(tokens.next())?,
                    );
                }
                expect(tokens.next(), "endloop")?;
                expect(tokens.next(), "endfacet")?;
                soup.push(tri);
            }
            _ => {
                let want = if in_solid {
                    "`facet` or `endsolid`"
                } else {
                    "`solid`"
                };
                return Err(IoError::malformed(path, format!("line {l}: `{w}`"), want));
            }
        }
    }
    if in_solid {
        return Err(eof("endsolid"));
    }
    Ok(weld_soup(&soup))
}

/// Builds an indexed mesh from a triangle soup, merging identical positions.
pub fn weld_soup(soup: &[[Vec3; 3]]) -> TriMesh {
    let mut m = TriMesh::new();
    m.vertices = soup.iter().flatten().copied().collect();
    m.triangles = (0..soup.len() as u32)
        .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
        .collect();
    // Exact welding keeps degenerate (repeated-vertex) triangles out; they carry no area.
    m.weld(0.0);
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ascii_errors_name_line_and_expectation() {
        let p = Path::new("x.stl");
        let bad = b"solid a\n facet normal 0 0 1\n outer loop\n vertex 0 0 zz\n";
        let e = parse_stl(bad, p).unwrap_err().to_string();
        assert!(
            e.contains("line 4") && e.contains("`zz`") && e.contains("finite number"),
            "{e}"
        );
        let e = parse_stl(b"solid a\n facet normal 0 0 1\n", p)
            .unwrap_err()
            .to_string();
        assert!(e.contains("end of file") && e.contains("outer"), "{e}");
        let e = parse_stl(b"hello", p).unwrap_err().to_string();
        assert!(e.contains("too short"), "{e}");
        let ok = b"solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
        let m = parse_stl(ok, p).unwrap();
        assert_eq!((m.vertices.len(), m.triangles.len()), (3, 1));
    }

    #[test]
    fn binary_records_over_several_blocks_decode_to_the_mesh() {
        // More triangles than one batch of blocks holds: every record at its place, decoded
        // field by field (header, count, normal, corners, attribute), on one thread and three.
        let n = 7 * BLOCK + 123;
        let mesh = TriMesh::from_parts(
            (0..n + 2)
                .map(|i| Vec3::new(i as f64 * 0.25, (i % 7) as f64, 1.0 / (1.0 + i as f64)))
                .collect(),
            (0..n as u32).map(|i| [i, i + 1, i + 2]).collect(),
        );
        let encode = |threads: usize| {
            let mut bytes = Vec::new();
            swarf_testdata::on_threads(threads, || write_stl_to(&mut bytes, &mesh)).unwrap();
            bytes
        };
        let bytes = encode(1);
        assert_eq!(bytes, encode(3));
        assert_eq!(bytes.len(), 84 + RECORD * n);
        assert!(bytes[..80].iter().all(|&b| b == 0));
        assert_eq!(
            u32::from_le_bytes(bytes[80..84].try_into().unwrap()),
            n as u32
        );
        let f = |at: usize| f32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
        for t in [0, 1, BLOCK - 1, BLOCK, 4 * BLOCK + 7, 6 * BLOCK + 1, n - 1] {
            let at = 84 + RECORD * t;
            let normal = mesh.triangle_normal(t);
            let corners = mesh.corners(t);
            for k in 0..3 {
                assert_eq!(f(at + 4 * k), normal[k] as f32, "triangle {t}");
                for (c, p) in corners.iter().enumerate() {
                    assert_eq!(f(at + 12 + 12 * c + 4 * k), p[k] as f32, "triangle {t}");
                }
            }
            assert_eq!(&bytes[at + 48..at + 50], &[0, 0]);
        }
    }
}
