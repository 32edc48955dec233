//! `asperity.subdiv`: multiresolution Catmull–Clark surfaces with
//! procedural detail, from options or a scene (velho-perlin;
//! `asperity_engine::subdiv`).

use std::path::PathBuf;

use asperity_engine::subdiv::{Options, Session, Source};
use asperity_subdiv::catmull_clark::Boundary;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::mesh_out;
use crate::job::{RunOptions, budget, run};

/// One surface (the CLI's `subdiv … --triangles`): a dict with `mesh`,
/// `levels` ((vertices, faces) per level), `euler_characteristic` and, with
/// `export_details`, `details` (the detail file's text).
#[pyfunction]
#[pyo3(signature = (scene_path, scene_text, base, levels, details, creases, boundary, limit,
    time, apply_details, export_details, seed, threads, progress))]
#[allow(clippy::too_many_arguments)]
pub fn subdiv<'py>(
    py: Python<'py>,
    scene_path: Option<PathBuf>,
    scene_text: Option<String>,
    base: String,
    levels: usize,
    details: Vec<String>,
    creases: Vec<String>,
    boundary: &str,
    limit: bool,
    time: f64,
    apply_details: Option<PathBuf>,
    export_details: bool,
    seed: u64,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let boundary = match crate::choice(boundary, &["edge-only", "edge-and-corner"], "boundary")? {
        "edge-and-corner" => Boundary::EdgeAndCorner,
        _ => Boundary::EdgeOnly,
    };
    let source = match (scene_path, scene_text) {
        (Some(path), Some(text)) => Source::Scene { path, text },
        _ => Source::Options(Options {
            base,
            levels,
            details,
            creases,
            boundary,
        }),
    };
    let opts = RunOptions { threads, progress };
    let (tri, composed, text) = run(py, &opts, move |w, _| {
        let s = Session::open(source, seed, limit, time, &budget())?;
        let scene = s.first.clone();
        let c = match &apply_details {
            Some(p) => s.apply_details(p, scene.boundary)?,
            None => s.frame(&scene, w)?,
        };
        let tri = c.to_trimesh(scene.limit, scene.boundary)?;
        let text = export_details.then(|| s.details_file(&c));
        Ok((tri, c, text))
    })?;
    let out = PyDict::new(py);
    out.set_item("mesh", mesh_out(py, &tri)?)?;
    out.set_item("levels", composed.counts.clone())?;
    out.set_item(
        "euler_characteristic",
        composed.mesh.mesh.euler_characteristic(),
    )?;
    out.set_item("details", text)?;
    Ok(out)
}

/// Adds this module's functions.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(subdiv, m)?)?;
    Ok(())
}
