//! Output for users: the original mesh with the cells packed into a texture
//! atlas, so a glTF or OBJ opens in Blender with the pattern in place; or the
//! cells themselves as a mesh, optionally displaced by a per-cell thickness.
//!
//! Each triangle's cell grid becomes one chart of the atlas, one pixel per cell
//! (the cell (i, j) is pixel (i, j) of its chart), with a one-pixel border;
//! charts are packed on shelves, tallest first. The triangle's UVs are its corner
//! positions in its own plane frame divided by h, so the texture is exactly the
//! cell grid — no resampling. Pixels of OUT-CELL squares and borders are filled
//! from the nearest cell of the same chart, so filtering does not bleed other
//! charts in. The mesh is split per triangle (each triangle has its own chart).

use asperity_core::{CoreError, MemoryBudget, RgbaImage, TriMesh};

use crate::cells::Cells;

/// Where each triangle's chart sits in the atlas (top-left corner, with its
/// one-pixel border), and the atlas' width and height.
struct Layout {
    offset: Vec<(usize, usize)>,
    width: usize,
    height: usize,
}

/// Shelf packing of the charts, tallest first.
fn layout(cells: &Cells) -> Layout {
    let grids = &cells.grids;
    let mut order: Vec<usize> = (0..grids.len()).collect();
    order.sort_by_key(|&t| (std::cmp::Reverse(grids[t].ny), t));
    let area: usize = grids.iter().map(|g| (g.nx + 2) * (g.ny + 2)).sum();
    let widest = grids.iter().map(|g| g.nx + 2).max().unwrap_or(1);
    let width = ((area as f64 * 1.15).sqrt().ceil() as usize).max(widest);
    let mut offset = vec![(0usize, 0usize); grids.len()];
    let (mut x, mut y, mut shelf) = (0usize, 0usize, 0usize);
    for &t in &order {
        let (w, h) = (grids[t].nx + 2, grids[t].ny + 2);
        if x + w > width {
            x = 0;
            y += shelf;
            shelf = 0;
        }
        offset[t] = (x, y);
        x += w;
        shelf = shelf.max(h);
    }
    Layout {
        offset,
        width,
        height: y + shelf,
    }
}

/// Fills the empty pixels of chart `t` (OUT-CELLs and the border) from its
/// nearest cell, breadth first, so filtering does not bleed other charts in.
fn fill_chart(img: &mut RgbaImage, filled: &mut [bool], at: &Layout, cells: &Cells, t: usize) {
    let g = &cells.grids[t];
    let (ox, oy) = at.offset[t];
    let (w, h) = (g.nx + 2, g.ny + 2);
    let mut frontier: Vec<(usize, usize)> = (0..h)
        .flat_map(|yy| (0..w).map(move |xx| (ox + xx, oy + yy)))
        .filter(|&(px, py)| filled[py * at.width + px])
        .collect();
    while !frontier.is_empty() {
        let mut next = Vec::new();
        for &(px, py) in &frontier {
            let col = img.get(px as u32, py as u32);
            for (dx, dy) in [
                (1i64, 0i64),
                (-1, 0),
                (0, 1),
                (0, -1),
                (1, 1),
                (-1, -1),
                (1, -1),
                (-1, 1),
            ] {
                let (qx, qy) = (px as i64 + dx, py as i64 + dy);
                if qx < ox as i64
                    || qy < oy as i64
                    || qx >= (ox + w) as i64
                    || qy >= (oy + h) as i64
                {
                    continue;
                }
                let k = qy as usize * at.width + qx as usize;
                if !filled[k] {
                    filled[k] = true;
                    img.put(qx as u32, qy as u32, col);
                    next.push((qx as usize, qy as usize));
                }
            }
        }
        frontier = next;
    }
}

/// The atlas image: one pixel per cell in its chart, empty pixels filled.
fn atlas_image(cells: &Cells, at: &Layout, color: impl Fn(usize) -> [u8; 4]) -> RgbaImage {
    let mut img = RgbaImage::filled(at.width as u32, at.height as u32, [0, 0, 0, 0]);
    let mut filled = vec![false; at.width * at.height];
    for c in 0..cells.len() {
        let (ox, oy) = at.offset[cells.triangle[c] as usize];
        let [i, j] = cells.ij[c];
        let (px, py) = (ox + 1 + i as usize, oy + 1 + j as usize);
        img.put(px as u32, py as u32, color(c));
        filled[py * at.width + px] = true;
    }
    for t in 0..cells.grids.len() {
        fill_chart(&mut img, &mut filled, at, cells, t);
    }
    img
}

/// The mesh with one chart per triangle and the atlas as its texture.
///
/// # Errors
/// [`CoreError::MemoryLimit`] when the atlas exceeds `budget`; mesh errors.
pub fn atlas_mesh(
    mesh: &TriMesh,
    cells: &Cells,
    color: impl Fn(usize) -> [u8; 4],
    budget: &MemoryBudget,
) -> Result<TriMesh, CoreError> {
    let at = layout(cells);
    let (width, height) = (at.width, at.height);
    budget.check_elements(width as u128 * height as u128, 4 + 4, "the texture atlas")?;
    let img = atlas_image(cells, &at, color);
    // Split the mesh: three corners per triangle with their chart UVs.
    let pos = mesh.positions();
    let normals = mesh.vertex_normals();
    let mut p = Vec::with_capacity(3 * mesh.n_faces());
    let mut n = Vec::with_capacity(3 * mesh.n_faces());
    let mut uv = Vec::with_capacity(3 * mesh.n_faces());
    let mut tris = Vec::with_capacity(mesh.n_faces());
    for (t, tri) in mesh.triangles().iter().enumerate() {
        let g = &cells.grids[t];
        let (ox, oy) = at.offset[t];
        for (k, &v) in tri.iter().enumerate() {
            let l = g.local[k];
            let px = ox as f64 + 1.0 + (l[0] - g.x0) / cells.h;
            let py = oy as f64 + 1.0 + l[1] / cells.h;
            p.push(pos[v as usize]);
            n.push(normals[v as usize]);
            // v = 0 is the bottom row (the crate-wide UV convention).
            uv.push([px / width as f64, 1.0 - py / height as f64]);
        }
        let b = 3 * t as u32;
        tris.push([b, b + 1, b + 2]);
    }
    Ok(TriMesh::new(p, tris)?
        .with_normals(n)?
        .with_uvs(uv)?
        .with_texture(img))
}

fn barycentric_normal(mesh: &TriMesh, normals: &[[f64; 3]], t: usize, q: [f64; 3]) -> [f64; 3] {
    let tri = mesh.triangles()[t].map(|v| v as usize);
    let p = mesh.positions();
    let [a, b, c] = tri.map(|v| p[v]);
    let sub = |x: [f64; 3], y: [f64; 3]| [x[0] - y[0], x[1] - y[1], x[2] - y[2]];
    let cross = |x: [f64; 3], y: [f64; 3]| {
        [
            x[1] * y[2] - x[2] * y[1],
            x[2] * y[0] - x[0] * y[2],
            x[0] * y[1] - x[1] * y[0],
        ]
    };
    let n = cross(sub(b, a), sub(c, a));
    let dot = |x: [f64; 3]| x[0] * n[0] + x[1] * n[1] + x[2] * n[2];
    let total = dot(n);
    let w0 = dot(cross(sub(b, q), sub(c, q))) / total;
    let w1 = dot(cross(sub(c, q), sub(a, q))) / total;
    let w2 = 1.0 - w0 - w1;
    let m: [f64; 3] = std::array::from_fn(|k| {
        w0 * normals[tri[0]][k] + w1 * normals[tri[1]][k] + w2 * normals[tri[2]][k]
    });
    let l = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
    if l > 0.0 {
        m.map(|x| x / l)
    } else {
        let l = total.sqrt();
        n.map(|x| x / l)
    }
}

/// Thickness at every polygon corner (in [`Cells::polygon`] order, flattened):
/// the mean over the cells meeting at that point; on a triangle edge, the mean
/// of that and the cell across the edge at the same point (gobron-chiba Figure
/// 20: the two sides' surfaces are averaged on the edge).
pub fn corner_thickness(cells: &Cells, thickness: &[f64]) -> Vec<f64> {
    let key = |p: [f64; 3]| p.map(|x| (x / (cells.h * 1e-6)).round() as i64);
    let mut sums: std::collections::HashMap<[i64; 3], (f64, u32)> =
        std::collections::HashMap::new();
    for (c, &th) in thickness.iter().enumerate().take(cells.len()) {
        for &q in cells.polygon(c) {
            let e = sums.entry(key(q)).or_insert((0.0, 0));
            e.0 += th;
            e.1 += 1;
        }
    }
    let mut out = Vec::new();
    for c in 0..cells.len() {
        let t = cells.triangle[c] as usize;
        let f = &cells.frames[t];
        for &q in cells.polygon(c) {
            let (s, n) = sums[&key(q)];
            let own = s / n as f64;
            let local = f.to_local(q);
            let on_edge: Vec<usize> = (0..3)
                .filter(|&e| f.edge_inside(local, e).abs() <= 1e-9 * cells.h)
                .collect();
            let value = match on_edge.as_slice() {
                [e] => {
                    let (va, vb) = (f.verts[*e], f.verts[(*e + 1) % 3]);
                    let other = cells
                        .edge_map
                        .get(&(va.min(vb), va.max(vb)))
                        .and_then(|l| l.iter().find(|(tt, _)| *tt as usize != t))
                        .and_then(|&(tt, _)| {
                            let g = &cells.frames[tt as usize];
                            let lq = g.to_local(q);
                            // The point is on g's edge: clamp rounding just outside its grid.
                            let i = (((lq[0] - g.x0) / cells.h).floor() as i64)
                                .clamp(0, g.nx as i64 - 1);
                            let j = ((lq[1] / cells.h).floor() as i64).clamp(0, g.ny as i64 - 1);
                            g.get(i, j).or_else(|| {
                                // On the boundary of the other grid: a neighbouring square.
                                (-1..=1)
                                    .flat_map(|dj| (-1..=1).map(move |di| (di, dj)))
                                    .find_map(|(di, dj)| g.get(i + di, j + dj))
                            })
                        });
                    match other {
                        Some(o) => 0.5 * (own + thickness[o as usize]),
                        None => own,
                    }
                }
                _ => own,
            };
            out.push(value);
        }
    }
    out
}

/// The cells as a mesh: each cell's part of its triangle, fan-triangulated, in
/// one flat colour (the cells tile the surface exactly), with normals
/// interpolated from the input mesh's vertex normals. With `displace =
/// Some((thickness, scale))` every corner moves along that normal by
/// `scale × ` [`corner_thickness`].
///
/// # Errors
/// Mesh construction errors; a thickness slice of the wrong length.
pub fn cell_mesh(
    mesh: &TriMesh,
    cells: &Cells,
    color: impl Fn(usize) -> [u8; 4],
    displace: Option<(&[f64], f64)>,
) -> Result<TriMesh, CoreError> {
    let normals = mesh.vertex_normals();
    let corner = match displace {
        Some((t, _)) => {
            if t.len() != cells.len() {
                return Err(CoreError::LengthMismatch {
                    what: "thickness".into(),
                    got: t.len(),
                    expected: cells.len(),
                });
            }
            Some(corner_thickness(cells, t))
        }
        None => None,
    };
    let scale = displace.map_or(0.0, |(_, s)| s);
    let mut pos = Vec::new();
    let mut tris = Vec::new();
    let mut cols = Vec::new();
    let mut ns = Vec::new();
    for c in 0..cells.len() {
        let poly = cells.polygon(c);
        let base = pos.len() as u32;
        let t = cells.triangle[c] as usize;
        for &q in poly {
            let n = barycentric_normal(mesh, &normals, t, q);
            let d = corner.as_ref().map_or(0.0, |ct| scale * ct[pos.len()]);
            pos.push([q[0] + d * n[0], q[1] + d * n[1], q[2] + d * n[2]]);
            ns.push(n);
        }
        cols.extend(std::iter::repeat_n(color(c), poly.len()));
        for k in 1..poly.len() as u32 - 1 {
            tris.push([base, base + k, base + k + 1]);
        }
    }
    let m = TriMesh::new(pos, tris)?.with_colors(cols)?;
    Ok(if displace.is_some() {
        m.with_computed_normals()
    } else {
        m.with_normals(ns)?
    })
}
