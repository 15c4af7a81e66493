//! STL, binary and ASCII. The binary writer is swarf's own: a binary STL is an 80-byte header,
//! a `u32` count and 50 bytes per triangle (normal and corners as little-endian `f32`, a zero
//! `u16`), which every viewer and slicer opens; swarf encodes it in blocks in parallel (on one
//! thread a 5-million-triangle envelope's STL took 0.4 s to encode, the larger part of its
//! output time). The reader is swarf's own too, so that it can tell binary from ASCII robustly,
//! report what it found where, and never panic on garbage. Triangles read are welded on
//! identical positions so that closedness can be checked by index.
//!
//! # What the reader accepts
//! Files from real exporters, as common viewers open them:
//! - **Binary or ASCII.** A file is binary when its size is `84 + 50 × count` for the count in
//!   its header, or when it is not text (a byte below 0x20 other than tab, line feed, carriage
//!   return, vertical tab and form feed, before the trailing junk below): binary files whose
//!   80-byte header starts with `solid` exist. A text file starting with `solid` (in any case,
//!   after a UTF-8 byte-order mark and white space) is ASCII.
//! - **Binary counts that disagree with the size**, read without a note (the reader has no
//!   channel for notes): a header count of 0 in a file of exactly `84 + 50 × n` bytes (streaming
//!   exporters fill the count in last, or never) reads the `n` triangles; bytes after the
//!   stated count's records (padding) are ignored. A count larger than the data is an error
//!   giving the count, the size it needs and the file's size.
//! - **ASCII leniency.** Keywords in any case (`SOLID`, `Facet`, `OUTER LOOP`, `ENDSOLID`…);
//!   bytes that are not UTF-8 (Latin-1 names and comments) decoded leniently — only the
//!   keywords and numbers matter; anything after the last `endsolid` made only of white space,
//!   NUL and Ctrl-Z (0x1A) bytes ignored; the facet normal's three tokens not read (normals are
//!   recomputed from the corners, so `nan`, `-1.#IND00` or `inf` there is no error). Vertex
//!   coordinates must be finite numbers. Control characters in error messages are escaped
//!   (`\u{1a}`).

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
    let header_count = (bytes.len() >= 84)
        .then(|| u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64);
    if let Some(count) = header_count {
        if 84 + 50 * count == bytes.len() as u64 {
            return parse_binary(bytes, count, path);
        }
    }
    // Trailing junk (Ctrl-Z, NUL padding, white space) is no evidence of binary data.
    let end = bytes.len()
        - bytes
            .iter()
            .rev()
            .take_while(|&&b| b == 0 || b == 0x1a || b.is_ascii_whitespace())
            .count();
    let body = &bytes[..end];
    let text = body.strip_prefix(b"\xef\xbb\xbf").unwrap_or(body);
    let lead = text.iter().take_while(|b| b.is_ascii_whitespace()).count();
    let solid = text.len() >= lead + 5 && text[lead..lead + 5].eq_ignore_ascii_case(b"solid");
    let control = body
        .iter()
        .position(|&b| b < 0x20 && !matches!(b, b'\t' | b'\n' | b'\r' | 0x0b | 0x0c));
    if solid && control.is_none() {
        return parse_ascii(text, path);
    }
    let not_text = match control.filter(|_| solid) {
        Some(at) => format!(
            "starts with `solid` but is not text (byte {at} is {}); ",
            shown(&char::from(bytes[at]).to_string())
        ),
        None => "not starting with `solid`; ".into(),
    };
    let expected =
        "a binary STL (84 + 50 × triangle count bytes) or an ASCII STL starting with `solid`";
    let Some(count) = header_count else {
        return Err(IoError::malformed(
            path,
            format!(
                "{} bytes, too short for a binary STL and {not_text}",
                bytes.len()
            )
            .trim_end_matches("; ")
            .to_string(),
            expected,
        ));
    };
    let records = (bytes.len() as u64 - 84) / RECORD as u64;
    if count == 0 && (bytes.len() as u64 - 84) % RECORD as u64 == 0 {
        // A streaming exporter that never filled in the count: the size tells it.
        return parse_binary(bytes, records, path);
    }
    if count <= records {
        // Padding after the stated records.
        return parse_binary(bytes, count, path);
    }
    Err(IoError::malformed(
        path,
        format!(
            "{} bytes, {not_text}as binary its header claims {count} triangles, which needs {} \
             bytes",
            bytes.len(),
            84 + 50 * count
        ),
        expected,
    ))
}

/// `w` with its control characters escaped (`\u{1a}`), for error messages.
fn shown(w: &str) -> String {
    w.chars()
        .map(|c| {
            if c.is_control() {
                c.escape_unicode().to_string()
            } else {
                c.to_string()
            }
        })
        .collect()
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

/// Reads ASCII STL from `bytes` (the byte-order mark and trailing junk already cut off), keywords in any case, text that is not UTF-8 decoded leniently.
fn parse_ascii(bytes: &[u8], path: &Path) -> Result<TriMesh, IoError> {
    let text = String::from_utf8_lossy(bytes);
    let mut tokens = text
        .lines()
        .enumerate()
        .flat_map(|(l, line)| line.split_whitespace().map(move |w| (l + 1, w)));
    let mut soup: Vec<[Vec3; 3]> = Vec::new();
    let eof = |expected: &str| IoError::malformed(path, "end of file", format!("`{expected}`"));
    // Line and column of a word (a slice of `text`), found only for an error.
    let found = |l: usize, w: &str| {
        let at = (w.as_ptr() as usize)
            .checked_sub(text.as_ptr() as usize)
            .filter(|&at| at <= text.len());
        let column = at.map_or(1, |at| {
            let start = text[..at].rfind(['\n', '\r']).map_or(0, |i| i + 1);
            text[start..at].chars().count() + 1
        });
        format!("line {l}, column {column}: `{}`", shown(w))
    };
    let expect = |tok: Option<(usize, &str)>, want: &str| -> Result<(), IoError> {
        match tok {
            Some((_, w)) if w.eq_ignore_ascii_case(want) => Ok(()),
            Some((l, w)) => Err(IoError::malformed(path, found(l, w), format!("`{want}`"))),
            None => Err(eof(want)),
        }
    };
    let number = |tok: Option<(usize, &str)>| -> Result<f64, IoError> {
        match tok {
            Some((l, w)) => match w.parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(x),
                _ => Err(IoError::malformed(path, found(l, w), "a finite number")),
            },
            None => Err(eof("a number")),
        }
    };
    let mut in_solid = false;
    while let Some((l, w)) = tokens.next() {
        let is = |kw: &str| w.eq_ignore_ascii_case(kw);
        if (is("solid") && !in_solid) || (is("endsolid") && in_solid) {
            in_solid = !in_solid;
            // The name runs to the end of the line — or, in a file written on one line, up to
            // what follows it there: after `solid`, its first facet (`facet normal`) or its
            // `endsolid`; after `endsolid`, the next solid's `solid` (the last `solid` before
            // that solid's first facet or `endsolid`: a name may hold the word).
            // Read ahead only to that point (a line of many solids stays linear).
            let (mut ahead, mut n, mut last_solid) = (tokens.clone(), 0usize, None);
            let body = loop {
                let Some((_, w2)) = ahead.next().filter(|&(l2, _)| l2 == l) else {
                    break None;
                };
                let at = |kw: &str| w2.eq_ignore_ascii_case(kw);
                let facet = at("facet")
                    && ahead
                        .clone()
                        .next()
                        .is_some_and(|(l2, w3)| l2 == l && w3.eq_ignore_ascii_case("normal"));
                if facet || at("endsolid") {
                    break Some(n);
                }
                if at("solid") {
                    last_solid = Some(n);
                }
                n += 1;
            };
            let name_len = match (in_solid, body) {
                (true, Some(n)) => n,
                (false, Some(_)) => last_solid.unwrap_or(n),
                (_, None) => n,
            };
            for _ in 0..name_len {
                tokens.next();
            }
        } else if is("facet") && in_solid {
            expect(tokens.next(), "normal")?;
            // The normal is recomputed from the corners: exporters write `nan`, `-1.#IND00`…
            // for degenerate facets, and any token is taken.
            for _ in 0..3 {
                tokens.next().ok_or_else(|| eof("a normal component"))?;
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
        } else {
            let want = if in_solid {
                "`facet` or `endsolid`"
            } else {
                "`solid`"
            };
            return Err(IoError::malformed(path, found(l, w), want));
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
            e.contains("line 4, column 13: `zz`") && e.contains("finite number"),
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

    /// A closed tetrahedron as binary STL (`count` written in the header, `extra` bytes after
    /// the records) and the ASCII facets of the same triangles, keywords as `kw` spells them.
    fn tetrahedron() -> TriMesh {
        TriMesh::from_parts(
            vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
            vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        )
    }

    fn binary(header: &[u8], count: u32, extra: &[u8]) -> Vec<u8> {
        let mut bytes = Vec::new();
        write_stl_to(&mut bytes, &tetrahedron()).unwrap();
        bytes[..header.len()].copy_from_slice(header);
        bytes[80..84].copy_from_slice(&count.to_le_bytes());
        bytes.extend_from_slice(extra);
        bytes
    }

    fn ascii(kw: [&str; 7], normal: &str) -> String {
        let [solid, facet, outer, vertex, endloop, endfacet, endsolid] = kw;
        let m = tetrahedron();
        let mut s = format!("{solid} part\n");
        for t in 0..m.triangles.len() {
            s += &format!("  {facet} {normal}\n    {outer}\n");
            for p in m.corners(t) {
                s += &format!("      {vertex} {} {} {}\n", p.x, p.y, p.z);
            }
            s += &format!("    {endloop}\n  {endfacet}\n");
        }
        s + &format!("{endsolid} part\n")
    }

    const LOWER: [&str; 7] = [
        "solid",
        "facet",
        "outer loop",
        "vertex",
        "endloop",
        "endfacet",
        "endsolid",
    ];

    fn closed_tetrahedron(m: &TriMesh) -> bool {
        m.triangles.len() == 4
            && m.edge_report().is_clean()
            && (m.volume() - 1.0 / 6.0).abs() < 1e-12
    }

    #[test]
    fn ascii_keywords_are_read_in_any_case() {
        let p = Path::new("x.stl");
        for kw in [
            [
                "SOLID",
                "FACET",
                "OUTER LOOP",
                "VERTEX",
                "ENDLOOP",
                "ENDFACET",
                "ENDSOLID",
            ],
            [
                "Solid",
                "Facet",
                "Outer Loop",
                "Vertex",
                "EndLoop",
                "EndFacet",
                "EndSolid",
            ],
        ] {
            let text = ascii(kw, "NORMAL 0 0 1");
            let m = parse_stl(text.as_bytes(), p).unwrap_or_else(|e| panic!("{kw:?}: {e}"));
            assert!(closed_tetrahedron(&m), "{kw:?}");
        }
        // Misspelt keywords are still refused, whatever their case.
        let bad = ascii(LOWER, "normal 0 0 1").replacen("outer loop", "OUTER LOOPS", 1);
        let e = parse_stl(bad.as_bytes(), p).unwrap_err().to_string();
        assert!(e.contains("line 3") && e.contains("`LOOPS`"), "{e}");
    }

    #[test]
    fn ascii_with_bom_latin1_names_and_trailing_junk_is_read() {
        let p = Path::new("x.stl");
        let text = ascii(LOWER, "normal 0 0 1");
        let mut bom = b"\xef\xbb\xbf".to_vec();
        bom.extend_from_slice(text.as_bytes());
        // "Pièce" in Latin-1: not UTF-8.
        let latin1 = [
            b"solid Pi\xe8ce usin\xe9e\n".as_slice(),
            &text.as_bytes()[11..],
        ]
        .concat();
        assert!(std::str::from_utf8(&latin1).is_err());
        for (what, bytes) in [
            ("BOM", bom),
            ("Latin-1 name", latin1),
            ("Ctrl-Z", [text.as_bytes(), b"\x1a"].concat()),
            (
                "NUL padding",
                [text.as_bytes(), &[0u8; 37], b"\n \x1a"].concat(),
            ),
        ] {
            let m = parse_stl(&bytes, p).unwrap_or_else(|e| panic!("{what}: {e}"));
            assert!(closed_tetrahedron(&m), "{what}");
        }
        // Junk that is not trailing makes the file no text: an error naming the byte, the
        // control character escaped.
        let mid = [text.as_bytes(), b"\x1ajunk\n"].concat();
        let e = parse_stl(&mid, p).unwrap_err().to_string();
        let at = text.len();
        assert!(
            e.contains(&format!(r"not text (byte {at} is \u{{1a}})")) && !e.contains('\x1a'),
            "{e}"
        );
        // Text after the last `endsolid`: an ASCII error, escaped too.
        let after = [text.as_bytes(), b"endsolid\x7f\n"].concat();
        let e = parse_stl(&after, p).unwrap_err().to_string();
        assert!(
            e.contains(r"`endsolid\u{7f}`") && e.contains("expected `solid`"),
            "{e}"
        );
    }

    #[test]
    fn ascii_on_one_line_is_read() {
        // Every keyword on one line, a name of two words, two solids: a name stops at the first
        // facet, an `endsolid`'s at the next `solid`.
        let one = ascii(LOWER, "normal 0 0 1").replace('\n', " ");
        let text = format!("{} {one}", one.replacen("solid part", "solid a name", 1));
        assert_eq!(text.lines().count(), 1);
        let m = parse_stl(text.as_bytes(), Path::new("one.stl")).unwrap();
        assert_eq!((m.triangles.len(), m.vertices.len()), (8, 4));
        let first = parse_stl(one.as_bytes(), Path::new("one.stl")).unwrap();
        assert!(closed_tetrahedron(&first));
        // An empty solid on one line.
        let m = parse_stl(b"solid x endsolid x", Path::new("e.stl")).unwrap();
        assert!(m.triangles.is_empty());
        // Names holding the words `solid` and `facet`, on lines of their own and on one line.
        let named = ascii(LOWER, "normal 0 0 1").replace(" part\n", " my solid facet part\n");
        assert!(named.starts_with("solid my solid facet part\n"), "{named}");
        let m = parse_stl(named.as_bytes(), Path::new("n.stl")).unwrap();
        assert!(closed_tetrahedron(&m));
        let line = named.replace('\n', " ");
        let m = parse_stl(format!("{line} {line}").as_bytes(), Path::new("n.stl")).unwrap();
        assert_eq!(m.triangles.len(), 8);
        let m = parse_stl(
            b"solid a solid endsolid a solid solid b endsolid b solid",
            Path::new("e.stl"),
        )
        .unwrap();
        assert!(m.triangles.is_empty());
        // Many solids on one line: each name is read up to its solid's body only (reading to
        // the end of the line at every solid took minutes for 200,000).
        let many = "solid a endsolid a ".repeat(50_000);
        let m = parse_stl(many.as_bytes(), Path::new("m.stl")).unwrap();
        assert!(m.triangles.is_empty());
    }

    #[test]
    fn non_finite_ascii_normals_are_not_read_but_vertices_must_be_finite() {
        let p = Path::new("x.stl");
        for normal in [
            "nan nan nan",
            "-nan 0 1",
            "1.#QNAN0 -1.#IND00 inf",
            "-1.#IND00 x 0",
        ] {
            let text = ascii(LOWER, &format!("normal {normal}"));
            let m = parse_stl(text.as_bytes(), p).unwrap_or_else(|e| panic!("{normal}: {e}"));
            assert!(closed_tetrahedron(&m), "{normal}");
        }
        let text = ascii(LOWER, "normal 0 0 1").replacen("vertex 0 0 0", "vertex nan 0 0", 1);
        let e = parse_stl(text.as_bytes(), p).unwrap_err().to_string();
        assert!(e.contains("`nan`") && e.contains("finite number"), "{e}");
    }

    #[test]
    fn binary_and_ascii_are_told_apart_by_content_not_by_the_word_solid() {
        let p = Path::new("x.stl");
        // Binary, header starting with "solid" (and with white space before it).
        for header in [b"solid part".as_slice(), b"  SOLID x"] {
            let m = parse_stl(&binary(header, 4, b""), p).unwrap();
            assert!(closed_tetrahedron(&m), "{header:?}");
        }
        // ASCII starting with "SOLID".
        let text = ascii(LOWER, "normal 0 0 1").replacen("solid", "SOLID", 1);
        assert!(closed_tetrahedron(&parse_stl(text.as_bytes(), p).unwrap()));
    }

    #[test]
    fn binary_counts_that_disagree_with_the_size() {
        let p = Path::new("x.stl");
        // Count 0 in a file of exactly four records: a streaming exporter's.
        assert!(closed_tetrahedron(
            &parse_stl(&binary(b"", 0, b""), p).unwrap()
        ));
        // Padding after the stated records, with or without "solid" in the header.
        for header in [b"".as_slice(), b"solid part"] {
            for extra in [&[0u8; 2][..], &[0u8; 50], &[0x1a]] {
                let m = parse_stl(&binary(header, 4, extra), p).unwrap();
                assert!(closed_tetrahedron(&m), "{header:?} + {} bytes", extra.len());
            }
        }
        // A count larger than the data: an error with the count and the sizes, also when the
        // header starts with "solid" (no word about UTF-8).
        for header in [b"".as_slice(), b"solid part"] {
            let e = parse_stl(&binary(header, 5, b""), p)
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("284 bytes")
                    && e.contains("claims 5 triangles")
                    && e.contains("334 bytes")
                    && !e.contains("UTF-8"),
                "{e}"
            );
        }
        let e = parse_stl(&binary(b"solid part", 5, b""), p)
            .unwrap_err()
            .to_string();
        assert!(e.contains(r"is not text (byte 10 is \u{0})"), "{e}");
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
