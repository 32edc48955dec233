//! Digital Surf MountainsMap documents (`.mnt`), read: the measured surfaces
//! they keep (the original measurement; the layers derived from it are
//! recomputed by Mountains and not stored).
//!
//! An `.mnt` file is an OLE compound file (MS-CFB; read with the `cfb` crate)
//! holding four streams: `ScopedContents` (the document), `XmlHeader` (the
//! software's name, build date and the operators the document used, as an MFC
//! `CArchive` UTF-16 string), `ScopedResults` and `ImagePreview` (not read).
//!
//! `ScopedContents` is its own length (u64) and then a tree of TLV entries —
//! tag (u16), size (u64), then a value or further entries, all little-endian;
//! a text is a byte 0x04 and UTF-16 characters. Under the main entry (tag 1),
//! the software's version (0xC8) and serial number (0xCB), and the contents
//! (0x2BD) holding the document's object list, whose entries each have an
//! extra u64 before them. Every object is a class number (entry 1 → 1), a body
//! (2) and a GUID (3). A measured surface (class 9012) has a header (title,
//! GUID) and the measurement (class 9062): a grid (its name, one axis per
//! lateral direction: the step, its unit, the display unit, the origin in the
//! display unit and the number of points; the optional mask of unmeasured
//! points, class 9056), the heights (class 9049) and the height axis (the step
//! per count, its unit, the display unit and the origin).
//!
//! The heights are i32 (or i16) counts, row by row with x fastest, in
//! zlib-compressed blocks after the array's byte count (u64): each block is
//! its first element (u64), its number of elements (u32), its compressed size
//! (u32) and the zlib stream. A height is `count × step + origin`, in the
//! height axis's display unit; the mask is an image of (nx + 2) × (ny + 2)
//! bytes with a one-pixel border, in which 9 marks a measured point (anything
//! else is read as missing: NaN). Lateral lengths are in the x axis's unit.
//!
//! The layout was learnt from SurfaceTopography's `MNT.py` (1.27) and checked
//! on its two example files (one with unmeasured points); sizes, heights and
//! masks are compared with SurfaceTopography's reader in
//! `python/tests/reference/check_instruments.py`.

use std::io::{Cursor, Read};

use asperity_core::{HeightField, LengthUnit, Units};

use crate::channel::{Channel, ChannelInfo, pick};
use crate::error::{FResult, FormatError, malformed};
use crate::sur::length_unit;
use crate::format::{Access, Codec, Magic, Registration};

/// An OLE compound file's signature (MS-CFB §2.2).
pub(crate) const MAGIC: &[u8] = b"\xd0\xcf\x11\xe0\xa1\xb1\x1a\xe1";

/// Class numbers of the document's objects.
const CLASS_SURFACE: u32 = 9012;
const CLASS_MEASUREMENT: u32 = 9062;
const CLASS_MASK: u32 = 9056;
const CLASS_HEIGHTS: u32 = 9049;
const CLASS_MASK_IMAGE: u32 = 9048;

/// The mask's value for a measured point.
const MEASURED: u8 = 9;
/// The tag of the nameless entries that group a level's base part.
const BASE: u16 = 0xFFFF;

fn bad(msg: impl Into<String>) -> FormatError {
    FormatError::Malformed(msg.into())
}

/// One level of the TLV tree: its entries (tag and value) in file order.
struct Node<'a>(Vec<(u16, &'a [u8])>);

impl<'a> Node<'a> {
    /// The entries of `data`; `prefixed`: each entry has a u64 before it (the
    /// document's object list). An entry longer than what is left is refused.
    fn parse(data: &'a [u8], prefixed: bool) -> FResult<Node<'a>> {
        let skip = if prefixed { 8 } else { 0 };
        let mut entries = Vec::new();
        let mut at = 0;
        while at < data.len() {
            let head = data
                .get(at + skip..at + skip + 10)
                .ok_or_else(|| bad("an entry of the document is cut short (truncated?)"))?;
            let tag = u16::from_le_bytes([head[0], head[1]]);
            let size = u64::from_le_bytes(head[2..10].try_into().expect("8 bytes"));
            let start = at + skip + 10;
            let end = usize::try_from(size)
                .ok()
                .and_then(|s| start.checked_add(s))
                .filter(|&end| end <= data.len())
                .ok_or_else(|| {
                    bad(format!(
                        "entry {tag:#06x} of {size} bytes does not fit in the {} left (truncated?)",
                        data.len() - start
                    ))
                })?;
            entries.push((tag, &data[start..end]));
            at = end;
        }
        Ok(Node(entries))
    }

    /// The value of the first entry tagged `tag`.
    fn raw(&self, tag: u16) -> Option<&'a [u8]> {
        self.0.iter().find(|(t, _)| *t == tag).map(|&(_, v)| v)
    }

    /// The entries under `tag`, if there is such an entry.
    fn node(&self, tag: u16) -> FResult<Option<Node<'a>>> {
        self.raw(tag).map(|v| Node::parse(v, false)).transpose()
    }

    /// The entries at the end of a path of tags.
    fn path(&self, tags: &[u16]) -> FResult<Option<Node<'a>>> {
        let mut node = Node(self.0.clone());
        for &tag in tags {
            match node.node(tag)? {
                Some(n) => node = n,
                None => return Ok(None),
            }
        }
        Ok(Some(node))
    }

    /// A fixed-size value; one of another size is ignored, as if absent.
    fn fixed<const N: usize>(&self, tag: u16) -> Option<[u8; N]> {
        self.raw(tag).and_then(|v| v.try_into().ok())
    }

    fn u32(&self, tag: u16) -> Option<u32> {
        self.fixed(tag).map(u32::from_le_bytes)
    }

    fn i32(&self, tag: u16) -> Option<i32> {
        self.fixed(tag).map(i32::from_le_bytes)
    }

    fn f64(&self, tag: u16) -> Option<f64> {
        self.fixed(tag).map(f64::from_le_bytes)
    }

    /// A text entry: 0x04, then UTF-16 (trailing NULs dropped).
    fn text(&self, tag: u16) -> Option<String> {
        let v = self.raw(tag)?;
        let (&marker, chars) = v.split_first()?;
        if marker != 4 || chars.len() % 2 != 0 {
            return None;
        }
        let units: Vec<u16> = chars
            .chunks_exact(2)
            .map(|c| u16::from_le_bytes([c[0], c[1]]))
            .collect();
        Some(
            String::from_utf16_lossy(&units)
                .trim_end_matches('\0')
                .to_string(),
        )
    }

    /// An object's class number (entry 1 → 1).
    fn class(&self) -> FResult<Option<u32>> {
        Ok(self.node(1)?.and_then(|c| c.u32(1)))
    }
}

/// The streams asperity reads.
struct Streams {
    contents: Vec<u8>,
    xml: Option<Vec<u8>>,
}

/// Reads the compound file's `ScopedContents` and `XmlHeader` streams.
fn streams(bytes: &[u8]) -> FResult<Streams> {
    if !bytes.starts_with(MAGIC) {
        return malformed("not an OLE compound file (its signature is missing)");
    }
    let mut file = cfb::CompoundFile::open(Cursor::new(bytes))
        .map_err(|e| bad(format!("the OLE compound file is damaged: {e}")))?;
    let mut read = |name: &str| -> FResult<Option<Vec<u8>>> {
        if !file.is_stream(name) {
            return Ok(None);
        }
        let stream = file
            .open_stream(name)
            .map_err(|e| bad(format!("stream {name}: {e}")))?;
        // A stream cannot hold more than the file: a larger length is damage,
        // refused before anything is sized by it.
        let len = stream.len();
        if len > bytes.len() as u64 {
            return malformed(format!(
                "stream {name} claims {len} bytes in a file of {}",
                bytes.len()
            ));
        }
        let mut out = Vec::new();
        stream
            .take(len)
            .read_to_end(&mut out)
            .map_err(|e| bad(format!("stream {name}: {e}")))?;
        Ok(Some(out))
    };
    let contents = read("ScopedContents")?.ok_or_else(|| {
        bad("the compound file has no ScopedContents stream: not a Mountains document")
    })?;
    let xml = read("XmlHeader")?;
    Ok(Streams { contents, xml })
}

/// One axis: its step (per grid point or per count) in `unit`, and its
/// origin in `display` units.
#[derive(Clone, Debug)]
struct Scale {
    step: f64,
    unit: String,
    display: String,
    origin: f64,
}

impl Scale {
    fn read(node: &Node<'_>, axis: &str) -> FResult<Scale> {
        let step = node.f64(1).filter(|s| s.is_finite() && *s != 0.0);
        let unit = node.text(2).filter(|u| !u.is_empty());
        let (Some(step), Some(unit)) = (step, unit) else {
            return malformed(format!("the {axis} axis has no step or no unit"));
        };
        let display = node
            .text(3)
            .filter(|u| !u.is_empty())
            .unwrap_or(unit.clone());
        let origin = node.f64(5).filter(|o| o.is_finite()).unwrap_or(0.0);
        Ok(Scale {
            step,
            unit,
            display,
            origin,
        })
    }
}

/// The factor from `from` to `to` units (1 where either is no length).
fn factor(from: &str, to: &str) -> f64 {
    let ((fu, ff), (tu, tf)) = (length_unit(from), length_unit(to));
    match (fu.metres(), tu.metres()) {
        (Some(f), Some(t)) => f * ff / (t * tf),
        _ => 1.0,
    }
}

/// A measured surface of the document.
struct Surface<'a> {
    name: String,
    title: Option<String>,
    dims: [usize; 2],
    x: Scale,
    y: Scale,
    z: Scale,
    counts: [Option<i32>; 2],
    heights: Array<'a>,
    mask: Option<Array<'a>>,
}

/// A compressed array: its number of elements and its data.
struct Array<'a> {
    count: usize,
    data: &'a [u8],
}

impl<'a> Array<'a> {
    fn read(node: &Node<'a>, class: u32, what: &str) -> FResult<Array<'a>> {
        if node.class()? != Some(class) {
            return malformed(format!("the {what} are not an array of class {class}"));
        }
        let body = node
            .node(2)?
            .ok_or_else(|| bad(format!("the {what} have no array")))?;
        match (body.u32(1), body.raw(2)) {
            (Some(count), Some(data)) => Ok(Array {
                count: count as usize,
                data,
            }),
            _ => malformed(format!("the {what} have no count or no data")),
        }
    }

    /// Decompresses the blocks into one buffer of `count` elements; returns
    /// it and the element size.
    fn decode(&self, what: &str) -> FResult<(Vec<u8>, usize)> {
        let head = self
            .data
            .get(..8)
            .ok_or_else(|| bad(format!("the {what} have no byte count (truncated?)")))?;
        let total = u64::from_le_bytes(head.try_into().expect("8 bytes"));
        let size = (self.count > 0)
            .then(|| total / self.count as u64)
            .filter(|s| matches!(s, 1 | 2 | 4) && total % self.count as u64 == 0)
            .ok_or_else(|| {
                bad(format!(
                    "the {what}: {total} bytes for {} elements",
                    self.count
                ))
            })? as usize;
        let total = self.count * size;
        let mut out = vec![0u8; total];
        let mut filled = Vec::new();
        let mut at = 8;
        while at < self.data.len() {
            let h = self
                .data
                .get(at..at + 16)
                .ok_or_else(|| bad(format!("a block of the {what} is cut short (truncated?)")))?;
            let first = u64::from_le_bytes(h[..8].try_into().expect("8 bytes"));
            let n = u32::from_le_bytes(h[8..12].try_into().expect("4 bytes")) as usize;
            let packed = u32::from_le_bytes(h[12..16].try_into().expect("4 bytes")) as usize;
            let stream = self
                .data
                .get(at + 16..at + 16 + packed)
                .ok_or_else(|| bad(format!("a block of the {what} is cut short (truncated?)")))?;
            let start = usize::try_from(first)
                .ok()
                .and_then(|f| f.checked_mul(size))
                .filter(|&s| {
                    n.checked_mul(size)
                        .and_then(|b| s.checked_add(b))
                        .is_some_and(|end| end <= total)
                })
                .ok_or_else(|| {
                    bad(format!(
                        "a block of the {what} (elements {first}+{n}) lies outside its {} elements",
                        self.count
                    ))
                })?;
            inflate(stream, &mut out[start..start + n * size], what)?;
            filled.push((start, start + n * size));
            at += 16 + packed;
        }
        filled.sort_unstable();
        let mut end = 0;
        for (s, e) in filled {
            if s != end {
                return malformed(format!("the {what}' blocks leave gaps or overlap"));
            }
            end = e;
        }
        if end != total {
            return malformed(format!("the {what}' blocks hold {end} of {total} bytes"));
        }
        Ok((out, size))
    }
}

/// Inflates one zlib stream into exactly `out`.
fn inflate(stream: &[u8], out: &mut [u8], what: &str) -> FResult<()> {
    let mut z = flate2::read::ZlibDecoder::new(stream);
    z.read_exact(out)
        .map_err(|e| bad(format!("a block of the {what} does not inflate: {e}")))?;
    let mut extra = [0u8; 1];
    if z.read(&mut extra)
        .map_err(|e| bad(format!("a block of the {what}: {e}")))?
        != 0
    {
        return malformed(format!(
            "a block of the {what} inflates to more than it declares"
        ));
    }
    Ok(())
}

/// The measured surfaces (class 9012) of the document.
fn surfaces(contents: &[u8]) -> FResult<Vec<Surface<'_>>> {
    let body = contents
        .get(8..)
        .ok_or_else(|| bad("the ScopedContents stream is shorter than its length field"))?;
    let top = Node::parse(body, false)?;
    let objects = top
        .path(&[1, 0x2BD, 2])?
        .and_then(|d| d.raw(1))
        .ok_or_else(|| bad("the document has no object list"))?;
    let mut out = Vec::new();
    for (tag, object) in Node::parse(objects, true)?.0 {
        let object = Node::parse(object, false)?;
        if tag != 1 || object.class()? != Some(CLASS_SURFACE) {
            continue;
        }
        if let Some(body) = object.raw(2) {
            out.push(surface(&Node::parse(body, false)?)?);
        }
    }
    if out.is_empty() {
        return malformed("the document holds no measured surface");
    }
    Ok(out)
}

/// Reads one measured surface's grid, axes and arrays.
fn surface<'a>(body: &Node<'a>) -> FResult<Surface<'a>> {
    let title = body.path(&[BASE])?.and_then(|h| h.text(4));
    let measurement = body
        .node(1)?
        .filter(|m| m.class().ok().flatten() == Some(CLASS_MEASUREMENT))
        .ok_or_else(|| bad("a surface has no measurement (class 9062)"))?;
    let data = measurement
        .node(2)?
        .ok_or_else(|| bad("the measurement has no body"))?
        .node(BASE)?
        .ok_or_else(|| bad("the measurement has no data"))?;
    let grid = data
        .node(BASE)?
        .ok_or_else(|| bad("the measurement has no grid"))?;
    let name = grid
        .path(&[BASE, BASE])?
        .and_then(|d| d.text(1))
        .filter(|n| !n.is_empty());
    let lateral = |tag: u16, axis: &str| -> FResult<(Scale, usize)> {
        let a = grid
            .path(&[tag, BASE])?
            .ok_or_else(|| bad(format!("the grid has no {axis} axis")))?;
        let scale = a
            .node(BASE)?
            .ok_or_else(|| bad(format!("the {axis} axis has no scale")))?;
        let n = a
            .u32(1)
            .filter(|&n| n > 0)
            .ok_or_else(|| bad(format!("the {axis} axis has no number of points")))?;
        Ok((Scale::read(&scale, axis)?, n as usize))
    };
    let (x, nx) = lateral(1, "x")?;
    let (y, ny) = lateral(2, "y")?;
    let z_axis = data
        .node(2)?
        .ok_or_else(|| bad("the measurement has no height axis"))?;
    let z = Scale::read(
        &z_axis
            .node(BASE)?
            .ok_or_else(|| bad("the height axis has no scale"))?,
        "height",
    )?;
    let heights = Array::read(
        &data
            .node(1)?
            .ok_or_else(|| bad("the measurement has no heights"))?,
        CLASS_HEIGHTS,
        "heights",
    )?;
    if Some(heights.count) != nx.checked_mul(ny) {
        return malformed(format!(
            "{} heights for a grid of {nx} × {ny}",
            heights.count
        ));
    }
    let mask = match grid.node(3)? {
        Some(m) if m.class()? == Some(CLASS_MASK) => {
            let m = m.node(2)?.ok_or_else(|| bad("the mask has no body"))?;
            if (m.u32(1), m.u32(2)) != (Some(nx as u32), Some(ny as u32)) {
                return malformed("the mask's size is not the grid's");
            }
            let array = m.node(5)?.ok_or_else(|| bad("the mask has no image"))?;
            let image = Array::read(&array, CLASS_MASK_IMAGE, "mask")?;
            // The image is the grid with a one-pixel border; checked before
            // anything is sized by its count.
            if Some(image.count) != (nx + 2).checked_mul(ny + 2) {
                return malformed(format!(
                    "the mask image has {} points, the grid with its border {} × {}",
                    image.count,
                    nx + 2,
                    ny + 2
                ));
            }
            Some(image)
        }
        _ => None,
    };
    Ok(Surface {
        name: name.or(title.clone()).unwrap_or_else(|| "Default".into()),
        title,
        dims: [nx, ny],
        x,
        y,
        z,
        counts: [z_axis.i32(1), z_axis.i32(2)],
        heights,
        mask,
    })
}

/// Whether a surface's heights are lengths (not an intensity or a colour).
fn is_height(s: &Surface<'_>) -> bool {
    length_unit(&s.z.display).0 != LengthUnit::None
}

/// The surfaces as channels (by their names).
fn channel_list(all: &[Surface<'_>]) -> Vec<ChannelInfo> {
    all.iter()
        .enumerate()
        .map(|(index, s)| ChannelInfo {
            index,
            name: s.name.clone(),
            height: is_height(s),
        })
        .collect()
}

/// The document's measured surfaces as channels.
pub(crate) fn channels(bytes: &[u8]) -> FResult<Vec<ChannelInfo>> {
    let s = streams(bytes)?;
    Ok(channel_list(&surfaces(&s.contents)?))
}

/// The points of the document's largest surface (for the memory estimate,
/// before anything is inflated).
pub(crate) fn declared_points(bytes: &[u8]) -> FResult<u128> {
    let s = streams(bytes)?;
    Ok(surfaces(&s.contents)?
        .iter()
        .map(|s| s.dims[0] as u128 * s.dims[1] as u128)
        .max()
        .unwrap_or(0))
}

/// Reads the surface `choice` names (by default the first whose heights are
/// lengths).
pub(crate) fn read_channel(bytes: &[u8], choice: Option<&Channel>) -> FResult<HeightField> {
    let streams = streams(bytes)?;
    let all = surfaces(&streams.contents)?;
    let s = &all[pick(&channel_list(&all), choice)?];
    let [nx, ny] = s.dims;
    let (counts, size) = s.heights.decode("heights")?;
    let (z_unit, _) = length_unit(&s.z.display);
    let step = s.z.step * factor(&s.z.unit, &s.z.display);
    let mut data: Vec<f64> = match size {
        2 => counts
            .chunks_exact(2)
            .map(|c| f64::from(i16::from_le_bytes([c[0], c[1]])) * step + s.z.origin)
            .collect(),
        4 => counts
            .chunks_exact(4)
            .map(|c| f64::from(i32::from_le_bytes([c[0], c[1], c[2], c[3]])) * step + s.z.origin)
            .collect(),
        _ => return malformed(format!("heights of {size} byte(s) each")),
    };
    if let Some(mask) = &s.mask {
        let (image, size) = mask.decode("mask")?;
        if size != 1 {
            return malformed(format!("a mask of {size}-byte values"));
        }
        for (row, line) in data.chunks_exact_mut(nx).enumerate() {
            let marks = &image[(row + 1) * (nx + 2) + 1..][..nx];
            for (h, &m) in line.iter_mut().zip(marks) {
                if m != MEASURED {
                    *h = f64::NAN;
                }
            }
        }
    }
    let (xy_unit, _) = length_unit(&s.x.unit);
    let dx = s.x.step;
    let dy = s.y.step * factor(&s.y.unit, &s.x.unit);
    let origin = [
        s.x.origin * factor(&s.x.display, &s.x.unit),
        s.y.origin * factor(&s.y.display, &s.x.unit),
    ];
    Ok(HeightField::from_vec([nx, ny], data)?
        .with_spacing([dx, dy])?
        .with_origin(origin)?
        .with_units(Units {
            xy: xy_unit,
            z: z_unit,
        }))
}

/// The XML header's `CArchive` string: FF FE FF, a length (u8, or u16 after
/// 0xFF, or u32 after 0xFFFF) and UTF-16 characters.
fn archive_string(data: &[u8]) -> Option<String> {
    let rest = data.strip_prefix(b"\xff\xfe\xff")?;
    let (len, at) = match *rest.first()? {
        0xFF => match u16::from_le_bytes([*rest.get(1)?, *rest.get(2)?]) {
            0xFFFF => (
                u32::from_le_bytes(rest.get(3..7)?.try_into().ok()?) as usize,
                7,
            ),
            n => (usize::from(n), 3),
        },
        n => (usize::from(n), 1),
    };
    let chars = rest.get(at..at + len.checked_mul(2)?)?;
    let units: Vec<u16> = chars
        .chunks_exact(2)
        .map(|c| u16::from_le_bytes([c[0], c[1]]))
        .collect();
    Some(String::from_utf16_lossy(&units))
}

/// The document's metadata: each surface's name, title and axes, then the
/// software that wrote it (version, serial number, name, build date and the
/// operators the document applies).
pub(crate) fn metadata(bytes: &[u8]) -> FResult<Vec<(String, String)>> {
    let streams = streams(bytes)?;
    let mut out = Vec::new();
    for (k, s) in surfaces(&streams.contents)?.iter().enumerate() {
        let p = format!("surface {k} ");
        out.push((format!("{p}name"), s.name.clone()));
        if let Some(t) = &s.title {
            out.push((format!("{p}title"), t.clone()));
        }
        for (axis, scale) in [("x", &s.x), ("y", &s.y), ("z", &s.z)] {
            out.push((
                format!("{p}{axis} step"),
                format!("{} {}", scale.step, scale.unit),
            ));
            out.push((
                format!("{p}{axis} origin"),
                format!("{} {}", scale.origin, scale.display),
            ));
        }
        if let [Some(lo), Some(hi)] = s.counts {
            out.push((format!("{p}z counts"), format!("{lo} to {hi}")));
        }
    }
    let top = Node::parse(&streams.contents[8..], false)?;
    if let Some(main) = top.node(1)? {
        if let Some(v) = main.node(0xC8)? {
            let parts: Vec<String> = (1..=4)
                .filter_map(|t| v.u32(t))
                .map(|n| n.to_string())
                .collect();
            if parts.len() == 4 {
                out.push(("software version".into(), parts.join(".")));
            }
        }
        if let Some(serial) = main.text(0xCB) {
            out.push(("software serial number".into(), serial));
        }
    }
    if let Some(text) = streams.xml.as_deref().and_then(archive_string)
        && let Ok(doc) = roxmltree::Document::parse(&text)
    {
        let root = doc.root_element();
        let field = |name: &str| {
            root.children()
                .find(|n| n.has_tag_name(name))
                .and_then(|n| n.text())
                .map(str::to_owned)
        };
        for (key, name) in [("software", "ProductName"), ("build date", "BuildDate")] {
            if let Some(v) = field(name) {
                out.push((key.into(), v));
            }
        }
        let operators: Vec<&str> = root
            .descendants()
            .filter(|n| n.has_tag_name("Operator"))
            .filter_map(|n| n.text())
            .collect();
        if !operators.is_empty() {
            out.push(("operators".into(), operators.join(", ")));
        }
    }
    Ok(out)
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "Digital Surf MountainsMap (.mnt)",
    extensions: &["mnt"],
    height: Access::Read,
    notes: "the document's measured surfaces as channels (by name): int32/int16 counts × the height step + origin in the height axis's display unit, steps in the x axis's unit; the mask's unmeasured points read as missing; surface names, axes and the software's version and operators kept as metadata",
    magic: Magic::Starts(&[MAGIC]),
    codec: Some(Codec::new(read_channel)
        .channels(channels)
        .metadata(metadata)
        .declared(|b| declared_points(b).map(crate::pixel_bytes))),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use std::io::Write;

    use super::*;

    fn entry(tag: u16, value: &[u8]) -> Vec<u8> {
        let mut e = tag.to_le_bytes().to_vec();
        e.extend((value.len() as u64).to_le_bytes());
        e.extend(value);
        e
    }

    fn text(s: &str) -> Vec<u8> {
        let mut t = vec![4u8];
        t.extend(s.encode_utf16().flat_map(u16::to_le_bytes));
        t
    }

    fn object(class: u32, body: &[u8]) -> Vec<u8> {
        [entry(1, &entry(1, &class.to_le_bytes())), entry(2, body)].concat()
    }

    fn scale(step: f64, unit: &str, display: &str, origin: f64) -> Vec<u8> {
        [
            entry(1, &step.to_le_bytes()),
            entry(2, &text(unit)),
            entry(3, &text(display)),
            entry(5, &origin.to_le_bytes()),
        ]
        .concat()
    }

    /// An array of `class` in two zlib blocks, the second first.
    fn array(class: u32, elements: &[u8], size: usize) -> Vec<u8> {
        let count = elements.len() / size;
        let half = count / 2;
        let mut data = (elements.len() as u64).to_le_bytes().to_vec();
        for (first, part) in [
            (half, &elements[half * size..]),
            (0, &elements[..half * size]),
        ] {
            let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
            z.write_all(part).unwrap();
            let packed = z.finish().unwrap();
            data.extend((first as u64).to_le_bytes());
            data.extend(((part.len() / size) as u32).to_le_bytes());
            data.extend((packed.len() as u32).to_le_bytes());
            data.extend(packed);
        }
        object(
            class,
            &[entry(1, &(count as u32).to_le_bytes()), entry(2, &data)].concat(),
        )
    }

    fn lateral(n: u32, step: f64, unit: &str) -> Vec<u8> {
        let axis = [
            entry(BASE, &scale(step, unit, "mm", 0.5)),
            entry(1, &n.to_le_bytes()),
        ]
        .concat();
        entry(BASE, &axis)
    }

    /// The ScopedContents stream of a document with one surface of
    /// `nx × ny` i32 counts (and a mask image, if given).
    fn contents(nx: u32, ny: u32, counts: &[i32], mask: Option<&[u8]>) -> Vec<u8> {
        let mut grid = [
            entry(BASE, &entry(BASE, &entry(1, &text("Height")))),
            entry(1, &lateral(nx, 2.0, "µm")),
            entry(2, &lateral(ny, 3000.0, "nm")),
        ]
        .concat();
        if let Some(m) = mask {
            let body = [
                entry(1, &nx.to_le_bytes()),
                entry(2, &ny.to_le_bytes()),
                entry(5, &array(CLASS_MASK_IMAGE, m, 1)),
            ]
            .concat();
            grid.extend(entry(3, &object(CLASS_MASK, &body)));
        }
        let bytes: Vec<u8> = counts.iter().flat_map(|c| c.to_le_bytes()).collect();
        let measurement = [
            entry(BASE, &grid),
            entry(1, &array(CLASS_HEIGHTS, &bytes, 4)),
            entry(
                2,
                &[
                    entry(BASE, &scale(10.0, "nm", "µm", 1.5)),
                    entry(1, &(-5i32).to_le_bytes()),
                ]
                .concat(),
            ),
        ]
        .concat();
        let surface = [
            entry(BASE, &entry(4, &text("1 : Height"))),
            entry(1, &object(CLASS_MEASUREMENT, &entry(BASE, &measurement))),
        ]
        .concat();
        let mut list = 0u64.to_le_bytes().to_vec();
        list.extend(entry(1, &object(CLASS_SURFACE, &surface)));
        let main = [
            entry(
                0xC8,
                &(1..=4u16)
                    .flat_map(|t| entry(t, &u32::from(t).to_le_bytes()))
                    .collect::<Vec<_>>(),
            ),
            entry(0x2BD, &entry(2, &entry(1, &list))),
        ]
        .concat();
        let body = entry(1, &main);
        [(body.len() as u64).to_le_bytes().to_vec(), body].concat()
    }

    /// `contents` in an OLE compound file (version 3: 512-byte sectors).
    fn compound(contents: &[u8]) -> Vec<u8> {
        let mut file =
            cfb::CompoundFile::create_with_version(cfb::Version::V3, Cursor::new(Vec::new()))
                .unwrap();
        file.create_stream("ScopedContents")
            .unwrap()
            .write_all(contents)
            .unwrap();
        file.flush().unwrap();
        file.into_inner().into_inner()
    }

    use crate::error::refused as err;

    #[test]
    fn counts_times_step_plus_origin_in_the_display_unit_with_the_mask() {
        // 3 × 2 points; the mask (5 × 4 with its border) leaves (1, 1) unmeasured.
        let mut mask = vec![22u8; 5 * 4];
        for (x, y) in [(0, 0), (1, 0), (2, 0), (0, 1), (2, 1)] {
            mask[(y + 1) * 5 + x + 1] = MEASURED;
        }
        let file = compound(&contents(3, 2, &[0, 100, -200, 300, 7, 500], Some(&mask)));
        let h = read_channel(&file, None).unwrap();
        assert_eq!(h.dims(), [3, 2]);
        assert_eq!(h.units().xy, LengthUnit::Um);
        assert_eq!(h.units().z, LengthUnit::Um);
        // x: 2 µm; y: 3000 nm = 3 µm; origins 0.5 mm = 500 µm.
        let near = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() + (a[1] - b[1]).abs() < 1e-9;
        assert!(near(h.spacing(), [2.0, 3.0]), "{:?}", h.spacing());
        assert!(near(h.origin(), [500.0, 500.0]), "{:?}", h.origin());
        // 10 nm per count = 0.01 µm, plus 1.5 µm.
        assert!((*h.get(1, 0) - 2.5).abs() < 1e-12);
        assert!((*h.get(2, 0) - -0.5).abs() < 1e-12);
        assert!((*h.get(0, 1) - 4.5).abs() < 1e-12);
        assert!(h.get(1, 1).is_nan());
        let ch = channels(&file).unwrap();
        assert_eq!((ch[0].name.as_str(), ch[0].height), ("Height", true));
        assert_eq!(declared_points(&file).unwrap(), 6);
        let meta = metadata(&file).unwrap();
        assert!(meta.contains(&("surface 0 title".into(), "1 : Height".into())));
        assert!(meta.contains(&("surface 0 z step".into(), "10 nm".into())));
        assert!(meta.contains(&("software version".into(), "1.2.3.4".into())));
    }

    #[test]
    fn truncated_and_damaged_documents_are_refused() {
        let good = contents(3, 2, &[1, 2, 3, 4, 5, 6], None);
        assert!(read_channel(&compound(&good), None).is_ok());
        for cut in 0..good.len() {
            let e = read_channel(&compound(&good[..cut]), None);
            assert!(e.is_err(), "cut at {cut}");
        }
        let file = compound(&good);
        for cut in [0, 8, 100, 511, 600, 1024] {
            assert!(
                read_channel(&file[..cut], None).is_err(),
                "file cut at {cut}"
            );
        }
        let wrong = contents(4, 2, &[1, 2, 3, 4, 5, 6], None);
        assert!(
            err(read_channel(&compound(&wrong), None)).contains("6 heights for a grid of 4 × 2")
        );
        let mut other = cfb::CompoundFile::create(Cursor::new(Vec::new())).unwrap();
        other
            .create_stream("WordDocument")
            .unwrap()
            .write_all(b"x")
            .unwrap();
        other.flush().unwrap();
        let other = other.into_inner().into_inner();
        assert!(err(read_channel(&other, None)).contains("not a Mountains document"));
        assert!(err(read_channel(b"PK\x03\x04 not ole", None)).contains("OLE"));
    }

    #[test]
    fn blocks_that_overflow_or_leave_gaps_are_refused() {
        let counts: Vec<u8> = [1i32, 2, 3, 4]
            .iter()
            .flat_map(|c| c.to_le_bytes())
            .collect();
        let a = array(CLASS_HEIGHTS, &counts, 4);
        let node = Node::parse(&a, false).unwrap();
        let good = Array::read(&node, CLASS_HEIGHTS, "heights").unwrap();
        assert_eq!(good.decode("heights").unwrap().0, counts);
        let refusal = |data: &[u8], count: usize| match (Array { count, data }).decode("heights") {
            Ok(_) => panic!("accepted"),
            Err(e) => format!("{e:?}"),
        };
        // Eight elements declared, four in the blocks.
        let mut short = good.data.to_vec();
        short[..8].copy_from_slice(&32u64.to_le_bytes());
        assert!(refusal(&short, 8).contains("hold 16 of 32 bytes"));
        // A block placed past the end.
        let mut far = good.data.to_vec();
        far[8..16].copy_from_slice(&3u64.to_le_bytes());
        assert!(refusal(&far, 4).contains("outside"));
    }

    /// The fuzz target's committed seed (`fuzz/seeds/mnt/m3x2.mnt`) is a
    /// document this reader reads as built here: 3 × 2, its second row
    /// unmeasured. `fuzz/make_seeds.sh` sets `ASPERITY_WRITE_SEEDS` to write it.
    #[test]
    fn the_fuzz_seed_is_a_document_this_reader_reads() {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/seeds/mnt/m3x2.mnt");
        if std::env::var_os("ASPERITY_WRITE_SEEDS").is_some() {
            let mut mask = vec![22u8; 5 * 4];
            mask[6..9].fill(MEASURED);
            let file = compound(&contents(3, 2, &[0, 100, -200, 300, 7, 500], Some(&mask)));
            std::fs::write(&path, file).unwrap();
        }
        let h = read_channel(&std::fs::read(&path).unwrap(), None).unwrap();
        assert_eq!((h.dims(), h.missing_count()), ([3, 2], 3));
        assert!((*h.get(1, 0) - 2.5).abs() < 1e-12 && h.get(1, 1).is_nan());
    }

    #[test]
    fn the_xml_headers_archive_string_is_read_in_its_three_length_forms() {
        let utf16 = |s: &str| {
            s.encode_utf16()
                .flat_map(u16::to_le_bytes)
                .collect::<Vec<u8>>()
        };
        let short = [b"\xff\xfe\xff\x02".to_vec(), utf16("ab")].concat();
        assert_eq!(archive_string(&short).as_deref(), Some("ab"));
        let long = [b"\xff\xfe\xff\xff\x03\x00".to_vec(), utf16("abc")].concat();
        assert_eq!(archive_string(&long).as_deref(), Some("abc"));
        let huge = [
            b"\xff\xfe\xff\xff\xff\xff\x01\x00\x00\x00".to_vec(),
            utf16("z"),
        ]
        .concat();
        assert_eq!(archive_string(&huge).as_deref(), Some("z"));
        assert_eq!(archive_string(b"\xff\xfe\xff\x09ab"), None);
    }
}
