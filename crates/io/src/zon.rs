//! Keyence `.zon` (VR series one-shot 3D measuring macroscopes), read.
//!
//! The magic `KPK0` or `KPK1`, the size of a BMP thumbnail (u32), the
//! thumbnail, then a zip archive whose members are named by UUIDs; in
//! `KPK1` files every member is a Zstandard frame (read with the pure-Rust
//! `ruzstd` decoder). The members read:
//!
//! - `686613b8-…` (XML): `XYCalibration/MeterPerPixel`, `ZCalibration/MeterPerUnit`;
//! - `4cdb0c75-…`: the heights, a 16-byte header (points along x and y,
//!   bytes an element = 4, bytes a row, i32 each) then int32 counts row by
//!   row, each row padded to its byte count (file rows are asperity's grid
//!   rows); height = count × metres per unit;
//! - `9e7ca6dd-…` (optional): one byte a point in the same layout, a point
//!   whose two low bits are set not measured (missing);
//! - `cbc1d39b-…` and `1d35862b-…` (XML): the device's model and serial
//!   number, the scan's date (kept as metadata).
//!
//! Layout from SurfaceTopography's `ZON.py`; checked against it on files
//! built to that layout (no instrument file is public). Every member is
//! inflated only as far as its own header declares (the XML members to
//! 1 MiB), and the memory estimate counts the declared grid first.

use std::io::{Cursor, Read};

use asperity_core::{HeightField, LengthUnit, Units};

use crate::Metadata;
use crate::error::{FResult, FormatError, malformed, unsupported};
use crate::format::{Access, Codec, Magic, Registration};

/// The magics of uncompressed and Zstandard-compressed members.
pub(crate) const MAGICS: [&[u8]; 2] = [b"KPK0", b"KPK1"];
const HEIGHTS: &str = "4cdb0c75-5706-48cc-a9a1-adf395d609ae";
const VALID: &str = "9e7ca6dd-0e6a-4d7b-8986-f0a7b773c916";
const UNITS: &str = "686613b8-27b5-4a29-8ffc-438c2780873e";
const DEVICE: &str = "cbc1d39b-215f-4d56-a20e-cf8e5f570755";
const SCAN: &str = "1d35862b-3b48-4df2-9235-833ef590b043";
const XML_LIMIT: u64 = 1 << 20;

type Archive<'a> = zip::ZipArchive<Cursor<&'a [u8]>>;

/// The archive and whether its members are Zstandard frames.
fn open(bytes: &[u8]) -> FResult<(Archive<'_>, bool)> {
    let compressed = match bytes.get(..4) {
        Some(b"KPK0") => false,
        Some(b"KPK1") => true,
        _ => return malformed("no KPK0 or KPK1 magic: not a Keyence ZON file"),
    };
    if bytes.len() < 8 {
        return malformed("the file ends inside its header (truncated?)");
    }
    let zip = zip::ZipArchive::new(Cursor::new(bytes))
        .map_err(|e| FormatError::Malformed(format!("the archive after the thumbnail: {e}")))?;
    Ok((zip, compressed))
}

/// Member `name`'s content, at most `limit` bytes of it.
fn member(zip: &mut Archive<'_>, zstd: bool, name: &str, limit: u64) -> FResult<Option<Vec<u8>>> {
    let Ok(file) = zip.by_name(name) else {
        return Ok(None);
    };
    let size = file.size();
    let raw = file.take(size);
    let mut out = Vec::new();
    let read = if zstd {
        let decoder = ruzstd::decoding::StreamingDecoder::new(raw).map_err(|e| {
            FormatError::Malformed(format!("member {name}: not a Zstandard frame: {e}"))
        })?;
        decoder.take(limit).read_to_end(&mut out)
    } else {
        raw.take(limit).read_to_end(&mut out)
    };
    read.map_err(|e| FormatError::Malformed(format!("member {name}: {e}")))?;
    Ok(Some(out))
}

fn xml(zip: &mut Archive<'_>, zstd: bool, name: &str) -> FResult<Option<String>> {
    Ok(member(zip, zstd, name, XML_LIMIT)?.map(|b| String::from_utf8_lossy(&b).into_owned()))
}

/// The text of the element at `path` (tags from the root's children down).
fn find(xml: &str, path: &[&str]) -> Option<String> {
    let doc = roxmltree::Document::parse(xml).ok()?;
    let mut node = doc.root_element();
    for tag in path {
        node = node.children().find(|c| c.has_tag_name(*tag))?;
    }
    node.text().map(|t| t.trim().to_owned())
}

/// An array member's header: points along x and y and bytes a row.
fn array_header(b: &[u8], name: &str, element: usize) -> FResult<(usize, usize, usize)> {
    let Some(h) = b.get(..16) else {
        return malformed(format!("member {name} ends inside its 16-byte header"));
    };
    let i = |o: usize| i32::from_le_bytes([h[o], h[o + 1], h[o + 2], h[o + 3]]);
    let (nx, ny, size, row) = (i(0), i(4), i(8), i(12));
    if nx <= 0 || ny <= 0 {
        return malformed(format!("member {name}: {nx} × {ny} points"));
    }
    if size as usize != element {
        return unsupported(format!(
            "member {name}: {size} bytes an element ({element} expected)"
        ));
    }
    let (nx, ny, row) = (nx as usize, ny as usize, row.max(0) as usize);
    if row < nx * element || row % element != 0 {
        return malformed(format!(
            "member {name}: rows of {row} bytes for {nx} points"
        ));
    }
    Ok((nx, ny, row))
}

/// The points the height member declares (the memory estimate).
pub(crate) fn declared_points(bytes: &[u8]) -> FResult<u128> {
    let (mut zip, zstd) = open(bytes)?;
    let head = member(&mut zip, zstd, HEIGHTS, 16)?
        .ok_or_else(|| FormatError::Malformed("no height data member".into()))?;
    let (nx, ny, _) = array_header(&head, HEIGHTS, 4)?;
    Ok(nx as u128 * ny as u128)
}

/// An array member's rows, read to its declared size.
fn array(
    zip: &mut Archive<'_>,
    zstd: bool,
    name: &str,
    element: usize,
) -> FResult<Option<(usize, usize, Vec<u8>)>> {
    let Some(head) = member(zip, zstd, name, 16)? else {
        return Ok(None);
    };
    let (nx, ny, row) = array_header(&head, name, element)?;
    let need = row
        .checked_mul(ny)
        .and_then(|n| n.checked_add(16))
        .ok_or_else(|| FormatError::Malformed(format!("member {name}: too large")))?;
    let all = member(zip, zstd, name, need as u64)?.unwrap_or_default();
    if all.len() < need {
        return malformed(format!(
            "member {name}: {nx} × {ny} points need {need} bytes, it has {} (truncated?)",
            all.len()
        ));
    }
    let data = all[16..]
        .chunks_exact(row)
        .flat_map(|r| r[..nx * element].to_vec())
        .collect();
    Ok(Some((nx, ny, data)))
}

/// Reads a `.zon` height field.
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    let (mut zip, zstd) = open(bytes)?;
    let units = xml(&mut zip, zstd, UNITS)?
        .ok_or_else(|| FormatError::Malformed("no calibration member (686613b8-…)".into()))?;
    let number = |path: &[&str]| -> FResult<f64> {
        find(&units, path)
            .and_then(|t| t.parse().ok())
            .filter(|v: &f64| v.is_finite() && *v > 0.0)
            .ok_or_else(|| {
                FormatError::Malformed(format!(
                    "the calibration gives no positive {}",
                    path.join("/")
                ))
            })
    };
    let per_pixel = number(&["XYCalibration", "MeterPerPixel"])?;
    let per_unit = number(&["ZCalibration", "MeterPerUnit"])?;
    let (nx, ny, counts) = array(&mut zip, zstd, HEIGHTS, 4)?
        .ok_or_else(|| FormatError::Malformed("no height data member (4cdb0c75-…)".into()))?;
    let valid = array(&mut zip, zstd, VALID, 1)?;
    if let Some((vx, vy, _)) = &valid
        && (*vx, *vy) != (nx, ny)
    {
        return malformed(format!(
            "the validity mask is {vx} × {vy}, the heights {nx} × {ny}"
        ));
    }
    let measured = |k: usize| valid.as_ref().is_none_or(|(_, _, v)| v[k] & 0x03 == 0);
    let data = counts
        .chunks_exact(4)
        .enumerate()
        .map(|(k, c)| {
            if measured(k) {
                f64::from(i32::from_le_bytes([c[0], c[1], c[2], c[3]])) * per_unit
            } else {
                f64::NAN
            }
        })
        .collect();
    let m = Units::same(LengthUnit::M);
    Ok(HeightField::from_vec([nx, ny], data)?
        .with_spacing([per_pixel, per_pixel])?
        .with_units(m))
}

/// The device's model and serial number and the scan's date.
pub(crate) fn metadata(bytes: &[u8]) -> FResult<Metadata> {
    let (mut zip, zstd) = open(bytes)?;
    let mut out = Vec::new();
    if let Some(device) = xml(&mut zip, zstd, DEVICE)? {
        for (key, tag) in [("Device", "DeviceModelName"), ("Serial", "DeviceSerialId")] {
            if let Some(v) = find(&device, &[tag]) {
                out.push((key.to_owned(), v));
            }
        }
    }
    if let Some(scan) = xml(&mut zip, zstd, SCAN)?
        && let Some(v) = find(&scan, &["ScanDateTime"])
    {
        out.push(("Date".to_owned(), v));
    }
    Ok(out)
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "Keyence ZON (.zon)",
    extensions: &["zon"],
    height: Access::Read,
    notes: "KPK0 and KPK1 (Zstandard members): int32 counts × metres per unit, metres per pixel from the calibration, points the validity mask marks read as missing; device, serial and date kept as metadata",
    magic: Magic::Starts(&MAGICS),
    codec: Some(Codec::new(|b, _| read_height(b))
        .metadata(metadata)
        .declared(|b| declared_points(b).map(crate::pixel_bytes))),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use std::io::Write;

    use super::*;

    fn zon(magic: &[u8], valid: bool) -> Vec<u8> {
        let mut head = magic.to_vec();
        head.extend(3u32.to_le_bytes());
        head.extend(b"BMP");
        let mut cursor = Cursor::new(head);
        cursor.set_position(11);
        let mut zip = zip::ZipWriter::new(cursor);
        let opts = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Stored);
        let mut put = |name: &str, data: Vec<u8>| {
            assert_eq!(magic, b"KPK0", "the tests build uncompressed members");
            zip.start_file(name, opts).unwrap();
            zip.write_all(&data).unwrap();
        };
        put(
            UNITS,
            b"<C><XYCalibration><MeterPerPixel>2e-6</MeterPerPixel></XYCalibration>\
              <ZCalibration><MeterPerUnit>1e-8</MeterPerUnit></ZCalibration></C>"
                .to_vec(),
        );
        put(
            DEVICE,
            b"<D><DeviceModelName>VR-6000</DeviceModelName></D>".to_vec(),
        );
        // 3 × 2 points, rows padded to 16 bytes.
        let mut h: Vec<u8> = [3i32, 2, 4, 16]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        for row in [[1i32, 2, 3, 99], [4, 5, 6, 99]] {
            h.extend(row.iter().flat_map(|v| v.to_le_bytes()));
        }
        put(HEIGHTS, h);
        if valid {
            let mut v: Vec<u8> = [3i32, 2, 1, 4]
                .iter()
                .flat_map(|v| v.to_le_bytes())
                .collect();
            v.extend([0, 0, 0, 7, 0, 3, 0, 7]);
            put(VALID, v);
        }
        zip.finish().unwrap().into_inner()
    }

    #[test]
    fn padded_rows_are_read_scaled_with_invalid_points_missing() {
        let h = read_height(&zon(b"KPK0", true)).unwrap();
        assert_eq!((h.dims(), h.spacing()), ([3, 2], [2e-6, 2e-6]));
        assert_eq!(h.row(0), &[1.0 * 1e-8, 2.0 * 1e-8, 3.0 * 1e-8]);
        assert!(h.row(1)[1].is_nan() && h.row(1)[0] == 4e-8);
        let plain = read_height(&zon(b"KPK0", false)).unwrap();
        assert_eq!(plain.missing_count(), 0);
        assert_eq!(metadata(&zon(b"KPK0", false)).unwrap()[0].1, "VR-6000");
        assert_eq!(declared_points(&zon(b"KPK0", false)).unwrap(), 6);
    }

    #[test]
    fn truncated_and_foreign_files_are_refused() {
        let f = zon(b"KPK0", true);
        for cut in [0, 3, 6, 40, f.len() / 2, f.len() - 1] {
            assert!(read_height(&f[..cut]).is_err(), "cut at {cut}");
        }
        let mut compressed = f;
        compressed[3] = b'1'; // the members are no Zstandard frames
        assert!(read_height(&compressed).is_err());
    }
}
