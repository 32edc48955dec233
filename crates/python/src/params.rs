//! Job parameters between Python and the engine: keyword arguments arrive as
//! JSON text and become the engine's parameter struct (defaults filled in,
//! unknown keys refused, ranges checked — the same code the CLI's flags go
//! through); results carry the record of what ran (`params`).

use asperity_engine::jobs as registry;
use asperity_engine::params::{self, JobParams};
use pyo3::prelude::*;

use crate::job::to_py;

/// The parameters of `P` and the seed from the JSON object Python sends
/// (the job's fields and `seed`, as a record holds them).
pub fn from_json<P: JobParams>(py: Python<'_>, text: &str) -> PyResult<(P, u64)> {
    let value: serde_json::Value =
        serde_json::from_str(text).map_err(|e| crate::value_error(format!("parameters: {e}")))?;
    params::parse::<P>(&value)
        .map(|p| (p.params, p.seed.unwrap_or(params::DEFAULT_SEED)))
        .map_err(|e| to_py(py, e))
}

/// The `job` a JSON parameter object names, if any.
pub fn job_of(text: &str) -> Option<String> {
    let value: serde_json::Value = serde_json::from_str(text).ok()?;
    value.get("job")?.as_str().map(str::to_owned)
}

/// The record of a run as JSON text (`result.params` in Python).
pub fn record<P: JobParams>(p: &P, seed: u64) -> String {
    params::record(p, seed).to_string()
}

/// What the Python package needs to present a job: its fields in order with
/// descriptions, defaults, types, bounds and choices (JSON text).
#[pyfunction]
pub fn describe(py: Python<'_>, job: &str) -> PyResult<String> {
    let entry = registry::job(job).map_err(|e| to_py(py, e))?;
    Ok((entry.describe)().to_string())
}

/// The names of the jobs [`describe`] knows.
#[pyfunction]
pub fn jobs() -> Vec<&'static str> {
    registry::jobs().iter().map(|j| j.name).collect()
}
