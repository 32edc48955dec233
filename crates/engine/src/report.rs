//! What a job did and measured: the files it wrote, its measurements and its
//! warnings — printed by the CLI with `--json`, written by the gallery as
//! `report.json`, returned to Python as a dict.

use std::path::Path;
use std::time::Instant;

use serde::Serialize;
use serde_json::{Map, Value};

/// One file written.
#[derive(Clone, Debug, Serialize)]
pub struct Output {
    /// The path as given.
    pub path: String,
    /// The format's name (from the extension), or `other`.
    pub format: &'static str,
    /// Its size on disk.
    pub bytes: u64,
}

/// Outputs, measurements and warnings of one command.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// The command, e.g. `growth dla`.
    pub command: &'static str,
    /// asperity's version.
    pub version: &'static str,
    /// The seed every random choice came from.
    pub seed: u64,
    /// Worker threads.
    pub threads: usize,
    /// Wall-clock seconds from [`Report::new`] to [`Report::stop_clock`].
    pub elapsed_s: f64,
    /// Files written, in order.
    pub outputs: Vec<Output>,
    /// Named measurements (sorted by name).
    pub measurements: Map<String, Value>,
    /// Warnings, in order.
    pub warnings: Vec<String>,
    /// The job's parameters as [`crate::params::record`] writes them: with
    /// them, `--params` (or Python's `**params`) runs the job again.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub params: Option<Value>,
    /// Parameters given as flags over those of a `--params` file.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub params_overridden: Vec<String>,
    /// The memory budget the job ran under and which limit set it
    /// (`{"bytes": …, "from": "cgroup"}`; see [`asperity_core::system_memory`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub memory_budget: Option<Value>,
    #[serde(skip)]
    started: Option<Instant>,
}

impl Report {
    /// A report for `command`, its clock started.
    pub fn new(command: &'static str, seed: u64, threads: usize) -> Self {
        Self {
            command,
            version: env!("CARGO_PKG_VERSION"),
            seed,
            threads,
            elapsed_s: 0.0,
            outputs: Vec::new(),
            measurements: Map::new(),
            warnings: Vec::new(),
            params: None,
            params_overridden: Vec::new(),
            memory_budget: None,
            started: Some(Instant::now()),
        }
    }

    /// Records a written file (format from the extension, size from disk).
    pub fn output(&mut self, path: &Path) {
        let format = asperity_io::Format::from_path(path)
            .map(|f| f.info().name)
            .unwrap_or("other");
        let bytes = asperity_io::staging::written_len(path).unwrap_or(0);
        self.outputs.push(Output {
            path: path.display().to_string(),
            format,
            bytes,
        });
    }

    /// Records the memory budget the job runs under.
    pub fn budget(&mut self, budget: &asperity_core::MemoryBudget) {
        self.memory_budget = Some(serde_json::json!({
            "bytes": budget.limit(),
            "from": budget.source().name(),
        }));
    }

    /// Records a measurement.
    pub fn measure(&mut self, key: &str, value: impl Serialize) {
        self.measurements.insert(key.to_owned(), to_value(value));
    }

    /// Records every measurement of `facts`.
    pub fn extend(&mut self, facts: Measurements) {
        self.measurements.extend(facts.0);
    }

    /// Records a warning.
    pub fn warn(&mut self, warning: impl Into<String>) {
        self.warnings.push(warning.into());
    }

    /// Sets [`Report::elapsed_s`] to the time since [`Report::new`].
    pub fn stop_clock(&mut self) {
        self.elapsed_s = self.started.map_or(0.0, |t| t.elapsed().as_secs_f64());
    }
}

/// A value as JSON (`null` if it cannot be one, e.g. a map with non-string keys).
pub fn to_value(value: impl Serialize) -> Value {
    serde_json::to_value(value).unwrap_or(Value::Null)
}

/// Named measurements of one job, as JSON values (keys sorted).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
#[serde(transparent)]
pub struct Measurements(pub Map<String, Value>);

impl Measurements {
    /// No measurements.
    pub fn new() -> Self {
        Self::default()
    }

    /// Sets `key` to `value`.
    pub fn set(&mut self, key: &str, value: impl Serialize) {
        self.0.insert(key.to_owned(), to_value(value));
    }

    /// The value of `key`.
    pub fn get(&self, key: &str) -> Option<&Value> {
        self.0.get(key)
    }

    /// The measurements as a JSON object.
    pub fn into_value(self) -> Value {
        Value::Object(self.0)
    }

    /// The measurements of a JSON object (anything else gives none).
    pub fn from_value(v: Value) -> Self {
        match v {
            Value::Object(m) => Self(m),
            _ => Self::default(),
        }
    }
}
