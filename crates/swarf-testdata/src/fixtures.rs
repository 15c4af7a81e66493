//! Small test inputs written by code, so that every checkout has them.

/// A STEP AP214 file (written for swarf's tests) of one closed face on a spherical surface of
/// radius `r` mm about the origin, as CAD systems write a sphere: an `ADVANCED_FACE` of a
/// `SPHERICAL_SURFACE` bounded by a vertex loop at the south pole, in millimetres.
#[must_use]
pub fn sphere_step(r: f64) -> String {
    format!(
        "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('swarf test sphere'),'2;1');\n\
         FILE_NAME('sphere.step','2026-01-01T00:00:00',(''),(''),'swarf tests','','');\n\
         FILE_SCHEMA(('AUTOMOTIVE_DESIGN {{ 1 0 10303 214 1 1 1 1 }}'));\nENDSEC;\nDATA;\n\
         #10 = ADVANCED_BREP_SHAPE_REPRESENTATION('',(#15),#27);\n\
         #15 = MANIFOLD_SOLID_BREP('',#16);\n\
         #16 = CLOSED_SHELL('',(#17));\n\
         #17 = ADVANCED_FACE('',(#18),#22,.T.);\n\
         #18 = FACE_BOUND('',#19,.T.);\n\
         #19 = VERTEX_LOOP('',#20);\n\
         #20 = VERTEX_POINT('',#21);\n\
         #21 = CARTESIAN_POINT('',(0.,0.,{south:?}));\n\
         #22 = SPHERICAL_SURFACE('',#23,{r:?});\n\
         #23 = AXIS2_PLACEMENT_3D('',#24,#25,#26);\n\
         #24 = CARTESIAN_POINT('',(0.,0.,0.));\n\
         #25 = DIRECTION('',(0.,0.,1.));\n\
         #26 = DIRECTION('',(1.,0.,0.));\n\
         #27 = ( GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNIT_ASSIGNED_CONTEXT((#28,#29)) \
         REPRESENTATION_CONTEXT('','') );\n\
         #28 = ( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.) );\n\
         #29 = ( NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.) );\n\
         ENDSEC;\nEND-ISO-10303-21;\n",
        south = -r
    )
}
