//! Rendered images and what is made of them: PNG files, a contact sheet of thumbnails, an animated
//! GIF.

use crate::io::{IoError, atomic_write};
use std::path::Path;

/// An 8-bit RGBA image, rows top to bottom.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<u8>,
}

impl Image {
    pub fn from_rgba(width: u32, height: u32, rgba: Vec<u8>) -> Self {
        Self {
            width,
            height,
            rgba,
        }
    }

    /// An image of one colour.
    pub fn filled(width: u32, height: u32, rgba: [u8; 4]) -> Self {
        let pixels = width as usize * height as usize;
        Self::from_rgba(width, height, rgba.repeat(pixels))
    }

    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        let i = 4 * (y as usize * self.width as usize + x as usize);
        [
            self.rgba[i],
            self.rgba[i + 1],
            self.rgba[i + 2],
            self.rgba[i + 3],
        ]
    }

    /// Reduced by an integer `factor` (each output pixel the mean of a factor × factor block).
    pub fn shrunk(&self, factor: u32) -> Image {
        let factor = factor.max(1);
        let (w, h) = (self.width / factor, self.height / factor);
        let mut rgba = Vec::with_capacity(4 * w as usize * h as usize);
        for y in 0..h {
            for x in 0..w {
                let mut sum = [0u32; 4];
                for dy in 0..factor {
                    for dx in 0..factor {
                        let p = self.pixel(x * factor + dx, y * factor + dy);
                        for k in 0..4 {
                            sum[k] += u32::from(p[k]);
                        }
                    }
                }
                let n = factor * factor;
                rgba.extend(sum.map(|s| ((s + n / 2) / n) as u8));
            }
        }
        Image::from_rgba(w, h, rgba)
    }

    /// Copies `other` into this image with its top-left corner at `(x, y)`, clipped.
    pub fn paste(&mut self, other: &Image, x: u32, y: u32) {
        for row in 0..other.height.min(self.height.saturating_sub(y)) {
            let width = other.width.min(self.width.saturating_sub(x)) as usize;
            let from = 4 * (row as usize * other.width as usize);
            let to = 4 * ((y + row) as usize * self.width as usize + x as usize);
            self.rgba[to..to + 4 * width].copy_from_slice(&other.rgba[from..from + 4 * width]);
        }
    }

    /// Writes the image as an 8-bit RGBA PNG, atomically.
    pub fn write_png(&self, path: &Path) -> Result<(), IoError> {
        atomic_write(path, |w| {
            let mut encoder = png::Encoder::new(w, self.width, self.height);
            encoder.set_color(png::ColorType::Rgba);
            encoder.set_depth(png::BitDepth::Eight);
            let mut writer = encoder.write_header().map_err(std::io::Error::other)?;
            writer
                .write_image_data(&self.rgba)
                .map_err(std::io::Error::other)?;
            writer.finish().map_err(std::io::Error::other)
        })
    }
}

/// A grid of `columns` thumbnails, in order, over `background`.
pub fn contact_sheet(thumbnails: &[Image], columns: usize, background: [u8; 4]) -> Image {
    let columns = columns.clamp(1, thumbnails.len().max(1));
    let rows = thumbnails.len().div_ceil(columns).max(1);
    let (w, h) = thumbnails.first().map_or((1, 1), |t| (t.width, t.height));
    let gap = 4;
    let mut sheet = Image::filled(
        columns as u32 * (w + gap) + gap,
        rows as u32 * (h + gap) + gap,
        background,
    );
    for (k, thumbnail) in thumbnails.iter().enumerate() {
        let (column, row) = ((k % columns) as u32, (k / columns) as u32);
        sheet.paste(thumbnail, gap + column * (w + gap), gap + row * (h + gap));
    }
    sheet
}

/// An animated GIF written frame by frame (each frame quantized to its own 256-colour palette),
/// looping forever; the file appears complete or not at all.
pub struct Animation {
    encoder: gif::Encoder<Vec<u8>>,
    width: u16,
    height: u16,
    /// Delay between frames, in hundredths of a second.
    delay: u16,
}

impl Animation {
    /// `None` when the images are too large for GIF (65535 pixels a side).
    pub fn new(width: u32, height: u32, fps: f32) -> Option<Self> {
        let (width, height) = (u16::try_from(width).ok()?, u16::try_from(height).ok()?);
        let mut encoder = gif::Encoder::new(Vec::new(), width, height, &[]).ok()?;
        encoder.set_repeat(gif::Repeat::Infinite).ok()?;
        let delay = (100.0 / fps.max(1.0)).round().clamp(1.0, 65535.0) as u16;
        Some(Self {
            encoder,
            width,
            height,
            delay,
        })
    }

    /// Appends one image of the animation's size.
    pub fn push(&mut self, image: &Image) -> Result<(), gif::EncodingError> {
        let mut rgba = image.rgba.clone();
        let mut frame = gif::Frame::from_rgba_speed(self.width, self.height, &mut rgba, 10);
        frame.delay = self.delay;
        self.encoder.write_frame(&frame)
    }

    /// Writes the whole animation to `path`, atomically.
    pub fn write(self, path: &Path) -> Result<(), IoError> {
        let bytes = self.encoder.into_inner().map_err(|e| IoError::Io {
            path: path.to_path_buf(),
            action: "encode",
            source: std::io::Error::other(e),
        })?;
        atomic_write(path, |w| w.write_all(&bytes))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shrinking_averages_blocks() {
        let mut image = Image::filled(4, 2, [0, 0, 0, 255]);
        image.paste(&Image::filled(1, 2, [200, 100, 40, 255]), 0, 0);
        let small = image.shrunk(2);
        assert_eq!((small.width, small.height), (2, 1));
        assert_eq!(small.pixel(0, 0), [100, 50, 20, 255]);
        assert_eq!(small.pixel(1, 0), [0, 0, 0, 255]);
    }

    #[test]
    fn a_sheet_places_thumbnails_in_rows() {
        let tiles: Vec<Image> = (0..5)
            .map(|k| Image::filled(3, 2, [k * 40, 0, 0, 255]))
            .collect();
        let sheet = contact_sheet(&tiles, 2, [9, 9, 9, 255]);
        assert_eq!((sheet.width, sheet.height), (2 * 7 + 4, 3 * 6 + 4));
        assert_eq!(sheet.pixel(4, 4), [0, 0, 0, 255]);
        assert_eq!(sheet.pixel(4 + 7, 4 + 6), [120, 0, 0, 255]);
        assert_eq!(sheet.pixel(0, 0), [9, 9, 9, 255]);
    }
}
