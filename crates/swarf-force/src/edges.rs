//! A cutter's cutting edges as the force model sees them: its flutes, their helix, and the
//! axial discs and bottom rings of the engagement with each slab's profile integrals and helix
//! lag.
//!
//! # What a slab contributes
//! An edge element of profile length `ds` at radius `ρ` and axial immersion `κ` carries the
//! chip `h = c·n` (its `sin κ` and `cos κ` parts) and the directions of the radial and axial
//! forces (again `sin κ`, `cos κ`), and the torque arm `ρ`. Integrated over a slab, with the
//! immersion angle constant across it, the model needs exactly these integrals along the
//! profile ([`ProfileIntegrals`]): `∫ds`, `∫sin κ ds = Δz`, `∫cos κ ds = Δρ` (on a surface of
//! revolution the profile's tangent is `(cos κ, sin κ)`), `∫ρ ds`, `∫ρ sin κ ds = ∫ρ dz`,
//! `∫ρ cos κ ds`, `∫sin²κ ds`, `∫sin κ cos κ ds`, `∫cos²κ ds`. They are computed in closed form
//! per profile piece, for the part of it inside the slab: on a line (cylinder, cone, the flat
//! bottom) `κ` is constant and `ρ` linear; on an arc of centre `(a, z_c)` and radius `r`
//! (sphere: `a = 0`, torus: `a` > 0) at polar angle `θ = κ`, `ρ = a + r sin θ`, `ds = r dθ`,
//! so e.g. `∫sin²κ ds = r·[θ/2 − sin 2θ/4]` and `∫ρ sin κ ds = a·Δz + r²·[θ/2 − sin 2θ/4]`.
//! Taking `ρ` and `κ` at the slab's circle and the profile length as the chip width instead is
//! first order in the slab and wrong where the profile turns flat: the first disc of a ball
//! (`dz` = 0.1 mm, R = 5) is 1.0017 mm of profile with `sin κ` = 0.141 at its circle,
//! 0.1413 mm of `∫sin κ ds` for the exact 0.1 (41 % high).

use swarf_engage::{EngageOptions, Strip, StripKind};
use swarf_tool::{AnyPiece, Cutter, Piece};

use crate::ForceError;

/// One slab of the cutter surface (an axial disc, or a ring of a flat bottom), in the cutter
/// frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slab {
    /// Radius of the slab's circle, mm.
    pub rho: f64,
    /// Height of the circle above the tip, mm.
    pub z: f64,
    /// Axial immersion angle κ of the edge at the slab's circle, radians: the angle between
    /// the tool axis and the surface normal (90° on a cylinder, 0 on a flat bottom, the profile
    /// angle on a ball, torus or cone). The model uses [`Slab::integrals`], exact over the slab.
    pub kappa: f64,
    /// Profile length of the slab, mm (the chip width `db`; `integrals.len`).
    pub width: f64,
    /// The slab's integrals along its profile, which the model uses.
    pub integrals: ProfileIntegrals,
    /// Helix lag at the slab's two ends, radians (`tan i·∫dz/ρ`, growing with height).
    pub lag: (f64, f64),
    /// The slab's parameter range (height or radius), mm.
    pub range: (f64, f64),
}

/// The edges of one cutter, prepared for the force model.
#[derive(Clone, Debug)]
pub struct CutterEdges {
    /// Number of flutes (uniform pitch).
    pub flutes: u32,
    /// Helix angle, degrees.
    pub helix_deg: f64,
    /// Normal rake, degrees, when known.
    pub rake_deg: Option<f64>,
    side: Option<Strip>,
    bottom: Option<Strip>,
    /// The side's profile pieces (every non-horizontal piece of the cutting part).
    pieces: Vec<AnyPiece>,
    /// Radius of the flat bottom (0 without one).
    bottom_radius: f64,
}

/// Integrals over a stretch of the cutter's profile (see the module doc), mm and mm².
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ProfileIntegrals {
    /// `∫ds`, the profile length.
    pub len: f64,
    /// `∫sin κ ds` (the height gained).
    pub sin: f64,
    /// `∫cos κ ds` (the radius gained).
    pub cos: f64,
    /// `∫ρ ds`.
    pub rho: f64,
    /// `∫ρ sin κ ds`.
    pub rho_sin: f64,
    /// `∫ρ cos κ ds`.
    pub rho_cos: f64,
    /// `∫sin²κ ds`.
    pub sin2: f64,
    /// `∫sin κ cos κ ds`.
    pub sin_cos: f64,
    /// `∫cos²κ ds`.
    pub cos2: f64,
}

impl ProfileIntegrals {
    fn add(&mut self, o: ProfileIntegrals) {
        self.len += o.len;
        self.sin += o.sin;
        self.cos += o.cos;
        self.rho += o.rho;
        self.rho_sin += o.rho_sin;
        self.rho_cos += o.rho_cos;
        self.sin2 += o.sin2;
        self.sin_cos += o.sin_cos;
        self.cos2 += o.cos2;
    }

    /// The integrals along the straight profile from `(ρ0, z0)` to `(ρ1, z1)`: κ constant,
    /// `sin κ = Δz/L`, `cos κ = Δρ/L`, ρ linear.
    pub fn line(p0: (f64, f64), p1: (f64, f64)) -> Self {
        let (dr, dz) = (p1.0 - p0.0, p1.1 - p0.1);
        let len = dr.hypot(dz);
        if len <= 0.0 {
            return Self::default();
        }
        let mid = 0.5 * (p0.0 + p1.0);
        Self {
            len,
            sin: dz,
            cos: dr,
            rho: len * mid,
            rho_sin: dz * mid,
            rho_cos: dr * mid,
            sin2: dz * dz / len,
            sin_cos: dz * dr / len,
            cos2: dr * dr / len,
        }
    }

    /// The integrals along the arc of centre `(a, ·)` and radius `r` between polar angles
    /// `t0 < t1` (the profile point `(a + r sin θ, z_c − r cos θ)`, κ = θ, `ds = r dθ`).
    pub fn arc(a: f64, r: f64, t0: f64, t1: f64) -> Self {
        let br = |f: &dyn Fn(f64) -> f64| f(t1) - f(t0);
        let sin = r * br(&|t| -t.cos());
        let cos = r * br(&f64::sin);
        let sin2 = r * br(&|t| 0.5 * t - 0.25 * (2.0 * t).sin());
        let cos2 = r * br(&|t| 0.5 * t + 0.25 * (2.0 * t).sin());
        let sin_cos = r * br(&|t| 0.5 * t.sin() * t.sin());
        Self {
            len: r * (t1 - t0),
            sin,
            cos,
            rho: a * r * (t1 - t0) + r * sin,
            rho_sin: a * sin + r * sin2,
            rho_cos: a * cos + r * sin_cos,
            sin2,
            sin_cos,
            cos2,
        }
    }
}

impl CutterEdges {
    /// The edges of `cutter`, with the engagement's discs (`opts.dz_mm`). `label` names the
    /// tool in errors.
    ///
    /// # Errors
    /// A cutter whose flute count was not given (the model needs it; a default would be a
    /// silent guess).
    pub fn new(cutter: &Cutter, opts: &EngageOptions, label: &str) -> Result<Self, ForceError> {
        Self::with_default_flutes(cutter, opts, label, None, None)
    }

    /// [`CutterEdges::new`], with `default_flutes` for a cutter that states no flute count
    /// (the user's own value for tools whose library cannot hold one: a LinuxCNC `.tbl`);
    /// `number` is the tool's number, for the error.
    ///
    /// # Errors
    /// A cutter whose flute count was not given, and no default.
    pub fn with_default_flutes(
        cutter: &Cutter,
        opts: &EngageOptions,
        label: &str,
        number: Option<u32>,
        default_flutes: Option<u32>,
    ) -> Result<Self, ForceError> {
        let flutes =
            cutter
                .flutes_given()
                .or(default_flutes)
                .ok_or_else(|| ForceError::NoFlutes {
                    tool: label.to_string(),
                    number,
                })?;
        let pieces = cutter
            .pieces()
            .iter()
            .filter(|p| !p.is_horizontal())
            .cloned()
            .collect();
        let bottom_radius = cutter
            .pieces()
            .iter()
            .find_map(|p| match p {
                AnyPiece::Disc(d) if !d.facing_up && d.outer > 0.0 => Some(d.outer),
                _ => None,
            })
            .unwrap_or(0.0);
        Ok(Self {
            flutes,
            helix_deg: cutter.helix_deg(),
            rake_deg: cutter.rake_deg(),
            side: Strip::side(cutter, opts.dz_mm),
            bottom: Strip::bottom(cutter, opts.dz_mm),
            pieces,
            bottom_radius,
        })
    }

    /// The integrals over the side's profile between heights `a < b` (clamped to the side),
    /// in closed form per piece.
    pub fn side_integrals(&self, a: f64, b: f64) -> ProfileIntegrals {
        let mut out = ProfileIntegrals::default();
        for p in &self.pieces {
            let (z0, z1) = p.z_range();
            let (lo, hi) = (a.max(z0), b.min(z1));
            if hi <= lo {
                continue;
            }
            out.add(piece_integrals(p, lo, hi));
        }
        out
    }

    /// The integrals over the flat bottom between radii `a < b` (clamped to the bottom).
    pub fn bottom_integrals(&self, a: f64, b: f64) -> ProfileIntegrals {
        let (lo, hi) = (a.max(0.0), b.min(self.bottom_radius));
        if hi <= lo {
            return ProfileIntegrals::default();
        }
        ProfileIntegrals::line((lo, 0.0), (hi, 0.0))
    }

    /// `slab` (of kind `kind`) cut down (or grown) to the parameter range `[a, b]` within its
    /// neighbours: its integrals exact over `[a, b]`, its lag scaled linearly (exact on
    /// cylinders and cones).
    pub fn clipped(&self, kind: StripKind, slab: &Slab, a: f64, b: f64) -> Slab {
        let (lo, hi) = slab.range;
        let len = hi - lo;
        if len <= 0.0 || b <= a {
            return Slab {
                width: 0.0,
                integrals: ProfileIntegrals::default(),
                ..*slab
            };
        }
        let at = |x: f64| slab.lag.0 + (slab.lag.1 - slab.lag.0) * (x - lo) / len;
        let integrals = match kind {
            StripKind::Side => self.side_integrals(a, b),
            StripKind::Bottom => self.bottom_integrals(a, b),
        };
        Slab {
            width: integrals.len,
            integrals,
            lag: (at(a), at(b)),
            range: (a, b),
            ..*slab
        }
    }

    /// The slab of the disc (`kind` side) or ring (bottom) reported at parameter `at`.
    pub fn slab(&self, kind: StripKind, at: f64) -> Option<Slab> {
        let strip = match kind {
            StripKind::Side => self.side.as_ref()?,
            StripKind::Bottom => self.bottom.as_ref()?,
        };
        let k = strip.circle_at(at)?;
        if !strip.is_reported(k) {
            return None;
        }
        let c = strip.circles[k];
        let tan_i = self.helix_deg.to_radians().tan();
        let (t0, t1) = strip.slab_turn[k];
        let range = strip.slab[k];
        let integrals = match kind {
            StripKind::Side => self.side_integrals(range.0, range.1),
            StripKind::Bottom => self.bottom_integrals(range.0, range.1),
        };
        Some(Slab {
            rho: c.rho,
            z: c.z,
            kappa: c.normal.x.atan2(-c.normal.y),
            width: integrals.len,
            integrals,
            lag: (tan_i * t0, tan_i * t1),
            range,
        })
    }
}

/// The integrals of side piece `p` between heights `lo < hi` within its range.
fn piece_integrals(p: &AnyPiece, lo: f64, hi: f64) -> ProfileIntegrals {
    // Polar angle on an arc of centre height `zc` and radius `r` at height z (z = zc − r cos θ).
    let theta = |zc: f64, r: f64, z: f64| ((zc - z) / r).clamp(-1.0, 1.0).acos();
    match p {
        AnyPiece::Sphere(s) => ProfileIntegrals::arc(
            0.0,
            s.radius,
            theta(s.center_z, s.radius, lo),
            theta(s.center_z, s.radius, hi),
        ),
        AnyPiece::Torus(t) => ProfileIntegrals::arc(
            t.major,
            t.minor,
            theta(t.center_z, t.minor, lo),
            theta(t.center_z, t.minor, hi),
        ),
        AnyPiece::Cylinder(c) => ProfileIntegrals::line((c.radius, lo), (c.radius, hi)),
        AnyPiece::Cone(c) => {
            let rho = |z: f64| {
                c.bottom.x + (c.top.x - c.bottom.x) * (z - c.bottom.y) / (c.top.y - c.bottom.y)
            };
            ProfileIntegrals::line((rho(lo), lo), (rho(hi), hi))
        }
        // Horizontal: no side.
        AnyPiece::Disc(_) => ProfileIntegrals::default(),
    }
}
