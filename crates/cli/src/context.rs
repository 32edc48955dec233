//! What every command shares after parsing (seed, output, threads, budget,
//! `--json`, `--quiet`), and [`Run`]: one command's files, report and
//! progress bar.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use anyhow::Context as _;
use asperity_engine::core::{
    HeightField, LengthUnit, MemoryBudget, PointSet, RgbaImage, TimeBudget, TriMesh,
};
use asperity_engine::io::{Surface, UpAxis, WriteOptions};
use asperity_engine::methods::render::plot::{plot_png, plot_svg};
use asperity_engine::params::{JobParams, field_names, parse, record};
use asperity_engine::plots::NamedPlot;
use asperity_engine::{Measurements, Report};

use crate::cli::{Global, MaxTime, ParamsFile};
use crate::progress::Bar;

/// Settings shared by every command after parsing.
pub struct Context {
    pub seed: u64,
    pub output: Option<PathBuf>,
    pub json: bool,
    pub quiet: bool,
    /// `--progress`.
    pub progress: crate::progress::ProgressMode,
    pub budget: MemoryBudget,
    pub time: TimeBudget,
    pub threads: usize,
    /// `--format`: set when `-o -` sends the output to stdout.
    pub format: Option<String>,
    /// `--xy-unit`, `--z-unit`: units given to height fields written.
    pub units: (Option<LengthUnit>, Option<LengthUnit>),
    /// `--up`: the up axis of mesh and point files read (and written, unless
    /// `--up-out`).
    pub up: Option<UpAxis>,
    /// `--up-out`: the up axis of mesh and point files written.
    pub up_out: Option<UpAxis>,
    /// `--channel`: the channel of multi-channel files read.
    pub channel: Option<asperity_engine::io::Channel>,
    /// The arguments given on the command line (clap ids: field names), so
    /// that flags win over a `--params` file.
    pub explicit: BTreeSet<String>,
}

/// A job's parameters as the command runs them.
pub struct Resolved<P> {
    /// The parameters: flags over a `--params` file over the engine's defaults.
    pub params: P,
    /// The seed: `--seed`, else the file's, else the default.
    pub seed: u64,
    /// The flags that replaced a value of the file.
    pub overridden: Vec<String>,
}

impl Context {
    pub fn new(g: &Global, explicit: BTreeSet<String>) -> anyhow::Result<Self> {
        if let Some(n) = g.threads {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n as usize)
                .build_global()
                .context("starting the thread pool")?;
        }
        let threads = rayon::current_num_threads();
        let axis = |a: &Option<String>| -> anyhow::Result<Option<UpAxis>> {
            a.as_deref()
                .map(str::parse)
                .transpose()
                .map_err(anyhow::Error::msg)
        };
        let time = match g.max_time {
            Some(MaxTime(None)) => TimeBudget::unlimited(),
            Some(MaxTime(Some(limit))) => TimeBudget::new(limit, threads),
            None => TimeBudget::new(asperity_engine::core::time_budget::DEFAULT_LIMIT, threads),
        };
        Ok(Self {
            time,
            format: g.format.clone(),
            seed: g.seed,
            output: g.output.clone(),
            json: g.json,
            quiet: g.quiet,
            progress: g.progress,
            budget: g.max_memory.map(MemoryBudget::new).unwrap_or_default(),
            threads,
            units: (g.xy_unit, g.z_unit),
            up: axis(&g.up)?,
            up_out: axis(&g.up_out)?,
            channel: g
                .channel
                .as_deref()
                .map(asperity_engine::io::Channel::parse),
            explicit,
        })
    }

    /// The parameters of a job: `flags` as parsed (the engine's defaults
    /// where none was given), or, with `--params FILE`, the file's values with
    /// the flags given on the command line over them.
    ///
    /// The result is validated against the job's schema (bounds, finite
    /// numbers, the job's own checks) before any work starts.
    pub fn job_params<P: JobParams>(
        &self,
        flags: P,
        file: &ParamsFile,
    ) -> anyhow::Result<Resolved<P>> {
        // Before the flags go through JSON, where NaN would read as unset.
        asperity_engine::params::refuse_not_finite(&flags)?;
        let resolved = self.resolve_params(flags, file)?;
        asperity_engine::params::validate(&resolved.params)?;
        Ok(resolved)
    }

    /// The flags over a `--params` file (see [`Self::job_params`]).
    fn resolve_params<P: JobParams>(
        &self,
        flags: P,
        file: &ParamsFile,
    ) -> anyhow::Result<Resolved<P>> {
        let Some(path) = &file.file else {
            return Ok(Resolved {
                params: flags,
                seed: self.seed,
                overridden: Vec::new(),
            });
        };
        let value = asperity_engine::params::read_file(path)?;
        let from_file =
            parse::<P>(&value).with_context(|| format!("reading {}", path.display()))?;
        let mut merged = match serde_json::to_value(&from_file.params)? {
            serde_json::Value::Object(m) => m,
            _ => anyhow::bail!("the parameters of {} are not an object", P::JOB),
        };
        let given = serde_json::to_value(&flags)?;
        let mut overridden = Vec::new();
        for name in field_names::<P>() {
            if self.explicit.contains(&name)
                && let Some(v) = given.get(&name)
            {
                if merged.get(&name) != Some(v) {
                    overridden.push(name.clone());
                }
                merged.insert(name, v.clone());
            }
        }
        let params = parse::<P>(&serde_json::Value::Object(merged))?.params;
        let seed = match from_file.seed {
            Some(s) if !self.explicit.contains("seed") => s,
            _ => self.seed,
        };
        for name in &overridden {
            self.note(format!(
                "{} from the command line replaces the value in {}",
                asperity_engine::core::wording::param(name),
                path.display()
            ));
        }
        Ok(Resolved {
            params,
            seed,
            overridden,
        })
    }

    /// `h` in the units `--xy-unit` and `--z-unit` give (each kept where not
    /// given): a unitless field is labelled, one with units is converted.
    pub fn with_units(&self, h: HeightField) -> HeightField {
        let mut u = h.units();
        if let Some(xy) = self.units.0 {
            u.xy = xy;
        }
        if let Some(z) = self.units.1 {
            u.z = z;
        }
        h.in_units(u)
    }

    /// Prints an informational line on stderr unless `--quiet` or `--json`.
    pub fn note(&self, msg: impl AsRef<str>) {
        if !self.quiet && !self.json {
            eprintln!("{}", self.shown(msg.as_ref()));
        }
    }

    /// `msg` with the private file behind `-o -` called what it is (stdout)
    /// and parameters named as flags.
    pub fn shown(&self, msg: &str) -> String {
        let msg = asperity_engine::core::wording::spell(
            msg,
            asperity_engine::core::wording::Spelling::Cli,
        );
        match (&self.format, &self.output) {
            (Some(_), Some(out)) => msg.replace(&out.display().to_string(), "stdout"),
            _ => msg,
        }
    }

    /// `-o`, or an error that shows an example.
    pub fn output(&self, example: &str) -> anyhow::Result<PathBuf> {
        self.output
            .clone()
            .with_context(|| format!("no output file: give -o {example}"))
    }

    /// Progress as `--progress` asks (a bar hidden with `--quiet`, `--json`
    /// or off a terminal).
    pub fn bar(&self) -> Bar {
        Bar::new(self.progress, self.quiet || self.json)
    }

    /// Reads any file under the memory budget; a height field gets the units
    /// `--xy-unit`/`--z-unit` give (for files that record none, such as .npy),
    /// a mesh or point set the up axis `--up` gives.
    pub fn load(&self, path: &Path) -> anyhow::Result<Surface> {
        let channel = self.channel.as_ref();
        Ok(
            match asperity_engine::files::load_channel(path, &self.budget, channel)? {
                Surface::Height(h) => Surface::Height(self.with_units(h)),
                s => self.oriented(path, s)?,
            },
        )
    }

    /// `s`, read from `path`, turned to the up axis `--up` gives (unchanged
    /// without it).
    pub fn oriented(&self, path: &Path, s: Surface) -> anyhow::Result<Surface> {
        Ok(match self.up {
            Some(up) => asperity_engine::io::reorient(s, path, up)?,
            None => s,
        })
    }

    /// A triangle mesh (`builtin:NAME` or a file), turned as `--up` says.
    pub fn load_mesh(&self, spec: &str) -> anyhow::Result<TriMesh> {
        let m = asperity_engine::files::load_mesh(spec, &self.budget)?;
        Ok(match self.up {
            Some(up) if !spec.starts_with("builtin:") => {
                asperity_engine::io::up::reorient_mesh(m, Path::new(spec), up)?
            }
            _ => m,
        })
    }

    /// A triangle mesh from a mesh file, turned as `--up` says.
    pub fn load_triangles(&self, path: &Path) -> anyhow::Result<TriMesh> {
        let m = asperity_engine::files::load_triangles(path, &self.budget)?;
        Ok(match self.up {
            Some(up) => asperity_engine::io::up::reorient_mesh(m, path, up)?,
            None => m,
        })
    }

    /// A point set (the points of a point file, the vertices of a mesh, the
    /// samples of a height field), turned as `--up` says.
    pub fn load_points(&self, path: &Path) -> anyhow::Result<PointSet> {
        let p = asperity_engine::files::load_points(path, &self.budget)?;
        Ok(match self.up {
            Some(up) => asperity_engine::io::up::reorient_points(p, path, up)?,
            None => p,
        })
    }

    /// The up axis of files written: `--up-out`, else `--up`.
    pub fn written_up(&self) -> Option<UpAxis> {
        self.up_out.or(self.up)
    }

    /// Writer options with `--up-out` (or `--up`).
    pub fn write_options(&self) -> WriteOptions {
        WriteOptions {
            up: self.written_up(),
            ..WriteOptions::default()
        }
    }
}

/// One command: the files it writes (recorded in its report), its
/// measurements, warnings and notes.
pub struct Run<'a> {
    pub ctx: &'a Context,
    pub report: Report,
}

impl<'a> Run<'a> {
    pub fn new(ctx: &'a Context, command: &'static str) -> Self {
        let mut report = Report::new(command, ctx.seed, ctx.threads);
        report.budget(&ctx.budget);
        Self { ctx, report }
    }

    /// Writer options with `--up` and the parameters recorded by
    /// [`Run::params`], which every file with a place for metadata keeps
    /// (`asperity_engine::io::metadata`).
    pub fn write_options(&self) -> WriteOptions {
        WriteOptions {
            params: self.report.params.clone(),
            ..self.ctx.write_options()
        }
    }

    /// Writes a triangle mesh.
    pub fn mesh(&mut self, path: &Path, m: &TriMesh) -> anyhow::Result<()> {
        asperity_engine::io::write_mesh(path, m, &self.write_options())?;
        self.report.output(path);
        Ok(())
    }

    /// Writes a height field with a title (where the format has one).
    pub fn height(
        &mut self,
        path: &Path,
        h: &asperity_engine::core::HeightField,
        title: String,
    ) -> anyhow::Result<()> {
        let opts = WriteOptions {
            title,
            ..self.write_options()
        };
        match self.ctx.units {
            (None, None) => asperity_engine::io::write_height(path, h, &opts)?,
            _ => asperity_engine::io::write_height(path, &self.ctx.with_units(h.clone()), &opts)?,
        }
        self.report.output(path);
        Ok(())
    }

    /// Writes points (refusing none) with a title.
    pub fn points(&mut self, path: &Path, pts: Vec<[f64; 3]>, title: &str) -> anyhow::Result<()> {
        anyhow::ensure!(!pts.is_empty(), "no particle to write");
        let opts = WriteOptions {
            title: title.into(),
            ..self.write_options()
        };
        asperity_engine::io::write_points(path, &PointSet::new(pts), &opts)?;
        self.report.output(path);
        Ok(())
    }

    /// Writes a point set.
    pub fn point_set(&mut self, path: &Path, ps: &PointSet) -> anyhow::Result<()> {
        asperity_engine::io::write_points(path, ps, &self.write_options())?;
        self.report.output(path);
        Ok(())
    }

    /// Writes text.
    pub fn text(&mut self, path: &Path, text: &str) -> anyhow::Result<()> {
        asperity_engine::io::write_text(path, text)?;
        self.report.output(path);
        Ok(())
    }

    /// Writes a PNG picture.
    pub fn png(&mut self, path: &Path, img: &RgbaImage) -> anyhow::Result<()> {
        asperity_engine::io::write_png_with(path, img, &self.write_options())?;
        self.report.output(path);
        Ok(())
    }

    /// Writes `plots` into `dir` (created if missing) at `size`: each by its
    /// name's extension, and an `.svg` also as `.png`.
    pub fn plots(
        &mut self,
        dir: &Path,
        plots: &[NamedPlot],
        size: (u32, u32),
    ) -> anyhow::Result<()> {
        asperity_engine::io::create_output_dir(dir)?;
        for p in plots {
            let path = dir.join(p.name);
            if p.name.ends_with(".svg") {
                self.text(&path, &plot_svg(&p.plot, size.0, size.1)?)?;
                self.png(
                    &path.with_extension("png"),
                    &plot_png(&p.plot, size.0, size.1)?,
                )?;
            } else {
                self.png(&path, &plot_png(&p.plot, size.0, size.1)?)?;
            }
        }
        Ok(())
    }

    /// Records the parameters the job ran with (and the seed, which the
    /// report states too).
    pub fn params<P: JobParams>(&mut self, params: &P, seed: u64, overridden: Vec<String>) {
        self.report.seed = seed;
        self.report.params = Some(record(params, seed));
        self.report.params_overridden = overridden;
    }

    /// Records measurements.
    pub fn measure(&mut self, facts: Measurements) {
        self.report.extend(facts);
    }

    /// Prints `kind: msg` on stderr (unless `--quiet`, even with `--json`) and
    /// records it as a warning in the report.
    pub fn warn(&mut self, kind: &str, msg: String) {
        // Warnings reach stderr with --json too (stdout holds the report); only
        // --quiet hides them.
        let msg = self.ctx.shown(&msg);
        if !self.ctx.quiet {
            eprintln!("{kind}: {msg}");
        }
        self.report.warn(msg);
    }

    /// Prints an informational line (see [`Context::note`]).
    pub fn note(&self, msg: impl AsRef<str>) {
        self.ctx.note(msg);
    }

    /// Prints the report as JSON on stdout with `--json`.
    pub fn finish(mut self) -> anyhow::Result<()> {
        self.report.stop_clock();
        if self.ctx.json {
            use std::io::Write;
            let mut out = std::io::stdout().lock();
            serde_json::to_writer_pretty(&mut out, &self.report)?;
            writeln!(out)?;
        }
        Ok(())
    }
}
