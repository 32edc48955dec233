//! `asperity.rd/rdsr/bd/dla`: the growth jobs of `asperity_engine::growth`
//! (kim-machiraju-thompson §4).

use asperity_engine::growth::curved::{self, CurvedJob, Substrate};
use asperity_engine::growth::deposition::{self, DepositionJob};
use asperity_engine::growth::dla::{self as engine_dla, DlaParams, SeedInputs, SeedShape};
use asperity_growth::Model;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::choice;
use crate::convert::{height_in, height_out, json, mesh_in, points_out};
use crate::job::{RunOptions, budget, run};

/// Flat- or curved-substrate deposition; returns a dict with `heights` (a
/// height-field dict, flat substrates), `points` (a point-set dict, when
/// asked for or on a curved substrate), `title` and `measurements` (the
/// CLI's JSON text).
#[pyfunction]
#[pyo3(signature = (model, size, dim, layers, runs, relax, bin, samples_per_decade, fit_window,
    alpha_sizes, points, substrate, radius, mesh, resolution, seed, threads, progress))]
#[allow(clippy::too_many_arguments)]
pub fn deposit<'py>(
    py: Python<'py>,
    model: &str,
    size: usize,
    dim: usize,
    layers: f64,
    runs: usize,
    relax: u32,
    bin: Option<usize>,
    samples_per_decade: usize,
    fit_window: Option<[f64; 2]>,
    alpha_sizes: Option<Vec<usize>>,
    points: bool,
    substrate: &str,
    radius: f64,
    mesh: Option<Bound<'py, PyAny>>,
    resolution: usize,
    seed: u64,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let model = match choice(model, &["rd", "rdsr", "bd"], "model")? {
        "rd" => Model::Rd,
        "rdsr" => Model::Rdsr { radius: relax },
        _ => Model::Bd,
    };
    let opts = RunOptions { threads, progress };
    let out = PyDict::new(py);
    match choice(substrate, &["flat", "sphere", "mesh"], "substrate")? {
        "flat" => {
            let job = DepositionJob {
                model,
                size,
                dim,
                layers,
                runs,
                bin,
                samples_per_decade,
                fit_window,
                alpha_sizes,
                keep_points: points,
            };
            let (job, r) = run(py, &opts, move |w, time| {
                let r = deposition::deposit(&job, seed, &budget(), time, w)?;
                Ok((job, r))
            })?;
            out.set_item("heights", height_out(py, r.deposit.height_field())?)?;
            out.set_item("title", job.title())?;
            if points {
                out.set_item("points", points_out(py, &r.deposit.point_set())?)?;
            }
            out.set_item("measurements", json(&r.measurements(&job))?)?;
        }
        kind => {
            let substrate = match (kind, mesh) {
                ("mesh", Some(m)) => Substrate::Mesh {
                    mesh: mesh_in(&m)?,
                    resolution,
                },
                ("mesh", None) => return Err(crate::value_error("substrate='mesh' needs mesh=")),
                _ => Substrate::Sphere(radius),
            };
            let job = CurvedJob {
                model,
                substrate,
                layers,
                samples_per_decade,
            };
            let (job, r) = run(py, &opts, move |w, _| {
                let r = curved::deposit(&job, seed, &budget(), w)?;
                Ok((job, r))
            })?;
            let pts = asperity_core::PointSet::new(r.world_points());
            out.set_item("points", points_out(py, &pts)?)?;
            out.set_item("title", model.name())?;
            out.set_item("measurements", json(&r.measurements(&job))?)?;
        }
    }
    Ok(out)
}

/// Diffusion-limited aggregation (`growth dla`) with the parameters and seed
/// of `params` (JSON, the engine's `DlaParams`) and the seed's inputs; returns
/// a dict with `points`, `title`, `warnings`, `measurements` and `params`
/// (JSON texts).
#[pyfunction]
#[pyo3(signature = (params, mesh, image, threads, progress))]
pub fn dla<'py>(
    py: Python<'py>,
    params: &str,
    mesh: Option<Bound<'py, PyAny>>,
    image: Option<Bound<'py, PyAny>>,
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
    };
    let opts = RunOptions { threads, progress };
    let r = run(py, &opts, move |w, time| {
        engine_dla::grow(&p, inputs, seed, &budget(), time, w)
    })?;
    let out = PyDict::new(py);
    let warnings: Vec<String> = r.warnings().into_iter().map(|(_, m)| m).collect();
    out.set_item(
        "points",
        points_out(py, &asperity_core::PointSet::new(r.world_points()))?,
    )?;
    out.set_item("title", "dla")?;
    out.set_item("warnings", crate::spelled_all(warnings))?;
    out.set_item("measurements", json(&r.measurements())?)?;
    out.set_item("params", crate::params::record(&r.resolved, seed))?;
    Ok(out)
}
