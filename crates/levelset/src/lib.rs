//! Level-set reconstruction of rough surfaces from point sets, after
//! [kim-machiraju-thompson] §5: the second pass of the paper's pipeline (Fig. 2),
//! which turns the particles of a growth simulation (or any point cloud) into a
//! watertight surface of any genus — arches and overhangs included — without the
//! smoothing of a curvature flow.
//!
//! | Module | Algorithm | Paper |
//! | --- | --- | --- |
//! | [`cloud`] | What a cloud is (a sampled surface or a deposit), its spacing, outliers and noise | §5–6, Fig. 7 |
//! | [`grid`] | Padded cubic grid around the points, memory estimate | §5.2 |
//! | [`distance`] | Unsigned distance: Godunov fast sweeping (8 orderings, hyperplane-parallel) or a closest-point wavefront | §5.2, Eqs. 7–9 |
//! | [`tagging`] | Initial offset surface {d = ε} by region growing from the box | §5.2, Algorithm 1 |
//! | [`evolve`](mod@evolve) | Narrow-band convection flow φ_t = d\|∇φ\|, ENO2 + TVD-RK2, cut-off, redistancing, clamping | §5.1–5.2, Eqs. 6, 10–12 |
//! | [`marching_cubes`] | Watertight, manifold marching cubes with normals (Eq. 1) and mean curvature (Eq. 2) | §6, ref. \[13\] |
//! | [`pipeline`] | The whole reconstruction, timed per stage | Fig. 5 |
//! | `sampled` | What the pipeline adds for a sampled surface: the cloud, the voids, the mesh's projection | Fig. 7, #52 |
//! | [`sparse`] | Every stage on 8³-node bricks near the data and the front: what `reconstruct` runs | §5.2, §6 |
//!
//! The dense driver — `evolve::evolve`, `evolve::from_tags`, `tagging::tag` and
//! the fused sweep over every node — is the reference the sparse path is
//! checked against, node for node; it is compiled only with the `reference`
//! feature (the crate's tests and the benchmarks turn it on). The step plan
//! (`evolve::plan`) and the lane kernels are shared and always built.
//!
//! ```
//! use asperity_core::{MemoryBudget, NoProgress};
//! use asperity_levelset::{ReconstructParams, Sizing, reconstruct};
//!
//! // Points on a sphere of radius 1.
//! let mut points = Vec::new();
//! for a in 0..40 {
//!     for b in 0..80 {
//!         let (t, p) = (std::f64::consts::PI * (a as f64 + 0.5) / 40.0, std::f64::consts::PI * b as f64 / 40.0);
//!         points.push([t.sin() * p.cos(), t.sin() * p.sin(), t.cos()]);
//!     }
//! }
//! let params = ReconstructParams { sizing: Sizing::Resolution(32), ..Default::default() };
//! let r = reconstruct(&points, &params, &MemoryBudget::unlimited(), &NoProgress, &mut |_, _| {}).unwrap();
//! assert!(r.mesh.is_watertight());
//! assert_eq!(r.mesh.euler_characteristic(), 2);
//! ```
//!
//! [kim-machiraju-thompson]: https://doi.org/10.1007/978-3-662-07443-5 "Kim, Machiraju, Thompson: Modeling Rough Surfaces. In Geometric Modeling for Scientific Visualization, Springer 2004, pp. 123-138"

pub mod cloud;
mod curvature;
pub mod distance;
pub mod evolve;
#[cfg(feature = "fault-injection")]
pub mod faults;
pub mod grid;
mod lanes;
pub mod marching_cubes;
pub mod orient;
pub mod pipeline;
#[cfg(feature = "reference")]
pub mod reference;
mod sampled;
pub mod sparse;
pub mod tagging;
#[cfg(feature = "reference")]
mod tube;

pub use distance::{DistanceField, DistanceMethod, unsigned_distance};
/// The dense driver (every node of the grid): the reference the sparse path is
/// checked against, for tests and benchmarks.
#[cfg(feature = "reference")]
pub use evolve::evolve;
pub use evolve::{
    Band, EvolveParams, EvolveStats, Flow, LevelSet, Neighbourhood, Scheme, StepStats,
};
pub use grid::{GridSpec, Sizing};
pub use marching_cubes::{ExtractOptions, ExtractStats, extract};
pub use pipeline::{
    FlowChoice, Length, ReconstructParams, Reconstruction, Timings, default_arrest_spacings,
    reconstruct, reconstruct_cloud,
};
pub use sampled::{CloudChoice, CloudFacts, VoidFacts, project_onto, widest_random_gap};
pub use sparse::SparseLevelSet;
pub use tagging::TagRule;
#[cfg(feature = "reference")]
pub use tagging::{Tags, tag};
