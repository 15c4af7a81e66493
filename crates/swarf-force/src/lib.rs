//! Cutting forces, torque and power along a program, and force-limited feed scheduling.
//!
//! # Model
//! The mechanistic milling model of Altintas for the generic (APT) cutter, fed by the
//! cutter–workpiece engagement of `swarf_engage`: the cutter is cut into the engagement's
//! axial discs (and bottom rings); on each, every flute's edge at immersion `φ` cuts a chip of
//! thickness `h = c·n` (the feed per tooth along the surface normal: `c·sin φ·sin κ` for a feed
//! across the axis, κ the axial immersion angle of the edge) with elemental forces
//!
//! ```text
//! dFt = Ktc·h·db + Kte·db,   dFr = Krc·h·db + Kre·db,   dFa = Kac·h·db + Kae·db
//! ```
//!
//! where the edge lies inside the engaged intervals of its disc; helical edges lag by
//! `ψ = tan i·∫dz/ρ` along the profile (`z·tan i/R` on a cylinder, `θ·tan i` on a ball of polar
//! angle θ). Forces are integrated in closed form along each edge and sampled over one spindle
//! revolution; their means are exact ([`mod@model`]). Conventions follow
//! `../shared/data/forces/REFERENCE.md`: φ clockwise from `+y_L` seen from the spindle, feed
//! along `+x_L`, forces on the tool, `Fx = −Ft cos φ − Fr sin φ`, `Fy = Ft sin φ − Fr cos φ`,
//! `Fz = Fa` on a cylinder.
//!
//! Coefficients come from a [`Material`]: a TOML file, or a built-in one such as Ti6Al4V,
//! predicted from an orthogonal database through the oblique transformation
//! ([`mod@coefficients`]). The feed per tooth is `F/(S·N)` (G95 and G93 converted by the
//! engagement). Units: mm, degrees at interfaces, N, N·m, W.
//!
//! # Example
//! A 10 mm, 4-flute end mill slots 4 mm deep at 400 mm/min and 1000 rpm (0.1 mm per tooth):
//! the mean forces equal the closed form of a full slot, `F̄y = N·a·(c·Ktc/4 + Kte/π)`.
//!
//! ```
//! use swarf_engage::{EngageOptions, Engager};
//! use swarf_force::{CoefficientSource, Coefficients, ForceModel, Material};
//! use swarf_geom::math::Vec3;
//! use swarf_path::load::{read_program_str, ReadOptions};
//! use swarf_path::Machine;
//! use swarf_stock::TriDexel;
//! use swarf_tool::{Cutter, ToolSet};
//!
//! let program = read_program_str(
//!     "G21 G90\nS1000 M3\nG0 X-10 Y10 Z-4\nG1 X50 F400\n",
//!     "slot.ngc",
//!     Machine::three_axis(),
//!     &ReadOptions::default(),
//! )
//! .unwrap();
//! let k = Coefficients { ktc: 796.0, krc: 168.8, kac: 222.0, kte: 27.7, kre: 30.8, kae: 1.8 };
//! let material = Material {
//!     name: "Al7075".into(),
//!     coefficients: CoefficientSource::Fixed(k),
//!     source: "example".into(),
//! };
//! let tools = ToolSet::single(Cutter::from_spec("flat:d=10,flutes=4,helix=30").unwrap());
//! let opts = EngageOptions::default();
//! let model = ForceModel::new(material, &tools, &[0], &opts, 360).unwrap();
//! let mut stock =
//!     TriDexel::from_box(Vec3::new(0.0, 0.0, -10.0), Vec3::new(40.0, 20.0, 0.0), 0.1).unwrap();
//! let at_20mm = Engager::new(&program, &tools, &mut stock, opts)
//!     .unwrap()
//!     .map(Result::unwrap)
//!     .find(|e| (e.tip.x - 20.0).abs() < 1e-9)
//!     .unwrap();
//! let (f, _curves) = model.forces(&model.evaluate(&at_20mm), None);
//! let fy = 4.0 * 4.0 * (0.1 * 796.0 / 4.0 + 27.7 / std::f64::consts::PI);
//! assert!((f.mean_n[1] - fy).abs() < 1e-3 * fy);
//! assert!(f.torque_peak_nm > f.torque_mean_nm && f.power_mean_w > 0.0);
//! ```
//!
//! # Layout
//! - [`coefficients`]: materials and coefficient prediction;
//! - [`edges`]: a cutter's flutes, helix and slabs;
//! - [`model`]: forces at one location per unit coefficient ([`UnitForces`]);
//! - [`location`]: the per-location summary, limits and the model over a tool set;
//! - [`schedule`]: feeds per move under a force, torque or power limit.

pub mod coefficients;
pub mod edges;
pub mod location;
pub mod model;
pub mod schedule;

pub use coefficients::{
    builtin_material, builtin_materials, parse_material, CoefficientSource, Coefficients, Material,
    OrthogonalDatabase,
};
pub use edges::{CutterEdges, Slab};
pub use location::{
    Evaluated, ForceModel, Limit, LocationForces, DEFAULT_SAMPLES_PER_REV, MAX_SAMPLES_PER_REV,
};
pub use model::{unit_forces, ForceCurves, UnitForces};
pub use schedule::{
    schedule_feeds, LocationCap, MoveCaps, MoveFeed, ScheduleOptions, ScheduleResult,
};

/// What can go wrong computing forces.
#[derive(Debug, thiserror::Error)]
pub enum ForceError {
    /// A cutter with no flute count (and no default given for one).
    #[error("{tool} has no flute count: the force model needs it — add flutes=N to its spec or `flutes = N` to its tool-library entry, or give a default for the tools that state none")]
    NoFlutes {
        /// Which tool.
        tool: String,
        /// Its number, when it is a numbered tool of the program (not the cutter for all).
        number: Option<u32>,
    },
    /// A predicted material and a cutter with no rake angle.
    #[error("{tool} has no rake angle, which the coefficient prediction of material {material} needs — add rake=DEG to its spec or `rake_deg = DEG` to its tool-library entry")]
    NoToolRake {
        /// Which tool.
        tool: String,
        /// The material.
        material: String,
    },
    /// A predicted material asked without a rake angle.
    #[error("material {material} predicts its coefficients from the tool's rake angle, and none was given")]
    NoRake {
        /// The material.
        material: String,
    },
    /// No built-in material of that name.
    #[error("no built-in material {name:?}; known: {known} (or give --coefficients FILE)")]
    UnknownMaterial {
        /// Name asked for.
        name: String,
        /// Known names.
        known: String,
    },
    /// A bad material file.
    #[error("{file}:{line}:{column}: {problem} ({expected})")]
    MaterialFile {
        /// File.
        file: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong there (the TOML reader's words for a syntax or key error).
        problem: String,
        /// What the file should hold, in a sentence.
        expected: String,
    },
    /// An option out of range.
    #[error("--{name} must be {want}, got {value}")]
    BadOption {
        /// Option name.
        name: &'static str,
        /// Value given.
        value: f64,
        /// What it must be.
        want: &'static str,
    },
    /// The engagement failed.
    #[error(transparent)]
    Engage(#[from] swarf_engage::EngageError),
}
