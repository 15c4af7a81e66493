//! Where a chained move can change a line: the front of the start instance, swept.
//!
//! # Why
//! In a program the moves are chained: a move starts where the last one ended, with the same
//! tool and axis, so its start instance `K` has already been cut. Most lines crossing a short
//! move's sweep `S = K ⊕ [0, v]` then meet it only where `K` was: their material is not
//! changed, and a cheap test that proves it saves the exact query.
//!
//! # The region (re-derived here)
//! Let `x ∈ S \ K` (a point the move can add to what is cut). Then `x = y + t·v` with `y ∈ K`,
//! `t ∈ (0, 1]`. The segment from `y` to `x` runs along `v` from inside `K` to outside, so it
//! leaves `K` at a point `q = x − s·v` (`s ∈ (0, t]`) where `v` points out of `K`: some outward
//! normal `n` of `K` at `q` has `n·v > 0` (a convex set's tangent cone is the polar of its normal
//! cone). Call those points the **front** `F`. So `S \ K ⊆ F ⊕ [0, 1]·v`: a line that misses
//! the front swept along the move meets `S` only inside `K`, and if `K` holds no material the
//! move removes nothing from it.
//!
//! # A half-space holding the front
//! Write the move as `v = a·x̂ + b·ẑ` in the move frame (`ẑ` the tool axis, `x̂` the move's part
//! across it, `a ≥ 0`) and a point of the profile's side at radius `ρ` and polar angle `φ`
//! (`φ = 0`: normal straight down the axis) as `q = tip + z·ẑ + ρ·r̂`. Its normal is
//! `n = sin φ·r̂ − cos φ·ẑ`, so `n·v = sin φ·a·(r̂·x̂) − cos φ·b`, and on the front
//! `a·(r̂·x̂) > b·cot φ`. Hence `(q − tip)·(a·x̂) = ρ·a·(r̂·x̂) ≥ −ρ·min(a, −b·cot φ)`: every
//! front point of an element lies in the half-space `(q − tip)·N ≥ −K` with `N = a·x̂` and
//! `K = sup ρ·min(a, −b·cot φ)` over the element (a disc, `sin φ = 0`, is front as a whole
//! when `cos φ·b < 0`, with `K = ρ_max·a`). Moving along `v` only increases `(q − tip)·N`, so
//! the swept front of the element lies in that half-space and in the element's swept box.
//!
//! `sup ρ·min(a, −b·cot φ) ≤ min(ρ_max·a, sup ρ·(−b·cot φ))`. On an arc
//! (`ρ = e + r·sin φ`), `ρ·cot φ = e·cot φ + r·cos φ` decreases in `φ`, so the second supremum
//! is at the arc's first angle when `b < 0` and at its last when `b > 0` (infinite where an
//! arc off the axis reaches `φ = 0` or `π`, where the first term bounds it). On a straight side
//! `φ` is constant and `ρ` runs between its ends. For a ball moving level (`b = 0`) the front
//! is the half-space ahead of the tip: half the lines across the tool need no query.
//!
//! The test is conservative: a line it rejects cannot be changed by the move (given `K` cut);
//! one it passes is queried exactly as before.

use super::profile::Element;
use super::SweptConvex;
use smallvec::SmallVec;
use swarf_geom::math::Vec3;
use swarf_geom::Aabb;

/// The front of a sweep's start instance, swept along the move (module documentation): for
/// each element of the profile with a front, the bound `K` of its half-space and the box of
/// the element's sweep.
#[derive(Clone, Debug)]
pub struct Front {
    /// `N`: the move's part across the tool axis, workpiece frame.
    n: Vec3,
    /// The tip at the start.
    tip: Vec3,
    /// Per element with a front: `K` (mm², with a rounding margin) and its swept box.
    units: SmallVec<[(f64, Aabb); 8]>,
}

/// The part of a [`Front`] that a block of parallel rays can meet: a ray through cross
/// coordinates `(cu, cv)` can be changed by the move only when [`FrontBlock::reaches`].
#[derive(Clone, Copy, Debug)]
pub struct FrontBlock {
    nu: f64,
    nv: f64,
    base: f64,
}

impl FrontBlock {
    /// Whether the ray through `(cu, cv)` can meet the swept front.
    #[inline]
    pub fn reaches(&self, cu: f64, cv: f64) -> bool {
        cu * self.nu + cv * self.nv >= self.base
    }
}

/// Margin on the half-space (mm): rays this close to its boundary are queried.
const FRONT_MARGIN_MM: f64 = 1e-9;

impl Front {
    /// The front of `sweep`'s start instance.
    pub(crate) fn of(sweep: &SweptConvex<'_>) -> Front {
        let (a, b) = (sweep.v.x, sweep.v.z);
        let n = sweep.frame.vector_to_world(Vec3::new(a, 0.0, 0.0));
        let margin = FRONT_MARGIN_MM * (a + b.abs());
        let mut units = SmallVec::new();
        for unit in sweep.units.iter().filter(|u| !u.joint) {
            if let Some(k) = element_bound(&sweep.prof.elements()[unit.index], a, b) {
                units.push((k + margin, unit.bbox));
            }
        }
        Front {
            n,
            tip: sweep.frame.origin,
            units,
        }
    }

    /// What the rays along world axis `k` whose cross coordinates lie within `half` of
    /// `centre`'s, and whose material lies within `material` along `k`, can meet of the swept
    /// front; `None` when none of them can (the move cannot change them).
    pub fn block(
        &self,
        k: usize,
        centre: Vec3,
        half: f64,
        material: (f64, f64),
    ) -> Option<FrontBlock> {
        let (u, w) = ((k + 1) % 3, (k + 2) % 3);
        let mut threshold = f64::NEG_INFINITY;
        for (bound, bb) in &self.units {
            let (lo, hi) = (bb.min[k].max(material.0), bb.max[k].min(material.1));
            if lo > hi
                || bb.max[u] < centre[u] - half
                || bb.min[u] > centre[u] + half
                || bb.max[w] < centre[w] - half
                || bb.min[w] > centre[w] + half
            {
                continue;
            }
            // The most the ray's own coordinate can add to (q − tip)·N over the unit.
            let along = ((lo - self.tip[k]) * self.n[k]).max((hi - self.tip[k]) * self.n[k]);
            threshold = threshold.max(bound + along);
        }
        if threshold == f64::NEG_INFINITY {
            return None;
        }
        let block = FrontBlock {
            nu: self.n[u],
            nv: self.n[w],
            base: self.tip[u] * self.n[u] + self.tip[w] * self.n[w] - threshold,
        };
        let best =
            centre[u] * block.nu + centre[w] * block.nv + half * (block.nu.abs() + block.nv.abs());
        (best >= block.base).then_some(block)
    }
}

/// `K` of the element (module documentation) for the move `(a, 0, b)`; `None` when the
/// element has no front.
fn element_bound(el: &Element, a: f64, b: f64) -> Option<f64> {
    match *el {
        Element::Line { p, q } => {
            let t = q - p;
            let (rho_min, rho_max) = (p.x.min(q.x), p.x.max(q.x));
            if t.y.abs() <= 1e-12 * t.length() {
                // A disc: front as a whole when the move leaves it (bottom down, top up).
                let leaves = (t.x > 0.0 && b < 0.0) || (t.x < 0.0 && b > 0.0);
                return leaves.then_some(rho_max * a);
            }
            if t.y < 0.0 {
                // Not met in a convex profile; the universal bound.
                return Some(rho_max * a);
            }
            let c = a.min(-b * t.x / t.y);
            Some(if c >= 0.0 { rho_max * c } else { rho_min * c })
        }
        Element::Arc {
            e, r, phi0, phi1, ..
        } => {
            let rho_max =
                if phi0 <= std::f64::consts::FRAC_PI_2 && phi1 >= std::f64::consts::FRAC_PI_2 {
                    e + r
                } else {
                    e + r * phi0.sin().max(phi1.sin())
                };
            let cap = rho_max * a;
            // ρ·cot φ at an end of the arc (infinite off the axis at φ = 0 or π).
            let rho_cot = |phi: f64| {
                let s = phi.sin();
                if s <= 1e-12 {
                    if e > 0.0 {
                        f64::INFINITY * phi.cos().signum()
                    } else {
                        r * phi.cos()
                    }
                } else {
                    e * phi.cos() / s + r * phi.cos()
                }
            };
            let along = if b < 0.0 {
                -b * rho_cot(phi0)
            } else if b > 0.0 {
                -b * rho_cot(phi1)
            } else {
                0.0
            };
            Some(cap.min(along))
        }
    }
}
