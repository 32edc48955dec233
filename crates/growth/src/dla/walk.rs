//! One DLA walk: the lattice the walkers share, and the walk of one particle
//! from its launch to the cell where it sticks (see [`super`] for the model,
//! the exact returns and the big jumps).
//!
//! A walk reads the lattice and writes nothing; `Lattice::occupy` adds the
//! particle afterwards. So that a walk may run while earlier particles are
//! still being added ([`super::speculative`]), a walker can *note* what it
//! reads: for every look-up whose answer a later particle could change, the
//! box of cells where such a particle would have to land (see `CellBox`).
//! A walk none of whose boxes holds a particle added meanwhile, and which saw
//! the same reach, read exactly what it would have read after them.

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering::Relaxed};

use asperity_core::vec3::{add, dist, norm, scale, sub};
use rand::SeedableRng;

use super::{DIRS2, DIRS3, DlaParams, SeedShape, WalkStats};
use crate::GrowthError;
use crate::error::bad;
use crate::occupancy::{DistanceMap, Occupancy};
use crate::rng::{FastRng, below, unit, unit_vector3};

/// What every walk of a run shares and never changes.
pub(super) struct Setup<'a> {
    pub params: &'a DlaParams,
    pub three_d: bool,
    pub plane: bool,
    /// Plane mode between reflecting side walls.
    pub walls: bool,
    /// The centre of radial modes (cell coordinates).
    pub center: [f64; 3],
}

/// The cluster as the walkers see it. Every walker reads it; one thread at a
/// time adds a particle to it.
pub(super) struct Lattice {
    pub occ: Occupancy,
    /// The contact set: cells with an occupied face neighbour (see
    /// [`Occupancy::set_neighbours`]), so a single step reads one word.
    pub contact: Occupancy,
    pub fine: DistanceMap,
    pub medium: DistanceMap,
    pub coarse: DistanceMap,
    /// Farthest occupied distance from the centre (radial) or highest z
    /// (plane), as `f64` bits.
    reach: AtomicU64,
    /// Plane modes: occupied cells in the lattice's top layer (a full one
    /// ends the run).
    top_used: AtomicUsize,
}

impl Lattice {
    pub fn new(
        occ: Occupancy,
        contact: Occupancy,
        [fine, medium, coarse]: [DistanceMap; 3],
    ) -> Self {
        Self {
            occ,
            contact,
            fine,
            medium,
            coarse,
            reach: AtomicU64::new(0f64.to_bits()),
            top_used: AtomicUsize::new(0),
        }
    }

    /// The reach walks start from.
    pub fn reach(&self) -> f64 {
        f64::from_bits(self.reach.load(Relaxed))
    }

    /// Plane modes: occupied cells in the top layer.
    pub fn top_used(&self) -> usize {
        self.top_used.load(Relaxed)
    }

    /// Adds cell `p` (inside the lattice). One writer at a time (see
    /// [`DistanceMap::occupy`]); walkers may read meanwhile.
    pub fn occupy(&self, setup: &Setup, p: [i32; 3]) {
        let q = self.occ.canonical(p).expect("inside the lattice");
        self.occ.set(q);
        self.contact.set_neighbours(q, setup.three_d);
        self.fine.occupy(q);
        self.medium.occupy(q);
        self.coarse.occupy(q);
        let r = if setup.plane {
            p[2] as f64
        } else {
            dist(p.map(f64::from), setup.center)
        };
        if r > self.reach() {
            self.reach.store(r.to_bits(), Relaxed);
        }
        if setup.plane && q[2] + 1 == setup.params.size[2] as i32 {
            self.top_used.fetch_add(1, Relaxed);
        }
    }
}

/// Where the growth stopped or changed mode.
#[derive(Default)]
pub(super) struct Ending {
    pub stopped: Option<String>,
    pub capped_at: Option<usize>,
}

impl Setup<'_> {
    /// The seed's solid cells (occupied throughout); a density image draws its
    /// seeds with `rng`.
    pub(super) fn solid_seed(&self, rng: &mut FastRng) -> Result<Vec<[i32; 3]>, GrowthError> {
        let size = self.params.size;
        let center = self.center;
        Ok(match &self.params.seed_shape {
            SeedShape::Point => vec![center.map(|c| c as i32)],
            SeedShape::Plane => (0..size[1] as i32)
                .flat_map(|y| (0..size[0] as i32).map(move |x| [x, y, 0]))
                .collect(),
            SeedShape::Sphere(r) => super::ball_cells(center, *r, self.three_d),
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
                    if unit(rng) < p {
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
    pub(super) fn surface_of(&self, lat: &Lattice, solid: &[[i32; 3]]) -> Vec<[i32; 3]> {
        let d: &[[i32; 3]] = if self.three_d { &DIRS3 } else { &DIRS2 };
        solid
            .iter()
            .copied()
            .filter(|&c| {
                d.iter().any(|e| {
                    let n = [c[0] + e[0], c[1] + e[1], c[2] + e[2]];
                    !(lat.occ.get(n) || self.plane && n[2] < 0)
                })
            })
            .collect()
    }

    /// After particle `k` stuck at `p` (added to `lat`): whether the run must
    /// stop (a full top layer, a radial cluster at the boundary); records the
    /// cap.
    pub(super) fn check_bounds(
        &self,
        (k, p): (usize, [i32; 3]),
        lat: &Lattice,
        end: &mut Ending,
    ) -> bool {
        let (size, particles) = (self.params.size, self.params.particles);
        if self.plane {
            let top = size[2] as i32 - 1;
            if p[2] >= top - self.params.launch_gap.round() as i32 && end.capped_at.is_none() {
                end.capped_at = Some(k + 1);
            }
            if lat.top_used() == size[0] * size[1] && k + 1 < particles {
                end.stopped = Some(format!(
                    "the lattice's top layer is full after {} particles; use a larger ⟨size⟩",
                    k + 1
                ));
                return true;
            }
            return false;
        }
        let edge = (0..3).any(|a| size[a] > 1 && (p[a] < 2 || p[a] >= size[a] as i32 - 2));
        if edge && k + 1 < particles {
            end.stopped = Some(format!(
                "the deposit reached the lattice boundary after {} particles; use a larger ⟨size⟩",
                k + 1
            ));
            return true;
        }
        false
    }
}

/// An inclusive box of cells (canonical coordinates; x and y wrap on a
/// periodic lattice): a particle landing inside it may change what a walk
/// read. Boxes may reach past the lattice.
#[derive(Clone, Copy, Debug)]
pub(super) struct CellBox {
    pub lo: [i32; 3],
    pub hi: [i32; 3],
}

impl CellBox {
    /// Whether cell `p` (canonical) lies in the box; `period` holds the x and
    /// y sizes of a periodic lattice, 0 on an open one.
    #[inline(always)]
    pub fn holds(&self, p: [i32; 3], period: [i32; 2]) -> bool {
        (0..3).all(|a| {
            let (lo, hi) = (self.lo[a], self.hi[a]);
            match period.get(a) {
                Some(&n) if n > 0 => hi - lo + 1 >= n || (p[a] - lo).rem_euclid(n) <= hi - lo,
                _ => lo <= p[a] && p[a] <= hi,
            }
        })
    }
}

/// One particle's walker: its own generator, work counters and, when asked,
/// the notes of what it read.
pub(super) struct Walker<'a> {
    setup: &'a Setup<'a>,
    lat: &'a Lattice,
    /// Particle k's generator is seeded from this and k (see [`Walker::begin`]).
    streams: u64,
    rng: FastRng,
    pub stats: WalkStats,
    /// The reach this walk reads: the lattice's when it began.
    pub reach: f64,
    noting: bool,
    pub reads: Vec<CellBox>,
}

impl<'a> Walker<'a> {
    pub fn new(setup: &'a Setup<'a>, lat: &'a Lattice, streams: u64) -> Self {
        Self {
            setup,
            lat,
            streams,
            rng: FastRng::seed_from_u64(streams),
            stats: WalkStats::default(),
            reach: 0.0,
            noting: false,
            reads: Vec::new(),
        }
    }

    /// Prepares the walk of particle `k`: its own generator (SplitMix64 of the
    /// run's stream seed and k, so a walk draws the same numbers whichever
    /// thread runs it, and whenever), zero counters, the lattice's reach;
    /// `noting` asks for the notes of what it reads.
    pub fn begin(&mut self, k: usize, noting: bool) {
        let key = self.streams ^ (k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        self.rng = FastRng::seed_from_u64(key);
        self.stats = WalkStats::default();
        self.reach = self.lat.reach();
        self.noting = noting;
        self.reads.clear();
    }

    /// Notes that the walk read cells `lo..=hi`'s state (or values they change).
    #[inline(always)]
    fn note(&mut self, lo: [i32; 3], hi: [i32; 3]) {
        if self.noting {
            self.reads.push(CellBox { lo, hi });
        }
    }

    /// Notes that the walk read block distance `k` of `map` at `q`.
    #[inline(always)]
    fn note_map(&mut self, map: &DistanceMap, q: [i32; 3], k: u8) {
        if self.noting
            && let Some((lo, hi)) = map.influence(q, k)
        {
            self.reads.push(CellBox { lo, hi });
        }
    }

    fn launch_level(&self) -> f64 {
        let lv = self.reach + self.setup.params.launch_gap;
        if self.setup.plane {
            // A plane deposit is capped by the lattice top: once it gets there,
            // particles are released from the top layer.
            lv.min((self.setup.params.size[2] - 1) as f64)
        } else {
            lv
        }
    }

    fn launch(&mut self) -> [i32; 3] {
        let lv = self.launch_level();
        if self.setup.plane {
            let [nx, ny, _] = self.setup.params.size;
            loop {
                let x = below(&mut self.rng, nx as u64) as i32;
                let y = below(&mut self.rng, ny as u64) as i32;
                let p = [x, y, lv.round() as i32];
                self.note(p, p);
                if !self.lat.occ.get(p) {
                    return p;
                }
                if self.lat.top_used() == nx * ny {
                    // Only a walk started ahead of its turn sees a full top
                    // layer: the run stops before its turn comes. End it.
                    return p;
                }
            }
        } else {
            let u = self.direction();
            round(add(self.setup.center, scale(u, lv)))
        }
    }

    /// A uniform direction (the x–z circle in 2-D).
    fn direction(&mut self) -> [f64; 3] {
        if self.setup.three_d {
            unit_vector3(&mut self.rng)
        } else {
            let t = std::f64::consts::TAU * unit(&mut self.rng);
            [t.cos(), 0.0, t.sin()]
        }
    }

    /// Wraps x and y in plane mode (or folds them back between the walls) and
    /// mirrors below the floor.
    fn settle(&self, mut p: [i32; 3]) -> [i32; 3] {
        if self.setup.plane {
            let [nx, ny, _] = self.setup.params.size;
            if self.setup.walls {
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
        if self.setup.plane {
            let h = w[2] as f64 - lv.round();
            if h <= 0.0 {
                return None;
            }
            self.stats.returns += 1;
            let [nx, ny, _] = self.setup.params.size;
            let (dx, dy) = if self.setup.three_d {
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
            let period = if self.setup.walls { 2.0 } else { 1.0 };
            let x = (w[0] as f64 + dx).rem_euclid(period * nx as f64);
            let y = (w[1] as f64 + dy).rem_euclid(period * ny as f64);
            let p = self.settle([x.round() as i32, y.round() as i32, lv.round() as i32]);
            // Only a deposit capped at the lattice top can occupy the launch plane.
            self.note(p, p);
            return Some(if self.lat.occ.get(p) {
                self.launch()
            } else {
                p
            });
        }
        let rel = sub(w.map(f64::from), self.setup.center);
        let r2 = rel[0] * rel[0] + rel[1] * rel[1] + rel[2] * rel[2];
        let far = 1.5 * lv + 4.0;
        if r2 <= far * far {
            return None;
        }
        let r = r2.sqrt();
        self.stats.returns += 1;
        let n = scale(rel, 1.0 / r);
        let dir = if self.setup.three_d {
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
        Some(round(add(self.setup.center, scale(dir, lv))))
    }

    /// A radius around `w` free of occupied cells.
    fn free_radius(&mut self, w: [i32; 3]) -> f64 {
        let lat = self.lat;
        let Some(q) = lat.occ.canonical(w) else {
            // Outside the lattice (radial modes): the cluster is inside it.
            let mut out: f64 = 0.0;
            for (a, &c) in w.iter().enumerate() {
                let v = c as f64;
                let hi = self.setup.params.size[a] as f64 - 1.0;
                out = out.max(-v).max(v - hi);
            }
            return out.max(self.global_bound(w));
        };
        // The walk is one chain of dependent reads, each likely a cache miss
        // in a large lattice: ask for the finer maps at once, so their misses
        // overlap with the coarse one's.
        lat.medium.prefetch(q);
        lat.fine.prefetch(q);
        lat.contact.prefetch(q);
        // Coarse to fine: a far walker touches only the small maps. A map
        // that says "near" (k ≤ 1) says so whatever is added later, so only
        // the others are noted.
        let k = lat.coarse.block_distance(q);
        if !DistanceMap::is_near(k) {
            self.note_map(&lat.coarse, q, k);
            let c = lat.coarse.bound(q, k);
            return if lat.coarse.is_cap(k) {
                c.max(self.global_bound(w))
            } else {
                c
            };
        }
        let k = lat.medium.block_distance(q);
        if !DistanceMap::is_near(k) {
            self.note_map(&lat.medium, q, k);
            return lat.medium.bound(q, k);
        }
        // Fine distances 0 and 1 give bounds under 3 (single steps), which a
        // later particle cannot change either.
        let k = lat.fine.block_distance(q);
        if !DistanceMap::is_near(k) {
            self.note_map(&lat.fine, q, k);
        }
        lat.fine.bound(q, k)
    }

    /// The bound from the reach alone: distance above the highest cell
    /// (plane) or beyond the farthest (radial).
    fn global_bound(&self, w: [i32; 3]) -> f64 {
        if self.setup.plane {
            w[2] as f64 - self.reach
        } else {
            dist(w.map(f64::from), self.setup.center) - self.reach
        }
    }

    /// Walks one particle until it sticks; returns its cell.
    pub fn walk(&mut self) -> [i32; 3] {
        let dirs: &[[i32; 3]] = if self.setup.three_d { &DIRS3 } else { &DIRS2 };
        let ndirs = dirs.len() as u64;
        let stick = self.setup.params.stick;
        let plane = self.setup.plane;
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
            let contact = self.lat.contact.block_word(w);
            if self.noting
                && let Some(q) = self.lat.occ.canonical(w)
            {
                // The contact word and the neighbours' bits read below: a
                // particle within one cell of this block changes them.
                let lo = q.map(|v| (v & !3) - 1);
                self.note(lo, lo.map(|v| v + 5));
            }
            loop {
                let touching = contact >> Occupancy::bit_in_block(w) & 1 == 1;
                if touching && (stick >= 1.0 || unit(&mut self.rng) < stick) {
                    return w;
                }
                self.stats.steps += 1;
                let e = dirs[below(&mut self.rng, ndirs) as usize];
                let n = [w[0] + e[0], w[1] + e[1], w[2] + e[2]];
                if !(touching && self.lat.occ.get(n) || plane && n[2] < 0) {
                    w = self.settle(n);
                }
                if w.map(|v| v >> 2) != block {
                    break;
                }
            }
        }
    }
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
