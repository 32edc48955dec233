//! `asperity.rd/rdsr/bd/dla`: the growth jobs of `asperity_engine::growth`
//! (kim-machiraju-thompson §4).

use asperity_engine::growth::curved::{self, CurvedJob, Substrate};
use asperity_engine::growth::deposition::{self, DepositionJob};
use asperity_engine::growth::dla::{self as engine_dla, DlaJob};
use asperity_growth::Model;
use asperity_growth::dla::Sides;
use asperity_growth::seeds::SeedSpec;
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

/// Diffusion-limited aggregation; returns a dict with `points`, `title`,
/// `warnings` and `measurements`.
#[pyfunction]
#[pyo3(signature = (seed_shape, size, dim, particles, stick, seed_radius, mesh, resolution,
    image, seed_density, launch_gap, sides, seed, threads, progress))]
#[allow(clippy::too_many_arguments)]
pub fn dla<'py>(
    py: Python<'py>,
    seed_shape: &str,
    size: Option<[usize; 3]>,
    dim: usize,
    particles: usize,
    stick: f64,
    seed_radius: f64,
    mesh: Option<Bound<'py, PyAny>>,
    resolution: usize,
    image: Option<Bound<'py, PyAny>>,
    seed_density: f64,
    launch_gap: f64,
    sides: &str,
    seed: u64,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let shapes = ["point", "plane", "sphere", "mesh", "image"];
    let seed_spec = match choice(seed_shape, &shapes, "seed_shape")? {
        "point" => SeedSpec::Point,
        "plane" => SeedSpec::Plane,
        "sphere" => SeedSpec::Sphere(seed_radius),
        "mesh" => SeedSpec::Mesh {
            mesh: mesh_in(
                &mesh.ok_or_else(|| crate::value_error("seed_shape='mesh' needs mesh="))?,
            )?,
            resolution,
        },
        _ => SeedSpec::Image {
            image: height_in(
                &image.ok_or_else(|| crate::value_error("seed_shape='image' needs image="))?,
            )?,
            density: seed_density,
        },
    };
    let sides = match choice(sides, &["periodic", "walls"], "sides")? {
        "walls" => Sides::Walls,
        _ => Sides::Periodic,
    };
    let job = DlaJob {
        dim,
        size,
        particles,
        stick,
        seed: seed_spec,
        launch_gap,
        sides,
    };
    let opts = RunOptions { threads, progress };
    let r = run(py, &opts, move |w, time| {
        engine_dla::grow(job, seed, &budget(), time, w)
    })?;
    let out = PyDict::new(py);
    let warnings: Vec<String> = r.warnings().into_iter().map(|(_, m)| m).collect();
    out.set_item(
        "points",
        points_out(py, &asperity_core::PointSet::new(r.world_points()))?,
    )?;
    out.set_item("title", "dla")?;
    out.set_item("warnings", warnings)?;
    out.set_item("measurements", json(&r.measurements())?)?;
    Ok(out)
}
