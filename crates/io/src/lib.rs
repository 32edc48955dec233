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

pub mod atomic;
mod error;
pub mod exr_io;
pub mod glb;
pub mod gsf;
pub mod gwy;
pub mod npy;
pub mod obj;
pub mod ply;
pub mod png_io;
pub mod staging;
pub mod stl;
pub mod text;
pub mod up;
pub mod x3p;

use std::path::Path;

use asperity_core::{CoreError, Diagonal, HeightField, PointSet, PolyMesh, RgbaImage, TriMesh};

pub use atomic::write_atomic;
pub use error::IoError;
use error::{FResult, FormatError};
pub use npy::NpyDtype;
pub use ply::PlyEncoding;
pub use staging::{Transaction, create_output_dir, exit_removing_temporaries, stale_temporaries};
pub use up::{UpAxis, reorient};

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

use Access::{None as No, ReadWrite as RW, Write as W};

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
        notes: "height (ny, nx) <f8 (or <f4); points (N, 3) <f8; reads any float/int dtype",
    },
    FormatInfo {
        format: Format::Png,
        name: "PNG, 16-bit grayscale",
        extensions: &["png"],
        mesh: No,
        points: No,
        height: RW,
        notes: "height range and spacing in tEXt chunks (asperity's and Gwyddion's Gwy:: keys); 8-bit/RGB PNGs read as [0, 1]",
    },
    FormatInfo {
        format: Format::Exr,
        name: "OpenEXR, float32",
        extensions: &["exr"],
        mesh: No,
        points: No,
        height: RW,
        notes: "channel Y; spacing/origin as header attributes",
    },
    FormatInfo {
        format: Format::Gsf,
        name: "Gwyddion Simple Field",
        extensions: &["gsf"],
        mesh: No,
        points: No,
        height: RW,
        notes: "float32; XReal/XOffset follow Gwyddion's pixel convention; unitless",
    },
    FormatInfo {
        format: Format::Csv,
        name: "CSV grid",
        extensions: &["csv"],
        mesh: No,
        points: No,
        height: RW,
        notes: "one row per line, geometry in a # comment line",
    },
    FormatInfo {
        format: Format::Gwy,
        name: "Gwyddion native (.gwy)",
        extensions: &["gwy"],
        mesh: No,
        points: No,
        height: RW,
        notes: "GwyContainer with one GwyDataField (the first channel is read); f64; base units (metres) or unitless",
    },
    FormatInfo {
        format: Format::X3p,
        name: "ISO 25178-72 x3p",
        extensions: &["x3p"],
        mesh: No,
        points: No,
        height: RW,
        notes: "zip of main.xml + f64 data with MD5 checksums; always metres; surfaces and profiles read (int16/32, f32, f64), not point clouds",
    },
];

impl Format {
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
}

impl Default for WriteOptions {
    fn default() -> Self {
        Self {
            ply_encoding: PlyEncoding::BinaryLittleEndian,
            npy_dtype: NpyDtype::Float64,
            diagonal: Diagonal::Forward,
            title: "asperity surface".into(),
            up: None,
        }
    }
}

fn read_bytes(path: &Path) -> Result<Vec<u8>, IoError> {
    std::fs::read(path).map_err(|e| IoError::os(path, e))
}

fn wrong(path: &Path, f: Format, kind: &'static str) -> IoError {
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
    let format = Format::from_path(path)?;
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
/// [`CoreError::MemoryLimit`] when the estimate exceeds `budget`.
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
    let f = Format::from_path(path)?;
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
        Format::Png | Format::Exr | Format::Gsf | Format::Csv | Format::Gwy | Format::X3p => {
            Surface::Height(read_height_bytes(bytes, f)?)
        }
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
        _ => unreachable!("caller checks the format"),
    };
    h.validate()?;
    Ok(h)
}

/// Reads a height field (`.npy`, `.png`, `.exr`, `.gsf`, `.csv`); NaN or infinite
/// heights are an error.
///
/// # Errors
/// [`IoError`].
pub fn read_height(path: &Path) -> Result<HeightField, IoError> {
    let f = Format::from_path(path)?;
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

/// Writes the polygons of `poly` (quads, n-gons, kept as they are) with the
/// per-vertex data (normals, colours, scalars) of `attrs`, which must have the
/// same vertices — typically `poly.triangulate()` with attributes added. PLY and
/// OBJ hold polygons; other mesh formats get `attrs`' triangles.
///
/// # Errors
/// [`IoError`]; [`IoError::Invalid`] when the vertex counts differ.
pub fn write_poly_mesh(
    path: &Path,
    poly: &PolyMesh,
    attrs: &TriMesh,
    opts: &WriteOptions,
) -> Result<(), IoError> {
    if poly.n_vertices() != attrs.n_vertices() {
        return Err(IoError::invalid(
            path,
            CoreError::LengthMismatch {
                what: "vertex attributes".into(),
                got: attrs.n_vertices(),
                expected: poly.n_vertices(),
            },
        ));
    }
    let f = Format::from_path(path)?;
    if f == Format::Ply && poly.faces().any(|face| face.len() > 255) {
        return Err(IoError::invalid(
            path,
            CoreError::InvalidParameter {
                name: "faces",
                reason: "PLY face lists hold at most 255 corners; write OBJ".into(),
            },
        ));
    }
    let os = |e| IoError::os(path, e);
    let up = up::written_up(f, opts.up);
    match f {
        Format::Ply if poly.n_faces() > 0 => write_atomic(path, |w| {
            ply::write_poly(
                w,
                &up::mesh_in_file_frame(attrs, up),
                poly.face_offsets(),
                poly.face_vertices(),
                opts.ply_encoding,
            )
            .map_err(os)
        }),
        Format::Obj if poly.n_faces() > 0 && attrs.texture().is_none() => write_atomic(path, |w| {
            obj::write_faces(
                w,
                &up::mesh_in_file_frame(attrs, up),
                poly.face_offsets(),
                poly.face_vertices(),
                None,
                up == UpAxis::Y,
            )
            .map_err(os)
        }),
        _ => write_mesh(path, attrs, opts),
    }
}

/// Writes a triangle mesh; the format follows the extension. A textured mesh
/// written as OBJ also gets `NAME.mtl` and `NAME_texture.png` beside it.
///
/// # Errors
/// [`IoError`]; [`IoError::WrongKind`] for formats that hold no meshes;
/// [`IoError::Invalid`] for a mesh without triangles (glTF cannot even express one).
pub fn write_mesh(path: &Path, mesh: &TriMesh, opts: &WriteOptions) -> Result<(), IoError> {
    let f = Format::from_path(path)?;
    if mesh.n_faces() == 0 {
        return Err(IoError::invalid(
            path,
            CoreError::Empty("the mesh (no triangles)"),
        ));
    }
    let os = |e| IoError::os(path, e);
    let up = up::written_up(f, opts.up);
    // (glTF's writer turns the mesh to y-up itself, with f32 positions)
    let in_file = || up::mesh_in_file_frame(mesh, up);
    match f {
        Format::Ply => write_atomic(path, |w| {
            ply::write_mesh(w, &in_file(), opts.ply_encoding).map_err(os)
        }),
        Format::Stl => write_atomic(path, |w| stl::write_mesh(w, &in_file()).map_err(os)),
        Format::Glb => write_atomic(path, |w| glb::write_mesh(w, mesh).map_err(os)),
        Format::Obj => {
            let mtl = match mesh.texture().filter(|_| mesh.uvs().is_some()) {
                Some(tex) => Some(write_obj_sidecars(path, tex)?),
                None => None,
            };
            write_atomic(path, |w| {
                obj::write_mesh(w, &in_file(), mtl.as_deref(), up == UpAxis::Y).map_err(os)
            })
        }
        Format::Xyz | Format::Npy => {
            write_points(path, &PointSet::new(mesh.positions().to_vec()), opts)
        }
        _ => Err(wrong(path, f, "a mesh")),
    }
}

fn write_obj_sidecars(path: &Path, tex: &RgbaImage) -> Result<String, IoError> {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "mesh".into());
    let (mtl_name, png_name) = (format!("{stem}.mtl"), format!("{stem}_texture.png"));
    let png_path = path.with_file_name(&png_name);
    let mtl_path = path.with_file_name(&mtl_name);
    write_atomic(&png_path, |w| {
        png_io::write_rgba(w, tex).map_err(|e| IoError::os(&png_path, e))
    })?;
    write_atomic(&mtl_path, |w| {
        obj::write_mtl(w, &png_name).map_err(|e| IoError::os(&mtl_path, e))
    })?;
    Ok(mtl_name)
}

/// Writes a point set (`.ply`, `.xyz`, `.npy`).
///
/// # Errors
/// [`IoError`]; [`IoError::Invalid`] for an empty set or non-finite coordinates.
pub fn write_points(path: &Path, points: &PointSet, opts: &WriteOptions) -> Result<(), IoError> {
    let f = Format::from_path(path)?;
    if points.is_empty() {
        return Err(IoError::invalid(path, CoreError::Empty("the point set")));
    }
    points.validate().map_err(|e| IoError::invalid(path, e))?;
    let os = |e| IoError::os(path, e);
    let points = &*up::points_in_file_frame(points, up::written_up(f, opts.up));
    match f {
        Format::Ply => write_atomic(path, |w| {
            ply::write_points(w, points, opts.ply_encoding).map_err(os)
        }),
        Format::Xyz => write_atomic(path, |w| text::write_xyz(w, points).map_err(os)),
        Format::Npy => {
            let flat: Vec<f64> = points.positions().iter().flatten().copied().collect();
            write_atomic(path, |w| {
                npy::write(w, &[points.len(), 3], &flat, NpyDtype::Float64).map_err(os)
            })
        }
        _ => Err(wrong(path, f, "a point set")),
    }
}

/// Writes a height field; mesh formats get its triangulation, point formats its samples.
///
/// # Errors
/// [`IoError`]; [`IoError::Invalid`] for NaN or infinite heights.
pub fn write_height(path: &Path, h: &HeightField, opts: &WriteOptions) -> Result<(), IoError> {
    let f = Format::from_path(path)?;
    h.validate().map_err(|e| IoError::invalid(path, e))?;
    let os = |e| IoError::os(path, e);
    match f {
        Format::Npy => write_atomic(path, |w| {
            npy::write(w, &[h.ny(), h.nx()], h.data(), opts.npy_dtype).map_err(os)
        }),
        Format::Png => write_atomic(path, |w| {
            png_io::write_height(w, h, &opts.title).map_err(os)
        }),
        Format::Exr => write_atomic(path, |w| exr_io::write_height(w, h).map_err(os)),
        Format::Gsf => write_atomic(path, |w| gsf::write_height(w, h, &opts.title).map_err(os)),
        Format::Csv => write_atomic(path, |w| text::write_csv(w, h).map_err(os)),
        Format::Gwy => write_atomic(path, |w| gwy::write_height(w, h, &opts.title).map_err(os)),
        Format::X3p => write_atomic(path, |w| x3p::write_height(w, h).map_err(os)),
        Format::Ply | Format::Obj | Format::Stl | Format::Glb => {
            let mesh = h
                .to_trimesh(opts.diagonal)
                .map_err(|e| IoError::invalid(path, e))?;
            let mesh = mesh
                .with_scalar("height", h.data().to_vec())
                .map_err(|e| IoError::invalid(path, e))?;
            write_mesh(path, &mesh, opts)
        }
        Format::Xyz => write_points(path, &h.to_point_set(), opts),
    }
}

/// Writes text (HTML, JSON, SVG…) atomically.
///
/// # Errors
/// [`IoError::Os`].
pub fn write_text(path: &Path, text: &str) -> Result<(), IoError> {
    write_atomic(path, |w| {
        std::io::Write::write_all(w, text.as_bytes()).map_err(|e| IoError::os(path, e))
    })
}

/// Writes an 8-bit RGBA picture (a render, a colour map, a texture) as PNG.
///
/// # Errors
/// [`IoError::Os`].
pub fn write_png(path: &Path, img: &RgbaImage) -> Result<(), IoError> {
    write_atomic(path, |w| {
        png_io::write_rgba(w, img).map_err(|e| IoError::os(path, e))
    })
}

/// `Ok` when `len` values fill `shape` exactly.
fn check_shape(path: &Path, shape: &[usize], len: usize) -> Result<(), IoError> {
    let n: usize = shape.iter().product();
    if n != len {
        let source = CoreError::GridSize {
            dims: shape.to_vec(),
            expected: n,
            got: len,
        };
        return Err(IoError::invalid(path, source));
    }
    Ok(())
}

/// Writes a `uint8` array of `shape` (C order) as `.npy`, e.g. a CA evolution
/// `(T+1, ny, nx)`.
///
/// # Errors
/// [`IoError::Os`]; [`IoError::Invalid`] if `data` does not fill `shape`.
pub fn write_npy_u8(path: &Path, shape: &[usize], data: &[u8]) -> Result<(), IoError> {
    check_shape(path, shape, data.len())?;
    write_atomic(path, |w| {
        npy::write_u8(w, shape, data).map_err(|e| IoError::os(path, e))
    })
}

/// Writes a C-order float64 `.npy` array of any `shape` (e.g. a 1-D profile),
/// atomically.
///
/// # Errors
/// [`IoError::Invalid`] when `shape` does not match the data; I/O errors.
pub fn write_npy_f64(path: &Path, shape: &[usize], data: &[f64]) -> Result<(), IoError> {
    check_shape(path, shape, data.len())?;
    write_atomic(path, |w| {
        npy::write(w, shape, data, npy::NpyDtype::Float64).map_err(|e| IoError::os(path, e))
    })
}

/// Writes a mesh with polylines drawn on it: OBJ `l` elements or a PLY `edge`
/// element (MeshLab and Blender read both). The polyline points are appended
/// to the vertices (with zero/default attributes) and referenced by the lines.
///
/// # Errors
/// [`IoError::WrongKind`] for formats other than OBJ and PLY; as [`write_mesh`].
pub fn write_mesh_with_polylines(
    path: &Path,
    mesh: &TriMesh,
    lines: &[Vec<[f64; 3]>],
    opts: &WriteOptions,
) -> Result<(), IoError> {
    let f = Format::from_path(path)?;
    if !matches!(f, Format::Obj | Format::Ply) {
        return Err(wrong(path, f, "polylines (use .obj or .ply)"));
    }
    let invalid = |e| IoError::invalid(path, e);
    let extra: usize = lines.iter().map(Vec::len).sum();
    let mut positions = mesh.positions().to_vec();
    let mut edges = Vec::new();
    for l in lines {
        let start = positions.len() as u32;
        positions.extend_from_slice(l);
        edges.extend((1..l.len() as u32).map(|k| [start + k - 1, start + k]));
    }
    let mut m = TriMesh::new(positions, mesh.triangles().to_vec()).map_err(invalid)?;
    if let Some(n) = mesh.normals() {
        m = m
            .with_normals(
                n.iter()
                    .copied()
                    .chain(std::iter::repeat_n([0.0, 0.0, 1.0], extra))
                    .collect(),
            )
            .map_err(invalid)?;
    }
    if let Some(c) = mesh.colors() {
        m = m
            .with_colors(
                c.iter()
                    .copied()
                    .chain(std::iter::repeat_n([0, 0, 0, 255], extra))
                    .collect(),
            )
            .map_err(invalid)?;
    }
    if let Some(uv) = mesh.uvs() {
        m = m
            .with_uvs(
                uv.iter()
                    .copied()
                    .chain(std::iter::repeat_n([0.0, 0.0], extra))
                    .collect(),
            )
            .map_err(invalid)?;
    }
    for a in mesh.scalars() {
        m = m
            .with_scalar(
                &a.name,
                a.values
                    .iter()
                    .copied()
                    .chain(std::iter::repeat_n(0.0, extra))
                    .collect(),
            )
            .map_err(invalid)?;
    }
    let os = |e| IoError::os(path, e);
    let up = up::written_up(f, opts.up);
    let m = up::mesh_in_file_frame(&m, up);
    match f {
        Format::Ply => write_atomic(path, |w| {
            ply::write_mesh_edges(w, &m, &edges, opts.ply_encoding).map_err(os)
        }),
        _ => write_atomic(path, |w| {
            obj::write_mesh(w, &m, None, up == UpAxis::Y)
                .and_then(|()| obj::write_lines(w, lines, mesh.n_vertices()))
                .map_err(os)
        }),
    }
}

/// Writes any [`Surface`].
///
/// # Errors
/// As the specific writers.
pub fn write(path: &Path, s: &Surface, opts: &WriteOptions) -> Result<(), IoError> {
    match s {
        Surface::Mesh(m) => write_mesh(path, m, opts),
        Surface::Points(p) => write_points(path, p, opts),
        Surface::Height(h) => write_height(path, h, opts),
    }
}

/// What writing `s` to `format` loses (attributes the format has no place for).
pub fn lost_data(s: &Surface, format: Format) -> Vec<String> {
    let mut lost = Vec::new();
    if let Surface::Mesh(m) = s {
        let no_scalars = matches!(format, Format::Obj | Format::Stl);
        if no_scalars {
            lost.extend(m.scalars().iter().map(|a| format!("scalar '{}'", a.name)));
        }
        if format == Format::Stl {
            if m.colors().is_some() {
                lost.push("vertex colours".into());
            }
            if m.uvs().is_some() {
                lost.push("UVs".into());
            }
        }
        if m.texture().is_some() && matches!(format, Format::Ply | Format::Stl) {
            lost.push("texture image".into());
        }
        if matches!(format, Format::Xyz | Format::Npy) {
            lost.push("faces".into());
        }
    }
    if let Surface::Height(h) = s {
        if !h.units().is_none() && format == Format::Npy {
            lost.push("units (npy has no metadata)".into());
        }
        if matches!(format, Format::Exr | Format::Gsf) {
            lost.push("f64 precision (stored as f32)".into());
        }
        if format == Format::Png {
            lost.push("precision below (max−min)/65535 (16-bit quantisation)".into());
        }
        if format == Format::Npy {
            lost.push("spacing and origin (npy has no metadata)".into());
        }
        if format == Format::X3p && h.units().is_none() {
            lost.push(
                "unitlessness (x3p lengths are metres: the numbers are written as metres)".into(),
            );
        }
    }
    lost
}
