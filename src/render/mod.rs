//! Pictures of a tracked sequence: every frame rasterized off-screen with wgpu (lavapipe, the
//! software Vulkan device, is enough), coloured by its carried colours, a texture through its
//! carried `uv`, or a scalar such as the wave `height` (paper §5's applications, seen), plus a
//! contact sheet and an animated GIF of the whole sequence from one camera.

mod camera;
mod colour;
mod corners;
mod error;
mod gpu;
mod image;
mod run;

pub use camera::Camera;
pub use colour::{Colouring, PLAIN, diverging, vertex_colours};
pub use corners::{Corner, Shading, corners};
pub use error::RenderError;
pub use gpu::{Renderer, SHADER};
pub use image::{Animation, Image, contact_sheet};
pub use run::{
    ANIMATION_FILE, ColourChoice, RENDER_FILE, RenderOptions, RenderSummary, SHEET_FILE,
    frame_files, render,
};
