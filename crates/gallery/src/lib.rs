//! The gallery (`asperity demo`): every method of the five papers on small
//! built-in defaults, written into a folder with an `index.html` that shows
//! each picture with its facts, and a `report.json` with the same as data.
//!
//! One module per paper (and two for the foundation and the renderer); each
//! contributes a [`Section`] of cards, one card per figure it reproduces:
//!
//! | Module | Section | Paper |
//! | --- | --- | --- |
//! | [`foundation`] | the shared types and every file format | — |
//! | [`renderer`] | shaders, views, overlays, plots | gobron-chiba light model |
//! | [`peridier`] | CA surfaces, Figures 1–4, 6, 9 | peridier |
//! | [`growth`] | RD, RDSR, BD, DLA, curved substrates | kim-machiraju-thompson §4 |
//! | [`levelset`] | level-set reconstruction, Figures 8–10 | kim-machiraju-thompson §5–6 |
//! | [`ifs`] | projected-IFS curves and surfaces, Figures 1, 2, 4 | poull-gentil |
//! | [`surfca`] | surface Voronoi, corrosion, Gray–Scott | gobron-chiba |
//! | [`subdiv`] | multiresolution surfaces, Figures 3–12 | velho-perlin |
//! | [`metrology`] | ISO 16610 filters, material ratio curve, feature segmentation | — (ISO 25178-2, ISO 16610) |
//!
//! Sections write their files through [`Env`], which records them for the page
//! and the report. Wall-clock timings go to `report.json` only, so the page is
//! the same bytes on every run with the same seed.

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::path::PathBuf;

use asperity_engine::core::{MemoryBudget, Progress, RgbaImage, TriMesh};
use asperity_engine::error::invalid;
use asperity_engine::io::{Surface, WriteOptions};
use asperity_engine::methods::render::{RenderOptions, Shader, render_mesh};
use asperity_engine::{Report, Result};

pub mod downloads;
pub mod foundation;
pub mod growth;
pub mod ifs;
pub mod levelset;
pub mod metrology;
pub mod page;
pub mod peridier;
pub mod renderer;
pub mod subdiv;
pub mod surfca;
pub mod viewer;

/// What the gallery is asked for.
#[derive(Clone, Debug)]
pub struct Options {
    /// The folder it is written into (created if missing).
    pub dir: PathBuf,
    /// The seed every random surface comes from.
    pub seed: u64,
    /// Smaller sizes for a fast run.
    pub quick: bool,
    /// Every mesh download whole (by default a mesh above
    /// [`downloads::TRIANGLE_BUDGETS`] is written reduced, see [`downloads`]).
    pub full_meshes: bool,
    /// Only these sections (by [`SECTIONS`] name); empty for all.
    pub only: Vec<String>,
    /// The memory budget of every job.
    pub budget: MemoryBudget,
    /// Worker threads (for the report).
    pub threads: usize,
}

/// What a section function gets: where to write, the seed, the sizes.
pub struct Env {
    /// The gallery folder.
    pub dir: PathBuf,
    /// The seed.
    pub seed: u64,
    /// The memory budget.
    pub budget: MemoryBudget,
    /// Smaller sizes.
    pub quick: bool,
    /// Meshes with more triangles are written reduced ([`downloads`]).
    pub download_budget: usize,
    /// Mesh files written reduced: file name → (triangles written, triangles whole).
    pub reduced: RefCell<BTreeMap<String, (usize, usize)>>,
    /// Outputs and measurements so far.
    pub report: RefCell<Report>,
    /// The 3-D view of each mesh file written (file name → `viewer/STEM.js`).
    pub models: RefCell<BTreeMap<String, String>>,
}

impl Env {
    /// Writes `s` as `name` in the gallery and records it.
    ///
    /// # Errors
    /// The writer's.
    /// Meshes above [`Self::download_budget`] triangles are written reduced
    /// ([`downloads`]); PLY files hold 32-bit floats, as Blender and MeshLab
    /// do.
    ///
    /// # Errors
    /// The writer's.
    pub fn write(&self, name: &str, s: &Surface) -> Result<String> {
        let path = self.dir.join(name);
        let opts = WriteOptions {
            ply_float32: true,
            ..WriteOptions::default()
        };
        match s {
            Surface::Mesh(m) if m.n_faces() > self.download_budget => {
                let r = downloads::reduced(m, self.download_budget)?;
                self.reduced
                    .borrow_mut()
                    .insert(name.to_owned(), (r.n_faces(), m.n_faces()));
                asperity_engine::io::write_mesh(&path, &r, &opts)?;
                self.model(name, &r)?;
            }
            Surface::Mesh(m) => {
                asperity_engine::io::write_mesh(&path, m, &opts)?;
                self.model(name, m)?;
            }
            _ => asperity_engine::io::write(&path, s, &opts)?,
        }
        self.report.borrow_mut().output(&path);
        Ok(name.to_owned())
    }

    /// Gives the mesh file `name` a 3-D view (one per file stem: a `.ply` and
    /// a `.glb` of the same mesh share it).
    fn model(&self, name: &str, m: &TriMesh) -> Result<()> {
        let stem = std::path::Path::new(name)
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let script = format!("{}/{stem}.js", viewer::DIR);
        let known = self.models.borrow().values().any(|v| *v == script);
        let script = match known {
            true => Some(script),
            false => viewer::write_model(&self.dir, &stem, m)?,
        };
        if let Some(script) = script {
            self.models.borrow_mut().insert(name.to_owned(), script);
        }
        Ok(())
    }

    /// Writes a mesh as `name`.
    ///
    /// # Errors
    /// The writer's.
    pub fn mesh(&self, name: &str, m: &TriMesh) -> Result<String> {
        self.write(name, &Surface::Mesh(m.clone()))
    }

    /// Render options for gallery pictures (smaller with `quick`).
    pub fn view(&self) -> RenderOptions {
        let (w, h) = if self.quick { (400, 300) } else { (800, 600) };
        RenderOptions {
            width: w,
            height: h,
            budget: self.budget,
            ..RenderOptions::default()
        }
    }

    /// Writes a text document (an SVG plot, a JSON report) and records it.
    ///
    /// # Errors
    /// The writer's.
    pub fn text(&self, name: &str, text: &str) -> Result<String> {
        let path = self.dir.join(name);
        asperity_engine::io::write_text(&path, text)?;
        self.report.borrow_mut().output(&path);
        Ok(name.to_owned())
    }

    /// Writes an RGBA picture as PNG and records it.
    ///
    /// # Errors
    /// The writer's.
    pub fn picture(&self, name: &str, img: &RgbaImage) -> Result<String> {
        let path = self.dir.join(name);
        asperity_engine::io::write_png(&path, img)?;
        self.report.borrow_mut().output(&path);
        Ok(name.to_owned())
    }

    /// Renders `m` with `opts` into `name`.
    ///
    /// # Errors
    /// The renderer's and the writer's.
    pub fn render(&self, name: &str, m: &TriMesh, opts: &RenderOptions) -> Result<String> {
        self.picture(name, &render_mesh(m, opts)?)
    }

    /// Writes `STEM.ply` and a render of it as `STEM.png` (default view);
    /// returns (file, picture).
    ///
    /// # Errors
    /// The renderer's and the writer's.
    pub fn shaded_mesh(&self, stem: &str, m: &TriMesh) -> Result<(String, String)> {
        let file = self.mesh(&format!("{stem}.ply"), m)?;
        let pic = self.render(&format!("{stem}.png"), m, &self.view())?;
        Ok((file, pic))
    }

    /// Writes `STEM.ply` and a render of it in its vertex colours as `STEM.png`;
    /// returns (file, picture).
    ///
    /// # Errors
    /// The renderer's and the writer's.
    pub fn colored_mesh(&self, stem: &str, m: &TriMesh) -> Result<(String, String)> {
        let file = self.mesh(&format!("{stem}.ply"), m)?;
        let opts = RenderOptions {
            shader: Shader::VertexColor,
            ..self.view()
        };
        let pic = self.render(&format!("{stem}.png"), m, &opts)?;
        Ok((file, pic))
    }

    /// Records a measurement in the report.
    pub fn measure(&self, key: &str, value: impl serde::Serialize) {
        self.report.borrow_mut().measure(key, value);
    }
}

/// One card in the gallery.
#[derive(Clone, Debug, Default)]
pub struct Item {
    /// Its title (the figure it reproduces).
    pub title: String,
    /// The picture.
    pub image: Option<String>,
    /// Files to download.
    pub files: Vec<String>,
    /// The script of its 3-D view (`viewer/STEM.js`), set for cards with a mesh
    /// file when the page is written.
    pub model: Option<String>,
    /// Facts, as (name, value).
    pub facts: Vec<(String, String)>,
}

impl Item {
    /// A card with a title, a picture, files and facts.
    pub fn new(
        title: impl Into<String>,
        image: Option<String>,
        files: Vec<String>,
        facts: Vec<(String, String)>,
    ) -> Self {
        Self {
            title: title.into(),
            image,
            files,
            facts,
            model: None,
        }
    }
}

/// One method family's part of the gallery.
#[derive(Clone, Debug)]
pub struct Section {
    /// Its heading.
    pub title: String,
    /// Where the code lives and what it implements.
    pub source: String,
    /// A paragraph on the method.
    pub blurb: String,
    /// The cards.
    pub items: Vec<Item>,
}

/// A fact for a card.
pub fn fact(k: &str, v: impl std::fmt::Display) -> (String, String) {
    (k.to_owned(), v.to_string())
}

type SectionFn = fn(&Env) -> Result<Section>;

/// The gallery, in page order: (name for `--only`, section).
pub const SECTIONS: &[(&str, SectionFn)] = &[
    ("foundation", foundation::section),
    ("renderer", renderer::section),
    ("peridier", peridier::section),
    ("growth", growth::section),
    ("levelset", levelset::section),
    ("ifs", ifs::section),
    ("surfca", surfca::section),
    ("subdiv", subdiv::section),
    ("metrology", metrology::section),
];

/// Refuses section names the gallery does not have.
fn check_only(only: &[String]) -> Result<()> {
    match only.iter().find(|x| !SECTIONS.iter().any(|(n, _)| n == x)) {
        Some(bad) => {
            let names: Vec<&str> = SECTIONS.iter().map(|(n, _)| *n).collect();
            Err(invalid(format!(
                "--only {bad}: no such section ({})",
                names.join(", ")
            )))
        }
        None => Ok(()),
    }
}

/// Writes `index.html` and `report.json` for `sections`; returns the report.
fn finish(env: Env, mut sections: Vec<Section>, o: &Options) -> Result<Report> {
    let models = env.models.borrow().clone();
    let reduced = env.reduced.borrow().clone();
    for it in sections.iter_mut().flat_map(|s| s.items.iter_mut()) {
        it.model = it.files.iter().find_map(|f| models.get(f)).cloned();
        let with_cli = it.facts.iter().any(|(k, _)| k == "CLI");
        for f in &it.files {
            if let Some((kept, whole)) = reduced.get(f) {
                it.facts.push(downloads::fact(f, *kept, *whole, with_cli));
            }
        }
    }
    if !reduced.is_empty() {
        let files: BTreeMap<&String, [usize; 2]> =
            reduced.iter().map(|(f, (k, w))| (f, [*k, *w])).collect();
        env.measure("reduced_downloads", files);
    }
    if !models.is_empty() {
        viewer::write_assets(&o.dir)?;
    }
    let index = o.dir.join("index.html");
    asperity_engine::io::write_text(&index, &page::page(&sections, o.seed, o.quick))?;
    let mut report = env.report.into_inner();
    report.output(&index);
    let titles: Vec<String> = sections.iter().map(|s| s.title.clone()).collect();
    report.measure("sections", titles);
    let json =
        serde_json::to_string_pretty(&report).map_err(|e| invalid(format!("report.json: {e}")))?;
    asperity_engine::io::write_text(&o.dir.join("report.json"), &json)?;
    Ok(report)
}

/// Writes the gallery; returns its report (also written as `report.json`).
///
/// # Errors
/// An unknown section name; the folder cannot be created; any section's
/// failure, named.
pub fn run(o: &Options, progress: &dyn Progress) -> Result<Report> {
    check_only(&o.only)?;
    std::fs::create_dir_all(o.dir.join(viewer::DIR)).map_err(|e| {
        invalid(format!(
            "cannot create gallery directory {}: {e}",
            o.dir.display()
        ))
    })?;
    let env = Env {
        dir: o.dir.clone(),
        seed: o.seed,
        budget: o.budget,
        quick: o.quick,
        download_budget: match (o.full_meshes, o.quick) {
            (true, _) => usize::MAX,
            (false, true) => downloads::TRIANGLE_BUDGETS.0,
            (false, false) => downloads::TRIANGLE_BUDGETS.1,
        },
        reduced: RefCell::default(),
        report: RefCell::new(Report::new("demo", o.seed, o.threads)),
        models: RefCell::default(),
    };
    let chosen: Vec<&(&str, SectionFn)> = SECTIONS
        .iter()
        .filter(|(n, _)| o.only.is_empty() || o.only.iter().any(|x| x == n))
        .collect();
    progress.start(chosen.len() as u64, "demo");
    let mut sections = Vec::new();
    for (name, f) in chosen {
        let t = std::time::Instant::now();
        let s = f(&env).map_err(|e| invalid(format!("demo section {name}: {e}")))?;
        env.measure(&format!("{name}_seconds"), t.elapsed().as_secs_f64());
        sections.push(s);
        progress.advance(1);
    }
    progress.finish();
    finish(env, sections, o)
}
