//! Re-sampling is local: on the synthetic scenes, with the tracked mesh registered onto each target
//! (every vertex moved to its nearest point on the target, as registration aims to), the two
//! topology passes of Algorithm 1 touch no vertex on frames without a topology change, re-sample a
//! small share of the mesh where the topology changes, and always leave the target's topology.
//! Also: the result does not depend on the number of threads.

#[path = "topology_support/mod.rs"]
pub mod topology_support;

use surftrack::compute::Backend;
use surftrack::events::EventList;
use surftrack::grid::GridFrame;
use surftrack::mesh::{IndexedMesh, Mesh};
use surftrack::project::{Bvh, closest_points};
use surftrack::synth::{Scene, SynthOptions, generate};
use surftrack::topology::{Field, TopologyOptions, constrain_topology};
use topology_support::{case, euler_list};

/// `mesh` with every vertex moved to its nearest point on `target` (or most of the way, when the
/// full move would make a triangle degenerate).
fn registered(mesh: &IndexedMesh, target: &IndexedMesh) -> IndexedMesh {
    let bvh = Bvh::build(target).unwrap();
    let near = closest_points(&Backend::Cpu, &bvh, &mesh.positions, f32::INFINITY).unwrap();
    for blend in [1.0f32, 0.99, 0.95, 0.9] {
        let mut m = mesh.clone();
        for (p, n) in m.positions.iter_mut().zip(&near) {
            *p += blend * (n.point - *p);
        }
        if m.validate().is_ok() {
            return m;
        }
    }
    mesh.clone()
}

struct Step {
    changed: bool,
    replaced: f64,
}

/// Both topology passes on every frame of a scene; checks each result against the target.
fn track(scene: Scene, resolution: usize, frames: usize) -> Vec<Step> {
    let options = SynthOptions { resolution, frames };
    let all: Vec<_> = generate(scene, &options)
        .unwrap()
        .map(|f| f.unwrap())
        .collect();
    let frame = GridFrame::for_mesh(&all[0].mesh, 1.0).unwrap();
    let mut steps = Vec::new();
    for j in 1..frames {
        let target = &all[j].mesh;
        let m = registered(&all[j - 1].mesh, target);
        let mut mesh = Mesh::from_indexed(&m).unwrap();
        let input = mesh.vertex_count();
        let phi_m = Field::signed_distance(&Backend::Cpu, frame, &m).unwrap();
        let own = constrain_topology(&mut mesh, &phi_m, &TopologyOptions::default()).unwrap();
        let phi_t = Field::signed_distance(&Backend::Cpu, frame, target).unwrap();
        let to_target = constrain_topology(&mut mesh, &phi_t, &TopologyOptions::default()).unwrap();
        let out = mesh.to_indexed();
        out.validate().unwrap();
        assert_eq!(
            out.topology().components.len(),
            all[j].truth.components,
            "{scene} frame {j}: components"
        );
        assert_eq!(
            euler_list(&out),
            euler_list(target),
            "{scene} frame {j}: topology"
        );
        steps.push(Step {
            changed: own.changed() || to_target.changed(),
            replaced: (own.deleted + to_target.deleted) as f64 / input as f64,
        });
    }
    steps
}

#[test]
fn merging_re_samples_only_where_the_spheres_meet() {
    let steps = track(Scene::Merge, 40, 24);
    let changed: Vec<usize> = (0..steps.len()).filter(|&i| steps[i].changed).collect();
    assert_eq!(
        changed.len(),
        1,
        "only the merge frame changes, got frames {changed:?}"
    );
    let share = steps[changed[0]].replaced;
    eprintln!(
        "merge frame: {:.2}% of the vertices replaced",
        100.0 * share
    );
    assert!(share < 0.1, "{share}");
}

#[test]
fn splits_and_droplets_take_the_target_topology() {
    for scene in [Scene::Split, Scene::Droplets, Scene::Morph] {
        let steps = track(scene, 32, 12);
        assert!(
            steps.iter().any(|s| s.changed),
            "{scene} never changes topology"
        );
    }
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    for seed in [3u64, 7, 11, 14, 20, 43] {
        let c = case(seed);
        if c.mesh.triangles.is_empty() {
            continue;
        }
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let mut mesh = Mesh::from_indexed(&c.mesh).unwrap();
                mesh.record_mutations();
                constrain_topology(&mut mesh, &c.theta, &TopologyOptions::default()).unwrap();
                (mesh.to_indexed(), EventList::drain(&mut mesh))
            })
        };
        let (one, events_one) = run(1);
        let (three, events_three) = run(3);
        assert_eq!(one.triangles, three.triangles, "seed {seed}");
        assert_eq!(one.ids, three.ids, "seed {seed}");
        let bits = |m: &IndexedMesh| -> Vec<u32> {
            m.positions
                .iter()
                .flat_map(|p| p.to_array().map(f32::to_bits))
                .collect()
        };
        assert_eq!(bits(&one), bits(&three), "seed {seed}");
        assert_eq!(events_one, events_three, "seed {seed}");
    }
}
