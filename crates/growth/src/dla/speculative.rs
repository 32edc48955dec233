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

use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard};
use std::time::Instant;

use asperity_core::Progress;

use super::WalkStats;
use super::walk::{CellBox, Ending, Lattice, Setup, Walker};

/// Particles one thread may walk ahead of the last committed one, at most (10⁶-particle
/// cluster, two threads: a window of 1 per thread took 10.2 s, 2: 8.8 s, 4: 8.6 s,
/// 8: 8.6 s; 0.2–0.4 % of the walks were walked again).
pub(super) const WINDOW_PER_THREAD: usize = 4;

/// The window adapts to the walks redone: every `ADAPT_EVERY` commits it
/// shrinks by a quarter (to no less than one walk a thread) when more than
/// `REDO_HIGH` of them were walked again, and grows by a quarter of the
/// threads when fewer than `REDO_LOW` were. A walk started k commits ahead
/// is redone with a chance about proportional to k (10⁶ particles, 16
/// walkers on 2 cores with the fixed window of 64: 53 in flight, 9.1 %
/// redone; with 2 walkers and 8: 2.5 in flight, 0.4 %).
const ADAPT_EVERY: usize = 512;
const REDO_HIGH: f64 = 0.025;
const REDO_LOW: f64 = 0.01;

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
    /// Σ over commits of the walks in flight then.
    in_flight_sum: u64,
    /// Walks redone since the window last adapted.
    recent_redos: usize,
    /// Nanoseconds waited for the lock and for the window, over all walkers.
    lock_wait_ns: u64,
    window_wait_ns: u64,
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
            in_flight_sum: 0,
            recent_redos: 0,
            lock_wait_ns: 0,
            window_wait_ns: 0,
        }
    }

    /// The run's [`super::Concurrency`] with `walkers` walkers.
    pub fn concurrency(&self, walkers: usize) -> super::Concurrency {
        let n = self.committed.max(1) as f64;
        super::Concurrency {
            walkers: walkers.max(1),
            mean_in_flight: if walkers <= 1 {
                1.0
            } else {
                self.in_flight_sum as f64 / n
            },
            redone_fraction: self.rewalks as f64 / n,
            ledger_wait_s: self.lock_wait_ns as f64 * 1e-9,
            window_wait_s: self.window_wait_ns as f64 * 1e-9,
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
    /// Slots for finished walks: the largest window.
    window: usize,
    /// The window now: walks may start this many particles ahead of the
    /// committed ones (adapted to the walks redone, see `ADAPT_EVERY`).
    limit: AtomicUsize,
    threads: usize,
    /// Next particle to claim.
    next: AtomicUsize,
    /// `Ledger::committed`, readable without the lock.
    committed: AtomicUsize,
    stop: AtomicBool,
    ledger: Mutex<Ledger>,
    /// Nanoseconds waited for the lock and for the window (added to the
    /// ledger at the end).
    lock_wait_ns: AtomicU64,
    window_wait_ns: AtomicU64,
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
            limit: AtomicUsize::new(1),
            threads: 1,
            next: AtomicUsize::new(0),
            committed: AtomicUsize::new(0),
            stop: AtomicBool::new(false),
            ledger: Mutex::new(ledger),
            lock_wait_ns: AtomicU64::new(0),
            window_wait_ns: AtomicU64::new(0),
        }
    }

    /// The ledger, the wait for it counted.
    fn lock(&self) -> MutexGuard<'_, Ledger> {
        let t = Instant::now();
        let guard = self.ledger.lock().unwrap_or_else(|e| e.into_inner());
        self.lock_wait_ns
            .fetch_add(t.elapsed().as_nanos() as u64, Ordering::Relaxed);
        guard
    }

    /// Grows all particles with `threads` walkers (1: the plain loop) and
    /// returns the ledger.
    pub fn run(mut self, threads: usize) -> Ledger {
        self.progress.start(self.particles as u64, "DLA");
        if threads <= 1 || self.particles < 2 {
            self.sequential();
        } else {
            self.window = WINDOW_PER_THREAD * threads;
            self.threads = threads;
            self.limit = AtomicUsize::new(2 * threads);
            self.ledger_mut().pending = (0..self.window).map(|_| None).collect();
            let this = &self;
            let spawn = || {
                rayon::scope(|s| {
                    for _ in 0..threads {
                        s.spawn(move |_| this.worker());
                    }
                })
            };
            // More walkers than the pool's threads (e.g. 16 on 2 cores, to
            // measure what 16 cores would see) get a pool of their own: each
            // walker is a thread, or the extra ones would only queue.
            match (threads > rayon::current_num_threads())
                .then(|| rayon::ThreadPoolBuilder::new().num_threads(threads).build())
            {
                Some(Ok(pool)) => pool.install(spawn),
                _ => spawn(),
            }
        }
        self.progress.finish();
        let (lock, window) = (
            self.lock_wait_ns.load(Ordering::Relaxed),
            self.window_wait_ns.load(Ordering::Relaxed),
        );
        let mut ledger = self.ledger.into_inner().unwrap_or_else(|e| e.into_inner());
        ledger.lock_wait_ns = lock;
        ledger.window_wait_ns = window;
        ledger
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
            let mut ledger = self.lock();
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
                    ledger.recent_redos += 1;
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
        let ahead = || self.committed.load(Ordering::Acquire) + self.limit.load(Ordering::Relaxed);
        if j < ahead() {
            return !self.stop.load(Ordering::Relaxed);
        }
        let t = Instant::now();
        let mut spins = 0u32;
        while j >= ahead() {
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
        self.window_wait_ns
            .fetch_add(t.elapsed().as_nanos() as u64, Ordering::Relaxed);
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
        // Claimed and not yet committed, this one included.
        let claimed = self.next.load(Ordering::Relaxed).min(self.particles);
        ledger.in_flight_sum += claimed.saturating_sub(k) as u64;
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
        if self.threads > 1 && (k + 1).is_multiple_of(ADAPT_EVERY) {
            self.adapt(ledger);
        }
        // Release: a walk that reads this count sees the lattice with the cell.
        self.committed.store(k + 1, Ordering::Release);
    }

    /// Narrows the window when too many walks were redone, widens it when few
    /// were (see `ADAPT_EVERY`); between one walk a thread and the slots.
    fn adapt(&self, ledger: &mut Ledger) {
        let rate = ledger.recent_redos as f64 / ADAPT_EVERY as f64;
        ledger.recent_redos = 0;
        let limit = self.limit.load(Ordering::Relaxed);
        let new = if rate > REDO_HIGH {
            (limit * 3 / 4).max(self.threads)
        } else if rate < REDO_LOW {
            (limit + (self.threads / 4).max(1)).min(self.window)
        } else {
            limit
        };
        self.limit.store(new, Ordering::Relaxed);
    }
}
