//! Projected IFS fractal surfaces from [poull-gentil].
//!
//! **Status: planned** (issue "Fractal surfaces from projected IFS").
//!
//! | Module (planned) | What | Paper section |
//! | --- | --- | --- |
//! | `ifs`, `pifs` | IFS and projected IFS attractors | §2.1–2.2 |
//! | `tensor` | Tensor-product surfaces, Takagi | §3 |
//! | `dcf`, `sdcf`, `pseudo_curvature` | Differential characteristic functions | §4 |
//!
//! [poull-gentil]: ../shared/papers/poull-gentil_differential-properties-rough-fractal-surfaces.txt
