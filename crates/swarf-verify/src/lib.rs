//! Verification of the machined part against the design part: what the machine will leave,
//! compared with what was wanted.
//!
//! # Model
//! The machined stock is `swarf-stock`'s tri-dexel after a program was simulated; its sampled
//! surface is the set of **exact ray ends** (the enter and exit of every interval of the X, Y
//! and Z rays), each on the true swept boundary. For each end, the signed distance to the
//! design ([`Design::project`]) is exact to the design's own geometry — for a closed STL part
//! ([`MeshDesign`]) the exact point–triangle distance through a BVH, signed by the
//! angle-weighted pseudo-normal — not a second voxelisation. Conventions: millimetres, the
//! workpiece frame; the **deviation** is positive outside the design (material left: excess)
//! and negative inside (material removed from the part: gouge).
//!
//! An end deeper inside the design than the gouge tolerance is a gouge end, one farther outside
//! than the excess tolerance an excess end ([`VerifyOptions`], defaults 0.01 mm). Ends of one
//! kind within [`DEFAULT_LINK_CELLS`] cells of each other form a connected [`Region`], with
//! its deepest point, depth, surface area, volume (for a solid design: the exact Z-ray pieces
//! of stock ∖ part or part ∖ stock) and, when the stock tracked provenance
//! ([`swarf_stock::TriDexel::track_provenance`]), the moves — and with the program, the file
//! and line — that cut it. [`deviation_mesh`] colours the machined part by deviation.
//!
//! Accuracy: a deviation is exact at the ray end; what the grid can miss is a defect narrower
//! than the ray spacing `h` between rays, and a region's depth is the deepest *sampled* end —
//! the true extreme of a curved defect lies within `h/2` of a ray, so its depth is
//! under-estimated by at most the defect's depth change over `h/2` (for a flat-bottomed gouge:
//! nothing).
//!
//! ```
//! use swarf_geom::math::Vec3;
//! use swarf_stock::TriDexel;
//! use swarf_verify::{verify, MeshDesign, VerifyOptions};
//! // The design: a 10 × 10 × 4 block; the stock: the same block 5 mm tall (1 mm excess).
//! let design = MeshDesign::new(&swarf_verify::box_mesh(Vec3::ZERO, Vec3::new(10.0, 10.0, 4.0)))
//!     .unwrap();
//! let stock = TriDexel::from_box(Vec3::ZERO, Vec3::new(10.0, 10.0, 5.0), 0.5).unwrap();
//! let v = verify(&stock, &design, None, &VerifyOptions::default()).unwrap();
//! assert_eq!(v.regions.len(), 1);
//! assert!((v.max_excess_mm - 1.0).abs() < 1e-9);
//! assert!((v.excess_volume_mm3.unwrap() - 100.0).abs() < 1e-9);
//! ```

pub mod design;
pub mod deviation;
pub mod error;
pub mod report;
pub mod surface;
pub mod union;
pub mod verify;

pub use design::{Design, MeshDesign, Projection};
pub use deviation::{deviation_mesh, Legend};
pub use error::VerifyError;
pub use report::{html_report, ReportInputs};
pub use surface::{SurfaceDesign, DEFAULT_SURFACE_ACCURACY_MM};
pub use union::UNION_GAP_MM;
pub use verify::{
    verify, verify_observed, DefectEnd, DefectKind, Histogram, Region, RegionMove, Verification,
    VerifyOptions, DEFAULT_EXCESS_TOLERANCE_MM, DEFAULT_GOUGE_TOLERANCE_MM, DEFAULT_LINK_CELLS,
    MAX_REGION_MOVES, ROUNDING_MM,
};

use swarf_geom::math::Vec3;

/// The closed, outward-oriented 12-triangle mesh of the box `min`–`max` (for tests, examples
/// and simple designs).
pub fn box_mesh(min: Vec3, max: Vec3) -> swarf_io::TriMesh {
    swarf_io::TriMesh::cuboid(min, max)
}
