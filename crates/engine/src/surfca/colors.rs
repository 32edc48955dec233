//! How the cells look: distinct colours for Voronoi labels, the patina over
//! copper of corrosion (gobron-chiba's two-layer model: unlit mixes per
//! vertex, and the two lit materials for asperity's renders), Gray–Scott's
//! activator through viridis.

use asperity_core::TriMesh;
use asperity_render::light::{Layer, TwoLayerShading};
use asperity_surfca::corrosion::{Behaviour, CorrosionCell};
use asperity_surfca::reaction_diffusion::Chemicals;
use asperity_surfca::voronoi::UNLABELLED;

use super::Covered;
use crate::error::Result;

/// Distinct colours for labels (golden-ratio hues, fixed saturation and value);
/// unlabelled cells are light grey.
pub fn label_color(label: u32) -> [u8; 4] {
    if label == UNLABELLED {
        return [200, 200, 200, 255];
    }
    asperity_render::colormap::distinct(label)
}

/// Patina's material colour (verdigris).
const PATINA: [f64; 3] = [0.27, 0.62, 0.50];
/// Copper's material colour.
const COPPER: [f64; 3] = [0.74, 0.43, 0.25];
const PATINA_OPACITY: f64 = 0.6;
const COPPER_OPACITY: f64 = 0.95;

/// Colour of a corrosion cell: the unlit material colours of patina over copper
/// mixed by the two-layer model (gobron-chiba "light through two layers");
/// holes are dark. Asperity's own renders light each layer first instead
/// ([`patina_shading`]).
pub fn patina_color(s: &CorrosionCell) -> [u8; 4] {
    let c = match s.behaviour {
        Behaviour::NonExistent => [0.12, 0.09, 0.07],
        _ => asperity_render::light::two_layer(
            PATINA,
            s.oxide as f64,
            PATINA_OPACITY,
            COPPER,
            s.metal.max(0.05) as f64,
            COPPER_OPACITY,
        ),
    };
    let to = |x: f64| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
    [to(c[0]), to(c[1]), to(c[2]), 255]
}

/// The patina and copper materials of [`patina_color`], lit separately as the
/// paper's two-layer model asks (gobron-chiba "light through two layers": each
/// layer's material colour goes through the light model, then the lit colours
/// mix through the layers): a matte patina over a shiny metal, so copper under
/// thin patina keeps its highlight. Reads the scalars of [`corrosion_mesh`].
pub fn patina_shading() -> TwoLayerShading {
    TwoLayerShading {
        top: Layer {
            color: PATINA,
            opacity: PATINA_OPACITY,
            ambient: 0.25,
            diffuse: 0.75,
            specular: 0.05,
            shininess: 8.0,
        },
        bottom: Layer {
            color: COPPER,
            opacity: COPPER_OPACITY,
            ambient: 0.25,
            diffuse: 0.75,
            specular: 0.9,
            shininess: 48.0,
        },
        top_scalar: "oxide".into(),
        bottom_scalar: "metal".into(),
    }
}

/// The corrosion cells as a mesh: [`patina_color`] per vertex (the unlit mix,
/// for viewers that light a colour once) and the layer thicknesses as the
/// scalars `oxide` and `metal` (0 and 0 in holes), for [`patina_shading`].
///
/// # Errors
/// The cell mesh's.
pub fn corrosion_mesh(cov: &Covered, states: &[CorrosionCell]) -> Result<TriMesh> {
    let m = cov.cell_mesh(|c| patina_color(&states[c]))?;
    let per_vertex = |f: &dyn Fn(&CorrosionCell) -> f64| -> Vec<f64> {
        (0..cov.cells.len())
            .flat_map(|c| std::iter::repeat_n(f(&states[c]), cov.cells.polygon(c).len()))
            .collect()
    };
    let hole = |s: &CorrosionCell| s.behaviour == Behaviour::NonExistent;
    let oxide = per_vertex(&|s| if hole(s) { 0.0 } else { f64::from(s.oxide) });
    let metal = per_vertex(&|s| {
        if hole(s) {
            0.0
        } else {
            f64::from(s.metal.max(0.05))
        }
    });
    Ok(m.with_scalar("oxide", oxide)?.with_scalar("metal", metal)?)
}

/// Colour of a Gray–Scott cell: v through viridis.
pub fn rd_color(s: &Chemicals) -> [u8; 4] {
    let c = asperity_render::ColorMap::Viridis.map((s.v as f64 / 0.45).clamp(0.0, 1.0));
    [c[0], c[1], c[2], 255]
}
