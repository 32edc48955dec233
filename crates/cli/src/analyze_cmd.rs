//! `asperity analyze` and `asperity generate fbm`.

use asperity_core::fourier_surface::FourierParams;
use asperity_engine::analyze::{AnalyzeOptions, analyze as analyze_surface};

use crate::cli::{AnalyzeArgs, FbmArgs};
use crate::context::{Context, Run};

pub fn analyze(ctx: &Context, a: &AnalyzeArgs) -> anyhow::Result<()> {
    let s = ctx.load(&a.input)?;
    let fit_window = match a.fit_window.as_deref() {
        None => None,
        Some([lo, hi]) => Some([*lo, *hi]),
        Some(w) => anyhow::bail!("--fit-window takes QMIN,QMAX with 0 < QMIN < QMAX, got {w:?}"),
    };
    let opts = AnalyzeOptions {
        level: a.level.clone(),
        bins: a.bins,
        fit_window,
        plots: a.plot.is_some(),
    };
    let name = a.input.display().to_string();
    let r = analyze_surface(&s, &name, &opts)?;
    let mut run = Run::new(ctx, "analyze");
    for w in &r.warnings {
        run.warn("warning", w.clone());
    }
    if let Some(dir) = &a.plot {
        if r.plots.is_empty() {
            run.note("no plots for point sets (growth commands plot R_g(n) and ρ(z) with --plot)");
        }
        run.plots(dir, &r.plots, (900, 640))?;
        for p in &r.plots {
            run.note(format!("plot written to {}", dir.join(p.name).display()));
        }
    }
    if ctx.json {
        run.report.measure("file", &name);
        run.measure(r.facts);
        return run.finish();
    }
    outln!("{name}");
    for (k, v) in r.facts.0 {
        if k == "psd" {
            outln!(
                "  {k:22} {} log-binned points (see --json)",
                v["q"].as_array().map_or(0, Vec::len)
            );
        } else {
            outln!("  {k:22} {v}");
        }
    }
    Ok(())
}

pub fn fbm(ctx: &Context, a: &FbmArgs) -> anyhow::Result<()> {
    let out = ctx.output("field.npy")?;
    let p = FourierParams {
        n: a.size,
        hurst: a.hurst,
        modes: a.size / 2,
        rms: a.rms,
        spacing: a.spacing,
    };
    // The FFT synthesis (O(N² log N)); the same field as core's direct sum.
    let h = asperity_analysis::synthesis::fbm(&p, ctx.seed, &ctx.budget)?;
    let mut run = Run::new(ctx, "generate fbm");
    run.height(&out, &h, format!("fBm H={}", a.hurst))?;
    run.report.measure("size", a.size);
    run.report.measure("hurst", a.hurst);
    run.report.measure("rms", a.rms);
    run.note(format!(
        "wrote {} ({}×{}, H = {}, rms {})",
        out.display(),
        a.size,
        a.size,
        a.hurst,
        a.rms
    ));
    run.finish()
}
