//! The quadratic error function of a cell patch, `Σ wᵢ (nᵢ · (x − pᵢ))²`, accumulated and
//! minimised with eigenvalue truncation and mass-point regularisation.

use swarf_geom::math::Vec3;

/// Accumulated planes and points, in coordinates relative to the cell's low corner (keeps the
/// sums accurate far from the origin).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Qef {
    /// Upper triangle of `Σ w n nᵀ`: xx, xy, xz, yy, yz, zz.
    ata: [f64; 6],
    /// `Σ w n (n · p)`.
    atb: Vec3,
    /// `Σ w (n · p)²`: with the two above, the error at any point (`residual`).
    btb: f64,
    mass: Vec3,
    points: u32,
    /// Sum of the plane weights.
    wsum: f64,
    /// The normal of the first plane, and whether every plane so far has exactly it (a cell on
    /// a flat face: the minimiser is the mass point projected onto the plane, no eigen-solve).
    first: Vec3,
    uniform: bool,
}

impl Qef {
    /// Adds a crossing `p`; its plane with unit normal `n` counts with weight `w` (none when
    /// `w == 0`).
    #[inline]
    pub(crate) fn add(&mut self, p: Vec3, n: Vec3, w: f64) {
        self.mass += p;
        self.points += 1;
        if w > 0.0 {
            if self.wsum == 0.0 {
                self.first = n;
                self.uniform = true;
            } else if n != self.first {
                self.uniform = false;
            }
            self.wsum += w;
            let wn = w * n;
            self.ata[0] += wn.x * n.x;
            self.ata[1] += wn.x * n.y;
            self.ata[2] += wn.x * n.z;
            self.ata[3] += wn.y * n.y;
            self.ata[4] += wn.y * n.z;
            self.ata[5] += wn.z * n.z;
            let np = n.dot(p);
            self.atb += wn * np;
            self.btb += w * np * np;
        }
    }

    /// Root mean square distance from `x` to the planes, weighted; `None` without planes.
    pub(crate) fn rms_distance(&self, x: Vec3) -> Option<f64> {
        (self.wsum > 0.0).then(|| {
            let e = x.dot(self.times_ata(x)) - 2.0 * x.dot(self.atb) + self.btb;
            (e.max(0.0) / self.wsum).sqrt()
        })
    }

    fn times_ata(&self, x: Vec3) -> Vec3 {
        let a = &self.ata;
        Vec3::new(
            a[0] * x.x + a[1] * x.y + a[2] * x.z,
            a[1] * x.x + a[3] * x.y + a[4] * x.z,
            a[2] * x.x + a[4] * x.y + a[5] * x.z,
        )
    }

    /// True when no crossing was added.
    pub(crate) fn is_empty(&self) -> bool {
        self.points == 0
    }

    /// The mass point (mean of the crossings).
    pub(crate) fn mass_point(&self) -> Vec3 {
        self.mass / self.points.max(1) as f64
    }

    /// The minimiser: `m + Σ_{λₖ > τ λ_max} vₖ (vₖ · (Aᵀb − AᵀA m)) / λₖ`.
    pub(crate) fn solve(&self, threshold: f64) -> Vec3 {
        let m = self.mass_point();
        if self.uniform {
            // One plane n·x = d with d the weighted mean of n·p: Σw n nᵀ = wsum n nᵀ has the
            // single eigenvalue wsum along n.
            let n = self.first;
            let d = n.dot(self.atb) / self.wsum;
            return m + n * (d - n.dot(m));
        }
        let a = [
            [self.ata[0], self.ata[1], self.ata[2]],
            [self.ata[1], self.ata[3], self.ata[4]],
            [self.ata[2], self.ata[4], self.ata[5]],
        ];
        let (vals, vecs) = sym_eigen(a);
        let lmax = vals.iter().fold(0.0f64, |x, &y| x.max(y));
        if lmax <= 0.0 {
            return m;
        }
        let am = Vec3::new(
            a[0][0] * m.x + a[0][1] * m.y + a[0][2] * m.z,
            a[1][0] * m.x + a[1][1] * m.y + a[1][2] * m.z,
            a[2][0] * m.x + a[2][1] * m.y + a[2][2] * m.z,
        );
        let r = self.atb - am;
        let mut x = m;
        for k in 0..3 {
            if vals[k] > threshold * lmax {
                x += vecs[k] * (vecs[k].dot(r) / vals[k]);
            }
        }
        x
    }
}

/// Eigenvalues and unit eigenvectors of a symmetric 3×3 matrix (cyclic Jacobi rotations).
pub(crate) fn sym_eigen(mut a: [[f64; 3]; 3]) -> ([f64; 3], [Vec3; 3]) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _sweep in 0..32 {
        // Converged when the off-diagonal part is at rounding level (Jacobi converges
        // quadratically: a handful of sweeps).
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        let diag = a[0][0].abs() + a[1][1].abs() + a[2][2].abs();
        if off <= 1e-15 * diag || off == 0.0 {
            break;
        }
        for (p, q) in [(0usize, 1usize), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // A ← Jᵀ A J with J the rotation in the (p, q) plane.
            for row in &mut a {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (rp, rq) = (a[p], a[q]);
            for k in 0..3 {
                a[p][k] = c * rp[k] - s * rq[k];
                a[q][k] = s * rp[k] + c * rq[k];
            }
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    let vals = [a[0][0], a[1][1], a[2][2]];
    let vecs = [0, 1, 2].map(|k| Vec3::new(v[0][k], v[1][k], v[2][k]));
    (vals, vecs)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigen_reconstructs_matrix() {
        let a = [[4.0, 1.0, -2.0], [1.0, 2.0, 0.5], [-2.0, 0.5, 3.0]];
        let (vals, vecs) = sym_eigen(a);
        for k in 0..3 {
            let v = vecs[k];
            let av = Vec3::new(
                a[0][0] * v.x + a[0][1] * v.y + a[0][2] * v.z,
                a[1][0] * v.x + a[1][1] * v.y + a[1][2] * v.z,
                a[2][0] * v.x + a[2][1] * v.y + a[2][2] * v.z,
            );
            assert!(
                (av - vals[k] * v).length() < 1e-12,
                "{k}: {av:?} vs {:?}",
                vals[k] * v
            );
            assert!((v.length() - 1.0).abs() < 1e-12);
        }
        assert!((vals.iter().sum::<f64>() - 9.0).abs() < 1e-12);
    }

    #[test]
    fn corner_edge_and_plane() {
        // Three orthogonal planes through (0.3, 0.6, 0.2): the corner exactly.
        let c = Vec3::new(0.3, 0.6, 0.2);
        let mut q = Qef::default();
        q.add(Vec3::new(0.3, 0.0, 0.0), Vec3::X, 1.0);
        q.add(Vec3::new(0.0, 0.6, 1.0), Vec3::Y, 1.0);
        q.add(Vec3::new(1.0, 1.0, 0.2), Vec3::Z, 0.5);
        assert!((q.solve(0.02) - c).length() < 1e-15);
        // Two planes: on their line, at the mass point's height along it.
        let mut e = Qef::default();
        e.add(Vec3::new(0.3, 0.1, 0.0), Vec3::X, 1.0);
        e.add(Vec3::new(0.9, 0.6, 1.0), Vec3::Y, 1.0);
        let x = e.solve(0.02);
        assert!((x - Vec3::new(0.3, 0.6, 0.5)).length() < 1e-15, "{x:?}");
        // Parallel planes (a flat face): the mass point projected onto their mean plane.
        let mut f = Qef::default();
        f.add(Vec3::new(0.2, 0.1, 0.3), Vec3::Z, 1.0);
        f.add(Vec3::new(0.6, 0.5, 0.5), Vec3::Z, 3.0);
        assert!((f.solve(0.02) - Vec3::new(0.4, 0.3, 0.45)).length() < 1e-15);
        // No planes: the mass point.
        let mut m = Qef::default();
        m.add(Vec3::ZERO, Vec3::X, 0.0);
        m.add(Vec3::ONE, Vec3::X, 0.0);
        assert_eq!(m.solve(0.02), Vec3::splat(0.5));
    }

    #[test]
    fn the_residual_is_the_planes_weighted_rms_distance() {
        // Planes of a curved patch, against the distances summed plane by plane; planes
        // through one point have none there; no planes, no residual.
        let planes: Vec<(Vec3, Vec3, f64)> = (0..9)
            .map(|i| {
                let t = i as f64 * 0.37;
                let n = Vec3::new(t.cos(), t.sin(), 0.4).normalize();
                (
                    Vec3::new(0.1 * t.sin(), 0.07 * i as f64, 0.05 + 0.02 * t),
                    n,
                    0.5 + 0.1 * i as f64,
                )
            })
            .collect();
        let mut q = Qef::default();
        for &(p, n, w) in &planes {
            q.add(p, n, w);
        }
        let x = q.solve(0.02);
        let (e, w) = planes.iter().fold((0.0, 0.0), |(e, w), &(p, n, wi)| {
            (e + wi * n.dot(x - p).powi(2), w + wi)
        });
        let rms = q.rms_distance(x).unwrap();
        assert!(
            (rms - (e / w).sqrt()).abs() < 1e-9,
            "{rms} vs {}",
            (e / w).sqrt()
        );
        assert!(rms > 1e-4, "the planes do not meet in a point: {rms}");
        let mut c = Qef::default();
        for n in [Vec3::X, Vec3::Y, Vec3::Z] {
            c.add(Vec3::splat(0.25), n, 1.0);
        }
        assert!(c.rms_distance(Vec3::splat(0.25)).unwrap() < 1e-12);
        assert_eq!(Qef::default().rms_distance(Vec3::ZERO), None);
        assert!(Qef::default().is_empty() && !c.is_empty());
    }
}
