//! `asperity.reconstruct`, `asperity.dla_terrain`, `asperity.rdsr_sphere`:
//! level-set reconstruction and the two-pass pipelines
//! (`asperity_engine::reconstruct`, kim-machiraju-thompson §5–6).

use asperity_engine::reconstruct::{self as engine, Grown, Job, LevelSetOptions};
use asperity_levelset::{DistanceMethod, FlowChoice, Length, Neighbourhood, Scheme, TagRule};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::choice;
use crate::convert::{json, mesh_out, points_out, rows};
use crate::job::{RunOptions, budget, run};

/// The level-set keywords, as the Python layer passes them (a dict of the
/// CLI's flag names with underscores).
fn options(kw: &Bound<'_, PyDict>) -> PyResult<LevelSetOptions> {
    let mut o = LevelSetOptions::default();
    for (k, v) in kw.iter() {
        let key: String = k.extract()?;
        if v.is_none() {
            continue;
        }
        match key.as_str() {
            "paper" => o.paper = v.extract()?,
            "resolution" => o.resolution = Some(v.extract()?),
            "spacing" => o.spacing = Some(v.extract()?),
            "offset" => {
                o.offset = Some(match v.extract::<f64>() {
                    Ok(x) => Length::World(x),
                    Err(_) => Length::parse(&v.extract::<String>()?).map_err(crate::value_error)?,
                })
            }
            "iterations" => o.iterations = Some(v.extract()?),
            "tolerance" => o.tolerance = Some(v.extract()?),
            "point_radius" => o.point_radius = Some(v.extract()?),
            "scheme" => {
                o.scheme = match choice(&v.extract::<String>()?, &["eno2", "upwind"], "scheme")? {
                    "upwind" => Scheme::Upwind,
                    _ => Scheme::Eno2,
                }
            }
            "flow" => {
                let flows = ["convection", "regularized", "zhao"];
                o.flow = match choice(&v.extract::<String>()?, &flows, "flow")? {
                    "convection" => FlowChoice::Convection,
                    "zhao" => FlowChoice::Zhao,
                    _ => FlowChoice::Regularized {
                        weight_cells: kw
                            .get_item("curvature_weight")?
                            .map_or(Ok(1.0), |w| w.extract())?,
                    },
                }
            }
            "curvature_weight" => {}
            "distance" => {
                let names = ["closest-point", "godunov"];
                o.distance = Some(match choice(&v.extract::<String>()?, &names, "distance")? {
                    "godunov" => DistanceMethod::GODUNOV,
                    _ => DistanceMethod::ClosestPoint,
                })
            }
            "tube_n" => {
                o.neighbourhood = Some(
                    match choice(&v.extract::<String>()?, &["axes", "cube"], "tube_n")? {
                        "cube" => Neighbourhood::Cube,
                        _ => Neighbourhood::Axes,
                    },
                )
            }
            "tagging" => {
                o.tag_rule =
                    match choice(&v.extract::<String>()?, &["paper", "threshold"], "tagging")? {
                        "threshold" => TagRule::Threshold,
                        _ => TagRule::Paper,
                    }
            }
            "tube" => o.tube_cells = v.extract()?,
            "beta" => o.beta_cells = v.extract()?,
            "cfl" => o.cfl = v.extract()?,
            "redistance" => o.redistance_iterations = v.extract()?,
            "full_grid" => o.full_grid = v.extract()?,
            "curvature" => o.curvature = v.extract()?,
            "min_shell" => o.min_shell_triangles = v.extract()?,
            other => {
                return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                    "unexpected keyword argument {other:?}"
                )));
            }
        }
    }
    Ok(o)
}

fn surface<'py>(
    py: Python<'py>,
    points: Vec<[f64; 3]>,
    params: asperity_levelset::ReconstructParams,
    opts: &RunOptions,
    out: &Bound<'py, PyDict>,
) -> PyResult<()> {
    let rec = run(py, opts, move |w, time| {
        let n = points.len();
        let rec = engine::surface(&points, &params, None, (&budget(), time), w, &mut |_, _| {})?;
        Ok((rec, n))
    })?;
    let (rec, n) = rec;
    out.set_item("mesh", mesh_out(py, &rec.mesh)?)?;
    let topology = rec.mesh.topology();
    out.set_item(
        "measurements",
        json(&engine::measurements(&rec, n, &topology))?,
    )?;
    Ok(())
}

/// Reconstructs a watertight surface from (N, 3) points; returns a dict with
/// `mesh` and `measurements`.
#[pyfunction]
#[pyo3(signature = (points, level_set, threads, progress))]
pub fn reconstruct<'py>(
    py: Python<'py>,
    points: &Bound<'py, PyAny>,
    level_set: &Bound<'py, PyDict>,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let pts = rows::<3>(points, "points")?;
    let params = options(level_set)?.params(Job::Reconstruct);
    let out = PyDict::new(py);
    surface(py, pts, params, &RunOptions { threads, progress }, &out)?;
    Ok(out)
}

fn pipeline<'py>(
    py: Python<'py>,
    grown: Grown,
    job: Job,
    level_set: &Bound<'py, PyDict>,
    opts: &RunOptions,
) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    let params = options(level_set)?.params(job);
    out.set_item(
        "points",
        points_out(py, &asperity_core::PointSet::new(grown.points.clone()))?,
    )?;
    out.set_item("warnings", crate::spelled_all(grown.warnings))?;
    out.set_item("grown", json(&grown.facts)?)?;
    surface(py, grown.points, params, opts, &out)?;
    Ok(out)
}

/// Grows a plane DLA deposit and reconstructs it (Figs. 9–11).
#[pyfunction]
#[pyo3(signature = (size, particles, stick, sides, level_set, seed, threads, progress))]
#[allow(clippy::too_many_arguments)]
pub fn dla_terrain<'py>(
    py: Python<'py>,
    size: [usize; 3],
    particles: Option<usize>,
    stick: f64,
    sides: &str,
    level_set: &Bound<'py, PyDict>,
    seed: u64,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let paper = options(level_set)?.paper;
    let particles = particles.unwrap_or(engine::terrain_particles(paper));
    let sides = match choice(sides, &["walls", "periodic"], "sides")? {
        "periodic" => asperity_engine::growth::dla::Sides::Periodic,
        _ => asperity_engine::growth::dla::Sides::Walls,
    };
    let opts = RunOptions { threads, progress };
    let grown = run(py, &opts, move |w, time| {
        engine::dla_terrain(size, particles, (stick, sides), (seed, &budget(), time, w))
    })?;
    pipeline(py, grown, Job::DlaTerrain, level_set, &opts)
}

/// Grows RDSR layers on a sphere and reconstructs them (Fig. 8).
#[pyfunction]
#[pyo3(signature = (radius, layers, relax, level_set, seed, threads, progress))]
#[allow(clippy::too_many_arguments)]
pub fn rdsr_sphere<'py>(
    py: Python<'py>,
    radius: f64,
    layers: f64,
    relax: u32,
    level_set: &Bound<'py, PyDict>,
    seed: u64,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let opts = RunOptions { threads, progress };
    let grown = run(py, &opts, move |w, _| {
        engine::rdsr_sphere(radius, layers, relax, (seed, &budget(), w))
    })?;
    pipeline(py, grown, Job::RdsrSphere, level_set, &opts)
}
