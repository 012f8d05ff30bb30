//! A box of grid cells numbered x fastest: the dense index of the lookups that mark or bucket
//! cells lying close together (a frame's surface, one re-sampling's points), where a hash map
//! of the same cells costs a hash lookup per question.

use glam::{I64Vec3, IVec3};

/// The cells from `low` to `low + size - 1` along each axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct CellBox {
    low: IVec3,
    size: IVec3,
}

impl CellBox {
    /// The box from `low` to `high` (both included) where it holds at least one cell and at
    /// most `most`; `None` otherwise (a caller then indexes its cells sparsely).
    pub fn spanning(low: IVec3, high: IVec3, most: usize) -> Option<Self> {
        let size = high.as_i64vec3() - low.as_i64vec3() + 1;
        if size.cmple(I64Vec3::ZERO).any() {
            return None;
        }
        let volume = size.x.saturating_mul(size.y).saturating_mul(size.z);
        usize::try_from(volume)
            .is_ok_and(|v| v <= most)
            .then(|| Self {
                low,
                size: size.as_ivec3(),
            })
    }

    pub fn low(&self) -> IVec3 {
        self.low
    }

    pub fn high(&self) -> IVec3 {
        self.low + self.size - 1
    }

    /// How many cells the box holds.
    pub fn volume(&self) -> usize {
        self.size.x as usize * self.size.y as usize * self.size.z as usize
    }

    /// The number of `cell`, x fastest; `None` outside the box.
    pub fn index(&self, cell: IVec3) -> Option<usize> {
        let local = cell.as_i64vec3() - self.low.as_i64vec3();
        if local.cmplt(I64Vec3::ZERO).any() || local.cmpge(self.size.as_i64vec3()).any() {
            return None;
        }
        let (x, y, z) = (local.x as usize, local.y as usize, local.z as usize);
        Some(x + self.size.x as usize * (y + self.size.y as usize * z))
    }

    /// The cell numbered `index` ([`CellBox::index`]'s inverse).
    pub fn cell(&self, index: usize) -> IVec3 {
        let (sx, sy) = (self.size.x as usize, self.size.y as usize);
        let (x, rest) = (index % sx, index / sx);
        let (y, z) = (rest % sy, rest / sy);
        self.low + IVec3::new(x as i32, y as i32, z as i32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_number_x_fastest_and_back() {
        let b = CellBox::spanning(IVec3::new(-2, 3, -1), IVec3::new(1, 4, 1), 24).unwrap();
        assert_eq!(b.volume(), 24);
        assert_eq!(b.high(), IVec3::new(1, 4, 1));
        assert_eq!(b.index(IVec3::new(-2, 3, -1)), Some(0));
        assert_eq!(b.index(IVec3::new(-1, 3, -1)), Some(1));
        assert_eq!(b.index(IVec3::new(-2, 4, -1)), Some(4));
        assert_eq!(b.index(IVec3::new(-2, 3, 0)), Some(8));
        assert_eq!(b.index(IVec3::new(2, 3, 0)), None);
        assert_eq!(b.index(IVec3::new(0, 3, i32::MIN)), None);
        for i in 0..b.volume() {
            assert_eq!(b.index(b.cell(i)), Some(i));
        }
        assert_eq!(CellBox::spanning(IVec3::ZERO, IVec3::splat(2), 26), None);
        assert_eq!(CellBox::spanning(IVec3::MAX, IVec3::MIN, usize::MAX), None);
    }
}
