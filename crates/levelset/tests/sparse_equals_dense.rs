//! `reconstruct` runs every stage on sparse bricks (`asperity_levelset::sparse`);
//! the dense stages stay in the crate as the reference. Here the whole sparse
//! pipeline is run against the dense stages, mesh for mesh and bit for bit, on
//! inputs it was not tuned on: a non-periodic crop of a plane DLA deposit (open
//! on every side, a tangle of branches that fills most of the box), a deposit
//! grown between walls, a point cloud with an empty middle, both distance
//! methods and both tagging rules.

use asperity_core::{MemoryBudget, NoProgress, TriMesh};
use asperity_growth::dla::{DlaParams, SeedShape, Sides, dla};
use asperity_levelset::evolve::from_tags;
use asperity_levelset::pipeline::grid_for;
use asperity_levelset::{
    DistanceMethod, EvolveParams, Flow, Length, ReconstructParams, Sizing, TagRule, evolve,
    extract, reconstruct, tag, unsigned_distance,
};

fn deposit(size: [usize; 3], particles: usize, sides: Sides) -> Vec<[f64; 3]> {
    let params = DlaParams {
        dim: 3,
        size,
        particles,
        stick: 1.0,
        seed_shape: SeedShape::Plane,
        launch_gap: 2.0,
        sides,
    };
    dla(&params, 11, 0, &MemoryBudget::unlimited(), &NoProgress)
        .expect("deposit")
        .points()
}

/// The mesh the dense stages give for `points` with the pipeline's grid and
/// settings (which must set the point radius, and use the convection flow).
fn dense(points: &[[f64; 3]], params: &ReconstructParams) -> (TriMesh, (usize, usize)) {
    let grid = grid_for(points, params, &MemoryBudget::unlimited()).expect("grid");
    let h = grid.spacing;
    let eps = params.offset.unwrap_or(Length::Cells(3.0)).world(h);
    let gamma = params.tube_cells * h;
    let cap = eps + gamma + 2.0 * h;
    let d = unsigned_distance(points, &grid, params.distance, cap, &NoProgress);
    let tags = tag(&d, eps, params.tag_rule, &NoProgress);
    let mut ls = from_tags(&d, &tags, eps, gamma, &NoProgress);
    let flow = EvolveParams {
        iterations: params.iterations,
        scheme: params.scheme,
        flow: Flow::Convection,
        cfl: params.cfl,
        beta: params.beta_cells * h,
        redistance_iterations: params.redistance_iterations,
        tolerance: params.tolerance,
        band: params.band,
        arrest: params.point_radius.expect("a point radius"),
        snapshot_every: None,
        neighbourhood: params.neighbourhood,
    };
    evolve(&mut ls, &d, &flow, &NoProgress, &mut |_, _| {});
    let (mesh, _) = extract(&ls.phi, &grid, &params.extract);
    (mesh, (tags.exterior_count, tags.refused))
}

fn same(points: &[[f64; 3]], params: &ReconstructParams) {
    let rec = reconstruct(
        points,
        params,
        &MemoryBudget::unlimited(),
        &NoProgress,
        &mut |_, _| {},
    )
    .expect("reconstruction");
    let (want, tagged) = dense(points, params);
    assert!(want.n_faces() > 1000, "{} triangles", want.n_faces());
    assert_eq!(rec.tagged, tagged);
    assert_eq!(rec.mesh.triangles(), want.triangles());
    assert_eq!(rec.mesh.positions(), want.positions());
    assert_eq!(rec.mesh.normals(), want.normals());
    assert!(rec.bricks.0 > 0 && rec.bricks.0 <= rec.bricks.1);
}

#[test]
fn crop_of_a_plane_deposit() {
    let pts: Vec<[f64; 3]> = deposit([48, 48, 40], 9000, Sides::Periodic)
        .into_iter()
        .filter(|p| (6.0..38.0).contains(&p[0]) && (9.0..41.0).contains(&p[1]))
        .collect();
    for rule in [TagRule::Paper, TagRule::Threshold] {
        same(
            &pts,
            &ReconstructParams {
                sizing: Sizing::Resolution(64),
                point_radius: Some(0.8),
                tag_rule: rule,
                iterations: 20,
                ..Default::default()
            },
        );
    }
}

#[test]
fn deposit_between_walls_with_the_paper_distance() {
    let pts = deposit([24, 24, 24], 1200, Sides::Walls);
    same(
        &pts,
        &ReconstructParams {
            sizing: Sizing::Spacing(0.7),
            offset: Some(Length::World(3.0)),
            point_radius: Some(0.75),
            distance: DistanceMethod::GODUNOV,
            neighbourhood: asperity_levelset::Neighbourhood::Cube,
            iterations: 15,
            ..Default::default()
        },
    );
}

/// Two shells far apart: most bricks between and around them stay empty.
#[test]
fn shells_with_an_empty_middle() {
    let mut pts = Vec::new();
    for a in 0..80 {
        for b in 0..160 {
            let th = std::f64::consts::PI * (a as f64 + 0.5) / 80.0;
            let ph = std::f64::consts::PI * b as f64 / 80.0;
            let dir = [th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()];
            let r = 3.0 + 0.2 * (7.0 * ph).sin() * (5.0 * th).cos();
            pts.push(dir.map(|x| r * x));
            pts.push([20.0 + 2.0 * dir[0], 14.0 + 2.0 * dir[1], 9.0 + 2.0 * dir[2]]);
        }
    }
    let params = ReconstructParams {
        sizing: Sizing::Resolution(96),
        point_radius: Some(0.2),
        ..Default::default()
    };
    same(&pts, &params);
    let rec = reconstruct(
        &pts,
        &params,
        &MemoryBudget::unlimited(),
        &NoProgress,
        &mut |_, _| {},
    )
    .unwrap();
    let (active, all) = rec.bricks;
    assert!(active * 4 < all, "{active} of {all} bricks");
}

/// The memory check counts the bricks near the points, not the box, and
/// refuses with that count in the message.
#[test]
fn the_memory_check_counts_bricks() {
    let pts = [[0.0, 0.0, 0.0], [100.0, 100.0, 100.0]];
    let params = ReconstructParams {
        sizing: Sizing::Resolution(1000),
        ..Default::default()
    };
    // A 1000³ grid would not fit in 64 MiB densely, but two points' bricks do.
    let small = MemoryBudget::new(64 << 20);
    let rec = reconstruct(&pts, &params, &small, &NoProgress, &mut |_, _| {}).unwrap();
    assert!(rec.bricks.0 < 100);
    // A dense cloud needs many bricks: refused, saying so.
    let cloud: Vec<[f64; 3]> = (0..20_000)
        .map(|i| {
            let t = i as f64;
            [
                (t * 0.618).fract() * 100.0,
                (t * 0.414).fract() * 100.0,
                (t * 0.732).fract() * 100.0,
            ]
        })
        .collect();
    let err = reconstruct(&cloud, &params, &small, &NoProgress, &mut |_, _| {}).unwrap_err();
    let msg = err.to_string();
    assert!(msg.contains("bricks"), "{msg}");
    assert!(
        matches!(err, asperity_core::CoreError::MemoryLimit { .. }),
        "{msg}"
    );
}
