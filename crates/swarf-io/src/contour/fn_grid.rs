//! [`FnGrid`]: a [`HermiteGrid`] from a signed distance function (negative inside), sampled
//! at the lattice points with each sign change refined to the exact crossing by a bracketed
//! secant (Illinois) iteration. Used by the tests and benches of the contouring, and by anyone
//! who wants a mesh of an implicit solid. Normals come from an optional gradient; without one
//! the contouring estimates them, exactly as it must for a tri-dexel.

use super::{HermiteGrid, Lattice, Span};
use crate::tolerance::DEFAULT_ROOT_TOLERANCE;
use swarf_geom::math::Vec3;

type Gradient = Box<dyn Fn(Vec3) -> Vec3 + Send + Sync>;

/// An implicit solid `{p : sdf(p) < 0}` sampled on a lattice.
pub struct FnGrid<F> {
    lattice: Lattice,
    sdf: F,
    gradient: Option<Gradient>,
    /// Crossings are refined until the bracket is below this fraction of the spacing.
    root_tolerance: f64,
}

impl<F: Fn(Vec3) -> f64 + Sync> FnGrid<F> {
    /// The solid where `sdf < 0`, sampled on `lattice`; normals left to the contouring.
    pub fn new(lattice: Lattice, sdf: F) -> Self {
        Self {
            lattice,
            sdf,
            gradient: None,
            root_tolerance: DEFAULT_ROOT_TOLERANCE,
        }
    }

    /// Exact normals from the gradient of the distance function (normalised by the caller of
    /// [`HermiteGrid::normal`]).
    pub fn with_gradient(
        mut self,
        gradient: impl Fn(Vec3) -> Vec3 + Send + Sync + 'static,
    ) -> Self {
        self.gradient = Some(Box::new(gradient));
        self
    }

    /// With crossings refined to `tol` × spacing.
    pub fn with_root_tolerance(mut self, tol: f64) -> Self {
        self.root_tolerance = tol;
        self
    }

    /// The root of `g` in `[a, b]` where `g(a)` and `g(b)` differ in sign (Illinois).
    fn root(
        &self,
        g: impl Fn(f64) -> f64,
        mut a: f64,
        mut b: f64,
        mut fa: f64,
        mut fb: f64,
        tol: f64,
    ) -> f64 {
        let mut side = 0;
        for _ in 0..200 {
            if (b - a).abs() <= tol {
                break;
            }
            let mut c = (a * fb - b * fa) / (fb - fa);
            if !(c > a.min(b) && c < a.max(b)) {
                c = 0.5 * (a + b);
            }
            let fc = g(c);
            if fc == 0.0 {
                return c;
            }
            if (fc < 0.0) == (fa < 0.0) {
                a = c;
                fa = fc;
                if side == -1 {
                    fb *= 0.5;
                }
                side = -1;
            } else {
                b = c;
                fb = fc;
                if side == 1 {
                    fa *= 0.5;
                }
                side = 1;
            }
            // Keep the bracket shrinking even when the secant stalls at one end.
            if side != 0 && (b - a).abs() > tol {
                let m = 0.5 * (a + b);
                let fm = g(m);
                if (fm < 0.0) == (fa < 0.0) {
                    a = m;
                    fa = fm;
                } else {
                    b = m;
                    fb = fm;
                }
            }
        }
        0.5 * (a + b)
    }
}

impl<F: Fn(Vec3) -> f64 + Sync> HermiteGrid for FnGrid<F> {
    fn lattice(&self) -> Lattice {
        self.lattice
    }

    fn line_spans(&self, axis: usize, u: usize, v: usize, out: &mut Vec<Span>) {
        let lat = &self.lattice;
        let mut base = lat.origin;
        base[(axis + 1) % 3] = lat.coord((axis + 1) % 3, u as isize);
        base[(axis + 2) % 3] = lat.coord((axis + 2) % 3, v as isize);
        let at = |t: f64| {
            let mut p = base;
            p[axis] = t;
            (self.sdf)(p)
        };
        let n = lat.n[axis] as isize;
        let tol = self.root_tolerance * lat.spacing[axis];
        let mut prev_t = lat.coord(axis, -1);
        let mut prev_f = at(prev_t);
        let mut enter = (prev_f < 0.0).then_some(prev_t);
        for i in 0..=n {
            let t = lat.coord(axis, i);
            let f = at(t);
            if (f < 0.0) != (prev_f < 0.0) {
                // Keep the crossing strictly on the outside sample's side of it, so that span
                // membership of the lattice points agrees with the signs sampled there (a
                // surface through a lattice point would otherwise be decided by rounding).
                let r = self.root(at, prev_t, t, prev_f, f, tol);
                let r = if prev_f < 0.0 {
                    r.clamp(prev_t, step_down(t))
                } else {
                    r.clamp(step_up(prev_t), t)
                };
                match enter.take() {
                    Some(e) => out.push(Span { enter: e, exit: r }),
                    None => enter = Some(r),
                }
            }
            prev_t = t;
            prev_f = f;
        }
        if let Some(e) = enter {
            out.push(Span {
                enter: e,
                exit: prev_t,
            });
        }
    }

    fn normal(&self, _axis: usize, p: Vec3) -> Option<Vec3> {
        self.gradient.as_ref().map(|g| g(p).normalize_or_zero())
    }
}

/// The next representable number above `x`.
fn step_up(x: f64) -> f64 {
    if x == 0.0 {
        f64::from_bits(1)
    } else if x > 0.0 {
        f64::from_bits(x.to_bits() + 1)
    } else {
        f64::from_bits(x.to_bits() - 1)
    }
}

/// The next representable number below `x`.
fn step_down(x: f64) -> f64 {
    -step_up(-x)
}
