//! Carrying per-vertex data through one frame transition (paper §4.6): forward in the order the events
//! happened using `f`, backward in reverse order using `g`.

use super::{Assignment, EventError, EventList, VertexValues};

/// Carries `values` from the frame before `events` to the frame after: each event's forward rules give
/// values to its created vertices, then the vertices it removed lose theirs. Vertices no event touches
/// keep their values bit for bit.
pub fn forward(events: &EventList, values: &mut VertexValues) -> Result<(), EventError> {
    for (index, event) in events.events.iter().enumerate() {
        apply(
            index,
            &event.forward,
            (&event.inputs, &event.outputs),
            values,
        )?;
    }
    Ok(())
}

/// Carries `values` from the frame after `events` back to the frame before: events are undone last
/// first, each event's backward rules give values to the vertices it had removed, and the vertices it
/// had created lose theirs. A `null` backward rule (splits, created patches) only drops.
pub fn backward(events: &EventList, values: &mut VertexValues) -> Result<(), EventError> {
    for (index, event) in events.events.iter().enumerate().rev() {
        apply(
            index,
            &event.backward,
            (&event.outputs, &event.inputs),
            values,
        )?;
    }
    Ok(())
}

/// Event `index` applied one way, from the vertex set `from` to `to`: `rules` give values to the
/// vertices they write, computed from the values before the event; the vertices only in `from`
/// lose theirs.
fn apply(
    index: usize,
    rules: &[Assignment],
    (from, to): (&[u64], &[u64]),
    values: &mut VertexValues,
) -> Result<(), EventError> {
    let computed = evaluate(index, rules, values)?;
    for &id in from {
        if !to.contains(&id) {
            values.remove(id);
        }
    }
    store(computed, values)
}

/// Evaluates every rule of one event against the values as they were before the event, so rules of
/// one event never see each other's results.
fn evaluate(
    index: usize,
    rules: &[Assignment],
    values: &VertexValues,
) -> Result<Vec<(u64, Vec<f32>)>, EventError> {
    let k = values.components();
    rules
        .iter()
        .map(|rule| {
            let mut sum = vec![0.0f32; k];
            for &(source, weight) in &rule.terms {
                let value = values.get(source).ok_or(EventError::MissingVertex {
                    event: index,
                    id: source,
                })?;
                for (s, &v) in sum.iter_mut().zip(value) {
                    *s += weight * v;
                }
            }
            Ok((rule.target, sum))
        })
        .collect()
}

fn store(computed: Vec<(u64, Vec<f32>)>, values: &mut VertexValues) -> Result<(), EventError> {
    for (id, value) in computed {
        values.insert(id, &value)?;
    }
    Ok(())
}
