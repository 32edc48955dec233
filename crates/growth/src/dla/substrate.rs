//! The fractal dimension of a DLA deposit about its substrate
//! (kim-machiraju-thompson §7: DLA grown on a sphere or on any object).
//!
//! About a seed of many cells R_g(n) ∝ n^{1/D} measures the seed, not the
//! deposit. Two measures here start from the seed's *surface*: the exact
//! Euclidean distance transform of the seed's solid (the one the curved
//! depositions use) sorts every lattice cell around it into shells one cell
//! thick, z ∈ (k − 1, k], each with a volume-equivalent radius r(z) —
//! (4π/3) r³ = the seed's volume plus every cell within z of it (π r² in 2-D) —
//! so that for a ball r is the distance from its centre and far from any seed
//! the shells become spheres. The window runs from the seed's radius + 5 cells
//! to where the cluster thins, taken as half the particles' radius of gyration
//! about the seed's centroid (the upper bound the point-seed mass–radius fit
//! uses).
//!
//! - **The shell density** ρ(r), the share of a shell's lattice cells a
//!   particle holds. About a point, ρ ∝ r^{D − d} (d = 2 or 3) is the mass–radius
//!   law M ∝ r^D in differential form; about a seed its slope mixes the deposit
//!   with the seed's shape. Close to a ball of radius R the deposit is a forest
//!   grown on a nearly flat surface, whose density falls with the height z, far
//!   from it a cluster about a point, whose density falls with r = R + z; the
//!   crossover fills the window (R + 5 to ≈ 2.2R at 200,000 particles), and a
//!   fit on r gave 2.0–2.2 on a ball of radius 20, a fit on z 2.6–2.7, against
//!   2.5 about a point. It is reported as a profile, not as D.
//! - **The pair correlation**, the measure D is reported from: the mean number
//!   N(s) of other particles within s of a particle of the window, N ∝ s^D
//!   (Meakin 1983 measured DLA on fibres and surfaces by this correlation). It
//!   counts the deposit about its own particles, so the seed enters only
//!   through which particles are averaged: at 200,000 particles it gives 2.50
//!   on a ball of radius 20 and 2.48 on a cube of side 33, against 2.48 by
//!   R_g(n) about a point (`tests/reference.rs`). The radii run from 4 cells
//!   (below which the count is the lattice's) to half the window's outer
//!   radius, so that a particle in the window sees the deposit still dense.
//!
//! [`shell_profile`] gives both; the fit is
//! `asperity_analysis::scaling::pair_dimension`.

use asperity_core::MemoryBudget;

use super::{DlaCluster, SeedShape, ball_cells};
use crate::GrowthError;
use crate::curved::distance_transform;
use crate::occupancy::Occupancy;

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
    /// The deposit's pair correlation about the particles of the fit window
    /// (`None` when the window is empty).
    pub pairs: Option<PairCorrelation>,
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

/// The shell profile and pair correlation of a cluster grown from a point, a
/// sphere or given cells; `None` for plane and image seeds, or below 256
/// particles.
///
/// # Errors
/// The memory budget (the distance transform covers the seed's box widened by
/// the thin radius; the pair count's occupancy grid that box widened by the
/// largest pair radius).
pub fn shell_profile(
    c: &DlaCluster,
    seed: &SeedShape,
    budget: &MemoryBudget,
) -> Result<Option<ShellProfile>, GrowthError> {
    let solid = match seed {
        SeedShape::Point => c.cells[..c.seeds].to_vec(),
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
    let counts = window.shell_counts(&solid, particles, shells);
    let mut inside = n;
    let (mut radius, mut density) = (Vec::new(), Vec::new());
    let mut shell_radius = vec![f64::NAN; shells + 1];
    for (k, (&v, &m)) in counts.volume.iter().zip(&counts.mass).enumerate().skip(1) {
        if v == 0 {
            continue;
        }
        let v = v as f64;
        shell_radius[k] = equivalent_radius(inside + 0.5 * v, c.dim);
        radius.push(shell_radius[k]);
        density.push(m as f64 / v);
        inside += v;
    }
    let mut profile = ShellProfile {
        dim: c.dim,
        seed_radius: equivalent_radius(n, c.dim),
        gyration,
        thin_radius: thin_radius.min(equivalent_radius(inside, c.dim)),
        radius,
        density,
        clipped: window.whole.is_finite(),
        pairs: None,
    };
    let [from, to] = profile.fit_range();
    if to > from {
        let centres: Vec<[i32; 3]> = particles
            .iter()
            .zip(&counts.particle_shell)
            .filter(|&(_, &k)| (from..=to).contains(&shell_radius[k as usize]))
            .map(|(p, _)| *p)
            .collect();
        profile.pairs = pair_correlation(c, particles, &centres, 0.5 * to, budget)?;
    }
    Ok(Some(profile))
}

/// The smallest pair radius (cells): below it the count is the lattice's, not
/// the cluster's.
const PAIR_RADIUS_MIN: f64 = 4.0;
/// Pair radii, log-spaced from [`PAIR_RADIUS_MIN`] to half the thin radius.
const PAIR_RADII: usize = 8;
/// At most this many centres (every k-th particle of the window in deposition
/// order, so the count does not depend on the thread count).
const PAIR_CENTRES: usize = 4096;

/// The deposit's pair correlation (see the module docs): the mean number of
/// other particles within s of a particle of the fit window.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PairCorrelation {
    /// The radii s (cells).
    pub radius: Vec<f64>,
    /// Mean count of other particles within each radius.
    pub neighbours: Vec<f64>,
    /// The centres averaged over.
    pub centres: usize,
}

/// Counts particles about `centres` (a subset of `particles`) out to `s_max`;
/// `None` when the window holds no centre or `s_max` is under twice
/// [`PAIR_RADIUS_MIN`].
///
/// No k-d tree: the particles are cells of the cluster's lattice, so its
/// occupancy bits and the list of lattice offsets in the ball answer every
/// fixed-radius count by lookups.
fn pair_correlation(
    c: &DlaCluster,
    particles: &[[i32; 3]],
    centres: &[[i32; 3]],
    s_max: f64,
    budget: &MemoryBudget,
) -> Result<Option<PairCorrelation>, GrowthError> {
    use rayon::prelude::*;
    if centres.is_empty() || s_max < 2.0 * PAIR_RADIUS_MIN {
        return Ok(None);
    }
    let step = centres.len().div_ceil(PAIR_CENTRES);
    let centres: Vec<[i32; 3]> = centres.iter().step_by(step).copied().collect();
    let radius: Vec<f64> = (0..PAIR_RADII)
        .map(|k| {
            PAIR_RADIUS_MIN * (s_max / PAIR_RADIUS_MIN).powf(k as f64 / (PAIR_RADII - 1) as f64)
        })
        .collect();
    // Radial seeds grow on a closed lattice (no wrap).
    let grid = Occupancy::new(c.size, false, budget)?;
    for &p in particles {
        grid.set(p);
    }
    // The first radius that holds each squared distance (as `ball_offsets`
    // assigns them), so that a centre visits the occupied cells of its box
    // instead of every cell of its ball (#55: at 10⁶ particles the ball's
    // 2·10⁵ look-ups a centre were a third of the run).
    let reach = radius[PAIR_RADII - 1].ceil() as i32;
    let bins = radius_bins(&radius);
    let counts = centres
        .par_iter()
        .map(|&p| {
            let mut n = [0u64; PAIR_RADII];
            grid.for_each_in_box(p.map(|v| v - reach), p.map(|v| v + reach), |q| {
                let d2 = (0..3).map(|a| (q[a] - p[a]).pow(2)).sum::<i32>() as usize;
                if let Some(&Some(k)) = bins.get(d2) {
                    n[k] += 1;
                }
            });
            n
        })
        .reduce(
            || [0u64; PAIR_RADII],
            |mut a, b| {
                for k in 0..PAIR_RADII {
                    a[k] += b[k];
                }
                a
            },
        );
    let mut within = 0u64;
    let neighbours = counts
        .iter()
        .map(|&n| {
            within += n;
            within as f64 / centres.len() as f64
        })
        .collect();
    Ok(Some(PairCorrelation {
        radius,
        neighbours,
        centres: centres.len(),
    }))
}

/// For each squared lattice distance d² up to the last of `radius`, the first
/// radius that holds it (`None` for 0 and beyond the last).
fn radius_bins(radius: &[f64]) -> Vec<Option<usize>> {
    let s_max = radius[radius.len() - 1];
    let reach = s_max.ceil() as usize;
    (0..=3 * reach * reach)
        .map(|d2| {
            let r = (d2 as f64).sqrt();
            if r == 0.0 || r > s_max * (1.0 + 1e-12) {
                return None;
            }
            let k = radius.partition_point(|&s| s < r * (1.0 - 1e-12));
            Some(k.min(radius.len() - 1))
        })
        .collect()
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
    /// (index 0 unused), outside the seed's solid, and each particle's shell.
    fn shell_counts(
        &self,
        solid: &[[i32; 3]],
        particles: &[[i32; 3]],
        shells: usize,
    ) -> ShellCounts {
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
        let mut particle_shell = vec![0u32; particles.len()];
        for (&p, shell) in particles.iter().zip(&mut particle_shell) {
            if let Some(i) = self.index(p)
                && !mask[i]
                && let Some(k) = shell_of(dist[i])
            {
                mass[k] += 1;
                *shell = k as u32;
            }
        }
        ShellCounts {
            volume,
            mass,
            particle_shell,
        }
    }
}

/// [`Window::shell_counts`]: per shell, and each particle's shell (0: none).
struct ShellCounts {
    volume: Vec<usize>,
    mass: Vec<usize>,
    particle_shell: Vec<u32>,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pair count's bins by the ball of offsets about each centre (how
    /// they were counted before the occupied cells of the box were visited).
    /// Every lattice offset within the last of `radius` but the cell's own (in the
    /// x–z plane in 2-D), with the first radius that holds it.
    fn ball_offsets(dim: usize, radius: &[f64]) -> Vec<([i32; 3], usize)> {
        let s_max = radius[radius.len() - 1];
        let reach = s_max.ceil() as i32;
        let ys = if dim == 3 { -reach..=reach } else { 0..=0 };
        let mut offsets = Vec::new();
        for dz in -reach..=reach {
            for dy in ys.clone() {
                for dx in -reach..=reach {
                    let r = f64::from(dx * dx + dy * dy + dz * dz).sqrt();
                    if r == 0.0 || r > s_max * (1.0 + 1e-12) {
                        continue;
                    }
                    let k = radius.partition_point(|&s| s < r * (1.0 - 1e-12));
                    offsets.push(([dx, dy, dz], k.min(radius.len() - 1)));
                }
            }
        }
        offsets
    }

    #[test]
    fn the_box_s_occupied_cells_count_as_the_ball_of_offsets() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand::rngs::StdRng::seed_from_u64(rand::random());
        for dim in [2, 3] {
            let n = 48;
            let dims = [n, if dim == 3 { n } else { 1 }, n];
            let grid = Occupancy::new(dims, false, &MemoryBudget::unlimited()).unwrap();
            let mut cells = Vec::new();
            for z in 0..dims[2] as i32 {
                for y in 0..dims[1] as i32 {
                    for x in 0..dims[0] as i32 {
                        if rng.random::<f64>() < 0.15 {
                            grid.set([x, y, z]);
                            cells.push([x, y, z]);
                        }
                    }
                }
            }
            let radius: Vec<f64> = (0..PAIR_RADII)
                .map(|k| 4.0 * 1.3f64.powi(k as i32))
                .collect();
            let reach = radius[PAIR_RADII - 1].ceil() as i32;
            let bins = radius_bins(&radius);
            let offsets = ball_offsets(dim, &radius);
            for &p in cells.iter().step_by(37) {
                let (mut by_box, mut by_ball) = ([0u64; PAIR_RADII], [0u64; PAIR_RADII]);
                grid.for_each_in_box(p.map(|v| v - reach), p.map(|v| v + reach), |q| {
                    let d2 = (0..3).map(|a| (q[a] - p[a]).pow(2)).sum::<i32>() as usize;
                    if let Some(&Some(k)) = bins.get(d2) {
                        by_box[k] += 1;
                    }
                });
                for &(o, k) in &offsets {
                    by_ball[k] += u64::from(grid.get([p[0] + o[0], p[1] + o[1], p[2] + o[2]]));
                }
                assert_eq!(by_box, by_ball, "{dim}-D, centre {p:?}");
            }
        }
    }
    use crate::rng::{fast_rng, unit};
    use asperity_analysis::psd::log_fit;
    use asperity_analysis::scaling::pair_dimension;

    /// A cluster of `seed` cells then `particles` on an n-cell lattice.
    fn cluster(dim: usize, n: i32, seed: &[[i32; 3]], particles: Vec<[i32; 3]>) -> DlaCluster {
        let c = f64::from(n / 2);
        let mut cells: Vec<[i32; 3]> = seed.to_vec();
        cells.extend(particles);
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

    /// A cloud with a known dimension: each lattice cell outside the seed is
    /// occupied with probability p(r) = min(1, a·r^(D − d)), r its distance from
    /// the seed's centre, out to `r_max`.
    fn cloud(dim: usize, n: i32, seed: &[[i32; 3]], d: f64, r_max: f64) -> DlaCluster {
        let mut rng = fast_rng(5, 0);
        let c = f64::from(n / 2);
        let solid: std::collections::HashSet<[i32; 3]> = seed.iter().copied().collect();
        let mut cells = Vec::new();
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
        cluster(dim, n, seed, cells)
    }

    /// d + the slope of ln ρ on ln r over the fit window.
    fn slope_d(p: &ShellProfile) -> f64 {
        let fit = log_fit(&p.radius, &p.density, p.fit_range()).unwrap();
        p.dim as f64 + fit.slope
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
        // No profile for a plane seed.
        assert!(
            shell_profile(&c, &SeedShape::Plane, &MemoryBudget::unlimited())
                .unwrap()
                .is_none()
        );
    }

    /// The pair count of sets whose dimension is exact: a filled ball (3), a
    /// plane sheet (2) and a line (1) in 3-D, a filled disc (2) in 2-D, each
    /// about a point seed at the lattice's centre. The lattice's own counts
    /// (257 cells within 4 of a cell, against 4π·4³/3 ≈ 268) lean the slope up
    /// by up to 0.05.
    #[test]
    fn the_pair_count_of_a_ball_a_sheet_and_a_line() {
        // Which cells (offsets from the centre) the set holds.
        type Keep = dyn Fn(i32, i32, i32) -> bool;
        let set = |dim: usize, n: i32, keep: &Keep| -> DlaCluster {
            let m = n / 2;
            let (ys, centre) = if dim == 3 {
                (0..n, [m, m, m])
            } else {
                (0..1, [m, 0, m])
            };
            let mut v = Vec::new();
            for z in 0..n {
                for y in ys.clone() {
                    for x in 0..n {
                        let p = [x, y, z];
                        if p != centre && keep(x - m, y - centre[1], z - m) {
                            v.push(p);
                        }
                    }
                }
            }
            cluster(dim, n, &[centre], v)
        };
        let cases: [(usize, i32, &Keep, f64); 4] = [
            (3, 161, &|x, y, z| x * x + y * y + z * z <= 78 * 78, 3.0),
            (3, 161, &|_, _, z| z == 0, 2.0),
            (3, 601, &|_, y, z| y == 0 && z == 0, 1.0),
            (2, 161, &|x, _, z| x * x + z * z <= 78 * 78, 2.0),
        ];
        for (dim, n, keep, d) in cases {
            let c = set(dim, n, keep);
            let p = shell_profile(&c, &SeedShape::Point, &MemoryBudget::unlimited())
                .unwrap()
                .unwrap();
            let pairs = p.pairs.as_ref().unwrap();
            assert_eq!(pairs.radius.len(), PAIR_RADII);
            assert!(pairs.radius[0] == PAIR_RADIUS_MIN && pairs.radius[7] > 11.0);
            assert!(pairs.centres >= 40, "{} centres", pairs.centres);
            let fit = pair_dimension(&pairs.radius, &pairs.neighbours).unwrap().d;
            assert!(
                (fit - d).abs() < 0.06,
                "{dim}-D set of dimension {d}: {fit}"
            );
        }
        // A budget too small for the occupancy grid is refused, not overrun.
        let c = set(3, 161, &|_, _, z| z == 0);
        assert!(shell_profile(&c, &SeedShape::Point, &MemoryBudget::new(1 << 16)).is_err());
    }
}
