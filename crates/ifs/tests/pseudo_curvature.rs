//! Checks against truths no one here chose: classical Bézier curvature, the
//! analytic curvature of a bicubic patch, the Takagi–Landsberg closed forms, the
//! Takagi series itself, and the Hutchinson fixed-point property.

mod common;

use asperity_core::vec3::{cross, dot};
use asperity_ifs::curvature::{curve_at, curve_report, surface_at, surface_report};
use asperity_ifs::model::{TAKAGI_SHEAR, takagi_grid, takagi_operators};
use asperity_ifs::{
    CurveClass, CurveIfs, DirectionAnalysis, FamilyOptions, Model, Pifs, PresetParams, SurfaceIfs,
    preset,
};
use common::{bezier_derivative, patch_curvature};

fn curve(name: &str, p: PresetParams) -> CurveIfs {
    match preset(name, &p).unwrap().build().unwrap() {
        Model::Curve(c) => c,
        Model::Surface(_) => panic!("{name} is a surface"),
    }
}

fn surface(name: &str, p: PresetParams) -> SurfaceIfs {
    match preset(name, &p).unwrap().build().unwrap() {
        Model::Surface(s) => s,
        Model::Curve(_) => panic!("{name} is a curve"),
    }
}

fn takagi(w: f64) -> CurveIfs {
    curve(
        "takagi-landsberg",
        PresetParams {
            w: Some(w),
            ..Default::default()
        },
    )
}

fn classical_curvature(pts: &[[f64; 3]], u: f64) -> f64 {
    let d1 = bezier_derivative(pts, 1, u);
    let d2 = bezier_derivative(pts, 2, u);
    cross(d1, d2)[2] / dot(d1, d1).powf(1.5)
}

#[test]
fn bezier_dcf_reproduces_classical_curvature_everywhere() {
    let cases = [
        ("bezier-quadratic", None),
        ("bezier-cubic", None),
        ("bezier", Some(5)),
    ];
    for (name, degree) in cases {
        let c = curve(
            name,
            PresetParams {
                degree,
                ..Default::default()
            },
        );
        let an = DirectionAnalysis::new(&c.pifs, &FamilyOptions::default());
        for a in &an.operators {
            assert_eq!(a.class, CurveClass::Finite, "{name}");
            let d = a.dcf.as_ref().unwrap();
            assert_eq!(d.alpha2(), 2.0);
            // The family collapses to one value (c₂ is the same for every starting point).
            let (lo, hi) = (d.lower().unwrap().c2, d.upper().unwrap().c2);
            assert!(
                (hi - lo).abs() < 1e-12 * lo.abs().max(1.0) && lo != 0.0,
                "{name}: c2 in [{lo}, {hi}]"
            );
            assert!(d.members.len() > 4000, "{}", d.members.len());
        }
        for s in [0.0, 0.125, 0.25, 0.375, 0.5, 0.75, 1.0] {
            let report = curve_at(&c, &an, s).unwrap();
            let exact = classical_curvature(c.control(), s);
            assert_eq!(report.sides.len(), if s == 0.0 || s == 1.0 { 1 } else { 2 });
            for side in &report.sides {
                let [lo, hi] = side.curvature.unwrap();
                assert!(
                    (lo - exact).abs() < 1e-12 && (hi - exact).abs() < 1e-12,
                    "{name} at {s} ({}): [{lo}, {hi}] vs classical {exact}",
                    side.side
                );
            }
        }
    }
    // The example: κ(0) = 0.5 for (0,0), (1,0), (1,1).
    let c = curve("bezier-quadratic", PresetParams::default());
    let an = DirectionAnalysis::new(&c.pifs, &FamilyOptions::default());
    let r = curve_report(&c, &an);
    let [lo, hi] = r[0].curvature.unwrap();
    assert!((lo - 0.5).abs() < 1e-12 && (hi - 0.5).abs() < 1e-12);
}

#[test]
fn takagi_classes_and_closed_forms() {
    let opts = FamilyOptions::default();
    let class = |w: f64| {
        let c = takagi(w);
        DirectionAnalysis::new(&c.pifs, &opts).operators[0].class
    };
    assert_eq!(class(0.2), CurveClass::Zero);
    assert_eq!(class(0.35), CurveClass::Infinite);
    assert_eq!(class(0.5), CurveClass::NonDiagonalisable);
    assert_eq!(class(0.6), CurveClass::Infinite);
    assert_eq!(class(0.8), CurveClass::Zero);

    // w = 1/√2: α₂ = 2 exactly and a true range [−(6 − 4√2), −(102 − 72√2)]
    // (negative: the curve leaves (0,0) upwards and turns right).
    let c = takagi(std::f64::consts::FRAC_1_SQRT_2);
    let an = DirectionAnalysis::new(&c.pifs, &opts);
    let a = &an.operators[0];
    assert_eq!(a.class, CurveClass::Finite);
    assert_eq!(a.dcf.as_ref().unwrap().alpha2(), 2.0);
    let r = curve_report(&c, &an);
    let [lo, hi] = r[0].curvature.unwrap();
    let sq2 = std::f64::consts::SQRT_2;
    assert!((lo + (6.0 - 4.0 * sq2)).abs() < 1e-9, "min {lo}");
    assert!((hi + (102.0 - 72.0 * sq2)).abs() < 1e-9, "max {hi}");
    // The extremes sit at the dyadic 1/2 (or 1) and at the periodic 2/3.
    let fam = r[0].family.as_ref().unwrap();
    assert!([0.5, 1.0].contains(&fam.lower_start), "{fam:?}");
    assert!((fam.upper_start - 2.0 / 3.0).abs() < 1e-12, "{fam:?}");

    // w = 1/4 is the parabola y = 2x(1 − x): one value, −4/5^{3/2}.
    let c = takagi(0.25);
    let an = DirectionAnalysis::new(&c.pifs, &opts);
    let [lo, hi] = curve_report(&c, &an)[0].curvature.unwrap();
    let exact = -4.0 / 5f64.powf(1.5);
    assert!(
        (lo - exact).abs() < 1e-12 && (hi - exact).abs() < 1e-12,
        "[{lo}, {hi}]"
    );
    // …and at every dyadic point it is the parabola's curvature.
    for s in [0.25, 0.5, 0.625] {
        let y1: f64 = 2.0 - 4.0 * s;
        let k = -4.0 / (1.0 + y1 * y1).powf(1.5);
        for side in curve_at(&c, &an, s).unwrap().sides {
            let [lo, hi] = side.curvature.unwrap();
            assert!(
                (lo - k).abs() < 1e-12 && (hi - k).abs() < 1e-12,
                "{s}: {lo} {hi} {k}"
            );
        }
    }
    // w = 1/2 is reported, never NaN.
    let c = takagi(0.5);
    let an = DirectionAnalysis::new(&c.pifs, &opts);
    let r = curve_report(&c, &an);
    assert_eq!(r[0].class, "non-diagonalisable");
    assert!(r[0].curvature.is_none() && r[0].reason.is_some());
    let json = serde_json::to_string(&r).unwrap();
    assert!(!json.contains("NaN"), "{json}");
}

#[test]
fn takagi_attractor_is_the_series() {
    for w in [0.3, 0.6, std::f64::consts::FRAC_1_SQRT_2] {
        let c = takagi(w);
        let depth = 10;
        let pts = c.attractor(depth).unwrap();
        for (k, p) in pts.iter().enumerate() {
            let x = k as f64 / (1 << depth) as f64;
            let y: f64 = (0..80)
                .map(|n| {
                    let t = x * 2f64.powi(n);
                    w.powi(n) * (t - t.round()).abs()
                })
                .sum();
            assert!(
                (p[0] - x).abs() < 1e-12 && (p[1] - y).abs() < 1e-9,
                "{w} {x}: {p:?} vs {y}"
            );
        }
    }
}

fn all_models() -> Vec<(String, Model)> {
    asperity_ifs::preset_names()
        .iter()
        .map(|(n, _)| {
            (
                n.to_string(),
                preset(n, &PresetParams::default())
                    .unwrap()
                    .build()
                    .unwrap(),
            )
        })
        .collect()
}

fn adjacency(p: &Pifs) -> f64 {
    (p.operator(0) * p.fixed_point(1) - p.operator(1) * p.fixed_point(0)).amax()
}

#[test]
fn attractors_are_hutchinson_fixed_points_and_continuous() {
    for (name, m) in all_models() {
        match m {
            Model::Curve(c) => {
                assert!(adjacency(&c.pifs) < 1e-12, "{name}");
                let d = 8;
                let n = c.pifs.size();
                let a = c.pifs.dyadic_points(d);
                let fine = c.attractor(d + 1).unwrap();
                // H(A_d) = T0(A_d) ∪ T1(A_d) lands exactly on A_{d+1}, and contains A_d.
                for (k, q) in a.chunks_exact(n).enumerate() {
                    for b in 0..2 {
                        let img = c.pifs.operator(b) * nalgebra::DVector::from_column_slice(q);
                        let p = c.project(img.as_slice());
                        let f = fine[b * (1 << d) + k];
                        let err = (0..3).map(|i| (p[i] - f[i]).abs()).fold(0.0, f64::max);
                        assert!(err < 1e-12, "{name}: T{b} point {k} off by {err}");
                    }
                }
                let coarse = c.attractor(d).unwrap();
                for (k, p) in coarse.iter().enumerate() {
                    let f = fine[2 * k];
                    assert!((0..3).all(|i| (p[i] - f[i]).abs() < 1e-12), "{name}");
                }
            }
            Model::Surface(s) => {
                assert!(adjacency(&s.s) < 1e-12 && adjacency(&s.t) < 1e-12, "{name}");
                let d = 4;
                let budget = asperity_core::MemoryBudget::unlimited();
                let fine = s.attractor_mesh(d + 1, &budget).unwrap();
                let (n, m) = s.grid_size();
                let (a, b) = (s.s.dyadic_points(d), s.t.dyadic_points(d));
                let cols = (1 << (d + 1)) + 1;
                for i in 0..2 {
                    for j in 0..2 {
                        // The NM×NM Kronecker operator applied to q⊗q′ (an independent path).
                        let op = s.operator(i, j);
                        for (k, qa) in a.chunks_exact(n).enumerate() {
                            for (l, qb) in b.chunks_exact(m).enumerate() {
                                let q = nalgebra::DVector::from_column_slice(qa)
                                    .kronecker(&nalgebra::DVector::from_column_slice(qb));
                                let img = &op * q;
                                let mut p = [0.0; 3];
                                for (w, c) in img.iter().zip(s.control()) {
                                    for x in 0..3 {
                                        p[x] += w * c[x];
                                    }
                                }
                                let v = (i * (1 << d) + k) * cols + j * (1 << d) + l;
                                let f = fine.positions()[v];
                                let err = (0..3).map(|x| (p[x] - f[x]).abs()).fold(0.0, f64::max);
                                assert!(err < 1e-12, "{name}: 𝒯{i}{j} ({k},{l}) off by {err}");
                            }
                        }
                    }
                }
                assert!(fine.is_edge_manifold() && fine.boundary_loops().len() == 1);
            }
        }
    }
}

#[test]
fn bicubic_patch_pseudo_curvature_is_the_analytic_curvature() {
    let s = surface("bezier-bicubic", PresetParams::default());
    let opts = FamilyOptions::default();
    let (an_s, an_t) = (
        DirectionAnalysis::new(&s.s, &opts),
        DirectionAnalysis::new(&s.t, &opts),
    );
    for r in surface_report(&s, &an_s, &an_t) {
        assert_eq!(r.class, "finite");
        let (k, h) = patch_curvature(&s, r.parameter[0], r.parameter[1]);
        let g = r.gaussian.unwrap();
        let m = r.mean.unwrap();
        assert!(
            (g[0] - k).abs() < 1e-12 && (g[1] - k).abs() < 1e-12,
            "{r:?} vs K={k}"
        );
        assert!(
            (m[0] - h).abs() < 1e-12 && (m[1] - h).abs() < 1e-12,
            "{r:?} vs H={h}"
        );
        let p = r.principal.unwrap();
        let d = (h * h - k).max(0.0).sqrt();
        assert!((p[0][0] - (h + d)).abs() < 1e-9 && (p[1][1] - (h - d)).abs() < 1e-9);
    }
    for (u, v) in [(0.5, 0.25), (0.75, 0.5), (0.0, 0.625), (0.375, 1.0)] {
        let (k, h) = patch_curvature(&s, u, v);
        let at = surface_at(&s, &an_s, &an_t, u, v).unwrap();
        let expected =
            (if u == 0.0 || u == 1.0 { 1 } else { 2 }) * (if v == 0.0 || v == 1.0 { 1 } else { 2 });
        assert_eq!(at.quadrants.len(), expected);
        for q in &at.quadrants {
            let g = q.gaussian.unwrap();
            let m = q.mean.unwrap();
            assert!(
                (g[0] - k).abs() < 1e-11 && (g[1] - k).abs() < 1e-11,
                "({u},{v}) {q:?} K={k}"
            );
            assert!(
                (m[0] - h).abs() < 1e-11 && (m[1] - h).abs() < 1e-11,
                "({u},{v}) {q:?} H={h}"
            );
        }
    }
}

#[test]
fn takagi_surface_ranges_match_the_sdcf_and_the_table() {
    let s = surface("takagi-landsberg-surface", PresetParams::default());
    let opts = FamilyOptions::default();
    let (an_s, an_t) = (
        DirectionAnalysis::new(&s.s, &opts),
        DirectionAnalysis::new(&s.t, &opts),
    );
    let report = surface_report(&s, &an_s, &an_t);
    let r00 = &report[0];
    assert_eq!(r00.class, "finite");
    let g = r00.gaussian.unwrap();
    assert!(g[1] - g[0] > 1e-3, "a true range: {g:?}");

    // Brute force over every pair of family members (not only the bound members),
    // with the SDCF differentiated numerically: for α = (0, 1, 2) the DCF is a
    // quadratic in t, so one-sided differences are exact up to rounding.
    let (a, b) = (&an_s.operators[0], &an_t.operators[0]);
    let (da, db) = (a.dcf.as_ref().unwrap(), b.dcf.as_ref().unwrap());
    let (mut kmin, mut kmax, mut hmin, mut hmax) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    let step = da.members.len() / 40;
    for ma in da.members.iter().step_by(step.max(1)).chain(da.upper()) {
        for mb in db.members.iter().step_by(step.max(1)).chain(db.upper()) {
            let h = 1e-3;
            let at = |i: f64, j: f64| {
                let p = da.evaluate(&ma.point, i * h / ma.x[1]);
                let q = db.evaluate(&mb.point, j * h / mb.x[1]);
                s.project(p.as_slice(), q.as_slice())
            };
            let sub = |x: [f64; 3], y: [f64; 3]| [x[0] - y[0], x[1] - y[1], x[2] - y[2]];
            let add = |x: [f64; 3], y: [f64; 3]| [x[0] + y[0], x[1] + y[1], x[2] + y[2]];
            let sc = |x: [f64; 3], k: f64| [x[0] * k, x[1] * k, x[2] * k];
            let (p00, p10, p20, p01, p02, p11) = (
                at(0., 0.),
                at(1., 0.),
                at(2., 0.),
                at(0., 1.),
                at(0., 2.),
                at(1., 1.),
            );
            let inv = 1.0 / h;
            let inv2 = inv * inv;
            // Exact for quadratics: f′(0) = (−3f0 + 4f1 − f2)/2h, f″ = (f0 − 2f1 + f2)/h².
            let d1 = |f0, f1, f2| sc(add(sc(sub(f1, f0), 4.0), sub(f0, f2)), 0.5 * inv);
            let su = d1(p00, p10, p20);
            let sv = d1(p00, p01, p02);
            let suu = sc(add(sub(p20, sc(p10, 2.0)), p00), inv2);
            let svv = sc(add(sub(p02, sc(p01, 2.0)), p00), inv2);
            let suv = sc(add(sub(sub(p11, p10), p01), p00), inv2);
            let nn = cross(su, sv);
            let len = dot(nn, nn).sqrt();
            let n = sc(nn, 1.0 / len);
            let (e, f, g) = (dot(su, su), dot(su, sv), dot(sv, sv));
            let (l, m, nv) = (dot(suu, n), dot(suv, n), dot(svv, n));
            let det = e * g - f * f;
            let k = (l * nv - m * m) / det;
            let hm = (e * nv + g * l - 2.0 * f * m) / (2.0 * det);
            kmin = kmin.min(k);
            kmax = kmax.max(k);
            hmin = hmin.min(hm);
            hmax = hmax.max(hm);
        }
    }
    let m = r00.mean.unwrap();
    assert!(
        (kmin - g[0]).abs() < 1e-5 && (kmax - g[1]).abs() < 1e-5,
        "K [{kmin}, {kmax}] vs {g:?}"
    );
    assert!(
        (hmin - m[0]).abs() < 1e-5 && (hmax - m[1]).abs() < 1e-5,
        "H [{hmin}, {hmax}] vs {m:?}"
    );

    // The 3×3 table with Takagi factors of different roughness.
    let mixed = |ws: f64, wt: f64| {
        let grid = takagi_grid(0.5, TAKAGI_SHEAR);
        let s = SurfaceIfs::new(
            Pifs::from_rows(&takagi_operators(ws)).unwrap(),
            Pifs::from_rows(&takagi_operators(wt)).unwrap(),
            &grid,
        )
        .unwrap();
        let (a, b) = (
            DirectionAnalysis::new(&s.s, &opts),
            DirectionAnalysis::new(&s.t, &opts),
        );
        surface_report(&s, &a, &b)[0].class
    };
    let r2 = std::f64::consts::FRAC_1_SQRT_2;
    assert_eq!(mixed(0.35, 0.35), "infinite");
    assert_eq!(mixed(0.35, r2), "infinite");
    assert_eq!(mixed(r2, 0.35), "infinite");
    assert_eq!(mixed(0.2, 0.35), "indefinite");
    assert_eq!(mixed(0.35, 0.8), "indefinite");
    assert_eq!(mixed(r2, r2), "finite");
    assert_eq!(mixed(r2, 0.2), "finite");
    assert_eq!(mixed(0.2, 0.8), "finite");
    assert_eq!(mixed(0.5, r2), "non-diagonalisable");

    // Bézier × Bézier through a generic mixed preset: smooth s, rough t.
    let s = surface("bezier-takagi", PresetParams::default());
    let (a, b) = (
        DirectionAnalysis::new(&s.s, &opts),
        DirectionAnalysis::new(&s.t, &opts),
    );
    let r = surface_report(&s, &a, &b);
    assert!(
        r.iter()
            .all(|r| r.class == "finite" && r.class_s == "finite")
    );
}

#[test]
fn per_vertex_curvature_of_the_bicubic_patch_is_analytic_everywhere() {
    let s = surface("bezier-bicubic", PresetParams::default());
    let opts = FamilyOptions::default();
    let (an_s, an_t) = (
        DirectionAnalysis::new(&s.s, &opts),
        DirectionAnalysis::new(&s.t, &opts),
    );
    let depth = 4;
    let attrs = asperity_ifs::curvature::vertex_curvature(&s, &an_s, &an_t, depth).unwrap();
    let get = |n: &str| &attrs.iter().find(|(k, _)| *k == n).unwrap().1;
    let (gmin, gmax, hmin, hmax) = (
        get("gaussian_min"),
        get("gaussian_max"),
        get("mean_min"),
        get("mean_max"),
    );
    let side = (1 << depth) + 1;
    let mesh = s
        .attractor_mesh(depth, &asperity_core::MemoryBudget::unlimited())
        .unwrap();
    assert_eq!(mesh.n_vertices(), gmin.len());
    for k in 0..side {
        for l in 0..side {
            let (u, v) = (k as f64 / (side - 1) as f64, l as f64 / (side - 1) as f64);
            let (kk, hh) = patch_curvature(&s, u, v);
            let i = k * side + l;
            for (x, want) in [(gmin[i], kk), (gmax[i], kk), (hmin[i], hh), (hmax[i], hh)] {
                assert!((x - want).abs() < 1e-10, "({u}, {v}): {x} vs {want}");
            }
        }
    }
}

#[test]
fn the_takagi_surface_is_the_tensor_square_of_the_curve() {
    let c = takagi(std::f64::consts::FRAC_1_SQRT_2);
    let sq = asperity_ifs::model::tensor_square(&c, 0.25, TAKAGI_SHEAR).unwrap();
    let s = surface("takagi-landsberg-surface", PresetParams::default());
    assert_eq!(sq.control(), s.control());
    // Its height is h(T(s) + T(t)).
    let m = s
        .attractor_mesh(5, &asperity_core::MemoryBudget::unlimited())
        .unwrap();
    let curve = c.attractor(5).unwrap();
    for (i, p) in m.positions().iter().enumerate() {
        let (k, l) = (i / 33, i % 33);
        let z = 0.25 * (curve[k][1] + curve[l][1]);
        assert!((p[2] - z).abs() < 1e-12);
    }
    let _ = takagi_grid(0.25, TAKAGI_SHEAR);
}
