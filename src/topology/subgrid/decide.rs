//! The decision, per component of the input, of which tracked components stay on it and which
//! are deleted, and whether a copy of it is inserted, replaces them whole or is grafted into them
//! (see the module above).

use glam::Vec3;
use rayon::prelude::*;

use super::earlier::all_within;
use super::graft::{self, Bounds, Graft, Side};
use super::matching::{Against, Component, TrackedNearest, far_components, far_from_tracked};
use super::{Fidelity, SMALL_CELLS, SubgridCounts, SubgridError, Surfaces};

/// What the sub-grid match does to each component.
pub(super) struct Plan {
    /// Per tracked component: whether it goes (deleted, replaced, or grafted: then only the
    /// triangles its graft keeps stay).
    pub delete: Vec<bool>,
    /// Per input component: whether a whole copy of it comes in.
    pub insert: Vec<bool>,
    /// Per input component: the graft that joins it to the tracked components it matches.
    pub grafts: Vec<Option<Graft>>,
    /// Per input component: the tracked components its copy or graft replaces.
    pub replaces: Vec<Vec<usize>>,
    pub counts: SubgridCounts,
    /// What the bound check measured between the input and the staying tracked triangles, where
    /// it measured exactly (see `earlier`).
    pub nearest: Option<TrackedNearest>,
}

/// Decides for every component of `s` matched as `matched` (the input component each tracked one
/// lies on) under `fidelity`.
pub(super) fn decide(
    s: &Surfaces,
    matched: &[Option<usize>],
    fidelity: Fidelity,
) -> Result<Plan, SubgridError> {
    let (current, target) = (s.current, s.target);
    let (ours, our_labels, our_triangles) = (&s.ours.list, &s.ours.labels, &s.ours.triangles);
    let (theirs, target_labels, their_triangles) =
        (&s.theirs.list, &s.theirs.labels, &s.theirs.triangles);
    let (backend, input, spacing, max_distance) = (s.backend, s.input, s.spacing, s.max_distance);
    let small = SMALL_CELLS * spacing;
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); theirs.len()];
    for (c, m) in matched.iter().enumerate() {
        if let Some(k) = *m {
            members[k].push(c);
        }
    }
    let largest: Vec<Option<usize>> = members
        .iter()
        .map(|group| {
            group
                .iter()
                .copied()
                .max_by_key(|&c| (ours[c].vertices.len(), std::cmp::Reverse(c)))
        })
        .collect();
    let (our_far, (their_far, nearest)) = match fidelity {
        Fidelity::Input | Fidelity::InputWhole if !current.triangles.is_empty() => {
            // The input is measured against what stays if every group is faithful: without the
            // unmatched components and the small duplicates, which are deleted then.
            let ours = &ours;
            let stays: Vec<u32> = members
                .iter()
                .zip(&largest)
                .flat_map(|(group, &l)| {
                    group
                        .iter()
                        .copied()
                        .filter(move |&c| Some(c) == l || ours[c].diagonal > small)
                })
                .flat_map(|c| our_triangles[c].iter().copied())
                .collect();
            let exact = || -> Result<(Vec<Vec<Vec3>>, Option<TrackedNearest>), SubgridError> {
                let staying = graft::submesh(current, &stays);
                if staying.triangles.is_empty() {
                    let far = theirs
                        .iter()
                        .map(|c| {
                            c.vertices
                                .iter()
                                .map(|&v| target.positions[v as usize])
                                .collect()
                        })
                        .collect();
                    return Ok((far, None));
                }
                let (far, nearest) = far_from_tracked(
                    backend,
                    (&staying, &stays),
                    target,
                    (target_labels, theirs.len()),
                    max_distance,
                )?;
                Ok((far, Some(nearest)))
            };
            // The two directions are independent: each measures on its own core.
            let (our_far, their_far) = rayon::join(
                || {
                    far_components(
                        backend,
                        Against::Input(input),
                        current,
                        our_labels,
                        ours.len(),
                        max_distance,
                    )
                },
                || -> Result<Option<_>, SubgridError> {
                    match s.earlier {
                        Some(earlier)
                            if !stays.is_empty()
                                && all_within(
                                    backend,
                                    earlier,
                                    (current, &stays),
                                    target,
                                    max_distance,
                                )? =>
                        {
                            Ok(None)
                        }
                        _ => exact().map(Some),
                    }
                },
            );
            let our_far = our_far?;
            let their_far = match their_far? {
                Some(measured) => measured,
                // Vouched for: no input sample is far. A group that is not faithful even so is
                // grafted, and a graft's check needs the exact measurement.
                None => {
                    let unfaithful = members.iter().zip(&largest).enumerate().any(|(k, (g, l))| {
                        l.is_some_and(|l| !alike((ours, &theirs[k]), &our_far, small, (g, l)))
                    });
                    if unfaithful {
                        exact()?
                    } else {
                        (vec![Vec::new(); theirs.len()], None)
                    }
                }
            };
            (our_far, their_far)
        }
        _ => (
            vec![Vec::new(); ours.len()],
            (vec![Vec::new(); theirs.len()], None),
        ),
    };

    // Decide, per component of theirs, which of ours stay on it, or whether a copy replaces them,
    // whole or grafted.
    let mut delete = vec![false; ours.len()];
    let mut insert = vec![false; theirs.len()];
    let mut grafts: Vec<Option<Graft>> = (0..theirs.len()).map(|_| None).collect();
    let mut replaces: Vec<Vec<usize>> = vec![Vec::new(); theirs.len()];
    let mut counts = SubgridCounts::default();
    for (c, _) in matched.iter().enumerate().filter(|(_, m)| m.is_none()) {
        delete[c] = true;
        counts.deleted += 1;
    }
    // The components whose tracked ones do not reproduce them, each with its largest tracked one.
    let mut unfaithful: Vec<usize> = Vec::new();
    for (k, group) in members.iter().enumerate() {
        let Some(largest) = largest[k] else {
            insert[k] = true;
            counts.inserted += 1;
            continue;
        };
        let faithful = match fidelity {
            Fidelity::Input | Fidelity::InputWhole => {
                alike((ours, &theirs[k]), &our_far, small, (group, largest))
                    && their_far[k].is_empty()
            }
            Fidelity::Grid => {
                ours[largest].euler == theirs[k].euler
                    || ours[largest].diagonal > small
                    || theirs[k].diagonal > small
            }
        };
        if faithful {
            let others = group.iter().copied().filter(|&c| c != largest);
            for c in others.filter(|&c| ours[c].diagonal <= small) {
                delete[c] = true;
                counts.deleted += 1;
            }
        } else {
            unfaithful.push(k);
        }
    }
    // Each graft reads the surfaces and the bound check's measurements only: the grafts of
    // different input components run side by side, so a droplet's graft takes the core the main
    // body's graft leaves idle, and their results are taken in component order.
    let graft_of = |k: usize| -> Result<Option<Graft>, SubgridError> {
        let group = &members[k];
        let far: Vec<Vec3> = group
            .iter()
            .flat_map(|&c| &our_far[c])
            .chain(&their_far[k])
            .copied()
            .collect();
        let same_euler = largest[k].is_some_and(|l| ours[l].euler == theirs[k].euler);
        let sides = rayon::join(
            || {
                let triangles = group.iter().flat_map(|&c| &our_triangles[c]);
                Side::new(current, triangles.copied().collect())
            },
            || Side::new(target, their_triangles[k].clone()),
        );
        graft::graft(
            (&sides.0, &sides.1),
            &far,
            group.len() == 1 && same_euler,
            &Bounds {
                backend,
                input,
                spacing,
                max_distance,
                euler: theirs[k].euler,
                nearest: nearest.as_ref(),
            },
        )
    };
    let results: Vec<Result<Option<Graft>, SubgridError>> = match fidelity {
        Fidelity::Input => unfaithful.par_iter().map(|&k| graft_of(k)).collect(),
        Fidelity::InputWhole | Fidelity::Grid => unfaithful.iter().map(|_| Ok(None)).collect(),
    };
    for (&k, grafted) in unfaithful.iter().zip(results) {
        let grafted = grafted?;
        for &c in &members[k] {
            delete[c] = true;
        }
        replaces[k] = members[k].clone();
        if grafted.is_some() {
            counts.grafted += 1;
        } else {
            insert[k] = true;
            counts.replaced += 1;
        }
        grafts[k] = grafted;
    }
    Ok(Plan {
        delete,
        insert,
        grafts,
        replaces,
        counts,
        nearest,
    })
}

/// Whether the tracked components `group` (the largest `largest`) reproduce the input component
/// `theirs` as `Fidelity::Input` asks, but for the input's own far samples: the same Euler
/// characteristic, no far sample of the tracked side, and no other component larger than `small`.
fn alike(
    (ours, theirs): (&[Component], &Component),
    our_far: &[Vec<Vec3>],
    small: f32,
    (group, largest): (&[usize], usize),
) -> bool {
    ours[largest].euler == theirs.euler
        && our_far[largest].is_empty()
        && group
            .iter()
            .all(|&c| c == largest || ours[c].diagonal <= small)
}
