//! The certified allowable size: best-first branch-and-bound over rational Bézier sub-patches.
//!
//! # The certificate
//! Every node is a rational Bézier sub-patch, contained in the convex hull of its control
//! points. For a node the solver computes a **rigorous lower bound** of the imaginary size of
//! every point of that hull, from two arguments:
//!
//! 1. *Separating planes.* The family is nested (`K(L) ⊂ K(L')` for `L < L'`) and each `K(L)`
//!    is convex with a support function affine in `L` piece by piece
//!    ([`CutterFamily`]'s `support`). If `min_i (P_i − C)·ν ≥ h_{K(L)}(ν) − C·ν` for a direction
//!    `ν`, the plane separates the hull from `int K(L)`; solving for `L` gives a bound. Any `ν`
//!    gives a valid bound; the solver tries `−n`, `−z` and the cutter's outward normal at the
//!    node's centroid (which makes the bound converge quadratically under subdivision), and for
//!    a bull-nose, where a node can still be pruned, the outward normal of the cutter of the
//!    node's least control-point size (or the best size, if smaller) at that control point, then
//!    at the hull point that stops that plane. The choice of directions only decides how tight
//!    the bound is, never whether it is valid.
//! 2. *Bernstein positivity* (ball family). A point is outside the ball of radius `L` tangent
//!    at `C` iff `q_L = |S − C|² − 2L·n·(S − C) ≥ 0`. Multiplied by `w²`, `q_L` is a polynomial
//!    of degree `(2p, 2q)` on the node, `A − 2L·B`, whose Bernstein coefficients follow from the
//!    control net; if all of `A_k − 2L·B_k` are ≥ 0 so is `q_L`. This bound is exact where the
//!    surface *is* a sphere (a concave spherical pocket, where every test point ties), which no
//!    hull-based bound can certify. The ball's cylinder lies above the plane
//!    `z = C_z + L·(n_z − sin θ)`, so a node below it only meets the sphere.
//!
//! The solver keeps the best imaginary size found at control-net corners (which are surface
//! points) and the curvature bound at `C`, and expands the node of lowest bound until that
//! bound is within the tolerance of the best value. Then no surface point outside the excluded
//! neighbourhood of `C` (a ball of [`CertifiedOptions::neighbourhood`] where the imaginary size
//! tends to the curvature bound, which is used there instead) can have an imaginary size below
//! `size − gap`: that `gap` is the certificate. When the node budget runs out first, the result
//! says so (`certified = false`) and the gap is still a valid bound.
//!
//! # Trimmed patches
//! A trimmed patch enters as its pieces that reach the part ([`swarf_surface::Trim`]; see the bezier
//! module): the bounds of a piece the trim boundary crosses are those of its whole net (a
//! superset, so still valid), only corners on the part are candidates, and such a piece is cut
//! along the boundary where the boundary follows a parameter line (halving it would keep the
//! boundary inside a half at every level), otherwise halved as usual, its halves classified
//! again. A crossing piece smaller than the trim's resolution counts as on the part, so the
//! certificate holds for the part grown by that resolution in parameters (conservative).
//!
//! # Check geometry
//! Triangles of a check mesh ([`PreparedSurface::with_check_mesh`]) are nodes like any other:
//! each is a degenerate bilinear piece whose control points' hull is the triangle, so the same
//! bounds hold for it and for the two triangles it is bisected into through an edge midpoint
//! (the edge along which the bound varies most), and the certificate covers the check geometry
//! too (the excluded neighbourhood of `C` included, as for the surface). A limiting point found
//! on check geometry is reported as [`Limit::Interference`].

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use glam::DVec4;
use smallvec::{smallvec, SmallVec};
use swarf_geom::math::Vec3;

use super::family::{bound_from_support, FamilyTrig};
use super::{
    classify, AllowableSize, Contact, CutterFamily, Limit, PreparedSurface, Regime, SizeError,
    SizeTolerances,
};
use swarf_surface::bezier::Piece;

/// Options of the certified solver (builder style, documented defaults).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CertifiedOptions {
    /// Absolute tolerance of the certificate, mm. Default `1e-7`.
    pub tol_abs: f64,
    /// Relative tolerance of the certificate. Default `1e-8`.
    pub tol_rel: f64,
    /// Radius (mm) of the ball around the CC point where the curvature bound stands for the
    /// surface. The imaginary size is `0/0` at the CC point and loses digits near it (its
    /// denominator is quadratic in the distance): at `1e-3` mm on a 5 mm radius a size is good
    /// to about `1e-7` mm (measured: a 10 mm cylinder's 10 mm ball reported up to 5.6e-7 mm low).
    /// The neighbourhood is left out a piece at a time (pieces within it), so near a point where
    /// the surface is singular (a fuselage's nose), where the size depends on how close to `C`
    /// one looks, the answer depends on the splits. A crease through the CC point (a V-groove's
    /// bottom), where the true size is 0, is therefore reported as a size of the order of this
    /// radius. Default `1e-3`.
    pub neighbourhood: f64,
    /// A limiting point within this distance (mm) of the CC point is a gouge limit, farther an
    /// interference. Default `1e-2`.
    pub gouge_radius: f64,
    /// Sizes at or above this (mm) count as unbounded: a node whose lower bound reaches it is
    /// pruned when nothing limits the size (a convex surface), and such a size is reported as
    /// `∞`. No cutter is a kilometre wide. Default `1e6`.
    pub unbounded_above: f64,
    /// Node budget per CC point. Default `200 000`.
    pub max_nodes: u64,
    /// Tolerances of the imaginary-size model.
    pub model: SizeTolerances,
}

impl CertifiedOptions {
    /// The documented defaults.
    pub const DEFAULT: CertifiedOptions = CertifiedOptions {
        tol_abs: 1e-7,
        tol_rel: 1e-8,
        neighbourhood: 1e-3,
        gouge_radius: 1e-2,
        unbounded_above: 1e6,
        max_nodes: 200_000,
        model: SizeTolerances::DEFAULT,
    };

    /// With another absolute and relative tolerance.
    pub fn with_tolerance(mut self, abs: f64, rel: f64) -> Self {
        self.tol_abs = abs;
        self.tol_rel = rel;
        self
    }

    /// With another node budget.
    pub fn with_max_nodes(mut self, n: u64) -> Self {
        self.max_nodes = n;
        self
    }

    /// With another excluded neighbourhood radius.
    pub fn with_neighbourhood(mut self, r: f64) -> Self {
        self.neighbourhood = r;
        self
    }

    /// Checks the ranges.
    ///
    /// # Errors
    /// When a tolerance is negative or not finite, or the budget is 0.
    pub fn validate(&self) -> Result<(), SizeError> {
        for (what, v) in [
            ("tol_abs", self.tol_abs),
            ("tol_rel", self.tol_rel),
            ("neighbourhood", self.neighbourhood),
            ("gouge_radius", self.gouge_radius),
            ("unbounded_above", self.unbounded_above),
        ] {
            if !(v >= 0.0 && v.is_finite()) {
                return Err(SizeError::Option {
                    what,
                    value: v,
                    range: "finite, ≥ 0",
                });
            }
        }
        if self.max_nodes == 0 {
            return Err(SizeError::Option {
                what: "max_nodes",
                value: 0.0,
                range: "≥ 1",
            });
        }
        Ok(())
    }

    fn tol(&self, best: f64) -> f64 {
        self.tol_abs.max(self.tol_rel * best)
    }
}

impl Default for CertifiedOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

struct Node {
    lb: f64,
    dir: usize,
    piece: Piece,
}

impl PartialEq for Node {
    fn eq(&self, o: &Self) -> bool {
        self.lb == o.lb
    }
}
impl Eq for Node {}
impl PartialOrd for Node {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Node {
    // Min-heap on the bound.
    fn cmp(&self, o: &Self) -> Ordering {
        o.lb.total_cmp(&self.lb)
    }
}

struct Search<'a> {
    family: &'a CutterFamily,
    /// The family with its angles' trigonometry computed once (support functions, the polar
    /// cone and the imaginary size of control points, at every node).
    trig: FamilyTrig,
    c: &'a Contact,
    regime: Regime,
    opts: &'a CertifiedOptions,
    best: f64,
    best_point: Option<Vec3>,
    best_is_local: bool,
    /// The best point lies on check geometry (always interference).
    best_is_check: bool,
    evaluations: u64,
    nodes: u64,
    cps: Vec<Vec3>,
    clipped: Vec<Vec3>,
}

impl Search<'_> {
    fn eval(&mut self, p: Vec3, check: bool) {
        if (p - self.c.point).length() < self.opts.neighbourhood {
            return;
        }
        self.evaluations += 1;
        let r = self
            .family
            .imaginary(self.c, &self.regime, p, &self.opts.model);
        if r < self.best && r < self.opts.unbounded_above {
            self.best = r;
            self.best_point = Some(p);
            self.best_is_local = false;
            self.best_is_check = check;
        }
    }

    /// Evaluates the corners `which` of the net that are on the (trimmed) part.
    fn eval_corners(&mut self, pc: &Piece, which: &[(usize, usize)]) {
        for &(i, j) in which {
            if pc.corner_on_part(i, j) {
                self.eval(pc.point(i, j), pc.check);
            }
        }
    }

    /// Rigorous lower bound of the imaginary size over the hull of the piece's control net, and
    /// the direction in which to split the piece next (the parameter along which the control
    /// net spreads most in the best separating direction: the other one does not limit the
    /// bound, so splitting it would only multiply nodes along a line of ties; where the ball's
    /// Bernstein bound is the better one, the parameter that bound needs, see [`SphereBound`]).
    fn lower_bound(&mut self, pc: &Piece) -> (f64, usize) {
        self.nodes += 1;
        let mut cps = std::mem::take(&mut self.cps);
        pc.euclidean(&mut cps);
        let c = self.c.point;
        let slack = self.opts.model.contact;
        let mut dirs: [Option<Vec3>; 3] = [Some(-self.c.normal), Some(-Vec3::Z), None];
        // A flat-bottomed APT cutter never reaches below its bottom plane, whatever its size:
        // clip the hull there (exactly, by the crossing points of the net's segments) so that
        // nodes straddling the plane are bounded by what lies above it.
        let bottom = match (*self.family, self.regime) {
            (
                CutterFamily::Apt {
                    corner, cone: 0.0, ..
                },
                Regime::Corner { q, u },
            ) => {
                dirs[1] = Some(-u);
                Some(q.z - corner)
            }
            (CutterFamily::Apt { cone: 0.0, .. }, Regime::Bottom) => Some(c.z),
            _ => None,
        };
        let mut clipped = std::mem::take(&mut self.clipped);
        let hull: &[Vec3] = match bottom {
            Some(zb) => {
                let zb = zb + slack;
                clipped.clear();
                clipped.extend(cps.iter().copied().filter(|p| p.z > zb));
                if clipped.is_empty() {
                    self.cps = cps;
                    self.clipped = clipped;
                    return (f64::INFINITY, 0);
                }
                for a in cps.iter().filter(|p| p.z > zb) {
                    for b in cps.iter().filter(|p| p.z <= zb) {
                        let t = (a.z - zb) / (a.z - b.z);
                        clipped.push(*a + t * (*b - *a));
                    }
                }
                &clipped
            }
            None => &cps,
        };
        // (Of the part above a flat bottom's plane: the rest cannot limit the size.)
        let centroid = hull.iter().copied().sum::<Vec3>() / hull.len() as f64;
        // The cutter that matters is the one of the current best size: a node is pruned when it
        // is clear of it. Its outward normal nearest the node's centroid is the candidate plane.
        let l_star = self
            .trig
            .imaginary(self.c, &self.regime, centroid, &self.opts.model)
            .min(self.best)
            .min(self.opts.unbounded_above);
        if l_star.is_finite() {
            if let Some(k) = self.family.placed(self.c, &self.regime, l_star) {
                let nu = self.trig.outward_normal(&k, centroid);
                if nu.is_finite() {
                    dirs[2] = Some(nu);
                }
            }
        }
        let mut lb: f64 = 0.0;
        let mut best_nu = dirs[2].unwrap_or(-self.c.normal);
        for nu in dirs.into_iter().flatten() {
            if let Some((b, nu)) = self.plane_bound(hull, nu) {
                if b > lb {
                    lb = b;
                    best_nu = nu;
                }
            }
        }
        // The plane that prunes a node the others miss: tangent to the cutter at the node's most
        // threatening control point (least imaginary size), of that point's size or the current
        // best if smaller. When that point is what limits the hull the plane separates it; when
        // another point of the hull stops the plane (its witness), the next plane is tangent
        // there. Near the CC point, where the hull spans many directions as seen from it, this
        // halves the nodes of a bull-nose. It is only worth its cost where it can prune: no hull
        // bound exceeds the least imaginary size of a control point (they are in the hull), so
        // a control point below the pruning level ends the attempt (the node will be split
        // anyway). Only the rounded APT cutters (bull-nose) gain: the ball's Bernstein bound
        // needs no help, and a flat end mill saves 2 % of its nodes for 30 % more time each.
        let target = self.prune_level();
        let rounded = matches!(*self.family, CutterFamily::Apt { corner, .. } if corner > 0.0);
        if rounded && lb < target && !self.surrounds_contact(hull) {
            if let Some((l_min, p_min)) = self.threat(hull, target) {
                let level = l_min.min(self.best).min(self.opts.unbounded_above);
                if let Some(k) = self.family.placed(self.c, &self.regime, level) {
                    let mut p = p_min;
                    for step in 1..=WITNESS_STEPS {
                        let nu = self.trig.outward_normal(&k, p);
                        let Some((b, nu)) = self.plane_bound(hull, nu) else {
                            break;
                        };
                        if b > lb {
                            lb = b;
                            best_nu = nu;
                        }
                        if lb >= target || step == WITNESS_STEPS {
                            break;
                        }
                        let w = self.witness(hull, nu);
                        if w == p {
                            break;
                        }
                        p = w;
                    }
                }
            }
        }
        self.clipped = clipped;
        let mut dir = if pc.check {
            triangle_split_edge(pc.triangle(), c, best_nu)
        } else {
            split_direction(pc, &cps, c, best_nu)
        };
        // Where the Bernstein bound beats the planes it is the one to refine: split along the
        // parameter that brings its limiting coefficient to the polynomial (see
        // [`SphereBound::dir`]), not along the planes' choice. On a line of ties across the
        // parameter lines (a concave cylinder of the ball's radius, the tie circle at a CC point
        // off the dyadic splits) the planes' choice and its aspect cap cut the line into
        // thousands of short nodes the Bernstein bound never needed.
        let sphere = |lb: &mut f64, dir: &mut usize| {
            let s = sphere_bound(pc, c, self.c.normal, slack);
            if s.lb > *lb {
                *lb = s.lb;
                // (A check triangle splits by its edges, which `dir` numbers there: the
                // parameter direction would leave one edge never split.)
                if let (Some(d), false) = (s.dir, pc.check) {
                    *dir = d;
                }
            }
        };
        if *self.family == CutterFamily::Sphere {
            sphere(&mut lb, &mut dir);
        } else if let (CutterFamily::TaperBall { taper }, Regime::Ball) =
            (*self.family, self.regime)
        {
            let dz = self.c.normal.z - taper.sin();
            let zmax = cps.iter().map(|p| p.z).fold(f64::NEG_INFINITY, f64::max);
            let l_h = if dz > 0.0 {
                ((zmax - c.z) / dz).max(0.0)
            } else {
                f64::INFINITY
            };
            // Below the plane z = C_z + L_h·(n_z − sin θ) the side cannot reach the node for
            // L ≥ L_h; for L < L_h the side lies within L·(1 + |n_xy|) + (z − C_z)·tan θ of C's
            // vertical, so a node horizontally farther than that is clear of it too.
            let (mut lo, mut hi) = (Vec3::splat(f64::INFINITY), Vec3::splat(f64::NEG_INFINITY));
            for p in &cps {
                lo = lo.min(*p);
                hi = hi.max(*p);
            }
            let dx = (lo.x - c.x).max(c.x - hi.x).max(0.0);
            let dy = (lo.y - c.y).max(c.y - hi.y).max(0.0);
            let nh = self.c.normal.truncate().length();
            let far = l_h.is_finite()
                && dx.hypot(dy) > l_h * (1.0 + nh) + (zmax - c.z).max(0.0) * taper.tan() + slack;
            if lb >= l_h || far {
                sphere(&mut lb, &mut dir);
            }
        }
        self.cps = cps;
        (lb, dir)
    }

    /// Bounds at or above this prune a node: within the tolerance of the best size found, or
    /// [`CertifiedOptions::unbounded_above`] while nothing limits the size.
    fn prune_level(&self) -> f64 {
        if self.best.is_finite() {
            self.best - self.opts.tol(self.best)
        } else {
            self.opts.unbounded_above
        }
    }

    /// True when the box of the hull contains the CC point: then (the hull about surrounds it)
    /// no plane separates the hull from the cutter touching there, and none is worth trying.
    fn surrounds_contact(&self, hull: &[Vec3]) -> bool {
        let c = self.c.point;
        let (mut lo, mut hi) = (c, c);
        for p in hull {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        lo.cmplt(c).all() && hi.cmpgt(c).all()
    }

    /// The control point of the hull with the least imaginary size, and that size; `None` as
    /// soon as one is below `target` (then no bound over the hull reaches it).
    fn threat(&self, hull: &[Vec3], target: f64) -> Option<(f64, Vec3)> {
        let (mut l_min, mut p_min) = (f64::INFINITY, self.c.point);
        for p in hull {
            let l = self
                .trig
                .imaginary(self.c, &self.regime, *p, &self.opts.model);
            if l < target {
                return None;
            }
            if l < l_min {
                l_min = l;
                p_min = *p;
            }
        }
        Some((l_min, p_min))
    }

    /// The separating-plane bound of the hull in direction `nu` (moved into the polar cone of
    /// the cutter's side), with that direction; `None` when the direction bounds nothing (not
    /// finite, or the support function is infinite there).
    fn plane_bound(&self, hull: &[Vec3], nu: Vec3) -> Option<(f64, Vec3)> {
        if !nu.is_finite() {
            return None;
        }
        let nu = self.trig.in_polar_cone(nu);
        let pieces = self.trig.support(self.c, &self.regime, nu)?;
        let c = self.c.point;
        let m = hull
            .iter()
            .map(|p| (*p - c).dot(nu))
            .fold(f64::INFINITY, f64::min);
        Some((bound_from_support(&pieces, m + self.opts.model.contact), nu))
    }

    /// The point of the hull nearest the plane of normal `nu` (the one that stops it).
    fn witness(&self, hull: &[Vec3], nu: Vec3) -> Vec3 {
        let c = self.c.point;
        hull.iter()
            .copied()
            .min_by(|a, b| (*a - c).dot(nu).total_cmp(&(*b - c).dot(nu)))
            .unwrap_or(c)
    }

    fn excluded(&self, pc: &Piece) -> (bool, f64) {
        let bb = swarf_geom::Aabb::from_points(self.cps_of(pc)).expect("non-empty net");
        let diag = bb.size().length();
        let q = self.c.point.clamp(bb.min, bb.max);
        let near = (q - self.c.point).length() < self.opts.neighbourhood;
        (near && diag < self.opts.neighbourhood, diag)
    }

    fn cps_of<'p>(&self, pc: &'p Piece) -> impl Iterator<Item = Vec3> + 'p {
        pc.net.iter().map(|h| Vec3::new(h.x, h.y, h.z) / h.w)
    }
}

/// 0 for u, 1 for v: the parameter along which `(P_ij − C)·ν` varies most.
fn split_direction(pc: &Piece, cps: &[Vec3], c: Vec3, nu: Vec3) -> usize {
    let (p, q) = (pc.p, pc.q);
    let f = |i: usize, j: usize| (cps[i * (q + 1) + j] - c).dot(nu);
    let mut var_u: f64 = 0.0;
    let mut var_v: f64 = 0.0;
    for j in 0..=q {
        var_u = var_u.max((f(p, j) - f(0, j)).abs());
    }
    for i in 0..=p {
        var_v = var_v.max((f(i, q) - f(i, 0)).abs());
    }
    // Also the control nets' own extent, so that a node flat in ν still gets smaller.
    let ext = |a: Vec3, b: Vec3| (a - b).length();
    let eu = ext(cps[p * (q + 1)], cps[0]).max(ext(cps[p * (q + 1) + q], cps[q]));
    let ev = ext(cps[q], cps[0]).max(ext(cps[p * (q + 1) + q], cps[p * (q + 1)]));
    // Keep nodes from growing needle-thin: past an aspect ratio of 8, split the long side.
    if eu > MAX_ASPECT * ev {
        return 0;
    }
    if ev > MAX_ASPECT * eu {
        return 1;
    }
    if var_u >= var_v {
        0
    } else {
        1
    }
}

/// The edge of a check triangle to bisect (`0`: `AB`, `1`: `BC`, `2`: `CA`): the one along which
/// `(P − C)·ν` varies most, as [`split_direction`] does for patches (a line of ties is then
/// resolved by thin triangles along it, not by a crowd of small ones), unless the longest edge is
/// more than [`MAX_ASPECT`] times longer, which is bisected instead.
fn triangle_split_edge(t: [Vec3; 3], c: Vec3, nu: Vec3) -> usize {
    let edge = |k: usize| (t[k], t[(k + 1) % 3]);
    let var = |k: usize| {
        let (x, y) = edge(k);
        ((y - c).dot(nu) - (x - c).dot(nu)).abs()
    };
    let len = |k: usize| {
        let (x, y) = edge(k);
        (y - x).length()
    };
    let longest = (0..3)
        .max_by(|&a, &b| len(a).total_cmp(&len(b)))
        .unwrap_or(0);
    let steepest = (0..3)
        .max_by(|&a, &b| var(a).total_cmp(&var(b)))
        .unwrap_or(0);
    if len(longest) > MAX_ASPECT * len(steepest) {
        longest
    } else {
        steepest
    }
}

/// Planes tried per node from the hull's most threatening control point on (see
/// [`Search::lower_bound`]): each further step starts from the previous plane's witness.
const WITNESS_STEPS: usize = 2;

/// Largest ratio of a node's long side to its short side that the split choice tolerates.
const MAX_ASPECT: f64 = 8.0;

/// The Bernstein bound of a piece ([`sphere_bound`]) and where to split the piece to raise it.
struct SphereBound {
    lb: f64,
    /// The parameter (0: u, 1: v) along which the limiting coefficient is farthest from the
    /// polynomial (its second difference along that parameter, at the bound's level): halving
    /// along it divides that difference by 4, halving along the other cannot move it at all
    /// when the coefficient lies on an edge of the other parameter. `None` when nothing limits
    /// the bound or the piece's net is too long and thin for more of the same (then the
    /// planes' choice stands). Only speed depends on it, never the bound.
    dir: Option<usize>,
}

/// Lower bound of the sphere-only imaginary size over a piece, by Bernstein positivity of
/// `w²·(|S − C|² − 2L·n·(S − C))` (see the module docs). `slack` (mm): a coefficient of the
/// normal offset this close to zero counts as touching.
fn sphere_bound(pc: &Piece, c: Vec3, n: Vec3, slack: f64) -> SphereBound {
    let (p, q) = (pc.p, pc.q);
    let (du, dv) = (2 * p + 1, 2 * q + 1);
    let mut a = vec![0.0; du * dv];
    let mut b = vec![0.0; du * dv];
    let y: Vec<(Vec3, f64)> = pc
        .net
        .iter()
        .map(|h: &DVec4| (Vec3::new(h.x, h.y, h.z) - h.w * c, h.w))
        .collect();
    let bu = binomials(p);
    let bv = binomials(q);
    let bu2 = binomials(2 * p);
    let bv2 = binomials(2 * q);
    for i in 0..=p {
        for j in 0..=q {
            let (yij, wij) = y[i * (q + 1) + j];
            for i2 in 0..=p {
                for j2 in 0..=q {
                    let (y2, _) = y[i2 * (q + 1) + j2];
                    let (k, l) = (i + i2, j + j2);
                    let f = bu[i] * bu[i2] / bu2[k] * bv[j] * bv[j2] / bv2[l];
                    a[k * dv + l] += f * yij.dot(y2);
                    b[k * dv + l] += f * wij * n.dot(y2);
                }
            }
        }
    }
    let wmax = pc.net.iter().map(|h| h.w).fold(0.0, f64::max);
    let b_slack = slack * wmax * wmax;
    let mut lb = f64::INFINITY;
    let mut at = None;
    for (k, (ak, bk)) in a.iter().zip(&b).enumerate() {
        if *bk > b_slack {
            let l = ak / (2.0 * bk);
            if l < lb {
                lb = l;
                at = Some(k);
            }
        } else if *ak < 0.0 {
            lb = 0.0;
            at = Some(k);
            break;
        }
    }
    let lb = lb.max(0.0);
    let dir = at.and_then(|k| {
        // The net's extents: past MAX_SPHERE_ASPECT the long side is split whatever the
        // coefficients say, so that every node keeps getting smaller.
        let (m, r) = (p, q);
        let pt = |i: usize, j: usize| pc.point(i, j);
        let eu = (pt(m, 0) - pt(0, 0))
            .length()
            .max((pt(m, r) - pt(0, r)).length());
        let ev = (pt(0, r) - pt(0, 0))
            .length()
            .max((pt(m, r) - pt(m, 0)).length());
        if eu > MAX_SPHERE_ASPECT * ev {
            return Some(0);
        }
        if ev > MAX_SPHERE_ASPECT * eu {
            return Some(1);
        }
        let f = |k: usize, l: usize| a[k * dv + l] - 2.0 * lb * b[k * dv + l];
        let (k, l) = (k / dv, k % dv);
        let second = |interior: bool, lo: f64, mid: f64, hi: f64| {
            if interior {
                (lo - 2.0 * mid + hi).abs()
            } else {
                0.0
            }
        };
        let d_u = second(
            k > 0 && k + 1 < du,
            f(k.saturating_sub(1), l),
            f(k, l),
            f((k + 1).min(du - 1), l),
        );
        let d_v = second(
            l > 0 && l + 1 < dv,
            f(k, l.saturating_sub(1)),
            f(k, l),
            f(k, (l + 1).min(dv - 1)),
        );
        if d_u > d_v {
            Some(0)
        } else if d_v > d_u {
            Some(1)
        } else {
            None
        }
    });
    SphereBound { lb, dir }
}

/// Largest ratio of a node's long side to its short side that the Bernstein bound's split
/// choice tolerates (a line of ties wants long thin nodes along it: 50 mm by a few µm).
const MAX_SPHERE_ASPECT: f64 = 1e6;

fn binomials(n: usize) -> Vec<f64> {
    let mut out = vec![1.0; n + 1];
    for k in 1..=n {
        out[k] = out[k - 1] * (n + 1 - k) as f64 / k as f64;
    }
    out
}

/// The allowable size at one contact, with its certificate (see the module docs).
///
/// ```
/// use swarf_geom::math::Vec3;
/// use swarf_plan::size::{allowable_certified, CertifiedOptions, Contact, CutterFamily};
/// use swarf_surface::{io, PreparedSurface, Tolerances};
/// // A floor with a 10 mm wall at x = 10: a flat end mill at the origin fits up to R = 10.
/// let json = r#"{"units": "mm", "patches": [
///   {"name": "floor", "degree_u": 1, "degree_v": 1, "knots_u": [0,0,1,1], "knots_v": [0,0,1,1],
///    "control_points": [[[-10,-10,0,1],[-10,10,0,1]],[[10,-10,0,1],[10,10,0,1]]]},
///   {"name": "wall", "degree_u": 1, "degree_v": 1, "knots_u": [0,0,1,1], "knots_v": [0,0,1,1],
///    "control_points": [[[10,-10,0,1],[10,-10,10,1]],[[10,10,0,1],[10,10,10,1]]]}]}"#;
/// let part = io::json::parse(json)?;
/// let prep = PreparedSurface::new(&part);
/// let cc = part.points(&[(0, 0.5, 0.5)]).unwrap()[0];
/// let c = Contact::at(&part, &cc, &Tolerances::DEFAULT).unwrap();
/// let a = allowable_certified(&prep, &CutterFamily::flat(), &c, &CertifiedOptions::DEFAULT);
/// assert!((a.size - 10.0).abs() < 1e-6 && a.certified);
/// # Ok::<(), swarf_surface::io::ReadError>(())
/// ```
pub fn allowable_certified(
    prep: &PreparedSurface,
    family: &CutterFamily,
    c: &Contact,
    opts: &CertifiedOptions,
) -> AllowableSize {
    let regime = family.regime(c, &opts.model);
    if regime == Regime::Unreachable {
        return AllowableSize::unreachable(c.point, true);
    }
    let local = family.local_bound(c, &regime);
    // Beyond `unbounded_above` a size is as good as infinite.
    let local = if local >= opts.unbounded_above {
        f64::INFINITY
    } else {
        local
    };
    let mut s = Search {
        family,
        trig: FamilyTrig::new(*family),
        c,
        regime,
        opts,
        best: local,
        best_point: local.is_finite().then_some(c.point),
        best_is_local: true,
        best_is_check: false,
        evaluations: 0,
        nodes: 0,
        cps: Vec::new(),
        clipped: Vec::new(),
    };
    let mut heap = BinaryHeap::new();
    // Lowest bound of nodes given up on (below the size floor): they weaken the certificate.
    let mut abandoned = f64::INFINITY;
    // Lowest bound of the nodes pruned against an earlier (larger) best value.
    let mut pruned = f64::INFINITY;
    for pc in &prep.pieces {
        let (p, q) = (pc.p, pc.q);
        s.eval_corners(pc, &[(0, 0), (p, 0), (0, q), (p, q)]);
        let (lb, dir) = s.lower_bound(pc);
        heap.push(Node {
            lb,
            dir,
            piece: pc.clone(),
        });
    }
    let scale = prep
        .bounding_box()
        .map_or(1.0, |b| b.size().length().max(f64::MIN_POSITIVE));
    let min_diag = scale * 1e-13;
    let mut exhausted = false;
    while let Some(node) = heap.pop() {
        let done = node.lb >= s.prune_level();
        if done || s.best == 0.0 {
            heap.push(node);
            break;
        }
        if s.nodes >= opts.max_nodes {
            heap.push(node);
            exhausted = true;
            break;
        }
        let (excluded, diag) = s.excluded(&node.piece);
        if excluded {
            continue;
        }
        if diag < min_diag {
            abandoned = abandoned.min(node.lb);
            continue;
        }
        let children: SmallVec<[Piece; 2]> = if node.piece.check {
            // A check triangle: bisected through the midpoint of the chosen edge (the new point).
            let (children, m) = node.piece.bisect_triangle(node.dir);
            s.eval(m, true);
            SmallVec::from_iter(children)
        } else {
            // Along a trim boundary that follows a parameter line where there is one (see
            // `Piece::trim_cut`), otherwise halved in the chosen direction.
            let (dir, t) = node.piece.trim_cut().unwrap_or((node.dir, 0.5));
            let (a, b) = node.piece.split_at(dir, t);
            let (p, q) = (a.p, a.q);
            // The two new surface points: the ends of the cut.
            if dir == 0 {
                s.eval_corners(&a, &[(p, 0), (p, q)]);
            } else {
                s.eval_corners(&a, &[(0, q), (p, q)]);
            }
            smallvec![a, b]
        };
        for child in children.into_iter().filter(Piece::on_part) {
            let (lb, dir) = s.lower_bound(&child);
            if lb < s.prune_level() {
                heap.push(Node {
                    lb,
                    dir,
                    piece: child,
                });
            } else {
                pruned = pruned.min(lb);
            }
        }
    }
    // A tie with the curvature bound (a sphere's every point gives its radius) is the gouge
    // limit: the curvature governs. Values within the tolerance below it are round-off (the
    // imaginary size loses digits near the CC point), so the curvature bound itself is
    // reported, and the certificate's gap grows by the difference.
    let mut raised = 0.0;
    if !s.best_is_local && local.is_finite() && s.best >= local - opts.tol(local) {
        raised = local - s.best;
        s.best_is_local = true;
        s.best_point = Some(c.point);
        s.best = local;
    }
    let open = heap
        .peek()
        .map_or(f64::INFINITY, |n| n.lb)
        .min(abandoned)
        .min(pruned);
    let gap = if s.best == 0.0
        || open >= s.best
        || (s.best.is_infinite() && open >= opts.unbounded_above)
    {
        0.0
    } else {
        s.best - open
    };
    let certified = !exhausted
        && if s.best.is_infinite() {
            open >= opts.unbounded_above
        } else {
            gap <= opts.tol(s.best) + raised
        };
    let limit = s.best.is_finite().then(|| {
        if s.best_is_local {
            Limit::Gouge
        } else if s.best_is_check {
            // Check geometry is never the CC point's own surface.
            Limit::Interference
        } else {
            classify(c.point, s.best_point.unwrap_or(c.point), opts.gouge_radius)
        }
    });
    AllowableSize {
        size: s.best,
        limit,
        limit_point: if s.best.is_finite() {
            s.best_point
        } else {
            None
        },
        gap,
        certified,
        evaluations: s.evaluations,
        nodes: s.nodes,
    }
}
