//! `asperity convert`, `asperity info` and `asperity formats`.

use anyhow::{Context as _, bail};
use asperity_core::{Diagonal, PointSet, Progress};
use asperity_engine::describe::describe;
use asperity_io::{FORMATS, Format, NpyDtype, PlyEncoding, Surface, WriteOptions};

use crate::cli::{ConvertArgs, DiagonalArg, InfoArgs, Kind};
use crate::context::{Context, Run};

pub fn diagonal(d: DiagonalArg) -> Diagonal {
    match d {
        DiagonalArg::Forward => Diagonal::Forward,
        DiagonalArg::Backward => Diagonal::Backward,
        DiagonalArg::Alternating => Diagonal::Alternating,
    }
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

/// Whether `format` can hold `s` (a height field also as a mesh or points; a
/// mesh also as points).
fn fits(s: &Surface, format: Format) -> bool {
    let info = format.info();
    match s {
        Surface::Mesh(_) => info.mesh.can_write() || info.points.can_write(),
        Surface::Points(_) => info.points.can_write(),
        Surface::Height(_) => {
            info.height.can_write() || info.mesh.can_write() || info.points.can_write()
        }
    }
}

pub fn run(ctx: &Context, a: &ConvertArgs) -> anyhow::Result<()> {
    let out = a
        .out_file
        .clone()
        .or_else(|| ctx.output.clone())
        .context("no output file: give OUT or -o PATH")?;
    let out_format = Format::from_path(&out)?;
    let mut run = Run::new(ctx, "convert");
    let bar = ctx.bar();
    bar.start(2, "converting");
    let mut s = ctx.load(&a.input)?;
    bar.advance(1);
    let diag = diagonal(a.diagonal);
    if let Some(k) = a.as_kind {
        s = to_kind(s, k, diag)?;
    }
    if a.repair {
        let Surface::Mesh(m) = &s else {
            bail!(
                "--repair works on meshes; {} holds {}",
                a.input.display(),
                s.kind()
            );
        };
        let (fixed, r) = asperity_core::mesh_check::repair_surface(m)
            .with_context(|| format!("{}: cannot repair", a.input.display()))?;
        run.note(format!(
            "repaired: {} degenerate triangles dropped, {} flipped, {} vertices split",
            r.dropped_degenerate, r.flipped, r.split_vertices
        ));
        run.report.measure("repair", &r);
        s = Surface::Mesh(fixed);
    }
    if let (Some(sp), Surface::Height(h)) = (&a.spacing, &mut s) {
        anyhow::ensure!(
            matches!(sp.len(), 1 | 2),
            "--spacing takes DX or DX,DY, got {sp:?}"
        );
        let sp = [sp[0], *sp.get(1).unwrap_or(&sp[0])];
        *h = h.clone().with_spacing(sp)?;
    }
    let info = out_format.info();
    if !fits(&s, out_format) {
        bail!(
            "{}: {} cannot hold {} (run `asperity formats`)",
            out.display(),
            info.name,
            s.kind()
        );
    }
    for lost in asperity_io::lost_data(&s, out_format) {
        run.warn("warning", format!("{} loses {lost}", out.display()));
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
        up: ctx.up,
    };
    asperity_io::write(&out, &s, &opts)?;
    bar.finish();
    run.report.output(&out);
    run.report.measure("input", a.input.display().to_string());
    run.report.measure("kind", s.kind());
    run.note(format!(
        "wrote {} ({}) from {}",
        out.display(),
        info.name,
        a.input.display()
    ));
    run.finish()
}

pub fn info(ctx: &Context, a: &InfoArgs) -> anyhow::Result<()> {
    let facts = describe(&ctx.load(&a.input)?);
    if ctx.json {
        let mut run = Run::new(ctx, "info");
        run.report.measure("file", a.input.display().to_string());
        run.measure(facts);
        return run.finish();
    }
    outln!("{}", a.input.display());
    for (k, v) in facts.0 {
        outln!("  {k:22} {v}");
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
        let ext: Vec<String> = f.extensions.iter().map(|e| format!(".{e}")).collect();
        outln!(
            "{:<38} {:<10} {:<11} {:<11} {:<11} {}",
            f.name,
            ext.join(" "),
            cell(f.mesh),
            cell(f.points),
            cell(f.height),
            f.notes
        );
    }
    Ok(())
}
