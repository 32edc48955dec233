//! Level-set reconstruction from [kim-machiraju-thompson] §5.
//!
//! **Status: planned** (issue "Level-set reconstruction"). Nothing is implemented yet.
//!
//! | Module (planned) | Algorithm | Paper section |
//! | --- | --- | --- |
//! | `fast_sweeping` | Unsigned distance by Godunov fast sweeping | §5.2, Eqs. 7–9 |
//! | `tagging` | Initial offset surface by tagging | §5.2, Algorithm 1 |
//! | `evolve` | Narrow-band convection flow φ_t = d|∇φ| | §5.1–5.2, Eqs. 6, 10–12 |
//! | `marching_cubes` | Isosurface extraction | §5.2 (ref. \[13\]) |
//!
//! [kim-machiraju-thompson]: ../shared/papers/kim-machiraju-thompson_modeling-rough-surfaces.txt
