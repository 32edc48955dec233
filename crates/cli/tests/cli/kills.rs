//! Runs killed while they write (#54): SIGKILL at seeded moments, with
//! anonymous staging (Linux `O_TMPFILE`) and with named temporaries; and
//! outputs that are the command's input.

use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use super::*;

/// Our temporaries in `dir` (`.NAME.XXXXXX.tmp`).
fn temporaries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.') && n.ends_with(".tmp"))
        .collect();
    names.sort();
    names
}

/// Waits until `child` is writing an output into `dir`: a temporary of ours
/// is there, or (anonymous staging) it holds an unnamed file of that folder
/// open — the kernel shows it as `DIR/#INODE (deleted)`.
pub(super) fn wait_for_a_write(child: &Child, dir: &Path) {
    let dir = dir.canonicalize().unwrap();
    let fds = format!("/proc/{}/fd", child.id());
    let start = Instant::now();
    loop {
        let anonymous = std::fs::read_dir(&fds)
            .into_iter()
            .flatten()
            .filter_map(|e| std::fs::read_link(e.ok()?.path()).ok())
            .any(|t| t.starts_with(&dir) && t.to_string_lossy().ends_with(" (deleted)"));
        if anonymous || !temporaries(&dir).is_empty() {
            return;
        }
        assert!(start.elapsed().as_secs() < 60, "no write was started");
        std::thread::sleep(Duration::from_micros(500));
    }
}

/// `generate fbm` into `dir/h.npy`, with named temporaries or not.
fn writer(dir: &Path, named: bool) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_asperity"));
    c.args([
        "--quiet", "generate", "fbm", "--size", "1024", "-o", "h.npy",
    ])
    .current_dir(dir)
    .stderr(Stdio::null());
    if named {
        c.env("ASPERITY_STAGING", "named");
    } else {
        c.env_remove("ASPERITY_STAGING");
    }
    c
}

/// Kills 100 runs that replace `dir/h.npy` at seeded moments over a run's
/// length, then one at a moment it is writing; checks after each that the
/// previous output is whole. Returns how many kills left a temporary, and
/// whether the last one did.
fn kill_writes(dir: &Path, named: bool, mut seed: u64) -> (usize, bool) {
    let start = Instant::now();
    assert!(writer(dir, named).status().unwrap().success());
    let span = start.elapsed() * 3 / 2;
    let whole = std::fs::metadata(dir.join("h.npy")).unwrap().len();
    let mut left = 0;
    let mut last = false;
    for i in 0..=100 {
        let mut child = writer(dir, named).spawn().unwrap();
        if i == 100 {
            wait_for_a_write(&child, dir);
        } else {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            std::thread::sleep(span.mul_f64((seed >> 11) as f64 / (1u64 << 53) as f64));
        }
        let _ = child.kill();
        let _ = child.wait();
        assert_eq!(
            std::fs::metadata(dir.join("h.npy")).unwrap().len(),
            whole,
            "the output is whole after kill {i}"
        );
        last = !temporaries(dir).is_empty();
        left += usize::from(last);
    }
    (left, last)
}

/// SIGKILL at 100 seeded moments of a run and once while it writes. Staged
/// anonymously, nothing but the previous output is left (a kill between the
/// link and the rename of a replaced output — two system calls — is allowed
/// once); with named temporaries, the next write into the folder removes
/// them and says so. Either way the output is the previous one or the new
/// one, whole.
#[test]
#[cfg(target_os = "linux")]
fn killed_runs_leave_nothing_behind_anonymous_or_after_the_next_write() {
    for named in [false, true] {
        let d = tempfile::tempdir().unwrap();
        let dir = d.path();
        if !named && !asperity_io::staging::stages_anonymously(dir) {
            eprintln!("skipped: anonymous staging (the test folder has no O_TMPFILE)");
            continue;
        }
        let (left, last) = kill_writes(dir, named, 54);
        let how = if named { "named" } else { "anonymous" };
        eprintln!("{how} staging: {left} of 101 kills left a temporary");
        if named {
            assert!(last, "the kill while writing left its temporary");
        } else {
            assert!(!last, "killed while writing: {:?}", temporaries(dir));
            assert!(left <= 1, "{left} kills left a temporary");
        }
        let o = asperity(&["generate", "fbm", "--size", "16", "-o", "small.npy"], dir);
        assert!(o.status.success(), "{}", stderr(&o));
        if named {
            assert!(
                stderr(&o).contains("note: removed .h.npy.")
                    && stderr(&o).contains("left by a run that was killed"),
                "{}",
                stderr(&o)
            );
        }
        assert!(temporaries(dir).is_empty(), "{:?}", temporaries(dir));
        let o = asperity(&["info", "h.npy"], dir);
        assert!(o.status.success(), "{}", stderr(&o));
    }
}

/// An output that is the command's input, by its name or through a link, is
/// refused before anything is written, and the input kept byte for byte.
#[test]
#[cfg(unix)]
fn inputs_are_never_outputs() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    let o = asperity(&["generate", "fbm", "--size", "16", "-o", "small.npy"], dir);
    assert!(o.status.success(), "{}", stderr(&o));
    let before = std::fs::read(dir.join("small.npy")).unwrap();
    std::os::unix::fs::symlink("small.npy", dir.join("link.npy")).unwrap();
    std::fs::hard_link(dir.join("small.npy"), dir.join("hard.npy")).unwrap();
    for out in ["small.npy", "link.npy", "hard.npy"] {
        let o = asperity(&["convert", "small.npy", out], dir);
        assert_clean_failure(
            &o,
            "is the input small.npy (the same file): write the output elsewhere",
        );
        assert!(
            !stderr(&o).contains("loses"),
            "warned first: {}",
            stderr(&o)
        );
        assert_eq!(std::fs::read(dir.join("small.npy")).unwrap(), before);
    }
}
