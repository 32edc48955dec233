//! Growth models against physical ground truth (exact results and published
//! exponents; see `../shared/notes/growth.md` §1.2 for the table and sources).
//! Tolerances are about 3σ of the run-to-run scatter measured at these sizes.

use std::collections::HashSet;

use asperity_analysis::psd::log_fit;
use asperity_analysis::scaling::{
    growth_exponent, growth_exponent_intrinsic, gyration_dimension, radius_of_gyration,
    roughness_exponent,
};
use asperity_core::{MemoryBudget, NoProgress};
use asperity_growth::curved::{CurvedParams, CurvedSubstrate, deposit_curved};
use asperity_growth::deposition::deposit_on_schedule;
use asperity_growth::dla::{DlaParams, SeedShape, Sides, dla, dla_with_walkers};
use asperity_growth::interface_width::uniform_schedule;
use asperity_growth::occupancy::FACE_NEIGHBOURS;
use asperity_growth::{DepositionParams, Lattice, Model, deposit, deposit_ensemble};
use rayon::prelude::*;

/// The six face neighbours of `p`.
fn faces(p: [i32; 3]) -> [[i32; 3]; 6] {
    FACE_NEIGHBOURS.map(|e| [p[0] + e[0], p[1] + e[1], p[2] + e[2]])
}

fn unlimited() -> MemoryBudget {
    MemoryBudget::unlimited()
}

fn ensemble(
    model: Model,
    l: usize,
    dim: usize,
    layers: f64,
    runs: usize,
    bin: Option<usize>,
) -> asperity_growth::WidthSeries {
    let mut p = DepositionParams::new(model, Lattice::new(l, dim).unwrap(), layers);
    p.bin = bin;
    deposit_ensemble(&p, 11, runs, &unlimited(), &NoProgress)
        .unwrap()
        .1
}

#[test]
fn rd_width_is_exact() {
    // ⟨W²⟩ = t (1 − 1/N) for N columns (binomial column counts).
    for (l, dim, runs) in [(1024, 1, 24), (48, 2, 24)] {
        let s = ensemble(Model::Rd, l, dim, 500.0, runs, None);
        let n = (l as f64).powi(dim as i32);
        for (t, w2) in s.t.iter().zip(&s.w2) {
            let exact = t * (1.0 - 1.0 / n);
            assert!(
                (w2 / exact - 1.0).abs() < 0.05,
                "L={l} d={dim} t={t}: W²={w2} vs {exact}"
            );
        }
    }
}

#[test]
fn mass_is_conserved_and_rd_rdsr_have_no_overhangs() {
    for model in [
        Model::Rd,
        Model::Rdsr { radius: 1 },
        Model::Rdsr { radius: 3 },
    ] {
        for dim in [1, 2] {
            let mut p = DepositionParams::new(model, Lattice::new(24, dim).unwrap(), 30.0);
            p.keep_particles = true;
            let d = deposit(&p, 5, 0, &unlimited(), &NoProgress).unwrap();
            let n = p.depositions();
            assert_eq!(d.heights.iter().map(|&h| h as u64).sum::<u64>(), n);
            // Replay: every particle lands exactly on top of its column.
            let mut h = vec![0u32; d.heights.len()];
            for c in d.particles.as_ref().unwrap() {
                let i = c[0] as usize + 24 * c[1] as usize;
                assert_eq!(c[2], h[i], "{model:?} d={dim}: overhang at {c:?}");
                h[i] += 1;
            }
            assert_eq!(h, d.heights);
            assert_eq!(d.point_set().len() as u64, n);
        }
    }
}

#[test]
fn rdsr_settles_no_higher_than_its_neighbours() {
    // Family's rule, checked on every deposit by replay: the landing column is
    // the lowest of the drop column's neighbourhood, which contains the landing
    // column and one of its neighbours, so it is never higher than both of its
    // neighbours. Random deposition breaks this on most deposits.
    let l = 64;
    let mut p = DepositionParams::new(
        Model::Rdsr { radius: 1 },
        Lattice::new(l, 1).unwrap(),
        200.0,
    );
    p.keep_particles = true;
    let d = deposit(&p, 3, 0, &unlimited(), &NoProgress).unwrap();
    let mut h = vec![0u32; l];
    for c in d.particles.as_ref().unwrap() {
        let i = c[0] as usize;
        // The landing column is no higher than both of its neighbours.
        let (a, b) = (h[(i + l - 1) % l], h[(i + 1) % l]);
        assert!(
            h[i] <= a.max(b) + 1,
            "column {i} at {} next to {a}, {b}",
            h[i]
        );
        h[i] += 1;
    }
    // RDSR is much smoother than RD at the same time.
    let rd = ensemble(Model::Rd, 1024, 1, 200.0, 4, None);
    let rdsr = ensemble(Model::Rdsr { radius: 1 }, 1024, 1, 200.0, 4, None);
    assert!(rdsr.w2.last().unwrap() * 20.0 < *rd.w2.last().unwrap());
}

#[test]
fn ballistic_contact_rule_holds_for_every_deposit() {
    for dim in [1, 2] {
        let l = 16;
        let mut p = DepositionParams::new(Model::Bd, Lattice::new(l, dim).unwrap(), 20.0);
        p.keep_particles = true;
        let d = deposit(&p, 9, 0, &unlimited(), &NoProgress).unwrap();
        let mut occ: HashSet<[i64; 3]> = HashSet::new();
        let wrap = |v: i64| v.rem_euclid(l as i64);
        let lateral = |c: [i64; 3]| -> Vec<[i64; 3]> {
            let mut v = vec![[wrap(c[0] - 1), c[1], c[2]], [wrap(c[0] + 1), c[1], c[2]]];
            if dim == 2 {
                v.push([c[0], wrap(c[1] - 1), c[2]]);
                v.push([c[0], wrap(c[1] + 1), c[2]]);
            }
            v
        };
        for c in d.particles.as_ref().unwrap() {
            let c = c.map(|v| v as i64);
            assert!(!occ.contains(&c));
            let below = c[2] == 0 || occ.contains(&[c[0], c[1], c[2] - 1]);
            let side = lateral(c).iter().any(|n| occ.contains(n));
            assert!(below || side, "{c:?} floats");
            // First contact: no cell above it in the column touched anything.
            for z in c[2] + 1..c[2] + 40 {
                let q = [c[0], c[1], z];
                assert!(!occ.contains(&q) && !occ.contains(&[c[0], c[1], z - 1]) || z - 1 == c[2]);
                assert!(
                    lateral(q).iter().all(|n| !occ.contains(n)),
                    "{c:?} passed contact at z={z}"
                );
            }
            occ.insert(c);
        }
        // BD is porous: fewer particles than the volume under its surface.
        let volume: u64 = d.heights.iter().map(|&h| h as u64).sum();
        assert!(
            volume > occ.len() as u64 * 3 / 2,
            "density {}",
            occ.len() as f64 / volume as f64
        );
    }
}

#[test]
fn rdsr_1d_exponents() {
    // β = 1/4 (Edwards–Wilkinson) at L = 8192, fit over [10, 1000].
    let s = ensemble(Model::Rdsr { radius: 1 }, 8192, 1, 1000.0, 8, None);
    let beta = growth_exponent(&s.t, &s.width(), [10.0, 1000.0])
        .unwrap()
        .exponent;
    assert!((beta - 0.25).abs() < 0.02, "β = {beta}");
    // α = 1/2 from saturated widths, time-averaged over t ∈ [L²/2, 2L²].
    let sizes = [16usize, 32, 64, 128];
    let wsat: Vec<f64> = sizes
        .par_iter()
        .map(|&l| {
            let p = DepositionParams::new(
                Model::Rdsr { radius: 1 },
                Lattice::new(l, 1).unwrap(),
                (2 * l * l) as f64,
            );
            let n = l as u64;
            let sched = uniform_schedule(n * (l * l / 2) as u64, n * (2 * l * l) as u64, 64);
            let w2: f64 = (0..24)
                .map(|r| {
                    let d = deposit_on_schedule(&p, 21, r, &sched, &NoProgress);
                    d.series.w2.iter().sum::<f64>() / d.series.w2.len() as f64
                })
                .sum::<f64>()
                / 24.0;
            w2.sqrt()
        })
        .collect();
    let alpha = roughness_exponent(&sizes.map(|l| l as f64), &wsat)
        .unwrap()
        .slope;
    assert!((alpha - 0.5).abs() < 0.04, "α = {alpha}, W_sat = {wsat:?}");
}

#[test]
fn rdsr_2d_width_grows_logarithmically() {
    let s = ensemble(Model::Rdsr { radius: 1 }, 256, 2, 1000.0, 4, None);
    // W² = a + b ln t: straight against ln t …
    let pts: Vec<(f64, f64)> =
        s.t.iter()
            .zip(&s.w2)
            .filter(|(t, _)| **t >= 10.0)
            .map(|(t, w)| (t.ln(), *w))
            .collect();
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let syy: f64 = pts.iter().map(|p| (p.1 - my).powi(2)).sum();
    let r2 = sxy * sxy / (sxx * syy);
    let b = sxy / sxx;
    assert!(r2 > 0.95, "r² = {r2}");
    assert!(b > 0.03 && b < 0.09, "slope of W² against ln t: {b}");
    // … and no power law: the effective β is near 0.
    let beta = growth_exponent(&s.t, &s.width(), [10.0, 1000.0])
        .unwrap()
        .exponent;
    assert!(beta < 0.08, "β_eff = {beta}");
}

#[test]
fn ballistic_exponents() {
    // 1+1D: β = 1/3 after max-height binning (ε = 4).
    let s = ensemble(Model::Bd, 8192, 1, 1000.0, 8, Some(4));
    let beta = growth_exponent(&s.t, &s.width_binned(), [10.0, 1000.0])
        .unwrap()
        .exponent;
    assert!((beta - 1.0 / 3.0).abs() < 0.03, "β (binned) = {beta}");
    let plain = growth_exponent(&s.t, &s.width(), [10.0, 1000.0])
        .unwrap()
        .exponent;
    assert!(plain < beta, "plain {plain} should be biased low");
    // 2+1D: β ≈ 0.24 (KPZ) with the intrinsic-width fit, W² = W_i² + A t^(2β);
    // the plain fit is far below (β_eff ≈ 0.14, notes §1.4).
    let mut p = DepositionParams::new(Model::Bd, Lattice::new(512, 2).unwrap(), 400.0);
    p.samples_per_decade = 20;
    let s = deposit_ensemble(&p, 11, 10, &unlimited(), &NoProgress)
        .unwrap()
        .1;
    let fit = growth_exponent_intrinsic(&s.t, &s.width(), [30.0, 400.0]).unwrap();
    assert!(
        (0.20..=0.29).contains(&fit.exponent),
        "β (intrinsic) = {}",
        fit.exponent
    );
    assert!(fit.intrinsic_width > 2.0, "W_i = {}", fit.intrinsic_width);
    let plain = growth_exponent(&s.t, &s.width(), [30.0, 400.0])
        .unwrap()
        .exponent;
    assert!(plain < 0.17, "plain β = {plain}");
}

fn assert_touching(c: &asperity_growth::dla::DlaCluster) {
    let mut occ: HashSet<[i32; 3]> = c.cells[..c.seeds].iter().copied().collect();
    // Solid seeds occupy more than the listed surface: accept contact with those.
    let plane = c.cells[..c.seeds].iter().all(|p| p[2] == 0);
    for p in c.particles() {
        let n = faces(*p);
        let wrap = |q: [i32; 3]| {
            if plane {
                [
                    q[0].rem_euclid(c.size[0] as i32),
                    q[1].rem_euclid(c.size[1] as i32),
                    q[2],
                ]
            } else {
                q
            }
        };
        assert!(
            n.iter().any(|q| occ.contains(&wrap(*q))),
            "particle {p:?} touches nothing"
        );
        assert!(occ.insert(*p), "particle {p:?} deposited twice");
    }
}

/// Between reflecting walls a plane deposit is one face-connected set with
/// no wrap (every particle touches the substrate through particles inside the
/// box), any size is accepted, and the bulk is the same DLA: D from ρ(z) ≈ 2.5
/// as with periodic sides.
#[test]
fn dla_between_walls_is_connected_without_wrap() {
    let params = DlaParams {
        dim: 3,
        size: [115, 115, 200],
        particles: 40_000,
        stick: 1.0,
        seed_shape: SeedShape::Plane,
        launch_gap: 2.0,
        sides: Sides::Walls,
    };
    let c = dla(&params, 5, 0, &unlimited(), &NoProgress).unwrap();
    assert!(c.stopped.is_none() && c.capped_at.is_none());
    let mut occ: HashSet<[i32; 3]> = c.cells[..c.seeds].iter().copied().collect();
    for p in c.particles() {
        assert!((0..2).all(|a| (0..115).contains(&p[a])), "{p:?} outside");
        assert!(
            faces(*p).iter().any(|q| occ.contains(q)),
            "particle {p:?} touches nothing inside the box"
        );
        assert!(occ.insert(*p));
    }
    // Particles reach every side wall (the walls reflect, they do not repel).
    for (a, edge) in [(0, 0), (0, 114), (1, 0), (1, 114)] {
        assert!(
            c.particles().iter().any(|p| p[a] == edge),
            "axis {a} at {edge}"
        );
    }
    let top = c.particles().iter().map(|p| p[2]).max().unwrap() as usize;
    let mut count = vec![0f64; top + 1];
    for p in c.particles() {
        count[p[2] as usize] += 1.0;
    }
    let z: Vec<f64> = (0..=top).map(|z| z as f64).collect();
    let rho: Vec<f64> = count.iter().map(|n| n / (115.0 * 115.0)).collect();
    let fit = log_fit(&z, &rho, [4.0, top as f64 / 3.0]).unwrap();
    let d = 3.0 + fit.slope;
    assert!((2.2..=2.8).contains(&d), "D from ρ(z) = {d}");
}

#[test]
fn dla_3d_dimension_and_contact() {
    let ds: Vec<f64> = (0..3u64)
        .into_par_iter()
        .map(|s| {
            let c = dla(
                &DlaParams::point(3, 100_000),
                100 + s,
                0,
                &unlimited(),
                &NoProgress,
            )
            .unwrap();
            assert!(c.stopped.is_none());
            assert_eq!(c.particles().len(), 100_000);
            assert_touching(&c);
            let d = gyration_dimension(&c.points()).unwrap().d;
            assert!((2.35..=2.65).contains(&d), "seed {s}: D = {d}");
            d
        })
        .collect();
    let mean = ds.iter().sum::<f64>() / 3.0;
    assert!((2.40..=2.60).contains(&mean), "mean D = {mean} ({ds:?})");
}

#[test]
fn dla_2d_dimension() {
    let c = dla(
        &DlaParams::point(2, 100_000),
        5,
        0,
        &unlimited(),
        &NoProgress,
    )
    .unwrap();
    assert_touching(&c);
    let d = gyration_dimension(&c.points()).unwrap().d;
    assert!((d - 1.71).abs() < 0.06, "D = {d}");
}

#[test]
fn low_sticking_probability_gives_compact_clusters() {
    let rg = |p: f64| {
        let mut params = DlaParams::point(3, 20_000);
        params.stick = p;
        let c = dla(&params, 8, 0, &unlimited(), &NoProgress).unwrap();
        assert_touching(&c);
        radius_of_gyration(&c.points())
    };
    let ratio = rg(0.1) / rg(1.0);
    assert!(ratio < 0.8, "R_g(0.1)/R_g(1) = {ratio}");
}

#[test]
fn dla_on_a_plane_sphere_and_image() {
    // Plane: the density profile ρ(z) ∝ z^(D−3) with D ≈ 2.5 in the growth zone.
    let params = DlaParams {
        dim: 3,
        size: [128, 128, 256],
        particles: 60_000,
        stick: 1.0,
        seed_shape: SeedShape::Plane,
        launch_gap: 2.0,
        sides: Sides::Periodic,
    };
    let c = dla(&params, 4, 0, &unlimited(), &NoProgress).unwrap();
    assert!(c.stopped.is_none(), "{:?}", c.stopped);
    assert_eq!(c.seeds, 128 * 128);
    assert_touching(&c);
    let top = c.particles().iter().map(|p| p[2]).max().unwrap() as usize;
    let mut count = vec![0f64; top + 1];
    for p in c.particles() {
        count[p[2] as usize] += 1.0;
    }
    let z: Vec<f64> = (0..=top).map(|z| z as f64).collect();
    let rho: Vec<f64> = count.iter().map(|n| n / (128.0 * 128.0)).collect();
    let fit = log_fit(&z, &rho, [4.0, top as f64 / 3.0]).unwrap();
    let d = 3.0 + fit.slope;
    assert!(
        (2.2..=2.8).contains(&d),
        "D from ρ(z) = {d} (slope {})",
        fit.slope
    );
    // Sphere: particles surround the ball.
    let params = DlaParams {
        dim: 3,
        size: [96, 96, 96],
        particles: 5_000,
        stick: 1.0,
        seed_shape: SeedShape::Sphere(10.0),
        launch_gap: 2.0,
        sides: Sides::Periodic,
    };
    let c = dla(&params, 4, 0, &unlimited(), &NoProgress).unwrap();
    let center = c.center;
    for p in c.particles() {
        let r = (0..3)
            .map(|a| (p[a] as f64 - center[a]).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(r > 10.0, "{p:?} inside the seed ball");
    }
    let octants: HashSet<[bool; 3]> = c
        .particles()
        .iter()
        .map(|p| [0, 1, 2].map(|a| p[a] as f64 > center[a]))
        .collect();
    assert_eq!(octants.len(), 8);
    // Image: seeds only where the density is positive (left half).
    let density: Vec<f64> = (0..64 * 64)
        .map(|k| if k % 64 < 32 { 0.05 } else { 0.0 })
        .collect();
    let params = DlaParams {
        dim: 3,
        size: [64, 64, 64],
        particles: 2_000,
        stick: 1.0,
        seed_shape: SeedShape::Density(density),
        launch_gap: 2.0,
        sides: Sides::Periodic,
    };
    let c = dla(&params, 4, 0, &unlimited(), &NoProgress).unwrap();
    assert!(c.seeds > 50 && c.seeds < 200, "{} seeds", c.seeds);
    assert!(c.cells[..c.seeds].iter().all(|p| p[0] < 32 && p[2] == 0));
    assert_touching(&c);
}

#[test]
fn same_seed_same_output_at_any_thread_count() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut p = DepositionParams::new(Model::Bd, Lattice::new(64, 2).unwrap(), 20.0);
            p.bin = Some(4);
            let (d, s) = deposit_ensemble(&p, 3, 4, &unlimited(), &NoProgress).unwrap();
            let c = dla(&DlaParams::point(3, 3000), 3, 0, &unlimited(), &NoProgress).unwrap();
            (d.heights, s, c.cells)
        })
    };
    let a = run(1);
    let b = run(2);
    assert_eq!(a.0, b.0);
    assert_eq!(a.1, b.1);
    assert_eq!(a.2, b.2);
    // A different seed gives a different cluster.
    let c = dla(&DlaParams::point(3, 3000), 4, 0, &unlimited(), &NoProgress).unwrap();
    assert_ne!(c.cells, a.2);
}

/// Walks started ahead of their turn (speculative walkers) give the cluster of
/// the plain sequential loop, cell for cell, in every mode; small lattices and
/// up to six walkers make many of them read cells a predecessor changes, so
/// the rewalk path is taken (counted) and checked too.
#[test]
fn speculative_walkers_give_the_sequential_cluster() {
    let base = |dim, size, particles, seed_shape, sides| DlaParams {
        dim,
        size,
        particles,
        stick: 1.0,
        seed_shape,
        launch_gap: 2.0,
        sides,
    };
    let density: Vec<f64> = (0..32 * 32).map(|k| (k % 7) as f64 / 30.0).collect();
    let mut moss = DlaParams::point(3, 3000);
    moss.stick = 0.1;
    let cases = [
        DlaParams::point(3, 4000),
        DlaParams::point(2, 3000),
        moss,
        base(3, [32, 32, 48], 6000, SeedShape::Plane, Sides::Periodic),
        base(3, [30, 26, 40], 5000, SeedShape::Plane, Sides::Walls),
        base(2, [64, 1, 64], 1500, SeedShape::Plane, Sides::Periodic),
        base(
            3,
            [48, 48, 48],
            3000,
            SeedShape::Sphere(6.0),
            Sides::Periodic,
        ),
        base(
            3,
            [32, 32, 24],
            3000,
            SeedShape::Density(density),
            Sides::Periodic,
        ),
        // Capped at the lattice top: launches from the top layer.
        base(3, [16, 16, 12], 1200, SeedShape::Plane, Sides::Periodic),
    ];
    let mut rewalks = 0;
    for (i, p) in cases.iter().enumerate() {
        let one = dla_with_walkers(p, 9, i as u64, &unlimited(), &NoProgress, 1).unwrap();
        assert_eq!(one.rewalks, 0);
        for walkers in [2, 3, 6] {
            // A pool of their own, so that the walkers do run at once.
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(walkers)
                .build()
                .unwrap();
            let many = pool
                .install(|| dla_with_walkers(p, 9, i as u64, &unlimited(), &NoProgress, walkers))
                .unwrap();
            assert_eq!(many.cells, one.cells, "case {i} with {walkers} walkers");
            assert_eq!(many.stats, one.stats, "case {i} with {walkers} walkers");
            assert_eq!(
                (many.stopped.clone(), many.capped_at),
                (one.stopped.clone(), one.capped_at)
            );
            rewalks += many.rewalks;
        }
    }
    assert!(
        rewalks > 100,
        "only {rewalks} rewalks: the check went untested"
    );
}

/// Sixteen walkers, more than the machine's cores (each gets a thread): the
/// same cluster as one walker, many walks in flight, and the window adapted so
/// that few are walked again (#37's figures, 10⁶ particles on 2 cores: 27 in
/// flight, 2.3 % redone; here a smaller cluster with loose bounds, since the
/// counts follow the threads' timing).
#[test]
fn sixteen_walkers_keep_many_walks_in_flight_and_few_redone() {
    let p = DlaParams::point(3, 60_000);
    let one = dla_with_walkers(&p, 4, 0, &unlimited(), &NoProgress, 1).unwrap();
    assert_eq!(one.concurrency.walkers, 1);
    let many = dla_with_walkers(&p, 4, 0, &unlimited(), &NoProgress, 16).unwrap();
    assert_eq!(many.cells, one.cells);
    let c = many.concurrency;
    assert_eq!(c.walkers, 16);
    assert!(c.mean_in_flight >= 4.0, "{c:?}");
    assert!(c.redone_fraction <= 0.10, "{c:?}");
    assert!(
        (c.redone_fraction - many.rewalks as f64 / 60_000.0).abs() < 1e-12,
        "{c:?}"
    );
}

#[test]
fn curved_substrates() {
    for model in [Model::Rd, Model::Rdsr { radius: 1 }, Model::Bd] {
        let params = CurvedParams {
            model,
            substrate: CurvedSubstrate::Sphere(12.0),
            layers: 4.0,
            samples_per_decade: 5,
        };
        let d = deposit_curved(&params, 2, 0, &unlimited(), &NoProgress).unwrap();
        let n = d.cells.len() - d.seeds;
        assert_eq!(n as f64, (4.0 * d.seeds as f64).round(), "{model:?}");
        // Every particle touches the substrate or an earlier particle.
        let c = d.size[0] as i32 / 2;
        let mut occ: HashSet<[i32; 3]> = HashSet::new();
        let solid = |p: [i32; 3]| {
            ((p[0] - c).pow(2) + (p[1] - c).pow(2) + (p[2] - c).pow(2)) as f64 <= 144.0
        };
        let mut radii = [0f64; 8];
        let mut counts = [0f64; 8];
        for p in &d.cells[d.seeds..] {
            let n = faces(*p);
            assert!(!solid(*p), "{model:?}: {p:?} inside the substrate");
            assert!(
                n.iter().any(|q| solid(*q) || occ.contains(q)),
                "{model:?}: {p:?} floats"
            );
            assert!(occ.insert(*p));
            if p.contains(&c) {
                continue; // on an octant boundary plane
            }
            let o = (p[0] > c) as usize + 2 * (p[1] > c) as usize + 4 * (p[2] > c) as usize;
            radii[o] += (((p[0] - c).pow(2) + (p[1] - c).pow(2) + (p[2] - c).pow(2)) as f64).sqrt();
            counts[o] += 1.0;
        }
        // Radial deposition is isotropic: the octants fill alike.
        let mean_count = counts.iter().sum::<f64>() / 8.0;
        for k in 0..8 {
            assert!(
                (counts[k] / mean_count - 1.0).abs() < 0.1,
                "{model:?}: octant counts {counts:?}"
            );
            let r = radii[k] / counts[k];
            assert!(
                r > 12.0 && r < 12.0 + 4.0 * 2.5 + 2.0,
                "{model:?}: mean radius {r}"
            );
        }
        assert!(d.series.w2.iter().all(|w| w.is_finite()));
    }
    // A voxelised mesh (an icosphere scaled to radius 10) as the substrate.
    let mesh = asperity_core::shapes::icosphere(3, 10.0);
    let m = asperity_growth::curved::margin(Model::Bd, 3.0);
    let vox = asperity_core::voxelize::voxelize(&mesh, 20, m, &unlimited()).unwrap();
    let to_lattice = |p: [f64; 3]| [0, 1, 2].map(|a| (p[a] - vox.origin[a]) / vox.spacing);
    let lattice_mesh = asperity_core::TriMesh::new(
        mesh.positions().iter().map(|&p| to_lattice(p)).collect(),
        mesh.triangles().to_vec(),
    )
    .unwrap();
    let params = CurvedParams {
        model: Model::Bd,
        substrate: CurvedSubstrate::Mesh {
            mesh: lattice_mesh,
            size: vox.dims,
            cells: vox.cells(),
        },
        layers: 3.0,
        samples_per_decade: 5,
    };
    let d = deposit_curved(&params, 2, 0, &unlimited(), &NoProgress).unwrap();
    let solid: HashSet<[i32; 3]> = vox.cells().into_iter().collect();
    let mut occ: HashSet<[i32; 3]> = HashSet::new();
    for p in &d.cells[d.seeds..] {
        let n = faces(*p);
        assert!(!solid.contains(p));
        assert!(
            n.iter().any(|q| solid.contains(q) || occ.contains(q)),
            "{p:?} floats"
        );
        occ.insert(*p);
    }
    assert!(
        d.thickness > 2.0 && d.thickness < 15.0,
        "thickness {}",
        d.thickness
    );
}

#[test]
fn bad_input_is_refused_clearly() {
    let budget = unlimited();
    let mut p = DlaParams::point(3, 100);
    p.stick = 0.0;
    assert!(
        dla(&p, 1, 0, &budget, &NoProgress)
            .unwrap_err()
            .to_string()
            .contains("(0, 1]")
    );
    p.stick = 1.5;
    assert!(dla(&p, 1, 0, &budget, &NoProgress).is_err());
    let mut p = DlaParams::point(3, 100);
    p.size = [0, 10, 10];
    assert!(
        dla(&p, 1, 0, &budget, &NoProgress)
            .unwrap_err()
            .to_string()
            .contains("zero")
    );
    let mut p = DlaParams::point(3, 2000);
    p.size = [10, 10, 10];
    let e = dla(&p, 1, 0, &budget, &NoProgress).unwrap_err().to_string();
    assert!(e.contains("do not fit"), "{e}");
    let p = DlaParams::point(3, 1_000_000);
    let e = dla(&p, 1, 0, &MemoryBudget::new(1 << 20), &NoProgress)
        .unwrap_err()
        .to_string();
    assert!(e.contains("memory limit"), "{e}");
    assert!(Lattice::new(0, 2).is_err());
    assert!(Lattice::new(16, 3).is_err());
    let p = DepositionParams::new(Model::Rd, Lattice::new(16, 2).unwrap(), -1.0);
    assert!(
        deposit(&p, 1, 0, &budget, &NoProgress)
            .unwrap_err()
            .to_string()
            .contains("layers")
    );
    let p = DepositionParams::new(Model::Rdsr { radius: 0 }, Lattice::new(16, 2).unwrap(), 1.0);
    assert!(deposit(&p, 1, 0, &budget, &NoProgress).is_err());
    let p = DepositionParams::new(Model::Rd, Lattice::new(1 << 15, 2).unwrap(), 100.0);
    let mut q = p.clone();
    q.keep_particles = true;
    assert!(deposit(&q, 1, 0, &MemoryBudget::new(1 << 30), &NoProgress).is_err());
}

/// A progress reporter that unwinds out of `advance` once `cancel` is set, as
/// the Python binding's does on Ctrl-C.
struct Cancelling(std::sync::atomic::AtomicBool);

impl asperity_core::Progress for Cancelling {
    fn start(&self, _total: u64, _message: &str) {}
    fn advance(&self, _n: u64) {
        if self.0.load(std::sync::atomic::Ordering::Relaxed) {
            std::panic::resume_unwind(Box::new("cancelled"));
        }
    }
    fn finish(&self) {}
}

/// Cancelled at any moment, the walkers all stop: the run unwinds within a
/// second, whatever the number of walkers (one reporting thread unwinds, the
/// others see the stop flag).
#[test]
fn cancelled_walkers_stop() {
    use std::sync::Arc;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::time::Duration;
    for (round, walkers) in (0..24).zip([2usize, 3, 4].into_iter().cycle()) {
        let progress = Arc::new(Cancelling(AtomicBool::new(false)));
        let (tx, rx) = std::sync::mpsc::channel();
        let reporter = progress.clone();
        std::thread::spawn(move || {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(walkers)
                .build()
                .unwrap();
            let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                pool.install(|| {
                    let p = DlaParams::point(3, 2_000_000);
                    dla_with_walkers(&p, 5, round, &unlimited(), &*reporter, walkers)
                })
            }));
            let _ = tx.send(outcome.is_err());
        });
        // From the first commits to well into the growth.
        std::thread::sleep(Duration::from_millis(2 + 7 * round));
        progress.0.store(true, Ordering::Relaxed);
        let unwound = rx
            .recv_timeout(Duration::from_secs(10))
            .unwrap_or_else(|_| panic!("round {round}: {walkers} walkers did not stop"));
        assert!(
            unwound,
            "round {round}: the run ended without being cancelled"
        );
    }
}

/// kim-machiraju-thompson §7: DLA grown on a sphere or any object. About a
/// seed of many cells R_g(n) measures the seed (D = 6.4); the deposit's pair
/// correlation N(s) ∝ s^D about its particles from the seed's radius + 5 cells
/// to half their R_g (`dla::substrate`) measures the deposit. At 200,000
/// particles, on a ball of radius 20 and on a cube of side 33, it agrees with
/// the point seed's D by R_g(n) — a measure no substrate enters — within 0.1
/// (measured: 2.50 and 2.48 against 2.48, 3 clusters each), and with the point
/// seed's own pair count (2.55). The shell density about the seed, ρ(r) ∝ r^(D−d),
/// does not: its slope mixes the deposit with the seed's curvature (2.0–2.2).
/// In 2-D, discs of radius 20 and 40 (1.72, 1.69) against the point seed (1.69
/// by R_g(n), 1.74 by pairs).
#[test]
#[ignore = "slow tier: nine 3-D DLA clusters of 200,000 particles and nine 2-D of 30,000, ~20 s (cargo test -- --ignored)"]
fn dla_dimension_about_a_sphere_and_a_cube() {
    use asperity_analysis::scaling::pair_dimension;
    use asperity_growth::dla::substrate::shell_profile;
    let cube: Vec<[i32; 3]> = (-16..=16)
        .flat_map(|x| {
            (-16..=16).flat_map(move |y| (-16..=16).map(move |z| [256 + x, 256 + y, 256 + z]))
        })
        .collect();
    let three_d = [
        SeedShape::Point,
        SeedShape::Sphere(20.0),
        SeedShape::Cells(cube),
    ];
    let two_d = [
        SeedShape::Point,
        SeedShape::Sphere(20.0),
        SeedShape::Sphere(40.0),
    ];
    let runs: Vec<(usize, usize, u64)> = [3usize, 2]
        .into_iter()
        .flat_map(|dim| (0..3).flat_map(move |k| (0..3u64).map(move |s| (dim, k, s))))
        .collect();
    /// One cluster: its dimension, its seed shape, D by R_g(n) (point seeds),
    /// D by the pair count, and the window.
    struct Measured {
        dim: usize,
        k: usize,
        rg: f64,
        pairs: f64,
        range: [f64; 2],
    }
    let ds: Vec<Measured> = runs
        .par_iter()
        .map(|&(dim, k, s)| {
            let (shape, size, n) = if dim == 3 {
                (three_d[k].clone(), [512, 512, 512], 200_000)
            } else {
                (two_d[k].clone(), [2048, 1, 2048], 30_000)
            };
            let params = DlaParams {
                dim,
                size,
                particles: n,
                stick: 1.0,
                seed_shape: shape.clone(),
                launch_gap: 2.0,
                sides: Sides::Periodic,
            };
            let c = dla(&params, 40 + s, 0, &unlimited(), &NoProgress).unwrap();
            assert!(c.stopped.is_none(), "{:?}", c.stopped);
            let rg = if k == 0 {
                gyration_dimension(&c.points()).unwrap().d
            } else {
                f64::NAN
            };
            let p = shell_profile(&c, &shape, &unlimited()).unwrap().unwrap();
            assert!(!p.clipped);
            let pairs = p.pairs.as_ref().expect("a window of particles");
            assert!(pairs.centres > 2000, "{} centres", pairs.centres);
            Measured {
                dim,
                k,
                rg,
                pairs: pair_dimension(&pairs.radius, &pairs.neighbours).unwrap().d,
                range: p.fit_range(),
            }
        })
        .collect();
    let mean = |dim: usize, k: usize, pick: fn(&Measured) -> f64| {
        ds.iter()
            .filter(|d| d.dim == dim && d.k == k)
            .map(pick)
            .sum::<f64>()
            / 3.0
    };
    // DLA's D about a point (Meakin; Tolman & Meakin in 2-D).
    let truth = |dim: usize| if dim == 3 { 2.5 } else { 1.71 };
    for dim in [3, 2] {
        let point_rg = mean(dim, 0, |d| d.rg);
        let point_pairs = mean(dim, 0, |d| d.pairs);
        assert!(
            (point_rg - truth(dim)).abs() < 0.1,
            "{dim}-D point R_g(n) D = {point_rg}"
        );
        for k in 1..3 {
            let d = mean(dim, k, |d| d.pairs);
            assert!(
                (d - point_rg).abs() < 0.1 && (d - point_pairs).abs() < 0.1,
                "{dim}-D seed {k}: D = {d} about the substrate, the point's {point_rg} by R_g(n), {point_pairs} by pairs"
            );
        }
    }
    for Measured {
        dim,
        k,
        pairs: d,
        range,
        ..
    } in &ds
    {
        let spread = if *dim == 3 { 0.12 } else { 0.1 };
        assert!(
            (d - truth(*dim)).abs() < spread,
            "{dim}-D seed {k}: D = {d}"
        );
        if *dim == 3 && *k > 0 {
            // From R + 5 (R = 20, or the cube's volume-equivalent 20.5) to R_g/2.
            assert!(
                (range[0] - 25.0).abs() < 0.6 && (38.0..55.0).contains(&range[1]),
                "{range:?}"
            );
        }
    }
}
