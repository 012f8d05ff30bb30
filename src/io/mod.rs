//! Frame I/O: reading the incoherent input meshes (one closed triangle mesh per frame), writing
//! the tracked mesh with its persistent vertex ids, and finding the frames of a sequence on disk.
//!
//! # Reading
//! [`read_frame`] reads `.obj` (through `tobj`), `.ply` (ASCII, binary little- and big-endian) and
//! Blender/Mantaflow `.bobj.gz` fluid caches, chosen by extension. Polygons are fan-triangulated.
//! Each frame is then repaired ([`RepairReport`]): vertices within 1e-6 × the mean edge length of
//! an earlier vertex are welded into it, faces with a repeated corner or exactly zero area are
//! dropped, non-manifold edges and vertices (touching parts, as dual meshers write them) are split
//! apart without moving a point, and vertices no face uses are removed. A clean closed mesh passes
//! unchanged.
//!
//! Every count in a file is checked against the bytes that remain before anything is allocated
//! for it, and every failure is an [`IoError`] naming the file, the line (text formats) or element
//! (binary formats), and what is wrong. Topology (closed, manifold, oriented) is not the readers'
//! business: `IndexedMesh::validate` judges what they return.
//!
//! # Writing
//! Writes are atomic ([`atomic_write`]): a temporary file beside the target, renamed into place
//! once complete. [`prepare_output_dir`] refuses to write into a non-empty directory without
//! `force`.
//!
//! [`write_ply`] writes binary little-endian PLY with this vertex layout, which Blender, Houdini
//! and MeshLab import:
//!
//! ```text
//! element vertex N
//! property float x
//! property float y
//! property float z
//! property uint id            (only with ids; `double` when an id exceeds u32::MAX, exact to 2^53)
//! property float <channel>    (one per attribute component, in attribute order)
//! element face F
//! property list uchar int vertex_indices
//! ```
//!
//! Attribute channels are named by convention: `color` (3 or 4 components) as
//! `red green blue [alpha]`, `normal` (3) as `nx ny nz`, `uv` (2) as `u v`, `velocity` (3) as
//! `vx vy vz`, any other single-component attribute by its name and any other k-component
//! attribute as `name_0 … name_{k-1}`. The reader groups properties back the same way (also accepting `s t`
//! and `texture_u texture_v` for `uv`), so every mesh `write_ply` accepts reads back identically;
//! integer colours from other tools are scaled to [0, 1].
//!
//! [`write_obj`] writes positions and triangles, optionally `vt` from `uv` and per-vertex colour
//! from `color`; [`write_bobj_gz`] writes positions, area-weighted normals and triangles.
//! Floats are written in their shortest exact form, so every format round-trips positions bit for
//! bit.
//!
//! # Sequences
//! [`discover_sequence`] finds the frames of a directory or a pattern (`fluid_####.obj`,
//! `frame_*.ply`), ordered by frame number, with the gaps between them.

mod atomic;
mod bobj;
mod error;
mod file;
mod format;
mod frame;
mod obj_read;
mod obj_write;
mod ply_channels;
mod ply_header;
mod ply_layout;
mod ply_read;
mod ply_values;
mod ply_write;
mod repair;
mod sequence;
mod split;
mod weld;

pub use atomic::{AtomicFile, atomic_write, prepare_output_dir, remove_stale_temporaries};
pub use bobj::write_bobj_gz;
pub use error::{IoError, Location};
pub use format::Format;
pub use frame::{Frame, ReadOptions, read_frame, read_frame_with};
pub use obj_write::{ObjOptions, write_obj};
pub use ply_header::PlyEncoding;
pub use ply_write::{write_ply, write_ply_with};
pub use repair::RepairReport;
pub use sequence::{EmptyEnds, Sequence, discover_sequence};
