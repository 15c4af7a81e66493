//! One patch of a compound surface: the surface kinds, their derivatives and the differential
//! geometry (normal, fundamental forms, principal curvatures) computed from them.
//!
//! Every kind implements [`ParametricSurface`]: a finite parameter box and the point with its
//! first and second partial derivatives ([`Derivs`]). The differential geometry is computed once,
//! for all kinds, by [`differential`], from those derivatives — so analytic surfaces and NURBS
//! share the same (tested) formulas and the same handling of degenerate points.

mod cone;
mod cylinder;
pub(crate) mod invert;
mod nurbs;
mod plane;
mod sphere;
mod torus;

pub use cone::ConicalSurface;
pub use cylinder::CylindricalSurface;
pub use nurbs::{NurbsError, NurbsSurface};
pub use plane::PlaneSurface;
pub use sphere::SphericalSurface;
pub use torus::ToroidalSurface;

use swarf_geom::math::Vec3;
use swarf_geom::Aabb;

/// The closed parameter rectangle `[u0, u1] × [v0, v1]` of a patch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamBox {
    /// `[u0, u1]`, `u0 < u1`.
    pub u: [f64; 2],
    /// `[v0, v1]`, `v0 < v1`.
    pub v: [f64; 2],
}

impl ParamBox {
    /// The box `[u0, u1] × [v0, v1]`.
    pub fn new(u0: f64, u1: f64, v0: f64, v1: f64) -> Self {
        Self {
            u: [u0, u1],
            v: [v0, v1],
        }
    }

    /// `(u, v)` clamped into the box.
    pub fn clamp(&self, u: f64, v: f64) -> (f64, f64) {
        (u.clamp(self.u[0], self.u[1]), v.clamp(self.v[0], self.v[1]))
    }

    /// True when `(u, v)` lies in the closed box.
    pub fn contains(&self, u: f64, v: f64) -> bool {
        u >= self.u[0] && u <= self.u[1] && v >= self.v[0] && v <= self.v[1]
    }

    /// The parameter at fraction `s ∈ [0, 1]` of the u range (exactly `u1` at `s = 1`).
    pub fn u_at(&self, s: f64) -> f64 {
        lerp(self.u, s)
    }

    /// The parameter at fraction `t ∈ [0, 1]` of the v range (exactly `v1` at `t = 1`).
    pub fn v_at(&self, t: f64) -> f64 {
        lerp(self.v, t)
    }

    /// Widths `(u1 - u0, v1 - v0)`.
    pub fn span(&self) -> (f64, f64) {
        (self.u[1] - self.u[0], self.v[1] - self.v[0])
    }
}

fn lerp(r: [f64; 2], s: f64) -> f64 {
    if s >= 1.0 {
        r[1]
    } else {
        r[0] + s * (r[1] - r[0])
    }
}

/// A point of a surface with its partial derivatives up to order two.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Derivs {
    /// S(u, v).
    pub point: Vec3,
    /// ∂S/∂u.
    pub su: Vec3,
    /// ∂S/∂v.
    pub sv: Vec3,
    /// ∂²S/∂u².
    pub suu: Vec3,
    /// ∂²S/∂u∂v.
    pub suv: Vec3,
    /// ∂²S/∂v².
    pub svv: Vec3,
}

/// What every patch kind answers. Parameters outside [`ParametricSurface::domain`] are clamped
/// into it; parameters must be finite.
pub trait ParametricSurface {
    /// The finite parameter box of the patch.
    fn domain(&self) -> ParamBox;
    /// The point S(u, v).
    fn point(&self, u: f64, v: f64) -> Vec3;
    /// The point with first and second partial derivatives.
    fn derivs(&self, u: f64, v: f64) -> Derivs;
    /// A box that contains the whole patch (for NURBS, the box of the control net, which holds
    /// the surface by the convex-hull property; for analytic kinds, an exact or slightly larger
    /// box of the parameter box's image).
    fn bounding_box(&self) -> Aabb;
}

/// A patch surface: NURBS or one of the STEP elementary surfaces.
#[derive(Clone, Debug, PartialEq)]
pub enum Surface {
    /// Rational or polynomial tensor-product B-spline.
    Nurbs(NurbsSurface),
    /// STEP `PLANE`.
    Plane(PlaneSurface),
    /// STEP `CYLINDRICAL_SURFACE`.
    Cylinder(CylindricalSurface),
    /// STEP `CONICAL_SURFACE`.
    Cone(ConicalSurface),
    /// STEP `SPHERICAL_SURFACE`.
    Sphere(SphericalSurface),
    /// STEP `TOROIDAL_SURFACE`.
    Torus(ToroidalSurface),
}

macro_rules! dispatch {
    ($self:ident, $s:ident => $e:expr) => {
        match $self {
            Surface::Nurbs($s) => $e,
            Surface::Plane($s) => $e,
            Surface::Cylinder($s) => $e,
            Surface::Cone($s) => $e,
            Surface::Sphere($s) => $e,
            Surface::Torus($s) => $e,
        }
    };
}

impl ParametricSurface for Surface {
    fn domain(&self) -> ParamBox {
        dispatch!(self, s => s.domain())
    }
    #[inline]
    fn point(&self, u: f64, v: f64) -> Vec3 {
        dispatch!(self, s => s.point(u, v))
    }
    #[inline]
    fn derivs(&self, u: f64, v: f64) -> Derivs {
        dispatch!(self, s => s.derivs(u, v))
    }
    fn bounding_box(&self) -> Aabb {
        dispatch!(self, s => s.bounding_box())
    }
}

impl Surface {
    /// A short name of the kind (`"nurbs"`, `"plane"`, `"cylinder"`, `"cone"`, `"sphere"`,
    /// `"torus"`).
    pub fn kind(&self) -> &'static str {
        match self {
            Surface::Nurbs(_) => "nurbs",
            Surface::Plane(_) => "plane",
            Surface::Cylinder(_) => "cylinder",
            Surface::Cone(_) => "cone",
            Surface::Sphere(_) => "sphere",
            Surface::Torus(_) => "torus",
        }
    }

    /// Sets the parameter box (a B-spline surface is cut down to it, exactly, its parameters
    /// kept; a box that is not within its knots leaves it as it is). Unchecked: the readers
    /// give it boxes within the surface's own.
    pub(crate) fn set_domain(&mut self, domain: ParamBox) {
        match self {
            Surface::Nurbs(n) => {
                if n.domain() != domain {
                    if let Ok(r) = n.restricted(domain.u, domain.v) {
                        *n = r;
                    }
                }
            }
            Surface::Plane(s) => s.domain = domain,
            Surface::Cylinder(s) => s.domain = domain,
            Surface::Cone(s) => s.domain = domain,
            Surface::Sphere(s) => s.domain = domain,
            Surface::Torus(s) => s.domain = domain,
        }
    }

    /// The differential geometry at `(u, v)` with the normal `S_u × S_v` (see
    /// [`differential`]).
    pub fn local(&self, u: f64, v: f64, tol: &Tolerances) -> LocalGeometry {
        differential(self, u, v, false, tol)
    }
}

/// Tolerances of the differential geometry, all relative (dimensionless).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerances {
    /// A point is degenerate when `|S_u × S_v| ≤ degenerate · max(|S_u|, |S_v|)²` (the sine of
    /// the angle between the partials, or a vanishing partial). Default `1e-10`.
    pub degenerate: f64,
    /// Step into the domain, as a fraction of the parameter span, at which a degenerate point's
    /// limit normal is sampled when the derivatives alone do not give it. Default `1e-6`.
    pub limit_step: f64,
    /// Step into the domain, as a fraction of the parameter span, at which a degenerate point's
    /// curvature is taken (its bias grows with the step, its round-off as `ε/step²` because the
    /// metric vanishes at the point). Default `1e-4`.
    pub limit_curvature_step: f64,
    /// Principal curvatures closer than `umbilic · (|k1| + |k2|)` make an umbilic: the principal
    /// directions are then arbitrary and returned as the unit `S_u` and `n × S_u`. Default `1e-9`.
    pub umbilic: f64,
}

impl Tolerances {
    /// The documented defaults.
    pub const DEFAULT: Tolerances = Tolerances {
        degenerate: 1e-10,
        limit_step: 1e-6,
        limit_curvature_step: 1e-4,
        umbilic: 1e-9,
    };
}

impl Default for Tolerances {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// The unit surface normal at a point, or why there is none.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SurfaceNormal {
    /// `S_u × S_v` is non-zero: the normal is exact.
    Regular(Vec3),
    /// `S_u × S_v` vanishes (pole, collapsed edge, cusp) but the normal has a limit, found from
    /// the second derivatives or from a point `limit_step` into the domain.
    Limit(Vec3),
    /// No normal: the surface is degenerate here and in every direction tried.
    Undefined,
}

impl SurfaceNormal {
    /// The unit vector, `None` when undefined.
    pub fn vector(&self) -> Option<Vec3> {
        match *self {
            SurfaceNormal::Regular(n) | SurfaceNormal::Limit(n) => Some(n),
            SurfaceNormal::Undefined => None,
        }
    }

    fn flipped(self) -> Self {
        match self {
            SurfaceNormal::Regular(n) => SurfaceNormal::Regular(-n),
            SurfaceNormal::Limit(n) => SurfaceNormal::Limit(-n),
            SurfaceNormal::Undefined => SurfaceNormal::Undefined,
        }
    }
}

/// Principal curvatures and directions at a point.
///
/// Sign convention: a curvature is **positive where the surface bends towards the normal**
/// (concave seen from the side the normal points to — from the cutter, for a patch of a
/// [`crate::CompoundSurface`]): a ball of radius `1/k` fits there. Inside a sphere of radius R with
/// the normal towards the centre both are `+1/R`; outside, `-1/R`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Curvature {
    /// The larger principal curvature, 1/mm.
    pub k1: f64,
    /// The smaller principal curvature, 1/mm.
    pub k2: f64,
    /// Unit tangent direction of `k1`.
    pub dir1: Vec3,
    /// Unit tangent direction of `k2` (`n × dir1`).
    pub dir2: Vec3,
}

impl Curvature {
    /// Gaussian curvature `k1·k2`.
    pub fn gaussian(&self) -> f64 {
        self.k1 * self.k2
    }
    /// Mean curvature `(k1 + k2)/2`.
    pub fn mean(&self) -> f64 {
        0.5 * (self.k1 + self.k2)
    }
    fn flipped(self) -> Self {
        Curvature {
            k1: -self.k2,
            k2: -self.k1,
            dir1: self.dir2,
            dir2: self.dir1,
        }
    }
}

/// Everything known about a surface at one parameter point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalGeometry {
    /// Parameters actually evaluated (the request clamped into the domain).
    pub uv: (f64, f64),
    /// Point and partial derivatives.
    pub derivs: Derivs,
    /// Unit normal (flipped when asked).
    pub normal: SurfaceNormal,
    /// Principal curvatures; at a [`SurfaceNormal::Limit`] point, those
    /// [`Tolerances::limit_curvature_step`] into the domain; `None` where the normal is undefined.
    pub curvature: Option<Curvature>,
}

impl LocalGeometry {
    /// The point S(u, v).
    pub fn point(&self) -> Vec3 {
        self.derivs.point
    }
}

/// Normal and curvature of a regular point, or `None` when `S_u × S_v` is degenerate.
fn regular(d: &Derivs, tol: &Tolerances) -> Option<(Vec3, Curvature)> {
    let cross = d.su.cross(d.sv);
    let len = cross.length();
    let scale = d.su.length_squared().max(d.sv.length_squared());
    if len.is_nan() || len <= tol.degenerate * scale || !len.is_finite() {
        return None;
    }
    let n = cross / len;
    Some((n, curvature(d, n, tol)))
}

/// Principal curvatures from the fundamental forms, at a regular point with unit normal `n`.
///
/// The second fundamental form is expressed in the orthonormal tangent basis
/// `e1 = S_u/|S_u|`, `e2 = n × e1` as a symmetric 2×2 matrix `[[a, b], [b, c]]`, whose
/// eigenvalues `(a+c)/2 ± hypot((a−c)/2, b)` are computed without cancellation (unlike
/// `H ± √(H² − K)`, which loses half the digits near umbilics).
fn curvature(d: &Derivs, n: Vec3, tol: &Tolerances) -> Curvature {
    let (e, f, g) = (d.su.dot(d.su), d.su.dot(d.sv), d.sv.dot(d.sv));
    let (l, m, nn) = (d.suu.dot(n), d.suv.dot(n), d.svv.dot(n));
    let det = e * g - f * f;
    let lu = e.sqrt();
    let e1 = d.su / lu;
    let e2 = n.cross(e1);
    // Parameter-space coefficients of e1 = (1/|S_u|, 0) and e2 = (α, β) (dual basis).
    let t = e2.dot(d.sv);
    let (al, be) = (-f * t / det, e * t / det);
    let a = l / e;
    let b = (l * al + m * be) / lu;
    let c = al * al * l + 2.0 * al * be * m + be * be * nn;
    let mid = 0.5 * (a + c);
    let rad = (0.5 * (a - c)).hypot(b);
    let (k1, k2) = (mid + rad, mid - rad);
    let dir1 = if rad <= tol.umbilic * (a.abs() + c.abs()) {
        e1
    } else {
        // Eigenvector of k1 from the better-conditioned row of [[a − k1, b], [b, c − k1]].
        let (x1, y1) = (b, k1 - a);
        let (x2, y2) = (k1 - c, b);
        let (x, y) = if x1 * x1 + y1 * y1 >= x2 * x2 + y2 * y2 {
            (x1, y1)
        } else {
            (x2, y2)
        };
        (x * e1 + y * e2).normalize()
    };
    Curvature {
        k1,
        k2,
        dir1,
        dir2: n.cross(dir1),
    }
}

/// The differential geometry of `surface` at `(u, v)` (clamped into the domain).
///
/// The normal is `S_u × S_v / |S_u × S_v|`, negated when `flipped`. At a degenerate point (see
/// [`Tolerances::degenerate`]) the limit normal is sought, approaching from inside the domain:
/// where one partial vanishes (a pole or collapsed edge, `S_u = 0` say), `S_u ≈ S_uv·δv` nearby
/// and the limit is `±S_uv × S_v` (L'Hôpital); otherwise, or if that too vanishes, the point
/// `limit_step` into the domain (diagonally towards the centre) is evaluated. The curvature of a
/// limit point is that of the point `limit_curvature_step` inside.
pub fn differential<S: ParametricSurface + ?Sized>(
    surface: &S,
    u: f64,
    v: f64,
    flipped: bool,
    tol: &Tolerances,
) -> LocalGeometry {
    let dom = surface.domain();
    let (u, v) = dom.clamp(u, v);
    let d = surface.derivs(u, v);
    let (normal, curvature) = match regular(&d, tol) {
        Some((n, c)) => (SurfaceNormal::Regular(n), Some(c)),
        None => limit(surface, &dom, u, v, &d, tol),
    };
    let (normal, curvature) = if flipped {
        (normal.flipped(), curvature.map(Curvature::flipped))
    } else {
        (normal, curvature)
    };
    LocalGeometry {
        uv: (u, v),
        derivs: d,
        normal,
        curvature,
    }
}

fn limit<S: ParametricSurface + ?Sized>(
    surface: &S,
    dom: &ParamBox,
    u: f64,
    v: f64,
    d: &Derivs,
    tol: &Tolerances,
) -> (SurfaceNormal, Option<Curvature>) {
    let (su_span, sv_span) = dom.span();
    // Directions into the domain (towards its centre).
    let du = if u < 0.5 * (dom.u[0] + dom.u[1]) {
        1.0
    } else {
        -1.0
    };
    let dv = if v < 0.5 * (dom.v[0] + dom.v[1]) {
        1.0
    } else {
        -1.0
    };
    let (lu, lv) = (d.su.length(), d.sv.length());
    let big = lu.max(lv);
    let tiny = tol.degenerate.sqrt() * big;
    // Candidate from the second derivatives.
    let candidate = if lu <= tiny && lv > tiny {
        Some(dv * d.suv.cross(d.sv))
    } else if lv <= tiny && lu > tiny {
        Some(du * d.su.cross(d.suv))
    } else {
        None
    };
    // Nearby points: one for the normal when the derivatives do not give it, one for the
    // curvature.
    let inside = |step: f64| {
        let (un, vn) = dom.clamp(u + du * step * su_span, v + dv * step * sv_span);
        regular(&surface.derivs(un, vn), tol)
    };
    let from_derivs = candidate.and_then(|c| {
        let l = c.length();
        (l > tol.degenerate * big * big.max(d.suv.length()) && l.is_finite()).then(|| c / l)
    });
    let curv = inside(tol.limit_curvature_step).map(|(_, c)| c);
    match from_derivs {
        Some(n) => (SurfaceNormal::Limit(n), curv),
        None => match inside(tol.limit_step) {
            Some((n, _)) => (SurfaceNormal::Limit(n), curv),
            None => (SurfaceNormal::Undefined, None),
        },
    }
}

/// The box of a circle with centre `c`, unit axis `a` and radius `r`.
fn circle_box(c: Vec3, a: Vec3, r: f64) -> Aabb {
    let ext = Vec3::new(
        (1.0 - a.x * a.x).max(0.0).sqrt(),
        (1.0 - a.y * a.y).max(0.0).sqrt(),
        (1.0 - a.z * a.z).max(0.0).sqrt(),
    ) * r;
    Aabb::new(c - ext, c + ext)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn umbilic_and_flip() {
        // A paraboloid z = (x² + y²)/2 at the origin: k1 = k2 = 1 with the +z normal.
        let d = Derivs {
            point: Vec3::ZERO,
            su: Vec3::X,
            sv: Vec3::Y,
            suu: Vec3::Z,
            suv: Vec3::ZERO,
            svv: Vec3::Z,
        };
        let (n, c) = regular(&d, &Tolerances::DEFAULT).unwrap();
        assert_eq!(n, Vec3::Z);
        assert!((c.k1 - 1.0).abs() < 1e-15 && (c.k2 - 1.0).abs() < 1e-15);
        assert_eq!(c.dir1, Vec3::X);
        let f = c.flipped();
        assert_eq!((f.k1, f.k2), (-1.0, -1.0));
    }

    #[test]
    fn saddle_directions() {
        // z = x·y: at the origin k = ±1 along the diagonals.
        let d = Derivs {
            point: Vec3::ZERO,
            su: Vec3::X,
            sv: Vec3::Y,
            suu: Vec3::ZERO,
            suv: Vec3::Z,
            svv: Vec3::ZERO,
        };
        let (_, c) = regular(&d, &Tolerances::DEFAULT).unwrap();
        assert!((c.k1 - 1.0).abs() < 1e-15 && (c.k2 + 1.0).abs() < 1e-15);
        let diag = Vec3::new(1.0, 1.0, 0.0).normalize();
        assert!(c.dir1.dot(diag).abs() > 1.0 - 1e-12);
        assert!(c.dir2.dot(c.dir1).abs() < 1e-15);
    }

    #[test]
    fn zero_partial_is_degenerate() {
        let d = Derivs {
            point: Vec3::ZERO,
            su: Vec3::ZERO,
            sv: Vec3::Y,
            suu: Vec3::ZERO,
            suv: Vec3::X,
            svv: Vec3::ZERO,
        };
        assert!(regular(&d, &Tolerances::DEFAULT).is_none());
    }
}
