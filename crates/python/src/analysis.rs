//! `asperity.analyze` and `asperity.fbm`: roughness reports
//! (`asperity_engine::analyze`) and self-affine test surfaces.

use asperity_core::fourier_surface::FourierParams;
use asperity_engine::analyze::{AnalyzeOptions, analyze as analyze_surface};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{height_out, json, surface_in};
use crate::job::{RunOptions, budget, run};

/// The CLI's `analyze` report of a mesh, height field or point set: a dict
/// with `measurements` (JSON text, the CLI's keys) and `warnings`.
#[pyfunction]
#[pyo3(signature = (surface, name, level, periodic, window, bins, fit_window, threads))]
#[allow(clippy::too_many_arguments)]
pub fn analyze<'py>(
    py: Python<'py>,
    surface: &Bound<'py, PyAny>,
    name: String,
    level: String,
    periodic: Option<bool>,
    window: String,
    bins: usize,
    fit_window: Option<[f64; 2]>,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let s = surface_in(surface)?;
    let opts = AnalyzeOptions {
        level,
        bins,
        fit_window,
        periodic,
        window,
        plots: false,
    };
    let r = run(py, &RunOptions::quiet(threads), move |_, _| {
        analyze_surface(&s, &name, &opts)
    })?;
    let out = PyDict::new(py);
    out.set_item("measurements", json(&r.facts)?)?;
    out.set_item("warnings", crate::spelled_all(r.warnings))?;
    Ok(out)
}

/// A periodic self-affine (fBm) height field by Fourier synthesis: the
/// CLI's `generate fbm`.
#[pyfunction]
#[pyo3(signature = (size, hurst, rms, spacing, seed, threads))]
#[allow(clippy::too_many_arguments)]
pub fn fbm<'py>(
    py: Python<'py>,
    size: usize,
    hurst: f64,
    rms: f64,
    spacing: f64,
    seed: u64,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let p = FourierParams {
        n: size,
        hurst,
        modes: size / 2,
        rms,
        spacing,
    };
    let h = run(py, &RunOptions::quiet(threads), move |_, _| {
        Ok(asperity_analysis::synthesis::fbm(&p, seed, &budget())?)
    })?;
    let d = height_out(py, h)?;
    d.set_item("title", format!("fBm H={hurst}"))?;
    Ok(d)
}
