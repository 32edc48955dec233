//! Walkers on every thread, with the result of one walker after another.
//!
//! DLA is sequential: particle k walks in the cluster of the k − 1 before it.
//! But a walk reads only a small part of the lattice, and most particles
//! stick far from where the next one wanders, so the next walks can start
//! before particle k is added and mostly read what they would have read after
//! it (optimistic concurrency, as in transactional memory).
//!
//! Each thread claims the next particle j, notes what its walk reads (the
//! boxes of `CellBox`, see [`super::walk`]) and leaves the cell it reached.
//! Particles are *committed* in order by whichever thread holds the ledger: a
//! walk is kept when no particle committed since it began landed in one of its
//! boxes and the reach it read is still the reach; otherwise it is walked
//! again, now on the exact cluster of its predecessors. Every committed
//! particle is therefore the one the plain sequential loop would give with
//! the same per-particle generators: the cluster is byte-identical at any
//! thread count, and only the time changes (tested against the sequential
//! loop, with walks started up to `WINDOW_PER_THREAD` × threads particles
//! ahead).
//!
//! Walks are not interrupted: at most a window of particles is claimed but
//! not committed, so a slow walk holds the others back only once they are a
//! window ahead of it, and every claimed particle is owned by a thread that
//! finishes it (no thread waits on a walk nobody runs).

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use asperity_core::Progress;

use super::WalkStats;
use super::walk::{CellBox, Ending, Lattice, Setup, Walker};

/// Particles one thread may walk ahead of the last committed one (10⁶-particle
/// cluster, two threads: a window of 1 per thread took 10.2 s, 2: 8.8 s, 4: 8.6 s,
/// 8: 8.6 s; 0.2–0.4 % of the walks were walked again).
pub(super) const WINDOW_PER_THREAD: usize = 4;

/// Sets the run's stop flag when a worker unwinds.
struct StopOnUnwind<'a>(&'a AtomicBool);

impl Drop for StopOnUnwind<'_> {
    fn drop(&mut self) {
        if std::thread::panicking() {
            self.0.store(true, Ordering::Relaxed);
        }
    }
}

/// A finished walk waiting for its turn.
struct Outcome {
    cell: [i32; 3],
    stats: WalkStats,
    /// Particles committed when the walk began.
    start: usize,
    /// The reach it read, as bits.
    reach: u64,
    reads: Vec<CellBox>,
}

/// The sequential record of the run; only the thread holding it commits.
pub(super) struct Ledger {
    /// Seeds, then particles in order.
    pub cells: Vec<[i32; 3]>,
    pub seeds: usize,
    pub end: Ending,
    pub stats: WalkStats,
    /// Walks done again (see `DlaCluster::rewalks`).
    pub rewalks: u64,
    /// Particles committed.
    committed: usize,
    /// Finished walks by particle index modulo the window.
    pending: Vec<Option<Outcome>>,
    stop: bool,
}

impl Ledger {
    pub fn new(cells: Vec<[i32; 3]>, seeds: usize) -> Self {
        Self {
            cells,
            seeds,
            end: Ending::default(),
            stats: WalkStats::default(),
            rewalks: 0,
            committed: 0,
            pending: Vec::new(),
            stop: false,
        }
    }
}

/// One run's growth: its lattice, its ledger and the threads' counters.
pub(super) struct Growth<'a> {
    pub setup: &'a Setup<'a>,
    pub lat: &'a Lattice,
    /// Seed of the particles' generators (see [`Walker::begin`]).
    pub streams: u64,
    pub progress: &'a dyn Progress,
    particles: usize,
    window: usize,
    /// Next particle to claim.
    next: AtomicUsize,
    /// `Ledger::committed`, readable without the lock.
    committed: AtomicUsize,
    stop: AtomicBool,
    ledger: Mutex<Ledger>,
}

impl<'a> Growth<'a> {
    pub fn new(
        setup: &'a Setup<'a>,
        lat: &'a Lattice,
        streams: u64,
        progress: &'a dyn Progress,
        ledger: Ledger,
    ) -> Self {
        Self {
            setup,
            lat,
            streams,
            progress,
            particles: setup.params.particles,
            window: 1,
            next: AtomicUsize::new(0),
            committed: AtomicUsize::new(0),
            stop: AtomicBool::new(false),
            ledger: Mutex::new(ledger),
        }
    }

    /// Grows all particles with `threads` walkers (1: the plain loop) and
    /// returns the ledger.
    pub fn run(mut self, threads: usize) -> Ledger {
        self.progress.start(self.particles as u64, "DLA");
        if threads <= 1 || self.particles < 2 {
            self.sequential();
        } else {
            self.window = WINDOW_PER_THREAD * threads;
            self.ledger_mut().pending = (0..self.window).map(|_| None).collect();
            let this = &self;
            rayon::scope(|s| {
                for _ in 0..threads {
                    s.spawn(move |_| this.worker());
                }
            });
        }
        self.progress.finish();
        self.ledger.into_inner().unwrap_or_else(|e| e.into_inner())
    }

    fn ledger_mut(&mut self) -> &mut Ledger {
        self.ledger.get_mut().unwrap_or_else(|e| e.into_inner())
    }

    fn sequential(&self) {
        let mut walker = Walker::new(self.setup, self.lat, self.streams);
        let mut ledger = self.ledger.lock().unwrap_or_else(|e| e.into_inner());
        for k in 0..self.particles {
            walker.begin(k, false);
            let cell = walker.walk();
            self.commit(&mut ledger, cell, walker.stats);
            if ledger.stop {
                break;
            }
        }
    }

    /// One thread: claim, walk ahead, leave the outcome, commit what is due.
    fn worker(&self) {
        // A panic here (a progress reporter cancelling the run unwinds through
        // `advance`) stops the other threads too; the scope re-raises it.
        let _stop_on_unwind = StopOnUnwind(&self.stop);
        let mut walker = Walker::new(self.setup, self.lat, self.streams);
        loop {
            let j = self.next.fetch_add(1, Ordering::Relaxed);
            if j >= self.particles || !self.wait_for_window(j) {
                return;
            }
            // Acquire: the lattice holds every particle before `start`.
            let start = self.committed.load(Ordering::Acquire);
            walker.begin(j, true);
            let cell = walker.walk();
            let outcome = Outcome {
                cell,
                stats: walker.stats,
                start,
                reach: walker.reach.to_bits(),
                reads: std::mem::take(&mut walker.reads),
            };
            let mut ledger = self.ledger.lock().unwrap_or_else(|e| e.into_inner());
            if ledger.stop || self.stop.load(Ordering::Relaxed) {
                return;
            }
            let slot = j % self.window;
            ledger.pending[slot] = Some(outcome);
            while !(ledger.stop || self.stop.load(Ordering::Relaxed)) {
                let k = ledger.committed;
                let Some(done) = ledger.pending[k % self.window].take() else {
                    break;
                };
                let (cell, stats) = if self.still_valid(&ledger, &done) {
                    (done.cell, done.stats)
                } else {
                    ledger.rewalks += 1;
                    walker.begin(k, false);
                    (walker.walk(), walker.stats)
                };
                walker.reads = done.reads;
                self.commit(&mut ledger, cell, stats);
            }
        }
    }

    /// Waits until particle `j` is within the window of the committed ones;
    /// false when the run stopped meanwhile.
    fn wait_for_window(&self, j: usize) -> bool {
        let mut spins = 0u32;
        while j >= self.committed.load(Ordering::Acquire) + self.window {
            if self.stop.load(Ordering::Relaxed) {
                return false;
            }
            spins += 1;
            if spins < 64 {
                std::hint::spin_loop();
            } else {
                std::thread::yield_now();
            }
        }
        !self.stop.load(Ordering::Relaxed)
    }

    /// Whether a walk read what it would have read on the committed cluster:
    /// the same reach, and no particle committed since it began in its boxes.
    fn still_valid(&self, ledger: &Ledger, done: &Outcome) -> bool {
        if done.reach != self.lat.reach().to_bits() {
            return false;
        }
        let period = if self.setup.params.periodic() {
            let s = self.setup.params.size;
            [s[0] as i32, s[1] as i32]
        } else {
            [0, 0]
        };
        // Committed cells are canonical (walks end inside the lattice, wrapped).
        let since = &ledger.cells[ledger.seeds + done.start..];
        since
            .iter()
            .all(|&p| !done.reads.iter().any(|b| b.holds(p, period)))
    }

    /// Adds the next particle at `cell` and records it.
    fn commit(&self, ledger: &mut Ledger, cell: [i32; 3], stats: WalkStats) {
        let k = ledger.committed;
        self.lat.occupy(self.setup, cell);
        ledger.cells.push(cell);
        ledger.stats += stats;
        ledger.committed = k + 1;
        if k % 1024 == 1023 {
            self.progress.advance(1024);
        }
        if self
            .setup
            .check_bounds((k, cell), self.lat, &mut ledger.end)
            || k + 1 == self.particles
        {
            ledger.stop = true;
            self.stop.store(true, Ordering::Relaxed);
        }
        // Release: a walk that reads this count sees the lattice with the cell.
        self.committed.store(k + 1, Ordering::Release);
    }
}
