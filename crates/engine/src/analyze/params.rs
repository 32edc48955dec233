//! The parameters of `analyze` (one definition for every front end, issue
//! #36) and the options the report is computed with.

use asperity_analysis::hurst;
use clap::Args;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::params::{JobParams, Window as FitWindow, choice};

choice! {
    /// The reference surface removed before the analysis (the F-operator).
    pub enum Level {
        /// The mean for periodic data, the mean-slope plane for periodic data with a tilt, the
        /// least-squares plane otherwise.
        Auto = "auto",
        /// Nothing removed.
        Keep = "none",
        /// The mean height.
        Mean = "mean",
        /// The mean-gradient plane (keeps periodic data periodic).
        Slope = "slope",
        /// The least-squares plane.
        Plane = "plane",
        /// The least-squares quadratic.
        Quadratic = "quadratic",
    }
}

choice! {
    /// Which Hurst estimators run (the report's `hurst` is always the PSD fit's).
    pub enum HurstChoice {
        /// Every estimator, and the model-based fractal dimensions (triangulation,
        /// partitioning).
        All = "all",
        /// The PSD fit alone: no other estimator, no model-based dimension.
        Psd = "psd",
        /// The PSD fit and the profile PSDs along x and y.
        PsdProfiles = "psd-profiles",
        /// The PSD fit and the structure function.
        StructureFunction = "structure-function",
        /// The PSD fit and the variable bandwidth method.
        VariableBandwidth = "variable-bandwidth",
    }
}

impl HurstChoice {
    fn which(self) -> hurst::Which {
        match self {
            HurstChoice::All => hurst::Which::All,
            HurstChoice::Psd => hurst::Which::Psd,
            HurstChoice::PsdProfiles => hurst::Which::PsdProfiles,
            HurstChoice::StructureFunction => hurst::Which::StructureFunction,
            HurstChoice::VariableBandwidth => hurst::Which::VariableBandwidth,
        }
    }
}

choice! {
    /// What `analyze` does with missing (unmeasured) points.
    pub enum FillChoice {
        /// Fill them by the discrete Laplace equation through the measured points (the
        /// smoothest surface, adding no roughness of its own), as SurfaceTopography's
        /// interpolate_undefined_data.
        Harmonic = "harmonic",
        /// Fill them with the mean measured height.
        Mean = "mean",
        /// Refuse a field with missing points.
        Refuse = "refuse",
    }
}

impl FillChoice {
    /// The fill, or `None` to refuse.
    pub fn fill(self) -> Option<asperity_analysis::fill::Fill> {
        match self {
            FillChoice::Harmonic => Some(asperity_analysis::fill::Fill::Harmonic),
            FillChoice::Mean => Some(asperity_analysis::fill::Fill::Mean),
            FillChoice::Refuse => None,
        }
    }
}

choice! {
    /// Nesting indices (filter cut-offs) that are not given.
    pub enum Nesting {
        /// No filter where none is given: the primary surface (after the F-operator).
        Given = "given",
        /// ISO 25178-3's defaults for those not given: λc the largest of the series (…, 1, 2, 2.5,
        /// 5, 8, 10, …) at most a fifth of the shorter side, λs the smallest at least three
        /// sampling intervals.
        Iso = "iso",
    }
}

/// Whether data are periodic: decided from the data (`auto`), or given
/// (`yes`/`no`; in JSON also `true`/`false`/`null`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, JsonSchema, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Periodic {
    /// Decide from the data: opposite edges that join as smoothly as neighbouring samples.
    Auto,
    /// Periodic: no window, pairs wrap around.
    Yes,
    /// Not periodic: windowed spectra.
    No,
}

impl Periodic {
    /// `None` for auto, else whether periodic.
    pub fn given(self) -> Option<bool> {
        match self {
            Periodic::Auto => None,
            Periodic::Yes => Some(true),
            Periodic::No => Some(false),
        }
    }
}

impl<'de> Deserialize<'de> for Periodic {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct V;
        impl serde::de::Visitor<'_> for V {
            type Value = Periodic;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("auto, yes or no (or true, false, null)")
            }
            fn visit_bool<E: serde::de::Error>(self, v: bool) -> std::result::Result<Periodic, E> {
                Ok(if v { Periodic::Yes } else { Periodic::No })
            }
            fn visit_unit<E: serde::de::Error>(self) -> std::result::Result<Periodic, E> {
                Ok(Periodic::Auto)
            }
            fn visit_none<E: serde::de::Error>(self) -> std::result::Result<Periodic, E> {
                Ok(Periodic::Auto)
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> std::result::Result<Periodic, E> {
                match v {
                    "auto" => Ok(Periodic::Auto),
                    "yes" => Ok(Periodic::Yes),
                    "no" => Ok(Periodic::No),
                    _ => Err(E::unknown_variant(v, &["auto", "yes", "no"])),
                }
            }
        }
        d.deserialize_any(V)
    }
}

/// `analyze`: roughness numbers of a height field (ISO 25178 parameters,
/// profiles, PSD, five Hurst estimators, fractal dimensions), a mesh
/// (topology, curvature) or a point set, in the conventions of Jacobs, Junge &
/// Pastewka (2017).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct AnalyzeParams {
    /// Reference surface removed first (the F-operator).
    #[arg(long, value_enum, default_value_t = Self::default().level)]
    pub level: Level,
    /// Periodic data (a surface generated on a torus): auto decides from the data — opposite
    /// edges that join as smoothly as neighbouring samples mean periodic; measured data and
    /// crops are not. Non-periodic data get a window before every FFT.
    #[arg(long, value_enum, default_value_t = Self::default().periodic)]
    pub periodic: Periodic,
    /// Window of non-periodic data: hann, kaiser (β 8.6), kaiser:BETA, blackman-harris, none.
    #[arg(long, default_value_t = Self::default().window)]
    pub window: String,
    /// Log-spaced bins of the radially averaged PSD.
    #[schemars(range(min = 2, max = 1_000_000))]
    #[arg(long, default_value_t = Self::default().bins)]
    pub bins: usize,
    /// Hurst fit window QMIN,QMAX in rad/length (default: picked from the PSD, leaving out a
    /// long-wavelength roll-off and a short-wavelength noise floor); the real-space estimators
    /// use the matching wavelengths.
    #[arg(long, value_name = "QMIN,QMAX")]
    pub fit_window: Option<FitWindow>,
    /// Which Hurst estimators run: all (every estimator and the model-based fractal
    /// dimensions), or the PSD fit alone or with one other — a user who needs one pays for one.
    #[arg(long, value_enum, default_value_t = Self::default().hurst)]
    pub hurst: HurstChoice,
    /// Missing (unmeasured) points of measured data: Sa, Sq, Sp, Sv, Sz, Ssk and Sku are
    /// computed over the measured points; the spectra, correlations and estimators on the
    /// field with its holes filled this way (the report's `missing` says how many).
    #[arg(long, value_enum, default_value_t = Self::default().fill)]
    pub fill: FillChoice,
    #[serde(flatten)]
    #[command(flatten)]
    #[allow(missing_docs)]
    pub filters: Filters,
    /// Wolf pruning threshold of the feature parameters (Spd, S5p, Sha, …), in % of Sz: hills and
    /// dales whose height above (depth below) their lowest saddle is less are merged into their
    /// neighbour (ISO 25178-3's default 5).
    #[schemars(range(min = 0.0, max = 100.0))]
    #[arg(long, value_name = "PERCENT", default_value_t = Self::default().pruning)]
    pub pruning: f64,
    /// Count the motifs that touch the field's edge or a missing point in the feature parameters
    /// (ISO leaves these incomplete motifs out).
    #[arg(long)]
    pub incomplete_motifs: bool,
    /// Heights c (in the data's height unit, from the mean plane of the levelled, filtered
    /// surface) at which to give the material ratio Smr(c) (Rmr(c) on a profile), in %.
    #[schemars(with = "Option<crate::params::Heights>")]
    #[arg(long, value_delimiter = ',', value_name = "C1,C2,...")]
    pub material_ratio_at: Option<Vec<f64>>,
    /// Material ratios mr in % (0 … 100) at which to give the height Smc(mr) (Rmc(mr) on a
    /// profile).
    #[schemars(with = "Option<crate::params::Percents>")]
    #[arg(long, value_delimiter = ',', value_name = "MR1,MR2,...")]
    pub height_at_ratio: Option<Vec<f64>>,
}

impl Default for AnalyzeParams {
    fn default() -> Self {
        Self {
            level: Level::Auto,
            periodic: Periodic::Auto,
            window: "hann".into(),
            bins: 40,
            fit_window: None,
            hurst: HurstChoice::All,
            fill: FillChoice::Harmonic,
            filters: Filters::DEFAULT,
            pruning: asperity_analysis::feature::DEFAULT_PRUNING_PERCENT,
            incomplete_motifs: false,
            material_ratio_at: None,
            height_at_ratio: None,
        }
    }
}

impl JobParams for AnalyzeParams {
    const JOB: &'static str = "analyze";
    const SEEDED: bool = false;

    fn check(&self) -> Result<()> {
        if let Some(w) = &self.fit_window {
            w.check("fit_window", "QMIN,QMAX")?;
        }
        self.filters.check()
    }
}

impl AnalyzeParams {
    /// The analysis options of these parameters; `plots`: make the plots too.
    pub fn options(&self, plots: bool) -> AnalyzeOptions {
        AnalyzeOptions {
            level: self.level.name().to_owned(),
            bins: self.bins,
            fit_window: self.fit_window.map(|w| w.0),
            periodic: self.periodic.given(),
            window: self.window.clone(),
            estimators: self.hurst.which(),
            fill: self.fill.fill(),
            filters: self.filters,
            pruning: self.pruning,
            incomplete_motifs: self.incomplete_motifs,
            material_ratio_at: self.material_ratio_at.clone(),
            height_at_ratio: self.height_at_ratio.clone(),
            plots,
        }
    }
}

/// The S- and L-filters (ISO 16610; see `asperity_analysis::filter`): one
/// definition for `analyze` and `filter`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct Filters {
    /// S-filter nesting index λs, in the data's length unit: the Gaussian filter of ISO 16610-61
    /// (ISO 16610-21 on a profile) removes wavelengths shorter than λs after the F-operator.
    #[schemars(range(max = 1e12), extend("exclusiveMinimum" = 0.0))]
    #[arg(long, value_name = "LENGTH")]
    pub lambda_s: Option<f64>,
    /// L-filter nesting index λc, in the data's length unit: the Gaussian filter removes
    /// wavelengths longer than λc (the waviness), leaving the S-L surface every parameter is
    /// computed on.
    #[schemars(range(max = 1e12), extend("exclusiveMinimum" = 0.0))]
    #[arg(long, value_name = "LENGTH")]
    pub lambda_c: Option<f64>,
    /// Nesting indices not given: none (given), or ISO 25178-3's defaults from the data's extent
    /// and spacing (iso).
    #[arg(long, value_enum, default_value_t = Self::DEFAULT.nesting)]
    pub nesting: Nesting,
    /// Degree of the L-filter's Gaussian regression: 1 is ISO 16610-61's filter inside and keeps
    /// planes to the border; 0 renormalises the kernel at the border; 2 is the second-order
    /// regression filter (keeps quadratic forms everywhere).
    #[schemars(range(min = 0, max = 2))]
    #[arg(long, default_value_t = Self::DEFAULT.filter_degree)]
    pub filter_degree: usize,
    /// Robust L-filter (ISO 16610-71, Tukey's biweight): deep valleys and spikes do not pull the
    /// waviness towards them.
    #[arg(long)]
    pub robust: bool,
}

impl Default for Filters {
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl Filters {
    /// No filter at all: the defaults.
    pub const DEFAULT: Self = Self {
        lambda_s: None,
        lambda_c: None,
        nesting: Nesting::Given,
        filter_degree: asperity_analysis::filter::DEFAULT_ORDER,
        robust: false,
    };

    /// No filter at all.
    pub const NONE: Self = Self::DEFAULT;

    /// Whether ISO 25178-3's defaults fill in the indices not given.
    pub fn iso_defaults(&self) -> bool {
        self.nesting == Nesting::Iso
    }

    /// Whether any filter runs.
    pub fn any(&self) -> bool {
        self.iso_defaults() || self.lambda_s.is_some() || self.lambda_c.is_some()
    }

    /// Refuses λs not below λc and a robust filter without an L-filter.
    ///
    /// # Errors
    /// [`crate::EngineError::Invalid`] naming the parameters.
    pub fn check(&self) -> Result<()> {
        use asperity_core::wording::param;
        if let (Some(s), Some(c)) = (self.lambda_s, self.lambda_c)
            && s >= c
        {
            return Err(crate::error::invalid(format!(
                "{} ({s}) must be below {} ({c})",
                param("lambda_s"),
                param("lambda_c")
            )));
        }
        if self.robust && self.lambda_c.is_none() && !self.iso_defaults() {
            return Err(crate::error::invalid(format!(
                "{} filters the L-filter: give {} or {}",
                param("robust"),
                param("lambda_c"),
                asperity_core::wording::param_value("nesting", "iso")
            )));
        }
        Ok(())
    }
}

/// How a height field is analysed, named and defaulted like `asperity analyze`.
#[derive(Clone, Debug, PartialEq)]
pub struct AnalyzeOptions {
    /// Reference surface removed first: auto, none, mean, slope, plane,
    /// quadratic. Default auto: the mean for periodic data, the mean-slope plane
    /// for periodic data with a tilt, the least-squares plane otherwise.
    pub level: String,
    /// Log-spaced bins of the radial PSD. Default 40.
    pub bins: usize,
    /// Hurst fit window [q_min, q_max] in rad/length (default: chosen from the
    /// PSD, see `asperity_analysis::psd::auto_range`).
    pub fit_window: Option<[f64; 2]>,
    /// Periodic data or not; `None` decides from the data (the edge-jump test of
    /// `asperity_analysis::window::edge_ratio`).
    pub periodic: Option<bool>,
    /// Window of non-periodic data: hann (default), `kaiser[:β]`, blackman-harris, none.
    pub window: String,
    /// The Hurst estimators to run (all by default; with another choice the
    /// model-based fractal dimensions are left out too).
    pub estimators: hurst::Which,
    /// How missing points are filled (harmonic by default); `None` refuses
    /// a field with missing points.
    pub fill: Option<asperity_analysis::fill::Fill>,
    /// The S- and L-filters (none by default).
    pub filters: Filters,
    /// Wolf pruning of the feature parameters, in % of Sz (5 by default).
    pub pruning: f64,
    /// Whether motifs touching the edge or a missing point count (no by default).
    pub incomplete_motifs: bool,
    /// Heights at which to give Smr(c).
    pub material_ratio_at: Option<Vec<f64>>,
    /// Material ratios (%) at which to give Smc(mr).
    pub height_at_ratio: Option<Vec<f64>>,
    /// Also make the plots.
    pub plots: bool,
}

impl Default for AnalyzeOptions {
    /// [`AnalyzeParams`]' defaults, without plots.
    fn default() -> Self {
        AnalyzeParams::default().options(false)
    }
}
