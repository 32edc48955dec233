//! One definition per job parameter (issue #36): every job's parameters are one
//! struct in the engine — documented fields with units and valid ranges, one
//! `Default`, serde — and every front end derives from it: the CLI flattens
//! the struct into its flags (help and defaults from here, through the `clap`
//! feature), Python turns keyword arguments into the same struct from JSON
//! ([`parse`]) and builds its signatures and docs from [`describe`], the
//! Blender add-on takes its properties' defaults from [`describe`] too.
//!
//! - **Ranges** are written once, as `#[schemars(range(...))]` on the field:
//!   they appear in the schema the front ends read, and [`validate`] checks a
//!   value against that same schema, so the two cannot disagree. A job's checks
//!   across fields are [`JobParams::check`].
//! - **Errors name the parameter** with [`asperity_core::wording::param`]
//!   markers; each front end spells them its own way (`--max-memory`,
//!   `max_memory=`).
//! - **Reproducible results**: [`record`] is what every report and Python
//!   result carries as `params` — the job, the schema version, the seed and
//!   every value that determines the output, defaults filled in; never the
//!   threads, budgets or paths (files stay byte-identical at any thread
//!   count). [`parse`] reads such a record back, so `--params FILE.json` and
//!   Python's `**params` re-run the job.

use std::fmt::Debug;

use asperity_core::wording::param;
use schemars::JsonSchema;
use serde::Serialize;
use serde::de::DeserializeOwned;
use serde_json::{Map, Value, json};

use crate::error::{EngineError, Result};

/// The version of the parameter records (`params.schema_version`); raised
/// when a field changes meaning, so an old record is refused, not misread.
pub const SCHEMA_VERSION: u32 = 1;

/// The seed every front end uses when none is given (`--seed`, `seed=`).
pub const DEFAULT_SEED: u64 = 7;

/// The keys a record holds besides the job's fields.
const RECORD_KEYS: [&str; 3] = ["job", "schema_version", "seed"];

/// The parameters of one engine job.
pub trait JobParams:
    Serialize + DeserializeOwned + JsonSchema + Clone + Default + Debug + Send + Sync + 'static
{
    /// The job's name, as the CLI's command (`growth dla`).
    const JOB: &'static str;
    /// Whether the seed changes the output (it is recorded only then).
    const SEEDED: bool = true;
    /// Fields that have no default: the job refuses to run without them
    /// ([`require`] in its [`JobParams::check`]), and Python's signature
    /// shows them without one.
    const REQUIRED: &'static [&'static str] = &[];

    /// Checks that involve more than one field (ranges of single fields are
    /// in the schema and checked by [`validate`]).
    ///
    /// # Errors
    /// [`EngineError::Invalid`] naming the parameters.
    fn check(&self) -> Result<()> {
        Ok(())
    }
}

/// The JSON Schema of `P` (draft 2020-12), with its fields' docs, defaults,
/// ranges and choices.
pub fn schema<P: JobParams>() -> Value {
    schemars::schema_for!(P).to_value()
}

/// Checks `p` against its schema's ranges, then [`JobParams::check`].
///
/// # Errors
/// [`EngineError::Invalid`] naming the first parameter out of range.
pub fn validate<P: JobParams>(p: &P) -> Result<()> {
    let schema = schema::<P>();
    let value = serde_json::to_value(p).map_err(|e| EngineError::Invalid(e.to_string()))?;
    let (Some(props), Value::Object(values)) = (schema.get("properties"), &value) else {
        return p.check();
    };
    for (name, field) in props.as_object().into_iter().flatten() {
        if let Some(v) = values.get(name) {
            check_value(&schema, field, v, name)?;
        }
    }
    p.check()
}

/// `v` against the (sub)schema `node` of `root`: numbers within their
/// bounds, array lengths and items, the non-null branch of an option.
fn check_value(root: &Value, node: &Value, v: &Value, name: &str) -> Result<()> {
    let node = resolve(root, node);
    if v.is_null() {
        // serde_json writes NaN and ±∞ as null: a number field that cannot be
        // null held one of them
        if is_number(node) && !nullable(root, node) {
            return Err(EngineError::Invalid(format!(
                "{} must be a finite number",
                param(name)
            )));
        }
        return Ok(());
    }
    if let Some(branches) = node.get("anyOf").and_then(Value::as_array) {
        for b in branches {
            let b = resolve(root, b);
            if b.get("type") != Some(&json!("null")) {
                check_value(root, b, v, name)?;
            }
        }
    }
    if let Some(x) = v.as_f64() {
        check_number(node, x, name)?;
    }
    if let Some(items) = v.as_array() {
        let len = items.len() as u64;
        let at_least = node.get("minItems").and_then(Value::as_u64).unwrap_or(0);
        let at_most = node
            .get("maxItems")
            .and_then(Value::as_u64)
            .unwrap_or(u64::MAX);
        if len < at_least || len > at_most {
            return Err(EngineError::Invalid(format!(
                "{} takes {}, got {len}",
                param(name),
                count_words(at_least, at_most)
            )));
        }
        if let Some(item) = node.get("items") {
            for x in items {
                check_value(root, item, x, name)?;
            }
        }
    }
    Ok(())
}

fn types(node: &Value) -> Vec<&str> {
    match node.get("type") {
        Some(Value::String(t)) => vec![t.as_str()],
        Some(Value::Array(ts)) => ts.iter().filter_map(Value::as_str).collect(),
        _ => Vec::new(),
    }
}

fn is_number(node: &Value) -> bool {
    types(node).contains(&"number")
}

fn nullable(root: &Value, node: &Value) -> bool {
    types(node).contains(&"null")
        || node
            .get("anyOf")
            .and_then(Value::as_array)
            .is_some_and(|bs| bs.iter().any(|b| types(resolve(root, b)).contains(&"null")))
}

fn count_words(at_least: u64, at_most: u64) -> String {
    match (at_least, at_most) {
        (a, b) if a == b => format!("{a} values"),
        (a, u64::MAX) => format!("at least {a} values"),
        (a, b) => format!("{a} to {b} values"),
    }
}

fn check_number(node: &Value, x: f64, name: &str) -> Result<()> {
    let bound = |key: &str| node.get(key).and_then(Value::as_f64);
    // (bound, inclusive)
    let lower = bound("minimum")
        .map(|b| (b, true))
        .or(bound("exclusiveMinimum").map(|b| (b, false)));
    let upper = bound("maximum")
        .map(|b| (b, true))
        .or(bound("exclusiveMaximum").map(|b| (b, false)));
    let above = lower.is_none_or(|(b, inc)| if inc { x >= b } else { x > b });
    let below = upper.is_none_or(|(b, inc)| if inc { x <= b } else { x < b });
    if x.is_finite() && above && below {
        return Ok(());
    }
    let range = match (lower, upper) {
        (Some((a, ai)), Some((b, bi))) => format!(
            "in {}{a}, {b}{}",
            if ai { '[' } else { '(' },
            if bi { ']' } else { ')' }
        ),
        (Some((a, true)), None) => format!("at least {a}"),
        (Some((a, false)), None) => format!("above {a}"),
        (None, Some((b, true))) => format!("at most {b}"),
        (None, Some((b, false))) => format!("below {b}"),
        (None, None) => "finite".to_owned(),
    };
    Err(EngineError::Invalid(format!(
        "{} must be {range}, got {x}",
        param(name)
    )))
}

/// `node`, or the definition its `$ref` points at.
fn resolve<'a>(root: &'a Value, node: &'a Value) -> &'a Value {
    match node.get("$ref").and_then(Value::as_str) {
        Some(r) => r
            .strip_prefix("#/$defs/")
            .and_then(|name| root.get("$defs")?.get(name))
            .unwrap_or(node),
        None => node,
    }
}

/// A parameter record read back: the job's parameters and the seed it gave.
#[derive(Clone, Debug)]
pub struct Parsed<P> {
    /// The parameters, validated.
    pub params: P,
    /// The record's seed, if it had one.
    pub seed: Option<u64>,
}

/// Parameters from a JSON object: the job's fields by name (missing ones take
/// their defaults), optionally with the record's `job`, `schema_version` and
/// `seed` (as [`record`] writes them). Unknown keys are refused, with the
/// parameters the job has.
///
/// # Errors
/// [`EngineError::Type`] for an unknown key or a value of the
/// wrong type, [`EngineError::Invalid`] for a value out of range or a record
/// of another job or schema version.
pub fn parse<P: JobParams>(value: &Value) -> Result<Parsed<P>> {
    let Value::Object(obj) = value else {
        return Err(type_error(format!(
            "the parameters of {} are a JSON object, got {value}",
            P::JOB
        )));
    };
    check_record(P::JOB, obj)?;
    let seed = match obj.get("seed") {
        None | Some(Value::Null) => None,
        Some(s) => Some(s.as_u64().ok_or_else(|| {
            type_error(format!(
                "{} must be a whole number ≥ 0, got {s}",
                param("seed")
            ))
        })?),
    };
    let fields: Map<String, Value> = obj
        .iter()
        .filter(|(k, _)| !RECORD_KEYS.contains(&k.as_str()))
        .map(|(k, v)| (k.clone(), v.clone()))
        .collect();
    let known = field_names::<P>();
    if let Some(unknown) = fields.keys().find(|k| !known.contains(k)) {
        return Err(type_error(format!(
            "{} has no parameter {unknown:?}; it takes {}",
            P::JOB,
            known.join(", ")
        )));
    }
    let params: P =
        serde_path_to_error::deserialize(Value::Object(fields.clone())).map_err(|e| {
            let at = e.path().to_string();
            let mut name = at.split(['.', '[']).next().unwrap_or(&at).to_owned();
            if !known.contains(&name) {
                // a flattened struct hides the path: the field that fails alone
                name = culprit::<P>(&fields).unwrap_or(name);
            }
            let message = format!("{}: {}", param(&name), e.inner());
            // a value of the wrong type is a TypeError; a bad value of the right
            // type (an unknown choice, a window out of order) a ValueError
            if e.inner().to_string().starts_with("invalid type") {
                type_error(message)
            } else {
                EngineError::Invalid(message)
            }
        })?;
    validate(&params)?;
    Ok(Parsed { params, seed })
}

/// The first field of `fields` that `P` cannot read on its own.
fn culprit<P: JobParams>(fields: &Map<String, Value>) -> Option<String> {
    fields.iter().find_map(|(k, v)| {
        let one = Value::Object(Map::from_iter([(k.clone(), v.clone())]));
        serde_json::from_value::<P>(one).is_err().then(|| k.clone())
    })
}

fn check_record(job: &str, obj: &Map<String, Value>) -> Result<()> {
    if let Some(j) = obj.get("job")
        && j.as_str() != Some(job)
    {
        return Err(EngineError::Invalid(format!(
            "these parameters are for {j}, not {job}"
        )));
    }
    match obj.get("schema_version") {
        None => Ok(()),
        Some(v) if v.as_u64() == Some(SCHEMA_VERSION.into()) => Ok(()),
        Some(v) => Err(EngineError::Invalid(format!(
            "these parameters were written with schema version {v}; this asperity reads version {SCHEMA_VERSION}"
        ))),
    }
}

fn type_error(message: String) -> EngineError {
    EngineError::Type(message)
}

/// A job the front ends can describe and run by name.
#[derive(Clone, Copy, Debug)]
pub struct JobEntry {
    /// [`JobParams::JOB`].
    pub name: &'static str,
    /// [`describe`] for the job.
    pub describe: fn() -> Value,
    /// [`schema`] for the job.
    pub schema: fn() -> Value,
}

impl JobEntry {
    /// The entry of `P`.
    pub fn of<P: JobParams>() -> Self {
        Self {
            name: P::JOB,
            describe: describe::<P>,
            schema: schema::<P>,
        }
    }
}

/// Every job whose parameters are described here, in the CLI's order.
pub fn jobs() -> Vec<JobEntry> {
    use crate::growth;
    vec![
        JobEntry::of::<growth::RdParams>(),
        JobEntry::of::<growth::RdsrParams>(),
        JobEntry::of::<growth::BdParams>(),
        JobEntry::of::<growth::dla::DlaParams>(),
        JobEntry::of::<crate::reconstruct::LevelSetParams>(),
        JobEntry::of::<crate::reconstruct::DlaTerrainParams>(),
        JobEntry::of::<crate::reconstruct::RdsrSphereParams>(),
        JobEntry::of::<crate::ca::CaRunParams>(),
        JobEntry::of::<crate::ca::CaRuleParams>(),
        JobEntry::of::<crate::ca::CaGalleryParams>(),
        JobEntry::of::<crate::ca::FacetParams>(),
        JobEntry::of::<crate::ca::InterpolateParams>(),
        JobEntry::of::<crate::surfca::SurfaceCaParams>(),
        JobEntry::of::<crate::subdiv::SubdivParams>(),
        JobEntry::of::<crate::ifs::IfsPresetParams>(),
        JobEntry::of::<crate::ifs::IfsCurveParams>(),
        JobEntry::of::<crate::ifs::IfsSurfaceParams>(),
        JobEntry::of::<crate::ifs::IfsDcfParams>(),
        JobEntry::of::<crate::ifs::IfsSdcfParams>(),
        JobEntry::of::<crate::ifs::IfsCurvatureParams>(),
        JobEntry::of::<crate::analyze::AnalyzeParams>(),
        JobEntry::of::<crate::synthesis::FbmParams>(),
        JobEntry::of::<crate::render::RenderParams>(),
        JobEntry::of::<crate::files::ConvertParams>(),
        JobEntry::of::<crate::files::InfoParams>(),
    ]
}

/// The entry of the job called `name` (`growth dla`).
///
/// # Errors
/// [`EngineError::Invalid`] naming the jobs there are.
pub fn job(name: &str) -> Result<JobEntry> {
    jobs().into_iter().find(|j| j.name == name).ok_or_else(|| {
        let names: Vec<&str> = jobs().iter().map(|j| j.name).collect();
        EngineError::Invalid(format!("no job {name:?}; there are: {}", names.join(", ")))
    })
}

/// `value`, or the error that a required parameter was not given.
///
/// # Errors
/// [`EngineError::Invalid`] naming the parameter.
pub fn require<T: Clone>(value: &Option<T>, name: &str) -> Result<T> {
    value
        .clone()
        .ok_or_else(|| EngineError::Invalid(format!("{} is required", param(name))))
}

/// `N` numbers: `a,b,c` on the command line, `[a, b, c]` in JSON (a circle
/// CX,CY,R, a point X,Y,Z, a light AZ,ALT).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Numbers<const N: usize>(pub [f64; N]);

impl<const N: usize> Serialize for Numbers<N> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        self.0.as_slice().serialize(s)
    }
}

impl<'de, const N: usize> serde::Deserialize<'de> for Numbers<N> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let v = Vec::<f64>::deserialize(d)?;
        let len = v.len();
        v.try_into()
            .map(Self)
            .map_err(|_| serde::de::Error::invalid_length(len, &format!("{N} numbers").as_str()))
    }
}

impl<const N: usize> JsonSchema for Numbers<N> {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        format!("Numbers{N}").into()
    }

    fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
        schemars::json_schema!({
            "type": "array",
            "items": {"type": "number"},
            "minItems": N,
            "maxItems": N,
        })
    }
}

impl<const N: usize> std::str::FromStr for Numbers<N> {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let v: Vec<f64> = s
            .split(',')
            .map(|x| x.trim().parse::<f64>())
            .collect::<std::result::Result<_, _>>()
            .map_err(|_| format!("{s:?} is not {N} numbers separated by commas"))?;
        v.try_into()
            .map(Self)
            .map_err(|_| format!("{s:?} is not {N} numbers separated by commas"))
    }
}

impl<const N: usize> std::fmt::Display for Numbers<N> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let parts: Vec<String> = self.0.iter().map(f64::to_string).collect();
        f.write_str(&parts.join(","))
    }
}

/// A size in cells or pixels, `WxH` on the command line, `[W, H]` in JSON.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize, JsonSchema)]
#[serde(from = "[usize; 2]", into = "[usize; 2]")]
#[schemars(with = "[usize; 2]")]
pub struct Size2(pub [usize; 2]);

impl From<[usize; 2]> for Size2 {
    fn from(v: [usize; 2]) -> Self {
        Self(v)
    }
}

impl From<Size2> for [usize; 2] {
    fn from(v: Size2) -> Self {
        v.0
    }
}

impl std::str::FromStr for Size2 {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let err = || format!("{s:?} is not WIDTHxHEIGHT, e.g. 1024x768");
        let (w, h) = s.split_once(['x', 'X', '×']).ok_or_else(err)?;
        let p = |v: &str| v.trim().parse::<usize>().map_err(|_| err());
        Ok(Self([p(w)?, p(h)?]))
    }
}

impl std::fmt::Display for Size2 {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}x{}", self.0[0], self.0[1])
    }
}

/// The largest parameter file read (a report is a few kilobytes).
const MAX_PARAMS_FILE: u64 = 16 << 20;

/// The parameters in a JSON file: a `--json` report's `params`, or the file's
/// object itself.
///
/// # Errors
/// [`EngineError::File`] when it cannot be read, [`EngineError::Invalid`] when
/// it is not JSON, too large, or holds no object.
pub fn read_file(path: &std::path::Path) -> Result<Value> {
    let len = std::fs::metadata(path)
        .map_err(|e| asperity_io::IoError::os(path, e))?
        .len();
    if len > MAX_PARAMS_FILE {
        return Err(EngineError::Invalid(format!(
            "{} holds {len} bytes: too large for parameters",
            path.display()
        )));
    }
    let text = crate::files::read_text(path)?;
    let value: Value = serde_json::from_str(&text)
        .map_err(|e| EngineError::Invalid(format!("{} is not JSON: {e}", path.display())))?;
    let value = match value.get("params") {
        Some(p) if p.is_object() => p.clone(),
        _ => value,
    };
    if !value.is_object() {
        return Err(EngineError::Invalid(format!(
            "{} holds no parameters (a JSON object, or a report with `params`)",
            path.display()
        )));
    }
    Ok(value)
}

/// The record of a run: `job`, `schema_version`, `seed` (for seeded jobs) and
/// every field of `p`, in the struct's order.
pub fn record<P: JobParams>(p: &P, seed: u64) -> Value {
    let mut obj = Map::new();
    obj.insert("job".into(), json!(P::JOB));
    obj.insert("schema_version".into(), json!(SCHEMA_VERSION));
    if P::SEEDED {
        obj.insert("seed".into(), json!(seed));
    }
    if let Value::Object(fields) = serde_json::to_value(p).unwrap_or(Value::Null) {
        for name in field_names::<P>() {
            if let Some(v) = fields.get(&name) {
                obj.insert(name, v.clone());
            }
        }
    }
    Value::Object(obj)
}

/// The field names of `P` in the order the struct declares them (serde's
/// serialisation order, which a JSON map does not keep).
pub fn field_names<P: JobParams>() -> Vec<String> {
    let text = serde_json::to_string(&P::default()).unwrap_or_default();
    serde_json::from_str::<OrderedKeys>(&text)
        .map(|k| k.0)
        .unwrap_or_default()
}

/// The keys of a JSON object in the order they appear.
struct OrderedKeys(Vec<String>);

impl<'de> serde::Deserialize<'de> for OrderedKeys {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct Keys;
        impl<'de> serde::de::Visitor<'de> for Keys {
            type Value = OrderedKeys;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a JSON object")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                mut map: A,
            ) -> std::result::Result<OrderedKeys, A::Error> {
                let mut keys = Vec::new();
                while let Some((k, _)) = map.next_entry::<String, serde::de::IgnoredAny>()? {
                    keys.push(k);
                }
                Ok(OrderedKeys(keys))
            }
        }
        d.deserialize_map(Keys)
    }
}

/// What a front end needs to present `P`'s parameters: for each field in
/// order its name, description, default, JSON type, bounds and choices (with
/// their descriptions), plus the job's name and whether it takes a seed.
pub fn describe<P: JobParams>() -> Value {
    let schema = schema::<P>();
    let defaults = serde_json::to_value(P::default()).unwrap_or(Value::Null);
    let props = schema.get("properties").cloned().unwrap_or(Value::Null);
    let fields: Vec<Value> = field_names::<P>()
        .into_iter()
        .map(|name| {
            let node = props.get(&name).cloned().unwrap_or(Value::Null);
            describe_field(&schema, &name, &node, defaults.get(&name))
        })
        .collect();
    let fields: Vec<Value> = fields
        .into_iter()
        .map(|mut f| {
            let required = f["name"].as_str().is_some_and(|n| P::REQUIRED.contains(&n));
            f["required"] = json!(required);
            f
        })
        .collect();
    json!({
        "job": P::JOB,
        "description": schema.get("description"),
        "seeded": P::SEEDED,
        "fields": fields,
    })
}

fn describe_field(root: &Value, name: &str, node: &Value, default: Option<&Value>) -> Value {
    let mut out = Map::new();
    out.insert("name".into(), json!(name));
    out.insert(
        "description".into(),
        node.get("description").cloned().unwrap_or(json!("")),
    );
    out.insert("default".into(), default.cloned().unwrap_or(Value::Null));
    let mut nullable = false;
    let mut body = resolve(root, node).clone();
    if let Some(branches) = body.get("anyOf").and_then(Value::as_array).cloned() {
        nullable = branches
            .iter()
            .any(|b| resolve(root, b).get("type") == Some(&json!("null")));
        if let Some(b) = branches
            .iter()
            .map(|b| resolve(root, b))
            .find(|b| b.get("type") != Some(&json!("null")))
        {
            body = b.clone();
        }
    }
    if let Some(t) = body.get("type") {
        let types: Vec<&Value> = match t {
            Value::Array(ts) => ts.iter().collect(),
            t => vec![t],
        };
        nullable |= types.iter().any(|t| *t == "null");
        if let Some(t) = types.into_iter().find(|t| *t != "null") {
            out.insert("type".into(), t.clone());
        }
    }
    if let Some(choices) = choices(&body) {
        out.insert("type".into(), json!("string"));
        out.insert("choices".into(), choices);
    }
    for key in [
        "minimum",
        "maximum",
        "exclusiveMinimum",
        "exclusiveMaximum",
        "minItems",
        "maxItems",
        "items",
    ] {
        if let Some(v) = node.get(key).or_else(|| body.get(key)) {
            out.insert(key.into(), v.clone());
        }
    }
    out.insert("nullable".into(), json!(nullable));
    Value::Object(out)
}

/// The choices of an enum schema (`oneOf` of constants with descriptions, or
/// a plain `enum`), as `[{"value", "description"}]`.
fn choices(node: &Value) -> Option<Value> {
    if let Some(values) = node.get("enum").and_then(Value::as_array) {
        return Some(Value::Array(
            values
                .iter()
                .map(|v| json!({"value": v, "description": ""}))
                .collect(),
        ));
    }
    let branches = node.get("oneOf")?.as_array()?;
    branches
        .iter()
        .map(|b| {
            let value = b
                .get("const")
                .or_else(|| b.get("enum").and_then(|e| e.get(0)))?;
            Some(json!({"value": value, "description": b.get("description").unwrap_or(&json!(""))}))
        })
        .collect::<Option<Vec<_>>>()
        .map(Value::Array)
}

/// Declares a choice of a job parameter: an enum whose variants are the
/// choices, each with its name, written once. From it come the parsing and
/// display (`FromStr`, `Display`, clap's `ValueEnum` with the doc comments as
/// help), the serde form (the same names) and the schema (the doc comments as
/// the choices' descriptions).
///
/// ```text
/// choice! {
///     /// Plane seeds: what happens at the lattice's x and y sides.
///     pub enum Sides {
///         /// The lattice wraps (sizes multiples of 8).
///         Periodic = "periodic",
///         /// Reflecting walls.
///         Walls = "walls",
///     }
/// }
/// ```
macro_rules! choice {
    (
        $(#[$meta:meta])*
        $vis:vis enum $name:ident {
            $( $(#[$vmeta:meta])* $variant:ident = $text:literal ),+ $(,)?
        }
    ) => {
        $(#[$meta])*
        #[derive(
            Clone, Copy, Debug, PartialEq, Eq, Hash,
            serde::Serialize, serde::Deserialize, schemars::JsonSchema, clap::ValueEnum,
        )]
        $vis enum $name {
            $(
                $(#[$vmeta])*
                #[serde(rename = $text)]
                #[value(name = $text)]
                $variant
            ),+
        }

        impl $name {
            /// Every choice, in order.
            pub const ALL: &'static [Self] = &[$(Self::$variant),+];

            /// The choice's name (`--flag NAME`, `key="NAME"`).
            pub fn name(self) -> &'static str {
                match self {
                    $(Self::$variant => $text),+
                }
            }
        }

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.name())
            }
        }

        impl std::str::FromStr for $name {
            type Err = String;
            fn from_str(s: &str) -> std::result::Result<Self, String> {
                Self::ALL
                    .iter()
                    .copied()
                    .find(|c| c.name().eq_ignore_ascii_case(s))
                    .ok_or_else(|| {
                        let names: Vec<&str> = Self::ALL.iter().map(|c| c.name()).collect();
                        format!("{s:?} is not one of: {}", names.join(", "))
                    })
            }
        }
    };
}
pub(crate) use choice;

/// Two numbers `A,B`: a fit window (monolayers, or wavenumbers), 0 < A < B
/// ([`Window::check`], called by the jobs that take one). On the command
/// line `A,B`; in JSON `[A, B]`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize, JsonSchema)]
#[serde(from = "[f64; 2]", into = "[f64; 2]")]
#[schemars(with = "[f64; 2]")]
pub struct Window(pub [f64; 2]);

impl From<[f64; 2]> for Window {
    fn from(w: [f64; 2]) -> Self {
        Self(w)
    }
}

impl From<Window> for [f64; 2] {
    fn from(w: Window) -> Self {
        w.0
    }
}

impl Window {
    /// Checks 0 < A < B for the parameter `name`, whose parts are called
    /// `parts` in the message (`TMIN,TMAX`).
    ///
    /// # Errors
    /// [`EngineError::Invalid`] naming the parameter.
    pub fn check(&self, name: &str, parts: &str) -> Result<()> {
        let [a, b] = self.0;
        if a > 0.0 && b > a && b.is_finite() {
            return Ok(());
        }
        let (lo, hi) = parts.split_once(',').unwrap_or(("A", "B"));
        Err(EngineError::Invalid(format!(
            "{} takes {parts} with 0 < {lo} < {hi}, got {:?}",
            param(name),
            self.0.to_vec()
        )))
    }
}

impl std::str::FromStr for Window {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let v: Vec<f64> = s
            .split(',')
            .map(|x| x.trim().parse::<f64>())
            .collect::<std::result::Result<_, _>>()
            .map_err(|_| format!("{s:?} is not A,B (two numbers)"))?;
        match v.as_slice() {
            [a, b] => Ok(Self([*a, *b])),
            _ => Err(format!("{s:?} is not A,B (two numbers)")),
        }
    }
}

impl std::fmt::Display for Window {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{},{}", self.0[0], self.0[1])
    }
}

/// A lattice size as given: one number N (a cube, or an N × N square in 2-D),
/// `NXxNZ` in 2-D, or `NXxNYxNZ`. On the command line `64`, `64x32`,
/// `64x64x32`; in JSON `64` or `[64, 64, 32]`. [`LatticeSize::resolve`] turns
/// it into the simulator's `[nx, ny, nz]` (`[nx, 1, nz]` in 2-D), the same for
/// every front end.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, JsonSchema)]
#[serde(into = "Vec<usize>")]
#[schemars(with = "SizeForm")]
pub struct LatticeSize(Vec<usize>);

/// The JSON forms of a [`LatticeSize`] (for its schema).
#[derive(JsonSchema)]
#[allow(dead_code)]
enum SizeForm {
    /// One number N.
    One(#[schemars(range(min = 1))] usize),
    /// One to three numbers.
    Many(#[schemars(length(min = 1, max = 3))] Vec<usize>),
}

impl<'de> serde::Deserialize<'de> for LatticeSize {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct Sides;
        impl<'de> serde::de::Visitor<'de> for Sides {
            type Value = Vec<usize>;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a lattice size: N or [NX, NY, NZ] (or [NX, NZ] in 2-D)")
            }
            fn visit_u64<E: serde::de::Error>(self, n: u64) -> std::result::Result<Vec<usize>, E> {
                usize::try_from(n).map(|n| vec![n]).map_err(E::custom)
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> std::result::Result<Vec<usize>, A::Error> {
                let mut v = Vec::new();
                while let Some(n) = seq.next_element::<usize>()? {
                    v.push(n);
                }
                Ok(v)
            }
        }
        let v = d.deserialize_any(Sides)?;
        LatticeSize::from_sides(v).map_err(serde::de::Error::custom)
    }
}

impl LatticeSize {
    fn from_sides(v: Vec<usize>) -> std::result::Result<Self, String> {
        if v.is_empty() || v.len() > 3 || v.contains(&0) {
            return Err(format!(
                "a lattice size is 1 to 3 sides, none zero (N, NXxNZ or NXxNYxNZ), got {v:?}"
            ));
        }
        Ok(Self(v))
    }
}

impl From<LatticeSize> for Vec<usize> {
    fn from(s: LatticeSize) -> Self {
        s.0
    }
}

impl LatticeSize {
    /// A size of these numbers (1 to 3 of them, none zero).
    ///
    /// # Errors
    /// [`EngineError::Invalid`] otherwise.
    pub fn new(sides: &[usize]) -> Result<Self> {
        Self::from_sides(sides.to_vec()).map_err(EngineError::Invalid)
    }

    /// An N × N × N lattice.
    pub fn cube(n: usize) -> Self {
        Self(vec![n; 3])
    }

    /// The sides as given.
    pub fn sides(&self) -> &[usize] {
        &self.0
    }

    /// The `[nx, ny, nz]` lattice of a `dim`-dimensional run: N gives N³
    /// (N × 1 × N in 2-D), NXxNZ a 2-D lattice NX × 1 × NZ, NXxNYxNZ itself.
    ///
    /// # Errors
    /// [`EngineError::Invalid`] when the count of numbers does not fit `dim`.
    pub fn resolve(&self, dim: usize) -> Result<[usize; 3]> {
        match (dim, self.0.as_slice()) {
            (3, [n]) => Ok([*n; 3]),
            (3, [x, y, z]) => Ok([*x, *y, *z]),
            (2, [n]) => Ok([*n, 1, *n]),
            (2, [x, z]) => Ok([*x, 1, *z]),
            (2, [x, 1, z]) => Ok([*x, 1, *z]),
            _ => Err(EngineError::Invalid(format!(
                "{} {self} does not fit {dim}-D: give N or {}",
                param("size"),
                if dim == 2 { "NXxNZ" } else { "NXxNYxNZ" }
            ))),
        }
    }
}

impl std::str::FromStr for LatticeSize {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let v: Vec<usize> = s
            .split(['x', 'X', '×'])
            .map(|x| x.trim().parse::<usize>())
            .collect::<std::result::Result<_, _>>()
            .map_err(|_| format!("{s:?} is not N, NXxNZ or NXxNYxNZ"))?;
        Self::from_sides(v)
    }
}

impl std::fmt::Display for LatticeSize {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let parts: Vec<String> = self.0.iter().map(usize::to_string).collect();
        f.write_str(&parts.join("x"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::growth::dla::{DlaParams, SeedShape, Sides};

    #[test]
    fn a_record_runs_the_same_job_again() {
        let p = DlaParams {
            seed_shape: SeedShape::Plane,
            size: Some(LatticeSize::new(&[64, 32, 48]).unwrap()),
            sides: Sides::Walls,
            ..DlaParams::DEFAULT
        };
        let r = record(&p, 11);
        assert_eq!(r["job"], "growth dla");
        assert_eq!(r["schema_version"], SCHEMA_VERSION);
        assert_eq!(r["seed"], 11);
        assert_eq!(r["size"], json!([64, 32, 48]));
        assert_eq!(r["sides"], "walls");
        let back = parse::<DlaParams>(&r).unwrap();
        assert_eq!(back.params, p);
        assert_eq!(back.seed, Some(11));
        // the record lists the fields in the struct's order
        let keys: Vec<&String> = r.as_object().unwrap().keys().collect();
        assert_eq!(keys.len(), 3 + field_names::<DlaParams>().len());
        assert_eq!(
            field_names::<DlaParams>()[..3],
            ["seed_shape", "size", "dim"]
        );
    }

    #[test]
    fn missing_fields_take_the_defaults_and_unknown_ones_are_refused() {
        let p = parse::<DlaParams>(&json!({"particles": 500}))
            .unwrap()
            .params;
        assert_eq!(
            p,
            DlaParams {
                particles: 500,
                ..DlaParams::DEFAULT
            }
        );
        let e = parse::<DlaParams>(&json!({"particle": 500})).unwrap_err();
        assert_eq!(e.kind(), crate::ErrorKind::Type);
        assert!(e.to_string().contains("no parameter \"particle\""), "{e}");
        let e = parse::<DlaParams>(&json!({"job": "growth rd"})).unwrap_err();
        assert!(
            e.to_string().contains("for \"growth rd\", not growth dla"),
            "{e}"
        );
        let e = parse::<DlaParams>(&json!({"schema_version": 99})).unwrap_err();
        assert!(e.to_string().contains("schema version 99"), "{e}");
        let e = parse::<DlaParams>(&json!({"particles": "many"})).unwrap_err();
        assert_eq!(e.kind(), crate::ErrorKind::Type, "{e}");
        let e = parse::<DlaParams>(&json!({"seed_shape": "blob"})).unwrap_err();
        assert_eq!(e.kind(), crate::ErrorKind::Invalid, "{e}");
        assert!(
            e.to_string().starts_with("⟨seed_shape⟩: unknown variant"),
            "{e}"
        );
    }

    #[test]
    fn ranges_come_from_the_schema() {
        let cases = [
            (json!({"stick": 0.0}), "⟨stick⟩ must be in (0, 1], got 0"),
            (json!({"stick": 1.5}), "⟨stick⟩ must be in (0, 1], got 1.5"),
            (json!({"dim": 4}), "⟨dim⟩ must be in [2, 3], got 4"),
            (
                json!({"launch_gap": 0.5}),
                "⟨launch_gap⟩ must be at least 1, got 0.5",
            ),
            (
                json!({"particles": 0}),
                "⟨particles⟩ must be at least 1, got 0",
            ),
        ];
        for (v, want) in cases {
            let e = parse::<DlaParams>(&v).unwrap_err();
            assert_eq!(e.to_string(), want);
        }
        // NaN and infinities (null once serialised) are refused by name
        let nan = DlaParams {
            stick: f64::NAN,
            ..DlaParams::DEFAULT
        };
        assert_eq!(
            validate(&nan).unwrap_err().to_string(),
            "⟨stick⟩ must be a finite number"
        );
        // the bounds a front end shows are those the check uses
        let d = describe::<DlaParams>();
        let stick = d["fields"]
            .as_array()
            .unwrap()
            .iter()
            .find(|f| f["name"] == "stick")
            .unwrap();
        assert_eq!(stick["exclusiveMinimum"], 0.0);
        assert_eq!(stick["maximum"], 1.0);
        assert_eq!(stick["default"], 1.0);
        let shape = &d["fields"][0];
        assert_eq!(shape["name"], "seed_shape");
        assert_eq!(
            shape["choices"].as_array().unwrap().len(),
            SeedShape::ALL.len()
        );
        assert_eq!(shape["choices"][1]["value"], "plane");
    }

    #[test]
    fn one_lattice_rule_for_every_front_end() {
        let n = LatticeSize::new(&[64]).unwrap();
        assert_eq!(n.resolve(3).unwrap(), [64, 64, 64]);
        assert_eq!(n.resolve(2).unwrap(), [64, 1, 64]);
        let xz: LatticeSize = "64x32".parse().unwrap();
        assert_eq!(xz.resolve(2).unwrap(), [64, 1, 32]);
        assert!(xz.resolve(3).is_err());
        let xyz: LatticeSize = serde_json::from_value(json!([8, 1, 16])).unwrap();
        assert_eq!(xyz.resolve(2).unwrap(), [8, 1, 16]);
        assert_eq!(xyz.resolve(3).unwrap(), [8, 1, 16]);
        let one: LatticeSize = serde_json::from_value(json!(5)).unwrap();
        assert_eq!(one, n_of(5));
        assert!("0x4x4".parse::<LatticeSize>().is_err());
        assert!(serde_json::from_value::<LatticeSize>(json!([1, 2, 3, 4])).is_err());
        assert_eq!(xyz.to_string(), "8x1x16");
    }

    fn n_of(n: usize) -> LatticeSize {
        LatticeSize::new(&[n]).unwrap()
    }

    #[test]
    fn choices_parse_and_print_their_names() {
        assert_eq!("Walls".parse::<Sides>().unwrap(), Sides::Walls);
        assert_eq!(Sides::Periodic.to_string(), "periodic");
        assert!(
            "wall"
                .parse::<Sides>()
                .unwrap_err()
                .contains("periodic, walls")
        );
        assert_eq!(serde_json::to_value(SeedShape::Image).unwrap(), "image");
    }
}
