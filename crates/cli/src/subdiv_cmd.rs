//! `asperity subdiv`: Catmull–Clark multiresolution surfaces with procedural
//! detail (velho-perlin; library: `asperity-subdiv`). So far: plain subdivision
//! with boundaries and limit positions, and rock detail.

use std::path::Path;

use anyhow::Context as _;
use asperity_core::PolyMesh;
use asperity_io::{Format, WriteOptions};
use asperity_subdiv::base;
use asperity_subdiv::catmull_clark::{Boundary, Creased, limit_positions};
use asperity_subdiv::detail::Rock;

use crate::cli::{BoundaryArg, Context, SubdivArgs};
use crate::report::Report;

fn load_base(spec: &str) -> anyhow::Result<PolyMesh> {
    Ok(match spec {
        "cube" => base::cube(),
        "sphere" => base::quad_sphere(2),
        "torus" => base::torus(1.0, 0.35, 16, 8),
        path => asperity_io::read_poly_mesh(Path::new(path)).with_context(|| {
            format!("reading the base mesh {path} (or use cube, sphere, torus)")
        })?,
    })
}

/// `rock:amplitude=A,decay=D`.
fn parse_detail(spec: &str) -> anyhow::Result<Rock> {
    let (name, params) = spec.split_once(':').unwrap_or((spec, ""));
    anyhow::ensure!(
        name == "rock",
        "unknown detail {name:?}: only rock is implemented so far (berry, tentacle, mushroom, spur and fbm are planned)"
    );
    let mut r = Rock::default();
    for kv in params.split(',').filter(|s| !s.is_empty()) {
        let (k, v) = kv
            .split_once('=')
            .with_context(|| format!("--detail: {kv:?} is not key=value"))?;
        let v: f64 = v
            .trim()
            .parse()
            .with_context(|| format!("--detail: {v:?} is not a number"))?;
        match k.trim() {
            "amplitude" => r.amplitude = v,
            "decay" => r.decay = v,
            other => anyhow::bail!("--detail rock: unknown parameter {other:?} (amplitude, decay)"),
        }
    }
    r.validate()
        .map_err(|e| anyhow::anyhow!("--detail rock: {e}"))?;
    Ok(r)
}

pub fn run(ctx: &Context, a: &SubdivArgs) -> anyhow::Result<()> {
    let out = ctx
        .output
        .clone()
        .context("no output file: give -o FILE (e.g. -o rock.ply)")?;
    anyhow::ensure!(
        Format::from_path(&out)?.info().mesh.can_write(),
        "{} cannot hold a mesh; use .ply, .obj, .stl or .glb",
        out.display()
    );
    let base = Creased::smooth(load_base(&a.base)?);
    let boundary = match a.boundary {
        BoundaryArg::EdgeOnly => Boundary::EdgeOnly,
        BoundaryArg::EdgeAndCorner => Boundary::EdgeAndCorner,
    };
    let levels = a.levels as usize;
    // Quads after level k: Σ|f| · 4^(k−1); refuse before allocating.
    let corners: u128 = base.mesh.faces().map(|f| f.len() as u128).sum();
    let quads = if levels == 0 {
        base.mesh.n_faces() as u128
    } else {
        corners << (2 * (levels - 1))
    };
    ctx.budget
        .check_elements(quads, 16 + 2 * 24 + 2 * 12, "the subdivided mesh")?;
    let rock = a.detail.as_deref().map(parse_detail).transpose()?;
    let mut report = Report::new("subdiv", ctx);
    let t = std::time::Instant::now();
    let built = asperity_subdiv::multires::build(&base, levels, boundary, |l| {
        Ok(rock.map(|r| r.details(ctx.seed, l.level, l.mesh.mesh.n_vertices())))
    })?;
    let all = built.levels;
    let fine = all.last().context("levels")?;
    let mut mesh = fine.mesh.clone();
    if a.limit && levels > 0 {
        mesh = mesh.with_positions(limit_positions(fine, boundary)?)?;
    }
    report.measure("build_s", t.elapsed().as_secs_f64());
    let tri = mesh.triangulate().with_computed_normals();
    asperity_io::write_mesh(&out, &tri, &WriteOptions::default())
        .with_context(|| format!("writing {}", out.display()))?;
    report.output(&out);
    report.measure(
        "levels",
        all.iter()
            .map(|l| {
                serde_json::json!({
                    "vertices": l.mesh.n_vertices(),
                    "faces": l.mesh.n_faces(),
                    "euler_characteristic": l.mesh.euler_characteristic(),
                })
            })
            .collect::<Vec<_>>(),
    );
    ctx.note(format!(
        "{} levels: {} vertices, {} quads written to {}",
        levels,
        mesh.n_vertices(),
        mesh.n_faces(),
        out.display()
    ));
    report.finish(ctx)
}
