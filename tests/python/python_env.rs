//! The Python interpreter for the tests that run independent reference code
//! (`tests/python/requirements.txt`: numpy, plyfile, trimesh, Pillow, OpenEXR,
//! SurfaceTopography) and the Python package's suite (pytest, tqdm, pandas,
//! Dask distributed, nbclient, ipykernel, matplotlib). Shared by the test crates through `#[path]`.
//!
//! The interpreter is `$ASPERITY_PYTHON`, else `.venv/bin/python` at the
//! workspace root, else a virtual environment created under
//! `target/asperity-pyenv` from the requirements (needs PyPI once). Set
//! `ASPERITY_SKIP_PYTHON=1` to skip on a machine without Python; CI never sets it.

use std::path::{Path, PathBuf};
use std::process::Command;

/// Every module the reference scripts import.
const MODULES: &str = "import numpy, plyfile, trimesh, PIL, OpenEXR, SurfaceTopography, pytest, tqdm, pandas, distributed, nbclient, ipykernel, matplotlib, gwyfile, x3pio";

/// The workspace root.
pub fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .canonicalize()
        .unwrap()
}

fn has_modules(py: &Path) -> bool {
    Command::new(py)
        .args(["-c", MODULES])
        .status()
        .is_ok_and(|s| s.success())
}

/// Whether the Python tests are switched off (`ASPERITY_SKIP_PYTHON`).
pub fn skipped() -> bool {
    let skip = std::env::var_os("ASPERITY_SKIP_PYTHON").is_some();
    if skip {
        eprintln!("skipped: ASPERITY_SKIP_PYTHON is set");
    }
    skip
}

/// The interpreter, set up on first use (see the module docs).
pub fn python() -> PathBuf {
    if let Ok(p) = std::env::var("ASPERITY_PYTHON") {
        return PathBuf::from(p);
    }
    let root = workspace();
    let venv = root.join(".venv/bin/python");
    if has_modules(&venv) {
        return venv;
    }
    let own = root.join("target/asperity-pyenv");
    let py = own.join("bin/python");
    if !has_modules(&py) {
        let ok = Command::new("python3")
            .args(["-m", "venv"])
            .arg(&own)
            .status()
            .is_ok_and(|s| s.success())
            && Command::new(&py)
                .args(["-m", "pip", "install", "-q", "-r"])
                .arg(root.join("tests/python/requirements.txt"))
                .status()
                .is_ok_and(|s| s.success());
        assert!(
            ok,
            "could not set up the Python reference packages; install tests/python/requirements.txt or set ASPERITY_PYTHON"
        );
    }
    py
}
