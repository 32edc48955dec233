//! The workloads the issues name, as jobs a front end times (`asperity bench`):
//! each builds its input once, then runs the measured work as often as asked.
//! criterion (`cargo bench -p asperity-benches`) measures the same algorithms
//! for developers; these let a user time them from the installed binary.

use std::path::PathBuf;

use asperity_core::fourier_surface::{FourierParams, benchmark_mesh, fourier_surface};
use asperity_core::{Grid2, HeightField, MemoryBudget, NoProgress};
use asperity_growth::dla::{DlaParams, SeedShape, dla};
use asperity_growth::{DepositionParams, Lattice, Model, deposit_ensemble};
use asperity_io::Surface;
use asperity_render::{RenderOptions, render_mesh};

use asperity_engine::error::{Result, invalid};

mod levelset;

pub(crate) use levelset::rdsr_sphere_cloud;
use levelset::*;

/// The measured work of a workload.
pub type Job = Box<dyn FnMut() -> Result<()> + Send>;

/// A workload, its input built.
pub struct Workload {
    /// Name, `crate/algorithm-input`.
    pub name: &'static str,
    /// What one run does, in words.
    pub what: String,
    /// Elements per run, for throughput.
    pub elements: u64,
    /// Their unit.
    pub unit: &'static str,
    /// The target in seconds per run, if any.
    pub target_s: Option<f64>,
    /// Long workloads run once, without warm-up, whatever the repeat count.
    pub once: bool,
    /// The work.
    pub job: Job,
}

/// Builds a workload's input (untimed).
pub type MakeWorkload = Box<dyn Fn() -> Result<Workload>>;

/// Where workloads that write files write them.
#[derive(Clone, Debug)]
pub struct Scratch(pub PathBuf);

impl Scratch {
    /// A folder for this process under the system's temporary folder.
    pub fn new() -> Self {
        Self(std::env::temp_dir().join(format!("asperity-bench-{}", std::process::id())))
    }

    fn file(&self, name: &str) -> Result<PathBuf> {
        std::fs::create_dir_all(&self.0)
            .map_err(|e| invalid(format!("creating {}: {e}", self.0.display())))?;
        Ok(self.0.join(name))
    }

    /// Removes the folder and what the workloads wrote into it.
    pub fn remove(&self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

impl Default for Scratch {
    fn default() -> Self {
        Self::new()
    }
}

/// What every workload is built from: full size or (`quick`) a size for tests,
/// the memory budget, and the scratch folder.
#[derive(Clone, Debug)]
pub struct Setup {
    /// Small sizes.
    pub quick: bool,
    /// The memory budget.
    pub budget: MemoryBudget,
    /// Where files are written.
    pub scratch: Scratch,
}

impl Setup {
    /// `full` at full size, `small` with `quick`.
    fn size<T>(&self, full: T, small: T) -> T {
        if self.quick { small } else { full }
    }

    /// The target, at full size only.
    fn target(&self, seconds: f64) -> Option<f64> {
        (!self.quick).then_some(seconds)
    }
}

type Builder = fn(&Setup) -> Result<Workload>;

/// Every workload, in the order `asperity bench` runs them.
const WORKLOADS: &[(&str, Builder)] = &[
    ("render/2m-triangles-1080p", render),
    ("ca/evolve-bits-8192", ca_bits),
    ("ca/evolve-bytes-8192", ca_bytes),
    ("ca/accumulate-8192x256", ca_accumulate),
    ("core/fourier-surface", fourier),
    ("io/write-ply", write_ply),
    ("analysis/analyze-2048", analyze_2048),
    ("growth/rd-2d", rd),
    ("growth/rdsr-2d", rdsr),
    ("growth/bd-2d", bd),
    ("growth/dla-point-1e5", dla_point_1e5),
    ("growth/dla-plane-1e5", dla_plane_1e5),
    ("growth/dla-point-1e6", dla_point_1e6),
    ("growth/dla-plane-1e6", dla_plane_1e6),
    ("growth/dla-point-1e7", dla_point_1e7),
    ("growth/dla-plane-1e7", dla_plane_1e7),
    ("surfca/voronoi-1m-1000", surfca_voronoi),
    ("surfca/corrosion-1m-1000", surfca_corrosion),
    ("subdiv/plain-10086-quads-4-levels", subdiv_plain),
    ("subdiv/rock-10086-quads-4-levels", subdiv_rock),
    ("ifs/surface-depth10", ifs_surface),
    ("ifs/curvature-presets", ifs_curvature),
    ("levelset/pipeline-128", levelset_128),
    ("levelset/full-grid-128", levelset_full_128),
    ("levelset/pipeline-256-1e6", levelset_256),
    ("levelset/plane-dla-256", levelset_plane_256),
    ("levelset/plane-dla-512", levelset_plane_512),
    ("levelset/plane-dla-1e6-1024", levelset_plane_1024),
];

/// Every workload by name, at full size or (`quick`) at a size for tests.
pub fn workloads(
    quick: bool,
    budget: MemoryBudget,
    scratch: &Scratch,
) -> Vec<(&'static str, MakeWorkload)> {
    let setup = Setup {
        quick,
        budget,
        scratch: scratch.clone(),
    };
    WORKLOADS
        .iter()
        .map(|&(name, build)| {
            let setup = setup.clone();
            let make: MakeWorkload = Box::new(move || build(&setup));
            (name, make)
        })
        .collect()
}

fn render(s: &Setup) -> Result<Workload> {
    // 1001² samples → 2 000 000 triangles (issue #3's workload).
    let n = s.size(1001, 101);
    let (w, h) = s.size((1920, 1080), (320, 180));
    let m = benchmark_mesh(n, &s.budget)?;
    let tris = m.n_faces() as u64;
    let opts = RenderOptions {
        width: w,
        height: h,
        supersample: 2,
        shadows: true,
        budget: s.budget,
        ..RenderOptions::default()
    };
    Ok(Workload {
        name: "render/2m-triangles-1080p",
        what: format!(
            "{tris} triangles at {w}×{h}, 4× supersampling, shadow map, ambient obscurance"
        ),
        elements: tris,
        unit: "triangles",
        target_s: s.target(2.0),
        once: false,
        job: Box::new(move || render_mesh(&m, &opts).map(|_| ()).map_err(Into::into)),
    })
}

/// Rule 450 and a random n × n grid of density 0.3.
pub(crate) fn ca_input(n: usize, budget: &MemoryBudget) -> Result<(asperity_ca::Rule, Grid2<u8>)> {
    let rule = asperity_ca::Rule::new(asperity_ca::Family::Totalistic9, 2, 450)?;
    let init = asperity_ca::Init::Random {
        density: 0.3,
        seed: 7,
    };
    let grid = asperity_ca::initial_grid(&init, Some([n, n]), 2, budget)?;
    Ok((rule, grid))
}

fn ca_bits(s: &Setup) -> Result<Workload> {
    let n = s.size(8192, 512);
    let (rule, init) = ca_input(n, &s.budget)?;
    let a = asperity_ca::evolve::BitGrid::from_bytes(init.data(), n, n);
    let mut b = a.clone();
    let steps = 8;
    Ok(Workload {
        name: "ca/evolve-bits-8192",
        what: format!("{n}×{n} cyclic, rule 450, {steps} steps, bit-sliced (64 cells a word)"),
        elements: (n * n * steps) as u64,
        unit: "cell-updates",
        target_s: None,
        once: false,
        job: Box::new(move || {
            let mut cur = a.clone();
            for _ in 0..steps {
                cur.step_into(&rule, &mut b);
                std::mem::swap(&mut cur, &mut b);
            }
            Ok(())
        }),
    })
}

fn ca_bytes(s: &Setup) -> Result<Workload> {
    let n = s.size(8192, 512);
    let (rule, init) = ca_input(n, &s.budget)?;
    let src = init.data().to_vec();
    let mut dst = src.clone();
    Ok(Workload {
        name: "ca/evolve-bytes-8192",
        what: format!(
            "{n}×{n} cyclic, rule 450, 1 step, one byte per cell (the straightforward baseline)"
        ),
        elements: (n * n) as u64,
        unit: "cell-updates",
        target_s: None,
        once: false,
        job: Box::new(move || {
            asperity_ca::evolve::step_bytes(&rule, &src, &mut dst, n, n);
            Ok(())
        }),
    })
}

fn ca_accumulate(s: &Setup) -> Result<Workload> {
    let (n, steps) = s.size((8192, 256), (256, 16));
    let (rule, init) = ca_input(n, &s.budget)?;
    let p = asperity_ca::CaParams::new(rule, steps);
    let budget = s.budget;
    Ok(Workload {
        name: "ca/accumulate-8192x256",
        what: format!(
            "{n}×{n} cyclic, rule 450, {steps} steps evolved and accumulated into a height field"
        ),
        elements: (n * n * steps) as u64,
        unit: "cell-updates",
        target_s: s.target(5.0),
        once: false,
        job: Box::new(move || {
            asperity_ca::accumulate(&init, &p, &budget)
                .map(|_| ())
                .map_err(Into::into)
        }),
    })
}

fn fourier(s: &Setup) -> Result<Workload> {
    let n = s.size(1025, 129);
    let p = FourierParams {
        n,
        hurst: 0.8,
        modes: n / 8,
        rms: 0.05,
        spacing: 1.0 / n as f64,
    };
    let budget = s.budget;
    Ok(Workload {
        name: "core/fourier-surface",
        what: format!("{n}×{n} reference surface, {} modes per axis", n / 8),
        elements: (n * n) as u64,
        unit: "samples",
        target_s: None,
        once: false,
        job: Box::new(move || {
            fourier_surface(&p, 7, &budget)
                .map(|_| ())
                .map_err(Into::into)
        }),
    })
}

/// `asperity analyze` of a non-periodic 2048² field on its defaults: periodicity
/// test, levelling, Hann window, PSD, five Hurst estimators, three dimensions,
/// scale-dependent parameters (#21).
fn analyze_2048(s: &Setup) -> Result<Workload> {
    let n = s.size(2048, 128);
    let p = asperity_core::fourier_surface::FourierParams {
        n: 2 * n,
        hurst: 0.7,
        modes: n,
        rms: 1.0,
        spacing: 1.0,
    };
    let big = asperity_analysis::synthesis::fbm(&p, 7, &s.budget)?;
    // A crop of a periodic surface: the non-periodic case of measured data.
    let crop = HeightField::from_vec(
        [n, n],
        (0..n).flat_map(|j| big.row(j)[..n].to_vec()).collect(),
    )?;
    let surface = Surface::Height(crop);
    Ok(Workload {
        name: "analysis/analyze-2048",
        what: format!("analyze a {n}×{n} non-periodic field (defaults: Hann window, 5 estimators)"),
        elements: (n * n) as u64,
        unit: "samples",
        target_s: None,
        once: false,
        job: Box::new(move || {
            asperity_engine::analyze::analyze(
                &surface,
                "bench",
                &asperity_engine::analyze::AnalyzeOptions::default(),
                &asperity_core::MemoryBudget::unlimited(),
            )
            .map(|_| ())
        }),
    })
}

fn write_ply(s: &Setup) -> Result<Workload> {
    let m = benchmark_mesh(s.size(513, 65), &s.budget)?;
    let path = s.scratch.file("bench.ply")?;
    let tris = m.n_faces() as u64;
    Ok(Workload {
        name: "io/write-ply",
        what: format!("{tris} triangles, binary PLY with normals, atomic write + fsync"),
        elements: tris,
        unit: "triangles",
        target_s: None,
        once: false,
        job: Box::new(move || {
            asperity_io::write_mesh(&path, &m, &asperity_io::WriteOptions::default())?;
            Ok(())
        }),
    })
}

/// An ensemble of `model` runs on an L×L substrate, one run per core (as W(t)
/// averages use: each run is sequential, so this is how a simulation uses both
/// cores); `target_rate` in depositions per second.
fn deposition(
    s: &Setup,
    name: &'static str,
    model: Model,
    target_rate: Option<f64>,
) -> Result<Workload> {
    let (l, layers) = s.size((256, 1000.0), (64, 20.0));
    let p = DepositionParams::new(model, Lattice::new(l, 2)?, layers);
    let runs = rayon::current_num_threads();
    let n = p.depositions() * runs as u64;
    let budget = s.budget;
    Ok(Workload {
        name,
        what: format!(
            "{} on {l}×{l} columns, {layers} monolayers, {runs} runs in parallel ({n} depositions)",
            model.name()
        ),
        elements: n,
        unit: "depositions",
        target_s: target_rate.and_then(|r| s.target(n as f64 / r)),
        once: false,
        job: Box::new(move || {
            deposit_ensemble(&p, 7, runs, &budget, &NoProgress)?;
            Ok(())
        }),
    })
}

fn rd(s: &Setup) -> Result<Workload> {
    deposition(s, "growth/rd-2d", Model::Rd, Some(50e6))
}

fn rdsr(s: &Setup) -> Result<Workload> {
    deposition(s, "growth/rdsr-2d", Model::Rdsr { radius: 1 }, Some(50e6))
}

fn bd(s: &Setup) -> Result<Workload> {
    deposition(s, "growth/bd-2d", Model::Bd, None)
}

/// A 3-D DLA cluster of `n_full` particles (a hundredth with `quick`) from a
/// point or the plane.
fn dla_cluster(s: &Setup, name: &'static str, plane: bool, n_full: usize) -> Result<Workload> {
    let n = s.size(n_full, n_full / 100);
    let mut p = DlaParams::point(3, n);
    if plane {
        p.seed_shape = SeedShape::Plane;
        // 10⁷ particles fill about 1000 layers of a 1024² plane.
        let side = match n_full {
            10_000_000.. => 1024,
            1_000_000.. => 512,
            _ => 256,
        };
        let side = s.size(side, side / 4);
        p.size = [
            side,
            side,
            if n_full >= 10_000_000 { 2 * side } else { side },
        ];
    }
    let budget = s.budget;
    Ok(Workload {
        name,
        what: format!(
            "3-D lattice DLA, {n} particles, p = 1, {} seed, {}x{}x{} lattice",
            if plane { "plane" } else { "point" },
            p.size[0],
            p.size[1],
            p.size[2]
        ),
        elements: n as u64,
        unit: "particles",
        // #26: 10⁷ particles in 120 s.
        target_s: s.target(match n_full {
            10_000_000.. => 120.0,
            1_000_000.. => 20.0,
            _ => 2.0,
        }),
        once: n_full >= 1_000_000,
        job: Box::new(move || {
            let c = dla(&p, 7, 0, &budget, &NoProgress)?;
            match c.stopped {
                None => Ok(()),
                Some(why) => Err(invalid(why)),
            }
        }),
    })
}

fn dla_point_1e5(s: &Setup) -> Result<Workload> {
    dla_cluster(s, "growth/dla-point-1e5", false, 100_000)
}

fn dla_plane_1e5(s: &Setup) -> Result<Workload> {
    dla_cluster(s, "growth/dla-plane-1e5", true, 100_000)
}

fn dla_point_1e6(s: &Setup) -> Result<Workload> {
    dla_cluster(s, "growth/dla-point-1e6", false, 1_000_000)
}

fn dla_plane_1e6(s: &Setup) -> Result<Workload> {
    dla_cluster(s, "growth/dla-plane-1e6", true, 1_000_000)
}

fn dla_point_1e7(s: &Setup) -> Result<Workload> {
    dla_cluster(s, "growth/dla-point-1e7", false, 10_000_000)
}

fn dla_plane_1e7(s: &Setup) -> Result<Workload> {
    dla_cluster(s, "growth/dla-plane-1e7", true, 10_000_000)
}

/// Surface CA (gobron-chiba): 1000 Voronoi steps on a million-cell sphere.
fn surfca_voronoi(s: &Setup) -> Result<Workload> {
    use asperity_surfca::engine::{RunOptions, run};
    use asperity_surfca::voronoi::{PAPER_P, UNLABELLED, VoronoiRule, random_sites};
    use asperity_surfca::{CellSize, build};
    let (n, steps) = s.size((1_000_000, 1000), (20_000, 50));
    let mesh = asperity_core::shapes::icosphere(4, 1.0);
    let cells = build(&mesh, CellSize::Count(n), &s.budget)?;
    let sites = random_sites(&cells, 12, 7);
    let count = cells.len() as u64;
    Ok(Workload {
        name: "surfca/voronoi-1m-1000",
        what: format!(
            "surface Voronoi (12 sites, P = √2/2 − ½) on an icosphere with {count} cells, {steps} steps"
        ),
        elements: count * steps,
        unit: "cell-updates",
        target_s: s.target(5.0),
        once: !s.quick,
        job: Box::new(move || {
            let mut states = vec![UNLABELLED; cells.len()];
            for (l, &c) in sites.iter().enumerate() {
                states[c] = l as u32;
            }
            let rule = VoronoiRule {
                diagonal_p: PAPER_P,
            };
            let opts = RunOptions {
                seed: 7,
                max_steps: steps,
                stop_when_stable: false,
            };
            run(&cells, &rule, &mut states, &opts, |_, _| true);
            Ok(())
        }),
    })
}

/// Copper corrosion on the cup, a million cells, 1000 steps.
fn surfca_corrosion(s: &Setup) -> Result<Workload> {
    use asperity_surfca::corrosion::{CorrosionParams, corrode, initial};
    use asperity_surfca::{CellSize, build};
    let (n, steps) = s.size((1_000_000, 1000), (20_000, 50));
    let mesh = asperity_core::shapes::cup(48);
    let cells = build(&mesh, CellSize::Count(n), &s.budget)?;
    let count = cells.len() as u64;
    let p = CorrosionParams::default();
    Ok(Workload {
        name: "surfca/corrosion-1m-1000",
        what: format!(
            "copper corrosion on the cup, {count} cells, {steps} steps (default constants)"
        ),
        elements: count * steps,
        unit: "cell-updates",
        target_s: s.target(15.0),
        once: !s.quick,
        job: Box::new(move || {
            let mut st = initial(&cells, &p, 7);
            corrode(&cells, &p, &mut st, 7, steps, |_, _| true);
            Ok(())
        }),
    })
}

/// Multiresolution subdivision (velho-perlin, issue #8): 4 levels of a
/// 10 086-quad closed mesh (a cube with 41 × 41 quads per face), plain or with
/// rock detail; the peers' figures are for the plain refinement.
fn subdivision(s: &Setup, name: &'static str, rock: bool) -> Result<Workload> {
    use asperity_subdiv::catmull_clark::{Boundary, Creased};
    use asperity_subdiv::compose::{Layer, grow};
    let (n, levels) = s.size((41, 4), (8, 2));
    let base = Creased::smooth(asperity_core::shapes::cube_quads(n));
    let quads = (base.mesh.n_faces() as u64) << (2 * levels);
    // The plain refinement: the same layer with no detail.
    let layer = match rock {
        true => Layer::rock(),
        false => Layer {
            features: Vec::new(),
            ..Layer::rock()
        },
    };
    Ok(Workload {
        name,
        what: format!(
            "{levels} levels of a {}-quad cube{} → {quads} quads",
            base.mesh.n_faces(),
            if rock { " with rock detail" } else { ", plain" }
        ),
        elements: quads,
        unit: "output quads",
        target_s: if rock { s.target(0.7) } else { None },
        once: false,
        job: Box::new(move || {
            grow(&base, levels, Boundary::EdgeOnly, &layer, 1)?;
            Ok(())
        }),
    })
}

fn subdiv_plain(s: &Setup) -> Result<Workload> {
    subdivision(s, "subdiv/plain-10086-quads-4-levels", false)
}

fn subdiv_rock(s: &Setup) -> Result<Workload> {
    subdivision(s, "subdiv/rock-10086-quads-4-levels", true)
}

/// Projected IFS (poull-gentil): a depth-10 tensor-product attractor (≈ 1M
/// vertices) built and written as binary PLY.
fn ifs_surface(s: &Setup) -> Result<Workload> {
    use asperity_ifs::{Model, PresetParams, preset};
    let depth = s.size(10, 6);
    let Model::Surface(surf) =
        preset("takagi-landsberg-surface", &PresetParams::default())?.build()?
    else {
        return Err(invalid("takagi-landsberg-surface is a surface preset"));
    };
    let path = s.scratch.file("attractor.ply")?;
    let n = ((1u64 << depth) + 1).pow(2);
    let budget = s.budget;
    Ok(Workload {
        name: "ifs/surface-depth10",
        what: format!(
            "Takagi ⊗ Takagi attractor at depth {depth} ({n} vertices), built and written as binary PLY"
        ),
        elements: n,
        unit: "vertices",
        target_s: s.target(1.0),
        once: false,
        job: Box::new(move || {
            let m = surf.attractor_mesh(depth, &budget)?;
            asperity_io::write_mesh(&path, &m, &asperity_io::WriteOptions::default())?;
            Ok(())
        }),
    })
}

/// The pseudo-curvature ranges of every operator of every preset.
fn ifs_curvature(_: &Setup) -> Result<Workload> {
    use asperity_ifs::curvature::{curve_report, surface_report};
    use asperity_ifs::{
        DirectionAnalysis, FamilyOptions, Model, PresetParams, preset, preset_names,
    };
    let models: Vec<Model> = preset_names()
        .iter()
        .map(|(n, _)| Ok(preset(n, &PresetParams::default())?.build()?))
        .collect::<Result<_>>()?;
    let ops: u64 = models
        .iter()
        .map(|m| match m {
            Model::Curve(_) => 2,
            Model::Surface(_) => 4,
        })
        .sum();
    let analyse = move || {
        let opts = FamilyOptions::default();
        for m in &models {
            match m {
                Model::Curve(c) => {
                    let an = DirectionAnalysis::new(&c.pifs, &opts);
                    std::hint::black_box(curve_report(c, &an));
                }
                Model::Surface(s) => {
                    let a = DirectionAnalysis::new(&s.s, &opts);
                    let b = DirectionAnalysis::new(&s.t, &opts);
                    std::hint::black_box(surface_report(s, &a, &b));
                }
            }
        }
        Ok(())
    };
    Ok(Workload {
        name: "ifs/curvature-presets",
        what: format!(
            "eigen-decomposition, DCF family (dyadic depth 10 + periods ≤ 12) and pseudo-curvature ranges of all {ops} operators of the {} presets",
            preset_names().len()
        ),
        elements: ops,
        unit: "operators",
        target_s: None,
        once: false,
        job: Box::new(analyse),
    })
}
