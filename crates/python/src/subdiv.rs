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

/// Adds this module's functions.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(subdiv, m)?)?;
    Ok(())
}
