//! The surface foundation of swarf's tool-size and orientation planner: compound surfaces made
//! of patches, read from swarf JSON, STEP and IGES, with exact differential geometry.
//!
//! # Model
//! A [`CompoundSurface`] is a list of [`Patch`]es. Each patch is a [`Surface`] — a rational or
//! polynomial tensor-product NURBS of any degree, or one of STEP's elementary surfaces (plane,
//! cylinder, cone, sphere, torus, with STEP's own parametrisation) — over a finite parameter
//! box, plus a `flipped` flag and its provenance.
//!
//! * **Units**: every length is in millimetres (readers convert inch, foot, metre… files);
//!   angular parameters of analytic surfaces are radians; curvatures are in 1/mm.
//! * **Normals point to the side the cutter comes from.** For an unflipped patch that is
//!   `S_u × S_v`; `flipped` negates it (STEP faces with `same_sense = .F.` are read flipped;
//!   [`CompoundSurface::flip_all`] is the CLI's `--flip`).
//! * **Curvatures** are signed against that normal: positive where the surface bends towards
//!   the cutter (concave, where a ball of radius `1/k` fits), negative where it bends away.
//! * **Parametrisation**: NURBS over `[U_p, U_n] × [V_q, V_m]`, control point `[i][j]` along u
//!   then v. Elementary surfaces as in ISO 10303-42 (see each type); their parameter box comes
//!   from the face bounds for linear parameters and is the full period for angles.
//! * **Degenerate points** (poles, collapsed edges, cone apices) never yield NaN: the normal is
//!   a [`SurfaceNormal`] that is `Regular`, `Limit` (the limit from inside the domain) or
//!   `Undefined`, so callers must decide what to do.
//! * **Tolerances** are named parameters: [`Tolerances`] (with documented defaults).
//!
//! [`size`] answers the planner's first question on top of this: the largest gouge- and
//! interference-free cutter of a family at every CC point (3-, 4- and 5-axis), certified or by
//! the thesis's particle swarm. [`gouge`] answers the converse for a given cutter and program:
//! where, along every move, the cutter gouges the surface or the tool interferes, and how deep.
//!
//! Evaluation is allocation-free for degrees up to 7 and meant for hot loops:
//! [`ParametricSurface::derivs`] gives the point with first and second partials;
//! [`Patch::local`] adds the normal and principal curvatures.
//!
//! ```
//! use swarf_plan::{io, ParametricSurface, SurfaceNormal, Tolerances};
//! // A 10 mm square floor at z = 0, the cutter above it (S_u × S_v = +z).
//! let json = r#"{"units": "mm", "patches": [{"name": "floor", "degree_u": 1, "degree_v": 1,
//!   "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
//!   "control_points": [[[0, 0, 0, 1], [0, 10, 0, 1]], [[10, 0, 0, 1], [10, 10, 0, 1]]]}]}"#;
//! let mut part = io::json::parse(json)?;
//! let g = part.patches[0].local(0.5, 0.5, &Tolerances::DEFAULT);
//! assert!((g.point() - swarf_geom::math::Vec3::new(5.0, 5.0, 0.0)).length() < 1e-12);
//! assert_eq!(g.normal, SurfaceNormal::Regular(swarf_geom::math::Vec3::Z));
//! assert_eq!(g.curvature.unwrap().k1, 0.0);
//! assert_eq!(part.grid(21).len(), 21 * 21);
//! part.flip_all();
//! let g = part.patches[0].local(0.5, 0.5, &Tolerances::DEFAULT);
//! assert_eq!(g.normal.vector(), Some(-swarf_geom::math::Vec3::Z));
//! # Ok::<(), swarf_plan::io::ReadError>(())
//! ```

pub mod compound;
pub mod gouge;
pub mod io;
pub mod mesh;
pub mod plot;
pub mod size;
pub mod surface;
pub mod trim;

pub use compound::{
    CcPoint, CcPointError, CompoundSurface, EntityRef, Patch, PatchSource, ReadNote,
};
pub use mesh::{tessellate, TriangleMesh};
pub use surface::{
    differential, ConicalSurface, Curvature, CylindricalSurface, Derivs, LocalGeometry, NurbsError,
    NurbsSurface, ParamBox, ParametricSurface, PlaneSurface, SphericalSurface, Surface,
    SurfaceNormal, Tolerances, ToroidalSurface,
};
pub use trim::{Coverage, Trim, TrimError};
