//! STL, binary and ASCII. Binary is written with `stl_io` (the de-facto standard every viewer
//! and slicer opens); the reader is swarf's own so that it can tell binary from ASCII robustly
//! (binary files whose 80-byte header starts with `solid` exist: a file is binary exactly when
//! its size is `84 + 50 × count` for the count in its header), report what it found where, and
//! never panic on garbage. Triangles read are welded on identical positions so that
//! closedness can be checked by index.

use crate::atomic::write_atomic;
use crate::error::IoError;
use crate::mesh::TriMesh;
use crate::tolerance::MAX_STL_TRIANGLES;
use std::io::Write;
use std::path::Path;
use swarf_geom::math::Vec3;

fn stl_triangles(mesh: &TriMesh) -> impl ExactSizeIterator<Item = stl_io::Triangle> + '_ {
    (0..mesh.triangles.len()).map(move |t| {
        let [a, b, c] = mesh.corners(t);
        let n = mesh.triangle_normal(t);
        let v = |p: Vec3| stl_io::Vertex::new([p.x as f32, p.y as f32, p.z as f32]);
        stl_io::Triangle {
            normal: stl_io::Normal::new([n.x as f32, n.y as f32, n.z as f32]),
            vertices: [v(a), v(b), v(c)],
        }
    })
}

/// Writes `mesh` as binary STL (single precision, facet normals from the vertex order),
/// atomically.
pub fn write_stl(path: &Path, mesh: &TriMesh) -> Result<(), IoError> {
    mesh.validate()?;
    if mesh.triangles.len() > u32::MAX as usize {
        return Err(IoError::InvalidMesh(format!(
            "{} triangles do not fit a binary STL",
            mesh.triangles.len()
        )));
    }
    write_atomic(path, |w| stl_io::write_stl(w, stl_triangles(mesh)))
}

/// Writes `mesh` as binary STL to `w` (what [`write_stl`] puts in its file); for a file of an
/// [`OutputSet`](crate::OutputSet).
///
/// # Errors
/// An invalid mesh (as [`write_stl`]) as [`std::io::ErrorKind::InvalidData`], or the writer's.
pub fn write_stl_to<W: std::io::Write>(w: &mut W, mesh: &TriMesh) -> std::io::Result<()> {
    mesh.validate()
        .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidData, e.to_string()))?;
    if mesh.triangles.len() > u32::MAX as usize {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("{} triangles do not fit a binary STL", mesh.triangles.len()),
        ));
    }
    stl_io::write_stl(w, stl_triangles(mesh))
}

/// Writes `mesh` as ASCII STL (`solid name` … `endsolid name`), atomically. Coordinates are
/// written with enough digits to read back the same `f32` values as the binary form.
pub fn write_stl_ascii(path: &Path, mesh: &TriMesh, name: &str) -> Result<(), IoError> {
    mesh.validate()?;
    let name: String = name.chars().filter(|c| !c.is_whitespace()).collect();
    write_atomic(path, |w| {
        writeln!(w, "solid {name}")?;
        for t in stl_triangles(mesh) {
            let n = t.normal;
            writeln!(w, "  facet normal {:e} {:e} {:e}", n[0], n[1], n[2])?;
            writeln!(w, "    outer loop")?;
            for v in &t.vertices {
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
}
