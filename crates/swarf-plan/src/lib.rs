//! swarf's tool-size and orientation planner, over the part surfaces of `swarf-surface`.
//!
//! [`size`] answers the planner's first question: the largest gouge- and interference-free
//! cutter of a family at every CC point of a compound surface (3-, 4- and 5-axis), certified by
//! a branch-and-bound over the surface's Bézier pieces or found by the thesis's particle swarm,
//! with standard-cutter selection. [`gouge`] answers the converse for a given cutter and
//! program: where, along every move, the cutter gouges the surface or the tool interferes, and
//! how deep (certified). [`plot`] draws the size maps (PNG per patch, the coloured part as glb).
//!
//! Units are those of the surface crate: millimetres, radians inside, degrees at the interfaces
//! that say so; normals point to the side the cutter comes from.
//!
//! ```
//! use swarf_plan::size::{allowable_certified, CertifiedOptions, Contact, CutterFamily};
//! use swarf_surface::{io, PreparedSurface, Tolerances};
//! // A 10 mm square floor at z = 0: nothing limits a ball standing on it.
//! let json = r#"{"units": "mm", "patches": [{"name": "floor", "degree_u": 1, "degree_v": 1,
//!   "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
//!   "control_points": [[[0, 0, 0, 1], [0, 10, 0, 1]], [[10, 0, 0, 1], [10, 10, 0, 1]]]}]}"#;
//! let part = io::json::parse(json)?;
//! let cc = part.grid(3)[4]; // the middle of the floor
//! let contact = Contact::at(&part, &cc, &Tolerances::DEFAULT).unwrap();
//! let prepared = PreparedSurface::new(&part);
//! let ball = CutterFamily::ball();
//! let size = allowable_certified(&prepared, &ball, &contact, &CertifiedOptions::default());
//! assert!(size.size.is_infinite());
//! # Ok::<(), swarf_surface::io::ReadError>(())
//! ```

pub mod gouge;
pub mod plot;
pub mod size;
