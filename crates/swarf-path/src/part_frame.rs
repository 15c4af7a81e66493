//! The part frame of the conversational and Sinumerik readers: where a program position is
//! on the machine once a datum shift, a rotation in the working plane and a tilted working
//! plane are in effect, and how that is told to a [`CanonSink`](crate::CanonSink).
//!
//! Machine position = `tilt · Rz(rot) · p + shift`: the plane is tilted about the shifted
//! datum, and a rotation turns within the (tilted) plane. A shift programmed while the plane
//! is tilted is measured along the tilted axes from the preset (the Heidenhain rule; an
//! incremental one adds along them to the shift in effect). The sink hears the same as
//! [`Canon::Offsets`] (the shift as G54's offset), [`Canon::XyRotation`] (the rotation, when
//! nothing is tilted) and [`Canon::WorkPlane`] (the tilt with the rotation inside it, the tool
//! turned to its Z).

use crate::{Axes, Canon, WorkPlane};

/// A 3 × 3 rotation, rows first.
pub(crate) type Mat = [[f64; 3]; 3];

pub(crate) fn rx(a: f64) -> Mat {
    let (s, c) = a.to_radians().sin_cos();
    [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]
}

pub(crate) fn ry(a: f64) -> Mat {
    let (s, c) = a.to_radians().sin_cos();
    [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]
}

pub(crate) fn rz(a: f64) -> Mat {
    let (s, c) = a.to_radians().sin_cos();
    [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
}

/// `a · b`.
pub(crate) fn mat(a: &Mat, b: &Mat) -> Mat {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

/// `m · v`.
pub(crate) fn mul(m: &Mat, v: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
}

pub(crate) fn transpose(m: &Mat) -> Mat {
    std::array::from_fn(|i| std::array::from_fn(|j| m[j][i]))
}

pub(crate) fn unit(v: [f64; 3]) -> Option<[f64; 3]> {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    (l > 1e-12 && l.is_finite()).then(|| v.map(|c| c / l))
}

pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The rotation whose columns are `x` (made orthogonal to `z`), `z × x` and `z`.
pub(crate) fn frame_of(x: [f64; 3], z: [f64; 3]) -> Option<Mat> {
    let z = unit(z)?;
    let d = x[0] * z[0] + x[1] * z[1] + x[2] * z[2];
    let x = unit([x[0] - d * z[0], x[1] - d * z[1], x[2] - d * z[2]])?;
    let y = cross(z, x);
    Some(std::array::from_fn(|i| [x[i], y[i], z[i]]))
}

/// Rotation by spatial angles: about the machine's X by `a`, then Y by `b`, then Z by `c`
/// (fixed axes).
pub(crate) fn spatial(a: f64, b: f64, c: f64) -> Mat {
    mat(&rz(c), &mat(&ry(b), &rx(a)))
}

/// Shift, rotation and tilt of the part frame.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct PartFrame {
    /// Datum shift, mm, machine axes.
    pub(crate) shift: [f64; 3],
    /// Rotation in the working plane, degrees.
    pub(crate) rot: f64,
    /// The tilted plane: its columns are the plane's axes in machine axes.
    pub(crate) tilt: Option<Mat>,
}

impl PartFrame {
    /// The turn of the program frame: the tilt, and within it the rotation about its Z.
    pub(crate) fn turn(&self) -> Mat {
        let r = rz(self.rot);
        self.tilt.map_or(r, |t| mat(&t, &r))
    }

    /// Machine position of program position `p`.
    pub(crate) fn machine_of(&self, p: [f64; 3]) -> [f64; 3] {
        let t = mul(&self.turn(), p);
        std::array::from_fn(|k| t[k] + self.shift[k])
    }

    /// Program position of machine position `m`.
    pub(crate) fn program_of(&self, m: [f64; 3]) -> [f64; 3] {
        let d = std::array::from_fn(|k| m[k] - self.shift[k]);
        mul(&transpose(&self.turn()), d)
    }

    /// A program direction in machine axes.
    pub(crate) fn direction(&self, d: [f64; 3]) -> [f64; 3] {
        mul(&self.turn(), d)
    }

    /// The shift as programmed: along the tilted axes when tilted, else machine axes.
    pub(crate) fn programmed_shift(&self) -> [f64; 3] {
        self.tilt
            .map_or(self.shift, |t| mul(&transpose(&t), self.shift))
    }

    /// Sets the shift as programmed (see [`Self::programmed_shift`]).
    pub(crate) fn set_programmed_shift(&mut self, v: [f64; 3]) {
        self.shift = self.tilt.map_or(v, |t| mul(&t, v));
    }

    /// What the sink hears of the frame: the offsets, the rotation and, when tilted, the
    /// plane (with the rotation inside it, the tool turned to its Z).
    pub(crate) fn events(&self) -> impl Iterator<Item = Canon<'static>> {
        let g5x = Axes {
            x: self.shift[0],
            y: self.shift[1],
            z: self.shift[2],
            ..Axes::default()
        };
        let rot = if self.tilt.is_some() { 0.0 } else { self.rot };
        let plane = self.tilt.map(|t| {
            Canon::WorkPlane(Some(WorkPlane {
                origin: [0.0; 3],
                rotation: mat(&t, &rz(self.rot)),
                tool_axis: true,
            }))
        });
        [
            Canon::Offsets {
                index: 1,
                g5x,
                g92: Axes::default(),
            },
            Canon::XyRotation(rot),
        ]
        .into_iter()
        .chain(plane)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spatial_angles_turn_about_fixed_axes_in_order() {
        // B+90 alone: the plane's Z turned about Y is the machine's +X.
        let r = spatial(0.0, 90.0, 0.0);
        assert!((r[0][2] - 1.0).abs() < 1e-12 && r[2][2].abs() < 1e-12);
        // A+90 then C+90: Z → −Y (about X), then about Z: −Y → +X.
        let r = spatial(90.0, 0.0, 90.0);
        let z = [r[0][2], r[1][2], r[2][2]];
        assert!((z[0] - 1.0).abs() < 1e-12 && z[1].abs() < 1e-12 && z[2].abs() < 1e-12);
        let f = frame_of([1.0, 0.0, 1.0], [0.0, 0.0, 2.0]).unwrap();
        assert_eq!(f, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
        assert!(frame_of([0.0, 0.0, 1.0], [0.0, 0.0, 1.0]).is_none());
    }

    #[test]
    fn a_shift_in_a_tilted_plane_moves_along_its_axes() {
        let mut f = PartFrame {
            shift: [1.0, 2.0, 3.0],
            tilt: Some(spatial(0.0, 90.0, 0.0)),
            ..PartFrame::default()
        };
        // Incremental: along the tilted X (the machine's −Z) from the shift in effect.
        let mut v = f.programmed_shift();
        v[0] += 10.0;
        f.set_programmed_shift(v);
        assert!((f.shift[0] - 1.0).abs() < 1e-12 && (f.shift[2] - (3.0 - 10.0)).abs() < 1e-12);
        // Absolute: from the preset.
        f.set_programmed_shift([10.0, 0.0, 0.0]);
        assert!(f.shift[0].abs() < 1e-12 && (f.shift[2] + 10.0).abs() < 1e-12);
        let p = [1.0, 2.0, 3.0];
        let q = f.program_of(f.machine_of(p));
        assert!(p.iter().zip(q).all(|(a, b)| (a - b).abs() < 1e-12));
    }
}
