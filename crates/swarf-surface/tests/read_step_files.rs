//! STEP reader: the shared fuselage and revolved-sphere files, units, rational complex
//! entities, elementary faces, orientation and malformed input.

mod common;
use common::{data, sphere_step_file};

use swarf_geom::math::Vec3;
use swarf_surface::io::{self, step, Format, ReadError};
use swarf_surface::{EntityRef, ParametricSurface, ReadNote, Surface, SurfaceNormal, Tolerances};

const TOL: Tolerances = Tolerances::DEFAULT;

#[test]
fn fuselage_has_eight_bicubic_10x4_patches_in_feet_converted_to_mm() {
    let Some(path) = data("step/occt_bug28366_fuselage.stp") else {
        return;
    };
    let s = io::read_file(&path).unwrap();
    assert_eq!(s.patches.len(), 8);
    assert!(
        s.notes
            .iter()
            .any(|n| matches!(n, ReadNote::UnitsConverted { factor, .. } if *factor == 304.8)),
        "{:?}",
        s.notes
    );
    let bb = s.bounding_box().unwrap().inflated(1e-9);
    for (k, p) in s.patches.iter().enumerate() {
        let Surface::Nurbs(n) = &p.surface else {
            panic!("patch {k} is {}", p.surface.kind())
        };
        assert_eq!((n.degree_u(), n.degree_v()), (3, 3));
        assert_eq!(n.net_size(), (10, 4));
        assert!(!n.is_rational());
        assert!(matches!(
            p.source.entity,
            EntityRef::Step { face: None, .. }
        ));
        assert!(p
            .source
            .file
            .as_deref()
            .unwrap()
            .ends_with("occt_bug28366_fuselage.stp"));
    }
    // First patch, first interior control point: (0.146…, 8.364…, −3) ft.
    let Surface::Nurbs(n) = &s.patches[0].surface else {
        unreachable!()
    };
    let c = n.control_point(1, 0);
    assert!((c - Vec3::new(0.146011067419878, 8.36496845015109, -3.0) * 304.8).length() < 1e-9);
    let mut finite = 0;
    for cc in s.grid(21) {
        let g = s.local(&cc, &TOL);
        assert!(bb.contains(g.point()), "{cc:?} outside the overall box");
        assert!(g.point().is_finite());
        if let Some(n) = g.normal.vector() {
            assert!((n.length() - 1.0).abs() < 1e-12);
            finite += 1;
        }
    }
    // The nose is a collapsed edge (row 0 of the net is one point): it gets a limit normal.
    assert_eq!(finite, 8 * 21 * 21);
    let g = s.patches[0].local(0.0, 0.5, &TOL);
    assert!(
        matches!(g.normal, SurfaceNormal::Limit(_)),
        "{:?}",
        g.normal
    );
}

#[test]
fn revolved_sphere_is_a_radius_5_sphere_with_curvature_one_fifth() {
    let s = io::read_file(&sphere_step_file()).unwrap();
    assert_eq!(s.patches.len(), 1);
    let p = &s.patches[0];
    let Surface::Sphere(sph) = &p.surface else {
        panic!("{}", p.surface.kind())
    };
    assert_eq!(sph.radius, 5.0);
    assert!(!p.flipped, "same_sense .T.");
    assert_eq!(
        p.source.entity,
        EntityRef::Step {
            surface: 22,
            face: Some(17)
        }
    );
    assert!(s.notes.is_empty(), "mm file: {:?}", s.notes);
    for cc in s.grid(21) {
        let g = s.local(&cc, &TOL);
        assert!((g.point().length() - 5.0).abs() < 1e-12);
        let c = g.curvature.unwrap();
        // Outward normal: the convex outside bends away from the cutter.
        assert!(
            (c.k1 + 0.2).abs() < 1e-7 && (c.k2 + 0.2).abs() < 1e-7,
            "{cc:?}: {c:?}"
        );
        assert!(g.normal.vector().unwrap().dot(g.point()) > 0.0);
    }
    // Machining the inside: --flip gives +1/5.
    let mut inside = s.clone();
    inside.flip_all();
    let c = inside.patches[0].local(1.0, 0.3, &TOL).curvature.unwrap();
    assert!((c.k1 - 0.2).abs() < 1e-12 && (c.k2 - 0.2).abs() < 1e-12);
}

const HEAD: &str = "ISO-10303-21;\nHEADER;\nFILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\nENDSEC;\nDATA;\n";

fn inch_context() -> &'static str {
    "#90=(LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.));\n\
     #91=LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(25.4),#90);\n\
     #92=(CONVERSION_BASED_UNIT('INCH',#91) LENGTH_UNIT() NAMED_UNIT(#93));\n\
     #93=DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.);\n\
     #94=(NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.));\n\
     #95=(GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNIT_ASSIGNED_CONTEXT((#92,#94)) REPRESENTATION_CONTEXT('',''));\n"
}

#[test]
fn rational_complex_entity_in_inches() {
    // A quarter cylinder of radius 1 in, height 2 in, as the complex rational B-spline entity.
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let text = format!(
        "{HEAD}{}#1=CARTESIAN_POINT('',(1.,0.,0.));#2=CARTESIAN_POINT('',(1.,0.,2.));\
         #3=CARTESIAN_POINT('',(1.,1.,0.));#4=CARTESIAN_POINT('',(1.,1.,2.));\
         #5=CARTESIAN_POINT('',(0.,1.,0.));#6=CARTESIAN_POINT('',(0.,1.,2.));\n\
         #10=( BOUNDED_SURFACE() B_SPLINE_SURFACE(2,1,((#1,#2),(#3,#4),(#5,#6)),.UNSPECIFIED.,.F.,.F.,.F.)\n\
         B_SPLINE_SURFACE_WITH_KNOTS((3,3),(2,2),(0.,1.),(0.,1.),.UNSPECIFIED.) GEOMETRIC_REPRESENTATION_ITEM()\n\
         RATIONAL_B_SPLINE_SURFACE(((1.,1.),({w},{w}),(1.,1.))) REPRESENTATION_ITEM('wall') SURFACE() );\n\
         ENDSEC;\nEND-ISO-10303-21;\n",
        inch_context()
    );
    let s = step::parse(&text).unwrap();
    assert_eq!(s.patches.len(), 1);
    assert_eq!(s.patches[0].name.as_deref(), Some("wall"));
    let Surface::Nurbs(n) = &s.patches[0].surface else {
        panic!()
    };
    assert!(n.is_rational());
    for k in 0..=10 {
        let g = s.patches[0].local(k as f64 / 10.0, 0.5, &TOL);
        let p = g.point();
        assert!((p.x.hypot(p.y) - 25.4).abs() < 1e-12 && (p.z - 25.4).abs() < 1e-12);
        let c = g.curvature.unwrap();
        assert!((c.k2 + 1.0 / 25.4).abs() < 1e-12 && c.k1.abs() < 1e-12);
    }
    assert!(s.notes.iter().any(|n| matches!(n, ReadNote::UnitsConverted { unit, factor } if unit == "INCH" && *factor == 25.4)));
}

#[test]
fn an_inch_conversion_factor_as_a_complex_instance_reads_as_the_simple_one() {
    // The factor written as `(LENGTH_MEASURE_WITH_UNIT() MEASURE_WITH_UNIT(value, unit))`
    // (the subtype's part empty, the supertype's holding the value), as some exporters do
    // (/tmp/geo-review/mk1.py, trough_inch2.stp): the same ×25.4 as the simple form.
    let simple = "#91=LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(25.4),#90);";
    let complex = "#91=( LENGTH_MEASURE_WITH_UNIT() MEASURE_WITH_UNIT(LENGTH_MEASURE(25.4),#90) );";
    assert!(inch_context().contains(simple));
    let text = |context: &str| {
        format!(
            "{HEAD}{context}#1=CARTESIAN_POINT('',(1.,0.,0.));#2=CARTESIAN_POINT('',(1.,0.,2.));\
             #3=CARTESIAN_POINT('',(0.,1.,0.));#4=CARTESIAN_POINT('',(0.,1.,2.));\n\
             #10=B_SPLINE_SURFACE_WITH_KNOTS('wall',1,1,((#1,#2),(#3,#4)),.UNSPECIFIED.,.F.,.F.,\
             .F.,(2,2),(2,2),(0.,1.),(0.,1.),.UNSPECIFIED.);\n\
             #11=SHAPE_REPRESENTATION('',(#10),#95);\nENDSEC;\nEND-ISO-10303-21;\n"
        )
    };
    let a = step::parse(&text(inch_context())).unwrap();
    let b = step::parse(&text(&inch_context().replace(simple, complex)))
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(a.patches, b.patches);
    assert_eq!(a.notes, b.notes);
    assert!(b.notes.iter().any(|n| matches!(n, ReadNote::UnitsConverted { unit, factor } if unit == "INCH" && *factor == 25.4)));
    // The corner (0, 1, 2) in is (0, 25.4, 50.8) mm.
    let p = b.patches[0].surface.point(1.0, 1.0);
    assert_eq!(p, Vec3::new(0.0, 25.4, 50.8));
    // No part with the value at all: refused, naming the measure.
    let e = err(&text(&inch_context().replace(
        simple,
        "#91=( LENGTH_MEASURE_WITH_UNIT() MEASURE_WITH_UNIT() );",
    )));
    let m = e.to_string();
    assert!(
        m.contains("#91") && m.contains("with a value and a unit"),
        "{m}"
    );
}

#[test]
fn elementary_faces_take_their_bounds_and_orientation() {
    // A cylinder face (radius 3, between z = 1 and z = 4, two circle edges) with same_sense .F.
    // (material outside: the cutter is inside), a conical face and a plane face bounded by a
    // circle, in mm, with an unsupported face kind among them.
    let text = format!(
        "{HEAD}\
         #1=CARTESIAN_POINT('',(0.,0.,0.));#2=DIRECTION('',(0.,0.,1.));#3=DIRECTION('',(1.,0.,0.));\n\
         #4=AXIS2_PLACEMENT_3D('',#1,#2,#3);\n\
         #5=CYLINDRICAL_SURFACE('',#4,3.);\n\
         #6=CARTESIAN_POINT('',(0.,0.,1.));#7=AXIS2_PLACEMENT_3D('',#6,#2,#3);#8=CIRCLE('',#7,3.);\n\
         #9=CARTESIAN_POINT('',(0.,0.,4.));#10=AXIS2_PLACEMENT_3D('',#9,#2,#3);#11=CIRCLE('',#10,3.);\n\
         #12=CARTESIAN_POINT('',(3.,0.,1.));#13=VERTEX_POINT('',#12);\n\
         #14=CARTESIAN_POINT('',(3.,0.,4.));#15=VERTEX_POINT('',#14);\n\
         #16=EDGE_CURVE('',#13,#13,#8,.T.);#17=EDGE_CURVE('',#15,#15,#11,.T.);\n\
         #18=ORIENTED_EDGE('',*,*,#16,.T.);#19=ORIENTED_EDGE('',*,*,#17,.F.);\n\
         #20=EDGE_LOOP('',(#18));#21=EDGE_LOOP('',(#19));\n\
         #22=FACE_BOUND('',#20,.T.);#23=FACE_BOUND('',#21,.T.);\n\
         #24=ADVANCED_FACE('bore',(#22,#23),#5,.F.);\n\
         #30=PLANE('',#7);#31=FACE_OUTER_BOUND('',#20,.T.);#32=ADVANCED_FACE('',(#31),#30,.T.);\n\
         #40=CONICAL_SURFACE('',#4,3.,0.5);#41=ADVANCED_FACE('',(#22,#23),#40,.T.);\n\
         #50=CURVE_BOUNDED_SURFACE('',#30,(),.F.);#51=ADVANCED_FACE('odd',(#22),#50,.T.);\n\
         #60=TOROIDAL_SURFACE('',#4,10.,2.);#61=ADVANCED_FACE('',(#22),#60,.T.);\n\
         ENDSEC;\nEND-ISO-10303-21;\n"
    );
    let s = step::parse(&text).unwrap();
    assert_eq!(s.patches.len(), 4);
    assert!(s.notes.iter().any(|n| matches!(n, ReadNote::UnitsAssumed)));
    assert!(s.notes.iter().any(|n| matches!(n, ReadNote::UnsupportedSurface { kind, .. } if kind == "CURVE_BOUNDED_SURFACE")));
    // Bore: flipped, v from 1 to 4, normal towards the axis, concave curvature +1/3.
    let bore = &s.patches[0];
    assert_eq!(bore.name.as_deref(), Some("bore"));
    assert!(bore.flipped);
    let d = bore.surface.domain();
    assert!(
        (d.v[0] - 1.0).abs() < 1e-12 && (d.v[1] - 4.0).abs() < 1e-12,
        "{d:?}"
    );
    let g = bore.local(0.0, 2.0, &TOL);
    assert_eq!(g.normal, SurfaceNormal::Regular(-Vec3::X));
    assert!((g.curvature.unwrap().k1 - 1.0 / 3.0).abs() < 1e-12);
    // Plane bounded by the circle of radius 3 at z = 1: u, v ∈ [−3, 3].
    let d = s.patches[1].surface.domain();
    assert!(
        (d.u[0] + 3.0).abs() < 1e-12 && (d.u[1] - 3.0).abs() < 1e-12,
        "{d:?}"
    );
    assert!(
        (d.v[0] + 3.0).abs() < 1e-12 && (d.v[1] - 3.0).abs() < 1e-12,
        "{d:?}"
    );
    assert!(matches!(s.patches[2].surface, Surface::Cone(_)));
    // The torus face is bounded only in angle: full parameter box, no default needed.
    assert!(matches!(s.patches[3].surface, Surface::Torus(_)));
}

fn err(text: &str) -> ReadError {
    step::parse(text).unwrap_err()
}

#[test]
fn malformed_step_files_give_positions_and_reasons() {
    match err("ISO-10303-21;\nDATA;\n#1=CARTESIAN_POINT('',(1.,2.,3.);\nENDSEC;") {
        ReadError::Syntax {
            format: Format::Step,
            line: 3,
            column,
            message,
        } => {
            assert_eq!(column, 33, "{message}");
            assert!(message.contains("expected `,` or `)`"), "{message}");
        }
        e => panic!("{e}"),
    }
    match err("ISO-10303-21;\nDATA;\n#1=PLANE('',#2);\n#1=PLANE('',#2);\nENDSEC;") {
        ReadError::Syntax {
            line: 4, message, ..
        } => assert!(message.contains("defined twice")),
        e => panic!("{e}"),
    }
    match err("ISO-10303-21;\nDATA;\n#7=PLANE('',#2);\nENDSEC;") {
        ReadError::Entity {
            line: 3,
            entity,
            message,
            ..
        } => {
            assert_eq!(entity, "#7");
            assert!(message.contains("#2, which is not defined"), "{message}");
        }
        e => panic!("{e}"),
    }
    // Knot multiplicities that do not match the net.
    let t = "ISO-10303-21;\nDATA;\n#1=CARTESIAN_POINT('',(0.,0.,0.));\n\
             #2=B_SPLINE_SURFACE_WITH_KNOTS('',1,1,((#1,#1),(#1,#1)),.UNSPECIFIED.,.F.,.F.,.F.,(2,2),(2,1),(0.,1.),(0.,1.),.UNSPECIFIED.);\nENDSEC;";
    match err(t) {
        ReadError::Entity {
            line: 4, message, ..
        } => assert!(
            message.contains("v multiplicities add up to 3; expected 4"),
            "{message}"
        ),
        e => panic!("{e}"),
    }
    // Decreasing knots are caught by the NURBS validation, with the entity, said once along
    // the error's chain (the CLI prints the chain; the reason was also the source and came
    // twice: "#2: knots in v: knot 3 … : knots in v: knot 3 …").
    let t = t.replace("(2,1),(0.,1.),(0.,1.)", "(2,2),(0.,1.),(1.,0.)");
    let e = err(&t);
    let mut chain = vec![e.to_string()];
    let mut at: &dyn std::error::Error = &e;
    while let Some(s) = at.source() {
        chain.push(s.to_string());
        at = s;
    }
    let chain = chain.join(": ");
    assert_eq!(chain.matches("is smaller than knot").count(), 1, "{chain}");
    match err(&t) {
        ReadError::Surface {
            line: 4, entity, ..
        } => assert_eq!(entity, "#2"),
        e => panic!("{e}"),
    }
    match err("no step here") {
        ReadError::Syntax { message, .. } => assert!(message.contains("DATA section"), "{message}"),
        e => panic!("{e}"),
    }
    match err("ISO-10303-21;\nDATA;\n#1=CARTESIAN_POINT('',(0.,0.,0.));\nENDSEC;") {
        ReadError::Empty { .. } => {}
        e => panic!("{e}"),
    }
    let msg = err("ISO-10303-21;\nDATA;\n#1=X('abc);\nENDSEC;").to_string();
    assert!(
        msg.starts_with("STEP line 3, column 6: unterminated string"),
        "{msg}"
    );
}

/// Sphere faces A (radius 0.25 in at the origin, in the inch context #95), B (radius 5 mm at
/// x = 20, in a mm context #`mm + 1`) and C (radius 1 at z = 50, in no representation).
fn two_contexts(mm: u64) -> String {
    format!(
        "{HEAD}{}#{mm}=(LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.));\n\
         #{}=(GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNIT_ASSIGNED_CONTEXT((#{mm})) REPRESENTATION_CONTEXT('',''));\n\
         #1=CARTESIAN_POINT('',(0.,0.,0.));#2=DIRECTION('',(0.,0.,1.));#3=DIRECTION('',(1.,0.,0.));\n\
         #4=AXIS2_PLACEMENT_3D('',#1,#2,#3);#5=SPHERICAL_SURFACE('',#4,0.25);#6=FACE_SURFACE('A',(),#5,.T.);\n\
         #7=OPEN_SHELL('',(#6));#8=SHELL_BASED_SURFACE_MODEL('',(#7));\n\
         #9=MANIFOLD_SURFACE_SHAPE_REPRESENTATION('A',(#4,#8),#95);\n\
         #11=CARTESIAN_POINT('',(20.,0.,0.));#14=AXIS2_PLACEMENT_3D('',#11,#2,#3);\n\
         #15=SPHERICAL_SURFACE('',#14,5.);#16=FACE_SURFACE('B',(),#15,.T.);\n\
         #17=OPEN_SHELL('',(#16));#18=SHELL_BASED_SURFACE_MODEL('',(#17));\n\
         #19=MANIFOLD_SURFACE_SHAPE_REPRESENTATION('B',(#18),#{});\n\
         #21=CARTESIAN_POINT('',(0.,0.,50.));#24=AXIS2_PLACEMENT_3D('',#21,#2,#3);\n\
         #25=SPHERICAL_SURFACE('',#24,1.);#26=FACE_SURFACE('C',(),#25,.T.);\n\
         ENDSEC;\nEND-ISO-10303-21;\n",
        inch_context(),
        mm + 1,
        mm + 1
    )
}

#[test]
fn each_representation_is_read_in_its_own_context_units() {
    // Two unit contexts: each face is scaled by its representation's (all were read in the
    // first context's unit: B came out 25.4 times too large, or A 25.4 times too small); a face
    // in no representation takes the first context's, and the note says so.
    for (mm, first, c_radius) in [(100, "INCH", 25.4), (80, "MILLI METRE", 1.0)] {
        let s = step::parse(&two_contexts(mm)).unwrap();
        let radius = |name: &str, centre: Vec3| {
            let p = s
                .patches
                .iter()
                .find(|p| p.name.as_deref() == Some(name))
                .unwrap();
            let d = p.surface.domain();
            let r = (p.surface.point(0.3 * d.u[1], 0.2) - centre).length();
            assert!(((p.surface.point(d.u[0], 0.7) - centre).length() - r).abs() < 1e-9);
            r
        };
        assert!(
            (radius("A", Vec3::ZERO) - 6.35).abs() < 1e-12,
            "{first} first"
        );
        assert!(
            (radius("B", Vec3::new(20.0, 0.0, 0.0)) - 5.0).abs() < 1e-12,
            "{first} first"
        );
        let c = radius("C", Vec3::new(0.0, 0.0, 50.0 * c_radius));
        assert!((c - c_radius).abs() < 1e-12, "{first} first: {c}");
        let note = s
            .notes
            .iter()
            .find(|n| matches!(n, ReadNote::UnitsMixed { .. }))
            .unwrap();
        assert_eq!(
            note,
            &ReadNote::UnitsMixed {
                units: vec!["MILLI METRE".into(), "INCH".into()],
                first: first.into(),
                defaulted: 1
            }
        );
        assert!(note
            .to_string()
            .contains("1 face(s) in no single representation read in"));
        assert!(!s
            .notes
            .iter()
            .any(|n| matches!(n, ReadNote::UnitsConverted { .. })));
    }
}

#[test]
fn assembly_placements_are_applied() {
    // A part placed by a MAPPED_ITEM at (100, 0, 0), and a part used twice by assembly
    // occurrences with their transformations, at (±100, 0, 0): each instance is read where it
    // is placed, with a note saying how many; a file without instances has no such note.
    let part = "#1=(LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.));\n\
        #2=(GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNIT_ASSIGNED_CONTEXT((#1)) REPRESENTATION_CONTEXT('',''));\n\
        #3=CARTESIAN_POINT('',(0.,0.,0.));#4=DIRECTION('',(0.,0.,1.));#5=DIRECTION('',(1.,0.,0.));\n\
        #6=AXIS2_PLACEMENT_3D('',#3,#4,#5);#7=SPHERICAL_SURFACE('',#6,5.);#8=FACE_SURFACE('ball',(),#7,.T.);\n\
        #9=OPEN_SHELL('',(#8));#10=SHELL_BASED_SURFACE_MODEL('',(#9));\n\
        #11=MANIFOLD_SURFACE_SHAPE_REPRESENTATION('Ball',(#6,#10),#2);\n\
        #20=CARTESIAN_POINT('',(100.,0.,0.));#21=AXIS2_PLACEMENT_3D('',#20,#4,#5);\n\
        #22=CARTESIAN_POINT('',(-100.,0.,0.));#23=AXIS2_PLACEMENT_3D('',#22,#4,#5);\n";
    let mapped = "#30=REPRESENTATION_MAP(#6,#11);#31=MAPPED_ITEM('',#30,#21);\n\
        #32=SHAPE_REPRESENTATION('Assy',(#31),#2);\n";
    let occurrences = "#40=PRODUCT_DEFINITION('design','',$,$);#41=PRODUCT_DEFINITION('design','',$,$);\n\
        #42=SHAPE_REPRESENTATION('Assy',(#6,#21,#23),#2);\n\
        #43=NEXT_ASSEMBLY_USAGE_OCCURRENCE('1','inst1','',#41,#40,$);#44=PRODUCT_DEFINITION_SHAPE('','',#43);\n\
        #45=ITEM_DEFINED_TRANSFORMATION('','',#6,#21);\n\
        #46=( REPRESENTATION_RELATIONSHIP('','',#11,#42) REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION(#45) SHAPE_REPRESENTATION_RELATIONSHIP() );\n\
        #47=CONTEXT_DEPENDENT_SHAPE_REPRESENTATION(#46,#44);\n\
        #53=NEXT_ASSEMBLY_USAGE_OCCURRENCE('2','inst2','',#41,#40,$);#54=PRODUCT_DEFINITION_SHAPE('','',#53);\n\
        #55=ITEM_DEFINED_TRANSFORMATION('','',#6,#23);\n\
        #56=( REPRESENTATION_RELATIONSHIP('','',#11,#42) REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION(#55) SHAPE_REPRESENTATION_RELATIONSHIP() );\n\
        #57=CONTEXT_DEPENDENT_SHAPE_REPRESENTATION(#56,#54);\n";
    let file = |extra: &str| format!("{HEAD}{part}{extra}ENDSEC;\nEND-ISO-10303-21;\n");
    for (extra, centres, names) in [
        (mapped, vec![100.0], vec!["ball"]),
        (
            occurrences,
            vec![100.0, -100.0],
            vec!["ball@#43", "ball@#53"],
        ),
    ] {
        let s = step::parse(&file(extra)).unwrap();
        assert_eq!(s.patches.len(), centres.len());
        for ((p, x), name) in s.patches.iter().zip(&centres).zip(names) {
            assert_eq!(p.name.as_deref(), Some(name));
            // A sphere of radius 5 about (x, 0, 0).
            let c = Vec3::new(*x, 0.0, 0.0);
            for (u, v) in [(0.0, 0.0), (1.0, 0.5), (4.0, -1.0)] {
                assert!((((p.surface.point(u, v) - c).length()) - 5.0).abs() < 1e-12);
            }
        }
        let note = s
            .notes
            .iter()
            .find(|n| matches!(n, ReadNote::PlacementsApplied { .. }))
            .unwrap();
        assert_eq!(
            note,
            &ReadNote::PlacementsApplied {
                instances: centres.len(),
                parts: 1
            }
        );
        assert!(
            !s.notes
                .iter()
                .any(|n| matches!(n, ReadNote::PlacementNotApplied { .. })),
            "{:?}",
            s.notes
        );
    }
    let s = step::parse(&file("")).unwrap();
    assert!(!s.notes.iter().any(|n| matches!(
        n,
        ReadNote::PlacementsApplied { .. } | ReadNote::PlacementNotApplied { .. }
    )));
}

/// A STEP file of `body`'s instances.
fn file(body: &str) -> String {
    format!("ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n{body}ENDSEC;\nEND-ISO-10303-21;\n")
}

#[test]
fn names_are_decoded_as_iso_10303_21_writes_them() {
    // \X2\ UCS-2 (a surrogate pair too), \X4\ UCS-4, \X\ and \S\ (ISO 8859-1), \\, a
    // malformed escape left as written, and the doubled quote.
    let names = [
        (r"Face \X2\00E9\X0\ d''angle", "Face é d'angle"),
        (r"\X2\D83DDE00\X0\ and \X4\0001F600\X0\", "😀 and 😀"),
        (r"Fl\X\E4che \S\i", "Fläche é"),
        (r"C:\\parts\\\X2\4F60597D\X0\", r"C:\parts\你好"),
        (r"odd \Q\ and \X2\12\X0\", r"odd \Q\ and \X2\12\X0\"),
    ];
    let mut body = String::from(
        "#1=CARTESIAN_POINT('',(0.,0.,0.));#2=DIRECTION('',(0.,0.,1.));\
         #3=DIRECTION('',(1.,0.,0.));#4=AXIS2_PLACEMENT_3D('',#1,#2,#3);\n",
    );
    for (k, (raw, _)) in names.iter().enumerate() {
        body.push_str(&format!(
            "#{}=SPHERICAL_SURFACE('{raw}',#4,{}.);\n",
            10 + k,
            k + 1
        ));
    }
    let s = step::parse(&file(&body)).unwrap();
    let got: Vec<&str> = s
        .patches
        .iter()
        .map(|p| p.name.as_deref().unwrap())
        .collect();
    let want: Vec<&str> = names.iter().map(|(_, n)| *n).collect();
    assert_eq!(got, want);
}

#[test]
fn uniform_quasi_uniform_and_bezier_surfaces_take_the_knots_their_kind_implies() {
    // One net of 5 × 3 points, degrees 2 × 2, written with knots (B_SPLINE_SURFACE_WITH_KNOTS)
    // and as each kind with implied knots (ISO 10303-42): quasi-uniform 0,0,0,1,2,3,3,3 and
    // 0,0,0,1,1,1; uniform −2 … 5 and −2 … 3; Bézier (pieces of degree 2) 0,0,0,1,1,2,2,2 and
    // 0,0,0,1,1,1. Each must be the surface its explicit knots give, point for point.
    let mut body = String::new();
    let mut pts = Vec::new();
    for i in 0..5 {
        let mut row = Vec::new();
        for j in 0..3 {
            let id = 100 + 3 * i + j;
            let z = [
                [0., 2., 1.],
                [3., -1., 2.],
                [1., 4., 0.],
                [-2., 1., 3.],
                [0., 0., 1.],
            ][i][j];
            body.push_str(&format!(
                "#{id}=CARTESIAN_POINT('',({:?},{:?},{z:?}));\n",
                10.0 * i as f64,
                7.0 * j as f64
            ));
            row.push(format!("#{id}"));
        }
        pts.push(format!("({})", row.join(",")));
    }
    let net = pts.join(",");
    let head = format!("2,2,({net}),.UNSPECIFIED.,.F.,.F.,.F.");
    let knotted = |name: &str, um: &str, uk: &str, vm: &str, vk: &str| {
        format!("B_SPLINE_SURFACE_WITH_KNOTS('{name}',{head},({um}),({vm}),({uk}),({vk}),.UNSPECIFIED.)")
    };
    let cases = [
        (
            format!(
                "(BOUNDED_SURFACE() B_SPLINE_SURFACE({head}) QUASI_UNIFORM_SURFACE() \
                 GEOMETRIC_REPRESENTATION_ITEM() REPRESENTATION_ITEM('quasi') SURFACE())"
            ),
            knotted("quasi knots", "3,1,1,3", "0.,1.,2.,3.", "3,3", "0.,1."),
        ),
        (
            format!("UNIFORM_SURFACE('uniform',{head})"),
            knotted(
                "uniform knots",
                "1,1,1,1,1,1,1,1",
                "-2.,-1.,0.,1.,2.,3.,4.,5.",
                "1,1,1,1,1,1",
                "-2.,-1.,0.,1.,2.,3.",
            ),
        ),
        (
            format!("BEZIER_SURFACE('bezier',{head})"),
            knotted("bezier knots", "3,2,3", "0.,1.,2.", "3,3", "0.,1."),
        ),
    ];
    for (implied, explicit) in cases {
        let text = file(&format!("{body}#1={implied};\n#2={explicit};\n"));
        let s = step::parse(&text).unwrap_or_else(|e| panic!("{e}\n{implied}"));
        assert_eq!(s.patches.len(), 2, "{:?}", s.notes);
        let (a, b) = (&s.patches[0].surface, &s.patches[1].surface);
        assert_eq!(a.domain(), b.domain(), "{implied}");
        let d = a.domain();
        for i in 0..=8 {
            for j in 0..=8 {
                let (u, v) = (d.u_at(i as f64 / 8.0), d.v_at(j as f64 / 8.0));
                assert_eq!(a.point(u, v), b.point(u, v), "{implied} at ({u}, {v})");
            }
        }
    }
    // 5 points are no pieces of degree 3: refused, naming the kind.
    let bad = file(&format!(
        "{body}#1=BEZIER_SURFACE('',3,2,({net}),.UNSPECIFIED.,.F.,.F.,.F.);\n"
    ));
    let e = err(&bad).to_string();
    assert!(
        e.contains("#1: BEZIER_SURFACE") && e.contains("degree 3"),
        "{e}"
    );
    // A B_SPLINE_SURFACE with no subtype has no knots at all: skipped under its own name.
    let bare = file(&format!(
        "{body}#1=(BOUNDED_SURFACE() B_SPLINE_SURFACE({head}) GEOMETRIC_REPRESENTATION_ITEM() \
         REPRESENTATION_ITEM('') SURFACE());\n"
    ));
    match err(&bare) {
        ReadError::Empty { detail, .. } => {
            assert!(
                detail.contains("surface type B_SPLINE_SURFACE is not"),
                "{detail}"
            )
        }
        e => panic!("{e}"),
    }
}

#[test]
fn a_misspelt_si_unit_name_is_refused_with_the_names_expected() {
    // `.METER.` is no SI unit name: the file was read as if in mm, with only a note.
    let body = |unit: &str| {
        format!(
            "#1=(LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,{unit}));\n\
             #2=(GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNIT_ASSIGNED_CONTEXT((#1)) \
             REPRESENTATION_CONTEXT('',''));\n\
             #3=CARTESIAN_POINT('',(0.,0.,0.));#4=DIRECTION('',(0.,0.,1.));\
             #5=DIRECTION('',(1.,0.,0.));#6=AXIS2_PLACEMENT_3D('',#3,#4,#5);\n\
             #7=SPHERICAL_SURFACE('',#6,5.);\n"
        )
    };
    match err(&file(&body(".METER."))) {
        ReadError::Entity {
            line: 5,
            entity,
            message,
            ..
        } => {
            assert_eq!(entity, "#1");
            assert!(
                message.contains(".METER.") && message.contains(".METRE."),
                "{message}"
            );
        }
        e => panic!("{e}"),
    }
    // An SI name, but not a length's.
    let e = err(&file(&body(".SECOND."))).to_string();
    assert!(e.contains(".SECOND.") && e.contains(".METRE."), "{e}");
    // The metre reads.
    let s = step::parse(&file(&body(".METRE."))).unwrap();
    assert!(s.notes.is_empty(), "{:?}", s.notes);
}
