//! STEP faces reversed by the topology that holds them: `ORIENTED_FACE`, `ORIENTED_OPEN_SHELL`
//! and `ORIENTED_CLOSED_SHELL` with orientation `.F.` flip the material side of their face (of
//! every face of their shell), reversals compose, the voids of a `BREP_WITH_VOIDS` come out
//! reversed, and a face two solids use both ways is read once each way. The region a face's
//! bounds enclose does not change.

mod common;
use common::step::Step;

use swarf_geom::math::Vec3;
use swarf_surface::io::{step, ReadError};
use swarf_surface::{ParametricSurface, Patch, SurfaceNormal, Tolerances};

const TOL: Tolerances = Tolerances::DEFAULT;

impl Step {
    /// The reviewer's concave trough (`/tmp/geo-review/mk9.py`): the quarter of a cylinder of
    /// radius 10 along +y (axis at z = 10, 20 long) between ±45° around its lowest line,
    /// bounded by two arcs and two lines, with same_sense .F.: the material is below, the
    /// cutter comes from the axis side. The ADVANCED_FACE's number.
    fn trough(&mut self) -> u64 {
        let c = std::f64::consts::FRAC_1_SQRT_2 * 10.0;
        let z = 10.0 - c;
        let corners = [[-c, 0.0, z], [c, 0.0, z], [c, 20.0, z], [-c, 20.0, z]];
        let v: Vec<u64> = corners
            .iter()
            .map(|&p| {
                let q = self.point(p);
                self.add(format!("VERTEX_POINT('',#{q})"))
            })
            .collect();
        let a0 = self.axis([0.0, 0.0, 10.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]);
        let c0 = self.add(format!("CIRCLE('',#{a0},10.0)"));
        let a1 = self.axis([0.0, 20.0, 10.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]);
        let c1 = self.add(format!("CIRCLE('',#{a1},10.0)"));
        let line = |s: &mut Step, from: [f64; 3], dy: f64| {
            let d = s.add(format!("DIRECTION('',(0.0,{dy:?},0.0))"));
            let vec = s.add(format!("VECTOR('',#{d},20.0)"));
            let p = s.point(from);
            s.add(format!("LINE('',#{p},#{vec})"))
        };
        let l0 = line(self, corners[1], 1.0);
        let l1 = line(self, corners[3], -1.0);
        let e = [
            self.add(format!("EDGE_CURVE('',#{},#{},#{c0},.F.)", v[0], v[1])),
            self.add(format!("EDGE_CURVE('',#{},#{},#{l0},.T.)", v[1], v[2])),
            self.add(format!("EDGE_CURVE('',#{},#{},#{c1},.T.)", v[2], v[3])),
            self.add(format!("EDGE_CURVE('',#{},#{},#{l1},.T.)", v[3], v[0])),
        ];
        let oe: Vec<String> = e
            .iter()
            .map(|&e| format!("#{}", self.add(format!("ORIENTED_EDGE('',*,*,#{e},.T.)"))))
            .collect();
        let lp = self.add(format!("EDGE_LOOP('',({}))", oe.join(",")));
        let ax = self.axis([0.0, 0.0, 10.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]);
        let s = self.add(format!("CYLINDRICAL_SURFACE('',#{ax},10.0)"));
        let b = self.add(format!("FACE_OUTER_BOUND('',#{lp},.T.)"));
        self.add(format!("ADVANCED_FACE('trough',(#{b}),#{s},.F.)"))
    }

    /// A whole sphere of `radius` about the origin as a face with same_sense .T. (normal
    /// outwards, away from the centre).
    fn sphere(&mut self, name: &str, radius: f64) -> u64 {
        let ax = self.axis([0.0; 3], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
        let s = self.add(format!("SPHERICAL_SURFACE('',#{ax},{radius:?})"));
        self.add(format!("ADVANCED_FACE('{name}',(),#{s},.T.)"))
    }

    /// `SHELL_BASED_SURFACE_MODEL` of `shell` in a MANIFOLD_SURFACE_SHAPE_REPRESENTATION.
    fn surface_model(&mut self, shell: u64) {
        let ctx = self.context(false);
        let m = self.add(format!("SHELL_BASED_SURFACE_MODEL('',(#{shell}))"));
        self.add(format!(
            "MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',(#{m}),#{ctx})"
        ));
    }
}

/// The trough's lowest line, (0, y, 0), is at angle 0 (the axis's x is −z), a whole turn on
/// in the parameter box, which starts at the outer loop's angle: the cylinder's own normal
/// there (S_u × S_v, away from the axis) is −z.
fn normal_at_bottom(p: &Patch) -> Vec3 {
    let tau = std::f64::consts::TAU;
    let u = tau * (p.surface.domain().u[0] / tau).ceil();
    match p.point_normal(u, 10.0, &TOL) {
        (q, SurfaceNormal::Regular(n)) => {
            assert!((q - Vec3::new(0.0, 10.0, 0.0)).length() < 1e-12, "{q:?}");
            n
        }
        (_, other) => panic!("{other:?}"),
    }
}

/// The trough alone, in an open shell: read as written (flipped, normal up).
fn plain() -> Patch {
    let mut s = Step::default();
    let f = s.trough();
    let sh = s.add(format!("OPEN_SHELL('',(#{f}))"));
    s.surface_model(sh);
    let r = s.parse();
    assert_eq!(r.patches.len(), 1);
    r.patches[0].clone()
}

#[test]
fn an_oriented_face_or_shell_reverses_the_face_s_side() {
    let plain = plain();
    assert!(plain.flipped);
    let n = normal_at_bottom(&plain);
    assert!((n - Vec3::Z).length() < 1e-12, "{n:?}");
    assert!(plain.trim.is_some());
    // (wrapping, flipped): the face wrapped in an ORIENTED_FACE, an ORIENTED_OPEN_SHELL, both,
    // or an ORIENTED_CLOSED_SHELL in a solid, with orientation .F. or .T.
    type Wrap = fn(&mut Step, u64) -> u64;
    let cases: [(&str, Wrap, bool); 7] = [
        (
            "ORIENTED_FACE .F.",
            |s, f| {
                let o = s.add(format!("ORIENTED_FACE('',*,#{f},.F.)"));
                s.add(format!("OPEN_SHELL('',(#{o}))"))
            },
            false,
        ),
        (
            "ORIENTED_FACE .T.",
            |s, f| {
                let o = s.add(format!("ORIENTED_FACE('',*,#{f},.T.)"));
                s.add(format!("OPEN_SHELL('',(#{o}))"))
            },
            true,
        ),
        (
            "ORIENTED_OPEN_SHELL .F.",
            |s, f| {
                let sh = s.add(format!("OPEN_SHELL('',(#{f}))"));
                s.add(format!("ORIENTED_OPEN_SHELL('',*,#{sh},.F.)"))
            },
            false,
        ),
        (
            "ORIENTED_OPEN_SHELL .T.",
            |s, f| {
                let sh = s.add(format!("OPEN_SHELL('',(#{f}))"));
                s.add(format!("ORIENTED_OPEN_SHELL('',*,#{sh},.T.)"))
            },
            true,
        ),
        (
            "ORIENTED_FACE .F. in ORIENTED_OPEN_SHELL .F.",
            |s, f| {
                let o = s.add(format!("ORIENTED_FACE('',*,#{f},.F.)"));
                let sh = s.add(format!("OPEN_SHELL('',(#{o}))"));
                s.add(format!("ORIENTED_OPEN_SHELL('',*,#{sh},.F.)"))
            },
            true,
        ),
        (
            "ORIENTED_FACE .F. in ORIENTED_CLOSED_SHELL .F.",
            |s, f| {
                let o = s.add(format!("ORIENTED_FACE('',*,#{f},.F.)"));
                let sh = s.add(format!("CLOSED_SHELL('',(#{o}))"));
                s.add(format!("ORIENTED_CLOSED_SHELL('',*,#{sh},.F.)"))
            },
            true,
        ),
        (
            "ORIENTED_FACE .F. in ORIENTED_CLOSED_SHELL .T.",
            |s, f| {
                let o = s.add(format!("ORIENTED_FACE('',*,#{f},.F.)"));
                let sh = s.add(format!("CLOSED_SHELL('',(#{o}))"));
                s.add(format!("ORIENTED_CLOSED_SHELL('',*,#{sh},.T.)"))
            },
            false,
        ),
    ];
    for (what, wrap, flipped) in cases {
        let mut s = Step::default();
        let f = s.trough();
        let shell = wrap(&mut s, f);
        // A closed shell is the outer shell of a solid; an open one a surface model's.
        if s.lines[shell as usize - 1].contains("CLOSED_SHELL") {
            let ctx = s.context(false);
            let b = s.add(format!("MANIFOLD_SOLID_BREP('',#{shell})"));
            s.add(format!(
                "ADVANCED_BREP_SHAPE_REPRESENTATION('',(#{b}),#{ctx})"
            ));
        } else {
            s.surface_model(shell);
        }
        // A colour on the face itself says nothing about its side.
        s.add(format!("STYLED_ITEM('colour',(),#{f})"));
        let r = s.parse();
        assert_eq!(r.patches.len(), 1, "{what}");
        let p = &r.patches[0];
        assert_eq!(p.flipped, flipped, "{what}");
        let up = if flipped { Vec3::Z } else { -Vec3::Z };
        let n = normal_at_bottom(p);
        assert!((n - up).length() < 1e-12, "{what}: {n:?}");
        // Only the side changes: the same surface, the same region of it.
        assert_eq!(p.surface, plain.surface, "{what}");
        assert_eq!(p.trim, plain.trim, "{what}");
        assert_eq!(p.name, plain.name, "{what}");
    }
}

#[test]
fn the_voids_of_a_brep_with_voids_come_out_reversed() {
    // A ball of radius 20 with a spherical void of radius 5: both faces written with
    // same_sense .T. (normals away from the centre) in their own closed shells, the void's
    // listed as ORIENTED_CLOSED_SHELL .F., as the standard has it. On the void the material is
    // outside, so the cutter side is towards the centre.
    let mut s = Step::default();
    let ctx = s.context(false);
    let outer_face = s.sphere("outer", 20.0);
    let void_face = s.sphere("void", 5.0);
    let outer = s.add(format!("CLOSED_SHELL('',(#{outer_face}))"));
    let void = s.add(format!("CLOSED_SHELL('',(#{void_face}))"));
    let oriented = s.add(format!("ORIENTED_CLOSED_SHELL('',*,#{void},.F.)"));
    let b = s.add(format!("BREP_WITH_VOIDS('',#{outer},(#{oriented}))"));
    s.add(format!(
        "ADVANCED_BREP_SHAPE_REPRESENTATION('',(#{b}),#{ctx})"
    ));
    let r = s.parse();
    assert_eq!(r.patches.len(), 2);
    let (o, v) = (&r.patches[0], &r.patches[1]);
    assert_eq!(o.name.as_deref(), Some("outer"));
    assert_eq!(v.name.as_deref(), Some("void"));
    assert!(!o.flipped);
    assert!(v.flipped);
    // u = 0, v = 0: the point on +x.
    let n = |p: &Patch| match p.point_normal(0.0, 0.0, &TOL).1 {
        SurfaceNormal::Regular(n) => n,
        other => panic!("{other:?}"),
    };
    assert!((n(o) - Vec3::X).length() < 1e-15, "{:?}", n(o));
    assert!((n(v) + Vec3::X).length() < 1e-15, "{:?}", n(v));
}

#[test]
fn a_face_two_solids_use_both_ways_is_read_once_each_way() {
    // The wall between two solids: the first solid's shell holds it as written, the second's
    // reversed. Material on both sides: one patch each way, same surface and trim.
    let mut s = Step::default();
    let ctx = s.context(false);
    let f = s.trough();
    let a = s.add(format!("CLOSED_SHELL('',(#{f}))"));
    let o = s.add(format!("ORIENTED_FACE('',*,#{f},.F.)"));
    let b = s.add(format!("CLOSED_SHELL('',(#{o}))"));
    let sa = s.add(format!("MANIFOLD_SOLID_BREP('a',#{a})"));
    let sb = s.add(format!("MANIFOLD_SOLID_BREP('b',#{b})"));
    s.add(format!(
        "ADVANCED_BREP_SHAPE_REPRESENTATION('',(#{sa},#{sb}),#{ctx})"
    ));
    let r = s.parse();
    assert_eq!(r.patches.len(), 2);
    assert!(r.patches[0].flipped);
    assert!(!r.patches[1].flipped);
    assert_eq!(r.patches[0].surface, r.patches[1].surface);
    assert_eq!(r.patches[0].trim, r.patches[1].trim);
    // The trim note is told of each patch.
    let trimmed: Vec<usize> = r
        .notes
        .iter()
        .filter_map(|n| match n {
            swarf_surface::ReadNote::Trimmed { patch, .. } => Some(*patch),
            _ => None,
        })
        .collect();
    assert_eq!(trimmed, [0, 1]);
}

#[test]
fn a_malformed_orientation_names_its_entity() {
    let mut s = Step::default();
    let f = s.trough();
    let o = s.add(format!("ORIENTED_FACE('',*,#{f},$)"));
    let sh = s.add(format!("OPEN_SHELL('',(#{o}))"));
    s.surface_model(sh);
    match step::parse(&s.text()) {
        Err(ReadError::Entity {
            entity,
            line,
            message,
            ..
        }) => {
            assert_eq!(entity, format!("#{o}"));
            assert_eq!(line, o as usize + 5);
            assert!(
                message.contains("ORIENTED_FACE orientation: found $"),
                "{message}"
            );
        }
        other => panic!("{other:?}"),
    }
}
