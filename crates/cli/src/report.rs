//! The `--json` report: what a command did and measured.

use std::path::Path;
use std::time::Instant;

use serde::Serialize;
use serde_json::{Map, Value};

/// One file written.
#[derive(Serialize)]
pub struct Output {
    pub path: String,
    pub format: &'static str,
    pub bytes: u64,
}

/// Collects outputs and measurements; printed as JSON on stdout with `--json`.
#[derive(Serialize)]
pub struct Report {
    pub command: &'static str,
    pub version: &'static str,
    pub seed: u64,
    pub threads: usize,
    pub elapsed_s: f64,
    pub outputs: Vec<Output>,
    pub measurements: Map<String, Value>,
    pub warnings: Vec<String>,
    #[serde(skip)]
    started: Option<Instant>,
}

impl Report {
    pub fn new(command: &'static str, ctx: &crate::cli::Context) -> Self {
        Self {
            command,
            version: env!("CARGO_PKG_VERSION"),
            seed: ctx.seed,
            threads: ctx.threads,
            elapsed_s: 0.0,
            outputs: Vec::new(),
            measurements: Map::new(),
            warnings: Vec::new(),
            started: Some(Instant::now()),
        }
    }

    /// Records a written file (format from the extension, size from disk).
    pub fn output(&mut self, path: &Path) {
        let format = asperity_io::Format::from_path(path)
            .map(|f| f.info().name)
            .unwrap_or("other");
        let bytes = std::fs::metadata(path).map(|m| m.len()).unwrap_or(0);
        self.outputs.push(Output {
            path: path.display().to_string(),
            format,
            bytes,
        });
    }

    /// Records a measurement.
    pub fn measure(&mut self, key: &str, value: impl Serialize) {
        self.measurements.insert(
            key.to_owned(),
            serde_json::to_value(value).unwrap_or(Value::Null),
        );
    }

    /// Prints the report as JSON on stdout if `--json`.
    pub fn finish(mut self, ctx: &crate::cli::Context) -> anyhow::Result<()> {
        self.elapsed_s = self.started.map_or(0.0, |t| t.elapsed().as_secs_f64());
        if ctx.json {
            use std::io::Write;
            let mut out = std::io::stdout().lock();
            serde_json::to_writer_pretty(&mut out, &self)?;
            writeln!(out)?;
        }
        Ok(())
    }
}
