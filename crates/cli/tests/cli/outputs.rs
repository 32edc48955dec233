//! Outputs: written together or not at all, interruptions, `-o -`.

use super::*;

/// Every output of a command lands together or not at all; an interrupted run
/// leaves no temporary file (#20).
#[test]
fn outputs_land_together_and_interruptions_leave_nothing() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    std::fs::write(dir.join("h.npy"), "precious").unwrap();
    // The secondary output's folder is missing: the primary must not replace
    // the existing file.
    fails(
        dir,
        &[
            "ca",
            "run",
            "--rule",
            "450",
            "--steps",
            "3",
            "--init",
            "seed",
            "-o",
            "h.npy",
            "--states-out",
            "nosuch/s.npy",
        ],
        "nosuch: the folder does not exist",
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("h.npy")).unwrap(),
        "precious"
    );
    // A parameter refused after the first output was computed.
    fails(
        dir,
        &[
            "growth",
            "rdsr",
            "--size",
            "32",
            "--layers",
            "5",
            "--alpha-sizes",
            "8,16",
            "-o",
            "h.npy",
        ],
        "needs at least 3 sizes",
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("h.npy")).unwrap(),
        "precious"
    );

    // SIGTERM in the middle of writing animation frames.
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../subdiv/scenes/tentacle.toml");
    let mut child = Command::new(env!("CARGO_BIN_EXE_asperity"))
        .args(["--quiet", "subdiv"])
        .arg(&scene)
        .args(["--frames", "2000", "-o", "t.glb"])
        .current_dir(dir)
        .spawn()
        .unwrap();
    // Wait until frames are being written (their temporaries appear).
    let start = std::time::Instant::now();
    while !std::fs::read_dir(dir)
        .unwrap()
        .any(|e| e.unwrap().file_name().to_string_lossy().ends_with(".tmp"))
    {
        assert!(start.elapsed().as_secs() < 60, "no frame was started");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let killed = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130));
    let left: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp") || n.starts_with("t_"))
        .collect();
    assert!(left.is_empty(), "left behind: {left:?}");
}

/// Runs killed (SIGKILL) at seeded moments of their write leave at most
/// their temporaries and never a half output; the next run that writes into
/// the folder removes them and says so (#54). An output that is the command's
/// input is refused and the input kept.
#[test]
#[cfg(unix)]
fn killed_runs_leave_nothing_after_the_next_write_and_inputs_are_never_outputs() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    let mut seed = 54u64;
    for _ in 0..12 {
        let mut child = Command::new(env!("CARGO_BIN_EXE_asperity"))
            .args(["generate", "fbm", "--size", "2048", "-o", "h.npy"])
            .current_dir(dir)
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        std::thread::sleep(std::time::Duration::from_millis(seed >> 54));
        let _ = child.kill();
        let _ = child.wait();
        if dir.join("h.npy").exists() {
            // Whatever landed is whole.
            let o = asperity(&["info", "h.npy"], dir);
            assert!(o.status.success(), "{}", stderr(&o));
        }
    }
    // One more, as a killed run leaves it (no process holds it).
    std::fs::write(dir.join(".h.npy.Ab12Cd.tmp"), "half a file").unwrap();
    let o = asperity(&["generate", "fbm", "--size", "16", "-o", "small.npy"], dir);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("note: removed .h.npy.Ab12Cd.tmp, left by a run that was killed"),
        "{}",
        stderr(&o)
    );
    let left: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect();
    assert!(left.is_empty(), "left behind: {left:?}");

    let before = std::fs::read(dir.join("small.npy")).unwrap();
    std::os::unix::fs::symlink("small.npy", dir.join("link.npy")).unwrap();
    for out in ["small.npy", "link.npy"] {
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

#[test]
fn dash_o_dash_writes_one_file_to_stdout_on_success_only() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    let o = asperity(
        &[
            "generate", "fbm", "--size", "32", "-o", "-", "--format", "npy",
        ],
        dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(o.stdout.starts_with(b"\x93NUMPY"), "an .npy on stdout");
    assert_eq!(o.stdout.len(), 128 + 32 * 32 * 8);
    assert!(stderr(&o).contains("wrote stdout"), "{}", stderr(&o));
    // The same bytes as a file.
    assert!(
        asperity(&["generate", "fbm", "--size", "32", "-o", "f.npy"], dir)
            .status
            .success()
    );
    assert_eq!(std::fs::read(dir.join("f.npy")).unwrap(), o.stdout);
    fails(
        dir,
        &["generate", "fbm", "-o", "-"],
        "needs the format: add --format npy",
    );
    fails(
        dir,
        &["generate", "fbm", "-o", "x.npy", "--format", "npy"],
        "--format names the format of -o -",
    );
    fails(
        dir,
        &["--json", "generate", "fbm", "-o", "-", "--format", "npy"],
        "--json prints its report on stdout",
    );
    fails(
        dir,
        &["generate", "fbm", "-o", "-", "--format", "doc"],
        "--format doc",
    );
    // A command that would write several files sends nothing.
    let frames = asperity(
        &[
            "render",
            "f.npy",
            "--turntable",
            "2",
            "--size",
            "32x32",
            "-o",
            "-",
            "--format",
            "png",
        ],
        dir,
    );
    assert_clean_failure(
        &frames,
        "sends one file to stdout, but this command wrote 2",
    );
    assert!(frames.stdout.is_empty());
}
