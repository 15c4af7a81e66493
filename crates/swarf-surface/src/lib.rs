//! The part surface of swarf: compound surfaces made of patches, with their trims, exact
//! differential geometry, rational Bézier pieces for rigorous bounds, a triangle mesh for
//! viewing, and the readers of swarf JSON, STEP and IGES.
//!
//! # Model
//! A [`CompoundSurface`] is a list of [`Patch`]es. Each patch is a [`Surface`] — a rational or
//! polynomial tensor-product NURBS of any degree, or one of STEP's elementary surfaces (plane,
//! cylinder, cone, sphere, torus, with STEP's own parametrisation) — over a finite parameter
//! box, plus a `flipped` flag, an optional [`Trim`] (the part of the box that is the part) and
//! its provenance.
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
//! * **Trims** are closed polygons in the patch's parameters ([`trim`]); nothing downstream
//!   knows which file format a trim came from.
//! * **Degenerate points** (poles, collapsed edges, cone apices) never yield NaN: the normal is
//!   a [`SurfaceNormal`] that is `Regular`, `Limit` (the limit from inside the domain) or
//!   `Undefined`, so callers must decide what to do.
//! * **Tolerances** are named parameters: [`Tolerances`] (with documented defaults).
//!
//! # What is built on it
//! [`PreparedSurface`] cuts every patch into rational Bézier pieces ([`bezier`]: NURBS at their
//! knots, elementary surfaces as exact rational arcs), each knowing how much of it is on the
//! trimmed part: the one representation every certified search of the planner (`swarf-plan`)
//! walks. [`tessellate`] gives a [`SurfaceMesh`] for viewing; [`io`] reads and writes files;
//! [`build`] writes analytic shapes and sampled height fields exactly as NURBS.
//!
//! Evaluation is allocation-free for degrees up to 7 and meant for hot loops:
//! [`ParametricSurface::derivs`] gives the point with first and second partials;
//! [`Patch::local`] adds the normal and principal curvatures.
//!
//! ```
//! use swarf_surface::{io, ParametricSurface, PreparedSurface, SurfaceNormal, Tolerances};
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
//! assert_eq!(PreparedSurface::new(&part).piece_count(), 1);
//! part.flip_all();
//! let g = part.patches[0].local(0.5, 0.5, &Tolerances::DEFAULT);
//! assert_eq!(g.normal.vector(), Some(-swarf_geom::math::Vec3::Z));
//! # Ok::<(), swarf_surface::io::ReadError>(())
//! ```

pub mod bezier;
pub mod build;
pub mod compound;
pub mod curve;
pub mod io;
pub mod mesh;
mod placement;
pub mod surface;
mod sweep;
pub mod trim;

pub use bezier::{CheckMeshError, PreparedSurface};
pub use compound::{
    Caveats, CcPoint, CcPointError, CompoundSurface, EntityRef, Patch, PatchSource, ReadNote,
    UnhonouredTrim,
};
pub use curve::{BSplineCurve, CurveError};
pub use mesh::{tessellate, SurfaceMesh};
pub use surface::{
    differential, ConicalSurface, Curvature, CylindricalSurface, Derivs, LocalGeometry, NurbsError,
    NurbsSurface, ParamBox, ParametricSurface, PlaneSurface, SphericalSurface, Surface,
    SurfaceNormal, Tolerances, ToroidalSurface,
};
pub use trim::{Coverage, Trim, TrimError};
