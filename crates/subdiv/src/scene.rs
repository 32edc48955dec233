//! Scene files (TOML) describing a composition: base, levels, details,
//! placements, edits, blends and shading (velho-perlin §3's framework,
//! Fig. 2). Every number may be animated: write `[from, to]` and it runs
//! linearly over the animation time t ∈ [0, 1] (§3: "an animation time
//! parameter can feed into any synthesized shape definition, the synthesized
//! alpha, and the post-processing shader").
//!
//! ```toml
//! base = "sphere"          # cube, sphere, torus, cylinder, plane, fuse, or a mesh file
//! levels = 4
//! seed = 7
//! boundary = "edge-only"   # or "edge-and-corner"
//! mode = "displace"        # or "scalar" (with [shade])
//!
//! [[detail]]
//! type = "rock"            # rock, fbm, berry, tentacle, mine, mushroom, spur
//! layer = "main"           # layers are summed, or blended by [blend]
//! amplitude = [0.05, 0.1]  # animated
//! levels = [1, 3]          # placement at chosen levels (default: all)
//! at = [[0, 0, 1]]         # seeds: points, `vertices = [..]`, or `spacing = 0.4`
//!
//! [[edit]]                 # local detail modification (§5.2)
//! at = [0, 0, 1]           # or vertex = 3
//! radius = 1.5             # base-level edges
//! levels = [2, 4]
//! factor = 0.0             # 0 smooths, > 1 exaggerates
//!
//! [blend]                  # multiscale blending (§6)
//! a = "main"
//! b = "rust"
//! width = 0.6              # c; the width at level l is c/2^(l-1)
//! plane = { normal = [1, 2, 0], offset = 0.0 }   # or noise = {..}, or alpha_map = "file"
//! # alpha_map = "painted.ply"  # a text column per base vertex, or a mesh painted over the
//! # alpha_from = "colour"      # base: its colour's luminance (black a, white b) or a scalar
//!
//! [[surface]]              # a captured surface as a layer (blend it with details)
//! layer = "scan"
//! file = "fine.ply"        # connectivity: `levels` subdivisions of the base
//!
//! [shade]                  # scalar mode post-shader (§6.2)
//! kind = "planet"
//! sea_level = 0.0
//! relief = 0.25
//! ```

use std::collections::BTreeMap;

use toml::{Table, Value};

use crate::blend::{AlphaSource, Blend, Paint};
use crate::catmull_clark::Boundary;
use crate::compose::{Anchor, Edit, Layer};
use crate::detail::{
    Berry, Coords, Fbm, Feature, Law, Mushroom, Procedure, Rock, Seeds, Spur, Tentacle,
    TentacleReading,
};
use crate::scalar::Planet;

/// Displacement or scalar mode.
#[derive(Clone, Debug, PartialEq)]
pub enum Mode {
    /// Details displace the surface.
    Displace,
    /// Details build a scalar field, shaded by the planet shader.
    Scalar(Planet),
}

/// A scene at one animation time.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// A built-in base name or a mesh path (relative to the scene file's folder).
    pub base: String,
    /// Subdivision levels.
    pub levels: usize,
    /// Random seed.
    pub seed: u64,
    /// Boundary rule.
    pub boundary: Boundary,
    /// Write limit positions.
    pub limit: bool,
    /// The layers, in order of first mention.
    pub layers: Vec<Layer>,
    /// A blend of two layers: (a, b, how). The alpha map, if any, is a path
    /// still to be read ([`Scene::alpha_map`]).
    pub blend: Option<(String, String, Blend)>,
    /// The alpha map of the blend, if it uses one: a path still to be read.
    pub alpha_map: Option<AlphaFile>,
    /// Displacement or scalar mode.
    pub mode: Mode,
    /// Tagged creases of the base: (vertex, vertex, sharpness).
    pub creases: Vec<(u32, u32, f64)>,
    /// Captured surfaces: (layer, mesh path) — a fine mesh whose connectivity
    /// is `levels` subdivisions of the base, analysed into that layer's base
    /// positions and details ([`crate::multires::analyze`]).
    pub surfaces: Vec<(String, String)>,
}

/// A number that may be animated: `x` or `[from, to]` over t ∈ [0, 1].
fn number(v: &Value, t: f64, what: &str) -> Result<f64, String> {
    match v {
        Value::Integer(i) => Ok(*i as f64),
        Value::Float(x) => Ok(*x),
        Value::Array(a) if a.len() == 2 => {
            let from = number(&a[0], t, what)?;
            let to = number(&a[1], t, what)?;
            Ok(from + (to - from) * t)
        }
        other => Err(format!(
            "{what}: expected a number or [from, to], got {other}"
        )),
    }
}

fn point(v: &Value, t: f64, what: &str) -> Result<[f64; 3], String> {
    match v {
        Value::Array(a) if a.len() == 3 => Ok([
            number(&a[0], t, what)?,
            number(&a[1], t, what)?,
            number(&a[2], t, what)?,
        ]),
        other => Err(format!("{what}: expected [x, y, z], got {other}")),
    }
}

/// Reads keys of a table, remembering which were used.
struct Keys<'a> {
    table: &'a Table,
    used: Vec<&'static str>,
    what: String,
    t: f64,
}

impl<'a> Keys<'a> {
    fn new(table: &'a Table, what: String, t: f64) -> Self {
        Self {
            table,
            used: Vec::new(),
            what,
            t,
        }
    }
    fn get(&mut self, k: &'static str) -> Option<&'a Value> {
        self.used.push(k);
        self.table.get(k)
    }
    fn num(&mut self, k: &'static str, default: f64) -> Result<f64, String> {
        let (what, t) = (format!("{} {k}", self.what), self.t);
        self.get(k).map_or(Ok(default), |v| number(v, t, &what))
    }
    fn int(&mut self, k: &'static str, default: usize) -> Result<usize, String> {
        let what = format!("{} {k}", self.what);
        match self.get(k) {
            None => Ok(default),
            Some(Value::Integer(i)) if *i >= 0 => Ok(*i as usize),
            Some(other) => Err(format!("{what}: expected a whole number ≥ 0, got {other}")),
        }
    }
    fn string(&mut self, k: &'static str) -> Result<Option<&'a str>, String> {
        let what = format!("{} {k}", self.what);
        match self.get(k) {
            None => Ok(None),
            Some(Value::String(s)) => Ok(Some(s)),
            Some(other) => Err(format!("{what}: expected a string, got {other}")),
        }
    }
    fn boolean(&mut self, k: &'static str, default: bool) -> Result<bool, String> {
        let what = format!("{} {k}", self.what);
        match self.get(k) {
            None => Ok(default),
            Some(Value::Boolean(b)) => Ok(*b),
            Some(other) => Err(format!("{what}: expected true or false, got {other}")),
        }
    }
    fn ints(&mut self, k: &'static str) -> Result<Option<Vec<usize>>, String> {
        let what = format!("{} {k}", self.what);
        match self.get(k) {
            None => Ok(None),
            Some(Value::Array(a)) => a
                .iter()
                .map(|x| match x {
                    Value::Integer(i) if *i >= 0 => Ok(*i as usize),
                    other => Err(format!("{what}: expected whole numbers, got {other}")),
                })
                .collect::<Result<Vec<_>, _>>()
                .map(Some),
            Some(other) => Err(format!(
                "{what}: expected a list of whole numbers, got {other}"
            )),
        }
    }
    fn finish(self) -> Result<(), String> {
        let unknown: Vec<&String> = self
            .table
            .keys()
            .filter(|k| !self.used.contains(&k.as_str()))
            .collect();
        match unknown.first() {
            None => Ok(()),
            Some(k) => Err(format!(
                "{}: unknown key {k:?} (known here: {})",
                self.what,
                self.used.join(", ")
            )),
        }
    }
}

fn law(k: &mut Keys<'_>, default: &str, decay: f64) -> Result<Law, String> {
    let decay = k.num("decay", decay)?;
    Ok(match k.string("law")?.unwrap_or(default) {
        "fractal" => Law::Fractal { decay },
        "morphogenic" => Law::Morphogenic,
        "independent" => Law::Independent,
        other => {
            return Err(format!(
                "{} law: {other:?} is not fractal, morphogenic or independent",
                k.what
            ));
        }
    })
}

/// A rock procedure from its keys.
fn rock(k: &mut Keys<'_>) -> Result<Procedure, String> {
    let amplitude = k.num("amplitude", 0.08)?;
    let law = law(k, "fractal", 0.5)?;
    let given_frequency = k.table.contains_key("frequency");
    let frequency = k.num("frequency", 2.0)?;
    let coords = match k.string("coords")?.unwrap_or("intrinsic") {
        "intrinsic" if given_frequency => {
            return Err(format!(
                "{}: frequency applies to coords = \"extrinsic\" (intrinsic rock has one value per vertex)",
                k.what
            ));
        }
        "intrinsic" => Coords::Intrinsic,
        "extrinsic" => Coords::Extrinsic { frequency },
        other => {
            return Err(format!(
                "{}: coords {other:?} is not intrinsic or extrinsic",
                k.what
            ));
        }
    };
    Ok(Procedure::Rock(Rock {
        amplitude,
        law,
        coords,
    }))
}

/// The procedure of a detail of type `kind` and its default seed spacing.
fn procedure(kind: &str, k: &mut Keys<'_>, what: &str) -> Result<(Procedure, f64), String> {
    Ok(match kind {
        "rock" => (rock(k)?, 0.5),
        "fbm" => (
            Procedure::Fbm(Fbm {
                amplitude: k.num("amplitude", 0.1)?,
                frequency: k.num("frequency", 2.0)?,
                law: law(k, "fractal", 0.5)?,
            }),
            0.5,
        ),
        "berry" => {
            let radius = k.num("radius", 0.25)?;
            (
                Procedure::Berry(Berry {
                    radius,
                    ratio: k.num("ratio", 0.5)?,
                    children: k.int("children", 6)?,
                    height: k.num("height", 1.0)?,
                }),
                2.0 * radius,
            )
        }
        "tentacle" | "mine" => {
            let mine = kind == "mine";
            (
                Procedure::Tentacle(Tentacle {
                    length: k.num("length", if mine { 0.08 } else { 0.05 })?,
                    theta: k.num("theta", 0.0)?,
                    alternate: k.boolean("alternate", !mine)?,
                    twist: k.boolean("twist", !mine)?,
                    reading: match k.string("reading")?.unwrap_or(if mine {
                        "literal"
                    } else {
                        "limb"
                    }) {
                        "literal" => TentacleReading::Literal,
                        "limb" => TentacleReading::Limb {
                            radius: k.num("radius", 0.35)?,
                            taper: k.num("taper", 0.7)?,
                        },
                        other => {
                            return Err(format!(
                                "{what}: unknown tentacle reading {other:?} (limb, literal)"
                            ));
                        }
                    },
                }),
                if mine { 0.6 } else { 0.8 },
            )
        }
        "mushroom" => (
            Procedure::Mushroom(Mushroom {
                height: k.num("height", 0.05)?,
                radius: k.num("radius", 0.2)?,
            }),
            0.9,
        ),
        "spur" => (
            Procedure::Spur(Spur {
                height: k.num("height", 3.0)?,
            }),
            0.5,
        ),
        other => {
            return Err(format!(
                "{what}: unknown detail type {other:?} (rock, fbm, berry, tentacle, mine, mushroom, spur)"
            ));
        }
    })
}

/// Where a detail grows: points `at`, base `vertices`, or a Poisson-disk set
/// with `spacing` (default `spacing`).
fn seeds(k: &mut Keys<'_>, t: f64, spacing: f64) -> Result<Seeds, String> {
    let at_what = format!("{} at", k.what);
    let seeds = if let Some(v) = k.get("at") {
        let Value::Array(a) = v else {
            return Err(format!("{at_what}: expected a list of [x, y, z] points"));
        };
        Seeds::Points(
            a.iter()
                .map(|p| point(p, t, &at_what))
                .collect::<Result<_, _>>()?,
        )
    } else if let Some(v) = k.ints("vertices")? {
        Seeds::Vertices(v.into_iter().map(|x| x as u32).collect())
    } else {
        Seeds::Poisson {
            spacing: k.num("spacing", spacing)?,
        }
    };
    // Keys that belong to other types are still unknown here.
    let _ = k.get("spacing");
    Ok(seeds)
}

/// A feature (and its layer name) from a table: `type` plus parameters.
///
/// # Errors
/// A message naming the bad or unknown key.
pub fn feature(table: &Table, t: f64, what: &str) -> Result<(String, Feature), String> {
    let mut k = Keys::new(table, what.to_string(), t);
    let kind = k.string("type")?.ok_or_else(|| {
        format!("{what}: missing type (rock, fbm, berry, tentacle, mine, mushroom, spur)")
    })?;
    k.what = format!("{what} ({kind})");
    let layer = k.string("layer")?.unwrap_or("main").to_string();
    let (procedure, spacing) = procedure(kind, &mut k, what)?;
    let levels = k.ints("levels")?;
    let seeds = seeds(&mut k, t, spacing)?;
    let f = Feature {
        procedure,
        seeds,
        levels,
    };
    let what_now = k.what.clone();
    k.finish()?;
    f.validate().map_err(|e| format!("{what_now}: {e}"))?;
    Ok((layer, f))
}

fn edit(table: &Table, t: f64, what: &str) -> Result<(String, Edit), String> {
    let mut k = Keys::new(table, what.to_string(), t);
    let layer = k.string("layer")?.unwrap_or("main").to_string();
    let at = match (k.get("at"), k.get("vertex")) {
        (Some(p), None) => Anchor::Point(point(p, t, &format!("{what} at"))?),
        (None, Some(Value::Integer(v))) if *v >= 0 => Anchor::Vertex(*v as u32),
        _ => return Err(format!("{what}: give either at = [x, y, z] or vertex = N")),
    };
    let levels = k.ints("levels")?.unwrap_or_else(|| vec![1, usize::MAX]);
    if levels.len() != 2 {
        return Err(format!("{what} levels: expected [first, last]"));
    }
    let e = Edit {
        at,
        radius: k.num("radius", 1.0)?,
        levels: (levels[0], levels[1]),
        factor: k.num("factor", 0.0)?,
    };
    k.finish()?;
    Ok((layer, e))
}

fn blend(table: &Table, t: f64) -> Result<(String, String, Blend, Option<AlphaFile>), String> {
    let mut k = Keys::new(table, "[blend]".into(), t);
    let a = k
        .string("a")?
        .ok_or("[blend]: missing a = \"layer\"")?
        .to_string();
    let b = k
        .string("b")?
        .ok_or("[blend]: missing b = \"layer\"")?
        .to_string();
    let width = k.num("width", 0.5)?;
    let plane = k.get("plane");
    let noise = k.get("noise");
    let map = k.string("alpha_map")?;
    let source = match (plane, noise, map) {
        (Some(Value::Table(p)), None, None) => {
            let mut pk = Keys::new(p, "[blend] plane".into(), t);
            let normal = point(
                pk.get("normal").ok_or("[blend] plane: missing normal")?,
                t,
                "[blend] plane normal",
            )?;
            let offset = pk.num("offset", 0.0)?;
            pk.finish()?;
            AlphaSource::Plane { normal, offset }
        }
        (None, Some(Value::Table(n)), None) => {
            let mut nk = Keys::new(n, "[blend] noise".into(), t);
            let frequency = nk.num("frequency", 1.5)?;
            let seed = nk.int("seed", 1)? as u32;
            nk.finish()?;
            AlphaSource::Noise { frequency, seed }
        }
        (None, None, Some(_)) => AlphaSource::Map(Vec::new()),
        _ => {
            return Err(
                "[blend]: give exactly one of plane = {..}, noise = {..}, alpha_map = \"file\""
                    .into(),
            );
        }
    };
    let paint = match k.string("alpha_from")? {
        None | Some("colour" | "color") => Paint::Colour,
        Some(name) => Paint::Scalar(name.to_string()),
    };
    let map = map.map(|path| AlphaFile {
        path: path.to_string(),
        paint,
    });
    k.finish()?;
    Ok((a, b, Blend { source, width }, map))
}

/// A blend's alpha-map file: a text column of values per base vertex, or a
/// mesh painted over the base (PLY or OBJ) read through `paint`.
#[derive(Clone, Debug, PartialEq)]
pub struct AlphaFile {
    /// The path, relative to the scene.
    pub path: String,
    /// What a painted mesh's alpha is read from (`alpha_from = "colour"`, the
    /// default, or the name of a per-vertex scalar).
    pub paint: Paint,
}

/// The scene's global keys: base, levels, seed, boundary, limit.
fn header(k: &mut Keys<'_>) -> Result<(String, usize, u64, Boundary, bool), String> {
    let base = k.string("base")?.unwrap_or("sphere").to_string();
    let levels = k.int("levels", 4)?;
    let seed = k.int("seed", 1)? as u64;
    let boundary = match k.string("boundary")?.unwrap_or("edge-only") {
        "edge-only" => Boundary::EdgeOnly,
        "edge-and-corner" => Boundary::EdgeAndCorner,
        other => {
            return Err(format!(
                "scene boundary: {other:?} is not edge-only or edge-and-corner"
            ));
        }
    };
    let limit = k.boolean("limit", false)?;
    Ok((base, levels, seed, boundary, limit))
}

/// `creases = [[a, b, sharpness], …]`.
fn creases(k: &mut Keys<'_>, t: f64) -> Result<Vec<(u32, u32, f64)>, String> {
    let Some(v) = k.get("creases") else {
        return Ok(Vec::new());
    };
    let Value::Array(a) = v else {
        return Err("scene creases: expected [[a, b, sharpness], ...]".into());
    };
    let mut out = Vec::new();
    for c in a {
        let item = match c {
            Value::Array(x) if x.len() == 3 => match (&x[0], &x[1]) {
                (Value::Integer(a), Value::Integer(b)) if *a >= 0 && *b >= 0 => {
                    Some((*a as u32, *b as u32, number(&x[2], t, "scene creases")?))
                }
                _ => None,
            },
            _ => None,
        };
        out.push(
            item.ok_or_else(|| format!("scene creases: {c} is not [vertex, vertex, sharpness]"))?,
        );
    }
    Ok(out)
}

/// The layers of a scene in order of first mention, by name.
#[derive(Default)]
struct Layers(BTreeMap<String, (usize, Layer)>);

impl Layers {
    fn add(&mut self, name: &str) {
        let n = self.0.len();
        self.0.entry(name.to_string()).or_insert((
            n,
            Layer {
                name: name.to_string(),
                ..Layer::default()
            },
        ));
    }

    fn get_mut(&mut self, name: &str) -> &mut Layer {
        &mut self.0.get_mut(name).expect("added").1
    }

    fn into_vec(self) -> Vec<Layer> {
        let mut layers: Vec<(usize, Layer)> = self.0.into_values().collect();
        layers.sort_by_key(|(i, _)| *i);
        layers.into_iter().map(|(_, l)| l).collect()
    }
}

/// Every table of the array `[[key]]`, each passed to `item` with its name
/// (`key N`); nothing when the key is absent.
fn tables<T>(
    k: &mut Keys<'_>,
    key: &'static str,
    mut item: impl FnMut(&Table, String) -> Result<T, String>,
) -> Result<Vec<T>, String> {
    let Some(v) = k.get(key) else {
        return Ok(Vec::new());
    };
    let Value::Array(a) = v else {
        return Err(format!("scene: {key} must be [[{key}]] tables"));
    };
    a.iter()
        .enumerate()
        .map(|(i, d)| {
            let Value::Table(d) = d else {
                return Err(format!("{key} {}: expected a table", i + 1));
            };
            item(d, format!("{key} {}", i + 1))
        })
        .collect()
}

/// A `[[surface]]` table: a captured fine mesh standing for a layer.
fn surface(d: &Table, t: f64, what: String) -> Result<(String, String), String> {
    let mut sk = Keys::new(d, what.clone(), t);
    let layer = sk
        .string("layer")?
        .ok_or_else(|| format!("{what}: missing layer = \"name\""))?
        .to_string();
    let file = sk
        .string("file")?
        .ok_or_else(|| format!("{what}: missing file = \"fine.ply\""))?
        .to_string();
    sk.finish()?;
    Ok((layer, file))
}

/// The `[blend]` table, its layers checked against those mentioned.
type SceneBlend = (Option<(String, String, Blend)>, Option<AlphaFile>);

fn scene_blend(k: &mut Keys<'_>, t: f64, layers: &Layers) -> Result<SceneBlend, String> {
    match k.get("blend") {
        None => Ok((None, None)),
        Some(Value::Table(b)) => {
            let (a, bb, how, map) = blend(b, t)?;
            for name in [&a, &bb] {
                if !layers.0.contains_key(name) {
                    return Err(format!("[blend]: no detail is in layer {name:?}"));
                }
            }
            Ok((Some((a, bb, how)), map))
        }
        Some(_) => Err("scene: blend must be a [blend] table".into()),
    }
}

/// The `[shade]` table: the planet post-shader's settings.
fn shade(k: &mut Keys<'_>, t: f64) -> Result<Option<Planet>, String> {
    match k.get("shade") {
        None => Ok(None),
        Some(Value::Table(s)) => {
            let mut sk = Keys::new(s, "[shade]".into(), t);
            match sk.string("kind")?.unwrap_or("planet") {
                "planet" => {}
                other => return Err(format!("[shade] kind: {other:?} is not planet")),
            }
            let d = Planet::default();
            let p = Planet {
                sea_level: sk.num("sea_level", d.sea_level)?,
                relief: sk.num("relief", d.relief)?,
                mountain: sk.num("mountain", d.mountain)?,
                snow: sk.num("snow", d.snow)?,
            };
            sk.finish()?;
            Ok(Some(p))
        }
        Some(_) => Err("scene: shade must be a [shade] table".into()),
    }
}

/// `mode` with its `[shade]`.
fn mode(k: &mut Keys<'_>, t: f64) -> Result<Mode, String> {
    let mode_name = k.string("mode")?.unwrap_or("displace").to_string();
    match (mode_name.as_str(), shade(k, t)?) {
        ("displace", None) => Ok(Mode::Displace),
        ("displace", Some(_)) => {
            Err("[shade] needs mode = \"scalar\" (the shader maps a scalar field)".into())
        }
        ("scalar", s) => Ok(Mode::Scalar(s.unwrap_or_default())),
        (other, _) => Err(format!("scene mode: {other:?} is not displace or scalar")),
    }
}

/// Parses a scene at animation time `t`.
///
/// # Errors
/// A message naming the bad key (TOML syntax errors included).
pub fn parse(text: &str, t: f64) -> Result<Scene, String> {
    let table: Table = text.parse().map_err(|e| format!("scene TOML: {e}"))?;
    let mut k = Keys::new(&table, "scene".into(), t);
    let (base, levels, seed, boundary, limit) = header(&mut k)?;
    let creases = creases(&mut k, t)?;
    let mut layers = Layers::default();
    let feats = tables(&mut k, "detail", |d, what| feature(d, t, &what))?;
    let surfaces = tables(&mut k, "surface", |d, what| surface(d, t, what))?;
    let edits = tables(&mut k, "edit", |d, what| edit(d, t, &what))?;
    // Layers in order of first mention: details, then surfaces, then edits.
    for name in feats
        .iter()
        .map(|(l, _)| l)
        .chain(surfaces.iter().map(|(l, _)| l))
        .chain(edits.iter().map(|(l, _)| l))
    {
        layers.add(name);
    }
    let (blend, alpha_map) = scene_blend(&mut k, t, &layers)?;
    let mode = mode(&mut k, t)?;
    k.finish()?;
    for (layer, f) in feats {
        layers.get_mut(&layer).features.push(f);
    }
    for (layer, e) in edits {
        layers.get_mut(&layer).edits.push(e);
    }
    for (layer, _) in &surfaces {
        let l = layers.get_mut(layer);
        if !l.features.is_empty() || !l.edits.is_empty() {
            return Err(format!(
                "layer {layer:?} has a captured surface and details or edits; give the details their own layer and blend"
            ));
        }
    }
    Ok(Scene {
        base,
        levels,
        seed,
        boundary,
        limit,
        layers: layers.into_vec(),
        blend,
        alpha_map,
        mode,
        creases,
        surfaces,
    })
}

/// A `--detail` argument (`name:key=value,…`, with `a..b` for an animated
/// number and `;` between list items) as a feature.
///
/// # Errors
/// A message naming the bad parameter.
pub fn feature_from_spec(spec: &str, t: f64) -> Result<Feature, String> {
    let (name, params) = spec.split_once(':').unwrap_or((spec, ""));
    let mut table = Table::new();
    table.insert("type".into(), Value::String(name.trim().into()));
    for kv in params.split(',').filter(|s| !s.trim().is_empty()) {
        let (key, v) = kv
            .split_once('=')
            .ok_or_else(|| format!("⟨detail⟩ {name}: {kv:?} is not key=value"))?;
        let v = v.trim();
        let parse_num = |x: &str| {
            x.trim()
                .parse::<f64>()
                .map_err(|_| format!("⟨detail⟩ {name}: {x:?} is not a number"))
        };
        let value = if let Some((a, b)) = v.split_once("..") {
            Value::Array(vec![
                Value::Float(parse_num(a)?),
                Value::Float(parse_num(b)?),
            ])
        } else if v.contains(';') {
            Value::Array(
                v.split(';')
                    .map(|x| {
                        x.trim()
                            .parse::<i64>()
                            .map(Value::Integer)
                            .map_err(|_| format!("⟨detail⟩ {name}: {x:?} is not a whole number"))
                    })
                    .collect::<Result<_, _>>()?,
            )
        } else if let Ok(i) = v.parse::<i64>() {
            if matches!(key.trim(), "children" | "levels" | "vertices") {
                Value::Integer(i)
            } else {
                Value::Float(i as f64)
            }
        } else if let Ok(x) = v.parse::<f64>() {
            Value::Float(x)
        } else if let Ok(b) = v.parse::<bool>() {
            Value::Boolean(b)
        } else {
            Value::String(v.into())
        };
        let value = match (key.trim(), value) {
            ("levels" | "vertices", Value::Integer(i)) => Value::Array(vec![Value::Integer(i)]),
            (_, v) => v,
        };
        table.insert(key.trim().into(), value);
    }
    feature(&table, t, "⟨detail⟩").map(|(_, f)| f)
}

/// A `--crease` argument `A-B:SHARPNESS` (e.g. `0-1:2` or `0-1:inf`).
///
/// # Errors
/// A message with the expected form.
pub fn crease_from_spec(spec: &str) -> Result<(u32, u32, f64), String> {
    let err = || format!("⟨crease⟩ {spec:?}: expected A-B:SHARPNESS, e.g. 0-1:2 or 0-1:inf");
    let (edge, s) = spec.split_once(':').ok_or_else(err)?;
    let (a, b) = edge.split_once('-').ok_or_else(err)?;
    let s: f64 = s.trim().parse().map_err(|_| err())?;
    Ok((
        a.trim().parse().map_err(|_| err())?,
        b.trim().parse().map_err(|_| err())?,
        s,
    ))
}

impl Scene {
    /// A scene of one layer, `main`, with `features`, in displacement mode: what
    /// `asperity subdiv --base … --detail …` describes without a scene file.
    pub fn single_layer(base: &str, levels: usize, seed: u64, features: Vec<Feature>) -> Self {
        Scene {
            base: base.to_string(),
            levels,
            seed,
            boundary: Boundary::EdgeOnly,
            limit: false,
            layers: vec![Layer {
                name: "main".into(),
                features,
                edits: Vec::new(),
            }],
            blend: None,
            alpha_map: None,
            mode: Mode::Displace,
            creases: Vec::new(),
            surfaces: Vec::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scenes_parse_animate_and_refuse_unknown_keys() {
        let s = parse(
            r#"
            base = "cube"
            levels = 3
            [[detail]]
            type = "rock"
            amplitude = [0.1, 0.3]
            [[detail]]
            type = "berry"
            layer = "b"
            radius = 0.2
            at = [[0, 0, 1]]
            levels = [1, 2]
            [[edit]]
            vertex = 2
            radius = 1.5
            levels = [2, 3]
            factor = 2.0
            [blend]
            a = "main"
            b = "b"
            width = 0.4
            plane = { normal = [1, 2, 0], offset = 0.0 }
            "#,
            0.5,
        )
        .unwrap();
        assert_eq!(s.levels, 3);
        assert_eq!(s.layers.len(), 2);
        let Procedure::Rock(r) = s.layers[0].features[0].procedure else {
            panic!()
        };
        assert!((r.amplitude - 0.2).abs() < 1e-15, "animated midway");
        assert_eq!(s.layers[1].features[0].levels, Some(vec![1, 2]));
        assert_eq!(s.layers[0].edits[0].levels, (2, 3));
        assert!(s.blend.is_some());
        for (bad, needle) in [
            (
                "[[detail]]\ntype = \"rock\"\namplitud = 1",
                "unknown key \"amplitud\"",
            ),
            ("[[detail]]\ntype = \"lava\"", "unknown detail type"),
            (
                "[[detail]]\ntype = \"berry\"\nratio = 2.0",
                "ratio must be < 1",
            ),
            ("levels = -1", "whole number"),
            (
                "[blend]\na = \"x\"\nb = \"y\"\nplane = { normal = [1, 0, 0] }",
                "no detail",
            ),
            ("mode = \"scalar\"\n[shade]\nkind = \"moon\"", "not planet"),
            ("levels = ", "scene TOML"),
            (
                "[[surface]]\nlayer = \"s\"\nfile = \"x.ply\"\n[[detail]]\ntype = \"rock\"\nlayer = \"s\"",
                "captured surface and details",
            ),
            ("[[surface]]\nlayer = \"s\"", "missing file"),
        ] {
            let e = parse(bad, 0.0).unwrap_err();
            assert!(e.contains(needle), "{bad:?}: {e}");
        }
        let f = feature_from_spec("tentacle:length=0.1..0.3,theta=1", 1.0).unwrap();
        let Procedure::Tentacle(t) = f.procedure else {
            panic!()
        };
        assert_eq!((t.length, t.theta, t.alternate), (0.3, 1.0, true));
        assert!(feature_from_spec("rock:decay=-2", 0.0).is_err());
        assert!(feature_from_spec("rock:amplitude", 0.0).is_err());
    }
}
