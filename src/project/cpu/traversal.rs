//! The traversal both query twins share, the twin of `descend` and `pop` in
//! `kernels/shared/bvh.wgsl`: a stack of nodes with their keys. A query tests a node's leaf
//! children, then asks [`Stack::descend`] for the interior child to visit next and, when there is
//! none, [`Stack::pop`]s one.

use crate::kernels::shared::BvhNode;
use crate::project::Bvh;

/// The nodes still to visit, each with its key (a lower bound of what it can hold).
pub(super) struct Stack {
    entries: [(u32, f32); Bvh::STACK_SIZE],
    sp: usize,
}

impl Stack {
    pub fn new() -> Self {
        Self {
            entries: [(0, 0.0); Bvh::STACK_SIZE],
            sp: 0,
        }
    }

    /// The interior children `k` of `node` with `visit(k)` and `keys[k] <= best`, nearest first:
    /// returns the nearest and pushes the others, farthest first.
    #[inline(always)]
    pub fn descend(
        &mut self,
        node: &BvhNode,
        keys: [f32; 4],
        visit: impl Fn(usize) -> bool,
        best: f32,
    ) -> Option<u32> {
        let mut near = [(0u32, 0.0f32); 4];
        let mut n_near = 0;
        for (k, &key) in keys.iter().enumerate() {
            if visit(k) && node.count[k] == 0 && key <= best {
                // Insertion by key, nearest first.
                let mut j = n_near;
                while j > 0 && near[j - 1].1 > key {
                    near[j] = near[j - 1];
                    j -= 1;
                }
                near[j] = (node.child[k], key);
                n_near += 1;
            }
        }
        if n_near == 0 {
            return None;
        }
        for j in (1..n_near).rev() {
            self.entries[self.sp] = near[j];
            self.sp += 1;
        }
        Some(near[0].0)
    }

    /// The next stacked node whose key is not above `best`; `None` when none is left.
    #[inline(always)]
    pub fn pop(&mut self, best: f32) -> Option<u32> {
        while self.sp > 0 {
            self.sp -= 1;
            let (next, key) = self.entries[self.sp];
            if key <= best {
                return Some(next);
            }
        }
        None
    }
}
