//! A procedural solid checkerboard: a colour defined everywhere in space, so it needs no mapping and
//! shows at a glance whether carried colours stay on the material (paper Fig. 11) or slide over it.

use glam::Vec3;
use serde::Serialize;

/// The light cells' colour (linear RGB).
pub const LIGHT: [f32; 3] = [0.92, 0.90, 0.85];
/// The dark cells' colour (linear RGB).
pub const DARK: [f32; 3] = [0.12, 0.22, 0.55];

/// Cubes of side `cell` aligned with `origin`, alternating `LIGHT` and `DARK` like a 3-D chessboard.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Checker {
    pub origin: Vec3,
    pub cell: f32,
}

impl Checker {
    /// Whether `p` lies in a light cell (the cell holding `origin` is light).
    pub fn is_light(&self, p: Vec3) -> bool {
        let index = ((p - self.origin) / self.cell).floor();
        let sum = index.x as i64 + index.y as i64 + index.z as i64;
        sum.rem_euclid(2) == 0
    }

    pub fn colour(&self, p: Vec3) -> [f32; 3] {
        if self.is_light(p) { LIGHT } else { DARK }
    }

    /// Distance from `p` to the nearest cell wall: how far a point may drift before its colour
    /// changes.
    pub fn wall_distance(&self, p: Vec3) -> f32 {
        let rel = (p - self.origin) / self.cell;
        let frac = rel - rel.floor();
        frac.min(Vec3::ONE - frac).min_element() * self.cell
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn neighbouring_cells_alternate() {
        let c = Checker {
            origin: Vec3::new(0.5, 0.0, -1.0),
            cell: 2.0,
        };
        let p = Vec3::new(1.0, 1.0, 0.0);
        assert!(c.is_light(p));
        for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
            assert!(!c.is_light(p + 2.0 * axis));
            assert!(!c.is_light(p - 2.0 * axis));
            assert!(c.is_light(p + 4.0 * axis));
        }
        assert!(c.is_light(p + Vec3::new(2.0, 2.0, 0.0)));
        assert_eq!(c.colour(p), LIGHT);
        assert_eq!(c.colour(p + Vec3::new(-2.0, 0.0, 0.0)), DARK);
        assert!((c.wall_distance(Vec3::new(1.0, 0.25, 0.0)) - 0.25).abs() < 1e-6);
    }
}
