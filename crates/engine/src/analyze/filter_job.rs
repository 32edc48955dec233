//! `filter`: the scale-limited surface of a height field or profile as an
//! operation of its own (issue #56) — the F-operator (levelling, as
//! `analyze`), then the S- and L-filters of ISO 16610 (see [`super::iso`] and
//! `asperity_analysis::filter`) — with the surface and every removed
//! component as height fields: form + waviness + noise + surface = input.

use asperity_analysis::{areal, filter, level};
use asperity_core::{HeightField, MemoryBudget};
use clap::Args;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use serde_json::json;

use super::params::{AnalyzeOptions, Filters, Level, Nesting, Periodic};
use super::{iso, level_holed, prepare};
use crate::error::Result;
use crate::params::JobParams;
use crate::report::Measurements;

/// `filter`: the S-L (or S-F, F-L) surface of a height field or profile by
/// the Gaussian filters of ISO 16610, and what they removed. Without any
/// nesting index, ISO 25178-3's defaults (as `--nesting iso`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct FilterParams {
    /// Reference surface removed first (the F-operator), as analyze's.
    #[arg(long, value_enum, default_value_t = Self::default().level)]
    pub level: Level,
    /// Periodic data (the filters wrap around): auto decides from the data, as analyze does.
    #[arg(long, value_enum, default_value_t = Self::default().periodic)]
    pub periodic: Periodic,
    #[serde(flatten)]
    #[command(flatten)]
    #[allow(missing_docs)]
    pub filters: Filters,
}

impl Default for FilterParams {
    fn default() -> Self {
        Self {
            level: Level::Auto,
            periodic: Periodic::Auto,
            filters: Filters::DEFAULT,
        }
    }
}

impl JobParams for FilterParams {
    const JOB: &'static str = "filter";
    const SEEDED: bool = false;

    fn check(&self) -> Result<()> {
        self.filters.check()
    }
}

/// A filtered field and its parts.
#[derive(Clone, Debug)]
pub struct Filtered {
    /// The scale-limited surface.
    pub surface: HeightField,
    /// What the F-operator removed (the form).
    pub form: HeightField,
    /// What the L-filter removed (the waviness), with one.
    pub waviness: Option<HeightField>,
    /// What the S-filter removed (the short-wavelength noise), with one.
    pub noise: Option<HeightField>,
    /// The specification and the rms height of every part (`filter --json`).
    pub facts: Measurements,
    /// What the user should know (a nesting index out of its useful range).
    pub warnings: Vec<String>,
}

/// `h` levelled as `p` says (the F-operator), whether it is periodic, the
/// levelling and the report's `periodic` entry: as `analyze` decides them.
fn form_removed(
    h: &HeightField,
    p: &FilterParams,
) -> Result<(HeightField, bool, level::Level, serde_json::Value)> {
    let o = AnalyzeOptions {
        level: p.level.name().to_owned(),
        periodic: p.periodic.given(),
        ..AnalyzeOptions::default()
    };
    if h.has_missing() {
        let (levelled, how, periodic) = level_holed(h, &o)?;
        let source = if o.periodic.is_some() {
            "option"
        } else {
            "missing points"
        };
        let mode = json!({"value": periodic, "source": source, "edge_ratio": null});
        Ok((levelled, periodic, how, mode))
    } else {
        let p = prepare(h, &o)?;
        let mode = json!({"value": p.periodic, "source": p.source, "edge_ratio": p.ratio});
        Ok((p.levelled, p.periodic, p.level, mode))
    }
}

/// Bytes [`filter()`] holds at its peak over `h`: the filters' fields and the
/// four parts.
pub fn filter_bytes(h: &HeightField, p: &FilterParams) -> u64 {
    iso::filter_bytes(&p.filters, h.len(), h.has_missing()) + 4 * 8 * h.len() as u64
}

/// Levels `h` as `p` says, then applies its filters.
///
/// # Errors
/// The parameters' ([`crate::params::validate`]), the memory budget, a
/// nesting index below two sampling intervals, an infinite height.
pub fn filter(h: &HeightField, p: &FilterParams, budget: &MemoryBudget) -> Result<Filtered> {
    crate::params::validate(p)?;
    h.validate_measured()?;
    budget.check(filter_bytes(h, p), "filtering")?;
    let (levelled, periodic, how, mode) = form_removed(h, p)?;
    let form = h.with_data(filter::difference(h, &levelled))?;
    let mut warnings = Vec::new();
    let filters = if p.filters.any() {
        p.filters
    } else {
        Filters {
            nesting: Nesting::Iso,
            ..p.filters
        }
    };
    let stage = iso::scale_limited(levelled, periodic, &filters, &mut warnings)?;
    let sq = |f: &HeightField| areal::measured_heights(f).map(|m| m.Sq).ok();
    let mut facts = Measurements::default();
    facts.set("filter", stage.facts);
    facts.set("levelling", how);
    facts.set("periodic", mode);
    facts.set("window", "none");
    facts.set("size", h.dims());
    facts.set("spacing", h.spacing());
    facts.set(
        "Sq",
        json!({
            "input": sq(h),
            "surface": sq(&stage.surface),
            "form": sq(&form),
            "waviness": stage.waviness.as_ref().and_then(sq),
            "noise": stage.noise.as_ref().and_then(sq),
        }),
    );
    Ok(Filtered {
        surface: stage.surface,
        form,
        waviness: stage.waviness,
        noise: stage.noise,
        facts,
        warnings,
    })
}
