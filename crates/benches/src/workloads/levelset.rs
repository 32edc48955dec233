//! The level-set workloads: reconstructions of sampled spheres, plane DLA
//! deposits at 256³ to 1024³, the dense driver beside the sparse one.

use super::*;

/// Level-set reconstruction of an RDSR sphere (kim-machiraju-thompson Fig. 8):
/// distance + tagging + 30 RK2 steps + marching cubes, narrow band or (`full`)
/// every node every step.
fn levelset(
    s: &Setup,
    name: &'static str,
    res: usize,
    full: bool,
    target: Option<f64>,
) -> Result<Workload> {
    use asperity_levelset::{Band, ReconstructParams, Sizing, reconstruct};
    let (radius, layers, res) = match (s.quick, res) {
        (true, _) => (8.0, 3.0, 32),
        (false, 128) => (30.0, 11.0, 128),
        _ => (60.0, 26.0, 256),
    };
    let points = rdsr_sphere_cloud(radius, layers, &s.budget)?;
    let params = ReconstructParams {
        sizing: Sizing::Resolution(res),
        band: if full { Band::Full } else { Band::Narrow },
        ..ReconstructParams::default()
    };
    let (n, budget) = (points.len() as u64, s.budget);
    let band = if full {
        ", every node every step (naive)"
    } else {
        ", narrow band"
    };
    Ok(Workload {
        name,
        what: format!("RDSR sphere, {n} points, {res} cells across, 30 ENO2/RK2 steps{band}"),
        elements: n,
        unit: "points",
        target_s: target.and_then(|t| s.target(t)),
        once: res >= 256,
        job: Box::new(move || {
            let r = reconstruct(&points, &params, &budget, &NoProgress, &mut |_, _| {})?;
            let t = r.timings;
            eprintln!(
                "  {name}: grid {:?}, distance {:.3} s, tagging {:.3} s, initial {:.3} s, flow {:.3} s, marching cubes {:.3} s, total {:.3} s",
                r.grid.dims, t.distance, t.tagging, t.initial, t.evolution, t.extraction, t.total
            );
            Ok(())
        }),
    })
}

/// Level-set reconstruction of a plane DLA deposit (#26's workloads): the
/// deposit `asperity growth dla --seed-shape plane --size X×Y×Z --particles
/// N` writes (seed plane included), reconstructed at `res` cells across with
/// the default settings. Most of the box lies near the deposit's branches, so
/// this is the sparse layout's hardest case.
fn levelset_plane(
    s: &Setup,
    name: &'static str,
    (lattice, particles, res): ([usize; 3], usize, usize),
    target: f64,
) -> Result<Workload> {
    use asperity_levelset::{ReconstructParams, Sizing, reconstruct};
    let (lattice, particles, res) = if s.quick {
        ([32, 32, 20], 2_000, 32)
    } else {
        (lattice, particles, res)
    };
    let job = asperity_engine::growth::dla::DlaParams {
        size: Some(asperity_engine::params::LatticeSize::new(&lattice)?),
        particles,
        seed_shape: asperity_engine::growth::dla::SeedShape::Plane,
        ..Default::default()
    };
    let grown = asperity_engine::growth::dla::grow(
        &job,
        Default::default(),
        7,
        &s.budget,
        &asperity_core::TimeBudget::unlimited(),
        &NoProgress,
    )?;
    let points = grown.world_points();
    let params = ReconstructParams {
        sizing: Sizing::Resolution(res),
        ..ReconstructParams::default()
    };
    let (n, budget) = (points.len() as u64, s.budget);
    let [x, y, z] = lattice;
    Ok(Workload {
        name,
        what: format!(
            "plane DLA deposit ({x}×{y}×{z} lattice, {particles} particles released, {n} points), {res} cells across, 30 steps, sparse bricks"
        ),
        elements: n,
        unit: "points",
        target_s: s.target(target),
        once: true,
        job: Box::new(move || {
            let r = reconstruct(&points, &params, &budget, &NoProgress, &mut |_, _| {})?;
            let t = r.timings;
            eprintln!(
                "  {name}: grid {:?}, {} of {} bricks, distance {:.3} s, tagging {:.3} s, initial {:.3} s, flow {:.3} s, marching cubes {:.3} s, total {:.3} s, {} triangles",
                r.grid.dims,
                r.bricks.0,
                r.bricks.1,
                t.distance,
                t.tagging,
                t.initial,
                t.evolution,
                t.extraction,
                t.total,
                r.mesh.n_faces()
            );
            Ok(())
        }),
    })
}

pub(super) fn levelset_plane_256(s: &Setup) -> Result<Workload> {
    // The 8.3 s, measured before the sparse layout.
    levelset_plane(
        s,
        "levelset/plane-dla-256",
        ([256, 256, 160], 300_000, 256),
        8.3,
    )
}

pub(super) fn levelset_plane_512(s: &Setup) -> Result<Workload> {
    levelset_plane(
        s,
        "levelset/plane-dla-512",
        ([256, 256, 160], 300_000, 512),
        15.0,
    )
}

pub(super) fn levelset_plane_1024(s: &Setup) -> Result<Workload> {
    levelset_plane(
        s,
        "levelset/plane-dla-1e6-1024",
        ([512, 512, 320], 1_000_000, 1024),
        90.0,
    )
}

/// The point cloud of RDSR layers grown on a sphere (the level-set workloads' input).
pub(crate) fn rdsr_sphere_cloud(
    radius: f64,
    layers: f64,
    budget: &MemoryBudget,
) -> Result<Vec<[f64; 3]>> {
    use asperity_growth::curved::{CurvedParams, CurvedSubstrate, deposit_curved};
    let growth = CurvedParams {
        model: Model::Rdsr { radius: 1 },
        substrate: CurvedSubstrate::Sphere(radius),
        layers,
        samples_per_decade: 2,
    };
    Ok(deposit_curved(&growth, 7, 0, budget, &NoProgress)?.points())
}

pub(super) fn levelset_128(s: &Setup) -> Result<Workload> {
    levelset(s, "levelset/pipeline-128", 128, false, Some(0.5))
}

pub(super) fn levelset_full_128(s: &Setup) -> Result<Workload> {
    levelset(s, "levelset/full-grid-128", 128, true, None)
}

pub(super) fn levelset_256(s: &Setup) -> Result<Workload> {
    levelset(s, "levelset/pipeline-256-1e6", 256, false, Some(3.0))
}
