//! The Python binding of asperity: `import asperity`.
//!
//! This crate is a front end like the CLI: it converts numpy arrays to
//! asperity's shared types and back (`convert`), runs one engine job per
//! call off the GIL and stoppable by Ctrl-C (`job`), and maps engine errors
//! to Python exceptions. It holds no algorithm — every function calls
//! `asperity_engine`. The Python package (`python/asperity`) wraps these
//! functions with documented keyword arguments, result classes and the Dask
//! sweep; see `docs/python.md`.

mod analysis;
mod ca;
mod convert;
mod growth;
mod ifs;
mod io;
mod job;
mod params;
mod reconstruct;
mod render;
mod subdiv;
mod surfca;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// `text` with parameters named as keywords (`max_memory=`).
pub(crate) fn spelled(text: &str) -> String {
    asperity_engine::core::wording::spell(text, asperity_engine::core::wording::Spelling::Python)
}

/// Each of `texts` with parameters named as keywords.
pub(crate) fn spelled_all(texts: impl IntoIterator<Item = String>) -> Vec<String> {
    texts.into_iter().map(|t| spelled(&t)).collect()
}

/// A ValueError with `msg`.
pub(crate) fn value_error(msg: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(msg.to_string())
}

/// The extension module `asperity._asperity`.
#[pymodule]
fn _asperity(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("DEFAULT_SEED", asperity_engine::params::DEFAULT_SEED)?;
    m.add("SCHEMA_VERSION", asperity_engine::params::SCHEMA_VERSION)?;
    m.add_function(wrap_pyfunction!(params::describe, m)?)?;
    m.add_function(wrap_pyfunction!(params::jobs, m)?)?;
    m.add_function(wrap_pyfunction!(job::set_limits, m)?)?;
    m.add_function(wrap_pyfunction!(job::memory_budget, m)?)?;
    m.add_function(wrap_pyfunction!(growth::deposit, m)?)?;
    m.add_function(wrap_pyfunction!(growth::dla, m)?)?;
    m.add_function(wrap_pyfunction!(reconstruct::reconstruct, m)?)?;
    m.add_function(wrap_pyfunction!(reconstruct::dla_terrain, m)?)?;
    m.add_function(wrap_pyfunction!(reconstruct::rdsr_sphere, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::analyze, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::filter_surface, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::fbm, m)?)?;
    m.add_function(wrap_pyfunction!(io::load, m)?)?;
    m.add_function(wrap_pyfunction!(io::save, m)?)?;
    m.add_function(wrap_pyfunction!(io::info, m)?)?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(render::encode_png, m)?)?;
    m.add_function(wrap_pyfunction!(render::save_png, m)?)?;
    ca::register(m)?;
    ifs::register(m)?;
    surfca::register(m)?;
    subdiv::register(m)?;
    Ok(())
}
