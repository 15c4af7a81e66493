//! A ball end's sweep on the rays normal to the plane of its motion: the chord as a distance
//! in that plane, so that consecutive moves in one plane can be cut together.
//!
//! A raster finishing pass (passes along X at fixed Y, a vertical tool) keeps the tool axis and
//! the tip's path in one plane `x_k = c`, normal to one ray family `k` (the Y rays there). A
//! point at `δ` from that plane lies in a ball-end instance — the points within `r` of the
//! segment from the sphere's centre up the axis to the top `z1` — iff `δ² ≤ r² − w² −
//! min(0, h − f)²` (`w` its in-plane distance from the axis, `h` its height over the tip, `f`
//! the centre's height) and `h ≤ z1`. Below the tool's top, that is `δ² ≤ r² − D²` with `D`
//! the in-plane distance from the point to the half-line up from the centre; swept along the
//! move, `D` becomes the distance to the union of those half-lines — the region on and above
//! the centre's path (its epigraph `E`, convex). So every ray of family `k` meets the sweep in
//! the chord `c ± √(r² − D²)`, centred on the plane, and the sweeps of several moves in the
//! same plane meet it in nested chords: the widest is their union, and the next move changes
//! the ray only if its `D` is smaller than every earlier one's. The stock's batched cut
//! (`swarf-stock`, `tridexel.rs`) uses that to cut a pass's moves together on those rays.
//!
//! Exactly the chord of [`super::SweptConvex::axis_ray_interval`] where the ray lies below the
//! tool's lowest top over the move ([`PlanarMember::top`]); the caller keeps to that.

/// One move of a ball end (sphere on a slab reaching its top) whose tool axis (a world axis)
/// and motion lie in a plane normal to the ray family `k`, seen in that plane: coordinates
/// `x` (the third world axis) and `z` (along the tool axis).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanarMember {
    k: usize,
    kt: usize,
    plane: f64,
    r: f64,
    rr: f64,
    /// The sphere centre's path: start and move.
    x0: f64,
    z0: f64,
    dx: f64,
    dz: f64,
    inv_dx: f64,
    /// Its extent: `x` range and lowest height.
    xmin: f64,
    xmax: f64,
    zlow: f64,
    /// The tool's lowest top over the move (along the tool axis).
    top: f64,
    /// Whether the family's first cross axis is the tool axis.
    height_is_u: bool,
}

impl PlanarMember {
    /// The member for a ball end of radius `r` whose sphere centre moves from `c0` by `delta`
    /// (world) along tool axis `+e_kt`, `f` over the tip, slab top `z1` over the tip, for the
    /// rays along world axis `k`, when the motion lies in a plane normal to them.
    pub(crate) fn new(
        k: usize,
        kt: usize,
        c0: swarf_geom::math::Vec3,
        delta: swarf_geom::math::Vec3,
        (f, r, z1): (f64, f64, f64),
    ) -> Option<PlanarMember> {
        if k == kt || delta[k] != 0.0 || r.is_nan() || r <= 0.0 {
            return None;
        }
        let a = 3 - k - kt;
        let (x0, z0, dx, dz) = (c0[a], c0[kt], delta[a], delta[kt]);
        Some(PlanarMember {
            k,
            kt,
            plane: c0[k],
            r,
            rr: r * r,
            x0,
            z0,
            dx,
            dz,
            inv_dx: if dx != 0.0 { 1.0 / dx } else { 0.0 },
            xmin: x0.min(x0 + dx),
            xmax: x0.max(x0 + dx),
            zlow: z0.min(z0 + dz),
            top: z0.min(z0 + dz) - f + z1,
            height_is_u: (k + 1) % 3 == kt,
        })
    }

    /// The plane's coordinate along the rays: every chord is centred on it.
    pub fn plane(&self) -> f64 {
        self.plane
    }

    /// The ball's radius: the widest half-chord.
    pub fn radius(&self) -> f64 {
        self.r
    }

    /// The tool axis (a world axis).
    pub fn tool_axis(&self) -> usize {
        self.kt
    }

    /// The highest coordinate along the tool axis at which a ray's chord is exact: the tool's
    /// lowest top over the move (above it, the flat top would cut the chord short).
    pub fn top(&self) -> f64 {
        self.top
    }

    /// Whether `o`'s chords and this one's are nested on every ray: the same family, tool
    /// axis, plane and radius.
    pub fn same_plane(&self, o: &PlanarMember) -> bool {
        self.k == o.k && self.kt == o.kt && self.plane == o.plane && self.r == o.r
    }

    /// The in-plane point `(x, z)` of the ray through cross coordinates `(cu, cv)`.
    #[inline(always)]
    pub fn point(&self, cu: f64, cv: f64) -> (f64, f64) {
        if self.height_is_u {
            (cv, cu)
        } else {
            (cu, cv)
        }
    }

    /// The sphere centre path's `x` range and lowest height: the squared distance from
    /// `(x, z)` is at least `ex² + ez²`, `ex` and `ez` how far `x` lies outside the range and
    /// `z` below the height ([`PlanarMember::box_bound2`]).
    #[inline(always)]
    pub fn extent(&self) -> (f64, f64, f64) {
        (self.xmin, self.xmax, self.zlow)
    }

    /// A lower bound of [`PlanarMember::dist2`] over the in-plane box `[x0, x1] × [z0, z1]`.
    #[inline(always)]
    pub fn box_bound2(&self, (x0, x1): (f64, f64), (_, z1): (f64, f64)) -> f64 {
        let ex = (self.xmin - x1).max(x0 - self.xmax).max(0.0);
        let ez = (self.zlow - z1).max(0.0);
        ex * ex + ez * ez
    }

    /// The squared in-plane distance from `(x, z)` to the region on and above the sphere
    /// centre's path: the ray there meets the sweep in `plane ± √(r² − D²)` when `D² < r²`.
    #[inline(always)]
    pub fn dist2(&self, x: f64, z: f64) -> f64 {
        let (px, pz) = (x - self.x0, z - self.z0);
        if self.dx == 0.0 {
            // A plunge, a lift or no motion: the half-line up from the lower centre.
            let v = (self.zlow - z).max(0.0);
            return px * px + v * v;
        }
        let s = px * self.inv_dx;
        if (0.0..=1.0).contains(&s) && pz >= s * self.dz {
            return 0.0;
        }
        // Outside: the nearest point of the boundary — the path, or a half-line up from an
        // end the point is level with or above.
        let ll = self.dx * self.dx + self.dz * self.dz;
        let t = ((px * self.dx + pz * self.dz) / ll).clamp(0.0, 1.0);
        let (ex, ez) = (px - t * self.dx, pz - t * self.dz);
        let mut d2 = ex * ex + ez * ez;
        if pz >= 0.0 {
            d2 = d2.min(px * px);
        }
        if pz >= self.dz {
            let qx = px - self.dx;
            d2 = d2.min(qx * qx);
        }
        d2
    }

    /// The chord's half-width for a squared distance `d2` from [`PlanarMember::dist2`]
    /// (`None` when the ray misses or grazes the sweep).
    #[inline(always)]
    pub fn half_width(&self, d2: f64) -> Option<f64> {
        (d2 < self.rr).then(|| (self.rr - d2).sqrt())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::swept::test_rng;
    use crate::{ConvexProfile, SweptConvex};
    use swarf_geom::math::Vec3;
    use swarf_tool::Cutter;

    /// Against the per-move exact kernel, for random moves in planes normal to each family
    /// and random rays below the tool's top.
    #[test]
    fn chords_are_the_exact_kernels() {
        let mut rnd = test_rng(7);
        let mut compared = (0, 0);
        for spec in ["ball:d=10", "ball:d=3,flute-length=20", "ball:d=12"] {
            let c = Cutter::from_spec(spec).unwrap();
            let prof = ConvexProfile::from_solid(c.cutting_solid()).unwrap();
            for kt in 0..3 {
                for k in (0..3).filter(|&k| k != kt) {
                    for n in 0..60 {
                        let tip = Vec3::new(rnd(), rnd(), rnd()) * 20.0;
                        let mut delta = Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 6.0;
                        delta[k] = 0.0;
                        match n % 4 {
                            0 => delta[3 - k - kt] = 0.0,
                            1 => delta[kt] = 0.0,
                            2 => delta = Vec3::ZERO,
                            _ => {}
                        }
                        let sw = SweptConvex::new(&prof, tip, Vec3::AXES[kt], delta);
                        let m = sw.planar(k).expect("a ball in the plane");
                        for _ in 0..200 {
                            let mut o =
                                tip + Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 24.0;
                            o[k] = 0.0;
                            if o[kt] > m.top() {
                                continue;
                            }
                            let (cu, cv) = (o[(k + 1) % 3], o[(k + 2) % 3]);
                            let (x, z) = m.point(cu, cv);
                            let exact = sw.axis_ray_interval(o, k);
                            let mine = m
                                .half_width(m.dist2(x, z))
                                .map(|s| (m.plane() - s, m.plane() + s));
                            match (exact, mine) {
                                (Some(e), Some(p)) => {
                                    assert!(
                                        (e.0 - p.0).abs() < 1e-9 && (e.1 - p.1).abs() < 1e-9,
                                        "{spec} kt {kt} k {k}: {e:?} vs {p:?}"
                                    );
                                    compared.0 += 1;
                                }
                                (None, None) => compared.1 += 1,
                                // A graze: a chord of (numerically) no length either way.
                                (Some(e), None) => assert!(e.1 - e.0 < 1e-6, "{e:?}"),
                                (None, Some(p)) => assert!(p.1 - p.0 < 1e-6, "{p:?}"),
                            }
                        }
                    }
                }
            }
        }
        assert!(compared.0 > 5000 && compared.1 > 5000, "{compared:?}");
    }

    /// The tile bound never exceeds the distance of a point of the box.
    #[test]
    fn box_bound_is_a_lower_bound() {
        let mut rnd = test_rng(8);
        for _ in 0..2000 {
            let c0 = Vec3::new(rnd(), rnd(), rnd()) * 10.0;
            let mut d = Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 6.0;
            d[1] = 0.0;
            let m = PlanarMember::new(1, 2, c0, d, (5.0, 5.0, 30.0)).unwrap();
            let (x0, z0) = (rnd() * 14.0 - 2.0, rnd() * 14.0 - 2.0);
            let (x1, z1) = (x0 + rnd(), z0 + rnd());
            let b = m.box_bound2((x0, x1), (z0, z1));
            for _ in 0..20 {
                let (x, z) = (x0 + rnd() * (x1 - x0), z0 + rnd() * (z1 - z0));
                assert!(b <= m.dist2(x, z) + 1e-12);
            }
        }
    }
}
