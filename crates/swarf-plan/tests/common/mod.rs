//! Shared builders for the planner's integration tests: analytic surfaces written exactly as
//! NURBS, a reproducible random source, and the brute-force reference of the solvers.
#![allow(dead_code, unreachable_pub)]

use swarf_geom::math::Vec3;
use swarf_plan::size::{CertifiedOptions, Contact, CutterFamily};
use swarf_surface::{build, CompoundSurface, NurbsSurface, ParametricSurface, Patch, Surface};

/// The third-party data file `rel` (`SWARF_TEST_DATA`), or `None` after the printed line that
/// says why the calling test skips.
pub fn data(rel: &str) -> Option<std::path::PathBuf> {
    swarf_testdata::path(rel)
}

/// A radius-5 STEP sphere ([`swarf_testdata::fixtures::sphere_step`]) written to a file of its
/// own; its path.
pub fn sphere_step_file() -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "swarf-sphere-{}-{:?}",
        std::process::id(),
        std::thread::current().id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("sphere.step");
    std::fs::write(&path, swarf_testdata::fixtures::sphere_step(5.0)).unwrap();
    path
}

/// [`build::revolved`], for profiles the tests know to be valid.
pub fn revolved(profile: &[(f64, f64, f64)], knots_v: Vec<f64>, degree_v: usize) -> NurbsSurface {
    build::revolved(profile, knots_v, degree_v).unwrap()
}

/// [`build::quarter_cylinder`], which cannot fail for finite sizes.
pub fn quarter_cylinder(r: f64, h: f64) -> NurbsSurface {
    build::quarter_cylinder(r, h).unwrap()
}

/// [`build::sphere_octant`], which cannot fail for a finite radius.
pub fn sphere_octant(r: f64) -> NurbsSurface {
    build::sphere_octant(r).unwrap()
}

/// A trough: the cylinder of radius `r` about the line `y = 0, z = r`, `x ∈ [0, len]`, polar
/// angle within `±alpha` of the bottom, exactly (a rational quadratic arc); normal up.
pub fn trough(r: f64, alpha: f64, len: f64) -> Patch {
    let arc = [
        (Vec3::new(0.0, -r * alpha.sin(), r - r * alpha.cos()), 1.0),
        (Vec3::new(0.0, 0.0, r - r / alpha.cos()), alpha.cos()),
        (Vec3::new(0.0, r * alpha.sin(), r - r * alpha.cos()), 1.0),
    ];
    let pts: Vec<Vec<Vec3>> = [0.0, len]
        .iter()
        .map(|&x| arc.iter().map(|(p, _)| *p + Vec3::X * x).collect())
        .collect();
    let ws: Vec<Vec<f64>> = (0..2)
        .map(|_| arc.iter().map(|(_, w)| *w).collect())
        .collect();
    Patch::new(Surface::Nurbs(
        NurbsSurface::new(
            1,
            2,
            vec![0.0, 0.0, 1.0, 1.0],
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            &pts,
            Some(&ws),
        )
        .unwrap(),
    ))
}

/// A linear congruential generator (Knuth's MMIX constants): reproducible random test inputs.
pub struct Rng(pub u64);

impl Rng {
    /// Uniform in `[0, 1)`.
    pub fn f(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The brute-force reference of the certified solver: the minimum imaginary size over `n × n`
/// samples of every patch (on the part only) and dense samples of the trim loops (the region's
/// boundary, which grid samples cannot reach), and the curvature bound at `c`; and what
/// sampling can miss around it (the variation over the adjacent samples).
pub fn sampled_min(
    part: &CompoundSurface,
    f: &CutterFamily,
    c: &Contact,
    opts: &CertifiedOptions,
    n: usize,
) -> (f64, f64) {
    let reg = f.regime(c, &opts.model);
    let mut best = f.local_bound(c, &reg);
    let mut spread: f64 = 0.0;
    for p in &part.patches {
        let d = p.surface.domain();
        let grid: Vec<Vec<f64>> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| {
                        let (u, v) = (
                            d.u_at(i as f64 / (n - 1) as f64),
                            d.v_at(j as f64 / (n - 1) as f64),
                        );
                        let q = p.surface.point(u, v);
                        if !p.on_part(u, v) || (q - c.point).length() < opts.neighbourhood {
                            f64::INFINITY
                        } else {
                            f.imaginary(c, &reg, q, &opts.model)
                        }
                    })
                    .collect()
            })
            .collect();
        if let Some(trim) = &p.trim {
            let value = |[u, v]: [f64; 2]| {
                let q = p.surface.point(u, v);
                if !d.contains(u, v) || (q - c.point).length() < opts.neighbourhood {
                    f64::INFINITY
                } else {
                    f.imaginary(c, &reg, q, &opts.model)
                }
            };
            for l in trim.loops() {
                let samples: Vec<f64> = (0..l.len())
                    .flat_map(|e| {
                        let (a, b) = (l[e], l[(e + 1) % l.len()]);
                        (0..64).map(move |k| {
                            let t = k as f64 / 64.0;
                            [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
                        })
                    })
                    .map(value)
                    .collect();
                for (k, &v) in samples.iter().enumerate() {
                    if v < best {
                        best = v;
                        let m = samples.len();
                        spread = [samples[(k + 1) % m], samples[(k + m - 1) % m]]
                            .into_iter()
                            .filter(|w| w.is_finite())
                            .fold(0.0, |s: f64, w| s.max((w - v).abs()));
                    }
                }
            }
        }
        for i in 0..n {
            for j in 0..n {
                let v = grid[i][j];
                if v < best {
                    best = v;
                    spread = 0.0;
                    for row in &grid[i.saturating_sub(1)..(i + 2).min(n)] {
                        for &w in &row[j.saturating_sub(1)..(j + 2).min(n)] {
                            if w.is_finite() {
                                spread = spread.max((w - v).abs());
                            }
                        }
                    }
                }
            }
        }
    }
    (best, spread)
}
