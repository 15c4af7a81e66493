//! What every surface fuzz target does with a surface that was read: evaluate each patch over a
//! small grid (normals and curvatures included) and cut the whole surface into Bézier pieces,
//! as the solvers do. Nothing may panic; a point may only be NaN when the file's own numbers
//! are so large that arithmetic overflows.

use swarf_plan::size::PreparedSurface;
use swarf_plan::{CompoundSurface, ParametricSurface, Tolerances};

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
    }
    let _ = PreparedSurface::new(surface).piece_count();
}
