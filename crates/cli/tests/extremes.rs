//! Every numeric parameter of every job at its extremes (#54), generated from
//! the engine's schema (`asperity_engine::jobs`), not from a hand list: each
//! scalar number or count at 0, −1, its type's largest value, 1e18, NaN and
//! ±∞, alone (the others at the small job below), under `--max-time 5s
//! --max-memory 1G`. Each run ends on its own, either
//! - refused before work starts: exit 2, one `error:` line, no progress line
//!   (`--progress lines` prints one when a stage starts) and no more memory
//!   than the process at rest ([`REFUSAL_EXTRA_KIB`]); or
//! - run within the budgets (its peak memory under `--max-memory` beyond the
//!   process at rest), its outputs finite (every height, vertex and
//!   point of the `o.*` files read back, no `null` in JSON, no `NaN`/`inf`
//!   in SVG or on stdout).
//!
//! A panic, an abort, a signal or a run past the watchdog fails the test,
//! naming the command. A new parameter is covered by construction; a new job
//! needs its row in [`SMALL_JOBS`] (the test says so). List-valued
//! parameters (sizes `WxH`, points, windows, weights) are tried with every
//! item at one extreme.

use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use asperity_engine::jobs::jobs;

/// Each job's command at a small size, with its inputs (made by [`inputs`]).
const SMALL_JOBS: &[(&str, &[&str])] = &[
    (
        "growth rd",
        &[
            "growth", "rd", "--size", "16", "--layers", "5", "-o", "o.npy",
        ],
    ),
    (
        "growth rdsr",
        &[
            "growth", "rdsr", "--size", "16", "--layers", "5", "-o", "o.npy",
        ],
    ),
    (
        "growth bd",
        &[
            "growth", "bd", "--size", "16", "--layers", "5", "--bin", "4", "-o", "o.npy",
        ],
    ),
    (
        "growth dla",
        &["growth", "dla", "--particles", "50", "-o", "o.ply"],
    ),
    (
        "reconstruct",
        &[
            "reconstruct",
            "p.xyz",
            "--resolution",
            "16",
            "--iterations",
            "3",
            "-o",
            "o.ply",
        ],
    ),
    (
        "generate dla-terrain",
        &[
            "generate",
            "dla-terrain",
            "--size",
            "16x16x8",
            "--particles",
            "50",
            "--resolution",
            "16",
            "--iterations",
            "3",
            "-o",
            "o.ply",
        ],
    ),
    (
        "generate rdsr-sphere",
        &[
            "generate",
            "rdsr-sphere",
            "--radius",
            "4",
            "--layers",
            "2",
            "--resolution",
            "16",
            "--iterations",
            "3",
            "-o",
            "o.ply",
        ],
    ),
    (
        "ca run",
        &[
            "ca", "run", "--rule", "450", "--steps", "3", "--size", "8x8", "-o", "o.npy",
        ],
    ),
    ("ca rule", &["ca", "rule", "450"]),
    (
        "ca gallery",
        &[
            "ca", "gallery", "--rules", "450", "--steps", "3", "--size", "8x8", "-o", "o.png",
        ],
    ),
    ("facet", &["facet", "h.npy", "-o", "o.ply"]),
    (
        "interpolate",
        &["interpolate", "h.npy", "--points", "p.csv"],
    ),
    (
        "surface-ca",
        &[
            "surface-ca",
            "builtin:cube",
            "--cells",
            "200",
            "--steps",
            "3",
            "--max-steps",
            "3",
            "-o",
            "o.ply",
        ],
    ),
    (
        "subdiv",
        &["subdiv", "--base", "cube", "--levels", "1", "-o", "o.ply"],
    ),
    (
        "ifs preset",
        &["ifs", "preset", "takagi-landsberg", "-o", "o.json"],
    ),
    (
        "ifs curve",
        &[
            "ifs",
            "curve",
            "--preset",
            "takagi-landsberg",
            "-o",
            "o.svg",
        ],
    ),
    (
        "ifs surface",
        &[
            "ifs",
            "surface",
            "--preset",
            "takagi-landsberg",
            "-o",
            "o.ply",
        ],
    ),
    (
        "ifs dcf",
        &["ifs", "dcf", "--preset", "takagi-landsberg", "-o", "o.svg"],
    ),
    (
        "ifs sdcf",
        &[
            "ifs",
            "sdcf",
            "--preset",
            "takagi-landsberg-surface",
            "-o",
            "o.ply",
        ],
    ),
    (
        "ifs curvature",
        &["ifs", "curvature", "--preset", "takagi-landsberg"],
    ),
    ("analyze", &["analyze", "h.npy"]),
    ("filter", &["filter", "h.npy", "o.npy", "--lambda-c", "6"]),
    (
        "generate fbm",
        &["generate", "fbm", "--size", "16", "-o", "o.npy"],
    ),
    (
        "render",
        &["render", "h.npy", "--size", "32x32", "-o", "o.png"],
    ),
    ("convert", &["convert", "h.npy", "o.ply"]),
    ("info", &["info", "h.npy"]),
];

/// The most memory a refusal may take beyond the peak of `info` on the
/// small height field (the process at rest: its code, threads and
/// allocator, about 20 MiB in a release build and 70 MiB in a debug one):
/// nothing of the work refused.
const REFUSAL_EXTRA_KIB: u64 = 16 << 10;

/// The extremes of a scalar parameter of JSON type `ty`.
fn extremes(ty: &str) -> [&'static str; 7] {
    let largest = if ty == "integer" {
        "18446744073709551615"
    } else {
        "1.7976931348623157e308"
    };
    ["0", "-1", largest, "1e18", "NaN", "inf", "-inf"]
}

/// The values a field is tried at: a scalar number's extremes; a list of
/// numbers (a size `WxH`, a point `X,Y,Z`, a window `A,B`, weights) with
/// every item at one extreme, written both ways a list is given (`,` and
/// `x`); nothing for other fields.
fn values(field: &serde_json::Value) -> Vec<String> {
    fn scalar(t: &serde_json::Value) -> Option<&str> {
        t.as_str().filter(|t| *t == "integer" || *t == "number")
    }
    if let Some(ty) = scalar(&field["type"]) {
        return extremes(ty).iter().map(|v| v.to_string()).collect();
    }
    let items = &field["items"];
    let Some(ty) = scalar(&items["type"]) else {
        return Vec::new();
    };
    let n = field["minItems"]
        .as_u64()
        .or(items["minItems"].as_u64())
        .unwrap_or(2)
        .max(1) as usize;
    let mut out = Vec::new();
    for v in extremes(ty) {
        for sep in [",", "x"] {
            out.push(vec![v; n].join(sep));
        }
    }
    out
}

/// The small inputs the jobs read: a height field, points on a sphere and
/// x,y points to interpolate at.
fn inputs(dir: &Path) {
    let o = asperity(dir, &["generate", "fbm", "--size", "16", "-o", "h.npy"]);
    assert!(o.code == Some(0), "{}", o.stderr);
    let mut xyz = String::new();
    for k in 0..300 {
        let z = 1.0 - 2.0 * (k as f64 + 0.5) / 300.0;
        let (r, phi) = ((1.0 - z * z).sqrt(), k as f64 * 2.399_963);
        xyz += &format!("{} {} {}\n", r * phi.cos(), r * phi.sin(), z);
    }
    std::fs::write(dir.join("p.xyz"), xyz).unwrap();
    std::fs::write(dir.join("p.csv"), "1,1\n2.5,3\n").unwrap();
}

/// How a run ended: its exit code (None: killed by a signal, or by the
/// watchdog), stdout, stderr and peak resident memory in KiB.
struct Ended {
    code: Option<i32>,
    stdout: String,
    stderr: String,
    peak_kib: u64,
}

/// Runs asperity in `dir` with a watchdog, progress as plain lines.
fn asperity(dir: &Path, args: &[&str]) -> Ended {
    let mut child = Command::new(env!("CARGO_BIN_EXE_asperity"))
        .args(["--quiet", "--progress", "lines"])
        .args(["--max-time", "5s", "--max-memory", "1G"])
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let drain = |r: Option<Box<dyn std::io::Read + Send>>| {
        std::thread::spawn(move || {
            let mut text = String::new();
            if let Some(mut r) = r {
                let _ = r.read_to_string(&mut text);
            }
            text
        })
    };
    let out = drain(child.stdout.take().map(|r| Box::new(r) as _));
    let err = drain(child.stderr.take().map(|r| Box::new(r) as _));
    let (code, peak_kib) = wait_with_peak(&mut child);
    Ended {
        code,
        stdout: out.join().unwrap(),
        stderr: err.join().unwrap(),
        peak_kib,
    }
}

/// Waits for `child` (killing it past the watchdog): its exit code and peak
/// resident memory (`wait4`'s `ru_maxrss`, KiB; std's `wait` does not
/// return it).
#[allow(unsafe_code)]
fn wait_with_peak(child: &mut std::process::Child) -> (Option<i32>, u64) {
    let started = Instant::now();
    // A hang is what this catches: far past the 5 s budget, whatever the
    // machine's load.
    let watchdog = Duration::from_secs(120);
    let pid = child.id() as libc::pid_t;
    loop {
        let mut status = 0;
        // SAFETY: rusage is plain integers, for which zero is valid; wait4
        // writes only the status and the rusage it is given, both alive
        // here, and reaps only the child `pid`.
        let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
        let got = unsafe { libc::wait4(pid, &mut status, libc::WNOHANG, &mut usage) };
        if got == pid {
            let code = libc::WIFEXITED(status).then(|| libc::WEXITSTATUS(status));
            return (code, usage.ru_maxrss.max(0) as u64);
        }
        assert!(got == 0, "wait4: {}", std::io::Error::last_os_error());
        if started.elapsed() > watchdog {
            let _ = child.kill();
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// What in a successful run's outputs in `dir` (`o.*`) and stdout is not
/// finite: a NaN or infinite value in a height field, a mesh or a point
/// set, a `null` in JSON, a `NaN`/`inf` word in text.
fn not_finite(dir: &Path, stdout: &str) -> Vec<String> {
    let mut found = Vec::new();
    let words = |what: &str, text: &str, found: &mut Vec<String>| {
        let bad = text
            .split(|c: char| !(c.is_ascii_alphanumeric() || c == '-'))
            .find(|w| {
                matches!(
                    w.trim_start_matches('-'),
                    "NaN" | "nan" | "inf" | "infinity"
                )
            });
        if let Some(w) = bad {
            found.push(format!("{what}: {w}"));
        }
    };
    words("stdout", stdout, &mut found);
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if !name.starts_with("o.") {
            continue;
        }
        let ext = path.extension().map(|e| e.to_string_lossy().into_owned());
        let finite = match ext.as_deref() {
            Some("npy" | "ply") => match asperity_io::read(&path) {
                Ok(asperity_io::Surface::Height(h)) => h.data().iter().all(|z| z.is_finite()),
                Ok(asperity_io::Surface::Mesh(m)) => finite_points(m.positions()),
                Ok(asperity_io::Surface::Points(p)) => finite_points(p.positions()),
                Err(e) => {
                    found.push(format!("{name}: {e}"));
                    continue;
                }
            },
            Some("json") => {
                let text = std::fs::read_to_string(&path).unwrap();
                !text.contains("null")
            }
            Some("svg") => {
                words(&name, &std::fs::read_to_string(&path).unwrap(), &mut found);
                true
            }
            _ => true,
        };
        if !finite {
            found.push(format!("{name}: a value that is not finite"));
        }
    }
    found
}

/// This test process's peak resident memory (Linux: VmHWM), KiB. A child's
/// `ru_maxrss` is at least the forking process's at the spawn (Linux carries
/// the high-water mark across exec), so it bounds the child's own peak from
/// above; it says something only above this.
fn own_peak_kib() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let line = status.lines().find(|l| l.starts_with("VmHWM:"));
    line.and_then(|l| l.split_whitespace().nth(1)?.parse().ok())
        .unwrap_or(0)
}

fn finite_points(p: &[[f64; 3]]) -> bool {
    p.iter().flatten().all(|c| c.is_finite())
}

/// `base` without the flag `flag` and its value (the one being varied).
fn without(base: &[&str], flag: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut skip = false;
    for a in base {
        if skip {
            skip = false;
        } else if *a == flag {
            skip = true;
        } else {
            out.push((*a).to_string());
        }
    }
    out
}

#[test]
fn every_numeric_parameter_at_its_extremes_is_refused_or_run_within_budget() {
    let d = tempfile::tempdir().unwrap();
    inputs(d.path());
    let at_rest = asperity(d.path(), &["info", "h.npy"]).peak_kib;
    let mut cases: Vec<Vec<String>> = Vec::new();
    for job in jobs() {
        let base = SMALL_JOBS
            .iter()
            .find(|(name, _)| *name == job.name)
            .unwrap_or_else(|| panic!("the job {:?} needs a row in SMALL_JOBS", job.name))
            .1;
        let described = (job.describe)();
        for field in described["fields"].as_array().unwrap() {
            let flag = format!("--{}", field["name"].as_str().unwrap().replace('_', "-"));
            for value in values(field) {
                let mut args = without(base, &flag);
                args.push(format!("{flag}={value}"));
                cases.push(args);
            }
        }
    }
    assert!(cases.len() >= 700, "{} cases", cases.len());
    let next = AtomicUsize::new(0);
    let (ran, refused) = (AtomicUsize::new(0), AtomicUsize::new(0));
    let failures = Mutex::new(Vec::new());
    let peaks = Mutex::new(Vec::new());
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get().min(4));
    std::thread::scope(|s| {
        for t in 0..threads {
            let (cases, next, failures) = (&cases, &next, &failures);
            let (ran, refused, peaks) = (&ran, &refused, &peaks);
            let dir = d.path().join(format!("t{t}"));
            std::fs::create_dir(&dir).unwrap();
            for f in ["h.npy", "p.xyz", "p.csv"] {
                std::fs::copy(d.path().join(f), dir.join(f)).unwrap();
            }
            s.spawn(move || {
                loop {
                    let k = next.fetch_add(1, Ordering::Relaxed);
                    let Some(args) = cases.get(k) else { break };
                    let args: Vec<&str> = args.iter().map(String::as_str).collect();
                    for entry in std::fs::read_dir(&dir).unwrap() {
                        let path = entry.unwrap().path();
                        if path
                            .file_name()
                            .unwrap()
                            .to_string_lossy()
                            .starts_with("o.")
                        {
                            std::fs::remove_file(path).unwrap();
                        }
                    }
                    let ended = asperity(&dir, &args);
                    let (code, err) = (ended.code, &ended.stderr);
                    peaks
                        .lock()
                        .unwrap()
                        .push((ended.peak_kib, code == Some(0)));
                    let clean = match code {
                        Some(0) => {
                            ran.fetch_add(1, Ordering::Relaxed);
                            let mut bad = not_finite(&dir, &ended.stdout);
                            if ended.peak_kib > at_rest.max(own_peak_kib()) + (1 << 20) {
                                bad.push(format!(
                                    "peak {} MiB over --max-memory 1G",
                                    ended.peak_kib >> 10
                                ));
                            }
                            bad.is_empty() || {
                                let note = format!("outside its budget: {}", bad.join(", "));
                                failures
                                    .lock()
                                    .unwrap()
                                    .push(format!("asperity {}: {note}", args.join(" ")));
                                true
                            }
                        }
                        Some(2) => {
                            refused.fetch_add(1, Ordering::Relaxed);
                            err.lines().filter(|l| l.starts_with("error:")).count() == 1
                                && !err.contains("progress:")
                                && ended.peak_kib <= at_rest.max(own_peak_kib()) + REFUSAL_EXTRA_KIB
                        }
                        _ => false,
                    };
                    if !clean {
                        let last: Vec<&str> = err.lines().rev().take(3).collect();
                        failures.lock().unwrap().push(format!(
                            "asperity {}: exit {code:?}, peak {} MiB: {}",
                            args.join(" "),
                            ended.peak_kib / 1024,
                            last.join(" | ")
                        ));
                    }
                }
            });
        }
    });
    let failures = failures.into_inner().unwrap();
    let (ran, refused) = (ran.into_inner(), refused.into_inner());
    let peaks = peaks.into_inner().unwrap();
    let most = |ran: bool| {
        let p = peaks.iter().filter(|p| p.1 == ran).map(|p| p.0).max();
        p.unwrap_or(0) / 1024
    };
    println!(
        "{} cases: {ran} ran (peak memory at most {} MiB), {refused} refused (at most {} MiB)",
        cases.len(),
        most(true),
        most(false)
    );
    // Both outcomes occur: values inside the bounds (a tolerance of 0, no
    // redistancing) run; the others are refused.
    assert!(ran >= 10 && refused >= 600, "{ran} ran, {refused} refused");
    assert!(
        failures.is_empty(),
        "{} of {} cases ended badly:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}
