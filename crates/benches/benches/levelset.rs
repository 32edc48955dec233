//! asperity-levelset: the reconstruction stages on an RDSR sphere at 128 cells
//! across (the 128³ workload): closest-point and Godunov distance, tagging,
//! 30 narrow-band flow steps, marching cubes, and the whole pipeline. (The 256³
//! workload from 10⁶ points runs in `asperity bench levelset`.)

use asperity_core::{MemoryBudget, NoProgress};
use asperity_growth::Model;
use asperity_growth::curved::{CurvedParams, CurvedSubstrate, deposit_curved};
use asperity_levelset::evolve::from_tags;
use asperity_levelset::grid::padding_nodes;
use asperity_levelset::{
    DistanceMethod, EvolveParams, GridSpec, ReconstructParams, Sizing, TagRule, evolve, extract,
    reconstruct, tag, unsigned_distance,
};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

fn stages(c: &mut Criterion) {
    let points = deposit_curved(
        &CurvedParams {
            model: Model::Rdsr { radius: 1 },
            substrate: CurvedSubstrate::Sphere(30.0),
            layers: 11.0,
            samples_per_decade: 2,
        },
        7,
        0,
        &MemoryBudget::unlimited(),
        &NoProgress,
    )
    .expect("deposit")
    .points();
    let budget = MemoryBudget::unlimited();
    let grid = GridSpec::around(
        &points,
        Sizing::Resolution(128),
        |h| padding_nodes(3.0 * h, 3.0 * h, h),
        &budget,
    )
    .expect("grid");
    let h = grid.spacing;
    let (eps, gamma) = (3.0 * h, 3.0 * h);
    let cap = eps + gamma + 2.0 * h;
    let mut g = c.benchmark_group("levelset/rdsr_sphere_128");
    g.sample_size(10);
    g.throughput(Throughput::Elements(grid.len() as u64));
    g.bench_function("distance closest point", |b| {
        b.iter(|| {
            unsigned_distance(
                &points,
                &grid,
                DistanceMethod::ClosestPoint,
                cap,
                &NoProgress,
            )
        })
    });
    g.bench_function("distance godunov", |b| {
        b.iter(|| unsigned_distance(&points, &grid, DistanceMethod::GODUNOV, cap, &NoProgress))
    });
    let dist = unsigned_distance(
        &points,
        &grid,
        DistanceMethod::ClosestPoint,
        cap,
        &NoProgress,
    );
    g.bench_function("tagging", |b| {
        b.iter(|| tag(&dist, eps, TagRule::Paper, &NoProgress))
    });
    let tags = tag(&dist, eps, TagRule::Paper, &NoProgress);
    let initial = from_tags(&dist, &tags, eps, gamma, &NoProgress);
    g.bench_function("30 flow steps", |b| {
        b.iter(|| {
            let mut ls = initial.clone();
            evolve(
                &mut ls,
                &dist,
                &EvolveParams::paper(h),
                &NoProgress,
                &mut |_, _| {},
            )
        })
    });
    g.bench_function("marching cubes", |b| {
        b.iter(|| extract(&initial.phi, &grid, &Default::default()))
    });
    g.bench_function("whole pipeline", |b| {
        let params = ReconstructParams {
            sizing: Sizing::Resolution(128),
            ..Default::default()
        };
        b.iter(|| reconstruct(&points, &params, &budget, &NoProgress, &mut |_, _| {}).expect("run"))
    });
    g.finish();
}

criterion_group!(benches, stages);
criterion_main!(benches);
