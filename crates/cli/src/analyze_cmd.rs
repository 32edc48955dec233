//! `asperity analyze` and `asperity generate fbm`.

use anyhow::Context as _;
use asperity_analysis::{areal, correlation, fractal, level, mesh, psd, scaling};
use asperity_core::fourier_surface::{FourierParams, fourier_surface};
use asperity_io::{Surface, WriteOptions};
use serde_json::{Value, json};

use crate::cli::{AnalyzeArgs, Context, FbmArgs};
use crate::report::Report;

fn height_report(h: &asperity_core::HeightField, a: &AnalyzeArgs) -> anyhow::Result<Value> {
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
    Ok(v)
}

fn mesh_report(m: &asperity_core::TriMesh) -> Value {
    let c = mesh::curvature(m);
    let chi = m.euler_characteristic();
    let watertight = m.is_watertight();
    json!({
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
    })
}

pub fn analyze(ctx: &Context, a: &AnalyzeArgs) -> anyhow::Result<()> {
    let mut report = Report::new("analyze", ctx);
    let s = crate::convert::load(ctx, &a.input)?;
    let facts = match &s {
        Surface::Height(h) => height_report(h, a)?,
        Surface::Mesh(m) => mesh_report(m),
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
    let h = fourier_surface(&p, ctx.seed, &ctx.budget)?;
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
