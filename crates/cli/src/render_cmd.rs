//! `asperity render`: any readable file to PNG (`asperity_engine::render`).

use anyhow::bail;
use asperity_engine::files::numbered;
use asperity_engine::render::render_job;

use crate::cli::RenderArgs;
use crate::context::{Context, Run};

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
    let job = ctx.job_params(a.params.clone(), &a.params_file)?;
    asperity_engine::params::validate(&job.params)?;
    let surface = ctx.load(&a.input)?;
    let mut run = Run::new(ctx, "render");
    run.params(&job.params, job.seed, job.overridden.clone());
    let frames = match a.turntable {
        Some(n) if !job.params.is_map() => n,
        _ => 1,
    };
    asperity_engine::estimate::check_file_count(u64::from(frames), "⟨turntable⟩")?;
    for k in 0..frames {
        let path = if frames > 1 || a.turntable.is_some() && !job.params.is_map() {
            numbered(&out, "", k as u64, 3)
        } else {
            out.clone()
        };
        let t = std::time::Instant::now();
        let img = render_job(&surface, &job.params, (k, frames), (&ctx.budget, &ctx.time))?;
        if !job.params.is_map() {
            run.report
                .measure(&format!("frame_{k}_seconds"), t.elapsed().as_secs_f64());
        }
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
