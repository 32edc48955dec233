//! Inputs and output names shared by every job: any file read under the memory
//! budget, the built-in meshes, text files, and the names of numbered outputs
//! (animation frames, saved steps).

use std::path::{Path, PathBuf};

use asperity_core::{Diagonal, HeightField, MemoryBudget, PointSet, TriMesh, shapes};
use asperity_io::{Format, IoError, Surface};
use clap::Args;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::error::{Result, invalid};
use crate::params::{JobParams, choice};

/// Refuses to read `path` when [`asperity_io::read_estimate`] (its size, and the
/// decoded size its header declares) exceeds the budget.
///
/// # Errors
/// [`IoError`] naming the file; the memory budget.
pub fn check_read(path: &Path, budget: &MemoryBudget) -> Result<()> {
    let bytes = asperity_io::read_estimate(path)?;
    budget.check(bytes, format!("reading {}", path.display()))?;
    Ok(())
}

/// `read(path)` after [`check_read`].
fn budgeted<T>(
    path: &Path,
    budget: &MemoryBudget,
    read: impl FnOnce(&Path) -> std::result::Result<T, IoError>,
) -> Result<T> {
    check_read(path, budget)?;
    Ok(read(path)?)
}

/// Reads whatever `path` holds (by extension) under the budget ([`check_read`]).
///
/// # Errors
/// [`IoError`] naming the file; the memory budget.
pub fn load(path: &Path, budget: &MemoryBudget) -> Result<Surface> {
    load_channel(path, budget, None)
}

/// [`load`] of the channel `choice` names in a multi-channel file
/// (`asperity_io::channel`; `None`: the height channel).
///
/// # Errors
/// As [`load`]; a channel the file does not have.
pub fn load_channel(
    path: &Path,
    budget: &MemoryBudget,
    choice: Option<&asperity_io::Channel>,
) -> Result<Surface> {
    budgeted(path, budget, |p| asperity_io::read_channel(p, choice))
}

/// A height field read under the budget ([`check_read`]).
///
/// # Errors
/// As [`load`]; the file holds no height field.
pub fn load_height(path: &Path, budget: &MemoryBudget) -> Result<HeightField> {
    budgeted(path, budget, asperity_io::read_height)
}

/// A point set read under the budget ([`check_read`]).
///
/// # Errors
/// As [`load`]; the file holds no point set.
pub fn load_points(path: &Path, budget: &MemoryBudget) -> Result<PointSet> {
    budgeted(path, budget, asperity_io::read_points)
}

/// A triangle mesh read from a file under the budget ([`check_read`]).
///
/// # Errors
/// As [`load`]; the file holds no mesh.
pub fn load_triangles(path: &Path, budget: &MemoryBudget) -> Result<TriMesh> {
    budgeted(path, budget, asperity_io::read_mesh)
}

/// `x y` rows read under the budget ([`check_read`]).
///
/// # Errors
/// As [`load`].
pub fn load_xy(path: &Path, budget: &MemoryBudget) -> Result<Vec<[f64; 2]>> {
    budgeted(path, budget, asperity_io::read_xy)
}

/// The names [`builtin_mesh`] knows.
pub const BUILTIN_MESHES: &[&str] = &["sphere", "cube", "cylinder", "cup"];

/// A built-in triangle mesh: `sphere` (icosphere, level 3), `cube` (4 × 4 per
/// face), `cylinder` (closed, radius 0.5, height 2), `cup` (the open cup of
/// gobron-chiba's figures).
///
/// # Errors
/// [`crate::EngineError::Invalid`] for an unknown name.
pub fn builtin_mesh(name: &str) -> Result<TriMesh> {
    Ok(match name {
        "sphere" => shapes::icosphere(3, 1.0),
        "cube" => shapes::cube(4),
        "cup" => shapes::cup(48),
        "cylinder" => shapes::revolve(
            &[
                [0.0, 0.0],
                [0.5, 0.0],
                [0.5, 0.5],
                [0.5, 1.0],
                [0.5, 1.5],
                [0.5, 2.0],
                [0.0, 2.0],
            ],
            48,
        ),
        _ => {
            return Err(invalid(format!(
                "unknown built-in mesh {name:?}; known: {}",
                BUILTIN_MESHES.join(", ")
            )));
        }
    })
}

/// A triangle mesh from `builtin:NAME` or a file.
///
/// # Errors
/// As [`builtin_mesh`] and [`load`]; [`crate::EngineError::Invalid`] when the
/// file holds no triangle mesh.
pub fn load_mesh(spec: &str, budget: &MemoryBudget) -> Result<TriMesh> {
    if let Some(name) = spec.strip_prefix("builtin:") {
        return builtin_mesh(name);
    }
    match load(Path::new(spec), budget)? {
        Surface::Mesh(m) => Ok(m),
        _ => Err(invalid(format!(
            "{spec} is not a triangle mesh (a surface CA lives on triangles)"
        ))),
    }
}

/// The text of `path`.
///
/// # Errors
/// [`IoError::Os`] naming the file.
pub fn read_text(path: &Path) -> Result<String> {
    asperity_io::staging::note_input(path);
    Ok(std::fs::read_to_string(path).map_err(|e| IoError::os(path, e))?)
}

/// `dir/STEM_TAGNNNN.EXT` beside `out`, with `k` zero-padded to `width` digits:
/// the name of frame or step `k` of an output.
pub fn numbered(out: &Path, tag: &str, k: u64, width: usize) -> PathBuf {
    let stem = out.file_stem().and_then(|s| s.to_str()).unwrap_or("frame");
    let ext = out.extension().and_then(|s| s.to_str()).unwrap_or("ply");
    out.with_file_name(format!("{stem}_{tag}{k:0width$}.{ext}"))
}

/// Whether `path` names a point-set format (`.ply`, `.xyz`, `.csv`) rather than a
/// height field.
///
/// # Errors
/// [`IoError::UnknownFormat`].
pub fn is_points_path(path: &Path) -> Result<bool> {
    let f = Format::of_file(path)?;
    Ok(matches!(f, Format::Ply | Format::Xyz | Format::Csv))
}

/// Refuses an output path whose format cannot hold a triangle mesh.
///
/// # Errors
/// [`IoError::UnknownFormat`]; [`crate::EngineError::Invalid`] naming the
/// formats that can.
pub fn require_mesh_format(path: &Path, formats: &str) -> Result<()> {
    if Format::from_path(path)?.info().mesh.can_write() {
        Ok(())
    } else {
        Err(invalid(format!(
            "{} cannot hold a mesh; use {formats}",
            path.display()
        )))
    }
}

/// The lower-case extension of `path` ("" without one).
pub fn extension(path: &Path) -> String {
    path.extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbered_names_keep_folder_and_extension() {
        let p = numbered(Path::new("out/terrain.glb"), "step", 10, 4);
        assert_eq!(p, Path::new("out/terrain_step0010.glb"));
        assert_eq!(
            numbered(Path::new("v.png"), "", 7, 3),
            Path::new("v_007.png")
        );
    }

    #[test]
    fn builtins_are_closed_or_named_in_the_error() {
        for name in BUILTIN_MESHES {
            let m = builtin_mesh(name).unwrap();
            assert!(m.n_faces() > 0, "{name}");
        }
        let e = builtin_mesh("teapot").unwrap_err().to_string();
        assert!(e.contains("sphere, cube, cylinder, cup"), "{e}");
    }
}

choice! {
    /// What a file's contents are taken as.
    pub enum KindName {
        /// A triangle mesh (height fields are triangulated).
        Mesh = "mesh",
        /// A point set (mesh vertices, height-field samples).
        Points = "points",
        /// A height field.
        Height = "height",
    }
}

choice! {
    /// The diagonal each grid cell is split along when a height field becomes triangles.
    pub enum DiagonalName {
        /// Every cell split along the same diagonal.
        Forward = "forward",
        /// Every cell split along the other diagonal.
        Backward = "backward",
        /// Alternating diagonals (peridier's facets).
        Alternating = "alternating",
    }
}

impl From<DiagonalName> for Diagonal {
    fn from(d: DiagonalName) -> Self {
        match d {
            DiagonalName::Forward => Diagonal::Forward,
            DiagonalName::Backward => Diagonal::Backward,
            DiagonalName::Alternating => Diagonal::Alternating,
        }
    }
}

/// `convert`: any surface file to any format that can hold it, optionally
/// taken as another kind, repaired, or given a spacing.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct ConvertParams {
    /// Treat the input as this kind (default: what the file holds).
    #[arg(long = "as", value_enum, value_name = "KIND")]
    pub as_kind: Option<KindName>,
    /// Write PLY as ASCII instead of binary.
    #[arg(long)]
    pub ascii: bool,
    /// Write 32-bit floats: .npy height fields as float32, PLY positions and scalars as
    /// float (instead of 64-bit).
    #[arg(long)]
    pub f32: bool,
    /// Diagonal for height field → mesh.
    #[arg(long, value_enum, default_value_t = Self::default().diagonal)]
    pub diagonal: DiagonalName,
    /// Set the height-field spacing before writing: DX, or DX,DY.
    #[schemars(
        with = "Option<Vec<crate::params::Positive>>",
        length(min = 1, max = 2)
    )]
    #[arg(long, value_name = "DX[,DY]", value_delimiter = ',')]
    pub spacing: Option<Vec<f64>>,
    /// Meshes: drop degenerate triangles, orient them consistently and split vertices where
    /// separate fans meet, so subdiv and surface-ca accept the mesh.
    #[arg(long)]
    pub repair: bool,
    /// Height fields with missing (unmeasured) points: fill them (harmonic: the smoothest
    /// surface through the measured points; mean: the mean measured height) or refuse the
    /// field. By default they are kept: NaN in .npy, .x3p, .exr, .gsf and .csv, Gwyddion's
    /// mask in .gwy, holes in meshes; PNG and SDF refuse them.
    #[arg(long, value_enum, value_name = "HOW")]
    pub fill: Option<crate::analyze::FillChoice>,
}

impl Default for ConvertParams {
    fn default() -> Self {
        Self {
            as_kind: None,
            ascii: false,
            f32: false,
            diagonal: DiagonalName::Forward,
            spacing: None,
            repair: false,
            fill: None,
        }
    }
}

impl JobParams for ConvertParams {
    const JOB: &'static str = "convert";
    const SEEDED: bool = false;
}

/// What `convert` did to a surface besides writing it.
#[derive(Clone, Debug, Default)]
pub struct Converted {
    /// The repair's changes, when one was asked for.
    pub repair: Option<asperity_core::mesh_check::RepairReport>,
    /// The missing points filled, when `--fill` filled some.
    pub filled: Option<asperity_analysis::fill::Filled>,
}

impl ConvertParams {
    /// `s` taken as the asked kind, repaired, given its spacing; `name`
    /// names the input in messages.
    ///
    /// # Errors
    /// A kind the surface cannot become; a repair of what is not a mesh, or
    /// one that fails; a bad spacing.
    pub fn apply(&self, mut s: Surface, name: &str) -> Result<(Surface, Converted)> {
        crate::params::validate(self)?;
        let mut done = Converted::default();
        if let (Some(how), Surface::Height(h)) = (self.fill, &mut s)
            && h.has_missing()
        {
            let Some(fill) = how.fill() else {
                return Err(asperity_core::CoreError::MissingPoints {
                    missing: h.missing_count(),
                    total: h.len(),
                    what: format!("convert {}", asperity_core::wording::param("fill")),
                }
                .into());
            };
            let (filled, report) = asperity_analysis::fill::fill_missing(h, fill)?;
            *h = filled;
            done.filled = Some(report);
        }
        if let Some(k) = self.as_kind {
            s = to_kind(s, k, self.diagonal.into())?;
        }
        if self.repair {
            let Surface::Mesh(m) = &s else {
                return Err(invalid(format!(
                    "{} works on meshes; {name} holds {}",
                    asperity_core::wording::param("repair"),
                    s.kind()
                )));
            };
            let (fixed, r) = asperity_core::mesh_check::repair_surface(m)
                .map_err(|e| invalid(format!("{name}: cannot repair: {e}")))?;
            done.repair = Some(r);
            s = Surface::Mesh(fixed);
        }
        if let (Some(sp), Surface::Height(h)) = (&self.spacing, &mut s) {
            let sp = [sp[0], *sp.get(1).unwrap_or(&sp[0])];
            *h = h.clone().with_spacing(sp)?;
        }
        Ok((s, done))
    }

    /// The writer's options: PLY encoding, npy type, diagonal, with `title`
    /// and the up axis.
    pub fn write_options(
        &self,
        title: String,
        up: Option<asperity_io::UpAxis>,
    ) -> asperity_io::WriteOptions {
        asperity_io::WriteOptions {
            ply_encoding: if self.ascii {
                asperity_io::PlyEncoding::Ascii
            } else {
                asperity_io::PlyEncoding::BinaryLittleEndian
            },
            ply_float32: self.f32,
            npy_dtype: if self.f32 {
                asperity_io::NpyDtype::Float32
            } else {
                asperity_io::NpyDtype::Float64
            },
            diagonal: self.diagonal.into(),
            title,
            up,
            params: None,
        }
    }
}

fn to_kind(s: Surface, kind: KindName, diag: Diagonal) -> Result<Surface> {
    Ok(match (s, kind) {
        (Surface::Height(h), KindName::Mesh) => Surface::Mesh(
            h.to_trimesh(diag)?
                .with_scalar("height", h.measured_values())?,
        ),
        (Surface::Height(h), KindName::Points) => Surface::Points(h.to_point_set()),
        (Surface::Mesh(m), KindName::Points) => {
            Surface::Points(asperity_core::PointSet::new(m.positions().to_vec()))
        }
        (s @ Surface::Mesh(_), KindName::Mesh)
        | (s @ Surface::Points(_), KindName::Points)
        | (s @ Surface::Height(_), KindName::Height) => s,
        (s, k) => {
            return Err(invalid(format!(
                "cannot turn {} into {}",
                s.kind(),
                match k {
                    KindName::Mesh => "a mesh",
                    KindName::Points => "a point set",
                    KindName::Height => "a height field",
                }
            )));
        }
    })
}

/// `info`: facts about a file; it has no parameters besides the file.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct InfoParams {}

impl JobParams for InfoParams {
    const JOB: &'static str = "info";
    const SEEDED: bool = false;
}
