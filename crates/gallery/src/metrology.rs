//! Metrology the ISO way (issue #56; not a paper's method): a measured-like
//! surface through the ISO 16610 filters, its material ratio curve with the
//! Sk construction, and its feature segmentation — each card from the
//! engine's `filter` and `analyze` jobs, as the CLI and Python run them.

use asperity_engine::Result;
use asperity_engine::analyze::{AnalyzeParams, FilterParams, analyze, filter};
use asperity_engine::core::HeightField;
use asperity_engine::io::Surface;
use asperity_engine::methods::render::plot::plot_png;
use asperity_engine::methods::render::{ColorMap, hillshade};
use asperity_engine::synthesis::{FbmParams, fbm};
use serde_json::{Value, json};

use crate::{Env, Item, Section, fact};

/// The section.
///
/// # Errors
/// The jobs' and the writers' errors.
pub fn section(env: &Env) -> Result<Section> {
    let n = if env.quick { 128 } else { 384 };
    let p = FbmParams {
        size: n,
        hurst: 0.8,
        rms: 1.0,
        ..FbmParams::DEFAULT
    };
    let periodic = fbm(&p, env.seed, &env.budget)?;
    // a crop, as a measurement is: not periodic, with a tilt
    let m = n * 3 / 4;
    let data = (0..m * m)
        .map(|k| periodic.data()[(k / m) * n + k % m] + 0.004 * (k % m) as f64)
        .collect();
    let h = HeightField::from_vec([m, m], data)?;
    Ok(Section {
        title: "Metrology: ISO 16610 filters and ISO 25178-2 parameters".into(),
        source: "asperity-analysis (filter, functional, feature), asperity-engine (analyze, filter)".into(),
        blurb: "A crop of a self-affine surface, tilted as a measurement is, taken through the F-operator and the Gaussian \
                S- and L-filters (ISO 16610-61, nesting indices from ISO 25178-3's series), then the areal material ratio \
                curve with the Sk construction (ISO 13565-2) and the watershed segmentation into hills with Wolf pruning \
                (ISO 25178-2 clause 5). The parameters agree with surfalize's (python/tests/reference/check_iso.py)."
            .into(),
        items: [components(env, &h)?, report_cards(env, &h)?].concat(),
    })
}

/// The input, the S-L surface and the waviness the L-filter removed.
fn components(env: &Env, h: &HeightField) -> Result<Vec<Item>> {
    let p: FilterParams = serde_json::from_value(json!({"nesting": "iso"}))
        .map_err(|e| asperity_engine::error::invalid(e.to_string()))?;
    let f = filter(h, &p, &env.budget)?;
    let spec = serde_json::to_value(&f.facts).unwrap_or(Value::Null);
    let mut items = Vec::new();
    for (name, title, field) in [
        (
            "metrology_input",
            "The input: a tilted, non-periodic crop",
            h,
        ),
        (
            "metrology_surface",
            "The S-L surface (form, waviness and noise removed)",
            &f.surface,
        ),
    ] {
        let picture = env.picture(
            &format!("{name}.png"),
            &hillshade::height_map(field, ColorMap::Viridis, 0.5, true),
        )?;
        let file = env.write(&format!("{name}.npy"), &Surface::Height(field.clone()))?;
        items.push(Item::new(title, Some(picture), vec![file], vec![]));
    }
    if let Some(w) = &f.waviness {
        let picture = env.picture(
            "metrology_waviness.png",
            &hillshade::height_map(w, ColorMap::Viridis, 0.5, true),
        )?;
        items.push(Item::new(
            "The waviness the L-filter removed",
            Some(picture),
            vec![],
            vec![
                fact("λs", &spec["filter"]["lambda_s"]),
                fact("λc", &spec["filter"]["lambda_c"]),
                fact("Sq: input, surface, waviness", format!(
                    "{:.4}, {:.4}, {:.4}",
                    spec["Sq"]["input"].as_f64().unwrap_or(f64::NAN),
                    spec["Sq"]["surface"].as_f64().unwrap_or(f64::NAN),
                    spec["Sq"]["waviness"].as_f64().unwrap_or(f64::NAN)
                )),
                fact("CLI", "asperity filter IN.npy surface.npy --nesting iso --waviness waviness.npy --form form.npy"),
            ],
        ));
    }
    Ok(items)
}

/// The material ratio curve and the hill segmentation of the S-L surface.
fn report_cards(env: &Env, h: &HeightField) -> Result<Vec<Item>> {
    let p: AnalyzeParams = serde_json::from_value(json!({"nesting": "iso", "hurst": "psd"}))
        .map_err(|e| asperity_engine::error::invalid(e.to_string()))?;
    let a = analyze(
        &Surface::Height(h.clone()),
        "gallery",
        &p.options(true),
        &env.budget,
    )?;
    let m = serde_json::to_value(&a.facts).unwrap_or(Value::Null);
    let number = |k: &str| m[k].as_f64().map_or("–".to_owned(), |v| format!("{v:.4}"));
    let mut items = Vec::new();
    if let Some(curve) = a.plots.iter().find(|p| p.name == "material_ratio.png") {
        let img = plot_png(&curve.plot, 900, 640)
            .map_err(|e| asperity_engine::error::invalid(e.to_string()))?;
        let picture = env.picture("metrology_material_ratio.png", &img)?;
        items.push(Item::new(
            "Material ratio curve with the Sk construction",
            Some(picture),
            vec![],
            vec![
                fact(
                    "Sk, Spk, Svk",
                    format!("{}, {}, {}", number("Sk"), number("Spk"), number("Svk")),
                ),
                fact(
                    "Smr1, Smr2 (%)",
                    format!("{}, {}", number("Smr1"), number("Smr2")),
                ),
                fact("Vmp, Vvv", format!("{}, {}", number("Vmp"), number("Vvv"))),
                fact(
                    "CLI",
                    "asperity analyze IN.npy --nesting iso --plot plots --json",
                ),
            ],
        ));
    }
    if let Some(hills) = a.images.iter().find(|i| i.name == "hills.png") {
        let picture = env.picture("metrology_hills.png", &hills.image)?;
        let features = &m["features"]["hills"];
        items.push(Item::new(
            "Hills by watershed and Wolf pruning (grey: touching the edge, left out)",
            Some(picture),
            vec![],
            vec![
                fact(
                    "hills before / after pruning",
                    format!(
                        "{} / {}",
                        features["before_pruning"], features["significant"]
                    ),
                ),
                fact("Spd", number("Spd")),
                fact(
                    "S5p, S5v, S10z",
                    format!("{}, {}, {}", number("S5p"), number("S5v"), number("S10z")),
                ),
                fact("Sha, Shv", format!("{}, {}", number("Sha"), number("Shv"))),
                fact(
                    "CLI",
                    "asperity analyze IN.npy --nesting iso --pruning 5 --plot plots",
                ),
            ],
        ));
    }
    env.measure("metrology_Spd", &m["Spd"]);
    Ok(items)
}
