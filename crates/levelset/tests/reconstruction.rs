//! The checks for the reconstruction pipeline, against analytic shapes and
//! a real DLA deposit.

use asperity_core::{CoreError, MemoryBudget, NoProgress, TriMesh};
use asperity_levelset::{Length, ReconstructParams, Reconstruction, Sizing, reconstruct};

/// Fibonacci points on a sphere of radius `r` about `c`.
fn sphere(n: usize, r: f64, c: [f64; 3]) -> Vec<[f64; 3]> {
    asperity_core::shapes::fibonacci_sphere(n)
        .into_iter()
        .map(|p| std::array::from_fn(|a| c[a] + r * p[a]))
        .collect()
}

/// Points on a torus (radii `big`, `small`) on a `n × m` grid of angles.
fn torus(n: usize, m: usize, big: f64, small: f64) -> Vec<[f64; 3]> {
    asperity_core::shapes::torus_quads(big, small, n, m)
        .positions()
        .to_vec()
}

fn run(points: &[[f64; 3]], params: &ReconstructParams) -> Reconstruction {
    reconstruct(
        points,
        params,
        &MemoryBudget::unlimited(),
        &NoProgress,
        &mut |_, _| {},
    )
    .unwrap()
}

/// Distance from each query to the nearest of `set`, by a uniform hash grid.
fn nearest_distances(queries: &[[f64; 3]], set: &[[f64; 3]], cell: f64) -> Vec<f64> {
    use std::collections::HashMap;
    let key = |p: &[f64; 3]| p.map(|x| (x / cell).floor() as i64);
    let mut map: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (i, p) in set.iter().enumerate() {
        map.entry(key(p)).or_default().push(i);
    }
    queries
        .iter()
        .map(|q| {
            let k = key(q);
            let mut best = f64::INFINITY;
            for ring in 0..64i64 {
                for dx in -ring..=ring {
                    for dy in -ring..=ring {
                        for dz in -ring..=ring {
                            if dx.abs().max(dy.abs()).max(dz.abs()) != ring {
                                continue;
                            }
                            if let Some(v) = map.get(&[k[0] + dx, k[1] + dy, k[2] + dz]) {
                                for &i in v {
                                    let p = set[i];
                                    let d = ((p[0] - q[0]).powi(2)
                                        + (p[1] - q[1]).powi(2)
                                        + (p[2] - q[2]).powi(2))
                                    .sqrt();
                                    best = best.min(d);
                                }
                            }
                        }
                    }
                }
                if best <= ring as f64 * cell {
                    break;
                }
            }
            best
        })
        .collect()
}

fn closed_manifold(mesh: &TriMesh) {
    assert!(mesh.n_faces() > 0);
    assert!(mesh.is_watertight(), "not watertight");
    assert!(mesh.is_manifold(), "not manifold");
    assert!(mesh.is_consistently_oriented());
}

#[test]
fn sphere_points_give_a_closed_sphere_within_one_and_a_half_cells() {
    let r = 1.0;
    let pts = sphere(20_000, r, [0.0; 3]);
    let rec = run(
        &pts,
        &ReconstructParams {
            sizing: Sizing::Resolution(40),
            ..Default::default()
        },
    );
    let h = rec.grid.spacing;
    let mesh = &rec.mesh;
    closed_manifold(mesh);
    assert_eq!(mesh.euler_characteristic(), 2);
    assert_eq!(rec.extraction.components, 1);
    // Mesh → sphere.
    for p in mesh.positions() {
        let d = ((p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - r).abs();
        assert!(d <= 1.5 * h, "vertex {d} from the sphere (h {h})");
    }
    // Sphere → mesh: every sample has a vertex within 1.5h.
    let back = nearest_distances(&pts, mesh.positions(), h);
    let worst = back.iter().copied().fold(0.0, f64::max);
    assert!(
        worst <= 1.5 * h,
        "a sample is {worst} from the mesh (h {h})"
    );
    // The flow moved the front from ε = 3h onto the data.
    let to_data = nearest_distances(mesh.positions(), &pts, h);
    let mean = to_data.iter().sum::<f64>() / to_data.len() as f64;
    assert!(mean < 0.75 * h, "mean vertex distance {mean} (h {h})");
    assert!(rec.evolution.steps.len() == 30);
}

/// The paper's distance method gives the same kind of surface, with the same
/// sample spacing (and so the same arrest δ) as the closest-point method.
#[test]
fn godunov_distance_reconstructs_the_sphere_too() {
    let pts = sphere(8000, 1.0, [0.0; 3]);
    let rec = run(
        &pts,
        &ReconstructParams {
            sizing: Sizing::Resolution(32),
            distance: asperity_levelset::DistanceMethod::GODUNOV,
            ..Default::default()
        },
    );
    closed_manifold(&rec.mesh);
    assert_eq!(rec.mesh.euler_characteristic(), 2);
    assert_eq!(rec.extraction.components, 1);
    // Fibonacci points on the unit sphere: spacing ≈ √(4π/n) ≈ 0.040 between
    // nearest neighbours, and up to √3 times that between Voronoi neighbours.
    let s = rec.sample_spacing.unwrap();
    assert!((0.04..0.07).contains(&s), "spacing {s}");
    let closest = run(
        &pts,
        &ReconstructParams {
            sizing: Sizing::Resolution(32),
            ..Default::default()
        },
    );
    // The wavefronts differ (a 2h band here, the whole tube there), so a
    // node's nearest point can differ at a tie: the medians agree within 2 %.
    let c = closest.sample_spacing.unwrap();
    assert!((c - s).abs() < 0.02 * c, "{c} against {s}");
}

#[test]
fn torus_points_keep_genus_one() {
    let pts = torus(240, 80, 1.0, 0.35);
    let rec = run(
        &pts,
        &ReconstructParams {
            sizing: Sizing::Resolution(64),
            ..Default::default()
        },
    );
    closed_manifold(&rec.mesh);
    assert_eq!(rec.mesh.genus(), Some(1));
}

/// Two spheres 0.3 apart: an offset ε above half the gap joins them in the
/// initial surface, and the flow separates them again (the bridge lies at
/// distance 0.15 from the data and moves in); a smaller ε keeps them apart from
/// the start.
#[test]
fn two_nearby_spheres_are_two_components_after_the_flow() {
    let mut pts = sphere(8000, 0.6, [-0.75, 0.0, 0.0]);
    pts.extend(sphere(8000, 0.6, [0.75, 0.0, 0.0]));
    for (offset, initial_components) in [(0.25, 1), (0.1, 2)] {
        let mut initial = 0;
        let rec = reconstruct(
            &pts,
            &ReconstructParams {
                sizing: Sizing::Resolution(64),
                offset: Some(Length::World(offset)),
                ..Default::default()
            },
            &MemoryBudget::unlimited(),
            &NoProgress,
            &mut |s, ls| {
                if s.step == 0 {
                    let (_, stats) = ls.extract(&Default::default());
                    initial = stats.components;
                }
            },
        )
        .unwrap();
        assert_eq!(initial, initial_components, "ε = {offset}: initial surface");
        closed_manifold(&rec.mesh);
        assert_eq!(rec.extraction.components, 2, "ε = {offset}: final surface");
        assert_eq!(rec.mesh.euler_characteristic(), 4);
    }
}

/// The paper's Fig. 9 pipeline on a small lattice: DLA from the plane between
/// walls, then reconstruction with ε = 3 (the paper's) at h = 0.7: one piece.
/// Arches make the genus positive, and the flow brings the front onto the particles (measured: mean
/// vertex distance 0.55 lattice units; 30 steps leave the deepest crevices at 0.78).
#[test]
fn dla_terrain_is_watertight_with_arches_and_hugs_the_particles() {
    use asperity_growth::dla::{DlaParams, SeedShape, Sides, dla};
    let params = DlaParams {
        dim: 3,
        size: [32, 32, 32],
        particles: 2500,
        stick: 1.0,
        seed_shape: SeedShape::Plane,
        launch_gap: 2.0,
        sides: Sides::Walls,
    };
    let cluster = dla(&params, 7, 0, &MemoryBudget::unlimited(), &NoProgress).unwrap();
    let pts = cluster.points();
    let rec = run(
        &pts,
        &ReconstructParams {
            sizing: Sizing::Spacing(0.7),
            offset: Some(Length::World(3.0)),
            iterations: 60,
            ..Default::default()
        },
    );
    let h = rec.grid.spacing;
    closed_manifold(&rec.mesh);
    assert_eq!(rec.extraction.components - rec.extraction.shells_removed, 1);
    let genus = rec.mesh.genus().unwrap();
    assert!(genus > 0, "genus {genus}");
    assert!(
        (rec.sample_spacing.unwrap() - 1.0).abs() < 0.05,
        "{:?}",
        rec.sample_spacing
    );
    let to_data = nearest_distances(rec.mesh.positions(), &pts, 1.0);
    let mean = to_data.iter().sum::<f64>() / to_data.len() as f64;
    assert!(mean < h, "mean vertex distance {mean} ≥ h = {h}");
}

#[test]
fn same_mesh_with_one_or_two_threads() {
    let pts = torus(120, 40, 1.0, 0.35);
    let params = ReconstructParams {
        sizing: Sizing::Resolution(40),
        ..Default::default()
    };
    let with = |n: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
            .install(|| run(&pts, &params))
    };
    let (a, b) = (with(1), with(2));
    assert_eq!(a.mesh.positions(), b.mesh.positions());
    assert_eq!(a.mesh.triangles(), b.mesh.triangles());
}

#[test]
fn bad_input_gets_a_clear_error() {
    let b = MemoryBudget::unlimited();
    let p = ReconstructParams::default();
    let err = |pts: &[[f64; 3]], p: &ReconstructParams, b: &MemoryBudget| {
        reconstruct(pts, p, b, &NoProgress, &mut |_, _| {}).unwrap_err()
    };
    assert!(matches!(err(&[], &p, &b), CoreError::Empty(_)));
    assert!(matches!(
        err(&[[0.0, f64::NAN, 1.0]], &p, &b),
        CoreError::NonFinite { .. }
    ));
    let e = err(&[[1.0; 3]; 5], &p, &b);
    assert!(e.to_string().contains("identical"), "{e}");
    let small = MemoryBudget::new(10 << 20);
    let e = err(
        &sphere(100, 1.0, [0.0; 3]),
        &ReconstructParams {
            sizing: Sizing::Resolution(512),
            ..p
        },
        &small,
    );
    assert!(matches!(e, CoreError::MemoryLimit { .. }), "{e}");
    let e = err(
        &sphere(100, 1.0, [0.0; 3]),
        &ReconstructParams {
            offset: Some(Length::World(-1.0)),
            ..p
        },
        &b,
    );
    assert!(e.to_string().contains("offset"), "{e}");
}
