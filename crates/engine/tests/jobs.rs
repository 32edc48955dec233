//! The engine's jobs checked against outside truths: what every front end
//! (CLI, gallery, Python, Blender) gets when it calls them.

use std::f64::consts::PI;

use asperity_core::{MemoryBudget, NoProgress, TimeBudget};
use asperity_engine::ErrorKind;
use asperity_engine::files::{builtin_mesh, load, load_mesh};
use asperity_engine::reconstruct::{PIPELINE, rdsr_sphere, surface};
use asperity_engine::surfca::{App, Covered, OutputShape, cover, run_app};
use asperity_levelset::ReconstructParams;
use asperity_surfca::CellSize;
use asperity_surfca::corrosion::CorrosionParams;

/// A built-in mesh covered with about `cells` cells.
fn covered(name: &str, cells: usize) -> Covered {
    let mesh = builtin_mesh(name).unwrap();
    cover(
        mesh,
        name,
        false,
        CellSize::Count(cells),
        &MemoryBudget::unlimited(),
    )
    .unwrap()
}

fn nearest_cell(centres: &[[f64; 3]], p: [f64; 3]) -> usize {
    let d2 = |c: &[f64; 3]| (0..3).map(|i| (c[i] - p[i]).powi(2)).sum::<f64>();
    (0..centres.len())
        .min_by(|&a, &b| d2(&centres[a]).total_cmp(&d2(&centres[b])))
        .expect("cells exist")
}

/// Two antipodal sites split a sphere into hemispheres (the exact spherical
/// Voronoi diagram): each label holds half of the area, and the cells' areas
/// sum to the mesh's.
#[test]
fn voronoi_of_antipodal_sites_is_two_hemispheres() {
    let cov = covered("sphere", 40_000);
    let sites = vec![
        nearest_cell(&cov.cells.centre, [0.0, 0.0, 1.0]),
        nearest_cell(&cov.cells.centre, [0.0, 0.0, -1.0]),
    ];
    let app = App::voronoi(sites, None, 100_000).unwrap();
    let run = run_app(&cov, app, 7, &TimeBudget::unlimited(), |_, _| {}).unwrap();
    assert!(run.warnings().is_empty(), "{:?}", run.warnings());

    let labels = run.labels(&cov).unwrap();
    let label = labels.attribute("label").unwrap();
    let area = labels.attribute("area").unwrap();
    let total: f64 = area.iter().sum();
    let mesh_area = cov.mesh.area();
    assert!(
        (total - mesh_area).abs() < 1e-9 * mesh_area,
        "{total} vs {mesh_area}"
    );
    let north: f64 = (0..area.len())
        .filter(|&c| label[c] == 0.0)
        .map(|c| area[c])
        .sum();
    assert!(
        (north / total - 0.5).abs() < 0.03,
        "north share {}",
        north / total
    );
    // Below the equator every cell belongs to the south site, except along the
    // ragged boundary the grid draws.
    let wrong = (0..area.len())
        .filter(|&c| label[c] == 0.0 && labels.positions()[c][2] < -0.15)
        .count();
    assert_eq!(wrong, 0);
}

/// Labels are a Voronoi output: the other applications refuse them, and a
/// displacement needs a field.
#[test]
fn outputs_an_application_cannot_give_are_refused() {
    let budget = MemoryBudget::unlimited();
    let cov = covered("cube", 5_000);
    let app = App::corrosion(CorrosionParams::default(), 5).unwrap();
    let run = run_app(&cov, app, 3, &TimeBudget::unlimited(), |_, _| {}).unwrap();
    let e = run.labels(&cov).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::Invalid);
    assert!(e.to_string().contains("voronoi"), "{e}");

    let sites = vec![0];
    let voronoi = run_app(
        &cov,
        App::voronoi(sites, None, 1000).unwrap(),
        3,
        &TimeBudget::unlimited(),
        |_, _| {},
    )
    .unwrap();
    let shape = OutputShape {
        displace: Some(1.0),
        ..OutputShape::default()
    };
    let e = voronoi.mesh(&cov, shape, &budget).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::Invalid);
    assert!(App::voronoi(vec![0], Some(1.5), 10).is_err());
}

/// The paper's Fig. 8 pipeline on a small ball: RDSR on a sphere, then the
/// level-set surface around the deposit — one closed, genus-0 surface that
/// encloses the substrate and lies within a few cells of the deposit's top.
#[test]
fn rdsr_sphere_pipeline_gives_a_closed_sphere_around_the_deposit() {
    let budget = MemoryBudget::unlimited();
    let (radius, layers) = (8.0, 3.0);
    let grown = rdsr_sphere(radius, layers, 1, (5, &budget, &NoProgress)).unwrap();
    let thickness = grown.facts.get("thickness").unwrap().as_f64().unwrap();
    assert!(thickness > 0.0 && thickness < 3.0 * layers, "{thickness}");

    let centre = {
        let n = grown.points.len() as f64;
        let mut c = [0.0; 3];
        for p in &grown.points {
            (0..3).for_each(|i| c[i] += p[i] / n);
        }
        c
    };
    let outer = grown
        .points
        .iter()
        .map(|p| {
            (0..3)
                .map(|i| (p[i] - centre[i]).powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .fold(0.0, f64::max);

    let params = ReconstructParams {
        sizing: PIPELINE.sizing,
        offset: PIPELINE.offset,
        iterations: PIPELINE.iterations,
        ..ReconstructParams::default()
    };
    let rec = surface(
        &grown.points,
        &params,
        None,
        (&budget, &TimeBudget::unlimited()),
        &NoProgress,
        &mut |_, _| {},
    )
    .unwrap();
    let m = &rec.mesh;
    assert!(m.is_watertight() && m.is_manifold());
    assert_eq!(m.euler_characteristic(), 2);
    // Every vertex lies outside the substrate ball (the deposit covers it) and
    // within a few cells of the deposit's outermost particle.
    for v in m.positions() {
        let r = (0..3)
            .map(|i| (v[i] - centre[i]).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(
            r > radius && r < outer + 3.0,
            "vertex at r = {r}, deposit from {radius} to {outer}"
        );
    }
    // So the enclosed volume lies between those balls'.
    let ball = |r: f64| 4.0 / 3.0 * PI * r.powi(3);
    let v = m.signed_volume();
    assert!(v > ball(radius) && v < ball(outer + 3.0), "volume {v}");
}

/// Files are refused by kind: a missing file is the system's, an oversized
/// one the budget's, an unknown built-in the caller's.
#[test]
fn files_are_refused_with_the_right_kind() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.ply");
    let e = load(&missing, &MemoryBudget::unlimited()).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::Os);
    assert!(e.to_string().contains("missing.ply"), "{e}");

    let npy = dir.path().join("h.npy");
    let h = asperity_core::HeightField::filled([64, 64], 0.0);
    asperity_io::write(
        &npy,
        &asperity_io::Surface::Height(h),
        &asperity_io::WriteOptions::default(),
    )
    .unwrap();
    let e = load(&npy, &MemoryBudget::new(1024)).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::Memory);
    assert!(load(&npy, &MemoryBudget::unlimited()).is_ok());

    let e = load_mesh("builtin:teapot", &MemoryBudget::unlimited()).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::Invalid);
    assert!(
        e.to_string().contains("sphere"),
        "names the known ones: {e}"
    );
}
