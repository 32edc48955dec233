//! Multiresolution subdivision surfaces with procedural detail from [velho-perlin].
//!
//! **Status: started** (issue "Multiresolution Catmull-Clark surfaces"): Catmull–Clark
//! subdivision with boundaries, creases and limit positions, and the
//! multiresolution levels with synthesis and analysis, are done; the procedural
//! details and the rest are planned. Input meshes are `asperity_core::PolyMesh`.
//!
//! | Module | What | Paper section |
//! | --- | --- | --- |
//! | [`base`] | built-in base meshes: cube, quad sphere, torus | §6 examples |
//! | [`catmull_clark`] | subdivision with boundaries, creases and limit positions (done) | §2 |
//! | [`multires`] | levels with detail offsets in local frames, synthesis and analysis (done) | §2 |
//! | [`detail`] | procedural detail: rock (done); berry, tentacle, mushroom (planned) | §3–4 |
//! | `placement`, `blend` | Local placement, multiscale blending | §5–6 |
//!
//! [velho-perlin]: ../shared/papers/velho-perlin_procedural-shape-synthesis-subdivision.txt

pub mod base;
pub mod catmull_clark;
pub mod compose;
pub mod detail;
pub mod multires;
pub mod scene;
