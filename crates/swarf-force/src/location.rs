//! Forces, torque and power at the cutter locations of a program.

use std::collections::BTreeMap;

use serde::Serialize;
use swarf_engage::{EngageOptions, Engagement};
use swarf_geom::math::Vec3;
use swarf_tool::ToolSet;

use crate::coefficients::{Coefficients, Material};
use crate::edges::CutterEdges;
use crate::model::{unit_forces, ForceCurves, UnitForces};
use crate::ForceError;

/// Default samples per spindle revolution.
pub const DEFAULT_SAMPLES_PER_REV: usize = 360;

/// Most spindle-angle samples per revolution: a hundredth of a degree, far finer than any
/// tooth-passing curve needs; more would only exhaust memory (each location keeps its curves).
pub const MAX_SAMPLES_PER_REV: usize = 36_000;

/// The force summary of one cutter location. Forces on the tool, N; `fx fy fz` in the tool frame
/// (`x_L` feed, `y_L`, `z_L` axis), `wx wy wz` in the workpiece frame; peaks are the largest
/// |component| over a revolution.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct LocationForces {
    /// Feed per tooth, mm.
    pub feed_per_tooth_mm: f64,
    /// Mean Fx, Fy, Fz over a revolution (tool frame), N.
    pub mean_n: [f64; 3],
    /// Peak |Fx|, |Fy|, |Fz| (tool frame), N.
    pub peak_n: [f64; 3],
    /// Peak resultant, N.
    pub peak_resultant_n: f64,
    /// Mean force in the workpiece frame, N.
    pub mean_world_n: [f64; 3],
    /// Mean spindle torque, N·m.
    pub torque_mean_nm: f64,
    /// Peak spindle torque, N·m.
    pub torque_peak_nm: f64,
    /// Mean spindle power, W.
    pub power_mean_w: f64,
    /// Peak spindle power, W.
    pub power_peak_w: f64,
    /// The coefficients used.
    pub coefficients: Coefficients,
}

/// What a force limit bounds.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Limit {
    /// Peak resultant force, N.
    Force(f64),
    /// Peak spindle torque, N·m.
    Torque(f64),
    /// Peak spindle power, W.
    Power(f64),
}

impl Limit {
    /// The limit's value.
    pub fn value(&self) -> f64 {
        match *self {
            Limit::Force(v) | Limit::Torque(v) | Limit::Power(v) => v,
        }
    }

    /// The limited quantity of `f`.
    pub fn measure(&self, f: &LocationForces) -> f64 {
        match self {
            Limit::Force(_) => f.peak_resultant_n,
            Limit::Torque(_) => f.torque_peak_nm,
            Limit::Power(_) => f.power_peak_w,
        }
    }
}

/// The force model of a run: the material, the tools' edges and the sampling.
pub struct ForceModel {
    material: Material,
    edges: BTreeMap<u32, CutterEdges>,
    fallback: Option<CutterEdges>,
    samples_per_rev: usize,
}

/// One location evaluated: its unit forces and what the program asks of it.
#[derive(Clone, Debug)]
pub struct Evaluated {
    /// Per unit coefficient and feed per tooth.
    pub unit: UnitForces,
    /// Feed per tooth the program gives, mm.
    pub feed_per_tooth_mm: f64,
    /// Spindle speed, rpm.
    pub spindle_rpm: f64,
    /// Spindle direction (the sign of the torque about `z_L` and of ω).
    pub spindle_dir: swarf_path::SpindleDir,
    /// Flutes of the tool.
    pub flutes: u32,
    /// Helix, degrees.
    pub helix_deg: f64,
    /// Rake, degrees, when given.
    pub rake_deg: Option<f64>,
    /// The location's tool frame `x_L, y_L, z_L`.
    pub frame: [Vec3; 3],
}

impl ForceModel {
    /// The model for `material` and every tool of `tools` that `tool_numbers` use (and the
    /// fallback cutter, for moves with no tool of their own), with the engagement's discs
    /// (`opts`).
    ///
    /// # Errors
    /// A tool without a flute count, or (for a predicted material) without a rake angle.
    pub fn new(
        material: Material,
        tools: &ToolSet,
        tool_numbers: &[u32],
        opts: &EngageOptions,
        samples_per_rev: usize,
    ) -> Result<Self, ForceError> {
        Self::with_default_flutes(material, tools, tool_numbers, opts, samples_per_rev, None)
    }

    /// [`ForceModel::new`], with `default_flutes` for the tools that state no flute count
    /// (tools from a LinuxCNC `.tbl`, which cannot hold one); a stated count wins.
    ///
    /// # Errors
    /// As [`ForceModel::new`]; a tool without a flute count only when there is no default.
    pub fn with_default_flutes(
        material: Material,
        tools: &ToolSet,
        tool_numbers: &[u32],
        opts: &EngageOptions,
        samples_per_rev: usize,
        default_flutes: Option<u32>,
    ) -> Result<Self, ForceError> {
        if !(1..=MAX_SAMPLES_PER_REV).contains(&samples_per_rev) {
            return Err(ForceError::BadOption {
                name: "samples-per-rev",
                value: samples_per_rev as f64,
                want: "a whole number from 1 to 36000",
            });
        }
        let mut edges = BTreeMap::new();
        for &n in tool_numbers {
            if let Some(c) = tools.resolved().get(&n) {
                let label = format!("tool {n} ({})", short(&c.cutter));
                let e = CutterEdges::with_default_flutes(
                    &c.cutter,
                    opts,
                    &label,
                    Some(n),
                    default_flutes,
                )?;
                check_rake(&material, &e, &label)?;
                edges.insert(n, e);
            }
        }
        let fallback = match tools.fallback() {
            Some(c) => {
                let label = format!("the cutter ({})", short(c));
                let e = CutterEdges::with_default_flutes(c, opts, &label, None, default_flutes)?;
                check_rake(&material, &e, &label)?;
                Some(e)
            }
            None => None,
        };
        Ok(Self {
            material,
            edges,
            fallback,
            samples_per_rev,
        })
    }

    /// The material.
    pub fn material(&self) -> &Material {
        &self.material
    }

    /// Samples per revolution.
    pub fn samples_per_rev(&self) -> usize {
        self.samples_per_rev
    }

    fn edges_of(&self, tool: u32) -> Option<&CutterEdges> {
        self.edges.get(&tool).or(self.fallback.as_ref())
    }

    /// The unit forces at `e` and the feed per tooth the program gives there.
    pub fn evaluate(&self, e: &Engagement) -> Evaluated {
        let Some(edges) = self.edges_of(e.tool) else {
            return Evaluated {
                unit: UnitForces::default(),
                feed_per_tooth_mm: 0.0,
                spindle_rpm: e.spindle_rpm,
                spindle_dir: e.spindle_dir,
                flutes: 1,
                helix_deg: 0.0,
                rake_deg: None,
                frame: [e.x_l, e.y_l, e.axis],
            };
        };
        let c = if e.spindle_rpm > 0.0 {
            e.feed_mm_min / (e.spindle_rpm * edges.flutes as f64)
        } else {
            0.0
        };
        Evaluated {
            unit: unit_forces(e, edges, self.samples_per_rev),
            feed_per_tooth_mm: c,
            spindle_rpm: e.spindle_rpm,
            spindle_dir: e.spindle_dir,
            flutes: edges.flutes,
            helix_deg: edges.helix_deg,
            rake_deg: edges.rake_deg,
            frame: [e.x_l, e.y_l, e.axis],
        }
    }

    /// The coefficients at an evaluated location cut at feed per tooth `c`.
    pub fn coefficients_at(&self, ev: &Evaluated, c: f64) -> Coefficients {
        self.material
            .coefficients(ev.rake_deg, ev.helix_deg, ev.unit.chip_per_feed * c)
            // The rake was checked when the model was built.
            .unwrap_or_default()
    }

    /// The forces at an evaluated location at feed per tooth `c` (the program's when `None`).
    pub fn forces(&self, ev: &Evaluated, c: Option<f64>) -> (LocationForces, ForceCurves) {
        let c = c.unwrap_or(ev.feed_per_tooth_mm);
        let coef = self.coefficients_at(ev, c);
        let curves = ev.unit.combine(coef.as_array(), c);
        let peaks = curves.peaks();
        // ω about z_L: negative for M4, whose torque about z_L is negative too.
        let omega = ev.spindle_rpm * std::f64::consts::TAU / 60.0;
        let signed_omega = if ev.spindle_dir == swarf_path::SpindleDir::CounterClockwise {
            -omega
        } else {
            omega
        };
        let [x, y, z] = ev.frame;
        let world = x * curves.means[0] + y * curves.means[1] + z * curves.means[2];
        let f = LocationForces {
            feed_per_tooth_mm: c,
            mean_n: [curves.means[0], curves.means[1], curves.means[2]],
            peak_n: [peaks[0], peaks[1], peaks[2]],
            peak_resultant_n: curves.peak_resultant(),
            mean_world_n: [world.x, world.y, world.z],
            torque_mean_nm: curves.means[3],
            torque_peak_nm: peaks[3],
            power_mean_w: curves.means[3] * signed_omega,
            power_peak_w: peaks[3] * omega,
            coefficients: coef,
        };
        (f, curves)
    }

    /// The largest feed per tooth in `[0, c_max]` whose `limit` measure stays at or under its
    /// value, or `None` when even the edge forces alone (feed → 0) exceed it.
    pub fn max_feed_per_tooth(&self, ev: &Evaluated, limit: Limit, c_max: f64) -> Option<f64> {
        let over = |c: f64| limit.measure(&self.forces(ev, Some(c)).0) > limit.value();
        if over(0.0) {
            return None;
        }
        if !over(c_max) {
            return Some(c_max);
        }
        // The measure is convex in c for fixed coefficients (a maximum of norms of affine
        // functions), so the feeds under the limit are an interval [0, c*]: bisect.
        let (mut lo, mut hi) = (0.0, c_max);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if over(mid) {
                hi = mid;
            } else {
                lo = mid;
            }
            if hi - lo <= 1e-9 * c_max {
                break;
            }
        }
        Some(lo)
    }
}

/// A cutter in a few words: `flat Ø10 mm`.
fn short(c: &swarf_tool::Cutter) -> String {
    format!("{} Ø{} mm", c.kind().spec_name(), c.apt_params().d)
}

fn check_rake(material: &Material, e: &CutterEdges, label: &str) -> Result<(), ForceError> {
    if !material.is_fixed() && e.rake_deg.is_none() {
        return Err(ForceError::NoToolRake {
            tool: label.to_string(),
            material: material.name.clone(),
        });
    }
    Ok(())
}
