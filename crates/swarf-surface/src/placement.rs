//! Moving surfaces: a similarity without reflection (a rigid motion, possibly scaled) applied
//! to a patch's geometry — NURBS control points, elementary surfaces' frames and radii — with
//! its trim, which lives in the surface's own parameters and moves with it (scaled along the
//! linear parameters under a scale). Used by the STEP reader's assembly placements and by
//! [`CompoundSurface::moved`](crate::compound::CompoundSurface::moved).

use swarf_geom::math::{Mat3, Vec3};
use swarf_geom::{Frame, RigidMotion};

use crate::surface::{ParamBox, ParametricSurface, Surface};
use crate::trim::Trim;

/// Largest translation (mm) and the range of scale factors a placement may have.
pub(crate) const MAX_SHIFT: f64 = 1e9;
pub(crate) const SCALE_RANGE: [f64; 2] = [1e-6, 1e6];

/// A similarity without reflection: `p ↦ scale·rot·p + shift` (`rot` a rotation, `scale` > 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Placement {
    pub(crate) rot: Mat3,
    pub(crate) scale: f64,
    pub(crate) shift: Vec3,
}

impl Placement {
    /// The rigid motion `m`, unscaled.
    pub(crate) fn rigid(m: &RigidMotion) -> Self {
        Placement {
            rot: Mat3::from_quat(m.rotation),
            scale: 1.0,
            shift: m.translation,
        }
    }

    pub(crate) const IDENTITY: Placement = Placement {
        rot: Mat3::IDENTITY,
        scale: 1.0,
        shift: Vec3::ZERO,
    };

    /// The motion taking the world frame onto `f` (local coordinates → world).
    pub(crate) fn of_frame(f: &Frame) -> Self {
        Placement {
            rot: f.matrix(),
            scale: 1.0,
            shift: f.origin,
        }
    }

    /// `self ∘ inner`: `inner` first.
    pub(crate) fn after(&self, inner: &Placement) -> Placement {
        Placement {
            rot: self.rot * inner.rot,
            scale: self.scale * inner.scale,
            shift: self.scale * (self.rot * inner.shift) + self.shift,
        }
    }

    pub(crate) fn inverse(&self) -> Placement {
        let rt = self.rot.transpose();
        Placement {
            rot: rt,
            scale: 1.0 / self.scale,
            shift: -(rt * self.shift) / self.scale,
        }
    }

    /// The motion taking frame `from` onto frame `to` (`to ∘ from⁻¹`).
    pub(crate) fn between(from: &Frame, to: &Frame) -> Placement {
        Placement::of_frame(to).after(&Placement::of_frame(from).inverse())
    }

    pub(crate) fn point(&self, p: Vec3) -> Vec3 {
        self.scale * (self.rot * p) + self.shift
    }

    pub(crate) fn frame(&self, f: &Frame) -> Frame {
        Frame {
            origin: self.point(f.origin),
            x: self.rot * f.x,
            y: self.rot * f.y,
            z: self.rot * f.z,
        }
    }

    /// Why this placement is refused, if it is: not finite, a translation beyond 1e9 mm, a
    /// scale outside [1e-6, 1e6].
    pub(crate) fn insane(&self) -> Option<String> {
        if !(self.shift.is_finite() && self.rot.is_finite() && self.scale.is_finite()) {
            return Some("it is not finite".into());
        }
        if self.shift.abs().max_element() > MAX_SHIFT {
            return Some(format!("it moves by more than {MAX_SHIFT:e} mm"));
        }
        if !(SCALE_RANGE[0]..=SCALE_RANGE[1]).contains(&self.scale) {
            return Some(format!(
                "its scale {} is outside [{:e}, {:e}]",
                self.scale, SCALE_RANGE[0], SCALE_RANGE[1]
            ));
        }
        None
    }
}

/// `surface` and its `trim` moved by `p`. Rigid motions leave the parameters (and so the trim)
/// as they are; a scale multiplies the linear parameters of planes (u and v), cylinders and
/// cones (v), and the trim's coordinates along them, with the radii.
pub(crate) fn place(
    surface: &Surface,
    trim: Option<&Trim>,
    p: &Placement,
) -> Result<(Surface, Option<Trim>), String> {
    let s = p.scale;
    let mut scale_uv = [1.0, 1.0];
    let placed = match surface {
        Surface::Nurbs(n) => {
            let (nu, nv) = n.net_size();
            let points: Vec<Vec<Vec3>> = (0..nu)
                .map(|i| (0..nv).map(|j| p.point(n.control_point(i, j))).collect())
                .collect();
            let weights: Option<Vec<Vec<f64>>> = n.is_rational().then(|| {
                (0..nu)
                    .map(|i| (0..nv).map(|j| n.weight(i, j)).collect())
                    .collect()
            });
            Surface::Nurbs(
                crate::surface::NurbsSurface::new(
                    n.degree_u(),
                    n.degree_v(),
                    n.knots_u().to_vec(),
                    n.knots_v().to_vec(),
                    &points,
                    weights.as_deref(),
                )
                .map_err(|e| e.to_string())?,
            )
        }
        Surface::Plane(q) => {
            let mut q = *q;
            q.frame = p.frame(&q.frame);
            scale_uv = [s, s];
            q.domain = scaled_box(&q.domain, scale_uv);
            Surface::Plane(q)
        }
        Surface::Cylinder(q) => {
            let mut q = *q;
            q.frame = p.frame(&q.frame);
            q.radius *= s;
            scale_uv = [1.0, s];
            q.domain = scaled_box(&q.domain, scale_uv);
            Surface::Cylinder(q)
        }
        Surface::Cone(q) => {
            let mut q = *q;
            q.frame = p.frame(&q.frame);
            q.radius *= s;
            scale_uv = [1.0, s];
            q.domain = scaled_box(&q.domain, scale_uv);
            Surface::Cone(q)
        }
        Surface::Sphere(q) => {
            let mut q = *q;
            q.frame = p.frame(&q.frame);
            q.radius *= s;
            Surface::Sphere(q)
        }
        Surface::Torus(q) => {
            let mut q = *q;
            q.frame = p.frame(&q.frame);
            q.major *= s;
            q.minor *= s;
            Surface::Torus(q)
        }
    };
    let trim = match trim {
        Some(t) if scale_uv != [1.0, 1.0] => {
            let sc = |l: &[[f64; 2]]| -> Vec<[f64; 2]> {
                l.iter()
                    .map(|q| [q[0] * scale_uv[0], q[1] * scale_uv[1]])
                    .collect()
            };
            Some(
                Trim::new(
                    &placed.domain(),
                    t.outer().map(sc),
                    t.holes().iter().map(|h| sc(h)).collect(),
                )
                .map_err(|e| format!("its trim, scaled: {e}"))?,
            )
        }
        other => other.cloned(),
    };
    Ok((placed, trim))
}

fn scaled_box(b: &ParamBox, s: [f64; 2]) -> ParamBox {
    ParamBox::new(b.u[0] * s[0], b.u[1] * s[0], b.v[0] * s[1], b.v[1] * s[1])
}
