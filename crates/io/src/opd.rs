//! Wyko `.opd` (Bruker/Veeco Vision, white-light interferometers), read.
//!
//! Little-endian. Two bytes, then a directory of 24-byte blocks: a name (16
//! bytes, NUL-padded), a type (i16), a length (i32) and attributes (u16).
//! The first entry is the directory itself (its length is the directory's
//! size); the blocks' contents follow the directory in the same order, each
//! `length` bytes. The data block (`RAW DATA`, `RAW_DATA`, `OPD` or `Raw`)
//! starts with nx, ny and the element size (u16 each) — 2 for int16, 4 for
//! f32 — then the values with y varying fastest, stored from the last row; an
//! int16 of 32766 or more, an f32 of 1e38 or more, NaN or ∞ marks a point not
//! measured, read as a missing point (NaN). `Wavelength` (f32, nm) and `Mult`
//! (u16) scale the values to heights: z = value × wavelength / mult, in nm
//! (SurfaceTopography: × 1e-6 in mm); `Pixel_size` (f32, mm) and `Aspect`
//! (f32, the y pixel's ratio to x) give the spacing. The first data block is
//! read (SurfaceTopography's default channel). Layout learnt from
//! SurfaceTopography's `OPD.py` and checked on its example file.

use asperity_core::{HeightField, LengthUnit, Units};

use crate::bytes::Fields;
use crate::error::{FResult, FormatError, malformed};
use crate::format::{Access, Codec, Magic, Registration};

const ENTRY: usize = 24;

/// The directory entry at `at`: a block's name and length.
fn entry(bytes: &[u8], at: usize) -> FResult<(String, usize)> {
    let e = bytes.get(at..at + ENTRY).ok_or_else(|| {
        FormatError::Malformed("the directory ends before its entries (truncated?)".into())
    })?;
    let name = e[..16].split(|&b| b == 0).next().unwrap_or_default();
    let len = Fields::le(e).i32(18)?;
    Ok((String::from_utf8_lossy(name).into_owned(), len.max(0) as usize))
}

/// The blocks' names and contents, in order.
fn blocks(bytes: &[u8]) -> FResult<Vec<(String, &[u8])>> {
    let entry = |at: usize| entry(bytes, at);
    let (name, dir_len) = entry(2)?;
    if name != "Directory" {
        return malformed(format!(
            "the first block is {name:?}, not the Directory (not a Wyko OPD file?)"
        ));
    }
    if dir_len % ENTRY != 0 || dir_len < ENTRY {
        return malformed(format!(
            "the directory's length {dir_len} is not a multiple of {ENTRY}"
        ));
    }
    let count = dir_len / ENTRY;
    let mut out = Vec::with_capacity(count.min(bytes.len() / ENTRY));
    let mut at = 2 + dir_len;
    for k in 1..count {
        let (name, len) = entry(2 + k * ENTRY)?;
        let content = at
            .checked_add(len)
            .and_then(|end| bytes.get(at..end))
            .ok_or_else(|| {
                FormatError::Malformed(format!(
                    "block {name:?} of {len} bytes runs past the file's end (truncated?)"
                ))
            })?;
        at += len;
        out.push((name, content));
    }
    Ok(out)
}

/// The f32 of a block, or u16 for `Mult`.
fn number(blocks: &[(String, &[u8])], name: &str) -> Option<f64> {
    let (_, b) = blocks.iter().find(|(n, _)| n == name)?;
    match (name, b.len()) {
        ("Mult", 2..) => Some(f64::from(u16::from_le_bytes([b[0], b[1]]))),
        (_, 4..) => Some(f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]]))),
        _ => None,
    }
}

/// Reads the first data block of a Wyko OPD file.
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    let blocks = blocks(bytes)?;
    let Some((name, data)) = blocks.iter().find(|(n, b)| {
        matches!(n.as_str(), "RAW DATA" | "RAW_DATA" | "OPD" | "Raw") && !b.is_empty()
    }) else {
        return malformed("no data block (RAW DATA, OPD or Raw)");
    };
    let (nx, ny, size, raw) = data_block(name, data)?;
    let scale = height_scale(&blocks)?;
    let value = |k: usize| -> f64 {
        let c = &raw[k * size..(k + 1) * size];
        if size == 2 {
            match i16::from_le_bytes([c[0], c[1]]) {
                v if v >= 32766 => f64::NAN,
                v => f64::from(v) * scale,
            }
        } else {
            match f32::from_le_bytes([c[0], c[1], c[2], c[3]]) {
                v if !v.is_finite() || v >= 1e38 => f64::NAN,
                v => f64::from(v) * scale,
            }
        }
    };
    // Stored x slowest, y fastest and from the last row.
    let mut heights = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        heights.extend((0..nx).map(|i| value(i * ny + (ny - 1 - j))));
    }
    let pixel = number(&blocks, "Pixel_size").unwrap_or(1.0);
    let (dx, dy) = (pixel, pixel * number(&blocks, "Aspect").unwrap_or(1.0));
    if !(dx.is_finite() && dx > 0.0 && dy.is_finite() && dy > 0.0) {
        return malformed(format!("the pixel size {dx} × {dy} mm is not positive"));
    }
    let units = Units { xy: LengthUnit::Mm, z: LengthUnit::Nm };
    Ok(HeightField::from_vec([nx, ny], heights)?
        .with_spacing([dx, dy])?
        .with_units(units))
}

/// A data block's points along x and y, element size, and elements.
fn data_block<'a>(name: &str, data: &'a [u8]) -> FResult<(usize, usize, usize, &'a [u8])> {
    if data.len() < 6 {
        return malformed(format!("the {name} block has no size"));
    }
    let f = Fields::le(data);
    let (nx, ny, size) = (f.u16(0)?, f.u16(2)?, f.u16(4)?);
    let (nx, ny, size) = (usize::from(nx), usize::from(ny), usize::from(size));
    if nx == 0 || ny == 0 {
        return malformed(format!("{nx} × {ny} points: no data"));
    }
    if size != 2 && size != 4 {
        return malformed(format!(
            "elements of {size} bytes (2, int16, and 4, f32, are read)"
        ));
    }
    let need = nx * ny * size;
    let raw = data.get(6..6 + need).ok_or_else(|| {
        FormatError::Malformed(format!(
            "{nx} × {ny} values of {size} bytes need {need} bytes, the {name} block has {} (truncated?)",
            data.len() - 6
        ))
    })?;
    Ok((nx, ny, size, raw))
}

/// Nanometres per stored unit: the wavelength / mult.
fn height_scale(blocks: &[(String, &[u8])]) -> FResult<f64> {
    let wavelength = number(blocks, "Wavelength").ok_or_else(|| {
        FormatError::Malformed("no Wavelength block: the heights have no scale".into())
    })?;
    let mult = number(blocks, "Mult").unwrap_or(1.0);
    if !(wavelength.is_finite() && wavelength != 0.0 && mult > 0.0) {
        return malformed(format!(
            "the height scale wavelength / mult = {wavelength} / {mult} is not usable"
        ));
    }
    Ok(wavelength / mult)
}

/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "Wyko OPD (.opd)",
    extensions: &["opd"],
    height: Access::Read,
    notes: "the first data block: int16 or f32 × wavelength / mult in nm, pixel size and aspect in mm; values at the type's limit read as missing",
    magic: Magic::Test(|head| head.get(2..11) == Some(b"Directory".as_slice())),
    codec: Some(Codec::new(|b, _| read_height(b))),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    fn entry(name: &str, len: usize) -> Vec<u8> {
        let mut e = vec![0u8; ENTRY];
        e[..name.len()].copy_from_slice(name.as_bytes());
        e[18..22].copy_from_slice(&(len as i32).to_le_bytes());
        e
    }

    /// A 2 × 3 int16 file (values 0..6 stored x slowest, y fastest), with
    /// `extra` blocks after the data.
    fn file(values: &[i16], extra: &[(&str, Vec<u8>)]) -> Vec<u8> {
        let mut data = Vec::new();
        for v in [2u16, 3, 2] {
            data.extend(v.to_le_bytes());
        }
        data.extend(values.iter().flat_map(|v| v.to_le_bytes()));
        let mut blocks = vec![("RAW DATA", data)];
        blocks.extend(extra.iter().map(|(n, b)| (*n, b.clone())));
        let mut out = vec![0u8; 2];
        out.extend(entry("Directory", ENTRY * (blocks.len() + 1)));
        for (n, b) in &blocks {
            out.extend(entry(n, b.len()));
        }
        for (_, b) in &blocks {
            out.extend(b);
        }
        out
    }

    fn scales() -> Vec<(&'static str, Vec<u8>)> {
        vec![
            ("Wavelength", 600.0f32.to_le_bytes().to_vec()),
            ("Mult", 2u16.to_le_bytes().to_vec()),
            ("Pixel_size", 0.5f32.to_le_bytes().to_vec()),
            ("Aspect", 2.0f32.to_le_bytes().to_vec()),
        ]
    }

    #[test]
    fn reads_columns_from_the_last_row_scaled_by_the_wavelength() {
        let h = read_height(&file(&[0, 1, 2, 3, 32767, 5], &scales())).unwrap();
        assert_eq!(h.dims(), [2, 3]);
        assert_eq!(h.spacing(), [0.5, 1.0]);
        assert_eq!(h.units().z, LengthUnit::Nm);
        // Column x = 0 holds 0, 1, 2 from the last row up.
        assert_eq!(
            [*h.get(0, 0), *h.get(0, 1), *h.get(0, 2)],
            [600.0, 300.0, 0.0]
        );
        assert_eq!(*h.get(1, 0), 1500.0);
        assert!(h.get(1, 1).is_nan(), "32767 is not measured");
        assert_eq!(*h.get(1, 2), 900.0);
    }

    #[test]
    fn truncation_and_missing_blocks_are_refused() {
        let good = file(&[0; 6], &scales());
        for cut in 0..good.len() {
            assert!(read_height(&good[..cut]).is_err(), "cut at {cut}");
        }
        let e = read_height(&file(&[0; 6], &[])).unwrap_err();
        assert!(format!("{e:?}").contains("Wavelength"), "{e:?}");
        let mut bad = good.clone();
        bad[2..11].copy_from_slice(b"Directorz");
        assert!(format!("{:?}", read_height(&bad).unwrap_err()).contains("Directory"));
    }
}
