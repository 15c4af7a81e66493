//! Standard cutters on an allowable-size map (Liu 2007, §4.2): the largest standard cutter at
//! every CC point, the share of the surface area each one can finish, and a small suggested set
//! that covers the surface with the largest tools.
//!
//! # Rules
//! * **Fit.** A standard cutter of diameter `D` fits a CC point when
//!   `D/2 ≤ radius_mm + fit_tol` (the allowable radius of the map; `fit_tol` is
//!   [`StandardCutters::fit_tol_mm`], default [`FIT_TOL_MM`] = 1e-6 mm, so that a solver
//!   answer of 4.9999999 mm for an exact 5 mm still takes the 10 mm cutter; set it to 0 for
//!   the strict rule). `inf` fits every cutter; `0` (unreachable)
//!   and an undefined radius (no normal) fit none. Fitting is monotone: where a cutter fits,
//!   every smaller one fits too.
//! * **Area of a point.** A CC point of an `n × n` iso-parametric grid stands for its parameter
//!   cell: the points of the patch's parameter box nearer to it than to its grid neighbours,
//!   i.e. `[u_{i−½}, u_{i+½}] × [v_{j−½}, v_{j+½}]` clipped to the box (half cells on the
//!   edges, quarter cells at the corners). Its area `∫∫ |S_u × S_v| du dv` is integrated with
//!   the tensor Gauss–Legendre rule of [`AreaRule`] (default 4 × 4 nodes, exact for
//!   polynomial integrands of degree 7 in each parameter). The cells tile every patch, so the
//!   cell areas add up to the patch area. On a trimmed patch a point stands for its cell's
//!   part on the part (the cell is quartered where the trim boundary crosses it, six levels
//!   deep, and the last level's nodes off the part weigh nothing), and grid points off the
//!   part are not CC points, so the sliver of the part in their cells is not counted.
//! * **Share.** The share of a cutter is the area of the cells where it fits over the total
//!   area of the map.
//! * **Suggested set** ([`StandardOptions::min_gain_share`]): go through the cutters from the
//!   largest down; each one *would finish* the area where it fits that no larger chosen cutter
//!   finishes. A cutter is chosen when that area is at least `min_gain_share` of the total
//!   area, and always when it is the *finishing cutter* — the smallest one needed, i.e. the
//!   largest cutter that fits at every reachable point (where some standard cutter fits). The
//!   walk stops at the finishing cutter: everything reachable is covered by then. Area a
//!   skipped cutter would have finished falls to the next chosen smaller one. With
//!   `min_gain_share = 0` the set is every cutter that is the largest fitting one somewhere.
//!   What no standard cutter fits is reported as uncovered (unreachable), and the cells whose
//!   normal is undefined separately.

use swarf_geom::math::Vec3;

use super::map::ToolSizeMap;
use swarf_surface::Coverage;
use swarf_surface::{CcPoint, CompoundSurface, ParametricSurface};

/// Errors of the standard-cutter list.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum StandardError {
    /// No diameters were given.
    #[error("the standard cutter list is empty")]
    Empty,
    /// A diameter is not a positive finite number.
    #[error("standard cutter diameter `{0}` is not a positive finite number of mm")]
    BadDiameter(String),
    /// The map is not an `n × n` grid of the surface's patches in [`CompoundSurface::grid`]
    /// order.
    #[error("the map has {points} points, not a {n}×{n} grid of {patches} patches")]
    NotAGrid {
        /// Points in the map.
        points: usize,
        /// Grid size asked for.
        n: usize,
        /// Patches of the surface.
        patches: usize,
    },
}

/// Default slack (mm) of the fit test: the accuracy the allowable radius is computed to
/// (the 1e-6 mm), far below machining tolerances.
pub const FIT_TOL_MM: f64 = 1e-6;

/// A list of standard cutter diameters (mm), kept sorted from the largest down, without
/// duplicates, with the slack of the fit test.
#[derive(Clone, Debug, PartialEq)]
pub struct StandardCutters {
    diameters_mm: Vec<f64>,
    fit_tol_mm: f64,
}

impl StandardCutters {
    /// The list from diameters in any order (duplicates are dropped).
    ///
    /// # Errors
    /// [`StandardError::Empty`] for an empty list, [`StandardError::BadDiameter`] for a
    /// diameter that is not positive and finite.
    pub fn new(diameters_mm: &[f64]) -> Result<Self, StandardError> {
        if diameters_mm.is_empty() {
            return Err(StandardError::Empty);
        }
        if let Some(d) = diameters_mm.iter().find(|d| !(d.is_finite() && **d > 0.0)) {
            return Err(StandardError::BadDiameter(d.to_string()));
        }
        let mut d = diameters_mm.to_vec();
        d.sort_by(|a, b| b.total_cmp(a));
        d.dedup();
        Ok(Self {
            diameters_mm: d,
            fit_tol_mm: FIT_TOL_MM,
        })
    }

    /// Parses `D1,D2,...` (mm, as the CLI's `--standard`).
    ///
    /// # Errors
    /// As [`StandardCutters::new`], and [`StandardError::BadDiameter`] for text that is not a
    /// number.
    pub fn parse(list: &str) -> Result<Self, StandardError> {
        let d = list
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(|s| {
                s.parse::<f64>()
                    .map_err(|_| StandardError::BadDiameter(s.to_string()))
            })
            .collect::<Result<Vec<_>, _>>()?;
        Self::new(&d)
    }

    /// The diameters, from the largest down.
    pub fn diameters_mm(&self) -> &[f64] {
        &self.diameters_mm
    }

    /// The same list with another fit slack, mm (`≥ 0`; negative values count as 0).
    pub fn with_fit_tolerance(mut self, fit_tol_mm: f64) -> Self {
        self.fit_tol_mm = fit_tol_mm.max(0.0);
        self
    }

    /// The slack of the fit test, mm.
    pub fn fit_tol_mm(&self) -> f64 {
        self.fit_tol_mm
    }

    /// Whether a cutter of diameter `d_mm` fits an allowable radius (`None`: undefined, `0`:
    /// unreachable — neither fits anything).
    pub fn fits(&self, d_mm: f64, radius_mm: Option<f64>) -> bool {
        radius_mm.is_some_and(|r| r > 0.0 && 0.5 * d_mm <= r + self.fit_tol_mm)
    }

    /// The largest standard diameter that fits the allowable radius `radius_mm`; `None` when
    /// even the smallest does not fit (or the radius is undefined).
    pub fn largest_fitting(&self, radius_mm: Option<f64>) -> Option<f64> {
        self.diameters_mm
            .iter()
            .copied()
            .find(|&d| self.fits(d, radius_mm))
    }

    /// [`StandardCutters::largest_fitting`] at every point of a map, in its order.
    pub fn per_point(&self, map: &ToolSizeMap) -> Vec<Option<f64>> {
        map.points
            .iter()
            .map(|p| self.largest_fitting(p.radius_mm))
            .collect()
    }
}

/// Header of the column [`StandardCutters::write_csv`] appends.
pub const STANDARD_COLUMN: &str = "standard_d_mm";

impl StandardCutters {
    /// Writes the map's CSV ([`ToolSizeMap::write_csv`], whatever columns it has) with one more
    /// column at the end, [`STANDARD_COLUMN`]: the diameter of the largest standard cutter that
    /// fits the point, empty when none fits (`radius_mm` tells why: `0`, too small, or
    /// undefined).
    ///
    /// # Errors
    /// When writing fails, or the map's CSV does not have one record per point.
    pub fn write_csv(
        &self,
        map: &ToolSizeMap,
        surface: &CompoundSurface,
        mut w: impl std::io::Write,
    ) -> std::io::Result<()> {
        let mut base = Vec::new();
        map.write_csv(surface, &mut base)?;
        let records = split_records(&base);
        if records.len() != map.points.len() + 1 {
            return Err(std::io::Error::other(format!(
                "the map CSV has {} records for {} points",
                records.len(),
                map.points.len()
            )));
        }
        w.write_all(records[0])?;
        writeln!(w, ",{STANDARD_COLUMN}")?;
        for (rec, p) in records[1..].iter().zip(&map.points) {
            w.write_all(rec)?;
            match self.largest_fitting(p.radius_mm) {
                Some(d) => writeln!(w, ",{d:?}")?,
                None => writeln!(w, ",")?,
            }
        }
        Ok(())
    }
}

/// The records of a CSV text without their line ends (`\n` outside double quotes ends a
/// record; quoted fields may hold newlines).
fn split_records(csv: &[u8]) -> Vec<&[u8]> {
    let mut out = Vec::new();
    let (mut start, mut quoted) = (0, false);
    for (i, &b) in csv.iter().enumerate() {
        match b {
            b'"' => quoted = !quoted,
            b'\n' if !quoted => {
                let end = if i > start && csv[i - 1] == b'\r' {
                    i - 1
                } else {
                    i
                };
                out.push(&csv[start..end]);
                start = i + 1;
            }
            _ => {}
        }
    }
    if start < csv.len() {
        out.push(&csv[start..]);
    }
    out
}

/// The quadrature of the cell areas: a tensor Gauss–Legendre rule.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AreaRule {
    /// Nodes per parameter direction, 1 to 5 (exact for polynomials of degree `2·nodes − 1`).
    pub nodes: usize,
}

impl AreaRule {
    /// The default: 4 × 4 nodes per cell.
    pub const DEFAULT: AreaRule = AreaRule { nodes: 4 };

    /// Nodes on `[−1, 1]` and weights of the rule (`nodes` clamped to 1..=5).
    fn nodes_weights(self) -> (&'static [f64], &'static [f64]) {
        const X1: [f64; 1] = [0.0];
        const W1: [f64; 1] = [2.0];
        const X2: [f64; 2] = [-0.577_350_269_189_625_8, 0.577_350_269_189_625_8];
        const W2: [f64; 2] = [1.0, 1.0];
        const X3: [f64; 3] = [-0.774_596_669_241_483_4, 0.0, 0.774_596_669_241_483_4];
        const W3: [f64; 3] = [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0];
        const X4: [f64; 4] = [
            -0.861_136_311_594_052_6,
            -0.339_981_043_584_856_3,
            0.339_981_043_584_856_3,
            0.861_136_311_594_052_6,
        ];
        const W4: [f64; 4] = [
            0.347_854_845_137_453_85,
            0.652_145_154_862_546_1,
            0.652_145_154_862_546_1,
            0.347_854_845_137_453_85,
        ];
        const X5: [f64; 5] = [
            -0.906_179_845_938_664,
            -0.538_469_310_105_683_1,
            0.0,
            0.538_469_310_105_683_1,
            0.906_179_845_938_664,
        ];
        const W5: [f64; 5] = [
            0.236_926_885_056_189_08,
            0.478_628_670_499_366_47,
            0.568_888_888_888_888_9,
            0.478_628_670_499_366_47,
            0.236_926_885_056_189_08,
        ];
        match self.nodes {
            0 | 1 => (&X1, &W1),
            2 => (&X2, &W2),
            3 => (&X3, &W3),
            4 => (&X4, &W4),
            _ => (&X5, &W5),
        }
    }
}

impl Default for AreaRule {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// `∫∫ |S_u × S_v| du dv` of patch `patch` over `[u0, u1] × [v0, v1]`.
pub fn param_area(
    surface: &CompoundSurface,
    patch: usize,
    u: [f64; 2],
    v: [f64; 2],
    rule: AreaRule,
) -> f64 {
    quadrature(surface, patch, u, v, rule, |_, _| true)
}

/// The tensor Gauss–Legendre rule for `∫∫ |S_u × S_v| du dv` over `[u0, u1] × [v0, v1]`, nodes
/// where `keep` is false weighing nothing.
fn quadrature(
    surface: &CompoundSurface,
    patch: usize,
    u: [f64; 2],
    v: [f64; 2],
    rule: AreaRule,
    keep: impl Fn(f64, f64) -> bool,
) -> f64 {
    let s = &surface.patches[patch].surface;
    let (x, w) = rule.nodes_weights();
    let (hu, hv) = (0.5 * (u[1] - u[0]), 0.5 * (v[1] - v[0]));
    let (cu, cv) = (0.5 * (u[0] + u[1]), 0.5 * (v[0] + v[1]));
    let mut sum = 0.0;
    for (xi, wi) in x.iter().zip(w) {
        for (xj, wj) in x.iter().zip(w) {
            let (pu, pv) = (cu + hu * xi, cv + hv * xj);
            if keep(pu, pv) {
                let d = s.derivs(pu, pv);
                let j: Vec3 = d.su.cross(d.sv);
                sum += wi * wj * j.length();
            }
        }
    }
    sum * hu * hv
}

/// `∫∫ |S_u × S_v| du dv` of patch `patch` over the part of `[u0, u1] × [v0, v1]` inside its
/// trim (see the module rules; the whole rectangle for an untrimmed patch).
pub fn trimmed_param_area(
    surface: &CompoundSurface,
    patch: usize,
    u: [f64; 2],
    v: [f64; 2],
    rule: AreaRule,
) -> f64 {
    let Some(trim) = &surface.patches[patch].trim else {
        return param_area(surface, patch, u, v, rule);
    };
    let mut stack = vec![(u, v, 0u32)];
    let mut sum = 0.0;
    while let Some((u, v, depth)) = stack.pop() {
        match trim.coverage([u[0], u[1], v[0], v[1]]) {
            Coverage::Outside => {}
            Coverage::Inside => sum += param_area(surface, patch, u, v, rule),
            Coverage::Crossing if depth < TRIM_AREA_LEVELS => {
                let (um, vm) = (0.5 * (u[0] + u[1]), 0.5 * (v[0] + v[1]));
                for (a, b) in [([u[0], um], [v[0], vm]), ([um, u[1]], [v[0], vm])] {
                    stack.push((a, b, depth + 1));
                }
                for (a, b) in [([u[0], um], [vm, v[1]]), ([um, u[1]], [vm, v[1]])] {
                    stack.push((a, b, depth + 1));
                }
            }
            Coverage::Crossing => {
                sum += quadrature(surface, patch, u, v, rule, |a, b| trim.contains(a, b));
            }
        }
    }
    sum
}

/// Levels of quartering of a grid cell the trim boundary crosses (see the module rules).
const TRIM_AREA_LEVELS: u32 = 6;

/// The area (mm²) each point of [`CompoundSurface::grid`]`(n)` stands for, in the grid's
/// order (see the module rules).
pub fn grid_cell_areas(surface: &CompoundSurface, n: usize, rule: AreaRule) -> Vec<f64> {
    let n = n.max(2);
    let mut out = Vec::with_capacity(surface.patches.len() * n * n);
    for (k, p) in surface.patches.iter().enumerate() {
        let d = p.surface.domain();
        // Cell edges: the domain ends and the midpoints between grid parameters.
        let edges = |at: &dyn Fn(f64) -> f64| -> Vec<[f64; 2]> {
            (0..n)
                .map(|i| {
                    let lo = if i == 0 {
                        at(0.0)
                    } else {
                        0.5 * (at((i - 1) as f64 / (n - 1) as f64) + at(i as f64 / (n - 1) as f64))
                    };
                    let hi = if i == n - 1 {
                        at(1.0)
                    } else {
                        0.5 * (at(i as f64 / (n - 1) as f64) + at((i + 1) as f64 / (n - 1) as f64))
                    };
                    [lo, hi]
                })
                .collect()
        };
        let ue = edges(&|s| d.u_at(s));
        let ve = edges(&|t| d.v_at(t));
        for (i, cu) in ue.iter().enumerate() {
            let u = d.u_at(i as f64 / (n - 1) as f64);
            for (j, cv) in ve.iter().enumerate() {
                if p.on_part(u, d.v_at(j as f64 / (n - 1) as f64)) {
                    out.push(trimmed_param_area(surface, k, *cu, *cv, rule));
                }
            }
        }
    }
    out
}

/// Options of the standard-cutter report.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StandardOptions {
    /// A cutter larger than the finishing cutter joins the suggested set only when it would
    /// finish at least this share of the total area. Default `0.05` (5 %).
    pub min_gain_share: f64,
    /// The quadrature of the cell areas.
    pub rule: AreaRule,
}

impl StandardOptions {
    /// The documented defaults.
    pub const DEFAULT: StandardOptions = StandardOptions {
        min_gain_share: 0.05,
        rule: AreaRule::DEFAULT,
    };
}

impl Default for StandardOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// One standard cutter in the report.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct CutterShare {
    /// Diameter, mm.
    pub diameter_mm: f64,
    /// Area of the cells where it fits, mm².
    pub fits_area_mm2: f64,
    /// `fits_area_mm2` over the total area.
    pub fits_share: f64,
    /// CC points where it is the largest fitting standard cutter.
    pub largest_at_points: usize,
    /// Whether it is in the suggested set.
    pub suggested: bool,
    /// Area it finishes in the suggested set, mm² (0 when not suggested).
    pub finishes_area_mm2: f64,
    /// `finishes_area_mm2` over the total area.
    pub finishes_share: f64,
}

/// The standard-cutter report of a map (see the module rules).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct StandardReport {
    /// One entry per cutter, from the largest down.
    pub cutters: Vec<CutterShare>,
    /// The suggested set's diameters, from the largest down.
    pub suggested_mm: Vec<f64>,
    /// Total area of the map's cells, mm².
    pub total_area_mm2: f64,
    /// Area no standard cutter fits (unreachable or too tight), mm², normal defined.
    pub uncovered_area_mm2: f64,
    /// `uncovered_area_mm2` over the total area.
    pub uncovered_share: f64,
    /// Area of cells whose normal is undefined, mm².
    pub undefined_area_mm2: f64,
    /// The minimum share a larger cutter must add to be suggested.
    pub min_gain_share: f64,
    /// Gauss–Legendre nodes per direction of the cell areas.
    pub area_rule_nodes: usize,
    /// Slack of the fit test, mm.
    pub fit_tol_mm: f64,
}

impl StandardReport {
    /// The report of allowable radii `radii` (`None`: undefined) with cell areas `areas`.
    ///
    /// # Panics
    /// When the two slices differ in length.
    pub fn from_radii(
        cutters: &StandardCutters,
        radii: &[Option<f64>],
        areas: &[f64],
        opts: &StandardOptions,
    ) -> StandardReport {
        assert_eq!(radii.len(), areas.len(), "one area per radius");
        let total = sum(areas.iter().copied());
        let share = |a: f64| if total > 0.0 { a / total } else { 0.0 };
        let largest: Vec<Option<f64>> = radii.iter().map(|&r| cutters.largest_fitting(r)).collect();
        let undefined = sum(radii
            .iter()
            .zip(areas)
            .filter(|(r, _)| r.is_none())
            .map(|(_, a)| *a));
        let uncovered = sum(radii
            .iter()
            .zip(&largest)
            .zip(areas)
            .filter(|((r, l), _)| r.is_some() && l.is_none())
            .map(|(_, a)| *a));
        // The finishing cutter: the smallest "largest fitting" over the reachable points.
        let finishing = largest.iter().flatten().copied().min_by(f64::total_cmp);
        let mut out = Vec::with_capacity(cutters.diameters_mm.len());
        // Points not yet finished by a chosen cutter.
        let mut open: Vec<bool> = largest.iter().map(Option::is_some).collect();
        let mut done = finishing.is_none();
        for &d in &cutters.diameters_mm {
            let fits_area = sum(radii
                .iter()
                .zip(areas)
                .filter(|(r, _)| cutters.fits(d, **r))
                .map(|(_, a)| *a));
            let largest_at = largest.iter().filter(|l| **l == Some(d)).count();
            let gain = sum(radii
                .iter()
                .zip(areas)
                .zip(&open)
                .filter(|((r, _), o)| **o && cutters.fits(d, **r))
                .map(|((_, a), _)| *a));
            let is_finishing = finishing == Some(d);
            let chosen =
                !done && gain > 0.0 && (is_finishing || share(gain) >= opts.min_gain_share);
            if chosen {
                for (o, r) in open.iter_mut().zip(radii) {
                    if cutters.fits(d, *r) {
                        *o = false;
                    }
                }
            }
            if is_finishing {
                done = true;
            }
            out.push(CutterShare {
                diameter_mm: d,
                fits_area_mm2: fits_area,
                fits_share: share(fits_area),
                largest_at_points: largest_at,
                suggested: chosen,
                finishes_area_mm2: if chosen { gain } else { 0.0 },
                finishes_share: if chosen { share(gain) } else { 0.0 },
            });
        }
        StandardReport {
            suggested_mm: out
                .iter()
                .filter(|c| c.suggested)
                .map(|c| c.diameter_mm)
                .collect(),
            cutters: out,
            total_area_mm2: total,
            uncovered_area_mm2: uncovered,
            uncovered_share: share(uncovered),
            undefined_area_mm2: undefined,
            min_gain_share: opts.min_gain_share,
            area_rule_nodes: opts.rule.nodes.clamp(1, 5),
            fit_tol_mm: cutters.fit_tol_mm,
        }
    }

    /// The report of a map over [`CompoundSurface::grid`]`(n)` of `surface`.
    ///
    /// # Errors
    /// [`StandardError::NotAGrid`] when the map's points are not that grid.
    pub fn from_grid_map(
        cutters: &StandardCutters,
        surface: &CompoundSurface,
        map: &ToolSizeMap,
        n: usize,
        opts: &StandardOptions,
    ) -> Result<StandardReport, StandardError> {
        check_grid(
            surface,
            &map.points.iter().map(|p| p.cc).collect::<Vec<_>>(),
            n,
        )?;
        let areas = grid_cell_areas(surface, n, opts.rule);
        let radii: Vec<Option<f64>> = map.points.iter().map(|p| p.radius_mm).collect();
        Ok(Self::from_radii(cutters, &radii, &areas, opts))
    }
}

/// A sum that is `+0.0` when empty (`Iterator::sum` of no `f64` is `-0.0`).
fn sum(values: impl Iterator<Item = f64>) -> f64 {
    values.fold(0.0, |a, b| a + b)
}

/// Checks that `ccs` is exactly [`CompoundSurface::grid`]`(n)`.
///
/// # Errors
/// [`StandardError::NotAGrid`] otherwise.
pub fn check_grid(
    surface: &CompoundSurface,
    ccs: &[CcPoint],
    n: usize,
) -> Result<(), StandardError> {
    let grid = surface.grid(n);
    if grid.as_slice() == ccs {
        Ok(())
    } else {
        Err(StandardError::NotAGrid {
            points: ccs.len(),
            n,
            patches: surface.patches.len(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_weights_sum_to_two_and_integrate_x_to_the_2n_minus_1() {
        for nodes in 1..=5 {
            let (x, w) = AreaRule { nodes }.nodes_weights();
            assert!((w.iter().sum::<f64>() - 2.0).abs() < 1e-15);
            // ∫_{-1}^{1} x^{2k} dx = 2/(2k+1) for 2k ≤ 2·nodes − 1.
            for k in 0..nodes {
                let exact = 2.0 / (2 * k + 1) as f64;
                let q: f64 = x.iter().zip(w).map(|(x, w)| w * x.powi(2 * k as i32)).sum();
                assert!(
                    (q - exact).abs() < 1e-14,
                    "nodes {nodes} k {k}: {q} vs {exact}"
                );
            }
        }
    }
}
