//! The 3-D view: camera → visibility buffer → shading → obscurance → overlays.
//!
//! # Pipeline
//! 1. Positions are centred on the bounding box (so `f32` keeps precision far from
//!    the origin) and projected at `supersample²` samples per pixel.
//! 2. [`crate::raster`] resolves visibility per sample.
//! 3. Shading runs per output pixel: its samples are grouped by triangle and each
//!    visible triangle is shaded once at the centroid of its samples, weighted by
//!    their count (the multisample idea: edges are anti-aliased at the cost of one
//!    shade per triangle and pixel). Lit shaders use the gobron-chiba model of
//!    [`crate::light`] with a shadow map of the key light.
//! 4. [`crate::ao`] darkens crevices from the per-pixel depth.
//! 5. Wireframe and polylines are drawn with a depth test and anti-aliasing.

use asperity_core::{Aabb, HeightField, MemoryBudget, PointSet, RgbaImage, TriMesh};
use glam::{Mat4, Vec2, Vec3};
use rayon::prelude::*;

use crate::camera::{Camera, Projection, View};
use crate::colormap::ColorMap;
use crate::light::{LightModel, ShadowMap, intensity, project};
use crate::raster::{EMPTY, ScreenVerts, barycentric, rasterize};
use crate::{RenderError, ao};

mod shade;

use shade::*;

/// How surfaces are coloured.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Shader {
    /// Smooth normals, material colour, light model.
    #[default]
    Phong,
    /// Per-facet normals (peridier's facets, gobron-chiba cells).
    Flat,
    /// World normal as RGB, unlit.
    Normals,
    /// Height (z or the scalar named by `scalar`) through the colour map, lit.
    Height,
    /// Mean curvature (or the named scalar) through a diverging colour map, lit.
    Curvature,
    /// The mesh's per-vertex colours, lit.
    VertexColor,
    /// The mesh's texture sampled with its UVs, lit.
    Texture,
}

impl Shader {
    /// Parses the CLI names.
    pub fn from_name(s: &str) -> Option<Self> {
        Some(match s {
            "phong" => Shader::Phong,
            "flat" => Shader::Flat,
            "normals" => Shader::Normals,
            "height" => Shader::Height,
            "curvature" => Shader::Curvature,
            "vertex-color" | "vertex-colour" => Shader::VertexColor,
            "texture" => Shader::Texture,
            _ => return None,
        })
    }
}

/// A line drawn over the surface (control cage, curve on the surface).
#[derive(Clone, Debug, PartialEq)]
pub struct Polyline {
    /// Vertices in world space.
    pub points: Vec<[f64; 3]>,
    /// Colour.
    pub color: [u8; 4],
    /// Join the last point back to the first.
    pub closed: bool,
}

/// Everything that controls a 3-D render.
#[derive(Clone, Debug)]
pub struct RenderOptions {
    /// Output width in pixels.
    pub width: u32,
    /// Output height in pixels.
    pub height: u32,
    /// Camera placement.
    pub view: View,
    /// Perspective or orthographic.
    pub projection: Projection,
    /// Colouring.
    pub shader: Shader,
    /// Samples per pixel along each axis (2 → 4× supersampling).
    pub supersample: u32,
    /// Light model coefficients and key-light direction.
    pub light: LightModel,
    /// Place the key light over the viewer's left shoulder instead of using
    /// `light.direction` (so every view is front-lit). Default: true.
    pub light_follows_camera: bool,
    /// Material colour C_m for [`Shader::Phong`] and [`Shader::Flat`].
    pub material: [u8; 3],
    /// Shadows from the key light.
    pub shadows: bool,
    /// Ambient-obscurance strength in [0, 1] (0 = off).
    pub ambient_occlusion: f32,
    /// Background: top and bottom colours of a vertical gradient.
    pub background: [[u8; 3]; 2],
    /// Colour map for [`Shader::Height`] (curvature always uses a diverging map).
    pub colormap: ColorMap,
    /// Draw triangle edges in this colour.
    pub wireframe: Option<[u8; 4]>,
    /// Lines drawn over the surface.
    pub polylines: Vec<Polyline>,
    /// Splat radius for point sets (world units; default from the point density).
    pub point_radius: Option<f64>,
    /// Scalar used by the height and curvature shaders (default: z / computed curvature).
    pub scalar: Option<String>,
    /// Vertical exaggeration applied to height fields (1 = true scale).
    pub z_scale: f64,
    /// Memory limit for the frame buffers.
    pub budget: MemoryBudget,
    /// Two layers lit separately, then mixed through their thicknesses
    /// (gobron-chiba "light through two layers"), where the mesh has the two
    /// thickness scalars; elsewhere the shader's colour.
    pub two_layer: Option<crate::light::TwoLayerShading>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            width: 800,
            height: 600,
            view: View::Iso,
            projection: Projection::Perspective { fov_deg: 30.0 },
            shader: Shader::Phong,
            supersample: 2,
            light: LightModel::default(),
            light_follows_camera: true,
            material: [196, 180, 160],
            shadows: true,
            ambient_occlusion: 0.6,
            background: [[250, 250, 252], [205, 210, 222]],
            colormap: ColorMap::Viridis,
            wireframe: None,
            polylines: Vec::new(),
            point_radius: None,
            scalar: None,
            z_scale: 1.0,
            budget: MemoryBudget::unlimited(),
            two_layer: None,
        }
    }
}

/// The top and bottom layer thicknesses `sh` names, per vertex.
fn layer_thicknesses(
    m: &TriMesh,
    sh: &crate::light::TwoLayerShading,
) -> Result<(Vec<f32>, Vec<f32>), RenderError> {
    let thickness = |name: &str| {
        m.scalar(name)
            .map(|v| v.iter().map(|&x| x as f32).collect::<Vec<f32>>())
            .ok_or_else(|| {
                RenderError::MissingData(format!("scalar '{name}' (a layer's thickness)"))
            })
    };
    Ok((thickness(&sh.top_scalar)?, thickness(&sh.bottom_scalar)?))
}

/// Per-vertex data the shading pass interpolates.
struct Prepared {
    positions: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    normals: Vec<Vec3>,
    face_normals: Option<Vec<Vec3>>,
    albedo: Option<Vec<Vec3>>,
    scalar: Option<(Vec<f32>, f32, f32, ColorMap)>,
    uvs: Option<Vec<Vec2>>,
    texture: Option<RgbaImage>,
    /// Top and bottom layer thicknesses (with [`RenderOptions::two_layer`]).
    layers: Option<(Vec<f32>, Vec<f32>)>,
}

fn v3(p: [f64; 3]) -> Vec3 {
    Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32)
}

fn check_size(o: &RenderOptions) -> Result<(), RenderError> {
    if o.width == 0 || o.height == 0 || o.width > 16384 || o.height > 16384 {
        return Err(RenderError::BadSize {
            width: o.width,
            height: o.height,
        });
    }
    if !(1..=8).contains(&o.supersample) {
        return Err(RenderError::BadOption(format!(
            "supersample must be 1..=8, got {}",
            o.supersample
        )));
    }
    if let Projection::Perspective { fov_deg } = o.projection
        && !(fov_deg > 0.0 && fov_deg < 180.0)
    {
        return Err(RenderError::BadOption(format!(
            "the field of view must be between 0 and 180 degrees, got {fov_deg}"
        )));
    }
    if let View::Explicit { eye, target } = o.view {
        if !eye.iter().chain(&target).all(|v| v.is_finite()) {
            return Err(RenderError::BadOption(format!(
                "eye {eye:?} and target {target:?} must be finite"
            )));
        }
        if eye == target {
            return Err(RenderError::BadOption(format!(
                "the eye and the target are the same point {eye:?}: there is no viewing direction"
            )));
        }
    }
    let samples = o.width as u128 * o.height as u128 * (o.supersample as u128).pow(2);
    // depth f32 + triangle id u32 per sample, plus the shadow map and pixel buffers.
    o.budget.check_elements(
        samples * 8 + 4096 * 4096 * 8 + o.width as u128 * o.height as u128 * 24,
        1,
        "the frame buffers",
    )?;
    Ok(())
}

/// Discrete mean curvature per vertex: half the norm of the cotangent Laplacian
/// of the positions over the barycentric vertex area, positive where the
/// surface is convex toward its normal (Meyer et al. 2003, with barycentric
/// instead of mixed areas). The analysis crate will own curvature; the renderer
/// needs one for its curvature shader now.
pub fn mean_curvature(m: &TriMesh) -> Vec<f64> {
    let p = m.positions();
    let n = p.len();
    let mut lap = vec![[0.0f64; 3]; n];
    let mut area = vec![0.0f64; n];
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let cross_len = |a: [f64; 3], b: [f64; 3]| {
        let c = [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ];
        dot(c, c).sqrt()
    };
    for t in m.triangles() {
        let [i, j, k] = t.map(|v| v as usize);
        let tri_area = 0.5 * cross_len(sub(p[j], p[i]), sub(p[k], p[i]));
        for (a, b, c) in [(i, j, k), (j, k, i), (k, i, j)] {
            // Cotangent of the angle at a, weighting edge (b, c).
            let (u, v) = (sub(p[b], p[a]), sub(p[c], p[a]));
            let cl = cross_len(u, v);
            if cl <= 1e-300 {
                continue;
            }
            let cot = dot(u, v) / cl;
            let e = sub(p[c], p[b]);
            for d in 0..3 {
                lap[b][d] += 0.5 * cot * e[d];
                lap[c][d] -= 0.5 * cot * e[d];
            }
            area[a] += tri_area / 3.0;
        }
    }
    let normals = m.vertex_normals();
    (0..n)
        .map(|v| {
            if area[v] <= 0.0 {
                return 0.0;
            }
            let hn = lap[v].map(|c| c / area[v]);
            let h = 0.5 * dot(hn, hn).sqrt();
            // Δx = −2H·n: positive H where the surface bends away from its normal
            // (a sphere with outward normals has H = 1/r).
            if dot(hn, normals[v]) > 0.0 { -h } else { h }
        })
        .collect()
}

fn robust_symmetric_range(v: &[f64]) -> f64 {
    let mut a: Vec<f64> = v
        .iter()
        .map(|x| x.abs())
        .filter(|x| x.is_finite())
        .collect();
    if a.is_empty() {
        return 1.0;
    }
    let k = ((a.len() as f64 * 0.98) as usize).min(a.len() - 1);
    let (_, q, _) = a.select_nth_unstable_by(k, |x, y| x.total_cmp(y));
    if *q > 0.0 { *q } else { 1.0 }
}

fn prepare(m: &TriMesh, o: &RenderOptions, center: [f64; 3]) -> Result<Prepared, RenderError> {
    let positions: Vec<Vec3> = m
        .positions()
        .iter()
        .map(|p| v3([p[0] - center[0], p[1] - center[1], p[2] - center[2]]))
        .collect();
    let normals: Vec<Vec3> = m
        .normals()
        .map(<[_]>::to_vec)
        .unwrap_or_else(|| m.vertex_normals())
        .into_iter()
        .map(v3)
        .collect();
    let face_normals =
        (o.shader == Shader::Flat).then(|| m.face_normals().into_iter().map(v3).collect());
    let mut prep = Prepared {
        positions,
        triangles: m.triangles().to_vec(),
        normals,
        face_normals,
        albedo: None,
        scalar: None,
        uvs: None,
        texture: None,
        layers: None,
    };
    if let Some(sh) = &o.two_layer {
        prep.layers = Some(layer_thicknesses(m, sh)?);
    }
    if let Some(name) = &o.scalar
        && m.scalar(name).is_none()
    {
        let known: Vec<&str> = m.scalars().iter().map(|a| a.name.as_str()).collect();
        return Err(RenderError::BadOption(format!(
            "the mesh has no scalar '{name}' (it has: {})",
            if known.is_empty() {
                "none".to_string()
            } else {
                known.join(", ")
            }
        )));
    }
    let named = |name: &str| {
        m.scalar(name)
            .map(<[f64]>::to_vec)
            .ok_or_else(|| RenderError::MissingData(format!("scalar '{name}'")))
    };
    match o.shader {
        Shader::Phong | Shader::Flat | Shader::Normals => {}
        Shader::VertexColor => {
            let c = m
                .colors()
                .ok_or_else(|| RenderError::MissingData("vertex colours".into()))?;
            prep.albedo = Some(
                c.iter()
                    .map(|c| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32) / 255.0)
                    .collect(),
            );
        }
        Shader::Texture => {
            let (Some(uv), Some(tex)) = (m.uvs(), m.texture()) else {
                return Err(RenderError::MissingData("UVs and a texture image".into()));
            };
            prep.uvs = Some(
                uv.iter()
                    .map(|t| Vec2::new(t[0] as f32, t[1] as f32))
                    .collect(),
            );
            prep.texture = Some(tex.clone());
        }
        Shader::Height => {
            let v = match &o.scalar {
                Some(name) => named(name)?,
                None => m.positions().iter().map(|p| p[2]).collect(),
            };
            let (lo, hi) = v
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                    (a.min(x), b.max(x))
                });
            prep.scalar = Some((
                v.iter().map(|&x| x as f32).collect(),
                lo as f32,
                hi as f32,
                o.colormap,
            ));
        }
        Shader::Curvature => {
            let v = match &o.scalar {
                Some(name) => named(name)?,
                None => mean_curvature(m),
            };
            let r = robust_symmetric_range(&v) as f32;
            prep.scalar = Some((
                v.iter().map(|&x| x as f32).collect(),
                -r,
                r,
                ColorMap::Coolwarm,
            ));
        }
    }
    Ok(prep)
}

/// Renders a triangle mesh.
///
/// # Errors
/// [`RenderError`] for an empty mesh, a bad image size, data the shader needs
/// but the mesh lacks, or frame buffers beyond the memory budget.
pub fn render_mesh(m: &TriMesh, o: &RenderOptions) -> Result<RgbaImage, RenderError> {
    check_size(o)?;
    if m.n_faces() == 0 {
        return Err(RenderError::Empty("mesh (no triangles)"));
    }
    let bounds = m.bounds().ok_or(RenderError::Empty("mesh"))?;
    let prep = prepare(m, o, bounds.center())?;
    let cam = frame(&bounds, Some(&prep.positions), o);
    Ok(render_prepared(&prep, &bounds, &cam, o))
}

/// Renders a height field as a surface (default shader: height colour map).
///
/// # Errors
/// As [`render_mesh`].
pub fn render_height(h: &HeightField, o: &RenderOptions) -> Result<RgbaImage, RenderError> {
    if !(o.z_scale.is_finite() && o.z_scale > 0.0) {
        return Err(RenderError::BadOption(format!(
            "z scale must be positive, got {}",
            o.z_scale
        )));
    }
    let scaled = h.map(|z| z * o.z_scale);
    // The colour map shows true heights whatever the exaggeration.
    let m = scaled
        .to_trimesh(asperity_core::Diagonal::Forward)?
        .with_scalar("height", h.measured_values())?;
    let o = RenderOptions {
        scalar: o.scalar.clone().or_else(|| Some("height".into())),
        ..o.clone()
    };
    render_mesh(&m, &o)
}

/// Renders a point set as lit spherical splats facing the camera.
///
/// # Errors
/// As [`render_mesh`]; [`RenderError::Empty`] for no points.
pub fn render_points(p: &PointSet, o: &RenderOptions) -> Result<RgbaImage, RenderError> {
    check_size(o)?;
    p.validate()?;
    let bounds = p.bounds().ok_or(RenderError::Empty("point set"))?;
    let c = bounds.center();
    let centred: Vec<Vec3> = p
        .positions()
        .iter()
        .map(|q| v3([q[0] - c[0], q[1] - c[1], q[2] - c[2]]))
        .collect();
    let cam = frame(&bounds, Some(&centred), o);
    let radius = o.point_radius.unwrap_or_else(|| {
        // Three quarters of the spacing the points would have on the box's largest
        // face, so neighbouring splats overlap a little.
        let e = bounds.extent();
        let mut s = [e[0], e[1], e[2]];
        s.sort_by(|a, b| b.total_cmp(a));
        0.75 * (s[0] * s[1].max(s[0] * 1e-3) / p.len() as f64).sqrt()
    }) as f32;
    let (right, up) = {
        let inv = cam.view.inverse();
        (
            inv.x_axis.truncate().normalize(),
            inv.y_axis.truncate().normalize(),
        )
    };
    let toward_eye = -cam.forward;
    let mut positions = Vec::with_capacity(4 * p.len());
    let mut normals = Vec::with_capacity(4 * p.len());
    let mut triangles = Vec::with_capacity(2 * p.len());
    let mut albedo = Vec::with_capacity(4 * p.len());
    let base = Vec3::new(
        o.material[0] as f32,
        o.material[1] as f32,
        o.material[2] as f32,
    ) / 255.0;
    for (k, q) in p.positions().iter().enumerate() {
        let q = v3([q[0] - c[0], q[1] - c[1], q[2] - c[2]]);
        let col = p.colors().map_or(base, |cs| {
            Vec3::new(cs[k][0] as f32, cs[k][1] as f32, cs[k][2] as f32) / 255.0
        });
        let i = positions.len() as u32;
        for (sx, sy) in [(-1.0f32, -1.0f32), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            let off = right * sx + up * sy;
            positions.push(q + off * radius);
            normals.push((off * 0.6 + toward_eye).normalize());
            albedo.push(col);
        }
        triangles.push([i, i + 1, i + 2]);
        triangles.push([i, i + 2, i + 3]);
    }
    let prep = Prepared {
        positions,
        triangles,
        normals,
        face_normals: None,
        albedo: Some(albedo),
        scalar: None,
        uvs: None,
        texture: None,
        layers: None,
    };
    let opts = RenderOptions {
        shader: if o.shader == Shader::Normals {
            Shader::Normals
        } else {
            Shader::VertexColor
        },
        ..o.clone()
    };
    Ok(render_prepared(&prep, &bounds, &cam, &opts))
}

/// Frames the centred `points` (or the centred box) as `o` asks.
fn frame(bounds: &Aabb, points: Option<&[Vec3]>, o: &RenderOptions) -> Camera {
    // Frame around the centred box: positions are shifted by the centre first.
    let c = bounds.center();
    let centred = Aabb {
        min: [0, 1, 2].map(|a| bounds.min[a] - c[a]),
        max: [0, 1, 2].map(|a| bounds.max[a] - c[a]),
    };
    let view = match o.view {
        View::Explicit { eye, target } => View::Explicit {
            eye: [0, 1, 2].map(|a| eye[a] - c[a]),
            target: [0, 1, 2].map(|a| target[a] - c[a]),
        },
        v => v,
    };
    Camera::frame_points(
        &centred,
        points,
        view,
        o.projection,
        o.width as f64 / o.height as f64,
    )
}

fn background(o: &RenderOptions, y: usize) -> Vec3 {
    let t = y as f32 / (o.height.max(2) - 1) as f32;
    let [a, b] = o
        .background
        .map(|c| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32) / 255.0);
    a + (b - a) * t
}

/// Per-pixel results of the shading pass.
struct Pixels {
    color: Vec<Vec3>,
    coverage: Vec<f32>,
    view_depth: Vec<f32>,
    ndc_depth: Vec<f32>,
}

fn render_prepared(p: &Prepared, bounds: &Aabb, cam: &Camera, o: &RenderOptions) -> RgbaImage {
    let (w, h, ss) = (o.width as usize, o.height as usize, o.supersample as usize);
    let vp = cam.view_proj();
    let sv = project(&p.positions, &vp, w * ss, h * ss);
    let vis = rasterize(&sv, &p.triangles, w * ss, h * ss);
    let radius = (0.5 * bounds.diagonal()).max(1e-9) as f32;
    let lit = !matches!(o.shader, Shader::Normals);
    let light_dir = if o.light_follows_camera {
        let inv = cam.view.inverse();
        let (right, up) = (inv.x_axis.truncate(), inv.y_axis.truncate());
        (-0.55 * right + 0.75 * up - 0.6 * cam.forward).normalize()
    } else {
        v3(o.light.direction).normalize_or(Vec3::Z)
    };
    let shadow = (o.shadows && lit).then(|| {
        let size = (2 * w.max(h)).clamp(1024, 4096);
        ShadowMap::build(
            &p.positions,
            &p.triangles,
            light_dir,
            Vec3::ZERO,
            radius,
            size,
        )
    });
    let px = shade(
        &ShadeCtx {
            p,
            sv: &sv,
            cam,
            o,
            shadow: shadow.as_ref(),
            light: light_dir,
        },
        &vis.tri,
    );
    let mut color = px.color;
    if o.ambient_occlusion > 0.0 {
        let depth: Vec<f32> = px
            .view_depth
            .iter()
            .zip(&px.coverage)
            .map(|(&d, &c)| if c > 0.0 { d } else { f32::NAN })
            .collect();
        let scale = pixels_per_world(cam, h);
        let occ = ao::obscurance(&depth, w, h, 0.04 * radius, &scale);
        let bg: Vec<Vec3> = (0..h).map(|y| background(o, y)).collect();
        for (i, c) in color.iter_mut().enumerate() {
            let cov = px.coverage[i];
            if cov > 0.0 {
                let b = bg[i / w];
                // Darken only the surface's share of the pixel.
                let surf = (*c - b * (1.0 - cov)) / cov;
                *c = surf * (1.0 - o.ambient_occlusion * occ[i]) * cov + b * (1.0 - cov);
            }
        }
    }
    let mut img = RgbaImage::filled(o.width, o.height, [0, 0, 0, 255]);
    for (i, c) in color.iter().enumerate() {
        let q = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
        img.pixels_mut()[4 * i..4 * i + 4].copy_from_slice(&[q(c.x), q(c.y), q(c.z), 255]);
    }
    let overlay = Overlay {
        vp,
        w,
        h,
        depth: &px.ndc_depth,
        center: bounds.center(),
    };
    if let Some(col) = o.wireframe {
        for t in &p.triangles {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                overlay.segment(
                    &mut img,
                    p.positions[a as usize],
                    p.positions[b as usize],
                    col,
                );
            }
        }
    }
    for line in &o.polylines {
        let pts: Vec<Vec3> = line
            .points
            .iter()
            .map(|q| {
                v3([
                    q[0] - overlay.center[0],
                    q[1] - overlay.center[1],
                    q[2] - overlay.center[2],
                ])
            })
            .collect();
        for s in pts.windows(2) {
            overlay.segment(&mut img, s[0], s[1], line.color);
        }
        if line.closed && pts.len() > 2 {
            overlay.segment(&mut img, pts[pts.len() - 1], pts[0], line.color);
        }
    }
    img
}

fn pixels_per_world(cam: &Camera, h: usize) -> impl Fn(f32) -> f32 + Sync + use<> {
    let (p11, ortho) = (cam.proj.y_axis.y, cam.orthographic);
    move |d: f32| {
        if ortho {
            0.5 * h as f32 * p11
        } else {
            0.5 * h as f32 * p11 / d.max(1e-6)
        }
    }
}
