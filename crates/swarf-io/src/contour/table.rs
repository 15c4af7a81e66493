//! For each of the 256 sign configurations of a cube's corners: which of its 12 edges carry a
//! crossing and which surface patch each belongs to. Patches are formed face by face: on a
//! face with two crossed edges they join; on a face with four (two diagonal inside corners)
//! the two edges around each inside corner join, so inside corners stay apart (inside is
//! 6-connected) — the same choice from both cells sharing the face. Where both cells would
//! join all four edges of a face into one patch (a sub-cell tunnel), the extraction asks for
//! the opposite pairing on that face (edges around each outside corner) in both; the case index
//! `mask | flips << 8` carries that choice per face.
//!
//! Corner `c = x + 2y + 4z` (bits are the offsets). Edge `4a + r` runs along axis `a` from the
//! corner with offset 0 to offset 1 along `a`; `r = o₁ + 2 o₂` holds the offsets along the
//! other two axes in increasing order.

use std::sync::OnceLock;

/// No patch: the edge has no crossing.
pub(crate) const NONE: u8 = u8::MAX;

/// One configuration.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CellCase {
    /// Patch of each edge, or [`NONE`].
    pub(crate) patch: [u8; 12],
    /// Number of patches (0 to 4).
    pub(crate) count: u8,
}

/// The two corners of edge `e`.
pub(crate) fn edge_corners(e: usize) -> [usize; 2] {
    let a = e / 4;
    let r = e % 4;
    let others: [usize; 2] = match a {
        0 => [1, 2],
        1 => [0, 2],
        _ => [0, 1],
    };
    let base = ((r & 1) << others[0]) | ((r >> 1) << others[1]);
    [base, base | (1 << a)]
}

fn find(p: &mut [usize; 12], mut x: usize) -> usize {
    while p[x] != x {
        p[x] = p[p[x]];
        x = p[x];
    }
    x
}

/// The case of corner mask `index & 0xff`, with bit `2f + s` of `index >> 8` asking for the
/// outside pairing (edges around each *outside* corner) on face `{corner bit f = s}`.
fn build(index: usize) -> CellCase {
    let mask = index & 0xff;
    let flips = index >> 8;
    let inside = |c: usize| mask >> c & 1 == 1;
    let crossed: Vec<bool> = (0..12)
        .map(|e| {
            let [c0, c1] = edge_corners(e);
            inside(c0) != inside(c1)
        })
        .collect();
    let mut parent: [usize; 12] = std::array::from_fn(|i| i);
    for f in 0..3 {
        for s in 0..2 {
            // Edges of the face {corner bit f = s}: along the other axes, offset s along f.
            let edges: Vec<usize> = (0..12)
                .filter(|&e| {
                    let [c0, c1] = edge_corners(e);
                    e / 4 != f && (c0 >> f & 1) == s && (c1 >> f & 1) == s
                })
                .collect();
            let cut: Vec<usize> = edges.iter().copied().filter(|&e| crossed[e]).collect();
            let mut join = |x: usize, y: usize| {
                let (rx, ry) = (find(&mut parent, x), find(&mut parent, y));
                parent[rx] = ry;
            };
            match cut.len() {
                2 => join(cut[0], cut[1]),
                4 => {
                    let around_inside = flips >> (2 * f + s) & 1 == 0;
                    for c in (0..8).filter(|&c| (c >> f & 1) == s && inside(c) == around_inside) {
                        let around: Vec<usize> = cut
                            .iter()
                            .copied()
                            .filter(|&e| edge_corners(e).contains(&c))
                            .collect();
                        join(around[0], around[1]);
                    }
                }
                _ => {}
            }
        }
    }
    let mut patch = [NONE; 12];
    let mut count = 0u8;
    let mut root_id = [NONE; 12];
    for e in 0..12 {
        if crossed[e] {
            let r = find(&mut parent, e);
            if root_id[r] == NONE {
                root_id[r] = count;
                count += 1;
            }
            patch[e] = root_id[r];
        }
    }
    CellCase { patch, count }
}

/// The table for every corner mask and face-rule choice (`mask | flips << 8`), built on first
/// use.
pub(crate) fn cases() -> &'static [CellCase] {
    static TABLE: OnceLock<Vec<CellCase>> = OnceLock::new();
    TABLE.get_or_init(|| (0..256 * 64).map(build).collect())
}

/// Faces (bit `2f + s`) with four crossed edges that the default pairing joins into a single
/// patch: a tunnel through the face closes inside the cell. When the cell across such a face
/// does the same, both switch to the outside pairing on it, which never joins them (checked
/// exhaustively in the tests), so the edge between their vertices keeps exactly two triangles.
pub(crate) fn joined_faces(mask: u8) -> u8 {
    static TABLE: OnceLock<[u8; 256]> = OnceLock::new();
    TABLE.get_or_init(|| {
        std::array::from_fn(|m| {
            let case = &cases()[m];
            let mut bits = 0u8;
            for (face, edges) in face_edges().iter().enumerate() {
                let p: Vec<u8> = edges
                    .iter()
                    .map(|&e| case.patch[e])
                    .filter(|&p| p != NONE)
                    .collect();
                if p.len() == 4 && p.iter().all(|&x| x == p[0]) {
                    bits |= 1 << face;
                }
            }
            bits
        })
    })[mask as usize]
}

/// True when some face of the cell of corner mask `mask` has all four edges crossed (two
/// diagonal inside corners): the faces where the two cells beside it must agree on a pairing.
pub(crate) fn has_ambiguous_face(mask: u8) -> bool {
    static TABLE: OnceLock<[bool; 256]> = OnceLock::new();
    TABLE.get_or_init(|| {
        std::array::from_fn(|m| {
            face_edges().iter().any(|edges| {
                edges.iter().all(|&e| {
                    let [c0, c1] = edge_corners(e);
                    (m >> c0 & 1) != (m >> c1 & 1)
                })
            })
        })
    })[mask as usize]
}

/// The four edges of each face, face index `2f + s`.
pub(crate) fn face_edges() -> [[usize; 4]; 6] {
    std::array::from_fn(|face| {
        let (f, s) = (face / 2, face % 2);
        let mut out = [0; 4];
        let mut n = 0;
        for e in 0..12 {
            let [c0, c1] = edge_corners(e);
            if e / 4 != f && (c0 >> f & 1) == s && (c1 >> f & 1) == s {
                out[n] = e;
                n += 1;
            }
        }
        out
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ambiguous_faces_are_the_diagonal_ones() {
        // Corners 0 and 3 (x + 2y + 4z) are diagonal on the face z = 0.
        assert!(has_ambiguous_face(0b0000_1001));
        // Corners 0 and 5 on the face y = 0, 0 and 6 on x = 0, all but 0 and 3.
        assert!(has_ambiguous_face(0b0010_0001));
        assert!(has_ambiguous_face(0b0100_0001));
        assert!(has_ambiguous_face(!0b0000_1001));
        // An edge, a face, a body diagonal, nothing, everything: no face with two diagonal
        // inside corners alone.
        for m in [0b0000_0011u8, 0b0000_1111, 0b1000_0001, 0, 0xff] {
            assert!(!has_ambiguous_face(m), "{m:#010b}");
        }
        // From the corners instead of the edges: a face is ambiguous when exactly two of its
        // corners are inside and they differ in both of the face's own coordinates.
        for m in 0..=255u8 {
            let by_corners = (0..3).any(|f| {
                (0..2).any(|s| {
                    let inside: Vec<usize> = (0..8)
                        .filter(|&c| c >> f & 1 == s && m >> c & 1 == 1)
                        .collect();
                    inside.len() == 2 && (inside[0] ^ inside[1]).count_ones() == 2
                })
            });
            assert_eq!(has_ambiguous_face(m), by_corners, "{m:#010b}");
        }
    }

    #[test]
    fn single_corner_diagonal_and_counts() {
        let t = cases();
        assert_eq!(t[0].count, 0);
        assert_eq!(t[255].count, 0);
        // One inside corner: three crossed edges, one patch.
        assert_eq!(t[1].count, 1);
        assert_eq!(t[1].patch.iter().filter(|&&p| p != NONE).count(), 3);
        // Two corners diagonal on the bottom face (0 and 3): kept apart.
        assert_eq!(t[0b1001].count, 2);
        // Opposite corners through the body (0 and 7): two patches.
        assert_eq!(t[0b1000_0001].count, 2);
        // Half the cube inside (bottom face): one patch of four edges.
        assert_eq!(t[0b1111].count, 1);
        // Complement symmetry of crossed edges, and at most four patches anywhere.
        for m in 0..256 {
            let crossed = |c: &CellCase| c.patch.map(|p| p != NONE);
            assert_eq!(crossed(&t[m]), crossed(&t[255 - m]));
            assert!(t[m].count <= 4);
        }
        assert_eq!(edge_corners(0), [0, 1]);
        assert_eq!(face_edges()[0], [4, 6, 8, 10]);
        assert_eq!(edge_corners(11), [3, 7]);
        assert_eq!(edge_corners(5), [1, 3]);
    }
}

#[cfg(test)]
mod exhaustive {
    use super::*;

    fn joined(index: usize, face: usize) -> bool {
        let p: Vec<u8> = face_edges()[face]
            .iter()
            .map(|&e| cases()[index].patch[e])
            .filter(|&p| p != NONE)
            .collect();
        p.len() == 4 && p.iter().all(|&x| x == p[0])
    }

    /// The two facts that make the extraction's flip rule (flip a face where both cells
    /// join it by default) manifold at every edge, checked over every mask and every set of
    /// flipped faces the rule can produce (subsets of the default-joined faces):
    /// 1. a face that is not flipped joins only if it joins by default; so when it is not
    ///    flipped because one side does not join by default, that side does not join at all;
    /// 2. a flipped face never joins.
    #[test]
    fn flip_rule_keeps_every_face_unjoined_on_at_least_one_side() {
        let mut checked = 0;
        for mask in 0..256usize {
            let default = joined_faces(mask as u8) as usize;
            // Every subset of the default-joined faces.
            let mut sub = default;
            loop {
                let index = mask | sub << 8;
                for face in 0..6 {
                    let flipped = sub >> face & 1 == 1;
                    if joined(index, face) {
                        assert!(
                            !flipped,
                            "mask {mask:#b} flips {sub:#b}: flipped face {face} joins"
                        );
                        assert!(
                            default >> face & 1 == 1,
                            "mask {mask:#b} flips {sub:#b}: face {face} joins only after flips"
                        );
                    }
                    checked += 1;
                }
                // Crossed edges do not depend on the pairing.
                assert_eq!(
                    cases()[index].patch.map(|p| p != NONE),
                    cases()[mask].patch.map(|p| p != NONE)
                );
                if sub == 0 {
                    break;
                }
                sub = (sub - 1) & default;
            }
        }
        assert!(checked > 1536, "{checked}");
    }
}
