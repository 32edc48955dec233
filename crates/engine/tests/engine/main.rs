//! The engine's behaviour, one module per engine module (issue #36): what
//! every front end (CLI, gallery, Python, Blender) gets when it calls a job,
//! one behaviour per test, checked against outside truths — closed forms,
//! physical exponents, the papers' figures. The CLI's tests check only its
//! own wiring (flags, files, messages); the algorithms' own crates test their
//! numerics against independent references.
//!
//! One test binary, so the engine is linked once.

mod analyze;
mod ca;
mod clouds;
mod files;
mod growth;
mod ifs;
mod params;
mod reconstruct;
mod render;
mod subdiv;
mod subdiv_examples;
mod surfca;
mod synthesis;
