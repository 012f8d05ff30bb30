//! surftrack: turns an incoherent sequence of closed triangle meshes into one temporally coherent
//! deforming mesh plus per-frame event lists (Bojsen-Hansen, Li & Wojtan 2012, "Tracking Surfaces
//! with Evolving Topology").

pub mod apps;
pub mod batch;
pub mod compute;
pub mod eval;
pub mod events;
pub mod export;
pub mod fuzz;
pub mod geometry;
pub mod grid;
pub mod improve;
pub mod io;
pub mod kernels;
pub mod mesh;
pub mod project;
pub mod propagate;
pub mod register;
pub mod render;
pub mod sequence;
pub mod synth;
pub mod topology;
pub mod track;
