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

use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering, fence};
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
/// shrinks by a quarter (to no less than two walks) when more than
/// `REDO_HIGH` of them were walked again, and grows by a quarter of the
/// threads when fewer than `REDO_LOW` were. A walk started k commits ahead
/// is redone with a chance about proportional to k (10⁶ particles, 16
/// walkers on 2 cores with the fixed window of 64: 53 in flight, 9.1 %
/// redone; with 2 walkers and 8: 2.5 in flight, 0.4 %). More walkers than
/// cores need a window below one walk a walker: walkers that leave their
/// walk to the committer start their next one on an older cluster (2·10⁵
/// particles, 16 walkers on 2 cores: 6.6 % redone with the floor at 16,
/// 2.8 % at 2).
const ADAPT_EVERY: usize = 512;
const REDO_HIGH: f64 = 0.025;
const REDO_LOW: f64 = 0.01;

/// Spins a walker makes while waiting for the window before it sleeps (a
/// commit is usually microseconds away; a sleep and a wake cost a few).
const SPINS_BEFORE_SLEEP: u32 = 200;

/// Stops the run when a worker unwinds.
struct StopOnUnwind<'a, 'g>(&'a Growth<'g>);

impl Drop for StopOnUnwind<'_, '_> {
    fn drop(&mut self) {
        if std::thread::panicking() {
            self.0.stop.store(true, Ordering::Relaxed);
            self.0.wake_sleepers();
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
    stop: bool,
    /// Σ over commits of the walks in flight then.
    in_flight_sum: u64,
    /// Walks redone since the window last adapted.
    recent_redos: usize,
    /// Nanoseconds waited for the window, over all walkers.
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
            stop: false,
            in_flight_sum: 0,
            recent_redos: 0,
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
    /// Finished walks by particle index modulo the window, waiting for
    /// their commit. Outside the ledger, so that a walker leaves its walk
    /// without waiting for the thread that is committing (see `commit_due`).
    pending: Vec<Mutex<Option<Outcome>>>,
    /// Walkers asleep until the window reaches their particle (or the run
    /// stops): how many, and each one's particle and thread, woken one by
    /// one as the window reaches it. Waiting blocks instead of spinning or
    /// yielding: on a busy machine a yield handed the core to the other
    /// program for its whole slice (#55); and only the walker whose turn
    /// came is woken, not all of them.
    sleepers: AtomicUsize,
    asleep: Mutex<Vec<(usize, std::thread::Thread)>>,
    /// Nanoseconds waited for the window (added to the ledger at the end).
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
            pending: Vec::new(),
            sleepers: AtomicUsize::new(0),
            asleep: Mutex::new(Vec::new()),
            window_wait_ns: AtomicU64::new(0),
        }
    }

    /// The finished walk of particle `k`, if it is there.
    fn slot(&self, k: usize) -> MutexGuard<'_, Option<Outcome>> {
        let slot = &self.pending[k % self.window];
        slot.lock().unwrap_or_else(|e| e.into_inner())
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
            self.pending = (0..self.window).map(|_| Mutex::new(None)).collect();
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
        let window = self.window_wait_ns.load(Ordering::Relaxed);
        let mut ledger = self.ledger.into_inner().unwrap_or_else(|e| e.into_inner());
        ledger.window_wait_ns = window;
        ledger
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
        let _stop_on_unwind = StopOnUnwind(self);
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
            *self.slot(j) = Some(outcome);
            self.commit_due(&mut walker);
            if self.stop.load(Ordering::Relaxed) {
                return;
            }
        }
    }

    /// Commits the finished walks that are due, in order, unless another
    /// thread is committing: that one commits them, this one walks on.
    /// Nobody waits for the ledger (#55: one walker blocked on the other's
    /// commit for a sleep and a wake, a fifth of its time).
    ///
    /// No walk is left behind: a walker leaves its walk, then tries the
    /// ledger; the committer releases the ledger, then looks again at the
    /// next slot. With a sequentially consistent fence on each side, either
    /// the walker finds the ledger free or the committer finds the walk.
    fn commit_due(&self, walker: &mut Walker<'_>) {
        loop {
            fence(Ordering::SeqCst);
            let mut ledger = match self.ledger.try_lock() {
                Ok(guard) => guard,
                Err(std::sync::TryLockError::Poisoned(e)) => e.into_inner(),
                Err(std::sync::TryLockError::WouldBlock) => return,
            };
            while !(ledger.stop || self.stop.load(Ordering::Relaxed)) {
                let k = ledger.committed;
                let Some(done) = self.slot(k).take() else {
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
            let next = ledger.committed;
            drop(ledger);
            fence(Ordering::SeqCst);
            if self.stop.load(Ordering::Relaxed) || self.slot(next).is_none() {
                return;
            }
        }
    }

    /// Waits until particle `j` is within the window of the committed ones:
    /// a few spins, then asleep until a commit moves the window; false when
    /// the run stopped meanwhile.
    fn wait_for_window(&self, j: usize) -> bool {
        let ahead = || self.committed.load(Ordering::SeqCst) + self.limit.load(Ordering::SeqCst);
        let stopped = || self.stop.load(Ordering::SeqCst);
        if j < ahead() {
            return !stopped();
        }
        let t = Instant::now();
        for _ in 0..SPINS_BEFORE_SLEEP {
            if j < ahead() || stopped() {
                break;
            }
            std::hint::spin_loop();
        }
        if j >= ahead() && !stopped() {
            // Registered before the last look: a commit after that look
            // finds this walker and wakes it (see `wake_sleepers`); a wake
            // before the park makes the park return at once.
            self.sleepers.fetch_add(1, Ordering::SeqCst);
            self.sleeping().push((j, std::thread::current()));
            while j >= ahead() && !stopped() {
                std::thread::park();
            }
            let mut asleep = self.sleeping();
            if let Some(i) = asleep.iter().position(|(k, _)| *k == j) {
                asleep.swap_remove(i);
            }
            drop(asleep);
            self.sleepers.fetch_sub(1, Ordering::SeqCst);
        }
        self.window_wait_ns
            .fetch_add(t.elapsed().as_nanos() as u64, Ordering::Relaxed);
        !stopped()
    }

    fn sleeping(&self) -> MutexGuard<'_, Vec<(usize, std::thread::Thread)>> {
        self.asleep.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Wakes the walkers asleep whose particle the window now reaches (all
    /// of them once the run stopped), if any.
    fn wake_sleepers(&self) {
        fence(Ordering::SeqCst);
        if self.sleepers.load(Ordering::SeqCst) == 0 {
            return;
        }
        let ahead = self.committed.load(Ordering::SeqCst) + self.limit.load(Ordering::SeqCst);
        let stopped = self.stop.load(Ordering::SeqCst);
        for (j, thread) in self.sleeping().iter() {
            if *j < ahead || stopped {
                thread.unpark();
            }
        }
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
        } else if k + 1 == self.particles {
            self.progress.advance(((k + 1) % 1024) as u64);
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
        self.committed.store(k + 1, Ordering::SeqCst);
        self.wake_sleepers();
    }

    /// Narrows the window when too many walks were redone, widens it when few
    /// were (see `ADAPT_EVERY`); between two walks and the slots.
    fn adapt(&self, ledger: &mut Ledger) {
        let rate = ledger.recent_redos as f64 / ADAPT_EVERY as f64;
        ledger.recent_redos = 0;
        let limit = self.limit.load(Ordering::Relaxed);
        let new = if rate > REDO_HIGH {
            (limit * 3 / 4).max(2)
        } else if rate < REDO_LOW {
            (limit + (self.threads / 4).max(1)).min(self.window)
        } else {
            limit
        };
        self.limit.store(new, Ordering::Relaxed);
    }
}
