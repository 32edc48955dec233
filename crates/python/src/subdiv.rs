//! `asperity.subdiv`: multiresolution Catmull–Clark surfaces with
//! procedural detail, from options or a scene (velho-perlin;
//! `asperity_engine::subdiv`).

use asperity_engine::subdiv::SubdivParams;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::mesh_out;
use crate::job::{RunOptions, budget, run};

/// One surface (the CLI's `subdiv … --triangles`) with the parameters and
/// seed of `params` (JSON): a dict with `mesh`, `levels` ((vertices, faces)
/// per level), `euler_characteristic`, `params` and, with `export_details`,
/// `details` (the detail file's text).
#[pyfunction]
#[pyo3(signature = (params, export_details, threads, progress))]
pub fn subdiv<'py>(
    py: Python<'py>,
    params: &str,
    export_details: bool,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (p, seed): (SubdivParams, u64) = crate::params::from_json(py, params)?;
    let opts = RunOptions { threads, progress };
    let (p, tri, composed, text) = run(py, &opts, move |w, _| {
        let s = p.open(seed, &budget())?;
        let (c, limit, boundary) = s.surface(&p, None, w)?;
        let tri = c.to_trimesh(limit, boundary)?;
        let text = export_details.then(|| s.details_file(&c));
        Ok((p, tri, c, text))
    })?;
    let out = PyDict::new(py);
    out.set_item("mesh", mesh_out(py, &tri)?)?;
    out.set_item("levels", composed.counts.clone())?;
    out.set_item(
        "euler_characteristic",
        composed.mesh.mesh.euler_characteristic(),
    )?;
    out.set_item("details", text)?;
    out.set_item("params", crate::params::record(&p, seed))?;
    Ok(out)
}

/// The built-in example scenes (JSON text): name, description, levels,
/// seed, the main detail's size and spacing.
#[pyfunction]
pub fn subdiv_examples() -> PyResult<String> {
    crate::convert::json(&asperity_engine::subdiv::examples())
}

/// The rock detail's defaults (JSON text: amplitude, decay).
#[pyfunction]
pub fn subdiv_rock_defaults() -> PyResult<String> {
    crate::convert::json(&asperity_engine::subdiv::rock_defaults())
}

/// The TOML text of example `name` with its knobs set where given.
#[pyfunction]
#[pyo3(signature = (name, levels = None, seed = None, size = None, spacing = None))]
pub fn subdiv_example(
    py: Python<'_>,
    name: &str,
    levels: Option<usize>,
    seed: Option<u64>,
    size: Option<f64>,
    spacing: Option<f64>,
) -> PyResult<String> {
    asperity_engine::subdiv::example_text(name, levels, seed, size, spacing)
        .map_err(|e| crate::job::to_py(py, e))
}

/// Adds this module's functions.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(subdiv, m)?)?;
    m.add_function(wrap_pyfunction!(subdiv_examples, m)?)?;
    m.add_function(wrap_pyfunction!(subdiv_example, m)?)?;
    m.add_function(wrap_pyfunction!(subdiv_rock_defaults, m)?)?;
    Ok(())
}
