//! Roughness and topology reports (`asperity analyze`): ISO 25178 and ISO 4287
//! parameters, the PSD with its Hurst exponent and fractal dimensions of a
//! height field; topology and curvature of a mesh; cluster dimensions of a
//! point set — each with the plots that show them.

use asperity_analysis::{AnalysisError, areal, correlation, fractal, level, mesh, psd, scaling};
use asperity_core::{HeightField, PointSet, TriMesh};
use asperity_io::Surface;
use asperity_render::plot::{Series, Style, histogram_plot};
use serde_json::{Value, json};

use crate::error::{Result, ensure, invalid};
use crate::plots::{NamedPlot, log_log, points};
use crate::report::Measurements;

/// How a height field is analysed, named and defaulted like `asperity analyze`.
#[derive(Clone, Debug, PartialEq)]
pub struct AnalyzeOptions {
    /// Reference surface removed first: none, mean, plane, quadratic. Default plane.
    pub level: String,
    /// Log-spaced bins of the radial PSD. Default 40.
    pub bins: usize,
    /// Hurst fit window [q_min, q_max] in rad/length (default: 2·q_min to Nyquist).
    pub fit_window: Option<[f64; 2]>,
    /// Also make the plots.
    pub plots: bool,
}

impl Default for AnalyzeOptions {
    fn default() -> Self {
        Self {
            level: "plane".into(),
            bins: 40,
            fit_window: None,
            plots: false,
        }
    }
}

/// A report and its plots.
#[derive(Clone, Debug, Default)]
pub struct Analysis {
    /// The measurements, with the same keys as `asperity analyze --json`.
    pub facts: Measurements,
    /// PNG plots to write (empty unless asked for; none for point sets).
    pub plots: Vec<NamedPlot>,
    /// The quantities that could not be estimated (their value is `null`) and why.
    pub warnings: Vec<String>,
}

/// Analyses whatever `s` holds; `name` names it in messages.
///
/// # Errors
/// [`crate::EngineError::Invalid`] for an unknown levelling, a bad fit window or
/// too few points; the analysis' own refusals.
pub fn analyze(s: &Surface, name: &str, o: &AnalyzeOptions) -> Result<Analysis> {
    match s {
        Surface::Height(h) => height(h, o),
        Surface::Mesh(m) => mesh_report(m, o.plots),
        Surface::Points(p) => point_report(p, name),
    }
}

/// A fitted dimension, or `null` with a warning naming `what` and why.
fn dimension_json(
    d: Result<fractal::Dimension, AnalysisError>,
    what: &str,
    warnings: &mut Vec<String>,
) -> Value {
    match d {
        Ok(d) => {
            json!({"D": d.d, "fit_range": d.fit.range, "r2": d.fit.r2, "points": d.fit.points})
        }
        Err(e) => {
            warnings.push(format!("{what} not estimated: {e}"));
            Value::Null
        }
    }
}

/// The levelling `o` names, after checking its fit window.
fn levelling(o: &AnalyzeOptions) -> Result<level::Level> {
    let how = level::Level::from_name(&o.level).ok_or_else(|| {
        invalid(format!(
            "unknown levelling {:?} (none, mean, plane, quadratic)",
            o.level
        ))
    })?;
    if let Some(w) = o.fit_window {
        ensure(w[0] > 0.0 && w[1] > w[0], || {
            format!(
                "--fit-window takes QMIN,QMAX with 0 < QMIN < QMAX, got {:?}",
                w.to_vec()
            )
        })?;
    }
    Ok(how)
}

/// The report on a height field.
fn height(h: &HeightField, o: &AnalyzeOptions) -> Result<Analysis> {
    let how = levelling(o)?;
    let lv = level::level(h, how)?;
    let areal = areal::areal(&lv)?;
    let r = psd::radial_psd(&lv, o.bins)?;
    if let Some([lo, hi]) = o.fit_window {
        ensure(
            lo.is_finite() && hi.is_finite() && 0.0 < lo && lo < hi,
            || format!("--fit-window needs 0 < QMIN < QMAX, got [{lo}, {hi}]"),
        )?;
    }
    // Estimates that need more data than a field may have: null and a warning,
    // never a refusal of everything else.
    let mut warnings = Vec::new();
    let hu = psd::hurst(&r, &lv, o.fit_window)
        .map_err(|e| warnings.push(format!("Hurst exponent (PSD fit) not estimated: {e}")))
        .ok();
    let mut facts = Measurements::from_value(
        serde_json::to_value(areal).map_err(|e| invalid(format!("areal parameters: {e}")))?,
    );
    facts.set("kind", "height field");
    facts.set("size", h.dims());
    facts.set("spacing", h.spacing());
    facts.set("levelling", how);
    facts.set("profile_x", areal::profile(&lv, false).ok());
    facts.set("profile_y", areal::profile(&lv, true).ok());
    facts.set("hurst", hu.as_ref().map(|hu| hu.hurst));
    let psd_dimension = hu.as_ref().map(|hu| {
        json!({"D": hu.fractal_dimension, "fit_range": hu.fit.range, "r2": hu.fit.r2, "points": hu.fit.points})
    });
    let triangulation = dimension_json(
        fractal::triangulation(&lv),
        "fractal dimension (triangulation)",
        &mut warnings,
    );
    let partitioning = dimension_json(
        fractal::partitioning(&lv),
        "fractal dimension (partitioning)",
        &mut warnings,
    );
    facts.set(
        "fractal_dimension",
        json!({"psd": psd_dimension, "triangulation": triangulation, "partitioning": partitioning}),
    );
    let sp = correlation::spatial(&lv)
        .map_err(|e| warnings.push(format!("Sal and Str not estimated: {e}")))
        .ok();
    facts.set("Sal", sp.as_ref().map(|s| s.Sal));
    facts.set("Str", sp.as_ref().map(|s| s.Str));
    facts.set("Str_capped", sp.as_ref().map(|s| s.capped));
    facts.set("psd", json!({"q": r.q, "C": r.c, "convention": "C(q) = A/N^2 |DFT|^2 (SurfaceTopography), radially averaged in log bins"}));
    let plots = if o.plots {
        height_plots(&lv, &r, hu.as_ref())?
    } else {
        Vec::new()
    };
    Ok(Analysis {
        facts,
        plots,
        warnings,
    })
}

/// The radial PSD with its Hurst fit.
/// The radial PSD, with its Hurst fit where there is one.
fn psd_plot(r: &psd::RadialPsd, hu: Option<&psd::Hurst>) -> NamedPlot {
    let mut series = vec![points(
        "C(q), log bins",
        r.q.iter().copied().zip(r.c.iter().copied()).collect(),
    )];
    let title = match hu {
        Some(hu) => {
            let fit = &hu.fit;
            let line: Vec<(f64, f64)> = [fit.range[0], fit.range[1]]
                .iter()
                .map(|&q| (q, (fit.intercept + fit.slope * q.ln()).exp()))
                .collect();
            series.push(Series {
                name: format!("fit, slope {:.3} = −2(1 + H)", fit.slope),
                points: line,
                style: Style::Fit,
            });
            format!(
                "Radially averaged PSD: H = {:.3}, D = {:.3} (r² = {:.4})",
                hu.hurst, hu.fractal_dimension, fit.r2
            )
        }
        None => "Radially averaged PSD (too few points for a Hurst fit)".to_string(),
    };
    NamedPlot {
        name: "psd.png",
        plot: log_log(title, "q (rad / length)", "C(q)", series),
    }
}

fn height_plots(
    lv: &HeightField,
    r: &psd::RadialPsd,
    hu: Option<&psd::Hurst>,
) -> Result<Vec<NamedPlot>> {
    let mut out = vec![psd_plot(r, hu)];
    if let Ok(hh) = correlation::hhcf_x(lv) {
        out.push(NamedPlot {
            name: "hhcf.png",
            plot: log_log(
                "Height-height correlation along x".into(),
                "lag τ",
                "H(τ) = ⟨(z(x+τ) − z(x))²⟩",
                vec![points("H(τ)", hh)],
            ),
        });
    }
    out.push(NamedPlot {
        name: "heights.png",
        plot: histogram_plot(lv.data(), 60, "Height distribution (levelled)", "z")?,
    });
    Ok(out)
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

fn curvature_plots(c: &mesh::Curvature) -> Result<Vec<NamedPlot>> {
    let mut out = Vec::new();
    for (name, values, title, x) in [
        (
            "curvature_mean.png",
            &c.mean,
            "Mean curvature per vertex (central 98 %)",
            "H",
        ),
        (
            "curvature_gaussian.png",
            &c.gaussian,
            "Gaussian curvature per vertex (central 98 %)",
            "K",
        ),
    ] {
        let plot = histogram_plot(&central(values), 60, title, x)?;
        out.push(NamedPlot { name, plot });
    }
    Ok(out)
}

/// The report on a mesh: topology, curvature, roughness, box-counting dimension.
fn mesh_report(m: &TriMesh, plots: bool) -> Result<Analysis> {
    let c = mesh::curvature(m);
    let mut warnings = Vec::new();
    let box_counting = match mesh::box_counting(m) {
        Ok(d) => json!({"D": d.d, "fit_range": d.fit.range, "r2": d.fit.r2}),
        Err(e) => {
            warnings.push(format!(
                "fractal dimension (box counting) not estimated: {e}"
            ));
            Value::Null
        }
    };
    let chi = m.euler_characteristic();
    let watertight = m.is_watertight();
    let facts = Measurements::from_value(json!({
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
        "fractal_dimension": {"box_counting": box_counting},
    }));
    Ok(Analysis {
        facts,
        warnings,
        plots: if plots {
            curvature_plots(&c)?
        } else {
            Vec::new()
        },
    })
}

/// The report on a point set (a growth cluster): R_g and two fractal dimensions.
fn point_report(p: &PointSet, name: &str) -> Result<Analysis> {
    ensure(p.len() >= 256, || {
        format!(
            "{name}: {} points are too few for cluster dimensions (need ≥ 256)",
            p.len()
        )
    })?;
    let rg = scaling::radius_of_gyration(p.positions());
    let g = scaling::gyration_dimension(p.positions())?;
    let m = scaling::mass_radius_dimension(p.positions(), 0.05 * rg)?;
    let facts = Measurements::from_value(json!({
        "kind": "point set",
        "points": p.len(),
        "radius_of_gyration": rg,
        "fractal_dimension": {
            "gyration": {"D": g.d, "r2": g.fit.r2, "note": "R_g of the first n points in file order (deposition order)"},
            "mass_radius": {"D": m.d, "fit_range": m.fit.range, "r2": m.fit.r2},
        },
    }));
    Ok(Analysis {
        facts,
        plots: Vec::new(),
        warnings: Vec::new(),
    })
}
