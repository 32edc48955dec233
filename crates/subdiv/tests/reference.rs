//! Checks of asperity-subdiv against truths no one here chose: Euler
//! characteristics, B-spline normals, symmetry, the paper's dome formula, and
//! exact identities of blending, editing and determinism.

use asperity_core::PolyMesh;
use asperity_subdiv::base;
use asperity_subdiv::blend::{AlphaSource, Blend, Paint, blend, painted_alpha};
use asperity_subdiv::catmull_clark::{
    Boundary, Creased, Topology, limit_normals, limit_positions, subdivide,
};
use asperity_subdiv::compose::{Anchor, Edit, Layer, grow};
use asperity_subdiv::detail::{
    Berry, Feature, Mushroom, Procedure, Rock, Seeds, Spur, Tentacle, TentacleReading,
};
use asperity_subdiv::multires::synthesize;
use asperity_subdiv::scalar::{Planet, scalar_field};

fn smooth(m: PolyMesh) -> Creased {
    Creased::smooth(m)
}

#[test]
fn counts_and_euler_characteristic_over_levels() {
    let mixed = PolyMesh::new(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.5, 1.0, 0.0],
            [2.0, 0.5, 0.0],
            [1.8, 1.4, 0.0],
            [1.0, 1.8, 0.0],
        ],
        &[vec![0u32, 1, 2], vec![1, 3, 4, 5, 2]],
    )
    .unwrap();
    for (m, chi) in [
        (base::cube(), 2),
        (base::torus(1.0, 0.3, 6, 4), 0),
        (base::plane(3), 1),
        (base::cylinder(0.5, 1.0, 5), 2),
        (mixed, 1),
    ] {
        let mut cur = smooth(m);
        for _ in 0..3 {
            let (v, e, f) = (
                cur.mesh.n_vertices(),
                cur.mesh.n_edges(),
                cur.mesh.n_faces(),
            );
            let corners: usize = cur.mesh.faces().map(<[u32]>::len).sum();
            let next = subdivide(&cur, Boundary::EdgeOnly).unwrap();
            let (v2, e2, f2) = (
                next.mesh.n_vertices(),
                next.mesh.n_edges(),
                next.mesh.n_faces(),
            );
            assert_eq!((v2, e2, f2), (v + e + f, 2 * e + corners, corners));
            assert_eq!(v2 as i64 - e2 as i64 + f2 as i64, chi);
            cur = next;
        }
    }
}

/// Uniform cubic B-spline basis and its derivative at t ∈ [0, 1].
fn basis(t: f64) -> ([f64; 4], [f64; 4]) {
    let s = 1.0 - t;
    (
        [
            s * s * s / 6.0,
            (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0,
            (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
            t * t * t / 6.0,
        ],
        [
            -s * s / 2.0,
            (3.0 * t * t - 4.0 * t) / 2.0,
            (-3.0 * t * t + 2.0 * t + 1.0) / 2.0,
            t * t / 2.0,
        ],
    )
}

#[test]
fn limit_normals_equal_the_bspline_normal_and_the_cube_symmetry() {
    // A bumpy 8×8 grid whose x, y are the B-spline parameters.
    let n = 8;
    let mesh = asperity_core::shapes::grid_quads(n, |i, j| {
        ((i * 7 + j * 3) % 5) as f64 * 0.3 - 0.2 * (i as f64 - j as f64).abs()
    });
    let pos = mesh.positions().to_vec();
    let grid = smooth(mesh);
    let l2 = subdivide(
        &subdivide(&grid, Boundary::EdgeOnly).unwrap(),
        Boundary::EdgeOnly,
    )
    .unwrap();
    let lim = limit_positions(&l2, Boundary::EdgeOnly).unwrap();
    let nrm = limit_normals(&l2, Boundary::EdgeOnly).unwrap();
    let mut checked = 0;
    for (q, nq) in lim.iter().zip(&nrm) {
        let (u, v) = (q[0], q[1]);
        if !(2.0..=n as f64 - 3.0).contains(&u) || !(2.0..=n as f64 - 3.0).contains(&v) {
            continue;
        }
        let (i, j) = (
            (u.floor() as usize).min(n - 4),
            (v.floor() as usize).min(n - 4),
        );
        let ((bu, du), (bv, dv)) = (basis(u - i as f64), basis(v - j as f64));
        let (mut su, mut sv) = ([0.0; 3], [0.0; 3]);
        for b in 0..4 {
            for a in 0..4 {
                let p = pos[(j + b - 1) * n + (i + a - 1)];
                for k in 0..3 {
                    su[k] += du[a] * bv[b] * p[k];
                    sv[k] += bu[a] * dv[b] * p[k];
                }
            }
        }
        let c = [
            su[1] * sv[2] - su[2] * sv[1],
            su[2] * sv[0] - su[0] * sv[2],
            su[0] * sv[1] - su[1] * sv[0],
        ];
        let l = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
        for k in 0..3 {
            assert!(
                (nq[k] - c[k] / l).abs() < 1e-12,
                "({u}, {v}): {nq:?} vs {c:?}"
            );
        }
        checked += 1;
    }
    assert!(checked > 100, "{checked}");
    // The cube's corner (valence 3, extraordinary): by symmetry its limit
    // normal is (1, 1, 1)/√3 exactly, at every level.
    let mut cube = subdivide(&smooth(base::cube()), Boundary::EdgeOnly).unwrap();
    for _ in 0..3 {
        let nrm = limit_normals(&cube, Boundary::EdgeOnly).unwrap();
        let c = nrm[nrm.len() - 1];
        for x in c {
            assert!((x - 1.0 / 3f64.sqrt()).abs() < 1e-12, "{c:?}");
        }
        cube = subdivide(&cube, Boundary::EdgeOnly).unwrap();
    }
}

#[test]
fn non_manifold_and_inconsistent_meshes_are_refused() {
    // Two squares touching at one vertex (a bowtie): a non-manifold vertex.
    let bowtie = PolyMesh::new(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [2.0, 1.0, 0.0],
            [2.0, 2.0, 0.0],
            [1.0, 2.0, 0.0],
        ],
        &[[0u32, 1, 2, 3], [2, 4, 5, 6]],
    )
    .unwrap();
    let b = smooth(bowtie);
    let t = Topology::new(&b).unwrap();
    let e = t
        .check_base(b.mesh.face_vertices())
        .unwrap_err()
        .to_string();
    assert!(e.contains("vertex 2"), "{e}");
    assert!(grow(&b, 1, Boundary::EdgeOnly, &Layer::default(), 1).is_err());
    // A flipped face.
    let flipped = PolyMesh::new(
        vec![
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [2.0, 0.0, 0.0],
            [2.0, 1.0, 0.0],
        ],
        &[[0u32, 1, 2, 3], [1, 2, 5, 4]],
    )
    .unwrap();
    let e = subdivide(&smooth(flipped), Boundary::EdgeOnly)
        .unwrap_err()
        .to_string();
    assert!(e.contains("orientation"), "{e}");
    // A face squashed to a line.
    let flat = PolyMesh::new(
        vec![
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [3.0, 1.0, 0.0],
        ],
        &[[0u32, 1, 2], [2, 1, 3]],
    )
    .unwrap();
    let e = grow(&smooth(flat), 1, Boundary::EdgeOnly, &Layer::default(), 1)
        .unwrap_err()
        .to_string();
    assert!(e.contains("face 0 is degenerate"), "{e}");
    // A seed vertex that the base does not have.
    let far = Layer {
        features: vec![Feature {
            procedure: Procedure::Spur(Spur { height: 1.0 }),
            seeds: Seeds::Vertices(vec![8]),
            levels: None,
        }],
        ..Layer::default()
    };
    let e = grow(&smooth(base::cube()), 2, Boundary::EdgeOnly, &far, 1)
        .unwrap_err()
        .to_string();
    assert!(e.contains("seed vertex 8"), "{e}");
}

fn rock_layer(amplitude: f64) -> Layer {
    Layer {
        name: "rock".into(),
        features: vec![Feature::global(Procedure::Rock(Rock::fractal(
            amplitude, 0.5,
        )))],
        edits: Vec::new(),
    }
}

#[test]
fn blending_is_exact_where_alpha_is_zero_or_one() {
    // A 16 × 16 patch over [−10, 10]²; two rocks blended across x = 0.
    let m = base::plane(16);
    let big: Vec<[f64; 3]> = m
        .positions()
        .iter()
        .map(|p| [10.0 * p[0], 10.0 * p[1], 0.0])
        .collect();
    let base = smooth(m.with_positions(big).unwrap());
    let levels = 4;
    let a = grow(&base, levels, Boundary::EdgeOnly, &rock_layer(0.5), 1).unwrap();
    let b = grow(&base, levels, Boundary::EdgeOnly, &rock_layer(0.8), 2).unwrap();
    let how = Blend {
        source: AlphaSource::Plane {
            normal: [1.0, 0.0, 0.0],
            offset: 0.0,
        },
        width: 0.5,
    };
    // Identical inputs blend to the input exactly.
    let (same, _) = blend(
        &base,
        None,
        (&a.details, &a.details),
        levels,
        Boundary::EdgeOnly,
        &how,
    )
    .unwrap();
    assert_eq!(same.finest().mesh.positions(), a.finest().mesh.positions());
    // Far from the seam (beyond level 0's width 2c plus three base edges of
    // subdivision support) the result is bit-identical to each input.
    let (mixed, alpha) = blend(
        &base,
        None,
        (&a.details, &b.details),
        levels,
        Boundary::EdgeOnly,
        &how,
    )
    .unwrap();
    let reference = synthesize(&base, &[], levels, Boundary::EdgeOnly).unwrap();
    let (mut left, mut right, mut seam) = (0, 0, 0);
    for (v, p) in reference[levels].mesh.positions().iter().enumerate() {
        let got = mixed.finest().mesh.positions()[v];
        if p[0] < -1.0 - 3.75 {
            assert_eq!(got, a.finest().mesh.positions()[v]);
            assert_eq!(alpha[v], 0.0);
            left += 1;
        } else if p[0] > 1.0 + 3.75 {
            assert_eq!(got, b.finest().mesh.positions()[v]);
            assert_eq!(alpha[v], 1.0);
            right += 1;
        } else if p[0].abs() < 0.01 {
            assert!(alpha[v] > 0.0 && alpha[v] < 1.0);
            seam += 1;
        }
    }
    assert!(
        left > 1000 && right > 1000 && seam > 10,
        "{left} {right} {seam}"
    );
    // The transition narrows with the level: c/2^(l−1).
    assert!((how.alpha(1, [0.25, 0.0, 0.0], 0.0) - 1.0).abs() < 1e-15);
    assert!(how.alpha(0, [0.25, 0.0, 0.0], 0.0) < 1.0);
    assert_eq!(how.alpha(3, [0.07, 0.0, 0.0], 0.0), 1.0);
    assert!(how.alpha(2, [0.07, 0.0, 0.0], 0.0) < 1.0);
    // A per-vertex alpha map: all 0 gives A, all 1 gives B, bit for bit.
    let n = base.mesh.n_vertices();
    for (value, want) in [(0.0, &a), (1.0, &b)] {
        let map = Blend {
            source: AlphaSource::Map(vec![value; n]),
            width: 0.5,
        };
        let (m, _) = blend(
            &base,
            None,
            (&a.details, &b.details),
            levels,
            Boundary::EdgeOnly,
            &map,
        )
        .unwrap();
        assert_eq!(m.finest().mesh.positions(), want.finest().mesh.positions());
    }
    // A per-vertex alpha map of the wrong size is refused.
    let bad = Blend {
        source: AlphaSource::Map(vec![0.5; 3]),
        width: 0.5,
    };
    assert!(
        blend(
            &base,
            None,
            (&a.details, &b.details),
            levels,
            Boundary::EdgeOnly,
            &bad
        )
        .is_err()
    );
}

#[test]
fn edits_scale_details_with_a_cubic_drop_off() {
    let base = smooth(base::quad_sphere(2));
    let plain = grow(&base, 4, Boundary::EdgeOnly, &rock_layer(0.2), 7).unwrap();
    let with = |factor: f64| {
        let mut l = rock_layer(0.2);
        l.edits.push(Edit {
            at: Anchor::Point([0.0, 0.0, 1.0]),
            radius: 1.0,
            levels: (2, 4),
            factor,
        });
        grow(&base, 4, Boundary::EdgeOnly, &l, 7).unwrap()
    };
    // Factor 1 changes nothing.
    assert_eq!(with(1.0).details, plain.details);
    let smoothed = with(0.0);
    // Level 1 is outside the band: untouched.
    assert_eq!(smoothed.details[0], plain.details[0]);
    for l in 2..=4 {
        let (s, p) = (&smoothed.details[l - 1], &plain.details[l - 1]);
        let changed = s.iter().zip(p).filter(|(a, b)| a != b).count();
        let zeroed = s.iter().filter(|d| d[2] == 0.0).count();
        // A disc of radius 2^l hops around the centre: the centre is zeroed,
        // and most of the surface is untouched.
        assert!(zeroed >= 1 && changed > 0, "level {l}");
        assert!(changed < s.len() / 3, "level {l}: {changed} of {}", s.len());
    }
    assert!(asperity_subdiv::detail::drop_off(0.5) == 0.5);
}

#[test]
fn placement_levels_berry_domes_and_stability() {
    let base = smooth(base::quad_sphere(3));
    // Spurs only at level 3: levels 1, 2 and 4 carry no detail (Fig. 9b).
    let spur = Feature {
        procedure: Procedure::Spur(Spur { height: 2.0 }),
        seeds: Seeds::Points(vec![[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]),
        levels: Some(vec![3]),
    };
    let m = grow(
        &base,
        4,
        Boundary::EdgeOnly,
        &Layer {
            features: vec![spur],
            ..Layer::default()
        },
        1,
    )
    .unwrap();
    assert!(m.details[0].is_empty() && m.details[1].is_empty() && m.details[3].is_empty());
    assert_eq!(m.details[2].iter().filter(|d| d[2] > 0.0).count(), 2);
    // Berry: at its first level the seed vertex rises by height·R exactly
    // (r = 0 in R·√(1 − r²/R²)), and every detail is a dome value ≤ height·R.
    let berry = Feature {
        procedure: Procedure::Berry(Berry {
            radius: 0.4,
            ratio: 0.5,
            children: 4,
            height: 0.5,
        }),
        seeds: Seeds::Points(vec![[0.0, 0.0, 1.0]]),
        levels: Some(vec![2, 3]),
    };
    let m = grow(
        &base,
        3,
        Boundary::EdgeOnly,
        &Layer {
            features: vec![berry],
            ..Layer::default()
        },
        1,
    )
    .unwrap();
    let d2 = &m.details[1];
    let top = d2.iter().map(|d| d[2]).fold(0.0, f64::max);
    assert!((top - 0.5 * 0.4).abs() < 1e-15, "{top}");
    assert!(d2.iter().all(|d| d[2] >= 0.0 && d[0] == 0.0 && d[1] == 0.0));
    // Children at level 3 have half the radius: domes at most 0.1 high.
    let top3 = m.details[2].iter().map(|d| d[2]).fold(0.0, f64::max);
    assert!(top3 > 0.0 && top3 <= 0.1 + 1e-15, "{top3}");
    // Rock details of coarse levels do not change when levels are added.
    let r3 = grow(&base, 3, Boundary::EdgeOnly, &rock_layer(0.1), 5).unwrap();
    let r5 = grow(&base, 5, Boundary::EdgeOnly, &rock_layer(0.1), 5).unwrap();
    assert_eq!(r3.details[..], r5.details[..3]);
}

/// The tentacle (§4.2, Fig. 5) read as a growing limb: after each level the
/// tip stands higher over the sphere by about that level's step length·l,
/// leaning the way the turned direction says, and the limb is thin (only
/// vertices near the seed's axis are raised far); read literally (the offset
/// on the seed vertex alone, sign flipped on even levels), the same
/// parameters leave a stub.
#[test]
fn the_tentacle_grows_a_limb_over_the_levels() {
    let base = smooth(base::quad_sphere(2));
    let radius0 = base.mesh.positions()[0]
        .iter()
        .map(|x| x * x)
        .sum::<f64>()
        .sqrt();
    let tentacle = |reading, levels: usize| {
        let feature = Feature {
            procedure: Procedure::Tentacle(Tentacle {
                length: 0.2,
                theta: 0.5,
                alternate: true,
                twist: true,
                reading,
            }),
            seeds: Seeds::Points(vec![[0.0, 0.0, radius0]]),
            levels: None,
        };
        let m = grow(
            &base,
            levels,
            Boundary::EdgeOnly,
            &Layer {
                features: vec![feature],
                ..Layer::default()
            },
            1,
        )
        .unwrap();
        let p = m.finest().mesh.positions().to_vec();
        let height = |q: &[f64; 3]| q.iter().map(|x| x * x).sum::<f64>().sqrt() - radius0;
        let tip = *p
            .iter()
            .max_by(|a, b| height(a).total_cmp(&height(b)))
            .unwrap();
        let raised = p.iter().filter(|q| height(q) > 0.5 * height(&tip)).count();
        (height(&tip), tip, raised as f64 / p.len() as f64)
    };
    let limb = TentacleReading::Limb {
        radius: 0.45,
        taper: 0.7,
    };
    let grown: Vec<_> = (1..=4).map(|levels| tentacle(limb, levels)).collect();
    for l in 2..=4 {
        // Each step leans 45° off the normal: its rise is length·l/√2,
        // less what the next subdivision smooths away (measured 10–17 %).
        let rise = grown[l - 1].0 - grown[l - 2].0;
        let step = 0.2 * l as f64 / 2f64.sqrt();
        assert!(
            rise > 0.7 * step && rise < 1.05 * step,
            "level {l}: rise {rise}, step {step}"
        );
    }
    let (top, tip, share) = grown[3];
    assert!(
        top > 1.0 && share < 0.01,
        "tip {top}, {share} of the vertices raised"
    );
    // The lean turns with the levels (π/3 each): the tip's bearing moves.
    let bearing = |q: [f64; 3]| q[1].atan2(q[0]).to_degrees();
    let turn = (bearing(tip) - bearing(grown[1].1)).abs();
    assert!(turn > 20.0, "the tip turned {turn}°");
    let (literal, _, _) = tentacle(TentacleReading::Literal, 4);
    assert!(literal < 0.1, "literal reading: a stub of {literal}");
}

/// A painted alpha map: every base vertex takes the value of the nearest
/// painted vertex — duplicated vertices (split at seams) and a finer painted
/// mesh over the base work; a painting of another shape is refused.
#[test]
fn painted_alpha_follows_the_nearest_painted_vertex() {
    let base = base::quad_sphere(1);
    let p = base.positions();
    // Painted: every base vertex twice (as an exporter splits at seams), plus
    // midpoints of consecutive vertices, coloured by the sign of x.
    let mut points: Vec<[f64; 3]> = p.iter().chain(p.iter()).copied().collect();
    points.extend(
        p.windows(2)
            .map(|w| std::array::from_fn(|a| 0.5 * (w[0][a] + w[1][a]))),
    );
    let grey = |q: &[f64; 3]| if q[0] > 0.0 { 255u8 } else { 0 };
    let colors = points.iter().map(|q| [grey(q); 4]).collect();
    let n = points.len() as u32;
    let painted = asperity_core::TriMesh::new(points.clone(), vec![[0, 1, n - 1]])
        .unwrap()
        .with_colors(colors)
        .unwrap();
    let a = painted_alpha(p, &painted, &Paint::Colour).unwrap();
    for (q, a) in p.iter().zip(&a) {
        assert_eq!(*a, if q[0] > 0.0 { 1.0 } else { 0.0 }, "{q:?}");
    }
    let far: Vec<[f64; 3]> = points.iter().map(|q| q.map(|x| 3.0 * x)).collect();
    let moved = asperity_core::TriMesh::new(far, vec![[0, 1, n - 1]])
        .unwrap()
        .with_scalar("mask", vec![0.5; n as usize])
        .unwrap();
    let err = painted_alpha(p, &moved, &Paint::Scalar("mask".into())).unwrap_err();
    assert!(err.to_string().contains("paint the base itself"), "{err}");
    let no_colour = painted_alpha(p, &moved, &Paint::Colour).unwrap_err();
    assert!(
        no_colour.to_string().contains("its scalars: mask"),
        "{no_colour}"
    );
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let base = smooth(base::quad_sphere(2));
    let layer = Layer {
        name: "all".into(),
        features: vec![
            Feature::global(Procedure::Rock(Rock::fractal(0.05, 0.5))),
            Feature {
                procedure: Procedure::Berry(Berry {
                    radius: 0.3,
                    ratio: 0.5,
                    children: 5,
                    height: 0.7,
                }),
                seeds: Seeds::Poisson { spacing: 0.6 },
                levels: Some(vec![2, 3]),
            },
            Feature {
                procedure: Procedure::Mushroom(Mushroom {
                    height: 0.05,
                    radius: 0.2,
                }),
                seeds: Seeds::Poisson { spacing: 0.9 },
                levels: None,
            },
        ],
        edits: vec![Edit {
            at: Anchor::Vertex(3),
            radius: 1.0,
            levels: (2, 4),
            factor: 2.0,
        }],
    };
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| grow(&base, 4, Boundary::EdgeOnly, &layer, 11).unwrap())
    };
    let (one, two) = (run(1), run(2));
    let bits = |m: &asperity_subdiv::multires::Multires| {
        m.finest()
            .mesh
            .positions()
            .iter()
            .flat_map(|p| p.map(f64::to_bits))
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&one), bits(&two));
}

#[test]
fn the_planet_clamps_relief_at_sea_level() {
    let base = smooth(base::quad_sphere(2));
    let earth = [Feature::global(Procedure::Rock(Rock::fractal(0.5, 0.55)))];
    let alien = [Feature::global(Procedure::Rock(Rock::fractal(0.35, 0.75)))];
    let how = Blend {
        source: AlphaSource::Plane {
            normal: [1.0, 0.0, 0.0],
            offset: 0.0,
        },
        width: 0.5,
    };
    let f = scalar_field(
        &base,
        4,
        Boundary::EdgeOnly,
        &earth,
        Some((&alien, &how)),
        3,
    )
    .unwrap();
    let planet = Planet::default();
    let (colours, pos) = planet.shade(&f);
    let (mut sea, mut land) = (0, 0);
    for v in 0..pos.len() {
        if f.value[v] <= planet.sea_level {
            assert_eq!(
                pos[v],
                f.mesh.mesh.positions()[v],
                "sea lies on the reference"
            );
            assert!(colours[v][2] > colours[v][0], "sea is blue");
            sea += 1;
        } else {
            land += 1;
        }
    }
    assert!(sea > 100 && land > 100, "{sea} {land}");
    assert!(f.alpha.contains(&0.0) && f.alpha.contains(&1.0));
}

/// An independent Catmull–Clark of the unit cube in exact rational arithmetic.
#[test]
fn cube_values_in_rational_arithmetic() {
    #[derive(Clone, Copy, Debug, PartialEq)]
    struct Q(i128, i128);
    fn gcd(a: i128, b: i128) -> i128 {
        if b == 0 { a.abs() } else { gcd(b, a % b) }
    }
    impl Q {
        fn new(n: i128, d: i128) -> Q {
            let g = gcd(n, d).max(1) * d.signum();
            Q(n / g, d / g)
        }
        fn add(self, o: Q) -> Q {
            Q::new(self.0 * o.1 + o.0 * self.1, self.1 * o.1)
        }
        fn mul(self, n: i128, d: i128) -> Q {
            Q::new(self.0 * n, self.1 * d)
        }
        fn f(self) -> f64 {
            self.0 as f64 / self.1 as f64
        }
    }
    type P = [Q; 3];
    let sum = |ps: &[P]| -> P {
        let mut s = [Q(0, 1); 3];
        for p in ps {
            for k in 0..3 {
                s[k] = s[k].add(p[k]);
            }
        }
        s
    };
    let scale = |p: P, n: i128, d: i128| -> P { p.map(|x| x.mul(n, d)) };
    // One step on a closed mesh (smooth rules only), in our documented order.
    let step = |pos: &[P], faces: &[Vec<usize>]| -> (Vec<P>, Vec<Vec<usize>>) {
        let fp: Vec<P> = faces
            .iter()
            .map(|f| {
                scale(
                    sum(&f.iter().map(|&v| pos[v]).collect::<Vec<_>>()),
                    1,
                    f.len() as i128,
                )
            })
            .collect();
        let mut edges: Vec<(usize, usize)> = Vec::new();
        let mut edge_faces: Vec<Vec<usize>> = Vec::new();
        for (fi, f) in faces.iter().enumerate() {
            for k in 0..f.len() {
                let (a, b) = (f[k], f[(k + 1) % f.len()]);
                let key = (a.min(b), a.max(b));
                match edges.iter().position(|&e| e == key) {
                    Some(i) => edge_faces[i].push(fi),
                    None => {
                        edges.push(key);
                        edge_faces.push(vec![fi]);
                    }
                }
            }
        }
        let ep: Vec<P> = edges
            .iter()
            .zip(&edge_faces)
            .map(|(&(a, b), fs)| scale(sum(&[pos[a], pos[b], fp[fs[0]], fp[fs[1]]]), 1, 4))
            .collect();
        let vp: Vec<P> = (0..pos.len())
            .map(|v| {
                let adj_f: Vec<P> = faces
                    .iter()
                    .enumerate()
                    .filter(|(_, f)| f.contains(&v))
                    .map(|(i, _)| fp[i])
                    .collect();
                let adj_e: Vec<P> = edges
                    .iter()
                    .filter(|e| e.0 == v || e.1 == v)
                    .map(|&(a, b)| scale(sum(&[pos[a], pos[b]]), 1, 2))
                    .collect();
                let n = adj_e.len() as i128;
                let q = scale(sum(&adj_f), 1, adj_f.len() as i128);
                let r = scale(sum(&adj_e), 2, n);
                scale(sum(&[q, r, scale(pos[v], n - 3, 1)]), 1, n)
            })
            .collect();
        let (nf, ne) = (faces.len(), edges.len());
        let mut out = fp;
        out.extend(ep);
        out.extend(vp);
        let eid = |a: usize, b: usize| {
            edges
                .iter()
                .position(|&e| e == (a.min(b), a.max(b)))
                .unwrap()
        };
        let quads = faces
            .iter()
            .enumerate()
            .flat_map(|(fi, f)| {
                let m = f.len();
                (0..m)
                    .map(|k| {
                        vec![
                            nf + ne + f[k],
                            nf + eid(f[k], f[(k + 1) % m]),
                            fi,
                            nf + eid(f[(k + m - 1) % m], f[k]),
                        ]
                    })
                    .collect::<Vec<_>>()
            })
            .collect();
        (out, quads)
    };
    let cube = base::cube();
    let mut pos: Vec<P> = cube
        .positions()
        .iter()
        .map(|p| p.map(|x| Q::new(x as i128, 1)))
        .collect();
    let mut faces: Vec<Vec<usize>> = cube
        .faces()
        .map(|f| f.iter().map(|&v| v as usize).collect())
        .collect();
    let mut ours = smooth(cube);
    for (level, corner) in [(1, Q(5, 9)), (2, Q(55, 108))] {
        (pos, faces) = step(&pos, &faces);
        ours = subdivide(&ours, Boundary::EdgeOnly).unwrap();
        // The (1, 1, 1) corner is the last vertex point: exactly 5/9, then 55/108.
        assert_eq!(pos[pos.len() - 1], [corner; 3], "level {level}");
        // Every vertex of ours equals the rational value to rounding.
        assert_eq!(ours.mesh.n_vertices(), pos.len());
        for (a, b) in ours.mesh.positions().iter().zip(&pos) {
            for k in 0..3 {
                assert!(
                    (a[k] - b[k].f()).abs() < 1e-15,
                    "level {level}: {a:?} vs {b:?}"
                );
            }
        }
        let ours_faces: Vec<Vec<usize>> = ours
            .mesh
            .faces()
            .map(|f| f.iter().map(|&v| v as usize).collect())
            .collect();
        assert_eq!(ours_faces, faces, "level {level}: the documented order");
    }
}
