//! Cellular automata on triangle meshes from [gobron-chiba].
//!
//! **Status: planned** (issue "Cellular automata on any triangle mesh"). Meshes are
//! `asperity_core::TriMesh`.
//!
//! | Module (planned) | What | Paper section |
//! | --- | --- | --- |
//! | `cells` | Per-triangle cell grids and edge pairing | "3D Surface Cellular Automata" |
//! | `voronoi` | Surface Voronoi diagrams | "Voronoi" |
//! | `corrosion` | Copper corrosion and patina | "Corrosion" |
//! | `light` | Two-layer light model | "Simple Light Model" |
//!
//! [gobron-chiba]: ../shared/papers/gobron-chiba_3d-surface-cellular-automata.txt
