//! `asperity render`: any readable file to PNG.

use anyhow::{Context as _, bail};
use asperity_engine::files::numbered;
use asperity_engine::render::{bounds, picture, turntable};
use asperity_io::Surface;
use asperity_render::{ColorMap, LightModel, Projection, RenderOptions, Shader, View, hillshade};

use crate::cli::{RenderArgs, ShaderArg, ViewArg};
use crate::context::{Context, Run};

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

fn check_vectors(a: &RenderArgs) -> anyhow::Result<()> {
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
    Ok(())
}

fn view(a: &RenderArgs, surface: &Surface) -> View {
    match (&a.eye, a.view) {
        (Some(e), _) => {
            let target = a.target.clone().unwrap_or_else(|| match bounds(surface) {
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
    }
}

fn options(a: &RenderArgs, surface: &Surface, colormap: ColorMap, ctx: &Context) -> RenderOptions {
    let default_shader = asperity_engine::render::default_shader(surface);
    RenderOptions {
        width: a.size.0,
        height: a.size.1,
        view: view(a, surface),
        projection: if a.ortho {
            Projection::Orthographic
        } else {
            Projection::Perspective { fov_deg: a.fov }
        },
        shader: a.shader.map(shader).unwrap_or(if a.patina {
            Shader::VertexColor
        } else {
            default_shader
        }),
        two_layer: a.patina.then(asperity_engine::surfca::patina_shading),
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
    }
}

pub fn run(ctx: &Context, a: &RenderArgs) -> anyhow::Result<()> {
    let out = ctx.output("view.png")?;
    if out
        .extension()
        .is_none_or(|e| !e.eq_ignore_ascii_case("png"))
    {
        bail!(
            "{}: render writes PNG images; use a .png name",
            out.display()
        );
    }
    check_vectors(a)?;
    let surface = ctx.load(&a.input)?;
    let mut run = Run::new(ctx, "render");
    let colormap = ColorMap::from_name(&a.colormap).with_context(|| {
        format!(
            "unknown colour map {:?} (viridis, magma, coolwarm, gray, labels)",
            a.colormap
        )
    })?;
    let map_view = matches!(a.view, ViewArg::Map | ViewArg::Hillshade);
    match (&surface, map_view) {
        (Surface::Height(h), true) => {
            let img = if a.view == ViewArg::Map {
                hillshade::height_map(h, colormap, 0.5, true)
            } else {
                let l = a.light.clone().unwrap_or_else(|| vec![315.0, 45.0]);
                hillshade::hillshade(h, l[0], l[1])
            };
            run.png(&out, &img)?;
            run.note(format!("wrote {}", out.display()));
            return run.finish();
        }
        (_, true) => bail!(
            "--view map and --view hillshade need a height field; {} holds {}",
            a.input.display(),
            surface.kind()
        ),
        _ => {}
    }
    let mut opts = options(a, &surface, colormap, ctx);
    let frames = a.turntable.unwrap_or(1);
    asperity_engine::estimate::check_file_count(u64::from(frames), "--turntable")?;
    let pixels =
        f64::from(opts.width) * f64::from(opts.height) * f64::from(opts.supersample).powi(2);
    asperity_engine::estimate::check(
        &ctx.time,
        &asperity_engine::estimate::render_frames(pixels, f64::from(frames)),
    )?;
    let b = bounds(&surface).context("nothing to render: the input is empty")?;
    for k in 0..frames {
        let path = if a.turntable.is_some() {
            // Orbit around the vertical axis through the centre at the iso elevation.
            opts.view = turntable(&b, k, frames);
            numbered(&out, "", k as u64, 3)
        } else {
            out.clone()
        };
        let t = std::time::Instant::now();
        let img = picture(&surface, &opts)?;
        run.report
            .measure(&format!("frame_{k}_seconds"), t.elapsed().as_secs_f64());
        run.png(&path, &img)?;
    }
    let many = if frames > 1 {
        format!(" ({frames} frames)")
    } else {
        String::new()
    };
    run.note(format!("wrote {}{many}", out.display()));
    run.finish()
}
