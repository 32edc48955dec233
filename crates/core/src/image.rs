//! An 8-bit RGBA raster: mesh textures and rendered pictures.

use crate::CoreError;

/// Row-major RGBA8 image; pixel (x, y) starts at byte `4 * (x + width * y)`, y down.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RgbaImage {
    width: u32,
    height: u32,
    pixels: Vec<u8>,
}

impl RgbaImage {
    /// An image filled with `rgba`.
    pub fn filled(width: u32, height: u32, rgba: [u8; 4]) -> Self {
        let n = width as usize * height as usize;
        Self {
            width,
            height,
            pixels: rgba.iter().copied().cycle().take(4 * n).collect(),
        }
    }

    /// Wraps existing pixels.
    ///
    /// # Errors
    /// [`CoreError::GridSize`] if `pixels.len() != 4·width·height` or a side is 0.
    pub fn from_pixels(width: u32, height: u32, pixels: Vec<u8>) -> crate::Result<Self> {
        let expected = 4 * width as usize * height as usize;
        if width == 0 || height == 0 || pixels.len() != expected {
            return Err(CoreError::GridSize {
                dims: vec![width as usize, height as usize, 4],
                expected,
                got: pixels.len(),
            });
        }
        Ok(Self {
            width,
            height,
            pixels,
        })
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The raw RGBA bytes.
    pub fn pixels(&self) -> &[u8] {
        &self.pixels
    }

    /// Mutable raw RGBA bytes.
    pub fn pixels_mut(&mut self) -> &mut [u8] {
        &mut self.pixels
    }

    /// Pixel (x, y).
    ///
    /// # Panics
    /// If (x, y) is outside the image.
    pub fn get(&self, x: u32, y: u32) -> [u8; 4] {
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) outside image"
        );
        let o = 4 * (x as usize + self.width as usize * y as usize);
        [
            self.pixels[o],
            self.pixels[o + 1],
            self.pixels[o + 2],
            self.pixels[o + 3],
        ]
    }

    /// Sets pixel (x, y).
    ///
    /// # Panics
    /// If (x, y) is outside the image.
    pub fn put(&mut self, x: u32, y: u32, rgba: [u8; 4]) {
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) outside image"
        );
        let o = 4 * (x as usize + self.width as usize * y as usize);
        self.pixels[o..o + 4].copy_from_slice(&rgba);
    }
}
