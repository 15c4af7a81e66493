//! Adding material: the union of swept volumes on the tri-dexel's rays.
//!
//! The stock removes sweeps; the envelope of a program (`swarf-envelope`) is the same exact
//! per-ray intervals united instead, on an empty tri-dexel ([`TriDexel::on_grid`]). One ray grid,
//! one contouring ([`TriDexel::to_mesh`]) and one volume for both.

use rayon::prelude::*;
use swarf_geom::math::Vec3;
use swarf_geom::Aabb;
use swarf_sweep::swept::Scratch;
use swarf_sweep::{SweepBound, SweptConvex};

use crate::dexel::{Dexel, Interval};
use crate::tridexel::{TriDexel, TILE, TILE_RAYS};

impl TriDexel {
    /// Adds (unites) the volumes `sweeps` to every ray they cross. Tiles are filled in parallel,
    /// each ray keeping its intervals sorted and merged (touching intervals merge; nothing is
    /// dropped, a tangent ray keeps its point). A ray skips the exact query of a sweep when its
    /// cheap outer bound along the ray (`bounds[i]`, [`SweepBound`]) misses or is already
    /// covered — inside the union, where the many overlapping sub-moves of a 5-axis move put most
    /// rays. Tile bounds grow with what is added. The added material has no provenance: a stock
    /// that tracked it stops tracking ([`TriDexel::tracks_provenance`] turns false).
    ///
    /// # Panics
    /// If `bounds` is not as long as `sweeps` (a caller's bug).
    pub fn unite_swept(&mut self, sweeps: &[SweptConvex<'_>], bounds: &[Option<SweepBound>]) {
        assert_eq!(sweeps.len(), bounds.len(), "one optional bound per sweep");
        let grid = *self.grid();
        let boxes: Vec<Aabb> = sweeps.iter().map(SweptConvex::bbox).collect();
        // Material may come back where the last instance was cut.
        self.last_instance = None;
        for fam in &mut self.families {
            fam.tags = Vec::new();
            let k = fam.axis;
            let (ua, va) = ((k + 1) % 3, (k + 2) % 3);
            let (nu, nv, ntu, bins) = (fam.nu, fam.nv, fam.ntu, fam.bins);
            fam.rays
                .par_chunks_mut(TILE_RAYS)
                .zip(fam.bounds.par_iter_mut())
                .enumerate()
                .for_each_init(Scratch::new, |scratch, (t, (tile, tile_bound))| {
                    let (i0, j0) = ((t % ntu) * TILE, (t / ntu) * TILE);
                    let (i1, j1) = ((i0 + TILE).min(nu) - 1, (j0 + TILE).min(nv) - 1);
                    for ((sw, b), bound) in sweeps.iter().zip(&boxes).zip(bounds) {
                        let (Some((a0, a1)), Some((c0, c1))) = (
                            grid.centers_in(ua, b.min[ua], b.max[ua]),
                            grid.centers_in(va, b.min[va], b.max[va]),
                        ) else {
                            continue;
                        };
                        let (a0, a1, c0, c1) = (a0.max(i0), a1.min(i1), c0.max(j0), c1.min(j1));
                        if a0 > a1 || c0 > c1 {
                            continue;
                        }
                        let mut rays = None;
                        for j in c0..=c1 {
                            for i in a0..=a1 {
                                let d = &mut tile[(j - j0) * TILE + (i - i0)];
                                let mut o = Vec3::ZERO;
                                o[ua] = grid.center(ua, i);
                                o[va] = grid.center(va, j);
                                if let Some(bd) = bound {
                                    match bd.range(o, k) {
                                        None => continue,
                                        Some((lo, hi)) if covered(d, lo, hi) => continue,
                                        Some(_) => {}
                                    }
                                }
                                // The closed forms of the stock's cut where the sweep has them.
                                let rays = rays.get_or_insert_with(|| sw.dexel_rays(k));
                                let at = (o[ua], o[va]);
                                if let Some((lo, hi)) = sw.dexel_interval(at, k, rays, scratch) {
                                    unite(d, lo, hi);
                                    tile_bound.add(lo, hi, &bins);
                                }
                            }
                        }
                    }
                });
        }
    }
}

/// Unites `[lo, hi]` with the sorted, disjoint intervals of `d`, merging what it overlaps or
/// touches.
fn unite(d: &mut Dexel, lo: f64, hi: f64) {
    // First interval that ends at or after lo; one past the last that starts at or before hi.
    let i = d.partition_point(|x| x.exit < lo);
    let j = d.partition_point(|x| x.enter <= hi);
    if i == j {
        d.insert(
            i,
            Interval {
                enter: lo,
                exit: hi,
            },
        );
        return;
    }
    let merged = Interval {
        enter: lo.min(d[i].enter),
        exit: hi.max(d[j - 1].exit),
    };
    d[i] = merged;
    d.drain(i + 1..j);
}

/// True when `[lo, hi]` lies inside one interval of the sorted, disjoint `d`.
fn covered(d: &[Interval], lo: f64, hi: f64) -> bool {
    let i = d.partition_point(|x| x.exit < hi);
    i < d.len() && d[i].enter <= lo
}

#[cfg(test)]
mod tests {
    use super::*;

    fn iv(a: f64, b: f64) -> Interval {
        Interval { enter: a, exit: b }
    }

    #[test]
    fn intervals_unite_and_cover() {
        let mut d = Dexel::new();
        for (a, b) in [(3.0, 4.0), (0.0, 1.0), (0.5, 2.0), (2.0, 2.5), (5.0, 6.0)] {
            unite(&mut d, a, b);
        }
        assert_eq!(&d[..], &[iv(0.0, 2.5), iv(3.0, 4.0), iv(5.0, 6.0)]);
        unite(&mut d, 2.4, 5.5);
        assert_eq!(&d[..], &[iv(0.0, 6.0)]);
        assert!(covered(&d, 1.0, 5.0) && !covered(&d, -1.0, 1.0) && !covered(&d, 5.0, 7.0));
        unite(&mut d, 7.0, 7.0);
        assert_eq!(&d[..], &[iv(0.0, 6.0), iv(7.0, 7.0)]);
    }
}
