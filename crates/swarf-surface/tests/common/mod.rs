//! Shared builders and checks for the surface crate's integration tests.
#![allow(dead_code, unreachable_pub)]

pub mod iges;
pub mod step;

use swarf_geom::math::Vec3;
use swarf_surface::{build, NurbsSurface, ParametricSurface};

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

/// [`build::quarter_cylinder`], which cannot fail for finite sizes.
pub fn quarter_cylinder(r: f64, h: f64) -> NurbsSurface {
    build::quarter_cylinder(r, h).unwrap()
}

/// [`build::sphere_octant`], which cannot fail for a finite radius.
pub fn sphere_octant(r: f64) -> NurbsSurface {
    build::sphere_octant(r).unwrap()
}

/// [`build::torus_quarter`], which cannot fail for finite radii.
pub fn torus_quarter(big: f64, r: f64) -> NurbsSurface {
    build::torus_quarter(big, r).unwrap()
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

/// Line, column and message of the syntax error the JSON reader gives for `text`.
///
/// # Panics
/// When `text` reads, or fails otherwise.
pub fn json_error(text: &str) -> (usize, usize, String) {
    match swarf_surface::io::json::parse(text).unwrap_err() {
        swarf_surface::io::ReadError::Syntax {
            format: swarf_surface::io::Format::Json,
            line,
            column,
            message,
        } => (line, column, message),
        e => panic!("{e}"),
    }
}
