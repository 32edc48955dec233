//! Zygo `.datx` (the HDF5 files of Zygo's Mx software), read.
//!
//! The layout, as Gwyddion's `datxfile.c` and SurfaceTopography's `DATX.py`
//! read it: the root dataset `MetaData` is a table of (Source, Link,
//! Destination) strings; from `Root`, following `Measurement` then `Surface`
//! (each a `{uuid}` naming further rows) leads to `Path`, the surface
//! dataset's path (usually `/Measurement/Surface`). That dataset holds the
//! heights row-major, rows along y and columns along x (asperity's own
//! order), with attributes:
//! - `Unit`: the heights' unit (`NanoMeters`, `MicroMeters`, `MilliMeters`,
//!   `Meters`; fringes and waves are refused, as SurfaceTopography refuses
//!   them);
//! - `X Converter`, `Y Converter`: compounds (Category, BaseUnit,
//!   Parameters) whose category is `LateralCat` in `Pixels`, the pixel size
//!   in metres being `Parameters[1]`;
//! - `Z Converter`: category `HeightCat`, its BaseUnit the same as `Unit`;
//! - `No Data` (optional): the value of unmeasured points, read as missing
//!   (so are non-finite heights).
//!
//! Lateral sizes are kept in the heights' unit (SurfaceTopography's choice).
//! The `MetaData` tree is kept as metadata (dotted keys), with the
//! instrument's `System Serial Number` and `System Type` found where
//! SurfaceTopography looks for them: on the surface dataset or a group above
//! it, else anywhere under `/Attributes`.
//!
//! Strings may be fixed-length or variable-length, and the parameters a
//! variable-length sequence or a fixed array: the `hdf5-reader` crate parses
//! compound types but leaves their variable-length members as references
//! into the global heap, which are resolved here through the crate's bounded
//! resolver. Checked against SurfaceTopography's reader on files built with
//! h5py to the layout (no instrument file is public in a repository asperity
//! can reach).

use std::collections::{HashMap, HashSet};

use asperity_core::{HeightField, LengthUnit, Units};
use hdf5_reader::Datatype;
use hdf5_reader::group::Group;
use hdf5_reader::{Attribute, Dataset};

use crate::channel::Channel;
use crate::error::{FResult, FormatError, malformed};
use crate::format::{Access, Codec, Magic, Registration};
use crate::{Metadata, h5};

/// How deep the `MetaData` tree and the `/Attributes` groups are followed.
const MAX_DEPTH: usize = 16;

/// The most bytes of `MetaData` table read (Zygo's hold a few hundred rows).
const MAX_TABLE_BYTES: u64 = 16 << 20;

/// The most numbers read from one variable-length sequence.
const MAX_PARAMETERS: usize = 1 << 16;

fn bad(e: impl std::fmt::Display) -> FormatError {
    FormatError::Malformed(format!("the HDF5 structure is damaged: {e}"))
}

/// `e` with `context` in front of its message.
fn within(context: &str, e: FormatError) -> FormatError {
    match e {
        FormatError::Malformed(m) => FormatError::Malformed(format!("{context}: {m}")),
        FormatError::Unsupported(m) => FormatError::Unsupported(format!("{context}: {m}")),
        other => other,
    }
}

/// Resolves a variable-length reference (count, heap address, index) into
/// `count × element size` bytes.
type Resolve<'a> = dyn Fn(&[u8], usize) -> FResult<Vec<u8>> + 'a;

/// One member of a compound value (or a whole simple value).
#[derive(Debug, Clone, PartialEq)]
enum Value {
    Text(String),
    Numbers(Vec<f64>),
}

impl Value {
    fn text(&self) -> String {
        match self {
            Value::Text(t) => t.clone(),
            Value::Numbers(v) => v
                .iter()
                .map(|x| x.to_string())
                .collect::<Vec<_>>()
                .join(" "),
        }
    }
}

fn number(t: &Datatype, b: &[u8]) -> Option<f64> {
    use hdf5_reader::ByteOrder::BigEndian;
    let le = |n: usize| -> Option<[u8; 8]> {
        let mut w = [0u8; 8];
        let s = b.get(..n)?;
        w[..n].copy_from_slice(s);
        Some(w)
    };
    match t {
        Datatype::FloatingPoint {
            size: size @ (4 | 8),
            byte_order,
        } => {
            let mut w = le(usize::from(*size))?;
            if *byte_order == BigEndian {
                w[..usize::from(*size)].reverse();
            }
            match size {
                8 => Some(f64::from_le_bytes(w)),
                4 => Some(f64::from(f32::from_le_bytes([w[0], w[1], w[2], w[3]]))),
                _ => None,
            }
        }
        Datatype::FixedPoint {
            size,
            signed,
            byte_order,
        } if matches!(size, 1 | 2 | 4 | 8) => {
            let n = usize::from(*size);
            let mut w = le(n)?;
            if *byte_order == BigEndian {
                w[..n].reverse();
            }
            let raw = u64::from_le_bytes(w);
            Some(if *signed {
                let shift = 64 - 8 * n as u32;
                (((raw << shift) as i64) >> shift) as f64
            } else {
                raw as f64
            })
        }
        _ => None,
    }
}

fn element_size(t: &Datatype) -> Option<usize> {
    match t {
        Datatype::FloatingPoint { size, .. } | Datatype::FixedPoint { size, .. } => {
            Some(usize::from(*size))
        }
        _ => None,
    }
}

fn text_of(b: &[u8]) -> String {
    String::from_utf8_lossy(b)
        .trim_end_matches(['\0', ' '])
        .to_owned()
}

/// The value of type `t` at the start of `b`.
fn value(t: &Datatype, b: &[u8], resolve: &Resolve) -> FResult<Value> {
    let short = || FormatError::Malformed(format!("a value of type {t:?} is cut short"));
    match t {
        Datatype::String {
            size: hdf5_reader::StringSize::Fixed(n),
            ..
        } => Ok(Value::Text(text_of(
            b.get(..*n as usize).ok_or_else(short)?,
        ))),
        Datatype::VarLen { base, kind, .. } => {
            if *kind == hdf5_reader::VarLenKind::String || matches!(**base, Datatype::String { .. })
            {
                return Ok(Value::Text(text_of(&resolve(b, 1)?)));
            }
            let size = element_size(base)
                .ok_or_else(|| FormatError::Malformed(format!("a sequence of {base:?}")))?;
            let bytes = resolve(b, size)?;
            if bytes.len() / size > MAX_PARAMETERS {
                return malformed(format!(
                    "a sequence of {} numbers (at most {MAX_PARAMETERS} read)",
                    bytes.len() / size
                ));
            }
            Ok(Value::Numbers(
                bytes
                    .chunks_exact(size)
                    .filter_map(|c| number(base, c))
                    .collect(),
            ))
        }
        Datatype::Array { base, dims } => {
            let size = element_size(base)
                .ok_or_else(|| FormatError::Malformed(format!("an array of {base:?}")))?;
            let n = dims
                .iter()
                .try_fold(1u64, |a, &d| a.checked_mul(d))
                .and_then(|n| usize::try_from(n).ok())
                .filter(|&n| n <= MAX_PARAMETERS)
                .ok_or_else(|| FormatError::Malformed(format!("an array of {dims:?}")))?;
            let bytes = b.get(..n * size).ok_or_else(short)?;
            Ok(Value::Numbers(
                bytes
                    .chunks_exact(size)
                    .filter_map(|c| number(base, c))
                    .collect(),
            ))
        }
        _ => number(t, b)
            .map(|x| Value::Numbers(vec![x]))
            .ok_or_else(|| FormatError::Malformed(format!("a value of type {t:?}"))),
    }
}

/// The members of a compound value at the start of `b`, by name.
fn compound(t: &Datatype, b: &[u8], resolve: &Resolve) -> FResult<Vec<(String, Value)>> {
    let Datatype::Compound { fields, .. } = t else {
        return malformed(format!("expected a compound, found {t:?}"));
    };
    fields
        .iter()
        .map(|f| {
            let at = b.get(f.byte_offset as usize..).ok_or_else(|| {
                FormatError::Malformed(format!("member {} lies outside its value", f.name))
            })?;
            Ok((f.name.clone(), value(&f.datatype, at, resolve)?))
        })
        .collect()
}

/// The first element of an attribute.
fn first(a: &Attribute, resolve: &Resolve) -> FResult<Value> {
    match &a.datatype {
        Datatype::Compound { .. } => malformed(format!("attribute `{}` is a compound", a.name)),
        _ => {
            if let Ok(strings) = a.read_strings() {
                return strings.into_iter().next().map(Value::Text).ok_or_else(|| {
                    FormatError::Malformed(format!("attribute `{}` is empty", a.name))
                });
            }
            value(&a.datatype, &a.raw_data, resolve)
        }
    }
}

/// What the surface dataset's attributes say.
struct Surface {
    path: String,
    nx: usize,
    ny: usize,
    unit: LengthUnit,
    /// Pixel sizes (x, y) in metres.
    pixel: [f64; 2],
    no_data: Option<f64>,
}

/// A Zygo unit name (`NanoMeters`…) or a length symbol as asperity's unit.
fn unit(name: &str) -> Option<LengthUnit> {
    let u = match name.trim() {
        "NanoMeters" => LengthUnit::Nm,
        "MicroMeters" => LengthUnit::Um,
        "MilliMeters" => LengthUnit::Mm,
        "Meters" => LengthUnit::M,
        symbol => LengthUnit::parse(symbol).ok()?,
    };
    u.metres().map(|_| u)
}

/// The (Category, BaseUnit, Parameters) of a converter attribute, by name or,
/// where the names differ, by position (first, second, last), as
/// SurfaceTopography reads them.
fn converter(d: &Dataset, name: &str) -> FResult<(String, String, Vec<f64>)> {
    let a = d
        .attribute(name)
        .map_err(|_| FormatError::Malformed(format!("the surface has no `{name}` attribute")))?;
    let resolve = |r: &[u8], size: usize| d.resolve_vlen_reference_bytes(r, size).map_err(bad);
    let members = compound(&a.datatype, &a.raw_data, &resolve)
        .map_err(|e| within(&format!("attribute `{name}`"), e))?;
    let by = |key: &str, at: Option<usize>| {
        members
            .iter()
            .find(|(k, _)| k == key)
            .or_else(|| at.and_then(|i| members.get(i)))
            .map(|(_, v)| v.clone())
    };
    let (Some(category), Some(base), Some(Value::Numbers(params))) = (
        by("Category", Some(0)),
        by("BaseUnit", Some(1)),
        by("Parameters", members.len().checked_sub(1)),
    ) else {
        return malformed(format!(
            "attribute `{name}` is not a (Category, BaseUnit, Parameters) converter"
        ));
    };
    Ok((category.text(), base.text(), params))
}

fn surface(file: &hdf5_reader::Hdf5File, path: &str) -> FResult<(Dataset, Surface)> {
    let d = file
        .dataset(path)
        .map_err(|e| FormatError::Malformed(format!("the surface dataset {path}: {e}")))?;
    let [ny, nx] = d.shape()[..] else {
        return malformed(format!(
            "the surface {path} has shape {:?}, not (rows, columns)",
            d.shape()
        ));
    };
    let to = |n: u64| usize::try_from(n).map_err(bad);
    let (nx, ny) = (to(nx)?, to(ny)?);
    if nx == 0 || ny == 0 {
        return malformed(format!("the surface {path} is empty ({ny} × {nx})"));
    }
    let resolve = |r: &[u8], size: usize| d.resolve_vlen_reference_bytes(r, size).map_err(bad);
    let unit_name = d
        .attribute("Unit")
        .map_err(|_| FormatError::Malformed("the surface has no `Unit` attribute".into()))
        .and_then(|a| first(&a, &resolve))?
        .text();
    let z_unit = unit(&unit_name).ok_or_else(|| {
        FormatError::Unsupported(format!(
            "heights in `{unit_name}`: not a length (fringes and waves are not converted)"
        ))
    })?;
    let mut pixel = [0.0; 2];
    for (k, axis) in ["X Converter", "Y Converter"].into_iter().enumerate() {
        let (category, base, params) = converter(&d, axis)?;
        if category != "LateralCat" || base != "Pixels" {
            return Err(FormatError::Unsupported(format!(
                "`{axis}` is {category} in {base}; only LateralCat in Pixels is read"
            )));
        }
        pixel[k] = params.get(1).copied().unwrap_or(f64::NAN);
        if !(pixel[k].is_finite() && pixel[k] > 0.0) {
            return malformed(format!(
                "`{axis}` gives the pixel size {:?} m, not a positive length",
                params.get(1)
            ));
        }
    }
    let (category, base, _) = converter(&d, "Z Converter")?;
    if category != "HeightCat" {
        return Err(FormatError::Unsupported(format!(
            "`Z Converter` is {category}; only HeightCat is read"
        )));
    }
    if unit(&base) != Some(z_unit) {
        return malformed(format!(
            "two height units: `{base}` in the Z converter and `{unit_name}` on the surface"
        ));
    }
    let no_data = match d.attribute("No Data") {
        Ok(a) => match first(&a, &resolve)? {
            Value::Numbers(v) => v.first().copied(),
            Value::Text(t) => return malformed(format!("`No Data` is the text {t:?}")),
        },
        Err(_) => None,
    };
    Ok((
        d,
        Surface {
            path: path.to_owned(),
            nx,
            ny,
            unit: z_unit,
            pixel,
            no_data,
        },
    ))
}

/// The `MetaData` table: each source's (link, destination) rows in order.
type Table = HashMap<String, Vec<(String, String)>>;

fn table(file: &hdf5_reader::Hdf5File) -> FResult<Table> {
    let d = file.dataset("MetaData").map_err(|_| {
        FormatError::Malformed("an HDF5 file without the `MetaData` table of a Zygo .datx".into())
    })?;
    let resolve = |r: &[u8], size: usize| d.resolve_vlen_reference_bytes(r, size).map_err(bad);
    let stride = d.raw_element_size().map_err(bad)?;
    if stride == 0 {
        return malformed("the `MetaData` table has empty rows");
    }
    // The table is read before the memory estimate (it leads to the
    // surface), so its declared size is bounded first.
    let rows = d.shape().iter().try_fold(1u64, |a, &n| a.checked_mul(n));
    let bytes = rows.and_then(|r| r.checked_mul(stride as u64));
    if bytes.is_none_or(|b| b > MAX_TABLE_BYTES) {
        return malformed(format!(
            "the `MetaData` table declares {:?} rows of {stride} bytes (at most {MAX_TABLE_BYTES} bytes read)",
            d.shape()
        ));
    }
    let raw = d.read_raw_bytes().map_err(bad)?;
    let mut out = Table::new();
    for row in raw.chunks_exact(stride) {
        let members =
            compound(d.dtype(), row, &resolve).map_err(|e| within("the `MetaData` table", e))?;
        let [a, b, c] = &members[..] else {
            return malformed(format!(
                "the `MetaData` table has {} columns, not (Source, Link, Destination)",
                members.len()
            ));
        };
        out.entry(a.1.text())
            .or_default()
            .push((b.1.text(), c.1.text()));
    }
    Ok(out)
}

/// The tree under `Root`, flattened to dotted keys in the table's order.
/// Each node is expanded once (a node reached again, or past the depth
/// limit, stays its `{uuid}`), so the output is at most the table's size.
fn flatten(t: &Table) -> Metadata {
    fn walk(t: &Table, node: &str, prefix: &str, seen: &mut HashSet<String>, out: &mut Metadata) {
        if !seen.insert(node.to_owned()) {
            return;
        }
        for (link, dest) in t.get(node).map(Vec::as_slice).unwrap_or_default() {
            let key = if prefix.is_empty() {
                link.clone()
            } else {
                format!("{prefix}.{link}")
            };
            let deeper = prefix.matches('.').count() + 1 < MAX_DEPTH;
            if dest.starts_with('{') && t.contains_key(dest) && deeper && !seen.contains(dest) {
                walk(t, dest, &key, seen, out);
            } else {
                out.push((key, dest.clone()));
            }
        }
    }
    let mut out = Metadata::new();
    walk(t, "Root", "", &mut HashSet::new(), &mut out);
    out
}

fn open(bytes: &[u8]) -> FResult<(hdf5_reader::Hdf5File, Metadata)> {
    if !bytes.starts_with(h5::MAGIC) {
        return malformed("missing the HDF5 signature");
    }
    let file = hdf5_reader::Hdf5File::from_bytes(bytes).map_err(bad)?;
    let meta = flatten(&table(&file)?);
    Ok((file, meta))
}

fn surface_path(meta: &Metadata) -> FResult<String> {
    meta.iter()
        .find(|(k, _)| k == "Measurement.Surface.Path")
        .map(|(_, v)| v.clone())
        .ok_or_else(|| {
            FormatError::Malformed(
                "the `MetaData` table names no Measurement → Surface → Path".into(),
            )
        })
}

/// Whether an HDF5 file is a `.datx` (it has the root `MetaData` table).
pub(crate) fn sniff(bytes: &[u8]) -> bool {
    bytes.starts_with(h5::MAGIC)
        && hdf5_reader::Hdf5File::from_bytes(bytes)
            .and_then(|f| f.dataset("MetaData"))
            .is_ok_and(|d| matches!(d.dtype(), Datatype::Compound { .. }))
}

/// The surface's points (for the memory estimate).
pub(crate) fn declared_points(bytes: &[u8]) -> FResult<u128> {
    let (file, meta) = open(bytes)?;
    let (_, s) = surface(&file, &surface_path(&meta)?)?;
    Ok(s.nx as u128 * s.ny as u128)
}

/// Reads the measured surface.
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    let (file, meta) = open(bytes)?;
    let (d, s) = surface(&file, &surface_path(&meta)?)?;
    let mut values = h5::read_f64(&d)
        .map_err(|e| FormatError::Malformed(format!("the surface {}: {e}", s.path)))?;
    if values.len() != s.nx * s.ny {
        return malformed(format!(
            "the surface {}: {} values for {} × {}",
            s.path,
            values.len(),
            s.ny,
            s.nx
        ));
    }
    for v in &mut values {
        if !v.is_finite() || Some(*v) == s.no_data {
            *v = f64::NAN;
        }
    }
    // Units per metre, the power of ten exactly (as SurfaceTopography scales).
    let per_metre = match s.unit {
        LengthUnit::Nm => 1e9,
        LengthUnit::Um => 1e6,
        LengthUnit::Mm => 1e3,
        _ => 1.0,
    };
    Ok(HeightField::from_vec([s.nx, s.ny], values)?
        .with_spacing([s.pixel[0] * per_metre, s.pixel[1] * per_metre])?
        .with_units(Units {
            xy: s.unit,
            z: s.unit,
        }))
}

/// The first attribute of `attrs` whose name ends with `key`, as text.
fn find_attr(attrs: &[Attribute], key: &str, resolve: &Resolve) -> Option<String> {
    attrs
        .iter()
        .filter(|a| a.name.ends_with(key))
        .find_map(|a| first(a, resolve).ok().map(|v| v.text()))
}

/// The instrument's serial number and type, where SurfaceTopography finds
/// them: the surface dataset, then each group above it (not the root), then
/// anything under `/Attributes`.
fn instrument(file: &hdf5_reader::Hdf5File, d: &Dataset, path: &str) -> [Option<String>; 2] {
    const KEYS: [&str; 2] = ["System Serial Number", "System Type"];
    let mut found: [Option<String>; 2] = [None, None];
    let mut take = |attrs: &[Attribute], resolve: &Resolve| {
        for (k, key) in KEYS.iter().enumerate() {
            if found[k].is_none() {
                found[k] = find_attr(attrs, key, resolve);
            }
        }
    };
    let resolve = |r: &[u8], size: usize| d.resolve_vlen_reference_bytes(r, size).map_err(bad);
    take(&d.attributes(), &resolve);
    let parts: Vec<&str> = path.split('/').filter(|p| !p.is_empty()).collect();
    for depth in (1..parts.len()).rev() {
        if let Ok(g) = group_at(file, &parts[..depth]) {
            let resolve =
                |r: &[u8], size: usize| g.resolve_vlen_reference_bytes(r, size).map_err(bad);
            take(&g.attributes().unwrap_or_default(), &resolve);
        }
    }
    if let Ok(root) = file.root_group()
        && let Ok(attributes) = root.group("Attributes")
    {
        let mut stack = vec![(attributes, 0)];
        while let Some((g, depth)) = stack.pop() {
            if depth >= MAX_DEPTH {
                continue;
            }
            let Ok((groups, sets)) = g.members() else {
                continue;
            };
            for s in &sets {
                let resolve =
                    |r: &[u8], size: usize| s.resolve_vlen_reference_bytes(r, size).map_err(bad);
                take(&s.attributes(), &resolve);
            }
            for child in groups.into_iter().rev() {
                let resolve = |r: &[u8], size: usize| {
                    child.resolve_vlen_reference_bytes(r, size).map_err(bad)
                };
                take(&child.attributes().unwrap_or_default(), &resolve);
                stack.push((child, depth + 1));
            }
        }
    }
    found
}

fn group_at(
    file: &hdf5_reader::Hdf5File,
    parts: &[&str],
) -> Result<Group, hdf5_reader::error::Error> {
    let mut g = file.root_group()?;
    for p in parts {
        g = g.group(p)?;
    }
    Ok(g)
}

/// The `MetaData` tree (dotted keys) and the instrument's serial number and
/// type.
pub(crate) fn metadata(bytes: &[u8]) -> FResult<Metadata> {
    let (file, mut meta) = open(bytes)?;
    let path = surface_path(&meta)?;
    let (d, _) = surface(&file, &path)?;
    let [serial, kind] = instrument(&file, &d, &path);
    meta.push(("Vendor".to_owned(), "Zygo".to_owned()));
    if let Some(s) = serial {
        meta.push(("System Serial Number".to_owned(), s));
    }
    if let Some(t) = kind {
        meta.push(("System Type".to_owned(), t));
    }
    Ok(meta)
}

/// A `.datx` under another name is read as one (SurfaceTopography too tries
/// DATX first); other files by their chosen channel.
fn read_channel_or_datx(bytes: &[u8], choice: Option<&Channel>) -> FResult<HeightField> {
    if choice.is_none() && sniff(bytes) {
        read_height(bytes)
    } else {
        h5::read_channel(bytes, choice)
    }
}

/// A `.datx` file's metadata; none for other HDF5 files.
fn metadata_or_datx(bytes: &[u8]) -> FResult<crate::Metadata> {
    if sniff(bytes) {
        metadata(bytes)
    } else {
        Ok(crate::Metadata::new())
    }
}

/// The registration of HDF5 files in general: here, not in `h5`, as a
/// `.datx` under another name is read as one (`h5` is this module's reader
/// of HDF5, and knows nothing of Zygo's layout).
pub(crate) const H5: Registration = Registration {
    name: "HDF5 (.h5, .hdf5)",
    extensions: &["h5", "hdf5"],
    height: Access::Read,
    notes: "every two-dimensional integer or float dataset a channel named by its path (first index x, second y, as SurfaceTopography reads it); no sizes or units in the file: step 1, unitless; a Zygo .datx (the MetaData table) read as one",
    magic: Magic::Starts(&[h5::MAGIC]),
    codec: Some(
        Codec::new(read_channel_or_datx)
            .channels(h5::channels)
            .metadata(metadata_or_datx)
            .declared(|b| h5::declared_points(b).map(crate::pixel_bytes)),
    ),
    ..Registration::NONE
};

/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "Zygo Mx (.datx)",
    extensions: &["datx"],
    height: Access::Read,
    notes: "HDF5: the surface the MetaData table leads to (Root, Measurement, Surface, Path), rows along y, in its Unit (nm, µm, mm, m; fringes refused), pixel sizes from the X and Y converters (LateralCat in Pixels); No Data and non-finite points read as missing; the MetaData tree, serial number and system type kept as metadata",
    codec: Some(
        Codec::new(|b, _| read_height(b))
            .metadata(metadata)
            .declared(|b| declared_points(b).map(crate::pixel_bytes)),
    ),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    /// Written by h5py to the layout (tests/data/README.md): a 3 × 4 surface
    /// in nm, pixels of 0.5 µm × 0.25 µm, `No Data` at (row 1, column 2),
    /// variable-length strings, serial 4242 under `/Attributes`.
    const SMALL: &[u8] = include_bytes!("../tests/data/small.datx");

    #[test]
    fn surface_units_spacing_and_missing_points() {
        assert!(sniff(SMALL));
        let h = read_height(SMALL).unwrap();
        assert_eq!(h.dims(), [4, 3]);
        assert_eq!(h.units().z, LengthUnit::Nm);
        let s = h.spacing();
        assert!(
            (s[0] - 500.0).abs() < 1e-9 && (s[1] - 250.0).abs() < 1e-9,
            "{s:?}"
        );
        assert!(h.get(2, 1).is_nan());
        assert_eq!((*h.get(0, 0), *h.get(3, 2)), (0.0, 11.0));
        assert_eq!(declared_points(SMALL).unwrap(), 12);
        let m = metadata(SMALL).unwrap();
        let get = |k: &str| m.iter().find(|(a, _)| a == k).map(|(_, v)| v.as_str());
        assert_eq!(
            get("Measurement.Surface.Path"),
            Some("/Measurement/Surface")
        );
        assert_eq!(get("System Serial Number"), Some("4242"));
    }

    #[test]
    fn metadata_loops_and_shared_nodes_are_expanded_once() {
        let row = |a: &str, b: &str| (a.to_owned(), b.to_owned());
        let mut t = Table::new();
        t.insert("Root".into(), vec![row("A", "{a}"), row("B", "{a}")]);
        t.insert(
            "{a}".into(),
            vec![row("Back", "Root"), row("Loop", "{a}"), row("K", "v")],
        );
        let m = flatten(&t);
        assert_eq!(
            m,
            [
                row("A.Back", "Root"),
                row("A.Loop", "{a}"),
                row("A.K", "v"),
                row("B", "{a}")
            ]
        );
    }

    #[test]
    fn plain_hdf5_truncated_and_foreign_files_are_refused() {
        let plain = include_bytes!("../tests/data/small.h5");
        assert!(!sniff(plain));
        let e = read_height(plain).unwrap_err();
        assert!(format!("{e:?}").contains("MetaData"), "{e:?}");
        // A cut file is refused, unless all the surface needs lies before
        // the cut (HDF5 places objects anywhere): then it reads the same.
        let whole = read_height(SMALL).unwrap();
        let mut refused = 0;
        for cut in (0..SMALL.len()).step_by(89) {
            match read_height(&SMALL[..cut]) {
                Ok(h) => {
                    let same = |a: f64, b: f64| a == b || (a.is_nan() && b.is_nan());
                    let all = h.data().iter().zip(whole.data()).all(|(&a, &b)| same(a, b));
                    assert!(all && h.spacing() == whole.spacing(), "cut at {cut}");
                }
                Err(_) => refused += 1,
            }
        }
        assert!(refused > 80, "{refused} cuts refused");
    }
}
