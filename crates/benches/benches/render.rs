//! asperity-render: the workload, a 2-million-triangle surface at
//! 1920×1080 with shadows and 4× supersampling, plus smaller sizes.

use asperity_benches::surface_mesh;
use asperity_render::{RenderOptions, render_mesh};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};

fn render(c: &mut Criterion) {
    let mut g = c.benchmark_group("render/mesh_1920x1080_ss2_shadows_ao");
    g.sample_size(10);
    // n×n samples give 2(n−1)² triangles: 1001 → 2.0 M.
    for n in [257, 1001] {
        let m = surface_mesh(n);
        let opts = RenderOptions {
            width: 1920,
            height: 1080,
            supersample: 2,
            shadows: true,
            ..RenderOptions::default()
        };
        g.throughput(Throughput::Elements(m.n_faces() as u64));
        g.bench_with_input(BenchmarkId::new("triangles", m.n_faces()), &m, |b, m| {
            b.iter(|| render_mesh(m, &opts).expect("render"))
        });
    }
    g.finish();
}

criterion_group!(benches, render);
criterion_main!(benches);
