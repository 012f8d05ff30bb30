//! A monotone priority queue over non-negative `f32` keys (a radix heap, Ahuja et al. 1990) for
//! the geodesic searches. Dijkstra never pushes a key below the last one popped, so the queue only
//! has to order keys relative to that minimum: it keeps 33 buckets by the highest bit in which a
//! key differs from it and touches memory sequentially. A binary heap over the hundreds of
//! thousands of tentative labels of a 100k-vertex mesh instead walks a cache-missing path per
//! operation, which made the nearest-node search grow much faster than the mesh.

/// Items popped in increasing key order; items with equal keys in increasing `T` order when they
/// were queued before that key became the minimum (the order is deterministic in any case).
#[derive(Debug, Clone)]
pub struct RadixHeap<T> {
    last: u32,
    buckets: Vec<Vec<(u32, T)>>,
}

impl<T: Copy + Ord> RadixHeap<T> {
    pub fn new() -> Self {
        Self {
            last: 0,
            buckets: vec![Vec::new(); 33],
        }
    }

    /// Empties the queue and forgets the last key popped, for a new search.
    pub fn restart(&mut self) {
        self.buckets.iter_mut().for_each(Vec::clear);
        self.last = 0;
    }

    /// Queues `item` at `key`. Keys below the last popped one (impossible for non-negative edge
    /// lengths) and negative keys are queued at that last key, so the order never breaks.
    pub fn push(&mut self, key: f32, item: T) {
        let bits = if key > 0.0 { key.to_bits() } else { 0 };
        let bits = bits.max(self.last);
        self.buckets[bucket(bits, self.last)].push((bits, item));
    }

    /// The item with the smallest key, with that key.
    pub fn pop(&mut self) -> Option<(f32, T)> {
        if self.buckets[0].is_empty() {
            let index = self.buckets.iter().position(|b| !b.is_empty())?;
            let moving = std::mem::take(&mut self.buckets[index]);
            self.last = moving.iter().map(|&(k, _)| k).min()?;
            for &(k, item) in &moving {
                self.buckets[bucket(k, self.last)].push((k, item));
            }
            self.buckets[index] = moving;
            self.buckets[index].clear();
            self.buckets[0].sort_unstable_by_key(|&(_, item)| std::cmp::Reverse(item));
        }
        self.buckets[0]
            .pop()
            .map(|(k, item)| (f32::from_bits(k), item))
    }
}

/// 0 for keys equal to `last`, else one more than the index of the highest differing bit.
fn bucket(key: u32, last: u32) -> usize {
    (32 - (key ^ last).leading_zeros()) as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pops_in_key_then_item_order_while_keys_grow() {
        let mut heap = RadixHeap::new();
        let mut reference = Vec::new();
        let mut state = 12345u32;
        let mut next = || {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            state >> 8
        };
        for i in 0..200u32 {
            let key = (next() % 50) as f32 * 0.25;
            heap.push(key, i);
            reference.push((key, i));
        }
        let mut popped = Vec::new();
        while let Some((key, item)) = heap.pop() {
            popped.push((key, item));
            if item % 3 == 0 && popped.len() < 400 {
                let later = key + (next() % 7) as f32 * 0.5 + 0.125;
                heap.push(later, item + 1000);
                reference.push((later, item + 1000));
            }
        }
        reference.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        assert_eq!(popped.len(), reference.len());
        assert!(popped.windows(2).all(|w| w[0].0 <= w[1].0));
        let mut sorted = popped.clone();
        sorted.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        assert_eq!(sorted, reference);
    }

    #[test]
    fn late_small_keys_do_not_break_the_order() {
        let mut heap = RadixHeap::new();
        heap.push(2.0, 0u32);
        assert_eq!(heap.pop(), Some((2.0, 0)));
        heap.push(1.0, 1);
        heap.push(-3.0, 2);
        heap.push(f32::NAN, 3);
        heap.push(5.0, 4);
        let mut at_two: Vec<(f32, u32)> = (0..3).filter_map(|_| heap.pop()).collect();
        at_two.sort_by_key(|&(_, item)| item);
        assert_eq!(at_two, [(2.0, 1), (2.0, 2), (2.0, 3)]);
        assert_eq!(heap.pop(), Some((5.0, 4)));
        assert_eq!(heap.pop(), None);
        heap.restart();
        heap.push(0.5, 5);
        assert_eq!(heap.pop(), Some((0.5, 5)));
    }
}
