//! Shared inputs for the criterion benchmarks in `benches/` (one file per crate).
//!
//! Run `cargo bench -p asperity-benches`; CI runs each benchmark once with
//! `cargo test -p asperity-benches --benches`. Record results in `BENCHMARKS.md`.

use asperity_core::fourier_surface::{FourierParams, fourier_surface};
use asperity_core::{Diagonal, HeightField, MemoryBudget, TriMesh};

/// The seeded reference surface of `n × n` samples used by every benchmark.
pub fn surface(n: usize) -> HeightField {
    let p = FourierParams {
        n,
        hurst: 0.8,
        modes: (n / 8).max(1),
        rms: 0.05,
        spacing: 1.0 / n as f64,
    };
    fourier_surface(&p, 7, &MemoryBudget::unlimited()).expect("valid benchmark parameters")
}

/// The reference surface triangulated with alternating diagonals, with normals
/// and a scalar, so writers do their full work.
pub fn surface_mesh(n: usize) -> TriMesh {
    let h = surface(n);
    h.to_trimesh(Diagonal::Alternating)
        .and_then(|m| {
            m.with_computed_normals()
                .with_scalar("height", h.data().to_vec())
        })
        .expect("valid mesh")
}
