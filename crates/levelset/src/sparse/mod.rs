//! The reconstruction of §5.2 on a sparse brick layout, so that memory and time
//! follow the surface rather than the box.
//!
//! Every stage of the pipeline needs values only near the data: the distance
//! is capped (beyond the cap every node reads as the cap), the offset surface
//! {d = ε} and the flow's tubes lie within the cap, and marching cubes only
//! meets φ = 0 inside the tubes. So the grid is cut into 8³-node bricks
//! ([`layout`]) and storage exists only for the bricks that a stage touches —
//! as OpenVDB stores leaf nodes only near the level set, with tile values
//! elsewhere. A brick without storage reads as its field's background: the
//! cap for d, and ±γ by the brick's exterior tag for φ.
//!
//! Each stage computes exactly what the dense stage computes, node for node
//! (the tests compare them bit for bit), in an order that does not depend on
//! the thread count.
//!
//! | Module | Stage |
//! | --- | --- |
//! | [`layout`] | Bricks, slots, node ids |
//! | [`distance`] | Closest-point distance on the bricks near the points |
//! | [`tagging`] | Algorithm 1: brick flood fills and the paper rule's descent |
//! | [`surface`] | The initial level set: signed distance to the tagged front |
//! | [`flow`] | The narrow-band convection flow, redistancing and clamping |
//! | [`extract`] | Marching cubes on the bricks that hold the front |
//! | [`voids`] | The inside of a sampled surface, behind its gaps: the merge tree of d |

pub mod distance;
pub mod extract;
pub mod flow;
pub mod layout;
pub mod surface;
pub mod tagging;
pub mod voids;

pub use distance::{SparseDistance, sparse_distance};
pub use extract::sparse_extract;
pub use flow::sparse_evolve;
pub use layout::Bricks;
pub use surface::{SparseLevelSet, sparse_initial};
pub use tagging::{SparseTags, sparse_tag};
pub use voids::{Voids, freeze, label_voids};
