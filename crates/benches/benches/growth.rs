//! asperity-growth: the workloads. RD/RDSR/BD depositions per second on
//! a 256² substrate (one run), and 3-D lattice DLA of 10⁵ particles from a point
//! and from a plane. (10⁶-particle DLA is measured by `asperity bench growth/dla`,
//! too long for criterion's repetitions.)

use asperity_core::{MemoryBudget, NoProgress};
use asperity_growth::dla::{DlaParams, SeedShape, dla};
use asperity_growth::{DepositionParams, Lattice, Model, deposit};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};

fn deposition(c: &mut Criterion) {
    let mut g = c.benchmark_group("growth/deposition_256x256_100_layers");
    g.sample_size(10);
    for (model, name) in [
        (Model::Rd, "rd"),
        (Model::Rdsr { radius: 1 }, "rdsr"),
        (Model::Bd, "bd"),
    ] {
        let p = DepositionParams::new(model, Lattice::new(256, 2).expect("lattice"), 100.0);
        g.throughput(Throughput::Elements(p.depositions()));
        g.bench_function(BenchmarkId::new(name, "one run"), |b| {
            b.iter(|| deposit(&p, 7, 0, &MemoryBudget::unlimited(), &NoProgress).expect("run"))
        });
    }
    g.finish();
}

fn diffusion_limited(c: &mut Criterion) {
    let mut g = c.benchmark_group("growth/dla_1e5_particles");
    g.sample_size(10);
    g.throughput(Throughput::Elements(100_000));
    let point = DlaParams::point(3, 100_000);
    let mut plane = DlaParams::point(3, 100_000);
    plane.seed_shape = SeedShape::Plane;
    plane.size = [256, 256, 256];
    for (p, name) in [(point, "point"), (plane, "plane")] {
        g.bench_function(BenchmarkId::new(name, "p = 1"), |b| {
            b.iter(|| dla(&p, 7, 0, &MemoryBudget::unlimited(), &NoProgress).expect("run"))
        });
    }
    g.finish();
}

criterion_group!(benches, deposition, diffusion_limited);
criterion_main!(benches);
