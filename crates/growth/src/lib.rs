//! Discrete surface-growth simulators from [kim-machiraju-thompson] §4.
//!
//! **Status: planned** (issue "Discrete surface-growth simulators"). Nothing is
//! implemented yet; this crate reserves the place in the workspace.
//!
//! | Module (planned) | Algorithm | Paper section |
//! | --- | --- | --- |
//! | `random_deposition` | Random deposition (RD) | §4.1, Fig. 3(a) |
//! | `rdsr` | RD with surface relaxation (Family model) | §4.1, Fig. 3(b) |
//! | `ballistic` | Ballistic deposition (KPZ class) | refs. of §4.1 |
//! | `dla` | Diffusion-limited aggregation | §4.2, Fig. 4 |
//! | `interface_width` | W(L, t) and the exponents α, β | §4.1 |
//!
//! [kim-machiraju-thompson]: ../shared/papers/kim-machiraju-thompson_modeling-rough-surfaces.txt
