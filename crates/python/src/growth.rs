//! `asperity.rd/rdsr/bd/dla`: the growth jobs of `asperity_engine::growth`
//! (kim-machiraju-thompson §4).

use asperity_engine::growth::dla::{self as engine_dla, DlaParams, SeedInputs, SeedShape};
use asperity_engine::growth::{
    self, BdParams, DepositJob, Deposited, RdParams, RdsrParams, SubstrateShape,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{height_in, height_out, json, mesh_in, points_out};
use crate::job::{RunOptions, budget, run};

/// RD, RDSR or BD (the `job` of `params`: `growth rd|rdsr|bd`) with the
/// parameters and seed of `params` (JSON, the engine's parameters of the job)
/// on a flat, spherical or mesh substrate; returns a dict with `heights` (a
/// height-field dict, flat substrates), `points` (a point-set dict, when asked
/// for or on a curved substrate), `title`, `measurements` and `params` (JSON
/// texts).
#[pyfunction]
#[pyo3(signature = (params, mesh, points, threads, progress))]
pub fn deposit<'py>(
    py: Python<'py>,
    params: &str,
    mesh: Option<Bound<'py, PyAny>>,
    points: bool,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    match crate::params::job_of(params).as_deref() {
        Some("growth rd") => {
            deposit_job::<RdParams>(py, params, mesh, points, RunOptions { threads, progress })
        }
        Some("growth rdsr") => {
            deposit_job::<RdsrParams>(py, params, mesh, points, RunOptions { threads, progress })
        }
        Some("growth bd") => {
            deposit_job::<BdParams>(py, params, mesh, points, RunOptions { threads, progress })
        }
        job => Err(crate::value_error(format!(
            "job {job:?} is not one of: growth rd, growth rdsr, growth bd"
        ))),
    }
}

fn deposit_job<'py, P: DepositJob>(
    py: Python<'py>,
    params: &str,
    mesh: Option<Bound<'py, PyAny>>,
    points: bool,
    opts: RunOptions,
) -> PyResult<Bound<'py, PyDict>> {
    let (p, seed): (P, u64) = crate::params::from_json(py, params)?;
    let mesh = match (&mesh, p.deposit().substrate) {
        (Some(m), SubstrateShape::Mesh) => Some(mesh_in(m)?),
        _ => None,
    };
    let (p, r) = run(py, &opts, move |w, time| {
        let r = growth::deposit(&p, mesh, points, seed, (&budget(), time), w)?;
        Ok((p, r))
    })?;
    let out = PyDict::new(py);
    match &r {
        Deposited::Flat(_, flat) => {
            out.set_item("heights", height_out(py, flat.deposit.height_field())?)?;
            if points {
                out.set_item("points", points_out(py, &r.points())?)?;
            }
        }
        Deposited::Curved(..) => out.set_item("points", points_out(py, &r.points())?)?,
    }
    out.set_item("title", r.title())?;
    out.set_item("measurements", json(&r.measurements())?)?;
    out.set_item("params", crate::params::record(&p, seed))?;
    Ok(out)
}

/// Diffusion-limited aggregation (`growth dla`) with the parameters and seed
/// of `params` (JSON, the engine's `DlaParams`) and the seed's inputs; returns
/// a dict with `points`, `title`, `warnings`, `measurements` and `params`
/// (JSON texts).
#[pyfunction]
#[pyo3(signature = (params, mesh, image, walkers, threads, progress))]
#[allow(clippy::too_many_arguments)]
pub fn dla<'py>(
    py: Python<'py>,
    params: &str,
    mesh: Option<Bound<'py, PyAny>>,
    image: Option<Bound<'py, PyAny>>,
    walkers: Option<usize>,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (p, seed): (DlaParams, u64) = crate::params::from_json(py, params)?;
    let inputs = SeedInputs {
        mesh: match (&mesh, p.seed_shape) {
            (Some(m), SeedShape::Mesh) => Some(mesh_in(m)?),
            _ => None,
        },
        image: match (&image, p.seed_shape) {
            (Some(i), SeedShape::Image) => Some(height_in(i)?),
            _ => None,
        },
        walkers,
    };
    let opts = RunOptions { threads, progress };
    let r = run(py, &opts, move |w, time| {
        engine_dla::grow(&p, inputs, seed, &budget(), time, w)
    })?;
    let out = PyDict::new(py);
    let warnings: Vec<String> = r.warnings().into_iter().map(|(_, m)| m).collect();
    out.set_item(
        "points",
        points_out(py, &asperity_engine::core::PointSet::new(r.world_points()))?,
    )?;
    out.set_item("title", "dla")?;
    out.set_item("warnings", crate::spelled_all(warnings))?;
    out.set_item("measurements", json(&r.measurements())?)?;
    out.set_item("params", crate::params::record(&r.resolved, seed))?;
    Ok(out)
}
