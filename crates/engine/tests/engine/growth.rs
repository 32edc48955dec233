//! The growth jobs' behaviour (kim-machiraju-thompson §4), tested here rather
//! than through the CLI (issue #36): one behaviour per test, through the
//! engine's parameter types as every front end builds them. The simulators'
//! exponents against the physics (β = 1/2 for RD, 1/4 for RDSR in 1+1D, D of
//! DLA) are tested in `asperity-growth`; here, what the jobs make of them.

use asperity_engine::core::{MemoryBudget, NoProgress, TimeBudget};
use asperity_engine::growth::dla::{DlaParams, DlaRun, SeedInputs, grow};
use asperity_engine::growth::{Deposited, RdParams, RdsrParams, deposit};
use serde_json::{Value, json};

/// Parameters of type `P` from the JSON a `--params` file or Python's
/// keywords would give, defaults for the rest.
fn params<P: serde::de::DeserializeOwned>(v: Value) -> P {
    serde_json::from_value(v).expect("valid parameters")
}

fn unlimited() -> (MemoryBudget, TimeBudget) {
    (MemoryBudget::unlimited(), TimeBudget::unlimited())
}

fn deposited<P: asperity_engine::growth::DepositJob>(p: &P, keep_points: bool) -> Deposited {
    let (m, t) = unlimited();
    deposit(p, None, keep_points, 7, (&m, &t), &NoProgress).unwrap()
}

fn dla(v: Value) -> DlaRun {
    let (m, t) = unlimited();
    grow(&params(v), SeedInputs::default(), 7, &m, &t, &NoProgress).unwrap()
}

fn dla_error(v: Value) -> String {
    let (m, t) = unlimited();
    let p: DlaParams = params(v.clone());
    match grow(&p, SeedInputs::default(), 7, &m, &t, &NoProgress) {
        Ok(_) => panic!("{v:?} should be refused"),
        Err(e) => e.to_string(),
    }
}

/// Deposition conserves mass: after 200 layers the mean height is 200
/// exactly, whatever the relaxation moved.
#[test]
fn rdsr_conserves_mass_and_reports_a_growing_width() {
    let p: RdsrParams = params(json!({"size": 64, "layers": 200}));
    let Deposited::Flat(_, run) = deposited(&p, false) else {
        panic!("a flat substrate gives a flat run")
    };
    let h = run.deposit.height_field();
    assert_eq!(h.dims(), [64, 64]);
    assert!((h.mean() - 200.0).abs() < 1e-9, "mean height {}", h.mean());
    let s = &run.series;
    assert!(s.w2.len() > 10);
    assert!(s.w2.iter().all(|&w2| w2 > 0.0));
    // 2+1D RDSR (Edwards–Wilkinson) grows logarithmically: β → 0, and it is
    // well below RD's 1/2 over 200 layers.
    let beta = run.beta().expect("β is fitted");
    assert!(beta > 0.0 && beta < 0.35, "β = {beta}");
}

/// Random deposition in 1+1D: independent columns, so W² = t(1 − 1/L) exactly
/// in expectation; one run of 100 columns over 50 layers lands within 25 %.
#[test]
fn one_dimensional_rd_gives_a_profile_with_poisson_width() {
    let p: RdParams = params(json!({"dim": 1, "size": 100, "layers": 50}));
    let Deposited::Flat(_, run) = deposited(&p, false) else {
        panic!("flat")
    };
    assert_eq!(run.deposit.heights.len(), 100);
    let w2 = *run.series.w2.last().unwrap();
    let expected = 50.0 * (1.0 - 1.0 / 100.0);
    assert!((w2 / expected - 1.0).abs() < 0.25, "W² = {w2}, t = 50");
}

/// A curved deposit is a point set: the sphere's substrate cells, then one
/// point per particle.
#[test]
fn rdsr_on_a_sphere_gives_substrate_and_particles() {
    let p: RdsrParams = params(json!({"substrate": "sphere", "radius": 8.0, "layers": 3}));
    let r = deposited(&p, false);
    let Deposited::Curved(_, run) = &r else {
        panic!("a sphere substrate gives a curved run")
    };
    let points = r.points();
    assert_eq!(points.len(), run.world_points().len());
    assert!(run.particles() > 0 && points.len() > run.particles());
    // Every point lies about a sphere of radius 8 (cells of size 1, 3 layers)
    // about the points' centroid.
    let n = points.len() as f64;
    let c: Vec<f64> = (0..3)
        .map(|i| points.positions().iter().map(|p| p[i]).sum::<f64>() / n)
        .collect();
    for p in points.positions() {
        let r = (0..3).map(|i| (p[i] - c[i]).powi(2)).sum::<f64>().sqrt();
        assert!((5.0..=13.0).contains(&r), "r = {r}");
    }
}

/// A plane seed of 32 × 32 cells and 3,000 particles: every particle stuck,
/// the seeds listed first.
#[test]
fn dla_on_a_plane_keeps_every_particle() {
    let run = dla(json!({
        "seed_shape": "plane", "size": [32, 32, 64], "particles": 3000, "stick": 0.5
    }));
    assert_eq!(run.cluster.seeds, 32 * 32);
    assert_eq!(run.cluster.particles().len(), 3000);
    assert_eq!(run.world_points().len(), 32 * 32 + 3000);
    assert!(run.radius_of_gyration > 1.0);
    assert!(run.cluster.stopped.is_none());
}

/// 3-D DLA from a point: D ≈ 2.5 (Meakin) by R_g(n), and the pair count the
/// substrates report beside it (the same measure as about a sphere, so the two
/// compare like for like).
#[test]
fn dla_from_a_point_measures_a_fractal_dimension() {
    let run = dla(json!({"particles": 20000}));
    let d = run.dimension.value.expect("a point seed has D");
    assert!(d > 2.2 && d < 2.8, "D = {d}");
    let pairs = run.dimension.details["pair_correlation"]["D"]
        .as_f64()
        .expect("the pair count about a point");
    assert!((pairs - d).abs() < 0.15, "R_g(n) {d}, pairs {pairs}");
    // Too few particles for the window: R_g(n) alone.
    let run = dla(json!({"particles": 2000}));
    assert!(run.dimension.value.is_some());
    assert!(run.dimension.details["pair_correlation"].is_null());
}

/// Around a ball R_g(n) measures the seed (it gave D = 6.4, #22): D is measured
/// about the substrate instead, from the deposit's pair correlation
/// (`asperity_growth::dla::substrate`), with its window; a cluster too small
/// for the window gets no D and a warning that says why.
#[test]
fn dla_around_a_sphere_measures_d_about_the_substrate() {
    let run = dla(json!({"seed_shape": "sphere", "particles": 2000}));
    assert!(run.dimension.value.is_none());
    let warnings = run.warnings();
    assert!(
        warnings
            .iter()
            .any(|(_, w)| w.contains("grow more particles")),
        "{warnings:?}"
    );
    let run = dla(json!({"seed_shape": "sphere", "seed_radius": 6.0, "particles": 30000}));
    let d = run.dimension.value.expect("D about the substrate");
    assert!(d > 2.2 && d < 2.8, "D = {d}");
    assert!(run.dimension.method.contains("about the substrate"));
    let sub = &run.dimension.details["substrate"];
    let pairs = &sub["pair_correlation"];
    assert_eq!(pairs["D"].as_f64(), Some(d));
    assert_eq!(pairs["radius"][0].as_f64(), Some(4.0));
    assert!(pairs["centres"].as_u64().unwrap() > 500, "{pairs}");
    // The pair count is drawn with its fit; R_g(n)'s plot says it measures the seed.
    let plots = run.plots();
    let drawn = plots
        .iter()
        .find(|p| p.name == "pairs.svg")
        .expect("pairs.svg");
    assert!(
        drawn.plot.title.contains(&format!("D = {d:.3}")),
        "{}",
        drawn.plot.title
    );
    assert_eq!(drawn.plot.series.len(), 2);
    assert!(plots[0].plot.title.contains("measures the seed"));
    let range = sub["fit_range"].as_array().unwrap();
    assert_eq!(
        range[0].as_f64(),
        Some(sub["seed_radius"].as_f64().unwrap() + 5.0)
    );
    assert!(range[1].as_f64().unwrap() > range[0].as_f64().unwrap());
    assert!(run.warnings().is_empty(), "{:?}", run.warnings());
}

/// kim-machiraju-thompson §7, DLA on a complex object: a torus mesh seed
/// (voxelised 48 cells across, the hole included) against a point seed, 200,000
/// particles, two clusters each. D about the substrate (the deposit's pair
/// count) is within 0.1 of the point seed's D by R_g(n), a measure no
/// substrate enters. Measured: 2.50 about the torus (2.51, 2.48) against 2.49
/// about a point (2.51, 2.47).
#[test]
#[ignore = "slow tier: four DLA clusters of 200,000 particles, ~20 s (cargo test -- --ignored)"]
fn dla_on_a_mesh_has_the_point_seeds_dimension() {
    use asperity_engine::core::shapes;
    let (m, t) = unlimited();
    let grown = |shape: &str, seed: u64| {
        let p: DlaParams = params(json!({
            "seed_shape": shape, "particles": 200_000, "resolution": 48
        }));
        let inputs = SeedInputs {
            mesh: (shape == "mesh").then(|| shapes::torus(1.0, 0.35, 48, 24)),
            ..SeedInputs::default()
        };
        let run = grow(&p, inputs, seed, &m, &t, &NoProgress).unwrap();
        assert!(run.warnings().is_empty(), "{:?}", run.warnings());
        run.dimension.value.expect("D")
    };
    let runs: Vec<(&str, u64)> = vec![("point", 1), ("point", 2), ("mesh", 1), ("mesh", 2)];
    let ds: Vec<f64> = {
        use rayon::prelude::*;
        runs.par_iter()
            .map(|&(shape, seed)| grown(shape, seed))
            .collect()
    };
    let (point, mesh) = ((ds[0] + ds[1]) / 2.0, (ds[2] + ds[3]) / 2.0);
    assert!((2.4..2.6).contains(&point), "point seed D = {point}");
    assert!(
        (mesh - point).abs() < 0.1,
        "D about the torus {mesh}, about a point {point}"
    );
}

/// A 2-D lattice from one size: `dim = 2, size = 64` is 64 × 64 (the rule the
/// CLI and Python once disagreed on, #36).
#[test]
fn a_two_dimensional_lattice_from_one_size() {
    let run = dla(json!({"dim": 2, "size": 64, "particles": 200}));
    assert_eq!(run.params.size, [64, 1, 64]);
}

#[test]
fn bad_dla_parameters_are_refused_naming_the_parameter() {
    let e = dla_error(json!({"stick": 0.0}));
    assert!(e.contains("(0, 1]") && e.contains("stick"), "{e}");
    // A zero side is refused as the parameters are read, before any job.
    let e = serde_json::from_value::<DlaParams>(json!({"size": [0, 4, 4]})).unwrap_err();
    assert!(e.to_string().contains("none zero"), "{e}");
    let e = dla_error(json!({"size": [8, 8, 8], "particles": 1000}));
    assert!(e.contains("do not fit"), "{e}");
}

#[test]
fn a_deposit_over_the_memory_budget_is_refused_with_the_estimate() {
    let p: RdParams = params(json!({"size": 4096, "layers": 10}));
    let budget = MemoryBudget::new(1 << 20);
    let e = deposit(
        &p,
        None,
        true,
        7,
        (&budget, &TimeBudget::unlimited()),
        &NoProgress,
    )
    .unwrap_err();
    assert!(e.to_string().contains("memory"), "{e}");
    let p: RdParams = params(json!({"size": 0}));
    let (m, t) = unlimited();
    let e = deposit(&p, None, false, 7, (&m, &t), &NoProgress).unwrap_err();
    assert!(e.to_string().contains("size"), "{e}");
}
