//! `asperity.ifs_*`: projected-IFS curves and surfaces, DCF/SDCF and
//! pseudo-curvature (poull-gentil; `asperity_engine::ifs`).

use asperity_engine::ifs::{
    IfsCurvatureParams, IfsCurveParams, IfsDcfParams, IfsPresetParams, IfsSdcfParams,
    IfsSurfaceParams,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{json, mesh_out, rows_out};
use crate::job::{RunOptions, budget, run, to_py};
use crate::params::{from_json, record};

/// Every preset: a list of dicts (name, kind, description) as JSON text.
#[pyfunction]
pub fn ifs_presets() -> PyResult<String> {
    json(&asperity_engine::ifs::presets())
}

/// The model of `params` (`ifs preset`, JSON) as a model file's JSON text.
#[pyfunction]
pub fn ifs_model(py: Python<'_>, params: &str) -> PyResult<String> {
    let (p, _): (IfsPresetParams, u64) = from_json(py, params)?;
    let l = p.model.load().map_err(|e| to_py(py, e))?;
    Ok(l.file().to_json())
}

/// A curve's attractor (`ifs curve`, JSON parameters): a dict with `points`
/// ((2^depth + 1, 3)), `name` and `params`.
#[pyfunction]
pub fn ifs_curve<'py>(py: Python<'py>, params: &str) -> PyResult<Bound<'py, PyDict>> {
    let (p, seed): (IfsCurveParams, u64) = from_json(py, params)?;
    let (p, name, pts) = run(py, &RunOptions::quiet(None), move |_, _| {
        let (name, _, _, pts) = p.attractor()?;
        Ok((p, name, pts))
    })?;
    let out = PyDict::new(py);
    out.set_item("points", rows_out(py, pts)?)?;
    out.set_item("name", name)?;
    out.set_item("params", record(&p, seed))?;
    Ok(out)
}

/// A surface's attractor mesh (`ifs surface`, JSON parameters): a dict with
/// `mesh`, `name`, `note` and `params`.
#[pyfunction]
#[pyo3(signature = (params, threads))]
pub fn ifs_surface<'py>(
    py: Python<'py>,
    params: &str,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let (p, seed): (IfsSurfaceParams, u64) = from_json(py, params)?;
    let (p, name, mesh, note) = run(py, &RunOptions::quiet(threads), move |_, _| {
        let (name, _, mesh, note) = p.mesh(&budget())?;
        Ok((p, name, mesh, note))
    })?;
    let out = PyDict::new(py);
    out.set_item("mesh", mesh_out(py, &mesh)?)?;
    out.set_item("name", name)?;
    out.set_item("note", note.map(|n| crate::spelled(&n)))?;
    out.set_item("params", record(&p, seed))?;
    Ok(out)
}

/// A curve operator's DCF (`ifs dcf`, JSON parameters): a dict with `points`,
/// `class`, `alpha` and `params`.
#[pyfunction]
pub fn ifs_dcf<'py>(py: Python<'py>, params: &str) -> PyResult<Bound<'py, PyDict>> {
    let (p, seed): (IfsDcfParams, u64) = from_json(py, params)?;
    let (p, d) = run(py, &RunOptions::quiet(None), move |_, _| {
        let (_, _, _, d) = p.dcf()?;
        Ok((p, d))
    })?;
    let out = PyDict::new(py);
    out.set_item("points", rows_out(py, d.points)?)?;
    out.set_item("class", d.class)?;
    out.set_item("alpha", d.alpha)?;
    out.set_item("params", record(&p, seed))?;
    Ok(out)
}

/// The SDCF mesh of a surface operator (`ifs sdcf`, JSON parameters): a dict
/// with `mesh` and `params`.
#[pyfunction]
pub fn ifs_sdcf<'py>(py: Python<'py>, params: &str) -> PyResult<Bound<'py, PyDict>> {
    let (p, seed): (IfsSdcfParams, u64) = from_json(py, params)?;
    let (p, mesh) = run(py, &RunOptions::quiet(None), move |_, _| {
        let (_, mesh) = p.mesh(&budget())?;
        Ok((p, mesh))
    })?;
    let out = PyDict::new(py);
    out.set_item("mesh", mesh_out(py, &mesh)?)?;
    out.set_item("params", record(&p, seed))?;
    Ok(out)
}

/// The pseudo-curvature report (`ifs curvature --json`, JSON text) with its
/// `params`.
#[pyfunction]
pub fn ifs_curvature(py: Python<'_>, params: &str) -> PyResult<String> {
    let (p, seed): (IfsCurvatureParams, u64) = from_json(py, params)?;
    let doc = run(py, &RunOptions::quiet(None), move |_, _| {
        let (_, _, mut doc) = p.report()?;
        doc["params"] = asperity_engine::params::record(&p, seed);
        Ok(doc)
    })?;
    json(&doc)
}

/// Adds this module's functions.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(ifs_presets, m)?)?;
    m.add_function(wrap_pyfunction!(ifs_model, m)?)?;
    m.add_function(wrap_pyfunction!(ifs_curve, m)?)?;
    m.add_function(wrap_pyfunction!(ifs_surface, m)?)?;
    m.add_function(wrap_pyfunction!(ifs_dcf, m)?)?;
    m.add_function(wrap_pyfunction!(ifs_sdcf, m)?)?;
    m.add_function(wrap_pyfunction!(ifs_curvature, m)?)?;
    Ok(())
}
