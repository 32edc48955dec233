//! RD, RDSR and BD on a flat periodic substrate (kim-machiraju-thompson §4.1),
//! with the measurements a growth study needs: W(t), the growth exponent β by
//! three fits, and optionally the roughness exponent α from saturated widths.

use asperity_analysis::AnalysisError;
use asperity_analysis::psd::LogFit;
use asperity_analysis::scaling::{
    GrowthFit, growth_exponent, growth_exponent_intrinsic, roughness_exponent,
};
use asperity_core::{MemoryBudget, NoProgress, Progress, TimeBudget};
use asperity_growth::deposition::deposit_on_schedule;
use asperity_growth::interface_width::uniform_schedule;
use asperity_growth::{Deposit, DepositionParams, Lattice, Model, WidthSeries, deposit_ensemble};
use asperity_render::plot::{Plot, Series};
use rayon::prelude::*;
use serde_json::{Value, json};

use crate::error::{Result, ensure, invalid};
use crate::estimate;
use crate::plots::{fit_line, log_log, points};
use crate::report::Measurements;

/// A flat-substrate growth run, named and defaulted like `asperity growth rd|rdsr|bd`.
#[derive(Clone, Debug, PartialEq)]
pub struct DepositionJob {
    /// RD, RDSR (with its relaxation radius) or BD.
    pub model: Model,
    /// Columns per side L. Default 256.
    pub size: usize,
    /// Substrate dimension d, 1 or 2. Default 2.
    pub dim: usize,
    /// Monolayers T. Default 100.
    pub layers: f64,
    /// Independent runs averaged for W(t). Default 1.
    pub runs: usize,
    /// Max-height binning side ε (must divide L). Default none.
    pub bin: Option<usize>,
    /// Width samples per decade of time. Default 10.
    pub samples_per_decade: usize,
    /// Fit window of β in monolayers (default: 10 to T, or 1 to T when T < 100).
    pub fit_window: Option<[f64; 2]>,
    /// Sizes L for the saturated widths that give α. Default none.
    pub alpha_sizes: Option<Vec<usize>>,
    /// Keep every particle's cell (for a point-set output).
    pub keep_points: bool,
}

impl DepositionJob {
    /// The CLI's defaults for `model` (`DepositParams::DEFAULT`'s).
    pub fn new(model: Model) -> Self {
        let d = super::DepositParams::DEFAULT;
        Self {
            model,
            size: d.size,
            dim: d.dim,
            layers: d.layers,
            runs: d.runs,
            bin: d.bin,
            samples_per_decade: d.samples_per_decade,
            fit_window: None,
            alpha_sizes: None,
            keep_points: false,
        }
    }

    /// The title a height field of this run carries (where the format has
    /// one): "rd L=256 T=100".
    pub fn title(&self) -> String {
        format!("{} L={} T={}", self.model.name(), self.size, self.layers)
    }

    /// The β fit window actually used.
    fn window(&self) -> Result<[f64; 2]> {
        match self.fit_window {
            Some(w) => {
                ensure(w[0] > 0.0 && w[1] > w[0], || {
                    format!(
                        "⟨fit_window⟩ takes TMIN,TMAX with 0 < TMIN < TMAX, got {:?}",
                        w.to_vec()
                    )
                })?;
                Ok(w)
            }
            None if self.layers >= 100.0 => Ok([10.0, self.layers]),
            None => Ok([1.0, self.layers]),
        }
    }
}

/// The saturated widths W_sat(L) and the fit W_sat ∝ L^α.
#[derive(Clone, Debug)]
pub struct AlphaStudy {
    /// The sizes L.
    pub sizes: Vec<usize>,
    /// W_sat for each size.
    pub saturated_width: Vec<f64>,
    /// The log–log fit; its slope is α.
    pub fit: LogFit,
}

/// What a flat-substrate run gives.
#[derive(Clone, Debug)]
pub struct DepositionRun {
    /// The first run's deposit (heights, particles if kept).
    pub deposit: Deposit,
    /// W(t) averaged over the runs.
    pub series: WidthSeries,
    /// β by a plain log–log fit of W(t).
    pub plain: Result<GrowthFit, AnalysisError>,
    /// β with an intrinsic width subtracted.
    pub intrinsic: Result<GrowthFit, AnalysisError>,
    /// β of the binned width, when binning is on.
    pub binned: Option<Result<GrowthFit, AnalysisError>>,
    /// α, when sizes were given.
    pub alpha: Option<AlphaStudy>,
}

/// Runs `job`: the ensemble, the β fits and the α study, before anything is
/// written.
///
/// # Errors
/// [`crate::EngineError::Invalid`] for a bad fit window, run count or α sizes;
/// the simulator's errors (lattice, binning, memory budget).
pub fn deposit(
    job: &DepositionJob,
    seed: u64,
    budget: &MemoryBudget,
    time: &TimeBudget,
    progress: &dyn Progress,
) -> Result<DepositionRun> {
    ensure(job.runs >= 1, || "⟨runs⟩ must be at least 1".into())?;
    let window = job.window()?;
    let lattice = Lattice::new(job.size, job.dim)?;
    let mut p = DepositionParams::new(job.model, lattice, job.layers);
    let mut work = estimate::deposition(p.depositions() as f64 * job.runs as f64);
    if let Some(sizes) = &job.alpha_sizes {
        let alpha = alpha_work(job, sizes, budget)?;
        work.units += alpha.units;
    }
    estimate::check(time, &work)?;
    p.bin = job.bin;
    ensure(job.samples_per_decade >= 1, || {
        "⟨samples_per_decade⟩ must be at least 1".into()
    })?;
    p.samples_per_decade = job.samples_per_decade;
    p.keep_particles = job.keep_points && job.model == Model::Bd;
    if job.keep_points {
        // Positions (24 bytes) plus the writer's buffer, per particle.
        budget.check_elements(
            p.depositions() as u128,
            48,
            "the point set of every deposited particle",
        )?;
    }
    let alpha = match &job.alpha_sizes {
        Some(sizes) => Some(alpha_study(job, sizes, seed)?),
        None => None,
    };
    let (deposit, series) = deposit_ensemble(&p, seed, job.runs, budget, progress)?;
    let plain = growth_exponent(&series.t, &series.width(), window);
    let intrinsic = growth_exponent_intrinsic(&series.t, &series.width(), window);
    let binned = (!series.w2_binned.is_empty())
        .then(|| growth_exponent(&series.t, &series.width_binned(), window));
    Ok(DepositionRun {
        deposit,
        series,
        plain,
        intrinsic,
        binned,
        alpha,
    })
}

/// The dynamic exponent z = α/β of `model` in `dim` dimensions (EW 2, KPZ
/// 1.5 in 1+1D and ≈ 1.62 in 2+1D): saturation takes about L^z monolayers.
fn dynamic_exponent(model: Model, dim: usize) -> f64 {
    match (model, dim) {
        (Model::Bd, 1) => 1.5,
        (Model::Bd, _) => 1.62,
        _ => 2.0,
    }
}

/// W² averaged over the last three quarters of run `r` to 2·L^z monolayers.
fn saturated_w2(model: Model, lat: Lattice, z: f64, seed: u64, r: u64) -> f64 {
    let layers = (2.0 * (lat.length as f64).powf(z)).ceil();
    let p = DepositionParams::new(model, lat, layers);
    let n = lat.columns() as u64;
    let total = p.depositions();
    let sched = uniform_schedule(total / 4 / n * n, total, 64);
    let d = deposit_on_schedule(&p, seed, 1000 + r, &sched, &NoProgress);
    d.series.w2.iter().sum::<f64>() / d.series.w2.len() as f64
}

/// The depositions of the α study (each size run to 2·L^z monolayers, `runs`
/// times), after checking that the largest lattices fit the budget (the runs go
/// in parallel, one lattice per thread).
fn alpha_work(
    job: &DepositionJob,
    sizes: &[usize],
    budget: &MemoryBudget,
) -> Result<asperity_core::Work> {
    let z = dynamic_exponent(job.model, job.dim);
    let mut depositions = 0.0;
    let mut largest = 0u128;
    for &l in sizes {
        let lat = Lattice::new(l, job.dim)?;
        let columns = lat.columns() as f64;
        depositions += job.runs as f64 * columns * (2.0 * (l as f64).powf(z)).ceil();
        largest = largest.max(lat.columns() as u128);
    }
    // Heights and the binned/relaxed work arrays: 16 bytes per column.
    let lanes = rayon::current_num_threads()
        .min(sizes.len() * job.runs)
        .max(1) as u128;
    budget.check_elements(largest * lanes, 16, "the α study's lattices")?;
    let mut w = estimate::deposition(depositions);
    w.what = "the α study".into();
    Ok(w)
}

/// Saturated widths for several sizes: each run to 2·L^z monolayers and W²
/// averaged over the last three quarters, over the job's runs.
fn alpha_study(job: &DepositionJob, sizes: &[usize], seed: u64) -> Result<AlphaStudy> {
    let (model, runs) = (job.model, job.runs);
    ensure(model != Model::Rd, || {
        "random deposition never saturates: α is undefined for rd".into()
    })?;
    ensure(sizes.len() >= 3, || {
        "⟨alpha_sizes⟩ needs at least 3 sizes".into()
    })?;
    let z = dynamic_exponent(model, job.dim);
    let lattices = sizes
        .iter()
        .map(|&l| Lattice::new(l, job.dim))
        .collect::<Result<Vec<_>, _>>()?;
    let jobs: Vec<(Lattice, u64)> = lattices
        .iter()
        .flat_map(|&l| (0..runs as u64).map(move |r| (l, r)))
        .collect();
    let w2: Vec<f64> = jobs
        .par_iter()
        .map(|&(lat, r)| saturated_w2(model, lat, z, seed, r))
        .collect();
    let saturated_width: Vec<f64> = (0..sizes.len())
        .map(|k| (w2[k * runs..(k + 1) * runs].iter().sum::<f64>() / runs as f64).sqrt())
        .collect();
    let ls: Vec<f64> = sizes.iter().map(|&l| l as f64).collect();
    let fit = roughness_exponent(&ls, &saturated_width)?;
    Ok(AlphaStudy {
        sizes: sizes.to_vec(),
        saturated_width,
        fit,
    })
}

/// A β fit as JSON (its error message when it failed).
pub fn fit_json(f: &Result<GrowthFit, AnalysisError>) -> Value {
    match f {
        Ok(f) => json!({
            "exponent": f.exponent,
            "intrinsic_width": f.intrinsic_width,
            "fit_window": f.fit.range,
            "r2": f.fit.r2,
            "points": f.fit.points,
        }),
        Err(e) => json!({"error": e.to_string()}),
    }
}

/// W(t) as `{t, w}` records.
pub fn width_records(s: &WidthSeries) -> Vec<Value> {
    s.t.iter()
        .zip(s.width())
        .map(|(t, w)| json!({"t": t, "w": w}))
        .collect()
}

/// W(t) as CSV: `t,w,w_binned,w2_stderr,mean_height`.
pub fn width_csv(s: &WidthSeries) -> String {
    let mut text = String::from("t,w,w_binned,w2_stderr,mean_height\n");
    for k in 0..s.t.len() {
        let wb = s
            .w2_binned
            .get(k)
            .map_or(String::new(), |v| v.sqrt().to_string());
        text += &format!(
            "{},{},{},{},{}\n",
            s.t[k],
            s.w2[k].sqrt(),
            wb,
            s.w2_stderr[k],
            s.mean_height[k]
        );
    }
    text
}

/// W(t) on log–log axes with its fits.
pub fn width_plot(
    title: &str,
    s: &WidthSeries,
    fit: Option<&GrowthFit>,
    binned: Option<&GrowthFit>,
) -> Plot {
    let mut series = vec![points("W(t)", s.t.iter().copied().zip(s.width()).collect())];
    if let Some(f) = fit {
        series.push(fit_line(format!("β = {:.3}", f.exponent), &f.fit));
    }
    if !s.w2_binned.is_empty() {
        series.push(points(
            "W binned",
            s.t.iter().copied().zip(s.width_binned()).collect(),
        ));
        if let Some(f) = binned {
            series.push(fit_line(format!("binned β = {:.3}", f.exponent), &f.fit));
        }
    }
    log_log(title.into(), "t (monolayers)", "interface width W", series)
}

impl DepositionRun {
    /// The measurements `asperity growth … --json` reports.
    pub fn measurements(&self, job: &DepositionJob) -> Measurements {
        let s = &self.series;
        let mut m = Measurements::new();
        m.set("model", job.model.name());
        m.set("lattice", json!({"L": job.size, "d": job.dim}));
        m.set("layers", job.layers);
        m.set("runs", job.runs);
        m.set("depositions_per_run", self.deposit.depositions);
        m.set("mean_height", s.mean_height.last());
        m.set("width", s.w2.last().map(|v| v.sqrt()));
        m.set("width_series", width_records(s));
        if !s.w2_binned.is_empty() {
            m.set("width_binned_series", s.width_binned());
        }
        m.set("beta", self.beta());
        m.set(
            "fits",
            json!({
                "plain": fit_json(&self.plain),
                "intrinsic_width": fit_json(&self.intrinsic),
                "binned": self.binned.as_ref().map(fit_json),
            }),
        );
        if let Some(a) = &self.alpha {
            m.set(
                "alpha",
                json!({"exponent": a.fit.slope, "r2": a.fit.r2, "sizes": a.sizes, "saturated_width": a.saturated_width}),
            );
        }
        m
    }

    /// β of the plain fit, if it could be made.
    pub fn beta(&self) -> Option<f64> {
        self.plain.as_ref().ok().map(|f| f.exponent)
    }

    /// One line: the model, the lattice, W, β and α.
    pub fn summary(&self, job: &DepositionJob) -> String {
        format!(
            "{}: L = {} ({}+1D), T = {} monolayers, {} run(s): W = {:.4}, β = {}{}",
            job.model.name(),
            job.size,
            job.dim,
            job.layers,
            job.runs,
            self.series.w2.last().map_or(0.0, |v| v.sqrt()),
            self.beta().map_or("n/a".into(), |b| format!("{b:.4}")),
            self.alpha
                .as_ref()
                .map_or(String::new(), |a| format!(", α = {:.4}", a.fit.slope)),
        )
    }

    /// `width.svg` (W(t) with its fits) and, with an α study, `saturation.svg`.
    pub fn plots(&self, job: &DepositionJob) -> Vec<crate::plots::NamedPlot> {
        let title = format!(
            "{} {}+1D, L = {}, {} runs",
            job.model.name().to_uppercase(),
            job.dim,
            job.size,
            job.runs
        );
        let binned = self.binned.as_ref().and_then(|b| b.as_ref().ok());
        let mut out = vec![crate::plots::NamedPlot {
            name: "width.svg",
            plot: width_plot(&title, &self.series, self.plain.as_ref().ok(), binned),
        }];
        if let Some(a) = &self.alpha {
            out.push(crate::plots::NamedPlot {
                name: "saturation.svg",
                plot: saturation_plot(a),
            });
        }
        out
    }
}

fn saturation_plot(a: &AlphaStudy) -> Plot {
    let data = a
        .sizes
        .iter()
        .map(|&l| l as f64)
        .zip(a.saturated_width.iter().copied())
        .collect();
    let series: Vec<Series> = vec![
        points("W_sat(L)", data),
        fit_line(format!("α = {:.3}", a.fit.slope), &a.fit),
    ];
    log_log(
        format!("saturated width, α = {:.3}", a.fit.slope),
        "L",
        "W_sat",
        series,
    )
}

/// Refuses an empty point set before a writer sees it.
///
/// # Errors
/// [`crate::EngineError::Invalid`] when `points` is empty.
pub fn non_empty(points: &[[f64; 3]]) -> Result<()> {
    if points.is_empty() {
        return Err(invalid("no particle to write"));
    }
    Ok(())
}
