//! `asperity subdiv`: multiresolution surfaces with procedural detail
//! (velho-perlin; `asperity_engine::subdiv`) from options or a scene file, with
//! animation frames and detail export and re-apply.

use asperity_core::{NoProgress, Progress};
use asperity_engine::files::{numbered, read_text, require_mesh_format};
use asperity_engine::subdiv::{Options, Session, Source};
use asperity_subdiv::catmull_clark::Boundary;
use asperity_subdiv::evaluate::Composed;
use serde_json::json;

use crate::cli::{BoundaryArg, SubdivArgs};
use crate::context::{Context, Run};

fn source(a: &SubdivArgs) -> anyhow::Result<Source> {
    Ok(match &a.scene {
        Some(p) => Source::Scene {
            path: p.clone(),
            text: read_text(p)?,
        },
        None => Source::Options(Options {
            base: a.base.clone(),
            levels: a.levels as usize,
            details: a.detail.clone(),
            creases: a.crease.clone(),
            boundary: match a.boundary {
                BoundaryArg::EdgeOnly => Boundary::EdgeOnly,
                BoundaryArg::EdgeAndCorner => Boundary::EdgeAndCorner,
            },
        }),
    })
}

/// The animation time of frame `i`: `--time` alone, 0…1 over `--frames`.
fn time(a: &SubdivArgs, i: u32, frames: u32) -> f64 {
    match a.frames {
        None => a.time,
        Some(_) if frames == 1 => 0.0,
        Some(_) => f64::from(i) / f64::from(frames - 1),
    }
}

/// One frame's surface: re-applied details, an analysed fine mesh, or the scene.
fn frame(
    s: &Session,
    a: &SubdivArgs,
    (i, frames): (u32, u32),
    bar: &dyn Progress,
) -> anyhow::Result<(Composed, bool, Boundary)> {
    let scene = if i == 0 && a.frames.is_none() {
        s.first.clone()
    } else {
        s.scene(time(a, i, frames))?
    };
    let c = match (&a.apply_details, &a.analyze) {
        (Some(p), _) => s.apply_details(p, scene.boundary)?,
        (None, Some(p)) => s.analyze_fine(p, &scene)?,
        (None, None) if frames == 1 => s.frame(&scene, bar)?,
        (None, None) => s.frame(&scene, &NoProgress)?,
    };
    Ok((c, scene.limit, scene.boundary))
}

pub fn run(ctx: &Context, a: &SubdivArgs) -> anyhow::Result<()> {
    let out = ctx.output("FILE (e.g. -o rock.ply)")?;
    require_mesh_format(&out, ".ply, .obj, .stl or .glb")?;
    let session = Session::open(source(a)?, ctx.seed, a.limit, a.time, &ctx.budget)?;
    let mut run = Run::new(ctx, "subdiv");
    let frames = a.frames.unwrap_or(1);
    asperity_engine::estimate::check_file_count(u64::from(frames), "--frames")?;
    let bar = ctx.bar();
    if frames > 1 {
        bar.start(u64::from(frames), "subdiv frames");
    }
    let mut last = None;
    let t0 = std::time::Instant::now();
    for i in 0..frames {
        let (composed, limit, boundary) = frame(&session, a, (i, frames), &bar)?;
        let tri = composed.to_trimesh(limit, boundary)?;
        let path = match a.frames {
            Some(_) => numbered(&out, "", u64::from(i), 4),
            None => out.clone(),
        };
        if a.triangles {
            run.mesh(&path, &tri)?;
        } else {
            let opts = ctx.write_options();
            asperity_io::write_poly_mesh(&path, &composed.mesh.mesh, &tri, &opts)?;
            run.report.output(&path);
        }
        if frames > 1 {
            bar.advance(1);
        }
        last = Some(composed);
    }
    bar.finish();
    run.report
        .measure("build_and_write_s", t0.elapsed().as_secs_f64());
    let composed = last.ok_or_else(|| anyhow::anyhow!("at least one frame"))?;
    if let Some(p) = &a.export_details {
        run.text(p, &session.details_file(&composed))?;
    }
    let counts: Vec<_> = composed
        .counts
        .iter()
        .map(|(v, f)| json!({ "vertices": v, "faces": f }))
        .collect();
    run.report.measure("levels", counts);
    let mesh = &composed.mesh.mesh;
    run.report
        .measure("euler_characteristic", mesh.euler_characteristic());
    let many = if frames > 1 {
        format!(", {frames} frames")
    } else {
        String::new()
    };
    run.note(format!(
        "{} levels: {} vertices, {} quads{many}",
        session.first.levels,
        mesh.n_vertices(),
        mesh.n_faces()
    ));
    run.finish()
}
