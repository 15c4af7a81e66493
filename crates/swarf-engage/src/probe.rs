//! Where a point is with respect to the material of a tri-dexel stock, and how far from its
//! boundary, read from the exact interval ends of the rays around it.
//!
//! Each family of rays (along X, Y or Z) sees the stock's boundary near a point `P` through the
//! four rays around `P` (cell centres `(i, i+1) × (j, j+1)` across the family). On each of them
//! the interval end nearest to `P`'s coordinate along the ray is an **exact** boundary point.
//! When the four nearest ends are of one kind (all material-entries or all material-exits) they
//! lie on one sheet of the boundary, which over the cell is the height field `t = e(u, v)`
//! interpolated bilinearly between them; `P`'s signed distance to that sheet's tangent plane
//! is `s·(t − e)/√(1 + |∇e|²)` (`s` = +1 when the material lies on the ray's positive side
//! of the sheet). That is exact for a plane and within `O(h²·κ)` of the truth for a sheet of
//! curvature `κ`. (The four ends must lie within `2·D₀` of `P`, the precision cap `D₀` below,
//! the distance is clamped to `D₀`, and the sheet may be at most twice as steep as level
//! across the family: four ends of one kind on either side of a wall along the rays are a
//! step, not a sheet.) Near a sheet parallel to a family the four rays straddle it (some
//! inside, some not) or step across it: that family is not **coherent** there and says
//! nothing; another, transverse to the sheet, does. Of the coherent families the nearest
//! sheet wins (the distance to a solid's boundary is the distance to its nearest face). Only
//! near an edge of the stock — within a ray spacing of two faces at once — may no family be
//! coherent. Beside an edge some of a family's rays end near `P` on one sheet, and the others
//! are air at `P` (an outer edge: none at all, or material only elsewhere along them, as over
//! a groove beside its wall's top) or material (an inner edge); that sheet is one of the edge's
//! faces, and `P`'s distance to it is measured (from one ray, or a pair whose ends give its
//! slope; ends too far apart for one sheet are a step — then the nearest ray and its neighbour
//! along a side of the cell that end on the face, whose word is taken only that `P` lies
//! outside an outer edge's face). At an outer edge the material is inside
//! both faces: outside a face's sheet `P` is outside, whatever the other face, and the nearest
//! such face's distance stands; inside the sheets `P` is inside unless a nearest ray of some
//! family found air where the sheets put material — it saw the edge's other face, which a
//! family across it sees only at the ray spacing, and the vote decides. At an inner edge the
//! material is on either face's side: inside a sheet `P` is inside; outside, the vote decides.
//! Where the faces lie on the rays' cell boundaries (a block's faces, a slot cut along them)
//! this is exact, where a vote put the axial depth of a cutter entering a block or passing
//! beside a slot 0.015 mm too deep. Elsewhere (a step, or the rays disagreeing) the rays
//! nearest to `P` vote on the side, and the distance is reported as a fraction of the spacing.
//!
//! Far from the boundary no family is coherent either, but then all twelve rays agree on the
//! side and their nearest ends are all farther than the probe's precision cap `D₀ = 4h`: the
//! point is **deep**, and `D/√3 − 2h` (`D` the nearest of those ends along its ray) is a lower
//! bound of its distance to any boundary the rays resolve — a sheet at distance `δ` crosses the
//! rays of the family most aligned with its normal (within 54.7°) at most `√3·(δ + √2·h)` away —
//! reported as at least `D₀`. Beside the grid (where a family has no rays) the material may be
//! as near as the grid's edge: such rays count as near, never as far.
//!
//! A probe reads twelve rays; [`MaterialProbe::inside_nearest_ray`] reads one, and guesses the
//! side — right away from the boundary, which is where the engagement uses it.

use swarf_geom::math::{greater, lesser, Vec3};
use swarf_stock::{Interval, TriDexel};

/// What the rays say about a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Depth {
    /// Signed distance to the stock's boundary, mm: positive inside the material.
    pub distance: f64,
    /// True when a family measured it (a coherent one, or beside an edge one whose measure
    /// stands); false when the rays only voted on the side.
    pub measured: bool,
    /// The outward normal (out of the material) of the boundary sheet the distance was
    /// measured to, when a family measured it.
    pub normal: Option<Vec3>,
}

/// Point queries against a stock. Cheap to make; borrows the stock.
#[derive(Clone, Copy, Debug)]
pub struct MaterialProbe<'a> {
    stock: &'a TriDexel,
    /// Each family's ray lattice, in the form the per-probe arithmetic wants.
    lattice: [Lattice; 3],
    /// Distances beyond this (mm) need no precision: the point is deep inside or far outside.
    cap: f64,
}

/// The nearest interval end to `t` on one ray: signed distance along the ray (positive in the
/// material), the end, and which kind of end it is (`+1`: an entry, the material on the ray's
/// positive side; `−1`: an exit; `0`: the ray holds no material).
///
/// Always inlined: called as a function it returns its triple through memory, and the caller's
/// 16-byte reload of two 8-byte stores stalls on store forwarding (a quarter of a probe's time).
#[inline(always)]
fn nearest_end(ray: &[Interval], t: f64) -> (f64, f64, i8) {
    let (end, kind) = if let [iv] = ray {
        // One interval (most rays): the scan below, unrolled.
        let (de, dx) = ((t - iv.enter).abs(), (t - iv.exit).abs());
        if de < f64::INFINITY {
            if dx < de {
                (iv.exit, -1)
            } else {
                (iv.enter, 1)
            }
        } else if dx < f64::INFINITY {
            (iv.exit, -1)
        } else {
            (0.0, 0)
        }
    } else if ray.len() <= SHORT_RAY {
        // Short rays (nearly all of them): every end compared, without data-dependent
        // branches; strict `<` keeps the lower of two equally near ends.
        let (mut best, mut end, mut kind) = (f64::INFINITY, 0.0, 0i8);
        for iv in ray {
            let d = (t - iv.enter).abs();
            if d < best {
                (best, end, kind) = (d, iv.enter, 1);
            }
            let d = (t - iv.exit).abs();
            if d < best {
                (best, end, kind) = (d, iv.exit, -1);
            }
        }
        (end, kind)
    } else {
        // The ends are sorted: only the last interval starting at or below t (its two ends)
        // and the first starting above it (its entry) can be nearest. Ties go to the lower
        // end, as a scan from the start would give them.
        let k = ray.partition_point(|iv| iv.enter <= t);
        let (mut end, mut kind) = (f64::NAN, 0i8);
        let mut consider = |e: f64, kd: i8| {
            if kind == 0 || (t - e).abs() < (t - end).abs() {
                (end, kind) = (e, kd);
            }
        };
        if k > 0 {
            consider(ray[k - 1].enter, 1);
            consider(ray[k - 1].exit, -1);
        }
        if let Some(iv) = ray.get(k) {
            consider(iv.enter, 1);
        }
        (end, kind)
    };
    (f64::from(kind) * (t - end), end, kind)
}

/// One family's ray lattice: its cross axes `u`, `v`, and the centres of its rays at
/// `min + (i + ½)·h` along each.
#[derive(Clone, Copy, Debug)]
struct Lattice {
    u: usize,
    v: usize,
    min: [f64; 2],
    h: [f64; 2],
    /// `1/h`, for the one-ray guess (whose ray may be either neighbour at a tie).
    inv_h: [f64; 2],
    n: [f64; 2],
    n_rays: [usize; 2],
}

/// A family is coherent when its four nearest ends, all of one kind, lie within this many
/// precision caps of the point (the distance it measures is then clamped to the cap). One cap
/// would leave points about a cap deep — where some of the four ends fall just inside it and
/// some just beyond — to a vote, which reports them a quarter spacing from the boundary.
const COHERENT_REACH: f64 = 2.0;

/// The steepest sheet a family measures: its ends may rise at most this much per unit across
/// the family between neighbouring rays. Every plane is at most `√2` steep to the family most
/// aligned with its normal (`|n_k| ≥ 1/√3`), so each plane keeps a family that measures it;
/// a wall along a family's rays (a step between a top and a floor) is left to the families
/// across it.
const MAX_SHEET_SLOPE: f64 = 2.0;

/// Rays with at most this many intervals are scanned whole for their nearest end.
const SHORT_RAY: usize = 4;

impl<'a> MaterialProbe<'a> {
    /// A probe of `stock`.
    pub fn new(stock: &'a TriDexel) -> Self {
        let g = stock.grid();
        let h = g.h;
        let lattice = std::array::from_fn(|k| {
            let (u, v) = ((k + 1) % 3, (k + 2) % 3);
            let (nu, nv) = stock.family(k).dims();
            Lattice {
                u,
                v,
                min: [g.min[u], g.min[v]],
                h: [h[u], h[v]],
                inv_h: [1.0 / h[u], 1.0 / h[v]],
                n: [nu as f64, nv as f64],
                n_rays: [nu, nv],
            }
        });
        Self {
            stock,
            lattice,
            cap: 4.0 * h[0].max(h[1]).max(h[2]),
        }
    }

    /// The same probe measuring distances out to at least `reach` mm before it clamps them
    /// (the precision cap `D₀`, `4h` by default, becomes `max(4h, reach)`). A caller that
    /// interpolates the boundary between points `s` apart needs `reach ≥ s`: each of two points
    /// either side of a face lies within `s` of it, and a clamped distance moves the
    /// interpolated crossing (engagement discs 0.75 mm apart at h = 0.1 put a slot's floor
    /// 0.054 mm off).
    pub fn with_reach(mut self, reach: f64) -> Self {
        self.cap = greater(self.cap, reach);
        self
    }

    /// The stock probed.
    pub fn stock(&self) -> &'a TriDexel {
        self.stock
    }

    /// The signed distance of `p` to the boundary of the material (positive inside).
    pub fn depth(&self, p: Vec3) -> Depth {
        let mut best: Option<(f64, Vec3)> = None;
        let mut votes = 0i32;
        let mut vote_scale = 0.0f64;
        // The measures of the families beside an edge: distance, sheet normal, outer edge?
        let (mut edges, mut n_edges) = ([(0.0, Vec3::ZERO, false); 3], 0);
        // What the nearest rays of the families that are not coherent found, and where they
        // passed (offsets from P across their family).
        let (mut nearest, mut n_nearest) = ([(false, Vec3::ZERO); 3], 0);
        // Whether a deep family found air.
        let mut deep_air = false;
        // Deep families: how many, and the nearest end among them.
        let (mut deep, mut deep_inside, mut deep_near) = (0, 0, f64::INFINITY);
        for k in 0..3 {
            match self.family_depth(k, p) {
                FamilyDepth::Coherent(d, n) => {
                    if best.map_or(true, |(b, _)| d.abs() < b.abs()) {
                        best = Some((d, n));
                    }
                }
                FamilyDepth::Edge(d, n, outer, ray, spacing) => {
                    edges[n_edges] = (d, n, outer);
                    n_edges += 1;
                    votes += if ray.inside { 1 } else { -1 };
                    vote_scale = greater(vote_scale, spacing);
                    nearest[n_nearest] = (ray.inside, ray.offset);
                    n_nearest += 1;
                }
                FamilyDepth::Vote(ray, spacing) => {
                    votes += if ray.inside { 1 } else { -1 };
                    vote_scale = greater(vote_scale, spacing);
                    nearest[n_nearest] = (ray.inside, ray.offset);
                    n_nearest += 1;
                }
                FamilyDepth::Deep(inside, near, spacing) => {
                    votes += if inside { 1 } else { -1 };
                    vote_scale = greater(vote_scale, spacing);
                    deep_air |= !inside;
                    deep += 1;
                    deep_inside += i32::from(inside);
                    deep_near = lesser(deep_near, near);
                }
            }
        }
        if deep == 3 && (deep_inside == 0 || deep_inside == 3) {
            let bound = greater(deep_near / 3f64.sqrt() - 2.0 * vote_scale, self.cap);
            return Depth {
                distance: if deep_inside == 3 { bound } else { -bound },
                measured: true,
                normal: None,
            };
        }
        let edge = edge_verdict(&edges[..n_edges], &nearest[..n_nearest], deep_air);
        match (best, edge) {
            (Some((d, n)), _) => Depth {
                distance: d.clamp(-self.cap, self.cap),
                measured: true,
                normal: Some(n),
            },
            (None, Some((d, n))) => Depth {
                distance: d.clamp(-self.cap, self.cap),
                measured: true,
                normal: Some(n),
            },
            (None, None) => Depth {
                // Three votes (every family that is not coherent votes): a tie is impossible.
                distance: f64::from(votes.signum()) * 0.25 * vote_scale,
                measured: false,
                normal: None,
            },
        }
    }

    /// True when `p` is inside the material (by [`MaterialProbe::depth`]).
    pub fn inside(&self, p: Vec3) -> bool {
        self.depth(p).distance > 0.0
    }

    /// A one-ray guess of [`MaterialProbe::inside`]: whether the ray of family `k` nearest to
    /// `p` holds material at `p`'s coordinate along it (false beside the grid). Exact on the
    /// ray; off it the boundary may shift by the sheet's slope times the ray's distance (at
    /// most `h/√2` across the family), so the guess agrees with the probe except within about
    /// a ray spacing of the boundary — when `k` is the family most aligned with the sheet's
    /// normal, within `h` of it. A tenth of a probe's cost: one ray, no neighbours.
    #[inline]
    pub fn inside_nearest_ray(&self, k: usize, p: Vec3) -> bool {
        // The family a constant in each arm: its axes index the point without a table (the
        // guess runs at every feasible sample of every location).
        match k {
            0 => self.inside_nearest_ray_of::<0>(p),
            1 => self.inside_nearest_ray_of::<1>(p),
            _ => self.inside_nearest_ray_of::<2>(p),
        }
    }

    #[inline(always)]
    fn inside_nearest_ray_of<const K: usize>(&self, p: Vec3) -> bool {
        let l = &self.lattice[K];
        let pa = [p.x, p.y, p.z];
        // Ray i's centre is at min + (i + ½)·h: the nearest ray is ⌊(x − min)/h⌋.
        let fu = (pa[(K + 1) % 3] - l.min[0]) * l.inv_h[0];
        let fv = (pa[(K + 2) % 3] - l.min[1]) * l.inv_h[1];
        if !(fu >= 0.0 && fv >= 0.0 && fu < l.n[0] && fv < l.n[1]) {
            return false;
        }
        let t = pa[K];
        // (In range: through `u32`, the cheaper conversion.)
        self.stock
            .family(K)
            .ray(fu as u32 as usize, fv as u32 as usize)
            .iter()
            .any(|iv| iv.enter <= t && t <= iv.exit)
    }

    #[inline(always)]
    fn family_depth(&self, k: usize, p: Vec3) -> FamilyDepth {
        let l = &self.lattice[k];
        let fam = self.stock.family(k);
        let pa = [p.x, p.y, p.z];
        let fu = (pa[l.u] - l.min[0]) * l.inv_h[0] - 0.5;
        let fv = (pa[l.v] - l.min[1]) * l.inv_h[1] - 0.5;
        let (i0, j0) = (floor(fu), floor(fv));
        let (wu, wv) = (fu - i0, fv - j0);
        let t = pa[k];
        let spacing = greater(l.h[0], l.h[1]);
        // The four rays (i0 + (r & 1), j0 + (r >> 1)): signed distance to the nearest end,
        // the end, its kind (0: no material, or no ray there).
        let mut near = [(0.0, 0.0, 0i8); 4];
        let inside = |i: f64, j: f64| i >= 0.0 && j >= 0.0 && i < l.n[0] && j < l.n[1];
        let mut outside = [false; 4];
        if i0 >= 0.0 && j0 >= 0.0 && i0 + 1.0 < l.n[0] && j0 + 1.0 < l.n[1] {
            let rays = fam.ray_quad(i0 as u32 as usize, j0 as u32 as usize);
            for (n, ray) in near.iter_mut().zip(rays) {
                *n = nearest_end(ray, t);
            }
        } else {
            for (r, out) in outside.iter_mut().enumerate() {
                let (i, j) = (i0 + (r & 1) as f64, j0 + (r >> 1) as f64);
                if inside(i, j) {
                    near[r] = nearest_end(fam.ray(i as u32 as usize, j as u32 as usize), t);
                } else {
                    *out = true;
                    near[r] = (0.0, 0.0, 0);
                }
            }
        }
        // No ray there to see a sheet: the material may come as near as the grid's edge, a
        // ray spacing beyond the outermost rays.
        let beyond = || {
            beyond_rays(fu, l.n_rays[0], l.h[0]).hypot(beyond_rays(fv, l.n_rays[1], l.h[1]))
                - spacing
        };
        let side = |r: usize| near[r].2 != 0 && near[r].0 > 0.0;
        let gap = |r: usize| match near[r] {
            (d, _, kd) if kd != 0 => d.abs(),
            _ if outside[r] => beyond(),
            _ => f64::INFINITY,
        };
        // All four rays far from any end, on one side: deep.
        let gaps = [gap(0), gap(1), gap(2), gap(3)];
        let s0 = side(0);
        if gaps.iter().all(|&x| x > self.cap) && (1..4).all(|r| side(r) == s0) {
            let far_near = lesser(lesser(gaps[0], gaps[1]), lesser(gaps[2], gaps[3]));
            return FamilyDepth::Deep(s0, far_near, spacing);
        }
        let kind = near[0].2;
        let ends = [near[0].1, near[1].1, near[2].1, near[3].1];
        // One sheet: four ends of one kind, near, and no steeper between neighbouring rays
        // than a sheet this family is fit to measure (ends of one kind on either side of a
        // wall along the rays — a top and a floor — are a step, not a sheet).
        let (su, sv) = (
            greater((ends[1] - ends[0]).abs(), (ends[3] - ends[2]).abs()) * l.inv_h[0],
            greater((ends[2] - ends[0]).abs(), (ends[3] - ends[1]).abs()) * l.inv_h[1],
        );
        let coherent = kind != 0
            && near
                .iter()
                .all(|&(d, _, kd)| kd == kind && d.abs() <= COHERENT_REACH * self.cap)
            && su * su + sv * sv <= MAX_SHEET_SLOPE * MAX_SHEET_SLOPE;
        if !coherent {
            // The ray nearest to P across the family (ties to the lower index).
            let r = usize::from(wu > 0.5) + 2 * usize::from(wv > 0.5);
            // Beside an edge of the material — some rays ending near P on one sheet, the others
            // air at P (an outer edge) or material (an inner one) — that sheet is one of the
            // edge's faces, and P's distance to it is measured (`edge_verdict` says what it
            // tells of P's side).
            let reach = COHERENT_REACH * self.cap;
            // What the nearest ray says, and where it passes: its centre less P's across.
            let mut offset = Vec3::ZERO;
            offset[l.u] = ((r & 1) as f64 - wu) * l.h[0];
            offset[l.v] = ((r >> 1) as f64 - wv) * l.h[1];
            let nearest = Nearest {
                inside: side(r),
                offset,
            };
            // The sheet an edge's rays end on: the nearest ray's, or else that of the nearest of
            // the rays that end near P; its rays are those ending near P with its kind (ends too
            // far apart for one sheet make it a step: `edge_distance`).
            // (The heaviest such ray, ties to the lower index: the nearest ray `r` when it ends
            // near P.)
            let w = [
                (1.0 - wu) * (1.0 - wv),
                wu * (1.0 - wv),
                (1.0 - wu) * wv,
                wu * wv,
            ];
            let ends_near = |q: usize| near[q].2 != 0 && near[q].0.abs() <= reach;
            let anchor = (0..4)
                .filter(|&q| ends_near(q))
                .reduce(|a, b| if w[b] > w[a] { b } else { a });
            if let Some(a) = anchor {
                let whole: [bool; 4] =
                    std::array::from_fn(|q| ends_near(q) && near[q].2 == near[a].2);
                // The anchor's sheet: its rays ending near P with its kind. Where those give no
                // measure — a step, as a wall's ends beside a floor's under a floor running just
                // below a row of rays beside a hole's wall, the rays above ending on the floor
                // further on — the anchor and its neighbour along either side of the cell, when
                // that one ends on the sheet too. A pair takes the sheet as level along the other
                // side, so only its word that P lies outside a face of an outer edge is taken
                // (the edge's verdict then stands against the vote); otherwise the vote.
                let pairs = [1, 2]
                    .map(|along| pair(whole, a, along))
                    .into_iter()
                    .filter(|p| p.iter().filter(|&&b| b).count() == 2 && *p != whole);
                for sheet in std::iter::once(whole).chain(pairs) {
                    // Beside an outer edge the other rays are air at P, beside an inner one
                    // material (with no other ray, both hold: no edge).
                    let mut others = (0..4).filter(|&q| !sheet[q]);
                    let outer = others.clone().all(|q| !side(q));
                    if outer == others.all(side) {
                        continue;
                    }
                    match edge_distance(k, l, &near, sheet, w, t) {
                        Some((d, n)) if sheet == whole || (outer && d < 0.0) => {
                            return FamilyDepth::Edge(d, n, outer, nearest, spacing);
                        }
                        _ => {}
                    }
                }
            }
            // The vote of the ray nearest to P.
            return FamilyDepth::Vote(nearest, spacing);
        }
        // Bilinear height field of the boundary sheet over the cell, and its gradient.
        let e = ends[0] * (1.0 - wu) * (1.0 - wv)
            + ends[1] * wu * (1.0 - wv)
            + ends[2] * (1.0 - wu) * wv
            + ends[3] * wu * wv;
        let de_du = ((ends[1] - ends[0]) * (1.0 - wv) + (ends[3] - ends[2]) * wv) * l.inv_h[0];
        let de_dv = ((ends[2] - ends[0]) * (1.0 - wu) + (ends[3] - ends[1]) * wu) * l.inv_h[1];
        let s = f64::from(kind);
        let along = s / (1.0 + de_du * de_du + de_dv * de_dv).sqrt();
        FamilyDepth::Coherent((t - e) * along, sheet_normal(k, along, de_du, de_dv))
    }
}

/// Of the rays on `sheet`, the anchor `a` and its neighbour along a side of the cell (`along`
/// 1: the other ray of its row, 2: of its column), when that one is on the sheet too; else
/// none.
fn pair(sheet: [bool; 4], a: usize, along: usize) -> [bool; 4] {
    let b = a ^ along;
    std::array::from_fn(|q| (q == a || q == b) && sheet[b])
}

/// `x.floor()` for the finite `x` of ray indices, inline (the library call is a tenth of a
/// probe's time on targets without a rounding instruction in their baseline).
#[inline(always)]
fn floor(x: f64) -> f64 {
    let i = x as i64 as f64;
    if i > x {
        i - 1.0
    } else {
        i
    }
}

/// Beside an edge of the material, the signed distance (positive inside) from the point at
/// `t` along the rays, at weights `w` of the four rays `near` (nearest ends as
/// [`nearest_end`] gives them), to the sheet that the rays of `sheet` end on, and its outward
/// normal; `None` where that sheet is steeper than a whole one may be (a step) or the weights
/// are not numbers. Out of line: the probe's other paths stay as compact as they were, and this
/// one runs only where the rays disagree.
#[cold]
#[inline(never)]
fn edge_distance(
    k: usize,
    l: &Lattice,
    near: &[(f64, f64, i8); 4],
    sheet: [bool; 4],
    w: [f64; 4],
    t: f64,
) -> Option<(f64, Vec3)> {
    let h = l.h;
    let kind = (0..4).find(|&q| sheet[q]).map_or(0, |q| near[q].2);
    let (mut sw, mut se) = (0.0, 0.0);
    for q in (0..4).filter(|&q| sheet[q]) {
        sw += w[q];
        se += w[q] * near[q].1;
    }
    // (NaN weights, from a NaN point, give no measure.)
    if kind == 0 || sw.is_nan() || sw <= 0.0 {
        return None;
    }
    // The sheet's slope across the family from the pairs of neighbouring rays that both end
    // on it (level where no pair does), as for a whole one.
    let slope = |pairs: [(usize, usize); 2], h: f64| {
        let (mut sum, mut count) = (0.0, 0.0);
        for (a, b) in pairs {
            if sheet[a] && sheet[b] {
                sum += near[b].1 - near[a].1;
                count += 1.0;
            }
        }
        if count > 0.0 {
            sum / (count * h)
        } else {
            0.0
        }
    };
    let (de_du, de_dv) = (slope([(0, 1), (2, 3)], h[0]), slope([(0, 2), (1, 3)], h[1]));
    // Ends this far apart between neighbours are a step, not a sheet (as for a whole one);
    // so are two diagonal ones with no neighbour between them on the sheet.
    let steep = de_du * de_du + de_dv * de_dv;
    let diagonal_step = [(0, 3), (1, 2)].iter().any(|&(a, b)| {
        sheet[a] && sheet[b] && (near[b].1 - near[a].1).abs() > MAX_SHEET_SLOPE * (h[0] + h[1])
    });
    if steep.is_nan() || steep > MAX_SHEET_SLOPE * MAX_SHEET_SLOPE || diagonal_step {
        return None;
    }
    let along = f64::from(kind) / (1.0 + steep).sqrt();
    Some(((t - se / sw) * along, sheet_normal(k, along, de_du, de_dv)))
}

/// The outward normal (out of the material) of a sheet `t = e(u, v)` of family `k` with
/// slopes `∂e/∂u`, `∂e/∂v` across it, the material on the rays' side `s` of it, given
/// `along = s/√(1 + |∇e|²)`: the distance grows into the material along `along·(e_k −
/// ∂e/∂u·e_u − ∂e/∂v·e_v)`, and the normal is its opposite. (One division, made by the
/// caller for the distance too; the components written by a constant index each, not by a
/// run-time one, which stored and reloaded the vector.)
#[inline(always)]
fn sheet_normal(k: usize, along: f64, de_du: f64, de_dv: f64) -> Vec3 {
    let (a, b, c) = (-along, along * de_du, along * de_dv);
    // Family k's cross axes are u = k + 1 and v = k + 2 (mod 3).
    match k {
        0 => Vec3::new(a, b, c),
        1 => Vec3::new(c, a, b),
        _ => Vec3::new(b, c, a),
    }
}

/// What the families' measures beside an edge (`(distance, outward normal, outer?)` each) say of
/// the point, given what the nearest rays of the families that are not coherent found there
/// (`(material?, offset from the point across the family)` each) and whether a deep family
/// found air: the measure that stands, or `None` for the vote.
///
/// At an outer edge the material is inside both faces. A point outside a face's sheet is
/// outside, whatever the other face: the nearest of those measures stands, against the vote,
/// whose nearest rays — up to half a spacing off — see a sheet slanted across them displaced by
/// its slope times that offset (a point 5 µm inside a bore's rim was voted 0.025 mm into the
/// material). A point inside the sheets is inside only if it is inside the other face too,
/// which a family across that face may see only at the ray spacing: a nearest ray that found
/// air where the sheets put material saw that face, and then the vote decides. A ray that
/// found air outside a sheet saw that sheet's own face and says nothing of the other: a point
/// 0.026 mm under a floor beside a hole's wall, whose X and Y rays nearest to it ran just above
/// the floor, was voted out of the material. At an inner edge the material lies on either
/// face's side: a point inside a sheet is inside (a point under a floor where it meets a wall
/// was voted out the same way); one outside the sheets may be inside the other face, which
/// the vote decides (the measure standing there put one-sample holes in a finishing raster's
/// engagement that the rays do not resolve). Outer and inner measures at one point contradict
/// each other: the vote. (The inner measures, and the outer ones whose other rays hold
/// material elsewhere along them, came with the hole's case: `tests/analytic_cases.rs`,
/// `helical_bore_enlarging_a_hole`.)
fn edge_verdict(
    edges: &[(f64, Vec3, bool)],
    nearest: &[(bool, Vec3)],
    deep_air: bool,
) -> Option<(f64, Vec3)> {
    let outer = edges.first()?.2;
    if edges.iter().any(|e| e.2 != outer) {
        return None;
    }
    if !outer {
        // Inside a sheet: the one it is deepest in.
        let &(d, n, _) = edges.iter().reduce(|a, b| if b.0 > a.0 { b } else { a })?;
        return (d > 0.0).then_some((d, n));
    }
    // Outside some sheet: the nearest of those faces. Inside every sheet: the nearest face.
    let outside = edges
        .iter()
        .filter(|e| e.0 < 0.0)
        .reduce(|a, b| if b.0 > a.0 { b } else { a });
    if let Some(&(d, n, _)) = outside {
        return Some((d, n));
    }
    let &(d, n, _) = edges.iter().reduce(|a, b| if b.0 < a.0 { b } else { a })?;
    // A nearest ray that found air at an offset `o` where every sheet puts material (each
    // sheet's distance along its normal) saw the other face.
    let other_face = deep_air
        || nearest.iter().any(|&(material, o)| {
            !material && edges.iter().all(|&(de, ne, _)| de - ne.dot(o) > 0.0)
        });
    (!other_face).then_some((d, n))
}

/// What a family's ray nearest to the point says: whether it holds material at the point's
/// coordinate along it, and where it passes (its centre less the point, across the family).
#[derive(Clone, Copy, Debug)]
struct Nearest {
    inside: bool,
    offset: Vec3,
}

/// How far (mm) a point at fractional ray index `f` lies beyond the outermost of `n` rays
/// spaced `h` apart (0 between them).
fn beyond_rays(f: f64, n: usize, h: f64) -> f64 {
    ((-f).max(f - (n as f64 - 1.0))).max(0.0) * h
}

enum FamilyDepth {
    /// The signed distance to the sheet the four rays agree on, and the sheet's outward normal.
    Coherent(f64, Vec3),
    /// Beside an outer edge of the material: the signed distance to the sheet that the rays
    /// holding material near the point agree on, the others holding none, and its outward
    /// normal; and, as a vote, the nearest ray's side (inside?) and the ray spacing.
    Edge(f64, Vec3, bool, Nearest, f64),
    /// The rays disagree: only the nearest ray's side and the ray spacing.
    Vote(Nearest, f64),
    /// All four rays on one side (inside?), their nearest end farther than the cap: that
    /// nearest end's distance along its ray, and the ray spacing.
    Deep(bool, f64, f64),
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_end_kinds() {
        let ray = [
            Interval {
                enter: 0.0,
                exit: 1.0,
            },
            Interval {
                enter: 2.0,
                exit: 5.0,
            },
        ];
        assert_eq!(nearest_end(&ray, 0.2), (0.2, 0.0, 1));
        assert_eq!(nearest_end(&ray, 0.9).2, -1);
        let (d, e, k) = nearest_end(&ray, 1.4);
        assert!((d + 0.4).abs() < 1e-15 && e == 1.0 && k == -1);
        let (d, e, k) = nearest_end(&ray, 1.7);
        assert!((d + 0.3).abs() < 1e-15 && e == 2.0 && k == 1);
        assert_eq!(nearest_end(&[], 1.0).2, 0);
        // A long ray (binary search) answers as a scan of its ends would, ties to the lower.
        let long: Vec<Interval> = (0..9)
            .map(|i| Interval {
                enter: 3.0 * i as f64,
                exit: 3.0 * i as f64 + 1.0 + 0.1 * i as f64,
            })
            .collect();
        for q in 0..300 {
            let t = -1.0 + 0.1 * q as f64;
            let mut scan = (f64::INFINITY, 0.0, 0i8);
            for iv in &long {
                for (e, kd) in [(iv.enter, 1), (iv.exit, -1)] {
                    if (t - e).abs() < scan.0 {
                        scan = ((t - e).abs(), e, kd);
                    }
                }
            }
            let (d, e, k) = nearest_end(&long, t);
            assert_eq!((e, k), (scan.1, scan.2), "t = {t}");
            assert_eq!(d, f64::from(k) * (t - e));
        }
    }

    #[test]
    fn inline_floor_is_floor() {
        for x in [
            -3.5,
            -3.0,
            -2.9999,
            -0.5,
            -0.0,
            0.0,
            1e-300,
            0.5,
            2.0,
            2.5,
            1e12 + 0.5,
        ] {
            assert_eq!(floor(x), x.floor(), "{x}");
        }
    }

    #[test]
    fn beside_an_edge_of_the_grid_is_not_deep() {
        // Beyond the outermost rays of two families and between none of the third: no ray
        // sees the box, yet it is 0.42 mm away; the probe must not call the point far outside
        // (the engagement interpolates depths between samples it calls far).
        let b = swarf_geom::Aabb::new(Vec3::ZERO, Vec3::splat(10.0));
        let stock = TriDexel::from_box(b.min, b.max, 0.25).unwrap();
        let probe = MaterialProbe::new(&stock);
        let p = Vec3::new(10.3, 10.3, 5.0);
        let d = probe.depth(p).distance;
        let truth = 0.3f64.hypot(0.3);
        assert!(d < 0.0 && -d <= truth, "{d}");
        // Far from the box it is deep, and says so.
        let d = probe.depth(Vec3::new(20.0, 20.0, 5.0)).distance;
        assert!(d <= -probe.cap, "{d}");
    }

    #[test]
    fn the_measured_sheet_s_normal_points_out_of_the_material() {
        // Near each face of a cube, inside and outside, the normal is the face's outward one;
        // under a plane sloping in x (a block cut by a ramp), the plane's.
        let b = swarf_geom::Aabb::new(Vec3::ZERO, Vec3::splat(10.0));
        let stock = TriDexel::from_box(b.min, b.max, 0.1).unwrap();
        let probe = MaterialProbe::new(&stock);
        for (p, n) in [
            (Vec3::new(5.02, 4.97, 9.93), Vec3::Z),
            (Vec3::new(5.02, 4.97, 10.03), Vec3::Z),
            (Vec3::new(0.06, 4.97, 5.01), -Vec3::X),
            (Vec3::new(5.02, 9.96, 5.01), Vec3::Y),
            (Vec3::new(5.02, 4.97, 0.02), -Vec3::Z),
        ] {
            let d = probe.depth(p);
            assert!((d.normal.unwrap() - n).length() < 1e-12, "{p}: {d:?}");
        }
        let slope = 0.2f64;
        let ramp = TriDexel::from_fn(b, 0.1, |k, cu, cv, d| {
            // The top at z = 5 + 0.2·x: along z the ray (x, y) = (cu, cv); along x the ray at
            // (y, z) = (cu, cv) holds x ≥ (z − 5)/0.2; along y the ray at (z, x) = (cu, cv).
            let (enter, exit) = match k {
                2 => (0.0, 5.0 + slope * cu),
                0 => (((cv - 5.0) / slope).max(0.0), 10.0),
                _ => (0.0, if cu <= 5.0 + slope * cv { 10.0 } else { -1.0 }),
            };
            if exit > enter {
                d.push(Interval { enter, exit });
            }
        })
        .unwrap();
        let probe = MaterialProbe::new(&ramp);
        let d = probe.depth(Vec3::new(5.03, 5.02, 5.95));
        let n = Vec3::new(-slope, 0.0, 1.0).normalize();
        assert!(d.distance > 0.0, "{d:?}");
        assert!((d.normal.unwrap() - n).length() < 1e-9, "{d:?} vs {n}");
    }

    #[test]
    fn beside_an_edge_of_the_material_the_nearer_face_is_measured() {
        // Within a ray spacing of the cube's edge x = 10, z = 10 no family's four rays all
        // end on one face. Inside, the distance is to the nearer face, exactly (the faces lie
        // on ray ends); beyond either face the point is outside.
        let b = swarf_geom::Aabb::new(Vec3::ZERO, Vec3::splat(10.0));
        let stock = TriDexel::from_box(b.min, b.max, 0.1).unwrap();
        let probe = MaterialProbe::new(&stock);
        let offsets = [-0.04, -0.01, 0.01, 0.02, 0.04];
        for a in offsets {
            for bz in offsets {
                let p = Vec3::new(10.0 - a, 5.02, 10.0 - bz);
                let d = probe.depth(p);
                if a > 0.0 && bz > 0.0 {
                    assert!(d.measured, "{a} {bz}: {d:?}");
                    assert!((d.distance - a.min(bz)).abs() < 1e-12, "{a} {bz}: {d:?}");
                } else {
                    assert!(d.distance < 0.0, "{a} {bz}: {d:?}");
                }
            }
        }
    }

    /// The block from `lo` to `hi` on a grid of rays 0.1 apart reaching 1 mm above it, less a
    /// hole of radius `hole` about the Z axis down to `bottom`.
    fn holed_block(lo: Vec3, hi: Vec3, hole: f64, bottom: f64) -> TriDexel {
        let b = swarf_geom::Aabb::new(lo, Vec3::new(hi.x, hi.y, hi.z.floor() + 1.0));
        TriDexel::from_fn(b, 0.1, |k, cu, cv, d| {
            let mut q = [0.0; 3];
            (q[(k + 1) % 3], q[(k + 2) % 3]) = (cu, cv);
            let mut push = |enter: f64, exit: f64| {
                if exit > enter {
                    d.push(Interval { enter, exit });
                }
            };
            if k == 2 {
                push(
                    lo.z,
                    if q[0].hypot(q[1]) < hole {
                        bottom
                    } else {
                        hi.z
                    },
                );
                return;
            }
            if q[2] > hi.z {
                return;
            }
            let across = q[1 - k];
            if q[2] > bottom && across.abs() < hole {
                let half = (hole * hole - across * across).sqrt();
                push(lo[k], -half);
                push(half, hi[k]);
            } else {
                push(lo[k], hi[k]);
            }
        })
        .unwrap()
    }

    #[test]
    fn just_inside_a_bore_under_its_rim_a_point_is_measured_outside() {
        // A bore of radius 8 down to z = -3 in a block whose top z = 0 is the grid's: points
        // 3 µm under the top and 1-10 µm inside the bore, all round it. The X and Y rays see
        // the wall, slanted across them; the nearest ones, up to half a spacing off, see it
        // up to 0.02 mm away, and voted some of these points 0.025 mm into the material.
        let (rb, floor) = (8.0f64, -3.0);
        let stock = holed_block(
            Vec3::new(-12.0, -12.0, -5.0),
            Vec3::new(12.0, 12.0, 0.0),
            rb,
            floor,
        );
        let probe = MaterialProbe::new(&stock);
        let mut worst = 0.0f64;
        for i in 0..360 {
            let a = (i as f64 + 0.37).to_radians();
            let radial = Vec3::new(a.cos(), a.sin(), 0.0);
            for inset in [1e-3, 2e-3, 5e-3, 1e-2] {
                let p = radial * (rb - inset) - Vec3::Z * 3e-3;
                let d = probe.depth(p);
                assert!(d.distance < 0.0, "{i}° {inset}: {d:?}");
                worst = worst.max((d.distance + inset).abs());
                // The sheet measured is the wall: its outward normal points into the bore.
                if let Some(n) = d.normal {
                    assert!(n.dot(-radial) > 0.99, "{i}° {inset}: {n:?}");
                }
            }
        }
        // The wall's distance to within its curvature between the rays.
        assert!(worst < 1e-3, "{worst}");
    }

    #[test]
    fn under_a_floor_beside_a_hole_the_floor_is_measured_though_the_nearest_rays_run_above_it() {
        // Material under a floor at z = 0.047, 3 µm under the row of X and Y rays at z = 0.05,
        // with a hole of radius 2 along Z: points 0.03 mm under the floor and 0.02-0.1 mm
        // beside the hole. The X and Y rays nearest to them run above the floor, in the air;
        // the Z rays measure the floor. Before, the vote of the first put such points out of
        // the material.
        let (rh, floor) = (2.0f64, 0.047);
        let stock = holed_block(Vec3::splat(-5.0), Vec3::new(5.0, 5.0, floor), rh, -5.0);
        let probe = MaterialProbe::new(&stock);
        for i in 0..72 {
            let a = (i as f64 * 5.0 + 1.3).to_radians();
            let radial = Vec3::new(a.cos(), a.sin(), 0.0);
            for beside in [0.02, 0.05, 0.1] {
                let p = radial * (rh + beside) + Vec3::Z * (floor - 0.03);
                let d = probe.depth(p);
                assert!(d.distance > 0.0, "{}° {beside}: {d:?}", i * 5);
                assert!(d.distance <= 0.03 + 1e-9, "{}° {beside}: {d:?}", i * 5);
            }
            // Inside the hole it is air.
            let p = radial * (rh - 0.05) + Vec3::Z * (floor - 0.03);
            assert!(probe.depth(p).distance < 0.0, "{}°", i * 5);
        }
    }

    #[test]
    fn beside_an_edge_between_the_rays_a_measure_never_contradicts_the_rays() {
        // Faces x = 9.97 and z = 10.03, between the ray centres 9.95 and 10.05: a point
        // beyond the face x = 9.97 (which only the X rays at z = 9.95 see, the nearest ones at
        // z = 10.05 being empty) but under z = 10.03 is outside, though the Z rays at x = 9.95
        // measure it 0.02 mm under their sheet.
        let b = swarf_geom::Aabb::new(Vec3::ZERO, Vec3::splat(10.2));
        let (x1, z1) = (9.97, 10.03);
        let stock = TriDexel::from_fn(b, 0.1, |k, cu, cv, d| {
            let (u, v) = ((k + 1) % 3, (k + 2) % 3);
            let mut q = [0.0; 3];
            (q[u], q[v]) = (cu, cv);
            let (hi, inside) = match k {
                0 => (x1, q[2] <= z1),
                2 => (z1, q[0] <= x1),
                _ => (10.2, q[0] <= x1 && q[2] <= z1),
            };
            if inside {
                d.push(Interval {
                    enter: 0.0,
                    exit: hi,
                });
            }
        })
        .unwrap();
        let probe = MaterialProbe::new(&stock);
        let d = probe.depth(Vec3::new(9.99, 5.02, 10.01));
        assert!(d.distance < 0.0, "{d:?}");
        // Under both faces, by more than half a spacing from the one between the Z rays: the
        // Z rays' sheet is measured.
        let d = probe.depth(Vec3::new(9.9, 5.02, 10.01));
        assert!(d.measured && (d.distance - 0.02).abs() < 1e-12, "{d:?}");
    }

    /// Material below the plane `n·x = 3` in a 10 mm cube, rays `h` apart, with `n` oblique to
    /// every family; and `n`.
    fn below_oblique_plane(h: f64) -> (Vec3, TriDexel) {
        let n = Vec3::new(0.3, -0.4, 0.866).normalize();
        let b = swarf_geom::Aabb::new(Vec3::splat(-5.0), Vec3::splat(5.0));
        let stock = TriDexel::from_fn(b, h, |k, cu, cv, d| {
            let (u, v) = ((k + 1) % 3, (k + 2) % 3);
            // Along the ray: n_k t + n_u cu + n_v cv <= 3.
            let rest = 3.0 - n[u] * cu - n[v] * cv;
            let t = rest / n[k];
            let (lo, hi) = if n[k] > 0.0 {
                (-5.0, t.min(5.0))
            } else {
                (t.max(-5.0), 5.0)
            };
            if hi > lo {
                d.push(Interval {
                    enter: lo,
                    exit: hi,
                });
            }
        })
        .unwrap();
        (n, stock)
    }

    #[test]
    fn points_about_a_cap_deep_are_measured_not_voted() {
        // Where some of a family's four ends fall just inside the cap and some just beyond,
        // the family still measures (clamped to the cap): a vote would report a quarter
        // spacing and make the engagement probe every sample around the point.
        let (n, stock) = below_oblique_plane(0.1);
        let probe = MaterialProbe::new(&stock);
        let mut measured = 0;
        for i in 0..400 {
            let s = 0.25 + 0.3 * i as f64 / 400.0; // 0.25–0.55 mm below the plane
            let base = Vec3::new(0.0137 * i as f64 - 2.0, 0.0071 * i as f64 - 1.0, 0.0);
            let base = base + n * (3.0 - n.dot(base));
            let d = probe.depth(base - n * s);
            assert!(d.distance > 0.0, "{s}: {d:?}");
            // Measured on the plane: the truth where it is well inside the cap; about a cap
            // deep, the cap (clamped, or a deep point's bound raised to it).
            if s < 0.3 {
                assert!((d.distance - s).abs() < 1e-9, "{s}: {d:?}");
            } else {
                assert!(
                    d.distance >= s.min(probe.cap) - 1e-9 && d.distance <= s.max(probe.cap),
                    "{s}: {d:?}"
                );
            }
            measured += usize::from(d.measured);
        }
        assert_eq!(measured, 400);
    }

    #[test]
    fn beside_a_wall_whose_rays_above_end_on_a_floor_further_on_the_wall_is_measured() {
        // Material where x ≥ x_w and z ≤ z_f + s·(x − x_w): a wall, and a floor rising gently
        // away from it (as a helix's floor beside the hole it enlarges). The X rays of the row
        // under the floor end on the wall; those of the row 12 µm above it end on the floor
        // 0.3 mm further on, with the same kind of end: the four together are a step. A point
        // 7 µm off the wall on the air side, 50 µm under the floor's level, is outside — though
        // the nearest Y and Z rays, half a spacing into the material, put it inside, and the
        // Z rays measure it under the floor (Aras fig. 6.13's hole: the entry read 0.63° early).
        let (h, x_w, z_f, s) = (0.1, 0.14, 0.138, 0.04);
        let b = swarf_geom::Aabb::new(Vec3::splat(-2.0), Vec3::splat(2.0));
        let floor = |x: f64| z_f + s * (x - x_w);
        let stock = TriDexel::from_fn(b, h, |k, cu, cv, d| match k {
            // (y, z): from the wall, or from where the floor rises above the ray.
            0 => {
                let from = x_w + ((cv - z_f) / s).max(0.0);
                if from < 2.0 {
                    d.push(Interval {
                        enter: from,
                        exit: 2.0,
                    });
                }
            }
            // (z, x): all along, or nothing.
            1 if cv >= x_w && cu <= floor(cv) => d.push(Interval {
                enter: -2.0,
                exit: 2.0,
            }),
            // (x, y): up to the floor.
            2 if cu >= x_w => d.push(Interval {
                enter: -2.0,
                exit: floor(cu),
            }),
            _ => {}
        })
        .unwrap();
        let probe = MaterialProbe::new(&stock);
        for y in [0.013, 0.031, 0.047, 0.069] {
            let p = Vec3::new(x_w - 0.007, y, z_f - 0.05);
            let d = probe.depth(p);
            assert!(d.measured, "{d:?}");
            assert!((d.distance + 0.007).abs() < 1e-9, "{d:?}");
            let n = d.normal.unwrap();
            assert!((n - Vec3::new(-1.0, 0.0, 0.0)).length() < 1e-9, "{d:?}");
        }
    }

    #[test]
    fn a_wall_along_the_rays_is_not_a_sheet() {
        // A step: material below z = 0 everywhere and up to z = H for x ≤ x_w, the wall
        // between two Z rays. Points inside the step, 0.04 mm from the wall, are inside and
        // that near the boundary: the Z rays on either side end at the top and at the floor
        // (ends of one kind), which is no sheet — the X rays across the wall measure it.
        let h = 0.1;
        for height in [0.3, 0.6, 1.0, 1.6] {
            let b = swarf_geom::Aabb::new(Vec3::splat(-2.0), Vec3::splat(2.0));
            // Rays at cell centres −1.95, …, 0.05, 0.15: the wall 0.09 past one, the points
            // halfway between the two.
            let x_w = 0.14;
            let stock = TriDexel::from_fn(b, h, |k, cu, cv, d| {
                let p = |t: f64| {
                    let mut q = [0.0; 3];
                    (q[k], q[(k + 1) % 3], q[(k + 2) % 3]) = (t, cu, cv);
                    q
                };
                // Along the ray, the material is where z ≤ 0, or x ≤ x_w and z ≤ H.
                let inside = |q: [f64; 3]| q[2] <= 0.0 || (q[0] <= x_w && q[2] <= height);
                match k {
                    2 => {
                        let top = if inside(p(height)) { height } else { 0.0 };
                        d.push(Interval {
                            enter: -2.0,
                            exit: top,
                        });
                    }
                    0 if inside(p(-2.0)) => d.push(Interval {
                        enter: -2.0,
                        exit: if cv <= 0.0 { 2.0 } else { x_w },
                    }),
                    1 if inside(p(0.0)) => d.push(Interval {
                        enter: -2.0,
                        exit: 2.0,
                    }),
                    _ => {}
                }
            })
            .unwrap();
            let probe = MaterialProbe::new(&stock);
            for i in 1..20 {
                let z = height * i as f64 / 20.0;
                let (below, above) = (z, height - z);
                if below.min(above) < 0.06 {
                    continue;
                }
                let p = Vec3::new(x_w - 0.04, 0.013 * i as f64, z);
                let d = probe.depth(p);
                assert!(
                    d.distance > 0.0 && d.distance <= 0.04 + 1e-9,
                    "H = {height}, z = {z}: {d:?}"
                );
            }
        }
    }

    #[test]
    fn the_nearest_ray_guess_reads_the_nearest_ray_of_each_family() {
        // Each family's guess is the material, at the point's coordinate along the rays, of
        // the ray whose centre is nearest across the family (found here by search): an
        // oblique plane, so that every family's rays end at different places. (Seen failing
        // with the two cross axes swapped in the per-family guess.)
        let h = 0.25;
        let (_, stock) = below_oblique_plane(h);
        let probe = MaterialProbe::new(&stock);
        let g = stock.grid();
        let (mut inside, mut total) = (0, 0);
        for q in 0..3000 {
            let f = |m: usize, p: usize| ((q * m) % p) as f64 / p as f64;
            let p = Vec3::new(
                11.0 * f(37, 1009) - 5.5,
                11.0 * f(53, 1013) - 5.5,
                11.0 * f(71, 1019) - 5.5,
            );
            for k in 0..3 {
                let (u, v) = ((k + 1) % 3, (k + 2) % 3);
                let fam = stock.family(k);
                let (nu, nv) = fam.dims();
                let centre = |axis: usize, i: usize| g.min[axis] + (i as f64 + 0.5) * g.h[axis];
                // Beside the grid (more than half a spacing beyond its outer rays): nothing.
                let beside = (0..2).any(|w| {
                    let (axis, n) = if w == 0 { (u, nu) } else { (v, nv) };
                    p[axis] < g.min[axis] || p[axis] > centre(axis, n - 1) + 0.5 * g.h[axis]
                });
                let nearest = |axis: usize, n: usize| {
                    (0..n)
                        .min_by(|&a, &b| {
                            (centre(axis, a) - p[axis])
                                .abs()
                                .total_cmp(&(centre(axis, b) - p[axis]).abs())
                        })
                        .unwrap()
                };
                let expected = !beside
                    && fam
                        .ray(nearest(u, nu), nearest(v, nv))
                        .iter()
                        .any(|iv| iv.enter <= p[k] && p[k] <= iv.exit);
                assert_eq!(
                    probe.inside_nearest_ray(k, p),
                    expected,
                    "family {k} at {p}"
                );
                inside += usize::from(expected);
                total += 1;
            }
        }
        // Both sides seen, in every family's share.
        assert!(
            inside > total / 5 && inside < total * 4 / 5,
            "{inside} of {total}"
        );
    }

    #[test]
    fn the_nearest_ray_guess_is_the_probes_side_away_from_the_boundary() {
        // Below an oblique plane, with the family most aligned with its normal (Z): points
        // farther than a ray spacing from the plane are guessed on the probe's side; nearer
        // ones may be guessed either way, but not all of them wrongly.
        let h = 0.25;
        let (n, stock) = below_oblique_plane(h);
        let probe = MaterialProbe::new(&stock);
        let (mut near, mut near_right) = (0, 0);
        for i in 0..2000 {
            let s = -0.6 + 1.2 * ((i * 7919) % 2000) as f64 / 2000.0;
            let (fx, fy) = (
                (i * 31 % 1000) as f64 / 1000.0,
                (i * 17 % 997) as f64 / 997.0,
            );
            let base = Vec3::new(6.0 * fx - 3.0, 4.0 * fy - 2.0, 0.0);
            let base = base + n * (3.0 - n.dot(base));
            let p = base - n * s;
            let guess = probe.inside_nearest_ray(2, p);
            let truth = probe.inside(p);
            assert_eq!(truth, s > 0.0, "{s}");
            if s.abs() > h {
                assert_eq!(guess, truth, "{s}");
            } else {
                near += 1;
                near_right += usize::from(guess == truth);
            }
        }
        assert!(near_right * 10 > near * 9, "{near_right} of {near}");
        // Beside the grid, nothing.
        assert!(!probe.inside_nearest_ray(2, Vec3::new(6.0, 0.0, -4.0)));
        assert!(!probe.inside_nearest_ray(0, Vec3::new(0.0, -5.2, -4.0)));
    }

    #[test]
    fn distance_to_an_oblique_plane_is_exact() {
        let (n, stock) = below_oblique_plane(0.25);
        let probe = MaterialProbe::new(&stock);
        for (i, s) in [-0.4, -0.1, -0.01, 0.003, 0.05, 0.3].iter().enumerate() {
            let base = Vec3::new(0.37 * i as f64 - 1.0, 0.11 * i as f64, 0.0);
            let base = base + n * (3.0 - n.dot(base));
            let p = base - n * *s; // depth s below the plane
            let d = probe.depth(p);
            assert!(d.measured);
            assert!((d.distance - s).abs() < 1e-9, "{s}: {d:?}");
        }
    }
}
