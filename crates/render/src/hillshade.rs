//! Map views of height fields: shaded relief and colour-mapped height with a legend.
//!
//! Hillshade follows the standard GIS formula (Burrough & McDonnell; GDAL's
//! `gdaldem hillshade`): slope and aspect from Horn's 3×3 finite differences,
//! shade = cos(zenith)·cos(slope) + sin(zenith)·sin(slope)·cos(azimuth − aspect),
//! with the light's azimuth clockwise from north (+y) and zenith = 90° − altitude.
//! Image row r shows grid row `ny − 1 − r`, so +y points up as on a map.

use asperity_core::{HeightField, RgbaImage};

use crate::colormap::ColorMap;
use crate::font::{draw_text, format_number, text_width};

/// Shaded relief in [0, 1] per sample (row-major like the grid), edges clamped.
pub fn hillshade_values(
    h: &HeightField,
    azimuth_deg: f64,
    altitude_deg: f64,
    z_factor: f64,
) -> Vec<f64> {
    let [nx, ny] = h.dims();
    let [dx, dy] = h.spacing();
    let zen = (90.0 - altitude_deg).to_radians();
    let az = azimuth_deg.to_radians();
    let z = |i: isize, j: isize| {
        *h.get(
            i.clamp(0, nx as isize - 1) as usize,
            j.clamp(0, ny as isize - 1) as usize,
        ) * z_factor
    };
    let mut out = vec![0.0; nx * ny];
    for j in 0..ny as isize {
        for i in 0..nx as isize {
            // Horn: weighted differences over the 3×3 neighbourhood.
            let dzdx = ((z(i + 1, j - 1) + 2.0 * z(i + 1, j) + z(i + 1, j + 1))
                - (z(i - 1, j - 1) + 2.0 * z(i - 1, j) + z(i - 1, j + 1)))
                / (8.0 * dx);
            let dzdy = ((z(i - 1, j + 1) + 2.0 * z(i, j + 1) + z(i + 1, j + 1))
                - (z(i - 1, j - 1) + 2.0 * z(i, j - 1) + z(i + 1, j - 1)))
                / (8.0 * dy);
            let slope = (dzdx * dzdx + dzdy * dzdy).sqrt().atan();
            // Direction of steepest descent, clockwise from north (+y).
            let aspect = (-dzdx).atan2(-dzdy);
            let s = zen.cos() * slope.cos() + zen.sin() * slope.sin() * (az - aspect).cos();
            out[i as usize + nx * j as usize] = s.max(0.0);
        }
    }
    out
}

fn put_grid(img: &mut RgbaImage, h: &HeightField, color: impl Fn(usize) -> [u8; 3]) {
    let [nx, ny] = h.dims();
    for r in 0..ny {
        let j = ny - 1 - r;
        for i in 0..nx {
            let c = color(i + nx * j);
            img.put(i as u32, r as u32, [c[0], c[1], c[2], 255]);
        }
    }
}

/// Grayscale shaded relief, one pixel per sample.
pub fn hillshade(h: &HeightField, azimuth_deg: f64, altitude_deg: f64) -> RgbaImage {
    let s = hillshade_values(h, azimuth_deg, altitude_deg, 1.0);
    let mut img = RgbaImage::filled(h.nx() as u32, h.ny() as u32, [0, 0, 0, 255]);
    put_grid(&mut img, h, |k| {
        let v = (s[k] * 255.0).round() as u8;
        [v, v, v]
    });
    img
}

/// Height through `map`, optionally modulated by hillshade (`relief` ∈ [0, 1]),
/// with a vertical legend bar labelled with the minimum and maximum heights.
/// The minimum maps to the colour map's start and the maximum to its end.
pub fn height_map(h: &HeightField, map: ColorMap, relief: f64, legend: bool) -> RgbaImage {
    let [nx, ny] = h.dims();
    let (lo, hi) = h.min_max();
    let span = if hi > lo { hi - lo } else { 1.0 };
    let shade = (relief > 0.0).then(|| hillshade_values(h, 315.0, 45.0, 1.0));
    let scale = if ny < 200 { 1 } else { 2 };
    let (lo_s, hi_s) = (format_number(lo), format_number(hi));
    let label_w = text_width(&lo_s, scale).max(text_width(&hi_s, scale));
    let extra = if legend { 24 * scale + label_w + 8 } else { 0 };
    let mut img = RgbaImage::filled(nx as u32 + extra, ny as u32, [255, 255, 255, 255]);
    put_grid(&mut img, h, |k| {
        let c = map.map((h.data()[k] - lo) / span);
        let f = shade.as_ref().map_or(1.0, |s| {
            1.0 - relief + relief * (0.35 + 0.65 * s[k] / std::f64::consts::FRAC_1_SQRT_2).min(1.3)
        });
        c.map(|v| (v as f64 * f).round().clamp(0.0, 255.0) as u8)
    });
    if legend {
        let x0 = nx as u32 + 6 * scale;
        let bar_w = 10 * scale;
        let top = (8 * scale).min(ny as u32 / 4);
        let bottom = (ny as u32).saturating_sub(top).max(top + 1).min(ny as u32);
        for y in top..bottom {
            let t = 1.0 - (y - top) as f64 / (bottom - top - 1).max(1) as f64;
            let c = map.map(t);
            for x in x0..x0 + bar_w {
                img.put(x, y, [c[0], c[1], c[2], 255]);
            }
        }
        let tx = x0 + bar_w + 4 * scale;
        draw_text(&mut img, tx, top, &hi_s, scale, [20, 20, 20, 255]);
        draw_text(
            &mut img,
            tx,
            bottom.saturating_sub(7 * scale),
            &lo_s,
            scale,
            [20, 20, 20, 255],
        );
    }
    img
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plane_facing_the_light_is_brightest() {
        // z = x: the slope faces west (−x); light from the west (azimuth 270°) at 45°
        // hits it head-on (slope 45°), so the shade is cos 0 = 1.
        let h = HeightField::from_vec([5, 5], (0..25).map(|k| (k % 5) as f64).collect()).unwrap();
        let s = hillshade_values(&h, 270.0, 45.0, 1.0);
        assert!((s[12] - 1.0).abs() < 1e-12, "{}", s[12]);
        // Light from the east at 45° grazes it: cos 90° = 0.
        let s = hillshade_values(&h, 90.0, 45.0, 1.0);
        assert!(s[12].abs() < 1e-12);
        // Flat ground: shade = sin(altitude).
        let flat = HeightField::filled([4, 4], 3.0);
        let s = hillshade_values(&flat, 315.0, 30.0, 1.0);
        assert!((s[5] - 0.5).abs() < 1e-12);
    }

    #[test]
    fn height_map_uses_the_colour_map_ends() {
        let h =
            HeightField::from_vec([8, 8], (0..64).map(|k| k as f64 * 0.5 - 3.0).collect()).unwrap();
        let img = height_map(&h, ColorMap::Viridis, 0.0, true);
        // Sample 0 (minimum) is grid row 0, drawn as the bottom image row.
        let min_px = img.get(0, 7);
        let max_px = img.get(7, 0);
        assert_eq!(&min_px[..3], &ColorMap::Viridis.map(0.0));
        assert_eq!(&max_px[..3], &ColorMap::Viridis.map(1.0));
        assert!(img.width() > 8, "legend added");
    }
}
