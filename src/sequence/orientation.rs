//! Frames whose triangles face inward. A closed surface oriented inward (a mesher with the
//! opposite sign convention, a scene mirrored on one axis on its way out of a DCC) encloses a
//! negative volume. Tracked as it is, every frame's Φ(M) reads the mesh as its own complement and
//! the topology step re-samples all of it: the dam break with every triangle turned carried 0% of
//! its vertices on every frame. So such a frame is tracked as its outward twin, and the tracked
//! frames face outward.
//!
//! A component facing inward inside the fluid is a bubble, as it should be; one facing inward
//! outside every other component is a droplet turned inside out (a mesher that orients each
//! component on its own), re-sampled whole every frame as the whole frame was (the drop pool with
//! its smallest component turned: 94.13% carried per frame against 97.03%). Each inward component
//! is placed by its nesting depth, the number of other components whose winding number at one of
//! its vertices is ±1 (disjoint closed surfaces give exactly 0 or ±1 there): at an even depth it
//! is turned.

use std::borrow::Cow;

use glam::DVec3;

use crate::mesh::IndexedMesh;

/// What [`outward`] turned.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(super) struct Turned {
    /// The whole frame enclosed a negative volume.
    pub whole: bool,
    /// Inward components outside every other (at an even depth).
    pub components: usize,
}

impl Turned {
    pub fn any(&self) -> bool {
        self.whole || self.components > 0
    }

    /// The warning for the first frame turned in a run, `name`.
    pub fn warning(&self, name: &str) -> String {
        let what = if self.whole {
            "its triangles face inward (it encloses a negative volume)".to_string()
        } else {
            format!(
                "components facing inward outside every other (droplets turned inside out): {}",
                self.components
            )
        };
        format!(
            "warning: {name}: {what}; it and every later frame so made are tracked turned, so the tracked frames face outward"
        )
    }
}

/// `frame` with its orientation made outward (see the module comment), and what was turned.
pub(super) fn outward(frame: Cow<'_, IndexedMesh>) -> (Cow<'_, IndexedMesh>, Turned) {
    let mut turned = Turned {
        whole: frame.signed_volume() < 0.0,
        components: 0,
    };
    let mut frame = frame;
    if turned.whole {
        let mut whole = frame.into_owned();
        for t in &mut whole.triangles {
            t.swap(1, 2);
        }
        frame = Cow::Owned(whole);
    }
    let outside = inward_outside(&frame);
    if !outside.is_empty() {
        let mut fixed = frame.into_owned();
        for &t in outside.iter().flatten() {
            fixed.triangles[t as usize].swap(1, 2);
        }
        turned.components = outside.len();
        frame = Cow::Owned(fixed);
    }
    (frame, turned)
}

/// The triangles of each component of `mesh` that encloses a negative volume at an even nesting
/// depth.
fn inward_outside(mesh: &IndexedMesh) -> Vec<Vec<u32>> {
    let (labels, count) = mesh.component_labels();
    let mut parts: Vec<Vec<u32>> = vec![Vec::new(); count];
    for (t, tri) in mesh.triangles.iter().enumerate() {
        parts[labels[tri[0] as usize] as usize].push(t as u32);
    }
    if parts.len() < 2 {
        return Vec::new();
    }
    let corners =
        |t: u32| mesh.triangles[t as usize].map(|v| mesh.positions[v as usize].as_dvec3());
    let bounds = |part: &[u32]| {
        part.iter()
            .flat_map(|&t| corners(t))
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p), hi.max(p))
            })
    };
    let boxes: Vec<(DVec3, DVec3)> = parts.iter().map(|p| bounds(p)).collect();
    let winding = |part: &[u32], p: DVec3| -> f64 {
        part.iter()
            .map(|&t| {
                let [a, b, c] = corners(t).map(|q| q - p);
                let (la, lb, lc) = (a.length(), b.length(), c.length());
                let den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
                2.0 * a.dot(b.cross(c)).atan2(den)
            })
            .sum::<f64>()
            / (4.0 * std::f64::consts::PI)
    };
    parts
        .iter()
        .enumerate()
        .filter(|(_, part)| mesh.signed_volume_of(part.iter().copied()) < 0.0)
        .filter(|&(c, part)| {
            let p = mesh.positions[mesh.triangles[part[0] as usize][0] as usize].as_dvec3();
            let depth = (0..parts.len())
                .filter(|&d| d != c)
                .filter(|&d| {
                    let (lo, hi) = boxes[d];
                    p.cmpge(lo).all() && p.cmple(hi).all() && winding(&parts[d], p).abs() > 0.5
                })
                .count();
            depth % 2 == 0
        })
        .map(|(_, part)| part.clone())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn turned(mut mesh: IndexedMesh) -> IndexedMesh {
        mesh.triangles.iter_mut().for_each(|t| t.swap(1, 2));
        mesh
    }

    #[test]
    fn inward_frames_and_inside_out_droplets_are_turned_and_bubbles_are_not() {
        let body = IndexedMesh::icosphere(Vec3::ZERO, 2.0, 2);
        let (same, what) = outward(Cow::Borrowed(&body));
        assert!(!what.any());
        assert!(matches!(same, Cow::Borrowed(_)));
        // The whole frame inward.
        let (fixed, what) = outward(Cow::Owned(turned(body.clone())));
        assert_eq!(
            what,
            Turned {
                whole: true,
                components: 0
            }
        );
        assert_eq!(fixed.triangles, body.triangles);
        // A bubble: a smaller inward sphere inside the body, left as it is.
        let bubble = turned(IndexedMesh::icosphere(Vec3::ZERO, 1.0, 2));
        let with_bubble = body.joined(&bubble);
        let (kept, what) = outward(Cow::Borrowed(&with_bubble));
        assert!(!what.any());
        assert_eq!(kept.triangles, with_bubble.triangles);
        // A droplet inside out beside the body, turned alone.
        let droplet = IndexedMesh::icosphere(Vec3::new(5.0, 0.0, 0.0), 0.5, 1);
        let inside_out = with_bubble.joined(&turned(droplet.clone()));
        let (fixed, what) = outward(Cow::Borrowed(&inside_out));
        assert_eq!(
            what,
            Turned {
                whole: false,
                components: 1
            }
        );
        assert_eq!(fixed.triangles, with_bubble.joined(&droplet).triangles);
        // A droplet in a bubble in the body faces outward: an inward one there is turned too.
        let nested = with_bubble.joined(&turned(IndexedMesh::icosphere(Vec3::ZERO, 0.25, 1)));
        let (_, what) = outward(Cow::Borrowed(&nested));
        assert_eq!(what.components, 1);
    }
}
