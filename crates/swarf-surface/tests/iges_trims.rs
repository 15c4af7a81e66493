//! IGES trims: 144 / 142 read into `Patch::trim` through the parameter-space curves, checked
//! against the file's own model-space curves on a real file, and on files built in code.

mod common;
use common::data;

use common::iges::{circle126, plate_with, polygon, Iges, PLATE};

use swarf_geom::math::Vec3;
use swarf_surface::io::{iges, ReadError};
use swarf_surface::{Coverage, ParametricSurface, ReadNote, UnhonouredTrim};

/// The OCCT example (third-party data), or `None` when the test skips.
fn example() -> Option<String> {
    Some(std::fs::read_to_string(data("iges/occt_bug29356.igs")?).unwrap())
}

/// Point of an IGES 126 curve at `t` by the Cox–de Boor recursion (independent of the reader).
fn curve_point(c: &iges::IgesCurve, t: f64) -> Vec3 {
    let (m, k) = (c.degree, &c.knots);
    let n = c.points.len();
    let t = t.clamp(k[m], k[n]);
    // Degree-0 basis: the half-open span holding t, the last non-empty one at the end.
    let last = (m..n).rev().find(|&i| k[i] < k[i + 1]).unwrap();
    let mut b: Vec<f64> = (0..k.len() - 1)
        .map(|i| {
            let inside = k[i] <= t && t < k[i + 1];
            f64::from(u8::from(inside || (i == last && t == k[n])))
        })
        .collect();
    for d in 1..=m {
        b = (0..k.len() - 1 - d)
            .map(|i| {
                let l = if k[i + d] > k[i] {
                    (t - k[i]) / (k[i + d] - k[i]) * b[i]
                } else {
                    0.0
                };
                let r = if k[i + d + 1] > k[i + 1] {
                    (k[i + d + 1] - t) / (k[i + d + 1] - k[i + 1]) * b[i + 1]
                } else {
                    0.0
                };
                l + r
            })
            .collect();
    }
    let (mut num, mut den) = (Vec3::ZERO, 0.0);
    for ((p, w), b) in c.points.iter().zip(&c.weights).zip(&b) {
        num += *p * (b * w);
        den += b * w;
    }
    num / den
}

fn segment_distance(p: Vec3, a: Vec3, b: Vec3) -> f64 {
    let d = b - a;
    let s = if d.length_squared() > 0.0 {
        ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + d * s)).length()
}

#[test]
fn occt_trim_maps_onto_the_model_space_boundary() {
    let Some(example) = example() else {
        return;
    };
    let doc = iges::parse_document(&example).unwrap();
    let s = &doc.surface;
    assert_eq!(s.patches.len(), 1, "the trimmed 128 is one patch, not two");
    let p = &s.patches[0];
    let d = p.surface.domain();
    println!("knot ranges: u {:?}, v {:?}", d.u, d.v);
    assert_eq!(d.u, [1.437351814e6, 1.437358332e6]);
    assert_eq!(d.v, [0.0, 13.06506657]);
    let trim = p.trim.as_ref().expect("the 144 is honoured");
    let notes: Vec<String> = s.notes.iter().map(ToString::to_string).collect();
    println!("notes: {notes:?}");
    let Some(ReadNote::Trimmed {
        patch: 0,
        by,
        loops: 1,
        points,
    }) = s
        .notes
        .iter()
        .find(|n| matches!(n, ReadNote::Trimmed { .. }))
    else {
        panic!("{notes:?}")
    };
    assert_eq!(by, "IGES 144 at D1");
    assert!(!s
        .notes
        .iter()
        .any(|n| matches!(n, ReadNote::TrimNotHonoured { .. })));
    let lp = trim.outer().expect("PTO gives the outer loop");
    assert_eq!(*points, lp.len());
    println!("loop points: {}", lp.len());
    // The loop lies in the parameter box. The file writes u to 10 significant digits (steps of
    // 0.001 at u ≈ 1.4e6), so the curves reach the box's edges to within half that.
    let diag = (d.u[1] - d.u[0]).hypot(d.v[1] - d.v[0]);
    let (mut out_u, mut out_v) = (0.0f64, 0.0f64);
    for q in lp {
        out_u = out_u.max(d.u[0] - q[0]).max(q[0] - d.u[1]);
        out_v = out_v.max(d.v[0] - q[1]).max(q[1] - d.v[1]);
    }
    println!("loop beyond the box: u {out_u:e}, v {out_v:e}");
    assert!(out_u <= 5e-4 && out_v <= 1e-6 * diag, "{out_u} {out_v}");

    // The model-space curve of the 142 at D5 (CPTR): the composite 102 at D25 of the 126s at
    // D27, D29, …, D41, as a dense polyline in mm.
    let mut model = Vec::new();
    for de in (27..=41).step_by(2) {
        let c = doc.curves.iter().find(|c| c.de == de).unwrap();
        let spline = c.spline().unwrap();
        let n = 4000;
        for i in 0..=n {
            let t = c.range[0] + (c.range[1] - c.range[0]) * i as f64 / n as f64;
            let q = curve_point(c, t);
            // The readers' de Boor evaluator agrees with the independent recursion.
            assert!((spline.point(t) - q).length() <= 1e-9 * (1.0 + q.length()));
            model.push(q);
        }
    }
    // S(loop) on the model-space curve. The tolerance: a u rounding of 5e-4 (10 significant
    // digits) moves S by |S_u| · 5e-4 ≈ 0.7 · 5e-4 mm; the chord tolerance 1e-6 · diag (in
    // parameters) by less than 1e-5 mm; the dense polyline's own chords are below 1e-7 mm off
    // the curve. Both curves are the CAD system's fits of one intersection, which agree to its
    // fitting tolerance; 1e-3 mm bounds all of it.
    let su = p
        .surface
        .derivs(0.5 * (d.u[0] + d.u[1]), 0.5 * (d.v[0] + d.v[1]))
        .su;
    println!("|S_u| at the middle: {} mm per unit u", su.length());
    let mut worst = 0.0f64;
    for q in lp {
        let x = p.surface.point(q[0], q[1]);
        let dist = model
            .windows(2)
            .map(|w| segment_distance(x, w[0], w[1]))
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(dist);
    }
    println!("max distance S(loop) to the model-space curve: {worst:e} mm");
    assert!(worst < 1e-3, "{worst}");
    // And the other way: the loop follows the whole model-space curve (S along each loop edge,
    // the edge cut in 16, against every 8th point of the model polyline).
    let image: Vec<Vec3> = (0..lp.len())
        .flat_map(|i| {
            let (a, b) = (lp[i], lp[(i + 1) % lp.len()]);
            (0..16).map(move |k| {
                let s = k as f64 / 16.0;
                [a[0] + (b[0] - a[0]) * s, a[1] + (b[1] - a[1]) * s]
            })
        })
        .map(|q| p.surface.point(q[0], q[1]))
        .collect();
    let mut back = 0.0f64;
    for &x in model.iter().step_by(8) {
        let dist = (0..image.len())
            .map(|i| segment_distance(x, image[i], image[(i + 1) % image.len()]))
            .fold(f64::INFINITY, f64::min);
        back = back.max(dist);
    }
    println!("max distance model-space curve to S(loop): {back:e} mm");
    assert!(back < 1e-3, "{back}");
    // Some of the patch is cut away, some is kept.
    let n = 101;
    let mut inside = 0;
    for i in 0..n {
        for j in 0..n {
            let u = d.u_at(i as f64 / (n - 1) as f64);
            let v = d.v_at(j as f64 / (n - 1) as f64);
            inside += usize::from(trim.contains(u, v));
        }
    }
    let fraction = inside as f64 / (n * n) as f64;
    println!("inside fraction of the {n}x{n} grid: {fraction}");
    assert!(fraction > 0.0 && fraction < 1.0);
    assert_eq!(
        trim.coverage([d.u[0], d.u[1], d.v[0], d.v[1]]),
        Coverage::Crossing
    );
}

/// The plate with three holes: the square `[0.4, 0.6]²` (a 102 of 110s), the disc of radius
/// 0.1 around (0.2, 0.2) (a 126) and around (0.8, 0.8) (a 100 about the origin moved by a 124).
/// A second 144 on the same 128 keeps only `[0.1, 0.9]²` (its outer boundary, a 102).
fn holed_plate(units: &str) -> String {
    let mut f = Iges::default();
    let plate = f.add(128, PLATE);
    let square = polygon(&mut f, &[[0.4, 0.4], [0.6, 0.4], [0.6, 0.6], [0.4, 0.6]]);
    let disc = circle126(&mut f, [0.2, 0.2], 0.1);
    let shift = f.add(124, "1.,0.,0.,0.8,0.,1.,0.,0.8,0.,0.,1.,0.");
    let arc = f.add_moved(100, "0.,0.,0.,0.1,0.,0.1,0.", shift);
    let c1 = f.add(142, &format!("0,{plate},{square},0,1"));
    let c2 = f.add(142, &format!("0,{plate},{disc},0,1"));
    let c3 = f.add(142, &format!("0,{plate},{arc},0,1"));
    f.add(144, &format!("{plate},0,3,0,{c1},{c2},{c3}"));
    let frame = polygon(&mut f, &[[0.1, 0.1], [0.9, 0.1], [0.9, 0.9], [0.1, 0.9]]);
    let c4 = f.add(142, &format!("0,{plate},{frame},0,1"));
    f.add(144, &format!("{plate},1,0,{c4}"));
    f.text(units)
}

#[test]
fn built_plate_with_holes_from_lines_a_spline_and_a_moved_arc() {
    for (units, scale) in [("2,2HMM", 1.0), ("1,2HIN", 25.4)] {
        let text = holed_plate(units);
        let s = iges::parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
        let notes: Vec<String> = s.notes.iter().map(ToString::to_string).collect();
        assert_eq!(s.patches.len(), 2, "{notes:?}");
        // Lengths are scaled; parameters are not.
        assert_eq!(
            s.patches[0].surface.point(1.0, 1.0),
            Vec3::new(10.0, 10.0, 0.0) * scale
        );
        let t = s.patches[0].trim.as_ref().unwrap();
        assert!(t.outer().is_none());
        assert_eq!(t.holes().len(), 3);
        for (u, v, on) in [
            (0.05, 0.05, true),
            (0.5, 0.5, false),
            (0.39, 0.5, true),
            (0.41, 0.5, false),
            (0.59, 0.59, false),
            (0.2, 0.2, false),
            (0.2, 0.295, false),
            (0.2, 0.305, true),
            (0.8, 0.8, false),
            (0.8, 0.705, false),
            (0.8, 0.695, true),
            (0.732, 0.732, false),
            (0.725, 0.725, true),
            (0.95, 0.5, true),
        ] {
            assert_eq!(t.contains(u, v), on, "({u}, {v}) {units}");
        }
        // The circles are sampled within 1e-6 · √2 of the true ones.
        for q in &t.holes()[1] {
            let r = (q[0] - 0.2).hypot(q[1] - 0.2);
            assert!((r - 0.1).abs() < 1e-12, "{r}");
        }
        for q in &t.holes()[2] {
            let r = (q[0] - 0.8).hypot(q[1] - 0.8);
            assert!((r - 0.1).abs() < 1e-12, "{r}");
        }
        // The second 144 trims a copy of the patch: the same surface, its parameter box cut
        // down to its outer boundary's `[0.1, 0.9]²` (the first keeps the whole box: no outer
        // boundary).
        let t2 = s.patches[1].trim.as_ref().unwrap();
        let (d0, d1) = (s.patches[0].surface.domain(), s.patches[1].surface.domain());
        assert_eq!((d0.u, d0.v), ([0.0, 1.0], [0.0, 1.0]));
        assert_eq!((d1.u, d1.v), ([0.1, 0.9], [0.1, 0.9]));
        for (u, v) in [(0.1, 0.1), (0.37, 0.81), (0.9, 0.5)] {
            let (a, b) = (
                s.patches[0].surface.point(u, v),
                s.patches[1].surface.point(u, v),
            );
            assert!(a.distance(b) < 1e-12 * scale, "({u}, {v}): {a} against {b}");
        }
        assert!(t2.contains(0.5, 0.5) && !t2.contains(0.05, 0.5) && !t2.contains(0.95, 0.95));
        let trimmed: Vec<_> = s
            .notes
            .iter()
            .filter_map(|n| match n {
                ReadNote::Trimmed {
                    patch,
                    loops,
                    points,
                    ..
                } => Some((*patch, *loops, *points)),
                _ => None,
            })
            .collect();
        assert_eq!(trimmed.len(), 2, "{notes:?}");
        assert_eq!((trimmed[0].0, trimmed[0].1), (0, 3));
        assert_eq!(trimmed[1], (1, 1, 4));
        println!("{notes:?}");
    }
}

#[test]
fn trims_that_cannot_be_honoured_leave_the_patch_whole_with_the_reason() {
    // Neither a parameter-space curve (BPTR = 0) nor a model-space one (CPTR = 0).
    let text = plate_with(|f, plate| f.add(142, &format!("0,{plate},0,0,2")));
    let s = iges::parse(&text).unwrap();
    assert!(s.patches[0].trim.is_none());
    let notes: Vec<String> = s.notes.iter().map(ToString::to_string).collect();
    assert_eq!(
        notes,
        ["patch 0 is trimmed by IGES 144 at D5 (142 at D3 has neither a parameter-space nor a model-space curve); the trim is not honoured (the whole patch is used)"],
    );
    // Only a model-space curve, of a type the reader does not evaluate (a 104 conic).
    let text = plate_with(|f, plate| {
        let conic = f.add(104, "1.,0.,1.,0.,0.,-1.,0.,1.,0.,1.,0.");
        f.add(142, &format!("0,{plate},0,{conic},2"))
    });
    let s = iges::parse(&text).unwrap();
    assert!(s.patches[0].trim.is_none());
    assert!(
        matches!(&s.notes[0], ReadNote::TrimNotHonoured { patch: 0, by } if by.to_string().contains("142 at D5: its model-space curve D3 is an entity 104, which is not supported")),
        "{:?}",
        s.notes
    );
    // A parameter-space curve of a type the reader does not evaluate (a 104 conic).
    let text = plate_with(|f, plate| {
        let conic = f.add(104, "1.,0.,1.,0.,0.,-0.01,0.,0.1,0.,0.1,0.");
        f.add(142, &format!("0,{plate},{conic},0,1"))
    });
    let s = iges::parse(&text).unwrap();
    assert!(s.patches[0].trim.is_none());
    assert!(
        matches!(&s.notes[0], ReadNote::TrimNotHonoured { patch: 0, by } if by.to_string().contains("D3 is an entity 104, which is not supported")),
        "{:?}",
        s.notes
    );
}

#[test]
fn a_loop_outside_the_parameter_box_is_not_honoured() {
    let text = plate_with(|f, plate| {
        let l = polygon(f, &[[0.4, 0.4], [1.5, 0.4], [0.4, 0.6]]);
        f.add(142, &format!("0,{plate},{l},0,1"))
    });
    let s = iges::parse(&text).unwrap();
    assert!(s.patches[0].trim.is_none());
    assert!(
        matches!(&s.notes[0], ReadNote::TrimNotHonoured { by: by @ UnhonouredTrim::Iges144 { .. }, .. } if by.to_string().contains("reaches (1.5, 0.4), outside the patch's parameter box")),
        "{:?}",
        s.notes
    );
}

fn syntax_error(text: &str) -> (usize, usize, String) {
    match iges::parse(text).unwrap_err() {
        ReadError::Syntax {
            line,
            column,
            message,
            ..
        } => (line, column, message),
        e => panic!("{e}"),
    }
}

/// Line of the first P record of the entity at `de` in `text`.
fn p_line(text: &str, de: usize) -> usize {
    text.lines()
        .position(|l| l.as_bytes()[72] == b'P' && l[64..72].trim() == de.to_string())
        .unwrap()
        + 1
}

#[test]
fn broken_trim_references_are_errors_at_the_pointer() {
    // The 144's inner boundary names no directory entry.
    let mut f = Iges::default();
    let plate = f.add(128, PLATE);
    f.add(144, &format!("{plate},0,1,0,99"));
    let text = f.text("2,2HMM");
    let (line, column, message) = syntax_error(&text);
    assert_eq!(line, p_line(&text, 3));
    assert!(column > 1, "{column}");
    assert_eq!(
        message,
        "inner boundary PTI points at D99, which is not a directory entry"
    );
    let e = iges::parse(&text).unwrap_err().to_string();
    assert!(
        e.starts_with(&format!("IGES line {line}, column {column}: ")),
        "{e}"
    );
    // The 144's surface names no entry (was: the trim dropped and the surface read whole),
    // or an entry that is no surface.
    for (pts, want) in [
        (
            "99",
            "surface PTS points at D99, which is not a directory entry",
        ),
        (
            "0",
            "surface PTS points at D0, which is not a directory entry",
        ),
        (
            "3",
            "surface PTS points at D3, an entity 110; expected a surface (128, 108, 118, 120, 122 or 190)",
        ),
    ] {
        let mut f = Iges::default();
        f.add(128, PLATE);
        f.add(110, "0.2,0.2,0.,0.4,0.4,0."); // D3
        let hole = polygon(&mut f, &[[0.2, 0.2], [0.8, 0.2], [0.5, 0.8]]);
        let c = f.add(142, &format!("0,1,{hole},0,1"));
        let t = f.add(144, &format!("{pts},0,1,0,{c}"));
        let text = f.text("2,2HMM");
        let (l, column, message) = syntax_error(&text);
        assert_eq!((l, message.as_str()), (p_line(&text, t), want));
        assert!(column > 1, "{column}");
    }
    // A 144 on a surface kind not read is skipped with it, not an error.
    let mut f = Iges::default();
    f.add(128, PLATE);
    let sphere = f.add(196, "0,5.,0");
    f.add(144, &format!("{sphere},0,0,0"));
    let s = iges::parse(&f.text("2,2HMM")).unwrap();
    assert_eq!(s.patches.len(), 1);
    assert!(s
        .notes
        .iter()
        .any(|n| matches!(n, ReadNote::UnsupportedSurface { kind, .. } if kind == "IGES 196")));
    // The 144's boundary is not a 142.
    let mut f = Iges::default();
    let plate = f.add(128, PLATE);
    f.add(144, &format!("{plate},0,1,0,{plate}"));
    let (_, _, message) = syntax_error(&f.text("2,2HMM"));
    assert!(
        message.contains("D1, an entity 128; expected a 142"),
        "{message}"
    );
    // The 142's parameter-space curve names no entry.
    let text = plate_with(|f, plate| f.add(142, &format!("0,{plate},41,0,1")));
    let (line, _, message) = syntax_error(&text);
    assert_eq!(line, p_line(&text, 3));
    assert_eq!(
        message,
        "BPTR points at D41, which is not a directory entry"
    );
    // … or a surface.
    let text = plate_with(|f, plate| f.add(142, &format!("0,{plate},{plate},0,1")));
    let (_, _, message) = syntax_error(&text);
    assert!(
        message.contains("BPTR points at D1, an entity 128; expected a curve"),
        "{message}"
    );
    // A composite curve that contains itself: refused, not followed for ever.
    let text = plate_with(|f, plate| {
        f.add(102, "2,3,3");
        f.add(142, &format!("0,{plate},3,0,1"))
    });
    let (_, _, message) = syntax_error(&text);
    assert!(message.contains("nest more than 8 deep"), "{message}");
    // A loop of two points encloses nothing.
    let text = plate_with(|f, plate| {
        let l = f.add(110, "0.2,0.2,0.,0.4,0.4,0.");
        f.add(142, &format!("0,{plate},{l},0,1"))
    });
    let (line, _, message) = syntax_error(&text);
    assert_eq!(
        line,
        text.lines().position(|l| l.ends_with("D0000005")).unwrap() + 1
    );
    assert_eq!(
        message,
        "entity 142 at D5 (a boundary of the 144 at D7): trim loop 0 has 2 point(s); a loop needs at least 3"
    );
}

#[test]
fn directory_entries_out_of_order_are_read_by_their_sequence_numbers() {
    // The same trimmed plate with its D section's entries (pairs of records) listed last
    // first: pointers name entries by sequence number, so the 144 still trims the 128 (it
    // was read as pointing at itself, and once PTS was checked, as an error).
    let text = plate_with(|f, plate| {
        let hole = polygon(f, &[[0.2, 0.2], [0.8, 0.2], [0.5, 0.8]]);
        f.add(142, &format!("0,{plate},{hole},0,1"))
    });
    let lines: Vec<&str> = text.lines().collect();
    let d: Vec<usize> = (0..lines.len())
        .filter(|&i| &lines[i][72..73] == "D")
        .collect();
    let pairs: Vec<[&str; 2]> = d.chunks(2).map(|c| [lines[c[0]], lines[c[1]]]).collect();
    let mut reversed: Vec<&str> = lines[..d[0]].to_vec();
    reversed.extend(pairs.iter().rev().flatten());
    reversed.extend(&lines[d[d.len() - 1] + 1..]);
    let reversed = reversed.join("\n") + "\n";
    assert_ne!(reversed, text);
    let (a, b) = (iges::parse(&text).unwrap(), iges::parse(&reversed).unwrap());
    assert_eq!(a.patches, b.patches);
    assert!(b.patches[0].trim.is_some());
    assert!(b
        .notes
        .iter()
        .any(|n| matches!(n, ReadNote::Trimmed { patch: 0, .. })));
}
