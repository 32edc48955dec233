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
    // Wait until frames are being written.
    super::kills::wait_for_a_write(&child, dir);
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
