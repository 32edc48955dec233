//! Mean and Gaussian curvature of a mesh at a stated scale, from osculating
//! jets: at each vertex, the quadric z = c₀ + c₁x + c₂y + c₃x² + c₄xy + c₅y²
//! fitted by least squares to the vertices within the scale, in the frame of
//! the vertex normal (Cazals & Pouget 2005, "Estimating differential
//! quantities using polynomial fitting of osculating jets", CAGD 22:121–146).
//!
//! H and K come from the fit's first and second derivatives at the vertex
//! ([`asperity_core::jet::Jet::curvatures`]), H = (κ₁ + κ₂)/2 positive where
//! the surface bends away from its normal (1/r on a sphere of radius r with
//! outward normals).
//!
//! The cotangent curvatures of [`crate::mesh::curvature`] are those of the
//! mesh's one-ring: on a reconstruction from a level set, whose triangles are
//! a fraction of a cell and follow the grid, they measure the grid as much as
//! the surface. A fit over a stated radius measures the surface at that scale,
//! and the scale is a number a report can give. The quadric reproduces a
//! quadric surface exactly; the error on a smooth surface is O(r), r the
//! scale, from the cubic terms (Cazals & Pouget, Theorem 2).

use asperity_core::TriMesh;
use asperity_core::jet::Jet;
use kiddo::SquaredEuclidean;
use kiddo::immutable::float::kdtree::ImmutableKdTree;
use rayon::prelude::*;

/// Per-vertex curvatures at a scale.
#[derive(Clone, Debug, PartialEq)]
pub struct JetCurvature {
    /// Mean curvature H = (κ₁ + κ₂)/2 per vertex (0 where no fit).
    pub mean: Vec<f64>,
    /// Gaussian curvature K = κ₁κ₂ per vertex (0 where no fit).
    pub gaussian: Vec<f64>,
    /// The radius of the fits.
    pub scale: f64,
    /// Vertices with too few neighbours or a degenerate fit.
    pub unfitted: usize,
}

/// Vertices a fit needs at least (six unknowns, and some to spare).
const MIN_NEIGHBOURS: usize = 10;

/// H and K of `m` at every vertex from jets fitted to the mesh's vertices
/// within `scale` (where fewer than ten vertices lie that near, the ten
/// nearest).
pub fn jet_curvature(m: &TriMesh, scale: f64) -> JetCurvature {
    jet_curvature_of_samples(m, m.positions(), scale)
}

/// H and K at every vertex of `m` of the surface that `samples` sample:
/// jets fitted to the samples within `scale` of the vertex (the ten nearest
/// where fewer lie that near), about the vertex, in the frame of the first
/// fit's own normal (the mesh's vertex normal starts it).
///
/// A reconstruction that stands off its points (the level-set flows that
/// arrest δ from the samples) has a surface dimpled between them at the
/// scale of the sample spacing: jets fitted to its vertices measure the
/// dimples. Fitted to the points, the quadric is the sampled surface's
/// (the moving-least-squares surface of Levin 2003), and the curvature is
/// its curvature at the point nearest the vertex along the normal.
pub fn jet_curvature_of_samples(m: &TriMesh, samples: &[[f64; 3]], scale: f64) -> JetCurvature {
    let p = m.positions();
    let normals = m.vertex_normals();
    let fitted_to_vertices = std::ptr::eq(p, samples);
    let tree: ImmutableKdTree<f64, u32, 3, 32> = ImmutableKdTree::new_from_slice(samples);
    let r2 = scale * scale;
    let fits: Vec<Option<(f64, f64)>> = (0..p.len())
        .into_par_iter()
        .map(|v| {
            let mut near: Vec<(f64, u32)> = tree
                .within_unsorted::<SquaredEuclidean>(&p[v], r2)
                .into_iter()
                .map(|n| (n.distance, n.item))
                .collect();
            if near.len() < MIN_NEIGHBOURS {
                let k = std::num::NonZero::new(MIN_NEIGHBOURS).expect("ten");
                near = tree
                    .nearest_n::<SquaredEuclidean>(&p[v], k)
                    .into_iter()
                    .map(|n| (n.distance, n.item))
                    .collect();
            }
            // A fixed order: the sums do not depend on the tree's visiting order.
            near.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            let reach = near.last().map_or(0.0, |n| n.0.sqrt()).max(1e-300);
            let pts: Vec<[f64; 3]> = near.iter().map(|n| samples[n.1 as usize]).collect();
            let n = asperity_core::vec3::unit(normals[v])?;
            if pts.len() < MIN_NEIGHBOURS {
                return None;
            }
            let jet = Jet::fit(p[v], n, pts.iter().copied(), reach)?;
            if fitted_to_vertices {
                return Some(jet.curvatures());
            }
            // The samples' own normal, not the dimpled mesh's.
            let n = asperity_core::vec3::unit(jet.normal())?;
            Jet::fit(p[v], n, pts, reach).map(|j| j.curvatures())
        })
        .collect();
    let unfitted = fits.iter().filter(|f| f.is_none()).count();
    let (mean, gaussian) = fits.into_iter().map(|f| f.unwrap_or((0.0, 0.0))).unzip();
    JetCurvature {
        mean,
        gaussian,
        scale,
        unfitted,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A UV sphere of radius `r`, outward normals.
    fn sphere(r: f64, n: usize) -> TriMesh {
        let mut pos = vec![[0.0, 0.0, r], [0.0, 0.0, -r]];
        for i in 1..n {
            let t = std::f64::consts::PI * i as f64 / n as f64;
            for j in 0..2 * n {
                let f = std::f64::consts::PI * j as f64 / n as f64;
                pos.push([r * t.sin() * f.cos(), r * t.sin() * f.sin(), r * t.cos()]);
            }
        }
        let ring = |i: usize, j: usize| (2 + (i - 1) * 2 * n + j % (2 * n)) as u32;
        let mut tri = Vec::new();
        for j in 0..2 * n {
            tri.push([0, ring(1, j), ring(1, j + 1)]);
            tri.push([1, ring(n - 1, j + 1), ring(n - 1, j)]);
            for i in 1..n - 1 {
                tri.push([ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)]);
                tri.push([ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)]);
            }
        }
        TriMesh::new(pos, tri).unwrap()
    }

    /// H = 1/r and K = 1/r² on a sphere, at any scale well below r.
    #[test]
    fn a_sphere_has_its_analytic_curvatures() {
        let r = 2.0;
        let m = sphere(r, 80);
        for scale in [0.1, 0.3] {
            let c = jet_curvature(&m, scale);
            assert_eq!(c.unfitted, 0);
            for (h, k) in c.mean.iter().zip(&c.gaussian) {
                assert!((h * r - 1.0).abs() < 0.01, "H = {h} at scale {scale}");
                assert!((k * r * r - 1.0).abs() < 0.02, "K = {k} at scale {scale}");
            }
        }
    }

    /// A mesh dimpled at a small scale (a sphere of radius 1.03 whose radius
    /// ripples by ±0.01 every few degrees, like a front standing off its
    /// samples) measured against random samples of the unit sphere: the
    /// samples' H = 1 and K = 1, where the mesh's own jets measure the ripples.
    #[test]
    fn samples_give_their_surface_s_curvature_on_a_dimpled_mesh() {
        use rand::{Rng, SeedableRng};
        let smooth = sphere(1.0, 120);
        let rippled: Vec<[f64; 3]> = smooth
            .positions()
            .iter()
            .map(|p| {
                let bump = 0.01 * (60.0 * p[0]).sin() * (60.0 * p[1]).sin() * (60.0 * p[2]).cos();
                p.map(|x| x * (1.03 + bump))
            })
            .collect();
        let m = TriMesh::new(rippled, smooth.triangles().to_vec()).unwrap();
        let seed: u64 = rand::random();
        let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
        let samples: Vec<[f64; 3]> = (0..40_000)
            .map(|_| {
                loop {
                    let v: [f64; 3] = std::array::from_fn(|_| rng.random::<f64>() * 2.0 - 1.0);
                    let r = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                    if r > 0.1 && r <= 1.0 {
                        break v.map(|x| x / r);
                    }
                }
            })
            .collect();
        let median = |mut v: Vec<f64>| {
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        };
        let c = jet_curvature_of_samples(&m, &samples, 0.1);
        assert_eq!(c.unfitted, 0);
        let within = c.mean.iter().filter(|h| (*h - 1.0).abs() < 0.1).count();
        assert!(
            within as f64 >= 0.95 * c.mean.len() as f64,
            "seed {seed}: {within}"
        );
        let (h, k) = (median(c.mean), median(c.gaussian));
        assert!(
            (h - 1.0).abs() < 0.02 && (k - 1.0).abs() < 0.04,
            "seed {seed}: {h} {k}"
        );
        let own = jet_curvature(&m, 0.1);
        let off = own
            .mean
            .iter()
            .filter(|h| (*h - 1.0 / 1.03).abs() > 0.1)
            .count();
        assert!(
            off as f64 > 0.2 * own.mean.len() as f64,
            "the ripples: {off}"
        );
    }

    /// A saddle z = (x² − y²)/2 at its centre: H = 0, K = −1.
    #[test]
    fn a_saddle_has_negative_gaussian_curvature() {
        let n = 41;
        let at = |i: usize| -1.0 + 2.0 * i as f64 / (n - 1) as f64;
        let mut pos = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let (x, y) = (at(i), at(j));
                pos.push([x, y, 0.5 * (x * x - y * y)]);
            }
        }
        let mut tri = Vec::new();
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                let v = (i + n * j) as u32;
                let n = n as u32;
                tri.push([v, v + 1, v + n + 1]);
                tri.push([v, v + n + 1, v + n]);
            }
        }
        let m = TriMesh::new(pos, tri).unwrap();
        let c = jet_curvature(&m, 0.2);
        let centre = n / 2 + n * (n / 2);
        assert!(c.mean[centre].abs() < 1e-9, "H = {}", c.mean[centre]);
        assert!(
            (c.gaussian[centre] + 1.0).abs() < 1e-9,
            "K = {}",
            c.gaussian[centre]
        );
    }
}
