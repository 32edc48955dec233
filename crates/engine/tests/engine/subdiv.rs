//! The subdivision job's behaviour, tested here rather than through the CLI
//! (issue #36): one behaviour per test, through `SubdivParams` and its
//! `Session`, against analytic values where there are some.

use std::path::Path;

use asperity_engine::core::{MemoryBudget, NoProgress, TriMesh};
use asperity_engine::subdiv::SubdivParams;

fn params(base: &str, levels: usize, detail: &[&str]) -> SubdivParams {
    SubdivParams {
        base: base.into(),
        levels,
        detail: detail.iter().map(|d| d.to_string()).collect(),
        ..Default::default()
    }
}

/// The triangle mesh of `p` with `seed` at time `t`.
fn surface(p: &SubdivParams, seed: u64, t: Option<f64>) -> (TriMesh, Vec<(usize, usize)>) {
    let session = p.open(seed, &MemoryBudget::unlimited()).unwrap();
    let (c, limit, boundary) = session.surface(p, t, &NoProgress).unwrap();
    (c.to_trimesh(limit, boundary).unwrap(), c.counts.clone())
}

/// Catmull–Clark on the [−1, 1]³ cube: 26 vertices after one level, 96 faces
/// after two; the corner's vertex point after two levels is 55/108 on each
/// axis (the vertex rule (Q + 2R + (n − 3)S)/n twice, n = 3).
#[test]
fn the_cube_after_two_levels_has_the_analytic_corner() {
    let (m, counts) = surface(&params("cube", 2, &[]), 7, None);
    assert_eq!(counts[1].0, 26);
    assert_eq!(counts[2].1, 96);
    assert_eq!(m.n_faces(), 192);
    assert_eq!(m.euler_characteristic(), 2);
    let c = m.positions()[m.n_vertices() - 1];
    assert!(c.iter().all(|&x| (x - 55.0 / 108.0).abs() < 1e-12), "{c:?}");
}

#[test]
fn a_surface_of_revolution_is_closed_and_a_flat_profile_is_refused() {
    let d = tempfile::tempdir().unwrap();
    let vase = d.path().join("vase.txt");
    std::fs::write(&vase, "# r z\n0.3 0\n0.6 0.5\n0.25 1.2\n0.4 1.6\n").unwrap();
    let base = format!("revolution:{}", vase.display());
    let (m, _) = surface(&params(&base, 2, &[]), 7, None);
    assert!(m.is_watertight() && m.euler_characteristic() == 2);
    let flat = d.path().join("flat.txt");
    std::fs::write(&flat, "0 0\n0.5 1\n").unwrap();
    let p = params(&format!("revolution:{}", flat.display()), 1, &[]);
    let e = p
        .open(7, &MemoryBudget::unlimited())
        .err()
        .expect("refused");
    assert!(e.to_string().contains("r > 0"), "{e}");
}

#[test]
fn an_animated_detail_changes_over_time() {
    let p = params("sphere", 3, &["tentacle:length=0.05,theta=0..3"]);
    let (a, _) = surface(&p, 7, Some(0.0));
    let (b, _) = surface(&p, 7, Some(1.0));
    assert_eq!(a.n_vertices(), b.n_vertices());
    assert_ne!(a.positions(), b.positions());
}

/// Writes `p`'s surface (polygons, as `subdiv` writes it) to `path` and
/// returns its details file.
fn write_with_details(p: &SubdivParams, path: &Path) -> String {
    let session = p.open(3, &MemoryBudget::unlimited()).unwrap();
    let (c, limit, boundary) = session.surface(p, None, &NoProgress).unwrap();
    let tri = c.to_trimesh(limit, boundary).unwrap();
    asperity_engine::io::write_poly_mesh(path, &c.mesh.mesh, &tri, &Default::default()).unwrap();
    session.details_file(&c)
}

#[test]
fn exported_details_reapplied_to_the_same_base_give_the_same_surface() {
    let d = tempfile::tempdir().unwrap();
    let rock = params("cube", 3, &["rock:amplitude=0.1"]);
    let details = write_with_details(&rock, &d.path().join("a.ply"));
    std::fs::write(d.path().join("d.json"), details).unwrap();
    let again = SubdivParams {
        apply_details: Some(d.path().join("d.json")),
        ..params("cube", 3, &[])
    };
    assert_eq!(
        surface(&again, 3, None).0.positions(),
        surface(&rock, 3, None).0.positions()
    );
}

#[test]
fn a_fine_mesh_analysed_into_details_is_rebuilt() {
    let d = tempfile::tempdir().unwrap();
    let fine = d.path().join("a.ply");
    let rock = params("cube", 3, &["rock:amplitude=0.1"]);
    write_with_details(&rock, &fine);
    let analysed = SubdivParams {
        analyze: Some(fine.clone()),
        ..params("cube", 3, &[])
    };
    let (back, _) = surface(&analysed, 3, None);
    let original = asperity_engine::io::read_mesh(&fine).unwrap();
    for (p, q) in original.positions().iter().zip(back.positions()) {
        assert!((0..3).all(|k| (p[k] - q[k]).abs() < 1e-12), "{p:?} {q:?}");
    }
}
