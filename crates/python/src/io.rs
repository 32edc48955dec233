//! `asperity.load`, `asperity.save`, `asperity.info`: every format asperity
//! reads and writes (`asperity_io`, through `asperity_engine::files`).

use std::path::PathBuf;

use asperity_io::{Surface, WriteOptions};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{json, surface_in, surface_out};
use crate::job::{RunOptions, budget, run};

/// Reads any file under the memory budget; a dict with its `kind`.
#[pyfunction]
pub fn load<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let s = run(py, &RunOptions::quiet(None), move |_, _| {
        asperity_engine::files::load(&path, &budget())
    })?;
    surface_out(py, s)
}

/// Writes a mesh, height field or point set by the path's extension,
/// atomically (a failure leaves no partial file).
#[pyfunction]
#[pyo3(signature = (path, surface, title = None))]
pub fn save(
    py: Python<'_>,
    path: PathBuf,
    surface: &Bound<'_, PyAny>,
    title: Option<String>,
) -> PyResult<()> {
    let s = surface_in(surface)?;
    let mut opts = WriteOptions::default();
    if let Some(t) = title {
        opts.title = t;
    }
    run(py, &RunOptions::quiet(None), move |_, _| {
        match &s {
            Surface::Points(p) if p.is_empty() => {
                return Err(asperity_engine::error::invalid("no point to write"));
            }
            _ => {}
        }
        Ok(asperity_io::write(&path, &s, &opts)?)
    })
}

/// The CLI's `info` facts of a surface (JSON text).
#[pyfunction]
pub fn info(surface: &Bound<'_, PyAny>) -> PyResult<String> {
    json(&asperity_engine::describe::describe(&surface_in(surface)?))
}
