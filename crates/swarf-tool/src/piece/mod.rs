//! Surface pieces of a solid of revolution: disc, cone frustum, cylinder, torus arc, sphere arc.
//!
//! A cutter (and a shank or holder) is described in its local frame: tip at the origin, axis
//! +Z. In a meridian half-plane its boundary is a **profile** of line segments and circular arcs
//! in (ρ, z) (ρ: distance to the axis); revolving each profile element about the axis gives a
//! [`Piece`]. Every piece is parameterised by a profile parameter `s ∈ [0, 1]` running from its
//! lower (or inner, for a horizontal disc) end to its upper (outer) end, and an angle `θ` about
//! the axis, so `point(s, θ) = (ρ(s)·cos θ, ρ(s)·sin θ, z(s))`.
//!
//! Ray intersections reuse the swarf-geom primitives and keep the hits inside the piece's own
//! band. Bands are **half-open** (`[z0, z1)`, or `[ρ0, ρ1)` for a disc) so that a ray through
//! the circle where two pieces join is counted once, by the upper piece.

mod cone;
mod cylinder;
mod disc;
mod sphere;
mod torus;

pub use cone::ConePiece;
pub use cylinder::CylinderPiece;
pub use disc::DiscPiece;
pub use sphere::SpherePiece;
pub use torus::TorusPiece;

use swarf_geom::math::{Vec2, Vec3};
use swarf_geom::Ray;

/// A surface of revolution bounded by two circles (or a circle and the axis).
pub trait Piece {
    /// Lowest and highest z of the piece (equal for a disc).
    fn z_range(&self) -> (f64, f64);

    /// Profile point `(ρ, z)` at parameter `s ∈ [0, 1]` (bottom/inner end at 0).
    fn profile_point(&self, s: f64) -> Vec2;

    /// Outward unit profile normal `(n_ρ, n_z)` at parameter `s`.
    fn profile_normal(&self, s: f64) -> Vec2;

    /// Profile radius at height `z`, `None` outside the piece's z band. A disc answers its
    /// outer radius at its own height.
    fn radius_at(&self, z: f64) -> Option<f64>;

    /// Appends the parameters where `ray` (cutter-local coordinates) crosses this piece, within
    /// its half-open band; not sorted across pieces.
    fn ray_intersections(&self, ray: &Ray, out: &mut Vec<f64>);

    /// True for a horizontal piece (a disc), which has no radius function of z.
    fn is_horizontal(&self) -> bool {
        false
    }

    /// The point at profile parameter `s` and angle `theta` (radians) about the axis.
    fn point(&self, s: f64, theta: f64) -> Vec3 {
        let p = self.profile_point(s);
        let (sn, cs) = theta.sin_cos();
        Vec3::new(p.x * cs, p.x * sn, p.y)
    }

    /// The outward unit normal at profile parameter `s` and angle `theta`.
    fn normal(&self, s: f64, theta: f64) -> Vec3 {
        let n = self.profile_normal(s);
        let (sn, cs) = theta.sin_cos();
        Vec3::new(n.x * cs, n.x * sn, n.y)
    }

    /// True when `p` lies in the piece's z band and within its radius there: the slab of the
    /// solid of revolution that this piece bounds.
    fn contains(&self, p: Vec3) -> bool {
        match self.radius_at(p.z) {
            Some(r) => p.x.hypot(p.y) <= r,
            None => false,
        }
    }
}

/// One of the piece shapes; the closed set that cutters, shanks and holders are made of.
#[derive(Clone, Debug, PartialEq)]
pub enum AnyPiece {
    /// Horizontal annulus or disc.
    Disc(DiscPiece),
    /// Cone frustum (non-zero taper).
    Cone(ConePiece),
    /// Cylinder band.
    Cylinder(CylinderPiece),
    /// Arc of a torus (corner with its centre off the axis).
    Torus(TorusPiece),
    /// Arc of a sphere (corner centred on the axis).
    Sphere(SpherePiece),
}

macro_rules! dispatch {
    ($self:ident, $p:ident => $e:expr) => {
        match $self {
            AnyPiece::Disc($p) => $e,
            AnyPiece::Cone($p) => $e,
            AnyPiece::Cylinder($p) => $e,
            AnyPiece::Torus($p) => $e,
            AnyPiece::Sphere($p) => $e,
        }
    };
}

impl AnyPiece {
    /// Short snake_case name of the shape (`disc`, `cone`, `cylinder`, `torus`, `sphere`).
    pub fn shape_name(&self) -> &'static str {
        match self {
            AnyPiece::Disc(_) => "disc",
            AnyPiece::Cone(_) => "cone",
            AnyPiece::Cylinder(_) => "cylinder",
            AnyPiece::Torus(_) => "torus",
            AnyPiece::Sphere(_) => "sphere",
        }
    }
}

impl Piece for AnyPiece {
    fn z_range(&self) -> (f64, f64) {
        dispatch!(self, p => p.z_range())
    }
    fn profile_point(&self, s: f64) -> Vec2 {
        dispatch!(self, p => p.profile_point(s))
    }
    fn profile_normal(&self, s: f64) -> Vec2 {
        dispatch!(self, p => p.profile_normal(s))
    }
    fn radius_at(&self, z: f64) -> Option<f64> {
        dispatch!(self, p => p.radius_at(z))
    }
    fn ray_intersections(&self, ray: &Ray, out: &mut Vec<f64>) {
        dispatch!(self, p => p.ray_intersections(ray, out))
    }
    fn is_horizontal(&self) -> bool {
        dispatch!(self, p => p.is_horizontal())
    }
}

/// Keeps the hits appended to `out` since `start` whose point satisfies `keep`.
fn retain_from(out: &mut Vec<f64>, start: usize, ray: &Ray, keep: impl Fn(Vec3) -> bool) {
    let mut w = start;
    for i in start..out.len() {
        let t = out[i];
        if keep(ray.at(t)) {
            out[w] = t;
            w += 1;
        }
    }
    out.truncate(w);
}

/// The half-open band test used by every non-horizontal piece.
fn in_band(z: f64, z0: f64, z1: f64) -> bool {
    z >= z0 && z < z1
}

/// Segment profile helpers shared by cone and cylinder pieces: the outward normal of the
/// segment from `a` to `b` traversed upwards is the direction rotated clockwise.
fn segment_normal(a: Vec2, b: Vec2) -> Vec2 {
    let d = (b - a).normalize();
    Vec2::new(d.y, -d.x)
}
