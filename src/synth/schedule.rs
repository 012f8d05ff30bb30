//! Time within a sequence, kept clear of topology transitions, and the per-frame grid jitter.

/// Time of frame `index` of `frames`: 0 for the first, 1 for the last.
pub(super) fn frame_time(index: usize, frames: usize) -> f64 {
    if frames <= 1 {
        0.0
    } else {
        index as f64 / (frames - 1) as f64
    }
}

/// A parameter that moves linearly from `start` (time 0) to `end` (time 1) through a topology
/// transition at `critical`, remapped so no frame lands within the band between `before` (the last
/// value allowed on `start`'s side) and `after` (the first allowed on `end`'s side).
///
/// Frames keep the side of the transition they had under the linear motion; each side is squeezed
/// affinely into its allowed range. The band is where a grid of the frame's spacing cannot be
/// trusted to resolve the field's topology (a neck thinner than a cell, a gap narrower than one),
/// so excluding it lets the manifest state the expected topology of every frame from the
/// analytic field alone.
pub(super) fn clear_of_transition(
    time: f64,
    start: f64,
    end: f64,
    critical: f64,
    before: f64,
    after: f64,
) -> f64 {
    let linear = start + time * (end - start);
    let on_start_side = (linear - critical) * (start - critical) > 0.0;
    if on_start_side {
        start + (linear - start) * (before - start) / (critical - start)
    } else {
        end + (linear - end) * (after - end) / (critical - end)
    }
}

/// The grid offset of frame `index`, as fractions of a cell in `[0, 1)³`, from a hash of the frame
/// number: consecutive frames sample the field at different points, so their triangulations never
/// coincide, as with independently meshed simulation frames.
pub(super) fn jitter(index: usize) -> [f32; 3] {
    let mut state = (index as u64).wrapping_mul(0x2545_F491_4F6C_DD1D) ^ 0x5EED_0F5E_ED0F_5EED;
    std::array::from_fn(|_| {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 40) as f32 / (1u64 << 24) as f32
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transition_band_is_never_landed_in_and_ends_are_kept() {
        for frames in 2..40 {
            for (start, end, critical, before, after) in
                [(1.4, 0.4, 0.9, 1.0, 0.8), (-0.6, 0.6, 0.0, -0.1, 0.1)]
            {
                let values: Vec<f64> = (0..frames)
                    .map(|i| {
                        let t = frame_time(i, frames);
                        clear_of_transition(t, start, end, critical, before, after)
                    })
                    .collect();
                assert!((values[0] - start).abs() < 1e-12);
                assert!((values[frames - 1] - end).abs() < 1e-12);
                let lo = f64::min(before, after);
                let hi = f64::max(before, after);
                for v in &values {
                    assert!(*v <= lo + 1e-12 || *v >= hi - 1e-12, "{v} in the band");
                }
                let monotone = values
                    .windows(2)
                    .all(|w| (w[1] - w[0]) * (end - start) > 0.0);
                assert!(monotone, "motion keeps its direction");
            }
        }
    }

    #[test]
    fn jitter_is_a_fraction_of_a_cell_and_differs_between_frames() {
        let mut previous = jitter(0);
        for index in 1..1000 {
            let j = jitter(index);
            assert!(j.iter().all(|v| (0.0..1.0).contains(v)));
            assert_ne!(j, previous);
            previous = j;
        }
        assert_eq!(jitter(17), jitter(17));
    }
}
