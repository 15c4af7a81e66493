//! A cheap proof that the material on a ray misses a sweep, before the exact interval is
//! computed (the general candidates cost hundreds of nanoseconds a ray; a torus band's more).
//!
//! # Why it holds
//! The sweep `S = K ⊕ [0, δ]` of a convex solid of revolution `K` (tip `T`, unit axis `a`)
//! moved by `δ` with its axis fixed is convex, with support function
//! `h_S(n) = h_K(n) + max(0, n·δ)` (`h_K` from `distance.rs`, exact). So every plane
//! `n·x = h_S(n)` bounds a half-space holding `S`, and a segment `X` of a ray misses `S` when
//! `min_{x ∈ X} n·x > h_S(n)` — over a segment that minimum is at one of its ends. Any `n`
//! gives a valid proof; its choice only decides how often the proof succeeds. The outward
//! direction at the point of `K` (placed at the middle of the move) nearest to the end of `X`
//! nearer the sweep makes it tight to second order: it fails only for material within about `κ·|δ|²` of the
//! sweep (`κ` its curvature there), which the exact query then settles.
//!
//! Finding that direction costs a signed distance, as much as a cheap exact query; but the
//! plane that separated one ray usually separates its neighbours too. So the last few planes
//! that worked for a family's rays against one sweep are kept ([`Planes`], in the per-thread
//! scratch, under a number that identifies the sweep's `DexelRays`) and tried first: two dot
//! products a ray while they hold. Where no plane is found the material meets the sweep, and
//! so will its neighbours' mostly: the search is then tried on a few rays only.
//!
//! A proof is accepted only with a margin ([`SEPARATION_MARGIN_MM`]) above the exact query's
//! own acceptance of candidates just outside `S` (`BAND_EPS`) and above rounding: a ray it
//! skips is one the exact query would have left unchanged.

use super::{DexelRays, Interval, RaysKind, Scratch, SweptConvex};
use std::sync::atomic::{AtomicU64, Ordering};
use swarf_geom::math::Vec3;

/// Least separation (mm) between a sweep and a ray's material for the ray to be skipped: ten
/// times `BAND_EPS`, far above the rounding of the support values at workpiece scale.
pub(crate) const SEPARATION_MARGIN_MM: f64 = 10.0 * super::BAND_EPS;

/// Planes kept per thread.
const KEPT: usize = 4;

/// Failed searches for a new plane after which the search is tried only on every
/// `RETRY_EVERY`-th ray, until one succeeds.
const FREE_TRIES: u32 = 2;
const RETRY_EVERY: u32 = 8;

/// The planes `n·x = h` (each holding the sweep on its side `n·x ≤ h`) that last separated
/// rays from the sweep of one `DexelRays`, `owner`.
#[derive(Clone, Debug, Default)]
pub(crate) struct Planes {
    owner: u64,
    planes: [(Vec3, f64); KEPT],
    len: usize,
    next: usize,
    /// Rays since a new plane was last found (the search is then tried less often).
    misses: u32,
}

/// Numbers handed to `DexelRays` (0 is never handed out: an empty `Planes` belongs to none).
static OWNERS: AtomicU64 = AtomicU64::new(1);

impl Planes {
    /// A number no `DexelRays` of this process had before.
    pub(crate) fn new_owner() -> u64 {
        OWNERS.fetch_add(1, Ordering::Relaxed)
    }

    /// Whether a kept plane of `owner` (another owner's are forgotten) leaves the segment
    /// from `p0` along world axis `k` by `len` beyond it; the latest kept is tried first.
    fn separate(&mut self, owner: u64, p0: Vec3, k: usize, len: f64) -> bool {
        if self.owner != owner {
            (self.owner, self.len, self.next, self.misses) = (owner, 0, 0, 0);
            return false;
        }
        (1..=self.len).any(|back| {
            let plane = self.planes[(self.next + KEPT - back) % KEPT];
            beyond(plane, p0, k, len)
        })
    }

    /// Keeps `plane` (the oldest goes when full).
    fn keep(&mut self, plane: (Vec3, f64)) {
        self.planes[self.next] = plane;
        self.next = (self.next + 1) % KEPT;
        self.len = (self.len + 1).min(KEPT);
        self.misses = 0;
    }

    /// Whether a kept plane of `owner` leaves the box `lo..hi` beyond it (by the margin).
    fn separate_box(&self, owner: u64, lo: Vec3, hi: Vec3) -> bool {
        if self.owner != owner || !(lo.cmple(hi).all()) {
            return false;
        }
        let (centre, ext) = (0.5 * (lo + hi), 0.5 * (hi - lo));
        self.planes[..self.len]
            .iter()
            .any(|&(n, h)| n.dot(centre) - n.abs().dot(ext) - h > SEPARATION_MARGIN_MM)
    }

    /// Whether to look for a new plane for this ray. Where the search keeps failing the rays
    /// meet the sweep (most of them change): it is then tried on every
    /// [`RETRY_EVERY`]-th ray only, as the rays may leave the sweep again. (Speed only: a ray
    /// not tried gets the exact query.)
    fn try_search(&mut self) -> bool {
        self.misses = self.misses.saturating_add(1);
        self.misses <= FREE_TRIES || self.misses % RETRY_EVERY == 0
    }
}

/// True when the segment from `p0` along world axis `k` by `len ≥ 0` lies beyond the plane
/// `(n, h)` by the margin (its lower end along `n` is `n·p0`, or `n·p0 + n_k·len`).
#[inline]
fn beyond((n, h): (Vec3, f64), p0: Vec3, k: usize, len: f64) -> bool {
    n.dot(p0) + (n[k] * len).min(0.0) - h > SEPARATION_MARGIN_MM
}

impl SweptConvex<'_> {
    /// True when a plane kept for the rays of `rays` (in `scratch`, from earlier rays of the
    /// family) separates the box `lo..hi` from the sweep: no ray's material inside the box can
    /// meet it (a whole tile of rays skipped by one test). Never for closed-form rays.
    pub fn box_clear(&self, lo: Vec3, hi: Vec3, rays: &DexelRays, scratch: &Scratch) -> bool {
        match &rays.0 {
            RaysKind::General(_, owner) => scratch.planes.separate_box(*owner, lo, hi),
            RaysKind::Fast(_) | RaysKind::Instance(_) | RaysKind::Tilted(_) => false,
        }
    }

    /// True when no material of the dexel `d` along world axis `k` through `origin` (whose
    /// coordinate `k` is ignored) within the range `(lo, hi)` can meet the sweep. `owner`
    /// identifies the `DexelRays` the query came with (its kept planes are this sweep's).
    pub(crate) fn misses_material(
        &self,
        origin: Vec3,
        k: usize,
        d: &[Interval],
        (lo, hi): (f64, f64),
        owner: u64,
        scratch: &mut Scratch,
    ) -> bool {
        let at = |t: f64| {
            let mut p = origin;
            p[k] = t;
            p
        };
        for iv in d.iter().filter(|iv| iv.enter < hi && iv.exit > lo) {
            let (t0, t1) = (iv.enter.max(lo), iv.exit.min(hi));
            let p0 = at(t0);
            if scratch.planes.separate(owner, p0, k, t1 - t0) {
                continue;
            }
            let p1 = at(t1);
            if !scratch.planes.try_search() {
                return false;
            }
            match self.separating_plane(p0, p1, k) {
                Some(plane) => scratch.planes.keep(plane),
                None => return false,
            }
        }
        true
    }

    /// A plane holding the sweep on one side and the segment from `p0` to `p1` (along world
    /// axis `k`) beyond it by the margin, from the outward direction at the point of the tool
    /// (at the middle of the move) nearest to the segment's end nearer the sweep's middle;
    /// `None` when that plane does not separate them (the material usually meets the sweep
    /// then: one signed distance is all a ray that changes pays).
    fn separating_plane(&self, p0: Vec3, p1: Vec3, k: usize) -> Option<(Vec3, f64)> {
        let tip = self.frame.origin;
        let axis = self.frame.z;
        let delta = self.frame.vector_to_world(self.v);
        let mid = tip + 0.5 * delta;
        let centre = 0.5 * (self.bbox.min[k] + self.bbox.max[k]);
        let p = if (p0[k] - centre).abs() <= (p1[k] - centre).abs() {
            p0
        } else {
            p1
        };
        let sd = self.prof.signed_distance(mid, axis, p);
        if sd.distance <= 0.0 {
            return None;
        }
        let n = sd.normal;
        let plane = (n, self.prof.support(tip, axis, n) + n.dot(delta).max(0.0));
        beyond(plane, p0, k, p1[k] - p0[k]).then_some(plane)
    }
}
