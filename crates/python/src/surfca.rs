//! `asperity.surface_ca`: cellular automata on a triangle mesh — Voronoi,
//! corrosion and patina, Gray–Scott (gobron-chiba; `asperity_engine::surfca`).

use asperity_engine::surfca::{AppRequest, OutputShape, check_time, cover, run_app};
use asperity_surfca::CellSize;
use asperity_surfca::corrosion::CorrosionParams;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{json, mesh_in, mesh_out, points_out, rows};
use crate::job::{RunOptions, budget, run};

/// The application's keywords, as the CLI's flags (underscored).
fn corrosion_params(kw: &Bound<'_, PyDict>) -> PyResult<CorrosionParams> {
    let mut p = CorrosionParams::default();
    for (k, v) in kw.iter() {
        if v.is_none() {
            continue;
        }
        match k.extract::<String>()?.as_str() {
            "k1" => p.k1 = v.extract()?,
            "k2" => p.k2 = v.extract()?,
            "k3" => p.k3 = v.extract()?,
            "seed_rate" => p.seed_rate = v.extract()?,
            "max_seeds" => p.max_seeds = v.extract()?,
            "strong_fraction" => p.strong_fraction = v.extract()?,
            "strong_noise" => p.strong_noise_scale = Some(v.extract()?),
            "max_attacked" => p.max_attacked = v.extract()?,
            "attack" => p.attack = v.extract()?,
            "maturity" => p.maturity = v.extract()?,
            other => {
                return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                    "unexpected corrosion keyword {other:?}"
                )));
            }
        }
    }
    Ok(p)
}

/// Runs an application on a mesh (a Mesh, or a spec such as
/// "builtin:cup" or a path): a dict with `mesh` (coloured cells, or the
/// original mesh with the cell atlas when `textured`), `labels` (Voronoi:
/// a point set of cell centres with their region), `field` (the per-cell oxide or
/// activator, if any), `warnings` and `measurements`.
#[pyfunction]
#[pyo3(signature = (mesh, app, cells, cell_size, repair, sites, site_points, diagonal_p,
    max_steps, steps, feed, kill, patches, corrosion, textured, cell_mesh, displace, seed,
    threads, progress))]
#[allow(clippy::too_many_arguments)]
pub fn surface_ca<'py>(
    py: Python<'py>,
    mesh: &Bound<'py, PyAny>,
    app: &str,
    cells: usize,
    cell_size: Option<f64>,
    repair: bool,
    sites: usize,
    site_points: Option<Bound<'py, PyAny>>,
    diagonal_p: Option<f64>,
    max_steps: u64,
    steps: u64,
    feed: f32,
    kill: f32,
    patches: usize,
    corrosion: &Bound<'py, PyDict>,
    textured: bool,
    cell_mesh: bool,
    displace: Option<f64>,
    seed: u64,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (base, name) = match mesh.extract::<String>() {
        Ok(spec) => (
            asperity_engine::files::load_mesh(&spec, &budget())
                .map_err(|e| crate::job::to_py(py, e))?,
            spec,
        ),
        Err(_) => (mesh_in(mesh)?, "mesh".to_string()),
    };
    let at = site_points
        .map(|p| rows::<3>(&p, "site_points"))
        .transpose()?
        .map(|p| (asperity_core::PointSet::new(p), "site_points".to_string()));
    let request = match crate::choice(app, &["voronoi", "corrosion", "gray-scott"], "app")? {
        "voronoi" => AppRequest::Voronoi {
            sites,
            at,
            diagonal_p,
            max_steps,
        },
        "corrosion" => AppRequest::Corrosion {
            params: corrosion_params(corrosion)?,
            steps,
            at,
        },
        _ => AppRequest::GrayScott {
            feed,
            kill,
            patches,
            steps,
        },
    };
    let size = match cell_size {
        Some(h) => CellSize::Size(h),
        None => CellSize::Count(cells),
    };
    let shape = OutputShape {
        textured,
        cell_mesh,
        displace,
    };
    let opts = RunOptions { threads, progress };
    let (cov, r, result) = run(py, &opts, move |w, time| {
        if let Ok(n) = asperity_surfca::cells::estimated_count(&base, size) {
            check_time(n, &request.kind(), time)?;
        }
        let cov = cover(base, &name, repair, size, &budget())?;
        let application = request.build(&cov, seed)?;
        asperity_engine::surfca::start_progress(w, &application);
        let r = run_app(&cov, application, seed, time, |_, _| {
            asperity_core::Progress::advance(w, 1)
        })?;
        let result = r.mesh(&cov, shape, &budget())?;
        Ok((cov, r, result))
    })?;
    let out = PyDict::new(py);
    out.set_item("mesh", mesh_out(py, &result)?)?;
    match &r.state {
        asperity_engine::surfca::State::Labels(_) => out.set_item(
            "labels",
            points_out(py, &r.labels(&cov).map_err(|e| crate::job::to_py(py, e))?)?,
        )?,
        _ => out.set_item("labels", py.None())?,
    }
    match r.state.field() {
        Some((name, values)) => {
            out.set_item("field_name", name)?;
            out.set_item("field", PyArray1::from_vec(py, values))?;
        }
        None => out.set_item("field", py.None())?,
    }
    let mut warnings: Vec<String> = cov.cells.stats.warnings.clone();
    warnings.extend(r.warnings());
    out.set_item("warnings", crate::spelled_all(warnings))?;
    out.set_item("measurements", json(&r.measurements(&cov))?)?;
    Ok(out)
}

/// Adds this module's functions.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(surface_ca, m)?)?;
    Ok(())
}
