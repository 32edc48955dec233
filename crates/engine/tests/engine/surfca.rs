//! The `surface-ca` job's behaviour (gobron-chiba), tested here rather than
//! through the CLI (issue #36): one behaviour per test, through
//! `SurfaceCaParams` and `run_job` as every front end calls them, and against
//! the exact spherical Voronoi split. The cell grids, edge pairing and the
//! rules are tested in `asperity-surfca`.

use asperity_engine::ErrorKind;
use asperity_engine::core::{MemoryBudget, NoProgress, PointSet, TimeBudget};
use asperity_engine::files::builtin_mesh;
use asperity_engine::surfca::{
    App, AppRun, Covered, OutputShape, SurfaceCaInputs, SurfaceCaParams, cover, run_app, run_job,
};
use asperity_surfca::corrosion::CorrosionParams;
use asperity_surfca::{CellSize, Pairing};
use serde_json::{Value, json};

fn params(v: Value) -> SurfaceCaParams {
    serde_json::from_value(v).expect("valid parameters")
}

fn run(mesh: &str, v: Value, at: Option<Vec<[f64; 3]>>) -> Result<(Covered, AppRun), String> {
    let inputs = SurfaceCaInputs {
        mesh: builtin_mesh(mesh).unwrap(),
        name: format!("builtin:{mesh}"),
        at: at.map(|p| (PointSet::new(p), "points".into())),
    };
    let (m, t) = (MemoryBudget::unlimited(), TimeBudget::unlimited());
    run_job(&params(v), inputs, 3, (&m, &t), &NoProgress, |_, _, _| {}).map_err(|e| e.to_string())
}

fn measured(cov: &Covered, r: &AppRun, key: &str) -> Value {
    serde_json::to_value(r.measurements(cov)).unwrap()[key].clone()
}

/// About the number of cells asked for, each labelled by one of the sites,
/// every label used, and the cells' areas summing to the mesh's.
#[test]
fn voronoi_labels_every_cell_with_one_of_its_sites() {
    let (cov, r) = run("sphere", json!({"sites": 5, "cells": 5000}), None).unwrap();
    let n = cov.cells.len();
    assert!((4000..6000).contains(&n), "{n} cells");
    let labels = r.labels(&cov).unwrap();
    let label = labels.attribute("label").unwrap();
    let mut used = [false; 5];
    for &l in label {
        assert!(l.fract() == 0.0 && (0.0..5.0).contains(&l), "{l}");
        used[l as usize] = true;
    }
    assert!(used.iter().all(|&u| u), "{used:?}");
    let area: f64 = labels.attribute("area").unwrap().iter().sum();
    assert!((area - cov.mesh.area()).abs() < 1e-9 * cov.mesh.area());
    let changed = measured(&cov, &r, "changed_fraction");
    assert_eq!(changed.as_array().unwrap().len() as u64, r.stats.steps);
}

/// The cell structure in the report: asperity's pairing by default, the
/// paper's Figure 8 measure beside it (counted on the same grids whichever
/// pairing links them); `pairing = "paper"` links as Figure 7 does and still
/// labels every cell.
#[test]
fn the_report_names_the_pairing_and_the_papers_redundancy() {
    let (cov, r) = run("sphere", json!({"sites": 5, "cells": 5000}), None).unwrap();
    let ours = measured(&cov, &r, "cell_structure");
    assert_eq!(ours["pairing"], "unfolded");
    let paper_measure = ours["paper_redundancy"].as_f64().unwrap();
    assert!((0.0..0.3).contains(&paper_measure), "{ours}");
    let (cov, r) = run(
        "sphere",
        json!({"sites": 5, "cells": 5000, "pairing": "paper"}),
        None,
    )
    .unwrap();
    let paper = measured(&cov, &r, "cell_structure");
    assert_eq!(paper["pairing"], "paper");
    assert_eq!(paper["paper_redundancy"].as_f64(), Some(paper_measure));
    assert!(r.warnings().is_empty(), "{:?}", r.warnings());
}

/// A coarse grid on the cube's 192 triangles gives cells at a corner more
/// than eight labelled side neighbours (found by the CLI/Python parity
/// property test: the rule kept them in an array of eight and panicked).
#[test]
fn voronoi_covers_coarse_cells_where_many_triangles_meet() {
    let inputs = SurfaceCaInputs {
        mesh: builtin_mesh("cube").unwrap(),
        name: "builtin:cube".into(),
        at: None,
    };
    let (m, t) = (MemoryBudget::unlimited(), TimeBudget::unlimited());
    let p = params(json!({"sites": 4, "cells": 996}));
    let (cov, r) = run_job(&p, inputs, 327, (&m, &t), &NoProgress, |_, _, _| {}).unwrap();
    let labels = r.labels(&cov).unwrap();
    let label = labels.attribute("label").unwrap();
    assert_eq!(label.len(), cov.cells.len());
    assert!(label.iter().all(|l| (0.0..4.0).contains(l)), "{label:?}");
}

/// Sites given as points start at the cells nearest them: the first site of
/// (0, 0, 1) on the unit sphere is a cell at the north pole.
#[test]
fn voronoi_sites_from_points_sit_at_the_points() {
    let at = vec![[0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]];
    let (cov, r) = run("sphere", json!({"cells": 4000}), Some(at)).unwrap();
    let sites = measured(&cov, &r, "sites");
    let sites = sites.as_array().unwrap();
    assert_eq!(sites.len(), 3);
    assert!(sites[0][2].as_f64().unwrap() > 0.95, "{}", sites[0]);
    assert!(sites[1][2].as_f64().unwrap() < -0.95, "{}", sites[1]);
    assert!(sites[2][0].as_f64().unwrap() > 0.95, "{}", sites[2]);
}

/// Corrosion with no random seeding spreads only from the sites given
/// (#22): none given, nothing corrodes; one given, it does.
#[test]
fn corrosion_spreads_only_from_its_sites() {
    let p = json!({"app": "corrosion", "cells": 3000, "steps": 40, "seed_rate": 0.0});
    let corroded = |at| {
        let (cov, r) = run("cube", p.clone(), at).unwrap();
        measured(&cov, &r, "corroded").as_u64().unwrap()
    };
    assert_eq!(corroded(None), 0);
    assert!(corroded(Some(vec![[0.3, 0.2, 5.0]])) > 0);
}

/// Gray–Scott keeps its two chemicals; the activator is the output's field.
#[test]
fn gray_scott_gives_an_activator_field() {
    let (cov, r) = run(
        "sphere",
        json!({"app": "gray-scott", "cells": 4000, "steps": 200}),
        None,
    )
    .unwrap();
    let (name, field) = r.state.field().expect("a field");
    assert_eq!(name, "activator");
    assert_eq!(field.len(), cov.cells.len());
    assert!(field.iter().all(|v| v.is_finite()));
}

#[test]
fn bad_parameters_are_refused_naming_the_parameter() {
    for (v, needle) in [
        (json!({"sites": 0}), "sites"),
        (json!({"diagonal_p": 2.0}), "diagonal_p"),
        (json!({"cells": 0}), "cells"),
        (json!({"app": "gray-scott", "feed": 0.9}), "feed"),
        (
            json!({"app": "corrosion", "max_attacked": 9}),
            "max_attacked",
        ),
    ] {
        let e = match serde_json::from_value::<SurfaceCaParams>(v.clone()) {
            Err(e) => e.to_string(),
            Ok(_) => run("cube", v.clone(), None)
                .err()
                .unwrap_or_else(|| panic!("{v} ran")),
        };
        assert!(e.contains(needle), "{v}: {e}");
    }
}

/// A built-in mesh covered with about `cells` cells.
fn covered(name: &str, cells: usize) -> Covered {
    let mesh = builtin_mesh(name).unwrap();
    cover(
        mesh,
        name,
        false,
        (CellSize::Count(cells), Pairing::Unfolded),
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
