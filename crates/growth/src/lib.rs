//! Discrete surface-growth simulators from [kim-machiraju-thompson] §4: the
//! physically derived point sets from which rough surfaces are reconstructed.
//!
//! | Module | Algorithm | Paper section |
//! | --- | --- | --- |
//! | [`random_deposition`] | Random deposition (RD) | §4.1, Fig. 3(a) |
//! | [`rdsr`] | RD with surface relaxation (Family model) | §4.1, Fig. 3(b) |
//! | [`ballistic`] | Ballistic deposition (KPZ class) | §2 refs. \[17\], \[22\]; §4.1 |
//! | [`deposition`] | The flat periodic lattice driver, ensembles of runs | §4.1 |
//! | [`curved`] | RD/RDSR/BD on a sphere or a voxelised closed mesh | §6 Fig. 8, §7 |
//! | [`dla`] | Diffusion-limited aggregation with big jumps | §4.2, Fig. 4; §6 Figs. 9–11 |
//! | [`lattice`] | The periodic substrate and the model rule trait | §4.1 |
//! | [`occupancy`] | Bit-packed voxel occupancy and its coarse distance map | — |
//! | [`seeds`] | DLA seeds and curved substrates from images and meshes | §7 |
//! | [`interface_width`] | W(L, t), schedules, max-height binning | §4.1 |
//!
//! Every simulation takes a `u64` seed and a run number and is sequential inside
//! a run; ensembles run in parallel, one run per task, so results do not depend
//! on the thread count (see [`rng`]).
//!
//! [kim-machiraju-thompson]: https://doi.org/10.1007/978-3-662-07443-5 "Kim, Machiraju, Thompson: Modeling Rough Surfaces. In Geometric Modeling for Scientific Visualization, Springer 2004, pp. 123-138"

pub mod ballistic;
pub mod curved;
pub mod deposition;
pub mod dla;
pub mod error;
pub mod interface_width;
pub mod lattice;
pub mod occupancy;
pub mod random_deposition;
pub mod rdsr;
pub mod rng;
pub mod seeds;

pub use deposition::{Deposit, DepositionParams, Model, deposit, deposit_ensemble};
pub use error::GrowthError;
pub use interface_width::WidthSeries;
pub use lattice::Lattice;
