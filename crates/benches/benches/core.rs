//! asperity-core: topology queries and the reference surface generator.

use asperity_benches::{surface, surface_mesh};
use asperity_core::fourier_surface::{FourierParams, fourier_surface};
use asperity_core::{Diagonal, MemoryBudget};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};

fn topology(c: &mut Criterion) {
    let mut g = c.benchmark_group("core/topology");
    g.sample_size(10);
    for n in [129, 513] {
        let m = surface_mesh(n);
        g.throughput(Throughput::Elements(m.n_faces() as u64));
        g.bench_with_input(BenchmarkId::new("edges", n), &m, |b, m| {
            b.iter(|| m.edges().len())
        });
        g.bench_with_input(BenchmarkId::new("is_watertight", n), &m, |b, m| {
            b.iter(|| m.is_watertight())
        });
        g.bench_with_input(BenchmarkId::new("boundary_loops", n), &m, |b, m| {
            b.iter(|| m.boundary_loops().len())
        });
    }
    g.finish();
}

fn generate(c: &mut Criterion) {
    let mut g = c.benchmark_group("core/generate");
    g.sample_size(10);
    for n in [257, 1025] {
        let p = FourierParams {
            n,
            hurst: 0.8,
            modes: n / 8,
            rms: 0.05,
            spacing: 1.0 / n as f64,
        };
        g.throughput(Throughput::Elements((n * n) as u64));
        g.bench_with_input(BenchmarkId::new("fourier_surface", n), &p, |b, p| {
            b.iter(|| fourier_surface(p, 7, &MemoryBudget::unlimited()).expect("valid"))
        });
        let h = surface(n);
        g.bench_with_input(BenchmarkId::new("to_trimesh_alternating", n), &h, |b, h| {
            b.iter(|| h.to_trimesh(Diagonal::Alternating).expect("valid"))
        });
    }
    g.finish();
}

criterion_group!(benches, topology, generate);
criterion_main!(benches);
