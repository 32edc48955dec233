//! `asperity.analyze` and `asperity.fbm`: roughness reports
//! (`asperity_engine::analyze`) and self-affine test surfaces.

use asperity_engine::analyze::{AnalyzeParams, FilterParams, analyze as analyze_surface};
use asperity_engine::synthesis::FbmParams;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{height_out, json, surface_in};
use crate::job::{RunOptions, budget, run};

/// The `analyze` report of a mesh, height field or point set with the
/// parameters of `params` (JSON): a dict with `measurements` (JSON text, the
/// CLI's keys), `warnings` and `params`.
#[pyfunction]
#[pyo3(signature = (params, surface, name, threads))]
pub fn analyze<'py>(
    py: Python<'py>,
    params: &str,
    surface: &Bound<'py, PyAny>,
    name: String,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let (p, seed): (AnalyzeParams, u64) = crate::params::from_json(py, params)?;
    let s = surface_in(surface)?;
    let opts = p.options(false);
    let r = run(py, &RunOptions::quiet(threads), move |_, _| {
        analyze_surface(&s, &name, &opts, &budget())
    })?;
    let out = PyDict::new(py);
    out.set_item("measurements", json(&r.facts)?)?;
    out.set_item("warnings", crate::spelled_all(r.warnings))?;
    out.set_item("params", crate::params::record(&p, seed))?;
    Ok(out)
}

/// The `filter` of a height field with the parameters of `params` (JSON):
/// a dict with `surface`, `form`, `waviness` and `noise` (height-field dicts,
/// the last two `None` without their filter), `measurements` (JSON text, the
/// CLI's keys), `warnings` and `params`.
#[pyfunction]
#[pyo3(signature = (params, surface, threads))]
pub fn filter_surface<'py>(
    py: Python<'py>,
    params: &str,
    surface: &Bound<'py, PyAny>,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let (p, seed): (FilterParams, u64) = crate::params::from_json(py, params)?;
    let h = crate::convert::height_in(surface)?;
    let job = p.clone();
    let f = run(py, &RunOptions::quiet(threads), move |_, _| {
        asperity_engine::analyze::filter(&h, &job, &budget())
    })?;
    let out = PyDict::new(py);
    out.set_item("surface", height_out(py, f.surface)?)?;
    out.set_item("form", height_out(py, f.form)?)?;
    out.set_item(
        "waviness",
        f.waviness.map(|w| height_out(py, w)).transpose()?,
    )?;
    out.set_item("noise", f.noise.map(|n| height_out(py, n)).transpose()?)?;
    out.set_item("measurements", json(&f.facts)?)?;
    out.set_item("warnings", crate::spelled_all(f.warnings))?;
    out.set_item("params", crate::params::record(&p, seed))?;
    Ok(out)
}

/// A periodic self-affine (fBm) height field by Fourier synthesis (`generate
/// fbm`) with the parameters and seed of `params` (JSON): a height-field dict
/// with `title` and `params` (JSON text).
#[pyfunction]
#[pyo3(signature = (params, threads))]
pub fn fbm<'py>(
    py: Python<'py>,
    params: &str,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let (p, seed): (FbmParams, u64) = crate::params::from_json(py, params)?;
    let (p, h) = run(py, &RunOptions::quiet(threads), move |_, _| {
        let h = asperity_engine::synthesis::fbm(&p, seed, &budget())?;
        Ok((p, h))
    })?;
    let d = height_out(py, h)?;
    d.set_item("title", p.title())?;
    d.set_item("params", crate::params::record(&p, seed))?;
    Ok(d)
}
