//! Meshes and pictures in and out of swarf: an indexed triangle mesh ([`TriMesh`], the one
//! triangle-mesh type of the workspace), its writers (binary and ASCII STL, glb, PLY) and
//! readers (STL, and glb/PLY for checking round trips), colour maps for per-vertex colouring,
//! pictures ([`image`]: an RGB raster with a built-in pixel font, written as PNG, so every
//! crate draws its plots the same way), and **dual contouring** of Hermite data on a regular
//! lattice ([`dual_contour`]), which turns a tri-dexel stock into the closed mesh of the
//! machined part, and the merge of a closed mesh's coplanar triangles into few
//! ([`TriMesh::merge_coplanar`], module [`planar`]).
//!
//! # Model and conventions
//! - Positions are `f64` millimetres ([`swarf_geom::math::Vec3`]) in the workpiece frame; the
//!   file formats store `f32`.
//! - Triangles are counter-clockwise seen from outside: normals point out of the solid, and the
//!   signed [`TriMesh::volume`] of a closed mesh is positive. [`TriMesh::edge_report`] proves
//!   closedness (every edge used by exactly two triangles, in opposite directions).
//! - Every writer writes a temporary file beside the target and renames it into place
//!   ([`write_atomic`]): a failed or interrupted write never leaves a partial file.
//! - Readers never panic on bad input; their errors ([`IoError`]) name the file, what was found
//!   and what was expected.
//! - Tolerances are named in [`tolerance`] and passed through option structs.
//!
//! # Contouring a solid
//! A [`HermiteGrid`] reports the solid's intervals along every lattice line of the three axes —
//! what a tri-dexel stores per ray. [`dual_contour`] reads the membership of lattice points and
//! the exact crossings from them, estimates normals where none are given, and places one vertex
//! per cell patch by minimising a quadric error function, which keeps walls flat and 90° edges
//! and corners sharp (see [`contour`]).
//!
//! ```
//! use swarf_geom::math::Vec3;
//! use swarf_geom::Aabb;
//! use swarf_io::{dual_contour, ContourOptions, FnGrid, Lattice};
//!
//! // A 2 × 1.4 × 1 box, sampled every 0.13 mm; normals estimated from the crossings.
//! let (lo, hi) = (Vec3::new(-1.0, -0.7, -0.5), Vec3::new(1.0, 0.7, 0.5));
//! let sdf = move |p: Vec3| {
//!     let q = (p - 0.5 * (lo + hi)).abs() - 0.5 * (hi - lo);
//!     q.max(Vec3::ZERO).length() + q.max_element().min(0.0)
//! };
//! let lattice = Lattice::covering(Aabb::new(lo, hi).inflated(0.3), 0.13);
//! let mesh = dual_contour(&FnGrid::new(lattice, sdf), &ContourOptions::default());
//! assert!(mesh.edge_report().is_clean());
//! assert!((mesh.volume() - 2.0 * 1.4 * 1.0).abs() < 1e-9);
//!
//! let dir = std::env::temp_dir().join(format!("swarf-io-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&dir).unwrap();
//! swarf_io::write_stl(&dir.join("box.stl"), &mesh).unwrap();
//! swarf_io::write_glb(&dir.join("box.glb"), &mesh, &Default::default()).unwrap();
//! let back = swarf_io::read_stl(&dir.join("box.stl")).unwrap();
//! assert_eq!(back.triangles.len(), mesh.triangles.len());
//! std::fs::remove_dir_all(&dir).unwrap();
//! ```

pub mod atomic;
pub mod color;
pub mod contour;
pub mod error;
pub mod glb;
pub mod html;
pub mod image;
pub mod mesh;
pub mod output_set;
pub mod planar;
pub mod ply;
pub mod stl;
pub mod tolerance;

pub use atomic::write_atomic;
pub use color::ColorMap;
pub use contour::{
    dual_contour, dual_contour_projected, dual_contour_projected_owned, dual_contour_with_stats,
    ContourOptions, ContourStats, FnGrid, HermiteGrid, Lattice, QuadSplit, Span,
};
pub use error::IoError;
pub use glb::{read_glb, write_glb, GlbOptions, Shading};
pub use mesh::{BadEdge, DegenerateRepair, EdgeReport, TriMesh};
pub use output_set::{FileBody, OutputSet, DEFAULT_MAX_OUTPUT_BYTES};
pub use planar::PlanarMerge;
pub use ply::{read_ply, write_ply};
pub use stl::{read_stl, write_stl, write_stl_ascii, write_stl_to};
