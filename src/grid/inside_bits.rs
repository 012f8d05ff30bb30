//! One bit per grid corner (set = inside), packed 64 corners of a row to a word: the whole
//! inside/outside picture of a 256³ grid fits in 2 MiB, empty cells are skipped 64 at a time, and
//! crossed edges are found and counted with xor and popcount.

use super::ScalarGrid;
use rayon::prelude::*;

pub(super) struct InsideBits {
    dims: [usize; 3],
    /// Words per row; one more bit than the row needs, so a row's last corner has a zero successor.
    words: usize,
    /// Word `w` of row `(j, k)` is `bits[(k * ny + j) * words + w]`.
    bits: Vec<u64>,
}

impl InsideBits {
    /// Inside (`value < iso`) bits of every corner. Corners on the grid's boundary are outside
    /// whatever their value, so the surface never leaves the grid and is always closed.
    pub(super) fn new(grid: &ScalarGrid, iso: f32) -> Self {
        let dims = grid.dims();
        let [nx, ny, _] = dims;
        let words = nx / 64 + 1;
        let nz = dims[2];
        let mut bits = vec![0u64; nz * ny * words];
        let values = grid.values();
        if words * ny > 0 {
            bits.par_chunks_mut(words * ny)
                .enumerate()
                .for_each(|(k, plane)| {
                    if k == 0 || k + 1 >= nz {
                        return;
                    }
                    for j in 1..ny.saturating_sub(1) {
                        let start = nx * (j + ny * k);
                        let row = &mut plane[j * words..(j + 1) * words];
                        pack_row(&values[start..start + nx], iso, row);
                        row[0] &= !1;
                        row[(nx - 1) / 64] &= !(1 << ((nx - 1) % 64));
                    }
                });
        }
        Self { dims, words, bits }
    }

    pub(super) fn words(&self) -> usize {
        self.words
    }

    /// Position of row `(j, k)`'s first word; arrays with one entry per word share this layout.
    #[inline]
    pub(super) fn row_start(&self, j: usize, k: usize) -> usize {
        (k * self.dims[1] + j) * self.words
    }

    /// Row `(j, k)` of inside bits.
    #[inline]
    pub(super) fn row(&self, j: usize, k: usize) -> &[u64] {
        let start = self.row_start(j, k);
        &self.bits[start..start + self.words]
    }
}

/// Packs `value < iso` for up to 64 values per word; NaN counts as outside.
fn pack_row(values: &[f32], iso: f32, out: &mut [u64]) {
    for (word, chunk) in out.iter_mut().zip(values.chunks(64)) {
        let mut w = 0u64;
        for (i, &v) in chunk.iter().enumerate() {
            w |= u64::from(v < iso) << i;
        }
        *word = w;
    }
}

/// Word `w` of a row's x-edge crossings: bit `i` set when corners `i` and `i + 1` differ.
#[inline]
pub(super) fn x_crossings(row: &[u64], w: usize) -> u64 {
    let next = row.get(w + 1).copied().unwrap_or(0);
    row[w] ^ ((row[w] >> 1) | (next << 63))
}

/// Bits `i` and `i + 1` of a row as the two low bits.
#[inline]
pub(super) fn bit_pair(row: &[u64], i: usize) -> u8 {
    let (w, b) = (i / 64, i % 64);
    let low = row[w] >> b;
    let high = if b == 63 {
        row.get(w + 1).copied().unwrap_or(0) << 1
    } else {
        0
    };
    ((low | high) & 3) as u8
}

/// Bit `i` of a row.
#[inline]
pub(super) fn bit(row: &[u64], i: usize) -> bool {
    row[i / 64] >> (i % 64) & 1 != 0
}
