//! Olympus (Evident) laser-scanning microscope files: `.oir`, and `.poir`
//! (a zip of `.oir` files), read.
//!
//! The layout, as SurfaceTopography's `OIR.py` reads it (after Gwyddion's
//! `oirfile.c`), little-endian: a 96-byte header opening with
//! `OLYMPUSRAWFORMAT`, then chunks, each an i32 size (−1 ends the file) and
//! an i32 type:
//! - 0, a list of metadata blocks filling `size` bytes; 1, one block (per
//!   frame, skipped); each block is a u32 type, eight u32 of header, then
//!   its content — XML texts (u32 length, then the text), and lists of
//!   prefixes and UUIDs;
//! - 2, a BMP preview of `size` bytes (skipped);
//! - 3, a data block: `size` bytes of header (u32 0, u32 image size, the
//!   block's name as a text), then u32 image size, u32 4 and the image;
//! - 5, a spacer of no bytes. Another type ends the chunks.
//!
//! Block 2 (the properties, XML) describes the image: `imageInfo` gives
//! width and height and lists the channels; a channel whose
//! `imageDefinition/imageType` is `HEIGHT` is a topography, its image the
//! data block `{prefix}_{channel id}_0` (the prefix from block 6), u8 or
//! u16 (by `depth`, else `bitCounts` rounded up to bytes) row by row (rows
//! along y, asperity's order). A pixel is `length/x` × `length/y` in the
//! channel's `pixelUnit`s, a count `length/z` in its z unit, each times the
//! microscope configuration's `pixelCalibration` where it gives one; lateral
//! sizes are kept in the z unit (SurfaceTopography's choice). A `.poir`'s
//! channels are its `.oir` members' height channels in order; members with
//! no laser-scanning image are skipped, as SurfaceTopography skips them.
//!
//! No OIR file is public in a repository asperity can reach; checked against
//! SurfaceTopography's reader on files built to this layout.

use std::collections::HashMap;

use asperity_core::{HeightField, LengthUnit, Units};

use crate::Metadata;
use crate::channel::{Channel, ChannelInfo, pick};
use crate::error::{FResult, FormatError, malformed};
use crate::format::{Access, Codec, Magic, Registration};
use crate::zipped;

/// The file's magic.
pub(crate) const MAGIC: &[u8] = b"OLYMPUSRAWFORMAT";
const HEADER_LEN: usize = 96;

/// Metadata block types kept (the others are read past).
const PROPERTIES: u32 = 2;
const TOPOGRAPHY_PREFIX: u32 = 6;

/// A little-endian reader over a byte range that names what it reads.
struct Reader<'a> {
    b: &'a [u8],
    at: usize,
    end: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize, what: &str) -> FResult<&'a [u8]> {
        let stop = self.at.checked_add(n).filter(|&s| s <= self.end);
        let Some(stop) = stop else {
            return malformed(format!(
                "{what} at byte {} runs past its chunk or the file's end (truncated?)",
                self.at
            ));
        };
        let out = &self.b[self.at..stop];
        self.at = stop;
        Ok(out)
    }

    fn u32(&mut self, what: &str) -> FResult<u32> {
        let w = self.take(4, what)?;
        Ok(u32::from_le_bytes([w[0], w[1], w[2], w[3]]))
    }

    /// A text: u32 length, then ASCII (NULs trimmed).
    fn text(&mut self, what: &str) -> FResult<String> {
        let n = self.u32(what)? as usize;
        let t = self.take(n, what)?;
        Ok(String::from_utf8_lossy(t).trim_matches('\0').to_owned())
    }

    /// `n` entries (a u32 count first), each read by `entry`.
    fn list<T>(
        &mut self,
        what: &str,
        mut entry: impl FnMut(&mut Self) -> FResult<T>,
    ) -> FResult<Vec<T>> {
        let n = self.u32(what)?;
        // Every entry holds at least four bytes.
        if n as usize > (self.end - self.at) / 4 {
            return malformed(format!("{what}: {n} entries cannot fit"));
        }
        (0..n).map(|_| entry(self)).collect()
    }
}

/// What the chunks hold: the last properties XML and prefix, and the data
/// blocks by name.
#[derive(Default)]
struct Parsed<'a> {
    properties: Option<String>,
    prefix: Option<String>,
    data: HashMap<String, &'a [u8]>,
}

/// One metadata block; keeps the properties and the topography prefix.
fn block(r: &mut Reader<'_>, out: &mut Parsed<'_>) -> FResult<()> {
    let kind = r.u32("a metadata block's type")?;
    r.take(32, "a metadata block's header")?;
    let t = |r: &mut Reader<'_>| r.text("a metadata text");
    let skip_u32 = |r: &mut Reader<'_>| r.u32("a metadata entry").map(drop);
    match kind {
        1 | 3 | 4 | 14 => {
            t(r)?;
        }
        PROPERTIES => out.properties = Some(t(r)?),
        5 => {
            r.list("lookup tables", |r| t(r).and(t(r)))?;
        }
        TOPOGRAPHY_PREFIX => {
            let prefixes = r.list("the topography prefix", |r| {
                let p = t(r)?;
                skip_u32(r)?;
                Ok(p)
            })?;
            out.prefix = prefixes.into_iter().next();
        }
        7 | 8 | 12 | 13 => {
            r.list("a list of names", |r| t(r).and(skip_u32(r)))?;
        }
        9 => {
            r.list("prefixes", |r| skip_u32(r).and(t(r)).and(t(r)))?;
        }
        10 => {
            r.list("camera entries", |r| {
                t(r).and(skip_u32(r)).and(t(r)).and(t(r))
            })?;
        }
        11 => {
            r.list("lookup tables", |r| t(r).and(t(r)))?;
        }
        other => return malformed(format!("a metadata block of unknown type {other}")),
    }
    Ok(())
}

fn parse(bytes: &[u8]) -> FResult<Parsed<'_>> {
    if !bytes.starts_with(MAGIC) {
        return malformed("missing the `OLYMPUSRAWFORMAT` magic");
    }
    if bytes.len() < HEADER_LEN {
        return malformed("the file ends inside its header (truncated?)");
    }
    let mut r = Reader {
        b: bytes,
        at: HEADER_LEN,
        end: bytes.len(),
    };
    let mut out = Parsed::default();
    loop {
        if r.at == r.end {
            return malformed("the file ends without its end marker (truncated?)");
        }
        let size = r.u32("a chunk's size")? as i32;
        if size == -1 {
            break;
        }
        let size = usize::try_from(size)
            .map_err(|_| FormatError::Malformed(format!("a chunk of {size} bytes")))?;
        let kind = r.u32("a chunk's type")?;
        let chunk =
            |r: &Reader<'_>| {
                let end = r.at.checked_add(size).filter(|&e| e <= r.end).ok_or_else(|| {
                FormatError::Malformed(format!(
                    "a chunk of {size} bytes at byte {} runs past the file's end (truncated?)",
                    r.at
                ))
            })?;
                Ok::<_, FormatError>(Reader {
                    b: bytes,
                    at: r.at,
                    end,
                })
            };
        match kind {
            0 => {
                let mut c = chunk(&r)?;
                while c.at < c.end {
                    block(&mut c, &mut out)?;
                }
                r.at = c.end;
            }
            1 | 2 => r.at = chunk(&r)?.end,
            3 => {
                let mut c = chunk(&r)?;
                c.u32("a data block's header")?;
                let n = c.u32("a data block's size")? as usize;
                let name = c.text("a data block's name")?;
                if c.at != c.end {
                    return malformed(format!("data block {name:?}: its header has extra bytes"));
                }
                r.at = c.end;
                if r.u32("a data block's size")? as usize != n {
                    return malformed(format!("data block {name:?}: two different sizes"));
                }
                r.u32("a data block's marker")?;
                let image = r.take(n, &format!("data block {name:?}"))?;
                out.data.insert(name, image);
            }
            5 => {}
            _ => break,
        }
    }
    Ok(out)
}

/// A height channel of the properties.
struct HeightChannel {
    id: String,
    nx: usize,
    ny: usize,
    depth: usize,
    /// Pixel sizes in the z unit.
    step: [f64; 2],
    /// A count in the z unit.
    z_per_count: f64,
    unit: LengthUnit,
}

/// Olympus's unit names (and the symbols) as asperity's units, with the
/// metres in one.
fn unit(name: &str) -> Option<(LengthUnit, f64)> {
    let u = match name.trim() {
        "NANO_METER" => LengthUnit::Nm,
        "MICRO_METER" => LengthUnit::Um,
        "MILLI_METER" => LengthUnit::Mm,
        "METER" => LengthUnit::M,
        symbol => LengthUnit::parse(symbol).ok()?,
    };
    Some((u, u.metres()?))
}

fn child<'a, 'i>(node: roxmltree::Node<'a, 'i>, tag: &str) -> Option<roxmltree::Node<'a, 'i>> {
    node.children()
        .find(|c| c.is_element() && c.tag_name().name() == tag)
}

fn path<'a, 'i>(node: roxmltree::Node<'a, 'i>, tags: &[&str]) -> Option<roxmltree::Node<'a, 'i>> {
    tags.iter().try_fold(node, |n, t| child(n, t))
}

fn text(node: roxmltree::Node<'_, '_>, tags: &[&str]) -> Option<String> {
    path(node, tags)
        .and_then(|n| n.text())
        .map(|t| t.trim().to_owned())
}

fn number(node: roxmltree::Node<'_, '_>, tags: &[&str], what: &str) -> FResult<f64> {
    let t = text(node, tags)
        .ok_or_else(|| FormatError::Malformed(format!("the properties give no {what}")))?;
    t.parse()
        .ok()
        .filter(|v: &f64| v.is_finite())
        .ok_or_else(|| FormatError::Malformed(format!("{what} {t:?} is not a number")))
}

/// The laser-scanning image's properties: its height channels and metadata.
fn channels_of(properties: &str) -> FResult<(Vec<HeightChannel>, Metadata)> {
    let doc = roxmltree::Document::parse(properties)
        .map_err(|e| FormatError::Malformed(format!("the properties XML: {e}")))?;
    // `lsmimage:imageProperties`: a laser-scanning image (a camera image's
    // properties hold no heights).
    let lsm = |n: &roxmltree::Node<'_, '_>| {
        n.tag_name()
            .namespace()
            .and_then(|uri| n.lookup_prefix(uri))
            == Some("lsmimage")
    };
    let image = doc
        .descendants()
        .find(|n| n.is_element() && n.tag_name().name() == "imageProperties" && lsm(n))
        .ok_or_else(|| {
            FormatError::Unsupported(
                "no laser-scanning image (`lsmimage`) in the properties: no heights".into(),
            )
        })?;
    let mut meta = vec![("Vendor".to_owned(), "Olympus".to_owned())];
    if let Some(name) = text(image, &["microscope", "name"]) {
        meta.push(("Microscope".to_owned(), name));
    }
    if let Some(date) = text(image, &["general", "creationDateTime"]) {
        meta.push(("Created".to_owned(), date));
    }
    let info = child(image, "imageInfo")
        .ok_or_else(|| FormatError::Malformed("the properties have no imageInfo".into()))?;
    let size = |tag: &str| -> FResult<usize> {
        let v = number(info, &[tag], &format!("image {tag}"))?;
        if v >= 1.0 && v <= u32::MAX as f64 && v.fract() == 0.0 {
            Ok(v as usize)
        } else {
            malformed(format!("an image {tag} of {v}"))
        }
    };
    let (nx, ny) = (size("width")?, size("height")?);
    let calibration = path(
        image,
        &["acquisition", "microscopeConfiguration", "pixelCalibration"],
    );
    let mut calibrate = [1.0; 3];
    for (k, axis) in ["x", "y", "z"].into_iter().enumerate() {
        if let Some(c) = calibration.filter(|c| child(*c, axis).is_some()) {
            calibrate[k] = number(c, &[axis], "a pixel calibration")?;
        }
    }
    let mut out = Vec::new();
    let group = path(info, &["phase", "group"]);
    for c in group
        .into_iter()
        .flat_map(|g| g.children())
        .filter(|c| c.is_element() && c.tag_name().name() == "channel")
    {
        if let Some(h) = height_channel(c, [nx, ny], calibrate)? {
            out.push(h);
        }
    }
    Ok((out, meta))
}

/// A `channel` element of the properties, if its image holds heights.
fn height_channel(
    c: roxmltree::Node<'_, '_>,
    [nx, ny]: [usize; 2],
    calibrate: [f64; 3],
) -> FResult<Option<HeightChannel>> {
    let Some(definition) = child(c, "imageDefinition") else {
        return Ok(None);
    };
    if text(definition, &["imageType"]).as_deref() != Some("HEIGHT") {
        return Ok(None);
    }
    let id = c.attribute("id").unwrap_or_default().to_owned();
    // `depth` is the bytes a pixel; `bitCounts` the significant bits.
    let depth = match child(definition, "depth") {
        Some(_) => number(definition, &["depth"], "a pixel depth")?,
        None => ((number(definition, &["bitCounts"], "a bit count")? + 7.0) / 8.0).floor(),
    };
    if depth != 1.0 && depth != 2.0 {
        return Err(FormatError::Unsupported(format!(
            "channel {id}: heights of {depth} bytes a pixel (1 and 2 are read)"
        )));
    }
    let units: Vec<(LengthUnit, f64)> = ["x", "y", "z"]
        .iter()
        .map(|a| {
            let name = text(c, &["pixelUnit", a]).unwrap_or_default();
            unit(&name).ok_or_else(|| {
                FormatError::Unsupported(format!(
                    "channel {id}: pixel unit {name:?} along {a} is not a length"
                ))
            })
        })
        .collect::<FResult<_>>()?;
    let length = |a: &str| number(c, &["length", a], &format!("a pixel length along {a}"));
    // Lateral lengths in the z unit, as SurfaceTopography keeps them.
    let z_metres = units[2].1;
    let step = [
        units[0].1 / z_metres * calibrate[0] * length("x")?,
        units[1].1 / z_metres * calibrate[1] * length("y")?,
    ];
    if !step.iter().all(|s| s.is_finite() && *s > 0.0) {
        return malformed(format!("channel {id}: pixel sizes {step:?}"));
    }
    Ok(Some(HeightChannel {
        id,
        nx,
        ny,
        depth: depth as usize,
        step,
        z_per_count: calibrate[2] * length("z")?,
        unit: units[2].0,
    }))
}

/// The height channels of one `.oir` and its parsed chunks.
fn open(bytes: &[u8]) -> FResult<(Parsed<'_>, Vec<HeightChannel>, Metadata)> {
    let parsed = parse(bytes)?;
    let props = parsed
        .properties
        .as_deref()
        .ok_or_else(|| FormatError::Malformed("the file has no properties block".into()))?;
    let (channels, meta) = channels_of(props)?;
    Ok((parsed, channels, meta))
}

fn infos(channels: &[&HeightChannel]) -> Vec<ChannelInfo> {
    channels
        .iter()
        .enumerate()
        .map(|(index, c)| ChannelInfo {
            index,
            name: c.id.clone(),
            height: true,
        })
        .collect()
}

fn height(parsed: &Parsed<'_>, c: &HeightChannel) -> FResult<HeightField> {
    let prefix = parsed
        .prefix
        .as_deref()
        .ok_or_else(|| FormatError::Malformed("the file names no topography prefix".into()))?;
    let name = format!("{prefix}_{}_0", c.id);
    let image = parsed
        .data
        .get(&name)
        .ok_or_else(|| FormatError::Malformed(format!("no data block {name:?}")))?;
    let need = c.nx.checked_mul(c.ny).and_then(|n| n.checked_mul(c.depth));
    if need != Some(image.len()) {
        return malformed(format!(
            "data block {name:?} holds {} bytes, not {} × {} × {}",
            image.len(),
            c.nx,
            c.ny,
            c.depth
        ));
    }
    let data = if c.depth == 1 {
        image
            .iter()
            .map(|&v| f64::from(v) * c.z_per_count)
            .collect()
    } else {
        image
            .chunks_exact(2)
            .map(|w| f64::from(u16::from_le_bytes([w[0], w[1]])) * c.z_per_count)
            .collect()
    };
    Ok(HeightField::from_vec([c.nx, c.ny], data)?
        .with_spacing(c.step)?
        .with_units(Units {
            xy: c.unit,
            z: c.unit,
        }))
}

/// The `.oir`'s height channels, by their ids.
pub(crate) fn channels(bytes: &[u8]) -> FResult<Vec<ChannelInfo>> {
    let (_, channels, _) = open(bytes)?;
    Ok(infos(&channels.iter().collect::<Vec<_>>()))
}

/// Reads the height channel `choice` names (by default the first).
pub(crate) fn read_channel(bytes: &[u8], choice: Option<&Channel>) -> FResult<HeightField> {
    let (parsed, channels, _) = open(bytes)?;
    let refs: Vec<&HeightChannel> = channels.iter().collect();
    height(&parsed, refs[pick(&infos(&refs), choice)?])
}

/// The vendor, microscope and creation date.
pub(crate) fn metadata(bytes: &[u8]) -> FResult<Metadata> {
    Ok(open(bytes)?.2)
}

fn bad_zip(e: String) -> FormatError {
    FormatError::Malformed(format!("not a readable packed OIR (zip) archive: {e}"))
}

/// The `.oir` members of a `.poir`, inflated, in the archive's order.
fn members(bytes: &[u8]) -> FResult<Vec<(String, Vec<u8>)>> {
    let mut zip = zipped::open(bytes, bad_zip)?;
    let mut out = Vec::new();
    for k in 0..zip.len() {
        let is_oir = match zip.name_for_index(k) {
            Some(name) => name
                .map_err(|e| bad_zip(e.to_string()))?
                .to_ascii_lowercase()
                .ends_with(".oir"),
            None => false,
        };
        if is_oir {
            out.push(zipped::by_index(&mut zip, k, bad_zip)?);
        }
    }
    if out.is_empty() {
        return malformed("the archive holds no .oir file (not a packed OIR)");
    }
    Ok(out)
}

/// One `.oir` opened: its chunks, height channels and metadata.
type Opened<'a> = (Parsed<'a>, Vec<HeightChannel>, Metadata);

/// The members with a laser-scanning image, opened, in order (the others
/// skipped, as SurfaceTopography skips them).
fn opened(members: &[(String, Vec<u8>)]) -> FResult<Vec<(&str, Opened<'_>)>> {
    let mut out = Vec::new();
    for (name, data) in members {
        match open(data) {
            Ok(o) => out.push((name.as_str(), o)),
            Err(FormatError::Unsupported(_)) => {}
            Err(e) => return Err(within(name, e)),
        }
    }
    Ok(out)
}

fn within(member: &str, e: FormatError) -> FormatError {
    match e {
        FormatError::Malformed(m) => FormatError::Malformed(format!("member {member:?}: {m}")),
        other => other,
    }
}

/// A `.poir`'s height channels, numbered across its members.
pub(crate) fn packed_channels(bytes: &[u8]) -> FResult<Vec<ChannelInfo>> {
    let members = members(bytes)?;
    let opened = opened(&members)?;
    let all: Vec<&HeightChannel> = opened.iter().flat_map(|(_, (_, c, _))| c).collect();
    Ok(infos(&all))
}

/// Reads the `.poir` channel `choice` names (by default the first).
pub(crate) fn read_packed(bytes: &[u8], choice: Option<&Channel>) -> FResult<HeightField> {
    let members = members(bytes)?;
    let opened = opened(&members)?;
    let all: Vec<(&str, &Parsed<'_>, &HeightChannel)> = opened
        .iter()
        .flat_map(|(name, (parsed, channels, _))| channels.iter().map(move |c| (*name, parsed, c)))
        .collect();
    let k = pick(&infos(&all.iter().map(|a| a.2).collect::<Vec<_>>()), choice)?;
    let (name, parsed, c) = all[k];
    height(parsed, c).map_err(|e| within(name, e))
}

/// The first height member's vendor, microscope and creation date.
pub(crate) fn packed_metadata(bytes: &[u8]) -> FResult<Metadata> {
    let members = members(bytes)?;
    let opened = opened(&members)?;
    Ok(opened
        .into_iter()
        .next()
        .map(|(_, (_, _, meta))| meta)
        .unwrap_or_default())
}

/// The registration of Oir: its row of `asperity formats`, how its files
/// are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const OIR: Registration = Registration {
    name: "Olympus OIR (.oir)",
    extensions: &["oir"],
    height: Access::Read,
    notes: "the laser-scanning image's HEIGHT channels by their ids: u8/u16 counts × the pixel length in z × the z calibration, pixel lengths × the x/y calibration, lateral sizes in the z unit; rows along y; the microscope and creation date kept as metadata",
    magic: Magic::Starts(&[MAGIC]),
    codec: Some(
        Codec::new(read_channel)
            .channels(channels)
            .metadata(metadata),
    ),
    ..Registration::NONE
};

/// The registration of Poir: its row of `asperity formats`, how its files
/// are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const POIR: Registration = Registration {
    name: "Olympus packed OIR (.poir)",
    extensions: &["poir"],
    height: Access::Read,
    notes: "a zip of .oir files: every member's height channels, numbered in order (members without a laser-scanning image skipped)",
    codec: Some(
        Codec::new(read_packed)
            .channels(packed_channels)
            .metadata(packed_metadata)
            .declared(crate::zipped::declared_twice),
    ),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    /// Built to the layout by python/tests/reference/oir_layout.py: a 5 × 3
    /// u16 height channel `h1` (counts 0…14 × 0.25 µm × calibration 2,
    /// pixels 0.1 µm, × 1.1 in x), an intensity channel, and a 1-byte height
    /// channel `h2` (counts × 0.5 µm × 2).
    const SMALL: &[u8] = include_bytes!("../tests/data/small.oir");

    #[test]
    fn height_channels_counts_scaled_and_pixel_sizes() {
        let names: Vec<String> = channels(SMALL)
            .unwrap()
            .into_iter()
            .map(|c| c.name)
            .collect();
        assert_eq!(names, ["h1", "h2"]);
        let h = read_channel(SMALL, None).unwrap();
        assert_eq!(h.dims(), [5, 3]);
        assert_eq!(h.units().z, LengthUnit::Um);
        assert!((h.spacing()[0] - 0.11).abs() < 1e-12, "{:?}", h.spacing());
        assert!((h.spacing()[1] - 0.1).abs() < 1e-12, "{:?}", h.spacing());
        assert_eq!((*h.get(0, 0), *h.get(4, 2)), (0.0, 14.0 * 0.25 * 2.0));
        let h2 = read_channel(SMALL, Some(&Channel::parse("h2"))).unwrap();
        assert_eq!(*h2.get(1, 0), 0.5 * 2.0);
        let m = metadata(SMALL).unwrap();
        assert!(
            m.contains(&("Microscope".to_owned(), "OLS5000".to_owned())),
            "{m:?}"
        );
    }

    #[test]
    fn truncated_and_foreign_files_are_refused() {
        for cut in (0..SMALL.len()).step_by(37) {
            assert!(read_channel(&SMALL[..cut], None).is_err(), "cut at {cut}");
        }
        assert!(read_channel(b"OLYMPUSRAWFORMAT", None).is_err());
        assert!(read_packed(b"PK\x03\x04", None).is_err());
    }
}
