//! What a reconstruction is worth against its points (#52): how far the
//! surface lies from the input, which of it spans holes in the data (and,
//! asked to stay open, the surface without them), and its curvature at a
//! stated scale.
//!
//! * **Distance to the points**: for every vertex, the distance to the
//!   nearest input point (a k-d tree over the points, `kiddo`): mean, 95th
//!   percentile and maximum, in the points' units and in grid cells.
//! * **Holes closed**: a triangle whose three vertices all lie farther than
//!   the support distance t from every input point spans a hole in the data
//!   (a gap between random samples, a scan's hole, the open side of a partial
//!   scan); connected such triangles are one hole, reported by count, area and
//!   radius (the largest vertex distance in it). t is two sample spacings
//!   (median nearest-neighbour distance), at least 1.5h; below it the surface
//!   is within reach of the samples around it. `--open` removes these
//!   triangles, so a partial scan keeps its boundary. Of the thin closed
//!   shell the level set wraps around a sheet sampled from one side (a
//!   terrain patch, a one-sided range scan) it first removes the far side and
//!   the rim (the vertices not in front of their points along the points'
//!   normals: the file's, else oriented by Hoppe's spanning tree to point up
//!   in sum, `asperity_levelset::orient`), then projects the near side, δ in
//!   front of the points, onto them (the points' quadrics, as the flow's own
//!   vertices are), and only then looks for holes.
//! * **Specks**: on a sampled surface, pieces with fewer than
//!   [`SPECK_FRACTION`] of the largest piece's triangles — the front closing
//!   around a stray point the cloud's outlier tests kept — are dropped.
//! * **Curvature**: mean and Gaussian curvature from jets fitted within the
//!   curvature scale (`asperity_analysis::jets`), by default three sample
//!   spacings and at least 3.5h ([`default_curvature_scale`]): on a sampled
//!   surface, jets fitted to the input points about each vertex (the same for
//!   every flow: the convection and regularised fronts stand δ off the points,
//!   dimpled between them, and their vertices' own jets measure the dimples);
//!   on a deposit, jets fitted to the mesh's vertices.

use asperity_analysis::jets::{jet_curvature, jet_curvature_of_samples};
use asperity_core::TriMesh;
use asperity_core::tri_mesh::component_labels;
use asperity_core::vec3::{cross, dot, norm, sub, unit};
use asperity_levelset::cloud::{Tree, nearest, tree};
use asperity_levelset::orient::oriented_normals;
use asperity_levelset::{Reconstruction, project_onto};
use rayon::prelude::*;
use serde::Serialize;

use crate::error::Result;

/// Distances from the output's vertices to the nearest input point.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Distances {
    /// Mean, in the points' units.
    pub mean: f64,
    /// 95th percentile.
    pub p95: f64,
    /// Largest.
    pub max: f64,
    /// The three in grid cells (mean, p95, max).
    pub in_h: [f64; 3],
}

/// Holes in the data that the surface spans.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Holes {
    /// Connected patches of triangles farther than `support` from every point.
    pub count: usize,
    /// Their area.
    pub area: f64,
    /// The largest patch's radius: its vertices' largest distance to the points.
    pub largest_radius: f64,
    /// The support distance t.
    pub support: f64,
    /// Whether they were removed (`--open`).
    pub removed: bool,
}

/// What [`finish`] measured.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Quality {
    /// Vertex-to-point distances.
    pub distance_to_points: Distances,
    /// The holes spanned.
    pub holes: Holes,
    /// The curvature fits' radius, when curvature was asked for.
    pub curvature_scale: Option<f64>,
    /// With `--open`: the triangles removed from the far side of thin parts
    /// and open surfaces (the level set wraps a sheet in a thin closed shell).
    pub thin_sides_removed: usize,
    /// With `--open`: the vertices of the sheet's near side moved onto the
    /// points' quadrics (the shell stands δ off a sheet's points).
    pub sheet_vertices_projected: usize,
}

/// The typical spacing of the points reconstructed: the cloud's median
/// nearest-neighbour distance where it was measured, else the level set's
/// sample spacing, else h.
pub fn typical_spacing(rec: &Reconstruction) -> f64 {
    rec.cloud
        .spacing
        .or(rec.sample_spacing)
        .unwrap_or(rec.grid.spacing)
}

/// The largest curvature scale accepted, in grid cells: the fits' cost grows
/// with the square of the scale in cells (some 800 vertices a fit at 16).
pub const MAX_CURVATURE_CELLS: f64 = 16.0;

/// The curvature fits' radius when none is given: three sample spacings, and
/// at least 3.5h — the mesh's own texture is a fraction of a cell (measured on
/// the sphere of 20 000 random points: at 2.5h 69 % of the vertices have H
/// within 15 % of 1, at 3.2h all of them).
pub fn default_curvature_scale(spacing: f64, h: f64) -> f64 {
    (3.0 * spacing).max(3.5 * h)
}

/// Per vertex of `m`, the distance to the nearest of the points in `t`.
fn vertex_distances(m: &TriMesh, t: &Tree) -> Vec<f64> {
    nearest_points(m, t).into_iter().map(|n| n.0).collect()
}

/// A vertex's distance to its nearest input point, and the point's index.
type NearestPoint = (f64, u32);

/// Per vertex of `m`, the distance to the nearest of the points in `t` and its index.
fn nearest_points(m: &TriMesh, t: &Tree) -> Vec<NearestPoint> {
    m.positions()
        .par_iter()
        .map(|p| {
            nearest(t, p, 1)
                .first()
                .map_or((f64::INFINITY, u32::MAX), |n| (n.0.sqrt(), n.1))
        })
        .collect()
}

/// The triangles on the far side and around the rim of a thin part or an
/// open surface. The level set wraps a sheet sampled from one side (a range
/// scan, a terrain patch) in a thin closed shell δ off its points: two sides,
/// where the offset from a vertex to its nearest point lies along the sheet's
/// normal, one way or the other, joined at the rim, where it lies along the
/// sheet. With the points' normals consistently oriented (the file's, else
/// [`oriented_normals`] pointing up in sum, +z: a terrain's top, a scan's
/// upper side), the far side is where the offset points against the normal
/// and the rim where it is within 60° of the sheet. Each side is the sheet
/// once projected onto its points, so on a sheet standing on edge either
/// serves. A triangle with a vertex on the far side or the rim is dropped.
fn back_of_thin(
    m: &TriMesh,
    thin: &[bool],
    (input, near, t): (&[[f64; 3]], &[NearestPoint], &Tree),
    normals: Option<&[[f64; 3]]>,
) -> Vec<bool> {
    if !thin.iter().any(|t| *t) {
        return vec![false; m.n_faces()];
    }
    let oriented;
    let normals = match normals {
        Some(n) => n,
        None => {
            oriented = oriented_normals(input, t, [0.0, 0.0, 1.0]);
            &oriented
        }
    };
    let p = m.positions();
    let behind: Vec<bool> = (0..p.len())
        .into_par_iter()
        .map(|v| {
            if !thin.get(v).copied().unwrap_or(false) {
                return false;
            }
            let q = near[v].1 as usize;
            let (Some(s), Some(n)) = (input.get(q), normals.get(q)) else {
                return false;
            };
            unit(sub(p[v], *s)).is_none_or(|o| dot(o, *n) < 0.5)
        })
        .collect();
    m.triangles()
        .iter()
        .map(|t| t.iter().any(|&v| behind[v as usize]))
        .collect()
}

fn summary(d: &[f64], h: f64) -> Distances {
    if d.is_empty() {
        return Distances::default();
    }
    let mut s = d.to_vec();
    s.sort_unstable_by(f64::total_cmp);
    let mean = s.iter().sum::<f64>() / s.len() as f64;
    let p95 = s[((s.len() - 1) as f64 * 0.95).round() as usize];
    let max = s[s.len() - 1];
    Distances {
        mean,
        p95,
        max,
        in_h: [mean / h, p95 / h, max / h],
    }
}

/// The triangles of `m` that span holes (every vertex farther than `support`).
fn spanning(m: &TriMesh, dist: &[f64], support: f64) -> Vec<bool> {
    m.triangles()
        .iter()
        .map(|t| t.iter().all(|&v| dist[v as usize] > support))
        .collect()
}

fn holes(m: &TriMesh, dist: &[f64], span: &[bool], support: f64) -> Holes {
    let tris: Vec<[u32; 3]> = m
        .triangles()
        .iter()
        .zip(span)
        .filter_map(|(t, &s)| s.then_some(*t))
        .collect();
    let (count, labels) = component_labels(m.n_vertices(), &tris);
    let mut radius = vec![0.0f64; count];
    let mut area = 0.0;
    let p = m.positions();
    for t in &tris {
        let l = labels[t[0] as usize] as usize;
        for &v in t {
            radius[l] = radius[l].max(dist[v as usize]);
        }
        let [a, b, c] = t.map(|v| p[v as usize]);
        area += 0.5 * norm(cross(sub(b, a), sub(c, a)));
    }
    Holes {
        count,
        area,
        largest_radius: radius.into_iter().fold(0.0, f64::max),
        support,
        removed: false,
    }
}

/// Pieces of a sampled surface's reconstruction with fewer triangles than this
/// fraction of the largest are specks around stray points the cloud's tests
/// kept, and are dropped (counted with the level set's removed shells).
pub const SPECK_FRACTION: f64 = 0.005;

fn drop_specks(rec: &mut Reconstruction) -> Result<()> {
    let m = &rec.mesh;
    let (count, labels) = component_labels(m.n_vertices(), m.triangles());
    if count < 2 {
        return Ok(());
    }
    let mut size = vec![0usize; count];
    for t in m.triangles() {
        size[labels[t[0] as usize] as usize] += 1;
    }
    let largest = size.iter().copied().max().unwrap_or(0);
    let keep = |l: u32| size[l as usize] as f64 >= SPECK_FRACTION * largest as f64;
    let drop: Vec<bool> = m
        .triangles()
        .iter()
        .map(|t| !keep(labels[t[0] as usize]))
        .collect();
    let dropped = (0..count).filter(|&l| !keep(l as u32)).count();
    if dropped > 0 {
        let (kept, origin) = without_mapped(m, &drop)?;
        rec.mesh = kept;
        rec.thin_vertices = remapped(&rec.thin_vertices, &origin);
        rec.extraction.shells_removed += dropped;
    }
    Ok(())
}

/// Per-vertex flags carried to the vertices `origin` kept (empty stays
/// empty: no vertex flagged).
fn remapped(flags: &[bool], origin: &[u32]) -> Vec<bool> {
    if flags.is_empty() {
        return Vec::new();
    }
    origin
        .iter()
        .map(|&v| flags.get(v as usize).copied().unwrap_or(false))
        .collect()
}

/// `m` without the triangles flagged in `drop` (and the vertices only they
/// used), with each kept vertex's index in `m`.
fn without_mapped(m: &TriMesh, drop: &[bool]) -> Result<(TriMesh, Vec<u32>)> {
    let mut map = vec![u32::MAX; m.n_vertices()];
    let mut origin = Vec::new();
    let mut tris = Vec::new();
    for (t, &d) in m.triangles().iter().zip(drop) {
        if d {
            continue;
        }
        tris.push(t.map(|v| {
            if map[v as usize] == u32::MAX {
                map[v as usize] = origin.len() as u32;
                origin.push(v);
            }
            map[v as usize]
        }));
    }
    let kept = m.with_vertices_from(&origin, tris)?;
    Ok((kept, origin))
}

/// Measures `rec` against the `input` points it came from; with `open`,
/// removes the triangles that span holes; with `curvature` = `Some(scale)`
/// (`None` inside: the default scale), stores `mean_curvature` and
/// `gaussian_curvature` per vertex.
///
/// # Errors
/// None in practice (the mesh's own indices).
pub fn finish(
    rec: &mut Reconstruction,
    (input, normals): (&[[f64; 3]], Option<&[[f64; 3]]>),
    open: bool,
    curvature: Option<Option<f64>>,
) -> Result<Quality> {
    let h = rec.grid.spacing;
    let spacing = typical_spacing(rec);
    if rec.cloud.surface {
        drop_specks(rec)?;
    }
    let t = tree(input);
    let near = nearest_points(&rec.mesh, &t);
    let dist: Vec<f64> = near.iter().map(|n| n.0).collect();
    let support = (2.0 * spacing).max(1.5 * h);
    let span = spanning(&rec.mesh, &dist, support);
    let mut holes = holes(&rec.mesh, &dist, &span, support);
    let mut quality = Quality {
        distance_to_points: summary(&dist, h),
        ..Quality::default()
    };
    if open {
        let back = back_of_thin(&rec.mesh, &rec.thin_vertices, (input, &near, &t), normals);
        quality.thin_sides_removed = back.iter().filter(|b| **b).count();
        if quality.thin_sides_removed > 0 {
            // The sheet's near side, δ in front of its points, onto them.
            let (front, origin) = without_mapped(&rec.mesh, &back)?;
            rec.thin_vertices = remapped(&rec.thin_vertices, &origin);
            let reach = rec.voids.as_ref().map_or(0.0, |v| v.thin_radius) + h;
            let skip: Vec<bool> = rec.thin_vertices.iter().map(|t| !t).collect();
            rec.mesh = front;
            if let Some(p) = project_onto(&mut rec.mesh, input, (reach + h, reach), &skip) {
                quality.sheet_vertices_projected = p.moved;
            }
        }
        let dist = vertex_distances(&rec.mesh, &t);
        let span = spanning(&rec.mesh, &dist, support);
        holes = self::holes(&rec.mesh, &dist, &span, support);
        if span.iter().any(|d| *d) {
            let (kept, origin) = without_mapped(&rec.mesh, &span)?;
            rec.mesh = kept;
            rec.thin_vertices = remapped(&rec.thin_vertices, &origin);
            holes.removed = holes.count > 0;
        }
        if quality.thin_sides_removed > 0 || holes.removed {
            quality.distance_to_points = summary(&vertex_distances(&rec.mesh, &t), h);
        }
    }
    quality.holes = holes;
    if let Some(scale) = curvature {
        let scale = scale.unwrap_or_else(|| default_curvature_scale(spacing, h));
        // A sampled surface's curvature is the points' (every flow: the
        // convection and regularised fronts stand δ off them, dimpled
        // between samples); a deposit's is its surface's.
        let c = if rec.cloud.surface {
            jet_curvature_of_samples(&rec.mesh, input, scale)
        } else {
            jet_curvature(&rec.mesh, scale)
        };
        let mesh = std::mem::replace(&mut rec.mesh, TriMesh::new(Vec::new(), Vec::new())?);
        rec.mesh = mesh
            .with_scalar("mean_curvature", c.mean)?
            .with_scalar("gaussian_curvature", c.gaussian)?;
        quality.curvature_scale = Some(scale);
    }
    Ok(quality)
}
