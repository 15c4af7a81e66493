//! Pictures of an allowable-size map: a PNG colour map per patch over its parameters `(u, v)`,
//! and the whole part as a glb whose vertices carry the colour of the allowable radius.
//!
//! # Colours
//! Finite positive radii go through [`ColorMap::Viridis`] on a **log scale** between the
//! smallest and the largest finite positive radius of the whole map ([`RadiusScale`]; one scale
//! for every patch and for the glb, so colours compare across them). The bottom is raised to
//! [`SCALE_FLOOR_MM`] (1e-3 mm) when smaller radii occur: those get the bottom colour and the
//! bottom label reads `<0.00100`. The other values have
//! their own colours, outside viridis:
//!
//! | value                               | colour                          |
//! |-------------------------------------|---------------------------------|
//! | `inf` (nothing limits the cutter)   | [`INF_RGB`], light pink         |
//! | `0` (unreachable, nothing fits)     | [`UNREACHABLE_RGB`], red        |
//! | undefined (no normal)               | [`UNDEFINED_RGB`], mid grey     |
//! | off a trimmed patch (no CC point)   | [`OFF_PART_RGB`], light grey    |
//!
//! The standard-cutter maps ([`patch_standard_image`], Liu's Fig. 4-2) colour each cell by the
//! largest standard cutter that fits there instead.
//!
//! # The PNG
//! Each CC point of the `n × n` grid is a square cell of [`PlotOptions::cell_px`] pixels, `u`
//! to the right and `v` upwards, under a title (the patch label), with a vertical colour bar
//! labelled at [`PlotOptions::ticks`] log-spaced radii and a legend of the special colours,
//! drawn with `swarf_io::image` (its built-in 5×7 pixel font, so no system font is needed and
//! the picture is the same on every machine), 8-bit RGB, written atomically.

use std::path::{Path, PathBuf};

use swarf_io::color::rgb8;
use swarf_io::image::font;
use swarf_io::image::RgbImage;
use swarf_io::{ColorMap, GlbOptions, IoError, TriMesh};

use crate::size::{StandardCutters, ToolSizeMap};
use swarf_surface::{tessellate, CompoundSurface, Tolerances};

/// Colour of `inf` radii (nothing limits the cutter).
pub const INF_RGB: [u8; 3] = [255, 170, 220];
/// Colour of radius `0` (the point cannot be machined).
pub const UNREACHABLE_RGB: [u8; 3] = [220, 20, 20];
/// Colour of points whose normal is undefined.
pub const UNDEFINED_RGB: [u8; 3] = [128, 128, 128];
/// Colour of grid points off a trimmed patch (not on the part, so not CC points).
pub const OFF_PART_RGB: [u8; 3] = [228, 228, 228];
/// Background of the PNG.
pub const BACKGROUND_RGB: [u8; 3] = [255, 255, 255];
/// Colour of text and frames.
pub const INK_RGB: [u8; 3] = [0, 0, 0];

/// Default floor of the colour scale, mm: smaller positive radii (numerical zeros of a flat
/// end mill in a concave corner, say) get the bottom colour instead of stretching the scale
/// over meaningless decades.
pub const SCALE_FLOOR_MM: f64 = 1e-3;

/// The log colour scale of finite positive radii.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RadiusScale {
    /// Radius at the bottom of the scale, mm (> 0).
    pub lo: f64,
    /// Radius at the top of the scale, mm (> `lo`).
    pub hi: f64,
    /// Whether some radii lie below `lo` (clamped to the bottom colour; the bottom label then
    /// reads `<lo`).
    pub clamped: bool,
}

impl RadiusScale {
    /// [`RadiusScale::with_floor`] at [`SCALE_FLOOR_MM`].
    pub fn from_radii(radii: impl IntoIterator<Item = Option<f64>>) -> Self {
        Self::with_floor(radii, SCALE_FLOOR_MM)
    }

    /// The scale spanning the finite positive radii given, its bottom raised to `floor_mm`
    /// when smaller radii occur; a single value `r` gives `[r/2, 2r]`, no value at all
    /// `[1, 10]` mm.
    pub fn with_floor(radii: impl IntoIterator<Item = Option<f64>>, floor_mm: f64) -> Self {
        let (lo, hi) = radii
            .into_iter()
            .flatten()
            .filter(|r| r.is_finite() && *r > 0.0)
            .fold((f64::INFINITY, 0.0_f64), |(lo, hi), r| {
                (lo.min(r), hi.max(r))
            });
        let floor = floor_mm.max(0.0);
        if lo > hi {
            return Self {
                lo: 1.0,
                hi: 10.0,
                clamped: false,
            };
        }
        let clamped = lo < floor;
        let (lo, hi) = (lo.max(floor), hi.max(floor));
        if lo == hi {
            // One value (or everything below the floor): a band around it.
            Self {
                lo: if clamped { lo } else { 0.5 * lo },
                hi: 2.0 * hi,
                clamped,
            }
        } else {
            Self { lo, hi, clamped }
        }
    }

    /// Position of `r` on the scale in `[0, 1]` (log-linear, clamped).
    pub fn t(&self, r: f64) -> f64 {
        ((r.ln() - self.lo.ln()) / (self.hi.ln() - self.lo.ln())).clamp(0.0, 1.0)
    }

    /// The radius at position `t` of the scale.
    pub fn at(&self, t: f64) -> f64 {
        (self.lo.ln() + t * (self.hi.ln() - self.lo.ln())).exp()
    }

    /// Colour of an allowable radius (`None`: undefined), 8-bit sRGB as in the PNG.
    pub fn rgb(&self, radius_mm: Option<f64>) -> [u8; 3] {
        match radius_mm {
            None => UNDEFINED_RGB,
            Some(r) if r.is_infinite() => INF_RGB,
            Some(r) if r <= 0.0 || r.is_nan() => UNREACHABLE_RGB,
            Some(r) => rgb8(ColorMap::Viridis.rgba(self.t(r))),
        }
    }

    /// Colour of an allowable radius as glTF `COLOR_0` (the same colour as the PNG).
    pub fn rgba(&self, radius_mm: Option<f64>) -> [f32; 4] {
        let [r, g, b] = self.rgb(radius_mm).map(|c| f32::from(c) / 255.0);
        [r, g, b, 1.0]
    }
}

/// Options of the PNG maps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PlotOptions {
    /// Pixels per CC point cell; `0` picks `max(4, 320 / n)`.
    pub cell_px: usize,
    /// Labelled ticks on the colour bar (at least 2).
    pub ticks: usize,
    /// Text magnification of the 5×7 font.
    pub text_scale: usize,
}

impl PlotOptions {
    /// The defaults: automatic cell size, 5 ticks, text at 2×.
    pub const DEFAULT: PlotOptions = PlotOptions {
        cell_px: 0,
        ticks: 5,
        text_scale: 2,
    };
}

impl Default for PlotOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Where things are in a patch map picture (pixels, from the top-left corner).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MapLayout {
    /// Grid points per direction.
    pub n: usize,
    /// Side of a CC point's cell.
    pub cell: usize,
    /// Left edge of the plot area.
    pub x0: usize,
    /// Top edge of the plot area.
    pub y0: usize,
    /// Image width.
    pub width: usize,
    /// Image height.
    pub height: usize,
}

impl MapLayout {
    /// The top-left pixel of the cell of grid point `(u_i, v_j)` (`u` to the right, `v` up).
    pub fn cell_origin(&self, i: usize, j: usize) -> (usize, usize) {
        (
            self.x0 + i * self.cell,
            self.y0 + (self.n - 1 - j) * self.cell,
        )
    }
}

const LEGEND: [([u8; 3], &str); 4] = [
    (INF_RGB, "inf"),
    (UNREACHABLE_RGB, "0 unreachable"),
    (UNDEFINED_RGB, "no normal"),
    (OFF_PART_RGB, "off part (trimmed)"),
];

/// What a map shows at a point of a patch's `n × n` grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MapCell {
    /// The point is off the trimmed patch: no CC point there.
    Off,
    /// The allowable radius, mm (`None` where the normal is undefined).
    Radius(Option<f64>),
}

/// The tick positions on the bar and their labels.
fn tick_labels(scale: &RadiusScale, opts: &PlotOptions) -> Vec<(f64, String)> {
    let ticks = opts.ticks.max(2);
    (0..ticks)
        .map(|k| {
            let t = k as f64 / (ticks - 1) as f64;
            let text = swarf_io::image::label(scale.at(t));
            if k == 0 && scale.clamped {
                (t, format!("<{text}"))
            } else {
                (t, text)
            }
        })
        .collect()
}

/// The layout of [`patch_radius_image`] for an `n × n` grid on `scale`.
pub fn map_layout(n: usize, scale: &RadiusScale, opts: &PlotOptions) -> MapLayout {
    let cell = if opts.cell_px == 0 {
        (320 / n.max(1)).max(4)
    } else {
        opts.cell_px
    };
    let ts = opts.text_scale.max(1);
    let (gw, lh) = (font::GLYPH_ADVANCE * ts, font::LINE_HEIGHT * ts);
    let plot = n * cell;
    let margin = 2 * gw;
    let (x0, y0) = (margin + gw, margin + lh);
    let bar_end = x0 + plot + 5 * gw;
    let label_w = tick_labels(scale, opts)
        .iter()
        .map(|(_, s)| s.len())
        .max()
        .unwrap_or(0)
        * gw;
    let legend_w = 2 * gw + LEGEND.iter().map(|(_, s)| s.len()).max().unwrap_or(0) * gw;
    MapLayout {
        n,
        cell,
        x0,
        y0,
        width: (bar_end + gw + label_w + margin).max(x0 + legend_w + margin),
        height: y0 + plot + lh + 2 + LEGEND.len() * lh + margin,
    }
}

/// The colour map of one patch: `cells[i·n + j]` is grid point `(u_i, v_j)` (the order of
/// [`CompoundSurface::lattice`]); laid out as [`map_layout`].
///
/// # Panics
/// When `cells.len() != n·n`.
pub fn patch_radius_image(
    cells: &[MapCell],
    n: usize,
    scale: &RadiusScale,
    title: &str,
    opts: &PlotOptions,
) -> RgbImage {
    assert_eq!(cells.len(), n * n, "one cell per grid point");
    let lay = map_layout(n, scale, opts);
    let (cell, x0, y0) = (lay.cell, lay.x0, lay.y0);
    let ts = opts.text_scale.max(1);
    let (gw, lh) = (font::GLYPH_ADVANCE * ts, font::LINE_HEIGHT * ts);
    let plot = n * cell;
    let margin = 2 * gw;
    let bar_x = x0 + plot + 2 * gw;
    let bar_w = 3 * gw;
    let tick_labels = tick_labels(scale, opts);
    let legend = LEGEND;
    let (width, height) = (lay.width, lay.height);
    let mut img = RgbImage::new(width, height, BACKGROUND_RGB);
    img.text(
        margin,
        margin / 2,
        &format!("{title}: radius mm (log scale)"),
        ts,
        INK_RGB,
    );
    for i in 0..n {
        for j in 0..n {
            let rgb = match cells[i * n + j] {
                MapCell::Off => OFF_PART_RGB,
                MapCell::Radius(r) => scale.rgb(r),
            };
            // u to the right, v upwards.
            let (x, y) = lay.cell_origin(i, j);
            img.fill(x, y, cell, cell, rgb);
        }
    }
    img.frame(x0, y0, plot, plot, INK_RGB);
    img.text(x0 + plot / 2 - gw / 2, y0 + plot + 3, "u", ts, INK_RGB);
    img.text(x0 - gw - 2, y0 + plot / 2 - lh / 2, "v", ts, INK_RGB);
    // The colour bar: low at the bottom.
    for y in 0..plot {
        let t = 1.0 - (y as f64 + 0.5) / plot as f64;
        let c = rgb8(ColorMap::Viridis.rgba(t));
        img.fill(bar_x, y0 + y, bar_w, 1, c);
    }
    img.frame(bar_x, y0, bar_w, plot, INK_RGB);
    for (t, s) in &tick_labels {
        let y = y0 + ((1.0 - t) * (plot - 1) as f64).round() as usize;
        img.fill(bar_x + bar_w, y, gw / 2, 1, INK_RGB);
        let ty = (y + 1).saturating_sub(7 * ts / 2).min(y0 + plot - 7 * ts);
        img.text(bar_x + bar_w + gw, ty.max(y0), s, ts, INK_RGB);
    }
    let mut ly = y0 + plot + lh + 2;
    for (rgb, s) in legend {
        img.fill(x0, ly, gw, 7 * ts, rgb);
        img.frame(x0, ly, gw, 7 * ts, INK_RGB);
        img.text(x0 + 2 * gw, ly, s, ts, INK_RGB);
        ly += lh;
    }
    img
}

/// Colour of standard cutter `k` of `count` (0 = the largest): viridis from yellow (largest)
/// down to dark blue (smallest), evenly spaced; one cutter is yellow.
pub fn standard_rgb(k: usize, count: usize) -> [u8; 3] {
    let t = if count > 1 {
        1.0 - k as f64 / (count - 1) as f64
    } else {
        1.0
    };
    rgb8(ColorMap::Viridis.rgba(t))
}

/// The standard-cutter map of one patch (Liu's Fig. 4-2): each grid cell in the colour of the
/// largest standard cutter that fits there ([`standard_rgb`]), [`UNREACHABLE_RGB`] where none
/// fits and [`UNDEFINED_RGB`] where the normal is undefined, with a legend of the diameters.
/// `radii` as in [`patch_radius_image`]; cells are laid out as [`map_layout`] places them
/// (the picture's width differs: the legend replaces the colour bar).
///
/// # Panics
/// When `cells.len() != n·n`.
pub fn patch_standard_image(
    cells: &[MapCell],
    n: usize,
    cutters: &StandardCutters,
    title: &str,
    opts: &PlotOptions,
) -> RgbImage {
    assert_eq!(cells.len(), n * n, "one cell per grid point");
    let d = cutters.diameters_mm();
    let colour = |c: MapCell| {
        let MapCell::Radius(r) = c else {
            return OFF_PART_RGB;
        };
        match (r, cutters.largest_fitting(r)) {
            (None, _) => UNDEFINED_RGB,
            (Some(_), None) => UNREACHABLE_RGB,
            (Some(_), Some(dd)) => {
                let k = d.iter().position(|x| *x == dd).unwrap_or(0);
                standard_rgb(k, d.len())
            }
        }
    };
    let mut legend: Vec<([u8; 3], String)> = d
        .iter()
        .enumerate()
        .map(|(k, x)| (standard_rgb(k, d.len()), format!("{x} mm")))
        .collect();
    legend.push((UNREACHABLE_RGB, "none fits".into()));
    legend.push((UNDEFINED_RGB, "no normal".into()));
    if cells.contains(&MapCell::Off) {
        legend.push((OFF_PART_RGB, "off part (trimmed)".into()));
    }
    let lay = map_layout(n, &RadiusScale::from_radii([]), opts);
    let ts = opts.text_scale.max(1);
    let (gw, lh) = (font::GLYPH_ADVANCE * ts, font::LINE_HEIGHT * ts);
    let plot = n * lay.cell;
    let lx = lay.x0 + plot + 2 * gw;
    let legend_w = 2 * gw + legend.iter().map(|(_, s)| s.len()).max().unwrap_or(0) * gw;
    let width = lx + legend_w + 2 * gw;
    let height = (lay.y0 + plot + lh + 2 * gw).max(lay.y0 + legend.len() * lh + 2 * gw);
    let mut img = RgbImage::new(width, height, BACKGROUND_RGB);
    img.text(
        2 * gw,
        gw,
        &format!("{title}: largest standard cutter"),
        ts,
        INK_RGB,
    );
    for i in 0..n {
        for j in 0..n {
            let (x, y) = lay.cell_origin(i, j);
            img.fill(x, y, lay.cell, lay.cell, colour(cells[i * n + j]));
        }
    }
    img.frame(lay.x0, lay.y0, plot, plot, INK_RGB);
    img.text(
        lay.x0 + plot / 2 - gw / 2,
        lay.y0 + plot + 3,
        "u",
        ts,
        INK_RGB,
    );
    img.text(
        lay.x0 - gw - 2,
        lay.y0 + plot / 2 - lh / 2,
        "v",
        ts,
        INK_RGB,
    );
    for (k, (rgb, s)) in legend.iter().enumerate() {
        let y = lay.y0 + k * lh;
        img.fill(lx, y, gw, 7 * ts, *rgb);
        img.frame(lx, y, gw, 7 * ts, INK_RGB);
        img.text(lx + 2 * gw, y, s, ts, INK_RGB);
    }
    img
}

/// Writes `dir/standard_<patch_png_name>` ([`patch_standard_image`]) for every patch of a map
/// over [`CompoundSurface::grid`]`(n)`; returns the paths.
///
/// # Errors
/// When the map is not that grid, or writing fails.
pub fn write_standard_maps(
    surface: &CompoundSurface,
    map: &ToolSizeMap,
    n: usize,
    cutters: &StandardCutters,
    dir: &Path,
    opts: &PlotOptions,
) -> Result<Vec<PathBuf>, IoError> {
    let n = n.max(2);
    let cells = cells_into(surface, map, n, dir)?;
    let mut out = Vec::with_capacity(surface.patches.len());
    for (k, chunk) in cells.chunks(n * n).enumerate() {
        let title = format!("patch {}", surface.patch_label(k));
        let img = patch_standard_image(chunk, n, cutters, &title, opts);
        let path = dir.join(format!("standard_{}", patch_png_name(surface, k)));
        img.write_png(&path)?;
        out.push(path);
    }
    Ok(out)
}

/// The file name of a patch's map: `patch_<label>.png`, the label (name, or index when
/// unnamed) with every character outside `[A-Za-z0-9_-]` replaced by `_`.
pub fn patch_png_name(surface: &CompoundSurface, patch: usize) -> String {
    format!(
        "patch_{}.png",
        swarf_surface::compound::file_safe(&surface.patch_label(patch))
    )
}

/// The map's values on [`CompoundSurface::lattice`]`(n)` of `surface` (off-part points as
/// [`MapCell::Off`]); `None` when the map is not over [`CompoundSurface::grid`]`(n)`.
fn map_cells(surface: &CompoundSurface, map: &ToolSizeMap, n: usize) -> Option<Vec<MapCell>> {
    let mut points = map.points.iter();
    let cells = surface
        .lattice(n)
        .into_iter()
        .map(|(cc, on)| {
            if !on {
                return Some(MapCell::Off);
            }
            let p = points.next()?;
            (p.cc == cc).then_some(MapCell::Radius(p.radius_mm))
        })
        .collect::<Option<Vec<_>>>()?;
    points.next().is_none().then_some(cells)
}

/// [`map_cells`] for pictures to be written into `dir`, which is created.
fn cells_into(
    surface: &CompoundSurface,
    map: &ToolSizeMap,
    n: usize,
    dir: &Path,
) -> Result<Vec<MapCell>, IoError> {
    let cells = map_cells(surface, map, n).ok_or_else(|| not_grid(dir))?;
    std::fs::create_dir_all(dir).map_err(|reason| IoError::Io {
        path: dir.to_path_buf(),
        reason,
    })?;
    Ok(cells)
}

fn not_grid(path: &Path) -> IoError {
    IoError::InvalidMesh(format!(
        "{}: the map is not the n×n grid of the surface",
        path.display()
    ))
}

/// Writes `dir/patch_<label>.png` for every patch of a map over [`CompoundSurface::grid`]`(n)`
/// (creating `dir`), all on the scale of the whole map; returns the paths.
///
/// # Errors
/// When the map is not that grid, or writing fails.
pub fn write_patch_maps(
    surface: &CompoundSurface,
    map: &ToolSizeMap,
    n: usize,
    dir: &Path,
    opts: &PlotOptions,
) -> Result<Vec<PathBuf>, IoError> {
    let n = n.max(2);
    let cells = cells_into(surface, map, n, dir)?;
    let scale = RadiusScale::from_radii(map.points.iter().map(|p| p.radius_mm));
    let mut out = Vec::with_capacity(surface.patches.len());
    for (k, chunk) in cells.chunks(n * n).enumerate() {
        let title = format!("patch {}", surface.patch_label(k));
        let img = patch_radius_image(chunk, n, &scale, &title, opts);
        let path = dir.join(patch_png_name(surface, k));
        img.write_png(&path)?;
        out.push(path);
    }
    Ok(out)
}

/// The part tessellated on the map's `n × n` grid ([`tessellate`], whose vertices are exactly
/// the points of [`CompoundSurface::lattice`]`(n)`), each vertex coloured by the allowable
/// radius there on the scale of the whole map (off-part vertices, which no kept triangle uses,
/// [`OFF_PART_RGB`]).
///
/// # Errors
/// When the map is not that grid.
pub fn part_mesh(
    surface: &CompoundSurface,
    map: &ToolSizeMap,
    n: usize,
    tol: &Tolerances,
) -> Result<TriMesh, IoError> {
    let n = n.max(2);
    let cells = map_cells(surface, map, n).ok_or_else(|| not_grid(Path::new("part")))?;
    let scale = RadiusScale::from_radii(map.points.iter().map(|p| p.radius_mm));
    let m = tessellate(surface, n, tol);
    let mut mesh = m.mesh;
    let off = OFF_PART_RGB.map(|c| f32::from(c) / 255.0);
    mesh.colors = Some(
        cells
            .iter()
            .map(|c| match c {
                MapCell::Off => [off[0], off[1], off[2], 1.0],
                MapCell::Radius(r) => scale.rgba(*r),
            })
            .collect(),
    );
    Ok(mesh)
}

/// Writes [`part_mesh`] as a glb (flat shading), atomically.
///
/// # Errors
/// When the map is not the grid, or writing fails.
pub fn write_part_glb(
    path: &Path,
    surface: &CompoundSurface,
    map: &ToolSizeMap,
    n: usize,
    tol: &Tolerances,
) -> Result<(), IoError> {
    let mesh = part_mesh(surface, map, n, tol)?;
    swarf_io::write_glb(path, &mesh, &GlbOptions::default())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_is_logarithmic_and_special_values_have_their_colours() {
        let s = RadiusScale::from_radii([Some(1.0), Some(100.0), Some(f64::INFINITY), None]);
        assert_eq!((s.lo, s.hi, s.clamped), (1.0, 100.0, false));
        let c = RadiusScale::from_radii([Some(1e-9), Some(1.0)]);
        assert_eq!((c.lo, c.hi, c.clamped), (SCALE_FLOOR_MM, 1.0, true));
        assert_eq!(c.t(1e-9), 0.0);
        let ticks = tick_labels(&c, &PlotOptions::DEFAULT);
        assert_eq!(ticks[0].1, "<0.00100");
        assert_eq!(ticks[4].1, "1.00");
        assert!((s.t(10.0) - 0.5).abs() < 1e-12);
        assert!((s.at(0.5) - 10.0).abs() < 1e-12);
        assert_eq!(s.rgb(Some(f64::INFINITY)), INF_RGB);
        assert_eq!(s.rgb(Some(0.0)), UNREACHABLE_RGB);
        assert_eq!(s.rgb(None), UNDEFINED_RGB);
        let specials = [INF_RGB, UNREACHABLE_RGB, UNDEFINED_RGB, BACKGROUND_RGB];
        for k in 0..=100 {
            let c = rgb8(ColorMap::Viridis.rgba(f64::from(k) / 100.0));
            assert!(
                !specials.contains(&c),
                "viridis hits a reserved colour {c:?}"
            );
        }
    }
}
