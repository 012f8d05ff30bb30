//! The per-frame breakdown of where vertices went: the stages' created and removed counts add up to
//! the frame's event list, the vertices they lost are exactly those of the previous frame missing
//! from this one, and the carried-over share is what the ids say.

use surftrack::compute::Backend;
use surftrack::events::EventKind;
use surftrack::sequence::{FrameSource, Progress, track_sequence};
use surftrack::synth::{Scene, SynthOptions, generate};
use surftrack::track::TrackOptions;

#[test]
fn churn_accounts_for_every_vertex_of_every_frame() {
    let options = SynthOptions {
        resolution: 36,
        frames: 8,
    };
    let frames: Vec<_> = generate(Scene::Merge, &options)
        .unwrap()
        .map(|f| f.unwrap().mesh)
        .collect();
    let mut previous: Vec<u64> = Vec::new();
    let mut checked = 0;
    track_sequence::<()>(
        FrameSource::Meshes(&frames),
        &Backend::Cpu,
        &TrackOptions::default(),
        None,
        |progress| {
            let Progress::Frame {
                tracker,
                events,
                log,
            } = progress
            else {
                return;
            };
            let mut ids = tracker.mesh().to_indexed().ids.unwrap();
            ids.sort_unstable();
            if log.frame > 0 {
                let c = &log.churn;
                let stages = [c.improve, c.topology_self, c.topology_target, c.subgrid];
                let created: usize = stages.iter().map(|s| s.created).sum();
                let removed: usize = stages.iter().map(|s| s.removed).sum();
                let count = |kinds: &[EventKind]| {
                    events
                        .events
                        .iter()
                        .filter(|e| kinds.contains(&e.kind))
                        .count()
                };
                assert_eq!(
                    created,
                    count(&[
                        EventKind::SplitEdge,
                        EventKind::SplitFace,
                        EventKind::Collapse,
                        EventKind::PatchCreated
                    ]),
                    "frame {}: created",
                    log.frame
                );
                let collapses = count(&[EventKind::Collapse]);
                assert_eq!(
                    removed,
                    2 * collapses + count(&[EventKind::Merge, EventKind::PatchDeleted]),
                    "frame {}: removed",
                    log.frame
                );
                let missing = previous
                    .iter()
                    .filter(|id| ids.binary_search(id).is_err())
                    .count();
                assert_eq!(c.lost(), missing, "frame {}: lost", log.frame);
                let kept = ids
                    .iter()
                    .filter(|id| previous.binary_search(id).is_ok())
                    .count();
                let carried = log.carried.expect("every later frame has a share");
                assert!(
                    (carried - kept as f64 / ids.len() as f64).abs() < 1e-12,
                    "frame {}: carried {carried}",
                    log.frame
                );
                checked += 1;
            }
            previous = ids;
        },
    )
    .unwrap();
    assert_eq!(checked, frames.len() - 1);
}
