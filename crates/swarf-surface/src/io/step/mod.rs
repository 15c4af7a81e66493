//! STEP (ISO 10303-21, AP203/AP214) surfaces.
//!
//! Read: `B_SPLINE_SURFACE_WITH_KNOTS` (simple, and the complex rational form with
//! `RATIONAL_B_SPLINE_SURFACE`), `UNIFORM_SURFACE`, `QUASI_UNIFORM_SURFACE` and
//! `BEZIER_SURFACE` (the same forms, with the knots ISO 10303-42 implies: uniform −d … n,
//! quasi-uniform 0 and n − d at both ends d + 1 times, Bézier pieces of degree d, for n control
//! points of degree d), `PLANE`, `CYLINDRICAL_SURFACE`, `CONICAL_SURFACE`,
//! `SPHERICAL_SURFACE`, `TOROIDAL_SURFACE`; and, built on those or on curves (see `swept.rs`),
//! `SURFACE_OF_REVOLUTION` and `SURFACE_OF_LINEAR_EXTRUSION` (exact NURBS of their swept line,
//! conic, B-spline or polyline), `RECTANGULAR_TRIMMED_SURFACE` (its basis over the rectangle;
//! one sense `.F.` reverses the normal, as ISO 10303-42 says), `OFFSET_SURFACE` of a plane,
//! cylinder, cone, sphere or torus (the same kind; a B-spline's offset is skipped with a note)
//! and `DEGENERATE_TOROIDAL_SURFACE` (the outer or the inner part); a swept `TRIMMED_CURVE`
//! keeps what its trims keep of its basis. A `CURVE_BOUNDED_SURFACE` outside a face is its
//! basis trimmed by its boundaries (`bounded.rs`). A surface that is the basis of a
//! rectangular trim, an offset or a curve-bounded surface is read only through it (unless a
//! face has it as its geometry).
//!
//! * **Patches**: when the file has faces (`ADVANCED_FACE`, `FACE_SURFACE`), one patch per face,
//!   named after the face (or its surface), flipped when the face's `same_sense` is `.F.`;
//!   faces on other surface kinds (a `CURVE_BOUNDED_SURFACE` among them) are skipped with a
//!   [`ReadNote::UnsupportedSurface`](crate::ReadNote::UnsupportedSurface). Then one patch per
//!   free surface: one a shape representation's items reach outside faces (through geometric
//!   sets, shells and surface models; not through curves, mapped items or styled items) —
//!   never a face's own surface again; free surfaces of kinds not read are skipped with the
//!   same note; a surface nothing refers to is in no shape and is not read. A file without
//!   faces gives one patch per surface instance.
//! * **Text**: strings are decoded as ISO 10303-21 encodes them (`\X2\…\X0\`, `\X4\…\X0\`,
//!   `\X\hh`, `\S\c`, `\\`), so names read as written in their CAD system.
//! * **Orientation**: an `ORIENTED_FACE`, `ORIENTED_OPEN_SHELL` or `ORIENTED_CLOSED_SHELL`
//!   with orientation `.F.` reverses its face (every face of its shell): the patch is flipped
//!   the other way, as if the face's `same_sense` were the opposite; the region its bounds
//!   enclose is the same. Reversals compose down the chain of solids, shells and oriented
//!   faces that holds a face (a reversed face in a reversed shell is not reversed); the voids
//!   of a `BREP_WITH_VOIDS` (`ORIENTED_CLOSED_SHELL(…, .F.)`) come out reversed. A face that
//!   its holders use both ways (two solids sharing it) gives one patch each way. Styled items
//!   and other references to a face do not count.
//! * **Face trims**: a face's bounds become the patch's [`Trim`](crate::Trim) (in the surface's own
//!   parameters), with a [`ReadNote::Trimmed`](crate::ReadNote::Trimmed): the `FACE_OUTER_BOUND` is the outer loop (no
//!   such bound: the loop with the largest parameter box), the other bounds are holes;
//!   `VERTEX_LOOP`s (a pole, an apex) enclose nothing and are left out, so a face bounded only
//!   by them is untrimmed. An `EDGE_LOOP` is walked through its `ORIENTED_EDGE`s and their
//!   `EDGE_CURVE`s (from the start to the end `VERTEX_POINT`, along or against the curve as
//!   `same_sense` says); a `POLY_LOOP` is a polygon. Edge curves read: `LINE`, `CIRCLE`,
//!   `ELLIPSE` (between the vertices' angles, a full turn when they are one vertex),
//!   `B_SPLINE_CURVE_WITH_KNOTS` (simple or rational complex; between the vertices' parameters,
//!   found by point inversion), `POLYLINE`, and through `SURFACE_CURVE`, `SEAM_CURVE`,
//!   `INTERSECTION_CURVE` and `TRIMMED_CURVE` their 3-D curve (run backwards for a trimmed
//!   curve whose `sense_agreement` is `.F.`). Each edge is sampled so that
//!   the chords, in parameters, stay within min(1e-3 mm, 1e-5 of the surface's size) of the
//!   curve on the surface (at least 4 steps per quarter turn, 8 per knot span), and each
//!   sample is mapped to the surface's parameters: in closed form on the elementary surfaces,
//!   by Newton inversion seeded from the previous sample (first: the nearest point of a grid)
//!   on B-spline surfaces. Angles are unwrapped along a loop; a loop is moved whole turns to
//!   lie in the parameter box (whose angle range may then start at the outer loop's), a hole
//!   across the box's edge is copied to the other side, a seam edge met twice on the same
//!   angle (through a pole or an apex) is moved a turn. Through a pole or an apex a loop runs
//!   along the box's edge there the way the face's side says (left of the loop, by the bound's
//!   orientation and the face's `same_sense`: towards −u along the top edge, +u along the
//!   bottom, up to a whole turn), so lunes wider than a half turn and their complements are
//!   told apart. A loop that winds once around the axis (a circle bounding a cylinder) is cut
//!   at the box's edge: two of them make the outer loop (the band between them; on a torus, of
//!   the two bands the one on the loops' face side, the box's other angle starting at it when
//!   it does not fit), one is closed along the box's far edge on the face's side. The outer
//!   loop's points on the box's edges across an angle sit a hair (1e-9 of a turn) outside it,
//!   so points on the seam inside a hole across it are off the part. Linear parameter ranges grow to
//!   hold the loops. An edge curve of another kind, a sample more than 1e-4 of the surface's
//!   size + 0.01 mm (or the file's declared `UNCERTAINTY_MEASURE_WITH_UNIT`, when coarser)
//!   off the surface, edges that do not join, a loop that does not close in
//!   the parameters or winds otherwise, or more than 200 000 points for a face (2 000 000 for
//!   the file) leave the patch untrimmed with a [`ReadNote::TrimNotHonoured`](crate::ReadNote::TrimNotHonoured) saying why.
//! * **Units**: the length unit of the `GLOBAL_UNIT_ASSIGNED_CONTEXT` (`SI_UNIT` with any prefix,
//!   or a `CONVERSION_BASED_UNIT` such as INCH or FOOT, resolved through its
//!   `LENGTH_MEASURE_WITH_UNIT`, simple or complex with the value in its `MEASURE_WITH_UNIT`
//!   part) scales lengths to mm; the plane-angle unit scales cone angles. An `SI_UNIT` whose
//!   name is not one of ISO 10303-41's (`.METER.`), or a length (plane-angle) unit not named
//!   `.METRE.` (`.RADIAN.`), refuses the file.
//!   No unit: mm, with a [`ReadNote::UnitsAssumed`](crate::ReadNote::UnitsAssumed). When unit
//!   contexts declare different length units, each face (each surface, in a file without
//!   faces) is read in the units of the representation that holds it (`(name, items,
//!   context)`, its items followed through shells and models to the faces, not into other
//!   representations), with a [`ReadNote::UnitsMixed`](crate::ReadNote::UnitsMixed); a face in
//!   no representation, or in several of different units, takes the first context's.
//! * **Assemblies**: placements of parts are applied, as a CAD kernel's reader (OCCT's
//!   `STEPControl_Reader`) applies them. The nodes are the shape representations
//!   (`…SHAPE_REPRESENTATION(name, items, context)`, simple or complex); those related by a
//!   `SHAPE_REPRESENTATION_RELATIONSHIP` without a transformation (a product's
//!   `SHAPE_REPRESENTATION` and the `ADVANCED_BREP_SHAPE_REPRESENTATION` /
//!   `MANIFOLD_SURFACE_SHAPE_REPRESENTATION` of its geometry) share one frame. Two things place
//!   one in another:
//!   - a `MAPPED_ITEM('', REPRESENTATION_MAP(origin, rep), target)` among a representation's
//!     items places `rep` in it by the motion taking `origin` (an `AXIS2_PLACEMENT_3D`) onto
//!     `target` (an `AXIS2_PLACEMENT_3D`, or a `CARTESIAN_TRANSFORMATION_OPERATOR_3D`: then the
//!     operator after the inverse of `origin`);
//!   - a representation relationship with a transformation, `(REPRESENTATION_RELATIONSHIP('',
//!     '', rep_1, rep_2) REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION(t)
//!     SHAPE_REPRESENTATION_RELATIONSHIP())` (the `representation_relation` of an assembly
//!     occurrence's `CONTEXT_DEPENDENT_SHAPE_REPRESENTATION`), places `rep_1` (the component)
//!     in `rep_2` (the assembly): with `t = ITEM_DEFINED_TRANSFORMATION('', '', item_1,
//!     item_2)` (two `AXIS2_PLACEMENT_3D`s, item 1 in `rep_1`'s context, item 2 in `rep_2`'s)
//!     by the motion `item_2 ∘ item_1⁻¹` taking frame item 1 onto frame item 2 — the
//!     component's points, given in item 1's frame, land at the same coordinates in item 2's;
//!     with a `CARTESIAN_TRANSFORMATION_OPERATOR_3D` by the operator. Rep 1 the child and rep 2
//!     the parent is OCCT's convention and what CAD systems write, with item 1 the component's
//!     origin (the world frame) and item 2 its placement in the assembly, so that the
//!     component lands on item 2. (OCCT computes `item_1⁻¹ ∘ item_2`,
//!     `gp_Trsf::SetTransformation(item_2, item_1)`: the same motion when either item is the
//!     world frame, as item 1 is in CAD exports, or both are translations; otherwise
//!     `item_2 ∘ item_1⁻¹` is the one that takes item 1 onto item 2, as ISO 10303-43 says.
//!     The same holds for a mapped item's origin and target.) When the
//!     `NEXT_ASSEMBLY_USAGE_OCCURRENCE` of the `CONTEXT_DEPENDENT_SHAPE_REPRESENTATION` says the
//!     other way round (through the `SHAPE_DEFINITION_REPRESENTATION`s of its relating and
//!     related product definitions, `rep_1` is the assembly's and `rep_2` the component's), the
//!     component `rep_2` is placed in `rep_1` by the inverse motion. A relationship the
//!     occurrence names without a transformation places at the identity.
//!
//!   The tree is walked from its roots (representations no placement places) down, the
//!   placements composed through nested sub-assemblies; each face (each surface, in a file
//!   without faces) a placed representation holds (its items followed through shells, solids
//!   and models, not into other representations, mapped items or styled items) gives one
//!   patch per placed instance, moved by the instance's motion, and named, when there are
//!   several, with the instance's path of placing entities (`skin@#43/#57`: the assembly
//!   occurrence, or the mapped item, at each level). Motions are rigid, or similarities with
//!   a uniform positive scale (the operator's): NURBS control points move (weights and knots
//!   unchanged), elementary surfaces' frames move and their radii scale; the trims stay in the
//!   surface's parameters, scaled along the linear parameters (plane u and v, cylinder and
//!   cone v) under a scale. Placement lengths are in the units of the representation whose
//!   context holds them. A [`ReadNote::PlacementsApplied`](crate::ReadNote::PlacementsApplied)
//!   counts the placed instances and parts (when a placement reaches any face). A placement
//!   that cannot be applied gets a
//!   [`ReadNote::PlacementNotApplied`](crate::ReadNote::PlacementNotApplied) naming it and
//!   saying why: a transformation of another kind, whose items are not axis placements, that
//!   mirrors, that scales outside [1e-6, 1e6] or moves beyond 1e9 mm (its component is placed
//!   without it, as OCCT does); composed with the placements above it, out of that range (that
//!   instance left out); a mapped item or relationship whose representations cannot be
//!   resolved; a placement in a cycle (not followed); a mapped item of a shape representation
//!   that no shape representation holds; an assembly occurrence with neither a
//!   `CONTEXT_DEPENDENT_SHAPE_REPRESENTATION` nor a mapped item placing its component;
//!   nesting deeper than 64 levels; a placement of a representation that holds no faces while
//!   some faces are read unplaced. More than 100 000 placed instances, placed faces making
//!   more than 500 000 patches, or more than 2 million B-spline control points or 50 million
//!   trim points summed over the placed instances (each instance copies its surface and its
//!   trim) refuse the file, before the copies are made. A face no placement reaches (every
//!   face of a single-part file) is read once, in its own frame, as it is written.
//! * **Parameter boxes of elementary surfaces**: angles take their full range (u ∈ [0, 2π];
//!   sphere v ∈ [−π/2, π/2]; torus v ∈ [0, 2π]); linear parameters (plane u, v; cylinder and
//!   cone v) span the face's boundary: its vertices, the control points of its B-spline edges
//!   and its circles and ellipses, projected — a range that holds the face, possibly larger.
//!   Without a face, or with a boundary of zero extent, they take [`DEFAULT_LINEAR_RANGE`] and
//!   a [`ReadNote::DefaultParameterBox`](crate::ReadNote::DefaultParameterBox) says so.
//! * **A trimmed face's box** (every kind, B-splines too) is then cut down to its outer loop's
//!   extent in the parameters (an angle range starting where the loop lies, as above), so that
//!   the planner's grid over the box covers the face rather than its whole surface; a
//!   B-spline surface is cut exactly ([`NurbsSurface::restricted`](crate::NurbsSurface::restricted)),
//!   its parameters kept. A placement's reference direction left out (`$`) is ISO 10303-42's
//!   `first_proj_axis`: (1, 0, 0) made square to the axis, (0, 1, 0) for an axis along ±X.

mod assembly;
mod bounded;
mod curves;
mod entities;
mod lex;
mod orient;
mod swept;
mod trims;

use super::ReadError;
use crate::compound::CompoundSurface;
use entities::Model;
use lex::Lexer;

/// Range (mm) of a linear parameter of an elementary surface when no face bounds it.
pub const DEFAULT_LINEAR_RANGE: [f64; 2] = [-100.0, 100.0];

/// Parse STEP text.
pub fn parse(text: &str) -> Result<CompoundSurface, ReadError> {
    let map = Lexer::new(text).instances()?;
    let mut model = Model {
        text,
        map,
        length: 1.0,
        angle: 1.0,
        accuracy: 0.0,
    };
    model.accuracy = model.declared_accuracy();
    model.read()
}

#[cfg(test)]
mod tests {
    use super::lex::{Lexer, Param};
    use super::*;

    #[test]
    fn lexer_handles_strings_comments_and_complex_instances() {
        let t = "ISO-10303-21;\nHEADER;FILE_NAME('a''b;','x');ENDSEC;\nDATA;\n/* c */ #1=( A(1,2.5E1) B('it''s',.T.,$,*,(#2,-3.)) );\n#2=C(LENGTH_MEASURE(1.));\nENDSEC;END-ISO-10303-21;";
        let m = Lexer::new(t).instances().unwrap();
        assert_eq!(m.len(), 2);
        let i = &m[&1];
        assert_eq!(i.parts.len(), 2);
        assert_eq!(i.part("A").unwrap(), &[Param::Num(1.0), Param::Num(25.0)]);
        assert_eq!(i.part("B").unwrap()[0], Param::Str("it's".into()));
        assert_eq!(i.part("B").unwrap()[1], Param::Enum("T".into()));
        assert_eq!(
            m[&2].part("C").unwrap()[0],
            Param::Typed("LENGTH_MEASURE".into(), vec![Param::Num(1.0)])
        );
    }

    #[test]
    fn syntax_errors_have_positions() {
        let t = "ISO-10303-21;\nDATA;\n#1=A(1,2;\nENDSEC;";
        match Lexer::new(t).instances() {
            Err(ReadError::Syntax {
                line,
                column,
                message,
                ..
            }) => {
                assert_eq!((line, column), (3, 9), "{message}");
                assert!(message.contains("expected `,` or `)`"), "{message}");
            }
            other => panic!("{other:?}"),
        }
    }
}
