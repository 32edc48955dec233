//! The gallery's 3-D views: every mesh card can be turned and zoomed in the
//! page, offline, from `file://`.
//!
//! The viewer is Google's `<model-viewer>` web component (Apache-2.0; it
//! bundles three.js, MIT, and lit, BSD-3-Clause), version 4.4.0, shipped in
//! `assets/` as its UMD build: a classic script, because browsers refuse ES
//! modules from `file://`. For the same reason a page opened from disk cannot
//! `fetch` a `.glb`, so each mesh is written as `viewer/STEM.js`, a script
//! that hands the `.glb` bytes (base64) to `asperityModel`; the page's own
//! script (`assets/asperity-viewer.js`) loads `<model-viewer>` and the model
//! when a card's "Turn in 3D" button is pressed and gives `<model-viewer>` a
//! `blob:` URL of it. Nothing is loaded until asked: opening the page costs its
//! pictures in view (they load lazily), not the 1 MB viewer nor the meshes.
//!
//! The `.glb` in `viewer/` is not the download: it is the view's copy
//! ([`compact`]), quantized, meshopt-compressed and simplified above
//! [`compact::TRIANGLE_BUDGET`] triangles, 5–15 times smaller than the
//! full-precision file. `<model-viewer>` decodes `EXT_meshopt_compression`
//! with the decoder it bundles, once its `meshoptDecoderLocation` script has
//! loaded: that script is meshoptimizer's own decoder (`meshopt_decoder.js`,
//! MIT, from npm `meshoptimizer` 1.3.0), shipped beside it.
//!
//! To update model-viewer: `npm pack @google/model-viewer@VERSION`, copy
//! `package/dist/model-viewer-umd.min.js` and `package/LICENSE` here, and run
//! the browser test (`crates/cli/tests/real_programs.rs`). To update the
//! decoder: `npm pack meshoptimizer@VERSION`, copy `meshopt_decoder.cjs` as
//! `meshopt_decoder.js` and `LICENSE.md`, and keep `tests/gltf/package.json`'s
//! `meshoptimizer` at the same version.

pub mod compact;

use std::path::Path;

use asperity_engine::Result;
use asperity_engine::core::TriMesh;
use base64::Engine as _;

/// The folder (inside the gallery) holding the viewer and the models.
pub const DIR: &str = "viewer";

/// The files the viewer needs beside the models, by name in `viewer/`: the
/// page's script, `<model-viewer>`, meshoptimizer's decoder and their licences.
pub const ASSETS: [(&str, &[u8]); 5] = [
    (
        "model-viewer-umd.min.js",
        include_bytes!("../assets/model-viewer-umd.min.js"),
    ),
    (
        "LICENSE-model-viewer.txt",
        include_bytes!("../assets/LICENSE-model-viewer.txt"),
    ),
    (
        "asperity-viewer.js",
        include_bytes!("../assets/asperity-viewer.js"),
    ),
    (
        "meshopt_decoder.js",
        include_bytes!("../assets/meshopt_decoder.js"),
    ),
    (
        "LICENSE-meshoptimizer.txt",
        include_bytes!("../assets/LICENSE-meshoptimizer.txt"),
    ),
];

/// Meshes larger than this get no 3-D view (a limit from before the views
/// were simplified, kept so the demo does not simplify multi-million-triangle
/// meshes; the demo's largest has about 400 000).
pub const MAX_TRIANGLES: usize = 1_000_000;

/// Writes the viewer's scripts and licences ([`ASSETS`]) into `gallery/viewer/`.
///
/// # Errors
/// The writer's.
pub fn write_assets(gallery: &Path) -> Result<()> {
    let dir = gallery.join(DIR); // made with the gallery folder
    for (name, bytes) in ASSETS {
        let path = dir.join(name);
        asperity_engine::io::write_atomic(&path, |w| {
            std::io::Write::write_all(w, bytes)
                .map_err(|e| asperity_engine::io::IoError::os(&path, e))
        })?;
    }
    Ok(())
}

/// Writes `gallery/viewer/STEM.js` holding the view's copy of `m`; returns its path
/// relative to the gallery, or `None` for a mesh too large for the page.
///
/// # Errors
/// The writer's.
pub fn write_model(gallery: &Path, stem: &str, m: &TriMesh) -> Result<Option<String>> {
    if m.n_faces() == 0 || m.n_faces() > MAX_TRIANGLES {
        return Ok(None);
    }
    // what the view shows: geometry, normals, colours, texture (no scalars)
    let glb = compact::encode(m, compact::TRIANGLE_BUDGET)
        .map_err(|e| asperity_engine::error::invalid(format!("3-D view of {stem}: {e}")))?;
    let name = format!("{DIR}/{stem}.js");
    let b64 = base64::engine::general_purpose::STANDARD.encode(glb);
    let quoted = serde_json::to_string(stem).unwrap_or_default(); // a JS string literal
    asperity_engine::io::write_text(
        &gallery.join(&name),
        &format!("asperityModel({quoted}, \"{b64}\");\n"),
    )?;
    Ok(Some(name))
}
