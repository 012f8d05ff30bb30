use glam::Vec3;

/// What became of one query.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Status {
    /// No target surface within the maximum distance (or the query point or normal was not
    /// usable: non-finite, or a zero normal).
    Miss,
    /// The nearest surface point is a valid correspondence.
    Accepted,
    /// The nearest hit's interpolated normal is further from the source normal than the maximum
    /// angle (paper §4.2 prunes beyond 60°); the hit is still reported.
    NormalMismatch,
}

impl Status {
    /// The code kernels write (`STATUS_*` in `kernels/shared/bvh.wgsl`).
    pub const fn code(self) -> u32 {
        match self {
            Self::Miss => 0,
            Self::Accepted => 1,
            Self::NormalMismatch => 2,
        }
    }

    /// Reads a kernel's code; codes no kernel writes read as [`Status::Miss`].
    pub const fn from_code(code: u32) -> Self {
        match code {
            1 => Self::Accepted,
            2 => Self::NormalMismatch,
            _ => Self::Miss,
        }
    }
}

gpu_struct! {
    mirrors BVH;
    /// The target point found for one query: by a normal ray ([`super::project`]) or as the nearest
    /// surface point ([`super::closest_points`]).
    ///
    /// Mirrors `struct Correspondence` in `kernels/shared/bvh.wgsl`. For a miss every field but
    /// `status` is 0 and `triangle` is [`Correspondence::NO_TRIANGLE`].
    pub struct Correspondence {
        /// The point on the target.
        pub point: Vec3,
        /// Signed distance to `point`: the ray parameter `t` of `p + t·n` for a projection (n unit),
        /// and for a closest point `|p − point|`, negative when `p` is inside the target.
        pub distance: f32,
        /// The target's vertex normals interpolated at `point` (unit).
        pub normal: Vec3,
        /// Index of the hit triangle in the target mesh.
        pub triangle: u32,
        /// Weights of the triangle's three corners (in the target's order) at `point`; they sum to 1.
        pub barycentric: Vec3,
        status: u32,
    }
}

impl Correspondence {
    /// `triangle` of a miss.
    pub const NO_TRIANGLE: u32 = u32::MAX;

    /// A query that found nothing.
    pub const MISS: Correspondence = Correspondence {
        point: Vec3::ZERO,
        distance: 0.0,
        normal: Vec3::ZERO,
        triangle: Self::NO_TRIANGLE,
        barycentric: Vec3::ZERO,
        status: 0,
    };

    pub fn new(
        point: Vec3,
        distance: f32,
        normal: Vec3,
        triangle: u32,
        barycentric: Vec3,
        status: Status,
    ) -> Self {
        Self {
            point,
            distance,
            normal,
            triangle,
            barycentric,
            status: status.code(),
        }
    }

    pub fn status(&self) -> Status {
        Status::from_code(self.status)
    }

    /// True for a correspondence that survived pruning.
    pub fn is_accepted(&self) -> bool {
        self.status() == Status::Accepted
    }

    /// The hit triangle, for a query that hit anything (pruned or not).
    pub fn hit_triangle(&self) -> Option<u32> {
        (self.status() != Status::Miss).then_some(self.triangle)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn status_codes_round_trip() {
        for status in [Status::Miss, Status::Accepted, Status::NormalMismatch] {
            assert_eq!(Status::from_code(status.code()), status);
        }
        assert_eq!(Status::from_code(7), Status::Miss);
        assert_eq!(Correspondence::MISS.status(), Status::Miss);
        assert_eq!(Correspondence::MISS.hit_triangle(), None);
    }
}
