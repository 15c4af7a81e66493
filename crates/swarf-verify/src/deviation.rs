//! The machined part coloured by its signed deviation from the design: the deviation map a
//! CAM programmer reads (red where the part is gouged, blue where material is left, white on
//! the design).

use rayon::prelude::*;
use swarf_io::{ColorMap, ContourOptions, TriMesh};
use swarf_stock::TriDexel;

use crate::design::Design;

/// Colour of vertices about which the design says nothing (beyond an open surface).
pub const UNMATCHED_RGBA: [f32; 4] = [0.6, 0.6, 0.6, 1.0];

/// The range and meaning of the colours of a deviation mesh (written in a glb's extras).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Legend {
    /// What is shown.
    pub quantity: &'static str,
    /// Deviation at the red end (gouge), mm: `-range_mm`.
    pub min_mm: f64,
    /// Deviation at the blue end (excess), mm: `range_mm`.
    pub max_mm: f64,
    /// Colour at `min_mm`, at 0 and at `max_mm`.
    pub colors: [&'static str; 3],
    /// Colour of vertices the design says nothing about.
    pub unmatched: &'static str,
    /// Largest deviation at a vertex, mm (gouge, excess), both ≥ 0.
    pub vertex_max_gouge_mm: f64,
    /// Largest excess at a vertex, mm.
    pub vertex_max_excess_mm: f64,
}

/// The stock's surface (contoured as by `simulate`) with every vertex coloured by the signed
/// distance to `design`, on a diverging scale from `-range_mm` (red, gouge) through 0 (white)
/// to `+range_mm` (blue, excess); deviations beyond the range take the end colours.
pub fn deviation_mesh(stock: &TriDexel, design: &dyn Design, range_mm: f64) -> (TriMesh, Legend) {
    let (mut mesh, _) = stock.to_mesh(&ContourOptions::default());
    let r = if range_mm > 0.0 && range_mm.is_finite() {
        range_mm
    } else {
        1.0
    };
    let devs: Vec<Option<f64>> = mesh
        .vertices
        .par_iter()
        .map(|&p| design.project(p).map(|pr| pr.distance))
        .collect();
    let colors = devs
        .iter()
        .map(|d| match d {
            // Diverging: 0 = blue, 1 = red; excess (d > 0) towards blue.
            Some(d) => ColorMap::Diverging.rgba(0.5 - d / (2.0 * r)),
            None => UNMATCHED_RGBA,
        })
        .collect();
    mesh.colors = Some(colors);
    let (g, e) = devs
        .iter()
        .flatten()
        .fold((0.0f64, 0.0f64), |(g, e), &d| (g.max(-d), e.max(d)));
    (
        mesh,
        Legend {
            quantity: "signed deviation of the machined surface from the design, mm \
                       (negative: gouge, inside the part; positive: excess, material left)",
            min_mm: -r,
            max_mm: r,
            colors: ["red", "white", "blue"],
            unmatched: "grey",
            vertex_max_gouge_mm: g,
            vertex_max_excess_mm: e,
        },
    )
}
