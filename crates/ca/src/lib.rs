//! Cellular-automaton height fields from [peridier].
//!
//! **Status: planned** (issue "Cellular-automaton height fields"). The
//! alternating-diagonal triangulation already lives in
//! `asperity_core::HeightField::to_trimesh(Diagonal::Alternating)`.
//!
//! | Module (planned) | What | Paper |
//! | --- | --- | --- |
//! | `rule` | Wolfram totalistic / outer-totalistic codes, B/S strings | Figure 2 |
//! | `evolve` | Cyclic and infinite-background evolution | Figure 3 |
//! | `accumulate` | Sum of steps into a height field | Figures 1, 4–6 |
//! | `facets` | Alternating-diagonal facets and their interpolation | Figure 7 |
//!
//! [peridier]: ../shared/papers/peridier_ca-rough-surfaces-facet-visualization.txt
