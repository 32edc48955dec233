//! The reconstruction pipeline of §5.2 (Fig. 5): distance → tagging → convection
//! flow → marching cubes, with each stage timed.
//!
//! Every stage runs on the sparse brick layout of [`crate::sparse`]: storage
//! and work follow the points' neighbourhood and the front, not the box. The
//! closest-point distance (the default) allocates only the bricks within its
//! cap of a point; the paper's Godunov sweeping needs the whole grid, so its
//! field is computed densely and then laid out in bricks, all of them active.
//! The result is the dense pipeline's, node for node and triangle for
//! triangle (each stage is tested against its dense counterpart).
//!
//! **Sampled surfaces** ([`CloudChoice`]). The paper reconstructs both the
//! occupied cells of its growth models and a sampled surface (the bunny of
//! Fig. 7). For the second kind, measured or given, the pipeline adds what
//! real clouds need (#52): the cloud's analysis first ([`crate::cloud`]:
//! outliers, noise), the voids behind the gaps between samples after the
//! distance ([`crate::sparse::voids`]: computed again under a larger cap while
//! one may be deeper than the cap), kept out of the tagging and held in the
//! flow; Zhao's flow by default ([`FlowChoice::Auto`]), with an obstacle that
//! keeps thin parts and open patches a thin shell; and last the vertices
//! projected onto the points' quadrics ([`crate::cloud::project`]).

use std::time::Instant;

use asperity_core::{CoreError, MemoryBudget, NoProgress, Progress, TriMesh};
use rayon::prelude::*;

use crate::distance::{DistanceMethod, closest_points, unsigned_distance};
use crate::evolve::{Band, EvolveParams, EvolveStats, Flow, Neighbourhood, Scheme, StepStats};
pub use crate::grid::Length;
use crate::grid::{GridSpec, Sizing, padding_nodes};
use crate::marching_cubes::{ExtractOptions, ExtractStats};
use crate::sampled::{CloudChoice, CloudFacts, VoidFacts};
use crate::sparse::distance::{bricks_for, sample_spacing as sparse_sample_spacing};
use crate::sparse::layout::BRICK_NODES;
use crate::sparse::{
    Bricks, SparseDistance, SparseLevelSet, sparse_evolve, sparse_extract, sparse_initial,
    sparse_tag,
};
use crate::tagging::TagRule;

/// Bytes per active node (a node of a brick with storage) the pipeline holds
/// at its peak: the distance stage's packed closest point (8) and distance
/// (4) while the one becomes the other, or the flow's d, φ and scratch (12),
/// plus the tubes' and tags' bits and the masks of the tagging; the mesh comes
/// on top (see [`MESH_BYTES_PER_ACTIVE_NODE`]).
pub const BYTES_PER_ACTIVE_NODE: u64 = 16;

/// Bytes of mesh per active node while the mesh is assembled and measured: a
/// rough surface's front cuts about a quarter of a triangle per active node
/// (measured on plane DLA deposits at 512³ and 1024³: 0.24), and a triangle
/// costs about 60 bytes then (its keys, indices, half a vertex, the link
/// lists of the topology). The process peaked at 30 and 24 bytes per active
/// node on those runs, the fixed start-up memory included.
pub const MESH_BYTES_PER_ACTIVE_NODE: u64 = 14;

/// Bytes per brick of the brick table (a 32-bit slot, and a bit while the
/// bricks near the points are marked).
const BYTES_PER_BRICK: u64 = 5;

/// Everything the pipeline needs to know; lengths in cells are multiples of h.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReconstructParams {
    /// Grid spacing.
    pub sizing: Sizing,
    /// Offset ε of the initial surface, in world units or in cells of h
    /// (default 3h, the paper's ε = 3 grid cells).
    pub offset: Option<Length>,
    /// Tube half-width γ in cells (≥ 2; default 3).
    pub tube_cells: f64,
    /// Full-speed half-width β in cells (< γ; default 2).
    pub beta_cells: f64,
    /// Distance method.
    pub distance: DistanceMethod,
    /// Tagging rule.
    pub tag_rule: TagRule,
    /// Time steps.
    pub iterations: usize,
    /// Time steps instead when the cloud turns out a sampled surface (`None`:
    /// `iterations`): Zhao's front travels at most about half a cell a step,
    /// and slowly where a concavity narrows (between a bunny's ears).
    pub surface_iterations: Option<usize>,
    /// Space discretisation.
    pub scheme: Scheme,
    /// The flow: the paper's convection (Eq. 6), regularised, or Zhao's.
    pub flow: FlowChoice,
    /// CFL number.
    pub cfl: f64,
    /// Redistancing iterations per step.
    pub redistance_iterations: usize,
    /// Stop when the front moves less than this many cells per step.
    pub tolerance: Option<f64>,
    /// Narrow band or the full grid.
    pub band: Band,
    /// Point radius δ, world units: the front stops this far from the data (0 is
    /// the paper's model). `None`: [`default_arrest_spacings`] × the measured sample
    /// spacing (0.75 up to 60 steps, growing to 1 at 200), at least 0.6h (below
    /// that the node shell leaks where the grid is coarser than the samples).
    pub point_radius: Option<f64>,
    /// Mesh options.
    pub extract: ExtractOptions,
    /// Show `on_step` the level set every this many steps (step 0 is always shown).
    pub snapshot_every: Option<usize>,
    /// How the flow tube T grows into the redistancing tube N.
    pub neighbourhood: Neighbourhood,
    /// What the points are: a deposit (the paper's growth models), a sampled
    /// surface (a scan, a random sample), or measured ([`crate::cloud`]).
    pub cloud: CloudChoice,
    /// For a sampled surface: move each point onto the quadric of its
    /// neighbours first ([`crate::cloud`]).
    pub denoise: bool,
    /// For a sampled surface: move the mesh's vertices onto the points'
    /// quadrics last ([`crate::cloud::project`]).
    pub project: bool,
}

/// The flow of [`ReconstructParams`] (lengths in cells, as the other settings).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum FlowChoice {
    /// φ_t = d|∇φ| (Eq. 6), the paper's.
    #[default]
    Convection,
    /// Eq. 6 plus the curvature term d·λκ|∇φ| of weight λ cells.
    Regularized {
        /// λ in cells.
        weight_cells: f64,
    },
    /// Zhao's φ_t = ∇d·∇φ (v = −∇d), the flow the paper replaces.
    Zhao,
    /// By the cloud: Zhao's for a sampled surface, whose front comes to rest
    /// on the samples and spans the gaps between them (∇d lies along a gap
    /// there); the paper's convection for a deposit, whose roughness it keeps.
    Auto,
}

impl FlowChoice {
    /// The flow for a cloud that `surface` samples or not.
    pub fn resolved(self, surface: bool) -> Self {
        match (self, surface) {
            (Self::Auto, true) => Self::Zhao,
            (Self::Auto, false) => Self::Convection,
            (f, _) => f,
        }
    }
}

impl Default for ReconstructParams {
    fn default() -> Self {
        Self {
            sizing: Sizing::Resolution(128),
            offset: None,
            tube_cells: crate::evolve::TUBE_CELLS,
            beta_cells: crate::evolve::BETA_CELLS,
            distance: DistanceMethod::ClosestPoint,
            tag_rule: TagRule::Paper,
            iterations: 30,
            surface_iterations: None,
            scheme: Scheme::Eno2,
            flow: FlowChoice::Convection,
            cfl: crate::evolve::CFL,
            redistance_iterations: 2,
            tolerance: None,
            band: Band::Narrow,
            point_radius: None,
            extract: ExtractOptions::default(),
            snapshot_every: None,
            neighbourhood: Neighbourhood::Axes,
            cloud: CloudChoice::Deposit,
            denoise: true,
            project: true,
        }
    }
}

/// The default arrest distance δ in sample spacings for a flow of `iterations`
/// steps: 0.75 up to 60 steps, then growing linearly to 1 at 200 steps, and 1
/// beyond.
///
/// The flow of Eq. 6 has no force that brings back a front which has crossed
/// the data (the unsigned d grows again behind it), so wherever the front sits
/// in a gap between samples for long enough it slips through: the longer the
/// run, the larger δ must be. Measured on the Fig. 7 stand-in
/// (`shapes::synthetic_bunny(7, 30_000)`, 134 cells, ε = 17 cells, sample
/// spacing 1.05h), genus after the run with δ = k × spacing:
///
/// | steps | k = 0.75 | 0.8 | 0.82 | 0.85 | 0.91 | 1.0 |
/// |---|---|---|---|---|---|---|
/// | 60 | 0 | | | | | |
/// | 100 | 7 | | **0** | | | |
/// | 150 | 35 | | | | **0** | |
/// | 200 | 444 | 100 | | 0 | | **0** |
/// | 300, 400 | | | | | | **0** |
///
/// (bold: this default). One spacing is above the gaps' half-width, so the
/// front cannot slip however long it runs; short runs keep the closer 0.75,
/// which the sphere tests hold to 1.5h.
pub fn default_arrest_spacings(iterations: usize) -> f64 {
    let grown = (iterations.saturating_sub(60) as f64 / 140.0).min(1.0);
    0.75 + 0.25 * grown
}

/// Seconds per stage.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timings {
    /// The cloud's analysis: neighbours, outliers, denoising.
    pub cloud: f64,
    /// Unsigned distance (every try, for a sampled surface).
    pub distance: f64,
    /// The voids of a sampled surface.
    pub voids: f64,
    /// Tagging (Algorithm 1).
    pub tagging: f64,
    /// Signed distance to the tagged front.
    pub initial: f64,
    /// The level-set evolution.
    pub evolution: f64,
    /// The projection of the vertices onto the points' quadrics.
    pub projection: f64,
    /// Marching cubes.
    pub extraction: f64,
    /// All of it.
    pub total: f64,
}

/// The result of [`reconstruct`].
#[derive(Clone, Debug)]
pub struct Reconstruction {
    /// The surface.
    pub mesh: TriMesh,
    /// The grid.
    pub grid: GridSpec,
    /// ε used.
    pub offset: f64,
    /// δ used.
    pub point_radius: f64,
    /// The typical sample spacing: the median distance between Voronoi-adjacent points
    /// near the surface (closest-point method) or the median nearest-neighbour distance
    /// (Godunov).
    pub sample_spacing: Option<f64>,
    /// Stage timings.
    pub timings: Timings,
    /// Distance: rounds (closest point) or sweeps (Godunov).
    pub distance_sweeps: usize,
    /// Nodes tagged exterior and refused by the paper's rule.
    pub tagged: (usize, usize),
    /// Per-step statistics.
    pub evolution: EvolveStats,
    /// Components and removed shells.
    pub extraction: ExtractStats,
    /// Bricks of 8³ nodes that held values at the end, of all the grid's
    /// bricks (the final level set itself is dropped before this returns;
    /// `on_step` sees it during the flow).
    pub bricks: (usize, usize),
    /// The flow that ran ([`FlowChoice::Auto`] resolved).
    pub flow: FlowChoice,
    /// What the cloud was measured or taken to be.
    pub cloud: CloudFacts,
    /// For a sampled surface: its voids.
    pub voids: Option<VoidFacts>,
    /// For a sampled surface: the vertices' projection onto the points'
    /// quadrics.
    pub projection: Option<crate::cloud::Projection>,
    /// Per vertex, whether it lies on a side of a thin part or an open
    /// surface (Zhao's flow on a sampled surface; empty when none does).
    pub thin_vertices: Vec<bool>,
}

fn invalid(name: &'static str, reason: String) -> CoreError {
    CoreError::InvalidParameter { name, reason }
}

impl ReconstructParams {
    /// Checks the settings.
    ///
    /// # Errors
    /// [`CoreError::InvalidParameter`] naming the bad setting.
    pub fn validate(&self) -> asperity_core::Result<()> {
        if let Some(e) = self.offset.map(Length::value)
            && !(e.is_finite() && e > 0.0)
        {
            return Err(invalid(
                "offset",
                format!("must be positive and finite, got {e}"),
            ));
        }
        if !(self.tube_cells.is_finite() && (2.0..=64.0).contains(&self.tube_cells)) {
            return Err(invalid(
                "tube",
                format!("γ must be 2 to 64 cells, got {}", self.tube_cells),
            ));
        }
        if !(self.beta_cells.is_finite()
            && self.beta_cells > 0.0
            && self.beta_cells < self.tube_cells)
        {
            return Err(invalid(
                "beta",
                format!(
                    "β must be positive and below γ = {} cells, got {}",
                    self.tube_cells, self.beta_cells
                ),
            ));
        }
        if let Some(r) = self.point_radius
            && !(r.is_finite() && r >= 0.0)
        {
            return Err(invalid(
                "point radius",
                format!("must be ≥ 0 and finite, got {r}"),
            ));
        }
        if !(self.cfl.is_finite() && self.cfl > 0.0 && self.cfl <= 1.0) {
            return Err(invalid(
                "cfl",
                format!("must be in (0, 1], got {}", self.cfl),
            ));
        }
        if self.iterations.max(self.surface_iterations.unwrap_or(0)) > 1_000_000 {
            return Err(invalid(
                "iterations",
                format!("at most 10⁶, got {}", self.iterations),
            ));
        }
        if let FlowChoice::Regularized { weight_cells: w } = self.flow
            && !(w.is_finite() && w > 0.0)
        {
            return Err(invalid(
                "curvature weight",
                format!("must be positive, got {w}"),
            ));
        }
        if let Some(t) = self.tolerance
            && !(t.is_finite() && t >= 0.0)
        {
            return Err(invalid(
                "tolerance",
                format!("must be a non-negative number of cells, got {t}"),
            ));
        }
        if let DistanceMethod::Godunov {
            tolerance,
            max_iterations,
            seed_cells,
        } = self.distance
            && !(tolerance.is_finite()
                && tolerance >= 0.0
                && max_iterations > 0
                && seed_cells <= 16)
        {
            return Err(invalid(
                "distance",
                "Godunov needs a tolerance ≥ 0, at least one iteration and at most 16 seed cells"
                    .into(),
            ));
        }
        Ok(())
    }
}

/// The unsigned distance to the points on bricks, the measured sample
/// spacing, and the rounds or sweeps the distance took; the active nodes are
/// checked against `budget` before they are allocated.
fn distance_stage(
    points: &[[f64; 3]],
    grid: &GridSpec,
    method: DistanceMethod,
    cap: f64,
    (budget, progress): (&MemoryBudget, &dyn Progress),
) -> asperity_core::Result<(SparseDistance, Option<f64>)> {
    distance_and_nearest(points, grid, (method, cap, false), (budget, progress))
        .map(|(d, s, _)| (d, s))
}

/// [`distance_stage`], and per node id its nearest point ([`u32::MAX`]
/// beyond the cap) when `nearest` and the method is the closest point's.
pub(crate) fn distance_and_nearest(
    points: &[[f64; 3]],
    grid: &GridSpec,
    (method, cap, nearest): (DistanceMethod, f64, bool),
    (budget, progress): (&MemoryBudget, &dyn Progress),
) -> asperity_core::Result<(SparseDistance, Option<f64>, Option<Vec<u32>>)> {
    let h = grid.spacing;
    match method {
        DistanceMethod::ClosestPoint => {
            let bricks = bricks_for(grid, points, cap);
            check_active(&bricks, budget)?;
            let (cells, rounds) =
                crate::sparse::distance::closest_points(points, &bricks, cap, progress);
            // The sample spacing is read off the closest points before they are
            // unpacked, so no nearest-point array is built for it.
            let spacing = sparse_sample_spacing(points, &bricks, &cells, 2.0 * h);
            let ids = nearest.then(|| {
                (0..cells.len())
                    .into_par_iter()
                    .map(|u| {
                        let c = cells.load(u);
                        if c == crate::distance::EMPTY {
                            u32::MAX
                        } else {
                            c as u32
                        }
                    })
                    .collect()
            });
            Ok((
                SparseDistance::from_cells(bricks, cells, cap, rounds),
                spacing,
                ids,
            ))
        }
        DistanceMethod::Godunov { .. } => {
            // The same spacing measure as the closest-point method, so that δ
            // (a multiple of the spacing) does not depend on the distance method: a thin
            // wavefront of 2h gives the nodes' nearest points.
            let near = 2.0 * h;
            let (cells, _) = closest_points(points, grid, near, &NoProgress, None);
            let spacing = dense_sample_spacing(points, grid, &cells, near);
            drop(cells);
            let dense = unsigned_distance(points, grid, method, cap, progress);
            Ok((
                bricked(&dense.values, grid, dense.cap, dense.sweeps),
                spacing,
                None,
            ))
        }
    }
}

/// A dense field laid out in bricks, every brick active.
fn bricked(values: &[f32], grid: &GridSpec, cap: f32, sweeps: usize) -> SparseDistance {
    let bricks = Bricks::all(grid);
    let mut out = vec![cap; bricks.nodes()];
    out.par_chunks_mut(BRICK_NODES)
        .enumerate()
        .for_each(|(s, brick)| {
            let b = bricks.slot_coords(s);
            for (l, x) in brick.iter_mut().enumerate() {
                let c = [b[0] * 8 + l % 8, b[1] * 8 + (l / 8) % 8, b[2] * 8 + l / 64];
                if c[0] < grid.dims[0] && c[1] < grid.dims[1] && c[2] < grid.dims[2] {
                    *x = values[grid.index(c[0], c[1], c[2])];
                }
            }
        });
    SparseDistance {
        bricks,
        values: out,
        cap,
        rounds: sweeps,
    }
}

/// Refuses `bricks` whose nodes, with the mesh to come, would not fit in `budget`.
fn check_active(bricks: &Bricks, budget: &MemoryBudget) -> asperity_core::Result<()> {
    let d = bricks.grid.dims;
    budget.check_elements(
        bricks.nodes() as u128,
        BYTES_PER_ACTIVE_NODE + MESH_BYTES_PER_ACTIVE_NODE,
        &format!(
            "level-set reconstruction on {} of the {} bricks of 8³ nodes of a {}×{}×{} grid (the bricks near the points)",
            bricks.slots(),
            bricks.brick_count(),
            d[0],
            d[1],
            d[2]
        ),
    )
}

/// The flow's settings in world units (h the grid spacing, δ the point radius).
fn evolve_params(params: &ReconstructParams, h: f64, point_radius: f64) -> EvolveParams {
    EvolveParams {
        iterations: params.iterations,
        scheme: params.scheme,
        flow: match params.flow {
            FlowChoice::Convection | FlowChoice::Auto => Flow::Convection,
            FlowChoice::Regularized { weight_cells } => Flow::Regularized {
                weight: weight_cells * h,
            },
            FlowChoice::Zhao => Flow::Zhao,
        },
        cfl: params.cfl,
        beta: params.beta_cells * h,
        redistance_iterations: params.redistance_iterations,
        tolerance: params.tolerance,
        band: params.band,
        arrest: point_radius,
        snapshot_every: params.snapshot_every,
        neighbourhood: params.neighbourhood,
    }
}

/// Seconds since `t`, stored in `slot`.
pub(crate) fn lap(slot: &mut f64, t: Instant) {
    *slot = t.elapsed().as_secs_f64();
}

/// The grid [`reconstruct`] uses for `points`: the sizing's spacing, padded for
/// the offset ε and the tube (see [`padding_nodes`]), checked against `budget`:
/// its brick table, and for the Godunov distance (which sweeps the whole grid)
/// its dense fields. The closest-point distance's bricks are checked once the
/// points have marked them.
///
/// # Errors
/// As [`GridSpec::fitting`], or the estimate above the budget.
pub fn grid_for(
    points: &[[f64; 3]],
    params: &ReconstructParams,
    budget: &MemoryBudget,
) -> asperity_core::Result<GridSpec> {
    let offset_of = |h: f64| params.offset.unwrap_or(Length::Cells(3.0)).world(h);
    let pad = |h| padding_nodes(offset_of(h), params.tube_cells * h, h);
    if matches!(params.distance, DistanceMethod::Godunov { .. }) {
        return GridSpec::around(points, params.sizing, pad, budget);
    }
    let grid = GridSpec::fitting(points, params.sizing, pad)?;
    let bricks = grid
        .dims
        .iter()
        .map(|&n| n.div_ceil(8) as u128)
        .product::<u128>();
    budget.check_elements(
        bricks,
        BYTES_PER_BRICK,
        &format!(
            "the brick table of a {}×{}×{} grid",
            grid.dims[0], grid.dims[1], grid.dims[2]
        ),
    )?;
    Ok(grid)
}

/// Reconstructs a watertight surface from `points`; `on_step` sees the initial level
/// set (step 0) and the level set every `params.snapshot_every` steps.
///
/// # Errors
/// Bad points (empty, non-finite, identical), bad settings, or a grid above the
/// memory budget.
pub fn reconstruct(
    points: &[[f64; 3]],
    params: &ReconstructParams,
    budget: &MemoryBudget,
    progress: &dyn Progress,
    on_step: &mut dyn FnMut(&StepStats, &SparseLevelSet),
) -> asperity_core::Result<Reconstruction> {
    reconstruct_cloud(points, None, params, budget, progress, on_step)
}

/// The distance for `cloud`: a sampled surface's with its voids
/// ([`crate::sampled::surface_distance`]), a deposit's as the paper's.
#[allow(clippy::type_complexity)] // the stage's three results, named at the call
fn cloud_distance(
    points: &[[f64; 3]],
    grid: &GridSpec,
    (params, cap, cloud): (&ReconstructParams, f64, &CloudFacts),
    (budget, progress, timings): (&MemoryBudget, &dyn Progress, &mut Timings),
) -> asperity_core::Result<(
    SparseDistance,
    Option<f64>,
    Option<(VoidFacts, crate::sparse::Voids)>,
)> {
    let h = grid.spacing;
    let flow = params.flow;
    Ok(if cloud.surface {
        let spacing = cloud.spacing.unwrap_or(h);
        let (d, s, v) = crate::sampled::surface_distance(
            points,
            &|cap, nearest| {
                distance_and_nearest(
                    points,
                    grid,
                    (params.distance, cap, nearest),
                    (budget, progress),
                )
            },
            (params.point_radius, cap, spacing, flow == FlowChoice::Zhao),
            (h, &mut timings.distance, &mut timings.voids),
        )?;
        (d, s, Some(v))
    } else {
        let t = Instant::now();
        let (d, s) = distance_stage(points, grid, params.distance, cap, (budget, progress))?;
        lap(&mut timings.distance, t);
        (d, s, None)
    })
}

/// [`reconstruct`] with the points' unit `normals` (from the file, when it had
/// them; used for a sampled surface's denoising).
///
/// # Errors
/// As [`reconstruct`].
pub fn reconstruct_cloud(
    points: &[[f64; 3]],
    normals: Option<&[[f64; 3]]>,
    params: &ReconstructParams,
    budget: &MemoryBudget,
    progress: &dyn Progress,
    on_step: &mut dyn FnMut(&StepStats, &SparseLevelSet),
) -> asperity_core::Result<Reconstruction> {
    params.validate()?;
    if points.len() >= u32::MAX as usize {
        return Err(invalid(
            "points",
            format!("{} points is more than 2³²−1", points.len()),
        ));
    }
    let start = Instant::now();
    let mut timings = Timings::default();
    let t = Instant::now();
    let (cleaned, cloud) = crate::sampled::cloud_stage(
        points,
        normals,
        (params.cloud, params.denoise),
        (budget, progress),
    )?;
    lap(&mut timings.cloud, t);
    let points = cleaned.as_deref().unwrap_or(points);
    let flow = params.flow.resolved(cloud.surface);
    let iterations = match params.surface_iterations {
        Some(n) if cloud.surface => n,
        _ => params.iterations,
    };
    let params = &ReconstructParams {
        flow,
        iterations,
        ..*params
    };
    let offset_of = |h: f64| params.offset.unwrap_or(Length::Cells(3.0)).world(h);
    let grid = grid_for(points, params, budget)?;
    let h = grid.spacing;
    let (eps, gamma) = (offset_of(h), params.tube_cells * h);
    let cap = eps + gamma + 2.0 * h;
    let (mut dist, sample_spacing, voids) = cloud_distance(
        points,
        &grid,
        (params, cap, &cloud),
        (budget, progress, &mut timings),
    )?;
    let t = Instant::now();
    let mut tags = sparse_tag(&mut dist, eps, params.tag_rule, progress);
    lap(&mut timings.tagging, t);
    let t = Instant::now();
    let mut ls = sparse_initial(&mut dist, &mut tags, eps, gamma, progress);
    if let Some((facts, labels)) = &voids {
        crate::sparse::voids::release(&mut dist, labels, facts.held_from);
    }
    let voids = voids.map(|(facts, _)| facts);
    lap(&mut timings.initial, t);
    let tagged = (tags.exterior_count, tags.refused);
    drop(tags);
    let initial = StepStats {
        step: 0,
        dt: 0.0,
        front_movement: 0.0,
        tube: 0,
    };
    on_step(&initial, &ls);
    let point_radius = params.point_radius.unwrap_or_else(|| match &voids {
        // Zhao's flow on a sampled surface: δ is the thin parts' obstacle.
        Some(v) if flow == FlowChoice::Zhao => v.thin_radius,
        _ => (default_arrest_spacings(params.iterations) * sample_spacing.unwrap_or(0.0))
            .max(0.6 * h),
    });
    let t = Instant::now();
    let evolution = sparse_evolve(
        &mut ls,
        &mut dist,
        &evolve_params(params, h, point_radius),
        progress,
        on_step,
    );
    lap(&mut timings.evolution, t);
    let distance_sweeps = dist.rounds;
    let t = Instant::now();
    let (mut mesh, extraction) = sparse_extract(&ls, &params.extract);
    let bricks = (ls.bricks.slots(), ls.bricks.brick_count());
    drop(ls);
    lap(&mut timings.extraction, t);
    let t = Instant::now();
    let (thin_vertices, projection) = crate::sampled::refine(
        &mut mesh,
        dist,
        (points, &cloud, voids.as_ref()),
        (params.project && flow == FlowChoice::Zhao, h),
    );
    lap(&mut timings.projection, t);
    lap(&mut timings.total, start);
    Ok(Reconstruction {
        mesh,
        grid,
        offset: eps,
        point_radius,
        sample_spacing,
        timings,
        distance_sweeps,
        tagged,
        evolution,
        extraction,
        bricks,
        flow,
        cloud,
        voids,
        projection,
        thin_vertices,
    })
}

/// The median distance between the nearest points of neighbouring nodes that differ
/// (Voronoi neighbours), over nodes within `near` of the data on every
/// ⌊n_z/16⌋-th plane: the typical sample spacing (on the dense grid, for the
/// Godunov distance).
fn dense_sample_spacing(
    points: &[[f64; 3]],
    grid: &GridSpec,
    cells: &[std::sync::atomic::AtomicU64],
    near: f64,
) -> Option<f64> {
    use crate::distance::{EMPTY, unpack_d2};
    use std::sync::atomic::Ordering::Relaxed;
    let strides = grid.strides();
    let nearest = |u: usize| {
        let c = cells[u].load(Relaxed);
        if c == EMPTY { u32::MAX } else { c as u32 }
    };
    let near2 = (near * near) as f32;
    // A sample of about 16 planes (a hundred thousand gaps at 256³) is plenty
    // for a median, and spares a pass over the whole grid.
    let plane = grid.dims[0] * grid.dims[1];
    let stride = (grid.dims[2] / 16).max(1);
    let mut gaps: Vec<f32> = (0..grid.dims[2].div_ceil(stride))
        .into_par_iter()
        .flat_map_iter(|k| k * stride * plane..(k * stride + 1) * plane)
        .filter(|&u| {
            let c = cells[u].load(Relaxed);
            c != EMPTY && unpack_d2(c) < near2
        })
        .flat_map_iter(|u| {
            let c = grid.coords(u);
            let p = nearest(u);
            (0..3).filter_map(move |a| {
                if c[a] + 1 >= grid.dims[a] {
                    return None;
                }
                let q = nearest(u + strides[a]);
                if q == p || q == u32::MAX {
                    return None;
                }
                let (x, y) = (points[p as usize], points[q as usize]);
                Some(
                    (((x[0] - y[0]).powi(2) + (x[1] - y[1]).powi(2) + (x[2] - y[2]).powi(2)).sqrt())
                        as f32,
                )
            })
        })
        .collect();
    if gaps.is_empty() {
        return None;
    }
    let mid = gaps.len() / 2;
    let (_, m, _) = gaps.select_nth_unstable_by(mid, f32::total_cmp);
    Some(f64::from(*m))
}
