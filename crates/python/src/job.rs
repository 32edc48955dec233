//! Running one engine job from Python: off the interpreter's lock, stoppable
//! by Ctrl-C, with progress, and with every failure an exception.
//!
//! The job runs on a worker thread while the calling thread waits with the
//! GIL released, waking every 100 ms to let Python handle signals and to show
//! progress. A KeyboardInterrupt sets a flag that the job's [`Progress`] reads
//! on its next report and unwinds from (with `resume_unwind`, which prints
//! nothing); the caller waits up to a second for that, then raises. Engine
//! errors become `ValueError`, `OSError`, `asperity.MemoryLimitError` or
//! `asperity.TimeLimitError` with the CLI's message; an internal panic
//! becomes a `RuntimeError` — the interpreter never aborts.

use std::panic::{AssertUnwindSafe, catch_unwind, resume_unwind};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{RecvTimeoutError, channel};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use asperity_engine::core::{CoreError, MemoryBudget, Progress, TimeBudget};
use asperity_engine::{EngineError, ErrorKind};
use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;

/// The limits every job runs under, set by `asperity.set_limits`.
static MAX_MEMORY: AtomicU64 = AtomicU64::new(0);
static MAX_TIME_S: AtomicU64 = AtomicU64::new(0);

/// Sets the memory budget in bytes (0: the system's, as the CLI: the least
/// of half of RAM and the headroom under the memory cgroup and rlimits) and the time
/// limit in seconds (0: one day, as the CLI; `u64::MAX`: none).
#[pyfunction]
#[pyo3(signature = (max_memory = 0, max_time = 0))]
pub fn set_limits(max_memory: u64, max_time: u64) {
    MAX_MEMORY.store(max_memory, Ordering::Relaxed);
    MAX_TIME_S.store(max_time, Ordering::Relaxed);
}

/// The memory budget in force, in bytes, and where it came from, as the CLI
/// report's `memory_budget` names it ("given", "half_of_ram", "cgroup", …).
#[pyfunction]
pub fn memory_budget() -> (u64, &'static str) {
    let b = budget();
    (b.limit(), b.source().name())
}

/// The memory budget in force.
pub fn budget() -> MemoryBudget {
    match MAX_MEMORY.load(Ordering::Relaxed) {
        0 => MemoryBudget::default(),
        n => MemoryBudget::new(n),
    }
}

/// The time budget in force for `threads` threads.
pub fn time_budget(threads: usize) -> TimeBudget {
    match MAX_TIME_S.load(Ordering::Relaxed) {
        0 => TimeBudget::new(asperity_engine::core::time_budget::DEFAULT_LIMIT, threads),
        u64::MAX => TimeBudget::unlimited(),
        s => TimeBudget::new(Duration::from_secs(s), threads),
    }
}

/// How a job runs: its thread count and an optional progress callback
/// `callback(done, total, message)`.
pub struct RunOptions {
    /// Worker threads (None: all cores, as the CLI).
    pub threads: Option<usize>,
    /// Called from the waiting thread about ten times a second.
    pub progress: Option<Py<PyAny>>,
}

impl RunOptions {
    /// A job without a progress callback, on `threads` threads (None: all).
    pub fn quiet(threads: Option<usize>) -> Self {
        Self {
            threads,
            progress: None,
        }
    }
}

/// The payload a cancelled job unwinds with.
struct Cancelled;

/// What the worker and the waiting thread share.
#[derive(Default)]
struct Shared {
    cancel: AtomicBool,
    total: AtomicU64,
    done: AtomicU64,
    message: Mutex<String>,
}

/// The [`Progress`] a job reports to: counts for the caller's progress bar,
/// and the point where a cancelled job stops.
pub struct Watch(Arc<Shared>);

impl Watch {
    fn stop_if_cancelled(&self) {
        if self.0.cancel.load(Ordering::Relaxed) {
            resume_unwind(Box::new(Cancelled));
        }
    }
}

impl Progress for Watch {
    fn start(&self, total: u64, message: &str) {
        self.stop_if_cancelled();
        self.0.total.store(total, Ordering::Relaxed);
        self.0.done.store(0, Ordering::Relaxed);
        if let Ok(mut m) = self.0.message.lock() {
            message.clone_into(&mut m);
        }
    }

    fn advance(&self, n: u64) {
        self.stop_if_cancelled();
        self.0.done.fetch_add(n, Ordering::Relaxed);
    }

    fn finish(&self) {
        let total = self.0.total.load(Ordering::Relaxed);
        self.0.done.store(total, Ordering::Relaxed);
    }
}

type Outcome<T> = std::thread::Result<asperity_engine::Result<T>>;

/// Runs `job` on a worker thread (with `threads` threads when given), the GIL
/// released, and returns its result or raises.
pub fn run<T, F>(py: Python<'_>, opts: &RunOptions, job: F) -> PyResult<T>
where
    T: Send + 'static,
    F: FnOnce(&Watch, &TimeBudget) -> asperity_engine::Result<T> + Send + 'static,
{
    if opts.threads == Some(0) {
        return Err(PyValueError::new_err("threads must be at least 1"));
    }
    let shared = Arc::new(Shared::default());
    let watch = Watch(shared.clone());
    let threads = opts.threads;
    let (tx, rx) = channel::<Outcome<T>>();
    // The receiver crosses into the GIL-free waits; a Mutex makes it Sync.
    let rx = Mutex::new(rx);
    let wait = |d: Duration| match rx.lock() {
        Ok(rx) => rx.recv_timeout(d),
        Err(_) => Err(RecvTimeoutError::Disconnected),
    };
    std::thread::Builder::new()
        .name("asperity-job".into())
        .spawn(move || {
            let outcome = catch_unwind(AssertUnwindSafe(|| match threads {
                None => job(&watch, &time_budget(rayon::current_num_threads())),
                Some(n) => match rayon::ThreadPoolBuilder::new().num_threads(n).build() {
                    Ok(pool) => pool.install(|| job(&watch, &time_budget(n))),
                    Err(e) => Err(EngineError::Invalid(format!(
                        "starting {n} threads failed: {e}"
                    ))),
                },
            }));
            let _ = tx.send(outcome);
        })
        .map_err(|e| PyRuntimeError::new_err(format!("starting the worker thread: {e}")))?;
    loop {
        match py.detach(|| wait(Duration::from_millis(100))) {
            Ok(outcome) => return finish(py, outcome),
            Err(RecvTimeoutError::Disconnected) => {
                return Err(PyRuntimeError::new_err(
                    "asperity's worker thread ended without a result",
                ));
            }
            Err(RecvTimeoutError::Timeout) => {}
        }
        let polled = py.check_signals().and_then(|()| report(py, opts, &shared));
        if let Err(e) = polled {
            shared.cancel.store(true, Ordering::Relaxed);
            // Give the job a second to reach its next progress report and stop.
            let _ = py.detach(|| wait(Duration::from_secs(1)));
            return Err(e);
        }
    }
}

fn report(py: Python<'_>, opts: &RunOptions, s: &Shared) -> PyResult<()> {
    let Some(cb) = &opts.progress else {
        return Ok(());
    };
    let message = s.message.lock().map(|m| m.clone()).unwrap_or_default();
    let (done, total) = (
        s.done.load(Ordering::Relaxed),
        s.total.load(Ordering::Relaxed),
    );
    cb.call1(py, (done, total, message))?;
    Ok(())
}

fn finish<T>(py: Python<'_>, outcome: Outcome<T>) -> PyResult<T> {
    match outcome {
        Ok(Ok(v)) => Ok(v),
        Ok(Err(e)) => Err(to_py(py, e)),
        Err(payload) if payload.is::<Cancelled>() => Err(PyRuntimeError::new_err("cancelled")),
        Err(payload) => {
            let what = payload
                .downcast_ref::<String>()
                .map(String::as_str)
                .or_else(|| payload.downcast_ref::<&str>().copied())
                .unwrap_or("a panic");
            Err(PyRuntimeError::new_err(format!(
                "internal error in asperity (please report it): {what}"
            )))
        }
    }
}

/// The Python exception for an engine error: the CLI's message, the class by
/// its kind.
pub fn to_py(py: Python<'_>, e: EngineError) -> PyErr {
    let msg = crate::spelled(&e.to_string());
    match e.kind() {
        ErrorKind::Invalid => PyValueError::new_err(msg),
        ErrorKind::Type => pyo3::exceptions::PyTypeError::new_err(msg),
        ErrorKind::Os => PyOSError::new_err(msg),
        ErrorKind::Memory => {
            let (needed, limit) = memory_numbers(&e);
            raised(py, "MemoryLimitError", (msg, needed, limit))
        }
        ErrorKind::Time => raised(py, "TimeLimitError", (msg,)),
    }
}

/// An instance of `asperity.errors.<class>` built from `args`.
fn raised<'py, A>(py: Python<'py>, class: &str, args: A) -> PyErr
where
    A: pyo3::call::PyCallArgs<'py>,
{
    let made = py
        .import("asperity.errors")
        .and_then(|m| m.getattr(class))
        .and_then(|c| c.call1(args));
    match made {
        Ok(exc) => PyErr::from_value(exc),
        Err(e) => e,
    }
}

fn memory_numbers(e: &EngineError) -> (u64, u64) {
    match e.core() {
        Some(CoreError::MemoryLimit { needed, limit, .. }) => (*needed, *limit),
        _ => (0, 0),
    }
}
