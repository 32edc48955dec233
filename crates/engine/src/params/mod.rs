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

mod command_line;
mod describe;
mod values;

pub use command_line::{CliJob, command_line};
pub use describe::describe;
pub(crate) use values::{Finite, Heights, Percents, Positive, Side};
pub use values::{LatticeSize, MAX_COORDINATE, MAX_SIDE, Numbers, Size2, Window};

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
    refuse_not_finite(p)?;
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

/// Refuses parameters that hold NaN or ±∞ anywhere (every number of every
/// job is finite), naming the first such field; before `p` goes through
/// JSON, which would write them as null.
///
/// # Errors
/// [`EngineError::Invalid`] naming the parameter.
pub fn refuse_not_finite<P: Serialize>(p: &P) -> Result<()> {
    match first_not_finite(p) {
        Some(name) => Err(EngineError::Invalid(format!(
            "{} must be a finite number",
            param(&name)
        ))),
        None => Ok(()),
    }
}

/// The first field of `p` that holds NaN or ±∞ anywhere in it. serde_json
/// writes them as null, which an optional field cannot tell from unset; a
/// CBOR value tree keeps them.
fn first_not_finite<P: Serialize>(p: &P) -> Option<String> {
    use ciborium::Value as V;
    fn finite(v: &V) -> bool {
        match v {
            V::Float(x) => x.is_finite(),
            V::Array(items) => items.iter().all(finite),
            V::Map(entries) => entries.iter().all(|(_, v)| finite(v)),
            V::Tag(_, v) => finite(v),
            _ => true,
        }
    }
    let V::Map(fields) = V::serialized(p).ok()? else {
        return None;
    };
    fields.iter().find_map(|(k, v)| {
        let name = k.as_text()?;
        (!finite(v)).then(|| name.to_owned())
    })
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

/// `value`, or the error that a required parameter was not given.
///
/// # Errors
/// [`EngineError::Invalid`] naming the parameter.
pub fn require<T: Clone>(value: &Option<T>, name: &str) -> Result<T> {
    value
        .clone()
        .ok_or_else(|| EngineError::Invalid(format!("{} is required", param(name))))
}

/// The largest parameter file read (a report is a few kilobytes).
const MAX_PARAMS_FILE: u64 = 16 << 20;

/// The parameters in a JSON file — a `--json` report's `params`, or the
/// file's object itself — or those a surface file records (a PLY, PNG, GSF…
/// that asperity wrote: [`asperity_io::metadata`]).
///
/// # Errors
/// [`EngineError::File`] when it cannot be read, [`EngineError::Invalid`] when
/// it is not JSON, too large, or holds no object, or a surface file records
/// no parameters.
pub fn read_file(path: &std::path::Path) -> Result<Value> {
    // A surface file asperity wrote records the parameters it was made with.
    let is_json = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    if !is_json && asperity_io::Format::from_path(path).is_ok() {
        return asperity_io::read_params(path)?.ok_or_else(|| {
            EngineError::Invalid(format!(
                "{} records no parameters (asperity records them in PLY, OBJ, glTF, PNG, EXR, \
                 GSF, .gwy, x3p and CSV files; a JSON report holds them for every job)",
                path.display()
            ))
        });
    }
    // Read at most one byte past the limit: a special file (`/dev/zero`, a
    // pipe) reports no size, so the size on disk cannot be trusted.
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| {
            std::io::Read::read_to_end(&mut std::io::Read::take(f, MAX_PARAMS_FILE + 1), &mut bytes)
        })
        .map_err(|e| asperity_io::IoError::os(path, e))?;
    if bytes.len() as u64 > MAX_PARAMS_FILE {
        return Err(EngineError::Invalid(format!(
            "{} holds more than {MAX_PARAMS_FILE} bytes: too large for parameters",
            path.display()
        )));
    }
    let text = String::from_utf8(bytes)
        .map_err(|_| EngineError::Invalid(format!("{} is not UTF-8 text", path.display())))?;
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
