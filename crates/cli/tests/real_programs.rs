//! asperity's files in the programs and libraries people open them with, for
//! real (issue #24); `.ci/run` installs every one of them:
//! - the Khronos glTF validator (npm `gltf-validator`, `tests/gltf`) on every
//!   `.glb` that `asperity demo --quick` writes: no errors, warnings, infos or
//!   hints. `npm ci` installs it into `tests/gltf` on first use;
//! - Gwyddion (Debian's `gwyddion`; `--convert-to-gwy` needs no display) reads
//!   asperity's `.gsf`, 16-bit `.png`, `.x3p` and `.gwy` height fields and the
//!   demo's with the right sizes, extents, offsets, units and heights, and
//!   asperity reads the `.gwy` files Gwyddion writes
//!   (`python/tests/reference/check_gwyddion.py`, read back with `gwyfile`);
//! - `.x3p` both ways with SurfaceTopography and x3pio
//!   (`python/tests/reference/check_x3p.py`);
//! - instrument files (`.sdf`, `.sur`: SurfaceTopography's own examples) read
//!   as SurfaceTopography reads them, and `.sdf` written for it
//!   (`python/tests/reference/check_instruments.py`);
//! - Blender (Debian's `blender`, headless) imports the demo's `.glb`, `.obj`,
//!   `.ply` and `.stl` upright, with the planet's colours equal in `.glb`, `.obj`
//!   and `.ply` and the cup's image texture (`tests/blender/check_import.py`);
//! - the gallery in headless Chromium (Debian's `chromium`, driven by npm
//!   `playwright-core` in `tests/browser`) from `file://`: no console errors,
//!   every image loaded, no horizontal overflow at 1280 and 390 px, every 3-D
//!   view paints its mesh (`tests/browser/check_gallery.mjs`); screenshots in
//!   `target/gallery-screenshots/`. Slow tier (`cargo test -- --ignored`).
//!
//! A check whose program is not on `PATH` is ignored with a line that names it
//! (the build script's probe, `asperity_fixtures::programs`), unless `CI` or
//! `ASPERITY_REQUIRE_ALL=1` is set: then it runs, and a missing program fails it.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use asperity_fixtures::programs::{BLENDER, CHROMIUM, GWYDDION, NODE, require};
use asperity_fixtures::{python::python, workspace};

/// `asperity demo --quick`, written once for every test here.
fn demo() -> PathBuf {
    static DEMO: OnceLock<tempfile::TempDir> = OnceLock::new();
    let dir = DEMO.get_or_init(|| {
        let d = tempfile::tempdir().unwrap();
        let o = Command::new(env!("CARGO_BIN_EXE_asperity"))
            .args(["--quiet", "demo", "--quick", "--out"])
            .arg(d.path().join("g"))
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        d
    });
    dir.path().join("g")
}

/// Runs `program args…`; asserts it passed and returns the number of `ok`
/// lines it printed (the check scripts print `ok   what` or `FAIL what`).
fn run_checks(program: &Path, args: &[&std::ffi::OsStr]) -> usize {
    let out = Command::new(program).args(args).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    eprintln!("{stdout}{}", String::from_utf8_lossy(&out.stderr));
    assert!(
        out.status.success(),
        "{} failed (see above)",
        program.display()
    );
    stdout.lines().filter(|l| l.starts_with("ok   ")).count()
}

fn script(path: &str) -> PathBuf {
    workspace().join(path)
}

/// `tests/NAME`, with its npm packages installed (`npm ci`, the registry once).
fn npm_package(name: &str, module: &str) -> PathBuf {
    let dir = script(&format!("tests/{name}"));
    if !dir.join("node_modules").join(module).exists() {
        require(&NODE);
        let ok = Command::new("npm")
            .args(["ci", "--silent", "--no-audit", "--no-fund"])
            .current_dir(&dir)
            .status()
            .is_ok_and(|s| s.success());
        assert!(
            ok,
            "could not install {module}: run `npm ci` in tests/{name}"
        );
    }
    dir
}

/// The quick demo's model scripts (`viewer/STEM.js`), sorted: every `.js` in
/// `viewer/` but the viewer's own files.
fn view_scripts() -> Vec<PathBuf> {
    let mut views: Vec<PathBuf> = std::fs::read_dir(demo().join("viewer"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "js"))
        .filter(|p| {
            let name = p.file_name().unwrap_or_default();
            !asperity_gallery::viewer::ASSETS
                .iter()
                .any(|(a, _)| name == *a)
        })
        .collect();
    views.sort();
    views
}

/// The 3-D views' copies (quantized, meshopt-compressed) decoded by
/// meshoptimizer's own JavaScript decoder are validator-clean, and the largest
/// meshes were simplified to the view's budget.
#[test]
#[cfg_attr(not(has_node), ignore = "needs node: apt-get install nodejs npm")]
fn every_view_copy_decodes_and_is_validator_clean() {
    let node = require(&NODE);
    let dir = npm_package("gltf", "meshoptimizer");
    let views = view_scripts();
    assert!(views.len() >= 40, "{} view copies", views.len());
    let v = Command::new(&node)
        .arg(dir.join("validate_views.mjs"))
        .args(&views)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&v.stdout);
    eprintln!("{text}{}", String::from_utf8_lossy(&v.stderr));
    assert!(v.status.success(), "a view copy failed (see above)");
    let triangles = |line: &str| -> usize {
        let t = line.split(" triangles").next().unwrap();
        t.rsplit(' ').next().unwrap().parse().unwrap()
    };
    let counts: Vec<usize> = text
        .lines()
        .filter(|l| l.contains(" triangles"))
        .map(triangles)
        .collect();
    assert_eq!(counts.len(), views.len());
    let budget = asperity_gallery::viewer::compact::TRIANGLE_BUDGET;
    assert!(counts.iter().all(|&n| n > 0 && n <= budget), "{counts:?}");
}

#[test]
#[cfg_attr(not(has_node), ignore = "needs node: apt-get install nodejs npm")]
fn every_demo_glb_is_validator_clean() {
    let node = require(&NODE);
    let dir = npm_package("gltf", "gltf-validator");
    let mut glbs: Vec<PathBuf> = std::fs::read_dir(demo())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "glb"))
        .collect();
    glbs.sort();
    let names: Vec<_> = glbs.iter().map(|p| p.file_name().unwrap()).collect();
    // the textured cup, the coloured planets, the torus: every kind of .glb
    for want in ["surfca_voronoi_cup.glb", "subdiv_planet.glb", "torus.glb"] {
        assert!(names.iter().any(|n| *n == want), "{want} in {names:?}");
    }
    // and a job's output, with its parameters in `asset.extras`
    let work = tempfile::tempdir().unwrap();
    let made = work.path().join("ifs_with_params.glb");
    let status = Command::new(env!("CARGO_BIN_EXE_asperity"))
        .args([
            "ifs",
            "surface",
            "--preset",
            "bezier-bicubic",
            "--depth",
            "4",
            "-o",
        ])
        .arg(&made)
        .status()
        .unwrap();
    assert!(status.success());
    assert!(asperity_io::read_params(&made).unwrap().is_some());
    glbs.push(made);
    let v = Command::new(&node)
        .arg(dir.join("validate.mjs"))
        .args(&glbs)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&v.stdout);
    assert!(
        v.status.success(),
        "the validator found messages:\n{text}{}",
        String::from_utf8_lossy(&v.stderr)
    );
    assert_eq!(
        text.matches("0 errors, 0 warnings, 0 infos, 0 hints")
            .count(),
        glbs.len(),
        "{text}"
    );
}

#[test]
#[cfg_attr(not(has_gwyddion), ignore = "needs gwyddion: apt-get install gwyddion")]
fn gwyddion_reads_our_height_fields_and_we_read_its_gwy() {
    require(&GWYDDION);
    let work = tempfile::tempdir().unwrap();
    let checks = run_checks(
        &python(),
        &[
            script("python/tests/reference/check_gwyddion.py").as_os_str(),
            env!("CARGO_BIN_EXE_asperity").as_ref(),
            work.path().as_os_str(),
            demo().as_os_str(),
        ],
    );
    assert_eq!(checks, 97, "every check ran");
}

#[test]
fn x3p_round_trips_through_surface_topography_and_x3pio() {
    let work = tempfile::tempdir().unwrap();
    let checks = run_checks(
        &python(),
        &[
            script("python/tests/reference/check_x3p.py").as_os_str(),
            env!("CARGO_BIN_EXE_asperity").as_ref(),
            work.path().as_os_str(),
        ],
    );
    assert_eq!(checks, 17, "every check ran");
}

#[test]
fn instrument_files_read_as_surface_topography_reads_them() {
    let work = tempfile::tempdir().unwrap();
    let checks = run_checks(
        &python(),
        &[
            script("python/tests/reference/check_instruments.py").as_os_str(),
            env!("CARGO_BIN_EXE_asperity").as_ref(),
            script("tests/data/surfacetopography").as_os_str(),
            work.path().as_os_str(),
        ],
    );
    assert_eq!(checks, 591, "every check ran");
}

#[test]
#[cfg_attr(
    not(has_blender),
    ignore = "needs blender: apt-get install blender python3-numpy"
)]
fn blender_imports_the_demo_meshes_upright_with_their_colours() {
    let blender = require(&BLENDER);
    let work = tempfile::tempdir().unwrap();
    let info = Command::new(env!("CARGO_BIN_EXE_asperity"))
        .args(["--quiet", "info", "--json"])
        .arg(demo().join("sample_mesh.ply"))
        .output()
        .unwrap();
    let info: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
    let bounds = work.path().join("bounds.json");
    std::fs::write(&bounds, info["measurements"]["bounds"].to_string()).unwrap();
    let planet_obj = work.path().join("subdiv_planet.obj");
    let converted = Command::new(env!("CARGO_BIN_EXE_asperity"))
        .args(["--quiet", "convert"])
        .arg(demo().join("subdiv_planet.ply"))
        .arg(&planet_obj)
        .status()
        .unwrap();
    assert!(converted.success());
    let checks = run_checks(
        &blender,
        &[
            "-b".as_ref(),
            "--factory-startup".as_ref(),
            "--python-exit-code".as_ref(),
            "1".as_ref(),
            "--python".as_ref(),
            script("tests/blender/check_import.py").as_os_str(),
            "--".as_ref(),
            demo().as_os_str(),
            bounds.as_os_str(),
            planet_obj.as_os_str(),
        ],
    );
    assert_eq!(checks, 15, "every check ran");
}

#[test]
#[cfg_attr(
    all(has_node, has_chromium),
    ignore = "slow tier: the gallery in headless Chromium, ~1 min (cargo test -- --ignored)"
)]
#[cfg_attr(
    not(all(has_node, has_chromium)),
    ignore = "needs chromium and node: apt-get install chromium nodejs npm"
)]
fn gallery_works_in_headless_chromium() {
    let node = require(&NODE);
    let chromium = require(&CHROMIUM);
    let dir = npm_package("browser", "playwright-core");
    let shots = workspace().join("target/gallery-screenshots");
    let out = Command::new(&node)
        .arg(dir.join("check_gallery.mjs"))
        .arg(demo())
        .arg(&shots)
        .arg(&chromium)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    eprintln!("{stdout}{}", String::from_utf8_lossy(&out.stderr));
    assert!(
        out.status.success(),
        "the gallery failed in Chromium (see above)"
    );
    let models = view_scripts().len();
    let painted = stdout
        .lines()
        .filter(|l| l.starts_with("ok   3D view "))
        .count();
    assert!(models >= 40, "{models} 3-D views in the quick demo");
    assert_eq!(painted, models, "every 3-D view painted");
    assert_eq!(
        stdout.lines().filter(|l| l.starts_with("ok   ")).count(),
        models + 8,
        "every view and the eight page checks (two of them: opening loads at most 5 MB)"
    );
    assert!(shots.join("gallery_phone.png").exists());
}
