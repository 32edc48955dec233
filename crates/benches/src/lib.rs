//! Shared inputs for the criterion benchmarks in `benches/` (one file per crate).
//!
//! Run `cargo bench -p asperity-benches`; CI runs each benchmark once with
//! `cargo test -p asperity-benches --benches`. Record results in `BENCHMARKS.md`.
//! The same workloads run from the binary with `asperity bench`: the harness
//! ([`workloads`], and [`scaling`] for `--scaling`) lives here, beside the
//! criterion benchmarks, and the CLI calls it.

pub mod scaling;
pub mod workloads;

use asperity_core::fourier_surface::{benchmark_mesh, benchmark_surface};
use asperity_core::{HeightField, MemoryBudget, TriMesh};

/// The seeded reference surface of `n × n` samples used by every benchmark.
pub fn surface(n: usize) -> HeightField {
    benchmark_surface(n, &MemoryBudget::unlimited()).expect("valid benchmark parameters")
}

/// The reference surface triangulated with alternating diagonals, with normals
/// and a scalar, so writers do their full work.
pub fn surface_mesh(n: usize) -> TriMesh {
    let h = surface(n);
    benchmark_mesh(n, &MemoryBudget::unlimited())
        .and_then(|m| m.with_scalar("height", h.measured_values()))
        .expect("valid mesh")
}
