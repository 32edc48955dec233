//! `asperity bench`: the workloads the issues name, timed end to end.
//!
//! criterion (`cargo bench -p asperity-benches`) gives statistically careful
//! figures for developers; this command lets a user measure the same workloads
//! on their own machine from the installed binary. Each workload builds its
//! input once (untimed), runs once to warm up, then `--repeat` timed runs; the
//! minimum and median are reported with throughput.

use std::time::Instant;

use anyhow::Context as _;
use asperity_core::fourier_surface::{FourierParams, fourier_surface};
use asperity_core::{Diagonal, MemoryBudget, TriMesh};
use asperity_growth::dla::{DlaParams, SeedShape, dla};
use asperity_growth::{DepositionParams, Lattice, Model, deposit_ensemble};
use asperity_render::{RenderOptions, render_mesh};
use serde_json::json;

use crate::cli::{BenchArgs, Context};
use crate::report::Report;

type Job = Box<dyn FnMut() -> anyhow::Result<()>>;

struct Workload {
    name: &'static str,
    what: String,
    /// Elements per run and their unit, for throughput.
    elements: u64,
    unit: &'static str,
    /// Target from the issue, if any (seconds per run).
    target_s: Option<f64>,
    /// Long workloads run once, without warm-up, whatever `--repeat` says.
    once: bool,
    job: Job,
}

fn surface_mesh(n: usize, budget: &MemoryBudget) -> anyhow::Result<TriMesh> {
    let h = fourier_surface(
        &FourierParams {
            n,
            hurst: 0.8,
            modes: (n / 8).max(1),
            rms: 0.05,
            spacing: 1.0 / n as f64,
        },
        7,
        budget,
    )?;
    Ok(h.to_trimesh(Diagonal::Alternating)?.with_computed_normals())
}

type MakeWorkload = Box<dyn Fn() -> anyhow::Result<Workload>>;

fn workloads(ctx: &Context, quick: bool) -> Vec<(&'static str, MakeWorkload)> {
    let budget = ctx.budget;
    let mut v: Vec<(&'static str, MakeWorkload)> = Vec::new();
    v.push((
        "render/2m-triangles-1080p",
        Box::new(move || {
            // 1001² samples → 2 000 000 triangles (issue #3's workload).
            let n = if quick { 101 } else { 1001 };
            let (w, h) = if quick { (320, 180) } else { (1920, 1080) };
            let m = surface_mesh(n, &budget)?;
            let tris = m.n_faces() as u64;
            let opts = RenderOptions {
                width: w,
                height: h,
                supersample: 2,
                shadows: true,
                budget,
                ..RenderOptions::default()
            };
            Ok(Workload {
                name: "render/2m-triangles-1080p",
                what: format!(
                    "{tris} triangles at {w}×{h}, 4× supersampling, shadow map, ambient obscurance"
                ),
                elements: tris,
                unit: "triangles",
                target_s: (!quick).then_some(2.0),
                once: false,
                job: Box::new(move || render_mesh(&m, &opts).map(|_| ()).map_err(Into::into)),
            })
        }),
    ));
    v.push((
        "ca/evolve-bits-8192",
        Box::new(move || {
            let n = if quick { 512 } else { 8192 };
            let rule = asperity_ca::Rule::new(asperity_ca::Family::Totalistic9, 2, 450)?;
            let init = asperity_ca::initial_grid(
                &asperity_ca::Init::Random {
                    density: 0.3,
                    seed: 7,
                },
                Some([n, n]),
                2,
                &budget,
            )?;
            let a = asperity_ca::evolve::BitGrid::from_bytes(init.data(), n, n);
            let mut b = a.clone();
            let steps = 8;
            Ok(Workload {
                name: "ca/evolve-bits-8192",
                what: format!(
                    "{n}×{n} cyclic, rule 450, {steps} steps, bit-sliced (64 cells a word)"
                ),
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
        }),
    ));
    v.push((
        "ca/evolve-bytes-8192",
        Box::new(move || {
            let n = if quick { 512 } else { 8192 };
            let rule = asperity_ca::Rule::new(asperity_ca::Family::Totalistic9, 2, 450)?;
            let init = asperity_ca::initial_grid(&asperity_ca::Init::Random { density: 0.3, seed: 7 }, Some([n, n]), 2, &budget)?;
            let src = init.data().to_vec();
            let mut dst = src.clone();
            Ok(Workload {
                name: "ca/evolve-bytes-8192",
                what: format!("{n}×{n} cyclic, rule 450, 1 step, one byte per cell (the straightforward baseline)"),
                elements: (n * n) as u64,
                unit: "cell-updates",
                target_s: None,
                once: false,
                job: Box::new(move || {
                    asperity_ca::evolve::step_bytes(&rule, &src, &mut dst, n, n);
                    Ok(())
                }),
            })
        }),
    ));
    v.push((
        "ca/accumulate-8192x256",
        Box::new(move || {
            let (n, steps) = if quick { (256, 16) } else { (8192, 256) };
            let rule = asperity_ca::Rule::new(asperity_ca::Family::Totalistic9, 2, 450)?;
            let init = asperity_ca::initial_grid(&asperity_ca::Init::Random { density: 0.3, seed: 7 }, Some([n, n]), 2, &budget)?;
            let p = asperity_ca::CaParams::new(rule, steps);
            Ok(Workload {
                name: "ca/accumulate-8192x256",
                what: format!("{n}×{n} cyclic, rule 450, {steps} steps evolved and accumulated into a height field"),
                elements: (n * n * steps) as u64,
                unit: "cell-updates",
                target_s: (!quick).then_some(5.0),
                once: false,
                job: Box::new(move || asperity_ca::accumulate(&init, &p, &budget).map(|_| ()).map_err(Into::into)),
            })
        }),
    ));
    v.push((
        "core/fourier-surface",
        Box::new(move || {
            let n = if quick { 129 } else { 1025 };
            let p = FourierParams {
                n,
                hurst: 0.8,
                modes: n / 8,
                rms: 0.05,
                spacing: 1.0 / n as f64,
            };
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
        }),
    ));
    v.push((
        "io/write-ply",
        Box::new(move || {
            let n = if quick { 65 } else { 513 };
            let m = surface_mesh(n, &budget)?;
            let dir = tempfile_dir()?;
            let path = dir.join("bench.ply");
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
        }),
    ));
    for (model, name, target_rate) in [
        (Model::Rd, "growth/rd-2d", Some(50e6)),
        (Model::Rdsr { radius: 1 }, "growth/rdsr-2d", Some(50e6)),
        (Model::Bd, "growth/bd-2d", None),
    ] {
        v.push((
            name,
            Box::new(move || {
                let (l, layers) = if quick { (64, 20.0) } else { (256, 1000.0) };
                let p = DepositionParams::new(model, Lattice::new(l, 2)?, layers);
                // One run per core (an ensemble, as W(t) averages use): each run
                // is sequential, so this is how a simulation uses both cores.
                let runs = rayon::current_num_threads();
                let n = p.depositions() * runs as u64;
                Ok(Workload {
                    name,
                    what: format!(
                        "{} on {l}×{l} columns, {layers} monolayers, {runs} runs in parallel ({n} depositions)",
                        model.name()
                    ),
                    elements: n,
                    unit: "depositions",
                    target_s: target_rate.filter(|_| !quick).map(|r| n as f64 / r),
                    once: false,
                    job: Box::new(move || {
                        deposit_ensemble(&p, 7, runs, &budget, &asperity_core::NoProgress)?;
                        Ok(())
                    }),
                })
            }),
        ));
    }
    for (name, plane, n_full) in [
        ("growth/dla-point-1e5", false, 100_000usize),
        ("growth/dla-plane-1e5", true, 100_000),
        ("growth/dla-point-1e6", false, 1_000_000),
        ("growth/dla-plane-1e6", true, 1_000_000),
    ] {
        v.push((
            name,
            Box::new(move || {
                let n = if quick { n_full / 100 } else { n_full };
                let mut p = DlaParams::point(3, n);
                if plane {
                    p.seed_shape = SeedShape::Plane;
                    let side = if n_full >= 1_000_000 { 512 } else { 256 };
                    let side = if quick { side / 4 } else { side };
                    p.size = [side, side, side];
                }
                let target = if n_full >= 1_000_000 { 20.0 } else { 2.0 };
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
                    target_s: (!quick).then_some(target),
                    once: n_full >= 1_000_000,
                    job: Box::new(move || {
                        let c = dla(&p, 7, 0, &budget, &asperity_core::NoProgress)?;
                        anyhow::ensure!(c.stopped.is_none(), "{:?}", c.stopped);
                        Ok(())
                    }),
                })
            }),
        ));
    }
    // Surface CA (gobron-chiba): 1000 Voronoi steps on a million-cell sphere.
    v.push((
        "surfca/voronoi-1m-1000",
        Box::new(move || {
            use asperity_surfca::engine::{RunOptions, run};
            use asperity_surfca::voronoi::{PAPER_P, UNLABELLED, VoronoiRule, random_sites};
            use asperity_surfca::{CellSize, build};
            let (n, steps) = if quick { (20_000, 50) } else { (1_000_000, 1000) };
            let mesh = asperity_core::shapes::icosphere(4, 1.0);
            let cells = build(&mesh, CellSize::Count(n), &budget)?;
            let sites = random_sites(&cells, 12, 7);
            let count = cells.len() as u64;
            Ok(Workload {
                name: "surfca/voronoi-1m-1000",
                what: format!(
                    "surface Voronoi (12 sites, P = √2/2 − ½) on an icosphere with {count} cells, {steps} steps"
                ),
                elements: count * steps,
                unit: "cell-updates",
                target_s: (!quick).then_some(5.0),
                once: !quick,
                job: Box::new(move || {
                    let mut states = vec![UNLABELLED; cells.len()];
                    for (l, &c) in sites.iter().enumerate() {
                        states[c] = l as u32;
                    }
                    run(
                        &cells,
                        &VoronoiRule { diagonal_p: PAPER_P },
                        &mut states,
                        &RunOptions {
                            seed: 7,
                            max_steps: steps,
                            stop_when_stable: false,
                        },
                        |_, _| true,
                    );
                    Ok(())
                }),
            })
        }),
    ));
    v.push((
        "surfca/corrosion-1m-1000",
        Box::new(move || {
            use asperity_surfca::corrosion::{CorrosionParams, corrode, initial};
            use asperity_surfca::{CellSize, build};
            let (n, steps) = if quick {
                (20_000, 50)
            } else {
                (1_000_000, 1000)
            };
            let mesh = asperity_core::shapes::cup(48);
            let cells = build(&mesh, CellSize::Count(n), &budget)?;
            let count = cells.len() as u64;
            let p = CorrosionParams::default();
            Ok(Workload {
                name: "surfca/corrosion-1m-1000",
                what: format!(
                    "copper corrosion on the cup, {count} cells, {steps} steps (default constants)"
                ),
                elements: count * steps,
                unit: "cell-updates",
                target_s: (!quick).then_some(15.0),
                once: !quick,
                job: Box::new(move || {
                    let mut s = initial(&cells, &p, 7);
                    corrode(&cells, &p, &mut s, 7, steps, |_, _| true);
                    Ok(())
                }),
            })
        }),
    ));
    // Multiresolution subdivision (velho-perlin, issue #8): 4 levels of a
    // 10 086-quad closed mesh (a cube with 41 × 41 quads per face), plain and
    // with rock detail; the peers' figures are for the plain refinement.
    for (name, rock) in [
        ("subdiv/plain-10086-quads-4-levels", false),
        ("subdiv/rock-10086-quads-4-levels", true),
    ] {
        v.push((
            name,
            Box::new(move || {
                use asperity_subdiv::catmull_clark::{Boundary, Creased};
                use asperity_subdiv::compose::{Layer, grow};
                use asperity_subdiv::detail::{Feature, Procedure, Rock};
                let (n, levels) = if quick { (8, 2) } else { (41, 4) };
                let base = Creased::smooth(asperity_core::shapes::cube_quads(n));
                let quads = (base.mesh.n_faces() as u64) << (2 * levels);
                let layer = Layer {
                    name: "rock".into(),
                    features: if rock {
                        vec![Feature::global(Procedure::Rock(Rock::fractal(0.02, 0.5)))]
                    } else {
                        Vec::new()
                    },
                    edits: Vec::new(),
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
                    target_s: (!quick && rock).then_some(0.7),
                    once: false,
                    job: Box::new(move || {
                        grow(&base, levels, Boundary::EdgeOnly, &layer, 1)?;
                        Ok(())
                    }),
                })
            }),
        ));
    }
    // Projected IFS (poull-gentil): a depth-10 tensor-product attractor (≈ 1M
    // vertices) built and written as binary PLY; and the pseudo-curvature ranges of
    // every operator of every preset.
    v.push((
        "ifs/surface-depth10",
        Box::new(move || {
            use asperity_ifs::{Model, PresetParams, preset};
            let depth = if quick { 6 } else { 10 };
            let Model::Surface(s) =
                preset("takagi-landsberg-surface", &PresetParams::default())?.build()?
            else {
                anyhow::bail!("takagi-landsberg-surface is a surface preset")
            };
            let dir = tempfile_dir()?;
            let path = dir.join("attractor.ply");
            let n = ((1u64 << depth) + 1).pow(2);
            Ok(Workload {
                name: "ifs/surface-depth10",
                what: format!("Takagi ⊗ Takagi attractor at depth {depth} ({n} vertices), built and written as binary PLY"),
                elements: n,
                unit: "vertices",
                target_s: (!quick).then_some(1.0),
                once: false,
                job: Box::new(move || {
                    let m = s.attractor_mesh(depth, &budget)?;
                    asperity_io::write_mesh(&path, &m, &asperity_io::WriteOptions::default())?;
                    Ok(())
                }),
            })
        }),
    ));
    v.push((
        "ifs/curvature-presets",
        Box::new(move || {
            use asperity_ifs::curvature::{curve_report, surface_report};
            use asperity_ifs::{DirectionAnalysis, FamilyOptions, Model, PresetParams, preset, preset_names};
            let models: Vec<Model> = preset_names()
                .iter()
                .map(|(n, _)| Ok(preset(n, &PresetParams::default())?.build()?))
                .collect::<anyhow::Result<_>>()?;
            let ops: u64 = models
                .iter()
                .map(|m| match m {
                    Model::Curve(_) => 2,
                    Model::Surface(_) => 4,
                })
                .sum();
            Ok(Workload {
                name: "ifs/curvature-presets",
                what: format!(
                    "eigen-decomposition, DCF family (dyadic depth 10 + periods ≤ 12) and pseudo-curvature ranges of all {ops} operators of the {} presets",
                    models.len()
                ),
                elements: ops,
                unit: "operators",
                target_s: None,
                once: false,
                job: Box::new(move || {
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
                }),
            })
        }),
    ));
    // Level-set reconstruction of an RDSR sphere (kim-machiraju-thompson Fig. 8):
    // distance + tagging + 30 RK2 steps + marching cubes, and the naive full grid.
    for (name, res, full, target) in [
        ("levelset/pipeline-128", 128usize, false, Some(0.5)),
        ("levelset/full-grid-128", 128, true, None),
        ("levelset/pipeline-256-1e6", 256, false, Some(3.0)),
    ] {
        v.push((
            name,
            Box::new(move || {
                use asperity_growth::curved::{CurvedParams, CurvedSubstrate, deposit_curved};
                use asperity_levelset::{Band, ReconstructParams, Sizing, reconstruct};
                let (radius, layers, res) = match (quick, res) {
                    (true, _) => (8.0, 3.0, 32),
                    (false, 128) => (30.0, 11.0, 128),
                    _ => (60.0, 26.0, 256),
                };
                let points = deposit_curved(
                    &CurvedParams {
                        model: Model::Rdsr { radius: 1 },
                        substrate: CurvedSubstrate::Sphere(radius),
                        layers,
                        samples_per_decade: 2,
                    },
                    7,
                    0,
                    &budget,
                    &asperity_core::NoProgress,
                )?
                .points();
                let params = ReconstructParams {
                    sizing: Sizing::Resolution(res),
                    band: if full { Band::Full } else { Band::Narrow },
                    ..ReconstructParams::default()
                };
                let n = points.len() as u64;
                Ok(Workload {
                    name,
                    what: format!(
                        "RDSR sphere, {n} points, {res} cells across, 30 ENO2/RK2 steps{}",
                        if full { ", every node every step (naive)" } else { ", narrow band" }
                    ),
                    elements: n,
                    unit: "points",
                    target_s: target.filter(|_| !quick),
                    once: res >= 256,
                    job: Box::new(move || {
                        let r = reconstruct(
                            &points,
                            &params,
                            &budget,
                            &asperity_core::NoProgress,
                            &mut |_, _| {},
                        )?;
                        let t = r.timings;
                        eprintln!(
                            "  {name}: grid {:?}, distance {:.3} s, tagging {:.3} s, initial {:.3} s, flow {:.3} s, marching cubes {:.3} s, total {:.3} s",
                            r.grid.dims, t.distance, t.tagging, t.initial, t.evolution, t.extraction, t.total
                        );
                        Ok(())
                    }),
                })
            }),
        ));
    }
    v
}

fn tempfile_dir() -> anyhow::Result<std::path::PathBuf> {
    let d = std::env::temp_dir().join(format!("asperity-bench-{}", std::process::id()));
    std::fs::create_dir_all(&d).with_context(|| format!("creating {}", d.display()))?;
    Ok(d)
}

pub fn run(ctx: &Context, a: &BenchArgs) -> anyhow::Result<()> {
    let mut report = Report::new("bench", ctx);
    let mut results = Vec::new();
    for (name, make) in workloads(ctx, a.quick) {
        if a.filter.as_deref().is_some_and(|f| !name.contains(f)) {
            continue;
        }
        let mut w = make()?;
        let repeat = if w.once { 1 } else { a.repeat };
        if !w.once {
            (w.job)()?; // warm-up
        }
        let mut times = Vec::with_capacity(repeat as usize);
        for _ in 0..repeat {
            let t = Instant::now();
            (w.job)()?;
            times.push(t.elapsed().as_secs_f64());
        }
        times.sort_by(f64::total_cmp);
        let (min, median) = (times[0], times[times.len() / 2]);
        let rate = w.elements as f64 / median;
        let verdict = w.target_s.map(|t| {
            if median <= t {
                format!(" (target < {t} s: met)")
            } else {
                format!(" (target < {t} s: MISSED)")
            }
        });
        if !ctx.json {
            outln!(
                "{:<28} median {:>9.3} ms  min {:>9.3} ms  {:>8.2} M {}/s{}",
                w.name,
                median * 1e3,
                min * 1e3,
                rate / 1e6,
                w.unit,
                verdict.unwrap_or_default()
            );
            outln!("{:<28} {}", "", w.what);
        }
        results.push(json!({"name": w.name, "what": w.what, "median_s": median, "min_s": min, "runs": times.len(), "elements": w.elements, "unit": w.unit, "per_second": rate, "target_s": w.target_s}));
    }
    let rate = |n: &str| {
        results
            .iter()
            .find(|r| r["name"] == n)
            .and_then(|r| r["per_second"].as_f64())
    };
    if let (Some(bits), Some(bytes)) = (rate("ca/evolve-bits-8192"), rate("ca/evolve-bytes-8192")) {
        if !ctx.json {
            outln!(
                "ca: bit-sliced / byte-per-cell evolution = {:.1}× (same run)",
                bits / bytes
            );
        }
        report.measure("ca_bits_over_bytes", bits / bytes);
    }
    let _ = std::fs::remove_dir_all(
        std::env::temp_dir().join(format!("asperity-bench-{}", std::process::id())),
    );
    anyhow::ensure!(
        !results.is_empty(),
        "no workload matches {:?}",
        a.filter.as_deref().unwrap_or("")
    );
    report.measure("workloads", results);
    report.measure(
        "machine",
        json!({"threads": ctx.threads, "os": std::env::consts::OS, "arch": std::env::consts::ARCH}),
    );
    report.finish(ctx)
}
