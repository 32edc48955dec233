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
//! | [`memory_hints`] | software prefetch (no change to values) | level set, DLA |
//! | [`progress`] | [`Progress`]: progress reporting without a UI dependency | long-running methods |
//! | [`error`] | [`CoreError`]: typed errors with numbers in their messages | everything |
//! | [`wording`] | parameters named in messages, spelled by each front end (`--max-memory`, `max_memory=`) | every error that names a parameter |
//! | [`shapes`] | built-in meshes (icosphere) | demo, tests |
//! | [`voxelize`] | Solid voxelisation of a closed mesh | growth substrates |
//! | [`jet`] | [`jet::Jet`]: the osculating quadric of points about an origin (height, H, K) | reconstruction (denoising, projection), curvature at a scale |
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
//! The five papers asperity implements are cited in module docs by a short key:
//!
//! - **kim-machiraju-thompson** — Y. Kim, R. Machiraju, D. Thompson, "Modeling Rough
//!   Surfaces", in G. Brunnett, B. Hamann, H. Müller, L. Linsen (eds.), *Geometric
//!   Modeling for Scientific Visualization*, Springer 2004, pp. 123–138,
//!   <https://doi.org/10.1007/978-3-662-07443-5>.
//! - **peridier** — V. J. Peridier, "Rough-Surface Simulation and the Visualization of
//!   Nonsmooth Arrays of Data", *The Mathematica Journal*, 2011,
//!   <https://www.mathematica-journal.com/2011/07/facetsurface-representation/>.
//! - **velho-perlin** — L. Velho, K. Perlin, L. Ying, H. Biermann, "Procedural Shape
//!   Synthesis on Subdivision Surfaces", SIBGRAPI 2001, <https://lvelho.impa.br/spd/>.
//! - **poull-gentil** — C. Poull, C. Gentil, C. Roudet, L. Druoton, M. Roy,
//!   "Differential properties of rough fractal surfaces", JFIG 2024, Strasbourg,
//!   <https://hal.science/hal-04790610>.
//! - **gobron-chiba** — S. Gobron, N. Chiba, "3D Surface Cellular Automata and Their
//!   Applications", *The Journal of Visualization and Computer Animation* 10(3):143–158,
//!   1999, <https://infoscience.epfl.ch/record/162175>.

pub mod aabb;
pub mod error;
pub mod fourier_surface;
pub mod grid2;
pub mod grid3;
pub mod image;
pub mod jet;
pub mod memory;
pub mod memory_hints;
pub mod mesh_check;
pub mod point_set;
pub mod poly_mesh;
pub mod polygon;
pub mod progress;
pub mod rng;
pub mod shapes;
pub mod system_memory;
pub mod time_budget;
pub mod tri_mesh;
pub mod units;
pub mod vec3;
pub mod voxelize;
pub mod wording;

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
pub use time_budget::{TimeBudget, Work};
pub use tri_mesh::{Attribute, Topology, TriMesh};
pub use units::{LengthUnit, Units};

/// Result alias for the core crate.
pub type Result<T, E = CoreError> = std::result::Result<T, E>;
