//! Alternating-diagonal triangular facets and the interpolation consistent with them.
//!
//! Paper: [peridier] §"How VisualizeFacetSurface Works" (Figure 7: column → x,
//! row → y, value → z; the diagonal of each grid cell alternates so interior nodes
//! belong to 4 or 8 facets) and §"TriangulatedInterpolation" (Figure 8: the four
//! cases by diagonal parity and side of the diagonal; Figure 9: a circle drawn on
//! the surface).
//!
//! Nodes of cell (i, j) are numbered counter-clockwise from node 1 = (i, j):
//! 2 = (i+1, j), 3 = (i+1, j+1), 4 = (i, j+1). With (u, v) the offsets of the
//! point from node 1 in cell units:
//!
//! | i + j | side | triangle | z |
//! | --- | --- | --- | --- |
//! | even (diagonal 1–3) | below, v ≤ u | 1, 2, 3 | z₁ + u(z₂ − z₁) + v(z₃ − z₂) |
//! | even | above, v > u | 1, 3, 4 | z₁ + u(z₃ − z₄) + v(z₄ − z₁) |
//! | odd (diagonal 2–4) | below, u + v ≤ 1 | 1, 2, 4 | z₁ + u(z₂ − z₁) + v(z₄ − z₁) |
//! | odd | above, u + v > 1 | 2, 3, 4 | z₃ + (1 − u)(z₄ − z₃) + (1 − v)(z₂ − z₃) |
//!
//! This is exactly the facet set of `HeightField::to_trimesh(Diagonal::Alternating)`.
//!
//! [peridier]: https://www.mathematica-journal.com/2011/07/facetsurface-representation/ "Peridier: Rough-Surface Simulation and the Visualization of Nonsmooth Arrays of Data. The Mathematica Journal, 2011"

use asperity_core::{Diagonal, HeightField, TriMesh};
use rayon::prelude::*;

use crate::CaError;

/// The facet mesh: with `flat`, every facet gets its own three vertices carrying
/// the facet normal, so any viewer shades it flat (as the paper's figures); else
/// nodes are shared (2(nx−1)(ny−1) triangles over nx·ny vertices).
///
/// # Errors
/// [`CaError::Core`] for NaN heights or grids smaller than 2×2.
pub fn facet_mesh(h: &HeightField, flat: bool) -> Result<TriMesh, CaError> {
    let shared = h
        .to_trimesh(Diagonal::Alternating)?
        .with_scalar("height", h.measured_values())?;
    if !flat {
        return Ok(shared);
    }
    let normals = shared.face_normals();
    let mut p = Vec::with_capacity(3 * shared.n_faces());
    let mut n = Vec::with_capacity(3 * shared.n_faces());
    let mut z = Vec::with_capacity(3 * shared.n_faces());
    for (t, nn) in shared.triangles().iter().zip(normals) {
        for &v in t {
            let q = shared.positions()[v as usize];
            p.push(q);
            n.push(nn);
            z.push(q[2]);
        }
    }
    let tris = (0..shared.n_faces() as u32)
        .map(|f| [3 * f, 3 * f + 1, 3 * f + 2])
        .collect();
    Ok(TriMesh::new(p, tris)?
        .with_normals(n)?
        .with_scalar("height", z)?)
}

/// z at physical (x, y) on the facets, `None` outside the grid, on a facet
/// with a missing corner (a NaN height), or for a grid smaller than 2×2.
pub fn interpolate(h: &HeightField, x: f64, y: f64) -> Option<f64> {
    let [nx, ny] = h.dims();
    if nx < 2 || ny < 2 || !x.is_finite() || !y.is_finite() {
        return None;
    }
    let [dx, dy] = h.spacing();
    let [x0, y0] = h.origin();
    // Snap to nodes within rounding of x0 + i·dx, so nodes give their heights exactly.
    let snap = |g: f64| {
        if (g - g.round()).abs() < 1e-9 {
            g.round()
        } else {
            g
        }
    };
    let (gu, gv) = (snap((x - x0) / dx), snap((y - y0) / dy));
    let eps = 1e-9;
    if gu < -eps || gv < -eps || gu > (nx - 1) as f64 + eps || gv > (ny - 1) as f64 + eps {
        return None;
    }
    let i = (gu.floor().max(0.0) as usize).min(nx - 2);
    let j = (gv.floor().max(0.0) as usize).min(ny - 2);
    let (u, v) = (
        (gu - i as f64).clamp(0.0, 1.0),
        (gv - j as f64).clamp(0.0, 1.0),
    );
    let z = |a: usize, b: usize| *h.get(a, b);
    let (z1, z2, z3, z4) = (z(i, j), z(i + 1, j), z(i + 1, j + 1), z(i, j + 1));
    // The table's formulas, written as barycentric sums so nodes come out exactly.
    let z = if (i + j).is_multiple_of(2) {
        if v <= u {
            (1.0 - u) * z1 + (u - v) * z2 + v * z3
        } else {
            (1.0 - v) * z1 + u * z3 + (v - u) * z4
        }
    } else if u + v <= 1.0 {
        (1.0 - u - v) * z1 + u * z2 + v * z4
    } else {
        (1.0 - v) * z2 + (u + v - 1.0) * z3 + (1.0 - u) * z4
    };
    (!z.is_nan()).then_some(z)
}

/// [`interpolate`] over many points, in parallel.
pub fn interpolate_many(h: &HeightField, points: &[[f64; 2]]) -> Vec<Option<f64>> {
    points
        .par_iter()
        .map(|p| interpolate(h, p[0], p[1]))
        .collect()
}

/// A polyline in the (x, y) plane lifted onto the facets: every segment is split
/// where it crosses a grid line or a facet diagonal, so the 3-D polyline lies
/// exactly on the surface.
///
/// # Errors
/// [`CaError::BadInit`] if a point lies outside the grid.
pub fn drape(h: &HeightField, xy: &[[f64; 2]]) -> Result<Vec<[f64; 3]>, CaError> {
    let [dx, dy] = h.spacing();
    let [x0, y0] = h.origin();
    let to_grid = |p: [f64; 2]| [(p[0] - x0) / dx, (p[1] - y0) / dy];
    let mut out = Vec::new();
    for (s, seg) in xy.windows(2).enumerate() {
        let (a, b) = (to_grid(seg[0]), to_grid(seg[1]));
        let mut ts = vec![0.0, 1.0];
        // Crossings with u = k, v = k, u − v = even k, u + v = even k.
        let lines: [(f64, f64, i64); 4] =
            [(1.0, 0.0, 1), (0.0, 1.0, 1), (1.0, -1.0, 2), (1.0, 1.0, 2)];
        for (cu, cv, step) in lines {
            let fa = cu * a[0] + cv * a[1];
            let fb = cu * b[0] + cv * b[1];
            if fa == fb {
                continue;
            }
            let (lo, hi) = (fa.min(fb), fa.max(fb));
            let mut k = (lo / step as f64).ceil() as i64 * step;
            while (k as f64) <= hi {
                ts.push((k as f64 - fa) / (fb - fa));
                k += step;
            }
        }
        ts.sort_by(f64::total_cmp);
        ts.dedup_by(|p, q| (*p - *q).abs() < 1e-12);
        for (n, &t) in ts.iter().enumerate() {
            if s > 0 && n == 0 {
                continue; // shared with the previous segment's end
            }
            let (x, y) = (
                seg[0][0] + t * (seg[1][0] - seg[0][0]),
                seg[0][1] + t * (seg[1][1] - seg[0][1]),
            );
            let z = interpolate(h, x, y).ok_or_else(|| {
                CaError::BadInit(format!(
                    "curve point ({x}, {y}) is outside the height field"
                ))
            })?;
            out.push([x, y, z]);
        }
    }
    Ok(out)
}

/// A closed circle of `n` points (first point repeated at the end), as in the
/// paper's Figure 9.
pub fn circle(cx: f64, cy: f64, r: f64, n: usize) -> Vec<[f64; 2]> {
    (0..=n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            [cx + r * a.cos(), cy + r * a.sin()]
        })
        .collect()
}
