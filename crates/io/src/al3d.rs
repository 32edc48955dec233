//! Alicona Imaging `.al3d` (the focus-variation microscopes of Alicona, now
//! Bruker Alicona), read: the depth image.
//!
//! The file is `AliconaImaging` NUL CR LF, then tags of 52 bytes each — a key
//! of 20 and a value of 30 NUL-padded characters and CR LF — starting with
//! `Version` and `TagCount` (the number of tags after it), then a 256-byte
//! comment. `Cols`, `Rows`, `PixelSizeXMeter`, `PixelSizeYMeter`,
//! `DepthImageOffset` and `InvalidPixelValue` locate and scale the depth
//! image: Rows rows of f32 heights in metres, each row padded to a multiple of
//! 8 bytes. Points that are NaN or equal (to 1.5e-7 relative) to the invalid
//! value were not measured: they are read as missing points (NaN).

use std::collections::HashMap;

use asperity_core::{HeightField, LengthUnit, Units};

use crate::error::{FResult, FormatError, malformed};
use crate::header_keys::HeaderKeys;
use crate::format::{Access, Codec, Magic, Registration};

pub(crate) const MAGIC: &[u8] = b"AliconaImaging\0\r\n";
/// Bytes of a tag: key, value, CR LF.
const TAG: usize = 52;

/// The tags, by key.
fn tags(bytes: &[u8]) -> FResult<HashMap<String, String>> {
    let text = |b: &[u8]| -> String {
        b.iter()
            .take_while(|&&c| c != 0)
            .map(|&c| char::from(c))
            .collect::<String>()
            .trim()
            .to_owned()
    };
    let tag = |k: usize| -> FResult<(String, String)> {
        let at = MAGIC.len() + k * TAG;
        let t = bytes.get(at..at + TAG).ok_or_else(|| {
            FormatError::Malformed("the file ends inside its tags (truncated?)".into())
        })?;
        if &t[50..] != b"\r\n" {
            return malformed(format!("tag {k} does not end with CR LF"));
        }
        Ok((text(&t[..20]), text(&t[20..50])))
    };
    let (version, _) = tag(0)?;
    let (count_key, count) = tag(1)?;
    if version != "Version" || count_key != "TagCount" {
        return malformed("the first tags are not Version and TagCount");
    }
    let count: usize = count
        .parse()
        .map_err(|_| FormatError::Malformed(format!("TagCount {count:?} is not a number")))?;
    (2..2 + count).map(tag).collect()
}

/// Reads the depth image of an AL3D file.
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    if !bytes.starts_with(MAGIC) {
        return malformed("missing the `AliconaImaging` magic");
    }
    let t = tags(bytes)?;
    let tag = HeaderKeys::tags(&t);
    let (nx, ny) = (tag.count("Cols")?, tag.count("Rows")?);
    let (dx, dy) = (tag.real("PixelSizeXMeter")?, tag.real("PixelSizeYMeter")?);
    for (k, v) in [("PixelSizeXMeter", dx), ("PixelSizeYMeter", dy)] {
        if !(v.is_finite() && v > 0.0) {
            return malformed(format!("{k} = {v} is not a positive length"));
        }
    }
    let offset = tag.count("DepthImageOffset")?;
    let invalid = t
        .get("InvalidPixelValue")
        .and_then(|v| v.parse::<f64>().ok());
    // Rows are padded to a multiple of 8 bytes.
    let stride = nx
        .checked_mul(4)
        .map(|b| b.div_ceil(8) * 8)
        .ok_or_else(|| FormatError::Malformed("Cols is too large".into()))?;
    let need = stride
        .checked_mul(ny)
        .ok_or_else(|| FormatError::Malformed("Cols × Rows is too large".into()))?;
    let body = bytes.get(offset..).unwrap_or(&[]);
    if body.len() < need {
        return malformed(format!(
            "{nx} × {ny} depths need {need} bytes from offset {offset}, the file has {} (truncated?)",
            body.len()
        ));
    }
    // An invalid depth is a point not measured: a missing point (NaN).
    let mut data = Vec::with_capacity(nx * ny);
    for row in body[..need].chunks_exact(stride) {
        for c in row[..4 * nx].chunks_exact(4) {
            let v = f64::from(f32::from_le_bytes([c[0], c[1], c[2], c[3]]));
            let bad = !v.is_finite()
                || invalid.is_some_and(|i| i.is_finite() && (v - i).abs() < 1.5e-7 * i.abs());
            data.push(if bad { f64::NAN } else { v });
        }
    }
    let metres = Units::same(LengthUnit::M);
    Ok(HeightField::from_vec([nx, ny], data)?
        .with_spacing([dx, dy])?
        .with_units(metres))
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "Alicona Imaging (.al3d)",
    extensions: &["al3d"],
    height: Access::Read,
    notes: "the depth image: f32 in metres, pixel sizes from the tags; invalid points read as missing",
    magic: Magic::Starts(&[MAGIC]),
    codec: Some(Codec::new(|b, _| read_height(b))),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    fn tag(key: &str, value: &str) -> Vec<u8> {
        let mut t = vec![0u8; TAG];
        t[..key.len()].copy_from_slice(key.as_bytes());
        t[20..20 + value.len()].copy_from_slice(value.as_bytes());
        t[50..].copy_from_slice(b"\r\n");
        t
    }

    /// A 3 × 2 depth image (rows padded from 12 to 16 bytes).
    fn file(values: [f32; 6]) -> Vec<u8> {
        let mut b = MAGIC.to_vec();
        let offset = MAGIC.len() + 9 * TAG + 256;
        for (k, v) in [
            ("Version", "1".to_string()),
            ("TagCount", "7".into()),
            ("Cols", "3".into()),
            ("Rows", "2".into()),
            ("PixelSizeXMeter", "5e-7".into()),
            ("PixelSizeYMeter", "2.5e-7".into()),
            ("DepthImageOffset", offset.to_string()),
            ("InvalidPixelValue", "3.000000028082e+15".into()),
            ("CreatingApplication", "test".into()),
        ] {
            b.extend(tag(k, &v));
        }
        b.extend([0u8; 256]);
        for row in values.chunks(3) {
            for v in row {
                b.extend(v.to_le_bytes());
            }
            b.extend([0u8; 4]);
        }
        b
    }

    #[test]
    fn depths_in_metres_without_the_row_padding() {
        let h = read_height(&file([1e-6, 2e-6, 3e-6, 4e-6, 5e-6, 6e-6])).unwrap();
        assert_eq!(h.dims(), [3, 2]);
        assert_eq!(h.spacing(), [5e-7, 2.5e-7]);
        assert_eq!(h.units().z, LengthUnit::M);
        assert_eq!(h.data()[4], f64::from(5e-6f32));
    }

    #[test]
    fn invalid_points_are_missing_and_truncation_is_refused() {
        let bad = file([1e-6, 3e15, 3e-6, f32::NAN, 5e-6, 6e-6]);
        let h = read_height(&bad).unwrap();
        assert_eq!(h.missing_count(), 2);
        assert!(h.data()[1].is_nan() && h.data()[3].is_nan());
        assert_eq!(h.data()[2], f64::from(3e-6f32));
        let good = file([0.0; 6]);
        for cut in 0..good.len() {
            assert!(read_height(&good[..cut]).is_err(), "cut at {cut}");
        }
    }
}
