//! STEP surfaces built on other geometry, read exactly: `SURFACE_OF_REVOLUTION`,
//! `SURFACE_OF_LINEAR_EXTRUSION`, `RECTANGULAR_TRIMMED_SURFACE`, `OFFSET_SURFACE` of elementary
//! surfaces and `DEGENERATE_TOROIDAL_SURFACE` (they were skipped with a note).

mod common;
use common::step::Step;

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use swarf_geom::math::Vec3;
use swarf_surface::io::{step, ReadError};
use swarf_surface::{CompoundSurface, ParametricSurface, Tolerances};

const TOL: Tolerances = Tolerances::DEFAULT;

impl Step {
    fn dir(&mut self, d: [f64; 3]) -> u64 {
        self.add(format!("DIRECTION('',({:?},{:?},{:?}))", d[0], d[1], d[2]))
    }
    fn vector(&mut self, d: [f64; 3], mag: f64) -> u64 {
        let d = self.dir(d);
        self.add(format!("VECTOR('',#{d},{mag:?})"))
    }
    fn line(&mut self, p: [f64; 3], d: [f64; 3]) -> u64 {
        let p = self.point(p);
        let v = self.vector(d, 1.0);
        self.add(format!("LINE('',#{p},#{v})"))
    }
    /// The line x = 10, y = 0 along +z revolved about z: a cylinder of radius 10.
    fn revolved_cylinder(&mut self) -> u64 {
        let l = self.line([10.0, 0.0, 0.0], [0.0, 0.0, 1.0]);
        let o = self.point([0.0, 0.0, 0.0]);
        let z = self.dir([0.0, 0.0, 1.0]);
        let a = self.add(format!("AXIS1_PLACEMENT('',#{o},#{z})"));
        self.add(format!("SURFACE_OF_REVOLUTION('rev',#{l},#{a})"))
    }
}

/// Every grid point of every patch.
fn points(part: &CompoundSurface, n: usize) -> Vec<(usize, Vec3)> {
    part.grid(n)
        .iter()
        .map(|c| (c.patch, part.patches[c.patch].surface.point(c.u, c.v)))
        .collect()
}

#[test]
fn a_revolved_line_is_a_cylinder_whose_inside_takes_a_ball_of_its_radius() {
    let mut s = Step::default();
    s.context(false);
    s.revolved_cylinder();
    let part = s.parse();
    assert_eq!(part.patches.len(), 1, "{:?}", part.notes);
    assert_eq!(part.patches[0].name.as_deref(), Some("rev"));
    for (_, q) in points(&part, 9) {
        assert!((q.x.hypot(q.y) - 10.0).abs() < 1e-9, "{q}");
    }
    // S_u × S_v points away from the axis (the line turns towards +y, runs up +z); flipped,
    // the cutter comes from inside: a ball of radius 10 fits, no larger.
    let mut part = part;
    part.flip_all();
    for c in part.grid(5) {
        let g = part.patches[0].local(c.u, c.v, &TOL);
        let k = g.curvature.unwrap();
        assert!((k.k1 - 0.1).abs() < 1e-9 && k.k2.abs() < 1e-9, "{k:?}");
        let n = g.normal.vector().unwrap();
        let q = g.point();
        assert!((n + Vec3::new(q.x, q.y, 0.0) / 10.0).length() < 1e-9);
    }
}

#[test]
fn an_extruded_circle_arc_is_a_cylinder_piece() {
    let mut s = Step::default();
    s.context(false);
    let a = s.axis([1.0, 2.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
    let c = s.add(format!("CIRCLE('',#{a},10.0)"));
    let v = s.vector([0.0, 0.0, 1.0], 5.0);
    s.add(format!("SURFACE_OF_LINEAR_EXTRUSION('ext',#{c},#{v})"));
    let part = s.parse();
    assert_eq!(part.patches.len(), 1, "{:?}", part.notes);
    for (_, q) in points(&part, 9) {
        assert!(((q.x - 1.0).hypot(q.y - 2.0) - 10.0).abs() < 1e-9, "{q}");
    }
    // Without a face, v spans the default ±100 mm (±20 of the 5 mm vector), with a note.
    let d = part.patches[0].surface.domain();
    assert_eq!(d.v, [-20.0, 20.0]);
    assert!(part.notes.iter().any(|n| n.to_string().contains("v")));
    for c in part.grid(5) {
        let k = part.patches[0].local(c.u, c.v, &TOL).curvature.unwrap();
        // The circle's normal S_u × S_v points outwards: the surface bends away, -1/10.
        assert!((k.k2 + 0.1).abs() < 1e-9 && k.k1.abs() < 1e-9, "{k:?}");
    }
}

#[test]
fn a_rectangular_trimmed_plane_covers_only_its_rectangle_and_not_its_whole_basis() {
    let mut s = Step::default();
    s.context(false);
    let a = s.axis([0.0, 0.0, 10.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
    let p = s.add(format!("PLANE('',#{a})"));
    s.add(format!(
        "RECTANGULAR_TRIMMED_SURFACE('rts',#{p},-5.,30.,0.,20.,.T.,.T.)"
    ));
    let part = s.parse();
    assert_eq!(
        part.patches.len(),
        1,
        "the basis is read only through the trim"
    );
    let pts = points(&part, 11);
    let (lo, hi) = pts.iter().fold(
        (Vec3::splat(f64::INFINITY), Vec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), (_, q)| (lo.min(*q), hi.max(*q)),
    );
    assert!((lo - Vec3::new(-5.0, 0.0, 10.0)).length() < 1e-12, "{lo}");
    assert!((hi - Vec3::new(30.0, 20.0, 10.0)).length() < 1e-12, "{hi}");
    let n = part.patches[0]
        .local(0.0, 5.0, &TOL)
        .normal
        .vector()
        .unwrap();
    assert_eq!(n, Vec3::Z);
}

#[test]
fn a_rectangular_trim_of_a_revolution_and_a_reversed_sense() {
    let mut s = Step::default();
    s.context(false);
    let r = s.revolved_cylinder();
    // A quarter turn, z from 2 to 5; the u sense reversed flips the normal (inwards).
    s.add(format!(
        "RECTANGULAR_TRIMMED_SURFACE('q',#{r},{:?},0.,2.,5.,.F.,.T.)",
        FRAC_PI_2
    ));
    let part = s.parse();
    assert_eq!(part.patches.len(), 1, "{:?}", part.notes);
    for (_, q) in points(&part, 9) {
        assert!((q.x.hypot(q.y) - 10.0).abs() < 1e-9, "{q}");
        assert!(
            q.x >= -1e-9 && q.y >= -1e-9 && q.z >= 2.0 - 1e-9 && q.z <= 5.0 + 1e-9,
            "{q}"
        );
    }
    assert!(part.patches[0].flipped);
    let c = part.grid(3)[4];
    let k = part.patches[0].local(c.u, c.v, &TOL).curvature.unwrap();
    assert!((k.k1 - 0.1).abs() < 1e-9, "{k:?}");
}

#[test]
fn offsets_of_elementary_surfaces_are_the_same_kind_and_a_bspline_offset_is_said() {
    let mut s = Step::default();
    s.context(false);
    let a = s.axis([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
    let c = s.add(format!("CYLINDRICAL_SURFACE('',#{a},10.0)"));
    s.add(format!("OFFSET_SURFACE('cyl15',#{c},5.,.F.)"));
    let b = s.add(format!("SPHERICAL_SURFACE('',#{a},10.0)"));
    s.add(format!("OFFSET_SURFACE('sph7',#{b},-3.,.F.)"));
    let t = s.add(format!("TOROIDAL_SURFACE('',#{a},20.0,4.0)"));
    s.add(format!("OFFSET_SURFACE('tor6',#{t},2.,.F.)"));
    let k = s.add(format!("CONICAL_SURFACE('',#{a},10.0,{:?})", PI / 6.0));
    s.add(format!("OFFSET_SURFACE('cone',#{k},2.,.F.)"));
    let pl = s.add(format!("PLANE('',#{a})"));
    s.add(format!("OFFSET_SURFACE('up',#{pl},-4.,.F.)"));
    // Along the basis's own normal: a rectangular trim with one sense .F. turns the plane's
    // normal to −z, so 5 mm out is z = −5.
    let rts = s.add(format!(
        "RECTANGULAR_TRIMMED_SURFACE('',#{pl},10.,-10.,-10.,10.,.F.,.T.)"
    ));
    s.add(format!("OFFSET_SURFACE('down',#{rts},5.,.F.)"));
    let q: Vec<u64> = (0..4)
        .map(|i| s.point([i as f64 % 2.0, (i / 2) as f64, 0.0]))
        .collect();
    let spl = s.add(format!(
        "B_SPLINE_SURFACE_WITH_KNOTS('',1,1,((#{},#{}),(#{},#{})),.UNSPECIFIED.,.F.,.F.,.F.,(2,2),(2,2),(0.,1.),(0.,1.),.UNSPECIFIED.)",
        q[0], q[1], q[2], q[3]
    ));
    s.add(format!("OFFSET_SURFACE('bs',#{spl},1.,.F.)"));
    let part = s.parse();
    let by = |n: &str| {
        part.patches
            .iter()
            .position(|p| p.name.as_deref() == Some(n))
            .unwrap_or_else(|| panic!("{n}: {:?}", part.notes))
    };
    let check = |n: &str, f: &dyn Fn(Vec3) -> f64| {
        let i = by(n);
        for (_, q) in points(&part, 7).into_iter().filter(|(k, _)| *k == i) {
            assert!(f(q).abs() < 1e-9, "{n}: {q} off by {}", f(q));
        }
    };
    check("cyl15", &|q| q.x.hypot(q.y) - 15.0);
    check("sph7", &|q| q.length() - 7.0);
    check("tor6", &|q| (q.x.hypot(q.y) - 20.0).hypot(q.z) - 6.0);
    check("up", &|q| q.z + 4.0);
    check("down", &|q| q.z + 5.0);
    // The cone 2 mm out along its normal: every point 2 mm from the basis cone (its distance
    // from the line through the apex at 30° to the axis).
    let (sa, ca) = (30f64.to_radians().sin(), 30f64.to_radians().cos());
    let apex_z = -10.0 / sa * ca;
    check("cone", &|q| {
        // (Signed: the default box runs past the apex onto the other nappe.)
        let (rho, h) = (q.x.hypot(q.y), q.z - apex_z);
        let f = |r: f64| r * ca - h * sa - 2.0;
        if f(rho).abs() < f(-rho).abs() {
            f(rho)
        } else {
            f(-rho)
        }
    });
    // The offset of the B-spline is not read: said, not dropped silently.
    assert!(part.patches.iter().all(|p| p.name.as_deref() != Some("bs")));
    assert!(part
        .notes
        .iter()
        .any(|n| n.to_string().contains("OFFSET_SURFACE") && n.to_string().contains("B-spline")));
}

#[test]
fn a_degenerate_torus_gives_its_outer_or_inner_part() {
    for (outer, v) in [
        (true, [-2.0 * PI / 3.0, 2.0 * PI / 3.0]),
        (false, [2.0 * PI / 3.0, 4.0 * PI / 3.0]),
    ] {
        let mut s = Step::default();
        s.context(false);
        let a = s.axis([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
        let sel = if outer { ".T." } else { ".F." };
        s.add(format!(
            "DEGENERATE_TOROIDAL_SURFACE('d',#{a},5.0,10.0,{sel})"
        ));
        let part = s.parse();
        assert_eq!(part.patches.len(), 1, "{:?}", part.notes);
        let d = part.patches[0].surface.domain();
        assert_eq!(d.u, [0.0, TAU]);
        assert!(
            (d.v[0] - v[0]).abs() < 1e-12 && (d.v[1] - v[1]).abs() < 1e-12,
            "{d:?}"
        );
        for (_, q) in points(&part, 9) {
            // On the tube: 10 from the centre circle of radius 5 on one side or the other.
            let rho = q.x.hypot(q.y);
            let off = ((rho - 5.0).hypot(q.z) - 10.0)
                .abs()
                .min(((rho + 5.0).hypot(q.z) - 10.0).abs());
            assert!(off < 1e-9, "{q}");
            // The apple reaches 15 from the axis, the lemon stays within 5.
            assert!(
                if outer {
                    rho <= 15.0 + 1e-9
                } else {
                    rho <= 5.0 + 1e-9
                },
                "{q}"
            );
        }
    }
}

#[test]
fn the_old_skip_remains_for_what_is_not_read() {
    let mut s = Step::default();
    s.context(false);
    let a = s.axis([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
    s.add(format!(
        "DEGENERATE_TOROIDAL_SURFACE('d',#{a},15.0,10.0,.F.)"
    ));
    match step::parse(&s.text()) {
        Err(ReadError::Empty { detail, .. }) => {
            assert!(detail.contains("DEGENERATE_TOROIDAL_SURFACE"), "{detail}")
        }
        other => panic!("{other:?}"),
    }
}

/// A context in mm and, when `degrees`, degrees (else radians).
fn context_with_angles(s: &mut Step, degrees: bool) {
    let mm = s.add("(LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.))");
    let rad = s.add("(NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.))");
    let angle = if degrees {
        let m = s.add(format!(
            "PLANE_ANGLE_MEASURE_WITH_UNIT(PLANE_ANGLE_MEASURE({:?}),#{rad})",
            PI / 180.0
        ));
        let d = s.add("DIMENSIONAL_EXPONENTS(0.,0.,0.,0.,0.,0.,0.)");
        s.add(format!(
            "(CONVERSION_BASED_UNIT('DEGREE',#{m}) NAMED_UNIT(#{d}) PLANE_ANGLE_UNIT())"
        ))
    } else {
        rad
    };
    s.add(format!(
        "(GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNIT_ASSIGNED_CONTEXT((#{mm},#{angle})) \
         REPRESENTATION_CONTEXT('',''))"
    ));
}

#[test]
fn a_trimmed_swept_curve_sweeps_only_what_its_trims_keep() {
    // The circle of radius 10 about the x axis (x = (0, 1, 0), y = (0, 0, 1)) trimmed from π
    // to 2π (the half with z ≤ 0), extruded 50 mm along x: a trough. The trims were dropped
    // and the whole tube read, its top half a phantom wall.
    for degrees in [false, true] {
        let mut s = Step::default();
        context_with_angles(&mut s, degrees);
        let a = s.axis([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        let c = s.add(format!("CIRCLE('',#{a},10.)"));
        let k = if degrees { 180.0 } else { PI };
        let t = s.add(format!(
            "TRIMMED_CURVE('',#{c},(PARAMETER_VALUE({:?})),(PARAMETER_VALUE({:?})),.T.,.PARAMETER.)",
            k,
            2.0 * k
        ));
        let v = s.vector([1.0, 0.0, 0.0], 50.0);
        s.add(format!("SURFACE_OF_LINEAR_EXTRUSION('trough',#{t},#{v})"));
        let part = s.parse();
        assert_eq!(part.patches.len(), 1, "{:?}", part.notes);
        let pts = points(&part, 9);
        let zmin = pts.iter().map(|(_, q)| q.z).fold(f64::INFINITY, f64::min);
        for (_, q) in &pts {
            assert!(
                (q.y.hypot(q.z) - 10.0).abs() < 1e-9 && q.z <= 1e-9,
                "{degrees}: {q}"
            );
        }
        // From y = −10 (u's start) round the bottom to y = 10.
        assert!((zmin + 10.0).abs() < 1e-9, "{zmin}");
        let d = part.patches[0].surface.domain();
        let ends = [d.u[0], d.u[1]].map(|u| part.patches[0].surface.point(u, 0.0));
        assert!(
            (ends[0] - Vec3::new(0.0, -10.0, 0.0)).length() < 1e-9,
            "{ends:?}"
        );
        assert!(
            (ends[1] - Vec3::new(0.0, 10.0, 0.0)).length() < 1e-9,
            "{ends:?}"
        );
    }
    // Trimmed by points, against the circle's sense: from (0, 10, 0) (t = 0) down to
    // (0, 0, 10) (t = π/2) — three quarters, all but the quarter where y > 0 and z > 0.
    let mut s = Step::default();
    s.context(false);
    let a = s.axis([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
    let c = s.add(format!("CIRCLE('',#{a},10.)"));
    let (p1, p2) = (s.point([0.0, 10.0, 0.0]), s.point([0.0, 0.0, 10.0]));
    let t = s.add(format!(
        "TRIMMED_CURVE('',#{c},(#{p1}),(#{p2}),.F.,.CARTESIAN.)"
    ));
    let v = s.vector([1.0, 0.0, 0.0], 50.0);
    s.add(format!("SURFACE_OF_LINEAR_EXTRUSION('',#{t},#{v})"));
    let part = s.parse();
    let p = &part.patches[0];
    let d = p.surface.domain();
    assert!((d.u[1] - d.u[0] - 1.5 * PI).abs() < 1e-9, "{d:?}");
    // Run backwards: from (0, 10, 0) to (0, 0, 10) the way round through y = −10.
    let ends = [d.u[0], d.u[1]].map(|u| p.surface.point(u, 0.0));
    assert!(
        (ends[0] - Vec3::new(0.0, 10.0, 0.0)).length() < 1e-9,
        "{ends:?}"
    );
    assert!(
        (ends[1] - Vec3::new(0.0, 0.0, 10.0)).length() < 1e-9,
        "{ends:?}"
    );
    for (_, q) in points(&part, 13) {
        assert!(!(q.y > 1e-6 && q.z > 1e-6), "{q}");
    }
    // A line trimmed from 0 to 5 revolved about z: the band of the cylinder z ∈ [0, 5] (it
    // was z ∈ [−100, 100], the default range of an unbounded line).
    let mut s = Step::default();
    s.context(false);
    let l = s.line([10.0, 0.0, 0.0], [0.0, 0.0, 1.0]);
    let t = s.add(format!(
        "TRIMMED_CURVE('',#{l},(PARAMETER_VALUE(0.)),(PARAMETER_VALUE(5.)),.T.,.PARAMETER.)"
    ));
    let o = s.point([0.0; 3]);
    let z = s.dir([0.0, 0.0, 1.0]);
    let ax = s.add(format!("AXIS1_PLACEMENT('',#{o},#{z})"));
    s.add(format!("SURFACE_OF_REVOLUTION('band',#{t},#{ax})"));
    let part = s.parse();
    assert!(
        !part
            .notes
            .iter()
            .any(|n| matches!(n, swarf_surface::ReadNote::DefaultParameterBox { .. })),
        "{:?}",
        part.notes
    );
    let pts = points(&part, 9);
    let (zlo, zhi) = pts
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (_, q)| {
            (a.min(q.z), b.max(q.z))
        });
    assert!(
        zlo.abs() < 1e-12 && (zhi - 5.0).abs() < 1e-12,
        "{zlo} {zhi}"
    );
}
