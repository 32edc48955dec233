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
        format: Format::Nid,
        name: "Nanosurf (.nid, .ezd)",
        extensions: &["nid", "ezd"],
        mesh: No,
        points: No,
        height: R,
        notes: "the data sets whose values are lengths (channels, as SurfaceTopography lists them): 8/16/32-bit raw × range / 2^bits + minimum, from the last line",
    },
    FormatInfo {
        format: Format::Mi,
        name: "Molecular Imaging (.mi)",
        extensions: &["mi"],
        mesh: No,
        points: No,
        height: R,
        notes: "PicoView images: every buffer a channel (heights where bufferUnit is a length; the first by default, as SurfaceTopography), int16/int32 × bufferRange / 2^15 or 2^31, from the last line; spectroscopy and text data refused",
    },
    FormatInfo {
        format: Format::Ibw,
        name: "Igor binary wave (.ibw)",
        extensions: &["ibw"],
        mesh: No,
        points: No,
        height: R,
        notes: "version 5, as Asylum Research AFMs write it: image stacks as channels (labels, else no name (k)), units from the Asylum note or the wave, lengths in the lateral unit, lines from the last; line scans as profiles; complex and 4-D waves refused",
    },
    FormatInfo {
        format: Format::Park,
        name: "Park Systems AFM TIFF (.tiff)",
        extensions: &["tiff", "tif"],
        mesh: No,
        points: No,
        height: R,
        notes: "the first directory's Park tags: int16/int32/f32 data, (raw × scale + offset) × gain in µm, scan size in µm, lines from the last; other TIFFs and line profiles refused",
    },
    FormatInfo {
        format: Format::Hfm,
        name: "HFM line scan (.hfm)",
        extensions: &["hfm"],
        mesh: No,
        points: No,
        height: R,
        notes: "X;Y;valid rows: a uniformly sampled profile (one row), heights in x's unit, rows marked 0 missing; non-uniform scans refused",
    },
    FormatInfo {
        format: Format::Dektak,
        name: "Bruker Dektak CSV (.csv, told by content)",
        extensions: &["csv"],
        mesh: No,
        points: No,
        height: R,
        notes: "the Scan Data block, units from the column titles: a uniformly sampled profile (one row); non-uniform scans refused with their steps",
    },
    FormatInfo {
        format: Format::CsvLineScan,
        name: "Line scan CSV (.csv with column titles, told by content)",
        extensions: &["csv"],
        mesh: No,
        points: No,
        height: R,
        notes: "a line of titles, then `x,z` or `index,x,z` rows (commas, semicolons or tabs; UTF-8 or UTF-16 with its BOM), units from the titles (`x in µm`): a uniformly sampled profile (one row); non-uniform scans refused with their steps",
    },
    FormatInfo {
        format: Format::Nms,
        name: "NanoFocus µsurf (.nms)",
        extensions: &["nms"],
        mesh: No,
        points: No,
        height: R,
        notes: "OM_MS_2.0 areas: u16 counts mapped onto the header's height range in µm, spacing in nm, points of intensity 0 missing; version, image name and date as metadata; profiles refused",
    },
    FormatInfo {
        format: Format::Mat,
        name: "MATLAB (.mat)",
        extensions: &["mat"],
        mesh: No,
        points: No,
        height: R,
        notes: "versions 5 (compressed or not, as scipy.io.savemat writes) and 7.3 (HDF5): every two-dimensional real numeric variable a channel by name, the matrix's rows along x (as SurfaceTopography reads it); no sizes or units in the file: step 1, unitless",
    },
    FormatInfo {
        format: Format::Npz,
        name: "NumPy archive (.npz)",
        extensions: &["npz"],
        mesh: No,
        points: No,
        height: R,
        notes: "numpy.savez / savez_compressed: every two-dimensional array a channel by name, each read as an .npy (shape (ny, nx); SurfaceTopography takes the first index along x); no sizes or units: step 1, unitless",
    },
    FormatInfo {
        format: Format::Hgt,
        name: "NASA SRTM elevation tile (.hgt)",
        extensions: &["hgt"],
        mesh: No,
        points: No,
        height: R,
        notes: "a square of big-endian int16 heights in metres, rows from the north; voids (-32768) read as missing; the step is an angle (1″ or 3″): read with step 1, unitless, the tile's size and resolution kept as metadata",
    },
    FormatInfo {
        format: Format::Vk,
        name: "Keyence VK (.vk3, .vk4, .vk6, .vk7)",
        extensions: &["vk3", "vk4", "vk6", "vk7"],
        mesh: No,
        points: No,
        height: R,
        notes: "the height images as channels: 8/16/32-bit counts × the height scale, pixel lengths from the measurement conditions (pm, read in nm); .vk6/.vk7 as the .vk4 in their zip; date, lens and scales kept as metadata",
    },
    FormatInfo {
        format: Format::Mdt,
        name: "NT-MDT (.mdt)",
        extensions: &["mdt"],
        mesh: No,
        points: No,
        height: R,
        notes: "scanned-data frames whose axes are lengths, as channels named by their signal (Height, DFL…): int16 counts × z step + offset, from the last line, heights in the lateral unit (cm read in m, Å in nm); spectroscopy, text and MDA frames skipped",
    },
    FormatInfo {
        format: Format::Os3d,
        name: "Digital Metrology OmniSurf3D (.os3d)",
        extensions: &["os3d"],
        mesh: No,
        points: No,
        height: R,
        notes: "f32 heights and f64 steps in µm; heights below -3e38 read as missing; version, identification and date kept as metadata",
    },
    FormatInfo {
        format: Format::Zmg,
        name: "KLA Zeta (.zmg)",
        extensions: &["zmg"],
        mesh: No,
        points: No,
        height: R,
        notes: "u16 counts × the z step, steps in µm; the recipe's name and the comment kept as metadata",
    },
    FormatInfo {
        format: Format::Plux,
        name: "Sensofar PLUX (.plux)",
        extensions: &["plux"],
        mesh: No,
        points: No,
        height: R,
        notes: "the zip's layers as channels: f32 heights in µm, pixel size from index.xml, NaN read as missing; the date and the INFO items (device…) kept as metadata",
    },
    FormatInfo {
        format: Format::Zon,
        name: "Keyence ZON (.zon)",
        extensions: &["zon"],
        mesh: No,
        points: No,
        height: R,
        notes: "KPK0 and KPK1 (Zstandard members): int32 counts × metres per unit, metres per pixel from the calibration, points the validity mask marks read as missing; device, serial and date kept as metadata",
    },
    FormatInfo {
        format: Format::Lext,
        name: "Olympus LEXT (.lext)",
        extensions: &["lext"],
        mesh: No,
        points: No,
        height: R,
        notes: "the TIFF's HEIGHT page (uncompressed) × 1e-12 × per-pixel Z × calibration Z in µm, pixel sizes from the measurement XML and the EXIF calibration; the measurement's HeightInfo kept as metadata",
    },
    FormatInfo {
        format: Format::Jpk,
        name: "JPK image scan (.jpk)",
        extensions: &["jpk"],
        mesh: No,
        points: No,
        height: R,
        notes: "the TIFF pages whose default slot is a length, as channels by their names (retrace marked): raw × ScalingMultiply + ScalingOffset, grid lengths from the first page, lines from the last unless reflected",
    },
    FormatInfo {
        format: Format::Qep,
        name: "Mahr MarWin QEP (.qep)",
        extensions: &["qep"],
        mesh: No,
        points: No,
        height: R,
        notes: "the measured and reference [p3dlin] profiles as channels: a uniformly sampled profile in mm (one row), invalid points missing; non-uniform scans refused with their steps; the >Key=Value entries kept as metadata",
    },
    FormatInfo {
        format: Format::Nmm,
        name: "SIOS nanomeasuring machine (.zip of .dsc/.dat)",
        extensions: &["zip"],
        mesh: No,
        points: No,
        height: R,
        notes: "the scan procedure description's field (points, lines, spacing, unit) and each line's -Lz+Az column (m, brought to the field's unit); every scan a channel; the description's keys kept as metadata",
    },
    FormatInfo {
        format: Format::Opdx,
        name: "Bruker Dektak OPDx (.opdx)",
        extensions: &["opdx"],
        mesh: No,
        points: No,
        height: R,
        notes: "Vision64 item tree: a surface profile's height channel (f64 × DataScale, step Extent / (n − 1)) as a one-row profile, or the primary 2-D height channel (f32 matrix)",
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
    FormatInfo {
        format: Format::Mnt,
        name: "Digital Surf MountainsMap (.mnt)",
        extensions: &["mnt"],
        mesh: No,
        points: No,
        height: R,
        notes: "the document's measured surfaces as channels (by name): int32/int16 counts × the height step + origin in the height axis's display unit, steps in the x axis's unit; the mask's unmeasured points read as missing; surface names, axes and the software's version and operators kept as metadata",
    },
    FormatInfo {
        format: Format::Asc,
        name: "Plain-text heights (.asc; .txt by content)",
        extensions: &["asc"],
        mesh: No,
        points: R,
        height: R,
        notes: "a matrix of heights (file rows are grid rows), Gwyddion's text export in any language (Width, Height, Value units), x-length/y-length/pixel size/height conversion factor headers; two columns x z a uniformly sampled profile (non-uniform refused), one column a profile; three columns x y z on a regular grid a height field (absent nodes missing), otherwise points; NaN missing",
    },
    FormatInfo {
        format: Format::Mitutoyo,
        name: "Mitutoyo SurfTest (.xlsx)",
        extensions: &["xlsx"],
        mesh: No,
        points: No,
        height: R,
        notes: "the DATA sheet's positions (E) and heights (F) as a uniformly sampled profile (non-uniform refused), heights in the first roughness parameter's unit, positions in the cut-off's; the tester's roughness parameters, date and cut-off kept as metadata",
    },
    FormatInfo {
        format: Format::H5,
        name: "HDF5 (.h5, .hdf5)",
        extensions: &["h5", "hdf5"],
        mesh: No,
        points: No,
        height: R,
        notes: "every two-dimensional integer or float dataset a channel named by its path (first index x, second y, as SurfaceTopography reads it); no sizes or units in the file: step 1, unitless; a Zygo .datx (the MetaData table) read as one",
    },
    FormatInfo {
        format: Format::Datx,
        name: "Zygo Mx (.datx)",
        extensions: &["datx"],
        mesh: No,
        points: No,
        height: R,
        notes: "HDF5: the surface the MetaData table leads to (Root, Measurement, Surface, Path), rows along y, in its Unit (nm, µm, mm, m; fringes refused), pixel sizes from the X and Y converters (LateralCat in Pixels); No Data and non-finite points read as missing; the MetaData tree, serial number and system type kept as metadata",
    },
    FormatInfo {
        format: Format::Oir,
        name: "Olympus OIR (.oir)",
        extensions: &["oir"],
        mesh: No,
        points: No,
        height: R,
        notes: "the laser-scanning image's HEIGHT channels by their ids: u8/u16 counts × the pixel length in z × the z calibration, pixel lengths × the x/y calibration, lateral sizes in the z unit; rows along y; the microscope and creation date kept as metadata",
    },
    FormatInfo {
        format: Format::Poir,
        name: "Olympus packed OIR (.poir)",
        extensions: &["poir"],
        mesh: No,
        points: No,
        height: R,
        notes: "a zip of .oir files: every member's height channels, numbered in order (members without a laser-scanning image skipped)",
    },
];

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
        matches!(
            self,
            Format::Di
                | Format::Plu
                | Format::Nid
                | Format::Mi
                | Format::Ibw
                | Format::Mnt
                | Format::H5
                | Format::Mat
                | Format::Npz
                | Format::Vk
                | Format::Mdt
                | Format::Plux
                | Format::Jpk
                | Format::Qep
                | Format::Nmm
                | Format::Oir
                | Format::Poir
        )
    }

    /// This format's row of [`FORMATS`].
    pub fn info(self) -> &'static FormatInfo {
        FORMATS
            .iter()
            .find(|f| f.format == self)
            .expect("every format has a row")
    }
}
