//! `asperity.ca_run`, `ca_rule`, `ca_gallery`, `facet`, `interpolate`: peridier's
//! cellular-automaton height fields (`asperity_engine::ca`).

use asperity_engine::ca::{
    CaGalleryParams, CaRuleParams, CaRunParams, FacetParams, facets, gallery_image,
    rule_measurements, run_job,
};
use asperity_engine::methods::ca::facets::interpolate_many;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{height_in, height_out, json, mesh_out, rows, rows_out};
use crate::job::{RunOptions, budget, run, to_py};

/// Evolves a CA and accumulates its steps into heights (`ca run`) with the
/// parameters and seed of `params` (JSON); a dict with `heights`
/// (height-field dict), `title`, `measurements`, `params` and, with
/// `keep_states`, `states` (T+1, ny, nx) uint8.
#[pyfunction]
#[pyo3(signature = (params, keep_states, threads, progress))]
pub fn ca_run<'py>(
    py: Python<'py>,
    params: &str,
    keep_states: bool,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (p, seed): (CaRunParams, u64) = crate::params::from_json(py, params)?;
    let opts = RunOptions { threads, progress };
    let (p, r) = run(py, &opts, move |w, time| {
        let r = run_job(&p, keep_states, seed, (&budget(), time), w)?;
        Ok((p, r))
    })?;
    let out = PyDict::new(py);
    out.set_item("measurements", json(&r.measurements())?)?;
    out.set_item("title", r.title())?;
    let [nx, ny] = r.output.heights.dims();
    if let Some(st) = r.output.states {
        out.set_item(
            "states",
            PyArray1::from_vec(py, st).reshape([r.job.steps + 1, ny, nx])?,
        )?;
    }
    out.set_item("heights", height_out(py, r.output.heights)?)?;
    out.set_item("params", crate::params::record(&p, seed))?;
    Ok(out)
}

/// A rule's look-up table and facts (`ca rule`): a dict with `describe`
/// (text), `measurements` and `params` (JSON texts).
#[pyfunction]
#[pyo3(signature = (params,))]
pub fn ca_rule<'py>(py: Python<'py>, params: &str) -> PyResult<Bound<'py, PyDict>> {
    let (p, seed): (CaRuleParams, u64) = crate::params::from_json(py, params)?;
    let code = asperity_engine::params::require(&p.rule, "rule").map_err(|e| to_py(py, e))?;
    let r = p.family.rule(&code).map_err(|e| to_py(py, e))?;
    let out = PyDict::new(py);
    out.set_item("describe", r.describe())?;
    out.set_item("measurements", json(&rule_measurements(&r))?)?;
    out.set_item("params", crate::params::record(&p, seed))?;
    Ok(out)
}

/// The alternating-diagonal facet mesh of a height field and the curves
/// draped on it (`facet`) with the parameters of `params` (JSON): a dict with
/// `mesh`, `curves` and `params`.
#[pyfunction]
#[pyo3(signature = (params, heights, polyline))]
pub fn facet<'py>(
    py: Python<'py>,
    params: &str,
    heights: &Bound<'py, PyAny>,
    polyline: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (p, seed): (FacetParams, u64) = crate::params::from_json(py, params)?;
    let h = height_in(heights)?;
    let polyline = polyline.map(|l| rows::<2>(&l, "polyline")).transpose()?;
    let (mesh, curves) = facets(&h, &p, polyline.as_deref()).map_err(|e| to_py(py, e))?;
    let out = PyDict::new(py);
    out.set_item("mesh", mesh_out(py, &mesh)?)?;
    let curves = curves
        .into_iter()
        .map(|c| rows_out(py, c))
        .collect::<PyResult<Vec<_>>>()?;
    out.set_item("curves", curves)?;
    out.set_item("params", crate::params::record(&p, seed))?;
    Ok(out)
}

/// A picture of CA height fields, one row per rule and one column per
/// initial condition (`ca gallery`): a dict with `image` (H, W, 4) and
/// `params`.
#[pyfunction]
#[pyo3(signature = (params, threads = None))]
pub fn ca_gallery<'py>(
    py: Python<'py>,
    params: &str,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let (p, seed): (CaGalleryParams, u64) = crate::params::from_json(py, params)?;
    let (p, img) = run(py, &RunOptions::quiet(threads), move |_, time| {
        let img = gallery_image(&p, seed, &budget(), time)?;
        Ok((p, img))
    })?;
    let out = PyDict::new(py);
    out.set_item("image", crate::convert::image_out(py, &img)?)?;
    out.set_item("params", crate::params::record(&p, seed))?;
    Ok(out)
}

/// Heights on the facets at (N, 2) points; NaN outside the field.
#[pyfunction]
pub fn interpolate<'py>(
    py: Python<'py>,
    heights: &Bound<'py, PyAny>,
    points: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let h = height_in(heights)?;
    let pts = rows::<2>(points, "points")?;
    let z: Vec<f64> = interpolate_many(&h, &pts)
        .into_iter()
        .map(|z| z.unwrap_or(f64::NAN))
        .collect();
    Ok(PyArray1::from_vec(py, z))
}

/// The engine's example terrain run (JSON text of `ca run`'s parameters).
#[pyfunction]
pub fn ca_terrain_example() -> PyResult<String> {
    crate::convert::json(&asperity_engine::ca::CaRunParams::terrain_example())
}

/// Adds this module's functions.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(ca_run, m)?)?;
    m.add_function(wrap_pyfunction!(ca_terrain_example, m)?)?;
    m.add_function(wrap_pyfunction!(ca_rule, m)?)?;
    m.add_function(wrap_pyfunction!(ca_gallery, m)?)?;
    m.add_function(wrap_pyfunction!(facet, m)?)?;
    m.add_function(wrap_pyfunction!(interpolate, m)?)?;
    Ok(())
}
