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
//! Each cluster is sequential (parallel DLA changes the dynamics); independent
//! clusters can run in parallel.

use asperity_core::vec3::{add, dist, norm, scale, sub};
use asperity_core::{MemoryBudget, Progress};
use serde::Serialize;

use crate::GrowthError;
use crate::error::bad;
use crate::occupancy::{DistanceMap, Occupancy};
use crate::rng::{FastRng, below, fast_rng, unit, unit_vector3};

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
    /// A 3-D point-seeded cluster of `particles` with sticking probability 1 on a
    /// lattice sized for it by [`auto_size`].
    pub fn point(dim: usize, particles: usize) -> Self {
        Self {
            dim,
            size: auto_size(dim, particles, 1.0),
            particles,
            stick: 1.0,
            seed_shape: SeedShape::Point,
            launch_gap: 2.0,
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

struct Walk<'a> {
    params: &'a DlaParams,
    three_d: bool,
    plane: bool,
    /// Plane mode between reflecting side walls.
    walls: bool,
    occ: Occupancy,
    /// The contact set: cells with an occupied face neighbour (see
    /// [`Occupancy::set_neighbours`]), so a single step reads one word.
    contact: Occupancy,
    fine: DistanceMap,
    medium: DistanceMap,
    coarse: DistanceMap,
    center: [f64; 3],
    /// Farthest occupied distance from the centre (radial) or highest z (plane).
    reach: f64,
    rng: FastRng,
    stats: WalkStats,
}

impl Walk<'_> {
    fn occupy(&mut self, p: [i32; 3]) {
        let q = self.occ.canonical(p).expect("inside the lattice");
        self.occ.set(q);
        self.contact.set_neighbours(q, self.three_d);
        self.fine.occupy(q);
        self.medium.occupy(q);
        self.coarse.occupy(q);
        let r = if self.plane {
            p[2] as f64
        } else {
            dist(p.map(f64::from), self.center)
        };
        self.reach = self.reach.max(r);
    }

    fn launch_level(&self) -> f64 {
        let lv = self.reach + self.params.launch_gap;
        if self.plane {
            // A plane deposit is capped by the lattice top: once it gets there,
            // particles are released from the top layer.
            lv.min((self.params.size[2] - 1) as f64)
        } else {
            lv
        }
    }

    fn launch(&mut self) -> [i32; 3] {
        let lv = self.launch_level();
        if self.plane {
            let [nx, ny, _] = self.params.size;
            loop {
                let x = below(&mut self.rng, nx as u64) as i32;
                let y = below(&mut self.rng, ny as u64) as i32;
                let p = [x, y, lv.round() as i32];
                if !self.occ.get(p) {
                    return p;
                }
            }
        } else {
            let u = self.direction();
            round(add(self.center, scale(u, lv)))
        }
    }

    /// A uniform direction (the x–z circle in 2-D).
    fn direction(&mut self) -> [f64; 3] {
        if self.three_d {
            unit_vector3(&mut self.rng)
        } else {
            let t = std::f64::consts::TAU * unit(&mut self.rng);
            [t.cos(), 0.0, t.sin()]
        }
    }

    /// Wraps x and y in plane mode (or folds them back between the walls) and
    /// mirrors below the floor.
    fn settle(&self, mut p: [i32; 3]) -> [i32; 3] {
        if self.plane {
            let [nx, ny, _] = self.params.size;
            if self.walls {
                p[0] = fold(p[0], nx as i32);
                p[1] = fold(p[1], ny as i32);
            } else {
                p[0] = p[0].rem_euclid(nx as i32);
                p[1] = p[1].rem_euclid(ny as i32);
            }
            if p[2] < 0 {
                p[2] = -1 - p[2];
            }
        }
        p
    }

    /// Handles a walker beyond the return distance; returns the new position, or
    /// `None` when the walker stays where it is.
    fn far_field(&mut self, w: [i32; 3]) -> Option<[i32; 3]> {
        let lv = self.launch_level();
        if self.plane {
            let h = w[2] as f64 - lv.round();
            if h <= 0.0 {
                return None;
            }
            self.stats.returns += 1;
            let [nx, ny, _] = self.params.size;
            let (dx, dy) = if self.three_d {
                // Half-space Poisson kernel: P(ρ' < ρ) = 1 − h/√(ρ² + h²).
                let u = unit(&mut self.rng);
                let rho = h * ((1.0 / (1.0 - u).powi(2)) - 1.0).sqrt();
                let phi = std::f64::consts::TAU * unit(&mut self.rng);
                (rho * phi.cos(), rho * phi.sin())
            } else {
                (
                    h * (std::f64::consts::PI * (unit(&mut self.rng) - 0.5)).tan(),
                    0.0,
                )
            };
            // The offset can span many periods: reduce it before rounding to a
            // cell (by the period of the mirror images between walls).
            let period = if self.walls { 2.0 } else { 1.0 };
            let x = (w[0] as f64 + dx).rem_euclid(period * nx as f64);
            let y = (w[1] as f64 + dy).rem_euclid(period * ny as f64);
            let p = self.settle([x.round() as i32, y.round() as i32, lv.round() as i32]);
            // Only a deposit capped at the lattice top can occupy the launch plane.
            return Some(if self.occ.get(p) { self.launch() } else { p });
        }
        let rel = sub(w.map(f64::from), self.center);
        let r2 = rel[0] * rel[0] + rel[1] * rel[1] + rel[2] * rel[2];
        let far = 1.5 * lv + 4.0;
        if r2 <= far * far {
            return None;
        }
        let r = r2.sqrt();
        self.stats.returns += 1;
        let n = scale(rel, 1.0 / r);
        let dir = if self.three_d {
            if unit(&mut self.rng) >= lv / r {
                self.stats.escapes += 1;
                return Some(self.launch());
            }
            // cos θ from the exterior Poisson kernel, by inverting its CDF.
            let (a, b) = (r * r + lv * lv, 2.0 * r * lv);
            let s = 1.0 / (r + lv) + unit(&mut self.rng) * (1.0 / (r - lv) - 1.0 / (r + lv));
            let c = ((a - 1.0 / (s * s)) / b).clamp(-1.0, 1.0);
            let (e1, e2) = orthonormal(n);
            let phi = std::f64::consts::TAU * unit(&mut self.rng);
            let sn = (1.0 - c * c).sqrt();
            add(
                scale(n, c),
                add(scale(e1, sn * phi.cos()), scale(e2, sn * phi.sin())),
            )
        } else {
            // Wrapped Cauchy with scale ln(r/R) about the walker's angle.
            let gamma = (r / lv).ln();
            let t = n[2].atan2(n[0])
                + gamma * (std::f64::consts::PI * (unit(&mut self.rng) - 0.5)).tan();
            [t.cos(), 0.0, t.sin()]
        };
        Some(round(add(self.center, scale(dir, lv))))
    }

    /// A radius around `w` free of occupied cells.
    fn free_radius(&self, w: [i32; 3]) -> f64 {
        let global = || {
            if self.plane {
                w[2] as f64 - self.reach
            } else {
                dist(w.map(f64::from), self.center) - self.reach
            }
        };
        match self.occ.canonical(w) {
            Some(q) => {
                // The walk is one chain of dependent reads, each likely a
                // cache miss in a large lattice: ask for the finer maps at
                // once, so their misses overlap with the coarse one's.
                self.medium.prefetch(q);
                self.fine.prefetch(q);
                self.contact.prefetch(q);
                // Coarse to fine: a far walker touches only the small maps.
                if !self.coarse.near(q) {
                    let c = self.coarse.lower_bound(q);
                    return if self.coarse.capped(q) {
                        c.max(global())
                    } else {
                        c
                    };
                }
                if !self.medium.near(q) {
                    return self.medium.lower_bound(q);
                }
                self.fine.lower_bound(q)
            }
            None => {
                // Outside the lattice (radial modes): the cluster is inside it.
                let mut out: f64 = 0.0;
                for (a, &c) in w.iter().enumerate() {
                    let v = c as f64;
                    let hi = self.params.size[a] as f64 - 1.0;
                    out = out.max(-v).max(v - hi);
                }
                out.max(global())
            }
        }
    }

    /// Walks one particle until it sticks; returns its cell.
    fn walk(&mut self) -> [i32; 3] {
        let dirs: &[[i32; 3]] = if self.three_d { &DIRS3 } else { &DIRS2 };
        let ndirs = dirs.len() as u64;
        let stick = self.params.stick;
        let mut w = self.launch();
        loop {
            if let Some(p) = self.far_field(w) {
                w = p;
                continue;
            }
            let d = self.free_radius(w);
            if d >= 3.0 {
                self.stats.jumps += 1;
                let u = self.direction();
                w = self.settle(round(add(w.map(f64::from), scale(u, d - 2.0))));
                continue;
            }
            // Near the cluster: single steps while the walker stays in this
            // 4-cell block (the maps cannot tell more inside it). The block's
            // word of the contact set says where the walker touches the
            // cluster; with p = 1 a walker that does not touch has no occupied
            // neighbour, so its moves need no occupancy look-up.
            let block = w.map(|v| v >> 2);
            let contact = self.contact.block_word(w);
            loop {
                let touching = contact >> Occupancy::bit_in_block(w) & 1 == 1;
                if touching && (stick >= 1.0 || unit(&mut self.rng) < stick) {
                    return w;
                }
                self.stats.steps += 1;
                let e = dirs[below(&mut self.rng, ndirs) as usize];
                let n = [w[0] + e[0], w[1] + e[1], w[2] + e[2]];
                if !(touching && self.occ.get(n) || self.plane && n[2] < 0) {
                    w = self.settle(n);
                }
                if w.map(|v| v >> 2) != block {
                    break;
                }
            }
        }
    }
}

/// Where the growth stopped or changed mode.
#[derive(Default)]
struct Ending {
    stopped: Option<String>,
    capped_at: Option<usize>,
    /// Particles in the top layer (a capped plane deposit launches from it).
    top_used: usize,
}

impl Walk<'_> {
    /// The seed's solid cells (occupied throughout); a density image draws its
    /// seeds with this walk's generator.
    fn solid_seed(&mut self) -> Result<Vec<[i32; 3]>, GrowthError> {
        let size = self.params.size;
        let center = self.center;
        Ok(match &self.params.seed_shape {
            SeedShape::Point => vec![center.map(|c| c as i32)],
            SeedShape::Plane => (0..size[1] as i32)
                .flat_map(|y| (0..size[0] as i32).map(move |x| [x, y, 0]))
                .collect(),
            SeedShape::Sphere(r) => {
                let ri = r.ceil() as i32 + 1;
                let c = center.map(|v| v as i32);
                let mut v = Vec::new();
                for dz in -ri..=ri {
                    for dy in if self.three_d { -ri..=ri } else { 0..=0 } {
                        for dx in -ri..=ri {
                            if ((dx * dx + dy * dy + dz * dz) as f64) <= r * r {
                                v.push([c[0] + dx, c[1] + dy, c[2] + dz]);
                            }
                        }
                    }
                }
                v
            }
            SeedShape::Cells(cells) => {
                if let Some(c) = cells
                    .iter()
                    .find(|&&c| (0..3).any(|a| c[a] < 1 || c[a] >= size[a] as i32 - 1))
                {
                    return Err(bad(format!(
                        "seed cell {c:?} lies on or outside the lattice boundary {}x{}x{}",
                        size[0], size[1], size[2]
                    )));
                }
                cells.clone()
            }
            SeedShape::Density(d) => {
                let mut v = Vec::new();
                for (k, &p) in d.iter().enumerate() {
                    if unit(&mut self.rng) < p {
                        v.push([(k % size[0]) as i32, (k / size[0]) as i32, 0]);
                    }
                }
                if v.is_empty() {
                    return Err(bad(
                        "the seed density image produced no seed (it is black or too dark)",
                    ));
                }
                v
            }
        })
    }

    /// The solid's cells with an empty face neighbour: the listed seeds.
    fn surface_of(&self, solid: &[[i32; 3]]) -> Vec<[i32; 3]> {
        let d: &[[i32; 3]] = if self.three_d { &DIRS3 } else { &DIRS2 };
        solid
            .iter()
            .copied()
            .filter(|&c| {
                d.iter().any(|e| {
                    let n = [c[0] + e[0], c[1] + e[1], c[2] + e[2]];
                    !(self.occ.get(n) || self.plane && n[2] < 0)
                })
            })
            .collect()
    }

    /// After particle `k` stuck at `p`: whether the run must stop (a full top
    /// layer, a radial cluster at the boundary); records the cap.
    fn check_bounds(&self, k: usize, p: [i32; 3], end: &mut Ending) -> bool {
        let (size, particles) = (self.params.size, self.params.particles);
        if self.plane {
            let top = size[2] as i32 - 1;
            if p[2] >= top - self.params.launch_gap.round() as i32 && end.capped_at.is_none() {
                end.capped_at = Some(k + 1);
            }
            if p[2] == top {
                end.top_used += 1;
            }
            if end.top_used == size[0] * size[1] && k + 1 < particles {
                end.stopped = Some(format!(
                    "the lattice's top layer is full after {} particles; use a larger --size",
                    k + 1
                ));
                return true;
            }
            return false;
        }
        let edge = (0..3).any(|a| size[a] > 1 && (p[a] < 2 || p[a] >= size[a] as i32 - 2));
        if edge && k + 1 < particles {
            end.stopped = Some(format!(
                "the deposit reached the lattice boundary after {} particles; use a larger --size",
                k + 1
            ));
            return true;
        }
        false
    }
}

/// Grows a DLA cluster with the generator of run `run` under `seed`.
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
    params.validate(budget)?;
    let plane = params.seed_shape.is_plane();
    let periodic = params.periodic();
    let occ = Occupancy::new(params.size, periodic, budget)?;
    let size = params.size;
    let center = [0, 1, 2].map(|a| ((size[a] - 1) / 2) as f64);
    let mut walk = Walk {
        params,
        three_d: params.dim == 3,
        plane,
        walls: plane && !periodic,
        contact: Occupancy::new(params.size, periodic, budget)?,
        fine: DistanceMap::new(&occ, 2, MAP_CAP),
        medium: DistanceMap::new(&occ, 3, MAP_CAP),
        coarse: DistanceMap::new(&occ, coarse_shift(size, periodic), MAP_CAP),
        occ,
        center,
        reach: 0.0,
        rng: fast_rng(seed, run),
        stats: WalkStats::default(),
    };
    let solid = walk.solid_seed()?;
    for &c in &solid {
        walk.occupy(c);
    }
    let mut cells = walk.surface_of(&solid);
    let seeds = cells.len();
    if plane && size[2] < 4 {
        return Err(bad("a plane deposit needs a lattice at least 4 cells high"));
    }
    cells.reserve(params.particles);
    progress.start(params.particles as u64, "DLA");
    let mut end = Ending::default();
    for k in 0..params.particles {
        let p = walk.walk();
        walk.occupy(p);
        cells.push(p);
        if k % 1024 == 1023 {
            progress.advance(1024);
        }
        if walk.check_bounds(k, p, &mut end) {
            break;
        }
    }
    progress.finish();
    Ok(DlaCluster {
        dim: params.dim,
        size,
        cells,
        seeds,
        center,
        stopped: end.stopped,
        capped_at: end.capped_at,
        stats: walk.stats,
    })
}

/// Cell `v` of the unfolded line mapped into `0..n` between reflecting walls at
/// −½ and n − ½: the mirror images of the box tile the line with period 2n.
#[inline(always)]
fn fold(v: i32, n: i32) -> i32 {
    let m = v.rem_euclid(2 * n);
    if m >= n { 2 * n - 1 - m } else { m }
}

/// Nearest cell (ties up). `f64::round` is a libm call on baseline x86-64;
/// truncation of a shifted positive value is not. Positions stay far inside
/// ±2²⁰ (walkers beyond 1.5 R + 4 are returned).
#[inline(always)]
fn round(a: [f64; 3]) -> [i32; 3] {
    const SHIFT: f64 = (1 << 20) as f64;
    a.map(|v| ((v + 0.5 + SHIFT) as i64 - (1 << 20)) as i32)
}

/// Two unit vectors completing unit `n` to an orthonormal basis.
fn orthonormal(n: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let t = if n[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let e1 = {
        let c = [
            n[1] * t[2] - n[2] * t[1],
            n[2] * t[0] - n[0] * t[2],
            n[0] * t[1] - n[1] * t[0],
        ];
        scale(c, 1.0 / norm(c))
    };
    let e2 = [
        n[1] * e1[2] - n[2] * e1[1],
        n[2] * e1[0] - n[0] * e1[2],
        n[0] * e1[1] - n[1] * e1[0],
    ];
    (e1, e2)
}
