//! How a crate file refers to a value (`ValueRep`): 64 bits, the top three flags (array, inlined,
//! compressed), the value type in bits 48..56 and a 48-bit payload, which is the value itself when
//! inlined (4 bytes at most: a token index, an int, a float, an enum) and otherwise the file offset
//! where the value is written.

/// The value types this layer writes, numbered as in USD's `crateDataTypes.h`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CrateType {
    Int = 3,
    Float = 8,
    Double = 9,
    Token = 11,
    Vec2f = 20,
    Vec3f = 24,
    Vec4f = 28,
    TokenVector = 41,
    Specifier = 42,
    Variability = 44,
    TimeSamples = 46,
    DoubleVector = 48,
}

impl CrateType {
    /// The element type of an array of `tuple` floats per element.
    pub fn floats(tuple: usize) -> Self {
        match tuple {
            1 => Self::Float,
            2 => Self::Vec2f,
            4 => Self::Vec4f,
            _ => Self::Vec3f,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ValueRep(pub u64);

const ARRAY: u64 = 1 << 63;
const INLINED: u64 = 1 << 62;
const COMPRESSED: u64 = 1 << 61;
const PAYLOAD: u64 = (1 << 48) - 1;

impl ValueRep {
    /// A value held in the rep itself.
    pub fn inlined(kind: CrateType, payload: u32) -> Self {
        Self(INLINED | ((kind as u64) << 48) | u64::from(payload))
    }

    /// A value written at file offset `at`.
    pub fn at(kind: CrateType, at: u64) -> Self {
        Self(((kind as u64) << 48) | (at & PAYLOAD))
    }

    /// An array of `kind` written at `at`; offset 0 is the empty array.
    pub fn array(kind: CrateType, at: u64) -> Self {
        Self(ARRAY | Self::at(kind, at).0)
    }

    /// The same array, written compressed.
    pub fn compressed(self) -> Self {
        Self(self.0 | COMPRESSED)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flags_type_and_payload_take_their_bits() {
        assert_eq!(
            ValueRep::inlined(CrateType::Token, 5).0,
            0x400B_0000_0000_0005
        );
        assert_eq!(
            ValueRep::array(CrateType::Int, 0x1234).compressed().0,
            0xA003_0000_0000_1234
        );
        assert_eq!(
            ValueRep::at(CrateType::TimeSamples, 88).0,
            0x002E_0000_0000_0058
        );
    }
}
