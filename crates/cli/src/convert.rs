//! `asperity convert`, `asperity info` and `asperity formats`.

use anyhow::{Context as _, bail};
use asperity_engine::core::Progress;
use asperity_engine::describe::describe;
use asperity_engine::io::{FORMATS, Format, Surface};

use crate::cli::{ConvertArgs, InfoArgs};
use crate::context::{Context, Run};

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
    let job = ctx.job_params(a.params.clone(), &a.params_file)?;
    let mut run = Run::new(ctx, "convert");
    run.params(&job.params, job.seed, job.overridden.clone());
    let bar = ctx.bar();
    bar.start(2, "converting");
    let s = ctx.load(&a.input)?;
    bar.advance(1);
    let (s, done) = job.params.apply(s, &a.input.display().to_string())?;
    if let Some(r) = &done.repair {
        run.note(format!(
            "repaired: {} degenerate triangles dropped, {} flipped, {} vertices split",
            r.dropped_degenerate, r.flipped, r.split_vertices
        ));
        run.report.measure("repair", r);
    }
    if let Some(f) = &done.filled {
        run.note(format!(
            "filled {} missing points ({} iterations)",
            f.missing, f.iterations
        ));
        run.report.measure(
            "filled",
            serde_json::json!({"points": f.missing, "iterations": f.iterations, "residual": f.residual}),
        );
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
    // An output that is the input is refused before any warning about it.
    asperity_engine::io::staging::refuse_input(&out)?;
    for lost in asperity_engine::io::lost_data(&s, out_format) {
        run.warn("warning", format!("{} loses {lost}", out.display()));
    }
    let title = a
        .input
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    // The surface's recipe: the parameters its file records, which a format
    // change keeps (a file without them gets none; the report has convert's).
    // A conversion that changes the surface (another kind, a new spacing, a
    // repair) keeps none: they would no longer make it.
    let recipe = asperity_engine::io::read_params(&a.input).unwrap_or_default();
    let changed = {
        let p = &job.params;
        p.as_kind.is_some() || p.spacing.is_some() || p.repair || done.filled.is_some()
    };
    if changed && recipe.is_some() {
        run.note(format!(
            "{} records no parameters: the conversion changed the surface that those of {} made",
            out.display(),
            a.input.display()
        ));
    }
    let opts = asperity_engine::io::WriteOptions {
        params: recipe.filter(|_| !changed),
        ..job.params.write_options(title, ctx.written_up())
    };
    asperity_engine::io::write(&out, &s, &opts)?;
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

/// The instrument's metadata of `path` (see
/// `asperity_io::instrument_metadata`) as a JSON object, if its format keeps
/// any.
pub fn instrument_json(path: &std::path::Path) -> anyhow::Result<Option<serde_json::Value>> {
    Ok(
        asperity_engine::io::instrument_metadata(path)?.map(|pairs| {
            serde_json::Value::Object(
                pairs
                    .into_iter()
                    .map(|(k, v)| (k, serde_json::Value::String(v)))
                    .collect(),
            )
        }),
    )
}

pub fn info(ctx: &Context, a: &InfoArgs) -> anyhow::Result<()> {
    let mut facts = describe(&ctx.load(&a.input)?);
    // A multi-channel file's channels, and which one was read.
    if let Some(list) = asperity_engine::io::channels(&a.input)? {
        let read = match &ctx.channel {
            Some(asperity_engine::io::Channel::Index(n)) => list.iter().find(|c| c.index == *n),
            Some(asperity_engine::io::Channel::Name(s)) => {
                list.iter().find(|c| c.name.eq_ignore_ascii_case(s))
            }
            None => list.iter().find(|c| c.height).or(list.first()),
        };
        facts.set("channel", read.map(|c| c.index));
        facts.set("channels", &list);
    }
    // The parameters the file was made with, where it records them.
    let made_with = asperity_engine::io::read_params(&a.input)?;
    if ctx.json {
        let mut run = Run::new(ctx, "info");
        run.params(&asperity_engine::files::InfoParams {}, ctx.seed, Vec::new());
        run.report.measure("file", a.input.display().to_string());
        run.measure(facts);
        if let Some(m) = instrument_json(&a.input)? {
            run.report.measure("instrument", m);
        }
        if let Some(p) = made_with {
            run.report.measure("made_with", p);
        }
        return run.finish();
    }
    outln!("{}", a.input.display());
    for (k, v) in facts.0 {
        outln!("  {k:22} {v}");
    }
    if let Some(p) = made_with {
        outln!("  {:22} {p}", "made_with");
    }
    Ok(())
}

pub fn formats(ctx: &Context) -> anyhow::Result<()> {
    if ctx.json {
        outln!("{}", serde_json::to_string_pretty(FORMATS)?);
        return Ok(());
    }
    let cell = |a: asperity_engine::io::Access| match (a.can_read(), a.can_write()) {
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
