//! `asperity analyze` and `asperity generate fbm`.

use asperity_engine::analyze::analyze as analyze_surface;
use asperity_engine::core::Progress;
use serde_json::Value;

use crate::cli::{AnalyzeArgs, FbmArgs, FilterArgs};
use crate::context::{Context, Run};

pub fn analyze(ctx: &Context, a: &AnalyzeArgs) -> anyhow::Result<()> {
    // The run (and its clock) starts first, so elapsed_s counts the reading
    // and the analysis.
    let mut run = Run::new(ctx, "analyze");
    // field-sized buffers come and go: keep their pages (crate::memory)
    let _keep = crate::memory::PurgeDelay::never();
    let job = ctx.job_params(a.params.clone(), &a.params_file)?;
    asperity_engine::params::validate(&job.params)?;
    run.params(&job.params, job.seed, job.overridden.clone());
    let s = ctx.load(&a.input)?;
    let opts = job.params.options(a.plot.is_some());
    let name = a.input.display().to_string();
    let r = analyze_surface(&s, &name, &opts, &ctx.budget)?;
    for w in &r.warnings {
        run.warn("warning", w.clone());
    }
    if let Some(dir) = &a.plot {
        if r.plots.is_empty() {
            run.note("no plots for point sets (growth commands plot R_g(n) and ρ(z) with --plot)");
        }
        run.plots(dir, &r.plots, (900, 640))?;
        for i in &r.images {
            run.png(&dir.join(i.name), &i.image)?;
        }
        let names = r
            .plots
            .iter()
            .map(|p| p.name)
            .chain(r.images.iter().map(|i| i.name));
        for name in names {
            run.note(format!("plot written to {}", dir.join(name).display()));
        }
    }
    if ctx.json {
        run.report.measure("file", &name);
        run.measure(r.facts);
        // The instrument's own metadata, carried into the report.
        if let Some(m) = crate::convert::instrument_json(&a.input)? {
            run.report.measure("instrument", m);
        }
        return run.finish();
    }
    outln!("{name}");
    text_report(&r.facts.0)
}

pub fn filter(ctx: &Context, a: &FilterArgs) -> anyhow::Result<()> {
    use anyhow::Context as _;
    let _keep = crate::memory::PurgeDelay::never();
    let out = a
        .out_file
        .clone()
        .or_else(|| ctx.output.clone())
        .context("no output file: give OUTPUT or -o PATH")?;
    let mut run = Run::new(ctx, "filter");
    let job = ctx.job_params(a.params.clone(), &a.params_file)?;
    asperity_engine::params::validate(&job.params)?;
    run.params(&job.params, job.seed, job.overridden.clone());
    for path in [
        Some(&out),
        a.waviness.as_ref(),
        a.noise.as_ref(),
        a.form.as_ref(),
    ]
    .into_iter()
    .flatten()
    {
        asperity_engine::io::Format::from_path(path)?;
        asperity_engine::io::staging::refuse_input(path)?;
    }
    let bar = ctx.bar();
    bar.start(2, "filtering");
    let h = match ctx.load(&a.input)? {
        asperity_engine::io::Surface::Height(h) => h,
        s => anyhow::bail!(
            "{}: filter takes a height field or profile, not {}",
            a.input.display(),
            s.kind()
        ),
    };
    bar.advance(1);
    let f = asperity_engine::analyze::filter(&h, &job.params, &ctx.budget)?;
    bar.finish();
    for w in &f.warnings {
        run.warn("warning", w.clone());
    }
    let stem = a
        .input
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let surface_name = f
        .facts
        .get("filter")
        .and_then(|v| v["surface"].as_str())
        .unwrap_or("surface");
    run.height(&out, &f.surface, format!("{stem}: {surface_name}"))?;
    let parts = [
        (
            &a.waviness,
            f.waviness.as_ref(),
            "waviness",
            "L-filter (--lambda-c)",
        ),
        (&a.noise, f.noise.as_ref(), "noise", "S-filter (--lambda-s)"),
        (&a.form, Some(&f.form), "form", "F-operator"),
    ];
    for (path, part, name, what) in parts {
        match (path, part) {
            (Some(path), Some(part)) => run.height(path, part, format!("{stem}: {name}"))?,
            (Some(path), None) => anyhow::bail!(
                "--{name} {}: nothing to write without an {what}",
                path.display()
            ),
            _ => {}
        }
    }
    run.note(format!("wrote {} ({surface_name})", out.display()));
    if ctx.json {
        run.report.measure("file", a.input.display().to_string());
        run.measure(f.facts);
        return run.finish();
    }
    text_report(&f.facts.0)
}

/// Six significant digits, or the JSON text for anything but a number.
fn short(v: &Value) -> String {
    match v.as_f64() {
        Some(x) if v.is_f64() && x != 0.0 && x.is_finite() => {
            let digits = (5 - x.abs().log10().floor() as i32).clamp(0, 12) as usize;
            format!("{x:.digits$}")
        }
        _ => v.to_string(),
    }
}

/// The report as text: the mode the data were analysed in first (periodic or
/// not, levelling, window), the Hurst estimators and dimensions as tables,
/// then every other quantity on its line.
fn text_report(facts: &serde_json::Map<String, Value>) -> anyhow::Result<()> {
    if let Some(p) = facts.get("periodic") {
        let ratio = p["edge_ratio"]
            .as_f64()
            .map_or(String::new(), |r| format!(", edge ratio {r:.3}"));
        outln!(
            "  mode: {} ({}{ratio}), levelling {}, window {}",
            if p["value"] == true {
                "periodic"
            } else {
                "non-periodic"
            },
            p["source"].as_str().unwrap_or("?"),
            facts
                .get("levelling")
                .and_then(Value::as_str)
                .unwrap_or("?"),
            facts.get("window").and_then(Value::as_str).unwrap_or("?"),
        );
    }
    if let Some(Value::Object(est)) = facts.get("hurst_estimates") {
        outln!("  Hurst exponent        H        ± stderr   r²       fit range");
        for (k, e) in est {
            if e.is_null() {
                outln!("    {k:19} not estimated (see the warnings)");
            } else {
                outln!(
                    "    {k:19} {:8} {:10} {:8} {}–{} {}",
                    short(&e["H"]),
                    short(&e["stderr"]),
                    short(&e["r2"]),
                    short(&e["fit_range"][0]),
                    short(&e["fit_range"][1]),
                    e["range_unit"].as_str().unwrap_or(""),
                );
            }
        }
    }
    if let Some(Value::Object(dims)) = facts.get("fractal_dimension") {
        outln!("  fractal dimension     D        ± stderr   r²");
        for (k, d) in dims {
            if d.is_null() {
                outln!("    {k:19} unreliable here (see the warnings)");
            } else {
                outln!(
                    "    {k:19} {:8} {:10} {:8}",
                    short(&d["D"]),
                    short(&d["stderr"]),
                    short(&d["r2"])
                );
            }
        }
    }
    for (k, v) in facts {
        match k.as_str() {
            "periodic" | "levelling" | "window" | "hurst_estimates" | "fractal_dimension" => {}
            "filter" => outln!(
                "  {k:22} {}: λs {}, λc {}, {} of degree {}{}",
                v["surface"].as_str().unwrap_or("?"),
                if v["lambda_s"].is_null() {
                    "none".into()
                } else {
                    short(&v["lambda_s"])
                },
                if v["lambda_c"].is_null() {
                    "none".into()
                } else {
                    short(&v["lambda_c"])
                },
                v["L_filter"].as_str().unwrap_or("no L-filter"),
                short(&v["degree"]),
                v["robust_iterations"]
                    .as_u64()
                    .map_or(String::new(), |n| format!(", {n} iterations")),
            ),
            "material_ratio" => outln!(
                "  {k:22} equivalent line {} → {} (40 % window from {} %; the curve: see --json, --plot)",
                short(&v["equivalent_line"]["at_0"]),
                short(&v["equivalent_line"]["at_100"]),
                short(&v["equivalent_line"]["window_start"]),
            ),
            "psd" | "scale_dependent" => outln!(
                "  {k:22} {} scales (see --json, --plot)",
                v.get("q")
                    .or_else(|| v.get("distance"))
                    .and_then(Value::as_array)
                    .map_or(0, Vec::len)
            ),
            _ => match v {
                Value::Object(m) if m.values().all(Value::is_number) => {
                    let parts: Vec<String> =
                        m.iter().map(|(k, v)| format!("{k} {}", short(v))).collect();
                    outln!("  {k:22} {}", parts.join("  "));
                }
                _ => outln!("  {k:22} {}", short(v)),
            },
        }
    }
    Ok(())
}

pub fn fbm(ctx: &Context, a: &FbmArgs) -> anyhow::Result<()> {
    let out = ctx.output("field.npy")?;
    let job = ctx.job_params(a.params.clone(), &a.params_file)?;
    let p = &job.params;
    let mut run = Run::new(ctx, "generate fbm");
    let h = asperity_engine::synthesis::fbm(p, job.seed, &ctx.budget)?;
    run.params(p, job.seed, job.overridden.clone());
    run.height(&out, &h, p.title())?;
    run.report.measure("size", p.size);
    run.report.measure("hurst", p.hurst);
    run.report.measure("rms", p.rms);
    run.note(format!(
        "wrote {} ({}×{}, H = {}, rms {})",
        out.display(),
        p.size,
        p.size,
        p.hurst,
        p.rms
    ));
    run.finish()
}
