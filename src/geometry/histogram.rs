//! The buckets every report sorts triangles into by their smallest angle, so the improvement
//! report and the evaluation report read alike.

/// Upper ends of the minimum-angle buckets in degrees (the paper's improvement threshold is 10°);
/// the last bucket (≥ 50°) is open.
pub const ANGLE_BUCKETS: [f32; 9] = [2.0, 4.0, 6.0, 8.0, 10.0, 20.0, 30.0, 40.0, 50.0];

/// The bucket of `x` among buckets with upper ends `edges` (ascending): the number of ends at or
/// below `x`, so the last bucket, past every end, is `edges.len()`.
pub fn bucket(edges: &[f32], x: f32) -> usize {
    edges.iter().take_while(|&&e| x >= e).count()
}
