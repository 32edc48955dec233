//! The formats asperity reads and writes: what each holds, its extensions,
//! and how a file's format is told (by extension, else by its first bytes).

use std::path::Path;

use crate::IoError;
use crate::{
    al3d, asc, bcr, di, frt, h5, mat, mdt, metropro, mi, mnt, nid, nms, oir, opdx, os3d, park, tmd,
    vk, wsxm, xz, zmg, zon,
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
    /// Nanosurf easyScan scanning-probe data.
    Nid,
    /// Molecular Imaging / Agilent PicoView images.
    Mi,
    /// Igor Pro binary waves (Asylum Research AFMs).
    Ibw,
    /// Park Systems AFM TIFF.
    Park,
    /// `X;Y;valid` line scans (`.hfm`).
    Hfm,
    /// Bruker Dektak profilometer CSV exports (told from a CSV grid by content).
    Dektak,
    /// Line scans as CSV with column titles (`x,z` or `index,x,z`; told
    /// from a CSV grid by content).
    CsvLineScan,
    /// Bruker Dektak Vision64 data.
    Opdx,
    /// NanoFocus µsurf confocal microscope data.
    Nms,
    /// MATLAB workspace files (version 5 and 7.3).
    Mat,
    /// NumPy archives of arrays.
    Npz,
    /// NASA SRTM elevation tiles.
    Hgt,
    /// Keyence VK confocal microscope data.
    Vk,
    /// NT-MDT scanning-probe data.
    Mdt,
    /// Digital Metrology OmniSurf3D data.
    Os3d,
    /// KLA Zeta optical profiler data.
    Zmg,
    /// Sensofar PLUX archives.
    Plux,
    /// Keyence ZON containers.
    Zon,
    /// Olympus LEXT confocal microscope data.
    Lext,
    /// JPK Instruments AFM image scans.
    Jpk,
    /// Mahr MarWin profile archives.
    Qep,
    /// SIOS nanomeasuring machine scans, zipped.
    Nmm,
    /// Digital Surf MountainsMap documents.
    Mnt,
    /// Height data as plain text (a matrix, Gwyddion's text export, profiles).
    Asc,
    /// Mitutoyo SurfTest Excel exports (profiles).
    Mitutoyo,
    /// HDF5 files (every 2-D numeric dataset a channel).
    H5,
    /// Zygo Mx `.datx` files (HDF5 in Zygo's layout).
    Datx,
    /// Olympus laser-scanning microscope files.
    Oir,
    /// Packed Olympus files (a zip of `.oir`).
    Poir,
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

mod table;

pub use table::FORMATS;

/// The first 64 KiB of a text file (enough for a header and data lines).
fn text_head(path: &Path) -> Vec<u8> {
    let mut head = Vec::new();
    let _ = std::fs::File::open(path)
        .and_then(|f| std::io::Read::read_to_end(&mut std::io::Read::take(f, 1 << 16), &mut head));
    head
}

impl Format {
    /// The format of the file at `path`: by its extension, or, where the
    /// extension names none (instruments' own or none at all), by the magic
    /// its content starts with (SDF, Digital Surf, npy, PNG, EXR, GSF, .gwy,
    /// PLY, TrueMap, BCR, MetroPro, Alicona, WSxM, the instruments' formats
    /// with a magic, and OLE compound files as Mountains documents).
    ///
    /// # Errors
    /// [`IoError::UnknownFormat`] when neither tells (or the file cannot be
    /// opened to look).
    pub fn of_file(path: &Path) -> Result<Format, IoError> {
        let by_name = Format::from_path(path);
        let mut head = [0u8; 64];
        let mut head = || {
            // A file that cannot be opened keeps the message about its name.
            let n = std::fs::File::open(path)
                .and_then(|mut f| std::io::Read::read(&mut f, &mut head))
                .unwrap_or(0);
            head[..n].to_vec()
        };
        let is_txt = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("txt"));
        match by_name {
            // A Dektak export is a .csv of its own layout.
            Ok(Format::Csv) if xz::is_dektak(&head()) => Ok(Format::Dektak),
            // A line scan exported with column titles (a CSV grid has none).
            Ok(Format::Csv) if xz::is_titled_csv(&text_head(path)) => Ok(Format::CsvLineScan),
            // A .txt of numbers: heights (a matrix, a profile, Gwyddion's
            // export, gridded `x y z`) or, off a grid, `x y z` points.
            Ok(Format::Xyz) if is_txt && asc::sniff(&text_head(path)) => Ok(Format::Asc),
            Ok(f) => Ok(f),
            Err(e) => Format::from_content(&head()).ok_or(e),
        }
    }

    /// The format whose magic `bytes` start with, if one does.
    pub fn from_content(bytes: &[u8]) -> Option<Format> {
        const MAGICS: [(&[u8], Format); 18] = [
            (opdx::MAGIC, Format::Opdx),
            (h5::MAGIC, Format::H5),
            (mi::MAGIC, Format::Mi),
            (nid::MAGIC, Format::Nid),
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
        if xz::is_hfm(bytes) {
            return Some(Format::Hfm);
        }
        if xz::is_dektak(bytes) {
            return Some(Format::Dektak);
        }
        if bytes.starts_with(mat::MAGIC) {
            return Some(Format::Mat);
        }
        if zon::MAGICS.iter().any(|m| bytes.starts_with(m)) {
            return Some(Format::Zon);
        }
        if bytes.starts_with(os3d::MAGIC) {
            return Some(Format::Os3d);
        }
        if bytes.starts_with(oir::MAGIC) {
            return Some(Format::Oir);
        }
        if bytes.starts_with(zmg::MAGIC) {
            return Some(Format::Zmg);
        }
        if bytes.starts_with(mdt::MAGIC) {
            return Some(Format::Mdt);
        }
        if vk::sniff(bytes) {
            return Some(Format::Vk);
        }
        if nms::sniff(bytes) {
            return Some(Format::Nms);
        }
        if park::sniff(bytes) {
            return Some(Format::Park);
        }
        if bytes.starts_with(mnt::MAGIC) {
            // Other OLE compound files are refused by the reader, which says
            // the file is no Mountains document.
            return Some(Format::Mnt);
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

    /// Whether files of this format can hold several channels (`--channel`
    /// picks one; other formats accept only channel 0).
    pub fn has_channels(self) -> bool {
        crate::codecs::of(self).is_some_and(|c| c.channels.is_some())
    }

    /// This format's row of [`FORMATS`].
    pub fn info(self) -> &'static FormatInfo {
        FORMATS
            .iter()
            .find(|f| f.format == self)
            .expect("every format has a row")
    }
}
