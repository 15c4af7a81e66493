//! The allowable cutter size at a cutter-contact point (Liu 2007, §2.3–2.4 and ch. 3), for
//! 3-axis milling (tool axis `+Z` of the part frame).
//!
//! # Model
//! A [`CutterFamily`] is a cutter shape with one free size parameter `L`:
//!
//! * [`CutterFamily::ball`], [`CutterFamily::ball_with_side`] and [`CutterFamily::taper_ball`]:
//!   the ball radius `r` is free (`ball` is the sphere alone; `ball_with_side` adds the cylinder
//!   above its equator, the tapered ball with taper 0 — a ball end mill has flutes on its side
//!   too, so a wall the sphere clears may still stop its side);
//! * [`CutterFamily::apt`] (and its special cases [`CutterFamily::flat`] and
//!   [`CutterFamily::bull`]): corner radius `r`, taper `θ` and bottom cone angle `ψ` are fixed,
//!   the distance `R` from the axis to the corner-circle centre is free.
//!
//! Every family is a **nested** family of solids `K(L)`: placed tangent to the surface at the CC
//! point `C` (unit normal `n` towards the cutter), `K(L) ⊂ K(L')` for `L < L'`. The *imaginary
//! size* of a test point `P` ([`CutterFamily::imaginary`]) is the size at which `P` reaches the
//! boundary of the cutter, `inf { L ≥ 0 : P ∈ int K(L) }` — `0` when even the smallest cutter
//! gouges `P`, `∞` when no size ever does. The *allowable size* is its minimum over every point
//! of the surface (Liu's theorem, §2.3.1); near `C` the imaginary size tends to the curvature
//! bound ([`CutterFamily::local_bound`]), which is used there as the local gouge bound.
//!
//! # Placement conventions
//! * Tangency: the contact normal of the cutter at `C` is `−n`. For the APT family the contact
//!   is on the corner torus (`Q = C + r·n` is the corner-circle centre and the axis lies at
//!   `Q + R·u`, `u` the unit horizontal part of `n`), unless:
//! * **vertical normal** (`|n_xy| ≤` [`SizeTolerances::vertical`]) with a flat bottom (`ψ = 0`),
//!   or a normal within `ψ` of vertical with a conical bottom: the cutter stands with **its axis
//!   through `C`** and its bottom (flat face or tip) on `C`, as CAM systems place it — the only
//!   placement that does not depend on `R`;
//! * a normal steeper than the cutter's side (`n_z < sin θ`, including undercuts): no cutter of
//!   the family can be tangent there in 3-axis: the allowable size is `0` (unreachable).
//! * `ψ = 0` is the plane limit of the conical bottom: points below the flat bottom are never
//!   touched (Liu's condition 3 with `ψ → 0`; the `Δz/tanψ` term of his eq. 2.30 is never
//!   evaluated).
//! * Touching is not gouging: a point within [`SizeTolerances::contact`] of the cutter's
//!   boundary counts as outside (so a flat floor never limits a flat end mill standing on it).
//!
//! # Solvers
//! * [`certified`] (the default): branch-and-bound over rational Bézier sub-patches with rigorous
//!   lower bounds; returns the minimum with a certificate (the gap between it and the lowest
//!   bound of any unexplored part of the surface).
//! * [`pso`]: the thesis's hybrid (particle swarm then Nelder–Mead), seeded and reproducible.
//!
//! [`map`] runs either over a grid of CC points and writes the CSV of the `swarf toolsize`
//! command.
//!
//! # Other tool axes
//! [`orient4`] solves for any tool axis by moving the part so that the axis is `+Z` (the same
//! certified solver, unchanged) and searches the 4-axis table angle that maximises the size;
//! [`orient5`] searches 5-axis lead and tilt within machine limits.

pub mod certified;
mod family;
mod imaginary_apt;
mod imaginary_ball;
mod imaginary_taper_ball;
pub mod map;
pub mod orient4;
pub mod orient5;
mod placed;
pub mod pso;
pub mod shank;
pub mod standard;

pub use certified::{allowable_certified, CertifiedOptions};
pub use family::{CutterFamily, Regime, FLAT_CURVATURE};
pub use map::{
    allowable_map, allowable_map_observed, allowable_map_prepared, Axes, MapOptions, MapPoint,
    MapSummary, Solver, ToolAngles, ToolSizeMap,
};
pub use orient4::{allowable_along, best_rotary_angle, Axis4Options, Orientation4, RotaryAxis};
pub use orient5::{best_lead_tilt, Axis5Options, LeadTiltFrame, Orientation5};
pub use placed::PlacedCutter;
pub use pso::{allowable_pso, PsoOptions};
pub use shank::{check_shank, shank_limited, ShankCheck, ShankStatus};
pub use standard::{
    grid_cell_areas, AreaRule, CutterShare, StandardCutters, StandardError, StandardOptions,
    StandardReport,
};
pub(crate) use swarf_surface::PreparedSurface;

use swarf_geom::math::Vec3;

use swarf_surface::{CcPoint, CompoundSurface, Curvature, Tolerances};

/// Tolerances of the imaginary-size model, in one place.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SizeTolerances {
    /// A normal whose horizontal part is at most this long is vertical (the flat-bottom
    /// convention applies). Dimensionless, default `1e-9`.
    pub vertical: f64,
    /// Distance (mm) within which a test point on the cutter's boundary counts as touching,
    /// not gouging. Default `1e-9` mm.
    pub contact: f64,
}

impl SizeTolerances {
    /// The documented defaults.
    pub const DEFAULT: SizeTolerances = SizeTolerances {
        vertical: 1e-9,
        contact: 1e-9,
    };
}

impl Default for SizeTolerances {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// A cutter-contact point as the size model sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// The CC point, mm.
    pub point: Vec3,
    /// Unit surface normal, pointing to the side the cutter comes from.
    pub normal: Vec3,
    /// Principal curvatures (signed against `normal`, positive where concave); `None` when the
    /// surface did not give them.
    pub curvature: Option<Curvature>,
}

impl Contact {
    /// The contact at a CC point of a compound surface; `None` where the normal is undefined.
    pub fn at(surface: &CompoundSurface, cc: &CcPoint, tol: &Tolerances) -> Option<Contact> {
        let g = surface.local(cc, tol);
        Some(Contact {
            point: g.point(),
            normal: g.normal.vector()?,
            curvature: g.curvature,
        })
    }
}

/// Why a size query is rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SizeError {
    /// A cutter family parameter is out of range.
    #[error("cutter family: {what} = {value} is out of range ({range})")]
    Family {
        /// The parameter.
        what: &'static str,
        /// Its value.
        value: f64,
        /// The accepted range.
        range: &'static str,
    },
    /// A solver option is out of range.
    #[error("solver option {what} = {value} is out of range ({range})")]
    Option {
        /// The option.
        what: &'static str,
        /// Its value.
        value: f64,
        /// The accepted range.
        range: &'static str,
    },
}

/// What limits the allowable size at a point (Liu §2.3.1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Limit {
    /// The surface near the CC point: its curvature, a crease, or a normal the cutter cannot
    /// be tangent to.
    Gouge,
    /// A point of the surface away from the CC point.
    Interference,
}

impl Limit {
    /// `"gouge"` or `"interference"`.
    pub fn as_str(self) -> &'static str {
        match self {
            Limit::Gouge => "gouge",
            Limit::Interference => "interference",
        }
    }
}

/// The allowable size at one CC point, with the evidence.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AllowableSize {
    /// The free parameter `L` of the family (ball radius, or `R` for the APT family): `∞` when
    /// nothing limits it, `0` when the point cannot be machined.
    pub size: f64,
    /// What limits it; `None` when `size` is infinite.
    pub limit: Option<Limit>,
    /// The limiting point (the CC point itself for a curvature bound); `None` when infinite.
    pub limit_point: Option<Vec3>,
    /// Certificate: no point of the surface outside the excluded neighbourhood of the CC point
    /// has an imaginary size below `size − gap` (certified solver), or `NaN` (PSO: no proof).
    pub gap: f64,
    /// True when `gap` is within the requested tolerance.
    pub certified: bool,
    /// Objective (imaginary-size) evaluations spent.
    pub evaluations: u64,
    /// Lower-bound computations (branch-and-bound nodes) spent; 0 for PSO.
    pub nodes: u64,
}

impl AllowableSize {
    /// The answer at a point no cutter of the family can reach (size 0, a gouge at the point
    /// itself): proven by the regime alone for the certified solver (`certified`, gap 0), merely
    /// asserted by the swarm (gap `NaN`).
    pub(crate) fn unreachable(point: Vec3, certified: bool) -> Self {
        AllowableSize {
            size: 0.0,
            limit: Some(Limit::Gouge),
            limit_point: Some(point),
            gap: if certified { 0.0 } else { f64::NAN },
            certified,
            evaluations: 0,
            nodes: 0,
        }
    }
}

/// Classification of a limiting test point: within `radius` of the CC point it is the gouge
/// bound, otherwise interference.
pub(crate) fn classify(c: Vec3, p: Vec3, radius: f64) -> Limit {
    if (p - c).length() <= radius {
        Limit::Gouge
    } else {
        Limit::Interference
    }
}
