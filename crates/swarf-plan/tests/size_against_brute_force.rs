//! The certified solver against brute force on random compound surfaces: dense sampling of
//! test points can only find values at or above the true minimum, so the certified size must
//! not exceed the sampled minimum (plus its tolerance), and must not fall below it by more than
//! what sampling can miss (bounded by the variation across the sample cells around the
//! sampled minimum).

use swarf_geom::math::Vec3;
use swarf_plan::size::{
    allowable_certified, CertifiedOptions, Contact, CutterFamily, Limit, PreparedSurface,
};
use swarf_plan::{CompoundSurface, NurbsSurface, ParametricSurface, Patch, Surface, Tolerances};

struct Rng(u64);
impl Rng {
    fn f(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A 2×2 arrangement of bicubic B-spline height fields (one interior knot each way), with
/// random heights; one patch rational. Normals up.
fn random_surface(rng: &mut Rng) -> CompoundSurface {
    let knots = vec![0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1.0];
    let mut patches = Vec::new();
    for (k, (ox, oy)) in [(0.0, 0.0), (10.0, 0.0), (0.0, 10.0), (10.0, 10.0)]
        .into_iter()
        .enumerate()
    {
        let pts: Vec<Vec<Vec3>> = (0..5)
            .map(|i| {
                (0..5)
                    .map(|j| Vec3::new(ox + 2.5 * i as f64, oy + 2.5 * j as f64, 6.0 * rng.f()))
                    .collect()
            })
            .collect();
        let w: Vec<Vec<f64>> = (0..5)
            .map(|_| (0..5).map(|_| 0.5 + 1.5 * rng.f()).collect())
            .collect();
        let s = NurbsSurface::new(
            3,
            3,
            knots.clone(),
            knots.clone(),
            &pts,
            (k == 3).then_some(&w[..]),
        )
        .unwrap();
        patches.push(Patch::new(Surface::Nurbs(s)));
    }
    CompoundSurface::new(patches)
}

const N: usize = 160;

/// The sampled minimum over all patches (and the curvature bound), and the sampling bound.
fn brute(
    part: &CompoundSurface,
    f: &CutterFamily,
    c: &Contact,
    opts: &CertifiedOptions,
) -> (f64, f64) {
    let reg = f.regime(c, &opts.model);
    let mut best = f.local_bound(c, &reg);
    let mut spread: f64 = 0.0;
    for p in &part.patches {
        let d = p.surface.domain();
        let val = |i: usize, j: usize| {
            let q = p.surface.point(
                d.u_at(i as f64 / (N - 1) as f64),
                d.v_at(j as f64 / (N - 1) as f64),
            );
            if (q - c.point).length() < opts.neighbourhood {
                f64::INFINITY
            } else {
                f.imaginary(c, &reg, q, &opts.model)
            }
        };
        let grid: Vec<Vec<f64>> = (0..N)
            .map(|i| (0..N).map(|j| val(i, j)).collect())
            .collect();
        for i in 0..N {
            for j in 0..N {
                let v = grid[i][j];
                if v < best {
                    best = v;
                    // What sampling can miss around it: the variation over the adjacent cells.
                    spread = 0.0;
                    let rows = &grid[i.saturating_sub(1)..(i + 2).min(N)];
                    for row in rows {
                        for &w in &row[j.saturating_sub(1)..(j + 2).min(N)] {
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

#[test]
fn certified_matches_dense_sampling_on_random_compound_surfaces() {
    let mut rng = Rng(20_260_521);
    let families = [
        CutterFamily::ball(),
        CutterFamily::ball_with_side(),
        CutterFamily::taper_ball(5.0).unwrap(),
        CutterFamily::flat(),
        CutterFamily::bull(1.0).unwrap(),
        CutterFamily::apt(1.0, 3.0, 5.0).unwrap(),
    ];
    let opts = CertifiedOptions::DEFAULT;
    let tol = Tolerances::DEFAULT;
    let (mut compared, mut interference, mut certified) = (0, 0, 0);
    for _ in 0..3 {
        let part = random_surface(&mut rng);
        let prep = PreparedSurface::new(&part);
        for _ in 0..6 {
            let k = (rng.f() * 4.0) as usize;
            let cc = part
                .points(&[(k, 0.05 + 0.9 * rng.f(), 0.05 + 0.9 * rng.f())])
                .unwrap()[0];
            let mut c = Contact::at(&part, &cc, &tol).unwrap();
            if c.normal.z < 0.0 {
                c.normal = -c.normal;
                c.curvature = None;
            }
            for f in &families {
                let a = allowable_certified(&prep, f, &c, &opts);
                let (b, spread) = brute(&part, f, &c, &opts);
                let t = opts.tol_abs.max(opts.tol_rel * b);
                if b.is_infinite() {
                    assert!(a.size >= 1e5, "{f:?}: brute ∞, certified {a:?}");
                    continue;
                }
                assert!(a.size <= b + t, "{f:?}: certified {} > sampled {b}", a.size);
                assert!(
                    a.size >= b - spread - t,
                    "{f:?}: certified {} < sampled {b} − {spread}",
                    a.size
                );
                compared += 1;
                interference += usize::from(a.limit == Some(Limit::Interference));
                certified += usize::from(a.certified);
            }
        }
    }
    eprintln!(
        "{compared} finite comparisons, {interference} interference-limited, {certified} certified"
    );
    assert!(compared >= 60 && interference >= 20);
    assert!(
        certified * 10 >= compared * 9,
        "too few certified: {certified}/{compared}"
    );
}
