//! What every surface fuzz target does with a surface that was read: evaluate each patch over a
//! small grid (normals and curvatures included), ask its trim (if any) about points and
//! rectangles, and cut the whole surface into Bézier pieces, as the solvers do. Nothing may
//! panic; a point may only be NaN when the file's own numbers are so large that arithmetic
//! overflows.

use swarf_surface::PreparedSurface;
use swarf_surface::{CompoundSurface, ParametricSurface, Tolerances};

/// Exercises `surface` (see the crate docs).
pub fn exercise(surface: &CompoundSurface) {
    let tol = Tolerances::DEFAULT;
    let modest = surface
        .bounding_box()
        .is_some_and(|b| b.min.abs().max_element() < 1e100 && b.max.abs().max_element() < 1e100);
    for patch in &surface.patches {
        let d = patch.surface.domain();
        for i in 0..=2 {
            for j in 0..=2 {
                let u = d.u[0] + (d.u[1] - d.u[0]) * f64::from(i) / 2.0;
                let v = d.v[0] + (d.v[1] - d.v[0]) * f64::from(j) / 2.0;
                let g = patch.local(u, v, &tol);
                if modest {
                    assert!(!g.point().is_nan(), "NaN point at ({u}, {v})");
                }
            }
        }
        if let Some(trim) = &patch.trim {
            // Points and rectangles over the box and a little beyond, and on the loops.
            let (du, dv) = (d.u[1] - d.u[0], d.v[1] - d.v[0]);
            for i in 0..=4 {
                for j in 0..=4 {
                    let u = d.u[0] + du * (f64::from(i) * 0.3 - 0.1);
                    let v = d.v[0] + dv * (f64::from(j) * 0.3 - 0.1);
                    let _ = trim.contains(u, v);
                    let _ = trim.coverage([u, u + 0.25 * du, v, v + 0.25 * dv]);
                    let _ = trim.coverage([u, u, v, v]);
                }
            }
            let _ = trim.coverage([d.u[0], d.u[1], d.v[0], d.v[1]]);
            for p in trim.loops().iter().flat_map(|l| l.iter().take(8)) {
                let _ = trim.contains(p[0], p[1]);
                let _ = trim.coverage([p[0], p[0] + 1e-3 * du, p[1], p[1] + 1e-3 * dv]);
            }
        }
    }
    let _ = PreparedSurface::new(surface).piece_count();
}
