//! USD's integer compression (`Usd_IntegerCompression`), used for the structural sections and int
//! arrays: each integer becomes its difference to the previous one (the first to 0); the most
//! common difference is written once (an `i32`; ties go to the largest), then a 2-bit code per
//! integer (four to a byte, lowest bits first: 0 the common difference, 1 an `i8`, 2 an `i16`,
//! 3 an `i32` follows), then the differences that are not the common one, in those widths. The
//! encoding is then compressed with [`super::lz4::compress`].

use super::lz4;
use rustc_hash::FxHashMap;
use std::io;

/// `values` encoded and compressed, as USD reads them (with the count stored elsewhere).
pub fn compress(values: &[i32]) -> io::Result<Vec<u8>> {
    lz4::compress(&encode(values))
}

/// The integer encoding of `values` (empty for none).
pub fn encode(values: &[i32]) -> Vec<u8> {
    if values.is_empty() {
        return Vec::new();
    }
    let deltas: Vec<i32> = std::iter::once(values[0])
        .chain(values.windows(2).map(|w| w[1].wrapping_sub(w[0])))
        .collect();
    let mut counts: FxHashMap<i32, usize> = FxHashMap::default();
    for &d in &deltas {
        *counts.entry(d).or_default() += 1;
    }
    let common = counts
        .into_iter()
        .max_by_key(|&(d, n)| (n, d))
        .map_or(0, |(d, _)| d);
    let mut out = common.to_le_bytes().to_vec();
    let codes_at = out.len();
    out.resize(codes_at + (deltas.len() * 2).div_ceil(8), 0);
    for (i, &d) in deltas.iter().enumerate() {
        let code: u8 = if d == common {
            0
        } else if let Ok(small) = i8::try_from(d) {
            out.extend(small.to_le_bytes());
            1
        } else if let Ok(medium) = i16::try_from(d) {
            out.extend(medium.to_le_bytes());
            2
        } else {
            out.extend(d.to_le_bytes());
            3
        };
        out[codes_at + i / 4] |= code << (2 * (i % 4));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_example_of_usds_integer_coding_gives_its_twelve_bytes() {
        // Differences [123, 1, 1, 100000, 0, 1, 0]; 1 is the most common.
        let encoded = encode(&[123, 124, 125, 100125, 100125, 100126, 100126]);
        assert_eq!(
            encoded,
            [
                1,
                0,
                0,
                0,             // the common difference
                0b11_00_00_01, // i8, common, common, i32
                0b00_01_00_01, // i8, common, i8 (and an unused pair)
                123,           // i8
                0xA0,
                0x86,
                0x01,
                0x00, // 100000 as i32
                0,
                0 // two i8 zeros
            ]
        );
    }

    #[test]
    fn ties_take_the_largest_difference_and_widths_follow_the_value() {
        // Differences [0, 300, -600], each once: 300 is common, 0 an i8, -600 an i16.
        assert_eq!(
            encode(&[0, 300, -300]),
            [0x2C, 0x01, 0, 0, 0b10_00_01, 0, 0xA8, 0xFD]
        );
        // A run of equal values: the common difference is 0, the first value an i32.
        assert_eq!(
            encode(&[-100000; 5]),
            [0, 0, 0, 0, 0b11, 0, 0x60, 0x79, 0xFE, 0xFF]
        );
        assert!(encode(&[]).is_empty());
    }

    #[test]
    fn extreme_differences_wrap_as_in_usd() {
        // i32::MIN - i32::MAX wraps to 1 (USD subtracts in 32-bit two's complement); both
        // differences occur once, so the larger, i32::MAX, is the common one.
        assert_eq!(
            encode(&[i32::MAX, i32::MIN]),
            [0xFF, 0xFF, 0xFF, 0x7F, 0b01_00, 1]
        );
    }
}
