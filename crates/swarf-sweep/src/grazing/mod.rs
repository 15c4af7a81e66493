//! Characteristic (grazing) curves of the cutter's pieces at one instant.
//!
//! A point `P` of the moving tool with outward normal `N` is a **grazing point** when
//! `f = N·V(P) = 0` (Aras eq. 5.18): the surface slides along itself there, and the envelope of
//! the motion is the union over time of these curves. One file per piece shape:
//!
//! * [`cone`] — a frustum as a **canal surface** (Aras §3.1–3.3): spheres centred on the axis
//!   with radius growing linearly along it. Each sphere touches the cone along a parallel, the
//!   *characteristic circle* `K`; the moving sphere meets the plane through its centre normal
//!   to the centre's velocity `m_u` in a *great circle* `S`; `K ∩ S` are the grazing points,
//!   in closed form `θ₁,₂ = atan2(A₁, A₂) ± acos(A₀ / √(A₁² + A₂²))` (eq. 3.58–3.60, re-derived
//!   below).
//! * [`sphere`] — the ball of a ball-nose: one sphere, so `S` is its great circle normal to the
//!   velocity of its centre and each parallel of the zone meets it in the same closed form.
//! * [`cylinder`] and [`torus`] — **pipe surfaces** (constant sphere radius, spine a line or a
//!   circle): the grazing normal is `N = m_t × m_u` (Aras Property 3.2, eq. 3.61) and the points
//!   are `m ± r·N/|N|`, no trigonometric solve at all.
//! * [`disc`] — flat bottoms and caps: the tangency is affine over the plane, its zero set a
//!   chord; the disc's **rim** is an edge whose normal cone joins the disc's and the
//!   neighbouring piece's normals, and a rim point grazes when that cone holds a direction
//!   normal to its velocity (the two tangencies differ in sign). A disc translating off its
//!   plane sweeps an (oblique) elliptic cylinder: the sweep of those rim points.
//!
//! # The closed form, re-derived
//! With `m` the moving-sphere centre, `r` its radius, `r_t = dr/dt` along a unit-speed spine,
//! the characteristic circle has centre `C = m − r·r_t·m_t` and radius `R = r·√(1 − r_t²)`
//! (eq. 3.8–3.9 with `|m_t| = 1`). A point `P = C + R(cos θ·w₁ + sin θ·w₂)` has normal
//! `(P − m)/r`, and for a rigid motion `V(P) − V(m) = ω × (P − m)` is normal to `P − m`, so
//! `N·V(P) = 0 ⇔ (P − m)·m_u = 0` with `m_u = V(m)`:
//!
//! ```text
//! A₂ cos θ + A₁ sin θ = A₀,  A₂ = R (w₁·m_u),  A₁ = R (w₂·m_u),  A₀ = r r_t (m_t·m_u) = −(C − m)·m_u
//! ```
//!
//! Real roots exist iff `A₀² ≤ A₁² + A₂²`. (Aras writes the phase `β = atan2(A₂, A₁)` for
//! `sin(θ + β)`; `atan2(A₁, A₂) ± acos` is the same pair and keeps both roots in one branch.)
//!
//! Every piece also answers the tangency on a parallel in one **harmonic** form
//! ([`Harmonic`]): for a profile point `(ρ, z)` with outward normal `(n_ρ, n_z)` and the motion
//! in the tool frame (`V_F`, `ω` components), `P × N = k (ẑ × u)` with `k = z n_ρ − ρ n_z`
//! (`k/n_ρ` is the height of the moving-sphere centre), so
//!
//! ```text
//! f(θ) = A cos θ + B sin θ − C,  A = n_ρ V_x + k ω_y,  B = n_ρ V_y − k ω_x,  C = −n_z V_z.
//! ```
//!
//! This is Aras eq. 5.24/5.33/5.39 for the upper cone, torus and lower cone at once; his
//! `A_T` (eq. 5.33) lost the major radius: it should read `sin φ (x·V_F) + (h_c sin φ +
//! R cos φ)(ω·y)`.

pub mod cone;
pub mod cylinder;
pub mod disc;
pub mod sphere;
pub mod torus;

use swarf_geom::math::{Vec2, Vec3};
use swarf_geom::Frame;
use swarf_tool::{AnyPiece, Piece};

use crate::kinematics::MotionState;

/// One grazing point of the tool at an instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GrazingPoint {
    /// Index of the piece in the slice it was computed from.
    pub piece: usize,
    /// Profile parameter of the piece (`s ∈ [0, 1]`, bottom/inner end at 0).
    pub s: f64,
    /// Angle about the axis in [`MotionState::tool_frame`], radians.
    pub theta: f64,
    /// The point, workpiece frame, mm.
    pub point: Vec3,
    /// A unit normal at the point with `normal · V(point) = 0`: the surface normal, or for a
    /// rim point one of the edge's normal cone.
    pub normal: Vec3,
    /// True for a point on a disc's rim (an edge of the tool).
    pub edge: bool,
}

/// The grazing points of a set of pieces at one instant.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GrazingSet {
    /// The points, piece by piece.
    pub points: Vec<GrazingPoint>,
    /// Parallels `(piece, s)` (for the torus: spine angles `(piece, θ)`) that graze as a whole
    /// circle: the motion is along the axis there (a plunge), where the closed forms have no
    /// isolated roots.
    pub whole: Vec<(usize, f64)>,
}

/// Roots of `f(θ) = A cos θ + B sin θ − C` over a full turn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Roots {
    /// `f` keeps one sign.
    None,
    /// Two roots (equal when the circle only touches).
    Two(f64, f64),
    /// `f ≡ 0` on the circle (within the tolerance given).
    Whole,
}

/// The tangency function along one circle: `f(θ) = a cos θ + b sin θ − c`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Harmonic {
    /// Coefficient of `cos θ`.
    pub a: f64,
    /// Coefficient of `sin θ`.
    pub b: f64,
    /// Constant (subtracted).
    pub c: f64,
}

impl Harmonic {
    /// The tangency on the parallel at profile point `(ρ, z)` with outward profile normal
    /// `(n_ρ, n_z)`, for tip velocity `v` and angular velocity `w` in tool-frame components.
    #[inline]
    pub fn on_parallel(p: Vec2, n: Vec2, v: Vec3, w: Vec3) -> Self {
        let k = p.y * n.x - p.x * n.y;
        Self {
            a: n.x * v.x + k * w.y,
            b: n.x * v.y - k * w.x,
            c: -n.y * v.z,
        }
    }

    /// `f(θ)`.
    #[inline]
    pub fn eval(&self, theta: f64) -> f64 {
        let (s, c) = theta.sin_cos();
        self.a * c + self.b * s - self.c
    }

    /// Largest value over the circle, `√(a² + b²) − c`.
    #[inline]
    pub fn max(&self) -> f64 {
        self.a.hypot(self.b) - self.c
    }

    /// Smallest value over the circle.
    #[inline]
    pub fn min(&self) -> f64 {
        -self.a.hypot(self.b) - self.c
    }

    /// The roots; `|f| ≤ eps` everywhere counts as [`Roots::Whole`].
    pub fn roots(&self, eps: f64) -> Roots {
        solve_cos_sin(self.a, self.b, self.c, eps)
    }
}

/// Solves `a cos θ + b sin θ = c`: `θ = atan2(b, a) ± acos(c / √(a² + b²))`.
pub fn solve_cos_sin(a: f64, b: f64, c: f64, eps: f64) -> Roots {
    let amp = a.hypot(b);
    if amp <= eps {
        return if c.abs() <= eps {
            Roots::Whole
        } else {
            Roots::None
        };
    }
    let q = c / amp;
    if q.abs() > 1.0 {
        // A touch lost to rounding still counts (|q| − 1 of the order of ε).
        if q.abs() - 1.0 <= eps / amp {
            let phase = b.atan2(a) + if q > 0.0 { 0.0 } else { std::f64::consts::PI };
            return Roots::Two(phase, phase);
        }
        return Roots::None;
    }
    let (phase, d) = (b.atan2(a), q.acos());
    Roots::Two(phase - d, phase + d)
}

/// The motion seen in the tool frame: components of `V_F` and `ω`, and the frame.
#[derive(Clone, Copy, Debug)]
pub struct Local {
    /// The tool frame ([`MotionState::tool_frame`]).
    pub frame: Frame,
    /// `V_F` in tool-frame components.
    pub v: Vec3,
    /// `ω` in tool-frame components.
    pub w: Vec3,
}

impl Local {
    /// The tool-frame view of `state`.
    pub fn of(state: &MotionState) -> Self {
        let frame = state.tool_frame();
        Self {
            frame,
            v: frame.vector_to_local(state.v_tip),
            w: frame.vector_to_local(state.omega),
        }
    }

    /// World point of the tool-frame cylindrical coordinates `(ρ, θ, z)`.
    #[inline]
    pub fn point(&self, rho: f64, theta: f64, z: f64) -> Vec3 {
        let (s, c) = theta.sin_cos();
        self.frame.to_world(Vec3::new(rho * c, rho * s, z))
    }

    /// World vector of the profile direction `(d_ρ, d_z)` at angle `θ`.
    #[inline]
    pub fn dir(&self, d: Vec2, theta: f64) -> Vec3 {
        let (s, c) = theta.sin_cos();
        self.frame.vector_to_world(Vec3::new(d.x * c, d.x * s, d.y))
    }

    /// Largest point speed over a ball of radius `reach` about the tip: the scale of `f`.
    pub fn speed(&self, reach: f64) -> f64 {
        self.v.length() + self.w.length() * reach
    }
}

/// Profile parameters `i/(n − 1)` for `n ≥ 2` samples (`[0.5]` for one).
pub fn parameters(n: usize) -> impl Iterator<Item = f64> {
    let d = (n.max(2) - 1) as f64;
    (0..n.max(1)).map(move |i| if n <= 1 { 0.5 } else { i as f64 / d })
}

/// Grazing points of every piece of `pieces` (tool frame: tip at the origin, axis +Z) under
/// `state`, with `samples` parallels (or spine angles) per piece.
pub fn grazing_points(pieces: &[AnyPiece], state: &MotionState, samples: usize) -> GrazingSet {
    let local = Local::of(state);
    let mut out = GrazingSet::default();
    for (i, p) in pieces.iter().enumerate() {
        match p {
            AnyPiece::Cone(c) => cone::grazing(c, i, state, &local, samples, &mut out),
            AnyPiece::Cylinder(c) => cylinder::grazing(c, i, state, &local, samples, &mut out),
            AnyPiece::Torus(t) => torus::grazing(t, i, state, &local, samples, &mut out),
            AnyPiece::Sphere(s) => sphere::grazing(s, i, state, &local, samples, &mut out),
            AnyPiece::Disc(d) => {
                disc::grazing(d, i, state, &local, samples, &mut out);
                for rho in [d.outer, d.inner] {
                    if rho > 0.0 {
                        let side = neighbour_normal(pieces, i, Vec2::new(rho, d.z));
                        disc::rim(d, i, rho, side, state, &local, samples, &mut out);
                    }
                }
            }
        }
    }
    out
}

/// Outward profile normal of the non-disc piece that ends at profile point `at`, if any.
fn neighbour_normal(pieces: &[AnyPiece], skip: usize, at: Vec2) -> Option<Vec2> {
    const JOIN_EPS: f64 = 1e-9;
    pieces.iter().enumerate().find_map(|(j, q)| {
        if j == skip || q.is_horizontal() {
            return None;
        }
        [0.0, 1.0].into_iter().find_map(|s| {
            (q.profile_point(s).distance(at) <= JOIN_EPS).then(|| q.profile_normal(s))
        })
    })
}

/// Pushes the two points of `roots` on the parallel `(ρ, z)` with profile normal `n`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn push_parallel_roots(
    roots: Roots,
    piece: usize,
    s: f64,
    p: Vec2,
    n: Vec2,
    local: &Local,
    out: &mut GrazingSet,
) {
    match roots {
        Roots::None => {}
        Roots::Whole => out.whole.push((piece, s)),
        Roots::Two(t1, t2) => {
            let ts: &[f64] = if t1 == t2 { &[t1] } else { &[t1, t2] };
            for &theta in ts {
                out.points.push(GrazingPoint {
                    piece,
                    s,
                    theta,
                    point: local.point(p.x, theta, p.y),
                    normal: local.dir(n, theta),
                    edge: false,
                });
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * (1.0 + a.abs().max(b.abs()))
    }

    #[test]
    fn cos_sin_equation_roots() {
        // cos θ = 0.5 → ±60°.
        match solve_cos_sin(1.0, 0.0, 0.5, 0.0) {
            Roots::Two(a, b) => {
                assert!(close(a, -60f64.to_radians()) && close(b, 60f64.to_radians()))
            }
            r => panic!("{r:?}"),
        }
        // 3 cos θ + 4 sin θ = 5 touches at θ = atan2(4, 3).
        match solve_cos_sin(3.0, 4.0, 5.0, 1e-12) {
            Roots::Two(a, b) => assert!(close(a, 4f64.atan2(3.0)) && close(a, b)),
            r => panic!("{r:?}"),
        }
        assert_eq!(solve_cos_sin(1.0, 1.0, 2.0, 1e-12), Roots::None);
        assert_eq!(solve_cos_sin(0.0, 0.0, 0.0, 1e-12), Roots::Whole);
        // Every root satisfies the equation.
        for (a, b, c) in [(0.3, -2.0, 1.1), (-1.0, 0.5, -0.2), (2.0, 2.0, 0.0)] {
            if let Roots::Two(t1, t2) = solve_cos_sin(a, b, c, 0.0) {
                for t in [t1, t2] {
                    assert!((a * t.cos() + b * t.sin() - c).abs() < 1e-14);
                }
            }
        }
    }

    #[test]
    fn harmonic_matches_the_dot_product() {
        // Tool-frame tangency on a parallel against N·(V + ω × P) directly.
        let (p, n) = (Vec2::new(2.0, 3.0), Vec2::new(0.6, -0.8));
        let (v, w) = (Vec3::new(1.0, -2.0, 0.5), Vec3::new(0.3, 0.7, -0.2));
        let h = Harmonic::on_parallel(p, n, v, w);
        for i in 0..16 {
            let t = i as f64 * 0.4;
            let (s, c) = t.sin_cos();
            let pt = Vec3::new(p.x * c, p.x * s, p.y);
            let nn = Vec3::new(n.x * c, n.x * s, n.y);
            assert!((h.eval(t) - nn.dot(v + w.cross(pt))).abs() < 1e-14);
        }
    }
}
