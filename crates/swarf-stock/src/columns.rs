//! A coarse height map of the stock's material, from the Z rays' tile bounds: per tile of
//! `TILE × TILE` Z rays (1 mm square at h = 0.1 mm), the highest material end. A caller that
//! must know where the stock is air — without reading rays — asks [`ColumnTops::top_near`]:
//! above it, no Z ray near the point holds material.
//!
//! What it certifies is what the Z rays sample. The X and Y rays sample the same solid: an X
//! ray holding material at a point `p` more than half a ray spacing above every Z ray within
//! a spacing of `p` along X would hold, between the two Z rays on either side of `p`, an
//! interval that neither reaches — a sliver narrower than the ray spacing, which no reading of
//! the rays resolves anyway. (Stocks made from meshes that are not closed can make the three
//! families disagree; their readers refuse such meshes unless told otherwise.)

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
    /// tiles around them. The tiles' bounds are conservative (a tile a cut changed keeps its
    /// bound, at least as high as its material, until it is made exact again), so the map is
    /// too.
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
        let (ntu, ntv) = fam.tile_dims();
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
    /// mapped tiles, or `r` is negative or not a number. Every Z ray within `r` of the point
    /// along X and along Y is in such a tile.
    #[inline]
    pub fn top_near(&self, x: f64, y: f64, r: f64) -> f64 {
        // A ray's tile is that of its centre, `min + (i + ½)·h`, half a spacing inside it: the
        // square's tiles hold every ray within `r` (the square is grown by a hair all the
        // same, against the rounding of `x·inv_tile`). Relative to the first tile, and
        // truncated once known non-negative (no `floor`, a library call on the baseline
        // x86_64).
        if r.is_nan() || r < 0.0 {
            return f64::INFINITY;
        }
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
    use crate::tridexel::LinearMove;
    use crate::Interval;
    use swarf_geom::math::Vec3;
    use swarf_sweep::ToolShape;

    /// A 10 × 7.35 × 10 mm block (not square, not a whole number of tiles along Y, the ray
    /// spacings unequal) whose part `x > 6, y > 3` is cut down to z = 4.
    fn stepped() -> TriDexel {
        let b = Aabb::new(Vec3::ZERO, Vec3::new(10.0, 7.35, 10.0));
        TriDexel::from_fn(b, 0.1, |k, cu, cv, d| {
            // The cross axes are (y, z) for X rays, (z, x) for Y rays, (x, y) for Z rays.
            let (x, y, z) = match k {
                0 => (None, Some(cu), Some(cv)),
                1 => (Some(cv), None, Some(cu)),
                _ => (Some(cu), Some(cv), None),
            };
            let cut = |a: Option<f64>, lim: f64| a.is_none_or(|a| a > lim);
            let end = match k {
                _ if !(cut(x, 6.0) && cut(y, 3.0) && cut(z, 4.0)) => 10.0,
                0 => 6.0,
                1 => 3.0,
                _ => 4.0,
            };
            d.push(Interval {
                enter: 0.0,
                exit: end,
            });
        })
        .unwrap()
    }

    fn top_of(s: &TriDexel, i: usize, j: usize) -> f64 {
        s.family(2)
            .ray(i, j)
            .iter()
            .map(|iv| iv.exit)
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// From every point within `r` (along X and Y) of every ray of `s`, the map is at or
    /// above the ray's material; returns how many answers were below +∞.
    fn never_below(s: &TriDexel, m: &ColumnTops) -> usize {
        let grid = *s.grid();
        let (nu, nv) = s.family(2).dims();
        let mut claims = 0;
        for j in 0..nv {
            for i in 0..nu {
                let (x, y) = (grid.center(0, i), grid.center(1, j));
                for r in [0.0, 0.05, 0.125, 0.7] {
                    for (dx, dy) in [(-r, -r), (r, r), (r, -r), (-r, r), (0.0, 0.0)] {
                        let top = m.top_near(x + dx, y + dy, r);
                        assert!(top >= top_of(s, i, j), "ray ({i}, {j}), r {r}: {top}");
                        claims += usize::from(top < f64::INFINITY);
                    }
                }
            }
        }
        claims
    }

    #[test]
    fn the_map_is_never_below_the_material_of_a_ray_near_and_tight_a_tile_away() {
        let s = stepped();
        let h = s.grid().h;
        assert!(h[0] != h[1], "{h:?}");
        let mut m = ColumnTops::new();
        m.fill(&s, &Aabb::new(Vec3::ZERO, Vec3::new(10.0, 7.35, 10.0)));
        assert!(never_below(&s, &m) > 0);
        let grid = *s.grid();
        let (nu, nv) = s.family(2).dims();
        for j in 0..nv {
            for i in 0..nu {
                let (x, y) = (grid.center(0, i), grid.center(1, j));
                // A tile and r past the step's edges (the tiles there hold only the floor),
                // the floor; a tile short of them, the top.
                if x > 7.2 && y > 4.2 && x < 9.9 && y < 7.2 {
                    assert_eq!(m.top_near(x, y, 0.125), 4.0, "({x}, {y})");
                }
                // (Within r of the grid's edge the square leaves the tiles: no claim.)
                if (x < 4.8 || y < 1.8) && x > 0.2 && y > 0.2 && x < 9.8 && y < 7.1 {
                    assert_eq!(m.top_near(x, y, 0.125), 10.0, "({x}, {y})");
                }
            }
        }
        // Beside the step along X only: the floor's tiles on one side, the top's on the other.
        assert_eq!(m.top_near(8.5, 5.0, 0.1), 4.0);
        assert_eq!(m.top_near(8.5, 2.5, 0.1), 10.0);
        // Maps of boxes inside (their first tiles not the grid's): the same answers, from the
        // right tiles (a tile's neighbours along X and along Y differ here), and none beyond
        // their tiles and the ring of tiles around them.
        m.fill(
            &s,
            &Aabb::new(Vec3::new(8.2, 5.2, 0.0), Vec3::new(8.8, 5.8, 10.0)),
        );
        assert_eq!(m.top_near(8.5, 5.5, 0.1), 4.0);
        assert_eq!(m.top_near(7.5, 4.5, 0.3), 4.0);
        assert_eq!(m.top_near(8.5, 6.8, 0.1), 4.0);
        assert_eq!(m.top_near(8.5, 7.0, 0.1), f64::INFINITY);
        assert_eq!(m.top_near(6.5, 5.5, 0.1), f64::INFINITY);
        assert_eq!(m.top_near(8.5, 3.5, 0.1), f64::INFINITY);
        m.fill(
            &s,
            &Aabb::new(Vec3::new(5.2, 2.2, 0.0), Vec3::new(5.8, 2.8, 10.0)),
        );
        assert_eq!(m.top_near(6.5, 3.5, 0.1), 4.0);
        assert_eq!(m.top_near(5.5, 3.5, 0.1), 10.0);
        assert_eq!(m.top_near(6.5, 2.5, 0.1), 10.0);
        assert_eq!(m.top_near(6.2, 3.5, 0.3), 10.0);
        assert_eq!(m.top_near(3.5, 2.5, 0.1), f64::INFINITY);
        // No claim for a point or a radius that is not a number, nor a negative radius.
        for (x, y, r) in [
            (f64::NAN, 5.5, 0.1),
            (8.5, f64::NAN, 0.1),
            (8.5, 5.5, f64::NAN),
            (8.5, 5.5, -0.1),
            (f64::INFINITY, 5.5, 0.1),
        ] {
            assert_eq!(m.top_near(x, y, r), f64::INFINITY, "({x}, {y}, {r})");
        }
    }

    #[test]
    fn the_map_of_a_cut_stock_holds_its_material_before_and_after_the_bounds_are_refreshed() {
        // A ball's raster leaves tiles whose bounds are stale (higher than their material).
        let b = Aabb::new(Vec3::ZERO, Vec3::new(9.0, 7.0, 4.0));
        let mut s = TriDexel::from_box(b.min, b.max, 0.1).unwrap();
        let tool = ToolShape::new(&swarf_tool::Cutter::ball(3.0).unwrap());
        let tips: Vec<Vec3> = (0..40)
            .map(|i| {
                let (pass, t) = (i / 10, (i % 10) as f64 * 0.9);
                let x = if pass % 2 == 0 { t } else { 8.1 - t };
                Vec3::new(x, 1.0 + pass as f64 * 1.3, 2.5 + 0.3 * (x * 0.7).sin())
            })
            .collect();
        s.cut_linear_batch(&tool, &LinearMove::chain(&tips, Vec3::Z));
        let mut m = ColumnTops::new();
        m.fill(&s, &b);
        let before = never_below(&s, &m);
        s.refresh_stale_bounds();
        m.fill(&s, &b);
        assert_eq!(never_below(&s, &m), before);
        // Where the raster ran, the map came down from the block's top.
        assert!(m.top_near(4.0, 2.3, 0.1) < 4.0);
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
