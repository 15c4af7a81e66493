//! STEP face bounds as trims: a plane with a circular hole, cylinder bands (two circles, with
//! and without a seam edge) and a half cylinder, a B-spline face with a B-spline hole, and the
//! shared files (natural-boundary faces keep every point).

mod common;

use std::f64::consts::{PI, TAU};

use swarf_geom::math::Vec3;
use swarf_plan::io::{self, step};
use swarf_plan::{CompoundSurface, NurbsSurface, ParametricSurface, Patch, ReadNote};

/// STEP text built entity by entity.
struct Step {
    lines: Vec<String>,
}

impl Step {
    fn new() -> Self {
        Self { lines: Vec::new() }
    }
    fn add(&mut self, s: impl Into<String>) -> u64 {
        let id = self.lines.len() as u64 + 1;
        self.lines.push(format!("#{id}={};", s.into()));
        id
    }
    fn pt(&mut self, p: [f64; 3]) -> u64 {
        self.add(format!(
            "CARTESIAN_POINT('',({:?},{:?},{:?}))",
            p[0], p[1], p[2]
        ))
    }
    fn dir(&mut self, d: [f64; 3]) -> u64 {
        self.add(format!("DIRECTION('',({:?},{:?},{:?}))", d[0], d[1], d[2]))
    }
    fn axis(&mut self, o: [f64; 3], z: [f64; 3], x: [f64; 3]) -> u64 {
        let (o, z, x) = (self.pt(o), self.dir(z), self.dir(x));
        self.add(format!("AXIS2_PLACEMENT_3D('',#{o},#{z},#{x})"))
    }
    fn vertex(&mut self, p: [f64; 3]) -> u64 {
        let c = self.pt(p);
        self.add(format!("VERTEX_POINT('',#{c})"))
    }
    fn line(&mut self, p: [f64; 3], d: [f64; 3]) -> u64 {
        let (p, d) = (self.pt(p), self.dir(d));
        let v = self.add(format!("VECTOR('',#{d},1.)"));
        self.add(format!("LINE('',#{p},#{v})"))
    }
    fn circle(&mut self, c: [f64; 3], r: f64) -> u64 {
        let a = self.axis(c, [0., 0., 1.], [1., 0., 0.]);
        self.add(format!("CIRCLE('',#{a},{r:?})"))
    }
    fn edge(&mut self, v0: u64, v1: u64, geom: u64, same: bool) -> u64 {
        self.add(format!(
            "EDGE_CURVE('',#{v0},#{v1},#{geom},{})",
            logical(same)
        ))
    }
    fn loop_of(&mut self, edges: &[(u64, bool)]) -> u64 {
        let oes: Vec<String> = edges
            .iter()
            .map(|&(e, o)| {
                format!(
                    "#{}",
                    self.add(format!("ORIENTED_EDGE('',*,*,#{e},{})", logical(o)))
                )
            })
            .collect();
        self.add(format!("EDGE_LOOP('',({}))", oes.join(",")))
    }
    fn bound(&mut self, l: u64, outer: bool) -> u64 {
        let kind = if outer {
            "FACE_OUTER_BOUND"
        } else {
            "FACE_BOUND"
        };
        self.add(format!("{kind}('',#{l},.T.)"))
    }
    fn face(&mut self, bounds: &[u64], surface: u64) -> u64 {
        let b: Vec<String> = bounds.iter().map(|b| format!("#{b}")).collect();
        self.add(format!(
            "ADVANCED_FACE('',({}),#{surface},.T.)",
            b.join(",")
        ))
    }
    fn bspline_curve(&mut self, pts: &[u64], degree: usize, knots: &[f64], mults: &[usize]) -> u64 {
        let p: Vec<String> = pts.iter().map(|p| format!("#{p}")).collect();
        let m: Vec<String> = mults.iter().map(|m| m.to_string()).collect();
        let k: Vec<String> = knots.iter().map(|k| format!("{k:?}")).collect();
        self.add(format!(
            "B_SPLINE_CURVE_WITH_KNOTS('',{degree},({}),.UNSPECIFIED.,.F.,.F.,({}),({}),.UNSPECIFIED.)",
            p.join(","),
            m.join(","),
            k.join(",")
        ))
    }
    fn parse(&self) -> CompoundSurface {
        let text = format!(
            "ISO-10303-21;\nHEADER;\nFILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\nENDSEC;\nDATA;\n{}\nENDSEC;\nEND-ISO-10303-21;\n",
            self.lines.join("\n")
        );
        step::parse(&text).unwrap()
    }
}

fn logical(b: bool) -> &'static str {
    if b {
        ".T."
    } else {
        ".F."
    }
}

/// Share of an n × n grid over the patch's box that is on the part (with `strict`, only the
/// points strictly inside the box).
fn fraction(p: &Patch, n: usize, strict: bool) -> f64 {
    let d = p.surface.domain();
    let (mut on, mut all) = (0, 0);
    let range = if strict { 1..n - 1 } else { 0..n };
    for i in range.clone() {
        for j in range.clone() {
            all += 1;
            let (u, v) = (
                d.u_at(i as f64 / (n - 1) as f64),
                d.v_at(j as f64 / (n - 1) as f64),
            );
            if p.on_part(u, v) {
                on += 1;
            }
        }
    }
    on as f64 / all as f64
}

fn trimmed_notes(s: &CompoundSurface) -> Vec<&ReadNote> {
    s.notes
        .iter()
        .filter(|n| {
            matches!(
                n,
                ReadNote::Trimmed { .. } | ReadNote::TrimNotHonoured { .. }
            )
        })
        .collect()
}

#[test]
fn plane_with_a_circular_hole() {
    let mut f = Step::new();
    let a = f.axis([0., 0., 0.], [0., 0., 1.], [1., 0., 0.]);
    let plane = f.add(format!("PLANE('',#{a})"));
    let c = [[0., 0., 0.], [100., 0., 0.], [100., 60., 0.], [0., 60., 0.]];
    let v: Vec<u64> = c.iter().map(|&p| f.vertex(p)).collect();
    let mut edges = Vec::new();
    for k in 0..4 {
        let (p, q) = (c[k], c[(k + 1) % 4]);
        let len = (q[0] - p[0]).hypot(q[1] - p[1]);
        let d = [(q[0] - p[0]) / len, (q[1] - p[1]) / len, 0.0];
        let l = f.line(p, d);
        edges.push((f.edge(v[k], v[(k + 1) % 4], l, true), true));
    }
    let outer = f.loop_of(&edges);
    let hv = f.vertex([40., 30., 0.]);
    let circle = f.circle([30., 30., 0.], 10.);
    let he = f.edge(hv, hv, circle, true);
    let hole = f.loop_of(&[(he, false)]);
    let (bo, bh) = (f.bound(outer, true), f.bound(hole, false));
    f.face(&[bo, bh], plane);
    let s = f.parse();
    println!("{:?}", trimmed_notes(&s));
    assert!(s.notes.iter().any(|n| matches!(
        n,
        ReadNote::Trimmed {
            patch: 0,
            loops: 2,
            ..
        }
    )));
    let p = &s.patches[0];
    let t = p.trim.as_ref().unwrap();
    let d = p.surface.domain();
    assert_eq!((d.u, d.v), ([0.0, 100.0], [0.0, 60.0]));
    assert!(!t.contains(30.0, 30.0));
    assert!(!t.contains(30.0, 39.9) && t.contains(30.0, 40.1));
    for (u, v) in [
        (0.5, 0.5),
        (99.5, 0.5),
        (99.5, 59.5),
        (0.5, 59.5),
        (0.0, 0.0),
        (100.0, 60.0),
    ] {
        assert!(t.contains(u, v), "({u}, {v})");
    }
    // The hole's polygon keeps within the chord tolerance of the circle.
    for q in &t.holes()[0] {
        let r = (q[0] - 30.0).hypot(q[1] - 30.0);
        assert!((10.0 - 1.1e-3..=10.0 + 1e-12).contains(&r), "{r}");
    }
    let frac = fraction(p, 41, false);
    let expect = 1.0 - PI * 100.0 / 6000.0;
    println!("plane with hole: fraction {frac:.5}, expected {expect:.5}");
    // One grid cell is 2.5 × 1.5 mm: the count along the circle errs by a few cells.
    assert!((frac - expect).abs() < 0.006, "{frac} vs {expect}");
}

/// A cylinder of radius 10 around z, a face between z = 0 and z = 50 bounded as `kind` says.
fn cylinder(kind: &str) -> CompoundSurface {
    let mut f = Step::new();
    let a = f.axis([0., 0., 0.], [0., 0., 1.], [1., 0., 0.]);
    let cyl = f.add(format!("CYLINDRICAL_SURFACE('',#{a},10.)"));
    match kind {
        "circles" => {
            let (v0, v1) = (f.vertex([10., 0., 0.]), f.vertex([10., 0., 50.]));
            let (c0, c1) = (f.circle([0., 0., 0.], 10.), f.circle([0., 0., 50.], 10.));
            let (e0, e1) = (f.edge(v0, v0, c0, true), f.edge(v1, v1, c1, true));
            let (l0, l1) = (f.loop_of(&[(e0, true)]), f.loop_of(&[(e1, false)]));
            let (b0, b1) = (f.bound(l0, false), f.bound(l1, false));
            f.face(&[b0, b1], cyl);
        }
        "seam" => {
            // The exporters' form: bottom circle, seam up, top circle backwards, seam down,
            // starting away from u = 0.
            let (v0, v1) = (f.vertex([0., 10., 0.]), f.vertex([0., 10., 50.]));
            let (c0, c1) = (f.circle([0., 0., 0.], 10.), f.circle([0., 0., 50.], 10.));
            let (e0, e1) = (f.edge(v0, v0, c0, true), f.edge(v1, v1, c1, true));
            let l = f.line([0., 10., 0.], [0., 0., 1.]);
            let seam = f.add(format!("SEAM_CURVE('',#{l},(),.PCURVE_S1.)"));
            let es = f.edge(v0, v1, seam, true);
            let lp = f.loop_of(&[(e0, true), (es, true), (e1, false), (es, false)]);
            let b = f.bound(lp, true);
            f.face(&[b], cyl);
        }
        "half" => {
            let v = [
                f.vertex([10., 0., 0.]),
                f.vertex([-10., 0., 0.]),
                f.vertex([-10., 0., 50.]),
                f.vertex([10., 0., 50.]),
            ];
            let (c0, c1) = (f.circle([0., 0., 0.], 10.), f.circle([0., 0., 50.], 10.));
            let bottom = f.edge(v[0], v[1], c0, true);
            let l1 = f.line([-10., 0., 0.], [0., 0., 1.]);
            let left = f.edge(v[1], v[2], l1, true);
            let top = f.edge(v[3], v[2], c1, true);
            let l2 = f.line([10., 0., 0.], [0., 0., 1.]);
            let right = f.edge(v[0], v[3], l2, true);
            let lp = f.loop_of(&[(bottom, true), (left, true), (top, false), (right, false)]);
            let b = f.bound(lp, true);
            f.face(&[b], cyl);
        }
        _ => unreachable!(),
    }
    f.parse()
}

#[test]
fn cylinder_bands_and_a_half_cylinder() {
    for kind in ["circles", "seam"] {
        let s = cylinder(kind);
        println!("{kind}: {:?}", trimmed_notes(&s));
        assert!(
            s.notes
                .iter()
                .any(|n| matches!(n, ReadNote::Trimmed { patch: 0, .. })),
            "{kind}: {:?}",
            s.notes
        );
        let p = &s.patches[0];
        let d = p.surface.domain();
        assert!(
            (d.u[1] - d.u[0] - TAU).abs() < 1e-12 && d.v == [0.0, 50.0],
            "{d:?}"
        );
        let frac = fraction(p, 41, false);
        println!("{kind}: fraction {frac}");
        assert_eq!(frac, 1.0, "{kind}");
    }
    let s = cylinder("half");
    println!("half: {:?}", trimmed_notes(&s));
    let p = &s.patches[0];
    let t = p.trim.as_ref().unwrap();
    assert!(t.contains(0.5 * PI, 25.0) && !t.contains(1.5 * PI, 25.0));
    let frac = fraction(p, 41, false);
    println!("half: fraction {frac} (21/41 = {})", 21.0 / 41.0);
    assert!((frac - 21.0 / 41.0).abs() < 1e-12, "{frac}");
}

#[test]
fn bspline_face_with_a_bspline_hole() {
    // A bicubic height field over [0, 100]², one Bézier patch, u and v in [0, 1].
    let z = [
        [0., 5., -3., 2.],
        [4., 10., 8., -2.],
        [-2., 6., 12., 3.],
        [1., -4., 2., 0.],
    ];
    let net: Vec<Vec<Vec3>> = (0..4)
        .map(|i| {
            (0..4)
                .map(|j| Vec3::new(100.0 * i as f64 / 3.0, 100.0 * j as f64 / 3.0, z[i][j]))
                .collect()
        })
        .collect();
    let bez = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
    let surf = NurbsSurface::new(3, 3, bez.clone(), bez, &net, None).unwrap();
    let mut f = Step::new();
    let ids: Vec<Vec<u64>> = net
        .iter()
        .map(|row| row.iter().map(|p| f.pt([p.x, p.y, p.z])).collect())
        .collect();
    let rows: Vec<String> = ids
        .iter()
        .map(|r| {
            format!(
                "({})",
                r.iter()
                    .map(|i| format!("#{i}"))
                    .collect::<Vec<_>>()
                    .join(",")
            )
        })
        .collect();
    let sid = f.add(format!(
        "B_SPLINE_SURFACE_WITH_KNOTS('',3,3,({}),.UNSPECIFIED.,.F.,.F.,.F.,(4,4),(4,4),(0.,1.),(0.,1.),.UNSPECIFIED.)",
        rows.join(",")
    ));
    // Corners and the four boundary curves (rows and columns of the net).
    let vx = |f: &mut Step, i: usize, j: usize| {
        let p = net[i][j];
        f.vertex([p.x, p.y, p.z])
    };
    let (c00, c30, c33, c03) = (
        vx(&mut f, 0, 0),
        vx(&mut f, 3, 0),
        vx(&mut f, 3, 3),
        vx(&mut f, 0, 3),
    );
    let cubic = |f: &mut Step, pts: Vec<u64>| f.bspline_curve(&pts, 3, &[0.0, 1.0], &[4, 4]);
    let b0 = cubic(&mut f, (0..4).map(|i| ids[i][0]).collect());
    let b1 = cubic(&mut f, (0..4).map(|j| ids[3][j]).collect());
    let b2 = cubic(&mut f, (0..4).map(|i| ids[i][3]).collect());
    let b3 = cubic(&mut f, (0..4).map(|j| ids[0][j]).collect());
    let e0 = f.edge(c00, c30, b0, true);
    let e1 = f.edge(c30, c33, b1, true);
    let e2 = f.edge(c03, c33, b2, true);
    let e3 = f.edge(c00, c03, b3, true);
    let outer = f.loop_of(&[(e0, true), (e1, true), (e2, false), (e3, false)]);
    // The hole: surface points of the parameter circle (0.5, 0.5) + 0.2 (cos θ, sin θ) as a
    // degree-1 B-spline.
    let n = 96;
    let (cu, cv, r) = (0.5, 0.5, 0.2);
    let mut hole_pts: Vec<u64> = (0..n)
        .map(|k| {
            let th = TAU * k as f64 / n as f64;
            let p = surf.point(cu + r * th.cos(), cv + r * th.sin());
            f.pt([p.x, p.y, p.z])
        })
        .collect();
    hole_pts.push(hole_pts[0]);
    let knots: Vec<f64> = (0..=n).map(|k| k as f64).collect();
    let mut mults = vec![1; n + 1];
    mults[0] = 2;
    mults[n] = 2;
    let hc = f.bspline_curve(&hole_pts, 1, &knots, &mults);
    let p0 = surf.point(cu + r, cv);
    let hv = f.vertex([p0.x, p0.y, p0.z]);
    let he = f.edge(hv, hv, hc, true);
    let hole = f.loop_of(&[(he, true)]);
    let (bo, bh) = (f.bound(outer, true), f.bound(hole, false));
    f.face(&[bo, bh], sid);
    let s = f.parse();
    println!("{:?}", trimmed_notes(&s));
    let p = &s.patches[0];
    let t = p.trim.as_ref().expect("trimmed");
    // The outer loop is the parameter box's edge.
    for q in t.outer().unwrap() {
        let on_edge = q.iter().any(|&x| x == 0.0 || x == 1.0);
        assert!(on_edge, "{q:?}");
    }
    // The hole: within the polyline's sagitta (chords of the 3-D points, projected) and the
    // sampling tolerance of the parameter circle.
    let sag = r * (1.0 - (PI / n as f64).cos());
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for q in &t.holes()[0] {
        let e = (q[0] - cu).hypot(q[1] - cv) - r;
        lo = lo.min(e);
        hi = hi.max(e);
    }
    println!(
        "hole: {} points, radius error in [{lo:.3e}, {hi:.3e}], sagitta {sag:.3e}",
        t.holes()[0].len()
    );
    assert!(hi < 1e-7 && lo > -1.5 * sag, "[{lo}, {hi}] vs {sag}");
    assert!(!t.contains(0.5, 0.5) && !t.contains(0.5, 0.69) && t.contains(0.5, 0.71));
    assert!(t.contains(0.0, 0.0) && t.contains(1.0, 1.0) && t.contains(0.05, 0.95));
    let frac = fraction(p, 41, false);
    let area = 1.0 - PI * r * r;
    // The grid points strictly inside the parameter circle are off the part (those on it are
    // on: the polygon lies inside the circle).
    let inside = (0..41)
        .flat_map(|i| (0..41).map(move |j| (i as f64 / 40.0 - cu).hypot(j as f64 / 40.0 - cv)))
        .filter(|&d| d < r - 1e-9)
        .count();
    let lattice = 1.0 - inside as f64 / (41.0 * 41.0);
    println!("B-spline with hole: fraction {frac:.5}, lattice count {lattice:.5}, area {area:.5}");
    assert_eq!(frac, lattice);
    assert!((frac - area).abs() < 0.015, "{frac} vs {area}");
}

#[test]
fn shared_files_keep_their_natural_boundaries() {
    for (file, patches) in [
        (data!("step/occt_bug28366_fuselage.stp"), 8),
        (data!("step/llnl_revolved_sphere.step"), 1),
    ] {
        let s = io::read_file(std::path::Path::new(file)).unwrap();
        assert_eq!(s.patches.len(), patches);
        println!("{file}: notes {:?}", s.notes);
        for (k, p) in s.patches.iter().enumerate() {
            let frac = fraction(p, 41, true);
            println!(
                "  patch {k}: trimmed {}, fraction strictly inside {frac}",
                p.trim.is_some()
            );
            assert_eq!(frac, 1.0);
        }
        // No face trim in either: the fuselage has no faces, the sphere's only bound is a
        // vertex loop (the pole).
        assert!(trimmed_notes(&s).is_empty(), "{:?}", s.notes);
    }
}
