//! asperity-subdiv (velho-perlin): 4 levels of multiresolution synthesis of a
//! 10 086-quad closed mesh (a subdivided cube, 2.58 M output quads), plain and
//! with rock detail — issue #8's workload (target ≤ 0.7 s on 2 cores).

use asperity_subdiv::catmull_clark::{Boundary, Creased};
use asperity_subdiv::compose::{Layer, grow};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

/// As in the `asperity` binary.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn synthesis(c: &mut Criterion) {
    let base = Creased::smooth(asperity_core::shapes::cube_quads(41));
    let mut g = c.benchmark_group("subdiv");
    g.sample_size(10);
    g.throughput(Throughput::Elements((base.mesh.n_faces() as u64) << 8));
    let plain = Layer {
        features: Vec::new(),
        ..Layer::rock()
    };
    for (name, layer) in [
        ("plain-10086-quads-4-levels", plain),
        ("rock-10086-quads-4-levels", Layer::rock()),
    ] {
        g.bench_function(name, |b| {
            b.iter(|| grow(&base, 4, Boundary::EdgeOnly, &layer, 1).expect("grow"))
        });
    }
    g.finish();
}

criterion_group!(benches, synthesis);
criterion_main!(benches);
