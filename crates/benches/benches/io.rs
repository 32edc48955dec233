//! asperity-io writers and readers on the reference surface mesh (throughput in
//! triangles or samples; files go to a temp dir, including the atomic rename and
//! fsync a real write pays).

use asperity_benches::{surface, surface_mesh};
use asperity_io::{PlyEncoding, WriteOptions};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};

fn mesh_writers(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut g = c.benchmark_group("io/write_mesh");
    g.sample_size(10);
    let m = surface_mesh(257);
    g.throughput(Throughput::Elements(m.n_faces() as u64));
    for ext in ["ply", "stl", "glb", "obj"] {
        let path = dir.path().join(format!("m.{ext}"));
        g.bench_with_input(BenchmarkId::new(ext, 257), &m, |b, m| {
            b.iter(|| asperity_io::write_mesh(&path, m, &WriteOptions::default()).expect("write"))
        });
    }
    let ascii = WriteOptions {
        ply_encoding: PlyEncoding::Ascii,
        ..Default::default()
    };
    let path = dir.path().join("a.ply");
    g.bench_with_input(BenchmarkId::new("ply_ascii", 257), &m, |b, m| {
        b.iter(|| asperity_io::write_mesh(&path, m, &ascii).expect("write"))
    });
    g.finish();

    let mut g = c.benchmark_group("io/read_mesh");
    g.sample_size(10);
    g.throughput(Throughput::Elements(m.n_faces() as u64));
    for ext in ["ply", "stl", "obj"] {
        let path = dir.path().join(format!("r.{ext}"));
        asperity_io::write_mesh(&path, &m, &WriteOptions::default()).expect("write");
        g.bench_function(BenchmarkId::new(ext, 257), |b| {
            b.iter(|| asperity_io::read_mesh(&path).expect("read"))
        });
    }
    g.finish();
}

fn height_writers(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("temp dir");
    let h = surface(512);
    let mut g = c.benchmark_group("io/write_height");
    g.sample_size(10);
    g.throughput(Throughput::Elements(h.len() as u64));
    for ext in ["npy", "png", "exr", "gsf", "csv"] {
        let path = dir.path().join(format!("h.{ext}"));
        g.bench_with_input(BenchmarkId::new(ext, 512), &h, |b, h| {
            b.iter(|| asperity_io::write_height(&path, h, &WriteOptions::default()).expect("write"))
        });
    }
    g.finish();
}

criterion_group!(benches, mesh_writers, height_writers);
criterion_main!(benches);
