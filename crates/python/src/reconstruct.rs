//! `asperity.reconstruct`, `asperity.dla_terrain`, `asperity.rdsr_sphere`:
//! level-set reconstruction and the two-pass pipelines
//! (`asperity_engine::reconstruct`, kim-machiraju-thompson §5–6).

use asperity_engine::reconstruct::{
    self as engine, DlaTerrainParams, Grown, Job, LevelSetParams, RdsrSphereParams,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{json, mesh_out, points_out, rows};
use crate::job::{RunOptions, budget, run};

fn surface<'py>(
    py: Python<'py>,
    (points, normals): (Vec<[f64; 3]>, Option<Vec<[f64; 3]>>),
    (params, job): (LevelSetParams, Job),
    opts: &RunOptions,
    out: &Bound<'py, PyDict>,
) -> PyResult<()> {
    let surf = run(py, opts, move |w, time| {
        let n = points.len();
        let cloud = engine::Cloud {
            points: &points,
            normals: normals.as_deref(),
        };
        let surf =
            engine::reconstruct_job(cloud, (&params, job), (&budget(), time), w, &mut |_, _| {})?;
        Ok((surf, n))
    })?;
    let (surf, n) = surf;
    out.set_item("mesh", mesh_out(py, &surf.rec.mesh)?)?;
    let topology = surf.rec.mesh.topology();
    out.set_item(
        "measurements",
        json(&engine::measurements(&surf, n, &topology))?,
    )?;
    Ok(())
}

/// Reconstructs a watertight surface from (N, 3) points with the level-set
/// settings of `params` (JSON, the engine's `LevelSetParams`); returns a dict
/// with `mesh`, `measurements` and `params`.
#[pyfunction]
#[pyo3(signature = (params, points, normals, threads, progress))]
pub fn reconstruct<'py>(
    py: Python<'py>,
    params: &str,
    points: &Bound<'py, PyAny>,
    normals: Option<&Bound<'py, PyAny>>,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (p, seed): (LevelSetParams, u64) = crate::params::from_json(py, params)?;
    let pts = rows::<3>(points, "points")?;
    let normals = normals.map(|n| rows::<3>(n, "normals")).transpose()?;
    let out = PyDict::new(py);
    surface(
        py,
        (pts, normals),
        (p.clone(), Job::Reconstruct),
        &RunOptions { threads, progress },
        &out,
    )?;
    out.set_item(
        "params",
        crate::params::record(&p.resolved(Job::Reconstruct), seed),
    )?;
    Ok(out)
}

fn pipeline<'py>(
    py: Python<'py>,
    grown: Grown,
    job: Job,
    level_set: &LevelSetParams,
    opts: &RunOptions,
) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    out.set_item(
        "points",
        points_out(
            py,
            &asperity_engine::core::PointSet::new(grown.points.clone()),
        )?,
    )?;
    out.set_item("warnings", crate::spelled_all(grown.warnings))?;
    out.set_item("grown", json(&grown.facts)?)?;
    surface(
        py,
        (grown.points, None),
        (level_set.clone(), job),
        opts,
        &out,
    )?;
    Ok(out)
}

/// Grows a plane DLA deposit and reconstructs it (Figs. 9–11) with the
/// parameters and seed of `params` (JSON, the engine's `DlaTerrainParams`).
#[pyfunction]
#[pyo3(signature = (params, threads, progress))]
pub fn dla_terrain<'py>(
    py: Python<'py>,
    params: &str,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (p, seed): (DlaTerrainParams, u64) = crate::params::from_json(py, params)?;
    let opts = RunOptions { threads, progress };
    let (p, grown) = run(py, &opts, move |w, time| {
        let grown = engine::dla_terrain(&p, (seed, &budget(), time, w))?;
        Ok((p, grown))
    })?;
    let out = pipeline(py, grown, Job::DlaTerrain, &p.level_set, &opts)?;
    let resolved = p.resolved().map_err(|e| crate::job::to_py(py, e))?;
    out.set_item("params", crate::params::record(&resolved, seed))?;
    Ok(out)
}

/// Grows RDSR layers on a sphere and reconstructs them (Fig. 8) with the
/// parameters and seed of `params` (JSON, the engine's `RdsrSphereParams`).
#[pyfunction]
#[pyo3(signature = (params, threads, progress))]
pub fn rdsr_sphere<'py>(
    py: Python<'py>,
    params: &str,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (p, seed): (RdsrSphereParams, u64) = crate::params::from_json(py, params)?;
    let opts = RunOptions { threads, progress };
    let (p, grown) = run(py, &opts, move |w, _| {
        let grown = engine::rdsr_sphere(&p, (seed, &budget(), w))?;
        Ok((p, grown))
    })?;
    let out = pipeline(py, grown, Job::RdsrSphere, &p.level_set, &opts)?;
    out.set_item("params", crate::params::record(&p.resolved(), seed))?;
    Ok(out)
}
