use super::transfer::Carry;

/// The default `continue_within`: a quarter of a cell, less than registration moves a vertex in
/// one frame of fluid (median nearest-vertex distance between consecutive inputs: about an edge).
pub const CONTINUE_WITHIN: f32 = 0.25;

/// Parameters of `constrain_topology`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TopologyOptions {
    /// Differences between the mesh and Θ that lie within this many grid steps (L1) of both
    /// surfaces are shallow and left alone (the paper's "deep cells": only differences deeper than
    /// about a cell re-sample the mesh, so wiggles of the surface do not churn it). 0 re-samples
    /// every difference. A shallow difference that would leave the topology different from Θ's is
    /// re-sampled anyway: the guarantee does not depend on this value.
    pub depth: u32,
    /// Keep the sheets, strands and gaps thinner than a cell that the mesh and the mesh Θ was
    /// sampled from both have (a grid edge the mesh crosses more than once, without overlap,
    /// where Θ's mesh crosses that edge or one beside it more than once), rather than
    /// re-sampling them to Θ's isosurface, which cannot hold them; components whose topology then
    /// differs from Θ's only through such a sheet are accepted. For a caller that matches the
    /// input's own topology below the grid afterwards (see `subgrid`): without it every thin sheet
    /// of a fluid is cut away by this step and copied back by that one, frame after frame.
    pub keep_shared_sheets: bool,
    /// How a vertex a patch creates or deletes takes its data from the surface it replaces.
    pub carry: Carry,
    /// A new vertex of a patch standing within this many grid spacings of the old vertex it takes
    /// its data from, which the patch removes, continues that vertex (its id and data) instead of
    /// replacing it (see `Replacement::continuing`); 0 gives every patch vertex a new id, as the
    /// paper does (§4.4).
    pub continue_within: f32,
    /// Which removed vertices a new vertex of the patch moves onto, so they go on as it (see
    /// `Moves`); none by default. Needs `continue_within` above 0.
    pub moves: Moves,
}

/// Where re-sampling moves a new vertex onto each carried vertex it removes (`move_onto`): a
/// topology patch's fill, the sub-grid match's copies.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Moves {
    /// Removed vertices with smaller ids (those carried over from an earlier frame) have a new
    /// vertex moved onto them where the move keeps the new surface in place; 0: none.
    pub carried_below: u64,
    /// No move makes an edge longer than this (world units) or than the longest around the
    /// vertex: improvement would split it, blending its ends' data (its `max_edge_length`).
    pub longest_edge: f32,
}

impl Moves {
    /// These moves where a moved vertex can continue the removed one it stands on
    /// (`continue_within` above 0); none where it cannot, since a move would then only reshape
    /// the new surface.
    pub fn where_continuing(self, continue_within: f32) -> Moves {
        if continue_within <= 0.0 {
            Moves::default()
        } else {
            self
        }
    }
}

impl Default for TopologyOptions {
    fn default() -> Self {
        Self {
            depth: 1,
            keep_shared_sheets: false,
            carry: Carry::default(),
            continue_within: CONTINUE_WITHIN,
            moves: Moves::default(),
        }
    }
}
