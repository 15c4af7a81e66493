//! The allowable-size map: every CC point of a grid (or list), in parallel, with the CSV
//! of `swarf toolsize` and its JSON summary.
//!
//! In 4- and 5-axis mode ([`MapOptions::axes`]) each point also gets the orientation that
//! maximises the size ([`super::orient4`], [`super::orient5`]; always the certified solver), and
//! the CSV gets `b_deg` or `lead_deg,tilt_deg` after the 14 columns of [`CSV_HEADER`].
//!
//! `radius_mm` is half the nominal diameter of the largest allowable cutter
//! ([`CutterFamily::nominal_radius`]): `inf` when nothing limits it, `0` when the point cannot
//! be machined, empty where the normal is undefined.

use std::io::{self, Write};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

use rayon::prelude::*;
use swarf_geom::math::Vec3;
use swarf_geom::progress::{Cancelled, Observer, Quiet};

use super::orient4::{axis_rotation, best_rotary_angle, in_tool_frame, Axis4Options};
use super::orient5::{best_lead_tilt, Axis5Options, LeadTiltFrame};
use super::shank::shank_limited;
use super::{
    allowable_certified, allowable_pso, AllowableSize, CertifiedOptions, Contact, CutterFamily,
    PreparedSurface, PsoOptions, ShankCheck, ShankStatus, SizeTolerances,
};
use swarf_surface::{CcPoint, CompoundSurface, Tolerances};

/// Which solver computes the allowable size.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Solver {
    /// Branch-and-bound with a certificate (the default).
    #[default]
    Certified,
    /// The thesis's particle swarm + Nelder–Mead.
    Pso,
}

/// The machine's axes: which tool orientations the map may choose. The options inside must be
/// valid ([`Axis4Options::validate`], [`Axis5Options::validate`]): the map panics otherwise.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Axes {
    /// 3-axis: the tool axis is `+Z` (the default).
    #[default]
    Three,
    /// 4-axis: the table angle about the rotary axis that maximises the size.
    Four(Axis4Options),
    /// 5-axis: the lead and tilt within limits that maximise the size.
    Five(Axis5Options),
}

/// The orientation chosen at a point in 4- or 5-axis mode.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ToolAngles {
    /// The table angle, degrees in `[0, 360)`.
    Rotary {
        /// `B`, degrees.
        b_deg: f64,
    },
    /// Lead and tilt, degrees ([`LeadTiltFrame`]).
    LeadTilt {
        /// Lead, degrees.
        lead_deg: f64,
        /// Tilt, degrees.
        tilt_deg: f64,
    },
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
    /// 3-, 4- or 5-axis (4/5: the certified options inside [`Axes`] are used, whatever
    /// `solver` says).
    pub axes: Axes,
}

impl MapOptions {
    /// The documented defaults: the certified solver with its defaults, no shank check.
    pub const DEFAULT: MapOptions = MapOptions {
        solver: Solver::Certified,
        certified: CertifiedOptions::DEFAULT,
        pso: PsoOptions::DEFAULT,
        shank: None,
        geometry: Tolerances::DEFAULT,
        axes: Axes::Three,
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
    /// The tool orientation chosen (4-/5-axis mode), with its axis in the part frame.
    pub orientation: Option<(ToolAngles, Vec3)>,
}

/// The map over all points.
#[derive(Clone, Debug, PartialEq)]
pub struct ToolSizeMap {
    /// The family solved for.
    pub family: CutterFamily,
    /// One entry per CC point, in input order.
    pub points: Vec<MapPoint>,
    /// The axes the map was computed for.
    pub axes: Axes,
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
    /// Points no cutter of the family reaches in this set-up (size 0: in 3-axis, where the
    /// surface faces away from the tool or lies under an overhang); they count in the
    /// minimum and the median, which they make 0.
    pub unreachable_points: usize,
    /// Smallest finite radius, mm (`None` when no point is bounded).
    pub min_radius_mm: Option<f64>,
    /// Median of the finite radii, mm.
    pub median_radius_mm: Option<f64>,
    /// Largest finite radius, mm.
    pub max_radius_mm: Option<f64>,
    /// Points whose size carries no certificate: every point of the swarm (`pso`), and those
    /// where the certified solver ran out of its node budget (their size is the best it found).
    pub uncertified_points: usize,
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
    let mut map = allowable_map_prepared(surface, &prep, family, ccs, opts);
    map.elapsed_s = start.elapsed().as_secs_f64();
    map
}

/// [`allowable_map`] against a surface already prepared, e.g. with check geometry added
/// ([`PreparedSurface::with_check_mesh`]); `prep` must be `surface` prepared. The certified
/// solver, the orientation searches and the shank check see everything in `prep`; the PSO
/// solver samples `surface` only (it ignores check geometry).
pub fn allowable_map_prepared(
    surface: &CompoundSurface,
    prep: &PreparedSurface,
    family: &CutterFamily,
    ccs: &[CcPoint],
    opts: &MapOptions,
) -> ToolSizeMap {
    match allowable_map_observed(surface, prep, family, ccs, opts, &Quiet) {
        Ok(map) => map,
        Err(_) => unreachable!("the quiet observer never stops the map"),
    }
}

/// [`allowable_map_prepared`], telling `observer` `progress(done, points)` as CC points are
/// solved (from any thread, in any order). When it answers `Break` no further point is started
/// and the map ends with [`Cancelled`] (CC points solved, of all).
///
/// # Errors
/// [`Cancelled`] when the observer stopped the map.
pub fn allowable_map_observed(
    surface: &CompoundSurface,
    prep: &PreparedSurface,
    family: &CutterFamily,
    ccs: &[CcPoint],
    opts: &MapOptions,
    observer: &dyn Observer,
) -> Result<ToolSizeMap, Cancelled> {
    let start = Instant::now();
    let (done, stopped) = (AtomicUsize::new(0), AtomicBool::new(false));
    let total = ccs.len() as u64;
    let point = |cc: &CcPoint| {
        if stopped.load(Ordering::Relaxed) {
            return None;
        }
        let p = map_point(surface, prep, family, cc, opts);
        let n = done.fetch_add(1, Ordering::Relaxed) + 1;
        if observer.progress(n as u64, total).is_break() {
            stopped.store(true, Ordering::Relaxed);
        }
        Some(p)
    };
    let points: Vec<Option<MapPoint>> = ccs.par_iter().map(point).collect();
    if stopped.load(Ordering::Relaxed) {
        return Err(Cancelled {
            done: done.load(Ordering::Relaxed) as u64,
            total,
        });
    }
    Ok(ToolSizeMap {
        family: *family,
        // Not stopped: every point was solved.
        points: points.into_iter().flatten().collect(),
        axes: opts.axes,
        elapsed_s: start.elapsed().as_secs_f64(),
    })
}

/// The allowable size (and orientation, shank check) at one CC point.
fn map_point(
    surface: &CompoundSurface,
    prep: &PreparedSurface,
    family: &CutterFamily,
    cc: &CcPoint,
    opts: &MapOptions,
) -> MapPoint {
    let g = surface.local(cc, &opts.geometry);
    let Some(c) = Contact::at(surface, cc, &opts.geometry) else {
        return MapPoint {
            cc: *cc,
            point: g.point(),
            normal: None,
            size: None,
            radius_mm: None,
            shank: None,
            orientation: None,
        };
    };
    if opts.axes != Axes::Three {
        return oriented_point(surface, prep, family, cc, &c, opts);
    }
    let size = match opts.solver {
        Solver::Certified => allowable_certified(prep, family, &c, &opts.certified),
        Solver::Pso => allowable_pso(surface, family, &c, &opts.pso),
    };
    let (size, shank) = match opts.shank {
        Some(s) => {
            let (size, st) = shank_limited(prep, family, &c, size, &s, &opts.certified.model);
            (size, Some(st))
        }
        None => (size, None),
    };
    MapPoint {
        cc: *cc,
        point: c.point,
        normal: Some(c.normal),
        size: Some(size),
        radius_mm: Some(radius_of(family, &c, &size, &opts.certified.model)),
        shank,
        orientation: None,
    }
}

/// One CC point in 4- or 5-axis mode: the best orientation, then the radius and shank check in
/// the tool frame of that orientation.
fn oriented_point(
    surface: &CompoundSurface,
    prep: &PreparedSurface,
    family: &CutterFamily,
    cc: &CcPoint,
    c: &Contact,
    opts: &MapOptions,
) -> MapPoint {
    let (mut size, angles, axis, q, certified) = match opts.axes {
        Axes::Three => unreachable!("3-axis points are solved in allowable_map"),
        Axes::Four(o) => {
            let best = best_rotary_angle(prep, family, c, &o);
            let q = o.rotary.part_rotation(best.b_deg);
            let angles = ToolAngles::Rotary { b_deg: best.b_deg };
            (best.size, angles, best.axis, q, o.certified)
        }
        Axes::Five(o) => {
            let d = surface.local(cc, &opts.geometry).derivs;
            let frame = [d.su, d.sv, Vec3::X, Vec3::Y]
                .into_iter()
                .find_map(|t| LeadTiltFrame::new(c.normal, t))
                .expect("some tangent is not along the normal");
            let best = best_lead_tilt(prep, family, c, &frame, &o);
            let angles = ToolAngles::LeadTilt {
                lead_deg: best.lead_deg,
                tilt_deg: best.tilt_deg,
            };
            (
                best.size,
                angles,
                best.axis,
                axis_rotation(best.axis),
                o.certified,
            )
        }
    };
    let (rprep, rc) = in_tool_frame(prep, c, q);
    let mut in_frame = AllowableSize {
        limit_point: size.limit_point.map(|p| q * p),
        ..size
    };
    let mut shank = None;
    if let Some(s) = opts.shank {
        let (limited, st) = shank_limited(&rprep, family, &rc, in_frame, &s, &certified.model);
        // Back to the part frame (the tool frame is the part turned by `q`).
        let back = |p: Vec3| q.inverse() * p;
        size = AllowableSize {
            limit_point: limited.limit_point.map(back),
            ..limited
        };
        shank = Some(match st {
            ShankStatus::Interferes { point, depth } => ShankStatus::Interferes {
                point: back(point),
                depth,
            },
            ShankStatus::Limits {
                point,
                cutting_size,
            } => ShankStatus::Limits {
                point: back(point),
                cutting_size,
            },
            other => other,
        });
        in_frame = limited;
    }
    MapPoint {
        cc: *cc,
        point: c.point,
        normal: Some(c.normal),
        size: Some(size),
        radius_mm: Some(radius_of(family, &rc, &in_frame, &certified.model)),
        shank,
        orientation: Some((angles, axis)),
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
        let extra = match self.axes {
            Axes::Three => "",
            Axes::Four(_) => ",b_deg",
            Axes::Five(_) => ",lead_deg,tilt_deg",
        };
        writeln!(w, "{CSV_HEADER}{extra},certified")?;
        let labels = surface.patch_labels();
        for p in &self.points {
            let label = labels
                .get(p.cc.patch)
                .cloned()
                .unwrap_or_else(|| p.cc.patch.to_string());
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
            // A size the solver proved (`true`), or the best it found without a proof (the swarm,
            // or the certified solver out of its node budget).
            let certified = p.size.map_or(String::new(), |s| s.certified.to_string());
            let angles = match (self.axes, p.orientation) {
                (Axes::Three, _) => String::new(),
                (_, Some((ToolAngles::Rotary { b_deg }, _))) => format!(",{}", num(b_deg)),
                (_, Some((ToolAngles::LeadTilt { lead_deg, tilt_deg }, _))) => {
                    format!(",{},{}", num(lead_deg), num(tilt_deg))
                }
                (Axes::Four(_), None) => ",".to_string(),
                (Axes::Five(_), None) => ",,".to_string(),
            };
            writeln!(
                w,
                "{label},{:?},{:?},{:?},{:?},{:?},{nx},{ny},{nz},{radius},{lx},{ly},{lz},{lim}{angles},{certified}",
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
            unreachable_points: finite.iter().take_while(|&&r| r <= 0.0).count(),
            min_radius_mm: finite.first().copied(),
            median_radius_mm: median,
            max_radius_mm: finite.last().copied(),
            uncertified_points: self
                .points
                .iter()
                .filter(|p| p.size.is_some_and(|s| !s.certified))
                .count(),
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
