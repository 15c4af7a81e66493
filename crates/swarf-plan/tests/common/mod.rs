//! Shared builders for the integration tests: analytic surfaces written exactly as NURBS.
#![allow(dead_code, unreachable_pub)]

pub mod iges;

use std::f64::consts::FRAC_1_SQRT_2;
use swarf_geom::math::Vec3;
use swarf_plan::size::{CertifiedOptions, Contact, CutterFamily};
use swarf_plan::{CompoundSurface, NurbsSurface, ParametricSurface, Patch, Surface};

/// Path of a file in the shared data set.
#[macro_export]
macro_rules! data {
    ($rel:literal) => {
        concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data/", $rel)
    };
}

pub const QUAD_KNOTS: [f64; 6] = [0.0, 0.0, 0.0, 1.0, 1.0, 1.0];

/// A profile point (ρ, z) with its weight, revolved by a quarter turn about +z (from +x to +y)
/// as a rational quadratic arc: returns the three (point, weight) pairs along u.
fn revolve_quarter(rho: f64, z: f64, w: f64) -> [(Vec3, f64); 3] {
    [
        (Vec3::new(rho, 0.0, z), w),
        (Vec3::new(rho, rho, z), w * FRAC_1_SQRT_2),
        (Vec3::new(0.0, rho, z), w),
    ]
}

/// A surface of revolution: a quarter turn (u) of a rational profile (v) given as
/// (ρ, z, weight) with its knot vector and degree.
pub fn revolved(profile: &[(f64, f64, f64)], knots_v: Vec<f64>, degree_v: usize) -> NurbsSurface {
    let mut pts = vec![Vec::new(), Vec::new(), Vec::new()];
    let mut ws = vec![Vec::new(), Vec::new(), Vec::new()];
    for &(rho, z, w) in profile {
        for (i, (p, wi)) in revolve_quarter(rho, z, w).into_iter().enumerate() {
            pts[i].push(p);
            ws[i].push(wi);
        }
    }
    NurbsSurface::new(2, degree_v, QUAD_KNOTS.to_vec(), knots_v, &pts, Some(&ws)).unwrap()
}

/// Quarter cylinder of radius `r`, height `h`: u the arc from +x to +y, v the height; the
/// normal S_u × S_v points outwards.
pub fn quarter_cylinder(r: f64, h: f64) -> NurbsSurface {
    let mut pts = Vec::new();
    let mut ws = Vec::new();
    for (p, w) in revolve_quarter(r, 0.0, 1.0) {
        pts.push(vec![p, p + Vec3::new(0.0, 0.0, h)]);
        ws.push(vec![w, w]);
    }
    NurbsSurface::new(
        2,
        1,
        QUAD_KNOTS.to_vec(),
        vec![0.0, 0.0, 1.0, 1.0],
        &pts,
        Some(&ws),
    )
    .unwrap()
}

/// Sphere octant of radius `r` (x, y, z ≥ 0): u the longitude arc, v from the equator (v = 0)
/// to the north pole (v = 1, a collapsed edge); normal outwards.
pub fn sphere_octant(r: f64) -> NurbsSurface {
    revolved(
        &[(r, 0.0, 1.0), (r, r, FRAC_1_SQRT_2), (0.0, r, 1.0)],
        QUAD_KNOTS.to_vec(),
        2,
    )
}

/// A quarter (in u) of a torus with major radius `big` and tube radius `r`, the full tube in v
/// (v = 0 outer equator, 0.25 top, 0.5 inner equator, 0.75 bottom); normal outwards.
pub fn torus_quarter(big: f64, r: f64) -> NurbsSurface {
    let h = FRAC_1_SQRT_2;
    let profile = [
        (big + r, 0.0, 1.0),
        (big + r, r, h),
        (big, r, 1.0),
        (big - r, r, h),
        (big - r, 0.0, 1.0),
        (big - r, -r, h),
        (big, -r, 1.0),
        (big + r, -r, h),
        (big + r, 0.0, 1.0),
    ];
    let knots = vec![
        0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0,
    ];
    revolved(&profile, knots, 2)
}

/// A planar but non-affine bilinear patch (a trapezoid in the plane z = 2x + 3y).
pub fn bilinear_plane() -> NurbsSurface {
    let z = |x: f64, y: f64| Vec3::new(x, y, 2.0 * x + 3.0 * y);
    let pts = vec![
        vec![z(0.0, 0.0), z(1.0, 4.0)],
        vec![z(6.0, 0.0), z(3.0, 5.0)],
    ];
    NurbsSurface::new(
        1,
        1,
        vec![0.0, 0.0, 1.0, 1.0],
        vec![0.0, 0.0, 1.0, 1.0],
        &pts,
        None,
    )
    .unwrap()
}

/// Largest deviation of the analytic partials from central differences over an interior grid,
/// relative to the partials' size.
pub fn max_fd_error<S: ParametricSurface>(s: &S, n: usize) -> f64 {
    max_fd_error_between(s, n, &[], &[])
}

/// [`max_fd_error`] for a surface whose higher derivatives jump at the parameters `breaks_u` and
/// `breaks_v` (knots): a central difference straddling a jump measures the jump, not an error
/// of the partials, so a sample closer to a break than the stencil is moved off it.
pub fn max_fd_error_between<S: ParametricSurface>(
    s: &S,
    n: usize,
    breaks_u: &[f64],
    breaks_v: &[f64],
) -> f64 {
    let d = s.domain();
    let (hu, hv) = (1e-5 * (d.u[1] - d.u[0]), 1e-5 * (d.v[1] - d.v[0]));
    let clear =
        |x: f64, h: f64, breaks: &[f64]| match breaks.iter().find(|&&b| (x - b).abs() < 4.0 * h) {
            Some(&b) => b + 4.0 * h,
            None => x,
        };
    let mut worst: f64 = 0.0;
    for i in 1..n {
        for j in 1..n {
            let u = clear(d.u_at(i as f64 / n as f64 + 0.013), hu, breaks_u);
            let v = clear(d.v_at(j as f64 / n as f64 + 0.007), hv, breaks_v);
            let a = s.derivs(u, v);
            let (up, um) = (s.derivs(u + hu, v), s.derivs(u - hu, v));
            let (vp, vm) = (s.derivs(u, v + hv), s.derivs(u, v - hv));
            let scale = 1.0 + a.su.length().max(a.sv.length());
            let scale2 = 1.0 + a.suu.length().max(a.svv.length()).max(a.suv.length());
            let checks = [
                ((up.point - um.point) / (2.0 * hu) - a.su).length() / scale,
                ((vp.point - vm.point) / (2.0 * hv) - a.sv).length() / scale,
                ((up.su - um.su) / (2.0 * hu) - a.suu).length() / scale2,
                ((vp.sv - vm.sv) / (2.0 * hv) - a.svv).length() / scale2,
                ((vp.su - vm.su) / (2.0 * hv) - a.suv).length() / scale2,
                ((up.sv - um.sv) / (2.0 * hu) - a.suv).length() / scale2,
            ];
            worst = checks.into_iter().fold(worst, f64::max);
        }
    }
    worst
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

/// Line, column and message of the syntax error the JSON reader gives for `text`.
///
/// # Panics
/// When `text` reads, or fails otherwise.
pub fn json_error(text: &str) -> (usize, usize, String) {
    match swarf_plan::io::json::parse(text).unwrap_err() {
        swarf_plan::io::ReadError::Syntax {
            format: swarf_plan::io::Format::Json,
            line,
            column,
            message,
        } => (line, column, message),
        e => panic!("{e}"),
    }
}
