//! `asperity.ca_run`, `ca_rule`, `facet`, `interpolate`: peridier's
//! cellular-automaton height fields (`asperity_engine::ca`).

use asperity_ca::facets::interpolate_many;
use asperity_ca::{Boundary, Weights};
use asperity_engine::ca::{
    FacetJob, RunJob, facets, parse_init, rule, rule_measurements, run_measurements,
};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{height_in, height_out, json, mesh_out, rows, rows_out};
use crate::job::{RunOptions, budget, run};

/// Evolves a CA and accumulates its steps into heights (the CLI's `ca run`);
/// a dict with `heights` (height-field dict), `title`, `measurements` and,
/// with `keep_states`, `states` (T+1, ny, nx) uint8.
#[pyfunction]
#[pyo3(signature = (rule_code, steps, family, states, init, size, boundary, no_step0, decay,
    weights, values, keep_states, seed, threads, progress))]
#[allow(clippy::too_many_arguments)]
pub fn ca_run<'py>(
    py: Python<'py>,
    rule_code: &str,
    steps: usize,
    family: &str,
    states: u8,
    init: &str,
    size: Option<[usize; 2]>,
    boundary: Option<&str>,
    no_step0: bool,
    decay: Option<f64>,
    weights: Option<Vec<f64>>,
    values: Option<Vec<f64>>,
    keep_states: bool,
    seed: u64,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let r = rule(family, states, rule_code).map_err(|e| crate::job::to_py(py, e))?;
    let k = r.states();
    let boundary = match boundary {
        None => None,
        Some(b) => Some(
            match crate::choice(b, &["cyclic", "infinite"], "boundary")? {
                "infinite" => Boundary::Infinite,
                _ => Boundary::Cyclic,
            },
        ),
    };
    let job = RunJob {
        init: parse_init(init, k, seed, &budget()).map_err(|e| crate::job::to_py(py, e))?,
        rule: r,
        steps,
        size,
        boundary,
        no_step0,
        weights: match (weights, decay) {
            (Some(w), _) => Weights::Explicit(w),
            (None, Some(r)) => Weights::Geometric(r),
            (None, None) => Weights::Uniform,
        },
        values,
        keep_states,
    };
    let opts = RunOptions { threads, progress };
    let (job, (result, boundary)) = run(py, &opts, move |w, time| {
        let r = asperity_engine::ca::run(&job, &budget(), time, w)?;
        Ok((job, r))
    })?;
    let h = result.heights;
    let [nx, ny] = h.dims();
    let out = PyDict::new(py);
    out.set_item("measurements", json(&run_measurements(&job, &h, boundary))?)?;
    out.set_item("title", format!("CA rule {}", job.rule.code()))?;
    if let Some(st) = result.states {
        out.set_item(
            "states",
            PyArray1::from_vec(py, st).reshape([steps + 1, ny, nx])?,
        )?;
    }
    out.set_item("heights", height_out(py, h)?)?;
    Ok(out)
}

/// A rule's look-up table and facts (the CLI's `ca rule`): a dict with
/// `describe` (text) and `measurements` (JSON text).
#[pyfunction]
#[pyo3(signature = (rule_code, family, states))]
pub fn ca_rule<'py>(
    py: Python<'py>,
    rule_code: &str,
    family: &str,
    states: u8,
) -> PyResult<Bound<'py, PyDict>> {
    let r = rule(family, states, rule_code).map_err(|e| crate::job::to_py(py, e))?;
    let out = PyDict::new(py);
    out.set_item("describe", r.describe())?;
    out.set_item("measurements", json(&rule_measurements(&r))?)?;
    Ok(out)
}

/// The alternating-diagonal facet mesh of a height field and the curves
/// draped on it (the CLI's `facet`): a dict with `mesh` and `curves`.
#[pyfunction]
#[pyo3(signature = (heights, smooth, shared, circle, polyline))]
pub fn facet<'py>(
    py: Python<'py>,
    heights: &Bound<'py, PyAny>,
    smooth: bool,
    shared: bool,
    circle: Option<[f64; 3]>,
    polyline: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let h = height_in(heights)?;
    let job = FacetJob {
        smooth,
        shared,
        circle,
        polyline: polyline.map(|p| rows::<2>(&p, "polyline")).transpose()?,
    };
    let (mesh, curves) = facets(&h, &job).map_err(|e| crate::job::to_py(py, e))?;
    let out = PyDict::new(py);
    out.set_item("mesh", mesh_out(py, &mesh)?)?;
    let curves = curves
        .into_iter()
        .map(|c| rows_out(py, c))
        .collect::<PyResult<Vec<_>>>()?;
    out.set_item("curves", curves)?;
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

/// Adds this module's functions.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(ca_run, m)?)?;
    m.add_function(wrap_pyfunction!(ca_rule, m)?)?;
    m.add_function(wrap_pyfunction!(facet, m)?)?;
    m.add_function(wrap_pyfunction!(interpolate, m)?)?;
    Ok(())
}
