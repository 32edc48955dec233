//! Pictures of any surface: its bounds, views that orbit it, and the image of
//! whatever a file holds with the renderer of `asperity-render`.

use asperity_core::{Aabb, MemoryBudget, RgbaImage, TimeBudget};
use asperity_io::Surface;
use asperity_render::{
    ColorMap, LightModel, Projection, RenderOptions, Shader, View, hillshade, render_height,
    render_mesh, render_points,
};
use clap::Args;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::error::{EngineError, Result};
use crate::params::{JobParams, Numbers, Size2, choice};

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

choice! {
    /// Where the camera looks from.
    pub enum ViewName {
        /// From the (+1, −1, +1) diagonal.
        Iso = "iso",
        /// Straight down.
        Top = "top",
        /// From −y.
        Front = "front",
        /// From +x.
        Side = "side",
        /// Height fields only: a 2-D map (colour + relief) with a legend.
        Map = "map",
        /// Height fields only: grayscale shaded relief (hillshade).
        Hillshade = "hillshade",
    }
}

choice! {
    /// How surfaces are coloured.
    pub enum ShaderName {
        /// Smooth normals, material colour, the gobron-chiba light model.
        Phong = "phong",
        /// Per-facet normals.
        Flat = "flat",
        /// World normals as RGB.
        Normals = "normals",
        /// Height through the colour map (the default for height fields).
        Height = "height",
        /// Mean curvature (or the scalar) through a diverging map.
        Curvature = "curvature",
        /// The mesh's vertex colours.
        VertexColor = "vertex-color",
        /// The mesh's texture.
        Texture = "texture",
    }
}

choice! {
    /// A colour map for heights, curvature and labels.
    pub enum ColorMapName {
        /// Perceptually uniform blue–green–yellow.
        Viridis = "viridis",
        /// Perceptually uniform black–red–yellow.
        Magma = "magma",
        /// Diverging blue–white–red (signed quantities).
        Coolwarm = "coolwarm",
        /// Gray levels.
        Gray = "gray",
        /// Distinct colours for integer labels.
        Labels = "labels",
    }
}

/// The background: `gradient` (light grey to blue-grey), `white`, `black` or
/// a colour `#RRGGBB`.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(try_from = "String", into = "String")]
#[schemars(with = "String")]
pub struct Background(String);

impl Background {
    /// The gradient's two colours (top, bottom).
    pub fn colors(&self) -> [[u8; 3]; 2] {
        match self.0.as_str() {
            "white" => [[255; 3]; 2],
            "black" => [[0; 3]; 2],
            hex if hex.starts_with('#') => {
                let c = |k: usize| u8::from_str_radix(&hex[k..k + 2], 16).unwrap_or(0);
                let rgb = [c(1), c(3), c(5)];
                [rgb, rgb]
            }
            _ => RenderOptions::default().background,
        }
    }
}

impl TryFrom<String> for Background {
    type Error = String;
    fn try_from(s: String) -> std::result::Result<Self, String> {
        let hex =
            s.len() == 7 && s.starts_with('#') && s[1..].chars().all(|c| c.is_ascii_hexdigit());
        if hex || ["gradient", "white", "black"].contains(&s.as_str()) {
            Ok(Self(s))
        } else {
            Err(format!("{s:?}: use gradient, white, black or #RRGGBB"))
        }
    }
}

impl From<Background> for String {
    fn from(b: Background) -> Self {
        b.0
    }
}

impl std::str::FromStr for Background {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        Self::try_from(s.to_owned())
    }
}

impl std::fmt::Display for Background {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// `render`: a picture of a mesh, point set or height field (headless, on
/// the CPU, with the gobron-chiba light model), or a map of a height field.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct RenderParams {
    /// Image size, WIDTHxHEIGHT pixels.
    #[arg(long, default_value_t = Self::default().size, value_name = "WxH")]
    pub size: Size2,
    /// Camera placement.
    #[arg(long, value_enum, default_value_t = Self::default().view)]
    pub view: ViewName,
    /// Explicit camera position X,Y,Z (overrides the view).
    #[arg(long, value_name = "X,Y,Z", allow_negative_numbers = true)]
    pub eye: Option<Numbers<3>>,
    /// Point looked at from the eye (default: the centre).
    #[arg(long, value_name = "X,Y,Z", allow_negative_numbers = true)]
    pub target: Option<Numbers<3>>,
    /// Vertical field of view in degrees.
    #[schemars(extend("exclusiveMinimum" = 0.0, "exclusiveMaximum" = 180.0))]
    #[arg(long, default_value_t = Self::default().fov)]
    pub fov: f64,
    /// Orthographic instead of perspective projection.
    #[arg(long)]
    pub ortho: bool,
    /// Colouring (default: phong; height for height fields; vertex-color for coloured points
    /// and patina).
    #[arg(long, value_enum)]
    pub shader: Option<ShaderName>,
    /// Key light as AZIMUTH,ALTITUDE in degrees, azimuth clockwise from +y (default: over the
    /// viewer's left shoulder; 315,45 for hillshade).
    #[arg(long, value_name = "AZ,ALT", allow_negative_numbers = true)]
    pub light: Option<Numbers<2>>,
    /// Draw triangle edges.
    #[arg(long)]
    pub wireframe: bool,
    /// Shadows from the key light (the CLI's --no-shadows turns them off).
    #[arg(long = "no-shadows", action = clap::ArgAction::SetFalse)]
    pub shadows: bool,
    /// Ambient-occlusion strength, 0 (off) to 1.
    #[schemars(range(min = 0.0, max = 1.0))]
    #[arg(long, default_value_t = Self::default().ao)]
    pub ao: f32,
    /// Supersampling per axis (2 = 4 samples per pixel).
    #[schemars(range(min = 1, max = 8))]
    #[arg(long, default_value_t = Self::default().supersample)]
    pub supersample: u32,
    /// Colour map.
    #[arg(long, value_enum, default_value_t = Self::default().colormap)]
    pub colormap: ColorMapName,
    /// Scalar attribute for the height and curvature shaders.
    #[arg(long)]
    pub scalar: Option<String>,
    /// A corrosion mesh from surface-ca's corrosion: light the patina and the copper each with
    /// its own material, then mix them through the `oxide` and `metal` thicknesses the mesh
    /// carries (gobron-chiba's two-layer model); holes keep their vertex colour.
    #[arg(long)]
    pub patina: bool,
    /// Vertical exaggeration of height fields.
    #[schemars(range(min = -1e6, max = 1e6))]
    #[arg(long, default_value_t = Self::default().z_scale)]
    pub z_scale: f64,
    /// Background: gradient, white, black, or a colour #RRGGBB.
    #[arg(long, default_value_t = Self::default().background)]
    pub background: Background,
}

impl Default for RenderParams {
    fn default() -> Self {
        let o = RenderOptions::default();
        Self {
            size: Size2([1024, 768]),
            view: ViewName::Iso,
            eye: None,
            target: None,
            fov: 30.0,
            ortho: false,
            shader: None,
            light: None,
            wireframe: false,
            shadows: o.shadows,
            ao: o.ambient_occlusion,
            supersample: o.supersample,
            colormap: ColorMapName::Viridis,
            scalar: None,
            patina: false,
            z_scale: o.z_scale,
            background: Background("gradient".into()),
        }
    }
}

impl JobParams for RenderParams {
    const JOB: &'static str = "render";
    const SEEDED: bool = false;

    fn check(&self) -> Result<()> {
        for (name, v) in [
            ("eye", self.eye.map(|v| v.0.to_vec())),
            ("target", self.target.map(|v| v.0.to_vec())),
            ("light", self.light.map(|v| v.0.to_vec())),
        ] {
            if let Some(v) = v
                && !v.iter().all(|x| x.is_finite())
            {
                return Err(EngineError::Invalid(format!(
                    "{} takes finite numbers, got {v:?}",
                    asperity_core::wording::param(name)
                )));
            }
        }
        Ok(())
    }
}

impl RenderParams {
    fn colormap(&self) -> ColorMap {
        match self.colormap {
            ColorMapName::Viridis => ColorMap::Viridis,
            ColorMapName::Magma => ColorMap::Magma,
            ColorMapName::Coolwarm => ColorMap::Coolwarm,
            ColorMapName::Gray => ColorMap::Gray,
            ColorMapName::Labels => ColorMap::Labels,
        }
    }

    fn view_of(&self, surface: &Surface) -> View {
        match (self.eye, self.view) {
            (Some(e), _) => View::Explicit {
                eye: e.0,
                target: self
                    .target
                    .map_or_else(|| bounds(surface).map_or([0.0; 3], |b| b.center()), |t| t.0),
            },
            (None, ViewName::Top) => View::Top,
            (None, ViewName::Front) => View::Front,
            (None, ViewName::Side) => View::Side,
            _ => View::Iso,
        }
    }

    /// The renderer's options for `surface` under `budget`.
    pub fn options(&self, surface: &Surface, budget: &MemoryBudget) -> RenderOptions {
        let shader = match (self.shader, self.patina) {
            (Some(s), _) => Shader::from_name(s.name()).unwrap_or(Shader::Phong),
            (None, true) => Shader::VertexColor,
            (None, false) => default_shader(surface),
        };
        let [width, height] = self.size.0.map(|v| u32::try_from(v).unwrap_or(u32::MAX));
        RenderOptions {
            width,
            height,
            view: self.view_of(surface),
            projection: if self.ortho {
                Projection::Orthographic
            } else {
                Projection::Perspective { fov_deg: self.fov }
            },
            shader,
            two_layer: self.patina.then(crate::surfca::patina_shading),
            supersample: self.supersample,
            light: match self.light {
                Some(l) => LightModel {
                    direction: LightModel::from_azimuth_altitude(l.0[0], l.0[1]),
                    ..LightModel::default()
                },
                None => LightModel::default(),
            },
            light_follows_camera: self.light.is_none(),
            shadows: self.shadows,
            ambient_occlusion: self.ao.clamp(0.0, 1.0),
            colormap: self.colormap(),
            wireframe: self.wireframe.then_some([20, 20, 30, 200]),
            scalar: self.scalar.clone(),
            z_scale: self.z_scale,
            background: self.background.colors(),
            budget: *budget,
            ..RenderOptions::default()
        }
    }

    /// Whether the view is a 2-D map of a height field (`map`, `hillshade`).
    pub fn is_map(&self) -> bool {
        matches!(self.view, ViewName::Map | ViewName::Hillshade)
    }
}

/// Bytes the renderer holds for the scene beside its frame buffers (which
/// it checks itself): a height field's mesh (a vertex per sample, two
/// triangles per cell) or the mesh given, with its normals, shading and the
/// per-triangle screen data — some 80 bytes a vertex and 40 a triangle
/// (measured: a 2048² height field peaks at 909 MiB above the process at
/// rest, 263 of them frame buffers; `crates/benches/scripts/estimate_honesty.py`).
pub fn scene_bytes(surface: &Surface) -> u64 {
    let (vertices, triangles) = match surface {
        Surface::Height(h) => (h.len() as u64, 2 * h.len() as u64),
        Surface::Mesh(m) => (m.n_vertices() as u64, m.n_faces() as u64),
        Surface::Points(p) => (p.len() as u64, 0),
    };
    vertices
        .saturating_mul(80)
        .saturating_add(triangles.saturating_mul(40))
}

/// The picture `render` makes of `surface` (`frames` > 1: frame `k` of a
/// turntable around it): a map or hillshade of a height field, or a 3-D view.
/// The whole run's time is checked against `time` before the first frame.
///
/// # Errors
/// The parameters'; a map view of what is not a height field; an empty
/// input; the renderer's and the budgets'.
pub fn render_job(
    surface: &Surface,
    p: &RenderParams,
    (k, frames): (u32, u32),
    (budget, time): (&MemoryBudget, &TimeBudget),
) -> Result<RgbaImage> {
    crate::params::validate(p)?;
    if p.is_map() {
        let Surface::Height(h) = surface else {
            return Err(EngineError::Invalid(format!(
                "{} and {} need a height field; the input holds {}",
                asperity_core::wording::param_value("view", "map"),
                asperity_core::wording::param_value("view", "hillshade"),
                surface.kind()
            )));
        };
        return Ok(if p.view == ViewName::Map {
            hillshade::height_map(h, p.colormap(), 0.5, true)
        } else {
            let [az, alt] = p.light.map_or([315.0, 45.0], |l| l.0);
            hillshade::hillshade(h, az, alt)
        });
    }
    let mut opts = p.options(surface, budget);
    if k == 0 {
        budget.check(scene_bytes(surface), "the scene to render")?;
        let pixels =
            f64::from(opts.width) * f64::from(opts.height) * f64::from(opts.supersample).powi(2);
        crate::estimate::check(
            time,
            &crate::estimate::render_frames(pixels, f64::from(frames)),
        )?;
    }
    let b = bounds(surface)
        .ok_or_else(|| EngineError::Invalid("nothing to render: the input is empty".into()))?;
    if frames > 1 {
        // Orbit around the vertical axis through the centre at the iso elevation.
        opts.view = turntable(&b, k, frames);
    }
    picture(surface, &opts)
}
