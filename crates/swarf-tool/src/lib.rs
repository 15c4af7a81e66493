//! The APT generic cutter, its surface pieces, holders and tool tables.
//!
//! # Model
//! A [`Cutter`] is described in its own frame: **tip at the origin, axis +Z**, lengths in mm,
//! angles in degrees at the public interface (radians inside). Its cutting part is the APT
//! seven-parameter profile `CUTTER/d, r, e, f, α, β, h` (exact convention and diagram in
//! [`cutter`]), revolved about the axis and decomposed into [`piece`]s — bottom disc or cone,
//! corner torus or sphere, side cylinder or cone, top cap — each answering point/normal
//! evaluation, profile radius, containment and ray intersection through the swarf-geom
//! primitives. Above the cutting part sit the shank and an optional [`Holder`], exposed as
//! [`RevolvedSolid`]s with the same queries for collision checks.
//!
//! Operations ask the cutter questions ([`Cutter::profile_radius`], [`Cutter::contains`],
//! [`Cutter::ray_intersections`]); nothing outside this crate matches on the cutter kind.
//!
//! Cutters come from named constructors, the spec strings of [`spec`] (`bull:d=16,r=2`), or
//! tool tables ([`table`]: swarf TOML, LinuxCNC `.tbl`, CAMotics `.camotics`).
//!
//! ```
//! use swarf_geom::math::Vec3;
//! use swarf_geom::Ray;
//! use swarf_tool::Cutter;
//! let c = Cutter::from_spec("bull:d=16,r=2").unwrap();
//! // The corner centre is 6 mm off the axis, 2 mm above the tip.
//! assert!((c.profile_radius(2.0).unwrap() - 8.0).abs() < 1e-12);
//! assert!(c.contains(Vec3::new(5.9, 0.0, 0.0)) && !c.contains(Vec3::new(7.9, 0.0, 0.1)));
//! let mut hits = Vec::new();
//! c.ray_intersections(&Ray::new(Vec3::new(0.0, 0.0, -10.0), Vec3::Z), &mut hits);
//! assert_eq!(hits, vec![10.0, 10.0 + 48.0]); // bottom disc, then the top cap at h = 3d
//! ```

pub mod cutter;
pub mod describe;
pub mod error;
pub mod family;
pub mod holder;
pub mod piece;
pub mod solid;
pub mod spec;
pub mod table;
pub mod toolset;

pub use cutter::{AptParams, Cutter, CutterKind, CutterOptions};
pub use describe::CutterDescription;
pub use error::{SpecError, TableError, ToolError};
pub use family::FamilySpec;
pub use holder::{Holder, HolderSegment};
pub use piece::{AnyPiece, Piece};
pub use solid::RevolvedSolid;
pub use table::{LengthUnit, ToolEntry, ToolTable};
pub use toolset::{ResolveError, ResolvedTool, ToolSet, ToolSource};

impl Cutter {
    /// Parses a tool spec string (see [`spec`]) into a validated cutter.
    pub fn from_spec(spec: &str) -> Result<Cutter, SpecError> {
        spec::parse(spec)
    }

    /// The spec string that rebuilds this cutter (with its options); the grammar lives in
    /// [`spec`], above the cutter model, which knows nothing of it.
    pub fn spec(&self) -> String {
        spec::to_spec(self)
    }

    /// A cutter from the seven numbers of a program's `CUTTER/` record (mm, degrees), where
    /// h = 0 means the program did not give the height of the cutting part: it is then taken
    /// as three diameters (the named constructors' default), or the corner's top if higher.
    ///
    /// ```
    /// let c = swarf_tool::Cutter::from_program_record([10.0, 2.0, 3.0, 2.0, 0.0, 0.0, 0.0]).unwrap();
    /// assert_eq!(c.apt_params().h, 30.0);
    /// ```
    ///
    /// # Errors
    /// As [`Cutter::apt`].
    pub fn from_program_record(p: [f64; 7]) -> Result<Cutter, ToolError> {
        let h = if p[6] > 0.0 {
            p[6]
        } else {
            (3.0 * p[0]).max(p[3] + p[1])
        };
        Cutter::apt(p[0], p[1], p[2], p[3], p[4], p[5], h)
    }

    /// The serialisable description (for `--json` output).
    pub fn describe(&self) -> CutterDescription {
        CutterDescription::of(self)
    }
}
