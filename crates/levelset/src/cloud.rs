//! What a point cloud is, read off each point's k nearest neighbours: its
//! typical spacing, whether it samples a surface or fills a deposit, its
//! outliers, and its noise removed by local quadric fits.
//!
//! kim-machiraju-thompson reconstruct two kinds of point sets (§5–6): the
//! occupied cells of a growth simulation (Figs. 8–11), whose surface is the
//! boundary of the solid the points fill, and a sampled surface, the bunny of
//! Fig. 7, whose points lie *on* the surface. A scan or a random sample of a
//! surface is the second kind, and it comes with what a simulation never has:
//! gaps several spacings wide between random samples, holes, noise and
//! outliers. This module measures which kind a cloud is and cleans a sampled
//! surface before the level set sees it.
//!
//! * **Spacing**: the median distance from a point to its nearest neighbour
//!   (the typical sample spacing).
//! * **Flatness**: the median over points of the surface variation
//!   λ₀/(λ₀ + λ₁ + λ₂) of the covariance of their k neighbours (Pauly, Gross &
//!   Kobbelt 2002, "Efficient simplification of point-sampled surfaces", §3):
//!   0 for points on a plane, 1/3 for points filling a volume. Samples of a
//!   smooth surface measure below 0.01 (0.04 with Gaussian noise of one
//!   spacing per coordinate); growth deposits measure 0.10 (a DLA terrain),
//!   0.15 (a DLA cluster) and 0.30 (an RDSR shell), so
//!   [`SURFACE_FLATNESS`] separates them.
//! * **Outliers**: a point whose mean distance to its k neighbours exceeds
//!   [`OUTLIER_RATIO`] times the median of the same measure over those
//!   neighbours (a local test, so a scan's fall-off of density is no outlier;
//!   after the statistical outlier removal of Rusu et al. 2008, made local),
//!   or [`GLOBAL_OUTLIER_RATIO`] times the median over all points (outliers
//!   strewn through a volume are one another's neighbours); and, for a
//!   denoised surface, a point farther from the quadric of its neighbours
//!   (below) than a sample spacing and [`RESIDUAL_RATIO`] robust standard
//!   deviations of its neighbours' distances to theirs (a stray near the
//!   surface, which the distance tests pass as noise).
//! * **Denoising**: each point moves to the value at its own position of the
//!   quadric z = c₀ + c₁x + c₂y + c₃x² + c₄xy + c₅y² fitted by least squares to
//!   its neighbours in the frame of their covariance (or of the input normal):
//!   one step of the osculating-jet projection (Cazals & Pouget 2005,
//!   "Estimating differential quantities using polynomial fitting of
//!   osculating jets"). A quadric surface is reproduced exactly, so a clean
//!   sample of a smooth surface barely moves (10⁻⁶ of the radius on a unit
//!   sphere of 5 000 random points), and noise across the surface is averaged
//!   over the k neighbours.
//!
//! The k-nearest-neighbour queries use `kiddo`'s immutable k-d tree; every
//! point's computation reads only the tree, so the result does not depend on
//! the thread count.

use std::num::NonZero;

use asperity_core::Progress;
use asperity_core::jet::Jet;
use asperity_core::vec3::{add, dist, scale as vscale, unit};
use kiddo::SquaredEuclidean;
use kiddo::immutable::float::kdtree::ImmutableKdTree;
use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

/// A k-d tree over points, items the point indices.
pub type Tree = ImmutableKdTree<f64, u32, 3, 32>;

/// Below this median surface variation a cloud samples a surface; above it
/// the points fill a deposit (see the module docs for the measured values).
pub const SURFACE_FLATNESS: f64 = 0.06;

/// A point is an outlier when its mean distance to its neighbours is this many
/// times the median of theirs.
pub const OUTLIER_RATIO: f64 = 3.0;

/// A point is an outlier when its mean distance to its neighbours is this many
/// times the median over all points: outliers scattered through a volume are
/// each other's neighbours, so the local test alone passes them.
pub const GLOBAL_OUTLIER_RATIO: f64 = 5.0;

/// A point is a stray when its distance to the quadric of its neighbours is
/// more than this many robust standard deviations (1.4826 × the median of
/// its neighbours' distances to theirs) and more than a sample spacing.
pub const RESIDUAL_RATIO: f64 = 4.0;

/// Neighbours of each point for every measure (k).
pub const NEIGHBOURS: usize = 24;

/// Bytes per point the analysis holds at its peak: the k + 1 neighbours' ids
/// and squared distances (12 bytes each), the k-d tree, the per-point
/// measures and the moved copy (measured: 2.6 GB for 5 million points with
/// the rest of a 512-cell reconstruction).
pub const BYTES_PER_POINT: u64 = 12 * (NEIGHBOURS as u64 + 1) + 120;

/// Points handed to one task of the neighbour queries.
const CHUNK: usize = 1024;

/// The k-d tree over `points`.
pub fn tree(points: &[[f64; 3]]) -> Tree {
    ImmutableKdTree::new_from_slice(points)
}

/// The `k` nearest points of `q` in `tree` (itself first when `q` is a point
/// of the tree), nearest first, with their squared distances.
pub fn nearest(tree: &Tree, q: &[f64; 3], k: usize) -> Vec<(f64, u32)> {
    let k = NonZero::new(k.max(1)).expect("k ≥ 1");
    tree.nearest_n::<SquaredEuclidean>(q, k)
        .into_iter()
        .map(|n| (n.distance, n.item))
        .collect()
}

/// What [`analyze`] found.
#[derive(Clone, Debug, PartialEq)]
pub struct Cloud {
    /// The points kept, denoised when asked: what the level set reconstructs.
    pub points: Vec<[f64; 3]>,
    /// The median nearest-neighbour distance of the points given.
    pub spacing: f64,
    /// The median surface variation λ₀/(λ₀ + λ₁ + λ₂) over k neighbours.
    pub flatness: f64,
    /// Points dropped as outliers.
    pub outliers: usize,
    /// The median and the largest distance a point moved when denoised (0
    /// when not denoised).
    pub moved: (f64, f64),
}

impl Cloud {
    /// Whether the points sample a surface (flatness below [`SURFACE_FLATNESS`]).
    pub fn is_surface(&self) -> bool {
        self.flatness < SURFACE_FLATNESS
    }
}

/// Per point: its k neighbours (itself first) and their squared distances.
struct Neighbourhoods {
    k: usize,
    items: Vec<u32>,
    d2: Vec<f64>,
}

impl Neighbourhoods {
    fn of(tree: &Tree, points: &[[f64; 3]], k: usize, progress: &dyn Progress) -> Self {
        let k = k.min(points.len());
        progress.start(points.len().div_ceil(CHUNK) as u64, "neighbours");
        let chunks: Vec<(Vec<u32>, Vec<f64>)> = points
            .par_chunks(CHUNK)
            .map(|ps| {
                let mut items = Vec::with_capacity(ps.len() * k);
                let mut d2 = Vec::with_capacity(ps.len() * k);
                for p in ps {
                    for (d, i) in nearest(tree, p, k) {
                        items.push(i);
                        d2.push(d);
                    }
                }
                progress.advance(1);
                (items, d2)
            })
            .collect();
        progress.finish();
        let (items, d2) =
            chunks
                .into_iter()
                .fold((Vec::new(), Vec::new()), |(mut a, mut b), (x, y)| {
                    a.extend(x);
                    b.extend(y);
                    (a, b)
                });
        Self { k, items, d2 }
    }

    fn items(&self, i: usize) -> &[u32] {
        &self.items[i * self.k..(i + 1) * self.k]
    }

    fn d2(&self, i: usize) -> &[f64] {
        &self.d2[i * self.k..(i + 1) * self.k]
    }

    /// Mean distance to the neighbours other than the point itself.
    fn mean_distance(&self, i: usize) -> f64 {
        let d = &self.d2(i)[1..];
        d.iter().map(|x| x.sqrt()).sum::<f64>() / d.len().max(1) as f64
    }
}

/// The median of `v` (0 for none).
fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    let mid = v.len() / 2;
    *v.select_nth_unstable_by(mid, f64::total_cmp).1
}

/// The covariance frame of `pts` about their centroid: eigenvalues ascending
/// and the matching unit eigenvectors (the first is the normal).
fn frame(pts: impl Iterator<Item = [f64; 3]> + Clone) -> ([f64; 3], [Vector3<f64>; 3]) {
    let n = pts.clone().count().max(1) as f64;
    let c = pts
        .clone()
        .fold(Vector3::zeros(), |a, p| a + Vector3::from(p))
        / n;
    let cov = pts.fold(Matrix3::zeros(), |a, p| {
        let d = Vector3::from(p) - c;
        a + d * d.transpose()
    }) / n;
    let e = cov.symmetric_eigen();
    let mut order = [0, 1, 2];
    order.sort_by(|&a, &b| e.eigenvalues[a].total_cmp(&e.eigenvalues[b]));
    (
        order.map(|i| e.eigenvalues[i].max(0.0)),
        order.map(|i| e.eigenvectors.column(i).into_owned()),
    )
}

/// The unoriented normal of the `points` at `at`: the least eigenvector of
/// the covariance of its `k` nearest (Hoppe et al. 1992, "Surface
/// reconstruction from unorganized points"). Unlike a jet's, it needs no
/// frame to start from: it holds where the sheet lies along a guess.
pub fn pca_normal(tree: &Tree, points: &[[f64; 3]], at: &[f64; 3], k: usize) -> Option<[f64; 3]> {
    let hood = nearest(tree, at, k);
    if hood.len() < 3 {
        return None;
    }
    let (_, axes) = frame(hood.iter().map(|&(_, j)| points[j as usize]));
    let n = axes[0];
    n.iter().all(|c| c.is_finite()).then(|| [n.x, n.y, n.z])
}

/// The surface variation λ₀/(λ₀ + λ₁ + λ₂) of eigenvalues `l` (ascending).
fn variation(l: [f64; 3]) -> f64 {
    let s = l[0] + l[1] + l[2];
    if s > 0.0 { l[0] / s } else { 0.0 }
}

/// Point `i` moved onto the quadric fitted to its neighbours `nb` (itself
/// among them) in the frame whose normal is `normal` (or the covariance's):
/// the jet projection of the module docs. `None` where the fit is degenerate.
fn jet_projection(
    points: &[[f64; 3]],
    i: usize,
    nb: &[u32],
    normal: Option<[f64; 3]>,
) -> Option<[f64; 3]> {
    if nb.len() < 10 {
        return None;
    }
    let pts = nb.iter().map(|&j| points[j as usize]);
    let n = match normal {
        Some(n) => unit(n)?,
        None => frame(pts.clone()).1[0].into(),
    };
    let p = points[i];
    let scale = pts.clone().map(|q| dist(q, p)).fold(0.0, f64::max);
    let jet = Jet::fit(p, n, pts, scale)?;
    Some(add(p, vscale(n, jet.height())))
}

/// Measures `points` (with their `normals`, when the file had them) and, for a
/// sampled surface, drops the outliers and denoises the rest when `denoise`.
/// `surface`: `Some` forces the kind, `None` measures it.
pub fn analyze(
    points: &[[f64; 3]],
    normals: Option<&[[f64; 3]]>,
    surface: Option<bool>,
    denoise: bool,
    progress: &dyn Progress,
) -> Cloud {
    let tree = tree(points);
    let hood = Neighbourhoods::of(&tree, points, NEIGHBOURS + 1, progress);
    let n = points.len();
    let spacing = median(
        (0..n)
            .filter_map(|i| hood.d2(i).get(1).map(|d| d.sqrt()))
            .collect(),
    );
    let flatness = median(
        (0..n)
            .into_par_iter()
            .map(|i| variation(frame(hood.items(i).iter().map(|&j| points[j as usize])).0))
            .collect(),
    );
    let mut cloud = Cloud {
        points: points.to_vec(),
        spacing,
        flatness,
        outliers: 0,
        moved: (0.0, 0.0),
    };
    if !surface.unwrap_or(cloud.is_surface()) || hood.k < 11 {
        return cloud;
    }
    let keep = distance_inliers(&hood, n);
    if !denoise {
        cloud.outliers = keep.iter().filter(|k| !**k).count();
        cloud.points = (0..n).filter(|&i| keep[i]).map(|i| points[i]).collect();
        return cloud;
    }
    let (keep, moved) = denoised(points, normals, &hood, keep, spacing);
    cloud.outliers = keep.iter().filter(|k| !**k).count();
    let shifts: Vec<f64> = (0..n).filter(|&i| keep[i]).map(|i| moved[i].1).collect();
    cloud.moved = (
        median(shifts.clone()),
        shifts.iter().fold(0.0, |a: f64, &b| a.max(b)),
    );
    cloud.points = (0..n).filter(|&i| keep[i]).map(|i| moved[i].0).collect();
    cloud
}

/// Per point, whether it passes the distance tests of the module docs (local
/// and global).
fn distance_inliers(hood: &Neighbourhoods, n: usize) -> Vec<bool> {
    let mean: Vec<f64> = (0..n)
        .into_par_iter()
        .map(|i| hood.mean_distance(i))
        .collect();
    let global = median(mean.clone());
    (0..n)
        .into_par_iter()
        .map(|i| {
            let local = median(
                hood.items(i)[1..]
                    .iter()
                    .map(|&j| mean[j as usize])
                    .collect(),
            );
            !(mean[i] > OUTLIER_RATIO * local || mean[i] > GLOBAL_OUTLIER_RATIO * global)
        })
        .collect()
}

/// Each kept point moved onto its neighbours' quadric, with the distance it
/// moved, in two passes: the first's distances find the stray points near the
/// surface that the distance tests passed (dropped from `keep`), the second
/// fits without them.
fn denoised(
    points: &[[f64; 3]],
    normals: Option<&[[f64; 3]]>,
    hood: &Neighbourhoods,
    mut keep: Vec<bool>,
    spacing: f64,
) -> (Vec<bool>, Vec<([f64; 3], f64)>) {
    let n = points.len();
    let fit = |keep: &[bool]| -> Vec<([f64; 3], f64)> {
        (0..n)
            .into_par_iter()
            .map(|i| {
                if !keep[i] {
                    return (points[i], f64::NAN);
                }
                let nb: Vec<u32> = hood
                    .items(i)
                    .iter()
                    .copied()
                    .filter(|&j| keep[j as usize])
                    .collect();
                let to = jet_projection(points, i, &nb, normals.map(|v| v[i])).unwrap_or(points[i]);
                (to, dist(to, points[i]))
            })
            .collect()
    };
    let first = fit(&keep);
    let strays: Vec<bool> = (0..n)
        .into_par_iter()
        .map(|i| {
            if !keep[i] {
                return false;
            }
            let local = median(
                hood.items(i)[1..]
                    .iter()
                    .filter(|&&j| keep[j as usize])
                    .map(|&j| first[j as usize].1)
                    .collect(),
            );
            first[i].1 > (RESIDUAL_RATIO * 1.4826 * local).max(spacing)
        })
        .collect();
    for (k, s) in keep.iter_mut().zip(&strays) {
        *k &= !s;
    }
    let second = fit(&keep);
    (keep, second)
}

/// What [`project`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Projection {
    /// Vertices moved.
    pub moved: usize,
    /// The median and the largest move.
    pub shift: (f64, f64),
}

/// Moves each vertex of `positions` (with unit `normals`) along its normal
/// onto the quadric fitted to its [`NEIGHBOURS`] nearest `points`, in the
/// frame of the normal: the moving-least-squares projection of point-set
/// surfaces (Levin 2003; Alexa et al. 2003, "Computing and rendering point
/// set surfaces"), with the osculating jet of the module docs as the local
/// surface. The level set places its front on the samples to a fraction of a
/// cell, and flat across the gaps between them (a chord, inside a convex
/// surface); the quadric carries the surface's curvature across the gap.
/// Vertices farther than `support` from every point (spanning a hole) stay,
/// and so do a vertex whose move would exceed `max_move` and the vertices
/// flagged in `skip` (when it is not empty).
pub fn project(
    positions: &mut [[f64; 3]],
    normals: &[[f64; 3]],
    points: &[[f64; 3]],
    (support, max_move): (f64, f64),
    skip: &[bool],
) -> Projection {
    let tree = tree(points);
    let k = NEIGHBOURS.min(points.len());
    let moves: Vec<Option<[f64; 3]>> = positions
        .par_iter()
        .zip(normals)
        .enumerate()
        .map(|(i, (v, n))| {
            if skip.get(i).copied().unwrap_or(false) {
                return None;
            }
            let near = nearest(&tree, v, k);
            if near.first().is_none_or(|f| f.0.sqrt() > support) || near.len() < 10 {
                return None;
            }
            let n = unit(*n)?;
            let scale = near.last().map_or(0.0, |l| l.0.sqrt());
            let neighbours = near.iter().map(|&(_, j)| points[j as usize]);
            let shift = Jet::fit(*v, n, neighbours, scale)?.height();
            (shift.abs() <= max_move).then(|| add(*v, vscale(n, shift)))
        })
        .collect();
    let mut shifts = Vec::new();
    for (v, m) in positions.iter_mut().zip(moves) {
        if let Some(m) = m {
            shifts.push(dist(m, *v));
            *v = m;
        }
    }
    Projection {
        moved: shifts.len(),
        shift: (
            median(shifts.clone()),
            shifts.iter().fold(0.0, |a: f64, &b| a.max(b)),
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use asperity_core::NoProgress;
    use rand::{Rng, SeedableRng};

    fn sphere(n: usize, seed: u64) -> Vec<[f64; 3]> {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        (0..n)
            .map(|_| {
                loop {
                    let v: [f64; 3] = std::array::from_fn(|_| rng.random::<f64>() * 2.0 - 1.0);
                    let r = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                    if r > 0.1 && r <= 1.0 {
                        break v.map(|x| x / r);
                    }
                }
            })
            .collect()
    }

    /// A random sample of the unit sphere is a surface; its spacing is the
    /// Poisson value √(ln 2/(πρ)); a clean sample barely moves.
    #[test]
    fn a_random_sphere_sample_is_a_surface_that_stays_put() {
        let pts = sphere(5000, 3);
        let c = analyze(&pts, None, None, true, &NoProgress);
        assert!(c.is_surface(), "flatness {}", c.flatness);
        let rho = 5000.0 / (4.0 * std::f64::consts::PI);
        let poisson = (std::f64::consts::LN_2 / (std::f64::consts::PI * rho)).sqrt();
        assert!(
            (c.spacing / poisson - 1.0).abs() < 0.05,
            "{} vs {poisson}",
            c.spacing
        );
        assert_eq!(c.outliers, 0);
        assert!(c.moved.1 < 1e-4, "moved {:?}", c.moved);
    }

    /// Noise across the surface is averaged away; far points are outliers.
    #[test]
    fn noise_is_reduced_and_far_points_dropped() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
        let clean = sphere(20_000, 4);
        let sigma = 0.012;
        let mut noisy: Vec<[f64; 3]> = clean
            .iter()
            .map(|p| {
                p.map(|x| {
                    // Box–Muller.
                    let (u, v): (f64, f64) = (rng.random(), rng.random());
                    x + sigma * (-2.0 * (1.0 - u).ln()).sqrt() * (std::f64::consts::TAU * v).cos()
                })
            })
            .collect();
        let far: Vec<[f64; 3]> = (0..100)
            .map(|_| std::array::from_fn(|_| rng.random::<f64>() * 1.6 - 0.8))
            .collect();
        noisy.extend(&far);
        let c = analyze(&noisy, None, None, true, &NoProgress);
        assert!(c.is_surface(), "flatness {}", c.flatness);
        // Those within about ten spacings of the sphere pass as noise.
        assert!((60..=100).contains(&c.outliers), "outliers {}", c.outliers);
        let rms = |ps: &[[f64; 3]]| {
            (ps.iter()
                .map(|p| ((p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 1.0).powi(2))
                .sum::<f64>()
                / ps.len() as f64)
                .sqrt()
        };
        let before = rms(&noisy[..clean.len()]);
        let after = rms(&c.points);
        assert!(after < 0.4 * before, "rms {before} → {after}");
    }

    /// Points filling a solid ball are no surface.
    #[test]
    fn a_filled_lattice_is_a_deposit() {
        let mut pts = Vec::new();
        for x in -8i32..=8 {
            for y in -8i32..=8 {
                for z in -8i32..=8 {
                    if x * x + y * y + z * z <= 64 {
                        pts.push([x, y, z].map(f64::from));
                    }
                }
            }
        }
        let c = analyze(&pts, None, None, true, &NoProgress);
        assert!(!c.is_surface(), "flatness {}", c.flatness);
        assert_eq!(c.points, pts, "a deposit is used as it is");
    }
}
