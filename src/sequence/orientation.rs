//! Frames whose triangles face inward. A closed surface oriented inward (a mesher with the
//! opposite sign convention, a scene mirrored on one axis on its way out of a DCC) encloses a
//! negative volume. Tracked as it is, every frame's Φ(M) reads the mesh as its own complement and
//! the topology step re-samples all of it: the dam break with every triangle turned carried 0% of
//! its vertices on every frame. So such a frame is tracked as its outward twin, and the tracked
//! frames face outward. A bubble inside the fluid is an inward-facing component of an outward
//! frame: only the frame's whole enclosed volume decides.

use std::borrow::Cow;

use crate::mesh::IndexedMesh;

/// `frame` with every triangle turned when it encloses a negative volume, and whether it was.
pub(super) fn outward(frame: Cow<'_, IndexedMesh>) -> (Cow<'_, IndexedMesh>, bool) {
    if frame.signed_volume() >= 0.0 {
        return (frame, false);
    }
    let mut turned = frame.into_owned();
    for t in &mut turned.triangles {
        t.swap(1, 2);
    }
    (Cow::Owned(turned), true)
}

/// The warning for the first frame [`outward`] turned in a run.
pub(super) fn turned_warning(name: &str) -> String {
    format!(
        "warning: {name}: its triangles face inward (it encloses a negative volume); it and every later frame facing inward are tracked with every triangle turned, so the tracked frames face outward"
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn an_inward_frame_is_turned_and_an_outward_one_with_a_bubble_is_not() {
        let sphere = IndexedMesh::icosphere(Vec3::ZERO, 2.0, 2);
        let (same, turned) = outward(Cow::Borrowed(&sphere));
        assert!(!turned);
        assert!(matches!(same, Cow::Borrowed(_)));
        let mut inward = sphere.clone();
        inward.triangles.iter_mut().for_each(|t| t.swap(1, 2));
        let (fixed, turned) = outward(Cow::Borrowed(&inward));
        assert!(turned);
        assert_eq!(fixed.triangles, sphere.triangles);
        // A bubble: a smaller inward sphere inside the outward one.
        let mut bubble = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 2);
        bubble.triangles.iter_mut().for_each(|t| t.swap(1, 2));
        let offset = sphere.positions.len() as u32;
        let mut both = sphere.clone();
        both.positions.extend(&bubble.positions);
        both.triangles
            .extend(bubble.triangles.iter().map(|t| t.map(|v| v + offset)));
        let (kept, turned) = outward(Cow::Borrowed(&both));
        assert!(!turned);
        assert_eq!(kept.triangles, both.triangles);
    }
}
