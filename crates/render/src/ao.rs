//! Screen-space ambient obscurance from the depth buffer.
//!
//! For each covered pixel, 12 directions × 3 radii of neighbours within a world
//! radius R are compared by linear view depth: a neighbour nearer to the eye by
//! Δ > 0 occludes by min(Δ/R, 1), faded out for Δ > 4R (a foreground object is
//! not a crevice). The obscurance is the mean occlusion; crevices, pits and the
//! feet of cliffs darken, flat and convex regions do not. This is the
//! depth-only variant of Crytek-style SSAO: no normals needed, cheap at final
//! resolution, and deterministic (fixed sample pattern).

use rayon::prelude::*;

/// Obscurance in [0, 1] per pixel from linear view depth (`NaN` = background).
/// `px_per_world(depth)` converts a world length at that depth into pixels.
pub fn obscurance(
    depth: &[f32],
    width: usize,
    height: usize,
    radius: f32,
    px_per_world: &(dyn Fn(f32) -> f32 + Sync),
) -> Vec<f32> {
    const DIRS: usize = 12;
    let dirs: Vec<(f32, f32)> = (0..DIRS)
        .map(|k| {
            let a = (k as f32 + 0.5) / DIRS as f32 * std::f32::consts::TAU;
            (a.cos(), a.sin())
        })
        .collect();
    let mut out = vec![0.0f32; width * height];
    out.par_chunks_mut(width).enumerate().for_each(|(y, row)| {
        for (x, o) in row.iter_mut().enumerate() {
            let d = depth[y * width + x];
            if d.is_nan() {
                continue;
            }
            let r_px = (radius * px_per_world(d)).clamp(1.0, 0.15 * height as f32);
            let (mut occ, mut n) = (0.0f32, 0.0f32);
            for (k, &(cx, cy)) in dirs.iter().enumerate() {
                for s in [0.35f32, 0.65, 1.0] {
                    // Rotate the radius pattern per direction to avoid banding.
                    let rr = r_px * (s + 0.1 * (k % 3) as f32).min(1.0);
                    let (sx, sy) = ((x as f32 + cx * rr).round(), (y as f32 + cy * rr).round());
                    if sx < 0.0 || sy < 0.0 || sx >= width as f32 || sy >= height as f32 {
                        continue;
                    }
                    let ds = depth[sy as usize * width + sx as usize];
                    n += 1.0;
                    if ds.is_nan() {
                        continue;
                    }
                    let delta = d - ds;
                    if delta > 0.0 {
                        let fade = if delta > 4.0 * radius { 0.0 } else { 1.0 };
                        occ += (delta / radius).min(1.0) * fade;
                    }
                }
            }
            *o = if n > 0.0 { occ / n } else { 0.0 };
        }
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pits_darken_plains_do_not() {
        let (w, h) = (64, 64);
        let mut depth = vec![10.0f32; w * h];
        // A pit: the centre is deeper (farther) than its surroundings.
        for y in 30..34 {
            for x in 30..34 {
                depth[y * w + x] = 11.0;
            }
        }
        let ao = obscurance(&depth, w, h, 0.5, &|_| 8.0);
        assert!(ao[32 * w + 32] > 0.5, "pit bottom {}", ao[32 * w + 32]);
        assert_eq!(ao[5 * w + 5], 0.0, "flat plain");
    }
}
