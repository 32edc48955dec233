//! `asperity analyze` and `asperity generate fbm`.

use anyhow::Context as _;
use asperity_analysis::{areal, correlation, fractal, level, mesh, psd, scaling};
use asperity_core::fourier_surface::FourierParams;
use asperity_io::{Surface, WriteOptions};
use asperity_render::plot::{Plot, Series, Style, histogram_plot, plot_png};
use serde_json::{Value, json};

use crate::cli::{AnalyzeArgs, Context, FbmArgs};
use crate::report::Report;

fn height_report(
    h: &asperity_core::HeightField,
    a: &AnalyzeArgs,
    plots: &mut Vec<(&'static str, Plot)>,
) -> anyhow::Result<Value> {
    let how = level::Level::from_name(&a.level).with_context(|| {
        format!(
            "unknown levelling {:?} (none, mean, plane, quadratic)",
            a.level
        )
    })?;
    let lv = level::level(h, how)?;
    let s = areal::areal(&lv)?;
    let px = areal::profile(&lv, false).ok();
    let py = areal::profile(&lv, true).ok();
    let r = psd::radial_psd(&lv, a.bins)?;
    let window = match &a.fit_window {
        Some(w) => {
            anyhow::ensure!(
                w.len() == 2 && w[0] > 0.0 && w[1] > w[0],
                "--fit-window takes QMIN,QMAX with 0 < QMIN < QMAX, got {w:?}"
            );
            Some([w[0], w[1]])
        }
        None => None,
    };
    let hu = psd::hurst(&r, &lv, window)?;
    let mut v = serde_json::to_value(s)?;
    let m = v
        .as_object_mut()
        .context("areal parameters serialise to an object")?;
    m.insert("kind".into(), json!("height field"));
    m.insert("size".into(), json!(h.dims()));
    m.insert("spacing".into(), json!(h.spacing()));
    m.insert("levelling".into(), json!(how));
    m.insert("profile_x".into(), json!(px));
    m.insert("profile_y".into(), json!(py));
    m.insert("hurst".into(), json!(hu.hurst));
    let dim = |d: Result<fractal::Dimension, asperity_analysis::AnalysisError>| match d {
        Ok(d) => {
            json!({"D": d.d, "fit_range": d.fit.range, "r2": d.fit.r2, "points": d.fit.points})
        }
        Err(e) => json!({"error": e.to_string()}),
    };
    m.insert(
        "fractal_dimension".into(),
        json!({
            "psd": {"D": hu.fractal_dimension, "fit_range": hu.fit.range, "r2": hu.fit.r2, "points": hu.fit.points},
            "triangulation": dim(fractal::triangulation(&lv)),
            "partitioning": dim(fractal::partitioning(&lv)),
        }),
    );
    let sp = correlation::spatial(&lv)?;
    m.insert("Sal".into(), json!(sp.Sal));
    m.insert("Str".into(), json!(sp.Str));
    m.insert("Str_capped".into(), json!(sp.capped));
    m.insert("psd".into(), json!({"q": r.q, "C": r.c, "convention": "C(q) = A/N^2 |DFT|^2 (SurfaceTopography), radially averaged in log bins"}));
    if a.plot.is_some() {
        let fit = &hu.fit;
        let line: Vec<(f64, f64)> = [fit.range[0], fit.range[1]]
            .iter()
            .map(|&q| (q, (fit.intercept + fit.slope * q.ln()).exp()))
            .collect();
        plots.push((
            "psd.png",
            Plot {
                title: format!(
                    "Radially averaged PSD: H = {:.3}, D = {:.3} (r² = {:.4})",
                    hu.hurst, hu.fractal_dimension, fit.r2
                ),
                x_label: "q (rad / length)".into(),
                y_label: "C(q)".into(),
                log_x: true,
                log_y: true,
                series: vec![
                    Series {
                        name: "C(q), log bins".into(),
                        points: r.q.iter().copied().zip(r.c.iter().copied()).collect(),
                        style: Style::Points,
                    },
                    Series {
                        name: format!("fit, slope {:.3} = −2(1 + H)", fit.slope),
                        points: line,
                        style: Style::Fit,
                    },
                ],
            },
        ));
        if let Ok(hh) = correlation::hhcf_x(&lv) {
            plots.push((
                "hhcf.png",
                Plot {
                    title: "Height-height correlation along x".into(),
                    x_label: "lag τ".into(),
                    y_label: "H(τ) = ⟨(z(x+τ) − z(x))²⟩".into(),
                    log_x: true,
                    log_y: true,
                    series: vec![Series {
                        name: "H(τ)".into(),
                        points: hh,
                        style: Style::Points,
                    }],
                },
            ));
        }
        plots.push((
            "heights.png",
            histogram_plot(lv.data(), 60, "Height distribution (levelled)", "z")?,
        ));
    }
    Ok(v)
}

/// The finite values between the 1st and 99th percentiles (curvature on rough or
/// fractal meshes has tails that would squash a histogram into one bin).
fn central(values: &[f64]) -> Vec<f64> {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.len() < 100 {
        return v;
    }
    v.sort_by(f64::total_cmp);
    let (lo, hi) = (v[v.len() / 100], v[v.len() - 1 - v.len() / 100]);
    v.retain(|&x| x >= lo && x <= hi);
    v
}

fn mesh_report(
    m: &asperity_core::TriMesh,
    a: &AnalyzeArgs,
    plots: &mut Vec<(&'static str, Plot)>,
) -> anyhow::Result<Value> {
    let c = mesh::curvature(m);
    if a.plot.is_some() {
        plots.push((
            "curvature_mean.png",
            histogram_plot(
                &central(&c.mean),
                60,
                "Mean curvature per vertex (central 98 %)",
                "H",
            )?,
        ));
        plots.push((
            "curvature_gaussian.png",
            histogram_plot(
                &central(&c.gaussian),
                60,
                "Gaussian curvature per vertex (central 98 %)",
                "K",
            )?,
        ));
    }
    let chi = m.euler_characteristic();
    let watertight = m.is_watertight();
    Ok(json!({
        "kind": "mesh",
        "vertices": m.n_vertices(),
        "triangles": m.n_faces(),
        "area": m.area(),
        "volume": if watertight { Some(m.signed_volume()) } else { None },
        "euler_characteristic": chi,
        "genus": m.genus(),
        "boundary_loops": m.boundary_loops().len(),
        "manifold": m.is_manifold(),
        "watertight": watertight,
        "curvature": {
            "mean": mesh::stats(&c.mean, &c.area),
            "gaussian": mesh::stats(&c.gaussian, &c.area),
            "total_gaussian": c.total_gaussian,
            "gauss_bonnet_2pi_chi": 2.0 * std::f64::consts::PI * chi as f64,
        },
        "roughness_vs_smoothed": mesh::smoothed_roughness(m, 10),
        "fractal_dimension": {"box_counting": match mesh::box_counting(m) {
            Ok(d) => json!({"D": d.d, "fit_range": d.fit.range, "r2": d.fit.r2}),
            Err(e) => json!({"error": e.to_string()}),
        }},
    }))
}

pub fn analyze(ctx: &Context, a: &AnalyzeArgs) -> anyhow::Result<()> {
    let mut report = Report::new("analyze", ctx);
    let s = crate::convert::load(ctx, &a.input)?;
    let mut plots = Vec::new();
    let facts = match &s {
        Surface::Height(h) => height_report(h, a, &mut plots)?,
        Surface::Mesh(m) => mesh_report(m, a, &mut plots)?,
        Surface::Points(p) => {
            anyhow::ensure!(
                p.len() >= 256,
                "{}: {} points are too few for cluster dimensions (need ≥ 256)",
                a.input.display(),
                p.len()
            );
            let rg = scaling::radius_of_gyration(p.positions());
            let g = scaling::gyration_dimension(p.positions())?;
            let m = scaling::mass_radius_dimension(p.positions(), 0.05 * rg)?;
            json!({
                "kind": "point set",
                "points": p.len(),
                "radius_of_gyration": rg,
                "fractal_dimension": {
                    "gyration": {"D": g.d, "r2": g.fit.r2, "note": "R_g of the first n points in file order (deposition order)"},
                    "mass_radius": {"D": m.d, "fit_range": m.fit.range, "r2": m.fit.r2},
                },
            })
        }
    };
    if let Some(dir) = &a.plot {
        if plots.is_empty() {
            ctx.note("no plots for point sets (growth commands plot R_g(n) and ρ(z) with --plot)");
        }
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create plot directory {}", dir.display()))?;
        for (name, plot) in &plots {
            let path = dir.join(name);
            asperity_io::write_png(&path, &plot_png(plot, 900, 640)?)?;
            report.output(&path);
            ctx.note(format!("plot written to {}", path.display()));
        }
    }
    if ctx.json {
        report.measure("file", a.input.display().to_string());
        if let Value::Object(map) = facts {
            report.measurements.extend(map);
        }
        return report.finish(ctx);
    }
    outln!("{}", a.input.display());
    if let Value::Object(map) = facts {
        for (k, v) in map {
            if k == "psd" {
                outln!(
                    "  {k:22} {} log-binned points (see --json)",
                    v["q"].as_array().map_or(0, Vec::len)
                );
            } else {
                outln!("  {k:22} {v}");
            }
        }
    }
    Ok(())
}

pub fn fbm(ctx: &Context, a: &FbmArgs) -> anyhow::Result<()> {
    let out = ctx
        .output
        .clone()
        .context("no output file: give -o field.npy")?;
    let p = FourierParams {
        n: a.size,
        hurst: a.hurst,
        modes: a.size / 2,
        rms: a.rms,
        spacing: a.spacing,
    };
    // The FFT synthesis (O(N² log N)); the same field as core's direct sum.
    let h = asperity_analysis::synthesis::fbm(&p, ctx.seed, &ctx.budget)?;
    asperity_io::write_height(
        &out,
        &h,
        &WriteOptions {
            title: format!("fBm H={}", a.hurst),
            ..WriteOptions::default()
        },
    )?;
    let mut r = Report::new("generate fbm", ctx);
    r.output(&out);
    r.measure("size", a.size);
    r.measure("hurst", a.hurst);
    r.measure("rms", a.rms);
    ctx.note(format!(
        "wrote {} ({}×{}, H = {}, rms {})",
        out.display(),
        a.size,
        a.size,
        a.hurst,
        a.rms
    ));
    r.finish(ctx)
}
