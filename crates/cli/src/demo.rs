//! `asperity demo`: the gallery of every method (`asperity_gallery`).

use std::path::PathBuf;

use crate::cli::DemoArgs;
use crate::context::Context;

pub fn run(ctx: &Context, a: &DemoArgs) -> anyhow::Result<()> {
    let dir = a
        .out
        .clone()
        .or_else(|| ctx.output.clone())
        .unwrap_or_else(|| PathBuf::from("gallery"));
    let options = asperity_gallery::Options {
        dir: dir.clone(),
        seed: ctx.seed,
        quick: a.quick,
        full_meshes: a.full_meshes,
        only: a.only.clone(),
        budget: ctx.budget,
        threads: ctx.threads,
    };
    let mut report = asperity_gallery::run(&options, &ctx.bar())?;
    ctx.note(format!(
        "gallery written to {}",
        dir.join("index.html").display()
    ));
    report.stop_clock();
    if ctx.json {
        outln!("{}", serde_json::to_string_pretty(&report)?);
    }
    Ok(())
}
