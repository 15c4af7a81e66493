//! Cutter–workpiece engagement (CWE) along a program: for every cutter location, which part of
//! the cutter's surface touches the in-process workpiece — the input of every cutting-force
//! model (Aras 2008, ch. 5–6).
//!
//! # Model
//! A program's feed moves are walked in order on a tri-dexel stock (`swarf_stock`), with a
//! **cutter location** every `step` mm of tool-tip travel and at each move's end
//! ([`Engager`]). At a location the **engagement region** is the part of the cutter's surface
//! that is kinematically feasible — its outward normal has a positive component along the
//! point's velocity, `f = N·V > 0` (`swarf_sweep::tangency`) — and lies in the stock as it is at
//! that instant: every earlier move, and this move up to the previous location, cut; material
//! ahead present. Rapids are cut as the simulation cuts them and have no locations.
//!
//! The region is found from exact cutter geometry against the stock's exact ray intervals, not
//! from a voxel mask: the cutter surface is cut into circles ([`Strip`]: axial discs of height
//! `dz` on its side, rings on a flat bottom), each sampled every `dφ`; at a sample the signed
//! distance to the stock's boundary is read from the interval ends of the rays around it
//! ([`MaterialProbe`]: exact for planar faces, `O(h²κ)` for curved ones) and the boundary is
//! placed between samples by interpolation ([`mod@engagement`]), so the error shrinks with the
//! ray spacing `h` and with `dφ` (README: convergence table, from `tests/convergence.rs`). A
//! tool coming back along a concave wall it cut before touches it tangentially, within the
//! micron or less by which the wall stands proud (chords of arcs) or the rays' sheet runs
//! inside it: such a **rub** — the cutter grazing the wall from the air side, no deeper than
//! the stock's own uncertainty — is not engagement (README).
//!
//! Most of the work would be probing (twelve rays per sample), so only the samples that matter
//! are probed: the tangency `f` is computed at every sample (it needs no stock); where `f > 0`
//! the sample's side is first guessed from the one ray nearest to it in the family most
//! aligned with the cutter's normal there ([`MaterialProbe::inside_nearest_ray`], right except
//! within about a ray spacing of the boundary); then every guessed sample next to a sample of
//! the other side is probed, and again around any whose side the probe flipped, until no
//! guess borders a side change. (With the tool axis vertical, a sample that stands more than
//! two ray spacings above the tiles of every Z ray near it — `swarf_stock::ColumnTops`, read
//! once for each band of the circles' radii at each angle — is guessed outside without
//! reading its ray.) So every value the interpolation of the boundary uses is a
//! probed one, and the boundary is where probing every sample ([`EngageOptions::exhaustive`])
//! puts it, except around a feature that every nearest ray misses (a sliver of material or air
//! narrower than the ray spacing): tested equal on eight programs, and on the first 1,000
//! locations of the finishing benchmark 998 are equal and three differ by 0.02–0.04 % of their
//! area (a one-degree island at a pass's turn).

//! # Frame and angles
//! Tool frame at a location: `z_L` the tool axis (tip → spindle); `x_L` the tip's feed
//! direction projected normal to `z_L` (for a move along the axis: the previous such
//! direction, else workpiece +X projected); `y_L = z_L × x_L`. The **immersion angle** `φ` is
//! measured clockwise about `z_L` seen from the spindle, from `+y_L`: the cutter point at radius
//! `ρ`, height `z` and angle `φ` is `tip + ρ·(sin φ·x_L + cos φ·y_L) + z·z_L`. With a clockwise
//! spindle (M3) this is the angle of the mechanistic force models: a full slot is engaged from 0°
//! to 180°, up-milling at radial depth `a_e` from 0° to `arccos(1 − a_e/R)`, down-milling from
//! `180° − arccos(1 − a_e/R)` to 180°. Heights `z` are above the tool tip along `z_L`. Millimetres
//! and degrees. The repository's `docs/engagement-frame.svg` draws it.
//!
//! # Example
//! A 10 mm flat end mill cuts a full slot 5 mm deep: engaged from 0° to 180° over the 5 mm of
//! its side that are in the material, area `π·R·a_p`.
//!
//! ```
//! use swarf_engage::{EngageOptions, Engager};
//! use swarf_geom::math::Vec3;
//! use swarf_path::load::{read_program_str, ReadOptions};
//! use swarf_path::Machine;
//! use swarf_stock::TriDexel;
//! use swarf_tool::{Cutter, ToolSet};
//!
//! let program = read_program_str(
//!     "G21 G90\nG0 X-10 Y10 Z-5\nG1 X30 F600\n",
//!     "slot.ngc",
//!     Machine::three_axis(),
//!     &ReadOptions::default(),
//! )
//! .unwrap();
//! let mut stock = TriDexel::from_box(Vec3::new(0.0, 0.0, -10.0), Vec3::new(40.0, 20.0, 0.0), 0.1).unwrap();
//! let tools = ToolSet::single(Cutter::flat(10.0).unwrap());
//! let run = Engager::new(&program, &tools, &mut stock, EngageOptions::default()).unwrap();
//! let at_20mm = run.map(Result::unwrap).find(|e| (e.tip.x - 20.0).abs() < 1e-9).unwrap();
//! let exact = std::f64::consts::PI * 5.0 * 5.0;
//! assert!((at_20mm.area_mm2 - exact).abs() / exact < 0.005);
//! assert!(at_20mm.phi_entry_deg.unwrap().abs() < 0.5);
//! assert!((at_20mm.phi_exit_deg.unwrap() - 180.0).abs() < 0.5);
//! assert!((at_20mm.ap_mm - 5.0).abs() < 0.01);
//! ```

pub mod bench;
pub mod engagement;
pub mod probe;
pub mod run;
mod sides;
pub mod strip;

pub use engagement::{CircleEngagement, Engagement, PhiInterval};
pub use probe::{Depth, MaterialProbe};
pub use run::{
    feed_rate, path_length, EngageError, EngageOptions, EngageStats, Engager, DEFAULT_DPHI_DEG,
    DEFAULT_DZ_MM, DEFAULT_STEP_MM, MAX_LOCATIONS_PER_MOVE, MAX_SAMPLES_PER_LOCATION,
};
pub use strip::{Circle, Strip, StripKind};
