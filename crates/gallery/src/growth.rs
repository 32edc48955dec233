//! Surface growth (kim-machiraju-thompson §4): RD, RDSR and BD height fields
//! and their widths (Figure 3), DLA clusters in 2-D (Figure 1) and 3-D (Figure
//! 4), DLA terrains from the
//! plane, dendritic and moss-like (Figures 9–11), and RDSR on a sphere
//! (Figure 8).

use asperity_engine::Result;
use asperity_engine::core::{NoProgress, PointSet, RgbaImage, TimeBudget};
use asperity_engine::error::invalid;
use asperity_engine::growth::dla::{self as dla_job, SeedInputs};
use asperity_engine::growth::{
    self as growth_job, BdParams, DepositJob, DepositParams, RdParams, RdsrParams, SubstrateShape,
};
use asperity_engine::io::Surface;
use asperity_engine::methods::analysis::scaling::{
    density_dimension, density_profile, growth_exponent, gyration_dimension,
};
use asperity_engine::methods::growth::curved::CurvedDeposit;
use asperity_engine::methods::growth::dla::DlaCluster;
use asperity_engine::methods::growth::{Deposit, WidthSeries};
use asperity_engine::methods::render::plot::{Plot, Series, Style, plot_svg};
use asperity_engine::methods::render::{
    ColorMap, RenderOptions, Shader, render_height, render_points,
};
use asperity_engine::params::{CliJob, LatticeSize, command_line};

use crate::{Env, Item, Section, fact};

/// The section.
///
/// # Errors
/// Any simulation's, writer's or renderer's.
pub fn section(env: &Env) -> Result<Section> {
    let mut items = deposition(env)?;
    items.push(dla_2d(env)?);
    items.push(dla_point(env)?);
    for (stick, tag) in [(1.0, "dendritic"), (0.1, "moss")] {
        items.push(dla_plane(env, stick, tag)?);
    }
    items.push(sphere(env)?);
    Ok(Section {
        title: "Surface growth (kim-machiraju-thompson §4)".into(),
        source: "asperity-growth — §4.1 Fig. 3, §4.2 Fig. 4, §6 Figs. 8–11".into(),
        blurb: "Random deposition, deposition with surface relaxation (Family), ballistic deposition and diffusion-limited \
                aggregation on the lattice, on a plane, a sphere or any closed mesh. The point sets feed the level-set \
                reconstruction; the exponents are checked against theory in the tests."
            .into(),
        items,
    })
}

/// An RDSR (Family) deposit of `layers` monolayers on a ball of `radius` cells
/// (kim-machiraju-thompson Fig. 8) as `asperity growth rdsr --substrate
/// sphere` makes it, and that command line; shared by the growth and
/// reconstruction sections.
///
/// # Errors
/// The simulator's.
pub fn rdsr_sphere(radius: f64, layers: f64, env: &Env) -> Result<(CurvedDeposit, String)> {
    let p = RdsrParams {
        deposit: DepositParams {
            substrate: SubstrateShape::Sphere,
            radius,
            layers,
            samples_per_decade: 5,
            ..DepositParams::DEFAULT
        },
        ..RdsrParams::DEFAULT
    };
    let growth_job::Deposited::Curved(_, run) = deposited(env, &p)? else {
        return Err(invalid("a sphere substrate gave a flat deposit"));
    };
    Ok((run.deposit, command_line(&p, env.seed, Some("pts.ply"))?))
}

/// The engine's deposition job `p`, run as the CLI runs it.
fn deposited<P: DepositJob>(env: &Env, p: &P) -> Result<growth_job::Deposited> {
    growth_job::deposit(
        p,
        None,
        false,
        env.seed,
        (&env.budget, &TimeBudget::unlimited()),
        &NoProgress,
    )
}

/// A flat deposit as `asperity growth rd|rdsr|bd` runs it with `p` (the
/// engine's job): the first run's deposit and W(t), and the command line.
fn deposit_job<P: DepositJob + CliJob>(
    env: &Env,
    p: &P,
) -> Result<((Deposit, WidthSeries), String)> {
    let growth_job::Deposited::Flat(_, run) = deposited(env, p)? else {
        return Err(invalid("a flat substrate gave a curved deposit"));
    };
    let cli = command_line(p, env.seed, Some("h.npy"))?;
    Ok(((run.deposit, run.series), cli))
}

/// DLA as `asperity growth dla` runs it with `p` (the engine's job), and
/// that command line.
fn grow_dla(env: &Env, p: &dla_job::DlaParams) -> Result<(DlaCluster, String)> {
    let run = dla_job::grow(
        p,
        SeedInputs::default(),
        env.seed,
        &env.budget,
        &TimeBudget::unlimited(),
        &NoProgress,
    )?;
    Ok((run.cluster, command_line(p, env.seed, Some("pts.ply"))?))
}

/// Points coloured by a per-point value in [0, 1] (deposition order, height).
fn colored_points(
    pts: Vec<[f64; 3]>,
    t: impl Fn(usize, &[f64; 3]) -> f64,
    map: ColorMap,
) -> Result<PointSet> {
    let cols: Vec<[u8; 4]> = pts
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let c = map.map(t(k, p).clamp(0.0, 1.0));
            [c[0], c[1], c[2], 255]
        })
        .collect();
    let mut ps = PointSet::new(pts);
    ps.set_colors(cols)?;
    Ok(ps)
}

/// Writes a point set and its render; returns (file, picture).
fn points(env: &Env, stem: &str, ps: PointSet) -> Result<(String, String)> {
    let pic = render_points(&ps, &env.view())?;
    let file = env.write(&format!("{stem}.ply"), &Surface::Points(ps))?;
    let pic = env.picture(&format!("{stem}.png"), &pic)?;
    Ok((file, pic))
}

/// Figure 3: RD, RDSR and BD height fields after the same time, and W(t).
fn deposition(env: &Env) -> Result<Vec<Item>> {
    let l = if env.quick { 64 } else { 128 };
    let mut items = Vec::new();
    let mut width_series = Vec::new();
    let deposit = DepositParams {
        size: l,
        ..DepositParams::DEFAULT
    };
    for (name, run) in [
        (
            "rd",
            deposit_job(
                env,
                &RdParams {
                    deposit: deposit.clone(),
                },
            )?,
        ),
        (
            "rdsr",
            deposit_job(
                env,
                &RdsrParams {
                    deposit: deposit.clone(),
                    ..RdsrParams::DEFAULT
                },
            )?,
        ),
        (
            "bd",
            deposit_job(
                env,
                &BdParams {
                    deposit: deposit.clone(),
                },
            )?,
        ),
    ] {
        let ((d, s), cli) = run;
        let h = d.height_field();
        let file = env.write(&format!("growth_{name}.npy"), &Surface::Height(h.clone()))?;
        let opts = RenderOptions {
            shader: Shader::Height,
            z_scale: 0.5,
            ..env.view()
        };
        let pic = env.picture(&format!("growth_{name}.png"), &render_height(&h, &opts)?)?;
        items.push(height_item(name, l, &s, pic, file, cli));
        width_series.push((name, s));
    }
    items.push(width_item(env, &width_series)?);
    Ok(items)
}

fn height_item(
    name: &str,
    l: usize,
    s: &WidthSeries,
    pic: String,
    file: String,
    cli: String,
) -> Item {
    let beta = growth_exponent(&s.t, &s.width(), [1.0, 100.0])
        .map(|f| f.exponent)
        .unwrap_or(f64::NAN);
    Item::new(
        format!("{}: {l}×{l} columns, 100 monolayers", name.to_uppercase()),
        Some(pic),
        vec![file],
        vec![
            fact(
                "interface width W",
                format!("{:.3}", s.w2.last().copied().unwrap_or(0.0).sqrt()),
            ),
            fact("β (log–log, t ∈ [1, 100])", format!("{beta:.3}")),
            fact("CLI", cli),
        ],
    )
}

fn width_item(env: &Env, series: &[(&str, WidthSeries)]) -> Result<Item> {
    let plot = Plot {
        title: "Interface width W(t), 2+1D".into(),
        x_label: "t (monolayers)".into(),
        y_label: "W".into(),
        log_x: true,
        log_y: true,
        series: series
            .iter()
            .map(|(n, s)| Series {
                name: n.to_uppercase(),
                points: s.t.iter().copied().zip(s.width()).collect(),
                style: Style::Line,
            })
            .collect(),
    };
    let svg = env.text("growth_width.svg", &plot_svg(&plot, 800, 560)?)?;
    Ok(Item::new(
        "W(t): RD grows as t^½, RDSR logarithmically (2+1D EW), BD as KPZ",
        Some(svg),
        vec![],
        vec![fact("exponent checks", "crates/growth/tests/reference.rs")],
    ))
}

/// Figure 1: a 2-D DLA cluster from a point seed, one pixel per lattice cell,
/// coloured by deposition order.
fn dla_2d(env: &Env) -> Result<Item> {
    let n = if env.quick { 3_000 } else { 20_000 };
    let (c, cli) = grow_dla(
        env,
        &dla_job::DlaParams {
            dim: 2,
            particles: n,
            ..dla_job::DlaParams::DEFAULT
        },
    )?;
    // A 2-D lattice is the x–z plane (one cell thick in y); the picture is
    // the cluster's bounding box with a margin.
    let margin = 8;
    let (lo, hi) = c
        .cells
        .iter()
        .fold(([i32::MAX; 2], [i32::MIN; 2]), |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[2])],
                [hi[0].max(p[0]), hi[1].max(p[2])],
            )
        });
    let (w, h) = (
        hi[0] - lo[0] + 1 + 2 * margin,
        hi[1] - lo[1] + 1 + 2 * margin,
    );
    let mut img = RgbaImage::filled(w as u32, h as u32, [250, 250, 252, 255]);
    let total = c.cells.len() as f64;
    for (k, p) in c.cells.iter().enumerate() {
        let rgb = ColorMap::Magma.map(0.85 * k as f64 / total);
        // Row 0 of the picture is the top (z up).
        let (x, y) = (p[0] - lo[0] + margin, hi[1] - p[2] + margin);
        img.put(x as u32, y as u32, [rgb[0], rgb[1], rgb[2], 255]);
    }
    let pic = env.picture("growth_dla_2d.png", &img)?;
    let d = gyration_dimension(&c.points())
        .map(|d| d.d)
        .unwrap_or(f64::NAN);
    Ok(Item::new(
        format!("2-D DLA from a point seed, {n} particles (Figure 1)"),
        Some(pic),
        vec![],
        vec![
            fact(
                "fractal dimension (R_g fit)",
                format!("{d:.3} (2-D DLA ≈ 1.71)"),
            ),
            fact("picture", format!("{w}×{h} cells, one pixel each")),
            fact("colour", "deposition order (magma)"),
            fact("CLI", cli),
        ],
    ))
}

/// Figure 4: a DLA cluster from a point seed.
fn dla_point(env: &Env) -> Result<Item> {
    let n = if env.quick { 5_000 } else { 30_000 };
    let (c, cli) = grow_dla(
        env,
        &dla_job::DlaParams {
            particles: n,
            ..dla_job::DlaParams::DEFAULT
        },
    )?;
    let pts = c.points();
    let d = gyration_dimension(&pts).map(|d| d.d).unwrap_or(f64::NAN);
    let total = pts.len() as f64;
    let ps = colored_points(pts, |k, _| k as f64 / total, ColorMap::Magma)?;
    let (file, pic) = points(env, "growth_dla_point", ps)?;
    Ok(Item::new(
        format!("DLA from a point seed, {n} particles, p = 1"),
        Some(pic),
        vec![file],
        vec![
            fact(
                "fractal dimension (R_g fit)",
                format!("{d:.3} (3-D DLA ≈ 2.5)"),
            ),
            fact("colour", "deposition order"),
            fact("CLI", cli),
        ],
    ))
}

/// Figures 9–11: a DLA terrain on the bottom plane, moss-like with small p.
fn dla_plane(env: &Env, stick: f64, tag: &str) -> Result<Item> {
    let side = if env.quick { 48 } else { 96 };
    let (c, cli) = grow_dla(
        env,
        &dla_job::DlaParams {
            seed_shape: dla_job::SeedShape::Plane,
            size: Some(LatticeSize::new(&[side, side, 2 * side])?),
            particles: side * side * 3 / 2,
            stick,
            ..dla_job::DlaParams::DEFAULT
        },
    )?;
    let parts: Vec<[f64; 3]> = c.particles().iter().map(|p| p.map(f64::from)).collect();
    let rho = density_profile(&parts, (side * side) as f64);
    let dd = density_dimension(&rho, 3)
        .map(|d| format!("{:.2}", d.d))
        .unwrap_or_else(|e| e.to_string());
    let top = parts.iter().map(|p| p[2]).fold(1.0, f64::max);
    let ps = colored_points(c.points(), |_, p| p[2] / top, ColorMap::Viridis)?;
    let (file, pic) = points(env, &format!("growth_dla_plane_{tag}"), ps)?;
    Ok(Item::new(
        format!("DLA terrain on a plane, p = {stick} ({tag})"),
        Some(pic),
        vec![file],
        vec![
            fact(
                "lattice",
                format!("{side}×{side}×{}, periodic in x and y", 2 * side),
            ),
            fact("particles", c.particles().len()),
            fact("D from ρ(z) ∝ z^(D−3)", dd),
            fact("CLI", cli),
        ],
    ))
}

/// Figure 8: RDSR on a sphere, coloured by height above the substrate.
fn sphere(env: &Env) -> Result<Item> {
    let (radius, layers) = if env.quick { (12.0, 6.0) } else { (24.0, 12.0) };
    let (d, cli) = rdsr_sphere(radius, layers, env)?;
    let c0 = (d.size[0] / 2) as f64;
    let rmax = radius + d.thickness;
    let height = |p: &[f64; 3]| {
        (((p[0] - c0).powi(2) + (p[1] - c0).powi(2) + (p[2] - c0).powi(2)).sqrt() - radius)
            / (rmax - radius).max(1.0)
    };
    let ps = colored_points(d.points(), |_, p| height(p), ColorMap::Viridis)?;
    let (file, pic) = points(env, "growth_rdsr_sphere", ps)?;
    Ok(Item::new(
        format!("Figure 8: RDSR on a sphere of radius {radius}, {layers} monolayers"),
        Some(pic),
        vec![file],
        vec![
            fact("particles", d.cells.len() - d.seeds),
            fact("thickness", format!("{:.1} cells", d.thickness)),
            fact("CLI", cli),
        ],
    ))
}
