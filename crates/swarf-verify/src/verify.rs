//! The comparison: signed deviation at every exact ray end of the stock, gouge and excess ends
//! grouped into connected regions, each region's depth, area, volume and moves.

use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Instant;

use rayon::prelude::*;
use swarf_geom::math::Vec3;
use swarf_geom::progress::{Observer, Quiet};
use swarf_path::Program;
use swarf_stock::{Dexel, MoveTag, TriDexel, UNCUT};

use crate::design::Design;
use crate::error::VerifyError;

/// Default gouge tolerance: material removed inside the part deeper than this is a gouge, mm.
pub const DEFAULT_GOUGE_TOLERANCE_MM: f64 = 0.01;
/// Default excess tolerance: material left outside the part thicker than this is excess, mm.
pub const DEFAULT_EXCESS_TOLERANCE_MM: f64 = 0.01;
/// Default link distance of regions, in cells (the largest cell size): defect ray ends closer
/// than this belong to one region. Two cells join the ends of neighbouring rays of a family
/// and of the other families on the same sheet (at most √3 cells apart on a flat face).
pub const DEFAULT_LINK_CELLS: f64 = 2.0;
/// Deviations no larger than this are rounding, not a defect, whatever the tolerances (mm): a
/// machined surface that meets the design computes a few 1e-15 mm off it, and a tolerance of 0
/// would make each such ray end a gouge or an excess.
pub const ROUNDING_MM: f64 = 1e-9;

/// Verification options; tolerances with their defaults in one place.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct VerifyOptions {
    /// Gouge tolerance, mm (default [`DEFAULT_GOUGE_TOLERANCE_MM`]).
    pub gouge_tolerance: f64,
    /// Excess tolerance, mm (default [`DEFAULT_EXCESS_TOLERANCE_MM`]).
    pub excess_tolerance: f64,
    /// Link distance of regions, in cells (default [`DEFAULT_LINK_CELLS`]).
    pub link_cells: f64,
}

impl Default for VerifyOptions {
    fn default() -> Self {
        Self {
            gouge_tolerance: DEFAULT_GOUGE_TOLERANCE_MM,
            excess_tolerance: DEFAULT_EXCESS_TOLERANCE_MM,
            link_cells: DEFAULT_LINK_CELLS,
        }
    }
}

impl VerifyOptions {
    /// With another gouge tolerance.
    pub fn with_gouge_tolerance(mut self, t: f64) -> Self {
        self.gouge_tolerance = t;
        self
    }

    /// With another excess tolerance.
    pub fn with_excess_tolerance(mut self, t: f64) -> Self {
        self.excess_tolerance = t;
        self
    }

    fn check(&self) -> Result<(), VerifyError> {
        for (name, value) in [
            ("gouge tolerance", self.gouge_tolerance),
            ("excess tolerance", self.excess_tolerance),
        ] {
            if !(value >= 0.0 && value.is_finite()) {
                return Err(VerifyError::BadTolerance { name, value });
            }
        }
        if !(self.link_cells > 0.0 && self.link_cells.is_finite()) {
            return Err(VerifyError::BadTolerance {
                name: "link distance",
                value: self.link_cells,
            });
        }
        Ok(())
    }
}

/// Gouge or excess.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum DefectKind {
    /// Material removed inside the part: the machined surface lies inside the design.
    Gouge,
    /// Material left outside the part: the machined surface lies outside the design.
    Excess,
}

impl DefectKind {
    /// `gouge` or `excess`.
    pub fn name(self) -> &'static str {
        match self {
            DefectKind::Gouge => "gouge",
            DefectKind::Excess => "excess",
        }
    }
}

/// One ray end of the stock beyond a tolerance.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct DefectEnd {
    /// The ray end: a point of the machined surface, mm.
    pub point: Vec3,
    /// Signed deviation from the design, mm (positive: outside, excess; negative: gouge).
    pub deviation: f64,
    /// The design's outward normal at its nearest point.
    pub normal: Vec3,
    /// Ray family (0 = X, 1 = Y, 2 = Z).
    pub family: u8,
    /// The move that cut this end last ([`UNCUT`]: the stock as built, or no provenance).
    pub tag: MoveTag,
    /// The area of the design's surface this end stands for, mm²: the family's cell area times
    /// the component along the ray of the design's normal where the ray meets the design (over
    /// the three families a surface element counts once: Σₖ nₖ² = 1). A region's area is thus
    /// its footprint on the design: the walls of a too-deep slot in a face project onto the
    /// face's edge and add nothing. The ray is followed from the end towards the design
    /// ([`Design::meet_along`]: exactly for a mesh; by sphere tracing for surfaces, and there
    /// only where the nearest point's normal is more than 60° off the ray, see
    /// [`Design::follow_rays_below`]) no further than twice the region's depth and a cell
    /// over the nearest normal's component along the ray (at least ½: the nearest face's own
    /// crossing is |deviation| over that component away), nor than the end's own stretch of
    /// air (a gouge) or material (an excess); where it does not meet
    /// the design that near, the end lies on a wall of the region (a slot's wall, whose ray
    /// runs along the face above it, then across the slot into the material beyond) and
    /// stands for no area. So the floor of a gouge reaching a convex edge of the design counts
    /// up to the edge, although its nearest point there lies on the side face, and a wall
    /// near another face of the design does not count as that face.
    pub area: f64,
    /// Which way along the ray the stock's material ends here: +1 where the ray leaves the
    /// material (an interval's exit), −1 where it enters it.
    pub outside: i8,
    /// How far along the ray, towards the design, the end's own stretch reaches (mm): for a
    /// gouge the air beyond the end up to the ray's next material, for an excess the end's
    /// interval of material. The ray is followed no further to find the design (beyond, it
    /// would meet another region's face).
    #[serde(skip)]
    pub(crate) room: f64,
}

impl DefectEnd {
    fn kind(&self) -> DefectKind {
        if self.deviation < 0.0 {
            DefectKind::Gouge
        } else {
            DefectKind::Excess
        }
    }
}

/// A move that cut part of a gouge (or left part of an excess).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RegionMove {
    /// Move index in the program.
    pub move_index: usize,
    /// Source file (empty without a program).
    pub file: String,
    /// 1-based source line (0 without a program).
    pub line: u32,
    /// The deepest deviation among the ends this move made, mm.
    pub depth_mm: f64,
    /// How many of the region's ray ends it made.
    pub ends: usize,
}

/// A connected region of gouge or excess.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Region {
    /// 1-based number: gouges first, deepest first, then excess, thickest first.
    pub id: usize,
    /// Gouge or excess.
    pub kind: DefectKind,
    /// Largest |deviation| of its ray ends, mm; for excess material that no ray end bounds (a
    /// cavity of the design that the stock fills), the farthest from the design of the
    /// middles of its Z-ray pieces.
    pub depth_mm: f64,
    /// Its footprint on the design's surface, mm² (see [`DefectEnd::area`]); 0 for material
    /// that no ray end bounds.
    pub area_mm2: f64,
    /// Volume of the gouge (part material missing) or excess (material left), mm³: with a
    /// solid design, the Z rays' exact pieces of stock ∖ part (or part ∖ stock), times their
    /// cell area — each piece near the region's ray ends, and each piece joined to those
    /// through pieces of neighbouring rays (the material of a hole left undrilled, away from
    /// the stock's surface), so that the excess regions' volumes add up to
    /// [`Verification::excess_volume_mm3`] less material nowhere thicker than the tolerance
    /// (a gouge's pieces that no gouge end reaches — nowhere deeper than the tolerance, or
    /// behind stock no move cut — belong to no region); otherwise ∫ |deviation| dA over the
    /// region.
    pub volume_mm3: f64,
    /// The deepest ray end.
    pub deepest: Vec3,
    /// The move that cut the deepest end last, if any.
    pub deepest_move: Option<usize>,
    /// Ray ends in the region (0: material that no ray end bounds, a cavity of the design the
    /// stock fills).
    pub ends: usize,
    /// Lower corner of the region's ray ends (of its Z-ray pieces when it has no ray end).
    pub bbox_min: Vec3,
    /// Upper corner.
    pub bbox_max: Vec3,
    /// The moves that cut its ends, deepest first (at most [`MAX_REGION_MOVES`]).
    pub moves: Vec<RegionMove>,
    /// How many moves cut its ends (`moves` lists the deepest of them).
    pub move_count: usize,
}

impl Region {
    /// A region of `kind` holding nothing yet, its depth `depth_mm` (what any end beats), its
    /// box empty.
    fn empty(kind: DefectKind, depth_mm: f64) -> Self {
        Self {
            id: 0,
            kind,
            depth_mm,
            area_mm2: 0.0,
            volume_mm3: 0.0,
            deepest: Vec3::ZERO,
            deepest_move: None,
            ends: 0,
            bbox_min: Vec3::splat(f64::INFINITY),
            bbox_max: Vec3::splat(f64::NEG_INFINITY),
            moves: Vec::new(),
            move_count: 0,
        }
    }
}

/// Most moves a region lists (the deepest); [`Region::move_count`] counts them all.
pub const MAX_REGION_MOVES: usize = 100;

/// A histogram of the signed deviation of every ray end.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Histogram {
    /// Bin edges, mm (`counts.len() + 1` of them).
    pub edges_mm: Vec<f64>,
    /// Ray ends per bin (ends beyond the range in the first or last bin).
    pub counts: Vec<u64>,
}

/// The result of [`verify`].
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Verification {
    /// Regions, gouges first (deepest first), then excess (thickest first).
    pub regions: Vec<Region>,
    /// Deepest gouge of any ray end, mm (0 when none lies inside the design).
    pub max_gouge_mm: f64,
    /// Thickest excess, mm: of any ray end, or of material no ray end bounds (a region's
    /// [`Region::depth_mm`]); 0 when none lies outside.
    pub max_excess_mm: f64,
    /// Ray ends compared with the design.
    pub ends_checked: u64,
    /// Ray ends about which the design says nothing: beyond a surface's edge, or (with
    /// provenance) stock no move cut lying inside the design — behind a surface the material
    /// under the part, in a solid the design beyond the stock, which the program never had to
    /// cut.
    pub ends_unmatched: u64,
    /// Ray ends beyond the gouge tolerance.
    pub gouge_ends: u64,
    /// Ray ends beyond the excess tolerance.
    pub excess_ends: u64,
    /// Volume of material left outside the part (stock ∖ part, Z rays), mm³; `None` when the
    /// design bounds no solid.
    pub excess_volume_mm3: Option<f64>,
    /// Volume of the part missing from the stock (part ∖ stock, Z rays), mm³, within the
    /// stock's box: design material the stock never reached is not a gouge of the program.
    pub gouge_volume_mm3: Option<f64>,
    /// Volume of the design above or below the stock's box over its footprint (Z rays), mm³:
    /// a design in another frame, or fixtures exported with the part; it is not compared.
    pub design_outside_stock_mm3: Option<f64>,
    /// True when the design's bounding box reaches beyond the stock's box by more than a ray
    /// spacing (then part of it may lie outside the footprint too, unseen by any ray).
    pub design_beyond_stock_box: bool,
    /// Histogram of the signed deviation (symmetric range of the largest deviation).
    pub histogram: Histogram,
    /// The options used.
    pub options: VerifyOptions,
    /// Grid cell sizes along X, Y, Z of the stock, mm.
    pub resolution_mm: [f64; 3],
    /// Wall-clock time, s.
    pub elapsed_s: f64,
}

impl Verification {
    /// Gouge regions.
    pub fn gouges(&self) -> impl Iterator<Item = &Region> {
        self.regions.iter().filter(|r| r.kind == DefectKind::Gouge)
    }

    /// Excess regions.
    pub fn excesses(&self) -> impl Iterator<Item = &Region> {
        self.regions.iter().filter(|r| r.kind == DefectKind::Excess)
    }

    /// Material left outside the part, mm³: [`Verification::excess_volume_mm3`] for a solid
    /// design, else the excess regions' volumes added up (0, never −0, when there are none).
    pub fn excess_volume(&self) -> f64 {
        self.excess_volume_mm3
            .unwrap_or_else(|| self.excesses().fold(0.0, |a, r| a + r.volume_mm3))
    }

    /// Part material missing, mm³: [`Verification::gouge_volume_mm3`] for a solid design, else
    /// the gouge regions' volumes added up (0 when there are none).
    pub fn gouge_volume(&self) -> f64 {
        self.gouge_volume_mm3
            .unwrap_or_else(|| self.gouges().fold(0.0, |a, r| a + r.volume_mm3))
    }

    /// How the volumes were measured: `z-rays` (the exact pieces along the Z rays, a solid
    /// design) or `surface-integral` (∫ |deviation| dA over the regions, a surface).
    pub fn volume_method(&self) -> &'static str {
        if self.excess_volume_mm3.is_some() {
            "z-rays"
        } else {
            "surface-integral"
        }
    }
}

/// Bins of [`Verification::histogram`].
pub const HISTOGRAM_BINS: usize = 41;

/// Per-row partial results.
#[derive(Default)]
struct Partial {
    defects: Vec<DefectEnd>,
    checked: u64,
    unmatched: u64,
    max_gouge: f64,
    max_excess: f64,
    deviations: Vec<f32>,
}

impl Partial {
    fn merge(mut self, o: Partial) -> Partial {
        self.defects.extend(o.defects);
        self.checked += o.checked;
        self.unmatched += o.unmatched;
        self.max_gouge = self.max_gouge.max(o.max_gouge);
        self.max_excess = self.max_excess.max(o.max_excess);
        self.deviations.extend(o.deviations);
        self
    }
}

/// Compares the machined `stock` with `design`: the signed distance of every ray end (enter
/// and exit of every interval of the three families), classified with the tolerances, grouped
/// into connected regions. When the stock tracked provenance
/// ([`TriDexel::track_provenance`]) every end knows the move that cut it; with `program`
/// those moves are named by file and line.
pub fn verify(
    stock: &TriDexel,
    design: &dyn Design,
    program: Option<&Program>,
    options: &VerifyOptions,
) -> Result<Verification, VerifyError> {
    verify_observed(stock, design, program, options, &Quiet)
}

/// [`verify`], telling `observer` `progress(done, rows)` as rows of rays (of the three
/// families together) are compared, from any thread, in any order. When it answers `Break` no
/// further row is started and the verification ends with [`VerifyError::Cancelled`].
///
/// # Errors
/// A tolerance out of range, or [`VerifyError::Cancelled`].
pub fn verify_observed(
    stock: &TriDexel,
    design: &dyn Design,
    program: Option<&Program>,
    options: &VerifyOptions,
    observer: &dyn Observer,
) -> Result<Verification, VerifyError> {
    options.check()?;
    let t0 = Instant::now();
    let rows: u64 = (0..3).map(|k| stock.family(k).dims().1 as u64).sum();
    let (rows_done, stopped) = (AtomicU64::new(0), AtomicBool::new(false));
    let grid = *stock.grid();
    // Deviations within rounding are no defect, whatever the tolerances.
    let (gt, et) = (
        options.gouge_tolerance.max(ROUNDING_MM),
        options.excess_tolerance.max(ROUNDING_MM),
    );
    // The stock's own faces that no move cut, lying inside the design (deeper than rounding:
    // on it, they are compared), are no gouge of the program: behind a surface that bounds no
    // solid the material under the part, in a solid design part of it the stock never reached
    // (a design wider than the stock) — only known when the stock tracked provenance.
    let skip_uncut_behind = stock.tracks_provenance();
    let all = (0..3usize)
        .map(|k| {
            let fam = stock.family(k);
            let (u, v) = ((k + 1) % 3, (k + 2) % 3);
            let (nu, nv) = fam.dims();
            let area = stock.ray_area(k);
            (0..nv)
                .into_par_iter()
                .fold(Partial::default, |mut acc, j| {
                    if stopped.load(Ordering::Relaxed) {
                        return acc;
                    }
                    for i in 0..nu {
                        let ray = fam.ray(i, j);
                        if ray.is_empty() {
                            continue;
                        }
                        let tags = fam.ray_tags(i, j);
                        let mut p = Vec3::ZERO;
                        p[u] = grid.center(u, i);
                        p[v] = grid.center(v, j);
                        for (n, iv) in ray.iter().enumerate() {
                            let ends = tags.map(|t| t[n]);
                            // The air on either side: up to the neighbouring intervals.
                            let before = n
                                .checked_sub(1)
                                .map_or(f64::INFINITY, |m| iv.enter - ray[m].exit);
                            let after = ray.get(n + 1).map_or(f64::INFINITY, |b| b.enter - iv.exit);
                            let inside = iv.exit - iv.enter;
                            for (t, tag, outside, air) in [
                                (iv.enter, ends.map_or(UNCUT, |e| e.enter), -1, before),
                                (iv.exit, ends.map_or(UNCUT, |e| e.exit), 1, after),
                            ] {
                                p[k] = t;
                                let Some(pr) = design.project(p) else {
                                    acc.unmatched += 1;
                                    continue;
                                };
                                let d = pr.distance;
                                if skip_uncut_behind && d < -ROUNDING_MM && tag == UNCUT {
                                    acc.unmatched += 1;
                                    continue;
                                }
                                acc.checked += 1;
                                acc.deviations.push(d as f32);
                                acc.max_gouge = acc.max_gouge.max(-d);
                                acc.max_excess = acc.max_excess.max(d);
                                if d < -gt || d > et {
                                    acc.defects.push(DefectEnd {
                                        point: p,
                                        deviation: d,
                                        normal: pr.normal,
                                        family: k as u8,
                                        tag,
                                        area: area * pr.normal[k].abs(),
                                        outside,
                                        room: if d < 0.0 { air } else { inside },
                                    });
                                }
                            }
                        }
                    }
                    let done = rows_done.fetch_add(1, Ordering::Relaxed) + 1;
                    if observer.progress(done, rows).is_break() {
                        stopped.store(true, Ordering::Relaxed);
                    }
                    acc
                })
                .reduce(Partial::default, Partial::merge)
        })
        .fold(Partial::default(), Partial::merge);
    if stopped.load(Ordering::Relaxed) {
        return Err(VerifyError::Cancelled {
            done: rows_done.load(Ordering::Relaxed),
            total: rows,
        });
    }
    let link = options.link_cells * grid.h.iter().copied().fold(0.0, f64::max);
    let mut defects = all.defects;
    let (labels, count) = connect(&defects, link);
    weigh_by_crossings(&mut defects, &labels, count, design, stock);
    let mut regions = summarise(&defects, &labels, count, program);
    let volumes = measure_volumes(stock, design, &defects, &labels, &regions, link, et);
    let mut max_excess = all.max_excess;
    if let Some(vol) = &volumes {
        for (r, v) in regions.iter_mut().zip(&vol.per_region) {
            r.volume_mm3 = *v;
        }
        for r in &vol.cavities {
            max_excess = max_excess.max(r.depth_mm);
        }
        regions.extend(vol.cavities.iter().cloned());
    } else {
        for (n, d) in defects.iter().enumerate() {
            regions[labels[n]].volume_mm3 += d.area * d.deviation.abs();
        }
    }
    // Deepest first within each kind, gouges first; numbered in that order.
    regions.sort_by(|a, b| {
        (a.kind == DefectKind::Excess)
            .cmp(&(b.kind == DefectKind::Excess))
            .then(b.depth_mm.total_cmp(&a.depth_mm))
    });
    for (n, r) in regions.iter_mut().enumerate() {
        r.id = n + 1;
    }
    let gouge_ends = defects.iter().filter(|d| d.deviation < 0.0).count() as u64;
    Ok(Verification {
        max_gouge_mm: all.max_gouge.max(0.0),
        max_excess_mm: max_excess.max(0.0),
        ends_checked: all.checked,
        ends_unmatched: all.unmatched,
        gouge_ends,
        excess_ends: defects.len() as u64 - gouge_ends,
        excess_volume_mm3: volumes.as_ref().map(|v| v.excess),
        gouge_volume_mm3: volumes.as_ref().map(|v| v.gouge),
        design_outside_stock_mm3: volumes.as_ref().map(|v| v.outside),
        design_beyond_stock_box: beyond_box(&grid, &design.bounding_box()),
        histogram: histogram(&all.deviations),
        regions,
        options: *options,
        resolution_mm: grid.h,
        elapsed_s: t0.elapsed().as_secs_f64(),
    })
}

fn histogram(devs: &[f32]) -> Histogram {
    let r = devs
        .iter()
        .fold(0.0f64, |m, &d| m.max(f64::from(d).abs()))
        .max(1e-6);
    let n = HISTOGRAM_BINS;
    let edges_mm: Vec<f64> = (0..=n)
        .map(|b| -r + 2.0 * r * b as f64 / n as f64)
        .collect();
    let mut counts = vec![0u64; n];
    for &d in devs {
        let b = ((f64::from(d) + r) / (2.0 * r) * n as f64).floor();
        counts[(b.max(0.0) as usize).min(n - 1)] += 1;
    }
    Histogram { edges_mm, counts }
}

/// Union–find over the defect ends: ends of one kind within `link` mm are one region.
/// Returns each end's region label (dense, `0..count`) and the count.
fn connect(defects: &[DefectEnd], link: f64) -> (Vec<usize>, usize) {
    let key = |p: Vec3| {
        [
            (p.x / link).floor() as i64,
            (p.y / link).floor() as i64,
            (p.z / link).floor() as i64,
        ]
    };
    let mut cells: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    for (n, d) in defects.iter().enumerate() {
        cells.entry(key(d.point)).or_default().push(n as u32);
    }
    let mut parent: Vec<u32> = (0..defects.len() as u32).collect();
    fn find(parent: &mut [u32], mut a: u32) -> u32 {
        while parent[a as usize] != a {
            parent[a as usize] = parent[parent[a as usize] as usize];
            a = parent[a as usize];
        }
        a
    }
    let link2 = link * link;
    for (n, d) in defects.iter().enumerate() {
        let c = key(d.point);
        let kind = d.kind();
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let Some(bucket) = cells.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) else {
                        continue;
                    };
                    for &m in bucket {
                        if (m as usize) >= n {
                            continue;
                        }
                        let o = &defects[m as usize];
                        if o.kind() == kind && o.point.distance_squared(d.point) <= link2 {
                            let (a, b) = (find(&mut parent, n as u32), find(&mut parent, m));
                            if a != b {
                                parent[a.max(b) as usize] = a.min(b);
                            }
                        }
                    }
                }
            }
        }
    }
    let mut dense: HashMap<u32, usize> = HashMap::new();
    let labels = (0..defects.len() as u32)
        .map(|n| {
            let root = find(&mut parent, n);
            let next = dense.len();
            *dense.entry(root).or_insert(next)
        })
        .collect();
    (labels, dense.len())
}

fn summarise(
    defects: &[DefectEnd],
    labels: &[usize],
    count: usize,
    program: Option<&Program>,
) -> Vec<Region> {
    let mut regions: Vec<Region> = (0..count)
        .map(|_| Region::empty(DefectKind::Gouge, -1.0))
        .collect();
    let mut per_move: Vec<HashMap<MoveTag, (f64, usize)>> = vec![HashMap::new(); count];
    for (d, &l) in defects.iter().zip(labels) {
        let r = &mut regions[l];
        let depth = d.deviation.abs();
        r.kind = d.kind();
        r.ends += 1;
        r.area_mm2 += d.area;
        r.bbox_min = r.bbox_min.min(d.point);
        r.bbox_max = r.bbox_max.max(d.point);
        if depth > r.depth_mm {
            r.depth_mm = depth;
            r.deepest = d.point;
            r.deepest_move = (d.tag != UNCUT).then_some(d.tag as usize);
        }
        if d.tag != UNCUT {
            let e = per_move[l].entry(d.tag).or_insert((0.0, 0));
            e.0 = e.0.max(depth);
            e.1 += 1;
        }
    }
    for (r, moves) in regions.iter_mut().zip(per_move) {
        let mut list: Vec<RegionMove> = moves
            .into_iter()
            .map(|(tag, (depth, ends))| {
                let m = program.and_then(|p| p.moves.get(tag as usize).map(|m| (p, m)));
                RegionMove {
                    move_index: tag as usize,
                    file: m
                        .and_then(|(p, m)| p.files.get(usize::from(m.file)).cloned())
                        .unwrap_or_default(),
                    line: m.map_or(0, |(_, m)| m.line),
                    depth_mm: depth,
                    ends,
                }
            })
            .collect();
        list.sort_by(|a, b| {
            b.depth_mm
                .total_cmp(&a.depth_mm)
                .then(a.move_index.cmp(&b.move_index))
        });
        r.move_count = list.len();
        list.truncate(MAX_REGION_MOVES);
        r.moves = list;
    }
    regions
}

/// Sets each defect end's [`DefectEnd::area`] from the design's normal where its ray meets the
/// design (see there): followed from the end ([`Design::meet_along`]), away from the stock's
/// material at a gouge (the missing part lies there) and into it at an excess, no further than
/// twice the region's depth and a cell over the nearest point's normal component along the ray
/// (at least ½), nor beyond the end's own stretch of air or material ([`DefectEnd::room`]).
fn weigh_by_crossings(
    defects: &mut [DefectEnd],
    labels: &[usize],
    count: usize,
    design: &dyn Design,
    stock: &TriDexel,
) {
    let below = design.follow_rays_below();
    if below <= 0.0 {
        return;
    }
    let h = stock.grid().h;
    let mut depth = vec![0.0f64; count];
    for (d, &l) in defects.iter().zip(labels) {
        depth[l] = depth[l].max(d.deviation.abs());
    }
    let areas = [0, 1, 2].map(|k| stock.ray_area(k));
    defects
        .par_iter_mut()
        .zip(labels.par_iter())
        .for_each(|(d, &l)| {
            let k = usize::from(d.family);
            if d.normal[k].abs() >= below {
                return;
            }
            let towards = if d.deviation < 0.0 {
                f64::from(d.outside)
            } else {
                -f64::from(d.outside)
            };
            // Where the ray meets the nearest point's own face: |deviation| / |n_k| away, at
            // most twice the region's depth (and a cell) on faces up to 60° off the ray; past
            // that, the rest of the end's own stretch of air or material.
            let reach = (2.0 * (depth[l] + h[k]) / d.normal[k].abs().max(0.5)).min(d.room);
            // Not met that near: the ray runs along the region's wall, not across its face.
            d.area = design
                .meet_along(d.point, k, towards, reach)
                .map_or(0.0, |n| areas[k] * n[k].abs());
        });
}

/// True when `b` reaches beyond the grid's box by more than a cell along some axis.
fn beyond_box(grid: &swarf_stock::Grid, b: &swarf_geom::Aabb) -> bool {
    (0..3).any(|k| {
        let (lo, hi) = (grid.min[k], grid.max[k]);
        b.min[k] < lo - grid.h[k] || b.max[k] > hi + grid.h[k]
    })
}

/// One piece of stock ∖ part (excess) or part ∖ stock (gouge) along a Z ray.
#[derive(Clone, Copy, Debug)]
struct Piece {
    /// The ray's cell.
    i: u32,
    j: u32,
    lo: f64,
    hi: f64,
    kind: DefectKind,
}

/// What [`measure_volumes`] finds.
struct Volumes {
    /// Each region's volume, mm³ (in the order of the regions given).
    per_region: Vec<f64>,
    /// Excess material that no ray end bounds (a cavity of the design the stock fills), thicker
    /// than the tolerance somewhere: a region each.
    cavities: Vec<Region>,
    /// stock ∖ part, mm³.
    excess: f64,
    /// part ∖ stock within the stock's box, mm³.
    gouge: f64,
    /// The design above or below the stock's box over its footprint, mm³.
    outside: f64,
}

/// Exact volumes from the Z rays when the design bounds a solid: per ray, the pieces of
/// stock ∖ part (excess) and part ∖ stock (gouge) within the stock's box. A piece goes to the
/// region of the defect end that bounds it (or the nearest one of its kind within `2·link` of
/// its middle); a piece no end is that near — material away from the stock's surface, such as
/// a hole left undrilled — goes to the region that reaches it first through pieces of its kind
/// in neighbouring rays (the eight around, overlapping along Z). Excess pieces that no region
/// reaches so make a region of each connected group (a cavity of the design, filled), unless
/// no piece's middle lies farther than `excess_tolerance` from the design. Returns `None` for
/// a design without a solid.
fn measure_volumes(
    stock: &TriDexel,
    design: &dyn Design,
    defects: &[DefectEnd],
    labels: &[usize],
    regions: &[Region],
    link: f64,
    excess_tolerance: f64,
) -> Option<Volumes> {
    let grid = *stock.grid();
    let fam = stock.family(2);
    let (nu, nv) = fam.dims();
    let area = stock.ray_area(2);
    let cell = (grid.h[0], grid.h[1]);
    if !design.bounds_solid() {
        return None;
    }
    let key = |p: Vec3| {
        [
            (p.x / link).floor() as i64,
            (p.y / link).floor() as i64,
            (p.z / link).floor() as i64,
        ]
    };
    let mut cells: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    for (n, d) in defects.iter().enumerate() {
        cells.entry(key(d.point)).or_default().push(n as u32);
    }
    // The region of the nearest defect end of `kind` within 2·link of `p`.
    let nearest = |p: Vec3, kind: DefectKind| -> Option<usize> {
        let c = key(p);
        let mut best: Option<(f64, usize)> = None;
        for dx in -2..=2 {
            for dy in -2..=2 {
                for dz in -2..=2 {
                    let Some(bucket) = cells.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) else {
                        continue;
                    };
                    for &m in bucket {
                        let d = &defects[m as usize];
                        let r = labels[m as usize];
                        if regions[r].kind != kind {
                            continue;
                        }
                        let dist = d.point.distance(p);
                        if dist <= 2.0 * link && best.map_or(true, |(b, _)| dist < b) {
                            best = Some((dist, r));
                        }
                    }
                }
            }
        }
        best.map(|(_, r)| r)
    };
    // The stock's box along Z: design material beyond it was never stock.
    let (z0, z1) = (grid.min[2], grid.max[2]);
    // Per row of rays: its pieces (by ray, then along it) with their regions, and the totals.
    type Row = (Vec<(Piece, Option<usize>)>, f64, f64, f64);
    let rows: Vec<Row> = (0..nv)
        .into_par_iter()
        .map(|j| {
            let (mut pieces, mut ex, mut go, mut out) = (Vec::new(), 0.0, 0.0, 0.0);
            let mut part = Dexel::new();
            let y = grid.center(1, j);
            for i in 0..nu {
                let x = grid.center(0, i);
                part.clear();
                design.solid_intervals(2, x, y, cell, &mut part);
                part.retain(|iv| {
                    let (a, b) = (iv.enter.max(z0), iv.exit.min(z1));
                    out += iv.len() - (b - a).max(0.0);
                    (iv.enter, iv.exit) = (a, b);
                    b > a
                });
                let ray = fam.ray(i, j);
                let first = pieces.len();
                for (kind, a, b) in [
                    (DefectKind::Excess, ray, &part[..]),
                    (DefectKind::Gouge, &part[..], ray),
                ] {
                    for (lo, hi) in difference(a, b) {
                        match kind {
                            DefectKind::Excess => ex += hi - lo,
                            DefectKind::Gouge => go += hi - lo,
                        }
                        // The piece's ends that are stock ends, then its middle.
                        let ends = [lo, hi]
                            .into_iter()
                            .filter(|t| ray.iter().any(|iv| iv.enter == *t || iv.exit == *t))
                            .chain([0.5 * (lo + hi)]);
                        let region = ends
                            .map(|t| nearest(Vec3::new(x, y, t), kind))
                            .find(Option::is_some)
                            .flatten();
                        let (i, j) = (i as u32, j as u32);
                        let piece = Piece { i, j, lo, hi, kind };
                        pieces.push((piece, region));
                    }
                }
                pieces[first..].sort_by(|a, b| a.0.lo.total_cmp(&b.0.lo));
            }
            (pieces, ex, go, out)
        })
        .collect();
    let (mut excess, mut gouge, mut outside) = (0.0, 0.0, 0.0);
    let mut pieces: Vec<Piece> = Vec::new();
    let mut owner: Vec<Option<usize>> = Vec::new();
    for (row, ex, go, out) in rows {
        excess += ex;
        gouge += go;
        outside += out;
        for (p, r) in row {
            pieces.push(p);
            owner.push(r);
        }
    }
    // Where each ray's pieces start (rays row by row), and a piece's neighbours: pieces of its
    // kind in the eight rays around that overlap it along Z.
    let mut start = vec![0u32; nu * nv + 1];
    for p in &pieces {
        start[p.j as usize * nu + p.i as usize + 1] += 1;
    }
    for r in 0..nu * nv {
        start[r + 1] += start[r];
    }
    let neighbours = |n: usize, out: &mut Vec<usize>| {
        out.clear();
        let p = pieces[n];
        for dj in -1i64..=1 {
            for di in -1i64..=1 {
                let (i, j) = (i64::from(p.i) + di, i64::from(p.j) + dj);
                if (di, dj) == (0, 0) || i < 0 || j < 0 || i >= nu as i64 || j >= nv as i64 {
                    continue;
                }
                let r = j as usize * nu + i as usize;
                let (first, end) = (start[r] as usize, start[r + 1] as usize);
                for (m, q) in pieces[first..end].iter().enumerate() {
                    if q.kind == p.kind && q.lo <= p.hi && p.lo <= q.hi {
                        out.push(first + m);
                    }
                }
            }
        }
    };
    // Every region reaches out from its pieces at once, a ring of neighbours at a time.
    let mut queue: std::collections::VecDeque<usize> =
        (0..pieces.len()).filter(|&n| owner[n].is_some()).collect();
    let mut next = Vec::new();
    while let Some(n) = queue.pop_front() {
        neighbours(n, &mut next);
        for &m in &next {
            if owner[m].is_none() {
                owner[m] = owner[n];
                queue.push_back(m);
            }
        }
    }
    let mut per_region = vec![0.0; regions.len()];
    for (p, r) in pieces.iter().zip(&owner) {
        if let Some(r) = r {
            per_region[*r] += (p.hi - p.lo) * area;
        }
    }
    // Excess no region reached: a region of each connected group thicker than the tolerance.
    let mut cavities = Vec::new();
    let mut seen = vec![false; pieces.len()];
    for n in 0..pieces.len() {
        if seen[n] || owner[n].is_some() || pieces[n].kind != DefectKind::Excess {
            continue;
        }
        seen[n] = true;
        let mut group = vec![n];
        let mut at = 0;
        while at < group.len() {
            neighbours(group[at], &mut next);
            for &m in &next {
                if !seen[m] {
                    seen[m] = true;
                    group.push(m);
                }
            }
            at += 1;
        }
        let mut r = Region::empty(DefectKind::Excess, 0.0);
        for &m in &group {
            let p = pieces[m];
            let (x, y) = (grid.center(0, p.i as usize), grid.center(1, p.j as usize));
            r.volume_mm3 += (p.hi - p.lo) * area;
            r.bbox_min = r.bbox_min.min(Vec3::new(x, y, p.lo));
            r.bbox_max = r.bbox_max.max(Vec3::new(x, y, p.hi));
            let mid = Vec3::new(x, y, 0.5 * (p.lo + p.hi));
            if let Some(pr) = design.project(mid) {
                if pr.distance > r.depth_mm {
                    r.depth_mm = pr.distance;
                    r.deepest = mid;
                }
            }
        }
        if r.depth_mm > excess_tolerance {
            cavities.push(r);
        }
    }
    Some(Volumes {
        per_region,
        cavities,
        excess: excess * area,
        gouge: gouge * area,
        outside: outside * area,
    })
}

/// The pieces of `a` not in `b` (both sorted, disjoint), as `(lo, hi)` pairs.
fn difference(a: &[swarf_stock::Interval], b: &[swarf_stock::Interval]) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for iv in a {
        let mut lo = iv.enter;
        for c in b {
            if c.exit <= lo || c.enter >= iv.exit {
                continue;
            }
            if c.enter > lo {
                out.push((lo, c.enter));
            }
            lo = lo.max(c.exit);
            if lo >= iv.exit {
                break;
            }
        }
        if lo < iv.exit {
            out.push((lo, iv.exit));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use swarf_stock::Interval;

    fn iv(a: f64, b: f64) -> Interval {
        Interval { enter: a, exit: b }
    }

    #[test]
    fn interval_difference() {
        let a = [iv(0.0, 10.0), iv(12.0, 14.0)];
        let b = [iv(-1.0, 1.0), iv(3.0, 4.0), iv(9.0, 13.0)];
        assert_eq!(
            difference(&a, &b),
            vec![(1.0, 3.0), (4.0, 9.0), (13.0, 14.0)]
        );
        assert_eq!(difference(&b, &a), vec![(-1.0, 0.0), (10.0, 12.0)]);
        assert!(difference(&a, &a).is_empty());
        assert_eq!(difference(&a, &[]), vec![(0.0, 10.0), (12.0, 14.0)]);
    }

    #[test]
    fn histogram_counts_every_end() {
        let h = histogram(&[-1.0, 0.0, 0.5, 1.0]);
        assert_eq!(h.counts.iter().sum::<u64>(), 4);
        assert_eq!(h.edges_mm.len(), HISTOGRAM_BINS + 1);
        assert_eq!(h.counts[0], 1);
        assert_eq!(h.counts[HISTOGRAM_BINS - 1], 1);
    }

    #[test]
    fn bad_tolerances_are_errors() {
        for o in [
            VerifyOptions::default().with_gouge_tolerance(-1.0),
            VerifyOptions::default().with_excess_tolerance(f64::NAN),
        ] {
            assert!(o.check().is_err());
        }
        assert!(VerifyOptions::default().check().is_ok());
    }
}
