//! The fractal dimension of a DLA deposit about its substrate
//! (kim-machiraju-thompson §7: DLA grown on a sphere or on any object).
//!
//! About a seed of many cells R_g(n) ∝ n^{1/D} measures the seed, not the
//! deposit, so the mass is counted by distance from the seed's *surface*: the
//! exact Euclidean distance transform of the seed's solid (the one the curved
//! depositions use) sorts every lattice cell around it into shells one cell
//! thick, z ∈ (k − 1, k]. The shell's density is the share of its lattice cells
//! a particle holds, and its radius is volume-equivalent — r(z) with
//! (4π/3) r³ = the seed's volume plus every cell within z of it (π r² in 2-D) —
//! so that for a ball r is the distance from its centre, and far from any seed
//! the shells become spheres. A cluster of dimension D has ρ(r) ∝ r^{D − d}
//! (d = 2 or 3), the point-seed mass–radius law M ∝ r^D in differential form.
//!
//! [`shell_profile`] gives the profile; the fit (in `asperity_analysis`) runs
//! from the seed's radius + 5 cells to where the cluster thins, taken as half
//! the particles' radius of gyration about the seed's centroid (the upper bound
//! the point-seed mass–radius fit uses).

use asperity_core::MemoryBudget;

use super::{DlaCluster, SeedShape, ball_cells};
use crate::GrowthError;
use crate::curved::distance_transform;

/// Density by volume-equivalent radius around a seed (see the module docs).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ShellProfile {
    /// 2 or 3.
    pub dim: usize,
    /// The seed's volume-equivalent radius (cells).
    pub seed_radius: f64,
    /// The particles' radius of gyration about the seed's centroid.
    pub gyration: f64,
    /// Where the cluster thins: half of `gyration`.
    pub thin_radius: f64,
    /// Volume-equivalent radius of each shell's middle.
    pub radius: Vec<f64>,
    /// Particles per lattice cell in each shell.
    pub density: Vec<f64>,
    /// Whether the lattice boundary cut the shells short (the profile then stops
    /// where it was whole).
    pub clipped: bool,
}

impl ShellProfile {
    /// The fit window: [seed radius + 5, thin radius].
    pub fn fit_range(&self) -> [f64; 2] {
        [self.seed_radius + 5.0, self.thin_radius]
    }
}

/// The volume-equivalent radius of `volume` cells in `dim` dimensions.
fn equivalent_radius(volume: f64, dim: usize) -> f64 {
    if dim == 3 {
        (3.0 * volume / (4.0 * std::f64::consts::PI)).cbrt()
    } else {
        (volume / std::f64::consts::PI).sqrt()
    }
}

/// The shell profile of a cluster grown from a sphere or from given cells;
/// `None` for point, plane and image seeds, or below 256 particles.
///
/// # Errors
/// The memory budget (the distance transform covers the seed's box widened by
/// the thin radius).
pub fn shell_profile(
    c: &DlaCluster,
    seed: &SeedShape,
    budget: &MemoryBudget,
) -> Result<Option<ShellProfile>, GrowthError> {
    let solid = match seed {
        SeedShape::Sphere(r) => ball_cells(c.center, *r, c.dim == 3),
        SeedShape::Cells(v) => v.clone(),
        _ => return Ok(None),
    };
    let particles = c.particles();
    if solid.is_empty() || particles.len() < 256 {
        return Ok(None);
    }
    let n = solid.len() as f64;
    let g: [f64; 3] =
        std::array::from_fn(|a| solid.iter().map(|p| f64::from(p[a])).sum::<f64>() / n);
    let gyration = (particles
        .iter()
        .map(|p| {
            (0..3)
                .map(|a| (f64::from(p[a]) - g[a]).powi(2))
                .sum::<f64>()
        })
        .sum::<f64>()
        / particles.len() as f64)
        .sqrt();
    let thin_radius = 0.5 * gyration;
    // A shell at distance z has volume-equivalent radius ≥ z, so every shell
    // the fit uses lies within the thin radius of the seed.
    let window = Window::around(&solid, thin_radius.ceil() as i32 + 2, c);
    budget.check_elements(
        window.cells() as u128,
        5,
        "the substrate distance transform",
    )?;
    let shells = (thin_radius.min(window.whole).floor() as usize).max(1) + 1;
    let (volume, mass) = window.shell_counts(&solid, particles, shells);
    let mut inside = n;
    let (mut radius, mut density) = (Vec::new(), Vec::new());
    for (v, m) in volume.into_iter().zip(mass).skip(1) {
        if v == 0 {
            continue;
        }
        let v = v as f64;
        radius.push(equivalent_radius(inside + 0.5 * v, c.dim));
        density.push(m as f64 / v);
        inside += v;
    }
    Ok(Some(ShellProfile {
        dim: c.dim,
        seed_radius: equivalent_radius(n, c.dim),
        gyration,
        thin_radius: thin_radius.min(equivalent_radius(inside, c.dim)),
        radius,
        density,
        clipped: window.whole.is_finite(),
    }))
}

/// The box the distance transform covers: the seed's cells widened by a reach,
/// clipped to the lattice.
struct Window {
    lo: [i32; 3],
    hi: [i32; 3],
    dims: [usize; 3],
    /// How far from the seed the box is whole (+∞ when nothing was clipped).
    whole: f64,
}

impl Window {
    fn around(solid: &[[i32; 3]], reach: i32, c: &DlaCluster) -> Self {
        let mut lo = [i32::MAX; 3];
        let mut hi = [i32::MIN; 3];
        for p in solid {
            for a in 0..3 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        }
        let mut whole = f64::INFINITY;
        for a in 0..3 {
            if a == 1 && c.dim != 3 {
                continue;
            }
            let (seed_lo, seed_hi) = (lo[a], hi[a]);
            lo[a] = (seed_lo - reach).max(0);
            hi[a] = (seed_hi + reach).min(c.size[a] as i32 - 1);
            if lo[a] > seed_lo - reach {
                whole = whole.min(f64::from(seed_lo - lo[a]));
            }
            if hi[a] < seed_hi + reach {
                whole = whole.min(f64::from(hi[a] - seed_hi));
            }
        }
        let dims = std::array::from_fn(|a| (hi[a] - lo[a] + 1) as usize);
        Self {
            lo,
            hi,
            dims,
            whole,
        }
    }

    fn cells(&self) -> usize {
        self.dims.iter().product()
    }

    fn index(&self, p: [i32; 3]) -> Option<usize> {
        (0..3)
            .all(|a| p[a] >= self.lo[a] && p[a] <= self.hi[a])
            .then(|| {
                let q: [usize; 3] = std::array::from_fn(|a| (p[a] - self.lo[a]) as usize);
                q[0] + self.dims[0] * (q[1] + self.dims[1] * q[2])
            })
    }

    /// Lattice cells and particles per shell z ∈ (k − 1, k], k = 1..=`shells`
    /// (index 0 unused), outside the seed's solid.
    fn shell_counts(
        &self,
        solid: &[[i32; 3]],
        particles: &[[i32; 3]],
        shells: usize,
    ) -> (Vec<usize>, Vec<usize>) {
        let mut mask = vec![false; self.cells()];
        for &p in solid {
            if let Some(i) = self.index(p) {
                mask[i] = true;
            }
        }
        let dist = distance_transform(self.dims, &mask);
        let shell_of = |z: f32| -> Option<usize> {
            let k = f64::from(z).ceil() as usize;
            (k >= 1 && k <= shells).then_some(k)
        };
        let mut volume = vec![0usize; shells + 1];
        let mut mass = vec![0usize; shells + 1];
        for (i, &z) in dist.iter().enumerate() {
            if !mask[i]
                && let Some(k) = shell_of(z)
            {
                volume[k] += 1;
            }
        }
        for &p in particles {
            if let Some(i) = self.index(p)
                && !mask[i]
                && let Some(k) = shell_of(dist[i])
            {
                mass[k] += 1;
            }
        }
        (volume, mass)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::{fast_rng, unit};

    /// A cloud with a known dimension: each lattice cell outside the seed is
    /// occupied with probability p(r) = min(1, a·r^(D − d)), r its distance from
    /// the seed's centre, out to `r_max`.
    fn cloud(dim: usize, n: i32, seed: &[[i32; 3]], d: f64, r_max: f64) -> DlaCluster {
        let mut rng = fast_rng(5, 0);
        let c = f64::from(n / 2);
        let solid: std::collections::HashSet<[i32; 3]> = seed.iter().copied().collect();
        let mut cells: Vec<[i32; 3]> = seed.to_vec();
        let ys = if dim == 3 { 0..n } else { 0..1 };
        for z in 0..n {
            for y in ys.clone() {
                for x in 0..n {
                    let p = [x, y, z];
                    let yy = if dim == 3 { f64::from(y) - c } else { 0.0 };
                    let r = (f64::from(x) - c).hypot(yy).hypot(f64::from(z) - c);
                    if solid.contains(&p) || r > r_max {
                        continue;
                    }
                    if unit(&mut rng) < (0.6 * (r / 20.0).powf(d - dim as f64)).min(1.0) {
                        cells.push(p);
                    }
                }
            }
        }
        DlaCluster {
            dim,
            size: [
                n as usize,
                if dim == 3 { n as usize } else { 1 },
                n as usize,
            ],
            cells,
            seeds: seed.len(),
            center: [c, if dim == 3 { c } else { 0.0 }, c],
            stopped: None,
            capped_at: None,
            stats: Default::default(),
            rewalks: 0,
            concurrency: Default::default(),
        }
    }

    fn slope_d(p: &ShellProfile) -> f64 {
        // Least squares of ln ρ on ln r over the fit window.
        let pts: Vec<(f64, f64)> = p
            .radius
            .iter()
            .zip(&p.density)
            .filter(|(r, rho)| **r >= p.fit_range()[0] && **r <= p.fit_range()[1] && **rho > 0.0)
            .map(|(r, rho)| (r.ln(), rho.ln()))
            .collect();
        let k = pts.len() as f64;
        let (mx, my) = pts
            .iter()
            .fold((0.0, 0.0), |a, q| (a.0 + q.0 / k, a.1 + q.1 / k));
        let sxy: f64 = pts.iter().map(|q| (q.0 - mx) * (q.1 - my)).sum();
        let sxx: f64 = pts.iter().map(|q| (q.0 - mx).powi(2)).sum();
        p.dim as f64 + sxy / sxx
    }

    #[test]
    fn a_cloud_of_known_dimension_about_a_disc_and_a_ball() {
        // 2-D: D = 1.71 about a disc of radius 40.
        let shape = SeedShape::Sphere(40.0);
        let c = cloud(
            2,
            1201,
            &ball_cells([600.0, 0.0, 600.0], 40.0, false),
            1.71,
            590.0,
        );
        let p = shell_profile(&c, &shape, &MemoryBudget::unlimited())
            .unwrap()
            .unwrap();
        assert!((p.seed_radius - 40.0).abs() < 0.2, "{}", p.seed_radius);
        assert!(
            !p.clipped && p.fit_range()[1] > 150.0,
            "{:?}",
            p.fit_range()
        );
        let d = slope_d(&p);
        assert!((d - 1.71).abs() < 0.03, "2-D D = {d}");
        // 3-D: D = 2.5 about a ball of radius 10.
        let c = cloud(3, 161, &ball_cells([80.0; 3], 10.0, true), 2.5, 78.0);
        let p = shell_profile(&c, &SeedShape::Sphere(10.0), &MemoryBudget::unlimited())
            .unwrap()
            .unwrap();
        assert!(p.fit_range()[1] > 25.0, "{:?}", p.fit_range());
        let d = slope_d(&p);
        assert!((d - 2.5).abs() < 0.03, "3-D D = {d}");
    }

    #[test]
    fn a_square_seed_gets_its_volume_equivalent_radius() {
        // An 81 × 81 square (2-D): radius 81/√π ≈ 45.7; far from it the shells
        // are circles about its centre, so a cloud of D = 1.71 about the centre
        // measures 1.71 (the near shells are rounded squares).
        let seed: Vec<[i32; 3]> = (-40..=40)
            .flat_map(|x| (-40..=40).map(move |z| [600 + x, 0, 600 + z]))
            .collect();
        let c = cloud(2, 1201, &seed, 1.71, 590.0);
        let p = shell_profile(&c, &SeedShape::Cells(seed), &MemoryBudget::unlimited())
            .unwrap()
            .unwrap();
        assert!((p.seed_radius - 81.0 / std::f64::consts::PI.sqrt()).abs() < 1e-9);
        let d = slope_d(&p);
        assert!((d - 1.71).abs() < 0.03, "D = {d}");
        // No profile for a point or a plane seed.
        assert!(
            shell_profile(&c, &SeedShape::Point, &MemoryBudget::unlimited())
                .unwrap()
                .is_none()
        );
    }
}
