//! End-to-end tests of the `asperity` binary: exit codes, messages, outputs,
//! one module per command (or per concern shared by every command).

use std::path::Path;
use std::process::{Command, Output};

mod analyze;
mod ca;
mod convert;
mod general;
mod growth;
mod hostile;
mod ifs;
mod kills;
mod outputs;
mod render;
mod subdiv;

fn asperity(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_asperity"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run asperity")
}

/// A PLY file's bytes without its `comment asperity-params` header line.
fn without_params(bytes: &[u8]) -> Vec<u8> {
    let key = b"comment asperity-params ";
    match bytes.windows(key.len()).position(|w| w == key) {
        Some(at) => {
            let end = at + bytes[at..].iter().position(|&b| b == b'\n').unwrap() + 1;
            [&bytes[..at], &bytes[end..]].concat()
        }
        None => bytes.to_vec(),
    }
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `asperity ARGS` in `dir` fails cleanly with `needle` in its message.
fn fails(dir: &Path, args: &[&str], needle: &str) {
    assert_clean_failure(&asperity(args, dir), needle);
}

/// A failure: exit code 2, one `error:` line with the cause, never a panic.
fn assert_clean_failure(o: &Output, needle: &str) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(2), "exit code; stderr: {e}");
    assert!(!e.contains("panicked"), "panic: {e}");
    assert!(e.contains(needle), "expected {needle:?} in: {e}");
    let line = e
        .lines()
        .find(|l| l.starts_with("error: "))
        .expect("an error line");
    let parts: Vec<&str> = line.split(": ").collect();
    for w in parts.windows(2) {
        assert!(w[0] != w[1], "a cause repeated in: {line}");
    }
}

/// Writes `asperity_core::shapes::fin` (three triangles on one edge, the
/// smallest mesh that is not edge-manifold) to `path`.
fn write_fin(path: &Path) {
    let fin = asperity_engine::core::shapes::fin();
    asperity_io::write_mesh(path, &fin, &asperity_io::WriteOptions::default()).unwrap();
}
