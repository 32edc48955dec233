//! The `analyze` job's behaviour, tested here rather than through the CLI
//! (issue #36): one behaviour per test, through `AnalyzeParams` as every
//! front end builds them, against closed forms (Gauss–Bonnet, the rms the
//! surface was scaled to, the Hurst exponent it was synthesised with). The
//! estimators against SurfaceTopography are in `asperity-analysis` and the
//! CLI's `analysis_reference` test.

use asperity_engine::analyze::{AnalyzeParams, analyze};
use asperity_engine::core::{HeightField, MemoryBudget, shapes};
use asperity_engine::io::Surface;
use asperity_engine::synthesis::{FbmParams, fbm};
use serde_json::{Value, json};

fn report(s: &Surface, v: Value) -> (Value, Vec<String>) {
    let p: AnalyzeParams = serde_json::from_value(v).expect("valid parameters");
    let a = analyze(s, "test", &p.options(false), &MemoryBudget::unlimited()).unwrap();
    (serde_json::to_value(&a.facts).unwrap(), a.warnings)
}

fn fbm_surface() -> Surface {
    let p = FbmParams {
        size: 256,
        hurst: 0.7,
        rms: 0.5,
        ..FbmParams::DEFAULT
    };
    Surface::Height(fbm(&p, 3, &MemoryBudget::unlimited()).unwrap())
}

/// The surface was scaled to Sq = 0.5 after removing its mean, and its
/// spectrum has H = 0.7.
#[test]
fn a_synthesised_surface_gives_back_its_rms_and_hurst_exponent() {
    let (m, _) = report(&fbm_surface(), json!({"level": "mean"}));
    for k in ["Sa", "Sq", "Sp", "Sv", "Sz", "Ssk", "Sku", "Sdq", "Sdr"] {
        assert!(m[k].is_number(), "{k} missing");
    }
    assert!(
        (m["Sq"].as_f64().unwrap() - 0.5).abs() < 1e-9,
        "{}",
        m["Sq"]
    );
    let h = m["hurst"].as_f64().unwrap();
    assert!((h - 0.7).abs() < 0.05, "H = {h}");
    let q = m["psd"]["q"].as_array().unwrap();
    assert_eq!(q.len(), m["psd"]["C"].as_array().unwrap().len());
}

/// A torus has genus 1 and, by Gauss–Bonnet, total Gaussian curvature
/// 2πχ = 0; as a smooth surface its box-counting dimension is 2.
#[test]
fn a_torus_has_genus_one_and_no_total_gaussian_curvature() {
    let torus = Surface::Mesh(shapes::torus(1.0, 0.35, 96, 48));
    let (m, warnings) = report(&torus, json!({}));
    assert_eq!(m["genus"], 1);
    let k = m["curvature"]["total_gaussian"].as_f64().unwrap();
    assert!(k.abs() < 1e-9, "∫K = {k}");
    let d = m["fractal_dimension"]["box_counting"]["D"]
        .as_f64()
        .unwrap();
    assert!((d - 2.0).abs() < 0.15, "D = {d}");
    assert!(!warnings.iter().any(|w| w.contains("covering dimension")));
}

/// A constant field is analysed, not refused: zeros where the numbers are
/// defined, null where not (skewness and kurtosis divide by Sq), and a
/// warning.
#[test]
fn a_constant_field_gives_zeros_nulls_and_a_warning() {
    let flat = Surface::Height(HeightField::filled([4, 4], 1.0));
    let (m, warnings) = report(&flat, json!({}));
    assert_eq!((m["Sa"].as_f64(), m["Sq"].as_f64()), (Some(0.0), Some(0.0)));
    assert!(m["Ssk"].is_null() && m["Sku"].is_null() && m["hurst"].is_null());
    assert!(
        warnings.iter().any(|w| w.contains("constant (z = 1)")),
        "{warnings:?}"
    );
}

/// A fit window above the Nyquist frequency holds no PSD point: no Hurst
/// exponent, the rest of the report, and a warning saying so (#20).
#[test]
fn a_fit_window_past_nyquist_leaves_hurst_out_and_says_why() {
    let (m, warnings) = report(&fbm_surface(), json!({"fit_window": [1e6, 2e6]}));
    assert!(m["hurst"].is_null());
    assert!(m["Sq"].is_number());
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("only 0 points in the fit window")),
        "{warnings:?}"
    );
}

#[test]
fn a_reversed_fit_window_is_refused_naming_its_form() {
    let e = serde_json::from_value::<AnalyzeParams>(json!({"fit_window": [5.0, 1.0]}))
        .map(|p| asperity_engine::params::validate(&p))
        .map_or_else(|e| e.to_string(), |r| r.unwrap_err().to_string());
    assert!(e.contains("QMIN,QMAX") || e.contains("fit_window"), "{e}");
}

/// `hurst = "psd"` runs the PSD fit alone: the same H as every estimator's
/// report, no other estimate and no model-based dimension; `all` has them.
#[test]
fn one_estimator_is_paid_for_alone() {
    let s = fbm_surface();
    let (all, _) = report(&s, json!({}));
    let (psd, _) = report(&s, json!({"hurst": "psd"}));
    assert_eq!(psd["hurst"], all["hurst"]);
    let names = |m: &Value| -> Vec<String> {
        m["hurst_estimates"]
            .as_object()
            .unwrap()
            .keys()
            .cloned()
            .collect()
    };
    assert_eq!(names(&psd), ["psd_2d"]);
    assert_eq!(names(&all).len(), 5, "{:?}", names(&all));
    assert!(psd["fractal_dimension"]["triangulation"].is_null());
    assert!(all["fractal_dimension"]["triangulation"].is_object());
    let (sf, _) = report(&s, json!({"hurst": "structure-function"}));
    assert_eq!(names(&sf), ["psd_2d", "structure_function"]);
    assert_eq!(
        sf["hurst_estimates"]["structure_function"],
        all["hurst_estimates"]["structure_function"]
    );
}

/// The estimates run at once on every core, each on its own: the report is
/// the same on one thread and on three.
#[test]
fn the_report_is_the_same_at_any_thread_count() {
    let s = fbm_surface();
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| report(&s, json!({})))
    };
    assert_eq!(on(1), on(3));
}

/// Missing points (issue #38): the height parameters over the measured points
/// alone (computed here directly), the rest on the filled field; the Hurst
/// exponent of an fBm survives a few percent of holes; `fill: refuse` refuses.
#[test]
fn missing_points_are_left_out_of_the_heights_and_filled_for_the_spectrum() {
    let Surface::Height(full) = fbm_surface() else {
        unreachable!()
    };
    let mut h = full.clone();
    let nx = h.nx();
    // A disc of radius 12 and every 37th sample: ~3 % missing.
    for k in 0..h.len() {
        let (i, j) = ((k % nx) as f64 - 80.0, (k / nx) as f64 - 100.0);
        if i * i + j * j < 144.0 || k % 37 == 0 {
            h.data_mut()[k] = f64::NAN;
        }
    }
    let missing = h.missing_count();
    let holed = Surface::Height(h.clone());
    let (m, warnings) = report(&holed, json!({"level": "none"}));
    assert_eq!(m["missing"]["count"], missing);
    assert_eq!(m["missing"]["fill"], "harmonic");
    let z = h.measured_values();
    let n = z.len() as f64;
    let sq = (z.iter().map(|v| v * v).sum::<f64>() / n).sqrt();
    let sa = z.iter().map(|v| v.abs()).sum::<f64>() / n;
    let hi = z.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    assert!(
        (m["Sq"].as_f64().unwrap() - sq).abs() <= 1e-12 * sq,
        "{}",
        m["Sq"]
    );
    assert!(
        (m["Sa"].as_f64().unwrap() - sa).abs() <= 1e-12 * sa,
        "{}",
        m["Sa"]
    );
    assert_eq!(m["Sp"].as_f64().unwrap(), hi);
    assert_eq!(m["periodic"]["source"], "missing points");
    assert!(warnings.iter().any(|w| w.contains("were not measured")));
    let (whole, _) = report(&Surface::Height(full), json!({"level": "plane"}));
    let (h_holed, h_full) = (
        m["hurst"].as_f64().unwrap(),
        whole["hurst"].as_f64().unwrap(),
    );
    assert!(
        (h_holed - h_full).abs() < 0.05,
        "H {h_holed} with holes, {h_full} without"
    );
    let p: AnalyzeParams = serde_json::from_value(json!({"fill": "refuse"})).unwrap();
    let e = analyze(
        &holed,
        "test",
        &p.options(false),
        &MemoryBudget::unlimited(),
    )
    .unwrap_err();
    assert!(
        e.to_string()
            .contains(&format!("{missing} of {} points", h.len())),
        "{e}"
    );
    // A constant field with a hole, and a profile with one: reports, no panic.
    let flat = HeightField::from_vec(
        [3, 3],
        vec![1.0, 1.0, 1.0, 1.0, f64::NAN, 1.0, 1.0, 1.0, 1.0],
    )
    .unwrap();
    let (c, _) = report(&Surface::Height(flat), json!({}));
    assert_eq!(c["missing"]["count"], 1);
    let profile: Vec<f64> = (0..64)
        .map(|i| {
            if i == 9 {
                f64::NAN
            } else {
                (i as f64 * 0.3).sin()
            }
        })
        .collect();
    let (p, _) = report(
        &Surface::Height(HeightField::from_vec([64, 1], profile).unwrap()),
        json!({"level": "mean"}),
    );
    assert_eq!(p["kind"], "profile");
    assert!(p["profile_x"]["Rq"].is_number());
}

/// The analysis is estimated before it starts: a 512² field (some 19 MB, 80
/// more with missing points) is refused under an 8 MB budget, naming it.
#[test]
fn an_analysis_over_the_budget_is_refused_first() {
    let h = HeightField::from_vec([512, 512], vec![0.5; 512 * 512]).unwrap();
    let budget = MemoryBudget::new(8 << 20);
    let p = AnalyzeParams::default();
    let e = analyze(
        &Surface::Height(h.clone()),
        "f.npy",
        &p.options(false),
        &budget,
    )
    .unwrap_err();
    assert!(e.to_string().contains("analysing f.npy"), "{e}");
    assert!(
        asperity_engine::analyze::height_bytes(&h) > 8 << 20,
        "the estimate"
    );
    let mut holed = h.clone();
    holed.data_mut()[1000] = f64::NAN;
    let full = asperity_engine::analyze::height_bytes(&holed);
    // the fill's twenty grids come on top (160 bytes a point)
    let plain = asperity_engine::analyze::height_bytes(&h);
    assert!(full >= plain + 160 * h.len() as u64, "{full} vs {plain}");
}

/// Two sinusoids on a periodic grid, one far below λc and one far above:
/// the S-L surface keeps (1 − T) of each, T = exp(−π(αλc/λ)²) the
/// transmission of ISO 16610-61, so its Sq is known in closed form.
#[test]
fn the_l_filter_removes_the_waviness_as_the_standard_transmits_it() {
    let (n, lambda_c) = (256usize, 32.0);
    let (short, long) = (16.0, 128.0);
    let (a_short, a_long) = (0.3, 2.0);
    let data = (0..n * n)
        .map(|k| {
            let (x, y) = ((k % n) as f64, (k / n) as f64);
            a_short * (2.0 * std::f64::consts::PI * x / short).sin()
                + a_long * (2.0 * std::f64::consts::PI * y / long).cos()
        })
        .collect();
    let h = Surface::Height(HeightField::from_vec([n, n], data).unwrap());
    let (m, _) = report(
        &h,
        json!({"level": "mean", "periodic": "yes", "lambda_c": lambda_c, "hurst": "psd"}),
    );
    let t = |l: f64| {
        let alpha = asperity_engine::methods::analysis::filter::ALPHA;
        (-std::f64::consts::PI * (alpha * lambda_c / l).powi(2)).exp()
    };
    let want = ((a_short * (1.0 - t(short))).powi(2) / 2.0
        + (a_long * (1.0 - t(long))).powi(2) / 2.0)
        .sqrt();
    let sq = m["Sq"].as_f64().unwrap();
    assert!(
        (sq / want - 1.0).abs() < 1e-3,
        "Sq {sq}, closed form {want}"
    );
    assert_eq!(m["filter"]["surface"], "F-L surface");
    assert_eq!(m["filter"]["lambda_c"], lambda_c);
    // the functional family comes with every height report, ordered as it must be
    for k in [
        "Sk", "Spk", "Svk", "Smr1", "Smr2", "Sxp", "Vmp", "Vmc", "Vvc", "Vvv",
    ] {
        assert!(m[k].as_f64().is_some_and(f64::is_finite), "{k}: {}", m[k]);
    }
    assert!(m["Smr1"].as_f64() < m["Smr2"].as_f64());
}

/// `nesting: iso` picks ISO 25178-3's series values from the extent and
/// spacing; λs not below λc and a robust filter without an L-filter are refused.
#[test]
fn nesting_indices_default_from_the_series_and_bad_ones_are_refused() {
    let (m, _) = report(&fbm_surface(), json!({"nesting": "iso", "hurst": "psd"}));
    // 256 samples of spacing 1 (a side of 255): λc ≤ 51 → 50, λs ≥ 3 → 5
    assert_eq!(m["filter"]["surface"], "S-L surface");
    assert_eq!(m["filter"]["lambda_c"], 50.0, "{}", m["filter"]);
    assert_eq!(m["filter"]["lambda_s"], 5.0, "{}", m["filter"]);
    for bad in [
        json!({"lambda_s": 0.5, "lambda_c": 0.1}),
        json!({"robust": true}),
        json!({"filter_degree": 3}),
        json!({"lambda_c": -1.0}),
    ] {
        let p = serde_json::from_value::<AnalyzeParams>(bad.clone());
        let refused = match p {
            Err(_) => true,
            Ok(p) => asperity_engine::params::validate(&p).is_err(),
        };
        assert!(refused, "{bad} accepted");
    }
}

/// `filter` splits a tilted field with holes into form, waviness, noise and
/// the scale-limited surface, which add up to the input at every measured
/// point (missing points stay missing in each part); the form is the plane
/// the field was tilted by, to rounding.
#[test]
fn the_filters_parts_add_up_to_the_input() {
    use asperity_engine::analyze::{FilterParams, filter};
    let Surface::Height(rough) = fbm_surface() else {
        unreachable!()
    };
    let (a, b, c) = (0.03, -0.02, 1.5);
    let mut data = rough.data().to_vec();
    for (k, z) in data.iter_mut().enumerate() {
        let (i, j) = ((k % 256) as f64, (k / 256) as f64);
        *z += a * i + b * j + c;
        if (k * 7919) % 97 == 0 {
            *z = f64::NAN;
        }
    }
    let h = rough.with_data(data).unwrap();
    let p: FilterParams =
        serde_json::from_value(json!({"lambda_s": 4.0, "lambda_c": 40.0})).unwrap();
    let f = filter(&h, &p, &MemoryBudget::unlimited()).unwrap();
    let (w, s) = (
        f.waviness.expect("an L-filter"),
        f.noise.expect("an S-filter"),
    );
    let mut measured = 0;
    for k in 0..h.len() {
        let parts = [
            f.form.data()[k],
            w.data()[k],
            s.data()[k],
            f.surface.data()[k],
        ];
        if h.data()[k].is_nan() {
            assert!(
                f.surface.data()[k].is_nan(),
                "point {k} filled in the surface"
            );
            continue;
        }
        measured += 1;
        let sum: f64 = parts.iter().sum();
        assert!(
            (sum - h.data()[k]).abs() < 1e-12,
            "point {k}: {parts:?} sum {sum} vs {}",
            h.data()[k]
        );
    }
    assert!(measured > 60_000 && measured < h.len());
    // the levelled plane is the tilt plus the fBm's own (small) best plane
    let slope = (f.form.data()[2] - f.form.data()[1]) - a;
    assert!(slope.abs() < 2e-3, "form slope off by {slope}");
    assert_eq!(
        serde_json::to_value(&f.facts).unwrap()["filter"]["surface"],
        "S-L surface"
    );
}

/// The feature parameters reach the report with how they were found: on a
/// periodic egg crate two peaks per period cell, peaks at its amplitude; with
/// plots, the hill and dale maps; a pruning beyond 100 % is refused.
#[test]
fn the_report_carries_the_feature_parameters_and_their_maps() {
    let (n, period) = (128usize, 32.0);
    let k = 2.0 * std::f64::consts::PI / period;
    let data = (0..n * n)
        .map(|p| 0.5 * (k * (p % n) as f64).cos() * (k * (p / n) as f64).cos())
        .collect();
    let s = Surface::Height(HeightField::from_vec([n, n], data).unwrap());
    let p: AnalyzeParams =
        serde_json::from_value(json!({"periodic": "yes", "level": "mean", "hurst": "psd"}))
            .unwrap();
    let a = analyze(&s, "test", &p.options(true), &MemoryBudget::unlimited()).unwrap();
    let m = serde_json::to_value(&a.facts).unwrap();
    assert_eq!(m["Spd"], 2.0 / (period * period), "{}", m["features"]);
    assert!(
        (m["S5p"].as_f64().unwrap() - 0.5).abs() < 1e-12,
        "{} {}",
        m["S5p"],
        m["levelling"]
    );
    assert_eq!(m["features"]["hills"]["counted"], 32);
    assert_eq!(m["features"]["pruning_percent_of_Sz"], 5.0);
    let names: Vec<_> = a.images.iter().map(|i| i.name).collect();
    assert_eq!(names, ["hills.png", "dales.png"]);
    assert!(a.images[0].image.width() >= 512);
    let bad: AnalyzeParams = serde_json::from_value(json!({"pruning": 101.0})).unwrap();
    assert!(asperity_engine::params::validate(&bad).is_err());
}

/// A sinusoidal profile over 19 whole periods (its samples at every phase of
/// the period, none twice): Rsm is its wavelength, Rc twice its amplitude,
/// and Rmr(c) the fraction of a period above c, 50 % − 100 % · asin(c/A)/π;
/// Rmc(mr) its inverse.
#[test]
fn a_sinusoidal_profile_gives_rsm_and_rmr_in_closed_form() {
    let (n, a, dx) = (200_000usize, 1.3, 0.01);
    let lambda = n as f64 / 19.0;
    let data = (0..n)
        .map(|i| a * (std::f64::consts::TAU * (i as f64 + 0.27) / lambda).sin())
        .collect();
    let h = HeightField::from_vec([n, 1], data)
        .unwrap()
        .with_spacing([dx, dx])
        .unwrap();
    let cs = [0.0, 0.5 * a, -0.3 * a, 0.9 * a];
    let (m, _) = report(
        &Surface::Height(h),
        json!({"level": "mean", "periodic": "yes", "hurst": "psd",
               "material_ratio_at": cs, "height_at_ratio": [10.0, 50.0]}),
    );
    let p = &m["profile_x"];
    let rsm = p["Rsm"].as_f64().unwrap();
    assert!((rsm - lambda * dx).abs() < 1e-6 * lambda * dx, "Rsm {rsm}");
    assert!(
        (p["Rc"].as_f64().unwrap() - 2.0 * a).abs() < 1e-4 * a,
        "Rc {}",
        p["Rc"]
    );
    for (k, c) in cs.iter().enumerate() {
        let want = 50.0 - 100.0 * (c / a).asin() / std::f64::consts::PI;
        let got = p["Rmr_at"][k]["mr_percent"].as_f64().unwrap();
        assert_eq!(p["Rmr_at"][k]["c"], *c);
        // to 1e-6 of the evaluation length (the chords' error: ~1e-8)
        assert!(
            (got - want).abs() < 1e-4,
            "Rmr({c}) = {got} %, not {want} %"
        );
    }
    let c10 = p["Rmc_at"][0]["c"].as_f64().unwrap();
    let want = a * (std::f64::consts::PI * (0.5 - 0.1)).sin();
    assert!(
        (c10 - want).abs() < 1e-6 * a,
        "Rmc(10 %) = {c10}, not {want}"
    );
    assert!(p["Rmc_at"][1]["c"].as_f64().unwrap().abs() < 1e-9);
    // Rdc(20 %, 80 %) = A (cos 0.2π − cos 0.8π) = 2A cos 0.2π
    let rdc = p["Rdc"].as_f64().unwrap();
    let want = 2.0 * a * (0.2 * std::f64::consts::PI).cos();
    assert!((rdc - want).abs() < 1e-6 * a, "Rdc = {rdc}, not {want}");
    assert_eq!(p["Rdc_mr_percent"], json!([20.0, 80.0]));
}

/// Rdc on a profile no one here tuned it on: a triangle wave of amplitude,
/// period, phase and length drawn per run, its corners on samples, so the
/// profile drawn straight between samples is the wave itself. Its material
/// length is linear in c, Rmr(c) = (A − c)/2A, so Rmc(mr) = A(1 − mr/50) and
/// Rdc(20 %, 80 %) = 1.2 A exactly (to the bisection's rounding).
#[test]
fn a_random_triangle_wave_gives_rdc_in_closed_form() {
    use rand::{Rng, SeedableRng};
    let seed: u64 = rand::random();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let a: f64 = rng.random_range(0.01..100.0);
    let quarter = rng.random_range(2..40usize);
    let period = 4 * quarter;
    let n = period * rng.random_range(3..30usize);
    let phase = rng.random_range(0..period);
    let offset: f64 = rng.random_range(-50.0..50.0);
    let data = (0..n)
        .map(|i| {
            // from −A at t = 0 up to A at half a period and down again
            let t = (i + phase) % period;
            let up = t.min(period - t) as f64 / (period / 2) as f64;
            offset + a * (2.0 * up - 1.0)
        })
        .collect();
    let h = HeightField::from_vec([n, 1], data).unwrap();
    let (m, _) = report(
        &Surface::Height(h),
        json!({"level": "mean", "periodic": "yes", "hurst": "psd"}),
    );
    let rdc = m["profile_x"]["Rdc"].as_f64().unwrap();
    assert!(
        (rdc - 1.2 * a).abs() < 1e-9 * a,
        "seed {seed}: A {a}, period {period}, n {n}: Rdc {rdc}, not {}",
        1.2 * a
    );
}
