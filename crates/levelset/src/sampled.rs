//! The sampled-surface model of the pipeline (#52): what [`crate::pipeline`]
//! adds for a cloud that samples a surface — a scan, a random sample, the
//! bunny of kim-machiraju-thompson's Fig. 7 — rather than filling a deposit.
//!
//! * **The cloud** ([`crate::cloud`]): measured (or taken as given), its
//!   outliers dropped and its noise averaged.
//! * **The voids** ([`crate::sparse::voids`]): after the distance, the
//!   insides behind the gaps between samples; the distance is computed again
//!   under a larger cap while one may be deeper than the cap. Every void node
//!   is marked for the tagging (Algorithm 1's flood stays out); the flow
//!   holds those deeper than every gap (Zhao's) or all of them (the others),
//!   and Zhao's flow keeps thin parts by an obstacle.
//! * **The mesh** ([`refine`]): the vertices on thin parts' sides found, and
//!   under Zhao's flow the others projected onto the points' quadrics
//!   ([`crate::cloud::project`]).

use std::time::Instant;

use asperity_core::{MemoryBudget, Progress, TriMesh};

use crate::cloud::Projection;
use crate::sparse::SparseDistance;

/// What the points of [`crate::ReconstructParams`] are.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CloudChoice {
    /// Occupied cells of a growth simulation (kim-machiraju-thompson Figs.
    /// 8–11), used as they are: the front stops δ from every point.
    #[default]
    Deposit,
    /// Samples of a surface (the bunny of Fig. 7, a scan, a random sample):
    /// outliers dropped, noise averaged, the voids behind the gaps held
    /// ([`crate::sparse::voids`]).
    Surface,
    /// Measured: a surface when the points' neighbourhoods are flat
    /// ([`crate::cloud::SURFACE_FLATNESS`]), else a deposit.
    Auto,
}

/// What the points were found to be (see [`crate::cloud`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CloudFacts {
    /// Reconstructed as a sampled surface (else as a deposit).
    pub surface: bool,
    /// Whether that was measured ([`CloudChoice::Auto`]) or given.
    pub measured: bool,
    /// The median nearest-neighbour distance (when the cloud was analysed).
    pub spacing: Option<f64>,
    /// The median surface variation (when analysed).
    pub flatness: Option<f64>,
    /// Outliers dropped.
    pub outliers: usize,
    /// The median and largest distance a point moved when denoised.
    pub moved: (f64, f64),
    /// Points reconstructed (after the outliers went).
    pub points: usize,
}

/// The voids of a sampled surface (see [`crate::sparse::voids`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VoidFacts {
    /// Enclosed voids found.
    pub count: usize,
    /// The depth τ a void must have (world units).
    pub depth: f64,
    /// The half-width of the widest gap between a void and the outside (world units).
    pub widest_gap: f64,
    /// The distance cap the voids were decided under (world units).
    pub cap: f64,
    /// Distance computations: more than one where a cap was too small.
    pub tries: usize,
    /// Whether a void deeper than the last cap may remain undecided.
    pub undecided: bool,
    /// Nodes near a thin part or an open surface, kept δ inside (Zhao's flow).
    pub thin_nodes: usize,
    /// That δ: 0.9h (half the diagonal of a cell, the least at which the
    /// nodes within δ of a sheet separate its sides at any orientation), or
    /// 1.1 × the widest gap between random samples ([`widest_random_gap`]) if
    /// that is more.
    pub thin_radius: f64,
    /// The flow holds the void nodes at least this far from the samples
    /// (the tagging stays out of all of them).
    pub held_from: f64,
}

/// The points to reconstruct and what they were found to be: for
/// [`CloudChoice::Deposit`] the points as given; otherwise the cloud's
/// analysis ([`crate::cloud`]), and for a sampled surface its points cleaned.
pub(crate) fn cloud_stage(
    points: &[[f64; 3]],
    normals: Option<&[[f64; 3]]>,
    (choice, denoise): (CloudChoice, bool),
    (budget, progress): (&MemoryBudget, &dyn Progress),
) -> asperity_core::Result<(Option<Vec<[f64; 3]>>, CloudFacts)> {
    let forced = match choice {
        CloudChoice::Deposit => {
            let facts = CloudFacts {
                points: points.len(),
                ..CloudFacts::default()
            };
            return Ok((None, facts));
        }
        CloudChoice::Surface => Some(true),
        CloudChoice::Auto => None,
    };
    budget.check_elements(
        points.len() as u128,
        crate::cloud::BYTES_PER_POINT,
        &format!(
            "the neighbours of {} points (k = {})",
            points.len(),
            crate::cloud::NEIGHBOURS
        ),
    )?;
    let normals = normals.filter(|n| n.len() == points.len());
    let c = crate::cloud::analyze(points, normals, forced, denoise, progress);
    let surface = forced.unwrap_or(c.is_surface());
    let facts = CloudFacts {
        surface,
        measured: forced.is_none(),
        spacing: Some(c.spacing),
        flatness: Some(c.flatness),
        outliers: c.outliers,
        moved: c.moved,
        points: c.points.len(),
    };
    Ok((surface.then_some(c.points), facts))
}

/// The radius of the widest empty disc among `n` random points on a surface
/// whose median nearest-neighbour distance is `spacing`: for a Poisson sample
/// of density ρ the median is √(ln 2/(πρ)) and the largest empty disc about
/// √(ln n/(πρ)), so the ratio is √(log₂ n).
pub fn widest_random_gap(spacing: f64, n: usize) -> f64 {
    spacing * (n.max(2) as f64).log2().sqrt()
}

/// Distance tries for the voids of a sampled surface: each after the first
/// doubles the cap at least.
const VOID_TRIES: usize = 4;

/// A distance computation: per cap and whether each node's nearest point is
/// wanted, the capped distance, the sample spacing and those points.
pub(crate) type Distance<'a> = dyn Fn(f64, bool) -> asperity_core::Result<(SparseDistance, Option<f64>, Option<Vec<u32>>)>
    + 'a;

/// The distance for a sampled surface, with its voids held (see
/// [`crate::sparse::voids`]): computed again with a larger cap while a void
/// may be deeper than the cap, up to [`VOID_TRIES`] times.
pub(crate) fn surface_distance(
    points: &[[f64; 3]],
    distance: &Distance,
    (point_radius, cap, spacing, zhao): (Option<f64>, f64, f64, bool),
    (h, distance_s, voids_s): (f64, &mut f64, &mut f64),
) -> asperity_core::Result<(
    SparseDistance,
    Option<f64>,
    (VoidFacts, crate::sparse::Voids),
)> {
    // The thin parts' obstacle δ must close the gaps of the sheet it keeps.
    fn thin_radius(h: f64, spacing: f64, n: usize) -> f64 {
        (0.9 * h).max(1.1 * widest_random_gap(spacing, n))
    }
    let depth = (2.0 * spacing).max(2.0 * h);
    let mut cap = cap.max(depth + 4.0 * h);
    let mut tries = 0;
    loop {
        tries += 1;
        let t = Instant::now();
        let (mut dist, sample_spacing, nearest) = distance(cap, zhao)?;
        *distance_s += t.elapsed().as_secs_f64();
        let t = Instant::now();
        let voids = crate::sparse::label_voids(&dist, depth);
        let retry = voids.undecided.filter(|_| tries < VOID_TRIES);
        if let Some(level) = retry {
            *voids_s += t.elapsed().as_secs_f64();
            cap = (2.0 * cap).max(level + depth + 4.0 * h);
            continue;
        }
        // Zhao's front comes to rest on the samples, and across the gaps
        // between them, by itself (∇d lies along a gap), so only the voids'
        // nodes deeper than every gap are held; and it closes on a thin part
        // from both sides: its nodes within δ of the samples get the obstacle
        // of `zhao_rate`. The other flows hold every void node, and their
        // arrest distance keeps thin parts.
        let thin_radius = point_radius.unwrap_or_else(|| thin_radius(h, spacing, points.len()));
        let reach = crate::sparse::voids::obstacle_reach(thin_radius, h);
        let (thin, hold_from) = if zhao {
            (
                nearest.as_deref().map(|n| (n, points, reach)),
                (voids.widest_gap + h).max(1.5 * h).max(reach + h),
            )
        } else {
            (None, 0.0)
        };
        // Every void node is marked for the tagging; the flow's are released
        // after it (`release`).
        let thin_nodes = crate::sparse::freeze(&mut dist, &voids, thin, 0.0);
        let thin = if zhao { thin_radius } else { 0.0 };
        *voids_s += t.elapsed().as_secs_f64();
        let facts = VoidFacts {
            count: voids.count,
            depth,
            widest_gap: voids.widest_gap,
            cap,
            tries,
            undecided: voids.undecided.is_some(),
            thin_nodes,
            thin_radius: thin,
            held_from: hold_from,
        };
        return Ok((dist, sample_spacing, (facts, voids)));
    }
}

/// The sampled surface's mesh finished: its vertices on thin parts' sides
/// found (while the marks of `dist` are at hand), and, for Zhao's flow, the
/// others projected onto the points' quadrics. Only Zhao's front rests on the
/// samples: the other flows' stands δ off them, on the union of δ-balls, and
/// projected it would fold; and so do the thin parts' sides, δ off theirs.
pub(crate) fn refine(
    mesh: &mut TriMesh,
    dist: SparseDistance,
    (points, cloud, voids): (&[[f64; 3]], &CloudFacts, Option<&VoidFacts>),
    (project, h): (bool, f64),
) -> (Vec<bool>, Option<Projection>) {
    let thin_vertices = match voids {
        Some(v) if v.thin_nodes > 0 => {
            let reach = crate::sparse::voids::obstacle_reach(v.thin_radius, h);
            crate::sparse::voids::thin_vertices(&dist, mesh.positions(), reach)
        }
        _ => Vec::new(),
    };
    drop(dist);
    if !(cloud.surface && project) {
        return (thin_vertices, None);
    }
    // Within reach of the samples on every side: across the gaps of a random
    // sample, not across a hole.
    let spacing = cloud.spacing.unwrap_or(h);
    let support = (1.2 * widest_random_gap(spacing, points.len())).max(1.5 * h);
    let p = project_onto(mesh, points, (support + h, h), &thin_vertices);
    (thin_vertices, p)
}

/// The mesh's vertices projected onto the points' local quadrics
/// ([`crate::cloud::project`]: within `limits` = (support, largest move),
/// the vertices flagged in `skip` left); its normals recomputed, its
/// scalars kept.
pub fn project_onto(
    mesh: &mut TriMesh,
    points: &[[f64; 3]],
    limits: (f64, f64),
    skip: &[bool],
) -> Option<crate::cloud::Projection> {
    let normals = mesh.vertex_normals();
    let mut positions = mesh.positions().to_vec();
    let p = crate::cloud::project(&mut positions, &normals, points, limits, skip);
    let moved = TriMesh::new(positions, mesh.triangles().to_vec()).ok()?;
    let scalars: Vec<(String, Vec<f64>)> = mesh
        .scalars()
        .iter()
        .map(|a| (a.name.clone(), a.values.clone()))
        .collect();
    let mut out = moved.with_computed_normals();
    for (name, values) in scalars {
        out = out.with_scalar(&name, values).ok()?;
    }
    *mesh = out;
    Some(p)
}
