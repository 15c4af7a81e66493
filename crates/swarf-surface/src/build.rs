//! Surfaces written exactly as NURBS: quarter turns of rational profiles about `+z` (cylinder,
//! sphere and torus pieces, as the tests and benchmarks use them) and height fields
//! `z = f(x, y)` as C¹ bicubic Hermite interpolants (the demo's design surface).

use std::f64::consts::FRAC_1_SQRT_2;

use swarf_geom::math::Vec3;

use crate::surface::{NurbsError, NurbsSurface};

/// Knots of one rational quadratic arc.
pub const QUAD_KNOTS: [f64; 6] = [0.0, 0.0, 0.0, 1.0, 1.0, 1.0];

/// A profile point (ρ, z) with its weight, revolved by a quarter turn about +z (from +x to +y)
/// as a rational quadratic arc: the three (point, weight) pairs along u.
fn revolve_quarter(rho: f64, z: f64, w: f64) -> [(Vec3, f64); 3] {
    [
        (Vec3::new(rho, 0.0, z), w),
        (Vec3::new(rho, rho, z), w * FRAC_1_SQRT_2),
        (Vec3::new(0.0, rho, z), w),
    ]
}

/// A surface of revolution: a quarter turn (u, from +x to +y) of a rational profile (v) given
/// as (ρ, z, weight) with its knot vector and degree.
///
/// # Errors
/// When the profile, knots and degree do not make a NURBS.
pub fn revolved(
    profile: &[(f64, f64, f64)],
    knots_v: Vec<f64>,
    degree_v: usize,
) -> Result<NurbsSurface, NurbsError> {
    let mut pts = vec![Vec::new(), Vec::new(), Vec::new()];
    let mut ws = vec![Vec::new(), Vec::new(), Vec::new()];
    for &(rho, z, w) in profile {
        for (i, (p, wi)) in revolve_quarter(rho, z, w).into_iter().enumerate() {
            pts[i].push(p);
            ws[i].push(wi);
        }
    }
    NurbsSurface::new(2, degree_v, QUAD_KNOTS.to_vec(), knots_v, &pts, Some(&ws))
}

/// Quarter cylinder of radius `r`, height `h`: u the arc from +x to +y, v the height; the
/// normal S_u × S_v points outwards.
///
/// # Errors
/// When `r` or `h` is not finite.
pub fn quarter_cylinder(r: f64, h: f64) -> Result<NurbsSurface, NurbsError> {
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
}

/// Sphere octant of radius `r` (x, y, z ≥ 0): u the longitude arc, v from the equator (v = 0)
/// to the north pole (v = 1, a collapsed edge); normal outwards.
///
/// # Errors
/// When `r` is not finite.
pub fn sphere_octant(r: f64) -> Result<NurbsSurface, NurbsError> {
    revolved(
        &[(r, 0.0, 1.0), (r, r, FRAC_1_SQRT_2), (0.0, r, 1.0)],
        QUAD_KNOTS.to_vec(),
        2,
    )
}

/// A quarter (in u) of a torus with major radius `big` and tube radius `r`, the full tube in v
/// (v = 0 outer equator, 0.25 top, 0.5 inner equator, 0.75 bottom); normal outwards.
///
/// # Errors
/// When the radii are not finite.
pub fn torus_quarter(big: f64, r: f64) -> Result<NurbsSurface, NurbsError> {
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

/// A height field on a square grid: `nx × ny` cells of side `h` mm from `origin`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeightGrid {
    /// The grid's corner `(x0, y0)`, mm.
    pub origin: [f64; 2],
    /// The cell side, mm.
    pub h: f64,
    /// Cells along x and y.
    pub cells: [usize; 2],
}

/// The height field `z = f(x, y)` over `grid` as one bicubic NURBS: the Bézier form of the C¹
/// bicubic Hermite interpolant of `f` at the grid's nodes. `jet(x, y)` gives
/// `[f, ∂f/∂x, ∂f/∂y, ∂²f/∂x∂y]`. Knots have multiplicity 3 at every node (u = i at node `i`
/// along x, v = j along y); the control point `h/3` from a node carries the first derivatives,
/// the one `h/3` from two nodes' lines the twist. The error is `O(h⁴)` of `f`'s fourth
/// derivatives (the demo's floor, 2 mm cells: within 1e-4 mm).
///
/// ```
/// use swarf_surface::build::{hermite_height_field, HeightGrid};
/// use swarf_surface::ParametricSurface;
/// // z = x·y is reproduced exactly (a bicubic contains it).
/// let grid = HeightGrid { origin: [0.0, 0.0], h: 1.0, cells: [2, 3] };
/// let s = hermite_height_field(&grid, |x, y| [x * y, y, x, 1.0]).unwrap();
/// let p = s.point(1.5, 2.25);
/// assert!((p.z - p.x * p.y).abs() < 1e-12);
/// ```
///
/// # Errors
/// When the grid is empty or `jet` gives non-finite numbers.
pub fn hermite_height_field(
    grid: &HeightGrid,
    jet: impl Fn(f64, f64) -> [f64; 4],
) -> Result<NurbsSurface, NurbsError> {
    let HeightGrid {
        origin: [x0, y0],
        h,
        cells: [nx, ny],
    } = *grid;
    // Index 3i + a along x: node i, offset a·h/3 (a = 0, 1) or node i + 1 at −h/3 (a = 2).
    let node = |idx: usize, n: usize| -> (usize, f64) {
        let (i, a) = (idx / 3, idx % 3);
        match a {
            0 => (i.min(n), 0.0),
            1 => (i, h / 3.0),
            _ => (i + 1, -h / 3.0),
        }
    };
    let knots = |n: usize| -> Vec<f64> {
        let mut v = vec![0.0; 4];
        for i in 1..n {
            v.extend([i as f64; 3]);
        }
        v.extend([n as f64; 4]);
        v
    };
    let pts: Vec<Vec<Vec3>> = (0..=3 * nx)
        .map(|i| {
            let (ix, dx) = node(i, nx);
            (0..=3 * ny)
                .map(|j| {
                    let (iy, dy) = node(j, ny);
                    let (x, y) = (x0 + h * ix as f64, y0 + h * iy as f64);
                    let [f, fx, fy, fxy] = jet(x, y);
                    let z = f + dx * fx + dy * fy + dx * dy * fxy;
                    Vec3::new(x + dx, y + dy, z)
                })
                .collect()
        })
        .collect();
    NurbsSurface::new(3, 3, knots(nx), knots(ny), &pts, None)
}
