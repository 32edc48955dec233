//! `asperity.load`, `asperity.save`, `asperity.info`: every format asperity
//! reads and writes (`asperity_engine::io`, through `asperity_engine::files`).

use std::path::PathBuf;

use asperity_engine::io::{Surface, WriteOptions};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{json, surface_in, surface_out};
use crate::job::{RunOptions, budget, run};

fn up_axis(up: Option<&str>) -> PyResult<Option<asperity_engine::io::UpAxis>> {
    up.map(|u| u.parse().map_err(pyo3::exceptions::PyValueError::new_err))
        .transpose()
}

/// Reads any file under the memory budget; a dict with its `kind`. `up`
/// ("y" or "z") overrides the file's up axis, as the CLI's `--up`.
#[pyfunction]
#[pyo3(signature = (path, up = None, channel = None))]
pub fn load<'py>(
    py: Python<'py>,
    path: PathBuf,
    up: Option<&str>,
    channel: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    let up = up_axis(up)?;
    let channel = channel.map(asperity_engine::io::Channel::parse);
    let s = run(py, &RunOptions::quiet(None), move |_, _| {
        let s = asperity_engine::files::load_channel(&path, &budget(), channel.as_ref())?;
        let made_with = asperity_engine::io::read_params(&path)?;
        let instrument = asperity_engine::io::instrument_metadata(&path)?;
        let channels = asperity_engine::io::channels(&path)?;
        Ok((
            match up {
                Some(up) => asperity_engine::io::reorient(s, &path, up)?,
                None => s,
            },
            made_with,
            instrument,
            channels,
        ))
    })?;
    let (s, made_with, instrument, channels) = s;
    let d = surface_out(py, s)?;
    if let Some(p) = made_with {
        d.set_item("params", json(&p)?)?;
    }
    if let Some(pairs) = instrument {
        d.set_item("instrument", pairs)?;
    }
    if let Some(list) = channels {
        let list: Vec<Bound<'_, PyDict>> = list
            .into_iter()
            .map(|c| {
                let e = PyDict::new(py);
                e.set_item("index", c.index)?;
                e.set_item("name", c.name)?;
                e.set_item("height", c.height)?;
                Ok(e)
            })
            .collect::<PyResult<_>>()?;
        d.set_item("channels", list)?;
    }
    Ok(d)
}

/// A record's JSON text (from Python's `json.dumps`) as a value.
pub(crate) fn params_value(params: Option<&str>) -> PyResult<Option<serde_json::Value>> {
    params
        .map(|t| {
            serde_json::from_str(t).map_err(|e| {
                pyo3::exceptions::PyValueError::new_err(format!("params is not JSON: {e}"))
            })
        })
        .transpose()
}

/// Writes a mesh, height field or point set by the path's extension,
/// atomically (a failure leaves no partial file); `params` (a record's JSON
/// text) go where the format keeps metadata.
#[pyfunction]
#[pyo3(signature = (path, surface, title = None, up = None, params = None))]
pub fn save(
    py: Python<'_>,
    path: PathBuf,
    surface: &Bound<'_, PyAny>,
    title: Option<String>,
    up: Option<&str>,
    params: Option<&str>,
) -> PyResult<()> {
    let s = surface_in(surface)?;
    let mut opts = WriteOptions {
        up: up_axis(up)?,
        params: params_value(params)?,
        ..WriteOptions::default()
    };
    if let Some(t) = title {
        opts.title = t;
    }
    run(py, &RunOptions::quiet(None), move |_, _| {
        match &s {
            Surface::Points(p) if p.is_empty() => {
                return Err(asperity_engine::error::invalid("no point to write"));
            }
            _ => {}
        }
        Ok(asperity_engine::io::write(&path, &s, &opts)?)
    })
}

/// The CLI's `info` facts of a surface (JSON text).
#[pyfunction]
pub fn info(surface: &Bound<'_, PyAny>) -> PyResult<String> {
    json(&asperity_engine::describe::describe(&surface_in(surface)?))
}
