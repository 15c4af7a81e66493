//! Raster pictures drawn the same way by every crate: an 8-bit RGB image with rectangles and
//! text in a built-in 5×7 pixel font (no system font, so a picture is byte-identical on every
//! machine), written as PNG atomically.
//!
//! ```
//! use swarf_io::image::RgbImage;
//! let mut img = RgbImage::new(40, 12, [255, 255, 255]);
//! img.text(1, 1, "r:2.5", 1, [0, 0, 0]);
//! img.frame(1, 1, 38, 10, [200, 0, 0]);
//! assert_eq!(img.get(0, 0), [200, 0, 0]);
//! let png = img.png_bytes().unwrap();
//! assert_eq!(&png[1..4], b"PNG");
//! ```

pub mod font;

use std::path::Path;

use crate::IoError;

/// An 8-bit RGB raster, rows from the top.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RgbImage {
    /// Width, px.
    pub width: usize,
    /// Height, px.
    pub height: usize,
    /// `width · height · 3` bytes, row-major from the top-left corner.
    pub pixels: Vec<u8>,
}

impl RgbImage {
    /// An image filled with `rgb`.
    pub fn new(width: usize, height: usize, rgb: [u8; 3]) -> Self {
        Self {
            width,
            height,
            pixels: rgb.repeat(width * height),
        }
    }

    /// The pixel at column `x`, row `y` (from the top).
    pub fn get(&self, x: usize, y: usize) -> [u8; 3] {
        let i = 3 * (y * self.width + x);
        [self.pixels[i], self.pixels[i + 1], self.pixels[i + 2]]
    }

    /// Fills the rectangle `[x, x + w) × [y, y + h)`, clipped to the image.
    pub fn fill(&mut self, x: usize, y: usize, w: usize, h: usize, rgb: [u8; 3]) {
        for yy in y..(y + h).min(self.height) {
            for xx in x..(x + w).min(self.width) {
                let i = 3 * (yy * self.width + xx);
                self.pixels[i..i + 3].copy_from_slice(&rgb);
            }
        }
    }

    /// A one-pixel frame around the rectangle `[x, x + w) × [y, y + h)`, outside it.
    pub fn frame(&mut self, x: usize, y: usize, w: usize, h: usize, rgb: [u8; 3]) {
        let (x0, y0) = (x.saturating_sub(1), y.saturating_sub(1));
        self.fill(x0, y0, w + 2, 1, rgb);
        self.fill(x0, y + h, w + 2, 1, rgb);
        self.fill(x0, y0, 1, h + 2, rgb);
        self.fill(x + w, y0, 1, h + 2, rgb);
    }

    /// Draws `text` with its top-left corner at `(x, y)` in the built-in font, `scale`× size.
    pub fn text(&mut self, x: usize, y: usize, text: &str, scale: usize, rgb: [u8; 3]) {
        for (k, ch) in text.chars().enumerate() {
            let rows = font::glyph(ch);
            let gx = x + k * font::GLYPH_ADVANCE * scale;
            for (r, row) in rows.iter().enumerate() {
                for (c, b) in row.bytes().enumerate() {
                    if b == b'#' {
                        self.fill(gx + c * scale, y + r * scale, scale, scale, rgb);
                    }
                }
            }
        }
    }

    /// The PNG file of the image in memory.
    ///
    /// # Errors
    /// When the encoder fails (it does not for a consistent image).
    pub fn png_bytes(&self) -> std::io::Result<Vec<u8>> {
        let mut out = Vec::new();
        let mut enc = png::Encoder::new(&mut out, self.width as u32, self.height as u32);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut w = enc.write_header().map_err(std::io::Error::other)?;
        w.write_image_data(&self.pixels)
            .map_err(std::io::Error::other)?;
        w.finish().map_err(std::io::Error::other)?;
        Ok(out)
    }

    /// Writes the image as PNG, atomically.
    ///
    /// # Errors
    /// When writing fails.
    pub fn write_png(&self, path: &Path) -> Result<(), IoError> {
        let bytes = self.png_bytes().map_err(|reason| IoError::Io {
            path: path.to_path_buf(),
            reason,
        })?;
        crate::write_atomic(path, |w| std::io::Write::write_all(w, &bytes))
    }
}

/// `x` with three significant digits, in plain or exponent form: the tick labels of every plot.
pub fn label(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let e = x.abs().log10().floor();
    if !(-3.0..5.0).contains(&e) {
        format!("{x:.2e}")
    } else {
        let dec = (2.0 - e).max(0.0) as usize;
        format!("{x:.dec$}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_have_three_significant_digits() {
        assert_eq!(label(12.345), "12.3");
        assert_eq!(label(0.5), "0.500");
        assert_eq!(label(1234.0), "1234");
        assert_eq!(label(123_456.0), "1.23e5");
        assert_eq!(label(0.000_123_4), "1.23e-4");
    }
}
