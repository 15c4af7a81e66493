//! Colour maps for per-vertex colouring (e.g. deviation from a design surface, engagement):
//! a scalar in a range is mapped to linear RGBA in `[0, 1]`.

/// A colour map from `[0, 1]` to RGBA.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ColorMap {
    /// Matplotlib's perceptually uniform *viridis* (dark blue → green → yellow).
    #[default]
    Viridis,
    /// Black to white.
    Grey,
    /// Blue → white → red (for signed values; `0.5` is white).
    Diverging,
}

/// Viridis sampled at 0, 0.1, …, 1 (matplotlib's table); interpolated linearly between samples.
const VIRIDIS: [[f32; 3]; 11] = [
    [0.267_004, 0.004_874, 0.329_415],
    [0.282_623, 0.140_926, 0.457_517],
    [0.253_935, 0.265_254, 0.529_983],
    [0.206_756, 0.371_758, 0.553_117],
    [0.163_625, 0.471_133, 0.558_148],
    [0.127_568, 0.566_949, 0.550_556],
    [0.134_692, 0.658_636, 0.517_649],
    [0.266_941, 0.748_751, 0.440_573],
    [0.477_504, 0.821_444, 0.318_195],
    [0.741_388, 0.873_449, 0.149_561],
    [0.993_248, 0.906_157, 0.143_936],
];

fn lerp3(a: [f32; 3], b: [f32; 3], t: f32) -> [f32; 3] {
    [0, 1, 2].map(|k| a[k] + (b[k] - a[k]) * t)
}

impl ColorMap {
    /// Colour of `t` in `[0, 1]` (clamped; NaN maps to the low end), opaque.
    pub fn rgba(self, t: f64) -> [f32; 4] {
        let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) } as f32;
        let rgb = match self {
            ColorMap::Viridis => {
                let x = t * 10.0;
                let i = (x.floor() as usize).min(9);
                lerp3(VIRIDIS[i], VIRIDIS[i + 1], x - i as f32)
            }
            ColorMap::Grey => [t; 3],
            ColorMap::Diverging => {
                if t < 0.5 {
                    lerp3([0.230, 0.299, 0.754], [1.0; 3], t * 2.0)
                } else {
                    lerp3([1.0; 3], [0.706, 0.016, 0.150], t * 2.0 - 1.0)
                }
            }
        };
        [rgb[0], rgb[1], rgb[2], 1.0]
    }

    /// Colours of `values` mapped linearly from `[lo, hi]` onto the map (a degenerate range maps
    /// everything to the middle).
    pub fn map(self, values: &[f64], lo: f64, hi: f64) -> Vec<[f32; 4]> {
        let span = hi - lo;
        values
            .iter()
            .map(|&v| {
                let t = if span.abs() > 0.0 {
                    (v - lo) / span
                } else {
                    0.5
                };
                self.rgba(t)
            })
            .collect()
    }
}

/// A linear RGBA colour in `[0, 1]` as 8-bit RGB (clamped, rounded; alpha dropped): how the
/// PNG pictures store [`ColorMap`] colours.
pub fn rgb8(c: [f32; 4]) -> [u8; 3] {
    [c[0], c[1], c[2]].map(|x| (x.clamp(0.0, 1.0) * 255.0).round() as u8)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ends_middle_and_clamping() {
        let v = ColorMap::Viridis;
        assert_eq!(v.rgba(0.0), [0.267_004, 0.004_874, 0.329_415, 1.0]);
        assert_eq!(v.rgba(1.0), [0.993_248, 0.906_157, 0.143_936, 1.0]);
        assert_eq!(v.rgba(2.0), v.rgba(1.0));
        assert_eq!(v.rgba(f64::NAN), v.rgba(0.0));
        let mid = v.rgba(0.55);
        for k in 0..3 {
            let expect = 0.5 * (VIRIDIS[5][k] + VIRIDIS[6][k]);
            assert!((mid[k] - expect).abs() < 1e-6);
        }
        assert_eq!(ColorMap::Diverging.rgba(0.5), [1.0; 4]);
        let c = ColorMap::Grey.map(&[0.0, 5.0, 10.0], 0.0, 10.0);
        assert_eq!(c[1], [0.5, 0.5, 0.5, 1.0]);
        assert_eq!(
            ColorMap::Grey.map(&[3.0], 1.0, 1.0)[0],
            [0.5, 0.5, 0.5, 1.0]
        );
    }
}
