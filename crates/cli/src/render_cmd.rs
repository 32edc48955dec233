//! `asperity render`: any readable file to PNG.

use std::path::{Path, PathBuf};

use anyhow::{Context as _, bail};
use asperity_io::Surface;
use asperity_render::{ColorMap, LightModel, Projection, RenderOptions, Shader, View, hillshade};

use crate::cli::{Context, RenderArgs, ShaderArg, ViewArg};
use crate::report::Report;

fn shader(s: ShaderArg) -> Shader {
    match s {
        ShaderArg::Phong => Shader::Phong,
        ShaderArg::Flat => Shader::Flat,
        ShaderArg::Normals => Shader::Normals,
        ShaderArg::Height => Shader::Height,
        ShaderArg::Curvature => Shader::Curvature,
        ShaderArg::VertexColor => Shader::VertexColor,
        ShaderArg::Texture => Shader::Texture,
    }
}

/// `view.png` → `view_007.png`.
fn frame_path(out: &Path, k: u32) -> PathBuf {
    let stem = out
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "frame".into());
    let ext = out
        .extension()
        .map(|e| e.to_string_lossy().into_owned())
        .unwrap_or_else(|| "png".into());
    out.with_file_name(format!("{stem}_{k:03}.{ext}"))
}

pub fn run(ctx: &Context, a: &RenderArgs) -> anyhow::Result<()> {
    let out = ctx
        .output
        .clone()
        .context("no output image: give -o view.png")?;
    if out
        .extension()
        .is_none_or(|e| !e.eq_ignore_ascii_case("png"))
    {
        bail!(
            "{}: render writes PNG images; use a .png name",
            out.display()
        );
    }
    for (name, v, n) in [
        ("--eye", &a.eye, 3),
        ("--target", &a.target, 3),
        ("--light", &a.light, 2),
    ] {
        if let Some(v) = v {
            anyhow::ensure!(
                v.len() == n && v.iter().all(|x| x.is_finite()),
                "{name} takes {n} comma-separated numbers, got {v:?}"
            );
        }
    }
    let surface = crate::convert::load(ctx, &a.input)?;
    let mut report = Report::new("render", ctx);
    let colormap = ColorMap::from_name(&a.colormap).with_context(|| {
        format!(
            "unknown colour map {:?} (viridis, magma, coolwarm, gray, labels)",
            a.colormap
        )
    })?;
    if let (ViewArg::Map | ViewArg::Hillshade, Surface::Height(h)) = (a.view, &surface) {
        let img = if a.view == ViewArg::Map {
            hillshade::height_map(h, colormap, 0.5, true)
        } else {
            let l = a.light.clone().unwrap_or_else(|| vec![315.0, 45.0]);
            hillshade::hillshade(h, l[0], l[1])
        };
        asperity_io::write_png(&out, &img)?;
        report.output(&out);
        ctx.note(format!("wrote {}", out.display()));
        return report.finish(ctx);
    }
    if matches!(a.view, ViewArg::Map | ViewArg::Hillshade) {
        bail!(
            "--view map and --view hillshade need a height field; {} holds {}",
            a.input.display(),
            surface.kind()
        );
    }
    let default_shader = match &surface {
        Surface::Height(_) => Shader::Height,
        Surface::Points(p) if p.colors().is_some() => Shader::VertexColor,
        _ => Shader::Phong,
    };
    let view = match (&a.eye, a.view) {
        (Some(e), _) => {
            let target = a
                .target
                .clone()
                .unwrap_or_else(|| match surface_bounds(&surface) {
                    Some(b) => b.center().to_vec(),
                    None => vec![0.0; 3],
                });
            View::Explicit {
                eye: [e[0], e[1], e[2]],
                target: [target[0], target[1], target[2]],
            }
        }
        (None, ViewArg::Top) => View::Top,
        (None, ViewArg::Front) => View::Front,
        (None, ViewArg::Side) => View::Side,
        _ => View::Iso,
    };
    let mut opts = RenderOptions {
        width: a.size.0,
        height: a.size.1,
        view,
        projection: if a.ortho {
            Projection::Orthographic
        } else {
            Projection::Perspective { fov_deg: a.fov }
        },
        shader: a.shader.map(shader).unwrap_or(default_shader),
        supersample: a.supersample,
        light: match &a.light {
            Some(l) => LightModel {
                direction: LightModel::from_azimuth_altitude(l[0], l[1]),
                ..LightModel::default()
            },
            None => LightModel::default(),
        },
        light_follows_camera: a.light.is_none(),
        shadows: !a.no_shadows,
        ambient_occlusion: a.ao.clamp(0.0, 1.0),
        colormap,
        wireframe: a.wireframe.then_some([20, 20, 30, 200]),
        scalar: a.scalar.clone(),
        z_scale: a.z_scale,
        background: a.background,
        budget: ctx.budget,
        ..RenderOptions::default()
    };
    let frames = a.turntable.unwrap_or(1);
    let bounds = surface_bounds(&surface).context("nothing to render: the input is empty")?;
    for k in 0..frames {
        if a.turntable.is_some() {
            // Orbit around the vertical axis through the centre at the iso elevation.
            let c = bounds.center();
            let r = bounds.diagonal() * 1.9;
            let ang =
                std::f64::consts::TAU * k as f64 / frames as f64 - std::f64::consts::FRAC_PI_4;
            let el = 35.26f64.to_radians();
            opts.view = View::Explicit {
                eye: [
                    c[0] + r * el.cos() * ang.cos(),
                    c[1] + r * el.cos() * ang.sin(),
                    c[2] + r * el.sin(),
                ],
                target: c,
            };
        }
        let t = std::time::Instant::now();
        let img = match &surface {
            Surface::Mesh(m) => asperity_render::render_mesh(m, &opts)?,
            Surface::Points(p) => asperity_render::render_points(p, &opts)?,
            Surface::Height(h) => asperity_render::render_height(h, &opts)?,
        };
        report.measure(&format!("frame_{k}_seconds"), t.elapsed().as_secs_f64());
        let path = if a.turntable.is_some() {
            frame_path(&out, k)
        } else {
            out.clone()
        };
        asperity_io::write_png(&path, &img)?;
        report.output(&path);
    }
    ctx.note(format!(
        "wrote {}{}",
        out.display(),
        if frames > 1 {
            format!(" ({frames} frames)")
        } else {
            String::new()
        }
    ));
    report.finish(ctx)
}

fn surface_bounds(s: &Surface) -> Option<asperity_core::Aabb> {
    match s {
        Surface::Mesh(m) => m.bounds(),
        Surface::Points(p) => p.bounds(),
        Surface::Height(h) => {
            let (lo, hi) = h.min_max();
            let o = h.origin();
            let e = h.extent();
            Some(asperity_core::Aabb {
                min: [o[0], o[1], lo],
                max: [o[0] + e[0], o[1] + e[1], hi],
            })
        }
    }
}
