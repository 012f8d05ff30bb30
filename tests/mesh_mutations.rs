//! Randomized mutations: after every single split, collapse, merge and flip the mesh still validates, ids are
//! never reused, the journal names what happened, and topology (χ per component) never changes.

use glam::Vec3;
use surftrack::mesh::{HalfEdgeId, IndexedMesh, Mesh, Mutation};

/// SplitMix64: a tiny deterministic generator, so a failure reproduces from its seed.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }

    fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
}

fn random_edge(mesh: &Mesh, rng: &mut Rng) -> HalfEdgeId {
    let faces: Vec<_> = mesh.faces().collect();
    let f = faces[rng.below(faces.len())];
    HalfEdgeId(mesh.face_half_edge(f).0 + rng.below(3) as u32)
}

fn exercise(input: &IndexedMesh, seed: u64, operations: usize) {
    let mut mesh = Mesh::from_indexed(input).expect("input mesh is valid");
    mesh.add_attribute("one", 1, 1.0);
    mesh.record_mutations();
    let euler = input.topology().euler();
    let mut rng = Rng(seed);
    let mut seen_ids: std::collections::HashSet<u64> =
        mesh.vertices().map(|v| mesh.id(v)).collect();
    let mut applied = [0usize; 5];
    for step in 0..operations {
        let h = random_edge(&mesh, &mut rng);
        let kind = rng.below(5);
        let done = match kind {
            0 => mesh.split_edge(h, 0.2 + 0.6 * rng.unit()).is_some(),
            1 => {
                let f = mesh.face(h);
                let (a, b) = (0.2 + 0.3 * rng.unit(), 0.2 + 0.3 * rng.unit());
                mesh.split_face(f, [a, b, 1.0 - a - b]).is_some()
            }
            2 => {
                let mid = (mesh.position(mesh.origin(h)) + mesh.position(mesh.target(h))) * 0.5;
                mesh.collapse(h, mid).is_some()
            }
            3 => {
                // Half the merges keep the origin where it is, half move it to the midpoint.
                let kept = mesh.origin(h);
                let (merged, at) = if rng.below(2) == 0 {
                    (mesh.position(kept), None)
                } else {
                    let mid = (mesh.position(kept) + mesh.position(mesh.target(h))) * 0.5;
                    (mid, Some(mid))
                };
                let merged_vertex = match at {
                    None => mesh.merge(h),
                    Some(mid) => mesh.merge_to(h, mid),
                };
                if let Some(v) = merged_vertex {
                    assert_eq!(v, kept, "a merge keeps the origin's slot");
                    assert_eq!(mesh.position(v), merged, "at the position asked for");
                }
                merged_vertex.is_some()
            }
            _ => mesh.flip(h).is_some(),
        };
        if let Err(e) = mesh.validate() {
            panic!("seed {seed}, step {step}, operation {kind}: {e}");
        }
        let journal = mesh.take_journal();
        assert_eq!(
            journal.len(),
            usize::from(done),
            "one record per applied mutation"
        );
        if done {
            applied[kind] += 1;
            let created = match journal[0] {
                Mutation::SplitEdge { created, .. }
                | Mutation::SplitFace { created, .. }
                | Mutation::Collapse { created, .. } => Some(created),
                Mutation::Merge { kept, removed } => {
                    assert!(mesh.vertices().any(|v| mesh.id(v) == kept), "kept {kept}");
                    assert!(mesh.vertices().all(|v| mesh.id(v) != removed));
                    None
                }
                Mutation::Flip { .. } => None,
                Mutation::PatchCreated { .. } | Mutation::PatchDeleted { .. } => {
                    panic!("a local mutation journaled a patch record")
                }
            };
            if let Some(id) = created {
                assert!(seen_ids.insert(id), "id {id} reused");
            }
        }
        assert_eq!(mesh.to_indexed().topology().euler(), euler, "step {step}");
    }
    for v in mesh.vertices() {
        assert!(
            (mesh.attribute(0, v)[0] - 1.0).abs() < 1e-5,
            "constant attribute drifted"
        );
    }
    assert!(
        applied.iter().all(|&n| n > operations / 20),
        "every kind applied: {applied:?}"
    );
    let mut compacted = mesh.clone();
    compacted.compact();
    assert_eq!(compacted.validate(), Ok(()));
    assert_eq!(compacted.to_indexed(), mesh.to_indexed());
}

#[test]
fn random_mutations_on_a_sphere_keep_the_mesh_valid() {
    exercise(&IndexedMesh::icosphere(Vec3::ZERO, 1.0, 2), 1, 3000);
}

#[test]
fn random_mutations_on_a_torus_keep_the_mesh_valid() {
    exercise(&IndexedMesh::torus(2.0, 0.7, 24, 12), 2, 3000);
}

/// Raw marching-cubes output of a synth scene: slivers, near-degenerate triangles, two components.
#[test]
fn random_mutations_on_a_synth_frame_keep_the_mesh_valid() {
    let options = surftrack::synth::SynthOptions {
        resolution: 24,
        frames: 2,
    };
    for (seed, frame) in surftrack::synth::generate(surftrack::synth::Scene::Merge, &options)
        .unwrap()
        .enumerate()
    {
        exercise(&frame.unwrap().mesh, 10 + seed as u64, 2000);
    }
}

#[test]
fn collapse_refuses_when_the_link_condition_fails() {
    let tet = IndexedMesh::new(
        vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
        vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
    );
    let mut mesh = Mesh::from_indexed(&tet).unwrap();
    for h in 0..12 {
        assert_eq!(mesh.collapse(HalfEdgeId(h), Vec3::splat(0.3)), None);
        assert_eq!(mesh.merge(HalfEdgeId(h)), None);
        assert_eq!(mesh.flip(HalfEdgeId(h)), None);
    }
    assert_eq!(mesh.validate(), Ok(()));
}

/// A flat droplet of two faces back to back, as splashsurf emits now and then (the DFSPH double
/// dam break's frames 17–19 and 27): every edge's two faces share their third vertex. No edge of
/// it can be split, flipped, collapsed or merged into a closed manifold, and improvement must
/// leave it as it is rather than open it.
#[test]
fn two_faces_back_to_back_refuse_every_edge_operation() {
    let pillow = IndexedMesh::new(
        vec![Vec3::ZERO, Vec3::X, Vec3::new(0.0, 1.0, 0.01)],
        vec![[0, 1, 2], [1, 0, 2]],
    );
    let mut mesh = Mesh::from_indexed(&pillow).unwrap();
    for h in 0..6 {
        assert_eq!(mesh.split_edge(HalfEdgeId(h), 0.5), None);
        assert_eq!(mesh.flip(HalfEdgeId(h)), None);
        assert_eq!(mesh.collapse(HalfEdgeId(h), Vec3::splat(0.3)), None);
        assert_eq!(mesh.merge(HalfEdgeId(h)), None);
    }
    assert_eq!(mesh.validate(), Ok(()));
    assert_eq!(mesh.face_count(), 2);
}
