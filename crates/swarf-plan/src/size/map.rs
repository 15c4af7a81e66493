//! The 3-axis allowable-size map: every CC point of a grid (or list), in parallel, with the CSV
//! of `swarf toolsize` and its JSON summary.
//!
//! `radius_mm` is half the nominal diameter of the largest allowable cutter
//! ([`CutterFamily::nominal_radius`]): `inf` when nothing limits it, `0` when the point cannot
//! be machined, empty where the normal is undefined.

use std::io::{self, Write};
use std::time::Instant;

use rayon::prelude::*;
use swarf_geom::math::Vec3;

use super::shank::check_shank;
use super::{
    allowable_certified, allowable_pso, AllowableSize, CertifiedOptions, Contact, CutterFamily,
    PreparedSurface, PsoOptions, ShankCheck, ShankStatus, SizeTolerances,
};
use crate::{CcPoint, CompoundSurface, Tolerances};

/// Which solver computes the allowable size.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Solver {
    /// Branch-and-bound with a certificate (the default).
    #[default]
    Certified,
    /// The thesis's particle swarm + Nelder–Mead.
    Pso,
}

/// Options of a map run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapOptions {
    /// The solver.
    pub solver: Solver,
    /// Options of the certified solver.
    pub certified: CertifiedOptions,
    /// Options of the PSO solver.
    pub pso: PsoOptions,
    /// Shank to check after the size is found, if any.
    pub shank: Option<ShankCheck>,
    /// Tolerances of the differential geometry.
    pub geometry: Tolerances,
}

impl MapOptions {
    /// The documented defaults: the certified solver with its defaults, no shank check.
    pub const DEFAULT: MapOptions = MapOptions {
        solver: Solver::Certified,
        certified: CertifiedOptions::DEFAULT,
        pso: PsoOptions::DEFAULT,
        shank: None,
        geometry: Tolerances::DEFAULT,
    };
}

impl Default for MapOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// One CC point of the map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapPoint {
    /// The CC point.
    pub cc: CcPoint,
    /// Its position.
    pub point: Vec3,
    /// Its normal (towards the cutter); `None` where undefined.
    pub normal: Option<Vec3>,
    /// The allowable size; `None` where the normal is undefined.
    pub size: Option<AllowableSize>,
    /// Half the nominal diameter of the allowable cutter; `None` where the normal is undefined.
    pub radius_mm: Option<f64>,
    /// The shank check, when asked for.
    pub shank: Option<ShankStatus>,
}

/// The map over all points.
#[derive(Clone, Debug, PartialEq)]
pub struct ToolSizeMap {
    /// The family solved for.
    pub family: CutterFamily,
    /// One entry per CC point, in input order.
    pub points: Vec<MapPoint>,
    /// Wall-clock time of the run, s.
    pub elapsed_s: f64,
}

/// The JSON summary printed by `swarf toolsize --json`.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct MapSummary {
    /// CC points in the map.
    pub points: usize,
    /// Points with a finite allowable size.
    pub bounded_points: usize,
    /// Smallest finite radius, mm (`None` when no point is bounded).
    pub min_radius_mm: Option<f64>,
    /// Median of the finite radii, mm.
    pub median_radius_mm: Option<f64>,
    /// Largest finite radius, mm.
    pub max_radius_mm: Option<f64>,
    /// Mean objective evaluations per point.
    pub evaluations_per_point: f64,
    /// Wall-clock time, s.
    pub elapsed_s: f64,
}

/// The allowable size of `family` at every CC point, in parallel (rayon).
pub fn allowable_map(
    surface: &CompoundSurface,
    family: &CutterFamily,
    ccs: &[CcPoint],
    opts: &MapOptions,
) -> ToolSizeMap {
    let start = Instant::now();
    let prep = PreparedSurface::new(surface);
    let points = ccs
        .par_iter()
        .map(|cc| {
            let g = surface.local(cc, &opts.geometry);
            let Some(c) = Contact::at(surface, cc, &opts.geometry) else {
                return MapPoint {
                    cc: *cc,
                    point: g.point(),
                    normal: None,
                    size: None,
                    radius_mm: None,
                    shank: None,
                };
            };
            let size = match opts.solver {
                Solver::Certified => allowable_certified(&prep, family, &c, &opts.certified),
                Solver::Pso => allowable_pso(surface, family, &c, &opts.pso),
            };
            let shank = opts
                .shank
                .map(|s| check_shank(&prep, family, &c, size.size, &s, &opts.certified.model));
            MapPoint {
                cc: *cc,
                point: c.point,
                normal: Some(c.normal),
                size: Some(size),
                radius_mm: Some(radius_of(family, &c, &size, &opts.certified.model)),
                shank,
            }
        })
        .collect();
    ToolSizeMap {
        family: *family,
        points,
        elapsed_s: start.elapsed().as_secs_f64(),
    }
}

/// Half the nominal diameter of the allowable cutter, `0` when no cutter of the family can
/// machine the point: the contact is unreachable, or the smallest cutter (`L = 0`: a bull-nose
/// degenerates to a ball of its corner radius) already gouges — a test point lies inside it, or
/// the surface curves more than its corner.
fn radius_of(family: &CutterFamily, c: &Contact, a: &AllowableSize, tol: &SizeTolerances) -> f64 {
    if a.size.is_infinite() {
        return f64::INFINITY;
    }
    if a.size > 0.0 {
        return family.nominal_radius(a.size);
    }
    let regime = family.regime(c, tol);
    let Some(k0) = family.placed(c, &regime, 0.0) else {
        return 0.0;
    };
    let inside = a.limit_point.is_some_and(|p| k0.contains(p, tol.contact));
    let too_curved = c.curvature.is_some_and(|k| k.k1 * k0.r > 1.0);
    if k0.r == 0.0 || inside || too_curved {
        0.0
    } else {
        family.nominal_radius(0.0)
    }
}

/// The exact CSV header of `toolsize.csv`.
pub const CSV_HEADER: &str = "patch,u,v,x,y,z,nx,ny,nz,radius_mm,limit_x,limit_y,limit_z,limit";

impl ToolSizeMap {
    /// Writes the CSV (header [`CSV_HEADER`]; numbers in Rust's shortest round-trip form, with
    /// an exponent for very small or large values, so they read back bit for bit; header [`CSV_HEADER`], one row per point; `radius_mm` is `inf`, a number
    /// or empty; the limit columns are empty when nothing limits the size).
    ///
    /// # Errors
    /// When writing fails.
    pub fn write_csv(&self, surface: &CompoundSurface, mut w: impl Write) -> io::Result<()> {
        writeln!(w, "{CSV_HEADER}")?;
        for p in &self.points {
            let label = surface
                .patches
                .get(p.cc.patch)
                .map_or_else(|| p.cc.patch.to_string(), |pt| pt.label(p.cc.patch));
            let label = if label.contains([',', '"', '\n']) {
                format!("\"{}\"", label.replace('"', "\"\""))
            } else {
                label
            };
            let (nx, ny, nz) = p
                .normal
                .map_or((String::new(), String::new(), String::new()), |n| {
                    (num(n.x), num(n.y), num(n.z))
                });
            let radius = match p.radius_mm {
                None => String::new(),
                Some(r) if r.is_infinite() => "inf".to_string(),
                Some(r) => num(r),
            };
            let (lx, ly, lz, lim) = match p.size.and_then(|s| s.limit_point.zip(s.limit)) {
                Some((q, l)) => (num(q.x), num(q.y), num(q.z), l.as_str().to_string()),
                None => Default::default(),
            };
            writeln!(
                w,
                "{label},{:?},{:?},{:?},{:?},{:?},{nx},{ny},{nz},{radius},{lx},{ly},{lz},{lim}",
                p.cc.u, p.cc.v, p.point.x, p.point.y, p.point.z
            )?;
        }
        Ok(())
    }

    /// The summary of the run.
    pub fn summary(&self) -> MapSummary {
        let mut finite: Vec<f64> = self
            .points
            .iter()
            .filter_map(|p| p.radius_mm)
            .filter(|r| r.is_finite())
            .collect();
        finite.sort_by(f64::total_cmp);
        let median = if finite.is_empty() {
            None
        } else if finite.len() % 2 == 1 {
            Some(finite[finite.len() / 2])
        } else {
            Some(0.5 * (finite[finite.len() / 2 - 1] + finite[finite.len() / 2]))
        };
        let evals: u64 = self
            .points
            .iter()
            .filter_map(|p| p.size)
            .map(|s| s.evaluations)
            .sum();
        MapSummary {
            points: self.points.len(),
            bounded_points: finite.len(),
            min_radius_mm: finite.first().copied(),
            median_radius_mm: median,
            max_radius_mm: finite.last().copied(),
            evaluations_per_point: if self.points.is_empty() {
                0.0
            } else {
                evals as f64 / self.points.len() as f64
            },
            elapsed_s: self.elapsed_s,
        }
    }
}

/// A number as the shortest text that reads back to the same `f64` (`5.0`, `3.1e-16`).
fn num(x: f64) -> String {
    format!("{x:?}")
}
