//! Headless CPU rendering of asperity surfaces.
//!
//! **Status: planned** (issue "Renderer and demo gallery"): z-buffered rasterisation,
//! the [gobron-chiba] light model, shadows and ambient occlusion, hillshade, plots.
//! Output images are `asperity_core::RgbaImage`.
//!
//! [gobron-chiba]: ../shared/papers/gobron-chiba_3d-surface-cellular-automata.txt
