//! Multiresolution subdivision surfaces with procedural detail from [velho-perlin].
//!
//! A base polygon mesh (`asperity_core::PolyMesh`, any manifold polygons) is
//! refined by Catmull–Clark subdivision; every level adds detail offsets in
//! local frames, from procedures evaluated on the surface the level grows from.
//! Features can be placed at chosen vertices and levels, edited locally, and two
//! surfaces blended level by level; in scalar mode the same machinery builds a
//! field that a post-shader turns into colours (the planet). Scenes (TOML)
//! describe compositions for `asperity subdiv`.
//!
//! | Module | What | Paper section |
//! | --- | --- | --- |
//! | [`base`] | built-in bases: cube, quad sphere, torus, cylinder, plane patch, revolution, fuse | §6.1 |
//! | [`catmull_clark`] | subdivision with boundaries, creases, limit positions and normals | §2 |
//! | [`multires`] | levels with detail offsets in local frames; synthesis and analysis | §2, Fig. 1 |
//! | [`detail`] | procedures: rock, fbm, berry, tentacle, mine, mushroom, spur; amplitude laws | §3–4 |
//! | [`topology`] | a level's connectivity: edges, twins, vertex corners, creases | §2 |
//! | [`detail_file`] | exported details, re-applied to an edited base | §2 |
//! | [`compose`] | layers, placement at chosen vertices, local edits | §5 |
//! | [`blend`] | multiscale blending of two surfaces | §6 |
//! | [`scalar`] | scalar mode and the planet post-shader | §6.2 |
//! | [`evaluate`] | a scene's layers, blends and captured surfaces, evaluated | §2–6 |
//! | [`scene`] | TOML scene files with animated parameters | §3, Fig. 2 |
//!
//! [velho-perlin]: https://lvelho.impa.br/spd/ "Velho, Perlin, Ying, Biermann: Procedural Shape Synthesis on Subdivision Surfaces. SIBGRAPI 2001"

pub mod base;
pub mod blend;
pub mod catmull_clark;
pub mod compose;
pub mod detail;
pub mod detail_file;
pub mod evaluate;
pub mod examples;
pub mod multires;
pub mod scalar;
pub mod scene;
pub mod topology;
