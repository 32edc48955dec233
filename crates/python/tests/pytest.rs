//! The Python package's test suite (`python/tests`, pytest) run against this
//! build: the extension module `cargo test` just built
//! (`target/<profile>/deps/lib_asperity.so`) is assembled with the package's
//! Python files into `target/<profile>/python-pkg`, and the CLI built beside
//! it (`target/<profile>/asperity`) is what the byte-for-byte checks compare
//! with. The interpreter and its packages: `tests/python/python_env.rs`.

#[path = "../../../tests/python/python_env.rs"]
mod python_env;

use std::path::{Path, PathBuf};
use std::process::Command;

/// `target/<profile>`, where cargo put the module and the CLI.
fn profile_dir() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    exe.parent().unwrap().parent().unwrap().to_path_buf()
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let name = e.file_name();
        if name == "__pycache__" {
            continue;
        }
        if e.file_type().unwrap().is_dir() {
            copy_dir(&e.path(), &to.join(&name));
        } else {
            std::fs::copy(e.path(), to.join(&name)).unwrap();
        }
    }
}

/// The package as `pip install ./python` lays it out, built from this tree.
fn assemble(dir: &Path) -> PathBuf {
    let root = python_env::workspace();
    // `cargo test` builds the library (see Cargo.toml) into deps/; a `cargo
    // build` also copies it up a level, where it may be older.
    let module = dir.join("deps/lib_asperity.so");
    assert!(
        module.exists(),
        "{} is missing: run `cargo test --workspace` (it builds the module)",
        module.display()
    );
    let site = dir.join("python-pkg");
    let _ = std::fs::remove_dir_all(&site);
    copy_dir(&root.join("python/asperity"), &site.join("asperity"));
    std::fs::copy(&module, site.join("asperity/_asperity.abi3.so")).unwrap();
    site
}

#[test]
fn python_package_suite() {
    if python_env::skipped() {
        return;
    }
    let dir = profile_dir();
    let cli = dir.join("asperity");
    assert!(
        cli.exists(),
        "{} is missing: run `cargo test --workspace` (the README's command builds the CLI too)",
        cli.display()
    );
    let site = assemble(&dir);
    let py = python_env::python();
    let root = python_env::workspace();
    let status = Command::new(&py)
        .args([
            "-m",
            "pytest",
            "-q",
            "-p",
            "no:cacheprovider",
            "python/tests",
        ])
        .current_dir(&root)
        .env("PYTHONPATH", &site)
        .env("ASPERITY_CLI", &cli)
        .env("ASPERITY_TEST_OUT", dir.join("python-tests"))
        .status()
        .expect("running pytest");
    assert!(
        status.success(),
        "the Python package's tests failed (output above)"
    );
}
