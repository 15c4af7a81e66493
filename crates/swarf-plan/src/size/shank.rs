//! The shank must be free too (Liu §2.3.1): after the allowable size is found, the cylinder of
//! the shank diameter above the flute length is checked against the surface by subdivision of
//! the same Bézier pieces, with separating planes (below the shank's bottom, or outside its
//! radius) as the pruning test and surface points strictly inside as the evidence; where it
//! interferes, [`shank_limited`] lowers the size by bisection until it is free.

use swarf_geom::math::Vec3;

use super::{AllowableSize, Contact, CutterFamily, Limit, PreparedSurface, Regime, SizeTolerances};
use swarf_surface::bezier::Piece;

/// The shank to check.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShankCheck {
    /// Flute (cutting) length above the tip, mm: the shank starts there.
    pub flute_length: f64,
    /// Shank diameter, mm; `None`: the cutter's own nominal diameter.
    pub diameter: Option<f64>,
    /// Node budget. Default 20 000.
    pub max_nodes: u64,
}

impl ShankCheck {
    /// A shank of the cutter's own diameter above `flute_length` mm.
    pub fn new(flute_length: f64) -> Self {
        Self {
            flute_length,
            diameter: None,
            max_nodes: 20_000,
        }
    }
}

/// The outcome of the shank check.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ShankStatus {
    /// No surface point is inside the shank.
    Free,
    /// This surface point is inside the shank, `depth` mm from its side.
    Interferes {
        /// The point.
        point: Vec3,
        /// How far inside, mm.
        depth: f64,
    },
    /// The budget ran out before every piece was proven free; no point found inside.
    Unresolved,
    /// Nothing to check (infinite or zero size, or unreachable contact).
    NotApplicable,
    /// The shank lowered the allowable size ([`shank_limited`]): at the cutting part's size
    /// `cutting_size` it reached into the surface, last at `point` during the bisection.
    Limits {
        /// The shank's point that limits the size.
        point: Vec3,
        /// The cutting part's own allowable size (`L`), above the reported one.
        cutting_size: f64,
    },
}

/// Checks the shank of the cutter of `size` placed at the contact.
pub fn check_shank(
    prep: &PreparedSurface,
    family: &CutterFamily,
    c: &Contact,
    size: f64,
    shank: &ShankCheck,
    tol: &SizeTolerances,
) -> ShankStatus {
    let regime = family.regime(c, tol);
    if !(size.is_finite() && size > 0.0) || regime == Regime::Unreachable {
        return ShankStatus::NotApplicable;
    }
    let Some(k) = family.placed(c, &regime, size) else {
        return ShankStatus::NotApplicable;
    };
    let z0 = k.tip().z + shank.flute_length;
    let radius = shank
        .diameter
        .map_or_else(|| family.nominal_radius(size), |d| 0.5 * d);
    let axis = k.axis;
    let inside = |p: Vec3| {
        let rho = Vec3::new(p.x - axis.x, p.y - axis.y, 0.0).length();
        let depth = (radius - rho).min(p.z - z0);
        (depth > tol.contact).then_some(depth)
    };
    let free = |pc: &Piece| {
        let pts: Vec<Vec3> = pc
            .net
            .iter()
            .map(|h| Vec3::new(h.x, h.y, h.z) / h.w)
            .collect();
        if pts.iter().all(|p| p.z <= z0 + tol.contact) {
            return true;
        }
        let centroid = pts.iter().copied().sum::<Vec3>() / pts.len() as f64;
        let e = Vec3::new(centroid.x - axis.x, centroid.y - axis.y, 0.0);
        if e.length() > 0.0 {
            let e = e.normalize();
            let m = pts
                .iter()
                .map(|p| (*p - axis).dot(e))
                .fold(f64::INFINITY, f64::min);
            return m >= radius - tol.contact;
        }
        false
    };
    let mut stack: Vec<Piece> = prep.pieces.clone();
    let mut nodes = 0;
    let mut unresolved = false;
    while let Some(pc) = stack.pop() {
        for p in pc.corners_on_part() {
            if let Some(depth) = inside(p) {
                return ShankStatus::Interferes { point: p, depth };
            }
        }
        if free(&pc) {
            continue;
        }
        nodes += 1;
        if nodes > shank.max_nodes {
            unresolved = true;
            break;
        }
        stack.extend(pc.children().into_iter().filter(Piece::on_part));
    }
    if unresolved {
        ShankStatus::Unresolved
    } else {
        ShankStatus::Free
    }
}

/// Bisection stops when the bracket on the shank-limited size is this narrow, mm (or this
/// fraction of the size).
const SHANK_BISECTION_ABS: f64 = 1e-7;
const SHANK_BISECTION_REL: f64 = 1e-9;

/// The allowable size with the shank free too (Liu §2.3.1): `size` (the cutting part's
/// allowable size, certified or not) when the shank is free at it, else the largest size found
/// by bisection at which the shank is proven free, limited by interference at the shank's
/// point, and the shank's status there ([`ShankStatus::Limits`] when it lowered the size).
///
/// Every size below the cutting part's allowable size keeps the cutting part free (the family
/// is nested), so the result is safe for the whole tool. The shank's interference need not be
/// monotone in the size (the shank moves with the cutter), so the result is the largest free
/// size of the bracket the bisection keeps, not a certified maximum. An unbounded size is first
/// cut to twice the diagonal of the surface's box: no larger cutter touches anything
/// differently.
pub fn shank_limited(
    prep: &PreparedSurface,
    family: &CutterFamily,
    c: &Contact,
    size: AllowableSize,
    shank: &ShankCheck,
    tol: &SizeTolerances,
) -> (AllowableSize, ShankStatus) {
    let reach = prep
        .bounding_box()
        .map_or(1e3, |b| 2.0 * (b.max - b.min).length().max(1.0));
    let hi0 = size.size.min(reach);
    let at_hi = check_shank(prep, family, c, hi0, shank, tol);
    let ShankStatus::Interferes { point, .. } = at_hi else {
        return (size, at_hi);
    };
    let (mut lo, mut hi, mut point) = (0.0, hi0, point);
    while hi - lo > SHANK_BISECTION_ABS + SHANK_BISECTION_REL * hi {
        let mid = 0.5 * (lo + hi);
        match check_shank(prep, family, c, mid, shank, tol) {
            ShankStatus::Free | ShankStatus::NotApplicable => lo = mid,
            ShankStatus::Interferes { point: p, .. } => {
                hi = mid;
                point = p;
            }
            // Not proven free: keep it out of the answer.
            ShankStatus::Unresolved | ShankStatus::Limits { .. } => hi = mid,
        }
    }
    let limited = AllowableSize {
        size: lo,
        limit: Some(Limit::Interference),
        limit_point: Some(point),
        ..size
    };
    (
        limited,
        ShankStatus::Limits {
            point,
            cutting_size: size.size,
        },
    )
}
