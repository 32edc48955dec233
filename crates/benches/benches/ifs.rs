//! asperity-ifs (poull-gentil): a depth-10 tensor-product attractor (≈ 1M vertices)
//! built, and built + written as binary PLY; per-vertex pseudo-curvature at depth 8;
//! the pseudo-curvature ranges of every operator of a preset.

use asperity_core::MemoryBudget;
use asperity_ifs::curvature::{surface_report, vertex_curvature};
use asperity_ifs::{DirectionAnalysis, FamilyOptions, Model, PresetParams, SurfaceIfs, preset};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

fn surface(name: &str) -> SurfaceIfs {
    match preset(name, &PresetParams::default())
        .expect("preset")
        .build()
        .expect("valid")
    {
        Model::Surface(s) => s,
        Model::Curve(_) => panic!("{name} is a curve"),
    }
}

fn attractor(c: &mut Criterion) {
    let s = surface("takagi-landsberg-surface");
    let budget = MemoryBudget::unlimited();
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("a.ply");
    let mut g = c.benchmark_group("ifs");
    g.sample_size(10);
    g.throughput(Throughput::Elements(1025 * 1025));
    g.bench_function("attractor-depth10", |b| {
        b.iter(|| s.attractor_mesh(10, &budget).expect("mesh"))
    });
    g.bench_function("attractor-depth10-write-ply", |b| {
        b.iter(|| {
            let m = s.attractor_mesh(10, &budget).expect("mesh");
            asperity_io::write_mesh(&path, &m, &asperity_io::WriteOptions::default())
                .expect("write")
        })
    });
    let opts = FamilyOptions::default();
    let (a, t) = (
        DirectionAnalysis::new(&s.s, &opts),
        DirectionAnalysis::new(&s.t, &opts),
    );
    g.throughput(Throughput::Elements(257 * 257));
    g.bench_function("vertex-curvature-depth8", |b| {
        b.iter(|| vertex_curvature(&s, &a, &t, 8).expect("finite"))
    });
    g.throughput(Throughput::Elements(4));
    g.bench_function("curvature-ranges-takagi-surface", |b| {
        b.iter(|| {
            let a = DirectionAnalysis::new(&s.s, &opts);
            let t = DirectionAnalysis::new(&s.t, &opts);
            surface_report(&s, &a, &t)
        })
    });
    g.finish();
}

criterion_group!(benches, attractor);
criterion_main!(benches);
