//! Discrete curvature of triangle meshes, with Gauss–Bonnet as a self-check.
//!
//! - Gaussian curvature K_v = (2π − Σ angles at v) / A_v for interior vertices
//!   (angle defect; boundary vertices use π − Σ angles, the geodesic-curvature
//!   part of Gauss–Bonnet), with A_v the barycentric area (a third of the
//!   incident triangle areas). Σ_v K_v A_v = 2πχ holds exactly for a closed mesh.
//! - Mean curvature H_v = ½ |Δx|_v signed against the vertex normal, from the
//!   cotangent Laplacian (Meyer, Desbrun, Schröder & Barr 2003), positive on a
//!   sphere with outward normals.

use asperity_core::TriMesh;
use asperity_core::vec3::{cross, dot, sub};
use rayon::prelude::*;
use rustc_hash::FxHashSet;
use serde::Serialize;

/// Per-vertex curvatures and the Gauss–Bonnet sums.
#[derive(Clone, Debug, PartialEq)]
pub struct Curvature {
    /// Gaussian curvature per vertex.
    pub gaussian: Vec<f64>,
    /// Mean curvature per vertex.
    pub mean: Vec<f64>,
    /// Barycentric vertex areas.
    pub area: Vec<f64>,
    /// Σ K_v A_v (total Gaussian curvature including boundary turning).
    pub total_gaussian: f64,
}

/// Summary statistics of a per-vertex quantity, weighted by vertex area.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Stats {
    /// Area-weighted mean.
    pub mean: f64,
    /// Area-weighted standard deviation.
    pub std: f64,
    /// Minimum.
    pub min: f64,
    /// Maximum.
    pub max: f64,
}

/// Area-weighted statistics of `values`.
pub fn stats(values: &[f64], weights: &[f64]) -> Stats {
    let wsum: f64 = weights.iter().sum::<f64>().max(1e-300);
    let mean = values.iter().zip(weights).map(|(v, w)| v * w).sum::<f64>() / wsum;
    let var = values
        .iter()
        .zip(weights)
        .map(|(v, w)| w * (v - mean).powi(2))
        .sum::<f64>()
        / wsum;
    let (min, max) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    Stats {
        mean,
        std: var.sqrt(),
        min,
        max,
    }
}

/// Curvatures of `m` (see the module docs).
pub fn curvature(m: &TriMesh) -> Curvature {
    let p = m.positions();
    let n = p.len();
    let mut angle_sum = vec![0.0f64; n];
    let mut area = vec![0.0f64; n];
    let mut lap = vec![[0.0f64; 3]; n];
    for t in m.triangles() {
        let [i, j, k] = t.map(|v| v as usize);
        let ta = 0.5
            * dot(
                cross(sub(p[j], p[i]), sub(p[k], p[i])),
                cross(sub(p[j], p[i]), sub(p[k], p[i])),
            )
            .sqrt();
        for (a, b, c) in [(i, j, k), (j, k, i), (k, i, j)] {
            let (u, v) = (sub(p[b], p[a]), sub(p[c], p[a]));
            let cl = dot(cross(u, v), cross(u, v)).sqrt();
            angle_sum[a] += cl.atan2(dot(u, v));
            area[a] += ta / 3.0;
            if cl > 1e-300 {
                let cot = dot(u, v) / cl;
                let e = sub(p[c], p[b]);
                for d in 0..3 {
                    lap[b][d] += 0.5 * cot * e[d];
                    lap[c][d] -= 0.5 * cot * e[d];
                }
            }
        }
    }
    let on_boundary = {
        let mut b = vec![false; n];
        for [u, v] in m.boundary_edges() {
            b[u as usize] = true;
            b[v as usize] = true;
        }
        b
    };
    let normals = m.vertex_normals();
    let mut gaussian = vec![0.0; n];
    let mut mean = vec![0.0; n];
    let mut total = 0.0;
    for v in 0..n {
        if area[v] <= 0.0 {
            continue;
        }
        let full = if on_boundary[v] {
            std::f64::consts::PI
        } else {
            std::f64::consts::TAU
        };
        let defect = full - angle_sum[v];
        total += defect;
        gaussian[v] = defect / area[v];
        let hn = lap[v].map(|c| c / area[v]);
        let h = 0.5 * dot(hn, hn).sqrt();
        mean[v] = if dot(hn, normals[v]) > 0.0 { -h } else { h };
    }
    Curvature {
        gaussian,
        mean,
        area,
        total_gaussian: total,
    }
}

/// Roughness relative to a smoothed copy of the mesh.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Roughness {
    /// Root-mean-square vertex displacement to the smoothed copy (area-weighted).
    pub rms: f64,
    /// Largest displacement.
    pub max: f64,
    /// Taubin iterations used.
    pub iterations: usize,
}

/// Taubin λ|μ smoothing (λ = 0.5, μ = −0.53, uniform Laplacian; Taubin 1995), which
/// removes high-frequency relief without the shrinkage of plain Laplacian smoothing.
/// Boundary vertices stay fixed.
pub fn taubin(m: &TriMesh, iterations: usize) -> Vec<[f64; 3]> {
    let n = m.n_vertices();
    let mut nbr: Vec<Vec<u32>> = vec![Vec::new(); n];
    for e in m.edges() {
        nbr[e.lo as usize].push(e.hi);
        nbr[e.hi as usize].push(e.lo);
    }
    let mut fixed = vec![false; n];
    for [a, b] in m.boundary_edges() {
        fixed[a as usize] = true;
        fixed[b as usize] = true;
    }
    let mut p = m.positions().to_vec();
    for _ in 0..iterations {
        for factor in [0.5, -0.53] {
            let next: Vec<[f64; 3]> = (0..n)
                .map(|v| {
                    if fixed[v] || nbr[v].is_empty() {
                        return p[v];
                    }
                    let k = nbr[v].len() as f64;
                    let mean = [0, 1, 2]
                        .map(|a| nbr[v].iter().map(|&u| p[u as usize][a]).sum::<f64>() / k);
                    [0, 1, 2].map(|a| p[v][a] + factor * (mean[a] - p[v][a]))
                })
                .collect();
            p = next;
        }
    }
    p
}

/// Vertex displacement from `m` to its Taubin-smoothed copy: rms (weighted by
/// vertex area) and max.
pub fn smoothed_roughness(m: &TriMesh, iterations: usize) -> Roughness {
    let s = taubin(m, iterations);
    let c = curvature(m);
    let d: Vec<f64> = m
        .positions()
        .iter()
        .zip(&s)
        .map(|(p, q)| dot(sub(*p, *q), sub(*p, *q)).sqrt())
        .collect();
    let w: f64 = c.area.iter().sum::<f64>().max(1e-300);
    let rms = (d.iter().zip(&c.area).map(|(x, a)| a * x * x).sum::<f64>() / w).sqrt();
    Roughness {
        rms,
        max: d.iter().copied().fold(0.0, f64::max),
        iterations,
    }
}

/// Calls `mark` on points covering the triangle so that every point of it
/// lies within `step` of one: along segments from the corner opposite the
/// shortest edge to points spread along that edge (at most `step` apart at
/// the edge), each segment sampled at most `step` apart. A triangle costs
/// about (1 + shortest/step)(longest/step) points: a long thin one about its
/// length over `step`, like its area over step² for a fat one.
fn sample_triangle(tri: [[f64; 3]; 3], step: f64, mark: &mut impl FnMut([f64; 3])) {
    let len = |u: [f64; 3], v: [f64; 3]| dot(sub(u, v), sub(u, v)).sqrt();
    let edges = [
        len(tri[1], tri[2]),
        len(tri[2], tri[0]),
        len(tri[0], tri[1]),
    ];
    if !edges.iter().all(|e| e.is_finite()) || step.is_nan() || step <= 0.0 {
        tri.into_iter().for_each(&mut *mark);
        return;
    }
    let k = (0..3)
        .min_by(|&x, &y| edges[x].total_cmp(&edges[y]))
        .expect("three edges");
    let [apex, p, q] = [tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]];
    let lerp = |u: [f64; 3], v: [f64; 3], s: f64| [0, 1, 2].map(|x| u[x] + s * (v[x] - u[x]));
    // Segments to the base's points at (i + ½)/m: at most step/2 across.
    let m = (edges[k] / step).ceil().max(1.0) as usize;
    for i in 0..m {
        let base = lerp(p, q, (i as f64 + 0.5) / m as f64);
        let n = (len(apex, base) / step).ceil().max(1.0) as usize;
        for j in 0..=n {
            mark(lerp(apex, base, j as f64 / n as f64));
        }
    }
    mark(p);
    mark(q);
}

/// Box-counting dimension of the surface: points sampled on every triangle at a
/// spacing of a quarter of the finest box, then the occupied boxes counted at box
/// sizes from 1/8 to 1/128 of the bounding-box diagonal; D = −slope of log N
/// against log s.
///
/// # Errors
/// [`crate::AnalysisError::BadInput`] for an empty or degenerate mesh.
pub fn box_counting(m: &TriMesh) -> Result<crate::fractal::Dimension, crate::AnalysisError> {
    let b = m
        .bounds()
        .ok_or_else(|| crate::AnalysisError::BadInput("empty mesh".into()))?;
    let diag = b.diagonal();
    if m.n_faces() == 0 || diag <= 0.0 {
        return Err(crate::AnalysisError::BadInput(
            "the mesh has no extent".into(),
        ));
    }
    let sizes: Vec<f64> = (3..=7).map(|k| diag / (1u32 << k) as f64).collect();
    let step = sizes[sizes.len() - 1] / 4.0;
    // Occupied boxes of the finest size, filled as the sample points are made
    // (memory follows the boxes, not the samples). The sizes halve from one to
    // the next on one grid origin, so a coarser box is a finest key halved.
    let finest = sizes[sizes.len() - 1];
    // Per chunk of triangles on every core, then merged: a set's union does
    // not depend on the order, so neither do the counts. Consecutive samples
    // mostly fall in the box before (four to a box along a segment): only a
    // new box is looked up.
    let occupied: FxHashSet<[i64; 3]> = m
        .triangles()
        .par_chunks(256)
        .map(|chunk| {
            let mut boxes = FxHashSet::default();
            let mut last = [i64::MIN; 3];
            for t in chunk {
                sample_triangle(t.map(|v| m.positions()[v as usize]), step, &mut |p| {
                    let key = [0, 1, 2].map(|x| ((p[x] - b.min[x]) / finest).floor() as i64);
                    if key != last {
                        boxes.insert(key);
                        last = key;
                    }
                });
            }
            boxes
        })
        .reduce(FxHashSet::default, |a, b| {
            let (mut big, small) = if a.len() >= b.len() { (a, b) } else { (b, a) };
            big.extend(small);
            big
        });
    let levels = sizes.len();
    let counts: Vec<f64> = (0..levels)
        .map(|i| {
            let shift = (levels - 1 - i) as u32;
            let coarse: FxHashSet<[i64; 3]> =
                occupied.iter().map(|k| k.map(|v| v >> shift)).collect();
            coarse.len() as f64
        })
        .collect();
    let fit = crate::psd::log_fit(&sizes, &counts, [sizes[sizes.len() - 1], sizes[0]])?;
    Ok(crate::fractal::Dimension { d: -fit.slope, fit })
}
