//! IGES surfaces made of curves and planes — 120 (surface of revolution), 122 (tabulated
//! cylinder), 118 (ruled surface), 190 (plane surface), 108 (plane) — read as exact surfaces,
//! checked against their analytic shapes on files built in code (each was skipped before).

mod common;

use common::iges::{polygon, Iges};
use swarf_geom::math::Vec3;
use swarf_surface::io::iges;
use swarf_surface::{CompoundSurface, ParametricSurface, Patch, ReadNote, Tolerances};

fn read(f: &Iges) -> CompoundSurface {
    iges::parse(&f.text("2,2HMM")).unwrap()
}

fn notes(s: &CompoundSurface) -> Vec<String> {
    s.notes.iter().map(ToString::to_string).collect()
}

/// Points of an `n × n` grid over the patch's box, with their unit normals.
fn grid(p: &Patch, n: usize) -> Vec<(Vec3, Option<Vec3>)> {
    let d = p.surface.domain();
    let mut out = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            let (u, v) = (d.u_at(i as f64 / n as f64), d.v_at(j as f64 / n as f64));
            let g = p.local(u, v, &Tolerances::DEFAULT);
            out.push((g.point(), g.normal.vector()));
        }
    }
    out
}

/// A 120 turning a line parallel to the axis at distance 10 is a cylinder: every point at
/// radius 10, curvature 1/10 across, 0 along; the angles SA, TA bound it.
#[test]
fn revolution_of_a_line_is_a_cylinder() {
    let mut f = Iges::default();
    let axis = f.add(110, "0.,0.,0.,0.,0.,1.");
    let gen = f.add(110, "10.,0.,-2.,10.,0.,7.");
    f.add(120, &format!("{axis},{gen},0.5,2."));
    let s = read(&f);
    assert_eq!(s.patches.len(), 1, "{:?}", notes(&s));
    for (q, n) in grid(&s.patches[0], 16) {
        assert!((q.x.hypot(q.y) - 10.0).abs() < 1e-9, "{q}");
        assert!(q.z > -2.0 - 1e-9 && q.z < 7.0 + 1e-9, "{q}");
        let a = q.y.atan2(q.x);
        assert!(a > 0.5 - 1e-9 && a < 2.0 + 1e-9, "{a}");
        // u the generatrix, v the turn: S_u × S_v = z × tangent points at the axis.
        let n = n.unwrap();
        assert!(
            (n + Vec3::new(q.x, q.y, 0.0) / 10.0).length() < 1e-9,
            "{n} at {q}"
        );
    }
    let d = s.patches[0].surface.domain();
    let g = s.patches[0].local(d.u_at(0.3), d.v_at(0.7), &Tolerances::DEFAULT);
    let k = g.curvature.unwrap();
    assert!((k.k1 - 0.1).abs() < 1e-9 && k.k2.abs() < 1e-9, "{k:?}");
}

/// A 120 of a 126 generatrix under its own 124 (a shift) and in inches: the placement and the
/// units apply as for a 128.
#[test]
fn revolution_is_placed_and_scaled() {
    let mut f = Iges::default();
    let t = f.add(124, "1.,0.,0.,5.,0.,1.,0.,0.,0.,0.,1.,0.");
    let axis = f.add(110, "0.,0.,0.,0.,0.,2.");
    // A line at radius 2 from z = 0 to 1 as a degree-1 126.
    let gen = f.add(
        126,
        "1,1,1,0,1,0,0.,0.,1.,1.,1.,1.,2.,0.,0.,2.,0.,1.,0.,1.,0.,0.,1.",
    );
    f.add_moved(120, &format!("{axis},{gen},0.,6.283185307179586"), t);
    let s = iges::parse(&f.text("1,2HIN")).unwrap();
    assert_eq!(s.patches.len(), 1, "{:?}", notes(&s));
    for (q, _) in grid(&s.patches[0], 12) {
        let r = (q.x - 5.0 * 25.4).hypot(q.y);
        assert!((r - 2.0 * 25.4).abs() < 1e-9, "{q}");
        assert!(q.z > -1e-9 && q.z < 25.4 + 1e-9, "{q}");
    }
}

/// A 122 of a quarter arc (100) is a piece of a cylinder: radius 5 about the arc's centre, from
/// the arc's plane to the generatrix's end.
#[test]
fn tabulated_arc_is_a_cylinder_piece() {
    let mut f = Iges::default();
    let arc = f.add(100, "0.,1.,2.,6.,2.,1.,7.");
    f.add(122, &format!("{arc},6.,2.,20."));
    let s = read(&f);
    assert_eq!(s.patches.len(), 1, "{:?}", notes(&s));
    for (q, n) in grid(&s.patches[0], 16) {
        assert!(((q.x - 1.0).hypot(q.y - 2.0) - 5.0).abs() < 1e-9, "{q}");
        assert!(q.x > 1.0 - 1e-9 && q.y > 2.0 - 1e-9, "{q}");
        assert!(q.z > -1e-9 && q.z < 20.0 + 1e-9, "{q}");
        // S_u (along the arc) × S_v (up): outward.
        let n = n.unwrap();
        assert!((n - Vec3::new(q.x - 1.0, q.y - 2.0, 0.0) / 5.0).length() < 1e-9);
    }
    let g = s.patches[0].local(0.5 * (0.0 + 0.5), 0.5, &Tolerances::DEFAULT);
    let k = g.curvature.unwrap();
    assert!((k.k2 + 0.2).abs() < 1e-9 && k.k1.abs() < 1e-9, "{k:?}");
}

/// A 118 between two parallel lines is a plane strip; DIRFLG 1 joins the first end of one to
/// the last of the other (here the second line is written backwards, so it gives the strip).
#[test]
fn ruled_between_parallel_lines_is_a_plane_strip() {
    for (dirflg, second) in [(0, "0.,4.,3.,10.,4.,3."), (1, "10.,4.,3.,0.,4.,3.")] {
        let mut f = Iges::default();
        let a = f.add(110, "0.,0.,3.,10.,0.,3.");
        let b = f.add(110, second);
        f.add(118, &format!("{a},{b},{dirflg},1"));
        let s = read(&f);
        assert_eq!(s.patches.len(), 1, "{:?}", notes(&s));
        let mut lo = Vec3::splat(f64::INFINITY);
        let mut hi = Vec3::splat(f64::NEG_INFINITY);
        for (q, n) in grid(&s.patches[0], 10) {
            assert!((q.z - 3.0).abs() < 1e-12, "{q}");
            assert!(
                (n.unwrap() - Vec3::Z).length() < 1e-12,
                "DIRFLG {dirflg}: {n:?}"
            );
            lo = lo.min(q);
            hi = hi.max(q);
        }
        assert!((lo - Vec3::new(0.0, 0.0, 3.0)).length() < 1e-12, "{lo}");
        assert!((hi - Vec3::new(10.0, 4.0, 3.0)).length() < 1e-12, "{hi}");
    }
}

/// A 118 whose rulings cannot be made exactly (form 1: equal parameter, a line to an arc whose
/// parameter is its angle) stays skipped, the note saying why.
#[test]
fn ruled_line_to_arc_by_parameter_is_skipped_with_the_reason() {
    let mut f = Iges::default();
    f.add(128, common::iges::PLATE);
    let a = f.add(110, "0.,0.,3.,10.,0.,3.");
    let arc = f.add(100, "3.,0.,0.,10.,0.,0.,10.");
    f.entities.push((118, format!("118,{a},{arc},0,0;"), 0));
    // (Form 1 is written in the directory entry below.)
    let text = f.text("2,2HMM").replace(
        "     118       0       0       1       0",
        "     118       0       0       1       1",
    );
    let s = iges::parse(&text).unwrap();
    assert_eq!(s.patches.len(), 1);
    let n = notes(&s).join("\n");
    assert!(
        n.contains("IGES 118 (form 1 joins points of equal relative parameter"),
        "{n}"
    );
}

/// A 190 through (1, 2, 5) with normal +z, and a 108 of 0x + 0y + 2z = 10, are the plane
/// z = 5 over the default box (said in a note); a 190 of form 1 takes u along its reference
/// direction.
#[test]
fn plane_surfaces_evaluate_on_their_plane() {
    let mut f = Iges::default();
    let p = f.add(116, "1.,2.,5.");
    let n = f.add(123, "0.,0.,3.");
    f.add(190, &format!("{p},{n}"));
    f.add(108, "0.,0.,2.,10.,0,0.,0.,0.,0.");
    let s = read(&f);
    assert_eq!(s.patches.len(), 2, "{:?}", notes(&s));
    for patch in &s.patches {
        for (q, n) in grid(patch, 4) {
            assert!((q.z - 5.0).abs() < 1e-12, "{q}");
            assert!((n.unwrap() - Vec3::Z).length() < 1e-12);
        }
        let d = patch.surface.domain();
        assert_eq!((d.u, d.v), ([-100.0, 100.0], [-100.0, 100.0]));
    }
    let c = s.patches[0].surface.point(0.0, 0.0);
    assert!((c - Vec3::new(1.0, 2.0, 5.0)).length() < 1e-12, "{c}");
    assert_eq!(
        s.notes
            .iter()
            .filter(|n| matches!(n, ReadNote::DefaultParameterBox { .. }))
            .count(),
        2
    );
    // Form 1: u along the reference direction (0, 1, 0).
    let mut f = Iges::default();
    let p = f.add(116, "1.,2.,5.");
    let n = f.add(123, "0.,0.,1.");
    let r = f.add(123, "0.,1.,0.");
    f.add(190, &format!("{p},{n},{r}"));
    let text = f.text("2,2HMM").replace(
        "     190       0       0       1       0",
        "     190       0       0       1       1",
    );
    let s = iges::parse(&text).unwrap();
    let q = s.patches[0].surface.point(3.0, 0.0);
    assert!((q - Vec3::new(1.0, 5.0, 5.0)).length() < 1e-12, "{q}");
}

/// A 190 plane (over the default box) trimmed by a 144 whose outer boundary is a triangle
/// (a model-space curve, mapped onto the plane): the box becomes the triangle's, and the
/// default box's note goes (the boundary gives the box), as for a STEP face.
#[test]
fn a_plane_trimmed_by_a_144_takes_its_outer_boundary_s_box() {
    let mut f = Iges::default();
    let p = f.add(116, "1.,2.,0.");
    let n = f.add(123, "0.,0.,1.");
    let plane = f.add(190, &format!("{p},{n}"));
    let tri = polygon(&mut f, &[[-10.0, 0.0], [30.0, 0.0], [-10.0, 20.0]]);
    let c = f.add(142, &format!("0,{plane},0,{tri},2"));
    f.add(144, &format!("{plane},1,0,{c}"));
    let s = read(&f);
    assert_eq!(s.patches.len(), 1, "{:?}", notes(&s));
    let patch = &s.patches[0];
    let t = patch
        .trim
        .as_ref()
        .unwrap_or_else(|| panic!("{:?}", notes(&s)));
    let d = patch.surface.domain();
    // The box is the loop's (its extent, within the default ±100).
    let outer = t.outer().unwrap();
    let ext = |k: usize| {
        outer
            .iter()
            .fold([f64::INFINITY, f64::NEG_INFINITY], |e, q| {
                [e[0].min(q[k]), e[1].max(q[k])]
            })
    };
    assert_eq!((d.u, d.v), (ext(0), ext(1)), "{:?}", notes(&s));
    assert!(d.u[1] - d.u[0] < 50.0 && d.v[1] - d.v[0] < 50.0, "{d:?}");
    assert!(
        !s.notes
            .iter()
            .any(|n| matches!(n, ReadNote::DefaultParameterBox { .. })),
        "{:?}",
        notes(&s)
    );
    // The box's corners are the plane's points (z = 0), and the triangle fills about half
    // of its box.
    for (u, v) in [(d.u[0], d.v[0]), (d.u[1], d.v[1])] {
        assert!(patch.surface.point(u, v).z.abs() < 1e-12);
    }
    let on = (0..=20)
        .flat_map(|i| (0..=20).map(move |j| (i, j)))
        .filter(|&(i, j)| {
            t.contains(
                d.u[0] + (d.u[1] - d.u[0]) * i as f64 / 20.0,
                d.v[0] + (d.v[1] - d.v[0]) * j as f64 / 20.0,
            )
        })
        .count();
    // (Half of the 441 points is 220; the edges' points count as on it.)
    assert!((200..=260).contains(&on), "{on}");
}

/// A bounded 108 (form 1) with a square 102 as its curve: the plane over the square's box,
/// trimmed by it (mapped from model space), at z = 5.
#[test]
fn bounded_plane_is_trimmed_by_its_curve() {
    let mut f = Iges::default();
    // A triangle at z = 0 (polygon's lines), moved up to z = 5 by a 124 on the 102.
    let tri = polygon(&mut f, &[[0.0, 0.0], [20.0, 0.0], [0.0, 10.0]]);
    let t = f.add(124, "1.,0.,0.,0.,0.,1.,0.,0.,0.,0.,1.,5.");
    let k = f.entities.len() - 1;
    let _ = t;
    // The 102 is entity tri; give it the 124 by rewriting its transform field.
    let idx = (tri - 1) / 2;
    f.entities[idx].2 = 2 * k + 1;
    f.add(108, &format!("0.,0.,1.,5.,{tri},0.,0.,0.,0."));
    let text = f.text("2,2HMM").replace(
        "     108       0       0       1       0",
        "     108       0       0       1       1",
    );
    let s = iges::parse(&text).unwrap();
    assert_eq!(s.patches.len(), 1, "{:?}", notes(&s));
    let p = &s.patches[0];
    let trim = p.trim.as_ref().unwrap_or_else(|| panic!("{:?}", notes(&s)));
    let inside = |x: f64, y: f64| {
        let q = Vec3::new(x, y, 5.0);
        let d = p.surface.domain();
        // The plane's parameters of q by projection onto its box corners.
        let (o, a, b) = (
            p.surface.point(d.u[0], d.v[0]),
            p.surface.point(d.u[1], d.v[0]),
            p.surface.point(d.u[0], d.v[1]),
        );
        let (eu, ev) = (a - o, b - o);
        let u = d.u[0] + (q - o).dot(eu) / eu.length_squared() * (d.u[1] - d.u[0]);
        let v = d.v[0] + (q - o).dot(ev) / ev.length_squared() * (d.v[1] - d.v[0]);
        assert!((p.surface.point(u, v) - q).length() < 1e-9);
        trim.contains(u, v)
    };
    assert!(inside(5.0, 2.0));
    assert!(!inside(15.0, 8.0));
    assert!(
        notes(&s).join("\n").contains("IGES 108 at D"),
        "{:?}",
        notes(&s)
    );
}

/// A 144 trimming a 122 through a model-space 142 (the 142 has no parameter-space curve)
/// trims it as it would a 128; one with only a parameter-space curve is left whole, the note
/// saying that the patch does not share the 122's parameters.
#[test]
fn trimmed_tabulated_cylinder() {
    for model in [true, false] {
        let mut f = Iges::default();
        let dir = f.add(110, "0.,0.,0.,10.,0.,0.");
        let surf = f.add(122, &format!("{dir},0.,10.,0."));
        // The square 2..8 × 2..8 in model space (z = 0), or in the 122's parameters.
        let sq = polygon(&mut f, &[[2.0, 2.0], [8.0, 2.0], [8.0, 8.0], [2.0, 8.0]]);
        let c142 = if model {
            f.add(142, &format!("1,{surf},0,{sq},2"))
        } else {
            let pc = polygon(&mut f, &[[0.2, 0.2], [0.8, 0.2], [0.8, 0.8], [0.2, 0.8]]);
            f.add(142, &format!("1,{surf},{pc},0,1"))
        };
        f.add(144, &format!("{surf},1,0,{c142}"));
        let s = read(&f);
        assert_eq!(s.patches.len(), 1, "{:?}", notes(&s));
        let p = &s.patches[0];
        if model {
            let t = p.trim.as_ref().unwrap_or_else(|| panic!("{:?}", notes(&s)));
            // u along x (0..10 → the line's 0..1), v along y (0..1).
            assert!(t.contains(0.5, 0.5));
            assert!(!t.contains(0.1, 0.5));
            assert!(!t.contains(0.5, 0.9));
        } else {
            assert!(p.trim.is_none());
            let n = notes(&s).join("\n");
            assert!(n.contains("parameters of the IGES 122 surface"), "{n}");
        }
    }
}
