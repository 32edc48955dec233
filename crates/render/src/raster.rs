//! Z-buffered triangle rasterisation into a visibility buffer, in parallel bands.
//!
//! Written here rather than taken from a crate: the Rust rasterisers on crates.io
//! (euc, rasterize-…) are either GPU-API emulators with per-pixel closures too
//! slow for millions of triangles, or 2-D vector fillers without depth. What we
//! need is small: a visibility buffer (depth + triangle id per sample) that the
//! shading pass reads, so every sample is shaded once, after visibility is known.
//!
//! # Algorithm
//! 1. Triangles are binned into horizontal bands of [`BAND`] sample rows by their
//!    screen-space y extent, in chunks processed in parallel and concatenated in
//!    chunk order, so each band lists its triangles in index order.
//! 2. Bands are rasterised in parallel. A sample is covered when its three edge
//!    functions are ≥ 0 (either winding: both faces are drawn). Depth is the
//!    screen-linear NDC z; a sample takes a triangle only if its depth is strictly
//!    smaller, so on ties the lower triangle index wins and the image does not
//!    depend on the thread count.

use rayon::prelude::*;

/// Sample rows per band (the unit of parallel work).
pub const BAND: usize = 16;
/// Triangle id of an empty sample.
pub const EMPTY: u32 = u32::MAX;

/// Projected vertices: screen x, y in samples (pixel centres at +0.5), NDC depth
/// in [−1, 1], and 1/w for perspective-correct interpolation.
#[derive(Clone, Debug, Default)]
pub struct ScreenVerts {
    /// Screen x (samples).
    pub x: Vec<f32>,
    /// Screen y (samples, down).
    pub y: Vec<f32>,
    /// NDC depth.
    pub z: Vec<f32>,
    /// 1 / clip w.
    pub inv_w: Vec<f32>,
    /// Whether the vertex is in front of the near plane.
    pub valid: Vec<bool>,
}

/// Depth and triangle id per sample, row-major.
pub struct VisBuffer {
    /// Width in samples.
    pub width: usize,
    /// Height in samples.
    pub height: usize,
    /// NDC depth (∞ where empty).
    pub depth: Vec<f32>,
    /// Triangle index ([`EMPTY`] where empty).
    pub tri: Vec<u32>,
}

#[inline]
fn edge(ax: f32, ay: f32, bx: f32, by: f32, px: f32, py: f32) -> f32 {
    (bx - ax) * (py - ay) - (by - ay) * (px - ax)
}

fn bin(v: &ScreenVerts, tris: &[[u32; 3]], width: usize, height: usize) -> Vec<Vec<u32>> {
    let n_bands = height.div_ceil(BAND);
    const CHUNK: usize = 1 << 15;
    let per_chunk: Vec<Vec<Vec<u32>>> = tris
        .par_chunks(CHUNK)
        .enumerate()
        .map(|(c, chunk)| {
            let mut bands: Vec<Vec<u32>> = vec![Vec::new(); n_bands];
            for (k, t) in chunk.iter().enumerate() {
                let [a, b, cc] = t.map(|i| i as usize);
                if !(v.valid[a] && v.valid[b] && v.valid[cc]) {
                    continue;
                }
                let (x0, x1) = (
                    v.x[a].min(v.x[b]).min(v.x[cc]),
                    v.x[a].max(v.x[b]).max(v.x[cc]),
                );
                let (y0, y1) = (
                    v.y[a].min(v.y[b]).min(v.y[cc]),
                    v.y[a].max(v.y[b]).max(v.y[cc]),
                );
                if !(x1 >= 0.0 && x0 < width as f32 && y1 >= 0.0 && y0 < height as f32) {
                    continue; // off screen (or NaN)
                }
                let b0 = (y0.max(0.0) as usize) / BAND;
                let b1 = ((y1.min(height as f32 - 1.0)) as usize) / BAND;
                for band in &mut bands[b0..=b1] {
                    band.push((c * CHUNK + k) as u32);
                }
            }
            bands
        })
        .collect();
    (0..n_bands)
        .into_par_iter()
        .map(|b| {
            let mut out = Vec::with_capacity(per_chunk.iter().map(|c| c[b].len()).sum());
            for c in &per_chunk {
                out.extend_from_slice(&c[b]);
            }
            out
        })
        .collect()
}

/// Rasterises `tris` over `v` into a `width × height` visibility buffer.
pub fn rasterize(v: &ScreenVerts, tris: &[[u32; 3]], width: usize, height: usize) -> VisBuffer {
    let bands = bin(v, tris, width, height);
    let mut depth = vec![f32::INFINITY; width * height];
    let mut tri = vec![EMPTY; width * height];
    depth
        .par_chunks_mut(BAND * width)
        .zip(tri.par_chunks_mut(BAND * width))
        .zip(bands.par_iter())
        .enumerate()
        .for_each(|(b, ((depth, ids), list))| {
            let row0 = b * BAND;
            let rows = depth.len() / width;
            for &t in list {
                let [a, bb, c] = tris[t as usize].map(|i| i as usize);
                raster_one(v, [a, bb, c], t, row0, rows, width, depth, ids);
            }
        });
    VisBuffer {
        width,
        height,
        depth,
        tri,
    }
}

#[allow(clippy::too_many_arguments)]
#[inline]
fn raster_one(
    v: &ScreenVerts,
    [a, b, c]: [usize; 3],
    id: u32,
    row0: usize,
    rows: usize,
    width: usize,
    depth: &mut [f32],
    ids: &mut [u32],
) {
    let (ax, ay, bx, by, cx, cy) = (v.x[a], v.y[a], v.x[b], v.y[b], v.x[c], v.y[c]);
    let area = edge(ax, ay, bx, by, cx, cy);
    if area == 0.0 || !area.is_finite() {
        return;
    }
    let inv = 1.0 / area;
    let (za, zb, zc) = (v.z[a], v.z[b], v.z[c]);
    let xmin = (ax.min(bx).min(cx) - 0.5).ceil().max(0.0) as usize;
    let xmax = ((ax.max(bx).max(cx) - 0.5).floor()).min(width as f32 - 1.0);
    let ymin = ((ay.min(by).min(cy) - 0.5).ceil().max(row0 as f32)) as usize;
    let ymax = ((ay.max(by).max(cy) - 0.5).floor()).min((row0 + rows) as f32 - 1.0);
    if xmax < 0.0 || ymax < 0.0 || (xmax as usize) < xmin || (ymax as usize) < ymin {
        return;
    }
    let (xmax, ymax) = (xmax as usize, ymax as usize);
    // Edge functions are affine: step them along x.
    let (dw0, dw1, dw2) = (-(cy - by) * inv, -(ay - cy) * inv, -(by - ay) * inv);
    for y in ymin..=ymax {
        let py = y as f32 + 0.5;
        let px = xmin as f32 + 0.5;
        let mut w0 = edge(bx, by, cx, cy, px, py) * inv;
        let mut w1 = edge(cx, cy, ax, ay, px, py) * inv;
        let mut w2 = edge(ax, ay, bx, by, px, py) * inv;
        let row = (y - row0) * width;
        for x in xmin..=xmax {
            if w0 >= 0.0 && w1 >= 0.0 && w2 >= 0.0 {
                let z = w0 * za + w1 * zb + w2 * zc;
                let i = row + x;
                if z < depth[i] && z >= -1.0 {
                    depth[i] = z;
                    ids[i] = id;
                }
            }
            w0 += dw0;
            w1 += dw1;
            w2 += dw2;
        }
    }
}

/// Perspective-correct barycentric weights of triangle `t` at sample centre (x, y).
#[inline]
pub fn barycentric(v: &ScreenVerts, t: [u32; 3], px: f32, py: f32) -> [f32; 3] {
    let [a, b, c] = t.map(|i| i as usize);
    let area = edge(v.x[a], v.y[a], v.x[b], v.y[b], v.x[c], v.y[c]);
    let w0 = edge(v.x[b], v.y[b], v.x[c], v.y[c], px, py) / area;
    let w1 = edge(v.x[c], v.y[c], v.x[a], v.y[a], px, py) / area;
    let w2 = 1.0 - w0 - w1;
    let (p0, p1, p2) = (w0 * v.inv_w[a], w1 * v.inv_w[b], w2 * v.inv_w[c]);
    let s = p0 + p1 + p2;
    if s.abs() > 0.0 {
        [p0 / s, p1 / s, p2 / s]
    } else {
        [w0, w1, w2]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn verts(p: &[[f32; 3]]) -> ScreenVerts {
        ScreenVerts {
            x: p.iter().map(|q| q[0]).collect(),
            y: p.iter().map(|q| q[1]).collect(),
            z: p.iter().map(|q| q[2]).collect(),
            inv_w: vec![1.0; p.len()],
            valid: vec![true; p.len()],
        }
    }

    #[test]
    fn coverage_area_and_depth_order() {
        // A 40×40 square as two triangles covers exactly 1600 samples, either winding.
        let v = verts(&[
            [10.0, 10.0, 0.5],
            [50.0, 10.0, 0.5],
            [50.0, 50.0, 0.5],
            [10.0, 50.0, 0.5],
            [0.0, 0.0, 0.0],
            [64.0, 0.0, 0.0],
            [0.0, 64.0, 0.0],
        ]);
        let vb = rasterize(&v, &[[0, 1, 2], [0, 3, 2]], 64, 64);
        assert_eq!(vb.tri.iter().filter(|&&t| t != EMPTY).count(), 1600);
        // A nearer triangle in front wins; the far square stays where it is not covered.
        let vb = rasterize(&v, &[[0, 1, 2], [0, 3, 2], [4, 5, 6]], 64, 64);
        assert_eq!(vb.tri[20 * 64 + 20], 2);
        assert_eq!(vb.tri[45 * 64 + 25], 1);
        assert_eq!(vb.tri[20 * 64 + 48], 0);
        // Equal depth: the lower index wins, whatever the order of drawing.
        let vb = rasterize(&v, &[[0, 3, 2], [0, 1, 2], [0, 1, 2]], 64, 64);
        assert_eq!(vb.tri[15 * 64 + 45], 1);
    }

    #[test]
    fn shared_edges_leave_no_gaps() {
        // A fan of thin triangles around a centre covers the disc without holes.
        let n = 97;
        let mut p = vec![[64.0f32, 64.0, 0.0]];
        for k in 0..n {
            let a = k as f32 / n as f32 * std::f32::consts::TAU;
            p.push([64.0 + 50.0 * a.cos(), 64.0 + 50.0 * a.sin(), 0.0]);
        }
        let tris: Vec<[u32; 3]> = (0..n as u32)
            .map(|k| [0, 1 + k, 1 + (k + 1) % n as u32])
            .collect();
        let vb = rasterize(&verts(&p), &tris, 128, 128);
        for y in 0..128 {
            for x in 0..128 {
                let (dx, dy) = (x as f32 + 0.5 - 64.0, y as f32 + 0.5 - 64.0);
                if (dx * dx + dy * dy).sqrt() < 48.0 {
                    assert_ne!(vb.tri[y * 128 + x], EMPTY, "hole at ({x}, {y})");
                }
            }
        }
    }
}
