//! The APT generic cutter: seven numbers, validated, decomposed into surface pieces.
//!
//! # The APT convention used by swarf
//!
//! `CUTTER/d, r, e, f, α, β, h` describes the cutting part in the tool frame: tip at the
//! origin, axis +Z, lengths in mm, angles in degrees at the interface (radians inside).
//!
//! ```text
//!            ρ_top
//!          |<---->|
//!   z = h  +------+            upper cone / cylinder: angle β from the axis
//!          |       \           (β > 0 widens upwards, β < 0 is a back taper)
//!          |        \
//!          |         \  P2     side meets corner, radius d/2:  d/2 = e + r·cos β
//!          |          )        corner arc, radius r, centre C = (e, f), polar angle
//!          |    C ·  /         φ ∈ [α, 90° − β] measured at C from straight down
//!          |        /  P1      bottom meets corner: P1 = (e + r·sin α, f − r·cos α)
//!          |     __/           lower cone: angle α from the horizontal, through the tip
//!   z = 0  +--'''                 (α = 0: a flat bottom disc of radius e)
//!          axis (ρ = 0)
//! ```
//!
//! * **d** — diameter where the corner arc meets the side (at `P2`). For a straight side
//!   (β = 0) this is the largest diameter of the cutter; for a tapered side it is the diameter
//!   at the top of the corner.
//! * **r** — corner radius (0: a sharp corner).
//! * **e** — radial distance from the axis to the corner centre.
//! * **f** — height of the corner centre above the tip.
//! * **α** — bottom angle, between the bottom cone and a plane normal to the axis (0: flat
//!   bottom; a 118° drill point has α = 31°). Range `[0°, 90°)`.
//! * **β** — side angle, between the side and the axis (0: cylindrical side). Range
//!   `(−90°, 90°)`, with `α + β ≤ 90°`.
//! * **h** — height of the cutting part (the solid modelled here runs from z = 0 to z = h).
//!
//! The corner is tangent to both the bottom cone and the side (the profile is G1 wherever
//! r > 0), and the bottom cone passes through the tip. Two of the seven numbers are therefore
//! implied by the others: `e = d/2 − r·cos β` and `f = (r + e·sin α)/cos α` (the distance from
//! C to the bottom line equals r). They are checked against the values given (tolerance
//! [`APT_CONSISTENCY_TOL_MM`]) and then replaced by the implied values so that the pieces join
//! exactly. This is the convention of Liu (2007, Fig. 2-1, eqs. 2.2–2.4), whose R is e, ψ is α
//! and θ is β: `x_C = R + r·sin ψ`, `z_O1 = R·tan ψ + r·sec ψ` (= f), `x_B = R + r·cos θ`
//! (= d/2), `z_B = z_O1 − r·sin θ`. (Liu's `x_A = R + r·cos θ + H·tan θ` is a slip for
//! `x_B + (H − z_B)·tan θ`, which eq. 2.4 itself uses.) Aras (2008, Fig. 5.3, eq. 5.14)
//! describes the same solid with the bottom angle measured from the **axis**
//! (`α_Aras = 90° − α`), corner centre `(R, h_c)` = (e, f) and cutter radius
//! `r = R + r_c·cos β` = d/2; his relations `h_l = (R + r_c·cos α_Aras)/tan α_Aras`,
//! `h_c = h_l + r_c·sin α_Aras` agree with the f above, but eq. 5.15-a writes `r·sin β` where
//! 5.14-a has `r_c·sin β` (a slip).
//!
//! # Pieces
//! Bottom to top: a [`DiscPiece`] (α = 0, e > 0) or a [`ConePiece`] through the tip (α > 0),
//! the corner ([`TorusPiece`] when e > 0, [`SpherePiece`] when e = 0, absent when r = 0 or the
//! arc is a single point), the side ([`CylinderPiece`] for β = 0, else [`ConePiece`]; absent
//! when the corner reaches z = h), and a top cap ([`DiscPiece`] at z = h, not a cutting surface)
//! that closes the solid.

use crate::error::ToolError;
use crate::holder::Holder;
use crate::piece::{AnyPiece, ConePiece, CylinderPiece, DiscPiece, Piece, SpherePiece, TorusPiece};
use crate::solid::RevolvedSolid;
use swarf_geom::math::{Vec2, Vec3};
use swarf_geom::Ray;

/// Tolerance (mm) for the two redundant APT numbers e and f: posts print them to 3 or 4
/// decimals, in mm or inches (a 118° drill's f = 4·tan 31° = 2.40344 written `2.403`; half a
/// unit of an inch file's fourth decimal is 0.00127 mm), and some to 2; a number
/// misread or mistyped is off by far more. The pieces are then built from the implied values.
pub const APT_CONSISTENCY_TOL_MM: f64 = 0.01;

/// The seven APT numbers, as typed (mm and degrees).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct AptParams {
    /// Diameter where the corner meets the side, mm.
    pub d: f64,
    /// Corner radius, mm.
    pub r: f64,
    /// Radial distance from the axis to the corner centre, mm.
    pub e: f64,
    /// Height of the corner centre above the tip, mm.
    pub f: f64,
    /// Bottom angle from the horizontal, degrees.
    pub alpha_deg: f64,
    /// Side angle from the axis, degrees.
    pub beta_deg: f64,
    /// Height of the cutting part, mm.
    pub h: f64,
}

/// Which named constructor made a cutter (for descriptions and spec round trips only;
/// geometry never depends on it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CutterKind {
    /// Flat end mill.
    Flat,
    /// Ball-nose end mill.
    Ball,
    /// Bull-nose (toroidal) end mill.
    Bull,
    /// Tapered flat end mill.
    TaperFlat,
    /// Tapered ball-nose end mill.
    TaperBall,
    /// Chamfer / engraving V-bit.
    Chamfer,
    /// Twist drill.
    Drill,
    /// General APT cutter.
    Apt,
}

impl CutterKind {
    /// The name used in spec strings (`taper-ball`, …).
    pub fn spec_name(self) -> &'static str {
        match self {
            CutterKind::Flat => "flat",
            CutterKind::Ball => "ball",
            CutterKind::Bull => "bull",
            CutterKind::TaperFlat => "taper-flat",
            CutterKind::TaperBall => "taper-ball",
            CutterKind::Chamfer => "chamfer",
            CutterKind::Drill => "drill",
            CutterKind::Apt => "apt",
        }
    }
}

/// Optional attributes beyond the cutting profile; `None` takes the documented default.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CutterOptions {
    /// Number of flutes (default [`DEFAULT_FLUTES`]).
    pub flutes: Option<u32>,
    /// Helix angle, degrees (default [`DEFAULT_HELIX_DEG`]; 0 for chamfer bits).
    pub helix_deg: Option<f64>,
    /// Normal rake angle of the cutting edges, degrees (no default: only the force model's
    /// coefficient prediction needs it, and it asks for it by name).
    pub rake_deg: Option<f64>,
    /// Cutting (flute) length, mm (default: the APT height h).
    pub flute_length: Option<f64>,
    /// Shank diameter, mm (default: the cutting part's diameter at its top, = d for untapered
    /// tools).
    pub shank_diameter: Option<f64>,
    /// Overall length from tip to shank end, mm (default: h + 2·shank diameter).
    pub overall_length: Option<f64>,
    /// Holder (default none).
    pub holder: Option<Holder>,
}

/// A milling cutter: the APT cutting part, its shank, optional holder and flute data.
///
/// All geometry is in the cutter frame: tip at the origin, axis +Z, mm.
#[derive(Clone, Debug, PartialEq)]
pub struct Cutter {
    kind: CutterKind,
    apt: AptParams,
    // Internal, radians.
    alpha: f64,
    beta: f64,
    cutting: RevolvedSolid,
    shank: RevolvedSolid,
    flutes: u32,
    /// Whether the flute count was given (a force model refuses the default).
    flutes_given: bool,
    helix_deg: f64,
    rake_deg: Option<f64>,
    flute_length: f64,
    shank_diameter: f64,
    overall_length: f64,
    holder: Option<Holder>,
    holder_solid: Option<RevolvedSolid>,
}

fn finite(param: &str, v: f64) -> Result<f64, ToolError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(ToolError::NotFinite {
            param: param.to_string(),
            value: v,
        })
    }
}

fn require(ok: bool, param: &str, value: f64, requirement: &str) -> Result<(), ToolError> {
    if ok {
        Ok(())
    } else {
        Err(ToolError::OutOfRange {
            param: param.to_string(),
            value,
            requirement: requirement.to_string(),
        })
    }
}

/// The largest cutter (and shank) diameter, mm (the largest face mills are about as large).
pub const MAX_DIAMETER_MM: f64 = 500.0;

/// The longest tool, mm (the default lengths of the largest cutter: 3 + 2 diameters).
pub const MAX_LENGTH_MM: f64 = 2500.0;

/// Default cutting length for named constructors: three diameters.
const DEFAULT_FLUTE_DIAMETERS: f64 = 3.0;
/// Default number of flutes.
pub const DEFAULT_FLUTES: u32 = 2;
/// Default helix angle for end mills and drills, degrees.
pub const DEFAULT_HELIX_DEG: f64 = 30.0;

impl Cutter {
    /// The general APT cutter `CUTTER/d, r, e, f, α, β, h` (angles in degrees) with default
    /// options. See the module documentation for the exact convention.
    pub fn apt(
        d: f64,
        r: f64,
        e: f64,
        f: f64,
        alpha_deg: f64,
        beta_deg: f64,
        h: f64,
    ) -> Result<Cutter, ToolError> {
        Self::build(
            CutterKind::Apt,
            AptParams {
                d,
                r,
                e,
                f,
                alpha_deg,
                beta_deg,
                h,
            },
            &CutterOptions::default(),
        )
    }

    /// Flat end mill of diameter `d`: `CUTTER/d, 0, d/2, 0, 0, 0, 3d`.
    pub fn flat(d: f64) -> Result<Cutter, ToolError> {
        Self::named(CutterKind::Flat, &[d], &CutterOptions::default())
    }

    /// Ball-nose end mill of diameter `d`: `CUTTER/d, d/2, 0, d/2, 0, 0, 3d`.
    pub fn ball(d: f64) -> Result<Cutter, ToolError> {
        Self::named(CutterKind::Ball, &[d], &CutterOptions::default())
    }

    /// Bull-nose (toroidal) end mill: `CUTTER/d, r, d/2 − r, r, 0, 0, 3d`.
    pub fn bull(d: f64, r: f64) -> Result<Cutter, ToolError> {
        Self::named(CutterKind::Bull, &[d, r], &CutterOptions::default())
    }

    /// Tapered flat end mill with tip diameter `d` and side half-angle `taper_deg`:
    /// `CUTTER/d, 0, d/2, 0, 0, β, 3d`.
    pub fn taper_flat(d: f64, taper_deg: f64) -> Result<Cutter, ToolError> {
        Self::named(
            CutterKind::TaperFlat,
            &[d, taper_deg],
            &CutterOptions::default(),
        )
    }

    /// Tapered ball-nose with **ball** diameter `d` and side half-angle `taper_deg`:
    /// `CUTTER/d·cos β, d/2, 0, d/2, 0, β, 3d` (APT's d is the diameter where the ball meets
    /// the taper, slightly less than the ball diameter).
    pub fn taper_ball(d: f64, taper_deg: f64) -> Result<Cutter, ToolError> {
        Self::named(
            CutterKind::TaperBall,
            &[d, taper_deg],
            &CutterOptions::default(),
        )
    }

    /// Chamfer / engraving V-bit of diameter `d` and included tip angle `tip_angle_deg`
    /// (90° typical): `CUTTER/d, 0, d/2, (d/2)·tan α, α, 0, h` with α = 90° − tip/2; h is
    /// `max(3d, cone height)`.
    pub fn chamfer(d: f64, tip_angle_deg: f64) -> Result<Cutter, ToolError> {
        Self::named(
            CutterKind::Chamfer,
            &[d, tip_angle_deg],
            &CutterOptions::default(),
        )
    }

    /// Twist drill of diameter `d` and point angle `point_angle_deg` (118° typical); same
    /// profile as [`Cutter::chamfer`].
    pub fn drill(d: f64, point_angle_deg: f64) -> Result<Cutter, ToolError> {
        Self::named(
            CutterKind::Drill,
            &[d, point_angle_deg],
            &CutterOptions::default(),
        )
    }

    /// Builds a named cutter from its spec numbers (`[d]`, `[d, r]`, `[d, angle]`, or the seven
    /// APT numbers for [`CutterKind::Apt`]) with options. The flute length, when given, is the
    /// cutting height h of named (non-APT) cutters.
    pub fn named(
        kind: CutterKind,
        nums: &[f64],
        opts: &CutterOptions,
    ) -> Result<Cutter, ToolError> {
        let get = |i: usize| nums.get(i).copied().unwrap_or(f64::NAN);
        let d = finite("d (diameter)", get(0))?;
        require(d > 0.0, "d (diameter)", d, "> 0 mm")?;
        let h_default = |cone_height: f64| match opts.flute_length {
            Some(l) => l,
            None => (DEFAULT_FLUTE_DIAMETERS * d).max(cone_height),
        };
        let apt = match kind {
            CutterKind::Flat => AptParams {
                d,
                r: 0.0,
                e: d / 2.0,
                f: 0.0,
                alpha_deg: 0.0,
                beta_deg: 0.0,
                h: h_default(0.0),
            },
            CutterKind::Ball => AptParams {
                d,
                r: d / 2.0,
                e: 0.0,
                f: d / 2.0,
                alpha_deg: 0.0,
                beta_deg: 0.0,
                h: h_default(d / 2.0),
            },
            CutterKind::Bull => {
                let r = finite("r (corner radius)", get(1))?;
                AptParams {
                    d,
                    r,
                    e: d / 2.0 - r,
                    f: r,
                    alpha_deg: 0.0,
                    beta_deg: 0.0,
                    h: h_default(r),
                }
            }
            CutterKind::TaperFlat => {
                let b = finite("taper (side angle β)", get(1))?;
                AptParams {
                    d,
                    r: 0.0,
                    e: d / 2.0,
                    f: 0.0,
                    alpha_deg: 0.0,
                    beta_deg: b,
                    h: h_default(0.0),
                }
            }
            CutterKind::TaperBall => {
                let b = finite("taper (side angle β)", get(1))?;
                require(
                    (0.0..90.0).contains(&b),
                    "taper (side angle β)",
                    b,
                    "in [0°, 90°)",
                )?;
                let rb = d / 2.0;
                AptParams {
                    d: d * b.to_radians().cos(),
                    r: rb,
                    e: 0.0,
                    f: rb,
                    alpha_deg: 0.0,
                    beta_deg: b,
                    h: h_default(rb),
                }
            }
            CutterKind::Chamfer | CutterKind::Drill => {
                let tip = finite("angle (tip angle)", get(1))?;
                require(
                    tip > 0.0 && tip <= 180.0,
                    "angle (tip angle)",
                    tip,
                    "in (0°, 180°]",
                )?;
                let alpha_deg = 90.0 - tip / 2.0;
                let f = d / 2.0 * alpha_deg.to_radians().tan();
                AptParams {
                    d,
                    r: 0.0,
                    e: d / 2.0,
                    f,
                    alpha_deg,
                    beta_deg: 0.0,
                    h: h_default(f),
                }
            }
            CutterKind::Apt => {
                if nums.len() != 7 {
                    return Err(ToolError::OutOfRange {
                        param: "number of APT parameters".into(),
                        value: nums.len() as f64,
                        requirement: "exactly 7 (d, r, e, f, α, β, h)".into(),
                    });
                }
                AptParams {
                    d,
                    r: nums[1],
                    e: nums[2],
                    f: nums[3],
                    alpha_deg: nums[4],
                    beta_deg: nums[5],
                    h: nums[6],
                }
            }
        };
        let mut opts = opts.clone();
        if kind == CutterKind::Chamfer && opts.helix_deg.is_none() {
            opts.helix_deg = Some(0.0);
        }
        Self::build(kind, apt, &opts)
    }

    /// Validates the APT numbers and options and builds the pieces.
    pub fn build(
        kind: CutterKind,
        apt: AptParams,
        opts: &CutterOptions,
    ) -> Result<Cutter, ToolError> {
        let AptParams {
            d,
            r,
            e,
            f,
            alpha_deg,
            beta_deg,
            h,
        } = apt;
        finite("d (diameter)", d)?;
        finite("r (corner radius)", r)?;
        finite("e (corner centre radial offset)", e)?;
        finite("f (corner centre height)", f)?;
        finite("α (bottom angle)", alpha_deg)?;
        finite("β (side angle)", beta_deg)?;
        finite("h (height)", h)?;
        require(d > 0.0, "d (diameter)", d, "> 0 mm")?;
        // A cutter of kilometres is a typing slip, and its sampling and sweeps ran for
        // minutes or exhausted memory before any other check.
        require(d <= MAX_DIAMETER_MM, "d (diameter)", d, "<= 500 mm")?;
        require(r >= 0.0, "r (corner radius)", r, ">= 0 mm")?;
        require(f >= 0.0, "f (corner centre height)", f, ">= 0 mm")?;
        require(h > 0.0, "h (height)", h, "> 0 mm")?;
        require(
            (0.0..90.0).contains(&alpha_deg),
            "α (bottom angle)",
            alpha_deg,
            "in [0°, 90°)",
        )?;
        require(
            beta_deg > -90.0 && beta_deg < 90.0,
            "β (side angle)",
            beta_deg,
            "in (-90°, 90°)",
        )?;
        // The corner centre may not cross the axis: e = d/2 − r·cos β ≥ 0 (for a straight side,
        // r ≤ d/2; a tapered ball has r·cos β = d/2 exactly).
        let r_cos_beta = r * beta_deg.to_radians().cos();
        if r_cos_beta > d / 2.0 + APT_CONSISTENCY_TOL_MM {
            return Err(ToolError::CornerTooLarge {
                r,
                r_cos_beta,
                half_d: d / 2.0,
            });
        }
        require(e >= 0.0, "e (corner centre radial offset)", e, ">= 0 mm")?;
        if alpha_deg + beta_deg > 90.0 {
            return Err(ToolError::AnglesDoNotJoin {
                alpha_deg,
                beta_deg,
            });
        }
        let (alpha, beta) = (alpha_deg.to_radians(), beta_deg.to_radians());
        // The two implied numbers (see the module doc).
        let e_impl = (d / 2.0 - r * beta.cos()).max(0.0);
        let f_impl = (r + e_impl * alpha.sin()) / alpha.cos();
        let tol = APT_CONSISTENCY_TOL_MM;
        if (e - e_impl).abs() > tol {
            return Err(ToolError::Inconsistent {
                param: "e (corner centre radial offset)".into(),
                given: e,
                expected: e_impl,
                why: "e = d/2 − r·cos β (side tangent to the corner at diameter d)".into(),
                tol,
            });
        }
        if (f - f_impl).abs() > tol {
            return Err(ToolError::Inconsistent {
                param: "f (corner centre height)".into(),
                given: f,
                expected: f_impl,
                why: "f = (r + e·sin α)/cos α (bottom through the tip, tangent to the corner)"
                    .into(),
                tol,
            });
        }
        let (e, f) = (e_impl, f_impl);
        // Computed exactly as the corner piece computes its upper end (polar angle
        // φ1 = 90° − β), so the corner and the side share the joint bit for bit.
        let phi1 = std::f64::consts::FRAC_PI_2 - beta;
        let p2 = Vec2::new(e + r * phi1.sin(), f - r * phi1.cos());
        if h < p2.y - tol {
            return Err(ToolError::HeightTooSmall { h, needed: p2.y });
        }
        let rho_top = p2.x + (h - p2.y) * beta.tan();
        if rho_top <= 0.0 {
            return Err(ToolError::SideReachesAxis {
                beta_deg,
                z_zero: p2.y - p2.x / beta.tan(),
                h,
            });
        }
        let cutting = profile_pieces(r, e, f, alpha, beta, h, p2, rho_top);

        // Options.
        let flutes = opts.flutes.unwrap_or(DEFAULT_FLUTES);
        require(flutes >= 1, "flutes", flutes as f64, ">= 1")?;
        let helix_deg = finite("helix", opts.helix_deg.unwrap_or(DEFAULT_HELIX_DEG))?;
        require(
            helix_deg > -90.0 && helix_deg < 90.0,
            "helix",
            helix_deg,
            "in (-90°, 90°)",
        )?;
        let rake_deg = match opts.rake_deg {
            Some(r) => {
                finite("rake", r)?;
                require(r > -90.0 && r < 90.0, "rake", r, "in (-90°, 90°)")?;
                Some(r)
            }
            None => None,
        };
        let flute_length = finite("flute length", opts.flute_length.unwrap_or(h))?;
        require(flute_length > 0.0, "flute length", flute_length, "> 0 mm")?;
        let shank_diameter = finite(
            "shank diameter",
            opts.shank_diameter.unwrap_or(2.0 * rho_top),
        )?;
        require(
            shank_diameter > 0.0 && shank_diameter <= MAX_DIAMETER_MM,
            // A shank the spec did not give is the cutting part's top: say what made it.
            if opts.shank_diameter.is_some() {
                "shank diameter"
            } else {
                "shank diameter (the cutting part's diameter at its top, from the diameter, \
                 taper and length given)"
            },
            shank_diameter,
            "in (0, 500] mm",
        )?;
        let overall_length = finite(
            "overall length",
            opts.overall_length.unwrap_or(h + 2.0 * shank_diameter),
        )?;
        require(
            overall_length > 0.0 && overall_length <= MAX_LENGTH_MM,
            "overall length",
            overall_length,
            "in (0, 2500] mm",
        )?;
        if flute_length > overall_length {
            return Err(ToolError::LongerThan {
                inner: "flute length".into(),
                inner_value: flute_length,
                outer: "overall length".into(),
                outer_value: overall_length,
            });
        }
        if h > overall_length {
            return Err(ToolError::LongerThan {
                inner: "cutting height h".into(),
                inner_value: h,
                outer: "overall length".into(),
                outer_value: overall_length,
            });
        }
        let shank = RevolvedSolid::stack(&if overall_length > h {
            vec![(
                h,
                overall_length,
                shank_diameter / 2.0,
                shank_diameter / 2.0,
            )]
        } else {
            vec![]
        });
        let holder_solid = match &opts.holder {
            Some(hd) => Some(hd.solid()?),
            None => None,
        };
        Ok(Cutter {
            kind,
            apt: AptParams { e, f, ..apt },
            alpha,
            beta,
            cutting,
            shank,
            flutes,
            flutes_given: opts.flutes.is_some(),
            helix_deg,
            rake_deg,
            flute_length,
            shank_diameter,
            overall_length,
            holder: opts.holder.clone(),
            holder_solid,
        })
    }

    /// The same cutter with other options (flutes, lengths, shank, holder), re-validated.
    pub fn with_options(&self, opts: &CutterOptions) -> Result<Cutter, ToolError> {
        Self::build(self.kind, self.apt, opts)
    }

    /// Which constructor made it.
    pub fn kind(&self) -> CutterKind {
        self.kind
    }

    /// The seven APT numbers (e and f as implied by the others, see the module doc).
    pub fn apt_params(&self) -> AptParams {
        self.apt
    }

    /// Bottom angle α, radians.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// Side angle β, radians.
    pub fn beta(&self) -> f64 {
        self.beta
    }

    /// Number of flutes (the default [`DEFAULT_FLUTES`] when none was given).
    pub fn flutes(&self) -> u32 {
        self.flutes
    }

    /// Number of flutes as given by the spec or tool library; `None` when it was left to the
    /// default (geometry does not need it; a force model does).
    pub fn flutes_given(&self) -> Option<u32> {
        self.flutes_given.then_some(self.flutes)
    }

    /// Normal rake angle of the edges, degrees, when given.
    pub fn rake_deg(&self) -> Option<f64> {
        self.rake_deg
    }

    /// Helix angle, degrees.
    pub fn helix_deg(&self) -> f64 {
        self.helix_deg
    }

    /// Cutting (flute) length, mm.
    pub fn flute_length(&self) -> f64 {
        self.flute_length
    }

    /// Shank diameter, mm.
    pub fn shank_diameter(&self) -> f64 {
        self.shank_diameter
    }

    /// Overall length (tip to end of shank), mm.
    pub fn overall_length(&self) -> f64 {
        self.overall_length
    }

    /// The holder, if any.
    pub fn holder(&self) -> Option<&Holder> {
        self.holder.as_ref()
    }

    /// The cutting part as a closed solid (z ∈ [0, h]).
    pub fn cutting_solid(&self) -> &RevolvedSolid {
        &self.cutting
    }

    /// The shank as a closed solid (z ∈ [h, overall length]; empty when they are equal).
    pub fn shank_solid(&self) -> &RevolvedSolid {
        &self.shank
    }

    /// The holder as a closed solid, if any.
    pub fn holder_solid(&self) -> Option<&RevolvedSolid> {
        self.holder_solid.as_ref()
    }

    /// Pieces of the cutting part, bottom to top (the last is the non-cutting top cap).
    pub fn pieces(&self) -> &[AnyPiece] {
        self.cutting.pieces()
    }

    /// Radius of the cutting part at height `z` (`None` outside `[0, h]`).
    pub fn profile_radius(&self, z: f64) -> Option<f64> {
        self.cutting.profile_radius(z)
    }

    /// True when `p` (cutter frame) is inside the closed cutting part.
    pub fn contains(&self, p: Vec3) -> bool {
        self.cutting.contains(p)
    }

    /// Every crossing of `ray` (cutter frame) with the cutting part's boundary, sorted.
    pub fn ray_intersections(&self, ray: &Ray, out: &mut Vec<f64>) {
        self.cutting.ray_intersections(ray, out)
    }

    /// The half-profile `(radius, height)` from the tip (on the axis) up the cutting part and
    /// the shank to the end of the shank (on the axis), `n + 1` heights evenly spaced, for
    /// drawing the tool (a report's tool figure).
    pub fn half_profile(&self, n: usize) -> Vec<(f64, f64)> {
        let top = self.overall_length();
        let n = n.max(1);
        let mut out = Vec::with_capacity(n + 3);
        out.push((0.0, 0.0));
        out.extend((0..=n).map(|i| {
            let z = top * i as f64 / n as f64;
            let r = self
                .profile_radius(z)
                .unwrap_or(0.5 * self.shank_diameter())
                .max(0.0);
            (r, z)
        }));
        out.push((0.0, top));
        out
    }

    /// Largest diameter of the cutting part.
    pub fn max_diameter(&self) -> f64 {
        2.0 * self.cutting.max_radius()
    }

    /// Corner centre `(e, f)` in the profile plane.
    pub fn corner_center(&self) -> Vec2 {
        Vec2::new(self.apt.e, self.apt.f)
    }
}

/// The profile pieces bottom to top, closed by the top cap (see the module doc).
#[allow(clippy::too_many_arguments)]
fn profile_pieces(
    r: f64,
    e: f64,
    f: f64,
    alpha: f64,
    beta: f64,
    h: f64,
    p2: Vec2,
    rho_top: f64,
) -> RevolvedSolid {
    let mut pieces = Vec::new();
    let p1 = Vec2::new(e + r * alpha.sin(), f - r * alpha.cos());
    if p1.x > 0.0 {
        if alpha == 0.0 {
            pieces.push(AnyPiece::Disc(DiscPiece::new(0.0, 0.0, p1.x, false)));
        } else {
            pieces.push(AnyPiece::Cone(ConePiece::new(Vec2::ZERO, p1)));
        }
    }
    let (phi0, phi1) = (alpha, std::f64::consts::FRAC_PI_2 - beta);
    if r > 0.0 && phi1 > phi0 {
        pieces.push(if e > 0.0 {
            AnyPiece::Torus(TorusPiece::new(e, r, f, phi0, phi1))
        } else {
            AnyPiece::Sphere(SpherePiece::new(r, f, phi0, phi1))
        });
    }
    if h > p2.y {
        let top = Vec2::new(rho_top, h);
        pieces.push(if beta == 0.0 {
            AnyPiece::Cylinder(CylinderPiece::new(p2.x, p2.y, h))
        } else {
            AnyPiece::Cone(ConePiece::new(p2, top))
        });
    }
    pieces.push(AnyPiece::Disc(DiscPiece::new(h, 0.0, rho_top, true)));
    RevolvedSolid::new(pieces, 0.0, h)
}

/// Largest gap between consecutive pieces' profile ends and largest angle (radians) between
/// their normals at the joints, for joints where APT implies tangency (not at sharp corners).
/// Exposed for tests and diagnostics.
pub fn joint_errors(c: &Cutter) -> (f64, f64) {
    let ps: Vec<&AnyPiece> = c
        .pieces()
        .iter()
        .filter(|p| !matches!(p, AnyPiece::Disc(d) if d.facing_up))
        .collect();
    let mut gap: f64 = 0.0;
    let mut ang: f64 = 0.0;
    for w in ps.windows(2) {
        let a = w[0].profile_point(1.0);
        let b = w[1].profile_point(0.0);
        gap = gap.max((a - b).length());
        let corner = matches!(w[0], AnyPiece::Torus(_) | AnyPiece::Sphere(_))
            || matches!(w[1], AnyPiece::Torus(_) | AnyPiece::Sphere(_));
        if corner {
            let na = w[0].profile_normal(1.0);
            let nb = w[1].profile_normal(0.0);
            // atan2 of cross and dot: accurate for tiny angles, unlike acos of the dot.
            ang = ang.max(na.perp_dot(nb).atan2(na.dot(nb)).abs());
        }
    }
    (gap, ang)
}
