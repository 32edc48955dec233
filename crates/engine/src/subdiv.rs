//! Multiresolution subdivision surfaces with procedural detail (velho-perlin):
//! a scene from a file or from options, its base and the files it names read,
//! evaluated frame by frame; details exported and re-applied to an edited base;
//! captured fine meshes analysed into details.

use std::path::{Path, PathBuf};

use asperity_core::{MemoryBudget, PolyMesh, Progress};
use asperity_subdiv::base;
use asperity_subdiv::blend::{painted_alpha, parse_alpha_map};
use asperity_subdiv::catmull_clark::{Boundary, Creased};
use asperity_subdiv::detail_file::DetailFile;
use asperity_subdiv::evaluate::{Captured, Composed, Inputs, evaluate};
use asperity_subdiv::examples::{EXAMPLES, Example, example};
use asperity_subdiv::multires::analyze_captured;
use asperity_subdiv::scene::{Scene, crease_from_spec, feature_from_spec, parse};

use clap::Args;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::error::{Result, ensure, invalid};
use crate::files::read_text;
use crate::params::{JobParams, choice};

choice! {
    /// The rule of Catmull–Clark subdivision at open boundaries.
    pub enum BoundaryRule {
        /// Boundary edges sharp, boundary vertices on the boundary B-spline.
        EdgeOnly = "edge-only",
        /// As edge-only, and boundary vertices with two edges stay fixed.
        EdgeAndCorner = "edge-and-corner",
    }
}

impl From<BoundaryRule> for Boundary {
    fn from(b: BoundaryRule) -> Self {
        match b {
            BoundaryRule::EdgeOnly => Boundary::EdgeOnly,
            BoundaryRule::EdgeAndCorner => Boundary::EdgeAndCorner,
        }
    }
}

/// `subdiv`: a multiresolution Catmull–Clark surface with procedural detail
/// (velho-perlin §2–6), from a scene or from a base, levels and details.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct SubdivParams {
    /// A scene file (TOML) describing base, levels, seed, details, edits, blends and shading
    /// (see crates/subdiv/scenes), or a built-in example: example:rock, example:berry,
    /// example:tentacle, example:mushroom, example:spur; the shape parameters below then cannot
    /// be given.
    #[arg(value_name = "SCENE")]
    pub scene: Option<PathBuf>,
    /// A scene's TOML text instead of its file (its relative paths: against the scene file's
    /// folder if one is given, else the current folder).
    #[arg(skip)]
    pub scene_text: Option<String>,
    /// Base mesh: cube, sphere (a quad sphere), torus, cylinder, plane, fuse,
    /// revolution:PROFILE (a text file of `r z` rows, bottom to top), or a mesh file (OBJ/PLY
    /// polygons kept).
    #[arg(long, default_value_t = Self::default().base, conflicts_with = "scene")]
    pub base: String,
    /// Subdivision levels.
    #[schemars(range(max = 10))]
    #[arg(long, default_value_t = Self::default().levels, conflicts_with = "scene")]
    pub levels: usize,
    /// Procedural details: rock, fbm, berry, tentacle, mine, mushroom or spur with key=value
    /// parameters, e.g. rock:amplitude=0.08,decay=0.5 or berry:radius=0.3,spacing=0.6; a..b
    /// animates a number over time.
    #[arg(long, value_name = "SPEC", conflicts_with = "scene")]
    pub detail: Vec<String>,
    /// Creases on the base: A-B:SHARPNESS (inf = sharp forever).
    #[arg(long, value_name = "A-B:S", conflicts_with = "scene")]
    pub crease: Vec<String>,
    /// Boundary rule for open meshes.
    #[arg(long, value_enum, default_value_t = Self::default().boundary, conflicts_with = "scene")]
    pub boundary: BoundaryRule,
    /// Move the finest level onto the limit surface (normals: exact limit normals).
    #[arg(long)]
    pub limit: bool,
    /// Animation time t in [0, 1].
    #[schemars(range(min = 0.0, max = 1.0))]
    #[arg(long, default_value_t = Self::default().time, conflicts_with = "frames")]
    pub time: f64,
    /// Re-apply exported details (a JSON file) to this base (same connectivity) instead of
    /// running the procedures.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["scene", "detail"])]
    pub apply_details: Option<PathBuf>,
    /// Analyse a fine mesh whose connectivity is the levels' subdivisions of the base (a PLY as
    /// subdiv writes it, positions edited freely) into base and details by quasi-interpolation.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["scene", "detail", "apply_details"])]
    pub analyze: Option<PathBuf>,
}

impl Default for SubdivParams {
    fn default() -> Self {
        Self {
            scene: None,
            scene_text: None,
            base: "cube".into(),
            levels: 3,
            detail: Vec::new(),
            crease: Vec::new(),
            boundary: BoundaryRule::EdgeOnly,
            limit: false,
            time: 0.0,
            apply_details: None,
            analyze: None,
        }
    }
}

/// The built-in example scene `name` (`asperity_subdiv::examples`).
///
/// # Errors
/// An unknown name, with the names there are.
fn built_in(name: &str) -> Result<&'static Example> {
    example(name).ok_or_else(|| {
        let names: Vec<&str> = EXAMPLES.iter().map(|e| e.name).collect();
        invalid(format!(
            "no example scene {name:?} (there are {})",
            names.join(", ")
        ))
    })
}

/// The built-in example scenes as the front ends list them: name,
/// description, levels, seed, the main detail's size (field and value) and
/// spacing (the Blender add-on's knobs).
pub fn examples() -> serde_json::Value {
    EXAMPLES
        .iter()
        .map(|e| {
            let (levels, seed) = e.levels_and_seed();
            serde_json::json!({
                "name": e.name,
                "description": e.description(),
                "levels": levels,
                "seed": seed,
                "size": e.size().map(|(field, value)| serde_json::json!({"field": field, "value": value})),
                "spacing": e.spacing(),
            })
        })
        .collect()
}

/// The rock detail's defaults (`rock` with no key=value: amplitude and the
/// 1/f decay), which the Blender add-on's Roughen shows.
pub fn rock_defaults() -> serde_json::Value {
    let rock = asperity_subdiv::detail::Rock::default();
    let decay = match rock.law {
        asperity_subdiv::detail::Law::Fractal { decay } => Some(decay),
        _ => None,
    };
    serde_json::json!({"amplitude": rock.amplitude, "decay": decay})
}

/// The text of example `name` with its levels, seed and main detail's size
/// and spacing set where given ([`Example::with`]).
///
/// # Errors
/// An unknown example, or a knob it does not have.
pub fn example_text(
    name: &str,
    levels: Option<usize>,
    seed: Option<u64>,
    size: Option<f64>,
    spacing: Option<f64>,
) -> Result<String> {
    built_in(name)?
        .with(levels, seed, size, spacing)
        .map_err(invalid)
}

impl JobParams for SubdivParams {
    const JOB: &'static str = "subdiv";
}

impl SubdivParams {
    /// Where the scene comes from: a file, a text, or the options.
    ///
    /// # Errors
    /// An unreadable scene file.
    pub fn source(&self) -> Result<Source> {
        Ok(match (&self.scene, &self.scene_text) {
            (path, Some(text)) => Source::Scene {
                path: path.clone().unwrap_or_else(|| PathBuf::from("scene.toml")),
                text: text.clone(),
            },
            (Some(path), None) => match path.to_str().and_then(|p| p.strip_prefix("example:")) {
                Some(name) => Source::Scene {
                    path: PathBuf::from(built_in(name)?.file),
                    text: built_in(name)?.text.to_owned(),
                },
                None => Source::Scene {
                    path: path.clone(),
                    text: read_text(path)?,
                },
            },
            (None, None) => Source::Options(Options {
                base: self.base.clone(),
                levels: self.levels,
                details: self.detail.clone(),
                creases: self.crease.clone(),
                boundary: self.boundary.into(),
            }),
        })
    }

    /// The session of these parameters (the scene at `time`).
    ///
    /// # Errors
    /// As [`Session::open`], and the parameters'.
    pub fn open(&self, seed: u64, budget: &MemoryBudget) -> Result<Session> {
        crate::params::validate(self)?;
        Session::open(self.source()?, seed, self.limit, self.time, budget)
    }
}

/// The built-in bases [`load_base`] knows.
pub const BUILTIN_BASES: &str = "cube, sphere, torus, cylinder, plane, fuse";

/// A built-in base by name, `revolution:PROFILE` (a file of `r z` rows), or a
/// polygon mesh file; files are relative to `dir`.
///
/// # Errors
/// An unreadable or invalid profile or mesh, naming the file.
pub fn load_base(spec: &str, dir: &Path, budget: &MemoryBudget) -> Result<PolyMesh> {
    Ok(match spec {
        "cube" => base::cube(),
        "sphere" => base::quad_sphere(2),
        "torus" => base::torus(1.0, 0.35, 16, 8),
        "cylinder" => base::cylinder(0.6, 1.0, 8),
        "plane" => base::plane(4),
        "fuse" => base::fuse(24, 10),
        spec if spec.starts_with("revolution:") => {
            let p = dir.join(&spec["revolution:".len()..]);
            let profile = base::parse_profile(&read_text(&p)?)
                .map_err(|e| invalid(format!("{}: {e}", p.display())))?;
            base::revolution(&profile, 16)
        }
        path => {
            let p = dir.join(path);
            crate::files::check_read(&p, budget)?;
            asperity_io::read_poly_mesh(&p).map_err(|e| {
                invalid(format!(
                    "reading the base mesh {e} (or use {BUILTIN_BASES})"
                ))
            })?
        }
    })
}

/// A surface without a scene file, as `asperity subdiv --base …` describes it.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// A built-in base, `revolution:PROFILE` or a mesh file.
    pub base: String,
    /// Subdivision levels.
    pub levels: usize,
    /// `--detail` specs (`name:key=value,…`).
    pub details: Vec<String>,
    /// `--crease` specs (`A-B:SHARPNESS`).
    pub creases: Vec<String>,
    /// Boundary rule.
    pub boundary: Boundary,
}

/// Where the scene comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum Source {
    /// A TOML scene file's text and the folder its paths are relative to.
    Scene {
        /// The file (for messages).
        path: PathBuf,
        /// Its text.
        text: String,
    },
    /// Options.
    Options(Options),
}

/// Evaluates scenes at animation times: the base and the files the scene
/// names are read once, then [`Session::frame`] evaluates any time.
pub struct Session {
    source: Source,
    seed: u64,
    limit: bool,
    dir: PathBuf,
    /// The scene at the first time asked for.
    pub first: Scene,
    /// The base with its creases.
    pub base: Creased,
    inputs: Inputs,
}

impl Session {
    /// Reads the scene at time `t`, its base and its files, and checks the size
    /// of the finest level against the budget; `limit` forces limit positions.
    ///
    /// # Errors
    /// A bad scene, base, crease, alpha map or captured surface; more than 10
    /// levels; the budget.
    pub fn open(
        source: Source,
        seed: u64,
        limit: bool,
        t: f64,
        budget: &MemoryBudget,
    ) -> Result<Self> {
        let dir = match &source {
            Source::Scene { path, .. } => path.parent().map(Path::to_path_buf).unwrap_or_default(),
            Source::Options(_) => PathBuf::new(),
        };
        let first = scene_at(&source, seed, limit, t)?;
        let base = Creased::with_creases(load_base(&first.base, &dir, budget)?, &first.creases)?;
        check_size(&base, first.levels, budget)?;
        let inputs = read_inputs(&first, &base, &dir, budget)?;
        Ok(Self {
            source,
            seed,
            limit,
            dir,
            first,
            base,
            inputs,
        })
    }

    /// The scene at time `t`.
    ///
    /// # Errors
    /// As [`Session::open`].
    pub fn scene(&self, t: f64) -> Result<Scene> {
        scene_at(&self.source, self.seed, self.limit, t)
    }

    /// The surface of `scene` on this base.
    ///
    /// # Errors
    /// The evaluation's (an inconsistent scene, bad features).
    pub fn frame(&self, scene: &Scene, progress: &dyn Progress) -> Result<Composed> {
        Ok(evaluate(scene, &self.base, &self.inputs, progress)?)
    }

    /// The surface of the base with the details of a details file re-applied.
    ///
    /// # Errors
    /// An unreadable file, one of another format or for another base.
    pub fn apply_details(&self, path: &Path, boundary: Boundary) -> Result<Composed> {
        let f = DetailFile::from_json(&read_text(path)?)
            .and_then(|f| f.check_base(&self.base).map(|()| f))
            .map_err(|e| invalid(format!("{}: {e}", path.display())))?;
        Ok(Composed::synthesized(
            &self.base, f.details, f.levels, boundary,
        )?)
    }

    /// A fine mesh (connectivity: the scene's levels of the base) analysed into
    /// base positions and details.
    ///
    /// # Errors
    /// An unreadable mesh, or one of other connectivity.
    pub fn analyze_fine(&self, path: &Path, scene: &Scene) -> Result<Composed> {
        let (coarse, details) = read_captured(path, &self.base, scene)?;
        Ok(Composed::synthesized(
            &coarse,
            details,
            scene.levels,
            scene.boundary,
        )?)
    }

    /// The surface of these parameters at time `t` (the scene's first time
    /// when `None`): re-applied details, an analysed fine mesh, or the scene
    /// evaluated; with the scene's limit and boundary rule.
    ///
    /// # Errors
    /// As [`Session::frame`], [`Session::apply_details`] and [`Session::analyze_fine`].
    pub fn surface(
        &self,
        p: &SubdivParams,
        t: Option<f64>,
        progress: &dyn Progress,
    ) -> Result<(Composed, bool, Boundary)> {
        let scene = match t {
            None => self.first.clone(),
            Some(t) => self.scene(t)?,
        };
        let c = match (&p.apply_details, &p.analyze) {
            (Some(path), _) => self.apply_details(path, scene.boundary)?,
            (None, Some(path)) => self.analyze_fine(path, &scene)?,
            (None, None) => self.frame(&scene, progress)?,
        };
        Ok((c, scene.limit, scene.boundary))
    }

    /// The details file of a composed surface (`--export-details`).
    pub fn details_file(&self, c: &Composed) -> String {
        DetailFile::new(&self.base, self.first.levels, c.details.clone()).to_json()
    }

    /// The folder the scene's paths are relative to.
    pub fn dir(&self) -> &Path {
        &self.dir
    }
}

fn scene_at(source: &Source, seed: u64, limit: bool, t: f64) -> Result<Scene> {
    ensure((0.0..=1.0).contains(&t), || {
        format!("⟨time={t}⟩ is outside [0, 1]")
    })?;
    match source {
        Source::Scene { path, text } => {
            let mut sc = parse(text, t).map_err(|e| invalid(format!("{}: {e}", path.display())))?;
            sc.limit |= limit;
            Ok(sc)
        }
        Source::Options(o) => {
            let features = o
                .details
                .iter()
                .map(|d| feature_from_spec(d, t))
                .collect::<Result<Vec<_>, String>>()?;
            let mut sc = Scene::single_layer(&o.base, o.levels, seed, features);
            sc.boundary = o.boundary;
            sc.limit = limit;
            sc.creases = o
                .creases
                .iter()
                .map(|c| crease_from_spec(c))
                .collect::<Result<_, String>>()?;
            Ok(sc)
        }
    }
}

/// Refuses more than 10 levels, and a finest level the budget cannot hold.
fn check_size(base: &Creased, levels: usize, budget: &MemoryBudget) -> Result<()> {
    ensure(levels <= 10, || format!("levels = {levels}: at most 10"))?;
    // Quads after level k: Σ|f| · 4^(k−1); refuse before allocating.
    let corners: u128 = base.mesh.faces().map(|f| f.len() as u128).sum();
    let quads = if levels == 0 {
        base.mesh.n_faces() as u128
    } else {
        corners << (2 * (levels - 1))
    };
    budget.check_elements(
        quads,
        // Positions and details of two surfaces, topology, output triangles
        // (208 bytes), times four: the coarser levels kept (a third more),
        // the output mesh's normals, colours and scalars, the writer's f32
        // copies. Measured peak RSS over the process at rest, against this:
        // rock 1.2, tentacle 1.3, planet 1.05, berry 0.67
        // (`crates/benches/scripts/estimate_honesty.py`); 208 alone gave 4–5×.
        4 * (3 * 24 + 4 * 16 + 2 * 12 + 48),
        "the subdivided mesh",
    )?;
    Ok(())
}

/// The alpha map and the captured surfaces a scene names.
fn read_inputs(scene: &Scene, base: &Creased, dir: &Path, budget: &MemoryBudget) -> Result<Inputs> {
    let alpha_map = match &scene.alpha_map {
        Some(file) => {
            let path = dir.join(&file.path);
            use asperity_io::Format;
            let painted = matches!(
                Format::from_path(&path),
                Ok(Format::Ply | Format::Obj | Format::Stl | Format::Glb)
            );
            let map = if painted {
                let mesh = crate::files::load_triangles(&path, budget)?;
                painted_alpha(base.mesh.positions(), &mesh, &file.paint)
                    .map_err(|e| invalid(format!("alpha map {}: {e}", path.display())))?
            } else {
                parse_alpha_map(&read_text(&path)?)
                    .map_err(|e| invalid(format!("alpha map {}: {e}", path.display())))?
            };
            Some(map)
        }
        None => None,
    };
    let mut captured = Vec::new();
    for (layer, file) in &scene.surfaces {
        let (b, details) = read_captured(&dir.join(file), base, scene)?;
        captured.push(Captured {
            layer: layer.clone(),
            base: b,
            details,
        });
    }
    Ok(Inputs {
        alpha_map,
        captured,
    })
}

fn read_captured(
    path: &Path,
    base: &Creased,
    scene: &Scene,
) -> Result<(Creased, asperity_subdiv::multires::Details)> {
    let fine = asperity_io::read_poly_mesh(path)
        .map_err(|e| invalid(format!("reading the fine mesh {e}")))?;
    analyze_captured(base, &fine, scene.levels, scene.boundary)
        .map_err(|e| invalid(format!("{}: {e}", path.display())))
}
