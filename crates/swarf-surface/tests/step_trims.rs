//! STEP face bounds as trims: a plane with a circular hole, cylinder bands (two circles, with
//! and without a seam edge) and a half cylinder, a B-spline face with a B-spline hole, and the
//! shared files (natural-boundary faces keep every point). Then surfaces of revolution against
//! their closed forms: a whole sphere (its seam twice), lunes (either sense, wider than a half
//! turn, across u = 0), zones and caps (every sense and orientation, through the pole by a
//! seam); a cone to its apex (vertex loop; sectors through it), frustums; torus bands both ways
//! round and a four-edge torus patch; a cylinder window across the seam and an outer loop that
//! moves the box. Poly loops, polylines, an ellipse (a cylinder cut by an inclined plane),
//! trimmed curves of either sense, rational B-spline circles; and a window in a STEP face that
//! is off the part.

mod common;
use common::{data, sphere_step_file};

use std::f64::consts::{PI, TAU};

use swarf_geom::math::Vec3;
use swarf_surface::io::{self, step};
use swarf_surface::{
    CompoundSurface, NurbsSurface, ParamBox, ParametricSurface, Patch, ReadNote, Surface,
};

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
    /// A circle of radius `r` around `c` in the plane normal to `z`, starting at `x`.
    fn circle_in(&mut self, c: [f64; 3], z: [f64; 3], x: [f64; 3], r: f64) -> u64 {
        let a = self.axis(c, z, x);
        self.add(format!("CIRCLE('',#{a},{r:?})"))
    }
    fn ellipse(&mut self, c: [f64; 3], z: [f64; 3], x: [f64; 3], a: f64, b: f64) -> u64 {
        let p = self.axis(c, z, x);
        self.add(format!("ELLIPSE('',#{p},{a:?},{b:?})"))
    }
    fn seam(&mut self, curve: u64) -> u64 {
        self.add(format!("SEAM_CURVE('',#{curve},(),.PCURVE_S1.)"))
    }
    /// An edge along `geom` between new vertices at `p` and `q`.
    fn edge_at(&mut self, p: [f64; 3], q: [f64; 3], geom: u64, same: bool) -> u64 {
        let (a, b) = (self.vertex(p), self.vertex(q));
        self.edge(a, b, geom, same)
    }
    /// A closed edge along `geom` from and to one new vertex at `p`.
    fn ring(&mut self, p: [f64; 3], geom: u64, same: bool) -> u64 {
        let a = self.vertex(p);
        self.edge(a, a, geom, same)
    }
    /// A straight edge from `p` to `q`.
    fn segment(&mut self, p: [f64; 3], q: [f64; 3]) -> u64 {
        let d = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let l = self.line(p, [d[0] / len, d[1] / len, d[2] / len]);
        self.edge_at(p, q, l, true)
    }
    fn bound_o(&mut self, l: u64, outer: bool, orientation: bool) -> u64 {
        let kind = if outer {
            "FACE_OUTER_BOUND"
        } else {
            "FACE_BOUND"
        };
        self.add(format!("{kind}('',#{l},{})", logical(orientation)))
    }
    fn face_s(&mut self, bounds: &[u64], surface: u64, same_sense: bool) -> u64 {
        let b: Vec<String> = bounds.iter().map(|b| format!("#{b}")).collect();
        self.add(format!(
            "ADVANCED_FACE('',({}),#{surface},{})",
            b.join(","),
            logical(same_sense)
        ))
    }
    fn vertex_loop(&mut self, p: [f64; 3]) -> u64 {
        let v = self.vertex(p);
        self.add(format!("VERTEX_LOOP('',#{v})"))
    }
    fn points(&mut self, pts: &[[f64; 3]]) -> String {
        let ids: Vec<String> = pts.iter().map(|&p| format!("#{}", self.pt(p))).collect();
        ids.join(",")
    }
    fn poly_loop(&mut self, pts: &[[f64; 3]]) -> u64 {
        let l = self.points(pts);
        self.add(format!("POLY_LOOP('',({l}))"))
    }
    fn polyline(&mut self, pts: &[[f64; 3]]) -> u64 {
        let l = self.points(pts);
        self.add(format!("POLYLINE('',({l}))"))
    }
    /// `basis` between the points `p` and `q`, along it or against it as `sense` says.
    fn trimmed(&mut self, basis: u64, p: [f64; 3], q: [f64; 3], sense: bool) -> u64 {
        let (a, b) = (self.pt(p), self.pt(q));
        self.add(format!(
            "TRIMMED_CURVE('',#{basis},(#{a}),(#{b}),{},.CARTESIAN.)",
            logical(sense)
        ))
    }
    /// The circle of radius `r` around `c` (normal z, from +x, counterclockwise) as a rational
    /// quadratic B-spline on the circumscribed square (9 points, weights 1 and √½), in the
    /// complex-entity form.
    fn rational_circle(&mut self, c: [f64; 3], r: f64) -> u64 {
        let corners = [
            [1., 0.],
            [1., 1.],
            [0., 1.],
            [-1., 1.],
            [-1., 0.],
            [-1., -1.],
            [0., -1.],
            [1., -1.],
            [1., 0.],
        ];
        let pts: Vec<[f64; 3]> = corners
            .iter()
            .map(|q| [c[0] + r * q[0], c[1] + r * q[1], c[2]])
            .collect();
        let l = self.points(&pts);
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let w: Vec<String> = (0..9)
            .map(|k| format!("{:?}", if k % 2 == 0 { 1.0 } else { h }))
            .collect();
        self.add(format!(
            "(BOUNDED_CURVE() B_SPLINE_CURVE(2,({l}),.CIRCULAR_ARC.,.T.,.F.) \
             B_SPLINE_CURVE_WITH_KNOTS((3,2,2,2,3),(0.,0.25,0.5,0.75,1.),.UNSPECIFIED.) CURVE() \
             GEOMETRIC_REPRESENTATION_ITEM() RATIONAL_B_SPLINE_CURVE(({})) \
             REPRESENTATION_ITEM(''))",
            w.join(",")
        ))
    }
    fn text(&self) -> String {
        format!(
            "ISO-10303-21;\nHEADER;\nFILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\nENDSEC;\nDATA;\n{}\nENDSEC;\nEND-ISO-10303-21;\n",
            self.lines.join("\n")
        )
    }
    fn parse(&self) -> CompoundSurface {
        step::parse(&self.text()).unwrap()
    }
}

fn logical(b: bool) -> &'static str {
    if b {
        ".T."
    } else {
        ".F."
    }
}

/// The box the shares below are of: the patch's, its angles a whole turn from where the box
/// starts (a sphere's latitude all of its half turn) — the face's share of its whole surface,
/// whatever box the reader fits to the face.
fn whole(p: &Patch) -> ParamBox {
    let mut d = p.surface.domain();
    let per = periodic(p);
    if per[0] {
        d.u[1] = d.u[0] + TAU;
    }
    if per[1] {
        d.v[1] = d.v[0] + TAU;
    }
    if matches!(p.surface, Surface::Sphere(_)) {
        d.v = [-PI / 2.0, PI / 2.0];
    }
    d
}

/// Share of an n × n grid over the patch's [`whole`] box that is on the part (with `strict`,
/// only the points strictly inside the box).
fn fraction(p: &Patch, n: usize, strict: bool) -> f64 {
    let d = whole(p);
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
    // The box is the face's, u from 0 to π, not the whole turn.
    let d = p.surface.domain();
    assert!(
        d.u[0].abs() < 1e-9 && (d.u[1] - PI).abs() < 1e-9 && d.v == [0.0, 50.0],
        "{d:?}"
    );
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
fn sphere_keeps_its_natural_boundary() {
    natural_boundaries(&sphere_step_file(), 1);
}

#[test]
fn fuselage_keeps_its_natural_boundaries() {
    if let Some(file) = data("step/occt_bug28366_fuselage.stp") {
        natural_boundaries(&file, 8);
    }
}

/// Every patch of `file` (`patches` of them) is untrimmed: no face trim, nothing cut off.
fn natural_boundaries(file: &std::path::Path, patches: usize) {
    {
        let s = io::read_file(file).unwrap();
        assert_eq!(s.patches.len(), patches);
        println!("{}: notes {:?}", file.display(), s.notes);
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

// ---------------------------------------------------------------------------------------------
// Surfaces of revolution, seams and poles, other loop and edge kinds, and a size end to end.

/// `x` moved whole turns into `[lo, lo + 2π)`.
fn ang(x: f64, lo: f64) -> f64 {
    lo + (x - lo).rem_euclid(TAU)
}

/// Which of u and v are angles (periodic) on the patch's surface.
fn periodic(p: &Patch) -> [bool; 2] {
    match p.surface {
        Surface::Cylinder(_) | Surface::Cone(_) | Surface::Sphere(_) => [true, false],
        Surface::Torus(_) => [true, true],
        _ => [false, false],
    }
}

/// The surface point at a trim point, its angles moved whole turns into the parameter box.
fn eval(p: &Patch, q: [f64; 2]) -> Vec3 {
    let d = p.surface.domain();
    let per = periodic(p);
    let u = if per[0] { ang(q[0], d.u[0]) } else { q[0] };
    let v = if per[1] { ang(q[1], d.v[0]) } else { q[1] };
    p.surface.point(u, v)
}

/// The centres of an n × n grid of cells over the patch's [`whole`] box, each checked against `inside`
/// (which says `None` for a centre too near the boundary to call); returns the share on the
/// part.
fn region(p: &Patch, n: usize, inside: impl Fn(f64, f64) -> Option<bool>) -> f64 {
    let d = whole(p);
    let mut on = 0;
    for i in 0..n {
        for j in 0..n {
            let (u, v) = (
                d.u_at((i as f64 + 0.5) / n as f64),
                d.v_at((j as f64 + 0.5) / n as f64),
            );
            let got = p.on_part(u, v);
            if let Some(want) = inside(u, v) {
                assert_eq!(got, want, "({u}, {v}) in {d:?}");
            }
            on += usize::from(got);
        }
    }
    on as f64 / (n * n) as f64
}

/// `Some(x < y)` unless they are within `eps`.
fn below(x: f64, y: f64, eps: f64) -> Option<bool> {
    ((x - y).abs() > eps).then_some(x < y)
}

/// Both, when both known (false as soon as one is known false).
fn and(a: Option<bool>, b: Option<bool>) -> Option<bool> {
    match (a, b) {
        (Some(false), _) | (_, Some(false)) => Some(false),
        (Some(true), Some(true)) => Some(true),
        _ => None,
    }
}

fn not(a: Option<bool>) -> Option<bool> {
    a.map(|x| !x)
}

/// Whether two angles are one up to whole turns.
fn same_angle(a: f64, b: f64) -> bool {
    let x = (a - b) / TAU;
    (x - x.round()).abs() < 1e-9
}

fn e(u: f64) -> [f64; 3] {
    [u.cos(), u.sin(), 0.0]
}

fn scale(k: f64, p: [f64; 3]) -> [f64; 3] {
    [k * p[0], k * p[1], k * p[2]]
}

fn plus(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn trimmed_patch(s: &CompoundSurface, k: usize) -> &Patch {
    assert!(
        s.notes
            .iter()
            .any(|n| matches!(n, ReadNote::Trimmed { patch, .. } if *patch == k)),
        "{:?}",
        s.notes
    );
    &s.patches[k]
}

const RS: f64 = 10.0;

/// A point of the sphere of radius `RS` around the origin (z the polar axis).
fn sph(u: f64, v: f64) -> [f64; 3] {
    plus(scale(RS * v.cos(), e(u)), [0.0, 0.0, RS * v.sin()])
}

fn sphere_surface(f: &mut Step) -> u64 {
    let a = f.axis([0., 0., 0.], [0., 0., 1.], [1., 0., 0.]);
    f.add(format!("SPHERICAL_SURFACE('',#{a},{RS:?})"))
}

/// The great circle through the poles and longitude u, its parameter the latitude.
fn meridian(f: &mut Step, u: f64) -> u64 {
    f.circle_in([0.; 3], [u.sin(), -u.cos(), 0.], e(u), RS)
}

/// The circle of latitude v, its parameter the longitude.
fn parallel(f: &mut Step, v: f64) -> u64 {
    f.circle([0., 0., RS * v.sin()], RS * v.cos())
}

const S_POLE: [f64; 3] = [0., 0., -RS];
const N_POLE: [f64; 3] = [0., 0., RS];

#[test]
fn sphere_bounded_through_its_poles() {
    // The whole sphere: its seam meridian up and back down.
    let mut f = Step::new();
    let sph_id = sphere_surface(&mut f);
    let m = meridian(&mut f, 0.0);
    let seam = f.seam(m);
    let es = f.edge_at(S_POLE, N_POLE, seam, true);
    let l = f.loop_of(&[(es, true), (es, false)]);
    let b = f.bound(l, true);
    f.face(&[b], sph_id);
    let s = f.parse();
    let p = trimmed_patch(&s, 0);
    let frac = region(p, 48, |_, _| Some(true));
    println!("full sphere: {:?}, fraction {frac}", p.surface.domain());
    // Lunes between longitudes a < b, up along b and down along a (the face on the left seen
    // from outside): [a, b] when the face's normal is the sphere's, the rest when it is not.
    // Wider than a half turn, a half turn, across u = 0.
    for (a, b) in [
        (-PI / 4.0, PI / 3.0),
        (0.0, 1.5 * PI),
        (0.0, PI),
        (0.5, 0.5 + PI),
    ] {
        for same_sense in [true, false] {
            let mut f = Step::new();
            let sph_id = sphere_surface(&mut f);
            let (ma, mb) = (meridian(&mut f, a), meridian(&mut f, b));
            let ea = f.edge_at(S_POLE, N_POLE, ma, true);
            let eb = f.edge_at(S_POLE, N_POLE, mb, true);
            let l = f.loop_of(&[(eb, true), (ea, false)]);
            let bd = f.bound(l, true);
            f.face_s(&[bd], sph_id, same_sense);
            let s = f.parse();
            let p = trimmed_patch(&s, 0);
            let (lo, width) = if same_sense {
                (a, b - a)
            } else {
                (b, TAU - (b - a))
            };
            let frac = region(p, 48, |u, _| below(ang(u, lo) - lo, width, 1e-6));
            println!("lune [{a:.4}, {b:.4}], same_sense {same_sense}: fraction {frac:.5}");
            assert!((frac - width / TAU).abs() < 1.0 / 48.0, "{frac}");
            // Every loop point lies on one of the two meridians (or a pole).
            for q in p.trim.as_ref().unwrap().loops().concat() {
                let x = eval(p, q);
                let on_meridian = |m: f64| {
                    let n = Vec3::new(m.sin(), -m.cos(), 0.0);
                    x.dot(n).abs() < 1e-7 && x.dot(Vec3::new(m.cos(), m.sin(), 0.0)) > -1e-9
                };
                assert!(
                    x.x.hypot(x.y) < 1e-9 || on_meridian(a) || on_meridian(b),
                    "{q:?} → {x:?}"
                );
            }
        }
    }
}

#[test]
fn sphere_zones_and_caps() {
    let (v1, v2) = (-PI / 6.0, PI / 4.0);
    // A zone between two parallels: two circles, or the exporters' seam form.
    for seam_form in [false, true] {
        let mut f = Step::new();
        let sph_id = sphere_surface(&mut f);
        let (c1, c2) = (parallel(&mut f, v1), parallel(&mut f, v2));
        if seam_form {
            let u0 = PI / 2.0;
            let (p1, p2) = (sph(u0, v1), sph(u0, v2));
            let (e1, e2) = (f.ring(p1, c1, true), f.ring(p2, c2, true));
            let m = meridian(&mut f, u0);
            let sm = f.seam(m);
            let es = f.edge_at(p1, p2, sm, true);
            let l = f.loop_of(&[(e1, true), (es, true), (e2, false), (es, false)]);
            let b = f.bound(l, true);
            f.face(&[b], sph_id);
        } else {
            let (e1, e2) = (
                f.ring(sph(0.0, v1), c1, true),
                f.ring(sph(0.0, v2), c2, true),
            );
            let (l1, l2) = (f.loop_of(&[(e1, true)]), f.loop_of(&[(e2, false)]));
            let (b1, b2) = (f.bound(l1, false), f.bound(l2, false));
            f.face(&[b1, b2], sph_id);
        }
        let s = f.parse();
        let p = trimmed_patch(&s, 0);
        let frac = region(p, 48, |_, v| and(below(v1, v, 1e-6), below(v, v2, 1e-6)));
        println!("zone (seam form {seam_form}): fraction {frac}");
        assert!((frac - (v2 - v1) / PI).abs() < 1e-12, "{frac}");
    }
    // A cap bounded by one parallel: the side kept follows the loop's direction, the bound's
    // orientation and the face's sense.
    let v0 = PI / 4.0;
    for same_sense in [true, false] {
        for bound_orientation in [true, false] {
            for edge_orientation in [true, false] {
                let mut f = Step::new();
                let sph_id = sphere_surface(&mut f);
                let c = parallel(&mut f, v0);
                let ec = f.ring(sph(0.0, v0), c, true);
                let l = f.loop_of(&[(ec, edge_orientation)]);
                let b = f.bound_o(l, true, bound_orientation);
                f.face_s(&[b], sph_id, same_sense);
                let s = f.parse();
                let p = trimmed_patch(&s, 0);
                // Going east seen from outside, the face is to the north.
                let east = edge_orientation == bound_orientation;
                let north = east == same_sense;
                let frac = region(p, 48, |_, v| {
                    let above = below(v0, v, 1e-6);
                    if north {
                        above
                    } else {
                        not(above)
                    }
                });
                let want = if north { 0.25 } else { 0.75 };
                println!(
                    "cap: same_sense {same_sense}, bound {bound_orientation}, edge \
                     {edge_orientation}: north {north}, fraction {frac}"
                );
                assert!((frac - want).abs() < 1e-12, "{frac}");
            }
        }
    }
    // A cap closed through its pole by the seam, up and back down: the north cap (the circle
    // eastwards), the south cap (the circle westwards).
    for north in [true, false] {
        let mut f = Step::new();
        let sph_id = sphere_surface(&mut f);
        let c = parallel(&mut f, v0);
        let p0 = sph(0.0, v0);
        let ec = f.ring(p0, c, true);
        let m = meridian(&mut f, 0.0);
        let sm = f.seam(m);
        let (pole, es) = if north {
            (N_POLE, f.edge_at(p0, N_POLE, sm, true))
        } else {
            (S_POLE, f.edge_at(S_POLE, p0, sm, true))
        };
        let _ = pole;
        let l = f.loop_of(&[(ec, north), (es, north), (es, !north)]);
        let b = f.bound(l, true);
        f.face(&[b], sph_id);
        let s = f.parse();
        let p = trimmed_patch(&s, 0);
        let frac = region(p, 48, |_, v| {
            let above = below(v0, v, 1e-6);
            if north {
                above
            } else {
                not(above)
            }
        });
        println!("cap through its pole (north {north}): fraction {frac}");
        assert!((frac - if north { 0.25 } else { 0.75 }).abs() < 1e-12);
    }
}

/// Semi-angle of the test cone (radius 10 at z = 0, widening upwards).
const CONE_ANGLE: f64 = PI / 6.0;

fn cone_surface(f: &mut Step) -> u64 {
    let a = f.axis([0., 0., 0.], [0., 0., 1.], [1., 0., 0.]);
    f.add(format!("CONICAL_SURFACE('',#{a},10.,{CONE_ANGLE:?})"))
}

/// The cone's point at angle u, height z.
fn cone_at(u: f64, z: f64) -> [f64; 3] {
    plus(scale(10.0 + z * CONE_ANGLE.tan(), e(u)), [0.0, 0.0, z])
}

#[test]
fn cones_with_an_apex_and_frustums() {
    let za = -10.0 / CONE_ANGLE.tan();
    let apex = [0.0, 0.0, za];
    // The apex as a vertex loop plus the base circle: the face lies between them whichever its
    // sense (the loop runs westwards seen from outside when the face's normal is the cone's).
    for same_sense in [true, false] {
        let mut f = Step::new();
        let cone = cone_surface(&mut f);
        let c = f.circle([0.; 3], 10.0);
        let ec = f.ring(cone_at(0.0, 0.0), c, true);
        let l = f.loop_of(&[(ec, !same_sense)]);
        let b = f.bound(l, true);
        let vl = f.vertex_loop(apex);
        let bv = f.bound(vl, false);
        f.face_s(&[b, bv], cone, same_sense);
        let s = f.parse();
        let p = trimmed_patch(&s, 0);
        let d = p.surface.domain();
        assert!((d.v[0] - za).abs() < 1e-9 && d.v[1].abs() < 1e-9, "{d:?}");
        let frac = region(p, 48, |_, _| Some(true));
        println!("cone to its apex (same_sense {same_sense}): {d:?}, fraction {frac}");
    }
    // A sector from the apex: up a generator at b, west along the base, down the generator at
    // 0 — the face is [0, b] (wider than a half turn too).
    for b in [PI / 2.0, 1.5 * PI] {
        let mut f = Step::new();
        let cone = cone_surface(&mut f);
        let up = f.segment(apex, cone_at(b, 0.0));
        let c = f.circle([0.; 3], 10.0);
        let arc = f.edge_at(cone_at(0.0, 0.0), cone_at(b, 0.0), c, true);
        let down = f.segment(cone_at(0.0, 0.0), apex);
        let l = f.loop_of(&[(up, true), (arc, false), (down, true)]);
        let bd = f.bound(l, true);
        f.face(&[bd], cone);
        let s = f.parse();
        let p = trimmed_patch(&s, 0);
        let frac = region(p, 48, |u, _| below(ang(u, 0.0), b, 1e-6));
        println!("cone sector [0, {b:.4}]: fraction {frac}");
        assert!((frac - b / TAU).abs() < 1e-12, "{frac}");
    }
    // A frustum between z = 0 and z = 20: two circles, or the seam form.
    for seam_form in [false, true] {
        let mut f = Step::new();
        let cone = cone_surface(&mut f);
        let r1 = 10.0 + 20.0 * CONE_ANGLE.tan();
        let (c0, c1) = (f.circle([0.; 3], 10.0), f.circle([0., 0., 20.], r1));
        if seam_form {
            let (p0, p1) = (cone_at(1.0, 0.0), cone_at(1.0, 20.0));
            let (e0, e1) = (f.ring(p0, c0, true), f.ring(p1, c1, true));
            let d = [p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]];
            let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            let l = f.line(p0, scale(1.0 / len, d));
            let sm = f.seam(l);
            let es = f.edge_at(p0, p1, sm, true);
            let lp = f.loop_of(&[(e0, true), (es, true), (e1, false), (es, false)]);
            let b = f.bound(lp, true);
            f.face(&[b], cone);
        } else {
            let (e0, e1) = (
                f.ring(cone_at(0.0, 0.0), c0, true),
                f.ring(cone_at(0.0, 20.0), c1, true),
            );
            let (l0, l1) = (f.loop_of(&[(e0, true)]), f.loop_of(&[(e1, false)]));
            let (b0, b1) = (f.bound(l0, false), f.bound(l1, false));
            f.face(&[b0, b1], cone);
        }
        let s = f.parse();
        let p = trimmed_patch(&s, 0);
        let d = p.surface.domain();
        assert!(d.v[0].abs() < 1e-9 && (d.v[1] - 20.0).abs() < 1e-9, "{d:?}");
        let frac = region(p, 48, |_, _| Some(true));
        println!("frustum (seam form {seam_form}): fraction {frac}");
        // The loop's points lie on the two circles.
        for q in p.trim.as_ref().unwrap().loops().concat() {
            let x = eval(p, q);
            let r = x.x.hypot(x.y);
            assert!(
                (x.z.abs() < 1e-9 && (r - 10.0).abs() < 1e-9)
                    || ((x.z - 20.0).abs() < 1e-9 && (r - r1).abs() < 1e-9)
                    || seam_form,
                "{q:?} → {x:?}"
            );
        }
    }
}

const TR: f64 = 20.0;
const TS: f64 = 5.0;

fn torus_surface(f: &mut Step) -> u64 {
    let a = f.axis([0., 0., 0.], [0., 0., 1.], [1., 0., 0.]);
    f.add(format!("TOROIDAL_SURFACE('',#{a},{TR:?},{TS:?})"))
}

fn torus_at(u: f64, v: f64) -> [f64; 3] {
    plus(scale(TR + TS * v.cos(), e(u)), [0.0, 0.0, TS * v.sin()])
}

/// The circle of the tube at angle u, its parameter v.
fn tube_circle(f: &mut Step, u: f64) -> u64 {
    f.circle_in(scale(TR, e(u)), [u.sin(), -u.cos(), 0.], e(u), TS)
}

/// The circle around the axis at tube angle v, its parameter u.
fn torus_parallel(f: &mut Step, v: f64) -> u64 {
    f.circle([0., 0., TS * v.sin()], TR + TS * v.cos())
}

#[test]
fn torus_bands_and_a_four_edge_patch() {
    let (a, b) = (-PI / 4.0, PI / 3.0);
    // Bands between two circles of the tube (u = a, u = b) and between two circles around the
    // axis (v = a, v = b): the face, and its complement, from the loops' directions.
    for around_v in [true, false] {
        for complement in [false, true] {
            let mut f = Step::new();
            let t = torus_surface(&mut f);
            // The face lies on the left of each loop seen from outside: going +v it lies at
            // −u, going +u at +v.
            let (lo, hi) = if complement { (b, a + TAU) } else { (a, b) };
            let bounds: Vec<u64> = [(lo, around_v), (hi, !around_v)]
                .into_iter()
                .map(|(x, forward)| {
                    let (c, p) = if around_v {
                        (tube_circle(&mut f, x), torus_at(x, 0.0))
                    } else {
                        (torus_parallel(&mut f, x), torus_at(0.0, x))
                    };
                    let ec = f.ring(p, c, true);
                    // At the low end: going −v (u band), going +u (v band).
                    let l = f.loop_of(&[(ec, !forward)]);
                    f.bound(l, false)
                })
                .collect();
            f.face(&bounds, t);
            let s = f.parse();
            let p = trimmed_patch(&s, 0);
            let frac = region(p, 48, |u, v| {
                let x = if around_v { u } else { v };
                below(ang(x, lo) - lo, hi - lo, 1e-6)
            });
            println!(
                "torus band (around v {around_v}, complement {complement}): {:?}, fraction \
                 {frac:.5}",
                p.surface.domain()
            );
            assert!((frac - (hi - lo) / TAU).abs() < 1.0 / 48.0, "{frac}");
        }
    }
    // u, v ∈ [−π/4, π/4]: two arcs around the axis, two of the tube; the box starts at the
    // loop's corner in both angles.
    let q = PI / 4.0;
    let mut f = Step::new();
    let t = torus_surface(&mut f);
    let (c_lo, c_hi) = (torus_parallel(&mut f, -q), torus_parallel(&mut f, q));
    let (t_lo, t_hi) = (tube_circle(&mut f, -q), tube_circle(&mut f, q));
    let e0 = f.edge_at(torus_at(-q, -q), torus_at(q, -q), c_lo, true);
    let e1 = f.edge_at(torus_at(q, -q), torus_at(q, q), t_hi, true);
    let e2 = f.edge_at(torus_at(-q, q), torus_at(q, q), c_hi, true);
    let e3 = f.edge_at(torus_at(-q, -q), torus_at(-q, q), t_lo, true);
    let l = f.loop_of(&[(e0, true), (e1, true), (e2, false), (e3, false)]);
    let bd = f.bound(l, true);
    f.face(&[bd], t);
    let s = f.parse();
    let p = trimmed_patch(&s, 0);
    let d = p.surface.domain();
    let frac = region(p, 48, |u, v| {
        and(
            below(ang(u, -q) + q, 2.0 * q, 1e-6),
            below(ang(v, -q) + q, 2.0 * q, 1e-6),
        )
    });
    println!("torus patch: {d:?}, fraction {frac}");
    assert!(same_angle(d.u[0], -q) && same_angle(d.v[0], -q), "{d:?}");
    assert!((frac - 1.0 / 16.0).abs() < 1e-12, "{frac}");
    for q2 in p.trim.as_ref().unwrap().loops().concat() {
        let x = eval(p, q2);
        let u = x.y.atan2(x.x);
        let v = x.z.atan2(x.x.hypot(x.y) - TR);
        let on = |a: f64| (a.abs() - q).abs() < 1e-7;
        assert!(on(u) || on(v), "{q2:?} → {x:?}");
    }
}

/// A cylinder of radius 10 around z (the test file's `cylinder`).
fn cylinder_surface(f: &mut Step) -> u64 {
    let a = f.axis([0., 0., 0.], [0., 0., 1.], [1., 0., 0.]);
    f.add(format!("CYLINDRICAL_SURFACE('',#{a},10.)"))
}

fn cyl_at(u: f64, z: f64) -> [f64; 3] {
    plus(scale(10.0, e(u)), [0.0, 0.0, z])
}

/// A loop on the cylinder around u ∈ [a, b], z ∈ [z0, z1]: arcs and lines.
fn cylinder_window(f: &mut Step, (a, b): (f64, f64), (z0, z1): (f64, f64)) -> u64 {
    let (c0, c1) = (f.circle([0., 0., z0], 10.0), f.circle([0., 0., z1], 10.0));
    let bottom = f.edge_at(cyl_at(a, z0), cyl_at(b, z0), c0, true);
    let right = f.segment(cyl_at(b, z0), cyl_at(b, z1));
    let top = f.edge_at(cyl_at(a, z1), cyl_at(b, z1), c1, true);
    let left = f.segment(cyl_at(a, z0), cyl_at(a, z1));
    f.loop_of(&[(bottom, true), (right, true), (top, false), (left, false)])
}

#[test]
fn cylinder_holes_and_outer_loops_across_the_seam() {
    let hole = (-0.3, 0.3);
    let in_hole = |u: f64, v: f64| {
        and(
            below(ang(u, -PI).abs(), 0.3, 1e-6),
            and(below(20.0, v, 1e-6), below(v, 30.0, 1e-6)),
        )
    };
    // The band z ∈ [0, 50] (two circles) with a window across u = 0.
    let mut f = Step::new();
    let cyl = cylinder_surface(&mut f);
    let (c0, c1) = (f.circle([0.; 3], 10.0), f.circle([0., 0., 50.], 10.0));
    let (e0, e1) = (
        f.ring(cyl_at(0.0, 0.0), c0, true),
        f.ring(cyl_at(0.0, 50.0), c1, true),
    );
    let (l0, l1) = (f.loop_of(&[(e0, true)]), f.loop_of(&[(e1, false)]));
    let lh = cylinder_window(&mut f, hole, (20.0, 30.0));
    let (b0, b1, bh) = (f.bound(l0, false), f.bound(l1, false), f.bound(lh, false));
    f.face(&[b0, b1, bh], cyl);
    let s = f.parse();
    let p = trimmed_patch(&s, 0);
    let d = p.surface.domain();
    for (u, v, on) in [
        (0.1, 25.0, false),
        (TAU - 0.1, 25.0, false),
        (0.0, 25.0, false),
        (TAU, 25.0, false),
        (0.5, 25.0, true),
        (TAU - 0.5, 25.0, true),
        (0.1, 31.0, true),
    ] {
        assert_eq!(p.on_part(u, v), on, "({u}, {v})");
    }
    let frac = region(p, 48, |u, v| not(in_hole(u, v)));
    let want = 1.0 - 0.6 * 10.0 / (TAU * 50.0);
    println!("band with a window across the seam: {d:?}, fraction {frac:.5} (area {want:.5})");
    assert!((frac - want).abs() < 0.01, "{frac}");
    // The face u ∈ [−1, 1], z ∈ [0, 50] with the same window: the box starts at the loop.
    let mut f = Step::new();
    let cyl = cylinder_surface(&mut f);
    let lo = cylinder_window(&mut f, (-1.0, 1.0), (0.0, 50.0));
    let lh = cylinder_window(&mut f, hole, (20.0, 30.0));
    let (bo, bh) = (f.bound(lo, true), f.bound(lh, false));
    f.face(&[bo, bh], cyl);
    let s = f.parse();
    let p = trimmed_patch(&s, 0);
    let d = p.surface.domain();
    assert!(same_angle(d.u[0], -1.0), "{d:?}");
    let frac = region(p, 48, |u, v| {
        and(below(ang(u, -PI).abs(), 1.0, 1e-6), not(in_hole(u, v)))
    });
    let want = (2.0 * 50.0 - 0.6 * 10.0) / (TAU * 50.0);
    println!("outer loop across the seam: {d:?}, fraction {frac:.5} (area {want:.5})");
    assert!((frac - want).abs() < 0.01, "{frac}");
    // The loops' points lie on the edges: on a circle z = 0, 20, 30, 50 or a line u = ±0.3, ±1.
    for q in p.trim.as_ref().unwrap().loops().concat() {
        let x = eval(p, q);
        let u = x.y.atan2(x.x);
        assert!((x.x.hypot(x.y) - 10.0).abs() < 1e-9);
        let on_line = [0.3, 1.0].iter().any(|&a| (u.abs() - a).abs() < 1e-7);
        let on_circle = [0.0, 20.0, 30.0, 50.0]
            .iter()
            .any(|&z| (x.z - z).abs() < 1e-9);
        assert!(on_line || on_circle, "{q:?} → {x:?}");
    }
}

#[test]
fn cylinder_cut_by_an_inclined_plane_has_an_elliptical_edge() {
    // The band between z = 0 and the plane z = 30 + x·tan β: its top edge is the ellipse of
    // semi-axes 10/cos β (along (cos β, 0, sin β)) and 10, so v = 30 + 10·tan β·cos u.
    let beta = PI / 6.0;
    let top = |u: f64| 30.0 + 10.0 * beta.tan() * u.cos();
    let mut f = Step::new();
    let cyl = cylinder_surface(&mut f);
    let c = f.circle([0.; 3], 10.0);
    let el = f.ellipse(
        [0., 0., 30.],
        [-beta.sin(), 0., beta.cos()],
        [beta.cos(), 0., beta.sin()],
        10.0 / beta.cos(),
        10.0,
    );
    let ec = f.ring(cyl_at(0.0, 0.0), c, true);
    let ee = f.ring([10.0, 0.0, top(0.0)], el, true);
    let (l0, l1) = (f.loop_of(&[(ec, true)]), f.loop_of(&[(ee, false)]));
    let (b0, b1) = (f.bound(l0, true), f.bound(l1, false));
    f.face(&[b0, b1], cyl);
    let s = f.parse();
    let p = trimmed_patch(&s, 0);
    let d = p.surface.domain();
    assert!(
        d.v[0].abs() < 1e-9 && (d.v[1] - top(0.0)).abs() < 1e-9,
        "{d:?}"
    );
    let frac = region(p, 48, |u, v| below(v, top(u), 1e-2));
    let want = 30.0 / top(0.0);
    println!("band under the ellipse: fraction {frac:.5}, area share {want:.5}");
    assert!((frac - want).abs() < 0.005, "{frac}");
    for k in 0..64 {
        let u = d.u_at(k as f64 / 63.0);
        assert!(
            p.on_part(u, top(u) - 1e-2) && !p.on_part(u, top(u) + 1e-2),
            "{u}"
        );
    }
    for q in p.trim.as_ref().unwrap().loops().concat() {
        let x = eval(p, q);
        assert!(
            x.z.abs() < 1e-9 || (x.z - 30.0 - x.x * beta.tan()).abs() < 1e-9,
            "{x:?}"
        );
    }
}

/// An L (60 × 20 and 20 × 20 more on its left), on the plane z = 0.
const ELL: [[f64; 3]; 6] = [
    [0., 0., 0.],
    [60., 0., 0.],
    [60., 20., 0.],
    [20., 20., 0.],
    [20., 40., 0.],
    [0., 40., 0.],
];
const TRIANGLE: [[f64; 3]; 3] = [[5., 5., 0.], [15., 5., 0.], [5., 15., 0.]];

fn xy_plane(f: &mut Step) -> u64 {
    let a = f.axis([0., 0., 0.], [0., 0., 1.], [1., 0., 0.]);
    f.add(format!("PLANE('',#{a})"))
}

/// The L less the triangle.
fn in_ell(x: f64, y: f64) -> Option<bool> {
    let ell = and(
        and(below(0.0, x, 1e-6), below(x, 60.0, 1e-6)),
        and(below(0.0, y, 1e-6), below(y, 40.0, 1e-6)),
    );
    let notch = and(below(20.0, x, 1e-6), below(20.0, y, 1e-6));
    let tri = and(
        and(below(5.0, x, 1e-6), below(5.0, y, 1e-6)),
        below(x + y, 20.0, 1e-6),
    );
    and(and(ell, not(notch)), not(tri))
}

#[test]
fn poly_loops_and_polyline_edges() {
    for polyline in [false, true] {
        let mut f = Step::new();
        let pl = xy_plane(&mut f);
        let (lo, lh) = if polyline {
            // Two polylines for the L (the second written backwards), one closed polyline for
            // the triangle, its vertex in the middle.
            let a = f.polyline(&ELL[..4]);
            let ea = f.edge_at(ELL[0], ELL[3], a, true);
            let back = [ELL[0], ELL[5], ELL[4], ELL[3]];
            let b = f.polyline(&back);
            let eb = f.edge_at(ELL[0], ELL[3], b, true);
            let lo = f.loop_of(&[(ea, true), (eb, false)]);
            let t = f.polyline(&[TRIANGLE[0], TRIANGLE[1], TRIANGLE[2], TRIANGLE[0]]);
            let et = f.ring(TRIANGLE[1], t, true);
            (lo, f.loop_of(&[(et, true)]))
        } else {
            (f.poly_loop(&ELL), f.poly_loop(&TRIANGLE))
        };
        let (bo, bh) = (f.bound(lo, true), f.bound(lh, false));
        f.face(&[bo, bh], pl);
        let s = f.parse();
        let p = trimmed_patch(&s, 0);
        let frac = region(p, 48, in_ell);
        let want = (1600.0 - 50.0) / 2400.0;
        println!(
            "L with a triangular hole (polylines {polyline}): fraction {frac:.5}, area {want:.5}"
        );
        assert!((frac - want).abs() < 0.01, "{frac}");
    }
}

#[test]
fn trimmed_curve_edges_keep_their_sense() {
    // A half disc over the diameter (30, 0)–(70, 0): the arc a TRIMMED_CURVE of the circle,
    // along it (from (70, 0)) or against it (from (30, 0)); the diameter a TRIMMED_CURVE of a
    // line.
    let (a, b) = ([30., 0., 0.], [70., 0., 0.]);
    for sense in [true, false] {
        let mut f = Step::new();
        let pl = xy_plane(&mut f);
        let line = f.line(a, [1., 0., 0.]);
        let tl = f.trimmed(line, a, b, true);
        let diameter = f.edge_at(a, b, tl, true);
        let c = f.circle([50., 0., 0.], 20.0);
        let arc = if sense {
            let tc = f.trimmed(c, b, a, true);
            (f.edge_at(b, a, tc, true), true)
        } else {
            let tc = f.trimmed(c, a, b, false);
            (f.edge_at(a, b, tc, true), false)
        };
        let l = f.loop_of(&[(diameter, true), arc]);
        let bd = f.bound(l, true);
        f.face(&[bd], pl);
        let s = f.parse();
        let p = trimmed_patch(&s, 0);
        // The box is the half disc's, 40 × 20 mm: it covers π·20²/2 of its 800 mm².
        let d = p.surface.domain();
        let near = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs().max((a[1] - b[1]).abs()) < 1e-9;
        assert!(near(d.u, [30.0, 70.0]) && near(d.v, [0.0, 20.0]), "{d:?}");
        let frac = region(p, 48, |x, y| {
            and(below((x - 50.0).hypot(y), 20.0, 2e-3), below(0.0, y, 1e-6))
        });
        println!("half disc (arc's sense {sense}): {d:?}, fraction {frac:.5}");
        assert!((frac - PI / 4.0).abs() < 0.01, "{frac}");
    }
}

#[test]
fn rational_bspline_circles() {
    // A hole on a plane (its vertex at the curve's start), and the bottom of a cylinder band
    // (its vertex at 45°, within the curve).
    let mut f = Step::new();
    let pl = xy_plane(&mut f);
    let c = [[0., 0., 0.], [100., 0., 0.], [100., 60., 0.], [0., 60., 0.]];
    let edges: Vec<(u64, bool)> = (0..4)
        .map(|k| (f.segment(c[k], c[(k + 1) % 4]), true))
        .collect();
    let outer = f.loop_of(&edges);
    let rc = f.rational_circle([30., 30., 0.], 10.0);
    let eh = f.ring([40., 30., 0.], rc, true);
    let hole = f.loop_of(&[(eh, false)]);
    let (bo, bh) = (f.bound(outer, true), f.bound(hole, false));
    f.face(&[bo, bh], pl);
    let s = f.parse();
    let p = trimmed_patch(&s, 0);
    let t = p.trim.as_ref().unwrap();
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for q in &t.holes()[0] {
        let r = (q[0] - 30.0).hypot(q[1] - 30.0);
        lo = lo.min(r);
        hi = hi.max(r);
    }
    println!(
        "rational circle hole: {} points, radius in [{lo}, {hi}]",
        t.holes()[0].len()
    );
    assert!(lo > 10.0 - 1.1e-3 && hi < 10.0 + 1e-9, "[{lo}, {hi}]");
    let frac = region(p, 48, |x, y| {
        not(below((x - 30.0).hypot(y - 30.0), 10.0, 2e-3))
    });
    assert!((frac - (1.0 - PI * 100.0 / 6000.0)).abs() < 0.01, "{frac}");

    let mut f = Step::new();
    let cyl = cylinder_surface(&mut f);
    let rc = f.rational_circle([0.; 3], 10.0);
    let e0 = f.ring(cyl_at(PI / 4.0, 0.0), rc, true);
    let c1 = f.circle([0., 0., 50.], 10.0);
    let e1 = f.ring(cyl_at(0.0, 50.0), c1, true);
    let (l0, l1) = (f.loop_of(&[(e0, true)]), f.loop_of(&[(e1, false)]));
    let (b0, b1) = (f.bound(l0, false), f.bound(l1, false));
    f.face(&[b0, b1], cyl);
    let s = f.parse();
    let p = trimmed_patch(&s, 0);
    let d = p.surface.domain();
    assert!(
        d.v == [0.0, 50.0] && (d.u[1] - d.u[0] - TAU).abs() < 1e-12,
        "{d:?}"
    );
    let frac = region(p, 48, |_, _| Some(true));
    println!("cylinder band on a rational circle: {d:?}, fraction {frac}");
    for q in p.trim.as_ref().unwrap().loops().concat() {
        let x = eval(p, q);
        assert!(x.z.abs() < 1e-9 || (x.z - 50.0).abs() < 1e-9, "{x:?}");
    }
}

#[test]
fn a_window_in_a_step_face_is_off_the_part() {
    // A floor z = 0 over [0, 20]² and, 5 mm above it, a ceiling facing down with a window
    // x ∈ [6, 14], y ∈ [7, 13] (swarf-plan's `step_window_limits_the_cutter` sizes a flat end
    // mill under the same files, kept in its tests/fixtures).
    for window in [true, false] {
        let part = step::parse(&window_part(window)).unwrap();
        assert_eq!(part.patches.len(), 2);
        assert_eq!(part.patches[1].on_part(10.0, -10.0), !window);
        assert!(part.patches[1].on_part(10.0, -5.0));
    }
}

/// The floor and the ceiling (with or without its window) as STEP text.
fn window_part(window: bool) -> String {
    let mut f = Step::new();
    let floor = xy_plane(&mut f);
    let sq = |f: &mut Step, z: f64, (x0, x1): (f64, f64), (y0, y1): (f64, f64)| {
        let c = [[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z]];
        let edges: Vec<(u64, bool)> = (0..4)
            .map(|k| (f.segment(c[k], c[(k + 1) % 4]), true))
            .collect();
        f.loop_of(&edges)
    };
    let l = sq(&mut f, 0.0, (0.0, 20.0), (0.0, 20.0));
    let b = f.bound(l, true);
    f.face(&[b], floor);
    let a = f.axis([0., 0., 5.], [0., 0., -1.], [1., 0., 0.]);
    let ceiling = f.add(format!("PLANE('',#{a})"));
    let l = sq(&mut f, 5.0, (0.0, 20.0), (0.0, 20.0));
    let mut bounds = vec![f.bound(l, true)];
    if window {
        let h = sq(&mut f, 5.0, (6.0, 14.0), (7.0, 13.0));
        bounds.push(f.bound(h, false));
    }
    f.face(&bounds, ceiling);
    f.text()
}

/// A half cylinder (r 10, z 0…50) whose end arcs are polylines of `n` chords (they sag
/// 10·(1 − cos(π/2n)) off the surface), in a file declaring `accuracy` mm.
fn polyline_half_cylinder(n: usize, accuracy: Option<f64>) -> CompoundSurface {
    let mut f = Step::new();
    let a = f.axis([0., 0., 0.], [0., 0., 1.], [1., 0., 0.]);
    let cyl = f.add(format!("CYLINDRICAL_SURFACE('',#{a},10.)"));
    let v = [
        f.vertex([10., 0., 0.]),
        f.vertex([-10., 0., 0.]),
        f.vertex([-10., 0., 50.]),
        f.vertex([10., 0., 50.]),
    ];
    let arc = |z: f64| -> Vec<[f64; 3]> {
        (0..=n)
            .map(|k| {
                let t = PI * k as f64 / n as f64;
                [10.0 * t.cos(), 10.0 * t.sin(), z]
            })
            .collect()
    };
    let (p0, p1) = (f.polyline(&arc(0.0)), f.polyline(&arc(50.0)));
    let bottom = f.edge(v[0], v[1], p0, true);
    let l1 = f.line([-10., 0., 0.], [0., 0., 1.]);
    let left = f.edge(v[1], v[2], l1, true);
    let top = f.edge(v[3], v[2], p1, true);
    let l2 = f.line([10., 0., 0.], [0., 0., 1.]);
    let right = f.edge(v[0], v[3], l2, true);
    let lp = f.loop_of(&[(bottom, true), (left, true), (top, false), (right, false)]);
    let b = f.bound(lp, true);
    f.face(&[b], cyl);
    if let Some(acc) = accuracy {
        let mm = f.add("(LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.))");
        let u = f.add(format!(
            "UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE({acc:?}),#{mm},\
             'distance_accuracy_value','confusion accuracy')"
        ));
        f.add(format!(
            "(GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#{u})) \
             GLOBAL_UNIT_ASSIGNED_CONTEXT((#{mm})) REPRESENTATION_CONTEXT('',''))"
        ));
    }
    f.parse()
}

#[test]
fn edges_a_few_microns_off_their_face_or_within_the_declared_accuracy_trim_it() {
    let honoured = |s: &CompoundSurface| {
        let t = s.patches[0].trim.as_ref();
        t.is_some_and(|t| t.contains(0.5 * PI, 25.0) && !t.contains(1.5 * PI, 25.0))
    };
    // 40 chords sag 7.7 µm: CAD edges lie that far off their faces; the trim holds.
    let s = polyline_half_cylinder(40, None);
    assert!(honoured(&s), "{:?}", trimmed_notes(&s));
    // 20 chords sag 31 µm: too far by default, within a declared 0.05 mm accuracy.
    let s = polyline_half_cylinder(20, None);
    assert!(!honoured(&s), "{:?}", trimmed_notes(&s));
    assert!(s
        .notes
        .iter()
        .any(|n| matches!(n, ReadNote::TrimNotHonoured { .. })));
    let s = polyline_half_cylinder(20, Some(0.05));
    assert!(honoured(&s), "{:?}", trimmed_notes(&s));
}

#[test]
fn a_face_is_gridded_over_its_own_box_not_its_whole_surface() {
    // A 14° window of the radius-10 cylinder, u ∈ [0.35, 0.35 + 14°], z ∈ [0, 30]: the
    // parameter box was the whole turn, whose 21 × 21 grid (columns 18° apart, at 0.314 and
    // 0.628) has no point on the face — toolsize gave it none, silently.
    let w = 14f64.to_radians();
    let mut f = Step::new();
    let cyl = cylinder_surface(&mut f);
    let l = cylinder_window(&mut f, (0.35, 0.35 + w), (0.0, 30.0));
    let b = f.bound(l, true);
    f.face(&[b], cyl);
    let s = f.parse();
    let p = trimmed_patch(&s, 0);
    let d = p.surface.domain();
    assert!(
        (d.u[0] - 0.35).abs() < 1e-9 && (d.u[1] - 0.35 - w).abs() < 1e-9 && d.v == [0.0, 30.0],
        "{d:?}"
    );
    let grid = s.grid(21);
    assert_eq!(grid.len(), 21 * 21);
    assert!(s.patches_off_grid(21).is_empty());
    for c in &grid {
        let q = p.surface.point(c.u, c.v);
        let a = q.y.atan2(q.x);
        assert!((0.35 - 1e-9..=0.35 + w + 1e-9).contains(&a), "{q}");
    }
    // A B-spline face (the plane z = 0 over [0, 100]², u = x/100, v = y/100) bounded by the
    // square [20, 40] × [60, 70]: its surface is cut down to the square's box, exactly.
    let mut f = Step::new();
    let pts: Vec<Vec<u64>> = (0..2)
        .map(|i| {
            (0..2)
                .map(|j| f.pt([100.0 * i as f64, 100.0 * j as f64, 0.0]))
                .collect()
        })
        .collect();
    let sid = f.add(format!(
        "B_SPLINE_SURFACE_WITH_KNOTS('',1,1,((#{},#{}),(#{},#{})),.UNSPECIFIED.,.F.,.F.,.F.,\
         (2,2),(2,2),(0.,1.),(0.,1.),.UNSPECIFIED.)",
        pts[0][0], pts[0][1], pts[1][0], pts[1][1]
    ));
    let l = f.poly_loop(&[
        [20., 60., 0.],
        [40., 60., 0.],
        [40., 70., 0.],
        [20., 70., 0.],
    ]);
    let b = f.bound(l, true);
    f.face(&[b], sid);
    let s = f.parse();
    let p = trimmed_patch(&s, 0);
    let d = p.surface.domain();
    let near = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs().max((a[1] - b[1]).abs()) < 1e-9;
    assert!(near(d.u, [0.2, 0.4]) && near(d.v, [0.6, 0.7]), "{d:?}");
    assert_eq!(s.grid(5).len(), 25);
    let q = p.surface.point(0.3, 0.65);
    assert!((q - Vec3::new(30.0, 65.0, 0.0)).length() < 1e-9, "{q}");
}
