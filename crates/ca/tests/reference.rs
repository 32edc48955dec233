//! The CA against an independent reference: Mathematica's rule specification
//! `{code, {k, weights}, {1, 1}}` evaluated literally (index = Σ weights × cells
//! over the 3×3 block, new state = base-k digit `index` of the code), on random
//! rules, sizes, initial grids and both boundary modes.

use asperity_ca::facets::{drape, facet_mesh, interpolate};
use asperity_ca::{Boundary, CaParams, Family, Init, Rule, accumulate, initial_grid};
use asperity_core::{Grid2, HeightField, MemoryBudget, seeded};
use proptest::prelude::*;
use rand::Rng;

fn weights(f: Family) -> [[u32; 3]; 3] {
    match f {
        Family::Totalistic9 => [[1, 1, 1], [1, 1, 1], [1, 1, 1]],
        Family::Totalistic5 => [[0, 1, 0], [1, 1, 1], [0, 1, 0]],
        Family::Outer9 => [[2, 2, 2], [2, 1, 2], [2, 2, 2]],
        Family::Outer5 => [[0, 2, 0], [2, 1, 2], [0, 2, 0]],
    }
}

/// Base-k digit `index` of `code`.
fn digit(code: u128, k: u128, index: u32) -> u8 {
    (code / k.pow(index) % k) as u8
}

/// One step on a cyclic grid, `cells[y][x]`.
fn reference_cyclic(f: Family, k: u8, code: u128, cells: &[Vec<u8>]) -> Vec<Vec<u8>> {
    let (h, w) = (cells.len() as i64, cells[0].len() as i64);
    let wt = weights(f);
    (0..h)
        .map(|y| {
            (0..w)
                .map(|x| {
                    let mut idx = 0;
                    for dy in -1..=1i64 {
                        for dx in -1..=1i64 {
                            idx += wt[(dy + 1) as usize][(dx + 1) as usize]
                                * cells[((y + dy).rem_euclid(h)) as usize]
                                    [((x + dx).rem_euclid(w)) as usize]
                                    as u32;
                        }
                    }
                    digit(code, k as u128, idx)
                })
                .collect()
        })
        .collect()
}

/// Mathematica's infinite background: pad by T + 1 cells of background, step on
/// the padded grid with out-of-grid cells equal to the background, track the
/// background, and report every step on the (p + 2T) region.
fn reference_infinite(
    f: Family,
    k: u8,
    code: u128,
    init: &[Vec<u8>],
    steps: usize,
) -> Vec<Vec<Vec<u8>>> {
    let pad = steps + 1;
    let (h, w) = (init.len() + 2 * pad, init[0].len() + 2 * pad);
    let mut g = vec![vec![0u8; w]; h];
    for (y, row) in init.iter().enumerate() {
        for (x, &v) in row.iter().enumerate() {
            g[y + pad][x + pad] = v;
        }
    }
    let wt = weights(f);
    let mut bg = 0u8;
    let crop = |g: &Vec<Vec<u8>>| -> Vec<Vec<u8>> {
        g[1..h - 1].iter().map(|r| r[1..w - 1].to_vec()).collect()
    };
    let mut out = vec![crop(&g)];
    for _ in 0..steps {
        let get = |g: &Vec<Vec<u8>>, y: i64, x: i64, bg: u8| {
            if y < 0 || x < 0 || y >= h as i64 || x >= w as i64 {
                bg
            } else {
                g[y as usize][x as usize]
            }
        };
        let next: Vec<Vec<u8>> = (0..h as i64)
            .map(|y| {
                (0..w as i64)
                    .map(|x| {
                        let mut idx = 0;
                        for dy in -1..=1i64 {
                            for dx in -1..=1i64 {
                                idx += wt[(dy + 1) as usize][(dx + 1) as usize]
                                    * get(&g, y + dy, x + dx, bg) as u32;
                            }
                        }
                        digit(code, k as u128, idx)
                    })
                    .collect()
            })
            .collect();
        let all_bg: u32 = wt.iter().flatten().sum::<u32>() * bg as u32;
        bg = digit(code, k as u128, all_bg);
        g = next;
        out.push(crop(&g));
    }
    out
}

fn random_case(rng: &mut impl Rng) -> (Family, u8, u128) {
    let f = [
        Family::Totalistic9,
        Family::Totalistic5,
        Family::Outer9,
        Family::Outer5,
    ][rng.random_range(0..4)];
    let k = if matches!(f, Family::Totalistic9 | Family::Totalistic5) && rng.random_bool(0.3) {
        3
    } else {
        2
    };
    let max = (k as u128).pow(f.table_len(k) as u32);
    (f, k, rng.random_range(0..max))
}

fn to_rows(g: &[u8], nx: usize) -> Vec<Vec<u8>> {
    g.chunks(nx).map(<[u8]>::to_vec).collect()
}

#[test]
fn cyclic_evolution_matches_the_reference_on_random_rules() {
    let mut rng = seeded(2024);
    for case in 0..300 {
        let (f, k, code) = random_case(&mut rng);
        // Widths of 64 and 128 exercise the bit-sliced path, others the byte path.
        let nx = [5, 13, 64, 128, 33][rng.random_range(0..5)];
        let ny = rng.random_range(3..20);
        let steps = rng.random_range(1..6);
        let rule = Rule::new(f, k, code).unwrap();
        let init = initial_grid(
            &Init::Random {
                density: rng.random(),
                seed: case,
            },
            Some([nx, ny]),
            k,
            &MemoryBudget::unlimited(),
        )
        .unwrap();
        let mut states = to_rows(init.data(), nx);
        let mut sum: Vec<Vec<f64>> = states
            .iter()
            .map(|r| r.iter().map(|&v| v as f64).collect())
            .collect();
        for _ in 0..steps {
            states = reference_cyclic(f, k, code, &states);
            for (s, r) in sum.iter_mut().zip(&states) {
                for (a, &b) in s.iter_mut().zip(r) {
                    *a += b as f64;
                }
            }
        }
        let got = accumulate(
            &init,
            &CaParams::new(rule.clone(), steps),
            &MemoryBudget::unlimited(),
        )
        .unwrap();
        let want: Vec<f64> = sum.concat();
        assert_eq!(
            got.heights.data(),
            &want[..],
            "case {case}: {f:?} k={k} code={code} {nx}×{ny} T={steps}"
        );
        // The kept states (byte path) agree step by step too.
        let kept = accumulate(
            &init,
            &CaParams {
                keep_states: true,
                ..CaParams::new(rule, steps)
            },
            &MemoryBudget::unlimited(),
        )
        .unwrap();
        let st = kept.states.unwrap();
        assert_eq!(
            &st[steps * nx * ny..],
            &states.concat()[..],
            "case {case}: final state"
        );
    }
}

#[test]
fn infinite_background_matches_the_reference() {
    let mut rng = seeded(7);
    let mut flipping = 0;
    for case in 0..200 {
        let (f, k, code) = random_case(&mut rng);
        let rule = Rule::new(f, k, code).unwrap();
        flipping += (rule.table()[0] != 0) as usize;
        let (px, py) = (rng.random_range(1..4), rng.random_range(1..4));
        let pattern: Vec<u8> = if case % 3 == 0 {
            vec![1; px * py]
        } else {
            (0..px * py).map(|_| rng.random_range(0..k)).collect()
        };
        let init = Grid2::from_vec([px, py], pattern.clone()).unwrap();
        let steps = rng.random_range(1..7);
        let p = CaParams {
            boundary: Boundary::Infinite,
            keep_states: true,
            ..CaParams::new(rule, steps)
        };
        let got = accumulate(&init, &p, &MemoryBudget::unlimited()).unwrap();
        let want = reference_infinite(f, k, code, &to_rows(&pattern, px), steps);
        let (nx, ny) = (px + 2 * steps, py + 2 * steps);
        assert_eq!(got.heights.dims(), [nx, ny]);
        let flat: Vec<u8> = want.iter().flat_map(|s| s.concat()).collect();
        assert_eq!(
            got.states.unwrap(),
            flat,
            "case {case}: {f:?} k={k} code={code}"
        );
    }
    assert!(
        flipping > 20,
        "background-changing rules are exercised ({flipping})"
    );
}

#[test]
fn rule_450_from_a_seed() {
    // Step 1 of rule 450 from one cell: every cell of the 3×3 block sees sum 1 → 1.
    let rule = Rule::new(Family::Totalistic9, 2, 450).unwrap();
    let init = initial_grid(&Init::Seed, None, 2, &MemoryBudget::unlimited()).unwrap();
    let p = CaParams {
        boundary: Boundary::Infinite,
        keep_states: true,
        ..CaParams::new(rule, 2)
    };
    let out = accumulate(&init, &p, &MemoryBudget::unlimited()).unwrap();
    let st = out.states.unwrap();
    assert_eq!(out.heights.dims(), [5, 5]);
    let step1: Vec<u8> = st[25..50].to_vec();
    #[rustfmt::skip]
    assert_eq!(step1, vec![0,0,0,0,0, 0,1,1,1,0, 0,1,1,1,0, 0,1,1,1,0, 0,0,0,0,0]);
    // Step 2: corners of the 5×5 see 1, edges 2 or 3, centre 9 → only sums 1, 6, 7, 8 live.
    #[rustfmt::skip]
    assert_eq!(st[50..75].to_vec(), vec![1,0,0,0,1, 0,0,1,0,0, 0,1,0,1,0, 0,0,1,0,0, 1,0,0,0,1]);
    assert_eq!(out.heights.get(2, 2), &2.0); // 1 (seed) + 1 + 0
}

#[test]
fn bad_input_is_refused() {
    let r = Rule::new(Family::Totalistic9, 2, 450).unwrap();
    let g = initial_grid(&Init::Seed, Some([8, 8]), 2, &MemoryBudget::unlimited()).unwrap();
    assert!(
        accumulate(&g, &CaParams::new(r.clone(), 0), &MemoryBudget::unlimited())
            .unwrap_err()
            .to_string()
            .contains("at least 1")
    );
    assert!(initial_grid(&Init::Seed, Some([0, 8]), 2, &MemoryBudget::unlimited()).is_err());
    assert!(
        initial_grid(
            &Init::Random {
                density: 1.5,
                seed: 1
            },
            Some([8, 8]),
            2,
            &MemoryBudget::unlimited()
        )
        .is_err()
    );
    assert!(
        initial_grid(
            &Init::Random {
                density: 0.5,
                seed: 1
            },
            None,
            2,
            &MemoryBudget::unlimited()
        )
        .is_err()
    );
    let three = Grid2::from_vec([2, 1], vec![0, 2]).unwrap();
    assert!(
        initial_grid(&Init::Grid(three), None, 2, &MemoryBudget::unlimited())
            .unwrap_err()
            .to_string()
            .contains("state 2")
    );
    let e = accumulate(&g, &CaParams::new(r, 1000), &MemoryBudget::new(100)).unwrap_err();
    assert!(e.to_string().contains("would need about"), "{e}");
}

fn arb_height() -> impl Strategy<Value = HeightField> {
    (2usize..9, 2usize..9).prop_flat_map(|(nx, ny)| {
        proptest::collection::vec(-5.0f64..5.0, nx * ny).prop_map(move |d| {
            HeightField::from_vec([nx, ny], d)
                .unwrap()
                .with_spacing([0.5, 2.0])
                .unwrap()
                .with_origin([1.0, -3.0])
                .unwrap()
        })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn interpolation_is_exact_at_nodes_and_planar_on_facets(h in arb_height(), u in 0.0f64..1.0, v in 0.0f64..1.0) {
        let [nx, ny] = h.dims();
        for j in 0..ny {
            for i in 0..nx {
                let [x, y] = h.position(i, j);
                prop_assert_eq!(interpolate(&h, x, y), Some(*h.get(i, j)));
            }
        }
        // A point inside some cell: find its facet in the mesh by barycentric
        // coordinates and compare with the plane through that facet.
        let m = facet_mesh(&h, false).unwrap();
        let (gx, gy) = (u * (nx - 1) as f64, v * (ny - 1) as f64);
        let [x0, y0] = h.origin();
        let (x, y) = (x0 + gx * 0.5, y0 + gy * 2.0);
        let z = interpolate(&h, x, y).unwrap();
        let mut found = false;
        for t in m.triangles() {
            let p = t.map(|k| m.positions()[k as usize]);
            let d = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
            let l1 = ((p[2][1] - p[0][1]) * (x - p[0][0]) - (p[2][0] - p[0][0]) * (y - p[0][1])) / d;
            let l2 = ((p[1][0] - p[0][0]) * (y - p[0][1]) - (p[1][1] - p[0][1]) * (x - p[0][0])) / d;
            let l0 = 1.0 - l1 - l2;
            if l0 >= -1e-12 && l1 >= -1e-12 && l2 >= -1e-12 {
                let zp = l0 * p[0][2] + l1 * p[1][2] + l2 * p[2][2];
                prop_assert!((zp - z).abs() < 1e-9, "{} vs {}", zp, z);
                found = true;
            }
        }
        prop_assert!(found);
    }

    #[test]
    fn draped_curves_lie_on_the_facets(h in arb_height(), r in 0.1f64..0.45) {
        let [nx, ny] = h.dims();
        let e = h.extent();
        let [x0, y0] = h.origin();
        let c = asperity_ca::facets::circle(x0 + e[0] / 2.0, y0 + e[1] / 2.0, r * e[0].min(e[1]), 40);
        let pts = drape(&h, &c).unwrap();
        prop_assert!(pts.len() >= 40);
        // Every vertex is on the surface, and so is every segment midpoint (which
        // holds only if segments never cross a facet edge).
        for w in pts.windows(2) {
            let mid = [(w[0][0] + w[1][0]) / 2.0, (w[0][1] + w[1][1]) / 2.0, (w[0][2] + w[1][2]) / 2.0];
            let z = interpolate(&h, mid[0], mid[1]).unwrap();
            prop_assert!((z - mid[2]).abs() < 1e-9, "midpoint off the surface by {}", z - mid[2]);
        }
        let _ = (nx, ny);
    }
}

#[test]
fn facet_mesh_counts_valences_and_normals() {
    let h = HeightField::from_vec(
        [7, 6],
        (0..42).map(|k| ((k * 37) % 11) as f64 * 0.3).collect(),
    )
    .unwrap();
    let m = facet_mesh(&h, false).unwrap();
    assert_eq!(m.n_faces(), 2 * 6 * 5);
    assert!(m.face_normals().iter().all(|n| n[2] > 0.0));
    let flat = facet_mesh(&h, true).unwrap();
    assert_eq!((flat.n_faces(), flat.n_vertices()), (60, 180));
    // Flat: each corner carries its facet's normal.
    for (f, t) in flat.triangles().iter().enumerate() {
        assert_eq!(
            flat.normals().unwrap()[t[0] as usize],
            flat.face_normals()[f]
        );
    }
}
