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
//! curvature `κ`. Near a sheet parallel to a family the four rays straddle it (some inside, some
//! not): that family is not **coherent** there and says nothing; another, transverse to the
//! sheet, does. Of the coherent families the nearest sheet wins (the distance to a solid's
//! boundary is the distance to its nearest face). Only near an edge of the stock — within a ray
//! spacing of two faces at once — may no family be coherent: the rays nearest to `P` then vote
//! on the side, and the distance is reported as a fraction of the spacing.
//!
//! Far from the boundary no family is coherent either, but then all twelve rays agree on the
//! side and their nearest ends are all farther than the probe's precision cap `D₀ = 4h`: the
//! point is **deep**, and `D/√3 − 2h` (`D` the nearest of those ends along its ray) is a lower
//! bound of its distance to any boundary the rays resolve — a sheet at distance `δ` crosses the
//! rays of the family most aligned with its normal (within 54.7°) at most `√3·(δ + √2·h)` away —
//! reported as at least `D₀`. The engagement uses that bound to skip samples that cannot be near
//! the boundary.

use swarf_geom::math::Vec3;
use swarf_stock::{Interval, TriDexel};

/// What the rays say about a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Depth {
    /// Signed distance to the stock's boundary, mm: positive inside the material.
    pub distance: f64,
    /// True when a coherent family measured it; false when the rays only voted on the side.
    pub measured: bool,
}

/// Point queries against a stock. Cheap to make; borrows the stock.
#[derive(Clone, Copy, Debug)]
pub struct MaterialProbe<'a> {
    stock: &'a TriDexel,
    /// Distances beyond this (mm) need no precision: the point is deep inside or far outside.
    cap: f64,
}

/// The nearest interval end to `t` on one ray: signed distance along the ray (positive in the
/// material), and which kind of end it is (`+1`: an entry, the material on the ray's positive
/// side; `−1`: an exit). `None` for a ray without material.
#[inline]
fn nearest_end(ray: &[Interval], t: f64) -> Option<(f64, f64, i8)> {
    if ray.len() <= SHORT_RAY {
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
        return (kind != 0).then(|| (f64::from(kind) * (t - end), end, kind));
    }
    // The ends are sorted: only the last interval starting at or below t (its two ends) and
    // the first starting above it (its entry) can be nearest. Ties go to the lower end, as a
    // scan from the start would give them.
    let k = ray.partition_point(|iv| iv.enter <= t);
    let mut best: Option<(f64, i8)> = None;
    let mut consider = |end: f64, kind: i8| {
        if best.map_or(true, |(b, _)| (t - end).abs() < (t - b).abs()) {
            best = Some((end, kind));
        }
    };
    if k > 0 {
        consider(ray[k - 1].enter, 1);
        consider(ray[k - 1].exit, -1);
    }
    if let Some(iv) = ray.get(k) {
        consider(iv.enter, 1);
    }
    best.map(|(end, kind)| (f64::from(kind) * (t - end), end, kind))
}

/// Rays with at most this many intervals are scanned whole for their nearest end.
const SHORT_RAY: usize = 4;

impl<'a> MaterialProbe<'a> {
    /// A probe of `stock`.
    pub fn new(stock: &'a TriDexel) -> Self {
        let h = stock.grid().h;
        Self {
            stock,
            cap: 4.0 * h[0].max(h[1]).max(h[2]),
        }
    }

    /// The stock probed.
    pub fn stock(&self) -> &'a TriDexel {
        self.stock
    }

    /// The signed distance of `p` to the boundary of the material (positive inside).
    pub fn depth(&self, p: Vec3) -> Depth {
        let mut best: Option<f64> = None;
        let mut votes = 0i32;
        let mut vote_scale = 0.0f64;
        // Deep families: how many, and the nearest end among them.
        let (mut deep, mut deep_inside, mut deep_near) = (0, 0, f64::INFINITY);
        for k in 0..3 {
            match self.family_depth(k, p) {
                FamilyDepth::Coherent(d) => {
                    if best.map_or(true, |b| d.abs() < b.abs()) {
                        best = Some(d);
                    }
                }
                FamilyDepth::Vote(inside, spacing) => {
                    votes += if inside { 1 } else { -1 };
                    vote_scale = vote_scale.max(spacing);
                }
                FamilyDepth::Deep(inside, near, spacing) => {
                    votes += if inside { 1 } else { -1 };
                    vote_scale = vote_scale.max(spacing);
                    deep += 1;
                    deep_inside += i32::from(inside);
                    deep_near = deep_near.min(near);
                }
            }
        }
        if deep == 3 && (deep_inside == 0 || deep_inside == 3) {
            let bound = (deep_near / 3f64.sqrt() - 2.0 * vote_scale).max(self.cap);
            return Depth {
                distance: if deep_inside == 3 { bound } else { -bound },
                measured: true,
            };
        }
        match best {
            Some(d) => Depth {
                distance: d.clamp(-self.cap, self.cap),
                measured: true,
            },
            None => Depth {
                // Three votes: a tie is impossible.
                distance: f64::from(votes.signum()) * 0.25 * vote_scale,
                measured: false,
            },
        }
    }

    /// True when `p` is inside the material (by [`MaterialProbe::depth`]).
    pub fn inside(&self, p: Vec3) -> bool {
        self.depth(p).distance > 0.0
    }

    fn family_depth(&self, k: usize, p: Vec3) -> FamilyDepth {
        let g = self.stock.grid();
        let fam = self.stock.family(k);
        let (u, v) = ((k + 1) % 3, (k + 2) % 3);
        let (nu, nv) = fam.dims();
        let fu = (p[u] - g.min[u]) / g.h[u] - 0.5;
        let fv = (p[v] - g.min[v]) / g.h[v] - 0.5;
        let (i0, j0) = (fu.floor(), fv.floor());
        let (wu, wv) = (fu - i0, fv - j0);
        let t = p[k];
        let spacing = g.h[u].max(g.h[v]);
        // The four rays: (di, dj) in {0,1}².
        let mut ends = [0.0f64; 4];
        let mut kind = 0i8;
        let mut coherent = true;
        let mut nearest = (f64::INFINITY, false);
        // Whether all four rays are far from any end on one side, and the nearest end.
        let (mut far_side, mut far_near) = (None::<bool>, f64::INFINITY);
        let mut far = true;
        for (r, (di, dj)) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
            .into_iter()
            .enumerate()
        {
            let (i, j) = (i0 + di, j0 + dj);
            let outside = i < 0.0 || j < 0.0 || i >= nu as f64 || j >= nv as f64;
            let ray: &[Interval] = if outside {
                &[]
            } else {
                fam.ray(i as usize, j as usize)
            };
            let near = nearest_end(ray, t);
            // The vote of the ray nearest to P across the family.
            let dist2 = (wu - di).powi(2) + (wv - dj).powi(2);
            if dist2 < nearest.0 {
                nearest = (dist2, near.is_some_and(|(d, _, _)| d > 0.0));
            }
            let (side, gap) = match near {
                Some((d, _, _)) => (d > 0.0, d.abs()),
                // No ray there to see a sheet: the material may come as near as the grid's
                // edge, a ray spacing beyond the outermost rays.
                None if outside => (
                    false,
                    beyond_rays(fu, nu, g.h[u]).hypot(beyond_rays(fv, nv, g.h[v])) - spacing,
                ),
                None => (false, f64::INFINITY),
            };
            far &= gap > self.cap && far_side.map_or(true, |s| s == side);
            far_side = Some(side);
            far_near = far_near.min(gap);
            match near {
                Some((d, end, kd)) if d.abs() <= self.cap => {
                    if kind == 0 {
                        kind = kd;
                    } else if kind != kd {
                        coherent = false;
                    }
                    ends[r] = end;
                }
                _ => coherent = false,
            }
        }
        if far {
            return FamilyDepth::Deep(far_side.unwrap_or(false), far_near, spacing);
        }
        if !coherent {
            return FamilyDepth::Vote(nearest.1, spacing);
        }
        // Bilinear height field of the boundary sheet over the cell, and its gradient.
        let e = ends[0] * (1.0 - wu) * (1.0 - wv)
            + ends[1] * wu * (1.0 - wv)
            + ends[2] * (1.0 - wu) * wv
            + ends[3] * wu * wv;
        let de_du = ((ends[1] - ends[0]) * (1.0 - wv) + (ends[3] - ends[2]) * wv) / g.h[u];
        let de_dv = ((ends[2] - ends[0]) * (1.0 - wu) + (ends[3] - ends[1]) * wu) / g.h[v];
        let s = f64::from(kind);
        FamilyDepth::Coherent(s * (t - e) / (1.0 + de_du * de_du + de_dv * de_dv).sqrt())
    }
}

/// How far (mm) a point at fractional ray index `f` lies beyond the outermost of `n` rays
/// spaced `h` apart (0 between them).
fn beyond_rays(f: f64, n: usize, h: f64) -> f64 {
    ((-f).max(f - (n as f64 - 1.0))).max(0.0) * h
}

enum FamilyDepth {
    /// The signed distance to the sheet the four rays agree on.
    Coherent(f64),
    /// The rays disagree: only the nearest ray's side (inside?) and the ray spacing.
    Vote(bool, f64),
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
        assert_eq!(nearest_end(&ray, 0.2), Some((0.2, 0.0, 1)));
        assert_eq!(nearest_end(&ray, 0.9).map(|x| x.2), Some(-1));
        let (d, e, k) = nearest_end(&ray, 1.4).unwrap();
        assert!((d + 0.4).abs() < 1e-15 && e == 1.0 && k == -1);
        let (d, e, k) = nearest_end(&ray, 1.7).unwrap();
        assert!((d + 0.3).abs() < 1e-15 && e == 2.0 && k == 1);
        assert_eq!(nearest_end(&[], 1.0), None);
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
    fn distance_to_an_oblique_plane_is_exact() {
        // Material below the plane n·x = 3 with n oblique to every family.
        let n = Vec3::new(0.3, -0.4, 0.866).normalize();
        let h = 0.25;
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
