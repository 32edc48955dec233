//! `asperity.render`: a picture of a surface as an (H, W, 4) uint8 array
//! (`asperity_engine::render`, the gobron-chiba light model).

use asperity_engine::render::{RenderParams, render_job};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{image_out, surface_in};
use crate::job::{RunOptions, budget, run};

/// A picture of `surface` (`render`, the parameters of `params` as JSON): a
/// dict with `image` ((H, W, 4) uint8) and `params`.
#[pyfunction]
#[pyo3(signature = (params, surface, threads))]
pub fn render<'py>(
    py: Python<'py>,
    params: &str,
    surface: &Bound<'py, PyAny>,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let (p, seed): (RenderParams, u64) = crate::params::from_json(py, params)?;
    let s = surface_in(surface)?;
    let (p, img) = run(py, &RunOptions::quiet(threads), move |_, time| {
        let img = render_job(&s, &p, (0, 1), (&budget(), time))?;
        Ok((p, img))
    })?;
    let out = PyDict::new(py);
    out.set_item("image", image_out(py, &img)?)?;
    out.set_item("params", crate::params::record(&p, seed))?;
    Ok(out)
}

/// An (H, W, 4) uint8 array as PNG bytes (for Jupyter's `_repr_png_`), with
/// `params` (a record's JSON text) in a `tEXt` chunk as the CLI writes them.
#[pyfunction]
#[pyo3(signature = (image, params = None))]
pub fn encode_png<'py>(
    py: Python<'py>,
    image: &Bound<'py, PyAny>,
    params: Option<&str>,
) -> PyResult<Bound<'py, pyo3::types::PyBytes>> {
    let img = crate::convert::image_in(image, "image")?;
    let text =
        crate::io::params_value(params)?.map(|v| asperity_engine::io::metadata::params_text(&v));
    let bytes = asperity_engine::io::png_io::encode_rgba_with(&img, text.as_deref())
        .map_err(crate::value_error)?;
    Ok(pyo3::types::PyBytes::new(py, &bytes))
}

/// Writes an (H, W, 4) uint8 array as PNG, atomically, with `params` as
/// [`encode_png`].
#[pyfunction]
#[pyo3(signature = (path, image, params = None))]
pub fn save_png(
    py: Python<'_>,
    path: std::path::PathBuf,
    image: &Bound<'_, PyAny>,
    params: Option<&str>,
) -> PyResult<()> {
    let img = crate::convert::image_in(image, "image")?;
    let opts = asperity_engine::io::WriteOptions {
        params: crate::io::params_value(params)?,
        ..Default::default()
    };
    crate::job::run(py, &crate::job::RunOptions::quiet(None), move |_, _| {
        Ok(asperity_engine::io::write_png_with(&path, &img, &opts)?)
    })
}
