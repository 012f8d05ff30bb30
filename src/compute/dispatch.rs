use super::ComputeError;

/// Workgroup counts `[x, y, 1]` that cover `items` invocations of `workgroup_size` threads without
/// exceeding `max_per_dimension` in any dimension.
///
/// A 1-D grid tops out at `max_per_dimension × workgroup_size` items (65 535 × 64 ≈ 4.2 M on most
/// GPUs, fewer than the triangles of a large fluid frame), so larger arrays wrap into a second
/// dimension. Kernels flatten the grid back with `(wg.y * groups.x + wg.x) * size + lane` and skip
/// the few invocations past the end; the total invocation count must fit that `u32` index.
pub fn workgroup_grid(
    items: u64,
    workgroup_size: u32,
    max_per_dimension: u32,
) -> Result<[u32; 3], ComputeError> {
    let too_large = ComputeError::DispatchTooLarge { items };
    if workgroup_size == 0 || max_per_dimension == 0 {
        return Err(too_large);
    }
    let size = u64::from(workgroup_size);
    let max = u64::from(max_per_dimension);
    let groups = items.div_ceil(size);
    let rows = groups.div_ceil(max).max(1);
    let columns = groups.div_ceil(rows);
    if rows > max || columns * rows * size > u64::from(u32::MAX) + 1 {
        return Err(too_large);
    }
    let x = u32::try_from(columns).map_err(|_| too_large.clone())?;
    let y = u32::try_from(rows).map_err(|_| too_large)?;
    Ok([x, y, 1])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn covered(grid: [u32; 3], workgroup_size: u32) -> u64 {
        grid.iter().map(|&g| u64::from(g)).product::<u64>() * u64::from(workgroup_size)
    }

    #[test]
    fn small_arrays_use_one_dimension() {
        assert_eq!(workgroup_grid(0, 64, 65_535), Ok([0, 1, 1]));
        assert_eq!(workgroup_grid(1, 64, 65_535), Ok([1, 1, 1]));
        assert_eq!(workgroup_grid(64, 64, 65_535), Ok([1, 1, 1]));
        assert_eq!(workgroup_grid(65, 64, 65_535), Ok([2, 1, 1]));
        assert_eq!(workgroup_grid(65_535 * 64, 64, 65_535), Ok([65_535, 1, 1]));
    }

    #[test]
    fn large_arrays_wrap_into_rows_within_the_limit() {
        for items in [65_535 * 64 + 1, 10_000_000, 123_456_789, 3_000_000_000] {
            let grid = workgroup_grid(items, 64, 65_535).unwrap();
            assert!(grid[0] <= 65_535 && grid[1] <= 65_535, "{grid:?}");
            let covered = covered(grid, 64);
            assert!(covered >= items, "{items} items, grid {grid:?}");
            assert!(
                covered - items < u64::from(grid[1]) * 64,
                "too much slack: {grid:?}"
            );
            assert!(
                covered <= 1 << 32,
                "flattened index overflows u32: {grid:?}"
            );
        }
        assert_eq!(workgroup_grid(9, 1, 4), Ok([3, 3, 1]));
        assert_eq!(workgroup_grid(16, 1, 4), Ok([4, 4, 1]));
    }

    #[test]
    fn impossible_grids_are_errors() {
        assert_eq!(
            workgroup_grid((1 << 32) + 1, 64, 65_535),
            Err(ComputeError::DispatchTooLarge {
                items: (1 << 32) + 1
            })
        );
        assert!(workgroup_grid(17, 1, 4).is_err());
        assert!(workgroup_grid(10, 0, 4).is_err());
    }
}
