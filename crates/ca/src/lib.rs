//! Cellular-automaton height fields with alternating-diagonal facets, from [peridier].
//!
//! | Module | What | Paper |
//! | --- | --- | --- |
//! | [`rule`] | Wolfram codes: totalistic 9/5-neighbour (k colours), outer-totalistic 9/5, B/S strings | Figure 2, enumeration after it |
//! | [`evolve`] | cyclic and infinite-background evolution; byte and bit-sliced paths | "Cellular Automaton Basics", Figure 3 |
//! | [`mod@accumulate`] | sum of the steps into a height field, weights, initial grids | Figures 1, 3, 4 |
//! | [`facets`] | alternating-diagonal facets and the consistent triangulated interpolation | Figures 7, 8, 9 |
//!
//! [peridier]: https://www.mathematica-journal.com/2011/07/facetsurface-representation/ "Peridier: Rough-Surface Simulation and the Visualization of Nonsmooth Arrays of Data. The Mathematica Journal, 2011"

pub mod accumulate;
pub mod evolve;
pub mod facets;
pub mod rule;

pub use accumulate::{
    CaOutput, CaParams, Init, Weights, accumulate, evolve_and_accumulate, initial_grid,
};
pub use evolve::Boundary;
pub use rule::{Family, Rule};

use asperity_core::CoreError;

/// Why a CA run was refused.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CaError {
    /// A rule number or string out of range for its family.
    #[error("invalid rule: {0}")]
    BadRule(String),
    /// Initial conditions or run parameters that cannot be used.
    #[error("{0}")]
    BadInit(String),
    /// Sizes, memory limit, invalid geometry.
    #[error(transparent)]
    Core(#[from] CoreError),
}
