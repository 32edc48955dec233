//! `asperity.surface_ca`: cellular automata on a triangle mesh — Voronoi,
//! corrosion and patina, Gray–Scott (gobron-chiba; `asperity_engine::surfca`).

use asperity_engine::surfca::{State, SurfaceCaInputs, SurfaceCaParams, run_job};
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{json, mesh_in, mesh_out, points_out, rows};
use crate::job::{RunOptions, budget, run, to_py};

/// Runs `surface-ca` with the parameters and seed of `params` (JSON) on a
/// mesh (a Mesh, or a spec such as "builtin:cup" or a path): a dict with
/// `mesh` (coloured cells, or the original mesh with the cell atlas when
/// `textured`), `labels` (Voronoi: a point set of cell centres with their
/// region), `field` (the per-cell oxide or activator, if any), `warnings`,
/// `measurements` and `params`.
#[pyfunction]
#[pyo3(signature = (params, mesh, site_points, textured, threads, progress))]
#[allow(clippy::too_many_arguments)] // the binding's boundary: parameters, three inputs, the run
pub fn surface_ca<'py>(
    py: Python<'py>,
    params: &str,
    mesh: &Bound<'py, PyAny>,
    site_points: Option<Bound<'py, PyAny>>,
    textured: bool,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (p, seed): (SurfaceCaParams, u64) = crate::params::from_json(py, params)?;
    let (base, name) = match mesh.extract::<String>() {
        Ok(spec) => (
            asperity_engine::files::load_mesh(&spec, &budget()).map_err(|e| to_py(py, e))?,
            spec,
        ),
        Err(_) => (mesh_in(mesh)?, "mesh".to_string()),
    };
    let at = site_points
        .map(|p| rows::<3>(&p, "site_points"))
        .transpose()?
        .map(|p| {
            (
                asperity_engine::core::PointSet::new(p),
                "site_points".to_string(),
            )
        });
    let inputs = SurfaceCaInputs {
        mesh: base,
        name,
        at,
    };
    let opts = RunOptions { threads, progress };
    let (p, cov, r, result) = run(py, &opts, move |w, time| {
        let (cov, r) = run_job(&p, inputs, seed, (&budget(), time), w, |_, _, _| {})?;
        let result = r.mesh(&cov, p.shape(textured), &budget())?;
        Ok((p, cov, r, result))
    })?;
    let out = PyDict::new(py);
    out.set_item("mesh", mesh_out(py, &result)?)?;
    match &r.state {
        State::Labels(_) => out.set_item(
            "labels",
            points_out(py, &r.labels(&cov).map_err(|e| to_py(py, e))?)?,
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
    out.set_item("params", crate::params::record(&p, seed))?;
    Ok(out)
}

/// Adds this module's functions.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(surface_ca, m)?)?;
    Ok(())
}
