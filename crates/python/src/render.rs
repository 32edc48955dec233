//! `asperity.render`: a picture of a surface as an (H, W, 4) uint8 array
//! (`asperity_engine::render`, the gobron-chiba light model).

use asperity_engine::render::picture;
use asperity_render::{ColorMap, Projection, RenderOptions, Shader, View};
use pyo3::prelude::*;

use crate::choice;
use crate::convert::{image_out, surface_in};
use crate::job::{RunOptions, budget, run};

/// Renders `surface` with the CLI's `render` defaults for what is not given.
#[pyfunction]
#[pyo3(signature = (surface, width, height, view, shader, colormap, z_scale, shadows, ao, patina, scalar, threads))]
#[allow(clippy::too_many_arguments)]
pub fn render<'py>(
    py: Python<'py>,
    surface: &Bound<'py, PyAny>,
    width: u32,
    height: u32,
    view: &str,
    shader: Option<String>,
    colormap: &str,
    z_scale: f64,
    shadows: bool,
    ao: f32,
    patina: bool,
    scalar: Option<String>,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyAny>> {
    let s = surface_in(surface)?;
    let view = match choice(view, &["iso", "top", "front", "side"], "view")? {
        "top" => View::Top,
        "front" => View::Front,
        "side" => View::Side,
        _ => View::Iso,
    };
    let shader = match shader {
        Some(name) => Shader::from_name(&name).ok_or_else(|| {
            crate::value_error(format!(
                "unknown shader {name:?} (phong, flat, normals, height, curvature, vertex-color, texture)"
            ))
        })?,
        None if patina => Shader::VertexColor,
        None => asperity_engine::render::default_shader(&s),
    };
    let colormap = ColorMap::from_name(colormap).ok_or_else(|| {
        crate::value_error(format!(
            "unknown colour map {colormap:?} (viridis, magma, coolwarm, gray, labels)"
        ))
    })?;
    let opts = RenderOptions {
        width,
        height,
        view,
        projection: Projection::Perspective { fov_deg: 30.0 },
        shader,
        two_layer: patina.then(asperity_engine::surfca::patina_shading),
        shadows,
        ambient_occlusion: ao.clamp(0.0, 1.0),
        colormap,
        scalar,
        z_scale,
        budget: budget(),
        ..RenderOptions::default()
    };
    let img = run(py, &RunOptions::quiet(threads), move |_, time| {
        let pixels =
            f64::from(opts.width) * f64::from(opts.height) * f64::from(opts.supersample).powi(2);
        asperity_engine::estimate::check(
            time,
            &asperity_engine::estimate::render_frames(pixels, 1.0),
        )?;
        picture(&s, &opts)
    })?;
    image_out(py, &img)
}

/// An (H, W, 4) uint8 array as PNG bytes (for Jupyter's `_repr_png_`).
#[pyfunction]
pub fn encode_png<'py>(
    py: Python<'py>,
    image: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, pyo3::types::PyBytes>> {
    let img = crate::convert::image_in(image, "image")?;
    let bytes = asperity_io::png_io::encode_rgba(&img).map_err(crate::value_error)?;
    Ok(pyo3::types::PyBytes::new(py, &bytes))
}
