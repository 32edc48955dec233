//! Headless CPU rendering of asperity surfaces: 3-D views of meshes, point sets
//! and height fields, map views of height fields, and colour maps.
//!
//! | Module | What | Source |
//! | --- | --- | --- |
//! | [`camera`] | automatic framing: iso, top, front, side, explicit; perspective/orthographic | — |
//! | [`raster`] | parallel z-buffered rasterisation into a visibility buffer | — |
//! | [`light`] | the light model, shadow map | [gobron-chiba] §"Simple Light Model" |
//! | [`ao`] | screen-space ambient obscurance | — |
//! | [`render`] | the 3-D pipeline: [`render_mesh`], [`render_points`], [`render_height`] | — |
//! | [`hillshade`] | shaded relief and colour-mapped height with legend | GDAL `hillshade` formula |
//! | [`plot`] | SVG plots (scaling curves with fits, histograms) through plotters | — |
//! | [`cells`] | cell grids (CA states) as pictures, pictures in strips | peridier Fig. 3 |
//! | [`colormap`] | viridis, magma, coolwarm, gray, labels | matplotlib |
//! | [`font`] | a 5×7 bitmap font for legend numbers | — |
//!
//! Everything runs on the CPU with rayon (no GPU, no display), and the same
//! input and options give the same pixels at any thread count.
//!
//! [gobron-chiba]: https://infoscience.epfl.ch/record/162175 "Gobron, Chiba: 3D Surface Cellular Automata and Their Applications. J. Visualization and Computer Animation 10(3):143-158, 1999"

pub mod ao;
pub mod camera;
pub mod cells;
pub mod colormap;
pub mod font;
pub mod hillshade;
pub mod light;
pub mod plot;
pub mod raster;
pub mod render;

pub use camera::{Camera, Projection, View};
pub use colormap::ColorMap;
pub use light::LightModel;
pub use render::{Polyline, RenderOptions, Shader, render_height, render_mesh, render_points};

use asperity_core::CoreError;

/// Why a render was refused.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RenderError {
    /// Nothing to draw.
    #[error("cannot render an empty {0}")]
    Empty(&'static str),
    /// Image size out of range.
    #[error("image size {width}×{height} is invalid: each side must be 1..=16384 pixels")]
    BadSize {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
    },
    /// The shader needs data the input does not have.
    #[error("this shader needs {0}, which the input does not have")]
    MissingData(String),
    /// An option is out of range.
    #[error("{0}")]
    BadOption(String),
    /// Invalid geometry (NaN coordinates…) or memory limit.
    #[error(transparent)]
    Core(#[from] CoreError),
}
