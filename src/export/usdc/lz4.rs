//! USD's general-purpose compression (`TfFastCompression`): LZ4 blocks behind a one-byte chunk
//! count. An input of at most [`MAX_CHUNK`] bytes is the byte 0 then one LZ4 block; a larger one is
//! the number of chunks, then per chunk its compressed size (`i32`) and its LZ4 block. The blocks
//! themselves come from `lz4_flex`, which writes the standard LZ4 block format that USD's
//! `LZ4_decompress_safe` reads.

use std::io;

/// `LZ4_MAX_INPUT_SIZE`: the most bytes one LZ4 block holds, hence one chunk.
pub const MAX_CHUNK: usize = 0x7E00_0000;

/// `input` compressed as USD reads it.
pub fn compress(input: &[u8]) -> io::Result<Vec<u8>> {
    compress_in_chunks(input, MAX_CHUNK)
}

/// [`compress`] with chunks of at most `chunk` bytes (separate so the chunked form can be tested
/// without gigabytes of input).
fn compress_in_chunks(input: &[u8], chunk: usize) -> io::Result<Vec<u8>> {
    if input.len() <= chunk {
        let mut out = vec![0u8];
        out.extend(lz4_flex::block::compress(input));
        return Ok(out);
    }
    let chunks = input.len().div_ceil(chunk);
    // USD reads the count as a signed byte.
    let count = i8::try_from(chunks)
        .map_err(|_| io::Error::other(format!("{} bytes are too many to compress", input.len())))?;
    let mut out = vec![count.to_le_bytes()[0]];
    for part in input.chunks(chunk) {
        let block = lz4_flex::block::compress(part);
        let size = i32::try_from(block.len()).map_err(io::Error::other)?;
        out.extend(size.to_le_bytes());
        out.extend(block);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_short_input_is_one_chunk_of_one_literal_run() {
        // LZ4 ends every block with at least five literals, so three bytes are a single sequence:
        // the token (3 literals, no match) and the bytes.
        assert_eq!(compress(b"abc").unwrap(), [0, 0x30, b'a', b'b', b'c']);
        // Fifteen literals and more take a length byte after the token: 15 + 2 = 17.
        let seventeen: Vec<u8> = (0..17).collect();
        let out = compress(&seventeen).unwrap();
        assert_eq!(out[..3], [0, 0xF0, 2]);
        assert_eq!(out[3..], seventeen[..]);
    }

    #[test]
    fn long_inputs_are_chunks_with_their_sizes() {
        let input: Vec<u8> = (0..1000u32).map(|i| (i * i % 251) as u8).collect();
        let out = compress_in_chunks(&input, 400).unwrap();
        assert_eq!(out[0], 3);
        let mut rest = &out[1..];
        let mut back = Vec::new();
        for expected in [400, 400, 200] {
            let size = i32::from_le_bytes(rest[..4].try_into().unwrap()) as usize;
            let part = lz4_flex::block::decompress(&rest[4..4 + size], expected).unwrap();
            assert_eq!(part.len(), expected);
            back.extend(part);
            rest = &rest[4 + size..];
        }
        assert!(rest.is_empty());
        assert_eq!(back, input);
    }

    #[test]
    fn repetitive_input_shrinks_and_decompresses() {
        let input = vec![7u8; 10_000];
        let out = compress(&input).unwrap();
        assert_eq!(out[0], 0);
        assert!(out.len() < 100, "{}", out.len());
        assert_eq!(
            lz4_flex::block::decompress(&out[1..], input.len()).unwrap(),
            input
        );
    }
}
