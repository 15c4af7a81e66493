//! STEP surfaces outside faces: free surfaces in a file that also has faces (a
//! `GEOMETRIC_SET` of a `GEOMETRICALLY_BOUNDED_SURFACE_SHAPE_REPRESENTATION` beside a B-rep),
//! each read once; and `CURVE_BOUNDED_SURFACE`s, read as their basis trimmed by their
//! boundaries (parameter-space pcurves, model-space curves, holes, an implicit outer boundary),
//! or, when a boundary cannot be read, as the whole basis with the trim said not honoured —
//! never the whole basis while saying the surface was skipped.

mod common;
use common::step::Step;

use std::f64::consts::FRAC_1_SQRT_2;

use swarf_surface::{CompoundSurface, EntityRef, ParametricSurface, ReadNote, UnhonouredTrim};

impl Step {
    fn ids(&mut self, v: &[u64]) -> String {
        v.iter()
            .map(|i| format!("#{i}"))
            .collect::<Vec<_>>()
            .join(",")
    }

    /// A plane through `o` normal to +z (x along +x).
    fn plane_at(&mut self, o: [f64; 3]) -> u64 {
        let a = self.axis(o, [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
        self.add(format!("PLANE('',#{a})"))
    }

    /// The half cylinder y² + z² = 100, z ≤ 0, along x from 0 to 50, as a rational quadratic
    /// B-spline: u ∈ [0, 1] round the half circle from y = −10 (two quarter arcs, the knot 0.5
    /// at the bottom), v ∈ [0, 50] the height x (x = v exactly).
    fn trough(&mut self) -> u64 {
        let w = FRAC_1_SQRT_2;
        let yz = [
            (-10.0, 0.0, 1.0),
            (-10.0, -10.0, w),
            (0.0, -10.0, 1.0),
            (10.0, -10.0, w),
            (10.0, 0.0, 1.0),
        ];
        let mut rows = Vec::new();
        let mut weights = Vec::new();
        for (y, z, wt) in yz {
            let (a, b) = (self.point([0.0, y, z]), self.point([50.0, y, z]));
            rows.push(format!("(#{a},#{b})"));
            weights.push(format!("({wt:?},{wt:?})"));
        }
        self.add(format!(
            "( BOUNDED_SURFACE() B_SPLINE_SURFACE(2,1,({}),.UNSPECIFIED.,.F.,.F.,.F.) \
             B_SPLINE_SURFACE_WITH_KNOTS((3,2,3),(2,2),(0.,0.5,1.),(0.,50.),.UNSPECIFIED.) \
             GEOMETRIC_REPRESENTATION_ITEM() RATIONAL_B_SPLINE_SURFACE(({})) \
             REPRESENTATION_ITEM('') SURFACE() )",
            rows.join(","),
            weights.join(",")
        ))
    }

    /// A 2-D context and a pcurve on `surface` along the closed polyline `uv`.
    fn pcurve_polyline(&mut self, surface: u64, uv: &[[f64; 2]]) -> u64 {
        let ctx = self.add(
            "( GEOMETRIC_REPRESENTATION_CONTEXT(2) PARAMETRIC_REPRESENTATION_CONTEXT() \
             REPRESENTATION_CONTEXT('2D SPACE','') )",
        );
        let pts: Vec<u64> = uv
            .iter()
            .map(|q| self.add(format!("CARTESIAN_POINT('',({:?},{:?}))", q[0], q[1])))
            .collect();
        let list = self.ids(&pts);
        let pl = self.add(format!("POLYLINE('',({list}))"));
        let dr = self.add(format!("DEFINITIONAL_REPRESENTATION('',(#{pl}),#{ctx})"));
        self.add(format!("PCURVE('',#{surface},#{dr})"))
    }

    /// A boundary curve (`kind`: BOUNDARY_CURVE or OUTER_BOUNDARY_CURVE) of one segment along
    /// `parent`.
    fn boundary(&mut self, kind: &str, parent: u64) -> u64 {
        let seg = self.add(format!(
            "COMPOSITE_CURVE_SEGMENT(.CONTINUOUS.,.T.,#{parent})"
        ));
        self.add(format!("{kind}('',(#{seg}),.F.)"))
    }

    /// A circle of radius `r` about `c` in the plane z = c.z, as a model-space surface curve.
    fn surface_circle(&mut self, c: [f64; 3], r: f64) -> u64 {
        let a = self.axis(c, [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
        let circle = self.add(format!("CIRCLE('',#{a},{r:?})"));
        self.add(format!("SURFACE_CURVE('',#{circle},(),.CURVE_3D.)"))
    }
}

/// The patches read from surface instance `id`.
fn from(s: &CompoundSurface, id: u64) -> usize {
    s.patches
        .iter()
        .filter(|p| matches!(p.source.entity, EntityRef::Step { surface, .. } if surface == id))
        .count()
}

#[test]
fn free_surfaces_beside_faces_are_read_each_once() {
    // A roof face at z = 0 in a surface model, and beside it a GEOMETRIC_SET holding a free
    // floor at z = −5 (a rectangular trim of a plane, ±100 mm), the roof's own plane again,
    // and a surface of a kind that is not read. The floor was dropped without a word (and a
    // check against the file certified a program that plunged into it).
    let mut s = Step::default();
    let ctx = s.context(false);
    let roof_plane = s.plane_at([0.0; 3]);
    let corners: Vec<u64> = [[0.0, -10.0], [50.0, -10.0], [50.0, 10.0], [0.0, 10.0]]
        .iter()
        .map(|c| s.point([c[0], c[1], 0.0]))
        .collect();
    let list = s.ids(&corners);
    let lp = s.add(format!("POLY_LOOP('',({list}))"));
    let b = s.add(format!("FACE_OUTER_BOUND('',#{lp},.T.)"));
    let roof = s.add(format!("ADVANCED_FACE('roof',(#{b}),#{roof_plane},.T.)"));
    let shell = s.add(format!("OPEN_SHELL('',(#{roof}))"));
    let model = s.add(format!("SHELL_BASED_SURFACE_MODEL('',(#{shell}))"));
    let origin = s.axis([0.0; 3], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
    s.add(format!(
        "MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',(#{origin},#{model}),#{ctx})"
    ));
    let floor_plane = s.plane_at([0.0, 0.0, -5.0]);
    let floor = s.add(format!(
        "RECTANGULAR_TRIMMED_SURFACE('floor',#{floor_plane},-100.,100.,-100.,100.,.T.,.T.)"
    ));
    let a = s.axis([0.0; 3], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
    let odd = s.add(format!(
        "DEGENERATE_TOROIDAL_SURFACE('odd',#{a},15.0,10.0,.F.)"
    ));
    let set = s.add(format!("GEOMETRIC_SET('',(#{floor},#{roof_plane},#{odd}))"));
    s.add(format!(
        "GEOMETRICALLY_BOUNDED_SURFACE_SHAPE_REPRESENTATION('',(#{set}),#{ctx})"
    ));
    // A plane nothing refers to (a datum an exporter left behind) is in no shape: not read
    // (read, it added a ±100 mm plane at x = 0 to the design: gouges that are not).
    let datum_axis = s.axis([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
    let datum = s.add(format!("PLANE('datum',#{datum_axis})"));
    let part = s.parse();
    assert_eq!(from(&part, datum), 0);
    assert_eq!(part.patches.len(), 2, "{:?}", part.notes);
    assert_eq!(part.patches[0].name.as_deref(), Some("roof"));
    assert_eq!(part.patches[1].name.as_deref(), Some("floor"));
    // The roof's plane once (its face's), the floor's basis only through the floor.
    assert_eq!(from(&part, roof_plane), 1);
    assert_eq!(from(&part, floor), 1);
    assert_eq!(from(&part, floor_plane), 0);
    let d = part.patches[1].surface.domain();
    assert_eq!((d.u, d.v), ([-100.0, 100.0], [-100.0, 100.0]));
    for c in part.grid(5).iter().filter(|c| c.patch == 1) {
        let q = part.patches[1].surface.point(c.u, c.v);
        assert!((q.z + 5.0).abs() < 1e-12 && q.x.abs() <= 100.0 && q.y.abs() <= 100.0);
    }
    // The surface that is not read is said, and counted.
    let caveats = part.caveats();
    assert_eq!(caveats.skipped_faces, 1, "{caveats:?}");
    assert!(
        caveats.skipped_face_notes[0]
            .starts_with(&format!("#{odd}: surface type DEGENERATE_TOROIDAL_SURFACE")),
        "{caveats:?}"
    );
}

#[test]
fn a_curve_bounded_bspline_is_its_basis_within_its_pcurve() {
    // The trough bounded by a pcurve rectangle u ∈ [0.25, 0.75], v ∈ [10, 40]: the bottom of
    // the trough from x = 10 to 40. The reader said it skipped the surface, and read its basis
    // whole (x from 0 to 50) as a patch of its own.
    let mut s = Step::default();
    s.context(false);
    let basis = s.trough();
    let rect = [
        [0.25, 10.0],
        [0.75, 10.0],
        [0.75, 40.0],
        [0.25, 40.0],
        [0.25, 10.0],
    ];
    let pc = s.pcurve_polyline(basis, &rect);
    let b = s.boundary("BOUNDARY_CURVE", pc);
    let cbs = s.add(format!(
        "CURVE_BOUNDED_SURFACE('patch',#{basis},(#{b}),.F.)"
    ));
    let part = s.parse();
    assert_eq!(part.patches.len(), 1, "{:?}", part.notes);
    let p = &part.patches[0];
    assert_eq!(p.name.as_deref(), Some("patch"));
    assert!(part.caveats().is_empty(), "{:?}", part.notes);
    assert!(part.notes.iter().any(|n| matches!(
        n,
        ReadNote::Trimmed { patch: 0, by, loops: 1, .. }
            if *by == format!("STEP curve-bounded surface #{cbs}")
    )));
    // The box is the boundary's, the region all of it (the pcurve is a rectangle there).
    let d = p.surface.domain();
    assert_eq!((d.u, d.v), ([0.25, 0.75], [10.0, 40.0]));
    let t = p.trim.as_ref().unwrap();
    assert!(t.contains(0.5, 25.0) && t.contains(0.25, 10.0) && t.contains(0.75, 40.0));
    assert!(!t.contains(0.5, 9.0) && !t.contains(0.2, 25.0) && !t.contains(0.5, 41.0));
    let grid = part.grid(9);
    assert_eq!(grid.len(), 81);
    for c in grid {
        let q = p.surface.point(c.u, c.v);
        assert!((q.y.hypot(q.z) - 10.0).abs() < 1e-9, "{q}");
        assert!(
            (10.0 - 1e-9..=40.0 + 1e-9).contains(&q.x) && q.z <= -5.0,
            "{q}"
        );
    }
}

#[test]
fn model_space_boundaries_holes_and_an_implicit_outer_boundary() {
    // A plane at z = 0 bounded by a circle of radius 20 about the origin with a hole of
    // radius 5 (both model-space surface curves): the larger loop is the outer one.
    let mut s = Step::default();
    s.context(false);
    let basis = s.plane_at([0.0; 3]);
    let (outer, hole) = (
        s.surface_circle([0.0; 3], 20.0),
        s.surface_circle([0.0; 3], 5.0),
    );
    let (bo, bh) = (
        s.boundary("BOUNDARY_CURVE", outer),
        s.boundary("BOUNDARY_CURVE", hole),
    );
    s.add(format!(
        "CURVE_BOUNDED_SURFACE('ring',#{basis},(#{bh},#{bo}),.F.)"
    ));
    let part = s.parse();
    assert_eq!(part.patches.len(), 1, "{:?}", part.notes);
    assert!(part.caveats().is_empty(), "{:?}", part.notes);
    // The box is the outer circle's (the plane's default ±100 mm is not used, nor said).
    assert!(!part
        .notes
        .iter()
        .any(|n| matches!(n, ReadNote::DefaultParameterBox { .. })));
    let p = &part.patches[0];
    let d = p.surface.domain();
    for r in [d.u, d.v] {
        assert!(
            (r[0] + 20.0).abs() < 1e-9 && (r[1] - 20.0).abs() < 1e-9,
            "{d:?}"
        );
    }
    for (x, y, on) in [
        (0.0, 0.0, false),
        (4.0, 0.0, false),
        (6.0, 0.0, true),
        (0.0, -19.0, true),
        (14.0, 14.5, false),
        (14.0, 14.0, true),
    ] {
        assert_eq!(p.on_part(x, y), on, "({x}, {y})");
    }
    // implicit_outer .T.: the plane's own (default) box is the outer boundary, every
    // boundary a hole.
    let mut s = Step::default();
    s.context(false);
    let basis = s.plane_at([0.0; 3]);
    let hole = s.surface_circle([0.0; 3], 5.0);
    let bh = s.boundary("BOUNDARY_CURVE", hole);
    s.add(format!(
        "CURVE_BOUNDED_SURFACE('holed',#{basis},(#{bh}),.T.)"
    ));
    let part = s.parse();
    let p = &part.patches[0];
    assert_eq!(p.surface.domain().u, [-100.0, 100.0]);
    assert!(p.on_part(90.0, -90.0) && p.on_part(6.0, 0.0) && !p.on_part(0.0, 0.0));
    assert!(part
        .notes
        .iter()
        .any(|n| matches!(n, ReadNote::DefaultParameterBox { .. })));
}

#[test]
fn a_boundary_that_cannot_be_read_leaves_the_basis_whole_and_says_so() {
    // A pcurve on a surface of linear extrusion (whose parameters the reader does not keep as
    // the file's): the whole basis, said untrimmed — not said skipped.
    let mut s = Step::default();
    s.context(false);
    let a = s.axis([0.0; 3], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
    let circle = s.add(format!("CIRCLE('',#{a},10.)"));
    let d = s.add("DIRECTION('',(0.,0.,1.))");
    let v = s.add(format!("VECTOR('',#{d},1.)"));
    let basis = s.add(format!("SURFACE_OF_LINEAR_EXTRUSION('',#{circle},#{v})"));
    let pc = s.pcurve_polyline(basis, &[[0.0, 0.0], [1.0, 0.0], [1.0, 5.0], [0.0, 0.0]]);
    let b = s.boundary("OUTER_BOUNDARY_CURVE", pc);
    let cbs = s.add(format!("CURVE_BOUNDED_SURFACE('',#{basis},(#{b}),.F.)"));
    let part = s.parse();
    assert_eq!(part.patches.len(), 1, "{:?}", part.notes);
    assert!(part.patches[0].trim.is_none());
    let caveats = part.caveats();
    assert_eq!(
        (caveats.skipped_faces, caveats.untrimmed_faces),
        (0, 1),
        "{caveats:?}"
    );
    assert!(part.notes.iter().any(|n| matches!(
        n,
        ReadNote::TrimNotHonoured { patch: 0, by: UnhonouredTrim::StepBounded { surface, .. } }
            if *surface == cbs
    )));
    let text = &caveats.untrimmed_face_notes[0];
    assert!(
        text.contains(&format!("STEP curve-bounded surface #{cbs}"))
            && text.contains("SURFACE_OF_LINEAR_EXTRUSION"),
        "{text}"
    );
    // Still one patch on the circle.
    for c in part.grid(5) {
        let q = part.patches[0].surface.point(c.u, c.v);
        assert!((q.x.hypot(q.y) - 10.0).abs() < 1e-9, "{q}");
    }
}
