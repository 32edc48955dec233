//! File formats for asperity: meshes, point sets and height fields.
//!
//! The format follows the file extension. Every writer is atomic (see [`atomic`]):
//! a failed or interrupted write leaves no partial file at the target path, and
//! an existing file there is kept until the new one is complete.
//!
//! | Format | Extensions | Mesh | Points | Height field | Module |
//! | --- | --- | --- | --- | --- | --- |
//! | PLY (binary LE / ASCII) | `.ply` | read + write | read + write | — | [`ply`] |
//! | Wavefront OBJ | `.obj` | read + write | — | — | [`obj`] |
//! | STL (binary; ASCII read) | `.stl` | read + write | — | — | [`stl`] |
//! | glTF 2.0 binary | `.glb` | write | — | — | [`glb`] |
//! | XYZ text | `.xyz`, `.txt` | — | read + write | — | [`text`] |
//! | NumPy | `.npy` | — | read + write `(N, 3)` | read + write `(ny, nx)` | [`npy`] |
//! | PNG, 16-bit gray | `.png` | — | — | read + write | [`png_io`] |
//! | OpenEXR float | `.exr` | — | — | read + write | [`exr_io`] |
//! | Gwyddion Simple Field | `.gsf` | — | — | read + write | [`gsf`] |
//! | Gwyddion native | `.gwy` | — | — | read + write | [`gwy`] |
//! | ISO 25178-72 x3p | `.x3p` | — | — | read + write | [`x3p`] |
//! | CSV grid | `.csv` | — | — | read + write | [`text`] |
//!
//! Height fields written to a mesh format are triangulated; meshes and height
//! fields written to a point format give their vertices / samples.
//!
//! Instruments' formats are read (and `.sdf` written), one module each:
//! [`sdf`], [`sur`], [`mnt`], [`tmd`], [`bcr`], [`metropro`], [`al3d`],
//! [`wsxm`], [`plu`], [`opd`], [`frt`], [`di`], [`nid`], [`mi`], [`ibw`],
//! [`park`], [`xz`] (`.hfm`, Dektak CSV, titled CSV line scans), [`nms`], [`opdx`], [`nc`], [`h5`], [`datx`], [`oir`] (`.oir`, `.poir`), [`mat`], [`npz`], [`hgt`], [`vk`], [`mdt`], [`os3d`], [`zmg`], [`plux`], [`zon`], [`lext`], [`jpk`], [`qep`], [`nmm`],
//! [`mitutoyo`] and [`asc`] (plain-text heights); [`FORMATS`] (and
//! `asperity formats`) lists every format with what it reads and keeps.

pub mod atomic;
mod bytes;
pub mod channel;
pub mod datx;
pub mod decimal;
mod error;
pub mod format;
pub mod h5;
mod header_keys;
pub mod metadata;
pub mod oir;
mod raster;
pub mod staging;
pub mod text;
mod tiff_dir;
pub mod up;
mod write;
pub mod xz;
mod zipped;

// The registry: every format, one line each, in the order `asperity formats`
// lists them (see `format::registry`). A line declares the format's module
// (unless it reads several and is declared above) and its variant of
// `Format`.
format::registry! {
    /// Stanford PLY.
    Ply => ply,
    /// Wavefront OBJ.
    Obj => obj,
    /// STL.
    Stl => stl,
    /// glTF 2.0 binary.
    Glb => glb,
    /// XYZ point text.
    Xyz => text::XYZ,
    /// NumPy array.
    Npy => npy,
    /// PNG image.
    Png => png_io,
    /// OpenEXR image.
    Exr => exr_io,
    /// Gwyddion Simple Field.
    Gsf => gsf,
    /// Comma-separated grid.
    Csv => text::CSV,
    /// Gwyddion's native format.
    Gwy => gwy,
    /// ISO 25178-72 x3p.
    X3p => x3p,
    /// ISO 25178-71 surface data file.
    Sdf => sdf,
    /// Digital Surf (MountainsMap) surface.
    Sur => sur,
    /// TrueMap surface.
    Tmd => tmd,
    /// BCR-STM / BCRF scanning-probe image.
    Bcr => bcr,
    /// Zygo MetroPro interferometer data.
    MetroPro => metropro,
    /// Alicona Imaging depth image.
    Al3d => al3d,
    /// WSxM scanning-probe image.
    Wsxm => wsxm,
    /// Sensofar confocal/interferometric topography.
    Plu => plu,
    /// NetCDF-3 topographies in SurfaceTopography's layout.
    Nc => nc,
    /// Nanosurf easyScan scanning-probe data.
    Nid => nid,
    /// Molecular Imaging / Agilent PicoView images.
    Mi => mi,
    /// Igor Pro binary waves (Asylum Research AFMs).
    Ibw => ibw,
    /// Park Systems AFM TIFF.
    Park => park,
    /// `X;Y;valid` line scans (`.hfm`).
    Hfm => xz::HFM,
    /// Bruker Dektak profilometer CSV exports (told from a CSV grid by content).
    Dektak => xz::DEKTAK,
    /// Line scans as CSV with column titles (`x,z` or `index,x,z`; told
    /// from a CSV grid by content).
    CsvLineScan => xz::CSV_LINE_SCAN,
    /// NanoFocus µsurf confocal microscope data.
    Nms => nms,
    /// MATLAB workspace files (version 5 and 7.3).
    Mat => mat,
    /// NumPy archives of arrays.
    Npz => npz,
    /// NASA SRTM elevation tiles.
    Hgt => hgt,
    /// Keyence VK confocal microscope data.
    Vk => vk,
    /// NT-MDT scanning-probe data.
    Mdt => mdt,
    /// Digital Metrology OmniSurf3D data.
    Os3d => os3d,
    /// KLA Zeta optical profiler data.
    Zmg => zmg,
    /// Sensofar PLUX archives.
    Plux => plux,
    /// Keyence ZON containers.
    Zon => zon,
    /// Olympus LEXT confocal microscope data.
    Lext => lext,
    /// JPK Instruments AFM image scans.
    Jpk => jpk,
    /// Mahr MarWin profile archives.
    Qep => qep,
    /// SIOS nanomeasuring machine scans, zipped.
    Nmm => nmm,
    /// Bruker Dektak Vision64 data.
    Opdx => opdx,
    /// Bruker / Veeco / Digital Instruments Nanoscope scanning-probe data.
    Di => di,
    /// FRT MicroProf profilometer data.
    Frt => frt,
    /// Wyko (Bruker Vision) interferometer data.
    Opd => opd,
    /// Digital Surf MountainsMap documents.
    Mnt => mnt,
    /// Height data as plain text (a matrix, Gwyddion's text export, profiles).
    Asc => asc,
    /// Mitutoyo SurfTest Excel exports (profiles).
    Mitutoyo => mitutoyo,
    /// HDF5 files (every 2-D numeric dataset a channel).
    H5 => datx::H5,
    /// Zygo Mx `.datx` files (HDF5 in Zygo's layout).
    Datx => datx::FORMAT,
    /// Point Cloud Library point clouds.
    Pcd => pcd,
    /// Olympus laser-scanning microscope files.
    Oir => oir::OIR,
    /// Packed Olympus files (a zip of `.oir`).
    Poir => oir::POIR,
}

use std::path::Path;

use asperity_core::{Diagonal, HeightField, PointSet, PolyMesh, TriMesh};

pub use atomic::write_atomic;
pub use channel::{Channel, ChannelInfo};
pub use error::IoError;
use error::{FResult, FormatError};
pub use format::{Access, FormatInfo};
pub use metadata::read_params;
pub use npy::NpyDtype;
pub use ply::PlyEncoding;
pub use staging::{Transaction, create_output_dir, exit_removing_temporaries, stale_temporaries};
pub use up::{UpAxis, reorient};
pub use write::{
    lost_data, write, write_height, write_mesh, write_mesh_with_polylines, write_npy_f64,
    write_npy_u8, write_png, write_png_with, write_points, write_poly_mesh, write_text,
};

/// Any of the three kinds of data asperity reads and writes.
#[derive(Clone, Debug, PartialEq)]
pub enum Surface {
    /// A triangle mesh.
    Mesh(TriMesh),
    /// A point set.
    Points(PointSet),
    /// A height field.
    Height(HeightField),
}

impl Surface {
    /// "a mesh", "a point set", "a height field".
    pub fn kind(&self) -> &'static str {
        match self {
            Surface::Mesh(_) => "a mesh",
            Surface::Points(_) => "a point set",
            Surface::Height(_) => "a height field",
        }
    }
}

/// Options for writers; the defaults suit most uses.
#[derive(Clone, Debug)]
pub struct WriteOptions {
    /// PLY encoding. Default: binary little-endian.
    pub ply_encoding: PlyEncoding,
    /// PLY positions and named scalars as 32-bit `float` instead of `double`
    /// (what Blender and MeshLab hold them in; a third smaller). Default: false.
    pub ply_float32: bool,
    /// `.npy` height-field element type. Default: float64.
    pub npy_dtype: NpyDtype,
    /// Diagonal used when a height field is written to a mesh format.
    pub diagonal: Diagonal,
    /// Title stored where the format has one (GSF, PNG, .gwy).
    pub title: String,
    /// The up axis of mesh and point files written (see [`up`]); `None` keeps
    /// each format's convention (OBJ y-up, the others z-up). glTF is always y-up.
    pub up: Option<UpAxis>,
    /// The parameters the data was made with (a job's `params` record),
    /// written where the format has a place for them ([`metadata`]).
    pub params: Option<serde_json::Value>,
}

impl WriteOptions {
    /// [`Self::params`] as the one-line text the writers record.
    pub(crate) fn params_text(&self) -> Option<String> {
        self.params.as_ref().map(metadata::params_text)
    }

    /// How PLY files are written.
    pub(crate) fn ply_format(&self) -> ply::PlyFormat {
        ply::PlyFormat {
            encoding: self.ply_encoding,
            float32: self.ply_float32,
        }
    }
}

impl Default for WriteOptions {
    fn default() -> Self {
        Self {
            ply_encoding: PlyEncoding::BinaryLittleEndian,
            ply_float32: false,
            npy_dtype: NpyDtype::Float64,
            diagonal: Diagonal::Forward,
            title: "asperity surface".into(),
            up: None,
            params: None,
        }
    }
}

fn read_bytes(path: &Path) -> Result<Vec<u8>, IoError> {
    staging::note_input(path);
    std::fs::read(path).map_err(|e| IoError::os(path, e))
}

pub(crate) fn wrong(path: &Path, f: Format, kind: &'static str) -> IoError {
    IoError::WrongKind {
        path: path.to_path_buf(),
        format: f.info().name,
        kind,
    }
}

/// Rough peak memory of reading a file, as a multiple of its size: text formats
/// shrink when parsed, STL's welded f32 corners grow about threefold into f64
/// vertices plus the weld table, a `u8` `.npy` grows eightfold into f64; 8×
/// covers every reader whose data is stored uncompressed.
const READ_MEMORY_FACTOR: u64 = 8;

/// An upper estimate of the memory that reading `path` needs, from its size and,
/// for compressed images (PNG, OpenEXR, x3p, Mountains documents), from the
/// dimensions in their header —
/// so a small file that decompresses to gigabytes (a "decompression bomb") is
/// refused before anything is decoded. Reads only the header.
///
/// # Errors
/// [`IoError::Os`] when the file cannot be opened; [`IoError::Malformed`] for an
/// unreadable header.
pub fn read_estimate(path: &Path) -> Result<u64, IoError> {
    let size = std::fs::metadata(path)
        .map_err(|e| IoError::os(path, e))?
        .len();
    let format = Format::of_file(path)?;
    let open = || {
        std::fs::File::open(path)
            .map(std::io::BufReader::new)
            .map_err(|e| IoError::os(path, e))
    };
    let decoded = match format {
        Format::Png => Some(png_io::header_pixels(open()?).map(pixel_bytes)),
        Format::Exr => Some(exr_io::header_pixels(open()?).map(pixel_bytes)),
        f => match f.registration().declared_size() {
            Some(declared) => Some(declared(&read_bytes(path)?)),
            None => None,
        },
    };
    estimate_from(size, decoded).map_err(|e| e.at(path, format.info().name))
}

/// [`read_estimate`] for a file already in memory.
fn estimate_bytes(bytes: &[u8], format: Format) -> FResult<u64> {
    let cursor = || std::io::Cursor::new(bytes);
    let decoded = match format {
        Format::Png => Some(png_io::header_pixels(cursor()).map(pixel_bytes)),
        Format::Exr => Some(exr_io::header_pixels(cursor()).map(pixel_bytes)),
        f => f
            .registration()
            .declared_size()
            .map(|declared| declared(bytes)),
    };
    estimate_from(bytes.len() as u64, decoded)
}

/// Decoded samples (up to four 16-bit or 32-bit channels) plus the f64 grid.
fn pixel_bytes(pixels: u128) -> u128 {
    pixels.saturating_mul(16 + 8)
}

/// The larger of the size rule and the decoded bytes a header declares.
fn estimate_from(size: u64, decoded: Option<FResult<u128>>) -> FResult<u64> {
    let by_size = size.saturating_mul(READ_MEMORY_FACTOR);
    let decoded = decoded
        .transpose()?
        .map_or(0, |n| u64::try_from(n).unwrap_or(u64::MAX));
    Ok(by_size.max(decoded))
}

/// Decodes `bytes` as a file in `format` — what [`read`] does once the file is
/// read — after checking the memory estimate ([`read_estimate`]) against
/// `budget`. `label` names the data in messages. For data that does not come
/// from a file (a network buffer, a fuzzer).
///
/// # Errors
/// [`IoError`] naming `label`; [`IoError::Invalid`] with
/// [`asperity_core::CoreError::MemoryLimit`] when the estimate exceeds `budget`.
pub fn decode(
    label: &Path,
    format: Format,
    bytes: &[u8],
    budget: &asperity_core::MemoryBudget,
) -> Result<Surface, IoError> {
    decode_channel(label, format, bytes, budget, None)
}

/// [`decode`] of the channel `choice` names (see [`channel`]; `None`: the
/// height channel SurfaceTopography would read).
///
/// # Errors
/// As [`decode`]; a channel the file does not have, named with the file's
/// channels.
pub fn decode_channel(
    label: &Path,
    format: Format,
    bytes: &[u8],
    budget: &asperity_core::MemoryBudget,
    choice: Option<&Channel>,
) -> Result<Surface, IoError> {
    let at = |e: FormatError| e.at(label, format.info().name);
    let needed = estimate_bytes(bytes, format).map_err(at)?;
    budget
        .check(needed, format!("reading {}", label.display()))
        .map_err(|e| IoError::invalid(label, e))?;
    surface_from_bytes(bytes, format, choice).map_err(at)
}

/// An instrument's metadata: keys and values in the file's order.
pub type Metadata = Vec<(String, String)>;

/// The instrument's metadata a file keeps beside its data (a Nanoscope or
/// Nanosurf header, an MI header, an Asylum wave note), as key and value in
/// the file's order; `None` for formats whose metadata asperity does not
/// read (their sizes, units and missing points are in the height field).
///
/// # Errors
/// [`IoError`] naming the file.
pub fn instrument_metadata(path: &Path) -> Result<Option<Metadata>, IoError> {
    let f = Format::of_file(path)?;
    let Some(read) = f.registration().codec.and_then(|c| c.metadata) else {
        return Ok(None);
    };
    let bytes = read_bytes(path)?;
    read(&bytes)
        .map(|m| (!m.is_empty()).then_some(m))
        .map_err(|e| e.at(path, f.info().name))
}

/// The channels of a multi-channel file (Nanoscope images, Sensofar
/// layers); `None` for a format with one channel.
///
/// # Errors
/// [`IoError`] naming the file.
pub fn channels(path: &Path) -> Result<Option<Vec<ChannelInfo>>, IoError> {
    let f = Format::of_file(path)?;
    let Some(list) = f.registration().codec.and_then(|c| c.channels) else {
        return Ok(None);
    };
    let bytes = read_bytes(path)?;
    list(&bytes)
        .map(Some)
        .map_err(|e| e.at(path, f.info().name))
}

/// Reads whatever `path` holds, deciding by extension and content: PLY with faces,
/// OBJ and STL give meshes; PLY without faces and XYZ give point sets; `.npy`
/// gives a point set for shape `(N, 3)` with N ≠ 3 and a height field for other
/// 2-D shapes; image and grid formats give height fields.
///
/// # Errors
/// [`IoError`] naming the file and what is wrong.
pub fn read(path: &Path) -> Result<Surface, IoError> {
    read_channel(path, None)
}

/// [`read`] of the channel `choice` names (see [`channel`]).
///
/// # Errors
/// As [`read`]; a channel the file does not have, named with the file's
/// channels.
pub fn read_channel(path: &Path, choice: Option<&Channel>) -> Result<Surface, IoError> {
    let f = Format::of_file(path)?;
    if f == Format::Glb {
        return Err(IoError::WrongKind {
            path: path.to_path_buf(),
            format: "glTF (write-only in asperity)",
            kind: "data to read",
        });
    }
    let bytes = read_bytes(path)?;
    surface_from_bytes(&bytes, f, choice).map_err(|e| e.at(path, f.info().name))
}

/// The decoding half of [`read`].
fn surface_from_bytes(bytes: &[u8], f: Format, choice: Option<&Channel>) -> FResult<Surface> {
    if !f.has_channels() {
        channel::only(choice)?;
    }
    match f.registration().read {
        Some(read) => read(bytes),
        None if f == Format::Glb => error::malformed("glTF is write-only in asperity"),
        None => read_height_bytes(bytes, f, choice).map(Surface::Height),
    }
}

/// A `.npy` file: a point set for shape `(N, 3)` with N ≠ 3, else a height
/// field.
fn npy_surface(bytes: &[u8]) -> FResult<Surface> {
    let a = npy::read(bytes)?;
    if a.shape.len() == 2 && a.shape[1] == 3 && a.shape[0] != 3 {
        Ok(Surface::Points(npy_points(a)?))
    } else {
        Ok(Surface::Height(npy_height(a)?))
    }
}

fn npy_points(a: npy::NpyArray) -> FResult<PointSet> {
    if a.shape.len() != 2 || a.shape[1] != 3 {
        return error::malformed(format!("a point set needs shape (N, 3), got {:?}", a.shape));
    }
    let p = PointSet::new(a.data.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect());
    p.validate()?;
    Ok(p)
}

/// A 2-D array `(ny, nx)` is a height map; a 1-D array `(n,)` a line scan
/// (a profile: `n × 1`).
fn npy_height(a: npy::NpyArray) -> FResult<HeightField> {
    match a.shape[..] {
        [n] => Ok(HeightField::from_vec([n, 1], a.data)?),
        [ny, nx] => Ok(HeightField::from_vec([nx, ny], a.data)?),
        _ => error::malformed(format!(
            "a height field needs a 2-D array (ny, nx) or a 1-D profile (n,), got shape {:?}",
            a.shape
        )),
    }
}

fn read_height_bytes(bytes: &[u8], f: Format, choice: Option<&Channel>) -> FResult<HeightField> {
    let Some(codec) = f.registration().codec else {
        return error::malformed(format!("{} holds no height field", f.info().name));
    };
    let h = (codec.height)(bytes, choice)?;
    // Missing points (NaN) are carried; ±∞ and a field with no measured
    // point are refused.
    h.validate_measured()?;
    Ok(h)
}

/// Reads a height field in any format that holds one. Unmeasured points
/// become NaN heights (missing points, see `asperity_core::HeightField`);
/// infinite heights are an error.
///
/// # Errors
/// [`IoError`].
pub fn read_height(path: &Path) -> Result<HeightField, IoError> {
    let f = Format::of_file(path)?;
    if !f.info().height.can_read() {
        return Err(wrong(path, f, "a height field"));
    }
    let bytes = read_bytes(path)?;
    read_height_bytes(&bytes, f, None).map_err(|e| e.at(path, f.info().name))
}

/// Reads a triangle mesh (`.ply`, `.obj`, `.stl`); polygons are triangulated
/// (fanned where convex, ear-clipped where not: `asperity_core::polygon`).
///
/// # Errors
/// [`IoError`].
pub fn read_mesh(path: &Path) -> Result<TriMesh, IoError> {
    let f = Format::from_path(path)?;
    let bytes = read_bytes(path)?;
    let r = match f {
        Format::Ply => ply::read_mesh(&bytes),
        Format::Obj => obj::read_mesh(&bytes),
        Format::Stl => stl::read_mesh(&bytes),
        _ => return Err(wrong(path, f, "a mesh to read")),
    };
    r.map_err(|e| e.at(path, f.info().name))
}

/// Reads a polygon mesh, faces kept as they are (`.ply`, `.obj`).
///
/// # Errors
/// [`IoError`].
pub fn read_poly_mesh(path: &Path) -> Result<PolyMesh, IoError> {
    let f = Format::from_path(path)?;
    if !matches!(f, Format::Ply | Format::Obj | Format::Stl) {
        return Err(wrong(path, f, "a polygon mesh to read"));
    }
    let bytes = read_bytes(path)?;
    poly_from_bytes(&bytes, f).map_err(|e| e.at(path, f.info().name))
}

/// [`read_poly_mesh`] for bytes in memory, under `budget` (see [`decode`]).
///
/// # Errors
/// As [`decode`]; formats that hold no polygon mesh.
pub fn decode_poly_mesh(
    label: &Path,
    format: Format,
    bytes: &[u8],
    budget: &asperity_core::MemoryBudget,
) -> Result<PolyMesh, IoError> {
    let at = |e: FormatError| e.at(label, format.info().name);
    let needed = estimate_bytes(bytes, format).map_err(at)?;
    budget
        .check(needed, format!("reading {}", label.display()))
        .map_err(|e| IoError::invalid(label, e))?;
    poly_from_bytes(bytes, format).map_err(at)
}

fn poly_from_bytes(bytes: &[u8], f: Format) -> FResult<PolyMesh> {
    match f {
        Format::Ply => ply::read_poly(bytes),
        Format::Obj => obj::read_poly(bytes),
        Format::Stl => stl::read_mesh(bytes).and_then(|m| Ok(PolyMesh::from_trimesh(&m)?)),
        _ => error::malformed(format!("{} holds no polygon mesh", f.info().name)),
    }
}

/// Reads a point set: the points of a point format, or the vertices of a mesh or
/// height-field file.
///
/// # Errors
/// [`IoError`].
pub fn read_points(path: &Path) -> Result<PointSet, IoError> {
    let f = Format::from_path(path)?;
    if f == Format::Npy {
        let bytes = read_bytes(path)?;
        return npy::read(&bytes)
            .and_then(npy_points)
            .map_err(|e| e.at(path, f.info().name));
    }
    Ok(match read(path)? {
        Surface::Points(p) => p,
        Surface::Mesh(m) => PointSet::new(m.positions().to_vec()),
        Surface::Height(h) => h.to_point_set(),
    })
}

/// Reads a list of `x,y` rows (see [`text`]): a curve to drape on a height
/// field, or points to interpolate at.
///
/// # Errors
/// [`IoError`] naming the file and the line.
pub fn read_xy(path: &Path) -> Result<Vec<[f64; 2]>, IoError> {
    decode_xy(path, &read_bytes(path)?)
}

/// [`read_xy`] for bytes in memory; `label` names them in messages (text is
/// never larger parsed than read, so no budget is needed).
///
/// # Errors
/// [`IoError`] naming `label` and the line.
pub fn decode_xy(label: &Path, bytes: &[u8]) -> Result<Vec<[f64; 2]>, IoError> {
    text::read_xy(bytes).map_err(|e| e.at(label, "x,y list"))
}
