//! What a front end needs to present a job's parameters (Python's
//! signatures and docs, the Blender add-on's properties, the `.pyi` stubs):
//! each field in order with its description, default, type, bounds and choices.

use serde_json::{Map, Value, json};

use super::{JobParams, field_names, resolve, schema};

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
    let (branches, nullable_branch) = forms(root, node);
    let mut nullable = nullable_branch;
    let mut body = Value::Null;
    match branches.as_slice() {
        [one] => body = one.clone(),
        // several forms (a number or a list, a number or a text): their types
        many => {
            let types: Vec<Value> = many.iter().filter_map(|b| b.get("type").cloned()).collect();
            out.insert("type".into(), Value::Array(types));
            if let Some(items) = many.iter().find_map(|b| b.get("items")) {
                out.insert("items".into(), items.clone());
            }
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

/// The non-null forms a value of `node` may take (nested `anyOf`s and
/// `$ref`s followed), and whether it may be null.
fn forms(root: &Value, node: &Value) -> (Vec<Value>, bool) {
    let node = resolve(root, node);
    match node.get("anyOf").and_then(Value::as_array) {
        Some(branches) => {
            let (mut all, mut nullable) = (Vec::new(), false);
            for b in branches {
                let (f, n) = forms(root, b);
                all.extend(f);
                nullable |= n;
            }
            (all, nullable)
        }
        None if node.get("type") == Some(&json!("null")) => (Vec::new(), true),
        None => (vec![node.clone()], false),
    }
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
