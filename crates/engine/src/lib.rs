//! The one library API of asperity: each method family of the five papers,
//! composed with file input, analysis and plots into the jobs that every front
//! end runs — the `asperity` CLI, the gallery (`asperity demo`), the Python
//! package and the Blender add-on. A front end parses its own arguments, calls
//! a job here, and writes what it returns; it holds no algorithm.
//!
//! | Module | Jobs | Papers |
//! | --- | --- | --- |
//! | [`files`] | reading any file under the memory budget, built-in meshes, output names | — |
//! | [`describe`] | facts about a mesh, point set or height field (`info`) | — |
//! | [`analyze`] | roughness and topology reports with plots (`analyze`) | kim-machiraju-thompson §2 |
//! | [`growth`] | RD/RDSR/BD (flat and curved) and DLA with their exponents | kim-machiraju-thompson §4 |
//! | [`reconstruct`] | level-set reconstruction and the two-pass pipelines | kim-machiraju-thompson §5–6 |
//! | [`ca`] | CA height fields, rule galleries, facets and draped curves | peridier |
//! | [`subdiv`] | multiresolution surfaces from options or scenes, detail files | velho-perlin |
//! | [`ifs`] | projected-IFS models, attractors, DCF/SDCF and curvature reports | poull-gentil |
//! | [`surfca`] | Voronoi, corrosion and Gray–Scott on a mesh, coloured and textured | gobron-chiba |
//! | [`synthesis`] | self-affine (fBm) test surfaces (`generate fbm`) | — |
//! | [`render`] | turntable views and surface bounds | gobron-chiba light model |
//! | [`estimate`] | run-time estimates of the long jobs, checked before they start | — |
//! | [`jobs`] | every job by name: its description and schema for the front ends | — |
//! | [`params`] | every job's parameters: schema, validation, records (`params`), parsing | — |
//! | [`report`] | what a job wrote and measured | — |
//!
//! Errors are [`EngineError`]s, with a kind ([`ErrorKind`]) a front end maps to
//! its conventions.

pub mod analyze;
pub mod ca;
pub mod describe;
pub mod error;
pub mod estimate;
pub mod files;
pub mod growth;
pub mod ifs;
pub mod jobs;
pub mod params;
pub mod plots;
pub mod reconstruct;
pub mod render;
pub mod report;
pub mod subdiv;
pub mod surfca;
pub mod synthesis;

pub use error::{EngineError, ErrorKind, Result};

/// The shared types (meshes, height fields, budgets, progress), re-exported
/// so that a front end depends on `asperity-engine` alone (#36).
pub use asperity_core as core;
/// The file formats, re-exported for the front ends.
pub use asperity_io as io;

/// The method crates under the jobs, re-exported for the front ends that need
/// their types (the gallery's figures, the CLI's few direct calls): a front
/// end depends on `asperity-engine` alone.
pub mod methods {
    pub use asperity_analysis as analysis;
    pub use asperity_ca as ca;
    pub use asperity_growth as growth;
    pub use asperity_ifs as ifs;
    pub use asperity_levelset as levelset;
    pub use asperity_render as render;
    pub use asperity_subdiv as subdiv;
    pub use asperity_surfca as surfca;
}
pub use report::{Measurements, Report};
