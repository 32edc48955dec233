//! Bruker Dektak `.opdx` (Vision64, stylus profilometers), read.
//!
//! After the magic `VCA DATA\x01\0\0\x55`, a tree of named items, each a
//! name (u32 length, UTF-8), a type byte and a value; little-endian. Lengths
//! of variable items are a size byte (1, 2 or 4) and a length of that size.
//! Containers (0x7D, and the raw-data wrappers 0x46, 0x47) hold items up to
//! a terminator (0x7F) and a u16; the paths of the items (`/1D_Data/Raw/
//! Array`) are their names joined. The values read here: integers and
//! floats, strings (0x12), string lists (0x42), quantities (0x13: a value, a
//! name and a unit symbol) and units (0x18), double arrays (0x40) and
//! matrices (0x00, 0x45: rows, columns and f32 data); time stamps, type ids
//! and position data are skipped by their lengths.
//!
//! A surface profile (`/MetaData/DataKind`, else the presence of `/1D_Data`)
//! reads the first channel of `/MetaData/1D_Channels/Height`: `NumPoints`
//! f64 values after a 5-byte prefix of its `Array`, times `DataScale` in the
//! lateral unit; `Extent` is the distance from the first point to the last,
//! so the step is Extent / (n − 1). A surface height reads the primary 2-D
//! channel's `Matrix` (rows of x), `Dimension2Points` × `Dimension1Points`,
//! the extents likewise. Layout learnt from SurfaceTopography's `OPDx.py` and
//! checked on its example file.

use std::collections::HashMap;

use asperity_core::{HeightField, LengthUnit, Units};

use crate::bytes::{Cursor, Fields};
use crate::error::{FResult, FormatError, malformed, unsupported};
use crate::format::{Access, Codec, Magic, Registration};

pub(crate) const MAGIC: &[u8] = b"VCA DATA\x01\x00\x00\x55";

/// A value of the tree, as far as the readers need it.
#[derive(Clone, Debug)]
enum Item {
    Number(f64),
    Text(String),
    Texts(Vec<String>),
    /// A value with a unit symbol.
    Quantity(f64, String),
    /// Bytes of a double array (start, length).
    Doubles(usize, usize),
    /// f32 data (start, length) of `columns` × `rows`.
    Matrix(usize, usize, usize, usize),
}

/// A text: its length (u32), then the bytes.
fn name(c: &mut Cursor<'_>) -> FResult<String> {
    let n = c.u32()? as usize;
    Ok(String::from_utf8_lossy(c.take(n)?).into_owned())
}

/// A length of 1, 2 or 4 bytes, after a byte giving which.
fn varlen(c: &mut Cursor<'_>) -> FResult<usize> {
    match c.u8()? {
        1 => Ok(usize::from(c.u8()?)),
        2 => Ok(usize::from(c.u16()?)),
        4 => Ok(c.u32()? as usize),
        k => malformed(format!("a length of {k} bytes")),
    }
}

/// Skips a block of `varlen` bytes, returning (start, length).
fn block(c: &mut Cursor<'_>) -> FResult<(usize, usize)> {
    let n = varlen(c)?;
    let start = c.at();
    c.skip(n)?;
    Ok((start, n))
}

/// Skips a block of `varlen` bytes, returning a cursor over it.
fn sub_block<'a>(c: &mut Cursor<'a>) -> FResult<Cursor<'a>> {
    let (start, n) = block(c)?;
    let mut inner = c.up_to(start + n)?;
    inner.seek(start);
    Ok(inner)
}

/// A number item of type `kind` (booleans, integers, floats).
fn number(c: &mut Cursor, kind: u8) -> FResult<f64> {
    let b = c.take(match kind {
        0x01 => 1,
        0x04 | 0x05 => 2,
        0x06 | 0x07 | 0x0C => 4,
        _ => 8,
    })?;
    Ok(match kind {
        0x01 => f64::from(b[0]),
        0x04 => f64::from(i16::from_le_bytes([b[0], b[1]])),
        0x05 => f64::from(u16::from_le_bytes([b[0], b[1]])),
        0x06 => f64::from(i32::from_le_bytes(b.try_into().expect("4"))),
        0x07 => f64::from(u32::from_le_bytes(b.try_into().expect("4"))),
        0x0A => i64::from_le_bytes(b.try_into().expect("8")) as f64,
        0x0B => u64::from_le_bytes(b.try_into().expect("8")) as f64,
        0x0C => f64::from(f32::from_le_bytes(b.try_into().expect("4"))),
        _ => f64::from_le_bytes(b.try_into().expect("8")),
    })
}

/// Reads the items of a container (or the file) into `manifest`, up to a
/// terminator or the end of `bytes`.
fn items(
    c: &mut Cursor,
    prefix: &str,
    manifest: &mut HashMap<String, Item>,
    depth: usize,
) -> FResult<()> {
    if depth > 64 {
        return malformed("containers nested more than 64 deep");
    }
    while !c.is_done() {
        let path = format!("{prefix}/{}", name(c)?);
        let kind = c.u8()?;
        if kind == 0x7F {
            return Ok(());
        }
        if matches!(kind, 0x7D | 0x46 | 0x47) {
            // A container: its items, under its path.
            let n = varlen(c)?;
            let end = c.at().saturating_add(n);
            items(&mut c.up_to(end)?, &path, manifest, depth + 1)?;
            c.seek(end);
        } else if let Some(item) = item(c, kind, &path)? {
            manifest.insert(path, item);
        }
    }
    Ok(())
}

/// One item of type `kind` other than a container: its value, if it is one
/// asperity keeps.
fn item(c: &mut Cursor, kind: u8, path: &str) -> FResult<Option<Item>> {
    Ok(match kind {
        0x7C | 0x0E => {
            name(c)?;
            block(c)?;
            None
        }
        0x01 | 0x04..=0x07 | 0x0A..=0x0D => Some(Item::Number(number(c, kind)?)),
        0x12 => {
            let n = varlen(c)?;
            Some(Item::Text(String::from_utf8_lossy(c.take(n)?).into_owned()))
        }
        0x13 => {
            let mut q = sub_block(c)?;
            let value = q.f64()?;
            name(&mut q)?;
            Some(Item::Quantity(value, name(&mut q)?))
        }
        0x15 => {
            c.skip(9)?;
            None
        }
        0x18 => {
            let mut u = sub_block(c)?;
            name(&mut u)?;
            let symbol = name(&mut u)?;
            Some(Item::Quantity(u.f64()?, symbol))
        }
        0x40 => {
            name(c)?;
            let (start, n) = block(c)?;
            Some(Item::Doubles(start, n))
        }
        0x42 => {
            name(c)?;
            let mut l = sub_block(c)?;
            let mut list = Vec::new();
            while !l.is_done() {
                list.push(name(&mut l)?);
            }
            Some(Item::Texts(list))
        }
        0x00 | 0x45 => Some(matrix(c, kind)?),
        k => return malformed(format!("item {path:?} of unknown type 0x{k:02x}")),
    })
}

/// A matrix item (0x00 with a type id and name before it, or 0x45): its
/// rows, columns and f32 data.
fn matrix(c: &mut Cursor, kind: u8) -> FResult<Item> {
    name(c)?;
    if kind == 0x00 {
        c.u32()?;
        name(c)?;
    }
    let n = varlen(c)?;
    let (rows, columns) = (c.u32()? as usize, c.u32()? as usize);
    let len = n
        .checked_sub(8)
        .ok_or_else(|| FormatError::Malformed("a matrix shorter than its size".into()))?;
    let start = c.at();
    c.skip(len)?;
    Ok(Item::Matrix(start, len, columns, rows))
}

/// `um`, `µm`, … as a length unit.
fn unit(symbol: &str) -> FResult<LengthUnit> {
    match symbol.trim() {
        "um" | "µm" => Ok(LengthUnit::Um),
        s => LengthUnit::parse(s)
            .ok()
            .filter(|u| *u != LengthUnit::None)
            .ok_or_else(|| FormatError::Malformed(format!("the unit {s:?} is not a length"))),
    }
}

/// The items read, by path.
struct Manifest(HashMap<String, Item>);

impl Manifest {
    fn get(&self, k: &str) -> FResult<&Item> {
        self.0
            .get(k)
            .ok_or_else(|| FormatError::Malformed(format!("no {k}")))
    }
    fn number(&self, k: &str) -> FResult<f64> {
        match self.get(k)? {
            Item::Number(v) => Ok(*v),
            other => malformed(format!("{k} is {other:?}, not a number")),
        }
    }
    fn quantity(&self, k: &str) -> FResult<(f64, LengthUnit)> {
        match self.get(k)? {
            Item::Quantity(v, s) => Ok((*v, unit(s)?)),
            other => malformed(format!("{k} is {other:?}, not a quantity")),
        }
    }
    /// A text, or the first of a list of texts.
    fn first(&self, k: &str) -> Option<String> {
        match self.0.get(k) {
            Some(Item::Texts(l)) => l.first().cloned(),
            Some(Item::Text(t)) => Some(t.clone()),
            _ => None,
        }
    }
    /// Whether the file holds a surface profile rather than a map.
    fn is_profile(&self) -> bool {
        let kind = self.first("/MetaData/DataKind").unwrap_or_default();
        let has = |p: &str| self.0.keys().any(|k| k.starts_with(p));
        kind == "Surface Profile"
            || (kind != "Surface Height" && !has("/2D_Data/") && has("/1D_Data/"))
    }
}

/// Where a channel's values are and how to scale them.
struct Layout {
    /// Byte range of the values.
    start: usize,
    end: usize,
    nx: usize,
    ny: usize,
    /// Step along x and y, in `xy`.
    steps: [f64; 2],
    xy: LengthUnit,
    /// DataScale and its unit.
    scale: (f64, LengthUnit),
    /// f64 values (profiles) or f32 (maps).
    doubles: bool,
}

/// The extents run from the first point to the last.
fn step(extent: f64, n: usize) -> f64 {
    if n > 1 {
        extent / (n - 1) as f64
    } else {
        extent
    }
}

fn profile_layout(m: &Manifest) -> FResult<Layout> {
    let name = m
        .first("/MetaData/1D_Channels/Height")
        .ok_or_else(|| FormatError::Malformed("no 1-D height channel".into()))?;
    let p = format!("/1D_Data/{name}");
    let nx = m.number(&format!("{p}/NumPoints"))? as usize;
    let (extent, xy) = m.quantity(&format!("{p}/Extent"))?;
    let Item::Doubles(start, len) = m.get(&format!("{p}/Array"))? else {
        return malformed("the profile's Array is no double array");
    };
    Ok(Layout {
        start: start + 5.min(*len),
        end: start + len,
        nx,
        ny: 1,
        steps: [step(extent, nx); 2],
        xy,
        scale: m.quantity(&format!("{p}/DataScale"))?,
        doubles: true,
    })
}

fn map_layout(m: &Manifest) -> FResult<Layout> {
    let name = m
        .first("/MetaData/PrimaryData2D")
        .or_else(|| m.first("/MetaData/2D_Channels/Height"))
        .ok_or_else(|| FormatError::Malformed("no 2-D height channel".into()))?;
    let p = format!("/2D_Data/{name}");
    let Item::Matrix(start, len, nx, ny) = m.get(&format!("{p}/Matrix"))? else {
        return unsupported("a 2-D channel without a Matrix");
    };
    let (ey, uy) = m.quantity(&format!("{p}/Dimension1Extent"))?;
    let (ex, xy) = m.quantity(&format!("{p}/Dimension2Extent"))?;
    let to = uy.metres().zip(xy.metres()).map_or(1.0, |(a, b)| a / b);
    Ok(Layout {
        start: *start,
        end: start + len,
        nx: *nx,
        ny: *ny,
        steps: [step(ex, *nx), step(ey * to, *ny)],
        xy,
        scale: m.quantity(&format!("{p}/DataScale"))?,
        doubles: false,
    })
}

/// Reads the height channel of an OPDx file (a profile or a map).
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    if !bytes.starts_with(MAGIC) {
        return malformed("missing the `VCA DATA` magic");
    }
    let mut items_read = HashMap::new();
    let mut c = Fields::le(bytes).cursor(MAGIC.len());
    items(&mut c, "", &mut items_read, 0)?;
    let m = Manifest(items_read);
    let l = if m.is_profile() {
        profile_layout(&m)?
    } else {
        map_layout(&m)?
    };
    let (nx, ny) = (l.nx, l.ny);
    if nx < 2 || ny == 0 {
        return malformed(format!("{nx} × {ny} points"));
    }
    let width = if l.doubles { 8 } else { 4 };
    let data = bytes.get(l.start..l.end).unwrap_or_default();
    let need = nx.checked_mul(ny).and_then(|n| n.checked_mul(width));
    if need.is_none_or(|n| data.len() < n) {
        return malformed(format!(
            "{nx} × {ny} values of {width} bytes do not fit in the data's {} bytes",
            data.len()
        ));
    }
    let (scale, zu) = l.scale;
    let to = zu.metres().zip(l.xy.metres()).map_or(1.0, |(a, b)| a / b);
    let heights = data
        .chunks_exact(width)
        .take(nx * ny)
        .map(|c| {
            let v = if l.doubles {
                f64::from_le_bytes(c.try_into().expect("8 bytes"))
            } else {
                f64::from(f32::from_le_bytes(c.try_into().expect("4 bytes")))
            };
            v * scale * to
        })
        .collect();
    let [dx, dy] = l.steps;
    if !(dx.is_finite() && dx > 0.0 && dy.is_finite() && dy > 0.0) {
        return malformed(format!("the steps {dx} × {dy} are not positive"));
    }
    Ok(HeightField::from_vec([nx, ny], heights)?
        .with_spacing([dx, dy])?
        .with_units(Units { xy: l.xy, z: l.xy }))
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "Bruker Dektak OPDx (.opdx)",
    extensions: &["opdx"],
    height: Access::Read,
    notes: "Vision64 item tree: a surface profile's height channel (f64 × DataScale, step Extent / (n − 1)) as a one-row profile, or the primary 2-D height channel (f32 matrix)",
    magic: Magic::Starts(&[MAGIC]),
    codec: Some(Codec::new(|b, _| read_height(b))),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    fn name(s: &str) -> Vec<u8> {
        let mut b = (s.len() as u32).to_le_bytes().to_vec();
        b.extend(s.as_bytes());
        b
    }

    fn item(n: &str, kind: u8, body: &[u8]) -> Vec<u8> {
        let mut b = name(n);
        b.push(kind);
        b.extend(body);
        b
    }

    fn sized(body: &[u8]) -> Vec<u8> {
        let mut b = vec![4u8];
        b.extend((body.len() as u32).to_le_bytes());
        b.extend(body);
        b
    }

    fn container(n: &str, children: &[Vec<u8>]) -> Vec<u8> {
        let mut inner: Vec<u8> = children.concat();
        inner.extend(item("", 0x7F, &[]));
        inner.extend([0, 0]);
        item(n, 0x7D, &sized(&inner))
    }

    fn quantity(n: &str, v: f64, symbol: &str) -> Vec<u8> {
        let mut q = v.to_le_bytes().to_vec();
        q.extend(name("Length"));
        q.extend(name(symbol));
        item(n, 0x13, &sized(&q))
    }

    /// A profile of 3 points over 2 µm, heights in nm.
    fn file(values: &[f64]) -> Vec<u8> {
        let mut array = name("double[]");
        let mut data = vec![0u8; 5];
        data.extend(values.iter().flat_map(|v| v.to_le_bytes()));
        array.extend(sized(&data));
        let mut list = name("list");
        list.extend(sized(&name("Raw")));
        let mut f = MAGIC.to_vec();
        f.extend(container(
            "MetaData",
            &[
                item(
                    "DataKind",
                    0x12,
                    &[&[1u8, 15][..], b"Surface Profile"].concat(),
                ),
                item(
                    "1D_Channels",
                    0x7D,
                    &sized(
                        &[item("Height", 0x42, &list), item("", 0x7F, &[]), vec![0, 0]].concat(),
                    ),
                ),
            ],
        ));
        f.extend(container(
            "1D_Data",
            &[container(
                "Raw",
                &[
                    item("NumPoints", 0x07, &3u32.to_le_bytes()),
                    quantity("Extent", 2.0, "µm"),
                    quantity("DataScale", 1.0, "nm"),
                    item("Array", 0x40, &array),
                ],
            )],
        ));
        f
    }

    #[test]
    fn reads_a_profile_scaled_to_the_lateral_unit() {
        let h = read_height(&file(&[1000.0, 2000.0, -500.0])).unwrap();
        assert_eq!(h.dims(), [3, 1]);
        assert_eq!(h.spacing(), [1.0, 1.0]);
        assert_eq!(h.units().z, LengthUnit::Um);
        let z: Vec<f64> = h.data().iter().map(|v| (v * 1e6).round() / 1e6).collect();
        assert_eq!(z, [1.0, 2.0, -0.5]);
    }

    #[test]
    fn truncation_is_refused() {
        let good = file(&[1.0, 2.0, 3.0]);
        for cut in MAGIC.len() + 1..good.len() {
            assert!(read_height(&good[..cut]).is_err(), "cut at {cut}");
        }
        assert!(read_height(b"VCA DATA").is_err());
    }
}
