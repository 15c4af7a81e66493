//! The 5-axis lead and tilt angles that maximise the allowable size at a CC point, within the
//! machine's limits (the thesis's future work, ch. 6).
//!
//! # The local frame
//! At a CC point with unit normal `n` (towards the cutter) and parametric tangent `S_u`:
//!
//! * `f` (feed) = `S_u` projected onto the tangent plane, normalised — the direction of travel
//!   along an iso-`v` tool path;
//! * `s` (side) = `n × f`, so that `(f, s, n)` is right-handed.
//!
//! The tool axis at lead `λ` and tilt `τ` is
//!
//! ```text
//! a(λ, τ) = cos τ · (cos λ · n + sin λ · f) + sin τ · s
//! ```
//!
//! i.e. `n` turned by `λ` about `−s` (towards the feed: **positive lead leans the tool's top
//! forward**, along `f`), then by `τ` about `f` (positive tilt leans it towards `s`). The
//! admissible set is `|λ| ≤ LEAD_MAX`, `|τ| ≤ TILT_MAX`; with both limits `0` the tool axis is the
//! normal. The 3-axis axis `+Z` has lead `atan2(Z·f, Z·n)` and tilt `asin(Z·s)`; when those lie
//! within the limits, `+Z` is also tried, so the optimum is never worse than the 3-axis size
//! there.
//!
//! # The search and its tolerance
//! The allowable size for each axis is the certified solve in the tool frame
//! ([`super::orient4::allowable_along`]). Over `(λ, τ)` it is not continuous (reachability and
//! placement switches), so the 2-D search is documented, not certified in the angles:
//!
//! 1. the `+Z` seed when admissible, the normal (`λ = τ = 0`), then a coarse grid of
//!    [`Axis5Options::grid`] × `grid` angles spanning the box (one value on an axis whose limit
//!    is 0); a later candidate replaces the best only when it gains more than the certificate's
//!    tolerance, so ties keep the 3-axis axis, else the normal;
//! 2. from the best [`Axis5Options::refine`] grid points, a compass (pattern) search clamped to
//!    the box: try `±h` on each angle, move on an improvement larger than the certificate's
//!    tolerance, halve `h` otherwise, from half the
//!    grid spacing down to [`Axis5Options::tol_deg`]. Deterministic: same input, same output.
//!
//! Candidates whose cheap upper bound cannot beat the best are skipped, as in 4-axis
//! ([`super::orient4`], *Pruning*). The result is the best size met (exact and certified at its
//! angles).

use swarf_geom::math::Vec3;

use super::orient4::{allowable_in_frame, axis_rotation, quick_upper_bound, Best};
use super::{AllowableSize, CertifiedOptions, Contact, CutterFamily, PreparedSurface, SizeError};

/// The lead/tilt frame at a CC point (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LeadTiltFrame {
    /// Unit normal, towards the cutter.
    pub normal: Vec3,
    /// Unit feed direction (`S_u` in the tangent plane).
    pub feed: Vec3,
    /// `normal × feed`.
    pub side: Vec3,
}

impl LeadTiltFrame {
    /// The frame from the normal and `S_u`; `None` when `S_u` is (nearly) along the normal or
    /// zero.
    pub fn new(normal: Vec3, su: Vec3) -> Option<Self> {
        let n = normal.normalize();
        let t = su - su.dot(n) * n;
        let len = t.length();
        if len.is_nan() || len <= 1e-12 * su.length() || !n.is_finite() {
            return None;
        }
        let feed = t / len;
        Some(Self {
            normal: n,
            feed,
            side: n.cross(feed),
        })
    }

    /// The tool axis at lead and tilt (degrees).
    pub fn axis(&self, lead_deg: f64, tilt_deg: f64) -> Vec3 {
        let (sl, cl) = lead_deg.to_radians().sin_cos();
        let (st, ct) = tilt_deg.to_radians().sin_cos();
        ct * (cl * self.normal + sl * self.feed) + st * self.side
    }

    /// Lead and tilt (degrees) of a unit axis `a`.
    pub fn angles_of(&self, a: Vec3) -> (f64, f64) {
        let tilt = a.dot(self.side).clamp(-1.0, 1.0).asin();
        let lead = a.dot(self.feed).atan2(a.dot(self.normal));
        (lead.to_degrees(), tilt.to_degrees())
    }
}

/// Options of the 5-axis search (builder style, documented defaults).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axis5Options {
    /// Largest lead, degrees (`|λ| ≤`). Default `15°`.
    pub lead_max_deg: f64,
    /// Largest tilt, degrees (`|τ| ≤`). Default `15°`.
    pub tilt_max_deg: f64,
    /// Coarse grid points per angle. Default `5`.
    pub grid: usize,
    /// Best grid points refined by the pattern search. Default `2`.
    pub refine: usize,
    /// Final pattern-search step, degrees. Default `1e-3°`.
    pub tol_deg: f64,
    /// Options of the certified solver run at each axis.
    pub certified: CertifiedOptions,
}

impl Axis5Options {
    /// The documented defaults.
    pub const DEFAULT: Axis5Options = Axis5Options {
        lead_max_deg: 15.0,
        tilt_max_deg: 15.0,
        grid: 5,
        refine: 2,
        tol_deg: 1e-3,
        certified: CertifiedOptions::DEFAULT,
    };

    /// With other machine limits, degrees.
    pub fn with_limits(mut self, lead_max_deg: f64, tilt_max_deg: f64) -> Self {
        self.lead_max_deg = lead_max_deg;
        self.tilt_max_deg = tilt_max_deg;
        self
    }

    /// Checks the ranges.
    ///
    /// # Errors
    /// When a limit is outside `[0°, 90°)`, the grid below 2, the tolerance not positive, or
    /// the solver options are invalid.
    pub fn validate(&self) -> Result<(), SizeError> {
        for (what, v) in [
            ("lead_max_deg", self.lead_max_deg),
            ("tilt_max_deg", self.tilt_max_deg),
        ] {
            if !(0.0..90.0).contains(&v) {
                return Err(SizeError::Option {
                    what,
                    value: v,
                    range: "[0, 90)",
                });
            }
        }
        if self.grid < 2 {
            return Err(SizeError::Option {
                what: "grid",
                value: self.grid as f64,
                range: "≥ 2",
            });
        }
        if !(self.tol_deg > 0.0 && self.tol_deg.is_finite()) {
            return Err(SizeError::Option {
                what: "tol_deg",
                value: self.tol_deg,
                range: "> 0",
            });
        }
        self.certified.validate()
    }
}

impl Default for Axis5Options {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// The best 5-axis orientation at a CC point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orientation5 {
    /// Lead, degrees.
    pub lead_deg: f64,
    /// Tilt, degrees.
    pub tilt_deg: f64,
    /// The tool axis, part frame.
    pub axis: Vec3,
    /// The allowable size there (limit point in the part frame); `evaluations` and `nodes` are
    /// the totals over all solves.
    pub size: AllowableSize,
    /// Certified solves spent.
    pub solves: u32,
    /// Candidates skipped without a solve (their cheap upper bound could not beat the best;
    /// see [`super::orient4`]).
    pub pruned: u32,
}

/// The lead and tilt within the limits that maximise the allowable size at `c` (module docs).
///
/// # Panics
/// When the options are invalid ([`Axis5Options::validate`]).
pub fn best_lead_tilt(
    prep: &PreparedSurface,
    family: &CutterFamily,
    c: &Contact,
    frame: &LeadTiltFrame,
    opts: &Axis5Options,
) -> Orientation5 {
    opts.validate().expect("valid 5-axis options");
    let (lm, tm) = (opts.lead_max_deg, opts.tilt_max_deg);
    let solve_axis = |a: Vec3| {
        allowable_in_frame(
            prep,
            family,
            c,
            axis_rotation(a.normalize()),
            &opts.certified,
        )
    };
    let solve = |(l, t): (f64, f64)| solve_axis(frame.axis(l, t));
    let bound = |(l, t): (f64, f64)| {
        let q = axis_rotation(frame.axis(l, t).normalize());
        quick_upper_bound(prep, family, c, q, &opts.certified)
    };
    let ticks = |max: f64| -> Vec<f64> {
        if max == 0.0 {
            vec![0.0]
        } else {
            let k = opts.grid;
            (0..k)
                .map(|i| -max + 2.0 * max * i as f64 / (k - 1) as f64)
                .collect()
        }
    };
    let mut candidates: Vec<(f64, f64)> = Vec::new();
    // The 3-axis seed first, when admissible.
    let (lz, tz) = frame.angles_of(Vec3::Z);
    let z_ok = lz.abs() <= lm && tz.abs() <= tm;
    if z_ok {
        candidates.push((lz, tz));
    }
    // Then the normal (ties keep the earlier candidate), then the grid.
    candidates.push((0.0, 0.0));
    for l in ticks(lm) {
        for t in ticks(tm) {
            if (l, t) != (0.0, 0.0) {
                candidates.push((l, t));
            }
        }
    }
    let mut best: Option<Best<(f64, f64)>> = None;
    let mut samples: Vec<((f64, f64), f64)> = Vec::new();
    for (k, at) in candidates.into_iter().enumerate() {
        // The 3-axis seed is solved with the axis exactly +Z (no rotation round-off).
        let solve_at = || {
            if k == 0 && z_ok {
                solve_axis(Vec3::Z)
            } else {
                solve(at)
            }
        };
        let s = match best.as_mut() {
            None => {
                let a = solve_at();
                best = Some(Best::new(at, a, &opts.certified));
                a.size
            }
            Some(b) => b.offer_bounded(at, bound(at), solve_at),
        };
        samples.push((at, s));
        if s.is_infinite() {
            break;
        }
    }
    let mut best = best.expect("at least one candidate");
    let h0 = 0.5
        * (2.0 * lm.max(tm) / (opts.grid - 1) as f64)
            .max(opts.tol_deg)
            .min(45.0);
    if best.size.size.is_finite() && (lm > 0.0 || tm > 0.0) {
        samples.sort_by(|x, y| y.1.total_cmp(&x.1));
        let seeds: Vec<((f64, f64), f64)> = samples
            .into_iter()
            .filter(|(_, s)| *s > 0.0)
            .take(opts.refine)
            .collect();
        for (seed, f_seed) in seeds {
            let (mut x, mut fx) = (seed, f_seed);
            let mut h = h0;
            while h >= opts.tol_deg && fx.is_finite() {
                let mut moved = false;
                for (dl, dt) in [(h, 0.0), (-h, 0.0), (0.0, h), (0.0, -h)] {
                    let y = (
                        (x.0 + dl * (lm > 0.0) as u8 as f64).clamp(-lm, lm),
                        (x.1 + dt * (tm > 0.0) as u8 as f64).clamp(-tm, tm),
                    );
                    if y == x {
                        continue;
                    }
                    let fy = best.offer_bounded(y, bound(y), || solve(y));
                    // A move needs a real gain (not round-off on a plateau).
                    if fy > fx + best.gain(fx) {
                        x = y;
                        fx = fy;
                        moved = true;
                        break;
                    }
                }
                if !moved {
                    h *= 0.5;
                }
            }
            if best.size.size.is_infinite() {
                break;
            }
        }
    }
    Orientation5 {
        lead_deg: best.at.0,
        tilt_deg: best.at.1,
        axis: frame.axis(best.at.0, best.at.1),
        size: best.totals(),
        solves: best.solves,
        pruned: best.pruned,
    }
}
