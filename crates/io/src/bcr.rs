//! BCR-STM and BCRF (`.bcr`, `.bcrf`), the interchange files of scanning
//! probe microscopes (Image Metrology's SPIP and others), read.
//!
//! A text header of `headersize` characters (2048 by default) in Latin-1 or
//! UTF-16 (`fileformat = bcrstm|bcrf`, or `…_unicode`), `key = value` lines
//! with `%` or `#` comments, then ypixels rows of xpixels samples: int16 for
//! BCR-STM (times `bit2nm`), f32 for BCRF, little-endian unless `intelmode = 0`.
//! `xlength` and `ylength` are the field's size in `xunit`/`yunit`; heights
//! are in `zunit`; every unit is nm when the header names none. Void points
//! (32767 in BCR-STM; above 1.7e38 or NaN in BCRF) were not measured: they
//! are read as missing points (NaN).

use std::collections::HashMap;

use asperity_core::{HeightField, LengthUnit, Units};

use crate::bytes::{Endian, Fields};
use crate::error::{FResult, FormatError, malformed};
use crate::header_keys::HeaderKeys;
use crate::format::{Access, Codec, Magic, Registration};

const MAGIC: &str = "fileformat = bcr";
/// The header's size when it does not say.
const DEFAULT_HEADER: usize = 2048;

/// Whether `bytes` start like a BCR file (Latin-1 or UTF-16, with or without
/// a byte-order mark).
pub(crate) fn sniff(bytes: &[u8]) -> bool {
    let utf16: Vec<u8> = MAGIC.bytes().flat_map(|b| [b, 0]).collect();
    bytes.starts_with(MAGIC.as_bytes())
        || bytes.starts_with(&utf16)
        || bytes.get(2..).is_some_and(|b| b.starts_with(&utf16)) && bytes.starts_with(&[0xFF, 0xFE])
}

/// The header text of `chars` characters and the bytes per character.
fn header_text(bytes: &[u8], chars: usize) -> FResult<(String, usize)> {
    if bytes.starts_with(MAGIC.as_bytes()) {
        let end = chars.min(bytes.len());
        return Ok((bytes[..end].iter().map(|&b| char::from(b)).collect(), 1));
    }
    let end = (2 * chars).min(bytes.len() & !1);
    let units: Vec<u16> = bytes[..end]
        .chunks_exact(2)
        .map(|c| u16::from_le_bytes([c[0], c[1]]))
        .collect();
    let text = String::from_utf16_lossy(&units);
    Ok((text.trim_start_matches('\u{feff}').to_owned(), 2))
}

/// The header's `key = value` pairs.
fn keys(text: &str) -> HashMap<String, String> {
    text.lines()
        .map(|l| l.trim_matches(|c: char| c.is_whitespace() || c == '\0'))
        .filter(|l| !l.starts_with('%') && !l.starts_with('#'))
        .filter_map(|l| l.split_once('='))
        .map(|(k, v)| (k.trim().to_ascii_lowercase(), v.trim().to_owned()))
        .collect()
}

/// A unit of the header (nm when absent; `um` and `µm` alike).
fn unit(keys: &HashMap<String, String>, key: &str) -> FResult<LengthUnit> {
    match keys.get(key) {
        None => Ok(LengthUnit::Nm),
        Some(u) => LengthUnit::parse(u)
            .ok()
            .filter(|u| *u != LengthUnit::None)
            .ok_or_else(|| {
                FormatError::Unsupported(format!(
                    "{key} = {u:?} is not a length unit (a BCR file of other data than heights)"
                ))
            }),
    }
}

/// The `nx` × `ny` samples after the `header`-byte header: int16 (BCR-STM)
/// or f32 (BCRF) in either byte order; a void sample (int16 max, f32 NaN or
/// above 1.7e38) was not measured: a missing point (NaN).
fn samples(
    body: &[u8],
    [nx, ny]: [usize; 2],
    stm: bool,
    endian: Endian,
    header: usize,
) -> FResult<Vec<f64>> {
    let size = if stm { 2 } else { 4 };
    let need = nx
        .checked_mul(ny)
        .and_then(|n| n.checked_mul(size))
        .ok_or_else(|| FormatError::Malformed("xpixels × ypixels is too large".into()))?;
    if body.len() < need {
        return malformed(format!(
            "{nx} × {ny} samples of {size} bytes need {need} bytes after the {header}-byte header, the file has {} (truncated?)",
            body.len()
        ));
    }
    let f = match endian {
        Endian::Little => Fields::le(&body[..need]),
        Endian::Big => Fields::be(&body[..need]),
    };
    (0..need / size)
        .map(|k| {
            Ok(if stm {
                match f.i16(2 * k)? {
                    i16::MAX => f64::NAN,
                    raw => f64::from(raw),
                }
            } else {
                match f.f32(4 * k)? {
                    raw if raw.is_nan() || raw > 1.7e38 => f64::NAN,
                    raw => f64::from(raw),
                }
            })
        })
        .collect()
}

/// The header's length in characters (`headersize`, 2048 by default) and
/// the bytes a character takes.
fn header_size(bytes: &[u8]) -> FResult<(usize, usize)> {
    let (probe, width) = header_text(bytes, DEFAULT_HEADER)?;
    let chars = match keys(&probe).get("headersize") {
        None => DEFAULT_HEADER,
        Some(v) => v.parse().ok().filter(|&n: &usize| n > 0).ok_or_else(|| {
            FormatError::Malformed(format!("headersize = {v:?} is not a size"))
        })?,
    };
    Ok((chars, width))
}

/// The samples' byte order (`intelmode`) and nanometres per count
/// (`bit2nm`, BCR-STM's integers only).
fn encoding(header: &HeaderKeys<'_>, stm: bool) -> FResult<(Endian, f64)> {
    let endian = if header.real_or("intelmode", 1.0)? != 0.0 {
        Endian::Little
    } else {
        Endian::Big
    };
    let scale = if stm {
        header.real_or("bit2nm", 1.0)?
    } else {
        1.0
    };
    Ok((endian, scale))
}

/// Reads a BCR-STM or BCRF file.
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    if !sniff(bytes) {
        return malformed("missing the `fileformat = bcr…` line");
    }
    let (chars, width) = header_size(bytes)?;
    let (text, _) = header_text(bytes, chars)?;
    let k = keys(&text);
    let header = HeaderKeys::new(&k);
    let format = header.text("fileformat")?;
    let stm = match format {
        "bcrstm" | "bcrstm_unicode" => true,
        "bcrf" | "bcrf_unicode" => false,
        other => return malformed(format!("unknown fileformat {other:?}")),
    };
    let (nx, ny) = (header.count("xpixels")?, header.count("ypixels")?);
    let (lx, ly) = (header.real("xlength")?, header.real("ylength")?);
    for (key, v) in [("xlength", lx), ("ylength", ly)] {
        if !(v.is_finite() && v > 0.0) {
            return malformed(format!("{key} = {v} is not a positive length"));
        }
    }
    let (ux, uy, uz) = (unit(&k, "xunit")?, unit(&k, "yunit")?, unit(&k, "zunit")?);
    if ux != uy {
        return malformed("x and y units differ");
    }
    let (endian, scale) = encoding(&header, stm)?;
    let body = bytes.get(chars * width..).unwrap_or(&[]);
    let data = samples(body, [nx, ny], stm, endian, chars * width)?;
    let data = data.into_iter().map(|v| v * scale).collect();
    Ok(HeightField::from_vec([nx, ny], data)?
        .with_spacing([lx / nx as f64, ly / ny as f64])?
        .with_units(Units { xy: ux, z: uz }))
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "BCR-STM / BCRF (.bcr, .bcrf)",
    extensions: &["bcr", "bcrf"],
    height: Access::Read,
    notes: "Latin-1 or UTF-16 header; int16 (× bit2nm) or f32, either byte order; the header's units (nm by default); void points read as missing",
    magic: Magic::Test(sniff),
    codec: Some(Codec::new(|b, _| read_height(b))),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    fn file(header: &str, utf16: bool, body: &[u8]) -> Vec<u8> {
        let mut h: Vec<u8> = if utf16 {
            header.encode_utf16().flat_map(u16::to_le_bytes).collect()
        } else {
            header.bytes().collect()
        };
        let width = if utf16 { 2 } else { 1 };
        h.resize(DEFAULT_HEADER * width, if utf16 { 0 } else { b' ' });
        h.extend(body);
        h
    }

    use crate::error::refused as err;

    #[test]
    fn bcrf_in_both_encodings_and_bcrstm_with_its_scale() {
        let body: Vec<u8> = [1.0f32, 2.0, 3.0, 4.5, 5.0, 6.0]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        for (utf16, format) in [(false, "bcrf"), (true, "bcrf_unicode")] {
            let head = format!(
                "fileformat = {format}\n%comment\nheadersize = 2048\nxpixels = 3\nypixels = 2\n\
                 xlength = 1.5\nylength = 2\nxunit = um\nyunit = um\nzunit = nm\n"
            );
            let h = read_height(&file(&head, utf16, &body)).unwrap();
            assert_eq!(h.dims(), [3, 2]);
            assert_eq!(h.spacing(), [0.5, 1.0]);
            assert_eq!(
                h.units(),
                Units {
                    xy: LengthUnit::Um,
                    z: LengthUnit::Nm
                }
            );
            assert_eq!(h.data(), &[1.0, 2.0, 3.0, 4.5, 5.0, 6.0]);
        }
        let stm = "fileformat = bcrstm\nxpixels = 2\nypixels = 1\nxlength = 4\nylength = 2\n\
                   bit2nm = 0.5\nintelmode = 0\n";
        let body: Vec<u8> = [10i16, -4].iter().flat_map(|v| v.to_be_bytes()).collect();
        let h = read_height(&file(stm, false, &body)).unwrap();
        assert_eq!(h.data(), &[5.0, -2.0]);
        assert_eq!(h.units().z, LengthUnit::Nm);
    }

    #[test]
    fn void_points_are_missing_and_truncation_and_odd_units_are_refused() {
        let head = "fileformat = bcrf\nxpixels = 2\nypixels = 1\nxlength = 1\nylength = 1\n";
        let void: Vec<u8> = [1.0f32, 3e38]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let holed = read_height(&file(head, false, &void)).unwrap();
        assert_eq!(holed.missing_count(), 1, "a void point is missing");
        assert!(holed.data()[1].is_nan());
        assert!(err(read_height(&file(head, false, &void[..7]))).contains("truncated"));
        let volts = format!("{head}zunit = V\n");
        assert!(err(read_height(&file(&volts, false, &void))).contains("not a length unit"));
        let huge = head.replace("xpixels = 2", "xpixels = 99999999999");
        assert!(err(read_height(&file(&huge, false, &void))).contains("truncated"));
        assert!(read_height(b"fileformat = bcrf").is_err());
    }
}
