//! Cellular automata on any triangle mesh, after Gobron & Chiba, *3D surface
//! cellular automata and their applications* (1999) — [gobron-chiba].
//!
//! **Status: partial** (issue "Cellular automata on any triangle mesh"): the cell
//! structure, the general engine, the surface Voronoi diagram, copper corrosion
//! with its patina colour, Gray–Scott reaction–diffusion, texture-atlas and
//! displaced outputs are done.
//!
//! | Module | What | Paper section |
//! | --- | --- | --- |
//! | [`repair`] | the completeness check (algorithm step 1) and `--repair` | Appendix 2 |
//! | [`atlas`] | the original mesh with the cells as a texture atlas (glTF/OBJ) | "Output for users" |
//! | [`cells`] | per-triangle cell grids, in/out flags, links across edges and vertices | "Triangle Division and Cell Properties", "Data Communication in CA" |
//! | [`engine`] | rule trait, synchronous parallel updates, counter-based randomness, per-step statistics | Appendix 2 |
//! | [`voronoi`](mod@voronoi) | surface Voronoi diagrams by regular probabilistic growth | "3D Surface Voronoi Diagram", Figure 14 |
//! | [`reaction_diffusion`] | Gray–Scott reaction–diffusion: a third application on the same engine | (engine generality) |
//! | [`corrosion`] | copper corrosion: strong cells, seeds, attack/defence, metal and oxide thickness | "Corrosion and Patina Generation", Appendix I |
//!
//! [gobron-chiba]: https://infoscience.epfl.ch/record/162175 "Gobron, Chiba: 3D Surface Cellular Automata and Their Applications. J. Visualization and Computer Animation 10(3):143-158, 1999"

pub mod atlas;
pub mod cells;
pub mod corrosion;
pub mod engine;
pub mod reaction_diffusion;
pub mod repair;
pub mod voronoi;

pub use cells::{CellSize, Cells, InFlag, Pairing, build, build_with};
pub use engine::{CellRng, Rule, RunOptions, RunStats, View, run};
pub use voronoi::{VoronoiRule, voronoi};
