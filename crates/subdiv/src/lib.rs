//! Multiresolution subdivision surfaces with procedural detail from [velho-perlin].
//!
//! **Status: planned** (issue "Multiresolution Catmull-Clark surfaces"). Input meshes
//! are `asperity_core::PolyMesh`.
//!
//! | Module (planned) | What | Paper section |
//! | --- | --- | --- |
//! | `catmull_clark` | Subdivision with creases and limit positions | §2 |
//! | `multires` | Levels with detail offsets in local frames | §2 |
//! | `detail` | Rock, berry, tentacle, mushroom detail functions | §3–4 |
//! | `placement`, `blend` | Local placement, multiscale blending | §5–6 |
//!
//! [velho-perlin]: ../shared/papers/velho-perlin_procedural-shape-synthesis-subdivision.txt
