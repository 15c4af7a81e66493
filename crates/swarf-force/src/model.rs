//! The mechanistic milling model at one cutter location: elemental forces on every engaged
//! slab, integrated along the helical edges and summed over the flutes, as curves over one
//! spindle revolution and as exact means.
//!
//! # The elemental forces
//! At a point of an edge at immersion `φ` on a slab of radius `ρ` and axial immersion `κ`, with
//! feed per tooth vector `c` (tool frame), the uncut chip thickness is the feed per tooth along
//! the outward surface normal `n = (sin κ sin φ, sin κ cos φ, −cos κ)`:
//!
//! ```text
//! h = c·n = c_x sin κ sin φ + c_y sin κ cos φ − c_z cos κ   (= c sin φ sin κ for a feed along x_L)
//! dF_t = K_tc h db + K_te db,  dF_r = K_rc h db + K_re db,  dF_a = K_ac h db + K_ae db
//! ```
//!
//! with `db` the element's profile length (the chip width; edge coefficients are per unit chip
//! width, as the mechanistic tests calibrate them). On the tool, in the tool frame:
//!
//! ```text
//! F = dF_t (−cos φ, sin φ, 0) + dF_r (−sin κ sin φ, −sin κ cos φ, cos κ)
//!   + dF_a (cos κ sin φ, cos κ cos φ, sin κ)
//! ```
//!
//! which on a cylinder (κ = 90°) is `Fx = −Ft cos φ − Fr sin φ, Fy = Ft sin φ − Fr cos φ, Fz =
//! Fa` (../shared/data/forces/REFERENCE.md), and the spindle torque is `ρ·dF_t`. Over a slab the
//! products of `h`, the directions and `ρ` are integrated along the profile — `∫ρ sin κ ds`,
//! `∫sin²κ ds` and the like, in closed form per piece ([`crate::edges`]) — not taken at the
//! slab's circle: where a ball or torus turns flat near the tip, `sin κ` changes by its own size
//! across one disc.
//!
//! # Along the edge and over a revolution
//! Flute `m` of `N` at spindle angle `θ` crosses a slab from immersion `θ + 2πm/N − ψ(lo)` at its
//! bottom to `θ + 2πm/N − ψ(hi)` at its top, `ψ = tan i·∫dz/ρ` the helix lag
//! ([`crate::edges`]), taken linear within a slab (exact on cylinders and cones). Every force
//! component is a combination of `1, sin φ, cos φ, sin²φ, sin φ cos φ, cos²φ` with constant
//! weights on a slab, so the force of a flute on a slab is the closed-form integral of those
//! over the part of its angular span inside the slab's engaged intervals, divided by the span
//! (a point value when the span is zero: no helix, or a flat bottom); the weights are already
//! integrated along the slab's profile. The mean over a revolution does not depend on the lag:
//! `N/2π · ∫_slab ∫_engaged f(φ) dφ ds`, exact.
//!
//! Everything is linear in the six coefficients, and the shear part linear in the feed per
//! tooth, so a location is evaluated once per coefficient ([`UnitForces`]) and any material
//! and feed are a weighted sum of those ([`UnitForces::combine`]) — which is what the feed
//! scheduling needs.

use std::f64::consts::{PI, TAU};

use swarf_engage::{CircleEngagement, Engagement, StripKind};
use swarf_geom::math::Vec3;
use swarf_path::SpindleDir;

use crate::edges::{CutterEdges, Slab};

/// The outputs per sample: force x, y, z in the tool frame (N) and torque (N·m).
pub const OUTPUTS: usize = 4;
/// The coefficients in model order `ktc, krc, kac, kte, kre, kae`.
pub const COEFFS: usize = 6;
const BASIS: usize = 6;

/// A location's forces per unit coefficient, at unit feed per tooth: `curves[k][o][j]` is output
/// `o` at sample `j` of a revolution with coefficient `k` = 1 (the others 0) and a feed per tooth
/// of 1 mm; `means[k][o]` the exact mean over a revolution.
#[derive(Clone, Debug, Default)]
pub struct UnitForces {
    /// Samples per revolution.
    pub samples: usize,
    /// Samples that repeat: the curves have period `samples / flutes` when that divides.
    pub period: usize,
    /// `[coefficient][output][sample]`, flattened; only the first `period` samples are stored.
    curves: Vec<f64>,
    /// `[coefficient][output]`.
    pub means: [[f64; OUTPUTS]; COEFFS],
    /// Mean uncut chip thickness per mm of feed per tooth over the engaged edges (0 when none).
    pub chip_per_feed: f64,
    /// True when any slab is engaged.
    pub engaged: bool,
}

/// Forces at one location for a material and a feed per tooth, tool frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ForceCurves {
    /// Samples per revolution (the curves hold one period, see [`UnitForces::period`]).
    pub samples: usize,
    /// Fx, Fy, Fz (N) and torque (N·m) per sample of one period.
    pub values: [Vec<f64>; OUTPUTS],
    /// Exact means over a revolution.
    pub means: [f64; OUTPUTS],
}

impl ForceCurves {
    /// Largest |component| per output over the revolution.
    pub fn peaks(&self) -> [f64; OUTPUTS] {
        let mut p = [0.0; OUTPUTS];
        for (o, v) in self.values.iter().enumerate() {
            p[o] = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        }
        p
    }

    /// Largest resultant `|F|` over the revolution, N.
    pub fn peak_resultant(&self) -> f64 {
        let [x, y, z, _] = &self.values;
        x.iter()
            .zip(y)
            .zip(z)
            .map(|((a, b), c)| (a * a + b * b + c * c).sqrt())
            .fold(0.0, f64::max)
    }

    /// Output `o` at sample `j` of the full revolution.
    pub fn at(&self, o: usize, j: usize) -> f64 {
        let v = &self.values[o];
        v[j % v.len().max(1)]
    }
}

impl UnitForces {
    fn idx(&self, k: usize, o: usize, j: usize) -> usize {
        (k * OUTPUTS + o) * self.period + j
    }

    /// The forces for coefficients `coef` (model order) and feed per tooth `c` mm: shear terms
    /// scale with `c`, edge terms do not.
    pub fn combine(&self, coef: [f64; COEFFS], c: f64) -> ForceCurves {
        let w: [f64; COEFFS] = std::array::from_fn(|k| if k < 3 { coef[k] * c } else { coef[k] });
        let mut values: [Vec<f64>; OUTPUTS] = std::array::from_fn(|_| vec![0.0; self.period]);
        let mut means = [0.0; OUTPUTS];
        for (k, &wk) in w.iter().enumerate() {
            if wk == 0.0 {
                continue;
            }
            for (o, vals) in values.iter_mut().enumerate() {
                means[o] += wk * self.means[k][o];
                let base = self.idx(k, o, 0);
                for (v, u) in vals.iter_mut().zip(&self.curves[base..base + self.period]) {
                    *v += wk * u;
                }
            }
        }
        ForceCurves {
            samples: self.samples,
            values,
            means,
        }
    }
}

/// A slab's engaged angles and weights, ready for sampling.
struct SlabLoad {
    /// `[coefficient][output][basis]` weights per unit angle (integrated over the slab).
    w: [[[f64; BASIS]; OUTPUTS]; COEFFS],
    lag: (f64, f64),
    /// Engaged intervals, radians, start in `[0, 2π)`.
    intervals: Vec<(f64, f64)>,
}

/// Antiderivatives of the basis `1, sin, cos, sin², sin·cos, cos²`.
#[inline]
fn antiderivative(phi: f64) -> [f64; BASIS] {
    let (s, c) = phi.sin_cos();
    let s2 = 2.0 * s * c;
    [
        phi,
        -c,
        s,
        0.5 * phi - 0.25 * s2,
        0.5 * s * s,
        0.5 * phi + 0.25 * s2,
    ]
}

#[inline]
fn basis(phi: f64) -> [f64; BASIS] {
    let (s, c) = phi.sin_cos();
    [1.0, s, c, s * s, s * c, c * c]
}

/// `∫ basis` over `[a, b] ∩ (intervals + 2πℤ)`.
fn integrate_span(intervals: &[(f64, f64)], a: f64, b: f64) -> [f64; BASIS] {
    let mut out = [0.0; BASIS];
    for &(s, e) in intervals {
        let k0 = ((a - e) / TAU).ceil() as i64;
        let k1 = ((b - s) / TAU).floor() as i64;
        for k in k0..=k1 {
            let shift = k as f64 * TAU;
            let (lo, hi) = (a.max(s + shift), b.min(e + shift));
            if hi > lo {
                let (g1, g0) = (antiderivative(hi), antiderivative(lo));
                for q in 0..BASIS {
                    out[q] += g1[q] - g0[q];
                }
            }
        }
    }
    out
}

/// True when `phi` lies in one of the intervals (periodically).
fn inside(intervals: &[(f64, f64)], phi: f64) -> bool {
    let p = phi.rem_euclid(TAU);
    intervals
        .iter()
        .any(|&(s, e)| (p >= s && p <= e) || (p + TAU >= s && p + TAU <= e))
}

/// Linear combination of `1, sin φ, cos φ` times `1`, `sin φ` or `cos φ`, in the basis.
fn times(l: [f64; 3], by: usize) -> [f64; BASIS] {
    match by {
        0 => [l[0], l[1], l[2], 0.0, 0.0, 0.0],
        1 => [0.0, l[0], 0.0, l[1], l[2], 0.0],
        _ => [0.0, 0.0, l[0], 0.0, l[1], l[2]],
    }
}

fn add(acc: &mut [f64; BASIS], v: [f64; BASIS], f: f64) {
    for q in 0..BASIS {
        acc[q] += f * v[q];
    }
}

impl SlabLoad {
    /// Weights of a slab with unit feed per tooth along `feed` (tool frame): every term
    /// integrated along the slab's profile ([`crate::edges::ProfileIntegrals`]), exact for the
    /// model whatever the slab's curvature.
    fn new(slab: &Slab, feed: Vec3, intervals: Vec<(f64, f64)>) -> Self {
        let q = &slab.integrals;
        // `∫ g·h ds` as [1, sin φ, cos φ] for a profile factor g: h = −c_z cos κ + c_x sin κ
        // sin φ + c_y sin κ cos φ, so only `∫g cos κ ds` and `∫g sin κ ds` enter.
        let h = |g_cos: f64, g_sin: f64| [-feed.z * g_cos, feed.x * g_sin, feed.y * g_sin];
        let mut w = [[[0.0; BASIS]; OUTPUTS]; COEFFS];
        for (k, wk) in w.iter_mut().enumerate() {
            // The coefficient's elemental force: shear ones carry h, edge ones 1, each with the
            // profile factor of its direction (1, sin κ, cos κ or ρ) integrated along the slab.
            let shear = k < 3;
            let one = if shear {
                h(q.cos, q.sin)
            } else {
                [q.len, 0.0, 0.0]
            };
            let by_sin = if shear {
                h(q.sin_cos, q.sin2)
            } else {
                [q.sin, 0.0, 0.0]
            };
            let by_cos = if shear {
                h(q.cos2, q.sin_cos)
            } else {
                [q.cos, 0.0, 0.0]
            };
            let by_rho = if shear {
                h(q.rho_cos, q.rho_sin)
            } else {
                [q.rho, 0.0, 0.0]
            };
            match k % 3 {
                0 => {
                    // Tangential: (−cos φ, sin φ, 0), torque ρ/1000.
                    add(&mut wk[0], times(one, 2), -1.0);
                    add(&mut wk[1], times(one, 1), 1.0);
                    add(&mut wk[3], times(by_rho, 0), 1e-3);
                }
                1 => {
                    // Radial: (−sin κ sin φ, −sin κ cos φ, cos κ).
                    add(&mut wk[0], times(by_sin, 1), -1.0);
                    add(&mut wk[1], times(by_sin, 2), -1.0);
                    add(&mut wk[2], times(by_cos, 0), 1.0);
                }
                _ => {
                    // Axial: (cos κ sin φ, cos κ cos φ, sin κ).
                    add(&mut wk[0], times(by_cos, 1), 1.0);
                    add(&mut wk[1], times(by_cos, 2), 1.0);
                    add(&mut wk[2], times(by_sin, 0), 1.0);
                }
            }
        }
        Self {
            w,
            lag: slab.lag,
            intervals,
        }
    }
}

/// The slabs engaged at `e`, with their engaged intervals (radians), the side's lowest and
/// highest engaged slabs stretched or cut to the engagement's interpolated axial extent. With
/// `mirror`, each interval is mirrored, φ → π − φ (see [`unit_forces`]).
fn engaged_slabs(
    e: &Engagement,
    edges: &CutterEdges,
    mirror: bool,
) -> Vec<(Slab, Vec<(f64, f64)>)> {
    let to_rad = |c: &CircleEngagement| -> Vec<(f64, f64)> {
        c.intervals
            .iter()
            .map(|iv| {
                let (s, len) = (iv.start_deg.to_radians(), iv.len_deg().to_radians());
                if mirror {
                    (
                        (PI - s - len).rem_euclid(TAU),
                        (PI - s - len).rem_euclid(TAU) + len,
                    )
                } else {
                    (s, s + len)
                }
            })
            .collect()
    };
    let mut out = Vec::with_capacity(e.discs.len() + e.bottom.len());
    let n = e.discs.len();
    for (i, d) in e.discs.iter().enumerate() {
        let Some(mut slab) = edges.slab(StripKind::Side, d.at_mm) else {
            continue;
        };
        if let Some((lo, hi)) = e.side_extent_mm {
            let (mut a, mut b) = slab.range;
            // The extent lies between this disc and its neighbour: the slab ends there.
            if i == 0 && lo.is_finite() {
                a = lo.clamp(slab.range.0 - 0.5 * (slab.range.1 - slab.range.0), slab.z);
            }
            if i + 1 == n && hi.is_finite() {
                b = hi.clamp(slab.z, slab.range.1 + 0.5 * (slab.range.1 - slab.range.0));
            }
            slab = edges.clipped(StripKind::Side, &slab, a.max(0.0), b);
        }
        out.push((slab, to_rad(d)));
    }
    for r in &e.bottom {
        if let Some(slab) = edges.slab(StripKind::Bottom, r.at_mm) {
            out.push((slab, to_rad(r)));
        }
    }
    out
}

/// The forces at engagement `e` per unit coefficient and unit feed per tooth, at `samples`
/// spindle angles over a revolution.
///
/// # Spindle direction
/// The model is written for a clockwise spindle (M3: φ, measured clockwise from `+y_L`, grows
/// as an edge turns). A counter-clockwise cutter (M4) is the mirror image, across the plane of
/// `x_L` and `z_L`, of a clockwise one: the mirror `(x, y, z) → (x, −y, z)` takes the point at
/// φ, `ρ(sin φ, cos φ)`, to `ρ(sin φ, −cos φ)`, the point at `π − φ`, turns the rotation
/// clockwise, and keeps the feed's x and z parts (its y part changes sign). So an M4 location
/// is computed as the clockwise cutter on the mirrored engagement (intervals `[a, b] →
/// [π − b, π − a]`, feed `c_y → −c_y`), and its force mapped back through the mirror: `F_y`
/// changes sign, `F_x` and `F_z` do not, and the torque about `z_L`, an axial vector, changes
/// sign too (`τ = r × F` under a reflection `M` is `det M · M τ`): the power `τ·ω` stays
/// positive, as ω does too. The curves are those of the mirrored cutter's spindle angle (their
/// phase is arbitrary anyway).
pub fn unit_forces(e: &Engagement, edges: &CutterEdges, samples: usize) -> UnitForces {
    let mirror = e.spindle_dir == SpindleDir::CounterClockwise;
    let samples = samples.max(1);
    let flutes = edges.flutes.max(1) as usize;
    let period = if samples % flutes == 0 {
        samples / flutes
    } else {
        samples
    };
    let mut u = UnitForces {
        samples,
        period,
        curves: vec![0.0; COEFFS * OUTPUTS * period],
        ..Default::default()
    };
    // Feed per tooth direction in the tool frame, per mm of tip feed, at a slab's height.
    let y_sign = if mirror { -1.0 } else { 1.0 };
    let frame = |v: Vec3| Vec3::new(v.dot(e.x_l), y_sign * v.dot(e.y_l), v.dot(e.axis));
    let pitch = TAU / flutes as f64;
    let mut chip = 0.0;
    let mut engaged_len = 0.0;
    for (slab, intervals) in engaged_slabs(e, edges, mirror) {
        if slab.width <= 0.0 || intervals.is_empty() {
            continue;
        }
        u.engaged = true;
        let f = frame(e.tip_direction + e.axis_rate.cross(e.axis * slab.z));
        let load = SlabLoad::new(&slab, f, intervals);
        // Exact mean: N/2π ∫ over the engaged angles.
        let full = integrate_span(&load.intervals, 0.0, TAU);
        for k in 0..COEFFS {
            for o in 0..OUTPUTS {
                let m: f64 = (0..BASIS).map(|q| load.w[k][o][q] * full[q]).sum();
                u.means[k][o] += flutes as f64 / TAU * m;
            }
        }
        // Mean chip: h weights (coefficient ktc, tangential, torque-free) → use h directly.
        let q = &slab.integrals;
        chip += -f.z * q.cos * full[0] + f.x * q.sin * full[1] + f.y * q.sin * full[2];
        engaged_len += q.len * full[0];
        let dlag = load.lag.1 - load.lag.0;
        for j in 0..period {
            let theta = TAU * j as f64 / samples as f64;
            let mut b = [0.0; BASIS];
            for m in 0..flutes {
                let base = theta + pitch * m as f64;
                if dlag.abs() > 1e-12 {
                    let (p0, p1) = (base - load.lag.0, base - load.lag.1);
                    let (a, z) = if p0 < p1 { (p0, p1) } else { (p1, p0) };
                    let i = integrate_span(&load.intervals, a, z);
                    add(&mut b, i, 1.0 / dlag.abs());
                } else {
                    let phi = base - load.lag.0;
                    if inside(&load.intervals, phi) {
                        add(&mut b, basis(phi), 1.0);
                    }
                }
            }
            if b.iter().all(|&x| x == 0.0) {
                continue;
            }
            for k in 0..COEFFS {
                for o in 0..OUTPUTS {
                    let val: f64 = (0..BASIS).map(|q| load.w[k][o][q] * b[q]).sum();
                    let i = u.idx(k, o, j);
                    u.curves[i] += val;
                }
            }
        }
    }
    if mirror {
        // Back through the mirror: F_y and the torque change sign.
        for k in 0..COEFFS {
            for o in [1, 3] {
                u.means[k][o] = -u.means[k][o];
                let i = u.idx(k, o, 0);
                for v in &mut u.curves[i..i + period] {
                    *v = -*v;
                }
            }
        }
    }
    u.chip_per_feed = if engaged_len > 0.0 {
        (chip / engaged_len).max(0.0)
    } else {
        0.0
    };
    u
}
