//! The hostile-input corpus (issue #20): every malformed file and bad parameter
//! set that `tests/corpus/make_corpus.py` writes, run through the real binary.
//! Each must end with exit code 2 and one `error:` line naming its cause once —
//! no panic, no signal — and leave the existing output file unchanged and no
//! file behind, temporary or otherwise.

use std::collections::BTreeSet;
use std::path::Path;
use std::process::Command;

fn listing(dir: &Path) -> BTreeSet<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect()
}

/// What is wrong with one case's run, if anything.
fn problems(dir: &Path, case: &serde_json::Value) -> Vec<String> {
    let args: Vec<String> = case["args"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a.as_str().unwrap().to_owned())
        .collect();
    let output = dir.join(case["output"].as_str().unwrap());
    std::fs::write(&output, "precious").unwrap();
    let before = listing(dir);
    let o = Command::new(env!("CARGO_BIN_EXE_asperity"))
        .args(&args)
        .current_dir(dir)
        .output()
        .expect("run asperity");
    let err = String::from_utf8_lossy(&o.stderr);
    let mut p = Vec::new();
    match o.status.code() {
        Some(2) => {}
        Some(c) => p.push(format!("exit code {c}")),
        None => p.push(format!("killed by a signal ({:?})", o.status)),
    }
    if err.contains("panicked") {
        p.push("panic".into());
    }
    let lines: Vec<&str> = err.lines().filter(|l| l.starts_with("error:")).collect();
    if lines.len() == 1 {
        let parts: Vec<&str> = lines[0].split(": ").collect();
        if parts.windows(2).any(|w| w[0] == w[1]) {
            p.push("a cause repeated".into());
        }
    } else {
        p.push(format!("{} error lines", lines.len()));
    }
    if let Some(needle) = case.get("needle").and_then(|n| n.as_str())
        && !err.contains(needle)
    {
        p.push(format!("no {needle:?} in the message"));
    }
    if std::fs::read_to_string(&output).ok().as_deref() != Some("precious") {
        p.push("the existing output changed".into());
    }
    for new in listing(dir).difference(&before) {
        p.push(format!("left {new}"));
        let path = dir.join(new);
        let _ = std::fs::remove_dir_all(&path).or_else(|_| std::fs::remove_file(&path));
    }
    let _ = std::fs::remove_file(&output);
    if !p.is_empty() {
        p.push(format!("stderr: {}", err.trim()));
    }
    p
}

#[test]
fn every_malformed_file_and_bad_parameter_is_a_clean_refusal() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/corpus/make_corpus.py");
    let made = Command::new("python3")
        .arg(&script)
        .arg(dir)
        .arg(env!("CARGO_BIN_EXE_asperity"))
        .output()
        .expect("python3 runs the corpus script");
    assert!(
        made.status.success(),
        "{}",
        String::from_utf8_lossy(&made.stderr)
    );
    let cases: Vec<serde_json::Value> =
        serde_json::from_str(&std::fs::read_to_string(dir.join("cases.json")).unwrap()).unwrap();
    let files = listing(dir).len() - 3; // less cases.json, h.npy, pts.xyz
    let params = cases
        .iter()
        .filter(|c| c["name"].as_str().unwrap().starts_with("param_"))
        .count();
    assert!(files >= 100, "only {files} malformed files");
    assert!(params >= 50, "only {params} bad parameter sets");
    let failures: Vec<String> = cases
        .iter()
        .filter_map(|c| {
            let p = problems(dir, c);
            (!p.is_empty()).then(|| format!("{}: {}", c["name"], p.join("; ")))
        })
        .collect();
    assert!(
        failures.is_empty(),
        "{} of {} cases failed:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}
