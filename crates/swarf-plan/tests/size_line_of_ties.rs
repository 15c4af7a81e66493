//! The certified ball size on a concave cylinder of the ball's own radius, where the ball
//! touches the whole circle through the CC point (a line of ties across the parameter lines
//! along the axis). At CC points off the dyadic splits of the patch (an 11 × 11 grid) the
//! solver had to cut that circle into some 20 000 short nodes per point (≈ 27 000 evaluations,
//! against ≈ 40 on a 5 × 5 grid, whose points lie on split lines); splitting where the
//! Bernstein bound's limiting coefficient needs it takes about 1 000. The same cylinder with its
//! knots normalised, scaled (0..100 × 0..50, as CAD kernels write them) or restricted to a
//! sub-range (IGES 128's U0..U1, by knot insertion) costs the same: the parameters' units play
//! no part in the search.

use swarf_geom::math::Vec3;
use swarf_plan::size::{allowable_certified, CertifiedOptions, Contact, CutterFamily};
use swarf_surface::{CompoundSurface, NurbsSurface, Patch, PreparedSurface, Surface, Tolerances};

/// The lower half of the cylinder of radius 10 about the x axis, `x ∈ [0, 50]`, as a rational
/// quadratic × linear B-spline (two 90° arcs, knots `0,0,0,1,1,2,2,2` × `0,0,1,1` times `su`,
/// `sv`), normal up (towards the axis).
fn half_cylinder(su: f64, sv: f64) -> NurbsSurface {
    let r = 10.0;
    let h = 0.5f64.sqrt();
    let profile = [(-r, 0.0), (-r, -r), (0.0, -r), (r, -r), (r, 0.0)];
    let weights = [1.0, h, 1.0, h, 1.0];
    let pts: Vec<Vec<Vec3>> = profile
        .iter()
        .map(|&(y, z)| [50.0, 0.0].iter().map(|&x| Vec3::new(x, y, z)).collect())
        .collect();
    let ws: Vec<Vec<f64>> = weights.iter().map(|&w| vec![w, w]).collect();
    let ku = [0.0, 0.0, 0.0, 1.0, 1.0, 2.0, 2.0, 2.0]
        .iter()
        .map(|k| k * su)
        .collect();
    let kv = [0.0, 0.0, 1.0, 1.0].iter().map(|k| k * sv).collect();
    NurbsSurface::new(2, 1, ku, kv, &pts, Some(&ws)).unwrap()
}

/// Mean evaluations per CC point of the certified ball size over an `n × n` grid of the
/// parameter box `u × v` of the one-patch `part`; every size is 10 and certified.
fn mean_evaluations(part: &CompoundSurface, u: [f64; 2], v: [f64; 2], n: usize) -> f64 {
    let prep = PreparedSurface::new(part);
    let opts = CertifiedOptions::DEFAULT;
    let (mut evaluations, mut points) = (0, 0);
    for i in 0..n {
        for j in 0..n {
            let s = i as f64 / (n - 1) as f64;
            let t = j as f64 / (n - 1) as f64;
            let (pu, pv) = (u[0] + s * (u[1] - u[0]), v[0] + t * (v[1] - v[0]));
            let cc = part.points(&[(0, pu, pv)]).unwrap();
            let c = Contact::at(part, &cc[0], &Tolerances::DEFAULT).unwrap();
            let a = allowable_certified(&prep, &CutterFamily::ball(), &c, &opts);
            assert!(a.certified, "({pu}, {pv}): not certified, gap {:e}", a.gap);
            // The ball of the cylinder's radius fits everywhere; what the solver finds may lie
            // below by the imaginary size's round-off at points just outside the excluded
            // neighbourhood of the CC point (≈ 1e-7 mm there), never above.
            assert!(
                (a.size - 10.0).abs() < 1e-6,
                "({pu}, {pv}): size {} instead of 10",
                a.size
            );
            evaluations += a.evaluations;
            points += 1;
        }
    }
    evaluations as f64 / points as f64
}

#[test]
fn a_line_of_ties_off_the_split_lines_costs_about_a_thousand_evaluations_in_any_parameters() {
    let one = |s: NurbsSurface| CompoundSurface::new(vec![Patch::new(Surface::Nurbs(s))]);
    let full = one(half_cylinder(1.0, 1.0));
    let scaled = one(half_cylinder(50.0, 50.0));
    let sub = one(half_cylinder(1.0, 1.0)
        .restricted([0.5, 1.5], [0.0, 1.0])
        .unwrap());
    let e_full = mean_evaluations(&full, [0.0, 2.0], [0.0, 1.0], 11);
    let e_scaled = mean_evaluations(&scaled, [0.0, 100.0], [0.0, 50.0], 11);
    let e_sub = mean_evaluations(&sub, [0.5, 1.5], [0.0, 1.0], 11);
    eprintln!("evaluations per point: full {e_full}, scaled {e_scaled}, sub-range {e_sub}");
    // Before: ≈ 26 900, 26 900 and 23 200; now ≈ 900 each.
    for (what, e) in [("full", e_full), ("scaled", e_scaled), ("sub-range", e_sub)] {
        assert!(e < 2500.0, "{what}: {e} evaluations per point");
    }
    // The parameters' scale changes nothing; the sub-range is a quarter of the circle, not the
    // half, so it costs about as much.
    assert!(
        (e_scaled / e_full - 1.0).abs() < 0.05,
        "{e_scaled} vs {e_full}"
    );
    assert!(
        e_sub < 2.0 * e_full && e_full < 2.0 * e_sub,
        "{e_sub} vs {e_full}"
    );
}
