//! Roughness and topology reports (`asperity analyze`): ISO 25178 and ISO 4287
//! parameters, the PSD with its Hurst exponent and fractal dimensions of a
//! height field; topology and curvature of a mesh; cluster dimensions of a
//! point set — each with the plots that show them.

use asperity_analysis::spectrum::PowerSpectrum;
use asperity_analysis::window::{self, Window};
use asperity_analysis::{AnalysisError, areal, correlation, fill, fractal, hurst, level, psd};
use asperity_core::{HeightField, MemoryBudget};
use asperity_io::Surface;
use asperity_render::plot::{Series, Style, histogram_plot};
use serde_json::{Value, json};

use crate::error::{Result, ensure, invalid};
use crate::plots::{NamedPlot, log_log, points};
use crate::report::Measurements;

mod features;
mod mesh_report;
use mesh_report::{mesh_report, point_report};
mod filter_job;
mod iso;
mod params;

pub use features::NamedImage;
pub use filter_job::{FilterParams, Filtered, filter, filter_bytes as filter_job_bytes};
pub use iso::filter_bytes;
pub use params::{
    AnalyzeOptions, AnalyzeParams, FillChoice, Filters, HurstChoice, Level, Nesting, Periodic,
};

/// A report and its plots.
#[derive(Clone, Debug, Default)]
pub struct Analysis {
    /// The measurements, with the same keys as `asperity analyze --json`.
    pub facts: Measurements,
    /// PNG plots to write (empty unless asked for; none for point sets).
    pub plots: Vec<NamedPlot>,
    /// Pictures to write with the plots (the feature segmentation's maps).
    pub images: Vec<NamedImage>,
    /// The quantities that could not be estimated (their value is `null`) and why.
    pub warnings: Vec<String>,
}

/// Analyses whatever `s` holds; `name` names it in messages.
///
/// # Errors
/// [`crate::EngineError::Invalid`] for an unknown levelling, a bad fit window or
/// too few points; the analysis' own refusals.
pub fn analyze(
    s: &Surface,
    name: &str,
    o: &AnalyzeOptions,
    budget: &MemoryBudget,
) -> Result<Analysis> {
    match s {
        Surface::Height(h) => {
            let filters = filter_bytes(&o.filters, h.len(), h.has_missing());
            budget.check(height_bytes(h) + filters, format!("analysing {name}"))?;
            height(h, o)
        }
        Surface::Mesh(m) => mesh_report(m, o.plots),
        Surface::Points(p) => point_report(p, name),
    }
}

/// Bytes an analysis of `h` allocates at its peak: some nine grids of its
/// size (the levelled and windowed copies, the spectrum, the correlation and
/// scale-dependent estimators' work, the material ratio curve's sorted
/// heights, the ACF of non-periodic data padded to four times the field),
/// and twenty more where points are
/// missing (the harmonic fill's conjugate-gradient vectors and multigrid
/// levels). Measured peak RSS over this, less the process's 20 MiB at rest
/// (`crates/benches/scripts/estimate_honesty.py`): 1.2–1.5 at 512²–2048²,
/// 1.0 with half the points missing.
pub fn height_bytes(h: &HeightField) -> u64 {
    let per_point = if h.has_missing() { 176 + 160 } else { 176 };
    h.len() as u64 * per_point
}

/// A dimension whose standard error exceeds this is reported as unreliable
/// (null with a warning): at 256² and H = 0.9 box variances scatter by ±0.1
/// from surface to surface, and the stated error tracks that scatter.
pub const UNRELIABLE_STDERR: f64 = 0.03;

/// A model-based dimension, or `null` with a warning naming `what` and why
/// (no fit, a fit at the edge of the range, r² below 0.9 or a standard error
/// above [`UNRELIABLE_STDERR`]).
fn dimension_json(
    d: Result<fractal::ModelDimension, AnalysisError>,
    what: &str,
    warnings: &mut Vec<String>,
) -> Value {
    let d = d.and_then(|d| {
        if d.fit.at_bound || d.fit.r2.is_nan() || d.fit.r2 < 0.9 {
            Err(AnalysisError::BadInput(format!(
                "the fit is poor (H = {:.3}, r² = {:.3})",
                d.fit.hurst, d.fit.r2
            )))
        } else if d.fit.stderr.is_nan() || d.fit.stderr > UNRELIABLE_STDERR {
            Err(AnalysisError::BadInput(format!(
                "the fit is too uncertain (D = {:.3} ± {:.3}; the largest scales hold too few independent modes)",
                d.d, d.fit.stderr
            )))
        } else {
            Ok(d)
        }
    });
    match d {
        Ok(d) => json!({
            "D": d.d, "fit_range": d.fit_range, "r2": d.fit.r2, "points": d.fit.points,
            "stderr": d.fit.stderr,
            "clarke_D": d.clarke,
        }),
        Err(e) => {
            warnings.push(format!("{what} not estimated: {e}"));
            Value::Null
        }
    }
}

/// How the field was prepared: periodicity, levelling, window.
#[derive(Clone, Debug)]
struct Prepared {
    levelled: HeightField,
    periodic: bool,
    /// "option" or "detected".
    source: &'static str,
    /// The edge-jump ratio behind a detection.
    ratio: Option<f64>,
    level: level::Level,
    /// The window applied to spectra (none for periodic data).
    window: Window,
}

/// The levelling and window `o` names, after checking its fit window.
fn parse_options(o: &AnalyzeOptions) -> Result<(Option<level::Level>, Window)> {
    let how = match o.level.as_str() {
        "auto" => None,
        name => Some(level::Level::from_name(name).ok_or_else(|| {
            invalid(format!(
                "unknown levelling {name:?} (auto, none, mean, slope, plane, quadratic)"
            ))
        })?),
    };
    let window = Window::from_name(&o.window).ok_or_else(|| {
        invalid(format!(
            "unknown window {:?} (hann, kaiser, kaiser:BETA, blackman-harris, none)",
            o.window
        ))
    })?;
    if let Some(w) = o.fit_window {
        ensure(
            w[0].is_finite() && w[1].is_finite() && w[0] > 0.0 && w[1] > w[0],
            || {
                format!(
                    "⟨fit_window⟩ takes QMIN,QMAX with 0 < QMIN < QMAX, got {:?}",
                    w.to_vec()
                )
            },
        )?;
    }
    Ok((how, window))
}

/// Below this many rows the edge test is not repeated after removing the mean
/// slope (see [`prepare`]).
const MIN_ROWS_FOR_TILT_TEST: usize = 16;

/// Decides periodicity and levelling (see [`AnalyzeOptions`]) and levels `h`.
fn prepare(h: &HeightField, o: &AnalyzeOptions) -> Result<Prepared> {
    let (how, window) = parse_options(o)?;
    h.validate()?;
    let below = |r: Option<f64>| r.is_some_and(|r| r < window::PERIODIC_BELOW);
    // The slope-levelled field of the tilt test, kept when it is the answer.
    let mut slope_levelled = None;
    let (periodic, source, ratio, auto_level) = match o.periodic {
        Some(true) => (true, "option", None, level::Level::Slope),
        Some(false) => (false, "option", None, level::Level::Plane),
        None => {
            let raw = window::edge_ratio(h);
            if below(raw) {
                (true, "detected", raw, level::Level::Mean)
            } else if h.ny() < MIN_ROWS_FOR_TILT_TEST {
                // Removing the mean slope closes a profile's end-to-end step
                // exactly (and nearly so with few rows): no test of a tilted
                // periodic profile is possible; --periodic yes says it.
                (false, "detected", raw, level::Level::Plane)
            } else {
                let s = level::level(h, level::Level::Slope)?;
                let tilted = window::edge_ratio(&s);
                slope_levelled = Some(s);
                if below(tilted) {
                    (true, "detected", tilted, level::Level::Slope)
                } else {
                    (false, "detected", raw, level::Level::Plane)
                }
            }
        }
    };
    let level = how.unwrap_or(auto_level);
    let levelled = match slope_levelled {
        Some(s) if level == level::Level::Slope => s,
        _ => level::level(h, level)?,
    };
    Ok(Prepared {
        levelled,
        periodic,
        source,
        ratio,
        level,
        window: if periodic { Window::None } else { window },
    })
}

/// The report on a height field (or a profile, when it has one row).
fn height(h: &HeightField, o: &AnalyzeOptions) -> Result<Analysis> {
    h.validate_measured()?;
    if h.has_missing() {
        return holed(h, o);
    }
    let (lo, hi) = h.min_max();
    if lo == hi {
        return Ok(constant(h, lo));
    }
    let (p, filtered, filter_warnings) = iso::prepare_filtered(h, o)?;
    let lv = &p.levelled;
    let profile = h.ny() == 1;
    let w = (p.window != Window::None).then(|| {
        if profile {
            p.window.profile(h.nx())
        } else {
            let [dx, dy] = h.spacing();
            p.window
                .radial(h.dims(), [h.nx() as f64 * dx, h.ny() as f64 * dy])
        }
    });
    // The parameters and the spectrum at once, then every estimate that
    // needs the spectrum's fit range beside the ones that do not: each part
    // on its own, so the report is the same whatever the thread count.
    let ((facts, motifs), spectrum) = rayon::join(
        || {
            rayon::join(
                || parameters(h, &p, o),
                || features::segment(lv, p.periodic, o),
            )
        },
        || PowerSpectrum::of(lv, w.as_deref()),
    );
    let (mut facts, r, motifs) = (
        facts?,
        psd::radial_from_spectrum(&spectrum, o.bins)?,
        motifs?,
    );
    let images = set_features(&mut facts, lv, motifs.as_ref(), o)?;
    if let Some(f) = filtered {
        facts.set("filter", f);
    }
    // Estimates that need more data than a field may have: null and a warning,
    // never a refusal of everything else.
    let psd_fit = psd::hurst(&r, o.fit_window);
    let hu = psd_fit.as_ref().ok();
    let models = o.estimators == hurst::Which::All && !profile;
    let ((estimates, dimensions), (spatial, scale)) = rayon::join(
        || {
            rayon::join(
                || {
                    let mut warnings = Vec::new();
                    let e = estimates_json(&p, &r, &psd_fit, o.estimators, &mut warnings);
                    (e, warnings)
                },
                || models.then(|| model_dimensions(lv, p.periodic)),
            )
        },
        || {
            rayon::join(
                || {
                    // Without a window the PSD's spectrum is the ACF's too.
                    (!profile).then(|| match w {
                        None => correlation::spatial_from_spectrum(&spectrum),
                        Some(_) => correlation::spatial_open(lv),
                    })
                },
                || hurst::scale_dependent(lv, p.periodic),
            )
        },
    );
    let (estimates, mut warnings) = estimates;
    warnings.extend(filter_warnings);
    facts.set("hurst", hu.map(|hu| hu.hurst));
    facts.set("hurst_estimates", estimates);
    let psd_dimension = hu.map(|hu| {
        json!({"D": hu.fractal_dimension, "fit_range": hu.fit.range, "r2": hu.fit.r2, "points": hu.fit.points, "stderr": hu.stderr})
    });
    if profile {
        facts.set("fractal_dimension", json!({"psd": psd_dimension}));
    } else {
        let mut d = json!({"psd": psd_dimension});
        if let Some((triangulation, partitioning)) = dimensions {
            d["triangulation"] = dimension_json(
                triangulation,
                "fractal dimension (triangulation)",
                &mut warnings,
            );
            d["partitioning"] = dimension_json(
                partitioning,
                "fractal dimension (partitioning)",
                &mut warnings,
            );
        }
        facts.set("fractal_dimension", d);
        let sp = spatial
            .expect("a height field has a spatial correlation")
            .map_err(|e| warnings.push(format!("Sal and Str not estimated: {e}")))
            .ok();
        facts.set("Sal", sp.as_ref().map(|s| s.Sal));
        facts.set("Str", sp.as_ref().map(|s| s.Str));
        facts.set("Str_capped", sp.as_ref().map(|s| s.capped));
        let direction = asperity_analysis::texture::texture_direction(&spectrum);
        facts.set("Std", direction.map(|t| t.Std));
    }
    facts.set("scale_dependent", &scale);
    facts.set("psd", psd_json(&r, p.window, profile));
    let plots = if o.plots {
        height_plots(lv, &r, hu, &scale)?
    } else {
        Vec::new()
    };
    Ok(Analysis {
        facts,
        plots,
        images,
        warnings,
    })
}

/// The feature parameters into the report, and their maps when plots are asked for.
fn set_features(
    facts: &mut Measurements,
    lv: &HeightField,
    motifs: Option<&asperity_analysis::feature::Features>,
    o: &AnalyzeOptions,
) -> Result<Vec<NamedImage>> {
    let Some(f) = motifs else {
        return Ok(Vec::new());
    };
    if let Value::Object(map) = features::facts(f, o)? {
        for (k, v) in map {
            facts.set(&k, v);
        }
    }
    Ok(if o.plots {
        features::maps(lv, f)
    } else {
        Vec::new()
    })
}

/// The F-operator on a field with missing points: levelled over its measured
/// points, a plane unless asked otherwise, and not periodic unless said
/// (measured data are not periodic). The levelled field, the levelling and
/// the periodicity.
fn level_holed(h: &HeightField, o: &AnalyzeOptions) -> Result<(HeightField, level::Level, bool)> {
    let how = parse_options(o)?.0.unwrap_or(level::Level::Plane);
    Ok((level::level(h, how)?, how, o.periodic.unwrap_or(false)))
}

/// The report on a field with missing points: levelled over its measured
/// points (a plane unless asked otherwise: measured data are not periodic),
/// its height parameters over the measured points alone, everything else on
/// the levelled field with its holes filled (`o.fill`).
fn holed(h: &HeightField, o: &AnalyzeOptions) -> Result<Analysis> {
    let missing = h.missing_count();
    let Some(how) = o.fill else {
        return Err(asperity_core::CoreError::MissingPoints {
            missing,
            total: h.len(),
            what: "analyze --fill refuse".into(),
        }
        .into());
    };
    let (levelled, level_how, periodic) = level_holed(h, o)?;
    let mut filter_warnings = Vec::new();
    let stage = iso::scale_limited(levelled, periodic, &o.filters, &mut filter_warnings)?;
    let (levelled, filtered) = (stage.surface, stage.facts);
    let heights = areal::measured_heights(&levelled)?;
    let functional = iso::functional_facts(&levelled, periodic, o)?;
    let (filled, report) = fill::fill_missing(&levelled, how)?;
    let inner = AnalyzeOptions {
        level: "none".into(),
        periodic: Some(periodic),
        filters: Filters::NONE,
        ..o.clone()
    };
    let mut a = height(&filled, &inner)?;
    a.warnings.extend(filter_warnings);
    let profile = h.ny() == 1;
    iso::set_functional(&mut a.facts, &functional, profile);
    // motifs end at missing points: segmented on the field with its holes
    let motifs = features::segment(&levelled, periodic, o)?;
    a.images = set_features(&mut a.facts, &levelled, motifs.as_ref(), o)?;
    if let Some(f) = filtered {
        a.facts.set("filter", f);
    }
    let prefix = if profile { "R" } else { "S" };
    let values = [
        ("a", heights.Sa),
        ("q", heights.Sq),
        ("p", heights.Sp),
        ("v", heights.Sv),
        ("z", heights.Sz),
        ("sk", heights.Ssk),
        ("ku", heights.Sku),
    ];
    if profile {
        let mut p = a.facts.get("profile_x").cloned().unwrap_or(Value::Null);
        for (k, v) in values {
            p[format!("{prefix}{k}")] = json!(v);
        }
        a.facts.set("profile_x", p);
    } else {
        for (k, v) in values {
            a.facts.set(&format!("{prefix}{k}"), v);
        }
    }
    if a.facts.get("periodic").is_some() {
        // Not for a constant field's report, which has no mode.
        a.facts.set("levelling", level_how);
        let source = if o.periodic.is_some() {
            "option"
        } else {
            "missing points"
        };
        a.facts.set(
            "periodic",
            json!({"value": periodic, "source": source, "edge_ratio": null}),
        );
    }
    let fraction = missing as f64 / h.len() as f64;
    a.facts.set(
        "missing",
        json!({"count": missing, "total": h.len(), "fraction": fraction,
            "fill": how.name(), "fill_iterations": report.iterations,
            "heights_over": "measured points (Sa, Sq, Sp, Sv, Sz, Ssk, Sku)",
            "filled_for": "slopes, Sdr, profiles, spectra, correlations, Hurst estimators, dimensions"}),
    );
    a.warnings.push(format!(
        "{missing} of {} points ({:.2} %) were not measured: the height parameters are over the \
         measured points, everything else on the field with them filled ({} fill)",
        h.len(),
        100.0 * fraction,
        how.name()
    ));
    Ok(a)
}

/// The model-based fractal dimensions (triangulation, partitioning) at once.
#[allow(clippy::type_complexity)]
fn model_dimensions(
    lv: &HeightField,
    periodic: bool,
) -> (
    std::result::Result<fractal::ModelDimension, AnalysisError>,
    std::result::Result<fractal::ModelDimension, AnalysisError>,
) {
    rayon::join(
        || fractal::triangulation(lv, periodic),
        || fractal::partitioning(lv),
    )
}

/// The report of a constant field z = `c`: every height, slope and area
/// parameter is 0 (Sdr too: the surface is its own projection); skewness,
/// kurtosis, spectra, Hurst exponents, dimensions and correlation lengths are
/// undefined — null, with one warning saying why.
fn constant(h: &HeightField, c: f64) -> Analysis {
    let profile = h.ny() == 1;
    let zeros = |p: &str| {
        let mut m = serde_json::Map::new();
        for k in ["a", "q", "p", "v", "z", "dq"] {
            m.insert(format!("{p}{k}"), json!(0.0));
        }
        m.insert(format!("{p}sk"), Value::Null);
        m.insert(format!("{p}ku"), Value::Null);
        Value::Object(m)
    };
    let mut facts = if profile {
        let mut f = Measurements::from_value(json!({"kind": "profile"}));
        f.set("profile_x", zeros("R"));
        f
    } else {
        let mut f = Measurements::from_value(zeros("S"));
        f.set("Sdr", 0.0);
        f.set("kind", "height field");
        f.set("profile_x", zeros("R"));
        f.set("profile_y", zeros("R"));
        f.set("Sal", Value::Null);
        f.set("Str", Value::Null);
        f
    };
    facts.set("size", h.dims());
    facts.set("spacing", h.spacing());
    facts.set("units", units_json(h));
    facts.set("constant", c);
    facts.set("hurst", Value::Null);
    facts.set("hurst_estimates", Value::Null);
    facts.set("fractal_dimension", Value::Null);
    Analysis {
        facts,
        images: Vec::new(),
        plots: Vec::new(),
        warnings: vec![format!(
            "the height field is constant (z = {c}): its height, slope and area parameters are 0; skewness, kurtosis, the spectrum, Hurst exponents and dimensions are undefined (null)"
        )],
    }
}

/// The mode (periodicity, levelling, window) and the ISO 25178 / ISO 4287
/// parameters of the levelled field.
fn parameters(h: &HeightField, p: &Prepared, o: &AnalyzeOptions) -> Result<Measurements> {
    let lv = &p.levelled;
    let mut facts = if h.ny() == 1 {
        let mut f = Measurements::from_value(json!({"kind": "profile"}));
        f.set("profile_x", areal::profile(lv, false, p.periodic)?);
        f
    } else {
        let mut f = Measurements::from_value(
            serde_json::to_value(areal::areal(lv, p.periodic)?)
                .map_err(|e| invalid(format!("areal parameters: {e}")))?,
        );
        f.set("kind", "height field");
        f.set("profile_x", areal::profile(lv, false, p.periodic).ok());
        f.set("profile_y", areal::profile(lv, true, p.periodic).ok());
        f
    };
    iso::set_functional(
        &mut facts,
        &iso::functional_facts(lv, p.periodic, o)?,
        h.ny() == 1,
    );
    facts.set("size", h.dims());
    facts.set("spacing", h.spacing());
    facts.set("units", units_json(h));
    facts.set(
        "periodic",
        json!({"value": p.periodic, "source": p.source, "edge_ratio": p.ratio}),
    );
    facts.set("levelling", p.level);
    facts.set("window", p.window.name());
    Ok(facts)
}

/// Every Hurst estimator by name (null with a warning where it failed), and a
/// warning when they disagree.
fn estimates_json(
    p: &Prepared,
    r: &psd::RadialPsd,
    psd_fit: &std::result::Result<psd::Hurst, AnalysisError>,
    which: hurst::Which,
    warnings: &mut Vec<String>,
) -> Value {
    let setup = hurst::Setup {
        periodic: p.periodic,
        window: p.window,
    };
    let estimates = hurst::estimate(&p.levelled, setup, r, psd_fit, which);
    let mut all = serde_json::Map::new();
    for (name, e) in &estimates {
        all.insert(
            (*name).into(),
            match e {
                Ok(e) => json!(e),
                Err(err) => {
                    warnings.push(format!("Hurst exponent ({name}) not estimated: {err}"));
                    Value::Null
                }
            },
        );
    }
    if let Some(s) = hurst::spread(&estimates).filter(|s| *s > hurst::DISAGREEMENT) {
        warnings.push(format!(
            "the Hurst estimators disagree by {s:.2} (more than {}): the surface may not be self-affine over the fit range, or be anisotropic (compare psd_x and psd_y)",
            hurst::DISAGREEMENT
        ));
    }
    Value::Object(all)
}

/// The radial (or profile) PSD with its bins and convention.
fn psd_json(r: &psd::RadialPsd, window: Window, profile: bool) -> Value {
    json!({
        "q": r.q, "C": r.c, "modes": r.modes, "q_edges": r.edges,
        "window": window.name(),
        "convention": if profile {
            "C(q) = L/N^2 |DFT(w h)|^2 (SurfaceTopography), log bins"
        } else {
            "C(q) = A/N^2 |DFT(w h)|^2 (SurfaceTopography), radially averaged in log bins"
        },
    })
}

/// The scale-dependent rms height, slope and curvature on one log–log plot.
fn scale_plot(s: &hurst::ScaleDependent) -> NamedPlot {
    let pairs = |x: &[f64], y: &[f64]| x.iter().copied().zip(y.iter().copied()).collect();
    let curvature: Vec<(f64, f64)> = s
        .distance
        .iter()
        .zip(&s.rms_curvature)
        .filter_map(|(d, c)| c.map(|c| (*d, c)))
        .collect();
    NamedPlot {
        name: "scale_dependent.png",
        plot: log_log(
            "Scale-dependent rms height, slope and curvature".into(),
            "scale (length)",
            "rms value",
            vec![
                points(
                    "rms height (variable bandwidth)",
                    pairs(&s.bandwidth, &s.rms_height),
                ),
                points("rms slope", pairs(&s.distance, &s.rms_slope)),
                points("rms curvature", curvature),
            ],
        ),
    }
}

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
    scale: &hurst::ScaleDependent,
) -> Result<Vec<NamedPlot>> {
    let curve = asperity_analysis::functional::MaterialRatioCurve::of(lv)?;
    let mut out = vec![
        psd_plot(r, hu),
        scale_plot(scale),
        iso::material_ratio_plot(&curve, lv.ny() == 1),
    ];
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

/// A height field's units as the reports give them: `{"xy": "µm", "z": "nm"}`
/// (`"none"` for unitless data). Lengths and heights in a report are in
/// these units; derived quantities follow (Sq in z units, Sdq as z per xy…).
pub fn units_json(h: &HeightField) -> Value {
    let u = h.units();
    serde_json::json!({"xy": u.xy.to_string(), "z": u.z.to_string()})
}
