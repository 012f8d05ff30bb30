/// Parameters of `constrain_topology`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TopologyOptions {
    /// Differences between the mesh and Θ that lie within this many grid steps (L1) of both
    /// surfaces are shallow and left alone (the paper's "deep cells": only differences deeper than
    /// about a cell re-sample the mesh, so wiggles of the surface do not churn it). 0 re-samples
    /// every difference. A shallow difference that would leave the topology different from Θ's is
    /// re-sampled anyway: the guarantee does not depend on this value.
    pub depth: u32,
}

impl Default for TopologyOptions {
    fn default() -> Self {
        Self { depth: 1 }
    }
}
