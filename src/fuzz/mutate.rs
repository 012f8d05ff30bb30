//! The mutations every harness draws from: truncation, bit flips, splices, inserted bytes, and
//! the values that break readers (huge counts, non-finite and overflowing numbers), for text and
//! for binary data.

use super::rng::Rng;

/// Words that replace a token of a text file: numbers at and past every type's limits,
/// non-finite values, malformed numbers and keywords out of place.
pub const GARBAGE_TOKENS: &[&str] = &[
    "nan",
    "NaN",
    "inf",
    "-inf",
    "+inf",
    "infinity",
    "1e30",
    "-1e30",
    "3.5e38",
    "1e400",
    "-1e400",
    "1e-45",
    "0",
    "-0",
    "-1",
    "1",
    "2",
    "255",
    "256",
    "65536",
    "2147483647",
    "2147483648",
    "-2147483648",
    "4294967295",
    "4294967296",
    "9223372036854775807",
    "18446744073709551615",
    "18446744073709551616",
    "99999999999999999999999999",
    "0x1F",
    "1.5.2",
    "-",
    "+",
    "e5",
    "1e",
    "1/2/3",
    "1//1",
    "/1",
    "//",
    "f",
    "v",
    "vt",
    "element",
    "property",
    "list",
    "end_header",
    "uchar",
    "double",
    "int",
    "face",
    "vertex",
    "ascii",
    "\u{fffd}",
    "#",
];

/// Element counts that claim far more than any small file holds.
pub const HUGE_COUNTS: &[&str] = &[
    "0",
    "1",
    "2147483648",
    "4294967295",
    "4294967296",
    "18446744073709551615",
    "-1",
    "99999999999999999999",
];

/// 32-bit words at and past the limits of counts and indices.
pub const GARBAGE_U32: &[u32] = &[
    0,
    1,
    2,
    3,
    0x7F,
    0x80,
    0xFF,
    0xFFFF,
    1 << 24,
    0x7FFF_FFFF,
    0x8000_0000,
    0xFFFF_FFFE,
    0xFFFF_FFFF,
];

/// Floats that no coordinate should be: non-finite, huge, subnormal, signed zero.
pub const GARBAGE_F32: &[f32] = &[
    f32::NAN,
    f32::INFINITY,
    f32::NEG_INFINITY,
    1e30,
    -1e30,
    f32::MAX,
    -f32::MAX,
    1e-45,
    -0.0,
];

/// Cuts `bytes` at a random length (possibly 0).
pub fn truncate(rng: &mut Rng, bytes: &mut Vec<u8>) {
    let at = rng.below(bytes.len() + 1);
    bytes.truncate(at);
}

/// Flips one to four random bits.
pub fn flip(rng: &mut Rng, bytes: &mut [u8]) {
    if bytes.is_empty() {
        return;
    }
    for _ in 0..1 + rng.below(4) {
        let at = rng.below(bytes.len());
        bytes[at] ^= 1 << rng.below(8);
    }
}

/// Replaces a random range of `bytes` with a random range of `donor`.
pub fn splice(rng: &mut Rng, bytes: &mut Vec<u8>, donor: &[u8]) {
    let start = rng.below(bytes.len() + 1);
    let end = (start + rng.below(64)).min(bytes.len());
    let from = rng.below(donor.len() + 1);
    let to = (from + rng.below(256)).min(donor.len());
    bytes.splice(start..end, donor[from..to].iter().copied());
}

/// Inserts up to 16 random bytes (NUL, CR and invalid UTF-8 among them) at a random place.
pub fn insert(rng: &mut Rng, bytes: &mut Vec<u8>) {
    let at = rng.below(bytes.len() + 1);
    let len = 1 + rng.below(16);
    let junk: Vec<u8> = (0..len)
        .map(|_| *rng.pick(&[0u8, b'\r', b'\n', b' ', 0xFF, 0xC3, b'-', b'9', b'.', b'e']))
        .collect();
    bytes.splice(at..at, junk);
}

/// Repeats a random range of `bytes` up to 64 times in place.
pub fn repeat(rng: &mut Rng, bytes: &mut Vec<u8>) {
    let start = rng.below(bytes.len() + 1);
    let end = (start + 1 + rng.below(128)).min(bytes.len());
    let chunk = bytes[start..end].to_vec();
    for _ in 0..rng.below(64) {
        bytes.splice(end..end, chunk.iter().copied());
    }
}

/// Writes a garbage word (1, 2, 4 or 8 bytes, or a garbage float) at a random offset, in either
/// byte order.
pub fn overwrite_word(rng: &mut Rng, bytes: &mut [u8]) {
    if bytes.is_empty() {
        return;
    }
    let at = rng.below(bytes.len());
    let word = garbage_word(rng);
    let width = *rng.pick(&[1usize, 2, 4, 4, 4, 8]);
    let mut value = if rng.chance(50) {
        word.to_le_bytes().to_vec()
    } else {
        word.to_be_bytes().to_vec()
    };
    value.truncate(width);
    put(bytes, at, &value);
}

/// A garbage u32 or the bits of a garbage f32, widened.
pub fn garbage_word(rng: &mut Rng) -> u64 {
    if rng.chance(50) {
        u64::from(*rng.pick(GARBAGE_U32))
    } else {
        u64::from(rng.pick(GARBAGE_F32).to_bits())
    }
}

/// Copies `value` over `bytes` from `at`, as far as `bytes` reaches.
pub fn put(bytes: &mut [u8], at: usize, value: &[u8]) {
    for (slot, &b) in bytes.iter_mut().skip(at).zip(value) {
        *slot = b;
    }
}

/// One of the byte-level mutations above.
pub fn bytes_any(rng: &mut Rng, bytes: &mut Vec<u8>, donor: &[u8]) {
    match rng.below(6) {
        0 => truncate(rng, bytes),
        1 => flip(rng, bytes),
        2 => splice(rng, bytes, donor),
        3 => insert(rng, bytes),
        4 => repeat(rng, bytes),
        _ => overwrite_word(rng, bytes),
    }
}

/// The byte ranges of the whitespace-separated tokens of `bytes`.
fn tokens(bytes: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, b) in bytes.iter().enumerate() {
        match (b.is_ascii_whitespace(), start) {
            (true, Some(s)) => {
                out.push((s, i));
                start = None;
            }
            (false, None) => start = Some(i),
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push((s, bytes.len()));
    }
    out
}

/// Replaces a random token of a text with `word`.
pub fn replace_token(rng: &mut Rng, bytes: &mut Vec<u8>, word: &str) {
    let tokens = tokens(bytes);
    if tokens.is_empty() {
        return;
    }
    let (start, end) = *rng.pick(&tokens);
    bytes.splice(start..end, word.bytes());
}

/// The byte ranges of the lines of `bytes`, each with its newline.
fn lines(bytes: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = 0;
    for (i, &b) in bytes.iter().enumerate() {
        if b == b'\n' {
            out.push((start, i + 1));
            start = i + 1;
        }
    }
    if start < bytes.len() {
        out.push((start, bytes.len()));
    }
    out
}

/// Deletes, repeats (up to 50 times) or moves a random line.
pub fn line_edit(rng: &mut Rng, bytes: &mut Vec<u8>) {
    let lines = lines(bytes);
    if lines.is_empty() {
        return;
    }
    let (start, end) = *rng.pick(&lines);
    let line = bytes[start..end].to_vec();
    match rng.below(3) {
        0 => {
            bytes.drain(start..end);
        }
        1 => {
            for _ in 0..1 + rng.below(50) {
                bytes.splice(end..end, line.iter().copied());
            }
        }
        _ => {
            bytes.drain(start..end);
            let (to, _) = *rng.pick(&lines);
            let to = to.min(bytes.len());
            bytes.splice(to..to, line);
        }
    }
}

/// One text mutation: a garbage token, a line edit, or a byte-level mutation.
pub fn text_any(rng: &mut Rng, bytes: &mut Vec<u8>, donor: &[u8]) {
    match rng.below(4) {
        0 | 1 => {
            let word = *rng.pick(GARBAGE_TOKENS);
            replace_token(rng, bytes, word);
        }
        2 => line_edit(rng, bytes),
        _ => bytes_any(rng, bytes, donor),
    }
}

/// Replaces the count of a random `element NAME COUNT` line of a PLY header with a huge count.
pub fn ply_element_count(rng: &mut Rng, bytes: &mut Vec<u8>) {
    let header_end = find(bytes, b"end_header").unwrap_or(bytes.len());
    let elements: Vec<(usize, usize)> = lines(&bytes[..header_end])
        .into_iter()
        .filter(|&(s, _)| bytes[s..].starts_with(b"element "))
        .collect();
    if elements.is_empty() {
        return;
    }
    let (start, end) = *rng.pick(&elements);
    let text = String::from_utf8_lossy(&bytes[start..end]).into_owned();
    let mut words: Vec<&str> = text.split_ascii_whitespace().collect();
    if let Some(last) = words.last_mut() {
        *last = *rng.pick(HUGE_COUNTS);
    }
    let line = format!("{}\n", words.join(" "));
    bytes.splice(start..end, line.bytes());
}

/// The first position of `needle` in `bytes`.
pub fn find(bytes: &[u8], needle: &[u8]) -> Option<usize> {
    bytes.windows(needle.len()).position(|w| w == needle)
}
