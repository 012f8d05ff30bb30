use super::ImproveError;

/// Mesh-improvement parameters (paper §4.1). Every length is relative to `edge_length`, so the same
/// parameters suit a mesh at any scale.
#[derive(Debug, Clone, PartialEq)]
pub struct ImproveParams {
    /// Target edge length `L` in world units: the first frame's mean edge length unless the user gives
    /// one. It is fixed for a whole sequence, so improving an improved mesh changes nothing.
    pub edge_length: f32,
    /// Triangles with a smaller interior angle are fixed (paper: 10°).
    pub min_angle_degrees: f32,
    /// Edges whose two faces meet at a smaller dihedral angle are fixed (paper: 45°); 180° is flat.
    pub min_dihedral_degrees: f32,
    /// Longest : shortest allowed edge (paper: 4). The allowed band is `[L/√r, L·√r]` — for r = 4,
    /// `[L/2, 2L]` — symmetric about `L` on a log scale, so a mesh whose edges scatter evenly about `L`
    /// is mostly left alone, and the halves of a split edge (≥ L·√r / 2 = L) never fall below the
    /// collapse threshold, which rules out split/collapse ping-pong for any r ≥ 2.
    pub edge_ratio: f32,
    /// Largest distance, relative to `L`, that one collapse or flip may move the surface away from
    /// where it was just before the operation. The bound is per operation, and so a function of the
    /// mesh alone, which keeps improvement idempotent; operations that touch the same spot add up,
    /// and on the synthetic scenes the total (one-sided Hausdorff, improved → input) stays below
    /// about twice this value.
    pub max_deviation: f32,
    /// Vertices whose id is below this may be moved along the surface instead of removed (see
    /// `relax`), and a collapse or merge keeps such an end (the older one), moved to the midpoint
    /// or to the other end, instead of removing it; 0: none. The tracker sets it each frame to the
    /// first id the frame creates, so the vertices carried over from the previous frame keep their
    /// ids wherever a move fixes their elements, while the frame's new vertices (the input's
    /// triangles copied in, topology patches, the first frame itself) are thinned to the target
    /// length as before: moving those instead would keep a copied region as dense as the input.
    pub relax_below: u64,
    /// Upper bound on the improvement rounds (each: split long edges, then fix short edges, small
    /// angles and sharp dihedrals until nothing more can be fixed).
    pub max_rounds: usize,
}

impl ImproveParams {
    /// The paper's parameters around target edge length `edge_length`.
    pub fn new(edge_length: f32) -> Self {
        Self {
            edge_length,
            min_angle_degrees: 10.0,
            min_dihedral_degrees: 45.0,
            edge_ratio: 4.0,
            max_deviation: 0.0225,
            relax_below: 0,
            max_rounds: 8,
        }
    }

    /// Edges longer than this are split.
    pub fn max_edge_length(&self) -> f32 {
        self.edge_length * self.edge_ratio.sqrt()
    }

    /// Edges shorter than this are collapsed.
    pub fn min_edge_length(&self) -> f32 {
        self.edge_length / self.edge_ratio.sqrt()
    }

    pub(super) fn check(&self) -> Result<(), ImproveError> {
        let fail = |name, expected, value| {
            Err(ImproveError::Parameter {
                name,
                expected,
                value,
            })
        };
        let positive = "finite and positive";
        if !(self.edge_length.is_finite() && self.edge_length > 0.0) {
            return fail("edge_length", positive, self.edge_length);
        }
        if !(self.min_angle_degrees >= 0.0 && self.min_angle_degrees < 60.0) {
            return fail("min_angle_degrees", "in [0, 60)", self.min_angle_degrees);
        }
        if !(self.min_dihedral_degrees >= 0.0 && self.min_dihedral_degrees < 180.0) {
            return fail(
                "min_dihedral_degrees",
                "in [0, 180)",
                self.min_dihedral_degrees,
            );
        }
        if !(self.edge_ratio.is_finite() && self.edge_ratio >= 2.0) {
            return fail("edge_ratio", "finite and at least 2", self.edge_ratio);
        }
        if !(self.max_deviation.is_finite() && self.max_deviation >= 0.0) {
            return fail(
                "max_deviation",
                "finite and non-negative",
                self.max_deviation,
            );
        }
        Ok(())
    }
}

/// The parameters in world units, as the checks use them.
#[derive(Debug, Clone, Copy)]
pub(super) struct Limits {
    pub target: f32,
    pub min_edge: f32,
    pub max_edge: f32,
    pub min_angle: f32,
    pub min_dihedral: f32,
    pub cos_min_dihedral: f32,
    pub edge_ratio: f32,
    pub deviation: f32,
    pub relax_below: u64,
    /// Cosines of the angle and dihedral limits widened by `FILTER_MARGIN_DEGREES`, for the
    /// trigonometry-free filters that run before an angle is measured.
    pub cos_angle_filter: f32,
    pub cos_dihedral_filter: f32,
}

/// The cheap filters let through everything within this many degrees of a limit, so rounding in
/// them never hides an element that the exact measure finds bad.
const FILTER_MARGIN_DEGREES: f32 = 0.01;

impl Limits {
    pub fn new(params: &ImproveParams) -> Self {
        Self {
            target: params.edge_length,
            min_edge: params.min_edge_length(),
            max_edge: params.max_edge_length(),
            min_angle: params.min_angle_degrees,
            min_dihedral: params.min_dihedral_degrees,
            cos_min_dihedral: params.min_dihedral_degrees.to_radians().cos(),
            edge_ratio: params.edge_ratio,
            deviation: params.max_deviation * params.edge_length,
            relax_below: params.relax_below,
            cos_angle_filter: (params.min_angle_degrees + FILTER_MARGIN_DEGREES)
                .min(90.0)
                .to_radians()
                .cos(),
            cos_dihedral_filter: (params.min_dihedral_degrees + FILTER_MARGIN_DEGREES)
                .min(180.0)
                .to_radians()
                .cos(),
        }
    }
}
