//! Command-line definition and the context shared by every command.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

const ABOUT: &str = "Generate, analyse, render and export rough surfaces.";

const LONG_ABOUT: &str = "\
asperity generates, analyses, renders and exports rough surfaces: the irregular,
fractal and weathered surfaces of rock, ice, corroded metal, terrain and machined
parts. It implements five papers (see the README): discrete growth with level-set
reconstruction (Kim, Machiraju & Thompson), cellular-automaton height fields
(Peridier), multiresolution subdivision with procedural detail (Velho, Perlin et
al.), projected-IFS fractal surfaces (Poull, Gentil et al.) and cellular automata
on meshes (Gobron & Chiba).

Each method family has its own command (growth, reconstruct, ca, facet,
subdiv, ifs, surface-ca, analyze, render, generate); `asperity demo` runs every
method and writes a gallery.";

const AFTER_HELP: &str = "\
Examples:
  asperity demo                       write gallery/index.html with every method
  asperity demo --quick --out /tmp/g  a smaller, faster gallery
  asperity convert rock.ply rock.glb  any mesh format to any other
  asperity convert dem.gsf dem.npy    any height-field format to any other
  asperity convert dem.npy dem.stl    triangulate a height field
  asperity info surface.ply --json    counts, bounds, topology as JSON
  asperity reconstruct pts.ply -o surface.ply        watertight surface from points
  asperity generate dla-terrain -o terrain.glb       DLA, then level-set reconstruction
  asperity ifs surface --preset takagi-landsberg-surface --depth 8 -o t.ply
  asperity ifs curvature --preset bezier-bicubic --at 0.5,0.25 --json
  asperity formats                    what can be read and written";

/// The `asperity` command line.
#[derive(Parser, Debug)]
#[command(name = "asperity", version, about = ABOUT, long_about = LONG_ABOUT, after_help = AFTER_HELP)]
#[command(propagate_version = true, max_term_width = 100)]
pub struct Cli {
    #[command(flatten)]
    pub global: Global,
    #[command(subcommand)]
    pub command: Command,
}

/// `--params FILE.json`, for the commands whose parameters are an engine job's.
#[derive(Args, Debug, Clone, Default)]
pub struct ParamsFile {
    /// Take the parameters from a file: a `--json` report (its `params`), a JSON object
    /// of this command's parameters, or a surface asperity wrote (PLY, OBJ, glTF, PNG,
    /// EXR, GSF, .gwy, x3p and CSV files record them). Flags given as well win, and the
    /// report says which.
    #[arg(long = "params", value_name = "FILE")]
    pub file: Option<PathBuf>,
}

/// Options every command accepts.
#[derive(Args, Debug, Clone)]
pub struct Global {
    /// Random seed; the same seed gives byte-identical output at any thread count.
    #[arg(long, global = true, default_value_t = asperity_engine::params::DEFAULT_SEED, value_name = "U64")]
    pub seed: u64,
    /// Output file or directory (commands say which); the format follows the extension.
    /// `-o -` writes a single-file output to stdout, in the format named by --format.
    #[arg(short = 'o', long = "output", global = true, value_name = "PATH")]
    pub output: Option<PathBuf>,
    /// The format of `-o -` (stdout), by extension: npy, ply, stl, csv, …
    #[arg(long, global = true, value_name = "EXT")]
    pub format: Option<String>,
    /// Worker threads (default: all cores).
    #[arg(long, global = true, value_name = "N", value_parser = clap::value_parser!(u16).range(1..=1024))]
    pub threads: Option<u16>,
    /// Print a machine-readable JSON report of what was done and measured on stdout.
    #[arg(long, global = true)]
    pub json: bool,
    /// No progress bars or informational messages (errors still print).
    #[arg(short, long, global = true)]
    pub quiet: bool,
    /// How long work shows progress: auto (a bar on a terminal), lines (plain lines on
    /// stderr, for logs), none.
    #[arg(long, global = true, value_name = "HOW", value_enum, default_value_t)]
    pub progress: crate::progress::ProgressMode,
    /// Refuse allocations estimated above this size, e.g. 512M, 4G (default: the least of half of
    /// RAM and the headroom under the memory cgroup and ulimit -v/-d; --json says which).
    #[arg(long, global = true, value_name = "SIZE", value_parser = parse_memory)]
    pub max_memory: Option<u64>,
    /// Refuse runs that even a fast machine could not finish within this time, e.g. 30m,
    /// 12h, 1w, or none (default: 1d). Guards against step counts with a typo.
    #[arg(long, global = true, value_name = "DURATION", value_parser = parse_time)]
    pub max_time: Option<MaxTime>,
    /// Length unit of the x, y coordinates of height fields written: m, mm, µm, nm or
    /// none (the default for synthetic data). Carried by GSF, .gwy, x3p (metres), PNG, EXR and CSV.
    #[arg(long, global = true, value_name = "UNIT", value_parser = asperity_engine::core::LengthUnit::parse)]
    pub xy_unit: Option<asperity_engine::core::LengthUnit>,
    /// Length unit of the heights of height fields written (as --xy-unit).
    #[arg(long, global = true, value_name = "UNIT", value_parser = asperity_engine::core::LengthUnit::parse)]
    pub z_unit: Option<asperity_engine::core::LengthUnit>,
    /// Up axis of mesh and point files (OBJ, PLY, STL, XYZ, npy) read and written: y writes
    /// (x, z, -y) and reads files as y-up, z takes coordinates as they are. Default: OBJ y-up
    /// (asperity's own OBJ read back unchanged, others as they are), the rest z-up; glTF is
    /// always y-up.
    #[arg(long, global = true, value_name = "AXIS", value_parser = ["y", "z"])]
    pub up: Option<String>,
    /// Up axis of the mesh and point files written, apart from the files read (which keep
    /// --up): `--up z --up-out y` reads z-up files and writes y-up ones. Default: --up.
    #[arg(long, global = true, value_name = "AXIS", value_parser = ["y", "z"])]
    pub up_out: Option<String>,
    /// The channel of a multi-channel file read (Nanoscope images, Sensofar layers): its
    /// number from 0 or its name (`asperity info FILE` lists them). Default: the first height
    /// channel, as SurfaceTopography reads.
    #[arg(long, global = true, value_name = "NAME|N")]
    pub channel: Option<String>,
}

/// `--max-time`: a duration, or none for no limit.
#[derive(Clone, Copy, Debug)]
pub struct MaxTime(pub Option<std::time::Duration>);

fn parse_time(s: &str) -> Result<MaxTime, String> {
    asperity_engine::core::time_budget::parse_duration(s)
        .map(MaxTime)
        .map_err(|e| e.to_string())
}

fn parse_memory(s: &str) -> Result<u64, String> {
    asperity_engine::core::memory::parse_size(s).map_err(|e| e.to_string())
}

/// The commands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Run every available method on small built-in defaults and write a gallery (index.html).
    Demo(DemoArgs),
    /// Convert between mesh, point-set and height-field formats (by extension).
    Convert(ConvertArgs),
    /// Describe a file: kind, sizes, bounds, topology, height range.
    Info(InfoArgs),
    /// Render a mesh, point set or height field to PNG (headless, CPU).
    Render(RenderArgs),
    /// Cellular-automaton height fields (peridier): run, rule tables, rule galleries.
    #[command(subcommand)]
    Ca(CaCommand),
    /// Alternating-diagonal facet mesh of a height field (peridier, Figure 7).
    Facet(FacetArgs),
    /// Heights on the facets at (x, y) points (peridier's TriangulatedInterpolation).
    Interpolate(InterpolateArgs),
    /// Roughness numbers of a height field or mesh (ISO 25178, PSD, Hurst, curvature).
    Analyze(AnalyzeArgs),
    /// The scale-limited surface of a height field or profile (ISO 16610 Gaussian filters)
    /// and what the filters removed.
    Filter(FilterArgs),
    /// Discrete surface growth (kim-machiraju-thompson §4): RD, RDSR, ballistic deposition, DLA.
    #[command(subcommand)]
    Growth(GrowthCommand),
    /// Generate surfaces from built-in models.
    #[command(subcommand)]
    Generate(GenerateCommand),
    /// Watertight surface from a point set by the level-set convection flow (kim-machiraju-thompson §5).
    Reconstruct(ReconstructArgs),
    /// Projected-IFS fractal curves and surfaces with DCF/SDCF pseudo-curvature (poull-gentil).
    #[command(subcommand)]
    Ifs(IfsCommand),
    /// Cellular automata on any triangle mesh: Voronoi, corrosion, reaction–diffusion (gobron-chiba).
    SurfaceCa(SurfaceCaArgs),
    /// Multiresolution Catmull–Clark surfaces with procedural detail, edits, blends and scenes (velho-perlin).
    Subdiv(SubdivArgs),
    /// Time the workloads named in the issues and print throughput.
    Bench(BenchArgs),
    /// List the file formats asperity reads and writes.
    Formats,
}

/// `asperity demo`
#[derive(Args, Debug)]
pub struct DemoArgs {
    /// Gallery directory (same as -o).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Smaller sizes for a fast run (CI uses this).
    #[arg(long)]
    pub quick: bool,
    /// Write every mesh download whole (by default a mesh above the gallery's triangle
    /// budget is written reduced, and its card says so).
    #[arg(long)]
    pub full_meshes: bool,
    /// Run only these sections (repeatable): foundation, renderer, peridier,
    /// growth, levelset, ifs, surfca, subdiv.
    #[arg(long, value_name = "SECTION")]
    pub only: Vec<String>,
}

/// `asperity convert`
#[derive(Args, Debug)]
pub struct ConvertArgs {
    /// Input file.
    pub input: PathBuf,
    /// Output file (or -o); its extension picks the format.
    #[arg(value_name = "OUTPUT")]
    pub out_file: Option<PathBuf>,
    #[command(flatten)]
    pub params: asperity_engine::files::ConvertParams,
    #[command(flatten)]
    pub params_file: ParamsFile,
}

/// `asperity render`
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Mesh, point-set or height-field file.
    pub input: PathBuf,
    #[command(flatten)]
    pub params: asperity_engine::render::RenderParams,
    /// Render N frames around the object (FILE_000.png …).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=3600))]
    pub turntable: Option<u32>,
    #[command(flatten)]
    pub params_file: ParamsFile,
}

/// `asperity ca …`
#[derive(Subcommand, Debug)]
pub enum CaCommand {
    /// Evolve a CA and write the accumulated height field (and optionally every step).
    Run(CaRunArgs),
    /// Print a rule's look-up table (as the paper's Figure 2).
    Rule(CaRuleArgs),
    /// Render a grid of surfaces: rows = rules, columns = initial conditions (Figure 4).
    Gallery(CaGalleryArgs),
}

/// `asperity ca run`
#[derive(Args, Debug)]
pub struct CaRunArgs {
    #[command(flatten)]
    pub params: asperity_engine::ca::CaRunParams,
    /// Write every step as a (T+1)×H×W uint8 .npy array.
    #[arg(long, value_name = "FILE")]
    pub states_out: Option<PathBuf>,
    /// Write every step as a PNG image into this directory (the paper's Figure 3).
    #[arg(long, value_name = "DIR")]
    pub steps_png: Option<PathBuf>,
    #[command(flatten)]
    pub params_file: ParamsFile,
}

/// `asperity ca rule`
#[derive(Args, Debug)]
pub struct CaRuleArgs {
    #[command(flatten)]
    pub params: asperity_engine::ca::CaRuleParams,
    #[command(flatten)]
    pub params_file: ParamsFile,
}

/// `asperity ca gallery`
#[derive(Args, Debug)]
pub struct CaGalleryArgs {
    #[command(flatten)]
    pub params: asperity_engine::ca::CaGalleryParams,
    #[command(flatten)]
    pub params_file: ParamsFile,
}

/// `asperity facet`
#[derive(Args, Debug)]
pub struct FacetArgs {
    /// Height field file.
    pub input: PathBuf,
    #[command(flatten)]
    pub params: asperity_engine::ca::FacetParams,
    /// Draw the polyline of x,y rows in this CSV file on the surface.
    #[arg(long, value_name = "FILE")]
    pub polyline: Option<PathBuf>,
    /// Also render the mesh (with the curves) to this PNG.
    #[arg(long, value_name = "PNG")]
    pub render: Option<PathBuf>,
    #[command(flatten)]
    pub params_file: ParamsFile,
}

/// `asperity interpolate`
#[derive(Args, Debug)]
pub struct InterpolateArgs {
    /// Height field file.
    pub input: PathBuf,
    /// CSV of x,y rows (physical units); prints x,y,z rows.
    #[arg(long)]
    pub points: PathBuf,
}

/// `asperity analyze`
#[derive(Args, Debug)]
pub struct AnalyzeArgs {
    /// Height-field or mesh file.
    pub input: PathBuf,
    #[command(flatten)]
    pub params: asperity_engine::analyze::AnalyzeParams,
    /// Write PNG plots into DIR: the PSD with its Hurst fit, the scale-dependent rms height,
    /// slope and curvature, the height-height correlation and the height histogram (height
    /// fields); curvature histograms (meshes).
    #[arg(long, value_name = "DIR")]
    pub plot: Option<std::path::PathBuf>,
    #[command(flatten)]
    pub params_file: ParamsFile,
}

/// `asperity filter`
#[derive(Args, Debug)]
pub struct FilterArgs {
    /// Height-field or profile file.
    pub input: PathBuf,
    /// Output file for the scale-limited surface (or -o); its extension picks the format.
    #[arg(value_name = "OUTPUT")]
    pub out_file: Option<PathBuf>,
    /// Also write what the L-filter removed (the waviness) to FILE.
    #[arg(long, value_name = "FILE")]
    pub waviness: Option<PathBuf>,
    /// Also write what the S-filter removed (the short-wavelength noise) to FILE.
    #[arg(long, value_name = "FILE")]
    pub noise: Option<PathBuf>,
    /// Also write what the F-operator removed (the form) to FILE.
    #[arg(long, value_name = "FILE")]
    pub form: Option<PathBuf>,
    #[command(flatten)]
    pub params: asperity_engine::analyze::FilterParams,
    #[command(flatten)]
    pub params_file: ParamsFile,
}

/// `asperity generate …`
#[derive(Subcommand, Debug)]
pub enum GenerateCommand {
    /// Self-affine (fractional Brownian) surface by Fourier filtering with random phases.
    Fbm(FbmArgs),
    /// DLA from the plane, then level-set reconstruction: a terrain with arches (kim-machiraju-thompson Figs. 9–11).
    DlaTerrain(DlaTerrainArgs),
    /// RDSR on a sphere, then level-set reconstruction: a rough ball (kim-machiraju-thompson Fig. 8).
    RdsrSphere(RdsrSphereArgs),
}

/// `asperity reconstruct`
#[derive(Args, Debug)]
pub struct ReconstructArgs {
    /// Point set (PLY, XYZ, CSV, OBJ/STL vertices …).
    pub input: PathBuf,
    #[command(flatten)]
    pub params: asperity_engine::reconstruct::LevelSetParams,
    #[command(flatten)]
    pub params_file: ParamsFile,
}

/// `asperity generate dla-terrain`
#[derive(Args, Debug)]
pub struct DlaTerrainArgs {
    #[command(flatten)]
    pub params: asperity_engine::reconstruct::DlaTerrainParams,
    /// Also write the particles (PLY, XYZ, CSV).
    #[arg(long, value_name = "FILE")]
    pub points: Option<PathBuf>,
    #[command(flatten)]
    pub params_file: ParamsFile,
}

/// `asperity generate rdsr-sphere`
#[derive(Args, Debug)]
pub struct RdsrSphereArgs {
    #[command(flatten)]
    pub params: asperity_engine::reconstruct::RdsrSphereParams,
    /// Also write the particles (PLY, XYZ, CSV).
    #[arg(long, value_name = "FILE")]
    pub points: Option<PathBuf>,
    #[command(flatten)]
    pub params_file: ParamsFile,
}

/// `asperity growth …`
#[derive(Subcommand, Debug)]
pub enum GrowthCommand {
    /// Random deposition: each particle lands on top of a random column.
    Rd(DepositArgs<asperity_engine::growth::RdParams>),
    /// Random deposition with surface relaxation (Family model) to the lowest nearby column.
    Rdsr(DepositArgs<asperity_engine::growth::RdsrParams>),
    /// Ballistic deposition: sticks at first contact with a nearest neighbour (porous, KPZ class).
    Bd(DepositArgs<asperity_engine::growth::BdParams>),
    /// Diffusion-limited aggregation on the cubic (or square) lattice.
    Dla(DlaArgs),
}

/// `asperity growth rd|rdsr|bd`: the job's parameters (`P`) and the files.
#[derive(Args, Debug)]
pub struct DepositArgs<P: Args> {
    #[command(flatten)]
    pub params: P,
    /// Closed mesh used as the substrate (`--substrate mesh`; OBJ, PLY, STL, GLB …).
    #[arg(long, value_name = "FILE")]
    pub mesh: Option<PathBuf>,
    /// Also write the occupied cells as a point set (flat substrate; PLY, XYZ, CSV, npy).
    #[arg(long, value_name = "FILE")]
    pub points: Option<PathBuf>,
    /// Write the width series as CSV (t, W, W_binned, stderr, mean height).
    #[arg(long, value_name = "FILE")]
    pub width_csv: Option<PathBuf>,
    /// Write plots of W(t) with the β fits into this directory (SVG and PNG).
    #[arg(long, value_name = "DIR")]
    pub plot: Option<PathBuf>,
    #[command(flatten)]
    pub params_file: ParamsFile,
}

/// `asperity growth dla`
#[derive(Args, Debug)]
pub struct DlaArgs {
    #[command(flatten)]
    pub params: asperity_engine::growth::dla::DlaParams,
    /// Closed mesh used as the seed (`--seed-shape mesh`).
    #[arg(long, value_name = "FILE")]
    pub mesh: Option<PathBuf>,
    /// Image whose grey levels give the seed density on the bottom plane (`--seed-shape
    /// image`; PNG, EXR, npy, GSF …).
    #[arg(long, value_name = "FILE")]
    pub image: Option<PathBuf>,
    /// Write plots (SVG and PNG): R_g(n), and the density profile ρ(z) in plane modes.
    #[arg(long, value_name = "DIR")]
    pub plot: Option<PathBuf>,
    /// Concurrent walks (default: one a core, at most 4, past which they mostly wait on each
    /// other). More than the cores measures the concurrency
    /// a larger machine would see (--json: walkers); the cluster is the same for any number.
    #[arg(long, value_name = "N")]
    pub walkers: Option<usize>,
    #[command(flatten)]
    pub params_file: ParamsFile,
}

/// `asperity generate fbm`
#[derive(Args, Debug)]
pub struct FbmArgs {
    #[command(flatten)]
    pub params: asperity_engine::synthesis::FbmParams,
    #[command(flatten)]
    pub params_file: ParamsFile,
}

/// `asperity subdiv`
#[derive(Args, Debug)]
pub struct SubdivArgs {
    #[command(flatten)]
    pub params: asperity_engine::subdiv::SubdivParams,
    /// Split the quads into triangles in PLY and OBJ too (glTF and STL always are).
    #[arg(long)]
    pub triangles: bool,
    /// Write an animation of N frames (t from 0 to 1): OUT becomes OUT_0000.ext, ….
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=10_000))]
    pub frames: Option<u32>,
    /// Write the details of every level (local frames) to a JSON file.
    #[arg(long, value_name = "FILE")]
    pub export_details: Option<std::path::PathBuf>,
    #[command(flatten)]
    pub params_file: ParamsFile,
}

/// `asperity surface-ca`
#[derive(Args, Debug)]
pub struct SurfaceCaArgs {
    /// Mesh file (OBJ, PLY, STL, …) or builtin:sphere, builtin:cube, builtin:cylinder, builtin:cup.
    pub mesh: String,
    #[command(flatten)]
    pub params: asperity_engine::surfca::SurfaceCaParams,
    /// Voronoi: sites at these points instead; corrosion: cells corroded from the start
    /// (any point-set file; the nearest cell each).
    #[arg(long, value_name = "FILE", conflicts_with = "sites")]
    pub site_points: Option<PathBuf>,
    /// Write the coloured cell mesh every K steps as OUT_stepNNNN.EXT (animation frames).
    #[arg(long, value_name = "K", value_parser = clap::value_parser!(u64).range(1..))]
    pub frames: Option<u64>,
    /// Point set of cell centres with integer `label` and float `area` (PLY).
    #[arg(long, value_name = "FILE")]
    pub labels_out: Option<PathBuf>,
    /// Per-step statistics: .csv (step, changed, changed_fraction, class fractions) or .json.
    #[arg(long, value_name = "FILE")]
    pub stats_out: Option<PathBuf>,
    /// PNG plot of the per-step statistics (the paper's Figure 16).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    #[command(flatten)]
    pub params_file: ParamsFile,
}

/// `asperity ifs …`
#[derive(Subcommand, Debug)]
pub enum IfsCommand {
    /// List the built-in presets.
    Presets,
    /// Write a preset as an editable model file (JSON; stdout without -o).
    Preset(IfsPresetArgs),
    /// Attractor of a curve model: polyline (.obj/.ply), table (.csv) or figure with DCFs (.svg, Fig. 2).
    Curve(IfsCurveArgs),
    /// Attractor of a tensor-product surface as a mesh, with per-vertex pseudo-curvature
    /// (a 2-D curve model is squared: z ≈ h(f(s) + f(t))).
    Surface(IfsSurfaceArgs),
    /// One DCF of a curve operator (and, in .svg, its family) from the fixed point to a start point.
    Dcf(IfsDcfArgs),
    /// One SDCF of a surface operator 𝒯ᵢⱼ as a mesh (Fig. 4).
    Sdcf(IfsSdcfArgs),
    /// Pseudo-curvature ranges at the fixed points of every operator and at dyadic points.
    Curvature(IfsCurvatureArgs),
}

/// `asperity ifs preset`
#[derive(Args, Debug)]
pub struct IfsPresetArgs {
    /// Preset name (or give --preset, or --ifs FILE to rewrite a model file with its edits).
    #[arg(value_name = "NAME")]
    pub name: Option<String>,
    #[command(flatten)]
    pub params: asperity_engine::ifs::IfsPresetParams,
    #[command(flatten)]
    pub params_file: ParamsFile,
}

/// `asperity ifs curve`
#[derive(Args, Debug)]
pub struct IfsCurveArgs {
    #[command(flatten)]
    pub params: asperity_engine::ifs::IfsCurveParams,
    #[command(flatten)]
    pub params_file: ParamsFile,
}

/// `asperity ifs surface`
#[derive(Args, Debug)]
pub struct IfsSurfaceArgs {
    #[command(flatten)]
    pub params: asperity_engine::ifs::IfsSurfaceParams,
    /// Also write the control grid as lines (.obj or .ply).
    #[arg(long, value_name = "FILE")]
    pub control_net: Option<PathBuf>,
    #[command(flatten)]
    pub params_file: ParamsFile,
}

/// `asperity ifs dcf`
#[derive(Args, Debug)]
pub struct IfsDcfArgs {
    #[command(flatten)]
    pub params: asperity_engine::ifs::IfsDcfParams,
    #[command(flatten)]
    pub params_file: ParamsFile,
}

/// `asperity ifs sdcf`
#[derive(Args, Debug)]
pub struct IfsSdcfArgs {
    #[command(flatten)]
    pub params: asperity_engine::ifs::IfsSdcfParams,
    #[command(flatten)]
    pub params_file: ParamsFile,
}

/// `asperity ifs curvature`
#[derive(Args, Debug)]
pub struct IfsCurvatureArgs {
    #[command(flatten)]
    pub params: asperity_engine::ifs::IfsCurvatureParams,
    #[command(flatten)]
    pub params_file: ParamsFile,
}

/// `asperity bench`
#[derive(Args, Debug)]
pub struct BenchArgs {
    /// Run only workloads whose name contains this text.
    pub filter: Option<String>,
    /// Small inputs (checks that the workloads run; not for figures).
    #[arg(long)]
    pub quick: bool,
    /// Timed repetitions per workload (the minimum and median are reported).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub repeat: u32,
    /// How a method's time and peak memory grow with its input: a doubling series of sizes,
    /// each run in a fresh process, with the fitted log-log slope beside the expected one
    /// (growth, dla, levelset, ca, subdivision, ifs, surfca, analysis, render, or all).
    #[arg(long, value_name = "METHOD")]
    pub scaling: Option<String>,
    /// One point of a --scaling series (the size), run by the series' parent process.
    #[arg(long, hide = true, requires = "scaling")]
    pub scaling_point: Option<u64>,
    /// Each workload at 1, 2, 4, … threads up to --threads (default: every core), with the
    /// speed-up over one thread and the parallel efficiency (speed-up / threads).
    #[arg(long, conflicts_with = "scaling")]
    pub threads_scaling: bool,
    /// Time the workloads on a busy machine: a CPU-bound loop at nice 10 on every core
    /// (another user's job, a build) runs beside them, stopped when the bench ends. Unix.
    #[arg(long, conflicts_with = "scaling")]
    pub background_load: bool,
}

/// `asperity info`
#[derive(Args, Debug)]
pub struct InfoArgs {
    /// The file to describe.
    pub input: PathBuf,
}

#[cfg(test)]
mod tests {
    use super::*;
    use asperity_engine::{analyze, ca, files, growth, ifs, reconstruct, render, subdiv, surfca};

    fn parsed(args: &[&str]) -> Command {
        let argv = std::iter::once("asperity").chain(args.iter().copied());
        Cli::try_parse_from(argv)
            .unwrap_or_else(|e| panic!("{args:?}: {e}"))
            .command
    }

    /// Every flag's default is the engine's: each command parsed with no
    /// option gives its job's `Default` (clap takes its defaults from the
    /// engine's structs, and this checks that nothing in between restates
    /// one); the seed's default is the engine's.
    #[test]
    fn every_flag_defaults_to_the_engine_default() {
        use Command as C;
        let cli = Cli::try_parse_from(["asperity", "formats"]).unwrap();
        assert_eq!(cli.global.seed, asperity_engine::params::DEFAULT_SEED);
        let mut checked = Vec::new();
        let mut check = |job: &str, same: bool| {
            assert!(same, "{job}: a flag's default differs from the engine's");
            checked.push(job.to_owned());
        };
        match parsed(&["growth", "rd"]) {
            C::Growth(GrowthCommand::Rd(a)) => {
                check("growth rd", a.params == growth::RdParams::default())
            }
            c => panic!("{c:?}"),
        }
        match parsed(&["growth", "rdsr"]) {
            C::Growth(GrowthCommand::Rdsr(a)) => {
                check("growth rdsr", a.params == growth::RdsrParams::default())
            }
            c => panic!("{c:?}"),
        }
        match parsed(&["growth", "bd"]) {
            C::Growth(GrowthCommand::Bd(a)) => {
                check("growth bd", a.params == growth::BdParams::default())
            }
            c => panic!("{c:?}"),
        }
        match parsed(&["growth", "dla"]) {
            C::Growth(GrowthCommand::Dla(a)) => {
                check("growth dla", a.params == growth::dla::DlaParams::default())
            }
            c => panic!("{c:?}"),
        }
        match parsed(&["reconstruct", "p.ply"]) {
            C::Reconstruct(a) => check(
                "reconstruct",
                a.params == reconstruct::LevelSetParams::default(),
            ),
            c => panic!("{c:?}"),
        }
        match parsed(&["generate", "dla-terrain"]) {
            C::Generate(GenerateCommand::DlaTerrain(a)) => check(
                "generate dla-terrain",
                a.params == reconstruct::DlaTerrainParams::default(),
            ),
            c => panic!("{c:?}"),
        }
        match parsed(&["generate", "rdsr-sphere"]) {
            C::Generate(GenerateCommand::RdsrSphere(a)) => check(
                "generate rdsr-sphere",
                a.params == reconstruct::RdsrSphereParams::default(),
            ),
            c => panic!("{c:?}"),
        }
        match parsed(&["generate", "fbm"]) {
            C::Generate(GenerateCommand::Fbm(a)) => check(
                "generate fbm",
                a.params == asperity_engine::synthesis::FbmParams::default(),
            ),
            c => panic!("{c:?}"),
        }
        match parsed(&["ca", "run"]) {
            C::Ca(CaCommand::Run(a)) => check("ca run", a.params == ca::CaRunParams::default()),
            c => panic!("{c:?}"),
        }
        match parsed(&["ca", "rule"]) {
            C::Ca(CaCommand::Rule(a)) => check("ca rule", a.params == ca::CaRuleParams::default()),
            c => panic!("{c:?}"),
        }
        match parsed(&["ca", "gallery"]) {
            C::Ca(CaCommand::Gallery(a)) => {
                check("ca gallery", a.params == ca::CaGalleryParams::default())
            }
            c => panic!("{c:?}"),
        }
        match parsed(&["facet", "h.npy"]) {
            C::Facet(a) => check("facet", a.params == ca::FacetParams::default()),
            c => panic!("{c:?}"),
        }
        check("interpolate", true); // no parameters besides its files
        match parsed(&["subdiv"]) {
            C::Subdiv(a) => check("subdiv", a.params == subdiv::SubdivParams::default()),
            c => panic!("{c:?}"),
        }
        match parsed(&["ifs", "preset"]) {
            C::Ifs(IfsCommand::Preset(a)) => {
                check("ifs preset", a.params == ifs::IfsPresetParams::default())
            }
            c => panic!("{c:?}"),
        }
        match parsed(&["ifs", "curve"]) {
            C::Ifs(IfsCommand::Curve(a)) => {
                check("ifs curve", a.params == ifs::IfsCurveParams::default())
            }
            c => panic!("{c:?}"),
        }
        match parsed(&["ifs", "surface"]) {
            C::Ifs(IfsCommand::Surface(a)) => {
                check("ifs surface", a.params == ifs::IfsSurfaceParams::default())
            }
            c => panic!("{c:?}"),
        }
        match parsed(&["ifs", "dcf"]) {
            C::Ifs(IfsCommand::Dcf(a)) => {
                check("ifs dcf", a.params == ifs::IfsDcfParams::default())
            }
            c => panic!("{c:?}"),
        }
        match parsed(&["ifs", "sdcf"]) {
            C::Ifs(IfsCommand::Sdcf(a)) => {
                check("ifs sdcf", a.params == ifs::IfsSdcfParams::default())
            }
            c => panic!("{c:?}"),
        }
        match parsed(&["ifs", "curvature"]) {
            C::Ifs(IfsCommand::Curvature(a)) => check(
                "ifs curvature",
                a.params == ifs::IfsCurvatureParams::default(),
            ),
            c => panic!("{c:?}"),
        }
        match parsed(&["surface-ca", "builtin:cube"]) {
            C::SurfaceCa(a) => check("surface-ca", a.params == surfca::SurfaceCaParams::default()),
            c => panic!("{c:?}"),
        }
        match parsed(&["analyze", "f.npy"]) {
            C::Analyze(a) => check("analyze", a.params == analyze::AnalyzeParams::default()),
            c => panic!("{c:?}"),
        }
        match parsed(&["filter", "f.npy", "g.npy"]) {
            C::Filter(a) => check("filter", a.params == analyze::FilterParams::default()),
            c => panic!("{c:?}"),
        }
        match parsed(&["render", "m.ply"]) {
            C::Render(a) => check("render", a.params == render::RenderParams::default()),
            c => panic!("{c:?}"),
        }
        match parsed(&["convert", "a.ply", "b.obj"]) {
            C::Convert(a) => check("convert", a.params == files::ConvertParams::default()),
            c => panic!("{c:?}"),
        }
        check("info", true); // no parameters besides its file
        // every job of the engine's registry is a command checked here
        let mut jobs: Vec<&str> = asperity_engine::jobs::jobs()
            .iter()
            .map(|j| j.name)
            .collect();
        jobs.sort_unstable();
        checked.sort();
        assert_eq!(jobs, checked);
    }
}
