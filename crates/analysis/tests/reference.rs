//! Analysis against known answers: self-affine surfaces of known H, spheres and tori.

use asperity_analysis::{areal, fractal, level, mesh, psd};
use asperity_core::fourier_surface::{FourierParams, fourier_surface};
use asperity_core::{MemoryBudget, TriMesh};

#[test]
fn hurst_exponent_is_recovered_from_self_affine_surfaces() {
    let n = 1024;
    for (h_true, seed) in [(0.3, 1), (0.5, 2), (0.5, 3), (0.8, 4)] {
        {
            let p = FourierParams {
                n,
                hurst: h_true,
                modes: n / 2,
                rms: 1.0,
                spacing: 1.0 / n as f64,
            };
            let h = fourier_surface(&p, seed, &MemoryBudget::unlimited()).unwrap();
            let r = psd::radial_psd(&h, 40).unwrap();
            let est = psd::hurst(&r, None).unwrap();
            assert!(
                (est.hurst - h_true).abs() < 0.05,
                "H = {h_true}, seed {seed}: estimated {}",
                est.hurst
            );
            assert!((est.fractal_dimension - (3.0 - est.hurst)).abs() < 1e-15);
            assert!(est.fit.r2 > 0.99, "r² = {}", est.fit.r2);
            // The triangulation estimate models the cell size (erfcx form), so it
            // needs no tall surface: the same heights as the PSD fit.
            let tri = fractal::triangulation(&h, true).unwrap();
            let part = fractal::partitioning(&h).unwrap();
            eprintln!(
                "H = {h_true}: triangulation D = {:.3}, partitioning D = {:.3}",
                tri.d, part.d
            );
            assert!(
                (tri.d - (3.0 - h_true)).abs() < 0.1,
                "triangulation D = {} for H = {h_true}",
                tri.d
            );
            assert!(
                (part.d - (3.0 - h_true)).abs() < 0.1,
                "partitioning D = {} for H = {h_true}",
                part.d
            );
            // The PSD integrates to the mean square height (Parseval, SurfaceTopography convention).
            let c = psd::psd_2d(&h);
            let area = (n as f64 / n as f64).powi(2);
            let ms = h.data().iter().map(|v| v * v).sum::<f64>() / h.len() as f64;
            assert!((c.iter().sum::<f64>() / area - ms).abs() < 1e-9 * ms);
        }
    }
}

#[test]
fn levelling_then_areal_on_a_tilted_sine() {
    let n = 128;
    let tau = std::f64::consts::TAU;
    // sin·sin is orthogonal to 1, x and y on the grid, so plane levelling of
    // sin·sin + a tilt gives back sin·sin exactly: Sku = 2.25, Sq = 1/2.
    let s2 = |k: usize| {
        (tau * (k % n) as f64 / n as f64).sin() * (tau * (k / n) as f64 / n as f64).sin()
    };
    let f = asperity_core::HeightField::from_vec(
        [n, n],
        (0..n * n)
            .map(|k| s2(k) + 0.3 + 0.01 * (k / n) as f64 - 0.02 * (k % n) as f64)
            .collect(),
    )
    .unwrap();
    let plane = level::level(&f, level::Level::Plane).unwrap();
    let s = areal::areal(&plane, true).unwrap();
    assert!(
        (s.Sku - 2.25).abs() < 1e-9 && (s.Sq - 0.5).abs() < 1e-12,
        "{} {}",
        s.Sku,
        s.Sq
    );
}

#[test]
fn sphere_gauss_bonnet_and_mean_curvature() {
    let r = 3.0;
    let s = asperity_core::shapes::icosphere(4, r);
    assert_eq!(s.euler_characteristic(), 2);
    let c = mesh::curvature(&s);
    assert!(
        (c.total_gaussian - 4.0 * std::f64::consts::PI).abs() < 1e-9,
        "{}",
        c.total_gaussian
    );
    let h = mesh::stats(&c.mean, &c.area);
    assert!((h.mean - 1.0 / r).abs() < 0.01 / r, "mean H = {}", h.mean);
    let k = mesh::stats(&c.gaussian, &c.area);
    assert!(
        (k.mean - 1.0 / (r * r)).abs() < 0.02 / (r * r),
        "mean K = {}",
        k.mean
    );
}

#[test]
fn torus_has_genus_one_and_zero_total_curvature() {
    let torus = asperity_core::shapes::torus(2.0, 0.6, 48, 24);
    assert_eq!(torus.genus(), Some(1));
    assert!(mesh::curvature(&torus).total_gaussian.abs() < 1e-9);
}

#[test]
fn smoothing_roughness_sees_noise_and_box_counting_sees_a_surface() {
    let s = asperity_core::shapes::icosphere(4, 1.0);
    let smooth = mesh::smoothed_roughness(&s, 10);
    // Radial noise of ±0.03 (rms 0.03/√3) on every vertex.
    let mut rng = asperity_core::seeded(3);
    let noisy_p: Vec<[f64; 3]> = s
        .positions()
        .iter()
        .map(|p| {
            let r = 1.0 + 0.03 * (2.0 * rand::Rng::random::<f64>(&mut rng) - 1.0);
            p.map(|c| c * r)
        })
        .collect();
    let noisy = TriMesh::new(noisy_p, s.triangles().to_vec()).unwrap();
    let rough = mesh::smoothed_roughness(&noisy, 10);
    let noise_rms = 0.03 / 3f64.sqrt();
    assert!(
        rough.rms > 5.0 * smooth.rms,
        "{} vs {}",
        rough.rms,
        smooth.rms
    );
    assert!(
        rough.rms > 0.5 * noise_rms && rough.rms < 1.5 * noise_rms,
        "{} vs noise {noise_rms}",
        rough.rms
    );
    // A smooth closed surface has box-counting dimension 2.
    let d = mesh::box_counting(&s).unwrap();
    assert!((d.d - 2.0).abs() < 0.1, "sphere D = {}", d.d);
}

/// A disc given as one 2,000-corner polygon, fan-triangulated into long thin
/// triangles: box counting sees a flat surface (D near 2) and its sampling
/// follows the triangles' lengths, not their squares (#20: a 20,000-corner
/// polygon took 24 GB before).
#[test]
fn box_counting_of_a_fan_of_slivers_is_a_plane() {
    let n = 2000;
    let positions: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            [a.cos(), a.sin(), 0.0]
        })
        .collect();
    let triangles: Vec<[u32; 3]> = (1..n as u32 - 1).map(|i| [0, i, i + 1]).collect();
    let disc = TriMesh::new(positions, triangles).unwrap();
    let d = mesh::box_counting(&disc).unwrap();
    assert!((1.8..2.05).contains(&d.d), "D = {}", d.d);
}
