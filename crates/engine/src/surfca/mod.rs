//! Cellular automata on a triangle mesh (gobron-chiba): the mesh checked (or
//! repaired) and covered with cells, then one application — surface Voronoi,
//! copper corrosion with patina, or Gray–Scott reaction–diffusion — run with
//! its per-step statistics, and the result coloured as a cell mesh or as a
//! texture atlas on the original mesh.

use std::time::Instant;

use asperity_core::{MemoryBudget, PointSet, Progress, TimeBudget, TriMesh};
use asperity_render::plot::{Plot, Series, Style};
use asperity_surfca::corrosion::{
    Behaviour, CorrosionCell, CorrosionParams, CorrosionRule, corrode, initial,
};
use asperity_surfca::engine::{RunOptions, RunStats, run};
use asperity_surfca::reaction_diffusion::{Chemicals, GrayScott, seeded_state};
use asperity_surfca::repair::{RepairReport, check, repair};
use asperity_surfca::voronoi::{PAPER_P, UNLABELLED, VoronoiRule, random_sites, voronoi};
use asperity_surfca::{CellSize, Cells, Pairing, Rule, build_with};
use serde_json::json;

use crate::error::{Result, ensure, invalid};
use crate::report::Measurements;

mod colors;
mod params;

pub use colors::{corrosion_mesh, label_color, patina_color, patina_shading, rd_color};
pub use params::{AppName, SurfaceCaInputs, SurfaceCaParams, run_job};

/// A mesh covered with cells, ready for an application.
pub struct Covered {
    /// The mesh (repaired if asked).
    pub mesh: TriMesh,
    /// What the repair changed, if one was asked for.
    pub repair: Option<RepairReport>,
    /// The cells.
    pub cells: Cells,
    /// Seconds spent building the cells.
    pub cells_s: f64,
}

/// What a run of an application will take, before its sites are chosen: its
/// kind and step count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AppKind {
    /// Voronoi growth, at most this many steps.
    Voronoi(u64),
    /// Corrosion or Gray–Scott, this many steps.
    Steps(u64),
}

/// An application as a front end asks for it, before the cells exist: the
/// sites are chosen once the mesh is covered ([`AppRequest::build`]).
#[derive(Clone, Debug)]
pub enum AppRequest {
    /// Surface Voronoi from `sites` random cells, or the cells nearest `at`.
    Voronoi {
        /// How many random sites.
        sites: usize,
        /// Sites at these points (named `name` in messages) instead.
        at: Option<(PointSet, String)>,
        /// The diagonal-neighbour probability (gobron-chiba §4.1).
        diagonal_p: Option<f64>,
        /// The most steps it may run.
        max_steps: u64,
    },
    /// Copper corrosion and patina, from random sites or those nearest `at`.
    Corrosion {
        /// The model's parameters.
        params: CorrosionParams,
        /// Steps.
        steps: u64,
        /// Initial corrosion sites at these points (named in messages).
        at: Option<(PointSet, String)>,
    },
    /// Gray–Scott reaction–diffusion.
    GrayScott {
        /// Feed rate.
        feed: f32,
        /// Kill rate.
        kill: f32,
        /// Initial patches.
        patches: usize,
        /// Steps.
        steps: u64,
    },
}

impl AppRequest {
    /// Its kind and length, for [`check_time`] before the cells are built.
    pub fn kind(&self) -> AppKind {
        match self {
            AppRequest::Voronoi { max_steps, .. } => AppKind::Voronoi(*max_steps),
            AppRequest::Corrosion { steps, .. } | AppRequest::GrayScott { steps, .. } => {
                AppKind::Steps(*steps)
            }
        }
    }

    /// The application on the cells of `cov`, its sites chosen with `seed`.
    ///
    /// # Errors
    /// Parameters out of range; sites that do not fit the cells.
    pub fn build(self, cov: &Covered, seed: u64) -> Result<App> {
        let sites_at = |at: &Option<(PointSet, String)>| {
            at.as_ref()
                .map(|(p, name)| App::sites_at(&cov.cells, p, name))
                .transpose()
        };
        match self {
            AppRequest::Voronoi {
                sites,
                ref at,
                diagonal_p,
                max_steps,
            } => {
                let chosen = match sites_at(at)? {
                    Some(s) => s,
                    None => App::random_sites(&cov.cells, sites, seed)?,
                };
                App::voronoi(chosen, diagonal_p, max_steps)
            }
            AppRequest::Corrosion {
                params,
                steps,
                ref at,
            } => match sites_at(at)? {
                Some(s) => App::corrosion_at(params, steps, s),
                None => App::corrosion(params, steps),
            },
            AppRequest::GrayScott {
                feed,
                kill,
                patches,
                steps,
            } => App::gray_scott(feed, kill, patches, steps),
        }
    }
}

/// Refuses a run of `app` on about `cells` cells that no machine could finish
/// within `time` — before the cells are built when `cells` is
/// [`asperity_surfca::cells::estimated_count`].
///
/// # Errors
/// [`crate::EngineError`] of kind time, with the estimate.
pub fn check_time(cells: f64, app: &AppKind, time: &TimeBudget) -> Result<()> {
    // Voronoi stops once its fronts have crossed the surface, about √cells
    // steps: only what it must run counts.
    let steps = match *app {
        AppKind::Voronoi(max_steps) => (max_steps as f64).min(2.0 * cells.sqrt()),
        AppKind::Steps(steps) => steps as f64,
    };
    crate::estimate::check(time, &crate::estimate::surface_ca(cells, steps))
}

/// Checks `mesh` (after repairing it when `fix`) and covers it with cells of
/// `size`, linked across edges by `pairing`; `name` names it in messages.
///
/// # Errors
/// A mesh that is not manifold, non-degenerate and consistently oriented (the
/// paper's step 1); the memory budget.
pub fn cover(
    mesh: TriMesh,
    name: &str,
    fix: bool,
    (size, pairing): (CellSize, Pairing),
    budget: &MemoryBudget,
) -> Result<Covered> {
    let (mesh, repair) = if fix {
        let (m, r) = repair(&mesh)?;
        (m, Some(r))
    } else {
        (mesh, None)
    };
    check(&mesh).map_err(|e| invalid(format!("{name}: {e}")))?;
    let t = Instant::now();
    let cells = build_with(&mesh, size, pairing, budget)?;
    Ok(Covered {
        mesh,
        repair,
        cells,
        cells_s: t.elapsed().as_secs_f64(),
    })
}

impl Covered {
    /// One line on the cell structure.
    pub fn summary(&self) -> String {
        let c = &self.cells;
        format!(
            "{} cells of side {:.4} on {} triangles ({} COMP-IN, {} PART-IN; {} pairing, redundancy {:.1} %; \
             the paper's Figure 8 measure {:.1} %)",
            c.len(),
            c.h,
            self.mesh.n_faces(),
            c.stats.comp_in,
            c.stats.part_in,
            c.stats.pairing.name(),
            100.0 * c.stats.pairing_redundancy,
            100.0 * c.stats.paper_redundancy
        )
    }

    /// The cells as a mesh of their own, each in its colour (see
    /// `asperity_surfca::atlas::cell_mesh`).
    ///
    /// # Errors
    /// Invalid geometry (not expected for built cells).
    pub fn cell_mesh(&self, color: impl Fn(usize) -> [u8; 4]) -> Result<TriMesh> {
        Ok(asperity_surfca::atlas::cell_mesh(
            &self.mesh,
            &self.cells,
            color,
            None,
        )?)
    }
}

/// An application and its settings.
#[derive(Clone, Debug)]
pub enum App {
    /// Surface Voronoi regions grown from sites.
    Voronoi {
        /// Site cells.
        sites: Vec<usize>,
        /// Diagonal growth probability (Figure 14; default √2/2 − ½).
        diagonal_p: f64,
        /// Step limit.
        max_steps: u64,
    },
    /// Copper corrosion and patina.
    Corrosion {
        /// The model's constants.
        params: CorrosionParams,
        /// Steps.
        steps: u64,
        /// Cells corroded from the start (besides the random seeding of
        /// `params.seed_rate`): the paper's chosen initial corrosion sites.
        sites: Vec<usize>,
    },
    /// Gray–Scott reaction–diffusion.
    GrayScott {
        /// Feed and kill rates.
        rule: GrayScott,
        /// Patches seeded.
        patches: usize,
        /// Steps.
        steps: u64,
    },
}

impl App {
    /// Voronoi from `sites` with the diagonal probability `p` (default the
    /// paper's), checked.
    ///
    /// # Errors
    /// [`crate::EngineError::Invalid`] for p outside [0, 1] or no site.
    pub fn voronoi(sites: Vec<usize>, p: Option<f64>, max_steps: u64) -> Result<Self> {
        let diagonal_p = p.unwrap_or(PAPER_P);
        ensure((0.0..=1.0).contains(&diagonal_p), || {
            format!("⟨diagonal_p⟩ must be in [0, 1], got {diagonal_p}")
        })?;
        Ok(App::Voronoi {
            sites,
            diagonal_p,
            max_steps,
        })
    }

    /// `n` random sites on `cells`.
    ///
    /// # Errors
    /// [`crate::EngineError::Invalid`] for no site or more sites than cells.
    pub fn random_sites(cells: &Cells, n: usize, seed: u64) -> Result<Vec<usize>> {
        ensure(n >= 1, || "⟨sites⟩ must be at least 1".into())?;
        ensure(n <= cells.len(), || {
            format!(
                "⟨sites={n}⟩ exceeds the {} cells; use more cells",
                cells.len()
            )
        })?;
        Ok(random_sites(cells, n, seed))
    }

    /// The cells nearest to `points`.
    ///
    /// # Errors
    /// [`crate::EngineError::Invalid`] for no point.
    pub fn sites_at(cells: &Cells, points: &PointSet, name: &str) -> Result<Vec<usize>> {
        ensure(!points.is_empty(), || format!("{name}: no site points"))?;
        Ok(asperity_surfca::voronoi::sites_at(
            cells,
            points.positions(),
        ))
    }

    /// Corrosion with `params`, checked.
    ///
    /// # Errors
    /// [`crate::EngineError::Invalid`] naming the bad constant.
    pub fn corrosion(params: CorrosionParams, steps: u64) -> Result<Self> {
        params
            .validate()
            .map_err(|e| invalid(format!("corrosion: {e}")))?;
        Ok(App::Corrosion {
            params,
            steps,
            sites: Vec::new(),
        })
    }

    /// Corrosion with `params` that starts at `sites` (cells corroded at step 0).
    ///
    /// # Errors
    /// As [`App::corrosion`]; no site.
    pub fn corrosion_at(params: CorrosionParams, steps: u64, sites: Vec<usize>) -> Result<Self> {
        ensure(!sites.is_empty(), || "corrosion: no initial site".into())?;
        Ok(match Self::corrosion(params, steps)? {
            App::Corrosion { params, steps, .. } => App::Corrosion {
                params,
                steps,
                sites,
            },
            other => other,
        })
    }

    /// Gray–Scott with feed F and kill k, checked.
    ///
    /// # Errors
    /// [`crate::EngineError::Invalid`] for bad rates or no patch.
    pub fn gray_scott(feed: f32, kill: f32, patches: usize, steps: u64) -> Result<Self> {
        let rule = GrayScott {
            feed,
            kill,
            ..GrayScott::default()
        };
        rule.validate()
            .map_err(|e| invalid(format!("gray-scott: {e}")))?;
        ensure(patches >= 1, || "⟨patches⟩ must be at least 1".into())?;
        Ok(App::GrayScott {
            rule,
            patches,
            steps,
        })
    }

    /// The most steps it runs (Voronoi stops earlier once every cell is reached).
    pub fn steps(&self) -> u64 {
        match self {
            App::Voronoi { max_steps, .. } => *max_steps,
            App::Corrosion { steps, .. } | App::GrayScott { steps, .. } => *steps,
        }
    }

    /// Its kind and step count (see [`check_time`]).
    pub fn kind(&self) -> AppKind {
        match self {
            App::Voronoi { max_steps, .. } => AppKind::Voronoi(*max_steps),
            _ => AppKind::Steps(self.steps()),
        }
    }

    /// `voronoi`, `corrosion` or `gray-scott`.
    pub fn name(&self) -> &'static str {
        match self {
            App::Voronoi { .. } => "voronoi",
            App::Corrosion { .. } => "corrosion",
            App::GrayScott { .. } => "gray-scott",
        }
    }
}

/// The end state of a run, whatever the application.
pub enum State {
    /// A label per cell.
    Labels(Vec<u32>),
    /// A corrosion state per cell.
    Corrosion(Vec<CorrosionCell>),
    /// Chemical concentrations per cell.
    Chemicals(Vec<Chemicals>),
}

impl State {
    /// Colour of cell `c`.
    pub fn color(&self, c: usize) -> [u8; 4] {
        match self {
            State::Labels(l) => label_color(l[c]),
            State::Corrosion(s) => patina_color(&s[c]),
            State::Chemicals(s) => rd_color(&s[c]),
        }
    }

    /// The per-cell field a displaced or attributed output carries:
    /// `oxide` (corrosion) or `activator` (Gray–Scott); none for labels.
    pub fn field(&self) -> Option<(&'static str, Vec<f64>)> {
        match self {
            State::Labels(_) => None,
            State::Corrosion(s) => Some(("oxide", s.iter().map(|x| x.oxide as f64).collect())),
            State::Chemicals(s) => Some(("activator", s.iter().map(|x| x.v as f64).collect())),
        }
    }
}

/// A finished run.
pub struct AppRun {
    /// The application.
    pub app: App,
    /// The end state.
    pub state: State,
    /// Per-step statistics.
    pub stats: RunStats,
    /// The statistics' class names.
    pub classes: Vec<&'static str>,
    /// Wall-clock seconds of the run.
    pub seconds: f64,
}

/// Colours a step's state for the caller's `on_step`.
type OnStep<'a> = dyn FnMut(u64, &dyn Fn(usize) -> [u8; 4]) + 'a;

/// A run's end state, statistics and class names.
type Ran = (State, RunStats, Vec<&'static str>);

fn run_voronoi(
    cells: &Cells,
    (sites, p, max): (&[usize], f64, u64),
    seed: u64,
    on_step: &mut OnStep,
) -> Ran {
    let rule = VoronoiRule { diagonal_p: p };
    let (labels, stats) = voronoi(cells, sites, &rule, seed, max, |step, l| {
        on_step(step, &|c| label_color(l[c]));
        true
    });
    (State::Labels(labels), stats, rule.classes().to_vec())
}

fn run_corrosion(
    cells: &Cells,
    (params, sites): (&CorrosionParams, &[usize]),
    steps: u64,
    seed: u64,
    on_step: &mut OnStep,
) -> Ran {
    let mut states = initial(cells, params, seed);
    for &c in sites {
        states[c].behaviour = Behaviour::Corroded;
    }
    let stats = corrode(cells, params, &mut states, seed, steps, |step, st| {
        on_step(step, &|c| patina_color(&st[c]));
        true
    });
    let classes = CorrosionRule { params: *params }.classes().to_vec();
    (State::Corrosion(states), stats, classes)
}

fn run_gray_scott(
    cells: &Cells,
    (rule, patches, steps): (&GrayScott, usize, u64),
    seed: u64,
    on_step: &mut OnStep,
) -> Ran {
    let mut states = seeded_state(cells, patches.min(cells.len()), seed);
    let opts = RunOptions {
        seed,
        max_steps: steps,
        stop_when_stable: false,
    };
    let stats = run(cells, rule, &mut states, &opts, |step, st| {
        on_step(step, &|c| rd_color(&st[c]));
        true
    });
    (State::Chemicals(states), stats, rule.classes().to_vec())
}

/// Runs `app` on the cells; `on_step(step, colour of cell c)` is called after
/// every step (for progress and animation frames).
///
/// # Errors
/// [`asperity_core::CoreError::TimeLimit`] when the cells × steps cannot finish
/// within `time`.
pub fn run_app(
    cov: &Covered,
    app: App,
    seed: u64,
    time: &TimeBudget,
    mut on_step: impl FnMut(u64, &dyn Fn(usize) -> [u8; 4]),
) -> Result<AppRun> {
    let cells = &cov.cells;
    check_time(cells.len() as f64, &app.kind(), time)?;
    let t = Instant::now();
    let (state, stats, classes) = match &app {
        App::Voronoi {
            sites,
            diagonal_p,
            max_steps,
        } => run_voronoi(cells, (sites, *diagonal_p, *max_steps), seed, &mut on_step),
        App::Corrosion {
            params,
            steps,
            sites,
        } => run_corrosion(cells, (params, sites), *steps, seed, &mut on_step),
        App::GrayScott {
            rule,
            patches,
            steps,
        } => run_gray_scott(cells, (rule, *patches, *steps), seed, &mut on_step),
    };
    Ok(AppRun {
        app,
        state,
        stats,
        classes,
        seconds: t.elapsed().as_secs_f64(),
    })
}

/// How the result is written.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OutputShape {
    /// The original mesh with the cells in a texture atlas (glTF, OBJ).
    pub textured: bool,
    /// The cells themselves even where a texture would do.
    pub cell_mesh: bool,
    /// Raise the cells by the per-cell field times this.
    pub displace: Option<f64>,
}

impl AppRun {
    /// The result mesh: displaced cells, the original mesh with a cell atlas,
    /// or the cell mesh with per-vertex colours and the per-cell field.
    ///
    /// # Errors
    /// [`crate::EngineError::Invalid`] for a displacement without a field or not
    /// finite; the atlas' memory budget.
    pub fn mesh(
        &self,
        cov: &Covered,
        shape: OutputShape,
        budget: &MemoryBudget,
    ) -> Result<TriMesh> {
        let (mesh, cells) = (&cov.mesh, &cov.cells);
        let color = |c: usize| self.state.color(c);
        let field = self.state.field();
        if let Some(k) = shape.displace {
            let (_, values) = field.as_ref().ok_or_else(|| {
                invalid("⟨displace⟩ needs a per-cell thickness (corrosion: oxide; gray-scott: activator)")
            })?;
            ensure(k.is_finite(), || "⟨displace⟩ must be finite".into())?;
            return Ok(asperity_surfca::atlas::cell_mesh(
                mesh,
                cells,
                color,
                Some((values, k)),
            )?);
        }
        if shape.textured && !shape.cell_mesh {
            return Ok(asperity_surfca::atlas::atlas_mesh(
                mesh, cells, color, budget,
            )?);
        }
        if let State::Corrosion(states) = &self.state {
            // The unlit colours plus both layers' thicknesses (render --patina).
            return corrosion_mesh(cov, states);
        }
        let mut m = cov.cell_mesh(color)?;
        if let Some((name, values)) = field {
            m = m.with_scalar(
                name,
                (0..cells.len())
                    .flat_map(|c| std::iter::repeat_n(values[c], cells.polygon(c).len()))
                    .collect(),
            )?;
        }
        Ok(m)
    }

    /// Voronoi only: the cell centres with their `label` (−1 unreached),
    /// `area` and label colour.
    ///
    /// # Errors
    /// [`crate::EngineError::Invalid`] for another application.
    pub fn labels(&self, cov: &Covered) -> Result<PointSet> {
        let State::Labels(labels) = &self.state else {
            return Err(invalid("labels exist for ⟨app=voronoi⟩ only"));
        };
        let mut ps = PointSet::new(cov.cells.centre.clone());
        ps.add_attribute(
            "label",
            labels
                .iter()
                .map(|&l| if l == UNLABELLED { -1.0 } else { l as f64 })
                .collect(),
        )?;
        ps.add_attribute("area", cov.cells.area.clone())?;
        ps.set_colors(labels.iter().map(|&l| label_color(l)).collect())?;
        Ok(ps)
    }

    /// Warnings for the user: Voronoi cells no site reached.
    pub fn warnings(&self) -> Vec<String> {
        match &self.state {
            State::Labels(l) => {
                let unreached = l.iter().filter(|&&x| x == UNLABELLED).count();
                (unreached > 0)
                    .then(|| {
                        format!(
                            "{unreached} cells were not reached (separate components, or the step limit)"
                        )
                    })
                    .into_iter()
                    .collect()
            }
            _ => Vec::new(),
        }
    }

    /// The measurements `asperity surface-ca --json` reports.
    pub fn measurements(&self, cov: &Covered) -> Measurements {
        let n = cov.cells.len();
        let mut m = Measurements::new();
        m.set("app", self.app.name());
        m.set("cells", n);
        m.set("steps", self.stats.steps);
        m.set("run_s", self.seconds);
        if let State::Chemicals(_) = self.state {
            let last = self.stats.per_step.last();
            m.set(
                "activator_fraction",
                last.map_or(0.0, |s| s.class_fraction[1]),
            );
            return m;
        }
        m.set("cell_structure", &cov.cells.stats);
        m.set("changed_fraction", self.changed_fraction(n));
        m.set(
            "cell_updates_per_s",
            n as f64 * self.stats.steps as f64 / self.seconds.max(1e-9),
        );
        match (&self.app, &self.state) {
            (
                App::Voronoi {
                    sites, diagonal_p, ..
                },
                _,
            ) => {
                m.set("diagonal_p", diagonal_p);
                let centres: Vec<_> = sites.iter().map(|&c| cov.cells.centre[c]).collect();
                m.set("sites", centres);
            }
            (_, State::Corrosion(s)) => {
                let count = |b: Behaviour| s.iter().filter(|x| x.behaviour == b).count();
                m.set("corroded", count(Behaviour::Corroded));
                m.set("non_existent", count(Behaviour::NonExistent));
            }
            _ => {}
        }
        m
    }

    /// The share of cells that changed at each step.
    fn changed_fraction(&self, n: usize) -> Vec<f64> {
        self.stats
            .per_step
            .iter()
            .map(|s| s.changed as f64 / n as f64)
            .collect()
    }

    /// One line on what happened.
    pub fn summary(&self, cov: &Covered) -> String {
        let (n, steps, secs) = (cov.cells.len(), self.stats.steps, self.seconds);
        match (&self.app, &self.state) {
            (App::Voronoi { sites, .. }, _) => format!(
                "{} sites grew over {n} cells in {steps} steps ({secs:.2} s)",
                sites.len()
            ),
            (_, State::Corrosion(s)) => {
                let frac = |b: Behaviour| {
                    100.0 * s.iter().filter(|x| x.behaviour == b).count() as f64 / n as f64
                };
                format!(
                    "{steps} steps over {n} cells in {secs:.2} s: {:.1} % corroded, {:.1} % eaten through",
                    frac(Behaviour::Corroded),
                    frac(Behaviour::NonExistent)
                )
            }
            _ => format!("{steps} Gray–Scott steps over {n} cells in {secs:.2} s"),
        }
    }

    /// The per-step statistics as CSV: step, changed, changed fraction, then
    /// the area fraction of each class.
    pub fn stats_csv(&self, n: usize) -> String {
        let mut t = String::from("step,changed,changed_fraction");
        for c in &self.classes {
            t += &format!(",{c}");
        }
        t.push('\n');
        for p in &self.stats.per_step {
            t += &format!("{},{},{}", p.step, p.changed, p.changed as f64 / n as f64);
            for f in &p.class_fraction {
                t += &format!(",{f}");
            }
            t.push('\n');
        }
        t
    }

    /// The per-step statistics as JSON.
    pub fn stats_json(&self, n: usize) -> String {
        let doc = json!({"classes": self.classes, "cells": n, "run": self.stats});
        serde_json::to_string_pretty(&doc).expect("statistics serialise")
    }

    /// The per-step statistics as a plot: changed cells and class fractions.
    pub fn stats_plot(&self, n: usize) -> Plot {
        let per_step = &self.stats.per_step;
        let line = |name: String, points: Vec<(f64, f64)>| Series {
            name,
            points,
            style: Style::Line,
        };
        let mut series = vec![line(
            "changed cells (fraction)".into(),
            per_step
                .iter()
                .map(|s| (s.step as f64, s.changed as f64 / n as f64))
                .collect(),
        )];
        for (k, c) in self.classes.iter().enumerate() {
            series.push(line(
                format!("{c} (area fraction)"),
                per_step
                    .iter()
                    .map(|s| {
                        (
                            s.step as f64,
                            s.class_fraction.get(k).copied().unwrap_or(0.0),
                        )
                    })
                    .collect(),
            ));
        }
        Plot {
            title: "Surface CA: per-step statistics".into(),
            x_label: "step".into(),
            y_label: "fraction".into(),
            log_x: false,
            log_y: false,
            series,
        }
    }
}

/// The progress bar's total and label for `app`.
pub fn progress_plan(app: &App) -> (u64, &'static str) {
    match app {
        App::Voronoi { .. } => (0, "surface Voronoi"),
        App::Corrosion { steps, .. } => (*steps, "corrosion"),
        App::GrayScott { steps, .. } => (*steps, "reaction-diffusion"),
    }
}

/// Starts `progress` for `app` (a helper for front ends with a bar).
pub fn start_progress(progress: &dyn Progress, app: &App) {
    let (total, label) = progress_plan(app);
    progress.start(total, label);
}
