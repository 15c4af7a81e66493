//! Liu's PSO study (Tables 3-2 to 3-4: success rate and iterations of swarm settings),
//! reproduced on a two-patch case built to have a near-tie: a floor, and a curved wall around
//! the CC point whose saddle-shaped surface bulges towards it in two places, the global minimum
//! (allowable flat end mill radius) about 0.4 % below a local one on the other side. The swarm
//! sometimes settles in the wrong basin; the certified solver must find the global one every
//! time. Run with `--nocapture` to see the table.

use swarf_geom::math::Vec3;
use swarf_plan::size::pso::{nelder_mead, particle_swarm, PsoOptions};
use swarf_plan::size::{allowable_certified, CertifiedOptions, Contact, CutterFamily, Limit};
use swarf_surface::PreparedSurface;
use swarf_surface::{CompoundSurface, NurbsSurface, ParametricSurface, Patch, Surface, Tolerances};

/// Horizontal distance of the wall from the origin at angle φ (degrees) and height fraction t:
/// two bulges (at −30° and +30°, the second 0.025 mm shallower) on a saddle that rises away
/// from mid-height.
fn wall_radius(phi_deg: f64, t: f64) -> f64 {
    let bump = |x: f64| (-(x / 9.0).powi(2)).exp();
    8.0 - 1.5 * bump(phi_deg + 30.0) - 1.475 * bump(phi_deg - 30.0)
        + 1.2 * (t - 0.5).powi(2)
        + 0.002 * (phi_deg / 10.0).powi(2)
}

fn part() -> CompoundSurface {
    let floor = NurbsSurface::new(
        1,
        1,
        vec![0.0, 0.0, 1.0, 1.0],
        vec![0.0, 0.0, 1.0, 1.0],
        &[
            vec![Vec3::new(-12.0, -12.0, 0.0), Vec3::new(-12.0, 12.0, 0.0)],
            vec![Vec3::new(12.0, -12.0, 0.0), Vec3::new(12.0, 12.0, 0.0)],
        ],
        None,
    )
    .unwrap();
    // Wall: cubic in φ (25 control columns), quadratic in height (5 rows), control points on
    // the target shape (close enough for a smooth bulging surface; the exact minima are found
    // by sampling below).
    let (nu, nv) = (25, 5);
    let mut ku = vec![0.0; 4];
    ku.extend((1..nu - 3).map(|k| k as f64 / (nu - 3) as f64));
    ku.extend([1.0; 4]);
    let kv = vec![0.0, 0.0, 0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0, 1.0, 1.0];
    let pts: Vec<Vec<Vec3>> = (0..nu)
        .map(|i| {
            let phi = -70.0 + 140.0 * i as f64 / (nu - 1) as f64;
            (0..nv)
                .map(|j| {
                    let t = j as f64 / (nv - 1) as f64;
                    let r = wall_radius(phi, t);
                    let a = phi.to_radians();
                    Vec3::new(r * a.cos(), r * a.sin(), 0.5 + 9.5 * t)
                })
                .collect()
        })
        .collect();
    let wall = NurbsSurface::new(3, 2, ku, kv, &pts, None).unwrap();
    let mut w = Patch::new(Surface::Nurbs(wall));
    w.name = Some("saddle wall".into());
    let n = w
        .local(0.5, 0.5, &Tolerances::DEFAULT)
        .normal
        .vector()
        .unwrap();
    w.flipped = n.x > 0.0; // towards the origin
    let mut f = Patch::new(Surface::Nurbs(floor));
    f.name = Some("floor".into());
    CompoundSurface::new(vec![f, w])
}

const DENSE: usize = 600;

/// Dense-sampled minimum of the wall's imaginary size over s < 0.5 and s ≥ 0.5.
fn sampled_minima(part: &CompoundSurface, f: &CutterFamily, c: &Contact) -> (f64, f64) {
    let tol = CertifiedOptions::DEFAULT.model;
    let reg = f.regime(c, &tol);
    let w = &part.patches[1].surface;
    let (mut lo, mut hi) = (f64::INFINITY, f64::INFINITY);
    for i in 0..DENSE {
        for j in 0..DENSE {
            let (s, t) = (i as f64 / (DENSE - 1) as f64, j as f64 / (DENSE - 1) as f64);
            let v = f.imaginary(c, &reg, w.point(s, t), &tol);
            if s < 0.5 {
                lo = lo.min(v);
            } else {
                hi = hi.min(v);
            }
        }
    }
    (lo, hi)
}

struct Setting {
    particles: usize,
    rounds: usize,
    inertia: [f64; 2],
    c: f64,
}

#[test]
fn pso_settings_success_rates_and_certified_always_global() {
    let part = part();
    let prep = PreparedSurface::new(&part);
    let family = CutterFamily::flat();
    let tol = Tolerances::DEFAULT;
    let cc = part.points(&[(0, 0.5, 0.5)]).unwrap()[0];
    let c = Contact::at(&part, &cc, &tol).unwrap();
    let (global, local) = sampled_minima(&part, &family, &c);
    let gap = (local - global) / global;
    eprintln!(
        "global {global:.6} mm (s < 0.5), local {local:.6} mm: {:.2} % apart",
        100.0 * gap
    );
    assert!(
        gap > 0.0 && gap < 0.01,
        "not a near-tie: {global} vs {local}"
    );

    // The certified solver, at this point and at CC points around it (where the tie shifts).
    let mut cert_ok = 0;
    let mut cert_evals = 0;
    let offsets = [-0.3, -0.15, 0.0, 0.15, 0.3];
    for &dx in &offsets {
        for &dy in &offsets {
            let cc = part
                .points(&[(0, 0.5 + dx / 24.0, 0.5 + dy / 24.0)])
                .unwrap()[0];
            let c = Contact::at(&part, &cc, &tol).unwrap();
            let (g, l) = sampled_minima(&part, &family, &c);
            let want = g.min(l);
            let a = allowable_certified(&prep, &family, &c, &CertifiedOptions::DEFAULT);
            cert_evals += a.evaluations;
            // The certified size is the value at a real point, so it may only undercut the
            // sampled minimum by what sampling misses (< 1e-3 mm here), and its limiting point
            // must lie in the global basin (s < 0.5 ⇔ y < 0).
            let basin_ok = a.limit_point.is_some_and(|p| (p.y < 0.0) == (g < l));
            if a.certified
                && basin_ok
                && a.size <= want + 1e-7
                && a.size >= want - 1e-3
                && a.limit == Some(Limit::Interference)
            {
                cert_ok += 1;
            } else {
                eprintln!("certified missed at ({dx}, {dy}): {a:?} vs {want}");
            }
        }
    }
    let n_cert = offsets.len() * offsets.len();
    eprintln!(
        "certified: {cert_ok}/{n_cert} global, {:.0} evaluations per point",
        cert_evals as f64 / n_cert as f64
    );
    assert_eq!(
        cert_ok, n_cert,
        "the certified solver must always find the global minimum"
    );

    // The swarm study on the wall patch (Liu Table 3-4 style).
    let settings = [
        Setting {
            particles: 64,
            rounds: 30,
            inertia: [0.1, 0.2],
            c: 0.5,
        },
        Setting {
            particles: 32,
            rounds: 30,
            inertia: [0.1, 0.2],
            c: 0.5,
        },
        Setting {
            particles: 16,
            rounds: 30,
            inertia: [0.1, 0.2],
            c: 0.5,
        },
        Setting {
            particles: 8,
            rounds: 30,
            inertia: [0.1, 0.2],
            c: 0.5,
        },
        Setting {
            particles: 64,
            rounds: 10,
            inertia: [0.1, 0.2],
            c: 0.5,
        },
        Setting {
            particles: 16,
            rounds: 10,
            inertia: [0.1, 0.2],
            c: 0.5,
        },
        Setting {
            particles: 16,
            rounds: 30,
            inertia: [0.4, 0.9],
            c: 2.0,
        },
        Setting {
            particles: 4,
            rounds: 10,
            inertia: [0.1, 0.2],
            c: 0.5,
        },
    ];
    let wall = &part.patches[1].surface;
    let reg = family.regime(&c, &CertifiedOptions::DEFAULT.model);
    let obj = |u: f64, v: f64| {
        family.imaginary(&c, &reg, wall.point(u, v), &CertifiedOptions::DEFAULT.model)
    };
    const SEEDS: u64 = 100;
    eprintln!("| set | N_P | N_R | inertia    | c2=c3 | success | mean iterations | evals/run |");
    eprintln!("|-----|-----|-----|------------|-------|---------|-----------------|-----------|");
    let mut rates = Vec::new();
    for (k, st) in settings.iter().enumerate() {
        let opts = PsoOptions {
            particles: st.particles,
            rounds: st.rounds,
            inertia: st.inertia,
            cognitive: st.c,
            social: st.c,
            ..PsoOptions::DEFAULT
        };
        let (mut ok, mut rounds, mut evals) = (0u64, 0usize, 0u64);
        for seed in 0..SEEDS {
            let run = particle_swarm(obj, wall.domain(), &opts, 1000 + seed);
            let ((_, _, v), n) = nelder_mead(&obj, wall.domain(), run.best_uv, opts.local_iters);
            evals += run.evaluations + n;
            if v.min(run.best) <= global + 1e-4 {
                ok += 1;
                rounds += run.converged_round(1e-4);
            }
        }
        let rate = ok as f64 / SEEDS as f64;
        rates.push(rate);
        eprintln!(
            "| {:>3} | {:>3} | {:>3} | [{:.1}, {:.1}] | {:>5.1} | {:>6.0} % | {:>15.1} | {:>9} |",
            k + 1,
            st.particles,
            st.rounds,
            st.inertia[0],
            st.inertia[1],
            st.c,
            100.0 * rate,
            if ok > 0 {
                rounds as f64 / ok as f64
            } else {
                f64::NAN
            },
            evals / SEEDS
        );
    }
    // The case is hard enough that some swarm settings fail some of the time.
    assert!(
        rates.iter().any(|&r| r < 1.0),
        "the near-tie never fooled the swarm: {rates:?}"
    );
}
