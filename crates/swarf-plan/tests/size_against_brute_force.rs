//! The certified solver against brute force on random compound surfaces: dense sampling of
//! test points can only find values at or above the true minimum, so the certified size must
//! not exceed the sampled minimum (plus its tolerance), and must not fall below it by more than
//! what sampling can miss (bounded by the variation across the sample cells around the
//! sampled minimum).

mod common;

use common::{sampled_min, Rng};

use swarf_geom::math::Vec3;
use swarf_plan::size::{allowable_certified, CertifiedOptions, Contact, CutterFamily, Limit};
use swarf_surface::PreparedSurface;
use swarf_surface::{CompoundSurface, NurbsSurface, Patch, Surface, Tolerances};

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
                let (b, spread) = sampled_min(&part, f, &c, &opts, 160);
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
