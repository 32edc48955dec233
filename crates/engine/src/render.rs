//! Pictures of any surface: its bounds, views that orbit it, and the image of
//! whatever a file holds with the renderer of `asperity-render`.

use asperity_core::{Aabb, RgbaImage};
use asperity_io::Surface;
use asperity_render::{RenderOptions, Shader, View, render_height, render_mesh, render_points};

use crate::error::Result;

/// The bounding box of whatever `s` holds (a height field's includes its height
/// range); `None` when it is empty.
pub fn bounds(s: &Surface) -> Option<Aabb> {
    match s {
        Surface::Mesh(m) => m.bounds(),
        Surface::Points(p) => p.bounds(),
        Surface::Height(h) => {
            let (lo, hi) = h.min_max();
            let o = h.origin();
            let e = h.extent();
            Some(Aabb {
                min: [o[0], o[1], lo],
                max: [o[0] + e[0], o[1] + e[1], hi],
            })
        }
    }
}

/// Frame `k` of `frames` orbiting `bounds` around the vertical axis through
/// its centre, at the iso view's elevation (35.26°), starting from the iso
/// azimuth.
pub fn turntable(bounds: &Aabb, k: u32, frames: u32) -> View {
    let c = bounds.center();
    let r = bounds.diagonal() * 1.9;
    let ang = std::f64::consts::TAU * k as f64 / frames.max(1) as f64 - std::f64::consts::FRAC_PI_4;
    let el = 35.26f64.to_radians();
    View::Explicit {
        eye: [
            c[0] + r * el.cos() * ang.cos(),
            c[1] + r * el.cos() * ang.sin(),
            c[2] + r * el.sin(),
        ],
        target: c,
    }
}

/// A 3-D picture of whatever `s` holds.
///
/// # Errors
/// The renderer's (empty input, image size, a shader without its data).
pub fn picture(s: &Surface, opts: &RenderOptions) -> Result<RgbaImage> {
    Ok(match s {
        Surface::Mesh(m) => render_mesh(m, opts)?,
        Surface::Points(p) => render_points(p, opts)?,
        Surface::Height(h) => render_height(h, opts)?,
    })
}

/// The shader a surface is drawn with when none is asked for: heights by a
/// colour map, coloured points by their colours, anything else Phong.
pub fn default_shader(s: &Surface) -> Shader {
    match s {
        Surface::Height(_) => Shader::Height,
        Surface::Points(p) if p.colors().is_some() => Shader::VertexColor,
        _ => Shader::Phong,
    }
}
