//! Diffusion-limited aggregation, DLA (kim-machiraju-thompson §4.2, Fig. 4;
//! Witten & Sander 1981), on the cubic lattice (and the square lattice in the
//! x–z plane for validation), with big jumps.
//!
//! **Model.** "A seed particle is fixed at a site … a second particle is then
//! released from a random position distant from the seed. It moves following …
//! a random walk until it reaches one of the … neighbor sites of the stationary
//! seed whereupon it sticks with some probability." Walkers step to one of the 6
//! (3-D) or 4 (2-D) face neighbours; a move into an occupied cell is rejected (the
//! walker stays, the step counts). On an empty cell with an occupied face
//! neighbour the walker sticks with probability `stick` (p = 1 dendritic, small
//! p moss-like, §4.2); if it does not, it walks on (Meakin's rule, not a bounce).
//!
//! **Seeds.** A point (the classic cluster), the bottom plane (terrain, the
//! paper's Figs. 9–11; periodic in x and y, or between reflecting side walls,
//! see [`Sides`]), a solid ball, any set of cells (a
//! voxelised mesh), or sparse cells on the bottom plane drawn from a density
//! image (§7: "use an image as the distribution of the initial seeds"). Solid
//! seeds are occupied throughout, but only their surface cells are listed.
//!
//! **Launching and far walkers.** Radial modes launch uniformly on the sphere
//! (circle) of radius R = r_max + δ about the lattice centre, r_max being the
//! farthest occupied cell; plane modes launch at a uniform (x, y) on the plane
//! z = h_max + δ. Far walkers are **returned exactly, never killed**:
//! - 3-D radial, beyond 1.5 R + 4: the walker escapes to infinity with
//!   probability 1 − R/r and is then relaunched (the hitting distribution from
//!   infinity is uniform), else it re-enters at its first hitting point on the
//!   launch sphere, drawn from the exterior Poisson kernel ∝ (r² − R²)/|x − y|³
//!   by inverting its CDF in cos θ;
//! - 2-D radial: the walk is recurrent; the re-entry angle is wrapped-Cauchy
//!   with scale ln(r/R) about the walker's angle (the exterior Poisson kernel of
//!   the disc);
//! - plane modes, above the launch plane at height h over it: the walker moves to
//!   its first hitting point on the plane, at a horizontal offset drawn from the
//!   half-space Poisson kernel (density ∝ h/(ρ² + h²)^{3/2} in 3-D, Cauchy with
//!   scale h in 2-D), wrapped periodically — exact for the periodic slab too —
//!   or folded back between the side walls (a walk between reflecting walls is
//!   the free walk folded by the mirror images of the box, so the kernel stays
//!   exact there as well).
//!
//! A plane deposit that reaches the lattice top is capped there: later walkers
//! are released from the top layer, and the region above is treated as empty,
//! so the deposit keeps filling its pores like a closed box fed from above
//! ([`DlaCluster::capped_at`] records when). Radial clusters stop at the lattice
//! boundary instead ([`DlaCluster::stopped`]).
//!
//! These kernels are those of Brownian motion; the lattice walk matches them up
//! to O(1/r) lattice corrections, far below the kill-radius bias they replace.
//!
//! **Big jumps.** Wherever the walker is, [`DistanceMap::lower_bound`] (blocks
//! of 4³ cells, distances to 124 cells) and the global bound (r − r_max, or
//! z − h_max) give a radius d within which every cell is empty. When d ≥ 3 the
//! walker jumps to a uniform point of the sphere (circle) of radius d − 2 about
//! it — the exit distribution of Brownian motion from a ball centred on its
//! start — rounded to the nearest cell, which is then still at least 1.1 from
//! every occupied cell, so a jump never lands on or touches the cluster. The map
//! sees the cluster itself, not its envelope, so one tall branch does not slow
//! plane mode. Steps are single only within a few cells of the cluster.
//!
//! **Threads.** The model is sequential: each particle walks in the cluster of
//! all the particles before it (walkers released together would change the
//! dynamics). Each particle draws from its own generator, so its walk is a
//! function of the cluster it sees, and [`speculative`] runs the next walks
//! on other threads before their predecessors are added, keeping a walk only
//! if nothing it read has changed meanwhile and walking it again otherwise.
//! The cluster is the sequential one, byte for byte, at any thread count.

pub mod speculative;
pub mod substrate;
pub mod walk;

use asperity_core::{MemoryBudget, Progress};
use rand::RngCore;
use serde::Serialize;

use crate::GrowthError;
use crate::error::bad;
use crate::occupancy::{DistanceMap, Occupancy};
use crate::rng::fast_rng;
use speculative::{Growth, Ledger};
use walk::{Lattice, Setup};

/// What the cluster grows from.
#[derive(Clone, Debug, PartialEq)]
pub enum SeedShape {
    /// One cell at the lattice centre.
    Point,
    /// The whole bottom plane z = 0 (periodic in x and y).
    Plane,
    /// A solid ball of this radius (cells) at the lattice centre.
    Sphere(f64),
    /// Given solid cells (e.g. a voxelised mesh), grown on radially.
    Cells(Vec<[i32; 3]>),
    /// Sparse seeds on the bottom plane: column (x, y) holds a seed with the
    /// given probability (x fastest, nx·ny values in [0, 1]); periodic in x and y,
    /// with a reflecting floor under z = 0.
    Density(Vec<f64>),
}

impl SeedShape {
    /// Whether the deposit grows on the bottom plane (periodic in x and y).
    pub fn is_plane(&self) -> bool {
        matches!(self, SeedShape::Plane | SeedShape::Density(_))
    }

    /// Short name.
    pub fn name(&self) -> &'static str {
        match self {
            SeedShape::Point => "point",
            SeedShape::Plane => "plane",
            SeedShape::Sphere(_) => "sphere",
            SeedShape::Cells(_) => "cells",
            SeedShape::Density(_) => "image",
        }
    }
}

/// What happens at the x and y sides of a plane deposit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Sides {
    /// Periodic in x and y (the standard set-up of growth physics: no edge
    /// effects). The deposit is one cluster only when the wrap is counted, so
    /// as a bounded object it falls into pieces at the sides.
    #[default]
    Periodic,
    /// Reflecting walls: a walker that steps out of the box stays in its cell,
    /// and a particle sticks only to neighbours inside the box. The deposit is
    /// one connected set without any wrap — a terrain that is one piece
    /// (kim-machiraju-thompson Figs. 9–11 show one connected surface). Any size.
    Walls,
}

/// DLA parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct DlaParams {
    /// 2 (square lattice in the x–z plane) or 3 (cubic lattice).
    pub dim: usize,
    /// Lattice size in cells (in 2-D: [nx, 1, nz]).
    pub size: [usize; 3],
    /// Particles to deposit (seeds not counted).
    pub particles: usize,
    /// Sticking probability p in (0, 1].
    pub stick: f64,
    /// The seed.
    pub seed_shape: SeedShape,
    /// Launch gap δ between the farthest (highest) occupied cell and the
    /// launch sphere (plane), in cells.
    pub launch_gap: f64,
    /// Plane modes: periodic sides or reflecting walls (ignored by radial modes).
    pub sides: Sides,
}

impl DlaParams {
    /// The launch gap δ every front end starts from, in cells: close enough
    /// that few walks are wasted far from the cluster, far enough that the
    /// launch sphere stays outside it.
    pub const DEFAULT_LAUNCH_GAP: f64 = 2.0;

    /// A 3-D point-seeded cluster of `particles` with sticking probability 1 on a
    /// lattice sized for it by [`auto_size`].
    pub fn point(dim: usize, particles: usize) -> Self {
        Self {
            dim,
            size: auto_size(dim, particles, 1.0),
            particles,
            stick: 1.0,
            seed_shape: SeedShape::Point,
            launch_gap: Self::DEFAULT_LAUNCH_GAP,
            sides: Sides::Periodic,
        }
    }

    /// Whether the lattice wraps in x and y (a plane deposit with periodic sides).
    pub fn periodic(&self) -> bool {
        self.seed_shape.is_plane() && self.sides == Sides::Periodic
    }

    /// Checks the parameters, the lattice capacity and the memory estimate.
    ///
    /// # Errors
    /// [`GrowthError::BadParameter`], [`GrowthError::Capacity`] or the budget.
    pub fn validate(&self, budget: &MemoryBudget) -> Result<(), GrowthError> {
        if self.dim != 2 && self.dim != 3 {
            return Err(bad(format!(
                "DLA dimension must be 2 or 3, got {}",
                self.dim
            )));
        }
        if !(self.stick > 0.0 && self.stick <= 1.0) {
            return Err(bad(format!(
                "sticking probability must be in (0, 1], got {}",
                self.stick
            )));
        }
        if self.size.contains(&0) {
            return Err(bad(format!(
                "lattice size {}x{}x{} has a zero side",
                self.size[0], self.size[1], self.size[2]
            )));
        }
        if self.dim == 2 && self.size[1] != 1 {
            return Err(bad("a 2-D lattice is [nx, 1, nz] (the x–z plane)"));
        }
        if self.particles == 0 {
            return Err(bad("the number of particles must be at least 1"));
        }
        if !(self.launch_gap.is_finite() && self.launch_gap >= 1.0) {
            return Err(bad(format!(
                "launch gap must be at least 1 cell, got {}",
                self.launch_gap
            )));
        }
        let cells = self.size.iter().map(|&s| s as u128).product::<u128>();
        if self.particles as u128 >= cells {
            return Err(GrowthError::Capacity(format!(
                "{} particles do not fit in a {}x{}x{} lattice of {cells} cells",
                self.particles, self.size[0], self.size[1], self.size[2]
            )));
        }
        if let SeedShape::Sphere(r) = self.seed_shape {
            let half = self.size[0].min(self.size[2]) as f64 / 2.0 - 3.0;
            if !(r.is_finite() && r >= 0.5 && r < half) {
                return Err(bad(format!(
                    "seed sphere radius must be in [0.5, {half}) for this lattice, got {r}"
                )));
            }
        }
        if let SeedShape::Density(d) = &self.seed_shape
            && d.len() != self.size[0] * self.size[1]
        {
            return Err(bad(format!(
                "seed density has {} values for a {}x{} plane",
                d.len(),
                self.size[0],
                self.size[1]
            )));
        }
        let periodic = self.periodic();
        if periodic
            && (!self.size[0].is_multiple_of(8)
                || (self.size[1] > 1 && !self.size[1].is_multiple_of(8)))
        {
            return Err(bad(format!(
                "a plane deposit with periodic sides needs x and y sizes that are multiples of 8, got {}x{} (or use walls at the sides)",
                self.size[0], self.size[1]
            )));
        }
        let bytes = 2 * Occupancy::estimate_bytes(self.size)
            + DistanceMap::estimate_bytes(self.size, 2)
            + DistanceMap::estimate_bytes(self.size, 3)
            + DistanceMap::estimate_bytes(self.size, coarse_shift(self.size, periodic))
            + self.particles as u128 * 12;
        budget.check_elements(bytes, 1, "DLA lattice and particle list")?;
        Ok(())
    }
}

/// A lattice size that holds a point-seeded cluster of `particles` with
/// sticking probability `stick`: a cube (square) of side about 2.6 times the
/// expected farthest particle, r_max ≈ 1.35 N^0.4 in 3-D and 2.0 N^0.585 in 2-D,
/// rounded up to a multiple of 4.
pub fn auto_size(dim: usize, particles: usize, stick: f64) -> [usize; 3] {
    let n = particles.max(1) as f64;
    let r = if dim == 3 {
        1.35 * n.powf(0.4)
    } else {
        2.0 * n.powf(1.0 / 1.71)
    };
    let _ = stick; // p < 1 only makes the cluster smaller.
    let side = ((2.6 * r + 16.0) / 4.0).ceil() as usize * 4;
    if dim == 3 { [side; 3] } else { [side, 1, side] }
}

/// Work counters of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct WalkStats {
    /// Single lattice steps (including rejected moves).
    pub steps: u64,
    /// Big jumps.
    pub jumps: u64,
    /// Exact returns of far walkers.
    pub returns: u64,
    /// Walkers that escaped to infinity (3-D radial) and were relaunched.
    pub escapes: u64,
}

impl std::ops::AddAssign for WalkStats {
    fn add_assign(&mut self, o: Self) {
        self.steps += o.steps;
        self.jumps += o.jumps;
        self.returns += o.returns;
        self.escapes += o.escapes;
    }
}

/// A grown cluster.
#[derive(Clone, Debug, PartialEq)]
pub struct DlaCluster {
    /// 2 or 3.
    pub dim: usize,
    /// Lattice size.
    pub size: [usize; 3],
    /// Listed seed cells, then every particle in deposition order (cell coordinates).
    pub cells: Vec<[i32; 3]>,
    /// How many of `cells` are seeds.
    pub seeds: usize,
    /// The centre of radial modes (cell coordinates).
    pub center: [f64; 3],
    /// Why the run stopped before `particles`, if it did.
    pub stopped: Option<String>,
    /// Plane modes: the particle count at which the deposit reached the lattice
    /// top; later particles were released from the top layer (a closed box fed
    /// from above) instead of from above the deposit.
    pub capped_at: Option<usize>,
    /// Work counters.
    pub stats: WalkStats,
    /// Walks started ahead of their turn that read a cell a predecessor then
    /// changed, and were walked again ([`speculative`]). The cluster does not
    /// depend on it; it varies with the threads' timing (0 with one walker).
    pub rewalks: u64,
    /// How the concurrent walks went (timing-dependent, like `rewalks`).
    pub concurrency: Concurrency,
}

/// How the walkers of a run shared the work ([`speculative`]): none of it
/// changes the cluster.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Concurrency {
    /// Concurrent walkers (1: the plain sequential loop).
    pub walkers: usize,
    /// Walks in flight (claimed, not yet committed) on average over the commits.
    pub mean_in_flight: f64,
    /// Share of the particles whose walk was done again.
    pub redone_fraction: f64,
    /// Seconds the walkers spent waiting to be within the window (spinning
    /// briefly, then asleep), summed over them: the only wait there is (a
    /// walker never waits for another's commit).
    pub window_wait_s: f64,
}

impl DlaCluster {
    /// The deposited particles (without the seeds).
    pub fn particles(&self) -> &[[i32; 3]] {
        &self.cells[self.seeds..]
    }

    /// Cell positions as `f64` points.
    pub fn points(&self) -> Vec<[f64; 3]> {
        self.cells.iter().map(|c| c.map(f64::from)).collect()
    }
}

/// The cells of the solid ball of radius `r` about the cell of `center` (a disc
/// in the x–z plane when not `three_d`).
pub(crate) fn ball_cells(center: [f64; 3], r: f64, three_d: bool) -> Vec<[i32; 3]> {
    let ri = r.ceil() as i32 + 1;
    let c = center.map(|v| v as i32);
    let mut v = Vec::new();
    for dz in -ri..=ri {
        for dy in if three_d { -ri..=ri } else { 0..=0 } {
            for dx in -ri..=ri {
                if ((dx * dx + dy * dy + dz * dz) as f64) <= r * r {
                    v.push([c[0] + dx, c[1] + dy, c[2] + dz]);
                }
            }
        }
    }
    v
}

/// Cap of the distance maps (4-, 8- and 32-cell blocks), in blocks.
const MAP_CAP: u8 = 8;

/// Coarse blocks of 32 cells, or of the largest power of two dividing the
/// periodic sizes (at least 8).
fn coarse_shift(size: [usize; 3], periodic: bool) -> u32 {
    if periodic {
        let tz = |n: usize| if n <= 1 { 5 } else { n.trailing_zeros() };
        5.min(tz(size[0])).min(tz(size[1])).max(3)
    } else {
        5
    }
}

const DIRS3: [[i32; 3]; 6] = crate::occupancy::FACE_NEIGHBOURS;
const DIRS2: [[i32; 3]; 4] = [[-1, 0, 0], [1, 0, 0], [0, 0, -1], [0, 0, 1]];

/// The most walkers [`dla`] starts by default. Measured on a 16-core Xeon
/// (10⁶ particles, point seed, whole process; BENCHMARKS.md, 2026-11-28
/// "16 cores"): 1 walker 22.6 s, 2: 13.2 s, 4: 10.9 s, 8: 12.7 s, 16: 21.4 s.
/// Past four the commits, made one at a time under the ledger's lock, are
/// the bottleneck and the walkers mostly wait (16 walkers: 175 s of lock
/// waits summed over them). `--walkers` still asks for more.
pub const DEFAULT_WALKERS_MAX: usize = 4;

/// Grows a DLA cluster with the generator of run `run` under `seed`, with
/// walkers on every thread of the current pool, at most one a core and at
/// most [`DEFAULT_WALKERS_MAX`] (the cluster does not depend on their number,
/// see [`dla_with_walkers`]).
///
/// # Errors
/// Invalid parameters, capacity or memory (see [`DlaParams::validate`]).
pub fn dla(
    params: &DlaParams,
    seed: u64,
    run: u64,
    budget: &MemoryBudget,
    progress: &dyn Progress,
) -> Result<DlaCluster, GrowthError> {
    // More walkers than cores only wait for each other (a walk preempted
    // midway holds back the commits); the cluster is the same either way.
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let walkers = rayon::current_num_threads()
        .min(cores)
        .min(DEFAULT_WALKERS_MAX);
    dla_with_walkers(params, seed, run, budget, progress, walkers)
}

/// [`dla`] with `walkers` concurrent walks (1: the plain sequential loop). The
/// cluster is byte-identical for any `walkers` ([`speculative`]).
///
/// # Errors
/// As [`dla`].
pub fn dla_with_walkers(
    params: &DlaParams,
    seed: u64,
    run: u64,
    budget: &MemoryBudget,
    progress: &dyn Progress,
    walkers: usize,
) -> Result<DlaCluster, GrowthError> {
    params.validate(budget)?;
    let plane = params.seed_shape.is_plane();
    let periodic = params.periodic();
    let size = params.size;
    if plane && size[2] < 4 {
        return Err(bad("a plane deposit needs a lattice at least 4 cells high"));
    }
    let occ = Occupancy::new(size, periodic, budget)?;
    let maps = [2, 3, coarse_shift(size, periodic)].map(|s| DistanceMap::new(&occ, s, MAP_CAP));
    let lat = Lattice::new(occ, Occupancy::new(size, periodic, budget)?, maps);
    let setup = Setup {
        params,
        three_d: params.dim == 3,
        plane,
        walls: plane && !periodic,
        center: [0, 1, 2].map(|a| ((size[a] - 1) / 2) as f64),
    };
    let mut rng = fast_rng(seed, run);
    let solid = setup.solid_seed(&mut rng)?;
    for &c in &solid {
        lat.occupy(&setup, c);
    }
    let mut cells = setup.surface_of(&lat, &solid);
    drop(solid);
    let seeds = cells.len();
    cells.reserve(params.particles);
    let streams = rng.next_u64();
    let growth = Growth::new(&setup, &lat, streams, progress, Ledger::new(cells, seeds));
    let ledger = growth.run(walkers);
    let concurrency = ledger.concurrency(walkers);
    Ok(DlaCluster {
        dim: params.dim,
        size,
        cells: ledger.cells,
        seeds,
        center: setup.center,
        stopped: ledger.end.stopped,
        capped_at: ledger.end.capped_at,
        stats: ledger.stats,
        rewalks: ledger.rewalks,
        concurrency,
    })
}
