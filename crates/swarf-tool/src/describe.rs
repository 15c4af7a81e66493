//! A serialisable description of a cutter, for `swarf tool SPEC --json` and reports.
//!
//! Field names are stable snake_case with units in the names.

use crate::cutter::Cutter;
use crate::holder::Holder;
use crate::piece::{AnyPiece, Piece};

/// The seven APT numbers with their meaning in the names.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct AptDescription {
    /// APT d: diameter where the corner meets the side.
    pub diameter_mm: f64,
    /// APT r: corner radius.
    pub corner_radius_mm: f64,
    /// APT e: radial distance from the axis to the corner centre.
    pub corner_center_radial_mm: f64,
    /// APT f: height of the corner centre above the tip.
    pub corner_center_height_mm: f64,
    /// APT α: bottom angle from the horizontal.
    pub bottom_angle_deg: f64,
    /// APT β: side angle from the axis.
    pub side_angle_deg: f64,
    /// APT h: height of the cutting part.
    pub height_mm: f64,
}

/// One boundary piece of the cutting part.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PieceDescription {
    /// `bottom_disc`, `bottom_cone`, `corner`, `side` or `top_cap`.
    pub role: &'static str,
    /// `disc`, `cone`, `cylinder`, `torus` or `sphere`.
    pub shape: &'static str,
    /// Lowest z.
    pub z_min_mm: f64,
    /// Highest z.
    pub z_max_mm: f64,
    /// Profile radius at the start of the piece (bottom, or inner edge of a disc).
    pub radius_start_mm: f64,
    /// Profile radius at the end of the piece (top, or outer edge of a disc).
    pub radius_end_mm: f64,
    /// Angle between the surface and the axis for cones, degrees.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub angle_from_axis_deg: Option<f64>,
    /// Tube radius of a torus or sphere piece.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub arc_radius_mm: Option<f64>,
    /// Centre `(ρ, z)` of the arc of a torus or sphere piece.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub arc_center_mm: Option<[f64; 2]>,
    /// Whether the piece cuts (the top cap does not).
    pub cutting: bool,
}

/// Everything the CLI prints about a cutter.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct CutterDescription {
    /// Constructor kind (`flat`, `ball`, `bull`, `taper_flat`, `taper_ball`, `chamfer`,
    /// `drill`, `apt`).
    pub kind: crate::cutter::CutterKind,
    /// Spec string that rebuilds the cutter.
    pub spec: String,
    /// The seven APT numbers (e and f as implied by the others), flattened into the top level
    /// of the JSON (`diameter_mm`, `corner_radius_mm`, …).
    #[serde(flatten)]
    pub apt: AptDescription,
    /// Number of flutes.
    pub flutes: u32,
    /// Whether the flute count was given (false: [`crate::cutter::DEFAULT_FLUTES`], which the
    /// force model does not take as a fact).
    pub flutes_given: bool,
    /// Helix angle.
    pub helix_deg: f64,
    /// Cutting length.
    pub flute_length_mm: f64,
    /// Shank diameter.
    pub shank_diameter_mm: f64,
    /// Tip to end of shank.
    pub overall_length_mm: f64,
    /// Holder, if any.
    pub holder: Option<Holder>,
    /// Largest diameter of the cutting part.
    pub max_diameter_mm: f64,
    /// Height of the corner centre above the tip (APT f).
    pub tip_to_corner_center_mm: f64,
    /// Diameter of the cutting part at its top (z = h).
    pub top_diameter_mm: f64,
    /// Boundary pieces bottom to top.
    pub pieces: Vec<PieceDescription>,
}

impl CutterDescription {
    /// Describes `c`.
    pub fn of(c: &Cutter) -> Self {
        let a = c.apt_params();
        let pieces = c.pieces().iter().map(describe_piece).collect();
        CutterDescription {
            kind: c.kind(),
            spec: c.spec(),
            apt: AptDescription {
                diameter_mm: a.d,
                corner_radius_mm: a.r,
                corner_center_radial_mm: a.e,
                corner_center_height_mm: a.f,
                bottom_angle_deg: a.alpha_deg,
                side_angle_deg: a.beta_deg,
                height_mm: a.h,
            },
            flutes: c.flutes(),
            flutes_given: c.flutes_given().is_some(),
            helix_deg: c.helix_deg(),
            flute_length_mm: c.flute_length(),
            shank_diameter_mm: c.shank_diameter(),
            overall_length_mm: c.overall_length(),
            holder: c.holder().cloned(),
            max_diameter_mm: c.max_diameter(),
            tip_to_corner_center_mm: a.f,
            top_diameter_mm: 2.0 * c.profile_radius(a.h).unwrap_or(0.0),
            pieces,
        }
    }
}

fn describe_piece(p: &AnyPiece) -> PieceDescription {
    let (z_min_mm, z_max_mm) = p.z_range();
    let (a, b) = (p.profile_point(0.0), p.profile_point(1.0));
    let mut d = PieceDescription {
        role: "side",
        shape: p.shape_name(),
        z_min_mm,
        z_max_mm,
        radius_start_mm: a.x,
        radius_end_mm: b.x,
        angle_from_axis_deg: None,
        arc_radius_mm: None,
        arc_center_mm: None,
        cutting: true,
    };
    match p {
        AnyPiece::Disc(disc) if disc.facing_up => {
            d.role = "top_cap";
            d.cutting = false;
        }
        AnyPiece::Disc(_) => d.role = "bottom_disc",
        AnyPiece::Cone(c) => {
            d.angle_from_axis_deg = Some(c.half_angle().to_degrees());
            if a.x == 0.0 && a.y == 0.0 {
                d.role = "bottom_cone";
            }
        }
        AnyPiece::Cylinder(_) => d.angle_from_axis_deg = Some(0.0),
        AnyPiece::Torus(t) => {
            d.role = "corner";
            d.arc_radius_mm = Some(t.minor);
            d.arc_center_mm = Some([t.major, t.center_z]);
        }
        AnyPiece::Sphere(s) => {
            d.role = "corner";
            d.arc_radius_mm = Some(s.radius);
            d.arc_center_mm = Some([0.0, s.center_z]);
        }
    }
    d
}
