//! Cell grids as pictures: a CA state per square of pixels (peridier's
//! Figure 3), and pictures placed side by side in a strip.

use asperity_core::RgbaImage;

/// `states` (x fastest, `nx × ny`) drawn as squares of `scale` pixels, each
/// coloured by `color`; with `gap`, every square's last row and column are
/// left in `background`, so neighbouring cells stay apart.
pub fn cell_image(
    states: &[u8],
    [nx, ny]: [usize; 2],
    scale: u32,
    gap: bool,
    background: [u8; 4],
    color: impl Fn(u8) -> [u8; 4],
) -> RgbaImage {
    let mut img = RgbaImage::filled(nx as u32 * scale, ny as u32 * scale, background);
    let side = if gap { scale.saturating_sub(1) } else { scale };
    for (n, &s) in states.iter().enumerate().take(nx * ny) {
        let c = color(s);
        let (x, y) = ((n % nx) as u32 * scale, (n / nx) as u32 * scale);
        for dy in 0..side {
            for dx in 0..side {
                img.put(x + dx, y + dy, c);
            }
        }
    }
    img
}

/// Grey levels for `k` states: 0 white, k − 1 black.
pub fn grey(k: u8) -> impl Fn(u8) -> [u8; 4] {
    move |s| {
        let g = 255 - (s as u32 * 255 / (k.max(2) as u32 - 1)) as u8;
        [g, g, g, 255]
    }
}

/// Pictures in a row, each followed by `gap` pixels of `background`; as tall as
/// the tallest.
pub fn strip(images: &[RgbaImage], gap: u32, background: [u8; 4]) -> RgbaImage {
    let width = images.iter().map(|i| i.width() + gap).sum::<u32>();
    let height = images.iter().map(RgbaImage::height).max().unwrap_or(0);
    let mut out = RgbaImage::filled(width, height, background);
    let mut x0 = 0;
    for img in images {
        blit(&mut out, img, x0, 0);
        x0 += img.width() + gap;
    }
    out
}

/// Copies `img` into `dst` with its top left corner at (x0, y0), clipped.
pub fn blit(dst: &mut RgbaImage, img: &RgbaImage, x0: u32, y0: u32) {
    for y in 0..img.height().min(dst.height().saturating_sub(y0)) {
        for x in 0..img.width().min(dst.width().saturating_sub(x0)) {
            dst.put(x0 + x, y0 + y, img.get(x, y));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_gaps_and_strips() {
        let img = cell_image(&[0, 1], [2, 1], 3, true, [9, 9, 9, 255], grey(2));
        assert_eq!((img.width(), img.height()), (6, 3));
        assert_eq!(img.get(0, 0), [255, 255, 255, 255]);
        assert_eq!(img.get(3, 1), [0, 0, 0, 255]);
        assert_eq!(img.get(2, 0), [9, 9, 9, 255], "the gap column");
        let s = strip(&[img.clone(), img], 2, [1, 2, 3, 255]);
        assert_eq!((s.width(), s.height()), (16, 3));
        assert_eq!(s.get(7, 0), [1, 2, 3, 255]);
        assert_eq!(s.get(11, 1), [0, 0, 0, 255]);
    }
}
