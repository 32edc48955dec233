//! Projected-IFS fractal curves and surfaces with DCF/SDCF pseudo-curvature, after
//! Poull, Gentil, Roudet, Druoton & Roy, *Differential properties of rough fractal
//! surfaces* (JFIG 2024) — [poull-gentil].
//!
//! | Module | What | Paper |
//! | --- | --- | --- |
//! | [`spectrum`] | ordered eigen-decomposition, α exponents, Jordan/complex detection | §2.3 |
//! | [`invariant`] | general spectra: multiplicities, generalised eigenspaces, DCF/SDCF and 𝒦/ℋ of any real-spectrum 𝒯 = T⊗T′ | §2.3, §3.2, §4.1 |
//! | [`pifs`] | P-IFS validation (barycentric, contractive, C⁰ adjacency), attractors, tensor products | §2.1–2.2, §3.1 |
//! | [`dcf`] | DCF, its family over the attractor, curve pseudo-curvature | §2.3 |
//! | [`curvature`] | SDCF fundamental forms, 𝒦/ℋ/κ ranges, the 3×3 table, dyadic transport | §4 |
//! | [`sdcf`] | DCF and SDCF geometry (Figs. 2 and 4) | §3 |
//! | [`model`] | model files (JSON) and presets: Bézier, Takagi–Landsberg, mixed | Figs. 1–4 |
//!
//! Conventions: barycentric points are column vectors, operators act as q ↦ Tq
//! and have columns summing to 1; a curve's attractor is parametrised by
//! s ∈ [0, 1] with T0(𝒜) the half [0, ½]; a surface's control grid is N×M,
//! row-major (a·M + b), and 𝒯ᵢⱼ = Tᵢ ⊗ T′ⱼ.
//!
//! The worked notes in `../shared/notes/dcf-math.md` were checked against the
//! paper and against the tests here (Bézier curvature, the bicubic patch's
//! analytic 𝒦 and ℋ, the Takagi w = 1/√2 range [102 − 72√2, 6 − 4√2]).
//!
//! [poull-gentil]: https://hal.science/hal-04790610 "Poull, Gentil, Roudet, Druoton, Roy: Differential properties of rough fractal surfaces. JFIG 2024, HAL hal-04790610"

pub mod curvature;
pub mod dcf;
mod error;
pub mod invariant;
pub mod model;
pub mod pifs;
pub mod sdcf;
pub mod spectrum;

pub use curvature::{DirectionAnalysis, SurfaceClass, SurfaceRanges};
pub use dcf::{CurveClass, FamilyOptions, OperatorAnalysis};
pub use error::{Constraint, IfsError, Result};
pub use invariant::SpectrumEntry;
pub use model::{Model, ModelFile, PresetParams, preset, preset_names};
pub use pifs::{CurveIfs, Pifs, SurfaceIfs};
