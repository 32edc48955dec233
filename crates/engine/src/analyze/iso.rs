//! The ISO stages of a height field's report (issue #56): the S- and
//! L-filters after the F-operator (ISO 16610-21/-61/-71, the scale-limited
//! surface of ISO 25178-2 §3.1.9; see `asperity_analysis::filter`) and the
//! functional parameters of the areal material ratio curve (ISO 25178-2 §4.5
//! and Annex B, ISO 13565-2 on a profile; see `asperity_analysis::functional`),
//! with the Abbott–Firestone plot of the Sk construction.

use asperity_analysis::filter::{self, Specification};
use asperity_analysis::functional::{Functional, MaterialRatioCurve};
use asperity_analysis::profile_elements;
use asperity_core::HeightField;
use asperity_render::plot::{Plot, Series, Style};
use serde_json::{Value, json};

use super::Prepared;
use super::params::{AnalyzeOptions, Filters};
use crate::report::Measurements;
use asperity_core::wording::param;

use crate::error::{Result, invalid};
use crate::plots::NamedPlot;

/// Points of the material ratio curve the report carries (every 1 %).
const CURVE_POINTS: usize = 101;

/// Bytes the filters of `f` hold at once over a field of `points` points.
pub fn filter_bytes(f: &Filters, points: usize, missing: bool) -> u64 {
    if !f.any() {
        return 0;
    }
    let weighted = missing || f.robust;
    (filter::fields_held(f.filter_degree, weighted) * 8 * points) as u64
}

/// The scale-limited surface, what the filters removed and the report's
/// `filter` entry.
pub struct Stage {
    /// The scale-limited surface (missing points stay missing).
    pub surface: HeightField,
    /// What the L-filter removed, with one.
    pub waviness: Option<HeightField>,
    /// What the S-filter removed, with one.
    pub noise: Option<HeightField>,
    /// The report's `filter` entry (`None` without a filter).
    pub facts: Option<Value>,
}

/// Applies the filters of `f` to the form-removed field `levelled`.
pub(super) fn scale_limited(
    levelled: HeightField,
    periodic: bool,
    f: &Filters,
    warnings: &mut Vec<String>,
) -> Result<Stage> {
    if !f.any() {
        return Ok(Stage {
            surface: levelled,
            waviness: None,
            noise: None,
            facts: None,
        });
    }
    let spec = specification(&levelled, periodic, f, warnings)?;
    let parts = filter::scale_limited(&levelled, &spec)?;
    let facts = json!({
        "surface": spec.surface_name(),
        "lambda_s": spec.lambda_s,
        "lambda_c": spec.lambda_c,
        "nesting": f.nesting,
        "S_filter": spec.lambda_s.map(|_| "Gaussian (ISO 16610-61; ISO 16610-21 on a profile)"),
        "L_filter": spec.lambda_c.map(|_| if f.robust {
            "robust Gaussian regression (ISO 16610-71)"
        } else {
            "Gaussian regression (ISO 16610-61; ISO 16610-21 on a profile)"
        }),
        "degree": f.filter_degree,
        "robust_iterations": f.robust.then_some(parts.iterations),
        "periodic": periodic,
        "truncation": "±λ (the weighting function at 6.5e-7 of its peak)",
    });
    Ok(Stage {
        surface: parts.surface,
        waviness: parts.waviness,
        noise: parts.noise,
        facts: Some(facts),
    })
}

/// The nesting indices in use (given, or ISO's defaults for `h`), refused
/// below two sampling intervals for λc, with a warning for a λs under three
/// intervals or a λc beyond the shorter side.
fn specification(
    h: &HeightField,
    periodic: bool,
    f: &Filters,
    warnings: &mut Vec<String>,
) -> Result<Specification> {
    let (default_s, default_c) = filter::default_cutoffs(h);
    let lambda_c = f.lambda_c.or(f.iso_defaults().then_some(default_c));
    // ISO's λs default only where it lies below the λc in use
    let lambda_s = f.lambda_s.or(f
        .iso_defaults()
        .then_some(default_s)
        .filter(|s| lambda_c.is_none_or(|c| *s < c)));
    let [dx, dy] = h.spacing();
    let step = if h.ny() > 1 { dx.max(dy) } else { dx };
    let [lx, ly] = h.extent();
    let side = if h.ny() > 1 { lx.min(ly) } else { lx };
    if let Some(c) = lambda_c.filter(|c| c.is_nan() || *c < 2.0 * step) {
        return Err(invalid(format!(
            "{} = {c} is below two sampling intervals ({}): the L-filter would leave nothing",
            param("lambda_c"),
            2.0 * step
        )));
    }
    if let Some(s) = lambda_s.filter(|s| *s < 3.0 * step) {
        warnings.push(format!(
            "λs = {s} is below three sampling intervals ({}): ISO 25178-3 asks for samples at most λs/3 apart, and the S-filter removes little",
            3.0 * step
        ));
    }
    if let Some(c) = lambda_c.filter(|c| *c > side) {
        warnings.push(format!(
            "λc = {c} exceeds the field's shorter side ({side}): the L-filter removes little beyond the form"
        ));
    }
    Ok(Specification {
        lambda_s,
        lambda_c,
        order: f.filter_degree,
        robust: f.robust,
        periodic,
    })
}

/// [`super::prepare`], then the S- and L-filters of `o`: the prepared field, the
/// report's `filter` entry and the filters' warnings.
pub(super) fn prepare_filtered(
    h: &HeightField,
    o: &AnalyzeOptions,
) -> Result<(Prepared, Option<Value>, Vec<String>)> {
    let mut p = super::prepare(h, o)?;
    let mut warnings = Vec::new();
    let stage = scale_limited(p.levelled, p.periodic, &o.filters, &mut warnings)?;
    p.levelled = stage.surface;
    Ok((p, stage.facts, warnings))
}

/// The functional parameters into the report: at the top for a field, in
/// `profile_x` under their profile names for a profile.
pub(super) fn set_functional(facts: &mut Measurements, functional: &Value, profile: bool) {
    if profile {
        let mut p = facts.get("profile_x").cloned().unwrap_or(json!({}));
        if let (Some(p), Value::Object(mut f)) = (p.as_object_mut(), as_profile(functional)) {
            if let Some(curve) = f.remove("material_ratio") {
                facts.set("material_ratio", curve);
            }
            p.extend(f);
        }
        facts.set("profile_x", p);
    } else if let Some(f) = functional.as_object() {
        for (k, v) in f {
            facts.set(k, v.clone());
        }
    }
}

/// The functional parameters of the measured points of `lv`, named for an
/// areal field (Sk, Vmp, …), with the sampled curve in `material_ratio`.
pub(super) fn functional_facts(
    lv: &HeightField,
    periodic: bool,
    o: &AnalyzeOptions,
) -> Result<Value> {
    let curve = MaterialRatioCurve::of(lv)?;
    let f = Functional::of(&curve);
    let mut v =
        serde_json::to_value(f).map_err(|e| invalid(format!("functional parameters: {e}")))?;
    let c = &f.core;
    let sampled = curve.samples(CURVE_POINTS);
    v["material_ratio"] = json!({
        "mr_percent": sampled.iter().map(|p| p[0]).collect::<Vec<_>>(),
        "height": sampled.iter().map(|p| p[1]).collect::<Vec<_>>(),
        "equivalent_line": {"at_0": c.line_top, "at_100": c.line_bottom, "window_start": c.window_start},
        "Smc": {"2.5": curve.height_at(2.5), "10": curve.height_at(10.0), "50": curve.height_at(50.0), "80": curve.height_at(80.0)},
        "convention": "Smc(mr): the (1 − mr/100) quantile of the heights, linear between order statistics; Sk by the 40 % secant of least gradient (ISO 13565-2, ISO 25178-2 Annex B.1)",
    });
    // Smr(c) and Smc(mr) at the user's values (ISO 25178-2 §4.5.1–4.5.2); on
    // a profile the material length of ISO 21920-2 (the profile drawn
    // straight between samples), which counts each step's length above c
    let profile = (lv.ny() == 1).then(|| lv.data());
    let ratio = |c: f64| match profile {
        Some(z) => profile_elements::material_length_ratio(z, c, periodic),
        None => curve.ratio_at(c),
    };
    let height = |mr: f64| match profile {
        Some(z) => profile_elements::height_at_length_ratio(z, mr, periodic),
        None => curve.height_at(mr),
    };
    if let Some(cs) = &o.material_ratio_at {
        v["Smr_at"] = cs
            .iter()
            .map(|&c| json!({"c": c, "mr_percent": ratio(c)}))
            .collect();
    }
    if let Some(mrs) = &o.height_at_ratio {
        v["Smc_at"] = mrs
            .iter()
            .map(|&mr| json!({"mr_percent": mr, "c": height(mr)}))
            .collect();
    }
    // Rdc (ISO 21920-2, ISO 4287's Rδc): the height between two material
    // length ratios, at RDC_RATIOS; any other pair is the difference of two
    // Rmc values (`--height-at-ratio`). Named the areal way here, as every
    // key of this map; `as_profile` makes it Rdc.
    if profile.is_some() {
        let [mr1, mr2] = RDC_RATIOS;
        v["Sdc"] = json!(height(mr1) - height(mr2));
        v["Sdc_mr_percent"] = json!(RDC_RATIOS);
    }
    if let Some(map) = v.as_object_mut() {
        for key in ["line_top", "line_bottom", "window_start"] {
            map.remove(key);
        }
    }
    Ok(v)
}

/// The material length ratios (%) between which a profile's Rdc is taken: the
/// pair instrument software reports by default (no copy of the standard's own
/// default was at hand; the report states the pair).
pub(super) const RDC_RATIOS: [f64; 2] = [20.0, 80.0];

/// The areal names as a profile's (ISO 21920-2 / ISO 13565-2): Sk → Rk,
/// Smr1 → Rmr1; the volume parameters and Sxp have no profile form here.
pub(super) fn as_profile(v: &Value) -> Value {
    let mut out = serde_json::Map::new();
    if let Some(map) = v.as_object() {
        for (k, x) in map {
            if k.starts_with('V') || k == "Sxp" {
                continue;
            }
            let name = match k.strip_prefix('S') {
                Some(rest) => format!("R{rest}"),
                None => k.clone(),
            };
            out.insert(name, x.clone());
        }
    }
    Value::Object(out)
}

/// The Abbott–Firestone curve with the Sk construction.
pub(super) fn material_ratio_plot(curve: &MaterialRatioCurve, profile: bool) -> NamedPlot {
    let c = curve.core();
    let (k, pk, vk) = if profile {
        ("Rk", "Rpk", "Rvk")
    } else {
        ("Sk", "Spk", "Svk")
    };
    let line = |name: String, points: Vec<(f64, f64)>, style| Series {
        name,
        points,
        style,
    };
    let (top, bottom) = (c.line_top, c.line_bottom);
    let series = vec![
        line(
            "Smc(mr)".into(),
            curve.samples(401).iter().map(|p| (p[0], p[1])).collect(),
            Style::Line,
        ),
        line(
            "equivalent line (40 % secant)".into(),
            vec![(0.0, top), (100.0, bottom)],
            Style::Fit,
        ),
        line(
            format!("{k}: the core between Smr1 and Smr2"),
            vec![(0.0, top), (c.Smr1, top), (c.Smr2, bottom), (100.0, bottom)],
            Style::Fit,
        ),
        line(
            format!("{pk}: peak triangle"),
            vec![(0.0, top + c.Spk), (c.Smr1, top)],
            Style::Fit,
        ),
        line(
            format!("{vk}: dale triangle"),
            vec![(c.Smr2, bottom), (100.0, bottom - c.Svk)],
            Style::Fit,
        ),
    ];
    NamedPlot {
        name: "material_ratio.png",
        plot: Plot {
            title: format!(
                "Material ratio curve: {k} {:.4}, {pk} {:.4}, {vk} {:.4}",
                c.Sk, c.Spk, c.Svk
            ),
            x_label: "material ratio mr (%)".into(),
            y_label: "height c".into(),
            log_x: false,
            log_y: false,
            series,
        },
    }
}
