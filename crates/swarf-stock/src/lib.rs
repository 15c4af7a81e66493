//! The in-process workpiece of swarf: a tri-dexel stock and exact material removal.
//!
//! # Model
//! The stock is a **tri-dexel** model (Aras 2008, §4.2): three families of parallel rays along
//! X, Y and Z. The rays of a family pass through the **cell centres** of a grid over the
//! stock's bounding box (cell size ≤ the requested resolution `h`, adjusted per axis so an
//! integer number of cells spans the box exactly), and each ray holds the sorted, disjoint
//! intervals `[enter, exit]` of material along it, in workpiece coordinates along the ray's
//! axis. A ray holds two intervals inline and spills to the heap once when it needs more; rays
//! are stored in 10 × 10 tiles (`TILE`), each with a conservative bound of its material, so
//! that a move touches only the tiles and rays that cross its swept volume's bounding box and
//! that hold material in its range (nothing scans the whole grid per move).
//!
//! Conventions: millimetres; the **workpiece frame** of `swarf-path` (tool tip and axis of
//! each move); the tool axis points from the tip to the spindle; volumes come from the Z rays
//! (`Σ lengths × cell area`), the X and Y estimates are reported as a cross-check.
//!
//! # Cutting
//! For a straight move with a fixed tool axis (3-axis and 3+2), the interval of each touched
//! ray inside the volume swept by the cutter's **cutting part** is computed exactly
//! (`swarf_sweep::swept`: caps, grazing-curve envelopes in closed form, torus by guaranteed root
//! isolation) and subtracted. Arcs and helices are cut as chords through exact arc points,
//! at most the chordal tolerance ([`DEFAULT_CHORDAL_TOLERANCE_MM`]) from the arc: the chords
//! lie inside the arc's convex hull, so the removal **under-cuts** by at most that tolerance.
//! Shank and holder sweeps are cut too and reported as collisions, as are rapids whose
//! cutting part meets material. Moves whose tool axis turns (5-axis simultaneous) are cut as
//! constant-axis straight sub-moves by adaptive bisection until a proven bound on the distance
//! between their sweep and the true one is within the same tolerance (`swarf_sweep::five_axis`, cut by [`cut`]).
//!
//! Everything else is exact up to floating point: the only discretisation is the ray grid
//! itself (the volume error shrinks with `h`), the chords of arcs and the 5-axis sub-moves.
//!
//! # Work per move
//! Material first: a move visits only the tiles of rays that cross its swept bounding box;
//! a tile is skipped when its material bound cannot meet a cheap range of the sweep along its
//! rays (`SweptConvex::block_range`: for a tool axis along a world axis, the lowest reach of
//! the profile at the tile's distance from the tip path, or the chord of the stadium of the
//! largest radius at the tile's heights); then each ray is skipped the same way
//! (`SweptConvex::dexel_range`); only rays whose material meets that range get the exact
//! interval, and within it the pieces that cannot move its ends inside the material are not
//! evaluated. The common case — a ball or flat end mill (or a cylindrical shank) on a move
//! whose tool axis is a world axis, or a bull-nose on such a move — skips all that for
//! closed-form kernels, chosen once per move (`SweptConvex::has_closed_form`): a capsule, a
//! swept slab, or the bull-nose's lozenge swept across its axis or along it as a product of a
//! stadium and a height interval (on a ramp: its Newton search alone), a few square roots per
//! ray, held to the general candidates by `tests/fast_paths.rs`; so does a flat, ball or
//! bull-nose tool *instance* at any axis (the cuts a 5-axis move is made of): its bounding
//! cylinder's chord (one quadratic) leaves most rays at once, and only a chord end below the
//! corner's spine inside the material needs the lozenge (`swept/instance.rs`, held to the
//! general candidates by `tests/instance_paths.rs`); and so does a flat, ball or bull-nose end mill
//! (a band of one, a shank) moving with its axis fixed off the world axes (3+2 moves, the
//! fixed-axis pieces of a 5-axis flat end mill): the swept slab's chord from at most fourteen
//! candidate points in the plane of the line parameter and the move's (`swept/tilted.rs`), the
//! sphere's capsule for a ball, the swept lozenge for a bull-nose, after the ray's material is
//! checked against the sweep's box in the move frame.
//! The tile's reach found first (the union of the parts' block ranges) is also the range each of
//! its rays' material must meet to be looked at. Consecutive moves are
//! cut in batches ([`TriDexel::cut_linear_batch`], used by [`simulate()`]; a 5-axis move's
//! instances are such a batch too): each tile row of the three families that the batch
//! reaches is one unit of work, taken by whichever thread is free (rayon), that runs the
//! batch's moves in order over its row — no barrier per move, the row's tiles stay in cache
//! from one move to the next, and the per-move figures are summed in row order; the per-ray
//! loop does not allocate. A computation made of many such short sections with serial work
//! between them (the simulation's moves cut one by one, an engagement's locations) runs under
//! [`pool::hot`], which keeps the pool's workers awake so that each section starts at once.
//!
//! # Accuracy parameters (one place)
//! [`DEFAULT_CHORDAL_TOLERANCE_MM`] (arcs and 5-axis moves, reported in
//! [`SimulationReport`]), the grid resolution (per stock), `swarf_sweep::swept::AXIS_SNAP` and
//! `swarf_sweep::swept::BAND_EPS` (floating-point guards of the exact cut, far below any resolution),
//! [`dexel::MIN_INTERVAL_MM`] (slivers dropped), `swarf_sweep::swept::SLIVER_MM` (material
//! ending within it inside a tool instance is left), [`cut::COLLISION_EPS_MM`] (removal that
//! counts as a collision) and `swarf_sweep::five_axis::MAX_SUB_MOVES` (a guard, not an accuracy).
//!
//! ```
//! use swarf_geom::math::Vec3;
//! use swarf_stock::TriDexel;
//! use swarf_sweep::ToolShape;
//! use swarf_tool::Cutter;
//! let mut stock = TriDexel::from_box(Vec3::ZERO, Vec3::new(40.0, 20.0, 10.0), 0.25).unwrap();
//! let v0 = stock.volume();
//! assert!((v0 - 8000.0).abs() < 1e-9);
//! // A 6 mm flat end mill cuts a 2 mm deep slot along X through the middle.
//! let tool = ToolShape::new(&Cutter::flat(6.0).unwrap());
//! let cut = stock.cut_linear(&tool, Vec3::new(-5.0, 10.0, 8.0), Vec3::new(45.0, 10.0, 8.0), Vec3::Z);
//! let removed = v0 - stock.volume();
//! assert!((removed - 40.0 * 6.0 * 2.0).abs() / 480.0 < 0.02, "{removed}");
//! assert!(cut.non_cutting.removed_length == [0.0; 3]);
//! ```

pub mod columns;
pub mod contour;
pub mod cut;
pub mod dexel;
pub mod error;
pub mod mesh;
pub mod pool;
pub mod simulate;
pub mod spec;
pub mod tridexel;
pub mod unite;

pub use columns::ColumnTops;
pub use cut::{
    DEFAULT_CHORDAL_TOLERANCE_MM, PIECES_PER_BATCH, RAPID_TOLERANCE_MM, SCREEN_TOLERANCE_MM,
};
pub use dexel::{Dexel, DexelTags, EndTags, Interval, MoveTag, UNCUT};
pub use error::StockError;
pub use mesh::{axis_line_intervals, MeshOptions};
pub use simulate::{
    collides, reach, simulate, simulate_observed, Collision, Reach, SimOptions, SimulationReport,
    SliverZones,
};
pub use spec::StockSpec;
pub use tridexel::{
    CutStats, DexelFamily, Grid, LinearMove, Removal, RemovalVisitor, SegmentCut, StockStats,
    TriDexel, MAX_RAYS, TILE,
};
