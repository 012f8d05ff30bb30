//! An RGB image to map onto the start frame through a [`super::Projection`].

use super::PropagateError;
use glam::Vec2;
use std::path::Path;

/// An RGB image, rows top to bottom, values in `[0, 1]` as stored (no colour-space conversion).
#[derive(Debug, Clone, PartialEq)]
pub struct Texture {
    width: usize,
    height: usize,
    rgb: Vec<[f32; 3]>,
}

impl Texture {
    /// An image from its pixels, row-major from the top-left; `None` when the sizes disagree or the
    /// image is empty.
    pub fn from_rgb(width: usize, height: usize, rgb: Vec<[f32; 3]>) -> Option<Self> {
        (width > 0 && height > 0 && rgb.len() == width.checked_mul(height)?).then_some(Self {
            width,
            height,
            rgb,
        })
    }

    /// Reads a PNG of any colour type and bit depth (palette and grey expanded, 16-bit reduced to
    /// 8); alpha is dropped.
    pub fn read_png(path: &Path) -> Result<Self, PropagateError> {
        let fail = |reason: String| PropagateError::Image {
            path: path.to_path_buf(),
            reason,
        };
        let file = std::fs::File::open(path).map_err(|e| fail(e.to_string()))?;
        let mut decoder = png::Decoder::new(std::io::BufReader::new(file));
        decoder.set_transformations(png::Transformations::normalize_to_color8());
        let mut reader = decoder.read_info().map_err(|e| fail(e.to_string()))?;
        let size = reader
            .output_buffer_size()
            .ok_or_else(|| fail("image too large".to_string()))?;
        let mut buffer = vec![0u8; size];
        let info = reader
            .next_frame(&mut buffer)
            .map_err(|e| fail(e.to_string()))?;
        let channels = info.color_type.samples();
        let (width, height) = (info.width as usize, info.height as usize);
        let rgb = buffer[..info.buffer_size()]
            .chunks_exact(info.line_size)
            .flat_map(|row| row[..width * channels].chunks_exact(channels))
            .map(|px| {
                // Grey (with or without alpha) has one colour sample, RGB(A) three.
                let rgb = if channels < 3 {
                    [px[0]; 3]
                } else {
                    [px[0], px[1], px[2]]
                };
                rgb.map(|c| f32::from(c) / 255.0)
            })
            .collect();
        Self::from_rgb(width, height, rgb).ok_or_else(|| fail("empty image".to_string()))
    }

    pub fn width(&self) -> usize {
        self.width
    }

    pub fn height(&self) -> usize {
        self.height
    }

    /// Bilinear sample at `uv`, `v = 0` at the bottom row (the OBJ and Blender convention), clamped
    /// at the borders.
    pub fn sample(&self, uv: Vec2) -> [f32; 3] {
        let x =
            (uv.x.clamp(0.0, 1.0) * self.width as f32 - 0.5).clamp(0.0, (self.width - 1) as f32);
        let y = ((1.0 - uv.y.clamp(0.0, 1.0)) * self.height as f32 - 0.5)
            .clamp(0.0, (self.height - 1) as f32);
        let (x0, y0) = (x.floor() as usize, y.floor() as usize);
        let (x1, y1) = ((x0 + 1).min(self.width - 1), (y0 + 1).min(self.height - 1));
        let (fx, fy) = (x - x0 as f32, y - y0 as f32);
        let px = |x: usize, y: usize| self.rgb[y * self.width + x];
        let mut out = [0.0; 3];
        for (c, o) in out.iter_mut().enumerate() {
            let top = px(x0, y0)[c] * (1.0 - fx) + px(x1, y0)[c] * fx;
            let bottom = px(x0, y1)[c] * (1.0 - fx) + px(x1, y1)[c] * fx;
            *o = top * (1.0 - fy) + bottom * fy;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_pixel_centres_exactly_and_blends_between() {
        let t = Texture::from_rgb(2, 1, vec![[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]).unwrap();
        assert_eq!(t.sample(Vec2::new(0.25, 0.5)), [1.0, 0.0, 0.0]);
        assert_eq!(t.sample(Vec2::new(0.75, 0.5)), [0.0, 0.0, 1.0]);
        assert_eq!(t.sample(Vec2::new(0.5, 0.5)), [0.5, 0.0, 0.5]);
        assert_eq!(t.sample(Vec2::new(-3.0, 7.0)), [1.0, 0.0, 0.0]);
    }

    #[test]
    fn v_zero_is_the_bottom_row() {
        let t = Texture::from_rgb(1, 2, vec![[1.0; 3], [0.0; 3]]).unwrap();
        assert_eq!(t.sample(Vec2::new(0.5, 0.0)), [0.0; 3]);
        assert_eq!(t.sample(Vec2::new(0.5, 1.0)), [1.0; 3]);
        assert!(Texture::from_rgb(2, 2, vec![[0.0; 3]; 3]).is_none());
        assert!(Texture::from_rgb(0, 0, Vec::new()).is_none());
    }
}
