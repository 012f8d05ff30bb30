use super::EventError;
use std::collections::HashMap;

/// One per-vertex channel (`components` f32 values per vertex) keyed by persistent vertex id: what
/// `forward` and `backward` carry through a frame transition.
///
/// Storage is dense; the id map is only used for look-ups and never iterated, so the order of `ids()`
/// depends only on the operations applied, never on hashing. Two channels are equal when they give
/// the same values to the same ids, whatever their storage order.
#[derive(Debug, Clone)]
pub struct VertexValues {
    components: usize,
    ids: Vec<u64>,
    values: Vec<f32>,
    slot: HashMap<u64, usize>,
}

impl VertexValues {
    pub fn new(components: usize) -> Self {
        Self {
            components,
            ids: Vec::new(),
            values: Vec::new(),
            slot: HashMap::new(),
        }
    }

    /// Values for `ids`, vertex-major (`values[i * components + c]` belongs to `ids[i]`).
    pub fn from_parts(components: usize, ids: &[u64], values: &[f32]) -> Result<Self, EventError> {
        if values.len() != ids.len() * components {
            return Err(EventError::ComponentMismatch {
                components,
                got: values.len(),
            });
        }
        let mut out = Self::new(components);
        for (i, &id) in ids.iter().enumerate() {
            if out.slot.contains_key(&id) {
                return Err(EventError::DuplicateVertex { id });
            }
            out.insert(id, &values[i * components..(i + 1) * components])?;
        }
        Ok(out)
    }

    pub fn components(&self) -> usize {
        self.components
    }

    pub fn len(&self) -> usize {
        self.ids.len()
    }

    pub fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }

    /// Ids that carry a value, in storage order.
    pub fn ids(&self) -> &[u64] {
        &self.ids
    }

    pub fn get(&self, id: u64) -> Option<&[f32]> {
        let s = *self.slot.get(&id)?;
        Some(&self.values[s * self.components..(s + 1) * self.components])
    }

    /// Sets the value of `id`, adding the vertex when it has none.
    pub fn insert(&mut self, id: u64, value: &[f32]) -> Result<(), EventError> {
        if value.len() != self.components {
            return Err(EventError::ComponentMismatch {
                components: self.components,
                got: value.len(),
            });
        }
        match self.slot.get(&id) {
            Some(&s) => {
                self.values[s * self.components..(s + 1) * self.components].copy_from_slice(value);
            }
            None => {
                self.slot.insert(id, self.ids.len());
                self.ids.push(id);
                self.values.extend_from_slice(value);
            }
        }
        Ok(())
    }

    /// Drops the value of `id` (the last vertex moves into its place); false when it had none.
    pub fn remove(&mut self, id: u64) -> bool {
        let Some(s) = self.slot.remove(&id) else {
            return false;
        };
        let last = self.ids.len() - 1;
        let k = self.components;
        if s != last {
            let moved = self.ids[last];
            self.ids[s] = moved;
            self.values.copy_within(last * k..(last + 1) * k, s * k);
            self.slot.insert(moved, s);
        }
        self.ids.pop();
        self.values.truncate(last * k);
        true
    }
}

impl PartialEq for VertexValues {
    fn eq(&self, other: &Self) -> bool {
        self.components == other.components
            && self.len() == other.len()
            && self.ids.iter().all(|&id| self.get(id) == other.get(id))
    }
}
