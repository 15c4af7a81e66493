//! Helpers shared by the integration tests: programs from text, the cutters of every type and a
//! deterministic generator (from `swarf-sweep`'s tests), and an independent reference for swept
//! volumes (the union of tool instances along lattice lines, by swarf-tool's own ray
//! intersections).
#![allow(dead_code, unreachable_pub)]

use swarf_geom::math::{Vec2, Vec3};
use swarf_geom::{Frame, Ray};
use swarf_io::HermiteGrid;
use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::{Machine, Program};
use swarf_stock::TriDexel;
use swarf_tool::{AnyPiece, Cutter, Piece, RevolvedSolid, ToolSet, ToolSource};

#[path = "../../../swarf-sweep/tests/common/mod.rs"]
mod sweep_common;
#[allow(unused_imports)]
pub use sweep_common::{cutters, generic, Rng};

pub fn gcode(text: &str) -> Program {
    read_program_str(
        text,
        "test.ngc",
        Machine::three_axis(),
        &ReadOptions::default(),
    )
    .unwrap()
}

pub fn gcode_on(text: &str, machine: &str) -> Program {
    let m = Machine::from_name(machine).unwrap();
    read_program_str(text, "test.ngc", m, &ReadOptions::default()).unwrap()
}

pub fn apt(text: &str) -> Program {
    read_program_str(
        text,
        "test.apt",
        Machine::three_axis(),
        &ReadOptions::default(),
    )
    .unwrap()
}

/// `c` as tool 0 (and no other tool).
pub fn tools(c: &Cutter) -> ToolSet {
    ToolSet::default().with(0, c.clone(), ToolSource::Spec)
}

/// The solids of the whole tool.
pub fn solids(c: &Cutter) -> Vec<&RevolvedSolid> {
    let mut v = vec![c.cutting_solid(), c.shank_solid()];
    v.extend(c.holder_solid());
    v
}

/// Union of the intervals of the line `o + t·axis_k` inside the tool instances at `poses`
/// (tip, axis), by swarf-tool's ray crossings (code independent of the sweep kernels).
pub fn instance_union(c: &Cutter, poses: &[(Vec3, Vec3)], o: Vec3, k: usize) -> Vec<(f64, f64)> {
    let mut spans = Vec::new();
    let mut hits = Vec::new();
    for &(tip, axis) in poses {
        let fr = Frame::from_axis(tip, axis);
        let ray = Ray::new(fr.to_local(o), fr.vector_to_local(Vec3::AXES[k]));
        for s in solids(c) {
            hits.clear();
            s.ray_intersections(&ray, &mut hits);
            hits.sort_by(f64::total_cmp);
            for pair in hits.chunks_exact(2) {
                spans.push((pair[0], pair[1]));
            }
        }
    }
    spans.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out: Vec<(f64, f64)> = Vec::new();
    for s in spans {
        match out.last_mut() {
            Some(l) if s.0 <= l.1 => l.1 = l.1.max(s.1),
            _ => out.push(s),
        }
    }
    out
}

/// Distance in a meridian half-plane from `(ρ, z)` to the profile curve of `piece`.
fn profile_distance(piece: &AnyPiece, q: Vec2) -> f64 {
    let seg = |a: Vec2, b: Vec2| {
        let d = b - a;
        let t = ((q - a).dot(d) / d.length_squared()).clamp(0.0, 1.0);
        (q - (a + d * t)).length()
    };
    let arc = |c: Vec2, r: f64, p0: f64, p1: f64| {
        let d = q - c;
        let phi = d.x.atan2(-d.y);
        if phi >= p0 && phi <= p1 {
            (d.length() - r).abs()
        } else {
            let e = |p: f64| (c + Vec2::new(r * p.sin(), -r * p.cos())).distance(q);
            e(p0).min(e(p1))
        }
    };
    match piece {
        AnyPiece::Disc(d) => seg(Vec2::new(d.inner, d.z), Vec2::new(d.outer, d.z)),
        AnyPiece::Cone(c) => seg(c.bottom, c.top),
        AnyPiece::Cylinder(c) => {
            let (z0, z1) = c.z_range();
            seg(Vec2::new(c.radius, z0), Vec2::new(c.radius, z1))
        }
        AnyPiece::Torus(t) => arc(Vec2::new(t.major, t.center_z), t.minor, t.phi0, t.phi1),
        AnyPiece::Sphere(s) => arc(Vec2::new(0.0, s.center_z), s.radius, s.phi0, s.phi1),
    }
}

/// Exact distance from `x` to the union of the tool instances at `poses` (0 inside one).
pub fn distance_to_instances(c: &Cutter, poses: &[(Vec3, Vec3)], x: Vec3) -> f64 {
    let mut best = f64::INFINITY;
    for &(tip, axis) in poses {
        let fr = Frame::from_axis(tip, axis);
        let y = fr.to_local(x);
        let q = Vec2::new(y.x.hypot(y.y), y.z);
        for s in solids(c) {
            if s.contains(y) {
                return 0.0;
            }
            for p in s.pieces() {
                best = best.min(profile_distance(p, q));
            }
        }
    }
    best
}

/// The largest distance from a boundary point of the envelope (an interval end on a lattice
/// line: an exact point of the swept volume's boundary) to the union of the instances. The
/// instances lie inside the sweep, so this is the Hausdorff distance between the two volumes.
pub fn envelope_to_instances(grid: &TriDexel, c: &Cutter, poses: &[(Vec3, Vec3)]) -> f64 {
    use rayon::prelude::*;
    let lat = grid.lattice();
    let rows: Vec<(usize, usize)> = (0..3)
        .flat_map(|k| (0..lat.n[(k + 2) % 3]).map(move |v| (k, v)))
        .collect();
    rows.par_iter()
        .map(|&(k, v)| {
            let (ua, va) = ((k + 1) % 3, (k + 2) % 3);
            let mut worst = 0.0f64;
            for u in 0..lat.n[ua] {
                for sp in grid.family(k).ray(u, v) {
                    for t in [sp.enter, sp.exit] {
                        let mut x = Vec3::ZERO;
                        x[ua] = lat.coord(ua, u as isize);
                        x[va] = lat.coord(va, v as isize);
                        x[k] = t;
                        worst = worst.max(distance_to_instances(c, poses, x));
                    }
                }
            }
            worst
        })
        .reduce(|| 0.0, f64::max)
}

/// Volume of the union of the instances from the Z lines of `grid`, mm³.
pub fn instance_volume(grid: &TriDexel, c: &Cutter, poses: &[(Vec3, Vec3)]) -> f64 {
    let lat = grid.lattice();
    let mut total = 0.0;
    for v in 0..lat.n[1] {
        for u in 0..lat.n[0] {
            let o = Vec3::new(lat.coord(0, u as isize), lat.coord(1, v as isize), 0.0);
            total += instance_union(c, poses, o, 2)
                .iter()
                .map(|s| s.1 - s.0)
                .sum::<f64>();
        }
    }
    total * lat.spacing.x * lat.spacing.y
}
