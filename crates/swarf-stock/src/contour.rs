//! The machined part as a closed triangle mesh: the tri-dexel is Hermite data for dual
//! contouring (`swarf-io`), with all three ray families used — inside/outside of the lattice
//! points and the exact crossing of every lattice edge come from the ray that edge lies on, so
//! vertical walls (crossed by X and Y rays) are as crisp as floors (crossed by Z rays).
//!
//! The lattice is the grid of ray crossings: lattice point (i, j, k) is where the X ray (j, k),
//! the Y ray (k, i) and the Z ray (i, j) meet, at cell centres of the stock's grid.

use swarf_geom::math::Vec3;
use swarf_io::{
    dual_contour_projected, dual_contour_projected_owned, dual_contour_with_stats, ContourOptions,
    ContourStats, HermiteGrid, Lattice, Span, TriMesh,
};

use crate::TriDexel;

impl HermiteGrid for TriDexel {
    fn lattice(&self) -> Lattice {
        // The grid's own cell size (for a stock grid, what `Lattice::cell_centres` of its box
        // computes; for a cubic grid, exactly its `h`).
        let g = self.grid();
        let h = Vec3::from(g.h);
        Lattice::new(g.min + 0.5 * h, h, g.n)
    }

    fn line_spans(&self, axis: usize, u: usize, v: usize, out: &mut Vec<Span>) {
        out.extend(self.family(axis).ray(u, v).iter().map(|iv| Span {
            enter: iv.enter,
            exit: iv.exit,
        }));
    }
}

impl TriDexel {
    /// The stock's surface as a closed, outward-oriented triangle mesh (see the module docs).
    ///
    /// ```
    /// use swarf_geom::math::Vec3;
    /// use swarf_stock::TriDexel;
    /// let stock = TriDexel::from_box(Vec3::ZERO, Vec3::new(10.0, 6.0, 4.0), 0.5).unwrap();
    /// let (mesh, _) = stock.to_mesh(&Default::default());
    /// assert!(mesh.is_closed());
    /// assert!((mesh.volume() - 240.0).abs() < 1e-9);
    /// ```
    pub fn to_mesh(&self, options: &ContourOptions) -> (TriMesh, ContourStats) {
        dual_contour_with_stats(self, options)
    }

    /// [`TriDexel::to_mesh`] with every vertex moved by `project` (its position and unit
    /// normal; `None` leaves it) before the mesh is made safe for `f32` storage: for a solid
    /// whose surface is known exactly (`swarf_io::dual_contour_projected`).
    pub fn to_mesh_projected<P>(
        &self,
        options: &ContourOptions,
        project: P,
    ) -> (TriMesh, ContourStats)
    where
        P: Fn(Vec3, Vec3) -> Option<Vec3> + Sync,
    {
        dual_contour_projected(self, options, project)
    }

    /// [`TriDexel::to_mesh_projected`] consuming the stock: its rays are dropped once the
    /// contouring has read them, before the extraction where a large mesh peaks (the same
    /// mesh; the rays' memory is free at the peak).
    pub fn into_mesh_projected<P>(
        self,
        options: &ContourOptions,
        project: P,
    ) -> (TriMesh, ContourStats)
    where
        P: Fn(Vec3, Vec3) -> Option<Vec3> + Sync,
    {
        dual_contour_projected_owned(self, options, project)
    }

    /// The size of [`TriDexel::to_mesh`]'s mesh, without building it: `(vertices, triangles)`.
    ///
    /// Dual contouring makes one quad (two triangles) per lattice edge the surface crosses, and
    /// every crossing is an end of an interval of the ray that edge lies on: two triangles per
    /// interval end bound the triangles from above (exact unless an interval begins and ends
    /// within one edge). Vertices are estimated as a closed mesh of that many triangles has
    /// them (Euler: V = T/2 + 2 for a sphere-like part).
    ///
    /// ```
    /// use swarf_geom::math::Vec3;
    /// use swarf_stock::TriDexel;
    /// let stock = TriDexel::from_box(Vec3::ZERO, Vec3::new(10.0, 6.0, 4.0), 0.5).unwrap();
    /// let (v, t) = stock.mesh_size_estimate();
    /// let (mesh, _) = stock.to_mesh(&Default::default());
    /// assert_eq!(t, mesh.triangles.len() as u64);
    /// assert_eq!(v, mesh.vertices.len() as u64);
    /// ```
    pub fn mesh_size_estimate(&self) -> (u64, u64) {
        let triangles = 4 * self.stats().intervals;
        (triangles / 2 + 2, triangles)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn consuming_the_stock_gives_the_same_mesh() {
        // A block with a ball-shaped pocket, its vertices nudged by a projection: the rays
        // dropped before the extraction change nothing.
        let b = swarf_geom::Aabb::new(Vec3::ZERO, Vec3::new(6.0, 5.0, 4.0));
        let centre = Vec3::new(3.0, 2.5, 4.0);
        let stock = TriDexel::from_fn(b, 0.25, |k, cu, cv, d| {
            let (u, v) = ((k + 1) % 3, (k + 2) % 3);
            let (lo, hi) = (b.min[k], b.max[k]);
            let (du, dv) = (cu - centre[u], cv - centre[v]);
            let r2 = 4.0 - du * du - dv * dv;
            if r2 <= 0.0 {
                d.push(crate::Interval {
                    enter: lo,
                    exit: hi,
                });
                return;
            }
            let (a, c) = (centre[k] - r2.sqrt(), centre[k] + r2.sqrt());
            for (s, e) in [(lo, a.min(hi)), (c.max(lo), hi)] {
                if e > s {
                    d.push(crate::Interval { enter: s, exit: e });
                }
            }
        })
        .unwrap();
        let nudge = |p: Vec3, n: Vec3| Some(p + n * 1e-3);
        let options = ContourOptions::default();
        let (a, sa) = stock.to_mesh_projected(&options, nudge);
        let (b, sb) = stock.into_mesh_projected(&options, nudge);
        assert!(a.is_closed() && a.len() > 100);
        assert_eq!(a.vertices, b.vertices);
        assert_eq!(a.triangles, b.triangles);
        assert_eq!(sa, sb);
    }
}
