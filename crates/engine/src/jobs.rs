//! Every engine job the front ends can describe and run by name (issue #36):
//! the registry Python's functions, the Blender add-on and the parity tests
//! read.

use serde_json::Value;

use crate::error::{EngineError, Result};
use crate::params::{JobParams, describe, schema};

/// A job the front ends can describe and run by name.
#[derive(Clone, Copy, Debug)]
pub struct JobEntry {
    /// [`JobParams::JOB`].
    pub name: &'static str,
    /// [`describe`] for the job.
    pub describe: fn() -> Value,
    /// [`schema`] for the job.
    pub schema: fn() -> Value,
    /// Parses and checks a JSON object of the job's parameters (as a record
    /// or Python's keywords give them).
    pub validate_defaults: fn(&Value) -> Result<()>,
}

impl JobEntry {
    /// The entry of `P`.
    pub fn of<P: JobParams>() -> Self {
        Self {
            name: P::JOB,
            describe: describe::<P>,
            schema: schema::<P>,
            validate_defaults: |v| crate::params::parse::<P>(v).map(|_| ()),
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
        JobEntry::of::<crate::analyze::FilterParams>(),
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Every job's defaults pass its own checks (a default outside the range
    /// the schema states would make every front end fail on defaults), its
    /// description lists its fields, and names are unique.
    #[test]
    fn every_job_is_described_and_its_defaults_are_valid() {
        let all = jobs();
        assert!(all.len() >= 25, "{} jobs", all.len());
        let mut names: Vec<&str> = all.iter().map(|j| j.name).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), all.len(), "unique names");
        for j in &all {
            let d = (j.describe)();
            assert_eq!(d["job"], j.name);
            let fields = d["fields"].as_array().unwrap();
            for f in fields {
                assert!(
                    f["description"].as_str().is_some_and(|s| !s.is_empty()),
                    "{}: {} has no description",
                    j.name,
                    f["name"]
                );
            }
            let defaults: serde_json::Map<String, Value> = fields
                .iter()
                .filter(|f| f["required"] != true)
                .map(|f| (f["name"].as_str().unwrap().to_owned(), f["default"].clone()))
                .collect();
            let required: Vec<&str> = fields
                .iter()
                .filter(|f| f["required"] == true)
                .map(|f| f["name"].as_str().unwrap())
                .collect();
            match (j.validate_defaults)(&Value::Object(defaults)) {
                Ok(()) => assert!(required.is_empty(), "{}: runs without {required:?}", j.name),
                // a job with required fields refuses its defaults alone, naming the first
                Err(e) => assert!(
                    required
                        .first()
                        .is_some_and(|r| e.to_string() == format!("⟨{r}⟩ is required")),
                    "{}: its defaults are refused: {e}",
                    j.name
                ),
            }
        }
        assert!(job("growth dla").is_ok());
        assert!(
            job("growth")
                .unwrap_err()
                .to_string()
                .contains("growth dla")
        );
    }
}
