//! TrueMap `.tmd` (TrueGage's TrueMap, version 2), read.
//!
//! The file is the line `Binary TrueMap Data File v2.0` (CR LF, NUL), a
//! NUL-terminated comment, then a little-endian header — points along x and
//! along y (u32), the field's length along x and y and its offsets (f32) —
//! and the heights as f32, x fastest. Lengths, offsets and heights are in
//! millimetres (Gwyddion's `rmitmd.c`; SurfaceTopography reads them so). The
//! comment's length varies in Gwyddion's reading; the files seen have 24 bytes.

use asperity_core::{HeightField, LengthUnit, Units};

use crate::bytes::Fields;
use crate::error::{FResult, FormatError, malformed};
use crate::format::{Access, Codec, Magic, Registration};

pub(crate) const MAGIC: &[u8] = b"Binary TrueMap Data File v2.0";

/// Reads a TrueMap file.
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    let (header, [nx, ny], [lx, ly, x0, y0]) = header(bytes)?;
    let body = &bytes[header..];
    let need = nx
        .checked_mul(ny)
        .and_then(|n| n.checked_mul(4))
        .ok_or_else(|| FormatError::Malformed("the point count is too large".into()))?;
    if body.len() < need {
        return malformed(format!(
            "{nx} × {ny} f32 heights need {need} bytes, the file has {} after its header (truncated?)",
            body.len()
        ));
    }
    let data = body[..need]
        .chunks_exact(4)
        .map(|c| f64::from(f32::from_le_bytes([c[0], c[1], c[2], c[3]])))
        .collect();
    let mm = Units::same(LengthUnit::Mm);
    Ok(HeightField::from_vec([nx, ny], data)?
        .with_geometry(Some([lx / nx as f64, ly / ny as f64]), Some([x0, y0]))?
        .with_units(mm))
}

/// Where the heights start, the points along x and y, and the lengths and
/// offsets (x, y lengths; x, y offsets), checked.
fn header(bytes: &[u8]) -> FResult<(usize, [usize; 2], [f64; 4])> {
    if !bytes.starts_with(MAGIC) {
        return malformed("missing the `Binary TrueMap Data File v2.0` line");
    }
    // The magic line and the comment, each NUL-terminated.
    let mut lines = Fields::le(bytes).cursor(MAGIC.len());
    for _ in 0..2 {
        lines.c_string().map_err(|_| {
            FormatError::Malformed("a header line is not NUL-terminated (truncated?)".into())
        })?;
    }
    let start = lines.at();
    let head = bytes.get(start..start + 24).ok_or_else(|| {
        FormatError::Malformed("the file ends inside its header (truncated?)".into())
    })?;
    let f = Fields::le(head);
    let (nx, ny) = (f.u32(0)? as usize, f.u32(4)? as usize);
    let [lx, ly, x0, y0] = [f.f32_wide(8)?, f.f32_wide(12)?, f.f32_wide(16)?, f.f32_wide(20)?];
    if nx == 0 || ny == 0 {
        return malformed(format!("{nx} × {ny} points: no data"));
    }
    for (name, v) in [("x length", lx), ("y length", ly)] {
        if !(v.is_finite() && v > 0.0) {
            return malformed(format!("the {name} {v} is not a positive length"));
        }
    }
    if !(x0.is_finite() && y0.is_finite()) {
        return malformed("the offsets are not finite");
    }
    Ok((start + 24, [nx, ny], [lx, ly, x0, y0]))
}

/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "TrueMap (.tmd)",
    extensions: &["tmd"],
    height: Access::Read,
    notes: "version 2: f32 heights, lengths and offsets in millimetres",
    magic: Magic::Starts(&[MAGIC]),
    codec: Some(Codec::new(|b, _| read_height(b))),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    fn file(comment: &[u8], values: &[f32]) -> Vec<u8> {
        let mut b = MAGIC.to_vec();
        b.extend(b"\r\n\0");
        b.extend(comment);
        b.push(0);
        b.extend(3u32.to_le_bytes());
        b.extend(2u32.to_le_bytes());
        for v in [1.5f32, 0.5, 0.25, -1.0] {
            b.extend(v.to_le_bytes());
        }
        for v in values {
            b.extend(v.to_le_bytes());
        }
        b
    }

    #[test]
    fn heights_and_geometry_in_millimetres() {
        for comment in [
            &b"Created by TrueMap v6\r\n"[..],
            b"",
            b"a longer comment than usual",
        ] {
            let h = read_height(&file(comment, &[1.0, 2.0, 3.0, 4.0, 5.0, 6.5])).unwrap();
            assert_eq!(h.dims(), [3, 2]);
            assert_eq!(h.spacing(), [0.5, 0.25]);
            assert_eq!(h.origin(), [0.25, -1.0]);
            assert_eq!(h.units().z, LengthUnit::Mm);
            assert_eq!(h.data(), &[1.0, 2.0, 3.0, 4.0, 5.0, 6.5]);
        }
    }

    #[test]
    fn truncated_and_damaged_files_are_refused() {
        let good = file(b"c", &[0.0; 6]);
        for cut in 0..good.len() {
            assert!(read_height(&good[..cut]).is_err(), "cut at {cut}");
        }
        let mut zero = good.clone();
        let at = MAGIC.len() + 3 + 2;
        zero[at..at + 4].copy_from_slice(&0u32.to_le_bytes());
        assert!(read_height(&zero).is_err());
        let mut huge = good;
        huge[at..at + 4].copy_from_slice(&u32::MAX.to_le_bytes());
        huge[at + 4..at + 8].copy_from_slice(&u32::MAX.to_le_bytes());
        assert!(read_height(&huge).is_err());
    }
}
