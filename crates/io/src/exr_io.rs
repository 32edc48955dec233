//! OpenEXR height fields through the `exr` crate: one `float32` channel `Y`, so
//! image viewers show it as grayscale and Gwyddion and Python's OpenEXR read it.
//!
//! Heights are stored as `f32` (EXR has no `f64` samples): expect a relative
//! error near 6e-8. The spacing and origin go into `double` header attributes
//! `asperity.dx`, `asperity.dy`, `asperity.x0`, `asperity.y0` (one text
//! attribute `asperity.geometry`), units into `asperity.units` (`xy=um z=nm`,
//! when the field has any), the parameters it was made with into the standard
//! `comments` attribute (one line of JSON). Reading accepts
//! the first layer's `Y`, `Z`, `R` or only channel, in any sample type.

use std::io::{Cursor, Seek, Write};

use asperity_core::{HeightField, LengthUnit, Units};
use exr::prelude::*;

use crate::error::{FResult, FormatError, malformed};
use crate::format::{Access, Codec, Magic, Registration};

const GEOMETRY: &str = "asperity.geometry";
const UNITS: &str = "asperity.units";

/// Writes a height field as a single-channel float EXR (ZIP-compressed, lossless).
pub(crate) fn write_height<W: Write + Seek>(
    w: W,
    h: &HeightField,
    params: Option<&str>,
) -> std::io::Result<()> {
    let samples: Vec<f32> = h.data().iter().map(|&z| z as f32).collect();
    let channel = AnyChannel::new("Y", FlatSamples::F32(samples));
    let mut attrs = LayerAttributes::named("height");
    let [dx, dy] = h.spacing();
    let [x0, y0] = h.origin();
    let geometry = format!("{dx:e} {dy:e} {x0:e} {y0:e}");
    attrs.other.insert(
        Text::from(GEOMETRY),
        AttributeValue::Text(Text::from(geometry.as_str())),
    );
    // The parameters in the standard `comments` attribute (ASCII:
    // the metadata module escapes the rest, as EXR's text wants).
    attrs.comments = params.map(Text::from);
    let layer = Layer::new(
        (h.nx(), h.ny()),
        attrs,
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(SmallVec::from_vec(vec![channel])),
    );
    let mut image = Image::from_layer(layer);
    // Custom attributes live in `exr`'s hash maps, written in their random
    // order: one per map (geometry in the layer's, units in the image's) keeps
    // the bytes the same from run to run. Both read back as the layer's.
    let units = h.units();
    if !units.is_none() {
        let text = format!("xy={} z={}", units.xy.ascii(), units.z.ascii());
        image.attributes.other.insert(
            Text::from(UNITS),
            AttributeValue::Text(Text::from(text.as_str())),
        );
    }
    image.write().to_buffered(w).map_err(|e| match e {
        exr::error::Error::Io(io) => io,
        other => std::io::Error::other(other.to_string()),
    })
}

/// The largest pixel count any layer of an OpenEXR file declares in its header,
/// read from `r` (nothing decoded).
pub(crate) fn header_pixels<R: std::io::Read + Seek>(r: R) -> FResult<u128> {
    let meta = exr::meta::MetaData::read_from_buffered(r, false)
        .map_err(|e| FormatError::Malformed(e.to_string()))?;
    Ok(meta
        .headers
        .iter()
        .map(|h| h.layer_size.width() as u128 * h.layer_size.height() as u128)
        .max()
        .unwrap_or(0))
}

/// The first layer's standard `comments` attribute (its header only is read).
pub(crate) fn comments(bytes: &[u8]) -> FResult<Option<String>> {
    let meta = exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), false)
        .map_err(|e| FormatError::Malformed(e.to_string()))?;
    Ok(meta
        .headers
        .first()
        .and_then(|h| h.own_attributes.comments.as_ref().map(Text::to_string)))
}

/// Reads a height field from the first layer of an EXR file.
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_buffered(Cursor::new(bytes))
        .map_err(|e| FormatError::Malformed(e.to_string()))?;
    let layer = &image.layer_data;
    let list = &layer.channel_data.list;
    let pick = ["Y", "Z", "R"]
        .iter()
        .find_map(|n| list.iter().find(|c| c.name.to_string() == *n))
        .or(if list.len() == 1 { list.first() } else { None });
    let Some(channel) = pick else {
        return malformed("no Y, Z or R channel and more than one channel to choose from");
    };
    let (nx, ny) = (layer.size.width(), layer.size.height());
    let data: Vec<f64> = channel.sample_data.values_as_f32().map(f64::from).collect();
    let mut h = HeightField::from_vec([nx, ny], data)?;
    if let Some(AttributeValue::Text(t)) = layer.attributes.other.get(&Text::from(GEOMETRY)) {
        let v: Vec<f64> = t
            .to_string()
            .split_whitespace()
            .filter_map(|s| s.parse().ok())
            .collect();
        let [dx, dy, x0, y0] = v[..] else {
            return malformed(format!("attribute {GEOMETRY} = {t:?} is not four numbers"));
        };
        h = h.with_spacing([dx, dy])?.with_origin([x0, y0])?;
    }
    if let Some(AttributeValue::Text(t)) = layer.attributes.other.get(&Text::from(UNITS)) {
        let text = t.to_string();
        let mut units = Units::default();
        for part in text.split_whitespace() {
            let parsed = match part.split_once('=') {
                Some(("xy", u)) => LengthUnit::parse(u).map(|u| units.xy = u),
                Some(("z", u)) => LengthUnit::parse(u).map(|u| units.z = u),
                _ => Err(format!("{part:?} is not xy=UNIT or z=UNIT")),
            };
            parsed.map_err(|e| FormatError::Malformed(format!("attribute {UNITS}: {e}")))?;
        }
        h = h.with_units(units);
    }
    Ok(h)
}

/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "OpenEXR, float32",
    extensions: &["exr"],
    height: Access::ReadWrite,
    notes: "channel Y; spacing/origin as header attributes; missing points NaN",
    magic: Magic::Starts(&[b"\x76\x2f\x31\x01"]),
    codec: Some(Codec::new(|b, _| read_height(b))),
    ..Registration::NONE
};
