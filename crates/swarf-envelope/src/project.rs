//! Mesh vertices put on the exact envelope.
//!
//! Dual contouring places a vertex where the tangent planes of its cell's ray crossings meet:
//! on a curved envelope that is a few micrometres off the surface (`O(h²κ)`), however exact the
//! crossings are. The envelope is known exactly along any line parallel to a world axis (the
//! union of the fixed-axis pieces' closed-form intervals), so each vertex is moved along the
//! world axis nearest to its normal onto the nearest end of that union whose side agrees with
//! the normal — an exact point of the envelope a fraction of a spacing away. The mesh's
//! connectivity is kept; a vertex with no such end within one spacing stays where it was.

use smallvec::SmallVec;
use swarf_geom::math::Vec3;
use swarf_geom::Aabb;
use swarf_sweep::SweptConvex;

/// The sweeps whose boxes (grown by a pad) meet each cell of a uniform grid: the few that can
/// pass near a point, found without testing every sweep.
pub(crate) struct SweepIndex {
    cells: Cells,
    /// `items[starts[c]..starts[c + 1]]` are the sweeps of cell `c`.
    starts: Vec<u32>,
    items: Vec<u32>,
    boxes: Vec<Aabb>,
}

impl SweepIndex {
    /// An index of `boxes` grown by `pad`, with cells of side `cell`.
    pub(crate) fn new(boxes: Vec<Aabb>, pad: f64, cell: f64) -> Self {
        let boxes: Vec<Aabb> = boxes.into_iter().map(|b| b.inflated(pad)).collect();
        let all = boxes
            .iter()
            .copied()
            .reduce(|a, b| a.union(&b))
            .unwrap_or_else(|| Aabb::new(Vec3::ZERO, Vec3::ZERO));
        let size = all.size();
        let n = [0, 1, 2].map(|k| ((size[k] / cell).floor() as usize + 1).max(1));
        let cells = Cells {
            origin: all.min,
            cell,
            n,
        };
        let mut index = Self {
            cells,
            starts: vec![0; n[0] * n[1] * n[2] + 1],
            items: Vec::new(),
            boxes,
        };
        // Counting sort: sizes, offsets, then fill.
        for b in &index.boxes {
            for c in cells.of(b) {
                index.starts[c + 1] += 1;
            }
        }
        for c in 1..index.starts.len() {
            index.starts[c] += index.starts[c - 1];
        }
        let mut next = index.starts.clone();
        index.items = vec![0; *index.starts.last().unwrap_or(&0) as usize];
        for (s, b) in index.boxes.iter().enumerate() {
            for c in cells.of(b) {
                index.items[next[c] as usize] = s as u32;
                next[c] += 1;
            }
        }
        index
    }

    /// The sweeps whose grown box holds `p`.
    pub(crate) fn near(&self, p: Vec3) -> impl Iterator<Item = usize> + '_ {
        let g = &self.cells;
        let inside =
            (0..3).all(|k| p[k] >= g.origin[k] && p[k] <= g.origin[k] + g.cell * g.n[k] as f64);
        let c = if inside {
            let [x, y, z] = [0, 1, 2].map(|k| g.range(p[k], p[k], k).0);
            (z * g.n[1] + y) * g.n[0] + x
        } else {
            0
        };
        let items = if inside {
            &self.items[self.starts[c] as usize..self.starts[c + 1] as usize]
        } else {
            &[][..]
        };
        items
            .iter()
            .map(|&s| s as usize)
            .filter(move |&s| self.boxes[s].contains(p))
    }
}

/// A uniform grid of cells.
#[derive(Clone, Copy)]
struct Cells {
    origin: Vec3,
    cell: f64,
    n: [usize; 3],
}

impl Cells {
    /// The cells along axis `k` that `[lo, hi]` meets (clamped to the grid).
    fn range(&self, lo: f64, hi: f64, k: usize) -> (usize, usize) {
        let f = |x: f64| {
            (((x - self.origin[k]) / self.cell).floor().max(0.0) as usize).min(self.n[k] - 1)
        };
        (f(lo), f(hi))
    }

    /// The cells that `b` meets, as linear indices.
    fn of(self, b: &Aabb) -> impl Iterator<Item = usize> {
        let [(x0, x1), (y0, y1), (z0, z1)] = [0, 1, 2].map(|k| self.range(b.min[k], b.max[k], k));
        let n = self.n;
        (z0..=z1).flat_map(move |z| {
            (y0..=y1).flat_map(move |y| (x0..=x1).map(move |x| (z * n[1] + y) * n[0] + x))
        })
    }
}

/// The point of the union of `sweeps`' volumes' boundary reached from `p` along the world axis
/// nearest to the outward normal `n`, when one lies within `limit`: the nearest end of the
/// union's intervals on that line whose kind agrees with `n` (an exit where `n` points along
/// the axis, an entry where it points against it). Where that line misses — a vertex just
/// outside a sharp edge of the envelope, whose axis lines pass beside both faces — the line
/// along `n` itself, which crosses the edge's wedge.
pub(crate) fn onto_envelope(
    sweeps: &[SweptConvex<'_>],
    index: &SweepIndex,
    p: Vec3,
    n: Vec3,
    limit: f64,
) -> Option<Vec3> {
    let k = (0..3).max_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs()))?;
    if n[k] == 0.0 || n[k].is_nan() {
        return None;
    }
    let along_axis = nearest_exit(
        index
            .near(p)
            .filter_map(|s| sweeps[s].axis_ray_interval(p, k)),
        p[k],
        n[k] > 0.0,
        limit,
    );
    if let Some(end) = along_axis {
        let mut q = p;
        q[k] = end;
        return Some(q);
    }
    let dir = n.normalize();
    nearest_exit(
        index.near(p).filter_map(|s| sweeps[s].ray_interval(p, dir)),
        0.0,
        true,
        limit,
    )
    .map(|t| p + dir * t)
}

/// Of the union of `spans` (intervals along a line), the end nearest to `t` within `limit`:
/// an exit (upper end) when `exit`, else an entry.
fn nearest_exit(
    spans: impl Iterator<Item = (f64, f64)>,
    t: f64,
    exit: bool,
    limit: f64,
) -> Option<f64> {
    let mut spans: SmallVec<[(f64, f64); 8]> = spans.collect();
    spans.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
    let mut best: Option<f64> = None;
    let mut consider = |end: f64| {
        if (end - t).abs() <= limit && best.map_or(true, |b| (end - t).abs() < (b - t).abs()) {
            best = Some(end);
        }
    };
    let mut current: Option<(f64, f64)> = None;
    for (lo, hi) in spans
        .into_iter()
        .chain(std::iter::once((f64::NAN, f64::NAN)))
    {
        match current {
            // Overlapping or touching intervals are one piece of the union.
            Some((a, b)) if lo <= b => current = Some((a, b.max(hi))),
            _ => {
                if let Some((a, b)) = current {
                    consider(if exit { b } else { a });
                }
                current = (!lo.is_nan()).then_some((lo, hi));
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_end_of_the_union_of_the_right_kind() {
        let spans = [(2.0, 5.0), (0.0, 1.0), (1.0, 3.0), (7.0, 9.0)];
        // Union: [0, 5] and [7, 9].
        let near = |t, exit, limit| nearest_exit(spans.iter().copied(), t, exit, limit);
        assert_eq!(near(4.8, true, 1.0), Some(5.0));
        // The touching ends at 1 and 3 are inside the union, not boundary.
        assert_eq!(near(1.1, true, 1.0), None);
        assert_eq!(near(1.1, false, 2.0), Some(0.0));
        assert_eq!(near(6.5, false, 1.0), Some(7.0));
        assert_eq!(near(6.5, true, 1.0), None);
        assert_eq!(near(6.5, true, 1.5), Some(5.0));
        assert_eq!(nearest_exit(std::iter::empty(), 0.0, true, 1.0), None);
    }

    #[test]
    fn the_index_finds_every_box_holding_a_point() {
        let boxes: Vec<Aabb> = (0..40)
            .map(|i| {
                let c = Vec3::new((i * 7 % 13) as f64, (i * 5 % 11) as f64, (i % 3) as f64);
                Aabb::new(c, c + Vec3::new(1.0 + (i % 4) as f64, 2.0, 0.5))
            })
            .collect();
        let index = SweepIndex::new(boxes.clone(), 0.1, 1.5);
        for i in 0..500 {
            let p = Vec3::new(
                (i * 37 % 170) as f64 * 0.1 - 1.0,
                (i * 53 % 150) as f64 * 0.1 - 1.0,
                (i * 11 % 40) as f64 * 0.1 - 0.5,
            );
            let mut found: Vec<usize> = index.near(p).collect();
            found.sort_unstable();
            let want: Vec<usize> = (0..boxes.len())
                .filter(|&s| boxes[s].inflated(0.1).contains(p))
                .collect();
            assert_eq!(found, want, "{p:?}");
        }
    }
}
