//! The samples' sides packed 64 to a word, one row of words per circle, and the samples whose
//! 3 × 3 neighbourhood holds both sides: where the sampling's pass 3 must probe. Bit `j % 64`
//! of word `j / 64` of a row is sample `j` of that circle; bits past the circle's `n` samples
//! are 0. A row's borders are found a word (64 samples) at a time, where a byte per sample
//! took 64 times the operations — the scan was an eighth of a location's time on two threads.

/// Words per row of `n` samples.
pub(crate) fn words(n: usize) -> usize {
    n.div_ceil(64)
}

/// Packs the samples `items` into `out` (`words(items.len())` words): bit `j` set where
/// `set(&items[j])`.
///
/// A word's samples are first written as 0/1 bytes (a loop without branches, which the
/// compiler vectorises), then gathered eight at a time by one multiply: the product of eight
/// 0/1 bytes `b₀ … b₇` (little-endian) with `0x0102040810204080` holds `bᵢ` at bit `56 + i`
/// and nothing else in its top byte — byte `k` of the multiplier has only bit `7 − k` set, so
/// the top byte collects exactly the terms `i + k = 7`, each at its own bit, without carries.
/// (Bit by bit, a variable shift and an index check per sample, this was 7 % of a location's
/// instructions.)
#[inline]
pub(crate) fn pack<T>(out: &mut [u64], items: &[T], set: impl Fn(&T) -> bool) {
    for (word, chunk) in out.iter_mut().zip(items.chunks(64)) {
        let mut bytes = [0u8; 64];
        for (b, x) in bytes.iter_mut().zip(chunk) {
            *b = u8::from(set(x));
        }
        *word = bytes
            .chunks_exact(8)
            .enumerate()
            .map(|(c, eight)| {
                let x = u64::from_le_bytes(eight.try_into().unwrap_or_default());
                (x.wrapping_mul(0x0102_0408_1020_4080) >> 56) << (8 * c)
            })
            .fold(0, |a, b| a | b);
    }
}

/// The OR and the AND of the bits at `j − 1`, `j`, `j + 1` round the circle (`n` samples,
/// the row `x`) for the 64 samples of word `w`.
#[inline]
fn spread(x: &[u64], n: usize, w: usize) -> (u64, u64) {
    let last = x.len() - 1;
    let top = (n - 1) % 64;
    // Sample j − 1 into bit j: the word shifted up, the previous word's top bit carried in
    // (round the circle: sample n − 1 into bit 0).
    let carry_in = if w == 0 {
        (x[last] >> top) & 1
    } else {
        x[w - 1] >> 63
    };
    let mut prev = (x[w] << 1) | carry_in;
    // Sample j + 1 into bit j: shifted down, the next word's bit 0 carried in (sample 0 into
    // bit n − 1).
    let mut next = (x[w] >> 1) | if w < last { x[w + 1] << 63 } else { 0 };
    if w == last {
        if n % 64 != 0 {
            prev &= (1u64 << (n % 64)) - 1;
        }
        next |= (x[0] & 1) << top;
    }
    (x[w] | prev | next, x[w] & prev & next)
}

/// The samples of word `w` of row `r` whose 3 × 3 neighbourhood (their circle and the ones
/// either side, round each circle) holds both sides; rows outside `0..rows` count as not
/// engaged. `sides` holds `rows` rows of `words(n)` words.
#[inline]
pub(crate) fn borders(sides: &[u64], rows: usize, n: usize, r: usize, w: usize) -> u64 {
    let nw = words(n);
    let (mut any, mut all) = (0u64, !0u64);
    for q in [r.wrapping_sub(1), r, r + 1] {
        if q >= rows {
            all = 0;
            continue;
        }
        let (o, a) = spread(&sides[q * nw..(q + 1) * nw], n, w);
        any |= o;
        all &= a;
    }
    any ^ all
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The neighbourhood test sample by sample, as written in the definition.
    fn borders_by_sample(sides: &[Vec<bool>], r: usize, j: usize) -> bool {
        let n = sides[0].len();
        let mut seen = [false; 2];
        for dr in [-1i64, 0, 1] {
            for dj in [n - 1, 0, 1] {
                let q = r as i64 + dr;
                let v = q >= 0 && (q as usize) < sides.len() && sides[q as usize][(j + dj) % n];
                seen[usize::from(v)] = true;
            }
        }
        seen[0] && seen[1]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(400))]
        /// Every sample's bit equals the definition, on circles of 1 to 200 samples (one word,
        /// several, a full last word) with random sides and runs.
        #[test]
        fn borders_are_the_neighbourhoods_with_both_sides(
            n in 1usize..200,
            rows in 1usize..6,
            seed in any::<u64>(),
            runs in any::<bool>(),
        ) {
            let mut state = seed | 1;
            let mut bit = || {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                state
            };
            let mut sides = vec![vec![false; n]; rows];
            for row in &mut sides {
                let mut v = bit() & 1 == 1;
                for s in row.iter_mut() {
                    // Runs: a side change now and then; else independent samples.
                    if !runs || bit() % 16 == 0 {
                        v = if runs { !v } else { bit() & 1 == 1 };
                    }
                    *s = v;
                }
            }
            let nw = words(n);
            let mut packed = vec![0u64; rows * nw];
            for (r, row) in sides.iter().enumerate() {
                pack(&mut packed[r * nw..(r + 1) * nw], row, |&b| b);
            }
            for r in 0..rows {
                for j in 0..n {
                    let got = borders(&packed, rows, n, r, j / 64) >> (j % 64) & 1 == 1;
                    prop_assert_eq!(got, borders_by_sample(&sides, r, j), "row {} sample {}", r, j);
                }
                // Nothing past the circle's samples.
                if n % 64 != 0 {
                    prop_assert_eq!(borders(&packed, rows, n, r, nw - 1) >> (n % 64), 0);
                }
            }
        }
    }

    /// The packing is the definition, bit by bit, on every length up to three words and
    /// random samples.
    #[test]
    fn packing_sets_exactly_the_samples_bits() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        for n in 1..=192 {
            for _ in 0..20 {
                let samples: Vec<bool> = (0..n)
                    .map(|_| {
                        state ^= state << 13;
                        state ^= state >> 7;
                        state ^= state << 17;
                        state & 1 == 1
                    })
                    .collect();
                let mut packed = vec![!0u64; words(n)];
                pack(&mut packed, &samples, |&b| b);
                for (w, &word) in packed.iter().enumerate() {
                    let want = (0..64)
                        .filter(|b| samples.get(w * 64 + b) == Some(&true))
                        .fold(0u64, |a, b| a | 1 << b);
                    assert_eq!(word, want, "n {n} word {w}");
                }
            }
        }
    }

    #[test]
    fn a_uniform_strip_has_borders_only_at_its_edge_rows() {
        // All engaged: the first and last rows border the rows outside, the middle none.
        let (n, rows) = (130, 3);
        let nw = words(n);
        let mut packed = vec![0u64; rows * nw];
        for r in 0..rows {
            pack(&mut packed[r * nw..(r + 1) * nw], &vec![(); n], |_| true);
        }
        let count = |r: usize| {
            (0..nw)
                .map(|w| borders(&packed, rows, n, r, w).count_ones())
                .sum::<u32>()
        };
        assert_eq!((count(0), count(1), count(2)), (130, 0, 130));
    }
}
