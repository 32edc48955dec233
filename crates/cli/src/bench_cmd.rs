//! `asperity bench`: the workloads the issues name (`asperity_benches::workloads`),
//! timed end to end. Each builds its input once (untimed), runs once to warm
//! up, then `--repeat` timed runs; the minimum and median are reported with
//! throughput. With `--threads-scaling`, each at 1, 2, 4, … threads (a rayon
//! pool of that size), with the speed-up and the parallel efficiency. With
//! `--background-load`, on a machine kept busy by loops at a lower priority.

use std::time::Instant;

use asperity_benches::workloads::{Scratch, workloads};
use serde_json::{Value, json};

use crate::cli::BenchArgs;
use crate::context::{Context, Run};

/// Times one workload: (median, min, runs).
fn time(
    w: &mut asperity_benches::workloads::Workload,
    repeat: u32,
) -> anyhow::Result<(f64, f64, usize)> {
    let repeat = if w.once { 1 } else { repeat };
    if !w.once {
        (w.job)()?; // warm-up
    }
    let mut times = Vec::with_capacity(repeat as usize);
    for _ in 0..repeat {
        let t = Instant::now();
        (w.job)()?;
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    Ok((times[times.len() / 2], times[0], times.len()))
}

/// The thread counts of a scaling run: 1, 2, 4, … below `max`, then `max`.
fn thread_counts(max: usize) -> Vec<usize> {
    let mut counts: Vec<usize> = (0..).map(|k| 1 << k).take_while(|&t| t < max).collect();
    counts.push(max.max(1));
    counts
}

/// Times `w` in a pool of each thread count of [`thread_counts`] and prints
/// the speed-up over one thread and the efficiency.
fn threads_scaling(
    ctx: &Context,
    w: &mut asperity_benches::workloads::Workload,
    repeat: u32,
) -> anyhow::Result<Value> {
    let mut rows = Vec::new();
    let mut one = None;
    for threads in thread_counts(ctx.threads) {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()?;
        let (median, min, runs) = pool.install(|| time(w, repeat))?;
        let base = *one.get_or_insert(median);
        let speedup = base / median;
        let efficiency = speedup / threads as f64;
        if !ctx.json {
            outln!(
                "{:<36} {threads:>3} threads  median {:>9.3} ms  speed-up {speedup:>5.2}×  efficiency {:>4.0} %",
                w.name,
                median * 1e3,
                efficiency * 100.0
            );
        }
        rows.push(
            json!({"threads": threads, "median_s": median, "min_s": min, "runs": runs,
            "speedup": speedup, "efficiency": efficiency}),
        );
    }
    Ok(
        json!({"name": w.name, "what": w.what, "elements": w.elements, "unit": w.unit,
        "threads_scaling": rows}),
    )
}

pub fn run(ctx: &Context, a: &BenchArgs) -> anyhow::Result<()> {
    if let Some(method) = &a.scaling {
        return match a.scaling_point {
            Some(n) => scaling_point(ctx, method, n, a.quick),
            None => crate::scaling_cmd::run(ctx, method, a.quick),
        };
    }
    let mut run = Run::new(ctx, "bench");
    let load = a.background_load.then(BackgroundLoad::start).transpose()?;
    if let Some(l) = &load {
        run.note(format!(
            "under a background load: {} CPU-bound loops at nice 10",
            l.0.len()
        ));
        run.report
            .measure("background_load", json!({"loops": l.0.len(), "nice": 10}));
    }
    let scratch = Scratch::new();
    let mut results: Vec<Value> = Vec::new();
    for (name, make) in workloads(a.quick, ctx.budget, &scratch) {
        if a.filter.as_deref().is_some_and(|f| !name.contains(f)) {
            continue;
        }
        let mut w = make()?;
        if a.threads_scaling {
            results.push(threads_scaling(ctx, &mut w, a.repeat)?);
            continue;
        }
        let (median, min, runs) = time(&mut w, a.repeat)?;
        let rate = w.elements as f64 / median;
        let verdict = w.target_s.map(|t| {
            let met = if median <= t { "met" } else { "MISSED" };
            format!(" (target < {t} s: {met})")
        });
        if !ctx.json {
            outln!(
                "{:<28} median {:>9.3} ms  min {:>9.3} ms  {:>8.2} M {}/s{}",
                w.name,
                median * 1e3,
                min * 1e3,
                rate / 1e6,
                w.unit,
                verdict.unwrap_or_default()
            );
            outln!("{:<28} {}", "", w.what);
        }
        results.push(json!({"name": w.name, "what": w.what, "median_s": median, "min_s": min, "runs": runs, "elements": w.elements, "unit": w.unit, "per_second": rate, "target_s": w.target_s}));
    }
    scratch.remove();
    let rate = |n: &str| {
        results
            .iter()
            .find(|r| r["name"] == n)
            .and_then(|r| r["per_second"].as_f64())
    };
    if let (Some(bits), Some(bytes)) = (rate("ca/evolve-bits-8192"), rate("ca/evolve-bytes-8192")) {
        if !ctx.json {
            outln!(
                "ca: bit-sliced / byte-per-cell evolution = {:.1}× (same run)",
                bits / bytes
            );
        }
        run.report.measure("ca_bits_over_bytes", bits / bytes);
    }
    anyhow::ensure!(
        !results.is_empty(),
        "no workload matches {:?}",
        a.filter.as_deref().unwrap_or("")
    );
    run.report.measure("workloads", results);
    run.report.measure(
        "machine",
        json!({"threads": ctx.threads, "os": std::env::consts::OS, "arch": std::env::consts::ARCH}),
    );
    run.finish()
}

/// CPU-bound loops at nice 10, one a core of the machine, killed when
/// dropped: what a workstation or a shared node runs beside a job.
struct BackgroundLoad(Vec<std::process::Child>);

impl BackgroundLoad {
    fn start() -> anyhow::Result<Self> {
        anyhow::ensure!(
            cfg!(unix),
            "--background-load needs a Unix system (nice, sh)"
        );
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        let mut load = Self(Vec::with_capacity(cores));
        for _ in 0..cores {
            let child = std::process::Command::new("nice")
                .args(["-n", "10", "sh", "-c", "while :; do :; done"])
                .stdin(std::process::Stdio::null())
                .stdout(std::process::Stdio::null())
                .stderr(std::process::Stdio::null())
                .spawn();
            match child {
                Ok(c) => load.0.push(c),
                Err(e) => anyhow::bail!("--background-load: starting `nice -n 10 sh`: {e}"),
            }
        }
        Ok(load)
    }
}

impl Drop for BackgroundLoad {
    fn drop(&mut self) {
        for c in &mut self.0 {
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}

/// One point of a scaling series, in this (fresh) process: builds the input,
/// times the work (the best of three; of one when a run takes over 10 s) and prints
/// `{"elements", "seconds", "peak_bytes"}` as one JSON line.
fn scaling_point(ctx: &Context, method: &str, n: u64, quick: bool) -> anyhow::Result<()> {
    let series = asperity_benches::scaling::series(method)?;
    let setup = asperity_benches::workloads::Setup {
        quick,
        budget: ctx.budget,
        scratch: Scratch::new(),
    };
    let mut w = series.workload(&setup, n)?;
    let mut best = f64::INFINITY;
    for _ in 0..3 {
        let t = Instant::now();
        (w.job)()?;
        best = best.min(t.elapsed().as_secs_f64());
        if best >= 10.0 {
            break;
        }
    }
    setup.scratch.remove();
    outln!(
        "{}",
        json!({"size": n, "elements": w.elements, "unit": w.unit, "what": w.what, "seconds": best, "peak_bytes": peak_memory()})
    );
    Ok(())
}

/// This process's peak resident memory (Linux: VmHWM), if the system says.
fn peak_memory() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}
