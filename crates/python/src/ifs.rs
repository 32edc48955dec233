//! `asperity.ifs_*`: projected-IFS curves and surfaces, DCF/SDCF and
//! pseudo-curvature (poull-gentil; `asperity_engine::ifs`).

use asperity_engine::ifs::{
    ModelSpec, curvature_doc, curvature_report, dcf_for, load, sdcf_for, surface_mesh,
};
use asperity_ifs::sdcf::Start;
use asperity_ifs::{FamilyOptions, PresetParams};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{json, mesh_out, rows_out};
use crate::job::{RunOptions, budget, run, to_py};

/// The model keywords every IFS function takes, as the Python layer passes
/// them: `preset` or `model` (a model file's JSON text), the preset
/// parameters, control-point moves and the family options.
fn spec(kw: &Bound<'_, PyDict>) -> PyResult<ModelSpec> {
    let get = |k: &str| kw.get_item(k).map(|v| v.filter(|v| !v.is_none()));
    let opt = |k: &str| -> PyResult<Option<f64>> { get(k)?.map(|v| v.extract()).transpose() };
    Ok(ModelSpec {
        preset: get("preset")?.map(|v| v.extract()).transpose()?,
        file: None,
        json: get("model")?.map(|v| v.extract()).transpose()?,
        params: PresetParams {
            w: opt("w")?,
            degree: get("degree")?.map(|v| v.extract()).transpose()?,
            height: opt("height")?,
        },
        control: None,
        moves: get("moves")?
            .map(|v| v.extract())
            .transpose()?
            .unwrap_or_default(),
        family: FamilyOptions {
            dyadic_depth: get("family_depth")?.map_or(Ok(10), |v| v.extract())?,
            period: get("family_period")?.map_or(Ok(12), |v| v.extract())?,
        },
    })
}

fn start(bound: Option<&str>, param: f64) -> PyResult<Start> {
    Ok(match bound {
        None => Start::Parameter(param),
        Some(b) => match crate::choice(b, &["lower", "upper"], "bound")? {
            "lower" => Start::Lower,
            _ => Start::Upper,
        },
    })
}

/// Every preset: a list of dicts (name, kind, description) as JSON text.
#[pyfunction]
pub fn ifs_presets() -> PyResult<String> {
    json(&asperity_engine::ifs::presets())
}

/// The model as a model file's JSON text (what `ifs preset` writes).
#[pyfunction]
pub fn ifs_model(py: Python<'_>, model: &Bound<'_, PyDict>) -> PyResult<String> {
    let l = load(&spec(model)?).map_err(|e| to_py(py, e))?;
    Ok(l.file().to_json())
}

/// A curve's attractor at `depth`: (2^depth + 1, 3) points, and its name.
#[pyfunction]
pub fn ifs_curve<'py>(
    py: Python<'py>,
    model: &Bound<'py, PyDict>,
    depth: u32,
) -> PyResult<(Bound<'py, PyAny>, String)> {
    let spec = spec(model)?;
    let (name, pts) = run(py, &RunOptions::quiet(None), move |_, _| {
        let (name, c, _) = load(&spec)?.curve()?;
        Ok((name, c.attractor(depth)?))
    })?;
    Ok((rows_out(py, pts)?, name))
}

/// A surface's attractor mesh at `depth` (with curvature scalars unless
/// `curvature=False`): a dict with `mesh`, `name` and `note`.
#[pyfunction]
pub fn ifs_surface<'py>(
    py: Python<'py>,
    model: &Bound<'py, PyDict>,
    depth: u32,
    curvature: bool,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let spec = spec(model)?;
    let height = spec.params.height;
    let (name, mesh, note) = run(py, &RunOptions::quiet(threads), move |_, _| {
        let (name, s, opts) = load(&spec)?.surface(height)?;
        let (mesh, note) = surface_mesh(&s, &opts, depth, curvature, &budget())?;
        Ok((name, mesh, note))
    })?;
    let out = PyDict::new(py);
    out.set_item("mesh", mesh_out(py, &mesh)?)?;
    out.set_item("name", name)?;
    out.set_item("note", note)?;
    Ok(out)
}

/// The DCF of operator `operator` of a curve: a dict with `points`, `class`
/// and `alpha`.
#[pyfunction]
#[pyo3(signature = (model, operator, start_at, bound, samples))]
pub fn ifs_dcf<'py>(
    py: Python<'py>,
    model: &Bound<'py, PyDict>,
    operator: usize,
    start_at: Option<f64>,
    bound: Option<&str>,
    samples: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let spec = spec(model)?;
    let first = start(bound, start_at.unwrap_or(1.0 - operator.min(1) as f64))?;
    let d = run(py, &RunOptions::quiet(None), move |_, _| {
        let (_, c, opts) = load(&spec)?.curve()?;
        dcf_for(&c, &opts, operator, Some(first), samples)
    })?;
    let out = PyDict::new(py);
    out.set_item("points", rows_out(py, d.points)?)?;
    out.set_item("class", d.class)?;
    out.set_item("alpha", d.alpha)?;
    Ok(out)
}

/// The SDCF mesh of the operator pair (i, j) of a surface.
#[pyfunction]
#[pyo3(signature = (model, operator, start_at, bound, resolution))]
pub fn ifs_sdcf<'py>(
    py: Python<'py>,
    model: &Bound<'py, PyDict>,
    operator: (usize, usize),
    start_at: Option<(f64, f64)>,
    bound: Option<&str>,
    resolution: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let (i, j) = operator;
    if i > 1 || j > 1 {
        return Err(crate::value_error(format!(
            "--operator {i},{j}: I and J are 0 or 1"
        )));
    }
    let spec = spec(model)?;
    let height = spec.params.height;
    let st = start_at.unwrap_or((1.0 - i as f64, 1.0 - j as f64));
    let starts = (start(bound, st.0)?, start(bound, st.1)?);
    let mesh = run(py, &RunOptions::quiet(None), move |_, _| {
        let (_, s, opts) = load(&spec)?.surface(height)?;
        sdcf_for(&s, &opts, (i, j), starts, resolution, &budget())
    })?;
    mesh_out(py, &mesh)
}

/// The pseudo-curvature report (the CLI's `ifs curvature --json`, JSON text).
#[pyfunction]
pub fn ifs_curvature(
    py: Python<'_>,
    model: &Bound<'_, PyDict>,
    at: Vec<String>,
) -> PyResult<String> {
    let spec = spec(model)?;
    let doc = run(py, &RunOptions::quiet(None), move |_, _| {
        let l = load(&spec)?;
        let report = curvature_report(&l, &at)?;
        curvature_doc(&l, &report)
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
