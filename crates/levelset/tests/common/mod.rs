//! The comparisons of the sparse stages with the independent dense reference
//! (`asperity_levelset::reference`), shared by `oracle.rs` (they pass) and
//! `faults.rs` (they fail once a shared kernel is broken).

#![allow(dead_code)]

use asperity_core::{MemoryBudget, NoProgress};
use asperity_growth::dla::{DlaParams, SeedShape, Sides, dla};
use asperity_levelset::evolve::{LevelSet, evolve};
use asperity_levelset::pipeline::grid_for;
use asperity_levelset::reference::{convection_flow, exact_distance};
use asperity_levelset::sparse::{
    SparseDistance, sparse_distance, sparse_evolve, sparse_initial, sparse_tag,
};
use asperity_levelset::{
    DistanceField, EvolveParams, Flow, GridSpec, Length, ReconstructParams, Sizing, SparseLevelSet,
};

/// A plane DLA deposit, cropped so that it is open on every side.
pub fn crop_of_a_deposit() -> Vec<[f64; 3]> {
    let params = DlaParams {
        dim: 3,
        size: [40, 40, 32],
        particles: 5000,
        stick: 1.0,
        seed_shape: SeedShape::Plane,
        launch_gap: 2.0,
        sides: Sides::Periodic,
    };
    dla(&params, 5, 0, &MemoryBudget::unlimited(), &NoProgress)
        .expect("deposit")
        .points()
        .into_iter()
        .filter(|p| (4.0..30.0).contains(&p[0]) && (7.0..33.0).contains(&p[1]))
        .collect()
}

/// A bumpy sphere sampled on a latitude–longitude grid (dense at the poles,
/// sparse at the equator), off the grid's axes.
pub fn bumpy_sphere() -> Vec<[f64; 3]> {
    let mut pts = Vec::new();
    for a in 0..60 {
        for b in 0..120 {
            let th = std::f64::consts::PI * (a as f64 + 0.5) / 60.0;
            let ph = std::f64::consts::PI * (b as f64 + 0.3) / 60.0;
            let r = 6.0 + 0.8 * (5.0 * ph).sin() * (3.0 * th).cos();
            pts.push([
                0.37 + r * th.sin() * ph.cos(),
                -0.21 + r * th.sin() * ph.sin(),
                0.11 + r * th.cos(),
            ]);
        }
    }
    pts
}

/// The pipeline's grid, offset ε, tube γ and distance cap for `params`.
pub struct Setup {
    pub grid: GridSpec,
    pub eps: f64,
    pub gamma: f64,
    pub cap: f64,
}

pub fn setup(points: &[[f64; 3]], params: &ReconstructParams) -> Setup {
    let grid = grid_for(points, params, &MemoryBudget::unlimited()).expect("grid");
    let h = grid.spacing;
    let eps = params.offset.unwrap_or(Length::Cells(3.0)).world(h);
    let gamma = params.tube_cells * h;
    Setup {
        grid,
        eps,
        gamma,
        cap: eps + gamma + 2.0 * h,
    }
}

/// The settings both flows run with: the pipeline's, for `steps` steps.
pub fn flow_params(params: &ReconstructParams, h: f64, steps: usize) -> EvolveParams {
    EvolveParams {
        iterations: steps,
        scheme: params.scheme,
        flow: Flow::Convection,
        cfl: params.cfl,
        beta: params.beta_cells * h,
        redistance_iterations: params.redistance_iterations,
        tolerance: None,
        band: params.band,
        arrest: params.point_radius.expect("a point radius"),
        snapshot_every: None,
        neighbourhood: params.neighbourhood,
    }
}

/// The settings of the tests: the pipeline's defaults at a small resolution.
pub fn params() -> ReconstructParams {
    ReconstructParams {
        sizing: Sizing::Resolution(48),
        point_radius: Some(0.7),
        ..Default::default()
    }
}

/// How the sparse closest-point distance compares with the exact one on the
/// nodes within the cap (less a cell), in cells.
#[derive(Debug)]
pub struct DistanceErrors {
    /// The largest error.
    pub worst: f64,
    /// The largest error on the nodes within 3 cells of the data (where the
    /// offset surface is tagged).
    pub worst_near: f64,
    /// The share of nodes off by more than rounding.
    pub share: f64,
    /// The most the sparse distance falls short of the exact one: a wavefront
    /// only ever finds actual points, so this is rounding unless the distance
    /// kernel is wrong.
    pub below: f64,
}

pub fn distance_errors(points: &[[f64; 3]], s: &Setup) -> DistanceErrors {
    let (dist, _) = sparse_distance(points, &s.grid, s.cap, &NoProgress);
    let exact = exact_distance(points, &s.grid, s.cap);
    let h = s.grid.spacing;
    let mut e = DistanceErrors {
        worst: 0.0,
        worst_near: 0.0,
        share: 0.0,
        below: 0.0,
    };
    let (mut off, mut counted) = (0usize, 0usize);
    for (u, &x) in exact.iter().enumerate() {
        if x >= s.cap - h {
            continue;
        }
        counted += 1;
        let got = f64::from(dist.at(s.grid.coords(u)));
        let err = (got - x).abs() / h;
        e.worst = e.worst.max(err);
        if x <= 3.0 * h {
            e.worst_near = e.worst_near.max(err);
        }
        e.below = e.below.max((x - got) / h);
        if err > 1e-5 {
            off += 1;
        }
    }
    assert!(counted > 1000, "{counted} nodes compared");
    e.share = off as f64 / counted as f64;
    e
}

/// The distance check. The closest-point wavefront is exact wherever it
/// reaches a node with that node's nearest point; where the data is sampled
/// about a cell apart it misses now and then (a node whose nearest point's
/// Voronoi cell holds none of its neighbours), and the error grows with the
/// distance. So: never below the exact distance, and the misses bounded as
/// measured on the test inputs with a margin: none on the dense deposit; on the
/// sphere sampled about a cell apart, 5.9% of the nodes within the cap, off by
/// up to 0.24 cells, also within 3 cells of the data (more than the
/// wavefront's docs used to claim; noted for the team).
pub fn check_distance(points: &[[f64; 3]], s: &Setup) -> Result<(), String> {
    let e = distance_errors(points, s);
    if e.below <= 1e-5 && e.worst <= 0.3 && e.share <= 0.08 {
        Ok(())
    } else {
        Err(format!("the distance is off the exact one: {e:?} (cells)"))
    }
}

/// The sparse stages up to the initial level set.
pub fn initial(
    points: &[[f64; 3]],
    s: &Setup,
    params: &ReconstructParams,
) -> (SparseDistance, SparseLevelSet) {
    let (mut dist, _) = sparse_distance(points, &s.grid, s.cap, &NoProgress);
    let mut tags = sparse_tag(&mut dist, s.eps, params.tag_rule, &NoProgress);
    let ls = sparse_initial(&mut dist, &mut tags, s.eps, s.gamma, &NoProgress);
    (dist, ls)
}

/// What the flows did after `steps` steps from the same initial level set.
pub struct FlowGap {
    /// The largest |φ_sparse − φ_reference| over the grid, in cells.
    pub phi: f64,
    /// The largest relative difference of the time steps.
    pub dt: f64,
    /// Steps taken by each.
    pub steps: (usize, usize),
    /// The optimised dense flow's largest difference from the sparse one (0:
    /// bit for bit), in cells.
    pub dense: f64,
}

pub fn flow_gap(
    points: &[[f64; 3]],
    s: &Setup,
    params: &ReconstructParams,
    steps: usize,
) -> FlowGap {
    let (mut dist, mut ls) = initial(points, s, params);
    let h = s.grid.spacing;
    let ev = flow_params(params, h, steps);
    let phi0 = ls.to_dense();
    let d: Vec<f32> = (0..s.grid.len())
        .map(|u| dist.at(s.grid.coords(u)))
        .collect();
    let reference = convection_flow(&phi0, &d, &s.grid, ls.gamma, &ev);
    // The optimised dense flow, which shares the kernels.
    let mut dense = LevelSet {
        grid: s.grid,
        phi: phi0,
        gamma: ls.gamma,
    };
    let field = DistanceField {
        grid: s.grid,
        values: d,
        cap: dist.cap,
        nearest: None,
        sweeps: 0,
        last_change: 0.0,
    };
    evolve(&mut dense, &field, &ev, &NoProgress, &mut |_, _| {});
    let stats = sparse_evolve(&mut ls, &mut dist, &ev, &NoProgress, &mut |_, _| {});
    let sparse = ls.to_dense();
    let gap = |a: &[f32]| -> f64 {
        sparse
            .iter()
            .zip(a)
            .map(|(&x, &y)| f64::from(x - y).abs() / h)
            .fold(0.0, f64::max)
    };
    let dt = stats
        .steps
        .iter()
        .zip(&reference.dts)
        .map(|(a, &b)| (a.dt - b).abs() / b)
        .fold(0.0, f64::max);
    FlowGap {
        phi: gap(&reference.phi),
        dt,
        steps: (stats.steps.len(), reference.dts.len()),
        dense: gap(&dense.phi),
    }
}

/// The flow check: the sparse flow within rounding of the reference, step
/// for step.
pub fn check_flow(g: &FlowGap) -> Result<(), String> {
    if g.steps.0 == g.steps.1 && g.dt <= 1e-5 && g.phi <= 1e-4 {
        Ok(())
    } else {
        Err(format!(
            "the flow is off the reference by up to {:.2e} cells (time steps {:.1e} apart; {} and {} steps)",
            g.phi, g.dt, g.steps.0, g.steps.1
        ))
    }
}
