//! IGES reader: the shared trimmed 128 example, units, transforms and malformed input.

mod common;
use common::data;
use common::iges::{Iges, PLATE};

use swarf_surface::io::{iges, Format, ReadError};
use swarf_surface::{EntityRef, ParametricSurface, ReadNote, Surface, Tolerances};

const TOL: Tolerances = Tolerances::DEFAULT;

/// The OCCT example (third-party data), or `None` when the test skips.
fn example() -> Option<String> {
    Some(std::fs::read_to_string(data("iges/occt_bug29356.igs")?).unwrap())
}

#[test]
fn occt_example_is_one_degree_5x5_patch_on_a_6x6_net_finite_everywhere() {
    let Some(example) = example() else {
        return;
    };
    let doc = iges::parse_document(&example).unwrap();
    let s = &doc.surface;
    assert_eq!(s.patches.len(), 1);
    let p = &s.patches[0];
    assert_eq!(
        p.source.entity,
        EntityRef::Iges {
            de: 3,
            entity_type: 128
        }
    );
    let Surface::Nurbs(n) = &p.surface else {
        panic!()
    };
    assert_eq!((n.degree_u(), n.degree_v()), (5, 5));
    assert_eq!(n.net_size(), (6, 6));
    assert!(!n.is_rational());
    // Control point (0,0) and (1,0) as listed (u runs fastest in IGES).
    assert_eq!(
        n.control_point(0, 0).to_array(),
        [-481.5300241, 394.2815039, -67.99341879]
    );
    assert_eq!(
        n.control_point(1, 0).to_array(),
        [-482.351216, 394.2668485, -67.57032814]
    );
    assert_eq!(
        n.control_point(0, 1).to_array(),
        [-482.1593728, 393.3425867, -69.15092165]
    );
    let d = n.domain();
    assert_eq!(d.u, [1.437351814e6, 1.437358332e6]);
    assert_eq!(d.v, [0.0, 13.06506657]);
    let bb = s.bounding_box().unwrap().inflated(1e-9);
    for cc in s.grid(41) {
        let g = s.local(&cc, &TOL);
        assert!(g.point().is_finite() && bb.contains(g.point()));
        let nrm = g.normal.vector().expect("regular patch");
        assert!(nrm.is_finite() && (nrm.length() - 1.0).abs() < 1e-12);
        let c = g.curvature.unwrap();
        assert!(c.k1.is_finite() && c.k2.is_finite() && c.k1 >= c.k2);
    }
    // The corners interpolate the corner control points (clamped knots).
    assert!((p.surface.point(d.u[0], d.v[0]) - n.control_point(0, 0)).length() < 1e-9);
    assert!((p.surface.point(d.u[1], d.v[1]) - n.control_point(5, 5)).length() < 1e-9);
    // Trims: one 144 whose outer boundary is the 142 at D5; honoured (see iges_trims.rs).
    assert_eq!(doc.trims.len(), 1);
    assert_eq!(doc.trims[0].patch, Some(0));
    assert_eq!(doc.trims[0].outer, Some(5));
    assert!(doc.trims[0].inner.is_empty());
    assert!(s
        .notes
        .iter()
        .any(|n| matches!(n, ReadNote::Trimmed { patch: 0, .. })));
    assert!(p.trim.is_some());
    assert_eq!(doc.curves.len(), 15);
    assert!(doc
        .curves
        .iter()
        .all(|c| c.points.len() + c.degree + 1 == c.knots.len()));
}

/// Replace the record with sequence `seq` of section `sec`, columns 1–72, by `data`.
fn patch_record(text: &str, sec: char, seq: usize, data: &str) -> String {
    let tag = format!("{sec}{seq:07}");
    text.lines()
        .map(|l| {
            if l.len() >= 80 && l[72..80] == tag {
                format!("{:<72}{}", data, &l[72..])
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn units_flag_converts_to_millimetres_and_transforms_apply() {
    // Units flag 1 (inch): every coordinate × 25.4. (Records keep their 72 data columns.)
    let Some(t) = example() else {
        return;
    };
    let inch = patch_record(
        &t,
        'G',
        3,
        ",1.,1,2HIN,1,0.01,15H20171129.170415,0.000370156,488.943514,5HBoris,,11,",
    );
    let s = iges::parse(&inch).unwrap();
    let Surface::Nurbs(n) = &s.patches[0].surface else {
        panic!()
    };
    assert!((n.control_point(0, 0).x - (-481.5300241 * 25.4)).abs() < 1e-9);
    assert!(matches!(&s.notes[0], ReadNote::UnitsConverted { factor, .. } if *factor == 25.4));
    // Units flag 3 names the unit.
    let named = patch_record(
        &t,
        'G',
        3,
        ",1.,3,2HCM,1,0.01,15H20171129.170415,0.000370156,488.943514,5HBoris,,11,",
    );
    let s = iges::parse(&named).unwrap();
    let Surface::Nurbs(n) = &s.patches[0].surface else {
        panic!()
    };
    assert!((n.control_point(0, 0).x - (-4815.300241)).abs() < 1e-9);
    // A 124 transformation (rotate 90° about z, then shift x by 5) referenced by the 128.
    let mut lines: Vec<String> = t.lines().map(str::to_string).collect();
    let d_end = lines
        .iter()
        .rposition(|l| l.as_bytes().get(72) == Some(&b'D'))
        .unwrap();
    lines.insert(
        d_end + 1,
        format!(
            "{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}D{:07}",
            124, 247, 0, 0, 0, 0, 0, 0, "00010000", 43
        ),
    );
    lines.insert(
        d_end + 2,
        format!(
            "{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}D{:07}",
            124, 0, 0, 1, 0, "", "", "", 0, 44
        ),
    );
    let p_end = lines
        .iter()
        .rposition(|l| l.as_bytes().get(72) == Some(&b'P'))
        .unwrap();
    lines.insert(
        p_end + 1,
        format!(
            "{:<64} {:>7}P{:07}",
            "124,0.,-1.,0.,5.,1.,0.,0.,0.,0.,0.,1.,0.;", 43, 247
        ),
    );
    let moved = patch_record(
        &lines.join("\n"),
        'D',
        3,
        "     128       2       0       0       0       0      43       000010000",
    );
    let s = iges::parse(&moved).unwrap();
    let Surface::Nurbs(m) = &s.patches[0].surface else {
        panic!()
    };
    let (a, b) = (n.control_point(2, 3) / 10.0, m.control_point(2, 3));
    assert!(
        (b - swarf_geom::math::Vec3::new(5.0 - a.y, a.x, a.z)).length() < 1e-9,
        "{a:?} → {b:?}"
    );
}

#[test]
fn malformed_iges_gives_record_positions() {
    let Some(t) = example() else {
        return;
    };
    // A letter where the degree M1 belongs (P record 2, the 128's data).
    let bad = patch_record(
        &t,
        'P',
        2,
        "128,5,5,X,5,0,0,1,0,0,1.437351814E+006,1.437351814E+006,        0000003",
    );
    match iges::parse(&bad).unwrap_err() {
        ReadError::Syntax {
            format: Format::Iges,
            line,
            column,
            message,
        } => {
            assert_eq!((line, column), (49, 9), "{message}");
            assert!(
                message.contains("found `X`, expected an integer (M1)"),
                "{message}"
            );
        }
        e => panic!("{e}"),
    }
    // K1 absurdly large: refused before allocating.
    let bad = patch_record(
        &t,
        'P',
        2,
        "128,999999999,5,5,5,0,0,1,0,0,1.437351814E+006,1.437351814E+006,",
    );
    let e = iges::parse(&bad).unwrap_err().to_string();
    assert!(e.contains("K1 = 999999999 is impossible"), "{e}");
    // A directory entry pointing past the P section.
    let bad = patch_record(
        &t,
        'D',
        3,
        "     128     999       0       0       0       0       0       000010000",
    );
    let e = iges::parse(&bad).unwrap_err().to_string();
    assert!(
        e.starts_with("IGES line 8, column 9: entity 128 at D3: parameter data at P999"),
        "{e}"
    );
    // A short record.
    let e = iges::parse("hello\n").unwrap_err().to_string();
    assert!(e.contains("expected 80 columns"), "{e}");
    // Knots that decrease: the NURBS validation names the entity.
    let bad = patch_record(&t, 'P', 6, "0.E+000,9.0,0.E+000,0.E+000,0.E+000,0.E+000,");
    match iges::parse(&bad).unwrap_err() {
        ReadError::Surface { entity, .. } => assert_eq!(entity, "entity 128 at D3"),
        e => panic!("{e}"),
    }
}

#[test]
fn accents_in_the_start_section_and_global_strings_are_read_by_the_column() {
    // European files carry accents in the Start section and in G-section strings, in
    // Latin-1 (one byte a column) or UTF-8 (records padded to 80 characters, or to 80 bytes).
    // Neither may cost the file; the surface is the one of the ASCII file.
    let mut f = Iges::default();
    f.add(128, PLATE);
    let ascii = f.text("2,2HMM");
    let plain = iges::parse(&ascii).unwrap();
    let start = |name: &[u8], pad: usize| {
        let mut r = name.to_vec();
        r.resize(r.len() + pad, b' ');
        r.extend_from_slice(b"S0000001");
        r
    };
    let latin1 = b"Pi\xe8ce usin\xe9e - soci\xe9t\xe9 Fran\xe7aise";
    let utf8 = "Pièce usinée - société Française".as_bytes();
    let chars = "Pièce usinée - société Française".chars().count();
    for (what, s_record, product) in [
        (
            "Latin-1",
            start(latin1, 72 - latin1.len()),
            b"4Hsw\xe9f".to_vec(),
        ),
        (
            "UTF-8 by characters",
            start(utf8, 72 - chars),
            "4Hswéf".as_bytes().to_vec(),
        ),
        (
            "UTF-8 by bytes",
            start(utf8, 72 - utf8.len()),
            b"4Hsw\xc3\xa9".to_vec(),
        ),
    ] {
        let mut bytes = Vec::new();
        for (k, line) in ascii.lines().enumerate() {
            let line = line.as_bytes();
            if k == 0 {
                bytes.extend_from_slice(&s_record);
            } else if line[72] == b'G' && k == 1 {
                // The product name (field 3), `4Hswrf`, with an accent.
                let at = line.windows(6).position(|w| w == b"4Hswrf").unwrap();
                bytes.extend_from_slice(&line[..at]);
                bytes.extend_from_slice(&product);
                bytes.extend_from_slice(&line[at + 6..]);
            } else {
                bytes.extend_from_slice(line);
            }
            bytes.extend_from_slice(b"\r\n");
        }
        let s = iges::parse_bytes(&bytes).unwrap_or_else(|e| panic!("{what}: {e}"));
        assert_eq!(s.patches.len(), 1, "{what}");
        assert_eq!(s.patches[0].surface, plain.patches[0].surface, "{what}");
        // Through the file reader too (which once decoded the bytes as UTF-8 first).
        let dir = swarf_testdata::scratch_dir("iges-accents");
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("piece.igs");
        std::fs::write(&path, &bytes).unwrap();
        let s = swarf_surface::io::read_file(&path).unwrap_or_else(|e| panic!("{what}: {e}"));
        assert_eq!(s.patches[0].surface, plain.patches[0].surface, "{what}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

#[test]
fn a_broken_global_string_after_the_units_is_no_error() {
    // The last G field's Hollerith count overruns the record delimiter (a count made for
    // another encoding of its text): fields after 15 (the unit name) are not used, so the file
    // is read; a break before them is still an error at its record and column.
    let mut f = Iges::default();
    f.add(128, PLATE);
    let ascii = f.text("1,2HIN");
    let plain = iges::parse(&ascii).unwrap();
    let at = ascii.rfind("15H20240101.000000;").unwrap();
    let broken = format!("{}16H{}", &ascii[..at], &ascii[at + 3..]);
    let s = iges::parse(&broken).unwrap();
    assert_eq!(s.patches[0].surface, plain.patches[0].surface);
    assert!(matches!(&s.notes[0], ReadNote::UnitsConverted { factor, .. } if *factor == 25.4));
    // The unit name's own count overruns: an error at the record and column of the count.
    let broken = f.text("1,999HIN");
    let lines: Vec<&str> = broken.lines().collect();
    let first_g = lines.iter().position(|l| &l[72..73] == "G").unwrap();
    let data: String = lines[first_g..]
        .iter()
        .take_while(|l| &l[72..73] == "G")
        .map(|l| &l[..72])
        .collect();
    let o = data.find("999H").unwrap();
    match iges::parse(&broken).unwrap_err() {
        ReadError::Syntax {
            line,
            column,
            message,
            ..
        } => assert!(
            (line, column) == (first_g + 1 + o / 72, o % 72 + 1) && message.contains("Hollerith"),
            "{line}:{column} {message}"
        ),
        e => panic!("{e}"),
    }
}

#[test]
fn a_128_is_restricted_to_its_parameter_range() {
    // x = 20u, y = 20v − 10, z a parabola in v (5, −5, 5 control heights) over the knots'
    // [0, 1]²; U0, U1, V0, V1 = `range` keeps a part of it.
    let patch = |range: &str| {
        let mut pts = Vec::new();
        for j in 0..3 {
            for i in 0..2 {
                let z = if j == 1 { -5.0 } else { 5.0 };
                pts.push(format!("{}.,{}.,{z}", 20 * i, 10 * j - 10));
            }
        }
        let mut f = Iges::default();
        f.add(
            128,
            &format!(
                "1,2,1,2,0,0,1,0,0,0.,0.,1.,1.,0.,0.,0.,1.,1.,1.,1.,1.,1.,1.,1.,1.,{},{range}",
                pts.join(",")
            ),
        );
        iges::parse(&f.text("2,2HMM"))
    };
    let whole = patch("0.,1.,0.,1.").unwrap();
    let part = patch("0.25,0.75,0.25,0.75").unwrap();
    let (s, p) = (&whole.patches[0].surface, &part.patches[0].surface);
    assert_eq!((s.domain().u, s.domain().v), ([0.0, 1.0], [0.0, 1.0]));
    assert_eq!((p.domain().u, p.domain().v), ([0.25, 0.75], [0.25, 0.75]));
    // The corners of the part, and its extent x 5…15, y −5…5.
    let z = |v: f64| 5.0 * (1.0 - v).powi(2) - 10.0 * v * (1.0 - v) + 5.0 * v * v;
    for (u, v) in [
        (0.25, 0.25),
        (0.75, 0.25),
        (0.25, 0.75),
        (0.75, 0.75),
        (0.5, 0.4),
    ] {
        let want = swarf_geom::math::Vec3::new(20.0 * u, 20.0 * v - 10.0, z(v));
        assert!(
            (p.point(u, v) - want).length() < 1e-12,
            "({u}, {v}): {}",
            p.point(u, v)
        );
        assert!((s.point(u, v) - want).length() < 1e-12);
    }
    let bb = p.bounding_box();
    assert!((bb.min.x - 5.0).abs() < 1e-12 && (bb.max.x - 15.0).abs() < 1e-12);
    assert!((bb.min.y + 5.0).abs() < 1e-12 && (bb.max.y - 5.0).abs() < 1e-12);
    // The grid of CC points covers the part only.
    let grid = part.grid(5);
    let xs: Vec<f64> = grid.iter().map(|cc| p.point(cc.u, cc.v).x).collect();
    assert!(
        xs.iter().all(|x| (5.0 - 1e-9..=15.0 + 1e-9).contains(x)),
        "{xs:?}"
    );
    // A range wider than the knots keeps the knots' domain; one that leaves nothing is an error
    // at its parameter.
    let wide = patch("-1.,2.,0.,1.").unwrap();
    assert_eq!(wide.patches[0].surface.domain().u, [0.0, 1.0]);
    let e = patch("2.,3.,0.,1.").unwrap_err().to_string();
    assert!(
        e.contains("U0, U1 = [2, 3] leaves nothing of the knots' [0, 1]"),
        "{e}"
    );
}
