//! The certified size on surfaces that fold through themselves or collapse to a point (issue 16
//! item 1): self-intersecting ("spindle") tori whose tube radius exceeds the ring radius — as
//! the analytic torus of STEP and as the rational B-splines CAD systems write (four 90° arcs,
//! three 120° arcs) — and a cone whose apex lies inside its parameter box. At every grid point
//! of each, from both sides, the certified size never exceeds what dense sampling of the whole
//! surface allows (a certificate is never wrong), and every search ends within its node budget.

mod common;

use common::sampled_min;

use swarf_geom::math::Vec3;
use swarf_geom::Frame;
use swarf_plan::size::{allowable_certified, CertifiedOptions, Contact, CutterFamily};
use swarf_surface::{
    CompoundSurface, ConicalSurface, NurbsSurface, ParamBox, ParametricSurface, Patch,
    PreparedSurface, Surface, Tolerances, ToroidalSurface,
};

/// A torus (ring radius `big`, tube radius `small`) as a rational biquadratic B-spline whose
/// circles are `arcs` equal rational arcs (4: 90° arcs, weights √½; 3: 120° arcs, weights ½).
fn nurbs_torus(big: f64, small: f64, arcs: usize) -> Surface {
    let half = std::f64::consts::PI / arcs as f64;
    let mut circle = Vec::new();
    for k in 0..arcs {
        let a = 2.0 * half * k as f64;
        circle.push((a.cos(), a.sin(), 1.0));
        let m = a + half;
        let out = 1.0 / half.cos();
        circle.push((out * m.cos(), out * m.sin(), half.cos()));
    }
    circle.push((1.0, 0.0, 1.0));
    let mut knots = vec![0.0; 3];
    for k in 1..arcs {
        knots.extend([k as f64 / arcs as f64; 2]);
    }
    knots.extend([1.0; 3]);
    let mut pts = Vec::new();
    let mut ws = Vec::new();
    for &(ax, ay, aw) in &circle {
        let (mut row, mut wrow) = (Vec::new(), Vec::new());
        for &(bx, by, bw) in &circle {
            let rad = big + small * bx;
            row.push(Vec3::new(rad * ax, rad * ay, small * by));
            wrow.push(aw * bw);
        }
        pts.push(row);
        ws.push(wrow);
    }
    Surface::Nurbs(NurbsSurface::new(2, 2, knots.clone(), knots, &pts, Some(&ws)).unwrap())
}

fn analytic_torus(big: f64, small: f64) -> Surface {
    let frame = Frame::from_axis(Vec3::ZERO, Vec3::Z);
    let tau = std::f64::consts::TAU;
    let domain = ParamBox::new(0.0, tau, 0.0, tau);
    Surface::Torus(ToroidalSurface::new(frame, big, small, domain).unwrap())
}

/// A cone of semi-angle 30° whose parameter box runs through its apex (v = −radius/tan 30°).
fn cone_through_apex() -> Surface {
    let frame = Frame::from_axis(Vec3::ZERO, Vec3::Z);
    let (radius, alpha) = (6.0f64, 30f64.to_radians());
    let apex = -radius / alpha.tan();
    let domain = ParamBox::new(0.0, std::f64::consts::TAU, apex - 5.0, 4.0);
    Surface::Cone(ConicalSurface::new(frame, radius, alpha, domain).unwrap())
}

#[test]
fn certificates_hold_on_self_intersecting_tori_and_through_a_cone_apex() {
    let surfaces = [
        ("analytic spindle torus 10/15", analytic_torus(10.0, 15.0)),
        (
            "nurbs spindle torus 10/15, 90° arcs",
            nurbs_torus(10.0, 15.0, 4),
        ),
        (
            "nurbs spindle torus 20/21, 120° arcs",
            nurbs_torus(20.0, 21.0, 3),
        ),
        ("analytic horn torus 12/12", analytic_torus(12.0, 12.0)),
        ("cone through its apex", cone_through_apex()),
    ];
    let families = [CutterFamily::ball(), CutterFamily::flat()];
    let opts = CertifiedOptions::DEFAULT;
    let tol = Tolerances::DEFAULT;
    let (mut compared, mut finite) = (0, 0);
    for (name, surface) in surfaces {
        let part = CompoundSurface::new(vec![Patch::new(surface)]);
        let prep = PreparedSurface::new(&part);
        let d = part.patches[0].surface.domain();
        let n = 5;
        for i in 0..n {
            for j in 0..n {
                let (fu, fv) = ((i as f64 + 0.37) / n as f64, (j as f64 + 0.61) / n as f64);
                let (u, v) = (
                    d.u[0] + fu * (d.u[1] - d.u[0]),
                    d.v[0] + fv * (d.v[1] - d.v[0]),
                );
                let Ok(cc) = part.points(&[(0, u, v)]) else {
                    continue;
                };
                let Some(c0) = Contact::at(&part, &cc[0], &tol) else {
                    continue; // no normal here (apex, the torus's pinch): not a CC point
                };
                for side in [1.0, -1.0] {
                    let mut c = c0;
                    if side < 0.0 {
                        c.normal = -c.normal;
                        c.curvature = None;
                    }
                    for f in &families {
                        let a = allowable_certified(&prep, f, &c, &opts);
                        let (b, _) = sampled_min(&part, f, &c, &opts, 120);
                        let t = opts.tol_abs.max(opts.tol_rel * b);
                        assert!(
                            a.size <= b + t,
                            "{name} at (u, v) = ({u:.3}, {v:.3}), side {side}, {f:?}: certified \
                             {} but a sampled point allows only {b}",
                            a.size
                        );
                        compared += 1;
                        finite += usize::from(b.is_finite());
                    }
                }
            }
        }
    }
    eprintln!("{compared} comparisons, {finite} with a finite sampled size");
    assert!(compared >= 150 && finite >= 50, "{compared} {finite}");
}
