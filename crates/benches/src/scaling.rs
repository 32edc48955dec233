//! How each method's cost grows with its input (`asperity bench --scaling`,
//! issue #26): a doubling series of input sizes per method, each point one
//! [`Workload`], and the log–log slope of time against the elements, to set
//! beside the algorithm's expected complexity.
//!
//! The front end runs each point in a fresh process, so its peak memory (the
//! kernel's high-water mark) belongs to that point alone.

use asperity_core::NoProgress;
use asperity_core::fourier_surface::{FourierParams, benchmark_mesh};
use asperity_growth::dla::{DlaParams, dla};
use asperity_growth::{DepositionParams, Lattice, Model, deposit};
use asperity_render::{RenderOptions, render_mesh};

use crate::workloads::{Setup, Workload};
use asperity_engine::error::{Result, invalid};

/// One method's series.
pub struct Series {
    /// The method, as `--scaling` names it.
    pub name: &'static str,
    /// What doubles from point to point.
    pub input: &'static str,
    /// The expected exponent of time in the elements.
    pub expected: f64,
    /// Why that exponent.
    pub why: &'static str,
    /// The input size of each point, at full size or (`quick`) for tests.
    sizes: fn(bool) -> Vec<u64>,
    /// The workload at one size.
    build: fn(&Setup, u64) -> Result<Workload>,
}

impl Series {
    /// The sizes of the series.
    pub fn sizes(&self, quick: bool) -> Vec<u64> {
        (self.sizes)(quick)
    }

    /// The workload of the point of size `n`.
    ///
    /// # Errors
    /// Building the input failed (memory budget, parameters).
    pub fn workload(&self, setup: &Setup, n: u64) -> Result<Workload> {
        (self.build)(setup, n)
    }
}

/// `first`, `first·√2`, `first·2`, … (`count` sizes whose squares double).
fn root2(first: f64, count: usize) -> Vec<u64> {
    (0..count)
        .map(|k| (first * 2f64.powf(k as f64 / 2.0)).round() as u64)
        .collect()
}

/// `first`, `2·first`, `4·first`, …
fn doubling(first: u64, count: usize) -> Vec<u64> {
    (0..count).map(|k| first << k).collect()
}

/// Every method's series, in table order.
pub const SERIES: &[Series] = &[
    Series {
        name: "growth",
        input: "columns L² (RDSR 2+1D, 100 monolayers)",
        expected: 1.0,
        why: "one local relaxation per deposition",
        sizes: |q| if q { root2(32.0, 5) } else { root2(256.0, 5) },
        build: growth,
    },
    Series {
        name: "dla",
        input: "particles (3-D, point seed)",
        expected: 1.0,
        why: "walks jump by the distance map, so a particle costs about the same however large the cluster",
        sizes: |q| {
            if q {
                doubling(500, 5)
            } else {
                doubling(25_000, 5)
            }
        },
        build: dla_point,
    },
    Series {
        name: "levelset",
        input: "grid nodes n³ (RDSR sphere, narrow band)",
        expected: 2.0 / 3.0,
        why: "every stage works on the 8³-node bricks near the points and the front, a shell whose nodes grow as n² = (n³)^(2/3)",
        sizes: |q| {
            if q {
                vec![24, 30, 38, 48, 60]
            } else {
                vec![64, 81, 102, 128, 161]
            }
        },
        build: levelset,
    },
    Series {
        name: "ca",
        input: "cells (rule 450, 16 steps accumulated)",
        expected: 1.0,
        why: "one bit-sliced update per cell per step",
        // any side: rows whose width is not a multiple of 64 end in a partly
        // filled word and take the same bit-sliced path
        sizes: |q| root2(if q { 256.0 } else { 1024.0 }, 5),
        build: ca,
    },
    Series {
        name: "subdivision",
        input: "base quads (cube, 3 levels with rock detail)",
        expected: 1.0,
        why: "each level quadruples the faces; work per face is constant",
        sizes: |q| if q { root2(4.0, 5) } else { root2(12.0, 5) },
        build: subdivision,
    },
    Series {
        name: "ifs",
        input: "attractor vertices (Takagi ⊗ Takagi, depth +1 quadruples them)",
        expected: 1.0,
        why: "one affine map per vertex per level",
        sizes: |q| {
            if q {
                vec![4, 5, 6, 7, 8]
            } else {
                vec![6, 7, 8, 9, 10]
            }
        },
        build: ifs,
    },
    Series {
        name: "surfca",
        input: "cells (surface Voronoi on an icosphere, 200 steps)",
        expected: 1.0,
        why: "each step visits every cell and its neighbours once",
        sizes: |q| {
            if q {
                doubling(5_000, 5)
            } else {
                doubling(25_000, 5)
            }
        },
        build: surfca,
    },
    Series {
        name: "analysis",
        input: "samples n² (fBm height field, analyze)",
        expected: 1.05,
        why: "FFT-based spectra, O(N log N): slope 1 plus log N / ln growth ≈ 0.05 over this range",
        sizes: |q| if q { root2(64.0, 5) } else { root2(256.0, 5) },
        build: analysis,
    },
    Series {
        name: "render",
        input: "triangles (at 960×540, shadows)",
        expected: 1.0,
        why: "transform and rasterise every triangle; the per-pixel work is fixed and flattens the slope at small sizes",
        sizes: |q| if q { root2(64.0, 5) } else { root2(256.0, 5) },
        build: render,
    },
];

/// The series of `name`.
///
/// # Errors
/// An unknown name, with the known ones.
pub fn series(name: &str) -> Result<&'static Series> {
    SERIES.iter().find(|s| s.name == name).ok_or_else(|| {
        let names: Vec<_> = SERIES.iter().map(|s| s.name).collect();
        invalid(format!(
            "⟨scaling⟩ {name:?}: no such method ({}, or all)",
            names.join(", ")
        ))
    })
}

/// The least-squares slope of log `y` against log `x`.
pub fn loglog_slope(x: &[f64], y: &[f64]) -> Option<f64> {
    let pts: Vec<(f64, f64)> = x
        .iter()
        .zip(y)
        .filter(|(a, b)| **a > 0.0 && **b > 0.0)
        .map(|(a, b)| (a.ln(), b.ln()))
        .collect();
    let n = pts.len() as f64;
    if pts.len() < 2 {
        return None;
    }
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

fn work(
    name: &'static str,
    what: String,
    elements: u64,
    unit: &'static str,
    job: crate::workloads::Job,
) -> Workload {
    Workload {
        name,
        what,
        elements,
        unit,
        target_s: None,
        once: true,
        job,
    }
}

fn growth(s: &Setup, l: u64) -> Result<Workload> {
    let p = DepositionParams::new(
        Model::Rdsr { radius: 1 },
        Lattice::new(l as usize, 2)?,
        100.0,
    );
    let budget = s.budget;
    let n = p.depositions();
    Ok(work(
        "growth",
        format!("RDSR on {l}×{l} columns, 100 monolayers"),
        n,
        "depositions",
        Box::new(move || {
            deposit(&p, 7, 0, &budget, &NoProgress)?;
            Ok(())
        }),
    ))
}

fn dla_point(s: &Setup, n: u64) -> Result<Workload> {
    let p = DlaParams::point(3, n as usize);
    let budget = s.budget;
    Ok(work(
        "dla",
        format!("3-D DLA from a point, {n} particles"),
        n,
        "particles",
        Box::new(move || {
            let c = dla(&p, 7, 0, &budget, &NoProgress)?;
            c.stopped.map_or(Ok(()), |why| Err(invalid(why)))
        }),
    ))
}

fn levelset(s: &Setup, res: u64) -> Result<Workload> {
    use asperity_levelset::{ReconstructParams, Sizing, reconstruct};
    let (radius, layers) = if s.quick { (8.0, 3.0) } else { (30.0, 11.0) };
    let points = crate::workloads::rdsr_sphere_cloud(radius, layers, &s.budget)?;
    let params = ReconstructParams {
        sizing: Sizing::Resolution(res as usize),
        ..ReconstructParams::default()
    };
    let budget = s.budget;
    Ok(work(
        "levelset",
        format!("RDSR sphere, {} points, {res} cells across", points.len()),
        res.pow(3),
        "nodes",
        Box::new(move || {
            reconstruct(&points, &params, &budget, &NoProgress, &mut |_, _| {})?;
            Ok(())
        }),
    ))
}

fn ca(s: &Setup, n: u64) -> Result<Workload> {
    let n = n as usize;
    let (rule, grid) = crate::workloads::ca_input(n, &s.budget)?;
    let steps = 16;
    let p = asperity_ca::CaParams::new(rule, steps);
    let budget = s.budget;
    Ok(work(
        "ca",
        format!("{n}×{n} cells, rule 450, {steps} steps accumulated"),
        (n * n) as u64,
        "cells",
        Box::new(move || {
            asperity_ca::accumulate(&grid, &p, &budget)?;
            Ok(())
        }),
    ))
}

fn subdivision(_: &Setup, n: u64) -> Result<Workload> {
    use asperity_subdiv::catmull_clark::{Boundary, Creased};
    use asperity_subdiv::compose::{Layer, grow};
    let base = Creased::smooth(asperity_core::shapes::cube_quads(n as usize));
    let quads = base.mesh.n_faces() as u64;
    let layer = Layer::rock();
    Ok(work(
        "subdivision",
        format!("3 levels of a {quads}-quad cube with rock detail"),
        quads,
        "base quads",
        Box::new(move || {
            grow(&base, 3, Boundary::EdgeOnly, &layer, 1)?;
            Ok(())
        }),
    ))
}

fn ifs(s: &Setup, depth: u64) -> Result<Workload> {
    use asperity_ifs::{Model as IfsModel, PresetParams, preset};
    let IfsModel::Surface(surf) =
        preset("takagi-landsberg-surface", &PresetParams::default())?.build()?
    else {
        return Err(invalid("takagi-landsberg-surface is a surface preset"));
    };
    let depth = depth as u32;
    let budget = s.budget;
    Ok(work(
        "ifs",
        format!("Takagi ⊗ Takagi attractor mesh at depth {depth}"),
        ((1u64 << depth) + 1).pow(2),
        "vertices",
        Box::new(move || {
            surf.attractor_mesh(depth, &budget)?;
            Ok(())
        }),
    ))
}

fn surfca(s: &Setup, n: u64) -> Result<Workload> {
    use asperity_surfca::engine::{RunOptions, run};
    use asperity_surfca::voronoi::{PAPER_P, UNLABELLED, VoronoiRule, random_sites};
    use asperity_surfca::{CellSize, build};
    let mesh = asperity_core::shapes::icosphere(4, 1.0);
    let cells = build(&mesh, CellSize::Count(n as usize), &s.budget)?;
    let sites = random_sites(&cells, 12, 7);
    let count = cells.len() as u64;
    Ok(work(
        "surfca",
        format!("surface Voronoi, {count} cells, 200 steps"),
        count,
        "cells",
        Box::new(move || {
            let mut states = vec![UNLABELLED; cells.len()];
            for (l, &c) in sites.iter().enumerate() {
                states[c] = l as u32;
            }
            let rule = VoronoiRule {
                diagonal_p: PAPER_P,
            };
            let opts = RunOptions {
                seed: 7,
                max_steps: 200,
                stop_when_stable: false,
            };
            run(&cells, &rule, &mut states, &opts, |_, _| true);
            Ok(())
        }),
    ))
}

fn analysis(s: &Setup, n: u64) -> Result<Workload> {
    let n = n as usize;
    let p = FourierParams {
        n,
        hurst: 0.8,
        modes: n / 2,
        rms: 1.0,
        spacing: 1.0,
    };
    let surface =
        asperity_io::Surface::Height(asperity_analysis::synthesis::fbm(&p, 7, &s.budget)?);
    Ok(work(
        "analysis",
        format!("analyze of a {n}×{n} fBm field (defaults)"),
        (n * n) as u64,
        "samples",
        Box::new(move || {
            asperity_engine::analyze::analyze(
                &surface,
                "scaling",
                &asperity_engine::analyze::AnalyzeOptions::default(),
                &asperity_core::MemoryBudget::unlimited(),
            )
            .map(|_| ())
        }),
    ))
}

fn render(s: &Setup, n: u64) -> Result<Workload> {
    let m = benchmark_mesh(n as usize, &s.budget)?;
    let opts = RenderOptions {
        width: 960,
        height: 540,
        shadows: true,
        budget: s.budget,
        ..RenderOptions::default()
    };
    Ok(work(
        "render",
        format!("{} triangles at 960×540 with shadows", m.n_faces()),
        m.n_faces() as u64,
        "triangles",
        Box::new(move || render_mesh(&m, &opts).map(|_| ()).map_err(Into::into)),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_of_a_power_law_and_sizes_that_double() {
        let x = [1.0, 2.0, 4.0, 8.0];
        let y: Vec<f64> = x.iter().map(|v: &f64| 3.0 * v.powf(1.5)).collect();
        assert!((loglog_slope(&x, &y).unwrap() - 1.5).abs() < 1e-12);
        assert_eq!(loglog_slope(&[1.0], &[1.0]), None);
        for s in SERIES {
            for quick in [false, true] {
                let sizes = s.sizes(quick);
                assert!(sizes.len() >= 5, "{}", s.name);
                assert!(
                    sizes.windows(2).all(|w| w[1] > w[0]),
                    "{} {sizes:?}",
                    s.name
                );
            }
        }
        assert!(series("nope").is_err());
    }
}
