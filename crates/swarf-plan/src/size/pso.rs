//! The thesis's hybrid global optimiser (Liu ch. 3): a particle swarm over each patch's
//! parameter box, then a Nelder–Mead polish (argmin) from the swarm's best point.
//!
//! The swarm uses the standard update (the thesis's eqs. 3.1/3.3 are garbled, see ERRATA):
//! `v ← w·v + c₂·r₁·(p_best − x) + c₃·r₂·(g_best − x)`, `x ← clamp(x + v)`, with the inertia
//! `w` decreasing linearly over the rounds from the top to the bottom of its range, and
//! `r₁, r₂` uniform in `[0, 1)` per coordinate from a seeded SplitMix64 stream, so every run is
//! reproducible. argmin's own particle swarm keeps a constant inertia and does not expose the
//! iteration at which the best was found (which the thesis's study reports), hence the swarm
//! here; the local step is argmin's Nelder–Mead.
//!
//! There is no certificate: [`AllowableSize::gap`] is `NaN`.

use std::cell::Cell;

use super::{
    classify, AllowableSize, Contact, CutterFamily, Limit, Regime, SizeError, SizeTolerances,
};
use argmin::core::{CostFunction, Executor, State};
use argmin::solver::neldermead::NelderMead;
use swarf_surface::{CompoundSurface, ParamBox, ParametricSurface};

/// Options of the hybrid solver, defaulting to the thesis's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PsoOptions {
    /// Rounds (iterations) of the swarm, `N_R`. Default 30.
    pub rounds: usize,
    /// Particles, `N_P`. Default 64.
    pub particles: usize,
    /// Inertia range `[w_min, w_max]`. Default `[0.1, 0.2]`.
    pub inertia: [f64; 2],
    /// Cognitive factor `c₂`. Default 0.5.
    pub cognitive: f64,
    /// Social factor `c₃`. Default 0.5.
    pub social: f64,
    /// Seed of the random stream. Default 1.
    pub seed: u64,
    /// Nelder–Mead iterations after the swarm (0: none). Default 100.
    pub local_iters: u64,
    /// As [`super::CertifiedOptions::neighbourhood`]. Default `1e-3` mm.
    pub neighbourhood: f64,
    /// As [`super::CertifiedOptions::gouge_radius`]. Default `1e-2` mm.
    pub gouge_radius: f64,
    /// Tolerances of the imaginary-size model.
    pub model: SizeTolerances,
}

impl PsoOptions {
    /// The thesis's settings.
    pub const DEFAULT: PsoOptions = PsoOptions {
        rounds: 30,
        particles: 64,
        inertia: [0.1, 0.2],
        cognitive: 0.5,
        social: 0.5,
        seed: 1,
        local_iters: 100,
        neighbourhood: 1e-3,
        gouge_radius: 1e-2,
        model: SizeTolerances::DEFAULT,
    };

    /// With another seed.
    pub fn with_seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }

    /// Checks the ranges.
    ///
    /// # Errors
    /// When a count is 0 or a factor is negative or not finite.
    pub fn validate(&self) -> Result<(), SizeError> {
        if self.rounds == 0 || self.particles == 0 {
            return Err(SizeError::Option {
                what: "rounds/particles",
                value: 0.0,
                range: "≥ 1",
            });
        }
        for (what, v) in [
            ("inertia min", self.inertia[0]),
            ("inertia max", self.inertia[1]),
            ("cognitive", self.cognitive),
            ("social", self.social),
        ] {
            if !(v >= 0.0 && v.is_finite()) {
                return Err(SizeError::Option {
                    what,
                    value: v,
                    range: "finite, ≥ 0",
                });
            }
        }
        Ok(())
    }
}

impl Default for PsoOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// A small, seeded, reproducible random stream (SplitMix64).
#[derive(Clone, Debug)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// A stream from a seed.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }
    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in `[0, 1)`.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The outcome of one swarm run.
#[derive(Clone, Debug, PartialEq)]
pub struct SwarmRun {
    /// Best parameters found.
    pub best_uv: (f64, f64),
    /// Best objective value.
    pub best: f64,
    /// The round (1-based) in which the best value was first reached.
    pub best_round: usize,
    /// Objective evaluations.
    pub evaluations: u64,
    /// The swarm's best value after each round.
    pub history: Vec<f64>,
}

impl SwarmRun {
    /// The first round (1-based) after which the swarm's best was within `tol` of its final
    /// value: the thesis's "iterations" to converge.
    pub fn converged_round(&self, tol: f64) -> usize {
        self.history
            .iter()
            .position(|&v| v <= self.best + tol)
            .map_or(self.history.len(), |k| k + 1)
    }
}

/// Minimise `f` over the box with the swarm of `opts` (no local step).
pub fn particle_swarm(
    mut f: impl FnMut(f64, f64) -> f64,
    dom: ParamBox,
    opts: &PsoOptions,
    seed: u64,
) -> SwarmRun {
    let mut rng = SplitMix64::new(seed);
    let (su, sv) = dom.span();
    let n = opts.particles;
    let mut x: Vec<[f64; 2]> = (0..n)
        .map(|_| {
            [
                dom.u[0] + su * rng.next_f64(),
                dom.v[0] + sv * rng.next_f64(),
            ]
        })
        .collect();
    let mut vel: Vec<[f64; 2]> = (0..n)
        .map(|_| {
            [
                0.2 * su * (rng.next_f64() - 0.5),
                0.2 * sv * (rng.next_f64() - 0.5),
            ]
        })
        .collect();
    let mut evals = 0u64;
    let mut fx: Vec<f64> = x
        .iter()
        .map(|p| {
            evals += 1;
            f(p[0], p[1])
        })
        .collect();
    let mut pbest = x.clone();
    let mut pbest_f = fx.clone();
    let (mut g, mut gf) = (x[0], fx[0]);
    for (p, &v) in x.iter().zip(&fx) {
        if v < gf {
            (g, gf) = (*p, v);
        }
    }
    let mut best_round = 1;
    let mut history = Vec::with_capacity(opts.rounds);
    let span = [su, sv];
    for round in 0..opts.rounds {
        let s = if opts.rounds > 1 {
            round as f64 / (opts.rounds - 1) as f64
        } else {
            0.0
        };
        let w = opts.inertia[1] + s * (opts.inertia[0] - opts.inertia[1]);
        for k in 0..n {
            for d in 0..2 {
                let (r1, r2) = (rng.next_f64(), rng.next_f64());
                let v = w * vel[k][d]
                    + opts.cognitive * r1 * (pbest[k][d] - x[k][d])
                    + opts.social * r2 * (g[d] - x[k][d]);
                vel[k][d] = v.clamp(-span[d], span[d]);
            }
            x[k] = [
                (x[k][0] + vel[k][0]).clamp(dom.u[0], dom.u[1]),
                (x[k][1] + vel[k][1]).clamp(dom.v[0], dom.v[1]),
            ];
            evals += 1;
            fx[k] = f(x[k][0], x[k][1]);
            if fx[k] < pbest_f[k] {
                pbest_f[k] = fx[k];
                pbest[k] = x[k];
            }
            if fx[k] < gf {
                (g, gf) = (x[k], fx[k]);
                best_round = round + 1;
            }
        }
        history.push(gf);
    }
    SwarmRun {
        best_uv: (g[0], g[1]),
        best: gf,
        best_round,
        evaluations: evals,
        history,
    }
}

/// Large finite stand-in for `∞` inside Nelder–Mead (which needs finite differences of costs).
const NM_INFINITY: f64 = 1e300;

struct NmCost<'a, F: Fn(f64, f64) -> f64> {
    f: &'a F,
    dom: ParamBox,
    count: &'a Cell<u64>,
}

impl<F: Fn(f64, f64) -> f64> CostFunction for NmCost<'_, F> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, x: &Self::Param) -> Result<f64, argmin::core::Error> {
        self.count.set(self.count.get() + 1);
        let (u, v) = self.dom.clamp(x[0], x[1]);
        Ok((self.f)(u, v).min(NM_INFINITY))
    }
}

/// Nelder–Mead from `start`, within `dom`: the best `(u, v, value)` and the evaluations.
pub fn nelder_mead(
    f: &impl Fn(f64, f64) -> f64,
    dom: ParamBox,
    start: (f64, f64),
    iters: u64,
) -> ((f64, f64, f64), u64) {
    let count = Cell::new(0);
    let (su, sv) = dom.span();
    // A simplex of 1 % of the box, pointing inwards at the upper edges.
    let step = |s: f64, hi: f64, x: f64| {
        let d = 0.01 * s;
        if x + d <= hi {
            x + d
        } else {
            x - d
        }
    };
    let (u0, v0) = start;
    let simplex = vec![
        vec![u0, v0],
        vec![step(su, dom.u[1], u0), v0],
        vec![u0, step(sv, dom.v[1], v0)],
    ];
    let f0 = f(u0, v0);
    count.set(1);
    let mut best = (u0, v0, f0);
    if iters == 0 {
        return (best, 1);
    }
    let cost = NmCost {
        f,
        dom,
        count: &count,
    };
    if let Ok(solver) = NelderMead::new(simplex).with_sd_tolerance(1e-14) {
        if let Ok(res) = Executor::new(cost, solver)
            .configure(|s| s.max_iters(iters))
            .run()
        {
            let st = res.state();
            if let Some(p) = st.get_best_param() {
                let (u, v) = dom.clamp(p[0], p[1]);
                let val = f(u, v);
                count.set(count.get() + 1);
                if val < best.2 {
                    best = (u, v, val);
                }
            }
        }
    }
    (best, count.get())
}

/// The allowable size at one contact by the hybrid method: a swarm per patch, Nelder–Mead
/// from the best, the minimum over patches and the curvature bound.
pub fn allowable_pso(
    surface: &CompoundSurface,
    family: &CutterFamily,
    c: &Contact,
    opts: &PsoOptions,
) -> AllowableSize {
    let regime = family.regime(c, &opts.model);
    if regime == Regime::Unreachable {
        return AllowableSize::unreachable(c.point, false);
    }
    let local = family.local_bound(c, &regime);
    let (mut best, mut best_point, mut is_local) = (local, c.point, true);
    let mut evaluations = 0;
    for (k, patch) in surface.patches.iter().enumerate() {
        let dom = patch.surface.domain();
        let f = |u: f64, v: f64| {
            // Points off a trimmed patch are not on the part: they limit nothing.
            if !patch.on_part(u, v) {
                return f64::INFINITY;
            }
            let p = patch.surface.point(u, v);
            if (p - c.point).length() < opts.neighbourhood {
                f64::INFINITY
            } else {
                family.imaginary(c, &regime, p, &opts.model)
            }
        };
        let seed = opts.seed ^ (k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        let run = particle_swarm(f, dom, opts, seed);
        evaluations += run.evaluations;
        let ((u, v, val), n) = nelder_mead(&f, dom, run.best_uv, opts.local_iters);
        evaluations += n;
        let (u, v, val) = if run.best < val {
            (run.best_uv.0, run.best_uv.1, run.best)
        } else {
            (u, v, val)
        };
        if val < best {
            best = val;
            best_point = patch.surface.point(u, v);
            is_local = false;
        }
    }
    let limit = best.is_finite().then(|| {
        if is_local {
            Limit::Gouge
        } else {
            classify(c.point, best_point, opts.gouge_radius)
        }
    });
    AllowableSize {
        size: best,
        limit,
        limit_point: best.is_finite().then_some(best_point),
        gap: f64::NAN,
        certified: false,
        evaluations,
        nodes: 0,
    }
}
