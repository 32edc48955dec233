//! Evaluating a scene ([`crate::scene::Scene`]): its layers grown
//! ([`crate::compose`]), blended ([`crate::blend`]) or carried as a scalar and
//! shaded ([`crate::scalar`]), with captured surfaces analysed into layers
//! (velho-perlin §2, Fig. 1: analysis and synthesis) — the whole of
//! velho-perlin's pipeline for one frame.

use asperity_core::{CoreError, Progress, TriMesh};

use crate::blend::{AlphaSource, Blend, blend};
use crate::catmull_clark::{Boundary, Creased, limit_normals, limit_positions};
use crate::compose::{Layer, grow_observed};
use crate::multires::{Details, Multires, build, synthesize};
use crate::scalar::scalar_field;
use crate::scene::{Mode, Scene};

/// The result of evaluating a scene.
#[derive(Clone, Debug)]
pub struct Composed {
    /// The finest level's connectivity and final positions.
    pub mesh: Creased,
    /// Vertex colours (scalar mode).
    pub colors: Option<Vec<[u8; 4]>>,
    /// Named per-vertex scalars (scalar mode: `height`, `alpha`; blends: `alpha`).
    pub scalars: Vec<(String, Vec<f64>)>,
    /// The details of every level (displacement mode).
    pub details: Details,
    /// (vertices, faces) per level.
    pub counts: Vec<(usize, usize)>,
}

impl Composed {
    /// `base` with `details` applied over `levels` levels (no procedures): a
    /// surface analysed or read back from a details file.
    ///
    /// # Errors
    /// As [`synthesize`].
    pub fn synthesized(
        base: &Creased,
        details: Details,
        levels: usize,
        boundary: Boundary,
    ) -> Result<Self, CoreError> {
        let mut all = synthesize(base, &details, levels, boundary)?;
        let counts = all
            .iter()
            .map(|l| (l.mesh.n_vertices(), l.mesh.n_faces()))
            .collect();
        let mesh = all.pop().expect("level 0 at least");
        Ok(Self {
            mesh,
            colors: None,
            scalars: Vec::new(),
            details,
            counts,
        })
    }

    /// The surface as triangles with normals — the limit normals when `limit`
    /// (after at least one level), else computed from the faces — and its
    /// colours and scalars.
    ///
    /// # Errors
    /// As [`limit_normals`].
    pub fn to_trimesh(&self, limit: bool, boundary: Boundary) -> Result<TriMesh, CoreError> {
        let levels = self.counts.len().saturating_sub(1);
        let mut tri = self.mesh.mesh.triangulate();
        tri = if limit && levels > 0 {
            tri.with_normals(limit_normals(&self.mesh, boundary)?)?
        } else {
            tri.with_computed_normals()
        };
        if let Some(col) = &self.colors {
            tri = tri.with_colors(col.clone())?;
        }
        for (name, v) in &self.scalars {
            tri = tri.with_scalar(name, v.clone())?;
        }
        Ok(tri)
    }
}

fn merged(layers: &[Layer]) -> Layer {
    Layer {
        name: "main".into(),
        features: layers.iter().flat_map(|l| l.features.clone()).collect(),
        edits: layers.iter().flat_map(|l| l.edits.clone()).collect(),
    }
}

/// A captured surface analysed into a layer: its base positions and details.
#[derive(Clone, Debug)]
pub struct Captured {
    /// The layer it stands for.
    pub layer: String,
    /// Base positions (the scene base's connectivity).
    pub base: Creased,
    /// Details of every level.
    pub details: Details,
}

/// What the caller read for a scene: the blend's alpha map and the captured
/// surfaces.
#[derive(Clone, Debug, Default)]
pub struct Inputs {
    /// One alpha in [0, 1] per base vertex, when the blend names a map.
    pub alpha_map: Option<Vec<f64>>,
    /// The scene's `[[surface]]` layers, analysed.
    pub captured: Vec<Captured>,
}

/// Evaluates a scene on its base (loaded by the caller) with the files the
/// scene names already read (`inputs`).
///
/// # Errors
/// [`CoreError::InvalidParameter`] for an inconsistent scene; as [`crate::compose::grow`],
/// [`blend`] and [`scalar_field`].
pub fn evaluate(
    scene: &Scene,
    base: &Creased,
    inputs: &Inputs,
    progress: &dyn Progress,
) -> Result<Composed, CoreError> {
    let bad = |reason: String| CoreError::InvalidParameter {
        name: "scene",
        reason,
    };
    let (levels, boundary, seed) = (scene.levels, scene.boundary, scene.seed);
    let find = |name: &str| {
        scene
            .layers
            .iter()
            .find(|l| l.name == name)
            .ok_or_else(|| bad(format!("no layer {name:?}")))
    };
    let captured = |name: &str| inputs.captured.iter().find(|c| c.layer == name);
    for (layer, _) in &scene.surfaces {
        if captured(layer).is_none() {
            return Err(bad(format!(
                "the captured surface of layer {layer:?} was not read"
            )));
        }
    }
    let blend_parts = match &scene.blend {
        Some((a, b, how)) => {
            if let Some(l) = scene.layers.iter().find(|l| &l.name != a && &l.name != b) {
                return Err(bad(format!(
                    "layer {:?} is neither side of the blend ({a:?}, {b:?})",
                    l.name
                )));
            }
            let mut how = how.clone();
            if let AlphaSource::Map(m) = &mut how.source {
                *m = inputs
                    .alpha_map
                    .clone()
                    .ok_or_else(|| bad("the blend's alpha map was not read".into()))?;
            }
            Some((find(a)?, find(b)?, how))
        }
        None => None,
    };
    if !inputs.captured.is_empty() {
        if matches!(scene.mode, Mode::Scalar(_)) {
            return Err(bad(
                "captured surfaces displace; scalar mode cannot use them".into(),
            ));
        }
        if blend_parts.is_none() && scene.layers.len() > 1 {
            return Err(bad(
                "a captured surface combines with other layers only through [blend]".into(),
            ));
        }
    }
    // One side of a blend (or the only layer): its base and details.
    let side = |layer: &Layer, salt: u64| -> Result<(Creased, Details), CoreError> {
        match captured(&layer.name) {
            Some(c) => Ok((c.base.clone(), c.details.clone())),
            None => Ok((
                base.clone(),
                grow_observed(base, levels, boundary, layer, seed ^ salt, progress)?.details,
            )),
        }
    };
    // One unit per level of every procedural surface grown.
    let surfaces = match (&blend_parts, &scene.mode) {
        (_, Mode::Scalar(_)) => 0,
        (Some((a, b, _)), _) => [a, b]
            .iter()
            .filter(|l| captured(&l.name).is_none())
            .count(),
        (None, _) => usize::from(inputs.captured.is_empty()),
    };
    progress.start((surfaces * levels) as u64, "subdivision levels");
    let out = evaluate_mode(scene, base, inputs, progress, blend_parts.as_ref(), &side);
    progress.finish();
    out
}

/// Builds one side of a blend: its base and details.
type SideFn<'a> = dyn Fn(&Layer, u64) -> Result<(Creased, Details), CoreError> + 'a;

/// The two sides of a blend and how.
type BlendParts<'a> = (&'a Layer, &'a Layer, Blend);

/// [`evaluate`] after the checks.
fn evaluate_mode(
    scene: &Scene,
    base: &Creased,
    inputs: &Inputs,
    progress: &dyn Progress,
    blend_parts: Option<&BlendParts<'_>>,
    side: &SideFn<'_>,
) -> Result<Composed, CoreError> {
    let (levels, boundary, seed) = (scene.levels, scene.boundary, scene.seed);
    let counts = |m: &Multires| {
        m.levels
            .iter()
            .map(|l| (l.mesh.n_vertices(), l.mesh.n_faces()))
            .collect::<Vec<_>>()
    };
    match &scene.mode {
        Mode::Displace => {
            let (m, alpha) = match &blend_parts {
                None => match inputs.captured.first() {
                    Some(c) => {
                        let d = &c.details;
                        let m = build(&c.base, levels, boundary, |l| {
                            Ok(d.get(l.level - 1).filter(|x| !x.is_empty()).cloned())
                        })?;
                        (m, None)
                    }
                    None => (
                        grow_observed(
                            base,
                            levels,
                            boundary,
                            &merged(&scene.layers),
                            seed,
                            progress,
                        )?,
                        None,
                    ),
                },
                Some((a, b, how)) => {
                    let (ba, da) = side(a, 0)?;
                    let (bb, db) = side(b, 0xb1e7_d000)?;
                    let base_b = (bb.mesh.positions() != ba.mesh.positions()).then_some(&bb);
                    let (m, alpha) = blend(&ba, base_b, (&da, &db), levels, boundary, how)?;
                    (m, Some(alpha))
                }
            };
            let mut mesh = m.finest().clone();
            if scene.limit && levels > 0 {
                let lim = limit_positions(&mesh, boundary)?;
                mesh.mesh.set_positions(lim)?;
            }
            Ok(Composed {
                counts: counts(&m),
                mesh,
                colors: None,
                scalars: alpha.map(|a| vec![("alpha".into(), a)]).unwrap_or_default(),
                details: m.details,
            })
        }
        Mode::Scalar(planet) => {
            if scene.layers.iter().any(|l| !l.edits.is_empty()) {
                return Err(CoreError::InvalidParameter {
                    name: "scene",
                    reason: "edits act on displacement details; scalar mode has none".into(),
                });
            }
            let f = match &blend_parts {
                None => scalar_field(
                    base,
                    levels,
                    boundary,
                    &merged(&scene.layers).features,
                    None,
                    seed,
                )?,
                Some((a, b, how)) => scalar_field(
                    base,
                    levels,
                    boundary,
                    &a.features,
                    Some((&b.features, how)),
                    seed,
                )?,
            };
            let (colors, positions) = planet.shade(&f);
            let mut mesh = f.mesh.clone();
            mesh.mesh.set_positions(positions)?;
            Ok(Composed {
                mesh,
                colors: Some(colors),
                scalars: vec![("height".into(), f.value), ("alpha".into(), f.alpha)],
                details: Vec::new(),
                counts: f.counts.clone(),
            })
        }
    }
}
