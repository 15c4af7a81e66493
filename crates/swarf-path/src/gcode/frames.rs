//! Fanuc's coordinate rotation (G68/G69) and scaling (G51/G50), read as a Fanuc 0i/30i-M
//! control does them (operator's manual, "Coordinate system rotation" and "Scaling").
//!
//! * `G68 X Y R`: the program's XY coordinates turn by `R` degrees (counter-clockwise) about
//!   (X, Y) — the current position when X or Y is left out — until G69. It is folded into the
//!   frame the canonical events state: with the rotation `A` about `c`, the XY part of
//!   program position + G92 offset is `c + A(p − c) + g92`, which is `A(p + g92')` with
//!   `g92' = A⁻¹(c + g92) − c`; so [`Canon::Offsets`](crate::Canon) carries `g92'` and
//!   [`Canon::XyRotation`](crate::Canon) the sum of the two rotations, and every later stage
//!   sees the rotated path. Only in G17.
//! * `G51 X Y Z P` (one factor) or `G51 X Y Z I J K` (a factor per axis): programmed positions
//!   are scaled about the centre (the current position for axes left out), incremental
//!   distances and arc centres and radii by the factor, until G50. `P` is read as the factor
//!   itself (`P1.5`); a control set to integer thousandths (`P1500`) needs the decimal form.
//!   Arcs need equal factors in their plane (otherwise they are ellipses); canned cycles are
//!   not read under scaling. G50 alone is accepted anywhere.
//! * `G68.2 X Y Z I J K` (Fanuc 30i-M "tilted working plane indexing", Haas the same): program
//!   positions are coordinates of a feature frame with origin (X, Y, Z) and axes turned by the
//!   Euler angles I, J, K — position in the untilted frame = origin + Rz(I)·Rx(J)·Rz(K)·p —
//!   until G69; `G53.1` turns the tool to the feature's Z. Stated with
//!   [`Canon::WorkPlane`](crate::Canon) and applied by the move builder (positions, arc
//!   planes, the tool axis); the interpreter keeps the same frame for G53, G28 and frame
//!   changes. Not combined with G68.

use super::block::{group, Block};
use super::interp::{rotate_xy, Interp};
use super::{Fault, Res};
use crate::{Canon, PathErrorKind, Plane, WorkPlane};

impl Interp<'_, '_> {
    /// The G92 offset and XY rotation the canonical events state: the G92 offset and the
    /// system's rotation with a G68 rotation folded in.
    pub(crate) fn effective_frame(&self, g92: &[f64; 6], rot: f64) -> ([f64; 6], f64) {
        match self.g68 {
            None => (*g92, rot),
            Some((c, a)) => {
                let mut q = *g92;
                q[0] += c[0];
                q[1] += c[1];
                let q = rotate_xy(q, -a);
                let mut out = *g92;
                out[0] = q[0] - c[0];
                out[1] = q[1] - c[1];
                (out, rot + a)
            }
        }
    }

    /// G68/G68.2/G69.
    pub(crate) fn rotation(&mut self, b: &Block, g: u16) -> Res<()> {
        let span = b.g_span(group::ROTATION);
        let m = self.machine();
        if g == 682 {
            return self.g68_2(b, m);
        }
        if g == 680 && self.tilt.is_some() {
            return Err(Fault::new(
                PathErrorKind::Semantic,
                span,
                "G68 while a tilted working plane (G68.2) is on",
                "G69 first",
            ));
        }
        if g == 690 {
            self.g68 = None;
            if let Some(w) = self.tilt.take() {
                self.held_axis |= w.tool_axis;
                self.emit(Canon::WorkPlane(None));
            }
        } else {
            if self.plane != Plane::XY {
                return Err(Fault::new(
                    PathErrorKind::Unsupported,
                    span,
                    "G68 coordinate rotation is read in the XY plane (G17) only",
                    "G17",
                ));
            }
            let r = b.get(b'r').ok_or_else(|| {
                Fault::new(
                    PathErrorKind::Semantic,
                    span,
                    "G68 needs the angle R",
                    "R<degrees>",
                )
            })?;
            let c = [
                b.get(b'x').map_or(self.p[0], |v| self.mm_from_units(0, v)),
                b.get(b'y').map_or(self.p[1], |v| self.mm_from_units(1, v)),
            ];
            self.g68 = Some((c, r));
        }
        // The tool stays where it is; its program coordinates are now the rotated frame's.
        self.p = self.program_of(&m, &self.off, &self.g92, self.rot);
        self.emit_offsets();
        Ok(())
    }

    /// `G68.2 [P0] X Y Z I J K`: a tilted working plane (feature coordinate system) whose origin
    /// is (X, Y, Z) in the current program frame (absolute, in program units; 0 when left out)
    /// and whose axes are the frame's turned by the Euler angles I, J, K (degrees): about Z,
    /// then about the new X, then about the new Z. Program positions are the feature's
    /// coordinates from here on; the tool stays where it is. A new G68.2 replaces the plane.
    fn g68_2(&mut self, b: &Block, m: [f64; 6]) -> Res<()> {
        let span = b.g_span(group::ROTATION);
        if self.g68.is_some() {
            return Err(Fault::new(
                PathErrorKind::Semantic,
                span,
                "G68.2 while a G68 rotation is on",
                "G69 first",
            ));
        }
        if let Some(p) = b.get(b'p').filter(|p| *p != 0.0) {
            return Err(Fault::new(
                PathErrorKind::Unsupported,
                b.span(b'p'),
                format!(
                    "G68.2 P{p} (roll-pitch-yaw, three points, two vectors or projection \
                     angles) is not read; G68.2 with Euler angles (P0, the default) is"
                ),
                "G68.2 X Y Z I J K",
            ));
        }
        // The origin is given in the untilted frame, whatever plane was on.
        self.tilt = None;
        let origin = [b'x', b'y', b'z'].map(|c| b.get(c).unwrap_or(0.0) * self.scale);
        let [i, j, k] = [b'i', b'j', b'k'].map(|c| b.get(c).unwrap_or(0.0).to_radians());
        use swarf_geom::math::Mat3;
        let r = Mat3::from_rotation_z(i) * Mat3::from_rotation_x(j) * Mat3::from_rotation_z(k);
        self.tilt = Some(WorkPlane {
            origin,
            rotation: std::array::from_fn(|row| std::array::from_fn(|col| r.col(col)[row])),
            tool_axis: false,
        });
        self.p = self.program_of(&m, &self.off, &self.g92, self.rot);
        self.emit(Canon::WorkPlane(self.tilt));
        Ok(())
    }

    /// `G53.1`: the tool is turned to the tilted plane's Z (the control's rotary axes do it).
    pub(crate) fn g53_1(&mut self, b: &Block) -> Res<()> {
        let Some(w) = &mut self.tilt else {
            return Err(Fault::new(
                PathErrorKind::Semantic,
                b.g_span(group::NON_MODAL),
                "G53.1 without a tilted working plane",
                "G68.2 before it",
            ));
        };
        w.tool_axis = true;
        let w = *w;
        self.held_axis = false;
        self.emit(Canon::WorkPlane(Some(w)));
        Ok(())
    }

    /// G51/G50.
    pub(crate) fn scaling(&mut self, b: &Block, g: u16) -> Res<()> {
        if g == 500 {
            self.g51 = None;
            return Ok(());
        }
        let span = b.g_span(group::SCALING);
        let mut center = [self.p[0], self.p[1], self.p[2]];
        for (i, c) in [b'x', b'y', b'z'].into_iter().enumerate() {
            if let Some(v) = b.get(c) {
                center[i] = self.mm_from_units(i, v);
            }
        }
        let factors = match b.get(b'p') {
            Some(p) => [p; 3],
            None if b.has(b'i') || b.has(b'j') || b.has(b'k') => [
                b.get(b'i').unwrap_or(1.0),
                b.get(b'j').unwrap_or(1.0),
                b.get(b'k').unwrap_or(1.0),
            ],
            None => {
                return Err(Fault::new(
                    PathErrorKind::Semantic,
                    span,
                    "G51 needs the scale factor",
                    "P<factor>, or I J K (a factor per axis)",
                ))
            }
        };
        if factors.iter().any(|f| !f.is_finite() || *f == 0.0) {
            return Err(Fault::semantic(span, "bad G51 scale factor"));
        }
        self.g51 = Some((center, factors));
        Ok(())
    }

    /// An absolute position word of axis `i` (mm) as scaled by G51.
    #[inline]
    pub(crate) fn scaled_position(&self, i: usize, v: f64) -> f64 {
        match self.g51 {
            Some((c, f)) if i < 3 => c[i] + f[i] * (v - c[i]),
            _ => v,
        }
    }

    /// An incremental distance of axis `i` (mm) as scaled by G51.
    #[inline]
    pub(crate) fn scaled_length(&self, i: usize, v: f64) -> f64 {
        match self.g51 {
            Some((_, f)) if i < 3 => f[i] * v,
            _ => v,
        }
    }

    /// The one factor an arc in the current plane is scaled by.
    pub(crate) fn arc_scale(&self, span: super::Span) -> Res<f64> {
        match self.g51 {
            None => Ok(1.0),
            Some((_, f)) => {
                let (a, b, _) = self.plane.axes();
                if f[a] == f[b] {
                    Ok(f[a])
                } else {
                    Err(Fault::new(
                        PathErrorKind::Unsupported,
                        span,
                        "an arc under unequal scale factors (G51 I J K) is an ellipse: not read",
                        "equal factors in the arc's plane",
                    ))
                }
            }
        }
    }
}
