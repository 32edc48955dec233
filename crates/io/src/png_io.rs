//! PNG: 16-bit grayscale height maps (with their height range recorded) and RGBA
//! textures, through the `png` crate.
//!
//! A height map stores `round((z − z_min) / (z_max − z_min) · 65535)`; `z_min`,
//! `z_max`, the spacing and the origin go into `tEXt` chunks with keywords
//! `asperity:z_min`, `asperity:z_max`, `asperity:dx`, `asperity:dy`,
//! `asperity:x0`, `asperity:y0`, so reading restores heights to within
//! (z_max − z_min)/131070. The same facts go into Gwyddion's own keys
//! (`Gwy::XReal`, `Gwy::YReal`, `Gwy::XOffset`, `Gwy::YOffset`, `Gwy::ZMin`,
//! `Gwy::ZMax`, `Gwy::XYUnit`, `Gwy::ZUnit`, `Gwy::Title`), so Gwyddion opens
//! the map with its sizes and heights (crates/cli/tests/real_programs.rs). A PNG
//! with Gwyddion's keys only (one Gwyddion exported) is read with them: the
//! heights between `Gwy::ZMin` and `Gwy::ZMax`, the spacing from `Gwy::XReal`,
//! the first sample at the pixel centre after `Gwy::XOffset`, the units from
//! `Gwy::XYUnit`/`Gwy::ZUnit`. Any other PNG (8-bit, RGB, palette) is read as
//! heights in [0, 1] from its Rec. 709 luminance.

use std::io::{Cursor, Write};

use asperity_core::{HeightField, LengthUnit, RgbaImage, Units};

use crate::error::{FResult, FormatError, malformed};
use crate::format::{Access, Codec, Magic, Registration};

/// The `tEXt` keyword of the parameters an image or field was made with.
pub(crate) const PARAMS_KEY: &str = "asperity:params";

/// Encodes an RGBA8 image as PNG bytes.
pub fn encode_rgba(img: &RgbaImage) -> Result<Vec<u8>, png::EncodingError> {
    encode_rgba_with(img, None)
}

/// Encodes an RGBA8 image as PNG bytes, with the parameters it was made with
/// (one line of JSON, the `metadata` module's) in a `tEXt` chunk. An image
/// whose every pixel is opaque (every render) is stored as RGB: a quarter
/// fewer bytes to compress, the same picture in every reader.
pub fn encode_rgba_with(
    img: &RgbaImage,
    params: Option<&str>,
) -> Result<Vec<u8>, png::EncodingError> {
    let pixels = img.pixels();
    let opaque = pixels.chunks_exact(4).all(|p| p[3] == u8::MAX);
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, img.width(), img.height());
    enc.set_color(match opaque {
        true => png::ColorType::Rgb,
        false => png::ColorType::Rgba,
    });
    enc.set_depth(png::BitDepth::Eight);
    if let Some(p) = params {
        enc.add_text_chunk(PARAMS_KEY.into(), p.into())?;
    }
    let mut w = enc.write_header()?;
    match opaque {
        true => {
            let rgb: Vec<u8> = pixels
                .chunks_exact(4)
                .flat_map(|p| [p[0], p[1], p[2]])
                .collect();
            w.write_image_data(&rgb)?;
        }
        false => w.write_image_data(pixels)?,
    }
    w.finish()?;
    Ok(out)
}

/// Writes an RGBA8 image as PNG (with the parameters, where given).
pub(crate) fn write_rgba(
    w: &mut dyn Write,
    img: &RgbaImage,
    params: Option<&str>,
) -> std::io::Result<()> {
    w.write_all(&encode_rgba_with(img, params).map_err(std::io::Error::other)?)
}

fn dims_u32(h: &HeightField) -> std::io::Result<(u32, u32)> {
    let c = |v: usize| {
        u32::try_from(v).map_err(|_| std::io::Error::other("PNG sides are limited to 2^31 pixels"))
    };
    Ok((c(h.nx())?, c(h.ny())?))
}

/// Writes a height field as a 16-bit grayscale PNG with its range in tEXt chunks.
pub(crate) fn write_height(
    w: &mut dyn Write,
    h: &HeightField,
    title: &str,
    params: Option<&str>,
) -> std::io::Result<()> {
    let (nx, ny) = dims_u32(h)?;
    let (lo, hi) = h.min_max();
    let scale = if hi > lo { 65535.0 / (hi - lo) } else { 0.0 };
    let mut enc = png::Encoder::new(w, nx, ny);
    enc.set_color(png::ColorType::Grayscale);
    enc.set_depth(png::BitDepth::Sixteen);
    let [dx, dy] = h.spacing();
    let [x0, y0] = h.origin();
    for (k, v) in [
        ("z_min", lo),
        ("z_max", hi),
        ("dx", dx),
        ("dy", dy),
        ("x0", x0),
        ("y0", y0),
    ] {
        enc.add_text_chunk(format!("asperity:{k}"), format!("{v:e}"))
            .map_err(std::io::Error::other)?;
    }
    let units = h.units();
    for (k, u) in [("xy_unit", units.xy), ("z_unit", units.z)] {
        if u.metres().is_some() {
            enc.add_text_chunk(format!("asperity:{k}"), u.ascii().to_string())
                .map_err(std::io::Error::other)?;
        }
    }
    // Gwyddion's own keys (its gwyddion.h GWY_IMGKEY_*): the field's extent and
    // the offset of its first pixel's edge (Gwyddion's pixel-area convention,
    // as in GSF), and the heights at 0 and 65535, in base units (metres) when
    // the field has units, with empty units when it has none.
    let (fx, fz) = (
        units.xy.metres().unwrap_or(1.0),
        units.z.metres().unwrap_or(1.0),
    );
    let gwy = [
        ("XReal", dx * nx as f64 * fx),
        ("YReal", dy * ny as f64 * fx),
        ("XOffset", (x0 - 0.5 * dx) * fx),
        ("YOffset", (y0 - 0.5 * dy) * fx),
        ("ZMin", lo * fz),
        ("ZMax", if hi > lo { hi } else { lo + 1.0 } * fz),
    ];
    for (k, v) in gwy {
        enc.add_text_chunk(format!("Gwy::{k}"), format!("{v:e}"))
            .map_err(std::io::Error::other)?;
    }
    let base = |u: LengthUnit| if u.metres().is_some() { "m" } else { "" };
    for (k, v) in [
        ("XYUnit", base(units.xy)),
        ("ZUnit", base(units.z)),
        ("Title", title),
    ] {
        enc.add_text_chunk(format!("Gwy::{k}"), v.to_string())
            .map_err(std::io::Error::other)?;
    }
    if let Some(p) = params {
        enc.add_text_chunk(PARAMS_KEY.into(), p.into())
            .map_err(std::io::Error::other)?;
    }
    let mut out = enc.write_header().map_err(std::io::Error::other)?;
    let data: Vec<u8> = h
        .data()
        .iter()
        .flat_map(|&z| (((z - lo) * scale).round().clamp(0.0, 65535.0) as u16).to_be_bytes())
        .collect();
    out.write_image_data(&data).map_err(std::io::Error::other)?;
    out.finish().map_err(std::io::Error::other)
}

fn decoding_error(e: png::DecodingError) -> FormatError {
    match e {
        png::DecodingError::IoError(io) => FormatError::from(io),
        other => FormatError::Malformed(other.to_string()),
    }
}

/// The pixel count a PNG declares in its header, read from `r` (nothing decoded).
pub(crate) fn header_pixels<R: std::io::BufRead + std::io::Seek>(r: R) -> FResult<u128> {
    let dec = png::Decoder::new(r);
    let reader = dec.read_info().map_err(decoding_error)?;
    let info = reader.info();
    Ok(info.width as u128 * info.height as u128)
}

/// The text of `tEXt` chunk `key` (the chunks before the image data).
pub(crate) fn text_chunk(bytes: &[u8], key: &str) -> FResult<Option<String>> {
    let reader = png::Decoder::new(Cursor::new(bytes))
        .read_info()
        .map_err(decoding_error)?;
    Ok(reader
        .info()
        .uncompressed_latin1_text
        .iter()
        .find(|t| t.keyword == key)
        .map(|t| t.text.clone()))
}

/// A PNG's `tEXt` chunks.
struct TextKeys(Vec<(String, String)>);

impl TextKeys {
    fn text(&self, key: &str) -> Option<&str> {
        self.0
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    fn number(&self, key: &str) -> FResult<Option<f64>> {
        self.text(key)
            .map(|v| {
                v.trim().parse().map_err(|_| {
                    FormatError::Malformed(format!("tEXt {key} = {v:?} is not a number"))
                })
            })
            .transpose()
    }
}

/// What a height map's keys say.
struct Geometry {
    range: (f64, f64),
    spacing: Option<[f64; 2]>,
    origin: Option<[f64; 2]>,
    units: Units,
}

/// asperity's keys; else Gwyddion's (a PNG Gwyddion exported); else the
/// range [0, 1] and no geometry.
fn geometry(keys: &TextKeys, nx: usize, ny: usize) -> FResult<Geometry> {
    let ours = |k: &str| keys.number(&format!("asperity:{k}"));
    let gwy = |k: &str| keys.number(&format!("Gwy::{k}"));
    // Both of a pair, or neither: half a pair is a damaged file, not a default.
    let pair = |a: &str, b: &str| -> FResult<Option<[f64; 2]>> {
        match (ours(a)?, ours(b)?) {
            (Some(x), Some(y)) => Ok(Some([x, y])),
            (None, None) => Ok(None),
            _ => malformed(format!(
                "tEXt has one of asperity:{a} and asperity:{b} but not both"
            )),
        }
    };
    let range = pair("z_min", "z_max")?;
    let (spacing, origin) = (pair("dx", "dy")?, pair("x0", "y0")?);
    if range.is_some() || spacing.is_some() {
        let unit = |k: &str| -> FResult<LengthUnit> {
            keys.text(&format!("asperity:{k}"))
                .map_or(Ok(LengthUnit::None), |v| {
                    LengthUnit::parse(v)
                        .map_err(|e| FormatError::Malformed(format!("tEXt asperity:{k}: {e}")))
                })
        };
        let [lo, hi] = range.unwrap_or([0.0, 1.0]);
        let units = Units {
            xy: unit("xy_unit")?,
            z: unit("z_unit")?,
        };
        return Ok(Geometry {
            range: (lo, hi),
            spacing,
            origin,
            units,
        });
    }
    let range = match (gwy("ZMin")?, gwy("ZMax")?) {
        (Some(lo), Some(hi)) => (lo, hi),
        _ => (0.0, 1.0),
    };
    let (mut spacing, mut origin) = (None, None);
    if let (Some(xr), Some(yr)) = (gwy("XReal")?, gwy("YReal")?) {
        // Gwyddion's extent covers whole pixels and its offset is the first
        // pixel's edge (as in GSF): samples sit at the pixels' centres.
        let d = [xr / nx as f64, yr / ny as f64];
        let edge = [
            gwy("XOffset")?.unwrap_or(0.0),
            gwy("YOffset")?.unwrap_or(0.0),
        ];
        spacing = Some(d);
        origin = Some([edge[0] + 0.5 * d[0], edge[1] + 0.5 * d[1]]);
    }
    // Gwyddion writes base units ("m"); a unit that is not a length (V, A…)
    // leaves the numbers unitless.
    let unit = |k: &str| {
        keys.text(&format!("Gwy::{k}"))
            .and_then(|v| LengthUnit::parse(v).ok())
            .unwrap_or_default()
    };
    let units = Units {
        xy: unit("XYUnit"),
        z: unit("ZUnit"),
    };
    Ok(Geometry {
        range,
        spacing,
        origin,
        units,
    })
}

/// Reads any PNG as a height field (see the module docs).
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    let err = decoding_error;
    let mut dec = png::Decoder::new(Cursor::new(bytes));
    dec.set_transformations(png::Transformations::EXPAND);
    let mut reader = dec.read_info().map_err(err)?;
    let keys = TextKeys(
        reader
            .info()
            .uncompressed_latin1_text
            .iter()
            .map(|t| (t.keyword.clone(), t.text.clone()))
            .collect(),
    );
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| FormatError::Malformed("image too large".into()))?;
    let mut buf = vec![0u8; size];
    let info = reader.next_frame(&mut buf).map_err(err)?;
    let (nx, ny) = (info.width as usize, info.height as usize);
    let channels = info.color_type.samples();
    let sixteen = info.bit_depth == png::BitDepth::Sixteen;
    let max = if sixteen { 65535.0 } else { 255.0 };
    let sample = |k: usize| -> f64 {
        if sixteen {
            u16::from_be_bytes([buf[2 * k], buf[2 * k + 1]]) as f64
        } else {
            buf[k] as f64
        }
    };
    let lum = |p: usize| -> f64 {
        let b = p * channels;
        match channels {
            1 | 2 => sample(b),
            _ => 0.2126 * sample(b) + 0.7152 * sample(b + 1) + 0.0722 * sample(b + 2),
        }
    };
    let g = geometry(&keys, nx, ny)?;
    let (lo, hi) = g.range;
    if !(lo.is_finite() && hi.is_finite()) {
        return malformed("recorded height range is not finite");
    }
    if lo > hi {
        return malformed(format!(
            "recorded height range is inverted: z_min = {lo} > z_max = {hi}"
        ));
    }
    let data = (0..nx * ny)
        .map(|p| lo + lum(p) / max * (hi - lo))
        .collect();
    Ok(HeightField::from_vec([nx, ny], data)?
        .with_geometry(g.spacing, g.origin)?
        .with_units(g.units))
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "PNG, 16-bit grayscale",
    extensions: &["png"],
    height: Access::ReadWrite,
    notes: "height range and spacing in tEXt chunks (asperity's and Gwyddion's Gwy:: keys); Gwyddion's exports read with their Gwy:: keys; PNGs with neither read as [0, 1]; no missing points",
    magic: Magic::Starts(&[b"\x89PNG\r\n\x1a\n"]),
    codec: Some(Codec::new(|b, _| read_height(b))),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    /// A 16-bit PNG as Gwyddion exports it: only `Gwy::` keys, metres.
    fn gwyddion_png(keys: &[(&str, &str)], samples: &[u16], [nx, ny]: [u32; 2]) -> Vec<u8> {
        let mut out = Vec::new();
        let mut enc = png::Encoder::new(&mut out, nx, ny);
        enc.set_color(png::ColorType::Grayscale);
        enc.set_depth(png::BitDepth::Sixteen);
        for (k, v) in keys {
            enc.add_text_chunk(format!("Gwy::{k}"), (*v).to_string())
                .unwrap();
        }
        let mut w = enc.write_header().unwrap();
        let data: Vec<u8> = samples.iter().flat_map(|s| s.to_be_bytes()).collect();
        w.write_image_data(&data).unwrap();
        w.finish().unwrap();
        out
    }

    /// The colour type and pixels a PNG decodes to.
    fn decoded(bytes: &[u8]) -> (png::ColorType, Vec<u8>) {
        let mut reader = png::Decoder::new(Cursor::new(bytes)).read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        buf.truncate(info.buffer_size());
        (info.color_type, buf)
    }

    #[test]
    fn opaque_pictures_are_stored_as_rgb_and_translucent_ones_as_rgba() {
        let mut img = RgbaImage::filled(3, 2, [10, 20, 30, 255]);
        img.put(1, 1, [200, 100, 0, 255]);
        let (color, rgb) = decoded(&encode_rgba(&img).unwrap());
        assert_eq!(color, png::ColorType::Rgb);
        let back: Vec<u8> = img
            .pixels()
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect();
        assert_eq!(rgb, back);
        img.put(2, 0, [1, 2, 3, 128]);
        let (color, rgba) = decoded(&encode_rgba(&img).unwrap());
        assert_eq!(color, png::ColorType::Rgba);
        assert_eq!(rgba, img.pixels());
    }

    #[test]
    fn gwyddion_keys_alone_give_heights_geometry_and_units() {
        let keys = [
            ("XReal", "3e-6"),
            ("YReal", "4e-6"),
            ("XOffset", "1e-6"),
            ("YOffset", "-2e-6"),
            ("ZMin", "-1e-8"),
            ("ZMax", "5.5535e-8"),
            ("XYUnit", "m"),
            ("ZUnit", "m"),
        ];
        let png = gwyddion_png(&keys, &[0, 65535, 32768, 1, 2, 3], [3, 2]);
        let h = read_height(&png).unwrap();
        assert_eq!(h.dims(), [3, 2]);
        assert_eq!(h.spacing(), [1e-6, 2e-6]);
        assert_eq!(h.origin(), [1.5e-6, -1e-6]);
        assert_eq!(h.units().xy, LengthUnit::M);
        assert_eq!(h.units().z, LengthUnit::M);
        let step = 6.5535e-8 / 65535.0;
        for (z, s) in h.data().iter().zip([0.0, 65535.0, 32768.0, 1.0, 2.0, 3.0]) {
            assert!((z - (-1e-8 + s * step)).abs() < 1e-20, "{z}");
        }
        // A unit that is not a length keeps the numbers, unitless.
        let volts = gwyddion_png(
            &[("ZMin", "0"), ("ZMax", "2"), ("ZUnit", "V")],
            &[0, 65535],
            [2, 1],
        );
        let v = read_height(&volts).unwrap();
        assert_eq!(v.units().z, LengthUnit::None);
        assert_eq!(v.data(), &[0.0, 2.0]);
        // Without any key: [0, 1] as before.
        let bare = read_height(&gwyddion_png(&[], &[0, 65535], [2, 1])).unwrap();
        assert_eq!(bare.data(), &[0.0, 1.0]);
    }

    #[test]
    fn our_keys_win_over_gwyddions() {
        let h = HeightField::from_vec([2, 2], vec![1.0, 2.0, 3.0, 5.0])
            .unwrap()
            .with_spacing([0.5, 0.25])
            .unwrap()
            .with_units(Units {
                xy: LengthUnit::Um,
                z: LengthUnit::Nm,
            });
        let mut out = Vec::new();
        write_height(&mut out, &h, "t", None).unwrap();
        let back = read_height(&out).unwrap();
        assert_eq!(back.spacing(), [0.5, 0.25]);
        assert_eq!(back.units(), h.units());
        assert!((back.data()[3] - 5.0).abs() < 1e-4);
    }
}
