//! `asperity convert`, `asperity info` and `asperity formats`.

use anyhow::{Context as _, bail};
use asperity_core::{Diagonal, HeightField, PointSet, TriMesh};
use asperity_io::{FORMATS, Format, NpyDtype, PlyEncoding, Surface, WriteOptions};
use serde_json::json;

use crate::cli::{Context, ConvertArgs, DiagonalArg, InfoArgs, Kind};
use crate::progress::Bar;
use crate::report::Report;
use asperity_core::Progress;

/// Rough peak memory of reading a file, as a multiple of its size: text formats
/// shrink when parsed, STL's welded f32 corners grow about threefold into f64
/// vertices plus the weld table; 8× covers every reader with margin.
const READ_MEMORY_FACTOR: u64 = 8;

pub fn diagonal(d: DiagonalArg) -> Diagonal {
    match d {
        DiagonalArg::Forward => Diagonal::Forward,
        DiagonalArg::Backward => Diagonal::Backward,
        DiagonalArg::Alternating => Diagonal::Alternating,
    }
}

pub fn load(ctx: &Context, path: &std::path::Path) -> anyhow::Result<Surface> {
    let size = std::fs::metadata(path)
        .with_context(|| format!("cannot read {}", path.display()))?
        .len();
    ctx.budget.check(
        size.saturating_mul(READ_MEMORY_FACTOR),
        format!("reading {}", path.display()),
    )?;
    Ok(asperity_io::read(path)?)
}

fn to_kind(s: Surface, kind: Kind, diag: Diagonal) -> anyhow::Result<Surface> {
    Ok(match (s, kind) {
        (Surface::Height(h), Kind::Mesh) => Surface::Mesh(
            h.to_trimesh(diag)?
                .with_scalar("height", h.data().to_vec())?,
        ),
        (Surface::Height(h), Kind::Points) => Surface::Points(h.to_point_set()),
        (Surface::Mesh(m), Kind::Points) => Surface::Points(PointSet::new(m.positions().to_vec())),
        (s @ Surface::Mesh(_), Kind::Mesh)
        | (s @ Surface::Points(_), Kind::Points)
        | (s @ Surface::Height(_), Kind::Height) => s,
        (s, k) => bail!("cannot turn {} into {}", s.kind(), kind_name(k)),
    })
}

fn kind_name(k: Kind) -> &'static str {
    match k {
        Kind::Mesh => "a mesh",
        Kind::Points => "a point set",
        Kind::Height => "a height field",
    }
}

pub fn run(ctx: &Context, a: &ConvertArgs) -> anyhow::Result<()> {
    let out = a
        .out_file
        .clone()
        .or_else(|| ctx.output.clone())
        .context("no output file: give OUT or -o PATH")?;
    let out_format = Format::from_path(&out)?;
    let mut report = Report::new("convert", ctx);
    let bar = Bar::new(ctx.quiet || ctx.json);
    bar.start(2, "converting");
    let mut s = load(ctx, &a.input)?;
    bar.advance(1);
    let diag = diagonal(a.diagonal);
    if let Some(k) = a.as_kind {
        s = to_kind(s, k, diag)?;
    }
    if let (Some(sp), Surface::Height(h)) = (&a.spacing, &mut s) {
        anyhow::ensure!(
            matches!(sp.len(), 1 | 2),
            "--spacing takes DX or DX,DY, got {sp:?}"
        );
        let sp = [sp[0], *sp.get(1).unwrap_or(&sp[0])];
        *h = h.clone().with_spacing(sp)?;
    }
    // A point set cannot become a mesh or a height field without a method.
    let info = out_format.info();
    let fits = match &s {
        Surface::Mesh(_) => info.mesh.can_write() || info.points.can_write(),
        Surface::Points(_) => info.points.can_write(),
        Surface::Height(_) => {
            info.height.can_write() || info.mesh.can_write() || info.points.can_write()
        }
    };
    if !fits {
        bail!(
            "{}: {} cannot hold {} (run `asperity formats`)",
            out.display(),
            info.name,
            s.kind()
        );
    }
    for lost in asperity_io::lost_data(&s, out_format) {
        let w = format!("{} loses {lost}", out.display());
        ctx.note(format!("warning: {w}"));
        report.warnings.push(w);
    }
    let opts = WriteOptions {
        ply_encoding: if a.ascii {
            PlyEncoding::Ascii
        } else {
            PlyEncoding::BinaryLittleEndian
        },
        npy_dtype: if a.f32 {
            NpyDtype::Float32
        } else {
            NpyDtype::Float64
        },
        diagonal: diag,
        title: a
            .input
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
    };
    asperity_io::write(&out, &s, &opts)?;
    bar.finish();
    report.output(&out);
    report.measure("input", a.input.display().to_string());
    report.measure("kind", s.kind());
    ctx.note(format!(
        "wrote {} ({}) from {}",
        out.display(),
        info.name,
        a.input.display()
    ));
    report.finish(ctx)
}

/// Facts about a mesh, as JSON.
pub fn mesh_facts(m: &TriMesh) -> serde_json::Value {
    let b = m.bounds();
    let watertight = m.is_watertight();
    json!({
        "kind": "mesh",
        "vertices": m.n_vertices(),
        "triangles": m.n_faces(),
        "edges": m.edges().len(),
        "euler_characteristic": m.euler_characteristic(),
        "components": m.n_components(),
        "boundary_loops": m.boundary_loops().len(),
        "manifold": m.is_manifold(),
        "watertight": watertight,
        "genus": m.genus(),
        "area": m.area(),
        "volume": if watertight { Some(m.signed_volume()) } else { None },
        "bounds": b,
        "normals": m.normals().is_some(),
        "colors": m.colors().is_some(),
        "uvs": m.uvs().is_some(),
        "scalars": m.scalars().iter().map(|a| a.name.clone()).collect::<Vec<_>>(),
    })
}

/// Facts about a height field, as JSON.
pub fn height_facts(h: &HeightField) -> serde_json::Value {
    let (lo, hi) = h.min_max();
    let mean = h.mean();
    let rms = (h.data().iter().map(|z| (z - mean).powi(2)).sum::<f64>() / h.len() as f64).sqrt();
    json!({
        "kind": "height field",
        "nx": h.nx(), "ny": h.ny(),
        "spacing": h.spacing(), "origin": h.origin(), "extent": h.extent(),
        "min": lo, "max": hi, "mean": mean, "rms_deviation": rms,
    })
}

fn point_facts(p: &PointSet) -> serde_json::Value {
    json!({
        "kind": "point set",
        "points": p.len(),
        "bounds": p.bounds(),
        "normals": p.normals().is_some(),
        "colors": p.colors().is_some(),
        "attributes": p.attributes().iter().map(|a| a.name.clone()).collect::<Vec<_>>(),
    })
}

pub fn info(ctx: &Context, a: &InfoArgs) -> anyhow::Result<()> {
    let s = load(ctx, &a.input)?;
    let facts = match &s {
        Surface::Mesh(m) => mesh_facts(m),
        Surface::Points(p) => point_facts(p),
        Surface::Height(h) => height_facts(h),
    };
    if ctx.json {
        let mut r = Report::new("info", ctx);
        r.measure("file", a.input.display().to_string());
        if let serde_json::Value::Object(map) = facts {
            r.measurements.extend(map);
        }
        return r.finish(ctx);
    }
    outln!("{}", a.input.display());
    if let serde_json::Value::Object(map) = facts {
        for (k, v) in map {
            outln!("  {k:22} {v}");
        }
    }
    Ok(())
}

pub fn formats(ctx: &Context) -> anyhow::Result<()> {
    if ctx.json {
        outln!("{}", serde_json::to_string_pretty(FORMATS)?);
        return Ok(());
    }
    let cell = |a: asperity_io::Access| match (a.can_read(), a.can_write()) {
        (true, true) => "read+write",
        (true, false) => "read",
        (false, true) => "write",
        (false, false) => "-",
    };
    outln!(
        "{:<38} {:<10} {:<11} {:<11} {:<11} notes",
        "format",
        "extension",
        "mesh",
        "points",
        "height"
    );
    for f in FORMATS {
        outln!(
            "{:<38} {:<10} {:<11} {:<11} {:<11} {}",
            f.name,
            f.extensions
                .iter()
                .map(|e| format!(".{e}"))
                .collect::<Vec<_>>()
                .join(" "),
            cell(f.mesh),
            cell(f.points),
            cell(f.height),
            f.notes
        );
    }
    Ok(())
}
