//! A coarse height map of the stock's material, from the Z rays' tile bounds: per tile of
//! `TILE × TILE` Z rays (1 mm square at h = 0.1 mm), the highest material end. A caller that
//! must know where the stock is air — without reading rays — asks [`ColumnTops::top_near`]:
//! above it, no Z ray near the point holds material.
//!
//! What it certifies is what the Z rays sample. The X and Y rays sample the same solid, so a
//! point well above the map (a few ray spacings) is air for them too, except inside a feature
//! that every Z ray around it misses — a sliver of material thinner than the ray spacing
//! standing above the rays beside it, which no ray-based reading resolves anyway.

use swarf_geom::Aabb;

use crate::tridexel::{TriDexel, TILE};

/// The highest material of each tile of Z rays over a box's footprint and one tile around it
/// ([`ColumnTops::fill`]); reused from one box to the next without allocating.
#[derive(Clone, Debug, Default)]
pub struct ColumnTops {
    /// The map's size in tiles (along X, Y; also as floats, compared with per query).
    dims: [usize; 2],
    dims_f: [f64; 2],
    /// A point's tile coordinate relative to the map's first tile is `x·inv_tile − offset`
    /// (`offset`: the grid corner over the tile's width plus the first tile's index).
    inv_tile: [f64; 2],
    offset: [f64; 2],
    /// Row-major along X: each tile's highest material end (−∞: none).
    tops: Vec<f64>,
}

impl ColumnTops {
    /// An empty map: [`ColumnTops::top_near`] is +∞ (no claim) everywhere until filled.
    pub fn new() -> Self {
        Self::default()
    }

    /// Maps the tiles of the Z rays whose centres lie in `bbox`'s footprint (X, Y), and the
    /// tiles around them. The tiles' bounds are conservative (a tile marked stale keeps a
    /// bound at least as high as its material), so the map is too.
    pub fn fill(&mut self, stock: &TriDexel, bbox: &Aabb) {
        self.dims = [0, 0];
        self.dims_f = [0.0, 0.0];
        self.tops.clear();
        let grid = stock.grid();
        let (Some((i0, i1)), Some((j0, j1))) = (
            grid.centers_in(0, bbox.min.x, bbox.max.x),
            grid.centers_in(1, bbox.min.y, bbox.max.y),
        ) else {
            return;
        };
        let fam = stock.family(2);
        let (ntu, ntv) = (grid.n[0].div_ceil(TILE), grid.n[1].div_ceil(TILE));
        let (ti0, tj0) = ((i0 / TILE).saturating_sub(1), (j0 / TILE).saturating_sub(1));
        let (ti1, tj1) = ((i1 / TILE + 1).min(ntu - 1), (j1 / TILE + 1).min(ntv - 1));
        self.dims = [ti1 - ti0 + 1, tj1 - tj0 + 1];
        self.dims_f = self.dims.map(|d| d as f64);
        self.inv_tile = [0, 1].map(|k| 1.0 / (grid.h[k] * TILE as f64));
        self.offset = [(0, ti0), (1, tj0)].map(|(k, t)| grid.min[k] * self.inv_tile[k] + t as f64);
        for tj in tj0..=tj1 {
            self.tops.extend((ti0..=ti1).map(|ti| fam.tile_hi(ti, tj)));
        }
    }

    /// The highest material end of the Z rays whose tiles meet the square of half-side `r`
    /// about `(x, y)` (−∞ where they hold none); +∞ (no claim) where the square leaves the
    /// mapped tiles. Every Z ray within `r` of the point along X and along Y is in such a
    /// tile.
    #[inline]
    pub fn top_near(&self, x: f64, y: f64, r: f64) -> f64 {
        // A ray's tile is ⌊(x − min)/(h·TILE)⌋ (that of ⌊(x − min)/h⌋, the ray's index); the
        // square is grown by a hair so that the two roundings cannot part at a tile's border.
        // Relative to the first tile and truncated once known non-negative (no `floor`, a
        // library call on the baseline x86_64).
        let r = r * (1.0 + 1e-9) + 1e-9;
        let (a0, a1) = (
            (x - r) * self.inv_tile[0] - self.offset[0],
            (x + r) * self.inv_tile[0] - self.offset[0],
        );
        let (b0, b1) = (
            (y - r) * self.inv_tile[1] - self.offset[1],
            (y + r) * self.inv_tile[1] - self.offset[1],
        );
        if !(a0 >= 0.0 && b0 >= 0.0 && a1 < self.dims_f[0] && b1 < self.dims_f[1]) {
            return f64::INFINITY;
        }
        let (a0, a1, b0, b1) = (a0 as usize, a1 as usize, b0 as usize, b1 as usize);
        let mut top = f64::NEG_INFINITY;
        for b in b0..=b1 {
            for &t in &self.tops[b * self.dims[0] + a0..=b * self.dims[0] + a1] {
                top = top.max(t);
            }
        }
        top
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Interval;
    use swarf_geom::math::Vec3;

    /// A 10 × 10 × 10 mm block whose quarter `x > 6, y > 6` is cut down to z = 4.
    fn stepped() -> TriDexel {
        let b = Aabb::new(Vec3::ZERO, Vec3::splat(10.0));
        TriDexel::from_fn(b, 0.1, |k, cu, cv, d| {
            // The cross axes are (y, z) for X rays, (z, x) for Y rays, (x, y) for Z rays.
            let (x, y, z) = match k {
                0 => (None, Some(cu), Some(cv)),
                1 => (Some(cv), None, Some(cu)),
                _ => (Some(cu), Some(cv), None),
            };
            let cut = |a: Option<f64>, lim: f64| a.map_or(true, |a| a > lim);
            let end = if cut(x, 6.0) && cut(y, 6.0) && cut(z, 4.0) {
                if k == 2 {
                    4.0
                } else {
                    6.0
                }
            } else {
                10.0
            };
            d.push(Interval {
                enter: 0.0,
                exit: end,
            });
        })
        .unwrap()
    }

    #[test]
    fn the_map_is_never_below_the_material_of_a_ray_near_and_tight_a_tile_away() {
        let s = stepped();
        let mut m = ColumnTops::new();
        m.fill(&s, &Aabb::new(Vec3::ZERO, Vec3::splat(10.0)));
        let fam = s.family(2);
        let grid = *s.grid();
        let (nu, nv) = fam.dims();
        let top_of = |i: usize, j: usize| {
            fam.ray(i, j)
                .iter()
                .map(|iv| iv.exit)
                .fold(f64::NEG_INFINITY, f64::max)
        };
        for j in 0..nv {
            for i in 0..nu {
                let (x, y) = (grid.center(0, i), grid.center(1, j));
                // From any point within r (along each axis) of the ray, the ray is near.
                for r in [0.0, 0.05, 0.125, 0.7] {
                    for (dx, dy) in [(-r, -r), (r, r), (r, -r), (0.0, 0.0)] {
                        let top = m.top_near(x + dx, y + dy, r);
                        assert!(top >= top_of(i, j), "ray ({i}, {j}), r {r}: {top}");
                    }
                }
                // Past the cut quarter's edge by more than a tile and r, the floor.
                if x > 7.2 && y > 7.2 && x < 9.9 && y < 9.9 {
                    assert_eq!(m.top_near(x, y, 0.125), 4.0, "({x}, {y})");
                }
            }
        }
        // Nearer the step, a tile that holds the top.
        assert_eq!(m.top_near(6.5, 6.5, 0.6), 10.0);
        // Beyond the mapped tiles (the box and a tile around it): no claim.
        m.fill(
            &s,
            &Aabb::new(Vec3::new(2.0, 2.0, 0.0), Vec3::new(4.0, 4.0, 10.0)),
        );
        assert_eq!(m.top_near(3.0, 3.0, 0.1), 10.0);
        assert_eq!(m.top_near(0.5, 3.0, 0.1), f64::INFINITY);
        assert_eq!(m.top_near(3.0, 5.95, 0.1), f64::INFINITY);
    }

    #[test]
    fn an_unfilled_or_empty_map_claims_nothing() {
        let m = ColumnTops::new();
        assert_eq!(m.top_near(0.0, 0.0, 0.1), f64::INFINITY);
        let s = stepped();
        let mut m = ColumnTops::new();
        m.fill(&s, &Aabb::new(Vec3::splat(20.0), Vec3::splat(30.0)));
        assert_eq!(m.top_near(25.0, 25.0, 0.1), f64::INFINITY);
    }
}
