//! General spectra of tensor operators (issue #40 item 3), checked against truths
//! no one here chose: the analytic curvature of Bézier patches whose tensor
//! operators repeat eigenvalues (quadratic ⊗ cubic, cubic ⊗ cubic), the orbit of
//! the operator itself, and the factor-wise DCFs the gallery draws today.

mod common;

use asperity_ifs::curvature::{sdcf_curvature, sides};
use asperity_ifs::invariant::{Decomposition, sdcf};
use asperity_ifs::model::takagi_operators;
use asperity_ifs::spectrum::{Structure, spectrum};
use asperity_ifs::{
    DirectionAnalysis, FamilyOptions, Model, Pifs, PresetParams, SurfaceIfs, preset,
};
use common::patch_curvature;
use nalgebra::{DMatrix, DVector};

fn factor(name: &str) -> Pifs {
    match preset(name, &PresetParams::default())
        .unwrap()
        .build()
        .unwrap()
    {
        Model::Curve(c) => c.pifs,
        Model::Surface(_) => panic!("{name} is a surface"),
    }
}

fn takagi_surface(w: f64) -> SurfaceIfs {
    let p = PresetParams {
        w: Some(w),
        ..Default::default()
    };
    match preset("takagi-landsberg-surface", &p)
        .unwrap()
        .build()
        .unwrap()
    {
        Model::Surface(s) => s,
        Model::Curve(_) => unreachable!(),
    }
}

/// A wavy (n+1)×(m+1) control grid that no generator here produced.
fn patch(s: Pifs, t: Pifs) -> SurfaceIfs {
    let (n, m) = (s.size(), t.size());
    let grid: Vec<Vec<Vec<f64>>> = (0..n)
        .map(|a| {
            (0..m)
                .map(|b| {
                    let (x, y) = (a as f64 / (n - 1) as f64, b as f64 / (m - 1) as f64);
                    vec![
                        x + 0.07 * (3.1 * y).sin(),
                        y + 0.05 * (2.3 * x).cos(),
                        0.4 * (1.7 * x + 0.3).sin() * (2.9 * y - 0.2).cos() + 0.2 * x * y,
                    ]
                })
                .collect()
        })
        .collect();
    SurfaceIfs::new(s, t, &grid).unwrap()
}

#[test]
fn bezier_tensor_operators_repeat_eigenvalues_and_give_the_analytic_curvature() {
    for (ds, dt) in [
        ("bezier-quadratic", "bezier-cubic"),
        ("bezier-cubic", "bezier-cubic"),
    ] {
        let surf = patch(factor(ds), factor(dt));
        let (n, m) = surf.grid_size();
        // The spectrum of 𝒯ᵢⱼ: 2^−k with multiplicity #{(a, b): a + b = k}.
        for (i, j) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
            let big = surf.operator(i, j);
            let d = Decomposition::new(&big).unwrap();
            assert!(d.is_diagonalisable(), "{ds}⊗{dt} 𝒯{i}{j}");
            assert_eq!(d.parts.len(), n + m - 1);
            let (fs, ft) = (
                Decomposition::new(surf.s.operator(i)).unwrap(),
                Decomposition::new(surf.t.operator(j)).unwrap(),
            );
            for (k, part) in d.parts.iter().enumerate() {
                let pairs: Vec<(usize, usize)> = (0..n)
                    .flat_map(|a| (0..m).map(move |b| (a, b)))
                    .filter(|(a, b)| a + b == k)
                    .collect();
                assert!((part.value - 0.5f64.powi(k as i32)).abs() < 1e-12);
                assert_eq!(part.multiplicity, pairs.len(), "𝒯{i}{j} λ = 2^-{k}");
                assert_eq!(part.eigenvectors, pairs.len());
                assert_eq!(part.alpha, k as f64);
                // 𝒯's invariant subspace is the sum of the factors' products.
                let sum = pairs
                    .iter()
                    .fold(DMatrix::zeros(n * m, n * m), |acc, &(a, b)| {
                        acc + fs.parts[a].projector.kronecker(&ft.parts[b].projector)
                    });
                let err = (&part.projector - sum).amax();
                assert!(err < 1e-9, "{ds}⊗{dt} 𝒯{i}{j} Π for 2^-{k}: {err:e}");
            }
            // The first-eigenvector code accepts it too (no refusal).
            assert!(matches!(
                spectrum(&big).unwrap().structure,
                Structure::Diagonalisable { .. }
            ));
        }
        // 𝒦 and ℋ at the corners and dyadic points, every quadrant, two starts.
        let points = [
            (0.0, 0.0),
            (1.0, 0.0),
            (0.0, 1.0),
            (1.0, 1.0),
            (0.5, 0.25),
            (0.75, 0.5),
            (0.25, 1.0),
            (0.5, 0.5),
            (0.375, 0.625),
        ];
        let mut checked = 0;
        for (u, v) in points {
            let (k_an, h_an) = patch_curvature(&surf, u, v);
            for side_s in sides(&surf.s, u).unwrap() {
                for side_t in sides(&surf.t, v).unwrap() {
                    let (i, j) = (side_s.operator, side_t.operator);
                    let (fs, ft) = (
                        Decomposition::new(surf.s.operator(i)).unwrap(),
                        Decomposition::new(surf.t.operator(j)).unwrap(),
                    );
                    let sigma = |op: usize| if op == 0 { 1.0 } else { -1.0 };
                    for start in [0.3f64, 0.8] {
                        // Any starting point off the fixed point: the other half's.
                        let (q, q2) = (
                            surf.s
                                .point_at(if i == 0 {
                                    start.max(0.55)
                                } else {
                                    start.min(0.45)
                                })
                                .unwrap(),
                            surf.t
                                .point_at(if j == 0 {
                                    1.0 - start * 0.4
                                } else {
                                    start * 0.4
                                })
                                .unwrap(),
                        );
                        let r = sdcf_curvature(
                            &surf,
                            (&fs, &q, &side_s.matrix, sigma(i)),
                            (&ft, &q2, &side_t.matrix, sigma(j)),
                        )
                        .unwrap();
                        for (got, want, what) in [(r.gaussian, k_an, "𝒦"), (r.mean, h_an, "ℋ")]
                        {
                            assert!(
                                (got[0] - want).abs() < 1e-9 && (got[1] - want).abs() < 1e-9,
                                "{ds}⊗{dt} at ({u}, {v}) {} {}: {what} {got:?} vs {want}",
                                side_s.side,
                                side_t.side
                            );
                        }
                        checked += 1;
                    }
                }
            }
        }
        assert_eq!(checked, 2 * (4 + 4 + 4 + 2 + 4 + 4));
    }
}

#[test]
fn the_square_takagi_dcf_of_t00_is_todays_sdcf_diagonal() {
    let opts = FamilyOptions::default();
    for w in [0.5f64.sqrt(), 0.6, 0.25] {
        let surf = takagi_surface(w);
        for (i, j) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
            let d = Decomposition::new(&surf.operator(i, j)).unwrap();
            assert!(d.is_diagonalisable(), "w = {w} 𝒯{i}{j}");
            assert_eq!(d.parts[1].multiplicity, 2, "w = {w}: λ₁ = λ′₁ twice");
        }
        let (an_s, an_t) = (
            DirectionAnalysis::new(&surf.s, &opts),
            DirectionAnalysis::new(&surf.t, &opts),
        );
        let (a, b) = (
            an_s.operators[0].dcf.as_ref().unwrap(),
            an_t.operators[0].dcf.as_ref().unwrap(),
        );
        // Fig. 4's start: the opposite corner Q = c₁ ⊗ c′₁.
        let (q, q2) = (surf.s.fixed_point(1), surf.t.fixed_point(1));
        let big_q = q.kronecker(q2);
        let general = Decomposition::new(&surf.operator(0, 0)).unwrap();
        for k in 0..=64 {
            let t = k as f64 / 64.0;
            let today = a.evaluate(q, t).kronecker(&b.evaluate(q2, t));
            let got = general.dcf(&big_q, t.max(1e-300));
            assert!(
                (&got - &today).amax() < 1e-12,
                "w = {w}, t = {t}: {got} vs {today}"
            );
        }
    }
}

#[test]
fn the_dcf_of_a_tensor_operator_is_a_curve_on_its_sdcf() {
    let m = |rows: Vec<Vec<f64>>| DMatrix::from_fn(rows.len(), rows.len(), |r, c| rows[r][c]);
    let cubic = factor("bezier-cubic");
    let cases: Vec<(&str, DMatrix<f64>, DMatrix<f64>)> = vec![
        // λ₁ = 0.6 against ½: the curve is (t, t^{ln ½ / ln 0.6}).
        (
            "Takagi 0.6 ⊗ cubic",
            m(takagi_operators(0.6)[0].clone()),
            cubic.operator(0).clone(),
        ),
        // A Jordan block in one factor: log t terms on both sides.
        (
            "Takagi ½ ⊗ cubic",
            m(takagi_operators(0.5)[0].clone()),
            cubic.operator(1).clone(),
        ),
        (
            "Takagi ½ ⊗ Takagi ½",
            m(takagi_operators(0.5)[0].clone()),
            m(takagi_operators(0.5)[1].clone()),
        ),
    ];
    for (name, s, t) in cases {
        let big = s.kronecker(&t);
        let (ds, dt, d) = (
            Decomposition::new(&s).unwrap(),
            Decomposition::new(&t).unwrap(),
            Decomposition::new(&big).unwrap(),
        );
        let l1 = d.lambda1();
        let (a, b) = (ds.lambda1().ln() / l1.ln(), dt.lambda1().ln() / l1.ln());
        let q = DVector::from_vec(vec![0.2, 0.3, 0.5]);
        let q2 = DVector::from_fn(t.nrows(), |r, _| [0.1, 0.4, 0.3, 0.2][r]);
        let big_q = q.kronecker(&q2);
        let mut orbit = big_q.clone();
        for n in 0..10 {
            let tau = l1.powi(n);
            let on_sdcf = sdcf((&ds, &q), (&dt, &q2), tau.powf(a), tau.powf(b));
            let got = d.dcf(&big_q, tau);
            assert!((&got - &on_sdcf).amax() < 1e-9, "{name} n = {n}");
            // Both pass through the orbit 𝒯ⁿQ.
            assert!((&got - &orbit).amax() < 1e-9, "{name} orbit n = {n}");
            orbit = &big * orbit;
        }
        for k in 1..=20 {
            let tau = k as f64 / 20.0;
            let on_sdcf = sdcf((&ds, &q), (&dt, &q2), tau.powf(a), tau.powf(b));
            assert!(
                (d.dcf(&big_q, tau) - on_sdcf).amax() < 1e-9,
                "{name} t = {tau}"
            );
        }
    }
}

/// The curvature report lists each tensor operator's own spectrum: for
/// quadratic ⊗ cubic every 𝒯ᵢⱼ has the eigenvalues 2^{−k} with multiplicity
/// #{a + b = k : a ≤ 2, b ≤ 3} = 1, 2, 3, 3, 2, 1, all with full eigenspaces.
/// On the square Takagi ½ surface each factor is 1 ⊕ J₂(½), so by the Kronecker
/// products of Jordan blocks every 𝒯ᵢⱼ is 1 ⊕ 2·J₂(½) ⊕ J₃(¼) ⊕ J₁(¼): ½ four
/// times with two eigenvectors, ¼ four times with two.
#[test]
fn the_curvature_report_lists_each_tensor_operators_spectrum() {
    // (λ, algebraic, geometric multiplicity) of every 𝒯ᵢⱼ, and its class.
    let check = |s: &SurfaceIfs, want: &[(f64, usize, usize)], class: &str| {
        use asperity_ifs::curvature::surface_report;
        let opts = FamilyOptions::default();
        let (an_s, an_t) = (
            DirectionAnalysis::new(&s.s, &opts),
            DirectionAnalysis::new(&s.t, &opts),
        );
        let report = surface_report(s, &an_s, &an_t);
        assert_eq!(report.len(), 4);
        for op in &report {
            let got: Vec<(f64, usize, usize)> = op
                .tensor_spectrum
                .as_ref()
                .expect("a real spectrum")
                .iter()
                .map(|p| (p.value, p.multiplicity, p.eigenvectors))
                .collect();
            assert_eq!(got.len(), want.len(), "{:?}: {got:?}", op.index);
            for (g, w) in got.iter().zip(want) {
                assert!(
                    (g.0 - w.0).abs() < 1e-9 && (g.1, g.2) == (w.1, w.2),
                    "{:?}: {got:?}",
                    op.index
                );
            }
            assert_eq!(op.class, class);
        }
    };
    let bezier: Vec<(f64, usize, usize)> = [1, 2, 3, 3, 2, 1]
        .iter()
        .enumerate()
        .map(|(k, &m)| (0.5f64.powi(k as i32), m, m))
        .collect();
    check(
        &patch(factor("bezier-quadratic"), factor("bezier-cubic")),
        &bezier,
        "finite",
    );
    check(
        &takagi_surface(0.5),
        &[(1.0, 1, 1), (0.5, 4, 2), (0.25, 4, 2)],
        "non-diagonalisable",
    );
}
