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

pub mod al3d;
pub mod atomic;
pub mod bcr;
pub mod decimal;
pub mod di;
mod error;
pub mod exr_io;
pub mod frt;
pub mod glb;
pub mod gsf;
pub mod gwy;
pub mod metadata;
pub mod metropro;
pub mod nc;
pub mod npy;
pub mod obj;
pub mod opd;
pub mod plu;
pub mod ply;
pub mod png_io;
pub mod sdf;
pub mod staging;
pub mod stl;
pub mod sur;
pub mod text;
pub mod tmd;
pub mod up;
mod write;
pub mod wsxm;
pub mod x3p;

use std::path::Path;

use asperity_core::{Diagonal, HeightField, PointSet, PolyMesh, TriMesh};

pub use atomic::write_atomic;
pub use error::IoError;
use error::{FResult, FormatError};
pub use metadata::read_params;
pub use npy::NpyDtype;
pub use ply::PlyEncoding;
pub use staging::{Transaction, create_output_dir, exit_removing_temporaries, stale_temporaries};
pub use up::{UpAxis, reorient};
pub use write::{
    lost_data, write, write_height, write_mesh, write_mesh_with_polylines, write_npy_f64,
    write_npy_u8, write_png, write_png_with, write_points, write_poly_mesh, write_text,
};

/// The file formats asperity knows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Format {
    /// Stanford PLY.
    Ply,
    /// Wavefront OBJ.
    Obj,
    /// STL.
    Stl,
    /// glTF 2.0 binary.
    Glb,
    /// XYZ point text.
    Xyz,
    /// NumPy array.
    Npy,
    /// PNG image.
    Png,
    /// OpenEXR image.
    Exr,
    /// Gwyddion Simple Field.
    Gsf,
    /// Comma-separated grid.
    Csv,
    /// Gwyddion's native format.
    Gwy,
    /// ISO 25178-72 x3p.
    X3p,
    /// ISO 25178-71 surface data file.
    Sdf,
    /// Digital Surf (MountainsMap) surface.
    Sur,
    /// TrueMap surface.
    Tmd,
    /// BCR-STM / BCRF scanning-probe image.
    Bcr,
    /// Zygo MetroPro interferometer data.
    MetroPro,
    /// Alicona Imaging depth image.
    Al3d,
    /// WSxM scanning-probe image.
    Wsxm,
    /// Sensofar confocal/interferometric topography.
    Plu,
    /// Wyko (Bruker Vision) interferometer data.
    Opd,
    /// FRT MicroProf profilometer data.
    Frt,
    /// Bruker / Veeco / Digital Instruments Nanoscope scanning-probe data.
    Di,
    /// NetCDF-3 topographies in SurfaceTopography's layout.
    Nc,
}

/// What a format can do with one kind of data.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Access {
    /// Not supported.
    None,
    /// Read only.
    Read,
    /// Write only.
    Write,
    /// Read and write.
    ReadWrite,
}

impl Access {
    /// Can this be read?
    pub fn can_read(self) -> bool {
        matches!(self, Access::Read | Access::ReadWrite)
    }
    /// Can this be written?
    pub fn can_write(self) -> bool {
        matches!(self, Access::Write | Access::ReadWrite)
    }
}

/// A row of the format table (`asperity formats`).
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct FormatInfo {
    /// The format.
    pub format: Format,
    /// Human name.
    pub name: &'static str,
    /// File extensions, lower case, without dots.
    pub extensions: &'static [&'static str],
    /// Triangle meshes.
    pub mesh: Access,
    /// Point sets.
    pub points: Access,
    /// Height fields.
    pub height: Access,
    /// What to know (precision, conventions).
    pub notes: &'static str,
}

use Access::{None as No, Read as R, ReadWrite as RW, Write as W};

/// Every format, in the order `asperity formats` lists them.
pub const FORMATS: &[FormatInfo] = &[
    FormatInfo {
        format: Format::Ply,
        name: "PLY (binary little-endian or ASCII)",
        extensions: &["ply"],
        mesh: RW,
        points: RW,
        height: No,
        notes: "f64 positions; normals, RGBA colours, UVs (s, t) and named scalars",
    },
    FormatInfo {
        format: Format::Obj,
        name: "Wavefront OBJ",
        extensions: &["obj"],
        mesh: RW,
        points: No,
        height: No,
        notes: "y-up (x, z, -y), read back unchanged; vertex colours (v x y z r g b), UVs, normals; texture as .mtl + .png; no scalars",
    },
    FormatInfo {
        format: Format::Stl,
        name: "STL (binary; ASCII also read)",
        extensions: &["stl"],
        mesh: RW,
        points: No,
        height: No,
        notes: "f32 corners, welded on read; geometry only",
    },
    FormatInfo {
        format: Format::Glb,
        name: "glTF 2.0 binary",
        extensions: &["glb"],
        mesh: W,
        points: No,
        height: No,
        notes: "y-up (x, z, -y); normals, linear COLOR_0, TEXCOORD_0 + embedded PNG texture (padded to powers of two), scalars as _NAME",
    },
    FormatInfo {
        format: Format::Xyz,
        name: "XYZ text",
        extensions: &["xyz", "txt"],
        mesh: No,
        points: RW,
        height: No,
        notes: "x y z per line",
    },
    FormatInfo {
        format: Format::Npy,
        name: "NumPy .npy",
        extensions: &["npy"],
        mesh: No,
        points: RW,
        height: RW,
        notes: "height (ny, nx) <f8 (or <f4), missing points NaN; points (N, 3) <f8; reads any float/int dtype",
    },
    FormatInfo {
        format: Format::Png,
        name: "PNG, 16-bit grayscale",
        extensions: &["png"],
        mesh: No,
        points: No,
        height: RW,
        notes: "height range and spacing in tEXt chunks (asperity's and Gwyddion's Gwy:: keys); Gwyddion's exports read with their Gwy:: keys; PNGs with neither read as [0, 1]; no missing points",
    },
    FormatInfo {
        format: Format::Exr,
        name: "OpenEXR, float32",
        extensions: &["exr"],
        mesh: No,
        points: No,
        height: RW,
        notes: "channel Y; spacing/origin as header attributes; missing points NaN",
    },
    FormatInfo {
        format: Format::Gsf,
        name: "Gwyddion Simple Field",
        extensions: &["gsf"],
        mesh: No,
        points: No,
        height: RW,
        notes: "float32; XReal/XOffset follow Gwyddion's pixel convention; unitless; missing points NaN (Gwyddion masks them)",
    },
    FormatInfo {
        format: Format::Csv,
        name: "CSV grid",
        extensions: &["csv"],
        mesh: No,
        points: No,
        height: RW,
        notes: "one row per line, geometry in a # comment line; missing points NaN",
    },
    FormatInfo {
        format: Format::Gwy,
        name: "Gwyddion native (.gwy)",
        extensions: &["gwy"],
        mesh: No,
        points: No,
        height: RW,
        notes: "GwyContainer with one GwyDataField (the first channel is read); f64; base units (metres) or unitless; missing points as the channel's mask",
    },
    FormatInfo {
        format: Format::X3p,
        name: "ISO 25178-72 x3p",
        extensions: &["x3p"],
        mesh: No,
        points: No,
        height: RW,
        notes: "zip of main.xml + f64 data with MD5 checksums; always metres; surfaces and profiles read (int16/32, f32, f64), not point clouds; missing points NaN (read: NaN or valid.bin)",
    },
    FormatInfo {
        format: Format::Sdf,
        name: "ISO 25178-71 SDF (.sdf)",
        extensions: &["sdf"],
        mesh: No,
        points: No,
        height: RW,
        notes: "text (aISO) and binary (bISO) read, int16/int32/f64; text written, f64 in metres; unmeasured (BAD) points read as missing, a field with missing points not written",
    },
    FormatInfo {
        format: Format::Sur,
        name: "Digital Surf / MountainsMap (.sur)",
        extensions: &["sur"],
        mesh: No,
        points: No,
        height: R,
        notes: "one surface of int16/int32 samples times the header's scale, in the file's units (Å, pm as nm); unmeasured points (zmin − 2) read as missing; series and multi-channel files refused",
    },
    FormatInfo {
        format: Format::Tmd,
        name: "TrueMap (.tmd)",
        extensions: &["tmd"],
        mesh: No,
        points: No,
        height: R,
        notes: "version 2: f32 heights, lengths and offsets in millimetres",
    },
    FormatInfo {
        format: Format::Bcr,
        name: "BCR-STM / BCRF (.bcr, .bcrf)",
        extensions: &["bcr", "bcrf"],
        mesh: No,
        points: No,
        height: R,
        notes: "Latin-1 or UTF-16 header; int16 (× bit2nm) or f32, either byte order; the header's units (nm by default); void points read as missing",
    },
    FormatInfo {
        format: Format::MetroPro,
        name: "Zygo MetroPro (.dat)",
        extensions: &["dat"],
        mesh: No,
        points: No,
        height: R,
        notes: "header formats 1-3; phase × S × O × λ / R in metres, pixels from the lateral resolution; invalid phases read as missing",
    },
    FormatInfo {
        format: Format::Al3d,
        name: "Alicona Imaging (.al3d)",
        extensions: &["al3d"],
        mesh: No,
        points: No,
        height: R,
        notes: "the depth image: f32 in metres, pixel sizes from the tags; invalid points read as missing",
    },
    FormatInfo {
        format: Format::Wsxm,
        name: "WSxM image (.stp, .top, .tom, .cur)",
        extensions: &["stp", "top", "tom", "cur"],
        mesh: No,
        points: No,
        height: R,
        notes: "int16 scaled to the Z amplitude, or f32/f64 heights; sizes from the X/Y amplitudes; stored from the last sample; NaN read as missing",
    },
    FormatInfo {
        format: Format::Plu,
        name: "Sensofar (.plu, .apx)",
        extensions: &["plu", "apx"],
        mesh: No,
        points: No,
        height: R,
        notes: "the first layer's f32 heights in µm, pixel sizes from the calibration; undefined points (1000001) read as missing; profiles refused",
    },
    FormatInfo {
        format: Format::Nc,
        name: "NetCDF (.nc, SurfaceTopography's layout)",
        extensions: &["nc"],
        mesh: No,
        points: No,
        height: R,
        notes: "NetCDF-3 (classic, 64-bit offsets): the variable heights(x, y) or heights(x), sizes from the length of x and y, unit attribute; a mask variable and NaN read as missing",
    },
    FormatInfo {
        format: Format::Di,
        name: "Bruker Nanoscope (.spm, .di, .001)",
        extensions: &["di", "spm", "001", "002", "003", "004", "005"],
        mesh: No,
        points: No,
        height: R,
        notes: "version 4.3 and later: the first channel's int16/int32 counts × its Z scale × the soft scale (nm/V), from the last line; sizes from Scan Size; channels that are no height and force curves refused",
    },
    FormatInfo {
        format: Format::Frt,
        name: "FRT MicroProf (.frt)",
        extensions: &["frt"],
        mesh: No,
        points: No,
        height: R,
        notes: "versions 1.00 and 1.01: the topography's 16/32-bit counts × the height scale in metres, sizes in metres; a count of 1 read as missing",
    },
    FormatInfo {
        format: Format::Opd,
        name: "Wyko OPD (.opd)",
        extensions: &["opd"],
        mesh: No,
        points: No,
        height: R,
        notes: "the first data block: int16 or f32 × wavelength / mult in nm, pixel size and aspect in mm; values at the type's limit read as missing",
    },
];

impl Format {
    /// The format of the file at `path`: by its extension, or, where the
    /// extension names none (instruments' own or none at all), by the magic
    /// its content starts with (SDF, Digital Surf, npy, PNG, EXR, GSF, .gwy,
    /// PLY, TrueMap, BCR, MetroPro, Alicona, WSxM).
    ///
    /// # Errors
    /// [`IoError::UnknownFormat`] when neither tells (or the file cannot be
    /// opened to look).
    pub fn of_file(path: &Path) -> Result<Format, IoError> {
        let by_name = Format::from_path(path);
        if by_name.is_ok() {
            return by_name;
        }
        let mut head = [0u8; 64];
        // A file that cannot be opened keeps the message about its name.
        let n = std::fs::File::open(path)
            .and_then(|mut f| std::io::Read::read(&mut f, &mut head))
            .unwrap_or(0);
        Format::from_content(&head[..n]).ok_or_else(|| by_name.unwrap_err())
    }

    /// The format whose magic `bytes` start with, if one does.
    pub fn from_content(bytes: &[u8]) -> Option<Format> {
        const MAGICS: [(&[u8], Format); 14] = [
            (b"CDF\x01", Format::Nc),
            (b"CDF\x02", Format::Nc),
            (frt::MAGIC, Format::Frt),
            (wsxm::MAGIC, Format::Wsxm),
            (al3d::MAGIC, Format::Al3d),
            (tmd::MAGIC, Format::Tmd),
            (b"aISO-1.0", Format::Sdf),
            (b"bISO-1.0", Format::Sdf),
            (b"DIGITAL SURF", Format::Sur),
            (b"\x93NUMPY", Format::Npy),
            (b"\x89PNG\r\n\x1a\n", Format::Png),
            (b"\x76\x2f\x31\x01", Format::Exr),
            (b"Gwyddion Simple Field", Format::Gsf),
            (b"GWYP", Format::Gwy),
        ];
        let ply = bytes.starts_with(b"ply\n") || bytes.starts_with(b"ply\r\n");
        if bcr::sniff(bytes) {
            return Some(Format::Bcr);
        }
        if di::sniff(bytes) {
            return Some(Format::Di);
        }
        if bytes.get(2..11) == Some(b"Directory".as_slice()) {
            return Some(Format::Opd);
        }
        if metropro::MAGICS.iter().any(|m| bytes.starts_with(m)) {
            return Some(Format::MetroPro);
        }
        MAGICS
            .iter()
            .find(|(m, _)| bytes.starts_with(m))
            .map(|&(_, f)| f)
            .or(ply.then_some(Format::Ply))
    }

    /// The format named by `path`'s extension (case-insensitive).
    ///
    /// # Errors
    /// [`IoError::UnknownFormat`].
    pub fn from_path(path: &Path) -> Result<Format, IoError> {
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        FORMATS
            .iter()
            .find(|f| f.extensions.contains(&ext.as_str()))
            .map(|f| f.format)
            .ok_or_else(|| IoError::UnknownFormat {
                path: path.to_path_buf(),
                ext,
            })
    }

    /// This format's row of [`FORMATS`].
    pub fn info(self) -> &'static FormatInfo {
        FORMATS
            .iter()
            .find(|f| f.format == self)
            .expect("every format has a row")
    }
}

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
}

impl Default for WriteOptions {
    fn default() -> Self {
        Self {
            ply_encoding: PlyEncoding::BinaryLittleEndian,
            npy_dtype: NpyDtype::Float64,
            diagonal: Diagonal::Forward,
            title: "asperity surface".into(),
            up: None,
            params: None,
        }
    }
}

fn read_bytes(path: &Path) -> Result<Vec<u8>, IoError> {
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
/// for compressed images (PNG, OpenEXR), from the dimensions in their header —
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
    let pixels = match format {
        Format::Png => Some(png_io::header_pixels(open()?)),
        Format::Exr => Some(exr_io::header_pixels(open()?)),
        Format::X3p => Some(x3p::header_pixels(&read_bytes(path)?)),
        _ => None,
    };
    estimate_from(size, pixels, format).map_err(|e| e.at(path, format.info().name))
}

/// [`read_estimate`] for a file already in memory.
fn estimate_bytes(bytes: &[u8], format: Format) -> FResult<u64> {
    let cursor = || std::io::Cursor::new(bytes);
    let pixels = match format {
        Format::Png => Some(png_io::header_pixels(cursor())),
        Format::Exr => Some(exr_io::header_pixels(cursor())),
        Format::X3p => Some(x3p::header_pixels(bytes)),
        _ => None,
    };
    estimate_from(bytes.len() as u64, pixels, format)
}

/// The larger of the size rule and the decoded pixels a header declares.
fn estimate_from(size: u64, pixels: Option<FResult<u128>>, _format: Format) -> FResult<u64> {
    let by_size = size.saturating_mul(READ_MEMORY_FACTOR);
    let pixels = pixels.transpose()?;
    // Decoded samples (up to four 16-bit or 32-bit channels) plus the f64 grid.
    let decoded = pixels.map_or(0, |n: u128| {
        u64::try_from(n.saturating_mul(16 + 8)).unwrap_or(u64::MAX)
    });
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
    let at = |e: FormatError| e.at(label, format.info().name);
    let needed = estimate_bytes(bytes, format).map_err(at)?;
    budget
        .check(needed, format!("reading {}", label.display()))
        .map_err(|e| IoError::invalid(label, e))?;
    surface_from_bytes(bytes, format).map_err(at)
}

/// Reads whatever `path` holds, deciding by extension and content: PLY with faces,
/// OBJ and STL give meshes; PLY without faces and XYZ give point sets; `.npy`
/// gives a point set for shape `(N, 3)` with N ≠ 3 and a height field for other
/// 2-D shapes; image and grid formats give height fields.
///
/// # Errors
/// [`IoError`] naming the file and what is wrong.
pub fn read(path: &Path) -> Result<Surface, IoError> {
    let f = Format::of_file(path)?;
    if f == Format::Glb {
        return Err(IoError::WrongKind {
            path: path.to_path_buf(),
            format: "glTF (write-only in asperity)",
            kind: "data to read",
        });
    }
    let bytes = read_bytes(path)?;
    surface_from_bytes(&bytes, f).map_err(|e| e.at(path, f.info().name))
}

/// The decoding half of [`read`].
fn surface_from_bytes(bytes: &[u8], f: Format) -> FResult<Surface> {
    Ok(match f {
        Format::Ply => {
            let c = ply::parse(bytes)?;
            if c.has_face_element && !c.faces.is_empty() {
                Surface::Mesh(ply::read_mesh(bytes)?)
            } else {
                Surface::Points(ply::read_points(bytes)?)
            }
        }
        Format::Obj => Surface::Mesh(obj::read_mesh(bytes)?),
        Format::Stl => Surface::Mesh(stl::read_mesh(bytes)?),
        Format::Glb => return error::malformed("glTF is write-only in asperity"),
        Format::Xyz => Surface::Points(text::read_xyz(bytes)?),
        Format::Npy => {
            let a = npy::read(bytes)?;
            if a.shape.len() == 2 && a.shape[1] == 3 && a.shape[0] != 3 {
                Surface::Points(npy_points(a)?)
            } else {
                Surface::Height(npy_height(a)?)
            }
        }
        Format::Png
        | Format::Exr
        | Format::Gsf
        | Format::Csv
        | Format::Gwy
        | Format::X3p
        | Format::Sdf
        | Format::Sur
        | Format::Tmd
        | Format::Bcr
        | Format::MetroPro
        | Format::Al3d
        | Format::Wsxm
        | Format::Plu
        | Format::Opd
        | Format::Frt
        | Format::Di
        | Format::Nc => Surface::Height(read_height_bytes(bytes, f)?),
    })
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

fn read_height_bytes(bytes: &[u8], f: Format) -> FResult<HeightField> {
    let h = match f {
        Format::Npy => npy_height(npy::read(bytes)?)?,
        Format::Png => png_io::read_height(bytes)?,
        Format::Exr => exr_io::read_height(bytes)?,
        Format::Gsf => gsf::read_height(bytes)?,
        Format::Csv => text::read_csv(bytes)?,
        Format::Gwy => gwy::read_height(bytes)?,
        Format::X3p => x3p::read_height(bytes)?,
        Format::Sdf => sdf::read_height(bytes)?,
        Format::Sur => sur::read_height(bytes)?,
        Format::Tmd => tmd::read_height(bytes)?,
        Format::Bcr => bcr::read_height(bytes)?,
        Format::MetroPro => metropro::read_height(bytes)?,
        Format::Al3d => al3d::read_height(bytes)?,
        Format::Wsxm => wsxm::read_height(bytes)?,
        Format::Plu => plu::read_height(bytes)?,
        Format::Nc => nc::read_height(bytes)?,
        Format::Di => di::read_height(bytes)?,
        Format::Frt => frt::read_height(bytes)?,
        Format::Opd => opd::read_height(bytes)?,
        _ => unreachable!("caller checks the format"),
    };
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
    read_height_bytes(&bytes, f).map_err(|e| e.at(path, f.info().name))
}

/// Reads a triangle mesh (`.ply`, `.obj`, `.stl`); polygons are fan-triangulated.
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
