//! Cellular-automaton height fields (peridier): rules and initial grids from
//! text, runs with their measurements, the Figure 4 gallery of rules ×
//! initial conditions, step pictures (Figure 3), and facet meshes with curves
//! draped on them (Figures 7–9).

use std::path::Path;

use asperity_ca::facets::{circle, drape, facet_mesh};
use asperity_ca::{
    Boundary, CaParams, Family, Init, Rule, Weights, accumulate, evolve_and_accumulate,
    initial_grid,
};
use asperity_core::{
    Diagonal, Grid2, HeightField, MemoryBudget, Progress, RgbaImage, TimeBudget, TriMesh,
};

use crate::estimate;
use asperity_render::cells::{blit, cell_image, grey};
use asperity_render::font::draw_text;
use asperity_render::{Polyline, RenderOptions, Shader, render_mesh};

use crate::error::{Result, ensure, invalid};
use crate::report::Measurements;

mod params;

pub use params::{
    BoundaryName, CaGalleryParams, CaRuleParams, CaRunParams, FacetParams, FamilyName,
    InterpolateParams, RuleCode, RuleFamily,
};

/// A rule of `family` (by name) with `states` states, from a Wolfram code or a
/// B/S string.
///
/// # Errors
/// [`crate::EngineError::Invalid`] for an unknown family; the rule's own.
pub fn rule(family: &str, states: u8, text: &str) -> Result<Rule> {
    let family = Family::from_name(family).ok_or_else(|| invalid("unknown family"))?;
    Ok(Rule::parse(family, states, text)?)
}

/// An initial grid from a file: `.npy`/`.csv` states 0…k−1, or an image
/// thresholded at 50 %.
fn init_from_file(text: &str, k: u8, budget: &MemoryBudget) -> Result<Init> {
    let path = Path::new(text);
    let h = crate::files::load_height(path, budget).map_err(|e| {
        invalid(format!(
            "initial grid {text:?} (use seed, random:DENSITY or a .npy/.png file): {e}"
        ))
    })?;
    let is_image = path
        .extension()
        .is_some_and(|e| !e.eq_ignore_ascii_case("npy") && !e.eq_ignore_ascii_case("csv"));
    let state = |(n, &v): (usize, &f64)| {
        if is_image {
            Ok((v >= 0.5) as u8)
        } else if v.fract() != 0.0 || v < 0.0 || v >= k as f64 {
            Err(invalid(format!(
                "{text}: value {v} at index {n} is not a state 0..{}",
                k - 1
            )))
        } else {
            Ok(v as u8)
        }
    };
    let states = h
        .data()
        .iter()
        .enumerate()
        .map(state)
        .collect::<Result<Vec<u8>>>()?;
    Ok(Init::Grid(Grid2::from_vec(h.dims(), states)?))
}

/// An initial condition: `seed`, `random:DENSITY[@SEED]` (the seed defaults to
/// `seed`), or a file — `.npy`/`.csv` states 0…k−1, or an image thresholded at
/// 50 %.
///
/// # Errors
/// A bad density or seed, an unreadable file or one over `budget`, a value
/// that is no state.
pub fn parse_init(text: &str, k: u8, seed: u64, budget: &MemoryBudget) -> Result<Init> {
    if text == "seed" {
        return Ok(Init::Seed);
    }
    let Some(r) = text.strip_prefix("random:") else {
        return init_from_file(text, k, budget);
    };
    let (d, s) = r.split_once('@').map_or((r, None), |(d, s)| (d, Some(s)));
    let density: f64 = d
        .parse()
        .map_err(|_| invalid(format!("{d:?} is not a density in [0, 1]")))?;
    let seed = match s {
        Some(s) => s
            .parse()
            .map_err(|_| invalid(format!("{s:?} is not a seed")))?,
        None => seed,
    };
    Ok(Init::Random { density, seed })
}

/// A run as `asperity ca run` describes it.
#[derive(Clone, Debug, PartialEq)]
pub struct RunJob {
    /// The rule.
    pub rule: Rule,
    /// Steps T.
    pub steps: usize,
    /// The initial condition.
    pub init: Init,
    /// Grid size; without it a seed sits on an infinite background.
    pub size: Option<[usize; 2]>,
    /// `cyclic` or `infinite` (default: infinite for a seed without a size).
    pub boundary: Option<Boundary>,
    /// Leave step 0 out of the sum.
    pub no_step0: bool,
    /// Step weights.
    pub weights: Weights,
    /// Height of each state.
    pub values: Option<Vec<f64>>,
    /// Keep every step (for state files and step pictures).
    pub keep_states: bool,
}

/// A finished run: the accumulated heights and, if kept, every step.
pub type RunOutput = asperity_ca::CaOutput;

/// What `ca run` gives: the run as resolved, its output and the boundary used.
#[derive(Clone, Debug)]
pub struct CaRun {
    /// The run: the rule, the initial condition, the steps.
    pub job: RunJob,
    /// The accumulated heights and, if kept, every step.
    pub output: RunOutput,
    /// The boundary the run used.
    pub boundary: Boundary,
}

impl CaRun {
    /// The measurements the job reports.
    pub fn measurements(&self) -> Measurements {
        run_measurements(&self.job, &self.output.heights, self.boundary)
    }

    /// The title of the height field written.
    pub fn title(&self) -> String {
        format!("CA rule {}", self.job.rule.code())
    }
}

/// Runs `ca run` with the parameters of `p`; `keep_states` keeps every step
/// (for state files and step pictures).
///
/// # Errors
/// The parameters' ([`crate::params::validate`]) and those of [`run`].
pub fn run_job(
    p: &CaRunParams,
    keep_states: bool,
    seed: u64,
    (budget, time): (&MemoryBudget, &TimeBudget),
    progress: &dyn Progress,
) -> Result<CaRun> {
    crate::params::validate(p)?;
    let rule = p.family.rule(&crate::params::require(&p.rule, "rule")?)?;
    let job = RunJob {
        init: parse_init(&p.init, rule.states(), seed, budget)?,
        rule,
        steps: crate::params::require(&p.steps, "steps")?,
        size: p.size.map(|s| s.0),
        boundary: p.boundary.map(Into::into),
        no_step0: p.no_step0,
        weights: p.step_weights(),
        values: p.values.clone(),
        keep_states,
    };
    let (output, boundary) = run(&job, budget, time, progress)?;
    Ok(CaRun {
        job,
        output,
        boundary,
    })
}

/// Evolves and accumulates `job`.
///
/// # Errors
/// [`crate::EngineError::Invalid`] for an infinite boundary with a size and a
/// seed; the CA's refusals (grid, weights, memory budget).
pub fn run(
    job: &RunJob,
    budget: &MemoryBudget,
    time: &TimeBudget,
    progress: &dyn Progress,
) -> Result<(RunOutput, Boundary)> {
    let seeded = matches!(job.init, Init::Seed);
    let boundary = job.boundary.unwrap_or(if seeded && job.size.is_none() {
        Boundary::Infinite
    } else {
        Boundary::Cyclic
    });
    ensure(
        !(boundary == Boundary::Infinite && job.size.is_some() && seeded),
        || {
            "⟨boundary=infinite⟩ takes its region from the pattern; drop ⟨size⟩ (or use ⟨boundary=cyclic⟩)".into()
        },
    )?;
    let params = CaParams {
        boundary,
        include_step0: !job.no_step0,
        weights: job.weights.clone(),
        values: job.values.clone(),
        keep_states: job.keep_states,
        ..CaParams::new(job.rule.clone(), job.steps)
    };
    // The whole run's estimates before the initial grid is drawn.
    if let Some(size) = job.size {
        asperity_ca::accumulate::check_memory(size, &params, budget)?;
    }
    estimate::check(time, &run_work(job, boundary))?;
    let grid = initial_grid(&job.init, job.size, job.rule.states(), budget)?;
    Ok((
        evolve_and_accumulate(&grid, &params, budget, progress)?,
        boundary,
    ))
}

/// The work of a run: every step of the grid, or of the pattern's region on an
/// infinite background, which grows by at least one cell a side each step
/// while the pattern lives (Σ (2t+1)² ≈ 4T³/3 cells for a seed).
fn run_work(job: &RunJob, boundary: Boundary) -> asperity_core::Work {
    let t = job.steps as f64;
    match (boundary, job.size) {
        (Boundary::Cyclic, Some([w, h])) => estimate::ca(w as f64 * h as f64, t),
        _ => {
            let mut w = estimate::ca(1.0, t);
            w.units = (4.0 / 3.0 * t * t * t).max(t * estimate::CA_MIN_CELLS_PER_STEP);
            w
        }
    }
}

/// The measurements `asperity ca run --json` reports.
pub fn run_measurements(job: &RunJob, h: &HeightField, boundary: Boundary) -> Measurements {
    let r = &job.rule;
    let (lo, hi) = h.min_max();
    let mut m = rule_measurements(r);
    m.set(
        "boundary",
        if boundary == Boundary::Cyclic {
            "cyclic"
        } else {
            "infinite"
        },
    );
    m.set("size", h.dims());
    m.set("steps", job.steps);
    m.set("height_range", [lo, hi]);
    m
}

/// A rule's code, family, state count and table.
pub fn rule_measurements(r: &Rule) -> Measurements {
    let mut m = Measurements::new();
    m.set("rule", r.code().to_string());
    m.set("family", r.family().name());
    m.set("states", r.states());
    m.set("table", r.table());
    m
}

/// One step as a picture: state 0 white, k − 1 black (the paper's Figure 3);
/// small grids are enlarged so cells stay visible.
pub fn step_image(states: &[u8], nx: usize, ny: usize, k: u8) -> RgbaImage {
    let scale = (256 / nx.max(ny)).max(1) as u32;
    cell_image(states, [nx, ny], scale, false, [255; 4], grey(k))
}

/// Facet mesh of a CA height field rendered flat. CA heights count steps on a
/// grid of unit spacing, so the view scales them to 15 % of the grid's extent
/// (the data are not changed).
///
/// # Errors
/// The renderer's.
pub fn render_facets(h: &HeightField, opts: &RenderOptions) -> Result<RgbaImage> {
    let (lo, hi) = h.min_max();
    let e = h.extent();
    let f = if hi > lo {
        0.15 * e[0].max(e[1]) / (hi - lo)
    } else {
        1.0
    };
    let m = facet_mesh(&h.map(|z| z * f), true)?;
    Ok(render_mesh(
        &m,
        &RenderOptions {
            shader: Shader::Flat,
            ..opts.clone()
        },
    )?)
}

/// The Figure 4 grid: one row per rule, one column per initial condition, each
/// tile labelled with its rule.
///
/// # Errors
/// [`crate::EngineError::Invalid`] with no rule or no initial condition; as
/// [`rule`], [`parse_init`] and the CA and renderer.
pub fn gallery_image(
    g: &CaGalleryParams,
    seed: u64,
    budget: &MemoryBudget,
    time: &TimeBudget,
) -> Result<RgbaImage> {
    crate::params::validate(g)?;
    let [tw, th] = g.tile.0.map(|v| u32::try_from(v).unwrap_or(u32::MAX));
    let (rows, cols) = (g.rules.len() as u32, g.inits.len() as u32);
    ensure(rows > 0 && cols > 0, || {
        "need at least one rule and one initial condition".into()
    })?;
    ensure(
        (1..=16384).contains(&tw) && (1..=16384).contains(&th),
        || format!("⟨tile⟩ must be 1..=16384 pixels a side, got {tw}x{th}"),
    )?;
    let tiles = f64::from(rows) * f64::from(cols);
    let mut work = estimate::ca(
        g.size.0[0] as f64 * g.size.0[1] as f64,
        g.steps as f64 * tiles,
    );
    work.what = "the gallery's CA runs".into();
    estimate::check(time, &work)?;
    let (width, height) = (cols as u64 * tw as u64, rows as u64 * th as u64);
    budget.check_elements(width as u128 * height as u128, 4, "the gallery image")?;
    ensure(
        width <= u32::MAX as u64 && height <= u32::MAX as u64,
        || format!("a {width}x{height} gallery image is too large"),
    )?;
    let mut img = RgbaImage::filled(width as u32, height as u32, [255, 255, 255, 255]);
    let opts = RenderOptions {
        width: tw,
        height: th,
        budget: *budget,
        ..RenderOptions::default()
    };
    for (r, code) in g.rules.iter().enumerate() {
        let rule = g.family.rule(code)?;
        for (c, init) in g.inits.iter().enumerate() {
            let init = parse_init(init, rule.states(), seed, budget)?;
            let grid = initial_grid(&init, Some(g.size.0), rule.states(), budget)?;
            let out = accumulate(&grid, &CaParams::new(rule.clone(), g.steps), budget)?;
            let tile = render_facets(&out.heights, &opts)?;
            let (x0, y0) = (c as u32 * tw, r as u32 * th);
            blit(&mut img, &tile, x0, y0);
            draw_text(
                &mut img,
                x0 + 6,
                y0 + 6,
                &rule.code().to_string(),
                2,
                [30, 30, 30, 255],
            );
        }
    }
    Ok(img)
}

/// The facet mesh of `h` and the curves draped on it.
///
/// # Errors
/// [`crate::EngineError::Invalid`] for a circle that is not finite or has no
/// positive radius; the CA's (a field too small to facet).
pub fn facets(
    h: &HeightField,
    job: &FacetParams,
    polyline: Option<&[[f64; 2]]>,
) -> Result<(TriMesh, Vec<Vec<[f64; 3]>>)> {
    crate::params::validate(job)?;
    let mesh = if job.smooth {
        h.to_trimesh(Diagonal::Forward)?
            .with_scalar("height", h.measured_values())?
    } else {
        facet_mesh(h, !job.shared)?
    };
    let mut curves = Vec::new();
    if let Some(c) = job.circle.map(|c| c.0) {
        ensure(c.iter().all(|v| v.is_finite()), || {
            format!("⟨circle⟩ takes CX,CY,R, got {:?}", c.to_vec())
        })?;
        ensure(c[2] > 0.0, || "circle radius must be positive".into())?;
        curves.push(drape(h, &circle(c[0], c[1], c[2], 180))?);
    }
    if let Some(p) = polyline {
        curves.push(drape(h, p)?);
    }
    Ok((mesh, curves))
}

/// The facet mesh with its curves in red: flat facets, or smooth shading for a
/// smooth or shared mesh.
///
/// # Errors
/// The renderer's.
pub fn render_with_curves(
    mesh: &TriMesh,
    curves: &[Vec<[f64; 3]>],
    job: &FacetParams,
    budget: &MemoryBudget,
) -> Result<RgbaImage> {
    let polylines = curves
        .iter()
        .map(|c| Polyline {
            points: c.clone(),
            color: [220, 30, 30, 255],
            closed: false,
        })
        .collect();
    Ok(render_mesh(
        mesh,
        &RenderOptions {
            shader: if job.smooth || job.shared {
                Shader::Phong
            } else {
                Shader::Flat
            },
            polylines,
            budget: *budget,
            ..RenderOptions::default()
        },
    )?)
}
