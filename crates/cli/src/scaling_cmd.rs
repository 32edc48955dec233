//! `asperity bench --scaling METHOD`: the doubling series of
//! `asperity_benches::scaling`, each point run by this binary in a fresh process
//! (`--scaling-point`) so its peak memory is its own, then the log–log slopes
//! of time and memory against the elements, beside the expected exponent.
//! Prints a Markdown table (as BENCHMARKS.md records it) or, with `--json`, the
//! numbers.

use std::process::Command;

use asperity_benches::scaling::{SERIES, Series, loglog_slope, series};
use asperity_engine::core::Progress;
use serde_json::{Value, json};

use crate::context::{Context, Run};

/// Runs one point in a child process; its JSON line.
fn point(ctx: &Context, s: &Series, n: u64, quick: bool) -> anyhow::Result<Value> {
    let exe = std::env::current_exe()?;
    let mut cmd = Command::new(exe);
    cmd.args(["--quiet", "--threads", &ctx.threads.to_string()]);
    cmd.args([
        "bench",
        "--scaling",
        s.name,
        "--scaling-point",
        &n.to_string(),
    ]);
    if quick {
        cmd.arg("--quick");
    }
    let out = cmd.output()?;
    anyhow::ensure!(
        out.status.success(),
        "{} at size {n}: {}",
        s.name,
        String::from_utf8_lossy(&out.stderr).trim()
    );
    let line = String::from_utf8_lossy(&out.stdout);
    Ok(serde_json::from_str(line.trim())?)
}

fn mib(bytes: Option<f64>) -> String {
    bytes.map_or("—".into(), |b| format!("{:.0}", b / (1u64 << 20) as f64))
}

pub fn run(ctx: &Context, method: &str, quick: bool) -> anyhow::Result<()> {
    let chosen: Vec<&Series> = if method == "all" {
        SERIES.iter().collect()
    } else {
        vec![series(method)?]
    };
    let mut run = Run::new(ctx, "bench");
    let mut table = Vec::new();
    for s in chosen {
        let bar = ctx.bar();
        let sizes = s.sizes(quick);
        bar.start(sizes.len() as u64, &format!("scaling {}", s.name));
        let mut points = Vec::new();
        for &n in &sizes {
            points.push(point(ctx, s, n, quick)?);
            bar.advance(1);
        }
        bar.finish();
        let col = |k: &str| -> Vec<f64> {
            points
                .iter()
                .map(|p| p[k].as_f64().unwrap_or(0.0))
                .collect()
        };
        let (elements, seconds, peak) = (col("elements"), col("seconds"), col("peak_bytes"));
        let time_slope = loglog_slope(&elements, &seconds);
        let memory_slope = loglog_slope(&elements, &peak);
        if !ctx.json {
            outln!("\n### {} — {}\n", s.name, s.input);
            outln!("| elements | time (s) | peak memory (MiB) |\n| ---: | ---: | ---: |");
            for p in &points {
                outln!(
                    "| {} {} | {:.3} | {} |",
                    p["elements"],
                    p["unit"].as_str().unwrap_or(""),
                    p["seconds"].as_f64().unwrap_or(f64::NAN),
                    mib(p["peak_bytes"].as_f64())
                );
            }
            outln!(
                "\nslope of time {} (expected {:.2}: {}); slope of peak memory {}",
                time_slope.map_or("—".into(), |v| format!("{v:.2}")),
                s.expected,
                s.why,
                memory_slope.map_or("—".into(), |v| format!("{v:.2}")),
            );
        }
        table.push(json!({"method": s.name, "input": s.input, "points": points, "time_slope": time_slope, "memory_slope": memory_slope, "expected": s.expected, "why": s.why}));
    }
    run.report.measure("scaling", table);
    run.report.measure(
        "machine",
        json!({"threads": ctx.threads, "os": std::env::consts::OS, "arch": std::env::consts::ARCH}),
    );
    run.finish()
}
