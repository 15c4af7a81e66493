//! Cutter families with one free size, their placement at a contact, and the three questions
//! the solvers ask: the imaginary size of a test point, the curvature (local gouge) bound, and
//! the support function of the placed solid (for rigorous lower bounds).

use super::imaginary_apt::AptTrig;
use smallvec::SmallVec;
use swarf_geom::math::{Vec2, Vec3};

use super::{
    imaginary_apt, imaginary_ball, imaginary_taper_ball, Contact, PlacedCutter, SizeError,
    SizeTolerances,
};

/// A cutter shape with one free size parameter `L` (see the [module docs](super)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CutterFamily {
    /// The ball alone (Liu eq. 2.35): radius free, centre `C + L·n`; what the ball end mill's
    /// spherical end can reach. Its side and shank are left to the shank check.
    Sphere,
    /// Tapered ball end mill: taper θ (radians) fixed, ball radius free. θ = 0 is the ball end
    /// mill (sphere and cylinder).
    TaperBall {
        /// Side taper θ, radians, `[0, π/2)`.
        taper: f64,
    },
    /// APT cutter: corner radius, taper and bottom cone angle fixed, `R` (axis to corner-circle
    /// centre) free. Flat end mill: all zero; bull-nose: corner only.
    Apt {
        /// Corner radius r, mm (≥ 0).
        corner: f64,
        /// Side taper θ, radians, `[0, π/2)`.
        taper: f64,
        /// Bottom cone angle ψ, radians, `[0, π/2)`.
        cone: f64,
    },
}

/// How a family's cutter touches the surface at a contact (3-axis, axis `+Z`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Regime {
    /// On the ball: centre at `C + L·n`.
    Ball,
    /// On the APT corner: corner-circle centre `q = C + r·n`, axis at `q + R·u`.
    Corner {
        /// Corner-circle centre at the contact.
        q: Vec3,
        /// Unit horizontal direction from the contact towards the axis.
        u: Vec3,
    },
    /// On the bottom (flat face or tip): the axis passes through the CC point.
    Bottom,
    /// The normal is steeper than the cutter's side: no cutter of the family is tangent.
    Unreachable,
}

/// An affine piece `α + β·L` of the support function `h(ν, L) − C·ν` of a placed cutter.
pub(crate) type Pieces = SmallVec<[(f64, f64); 3]>;

impl CutterFamily {
    /// The ball end mill (sphere and cylinder), radius free.
    pub const BALL: CutterFamily = CutterFamily::TaperBall { taper: 0.0 };
    /// The flat end mill, radius free.
    pub const FLAT: CutterFamily = CutterFamily::Apt {
        corner: 0.0,
        taper: 0.0,
        cone: 0.0,
    };

    /// The ball end mill's sphere alone ([`CutterFamily::Sphere`]): `swarf toolsize --cutter
    /// ball`.
    pub fn ball() -> Self {
        CutterFamily::Sphere
    }

    /// The ball end mill with its cylindrical side (the tapered ball with taper 0).
    pub fn ball_with_side() -> Self {
        Self::BALL
    }

    /// The flat end mill.
    pub fn flat() -> Self {
        Self::FLAT
    }

    /// A bull-nose end mill with corner radius `r` mm (`R + r` is its radius).
    ///
    /// # Errors
    /// When `r` is negative or not finite.
    pub fn bull(r: f64) -> Result<Self, SizeError> {
        Self::apt(r, 0.0, 0.0)
    }

    /// The general APT family: corner radius `r` mm, taper and cone angles in degrees.
    ///
    /// # Errors
    /// When a parameter is out of range.
    pub fn apt(r: f64, taper_deg: f64, cone_deg: f64) -> Result<Self, SizeError> {
        if !(r >= 0.0 && r.is_finite()) {
            return Err(SizeError::Family {
                what: "corner radius",
                value: r,
                range: "0 ≤ r < ∞ mm",
            });
        }
        Ok(CutterFamily::Apt {
            corner: r,
            taper: angle("taper", taper_deg)?,
            cone: angle("cone angle", cone_deg)?,
        })
    }

    /// The family a spec names ([`swarf_tool::FamilySpec`], `swarf toolsize --cutter`).
    ///
    /// ```
    /// use swarf_plan::size::CutterFamily;
    /// use swarf_tool::FamilySpec;
    /// let f = CutterFamily::from_spec(&FamilySpec::parse("bull:r=2").unwrap()).unwrap();
    /// assert_eq!(f, CutterFamily::bull(2.0).unwrap());
    /// ```
    ///
    /// # Errors
    /// A parameter out of range.
    pub fn from_spec(spec: &swarf_tool::FamilySpec) -> Result<Self, SizeError> {
        use swarf_tool::FamilySpec as F;
        match *spec {
            F::Ball => Ok(Self::ball()),
            F::BallWithSide => Ok(Self::ball_with_side()),
            F::Flat => Ok(Self::flat()),
            F::Bull { corner_radius } => Self::bull(corner_radius),
            F::TaperBall { taper_deg } => Self::taper_ball(taper_deg),
            F::Apt {
                corner_radius,
                taper_deg,
                cone_deg,
            } => Self::apt(corner_radius, taper_deg, cone_deg),
        }
    }

    /// The tapered ball end mill with a taper in degrees.
    ///
    /// # Errors
    /// When the taper is out of `[0°, 90°)`.
    pub fn taper_ball(taper_deg: f64) -> Result<Self, SizeError> {
        Ok(CutterFamily::TaperBall {
            taper: angle("taper", taper_deg)?,
        })
    }

    /// Side taper θ in radians.
    pub fn taper(&self) -> f64 {
        match *self {
            CutterFamily::TaperBall { taper } | CutterFamily::Apt { taper, .. } => taper,
            CutterFamily::Sphere => 0.0,
        }
    }

    /// Half the nominal diameter of the cutter of size `size`: the ball radius, or for the APT
    /// family `R + r·cos θ`, the radius where the side meets the corner (swarf-tool's `d/2`;
    /// `R + r` for a bull-nose, `R` for a flat end mill).
    pub fn nominal_radius(&self, size: f64) -> f64 {
        match *self {
            CutterFamily::Sphere | CutterFamily::TaperBall { .. } => size,
            CutterFamily::Apt { corner, taper, .. } => size + corner * taper.cos(),
        }
    }

    /// How the cutter touches at this contact.
    pub fn regime(&self, c: &Contact, tol: &SizeTolerances) -> Regime {
        let n = c.normal;
        let nh = Vec3::new(n.x, n.y, 0.0);
        let sin_phi = nh.length();
        // Steeper than the side (tolerance: a flat end mill still finishes a vertical wall).
        if n.z < self.taper().sin() - tol.vertical {
            return Regime::Unreachable;
        }
        match *self {
            CutterFamily::Sphere | CutterFamily::TaperBall { .. } => Regime::Ball,
            CutterFamily::Apt { corner, cone, .. } => {
                if sin_phi <= tol.vertical || (cone > 0.0 && sin_phi <= cone.sin()) {
                    Regime::Bottom
                } else {
                    Regime::Corner {
                        q: c.point + corner * n,
                        u: nh / sin_phi,
                    }
                }
            }
        }
    }

    /// The cutter of size `size` placed tangent at the contact (`None` when unreachable).
    pub fn placed(&self, c: &Contact, regime: &Regime, size: f64) -> Option<PlacedCutter> {
        match (*self, *regime) {
            (CutterFamily::Sphere, Regime::Ball) => {
                let o = c.point + size * c.normal;
                Some(PlacedCutter {
                    axis: o,
                    corner_z: o.z,
                    big_r: 0.0,
                    r: size,
                    taper: 0.0,
                    cone: 0.0,
                    sphere_only: true,
                })
            }
            (CutterFamily::TaperBall { taper }, Regime::Ball) => {
                let o = c.point + size * c.normal;
                Some(PlacedCutter {
                    axis: o,
                    corner_z: o.z,
                    big_r: 0.0,
                    r: size,
                    taper,
                    cone: 0.0,
                    sphere_only: false,
                })
            }
            (
                CutterFamily::Apt {
                    corner,
                    taper,
                    cone,
                },
                Regime::Corner { q, u },
            ) => Some(PlacedCutter {
                axis: q + size * u,
                corner_z: q.z,
                big_r: size,
                r: corner,
                taper,
                cone,
                sphere_only: false,
            }),
            (
                CutterFamily::Apt {
                    corner,
                    taper,
                    cone,
                },
                Regime::Bottom,
            ) => Some(PlacedCutter {
                axis: c.point,
                corner_z: c.point.z + size * cone.tan() + corner / cone.cos(),
                big_r: size,
                r: corner,
                taper,
                cone,
                sphere_only: false,
            }),
            _ => None,
        }
    }

    /// The imaginary size of test point `p`: `inf { L ≥ 0 : p ∈ int K(L) }` (Liu §2.3.2–2.3.3),
    /// `0` when the smallest cutter already gouges `p` (or the contact is unreachable), `∞` when
    /// no size does.
    pub fn imaginary(&self, c: &Contact, regime: &Regime, p: Vec3, tol: &SizeTolerances) -> f64 {
        match (*self, *regime) {
            (_, Regime::Unreachable) => 0.0,
            (CutterFamily::Sphere, _) => imaginary_ball::sphere(c.point, c.normal, p),
            (CutterFamily::TaperBall { taper }, _) => {
                imaginary_taper_ball::imaginary(taper, c, p, tol)
            }
            (
                CutterFamily::Apt {
                    corner,
                    taper,
                    cone,
                },
                Regime::Corner { q, u },
            ) => imaginary_apt::corner(&AptTrig::new(taper, cone), corner, q, u, p, tol),
            (
                CutterFamily::Apt {
                    corner,
                    taper,
                    cone,
                },
                _,
            ) => imaginary_apt::bottom(self, &AptTrig::new(taper, cone), corner, cone, c, p, tol),
        }
    }
}

/// Principal curvatures (1/mm) at most this large count as zero under a flat bottom: a plane
/// moved by a rigid motion gets curvatures of the order of `1e-19` from round-off, and a radius
/// of curvature of `1e12` mm is far beyond any cutter (and beyond
/// [`CertifiedOptions::unbounded_above`](super::CertifiedOptions::unbounded_above)).
pub const FLAT_CURVATURE: f64 = 1e-12;

impl CutterFamily {
    /// The limit of the imaginary size as the test point approaches the CC point along the
    /// surface (the local gouge bound), from the principal curvatures: the largest size whose
    /// normal curvatures at the contact dominate the surface's in every direction. `∞` when the
    /// surface is not concave enough to matter, `0` when no size fits (unreachable, or a
    /// concave spot under a flat bottom, concave meaning `k1 >` [`FLAT_CURVATURE`]).
    pub fn local_bound(&self, c: &Contact, regime: &Regime) -> f64 {
        let Some(k) = c.curvature else {
            return f64::INFINITY;
        };
        match (*self, *regime) {
            (_, Regime::Unreachable) => 0.0,
            (CutterFamily::Sphere | CutterFamily::TaperBall { .. }, _) if k.k1 > 0.0 => 1.0 / k.k1,
            (CutterFamily::Sphere | CutterFamily::TaperBall { .. }, _) => f64::INFINITY,
            // Flat bottom: any concavity under it gouges; a conical tip is sharp.
            // (Concavity below `FLAT_CURVATURE` is the round-off of a plane: a rotated floor.)
            (CutterFamily::Apt { cone, .. }, Regime::Bottom)
                if cone == 0.0 && k.k1 > FLAT_CURVATURE =>
            {
                0.0
            }
            (CutterFamily::Apt { .. }, Regime::Bottom) => f64::INFINITY,
            (CutterFamily::Apt { corner, .. }, Regime::Corner { u, .. }) => {
                let n = c.normal;
                let sin_phi = Vec3::new(n.x, n.y, 0.0).length();
                // Principal directions of the corner torus at the contact.
                let tp = Vec3::Z.cross(u).normalize();
                let tm = n.cross(tp).normalize();
                let ii = |a: Vec3, b: Vec3| {
                    k.k1 * a.dot(k.dir1) * b.dot(k.dir1) + k.k2 * a.dot(k.dir2) * b.dot(k.dir2)
                };
                let (smm, smp, spp) = (ii(tm, tm), ii(tm, tp), ii(tp, tp));
                // Cutter: 1/r along the meridian, sin φ/(R + r sin φ) along the parallel;
                // II_cutter − II_surface must be positive semi-definite.
                let a = if corner > 0.0 {
                    1.0 / corner - smm
                } else {
                    f64::INFINITY
                };
                if a <= 0.0 {
                    return 0.0;
                }
                let kk = spp + if a.is_finite() { smp * smp / a } else { 0.0 };
                if kk <= 0.0 {
                    f64::INFINITY
                } else {
                    (sin_phi / kk - corner * sin_phi).max(0.0)
                }
            }
            _ => f64::INFINITY,
        }
    }

    /// The support function of the placed cutter `K(L)` in direction `ν`, relative to the CC
    /// point, as `max_k (α_k + β_k·L)`; `None` when it is infinite (the cutter's side reaches up
    /// without end, so only directions in the polar cone of the side bound it).
    #[cfg(test)]
    pub(crate) fn support(&self, c: &Contact, regime: &Regime, nu: Vec3) -> Option<Pieces> {
        FamilyTrig::new(*self).support(c, regime, nu)
    }
}

/// A family with the sines, cosines and tangents of its fixed angles computed once: the
/// certified solver asks these questions at every node (a few planes each, and the imaginary
/// size of every control point to choose them by), and libm calls would otherwise be most of
/// its time. The values are those `f64::sin` etc. give, so the answers are the same bit for bit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FamilyTrig {
    family: CutterFamily,
    /// The side taper's and bottom cone's trigonometry (cone 0 outside the APT family).
    apt: AptTrig,
}

impl FamilyTrig {
    pub(crate) fn new(family: CutterFamily) -> Self {
        let th = family.taper();
        let ps = match family {
            CutterFamily::Apt { cone, .. } => cone,
            _ => 0.0,
        };
        Self {
            family,
            apt: AptTrig::new(th, ps),
        }
    }

    /// `ν` moved into the polar cone of the cutter's side (`ν_z ≤ −tan θ·|ν_xy|`), where the
    /// support function is finite: the outward normal of the side lies on that cone's boundary
    /// and round-off would otherwise throw it out.
    pub(crate) fn in_polar_cone(&self, nu: Vec3) -> Vec3 {
        if self.family == CutterFamily::Sphere {
            return nu;
        }
        let h = Vec3::new(nu.x, nu.y, 0.0).length();
        let zmax = -self.apt.tan_t * h - 1e-12 * (h + nu.z.abs());
        Vec3::new(nu.x, nu.y, nu.z.min(zmax))
    }

    /// See [`CutterFamily::support`].
    pub(crate) fn support(&self, c: &Contact, regime: &Regime, nu: Vec3) -> Option<Pieces> {
        let nuh = Vec3::new(nu.x, nu.y, 0.0);
        let nuh_len = nuh.length();
        if self.family == CutterFamily::Sphere {
            // A ball of radius L centred at C + L n: bounded in every direction.
            let mut out = Pieces::new();
            out.push((0.0, 1.0 + c.normal.dot(nu)));
            return Some(out);
        }
        if self.apt.sin_t * nuh_len + self.apt.cos_t * nu.z > 0.0 {
            return None;
        }
        let n = c.normal;
        let mut out = Pieces::new();
        match (self.family, *regime) {
            (CutterFamily::TaperBall { .. }, _) => {
                // Cone with apex at C + L n, Minkowski ball of radius L.
                out.push((0.0, 1.0 + n.dot(nu)));
            }
            (CutterFamily::Apt { corner, cone, .. }, Regime::Corner { u, .. }) => {
                let r = corner;
                out.push((r * n.dot(nu) + r, u.dot(nuh) + nuh_len));
                if cone > 0.0 {
                    out.push((
                        r * n.dot(nu) - r / self.apt.cos_c * nu.z,
                        u.dot(nuh) - self.apt.tan_c * nu.z,
                    ));
                }
            }
            (CutterFamily::Apt { corner, cone, .. }, Regime::Bottom) => {
                let r = corner;
                out.push((
                    r / self.apt.cos_c * nu.z + r,
                    nuh_len + self.apt.tan_c * nu.z,
                ));
                if cone > 0.0 {
                    out.push((0.0, 0.0));
                }
            }
            _ => return None,
        }
        Some(out)
    }

    /// [`CutterFamily::imaginary`], with the APT family's closed forms (corner contact, and
    /// bottom contact under a flat bottom) evaluated here on the stored trigonometry: the same
    /// formulas as `imaginary_apt`, the same values. The solver only uses it to choose which
    /// planes to try (any plane gives a valid bound), never as the objective.
    pub(crate) fn imaginary(
        &self,
        c: &Contact,
        regime: &Regime,
        p: Vec3,
        tol: &SizeTolerances,
    ) -> f64 {
        match (self.family, *regime) {
            (CutterFamily::Apt { corner: r, .. }, Regime::Corner { q, u }) => {
                imaginary_apt::corner(&self.apt, r, q, u, p, tol)
            }
            (
                CutterFamily::Apt {
                    corner: r,
                    cone: 0.0,
                    ..
                },
                Regime::Bottom,
            ) => imaginary_apt::bottom(&self.family, &self.apt, r, 0.0, c, p, tol),
            _ => self.family.imaginary(c, regime, p, tol),
        }
    }

    /// The outward unit normal of the placed cutter `k` (of this family) at the point of its
    /// boundary nearest `p`: [`PlacedCutter::outward_normal`] on the stored trigonometry, the
    /// corner arc's normal clamped to its ends without angles. Only ever a direction to try a
    /// separating plane in (any direction gives a valid bound).
    pub(crate) fn outward_normal(&self, k: &PlacedCutter, p: Vec3) -> Vec3 {
        if k.sphere_only {
            return k.outward_normal(p);
        }
        let (rho, z, e) = k.meridian(p);
        let (_, n) = self.apt.closest_on_profile(k.big_r, k.r, Vec2::new(rho, z));
        (n.x * e + n.y * Vec3::Z).normalize()
    }
}

fn angle(what: &'static str, deg: f64) -> Result<f64, SizeError> {
    if (0.0..90.0).contains(&deg) {
        Ok(deg.to_radians())
    } else {
        Err(SizeError::Family {
            what,
            value: deg,
            range: "0° ≤ angle < 90°",
        })
    }
}

/// The largest `L ≥ 0` such that every point whose offset from the contact has `·ν ≥ m` is
/// outside `int K(L)` — a rigorous lower bound of the imaginary size over such points.
pub(crate) fn bound_from_support(pieces: &Pieces, m: f64) -> f64 {
    let mut lb = f64::INFINITY;
    for &(a, b) in pieces {
        if a > m {
            // Not separated even by the smallest cutter.
            return 0.0;
        }
        if b > 0.0 {
            lb = lb.min((m - a) / b);
        }
    }
    lb.max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reproducible uniform numbers in `[−1, 1)` (Knuth's MMIX generator).
    fn uniform(mut k: u64) -> impl FnMut() -> f64 {
        move || {
            k = k
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (k >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        }
    }

    /// A contact near the origin with its normal within about 40° of +z (exactly +z when
    /// `vertical`), and a test point up to 8 mm beside and 6 mm above or below it.
    fn contact_and_point(r: &mut impl FnMut() -> f64, vertical: bool) -> (Contact, Vec3) {
        let normal = if vertical {
            Vec3::Z
        } else {
            Vec3::new(0.6 * r(), 0.6 * r(), 1.0).normalize()
        };
        let c = Contact {
            point: Vec3::new(r(), r(), r()),
            normal,
            curvature: None,
        };
        let p = c.point + Vec3::new(8.0 * r(), 8.0 * r(), 6.0 * r());
        (c, p)
    }

    /// The solver's imaginary size on stored trigonometry is the family's, bit for bit.
    #[test]
    fn imaginary_on_stored_trigonometry_is_the_same() {
        let mut r = uniform(7);
        let fams = [
            CutterFamily::flat(),
            CutterFamily::bull(1.5).unwrap(),
            CutterFamily::apt(1.0, 4.0, 10.0).unwrap(),
            CutterFamily::apt(2.0, 12.0, 0.0).unwrap(),
        ];
        let tol = SizeTolerances::DEFAULT;
        for f in &fams {
            let ft = FamilyTrig::new(*f);
            for trial in 0..4000 {
                let (c, p) = contact_and_point(&mut r, trial % 10 == 0);
                let reg = f.regime(&c, &tol);
                let (a, b) = (
                    f.imaginary(&c, &reg, p, &tol),
                    ft.imaginary(&c, &reg, p, &tol),
                );
                assert!(
                    a == b || (a.is_nan() && b.is_nan()),
                    "{f:?} {reg:?}: {a} ≠ {b}"
                );
            }
        }
    }

    /// The separating-plane bound of a single point never exceeds its imaginary size, for any
    /// direction: the support functions are right.
    #[test]
    fn support_bound_is_below_the_imaginary_size() {
        let mut r = uniform(99);
        let fams = [
            CutterFamily::Sphere,
            CutterFamily::ball_with_side(),
            CutterFamily::taper_ball(7.0).unwrap(),
            CutterFamily::flat(),
            CutterFamily::bull(1.5).unwrap(),
            CutterFamily::apt(1.0, 4.0, 10.0).unwrap(),
            CutterFamily::apt(0.0, 0.0, 15.0).unwrap(),
        ];
        let tol = SizeTolerances::DEFAULT;
        for f in &fams {
            for trial in 0..4000 {
                let (c, p) = contact_and_point(&mut r, trial % 10 == 0);
                let reg = f.regime(&c, &tol);
                let l = f.imaginary(&c, &reg, p, &tol);
                let nu = Vec3::new(r(), r(), r()).normalize();
                if let Some(pieces) = f.support(&c, &reg, nu) {
                    let b = bound_from_support(&pieces, (p - c.point).dot(nu));
                    assert!(
                        b <= l * (1.0 + 1e-9) + 1e-9,
                        "{f:?} {reg:?}: bound {b} > size {l} at {p:?}, ν {nu:?}"
                    );
                }
            }
        }
    }
}
