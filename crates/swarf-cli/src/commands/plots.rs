//! The pictures of a run along a program: the φ–z engagement map of a location, curves along
//! the program and over a spindle revolution. Drawn with the workspace's raster and pixel font
//! so every swarf plot looks alike.

use swarf_io::OutputSet;

use anyhow::{Context, Result};
use swarf_engage::Engagement;
use swarf_io::image::{label, RgbImage};

const INK: [u8; 3] = [0, 0, 0];
const PAPER: [u8; 3] = [255, 255, 255];
const GRID: [u8; 3] = [225, 225, 225];
const ENGAGED: [u8; 3] = [200, 40, 30];
const CURVE: [u8; 3] = [30, 80, 200];

/// Plot area and margins, px.
const W: usize = 720;
const H: usize = 360;
const LEFT: usize = 70;
const TOP: usize = 40;
const BOTTOM: usize = 50;

fn axes(img: &mut RgbImage, title: &str, xlabel: &str, ylabel: &str) {
    img.text(LEFT, 12, title, 2, INK);
    img.fill(LEFT, TOP + H, W, 1, INK);
    img.fill(LEFT - 1, TOP, 1, H + 1, INK);
    img.text(
        LEFT + W / 2 - 3 * xlabel.len(),
        TOP + H + 30,
        xlabel,
        1,
        INK,
    );
    img.text(4, TOP - 14, ylabel, 1, INK);
}

fn y_ticks(img: &mut RgbImage, max: f64) {
    for t in 0..=4 {
        let v = max * t as f64 / 4.0;
        let y = TOP + H - (H as f64 * t as f64 / 4.0) as usize;
        img.fill(LEFT, y, W, 1, GRID);
        img.fill(LEFT - 5, y, 5, 1, INK);
        img.text(4, y.saturating_sub(3), &label(v), 1, INK);
    }
}

/// The φ–z engagement map of one location: engaged angle intervals per axial disc.
pub(crate) fn phi_z_map(e: &Engagement, dz: f64, set: &mut OutputSet, name: &str) -> Result<()> {
    let mut img = RgbImage::new(LEFT + W + 30, TOP + H + BOTTOM, PAPER);
    let z_top = e
        .discs
        .iter()
        .map(|d| d.at_mm + dz)
        .fold(dz, f64::max)
        .max(1.0);
    let z_max = (z_top * 1.1 * 10.0).ceil() / 10.0;
    for t in 0..=8 {
        let x = LEFT + W * t / 8;
        img.fill(x, TOP, 1, H, GRID);
        img.fill(x, TOP + H, 1, 5, INK);
        let v = format!("{}", 45 * t);
        img.text(x.saturating_sub(3 * v.len()), TOP + H + 10, &v, 1, INK);
    }
    y_ticks(&mut img, z_max);
    let px = |phi: f64| LEFT + ((phi / 360.0) * W as f64).round() as usize;
    let py = |z: f64| TOP + H - ((z / z_max) * H as f64).round().min(H as f64) as usize;
    for d in &e.discs {
        let (y0, y1) = (py(d.at_mm + 0.5 * dz), py(d.at_mm - 0.5 * dz));
        for iv in &d.intervals {
            for (a, b) in iv.split_at_zero() {
                let (x0, x1) = (px(a), px(b));
                img.fill(x0, y0, (x1 - x0).max(1), (y1 - y0).max(1), ENGAGED);
            }
        }
    }
    let title = format!(
        "location {} (line {}): {:.2} mm2 - ap {:.2} mm{}",
        e.location,
        e.line,
        e.area_mm2,
        e.ap_mm,
        if e.bottom.is_empty() {
            String::new()
        } else {
            format!(" - {} bottom rings", e.bottom.len())
        }
    );
    axes(
        &mut img,
        &title,
        "immersion angle phi (deg) clockwise from +y_L",
        "z above tip (mm)",
    );
    put(set, name, &img)
}

/// The engaged rings of a flat bottom seen from the spindle (polar: `x_L` right, `y_L` up, φ
/// clockwise from `+y_L`), written only when the bottom is engaged.
pub(crate) fn bottom_map(e: &Engagement, dr: f64, set: &mut OutputSet, name: &str) -> Result<()> {
    let Some(r_max) = e.bottom.iter().map(|c| c.at_mm + 0.5 * dr).reduce(f64::max) else {
        return Ok(());
    };
    const SIDE: usize = 360;
    let mut img = RgbImage::new(SIDE + 2 * LEFT, SIDE + TOP + BOTTOM, PAPER);
    let (cx, cy) = (LEFT + SIDE / 2, TOP + SIDE / 2);
    let scale = (SIDE / 2) as f64 / r_max;
    for py in 0..SIDE {
        for px in 0..SIDE {
            let x = (px as f64 + 0.5 - (SIDE / 2) as f64) / scale;
            let y = ((SIDE / 2) as f64 - py as f64 - 0.5) / scale;
            let r = x.hypot(y);
            if r > r_max {
                continue;
            }
            let phi = x.atan2(y).to_degrees().rem_euclid(360.0);
            let ring = e.bottom.iter().find(|c| (c.at_mm - r).abs() <= 0.5 * dr);
            let engaged = ring.is_some_and(|c| {
                c.intervals
                    .iter()
                    .any(|iv| iv.split_at_zero().any(|(a, b)| phi >= a && phi <= b))
            });
            let colour = if engaged { ENGAGED } else { GRID };
            img.fill(LEFT + px, TOP + py, 1, 1, colour);
        }
    }
    // The feed direction x_L and the φ = 0 direction y_L.
    img.fill(cx, cy, SIDE / 2 + 10, 1, INK);
    img.text(
        cx + SIDE / 2 + 12,
        cy.saturating_sub(3),
        "x_L (feed)",
        1,
        INK,
    );
    img.fill(cx, TOP - 10, 1, SIDE / 2 + 10, INK);
    img.text(cx + 4, TOP - 12, "y_L (phi 0)", 1, INK);
    let title = format!(
        "location {} (line {}): bottom face seen from the spindle - radius {} mm",
        e.location,
        e.line,
        label(r_max)
    );
    img.text(8, 12, &title, 1, INK);
    put(set, name, &img)
}

/// Puts `img` into the output set as PNG file `name`.
fn put(set: &mut OutputSet, name: &str, img: &RgbImage) -> Result<()> {
    let bytes = img
        .png_bytes()
        .with_context(|| format!("encoding {name}"))?;
    set.write_bytes(name, &bytes)?;
    Ok(())
}

/// One curve of a line plot: a legend name, its values at evenly spaced x, a colour.
pub(crate) struct Series<'a> {
    pub(crate) name: &'a str,
    pub(crate) values: &'a [f64],
    pub(crate) colour: [u8; 3],
}

/// Colours for up to four curves.
pub(crate) const PALETTE: [[u8; 3]; 4] = [CURVE, [200, 40, 30], [40, 150, 60], [120, 60, 160]];

/// Curves over `x ∈ [x0, x1]` (evenly spaced samples), y from the data (0 always shown).
pub(crate) fn lines(
    series: &[Series<'_>],
    x: (f64, f64),
    title: &str,
    xlabel: &str,
    ylabel: &str,
    set: &mut OutputSet,
    name: &str,
) -> Result<()> {
    let mut img = RgbImage::new(LEFT + W + 30, TOP + H + BOTTOM, PAPER);
    let all = series.iter().flat_map(|s| s.values.iter().copied());
    let (lo, hi) = all.fold((0.0f64, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
    let span = if hi > lo { (hi - lo) * 1.05 } else { 1.0 };
    let (lo, hi) = if lo < 0.0 {
        (lo - 0.025 * span, hi + 0.025 * span)
    } else {
        (0.0, lo + span)
    };
    for t in 0..=4 {
        let v = lo + (hi - lo) * t as f64 / 4.0;
        let y = TOP + H - (H as f64 * t as f64 / 4.0) as usize;
        img.fill(LEFT, y, W, 1, GRID);
        img.fill(LEFT - 5, y, 5, 1, INK);
        img.text(4, y.saturating_sub(3), &label(v), 1, INK);
        let xv = x.0 + (x.1 - x.0) * t as f64 / 4.0;
        let xp = LEFT + W * t / 4;
        img.fill(xp, TOP + H, 1, 5, INK);
        let s = label(xv);
        img.text(xp.saturating_sub(3 * s.len()), TOP + H + 10, &s, 1, INK);
    }
    let py = |v: f64| {
        TOP + H
            - (((v - lo) / (hi - lo)) * H as f64)
                .round()
                .clamp(0.0, H as f64) as usize
    };
    for (k, s) in series.iter().enumerate() {
        let n = s.values.len().max(2);
        let mut prev: Option<(usize, usize)> = None;
        for (i, &v) in s.values.iter().enumerate() {
            let xp = LEFT + (W as f64 * i as f64 / (n - 1) as f64).round() as usize;
            let yp = py(v);
            if let Some((x0, y0)) = prev {
                let (a, b) = (y0.min(yp), y0.max(yp));
                img.fill(x0, a, (xp - x0).max(1), b - a + 2, s.colour);
            } else {
                img.fill(xp, yp, 2, 2, s.colour);
            }
            prev = Some((xp, yp));
        }
        if series.len() > 1 {
            let lx = LEFT + W - 150;
            let ly = TOP + 8 + 14 * k;
            img.fill(lx, ly + 2, 16, 3, s.colour);
            img.text(lx + 22, ly, s.name, 1, INK);
        }
    }
    axes(&mut img, title, xlabel, ylabel);
    put(set, name, &img)
}

/// A curve of `values` over the cutter locations.
pub(crate) fn curve(
    values: &[f64],
    title: &str,
    ylabel: &str,
    set: &mut OutputSet,
    name: &str,
) -> Result<()> {
    let series = [Series {
        name: ylabel,
        values,
        colour: CURVE,
    }];
    let last = values.len().saturating_sub(1).max(1) as f64;
    lines(
        &series,
        (0.0, last),
        title,
        "cutter location",
        ylabel,
        set,
        name,
    )
}

/// Area and removal rate along the program.
pub(crate) fn along_program(
    locations: &[Engagement],
    set: &mut OutputSet,
    dir: &str,
) -> Result<()> {
    let area: Vec<f64> = locations.iter().map(|e| e.area_mm2).collect();
    let mrr: Vec<f64> = locations.iter().map(|e| e.mrr_mm3_min).collect();
    curve(
        &area,
        "engaged area along the program",
        "area (mm2)",
        set,
        &format!("{dir}area.png"),
    )?;
    curve(
        &mrr,
        "material removal rate along the program",
        "MRR (mm3/min)",
        set,
        &format!("{dir}mrr.png"),
    )
}
