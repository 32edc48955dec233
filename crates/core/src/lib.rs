//! Shared geometry types and conventions for asperity.
//!
//! Every other asperity crate builds on these types; none invents its own.
//!
//! | Module | What | Used by |
//! | --- | --- | --- |
//! | [`grid2`] | [`Grid2`] / [`HeightField`]: regular 2-D grids with spacing and origin | growth (RD/RDSR heights), 2-D CA, analysis, io |
//! | [`grid3`] | [`Grid3`] / [`ScalarGrid`] / [`VoxelGrid`]: dense 3-D grids | DLA occupancy, distance fields, level sets |
//! | [`point_set`] | [`PointSet`]: positions plus optional colours and named attributes | growth output, reconstruction input |
//! | [`tri_mesh`] | [`TriMesh`]: indexed triangles with normals, colours, scalars, UVs, texture | every mesh producer and writer |
//! | [`poly_mesh`] | [`PolyMesh`]: polygonal faces (quads first), CSR layout | subdivision input |
//! | [`image`] | [`RgbaImage`]: 8-bit RGBA raster (mesh textures, renders) | render, io |
//! | [`rng`] | [`SimRng`], [`seeded`], [`substream`]: reproducible randomness | every stochastic method |
//! | [`memory`] | [`MemoryBudget`]: estimate-then-refuse for large allocations | every grid allocation |
//! | [`progress`] | [`Progress`]: progress reporting without a UI dependency | long-running methods |
//! | [`error`] | [`CoreError`]: typed errors with numbers in their messages | everything |
//! | [`shapes`] | built-in meshes (icosphere) | demo, tests |
//! | [`voxelize`] | Solid voxelisation of a closed mesh | growth substrates |
//! | [`fourier_surface`] | Reference self-affine surface with a known spectrum | demo, analysis tests, benchmarks |
//!
//! # Global conventions
//! - **Axes**: right-handed, **z up**. Height fields store z over the (x, y) plane.
//! - **Faces**: counter-clockwise seen from the front (outside); normals point outward.
//! - **Level sets**: φ < 0 is *inside*, φ > 0 outside, the surface is φ = 0.
//! - **Grids**: x varies fastest. [`Grid2`] value (i, j) is `data[i + nx * j]` at
//!   `origin + (i·dx, j·dy)`; [`Grid3`] value (i, j, k) is `data[i + nx * (j + ny * k)]`.
//!   File formats store grid row j as the j-th row of the file (as numpy's `(ny, nx)`
//!   C-order array, and as Gwyddion does, so image viewers show +y pointing down).
//! - **Precision**: public geometry is `f64`; big grids may store narrower types
//!   (`Grid3<f32>`, `Grid3<bool>`), which their users document.
//! - **Randomness**: a `u64` seed everywhere, never the OS; see [`rng`] for how
//!   parallel code derives sub-streams so output does not depend on thread count.
//!
//! The five papers asperity implements are cited by the author part of their file
//! names in `../shared/papers/`: kim-machiraju-thompson, peridier, velho-perlin,
//! poull-gentil and gobron-chiba.

pub mod aabb;
pub mod error;
pub mod fourier_surface;
pub mod grid2;
pub mod grid3;
pub mod image;
pub mod memory;
pub mod point_set;
pub mod poly_mesh;
pub mod progress;
pub mod rng;
pub mod shapes;
pub mod tri_mesh;
pub mod vec3;
pub mod voxelize;

#[cfg(feature = "proptest")]
pub mod strategies;

pub use aabb::Aabb;
pub use error::CoreError;
pub use grid2::{Diagonal, Grid2, HeightField};
pub use grid3::{Grid3, ScalarGrid, VoxelGrid};
pub use image::RgbaImage;
pub use memory::MemoryBudget;
pub use point_set::PointSet;
pub use poly_mesh::PolyMesh;
pub use progress::{NoProgress, Progress};
pub use rng::{SimRng, seeded, substream};
pub use tri_mesh::{Attribute, TriMesh};

/// Result alias for the core crate.
pub type Result<T, E = CoreError> = std::result::Result<T, E>;
