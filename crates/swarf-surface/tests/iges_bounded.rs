//! IGES surfaces bounded otherwise than by a 144: a 143 bounded surface with 141 boundaries
//! (parameter-space curves, model-space curves, curves in reverse), a 144 placed by its own
//! 124, the faces of a manifold solid B-rep (510), a 108 plane and subfigure instances (408)
//! — each either honoured or said in a note, never dropped silently.

mod common;

use common::iges::{polygon, Iges, PLATE};

use swarf_surface::io::iges;
use swarf_surface::{ParametricSurface, ReadNote, UnhonouredTrim};

/// The plate bounded by a 143 whose boundaries are built by `bounds` (given the plate's DE;
/// returns the 141s' DEs).
fn bounded(bounds: impl FnOnce(&mut Iges, usize) -> Vec<usize>) -> String {
    let mut f = Iges::default();
    let plate = f.add(128, PLATE);
    let b = bounds(&mut f, plate);
    let list: Vec<String> = b.iter().map(ToString::to_string).collect();
    f.add(143, &format!("1,{plate},{},{}", b.len(), list.join(",")));
    f.text("2,2HMM")
}

/// A 141 of one curve: model-space `c` (0 for none), SENSE `sense`, parameter-space `p` (0 for
/// none).
fn boundary(f: &mut Iges, plate: usize, c: usize, sense: u32, p: usize) -> usize {
    let (kind, k) = if p == 0 { (0, 0) } else { (1, 1) };
    let ps = if p == 0 {
        String::new()
    } else {
        format!(",{p}")
    };
    f.add(141, &format!("{kind},1,{plate},1,{c},{sense},{k}{ps}"))
}

#[test]
fn a_143_bounds_its_surface_by_its_141s() {
    // The plate (10 mm over [0, 1]²) without its outer frame: the square [0.2, 0.8]² with a
    // square hole [0.4, 0.6]², the hole listed first (the largest loop is the outer one).
    let text = bounded(|f, plate| {
        let hole = polygon(f, &[[0.4, 0.4], [0.6, 0.4], [0.6, 0.6], [0.4, 0.6]]);
        let outer = polygon(f, &[[0.2, 0.2], [0.8, 0.2], [0.8, 0.8], [0.2, 0.8]]);
        vec![
            boundary(f, plate, 0, 1, hole),
            boundary(f, plate, 0, 1, outer),
        ]
    });
    let s = iges::parse(&text).unwrap();
    assert_eq!(s.patches.len(), 1);
    let trim = s.patches[0].trim.as_ref().expect("the 143 is honoured");
    for (u, v, inside) in [
        (0.3, 0.3, true),
        (0.7, 0.5, true),
        (0.5, 0.5, false),
        (0.1, 0.5, false),
        (0.9, 0.9, false),
    ] {
        assert_eq!(trim.contains(u, v), inside, "({u}, {v})");
    }
    let notes: Vec<String> = s.notes.iter().map(ToString::to_string).collect();
    assert_eq!(notes.len(), 1, "{notes:?}");
    assert!(notes[0].contains("IGES 143 at D"), "{notes:?}");
}

#[test]
fn a_141_from_model_space_curves_written_in_reverse() {
    // Model space only (TYPE 0): the square [4, 6]² mm on the plate (z = 0), its four sides as
    // separate curves, two of them written backwards (SENSE 2).
    let text = bounded(|f, plate| {
        let side = |f: &mut Iges, a: [f64; 2], b: [f64; 2]| {
            f.add(110, &format!("{},{},0.,{},{},0.", a[0], a[1], b[0], b[1]))
        };
        let s1 = side(f, [4.0, 4.0], [6.0, 4.0]);
        let s2 = side(f, [6.0, 6.0], [6.0, 4.0]); // reversed
        let s3 = side(f, [6.0, 6.0], [4.0, 6.0]);
        let s4 = side(f, [4.0, 4.0], [4.0, 6.0]); // reversed
        let b = f.add(
            141,
            &format!("0,1,{plate},4,{s1},1,0,{s2},2,0,{s3},1,0,{s4},2,0"),
        );
        vec![b]
    });
    let s = iges::parse(&text).unwrap();
    let p = &s.patches[0];
    let trim = p.trim.as_ref().expect("the 143 is honoured");
    assert!(trim.contains(0.5, 0.5));
    assert!(!trim.contains(0.3, 0.5));
    assert!(!trim.contains(0.5, 0.65));
    // Its corners map to the parameters of the square's corners.
    let (lo, hi) = trim.loops()[0]
        .iter()
        .fold(([1.0f64; 2], [0.0f64; 2]), |(lo, hi), q| {
            (
                [lo[0].min(q[0]), lo[1].min(q[1])],
                [hi[0].max(q[0]), hi[1].max(q[1])],
            )
        });
    for (a, b) in lo.iter().chain(&hi).zip([0.4, 0.4, 0.6, 0.6]) {
        assert!((a - b).abs() < 1e-6, "{lo:?} {hi:?}");
    }
    assert!(
        s.notes[0]
            .to_string()
            .contains("the loop of the 141 at D11 mapped from its model-space curve"),
        "{:?}",
        s.notes
    );
    // Without the reversal, the sides do not join into a loop: the trim is not honoured,
    // and the note names the 141.
    let text = text.replace(",2,0,", ",1,0,");
    let s = iges::parse(&text).unwrap_or_else(|e| panic!("{e}"));
    if s.patches[0].trim.is_none() {
        assert!(
            matches!(
                &s.notes[0],
                ReadNote::TrimNotHonoured {
                    by: UnhonouredTrim::Iges { kind: 143, .. },
                    ..
                }
            ),
            "{:?}",
            s.notes
        );
    }
}

#[test]
fn a_144_is_placed_by_its_own_transformation() {
    let mut f = Iges::default();
    let plate = f.add(128, PLATE);
    let hole = polygon(&mut f, &[[0.4, 0.4], [0.6, 0.4], [0.6, 0.6], [0.4, 0.6]]);
    let c = f.add(142, &format!("0,{plate},{hole},0,1"));
    let m = f.add(124, "1.,0.,0.,100.,0.,1.,0.,0.,0.,0.,1.,5.");
    f.add_moved(144, &format!("{plate},1,0,{c}"), m);
    let s = iges::parse(&f.text("2,2HMM")).unwrap();
    let p = &s.patches[0];
    assert!(p.trim.is_some());
    // The plate's point (u, v) = (0.5, 0.5) is at (5, 5, 0) as defined, (105, 5, 5) placed.
    let q = p.surface.point(0.5, 0.5);
    assert!(
        (q - swarf_geom::math::Vec3::new(105.0, 5.0, 5.0)).length() < 1e-12,
        "{q:?}"
    );
}

#[test]
fn solid_faces_planes_and_subfigures_are_said() {
    // A 510 face on the plate: its loops are not read, the whole plate stands, with a note.
    let mut f = Iges::default();
    let plate = f.add(128, PLATE);
    f.add(510, &format!("{plate},1,1,0"));
    let s = iges::parse(&f.text("2,2HMM")).unwrap();
    assert!(
        matches!(
            &s.notes[..],
            [ReadNote::TrimNotHonoured {
                patch: 0,
                by: UnhonouredTrim::Iges { kind: 510, .. }
            }]
        ),
        "{:?}",
        s.notes
    );
    // A 108 plane beside it: read as the plane x = 50 over the default box, said.
    let mut f = Iges::default();
    f.add(128, PLATE);
    f.add(108, "1.,0.,0.,50.,0,0.,0.,0.,0.");
    let s = iges::parse(&f.text("2,2HMM")).unwrap();
    assert!(
        matches!(
            &s.notes[..],
            [ReadNote::DefaultParameterBox { patch: 1, .. }]
        ),
        "{:?}",
        s.notes
    );
    assert!((s.patches[1].surface.point(3.0, -7.0).x - 50.0).abs() < 1e-12);
    // A surface kind still not read (114, parametric spline surface): skipped, said (so a gouge
    // check is not certified).
    let mut f = Iges::default();
    f.add(128, PLATE);
    f.add(114, "1,1,1,1");
    let s = iges::parse(&f.text("2,2HMM")).unwrap();
    assert!(
        matches!(&s.notes[..], [ReadNote::UnsupportedSurface { kind, .. }] if kind == "IGES 114"),
        "{:?}",
        s.notes
    );
    // Subfigure instances: not applied, said.
    let mut f = Iges::default();
    let plate = f.add(128, PLATE);
    let def = f.add(308, &format!("0,3HSUB,1,{plate}"));
    f.add(408, &format!("{def},100.,0.,0.,1."));
    let s = iges::parse(&f.text("2,2HMM")).unwrap();
    assert!(
        matches!(&s.notes[..], [ReadNote::PlacementNotApplied { entity, .. }] if entity.starts_with("IGES 408")),
        "{:?}",
        s.notes
    );
}

#[test]
fn records_without_line_ends_or_with_lone_carriage_returns() {
    let mut f = Iges::default();
    let plate = f.add(128, PLATE);
    let hole = polygon(&mut f, &[[0.4, 0.4], [0.6, 0.4], [0.6, 0.6], [0.4, 0.6]]);
    let c = f.add(142, &format!("0,{plate},{hole},0,1"));
    f.add(144, &format!("{plate},1,0,{c}"));
    let text = f.text("2,2HMM");
    let want = iges::parse(&text).unwrap();
    assert!(want.patches[0].trim.is_some());
    let records: Vec<&str> = text.lines().collect();
    assert!(records.iter().all(|r| r.len() == 80));
    for joined in [records.concat(), records.join("\r")] {
        let got = iges::parse(&joined).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(got.patches.len(), 1);
        assert_eq!(got.patches[0].trim, want.patches[0].trim);
    }
}

#[test]
fn a_second_144_that_fails_keeps_its_own_placed_face() {
    // One plate, two placed 144s: A (+100 in x) trims it by a square; B (+100 in y) has a 142
    // with no curve at all, so its face is the whole plate — at its own place, while A's
    // trimmed face stays where A put it.
    let mut f = Iges::default();
    let plate = f.add(128, PLATE);
    let square = polygon(&mut f, &[[0.4, 0.4], [0.6, 0.4], [0.6, 0.6], [0.4, 0.6]]);
    let good = f.add(142, &format!("0,{plate},{square},0,1"));
    let bad = f.add(142, &format!("0,{plate},0,0,2"));
    let ma = f.add(124, "1.,0.,0.,100.,0.,1.,0.,0.,0.,0.,1.,0.");
    let mb = f.add(124, "1.,0.,0.,0.,0.,1.,0.,100.,0.,0.,1.,0.");
    f.add_moved(144, &format!("{plate},1,0,{good}"), ma);
    f.add_moved(144, &format!("{plate},1,0,{bad}"), mb);
    let s = iges::parse(&f.text("2,2HMM")).unwrap();
    assert_eq!(s.patches.len(), 2);
    let at = |i: usize| s.patches[i].surface.point(0.5, 0.5);
    assert!((at(0) - swarf_geom::math::Vec3::new(105.0, 5.0, 0.0)).length() < 1e-12);
    assert!(s.patches[0].trim.is_some());
    assert!((at(1) - swarf_geom::math::Vec3::new(5.0, 105.0, 0.0)).length() < 1e-12);
    assert!(s.patches[1].trim.is_none());
    assert!(
        matches!(
            &s.notes[..],
            [
                ReadNote::Trimmed { patch: 0, .. },
                ReadNote::TrimNotHonoured { patch: 1, .. }
            ]
        ),
        "{:?}",
        s.notes
    );
}
