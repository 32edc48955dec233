//! Sensofar `.plu` (and `.apx`), the confocal and interferometric
//! profilometers' topography files, read.
//!
//! Little-endian, no magic: a 128-byte date string, the time (u32) and a
//! 256-byte comment; the calibration at byte 388 — rows (u32), columns (u32),
//! a third count, a factor, then f32 µm per pixel along x and along y, the x
//! and y offsets, µm per level and the z offset; the measurement
//! configuration at 428 — type (u32, 3 for a topography; 1, a profile, is
//! refused), algorithm, method, objective, area type — then 40 bytes of scan
//! settings (their layout depends on the area type, their size does not); at
//! 488 the second configuration: restore, the number of layers, version,
//! hardware, images (u8 each), three reserved bytes and a u32. Then each
//! layer: rows and columns (u32), the heights as f32 in µm (row by row, x
//! fastest), its minimum and maximum (f32). A height of 1000001 marks a point
//! not measured: it is read as a missing point (NaN). The first layer is the
//! topography SurfaceTopography reads by default; later layers are ignored.
//! Lengths are µm. Layout learnt from SurfaceTopography's `PLU.py` and checked
//! on its example file.

use asperity_core::{HeightField, LengthUnit, Units};

use crate::channel::{Channel, ChannelInfo, pick};
use crate::bytes::Fields;
use crate::error::{FResult, FormatError, malformed, unsupported};
use crate::format::{Access, Codec, Registration};

/// Byte offsets of the header's parts.
const CALIBRATION: usize = 388;
const CONFIGURATION: usize = 428;
const LAYERS: usize = 488;
const FIRST_LAYER: usize = 500;

/// A height marking a point not measured.
const UNDEFINED: f32 = 1_000_001.0;

/// Measurement types.
const TOPOGRAPHY: u32 = 3;
const PROFILE: u32 = 1;

/// The layers: (rows, columns, the offset of their heights), each checked
/// against the file's length.
fn layers(bytes: &[u8]) -> FResult<Vec<(usize, usize, usize)>> {
    let Some(head) = bytes.get(..FIRST_LAYER) else {
        return malformed(format!(
            "the header has {FIRST_LAYER} bytes, the file {} (truncated?)",
            bytes.len()
        ));
    };
    match Fields::le(head).u32(CONFIGURATION)? {
        TOPOGRAPHY => {}
        PROFILE => return unsupported("a Sensofar profile (measurement type 1) is not supported"),
        t => return malformed(format!("measurement type {t} is not a topography (3)")),
    }
    let count = head[LAYERS + 1];
    if count == 0 {
        return malformed("the file declares no layer");
    }
    let mut out = Vec::with_capacity(usize::from(count));
    let mut at = FIRST_LAYER;
    for k in 0..count {
        let dims = bytes.get(at..at + 8).ok_or_else(|| {
            FormatError::Malformed(format!("the file ends before layer {k} (truncated?)"))
        })?;
        let dims = Fields::le(dims);
        let (ny, nx) = (dims.u32(0)? as usize, dims.u32(4)? as usize);
        if nx == 0 || ny == 0 {
            return malformed(format!("layer {k} of {nx} × {ny} points: no data"));
        }
        let end = nx
            .checked_mul(ny)
            .and_then(|n| n.checked_mul(4))
            .and_then(|n| n.checked_add(at + 16))
            .filter(|&end| end <= bytes.len())
            .ok_or_else(|| {
                FormatError::Malformed(format!(
                    "layer {k}: {nx} × {ny} f32 heights and its range do not fit in the file's {} bytes (truncated?)",
                    bytes.len()
                ))
            })?;
        out.push((ny, nx, at + 8));
        at = end;
    }
    Ok(out)
}

/// The file's layers as channels (`layer0`, `layer1`, …), all heights.
pub(crate) fn channels(bytes: &[u8]) -> FResult<Vec<ChannelInfo>> {
    Ok((0..layers(bytes)?.len())
        .map(|index| ChannelInfo {
            index,
            name: format!("layer{index}"),
            height: true,
        })
        .collect())
}

/// Reads the layer `choice` names (by default the first).
pub(crate) fn read_channel(bytes: &[u8], choice: Option<&Channel>) -> FResult<HeightField> {
    let layers = layers(bytes)?;
    let (ny, nx, start) = layers[pick(&channels(bytes)?, choice)?];
    let (dx, dy) = (
        Fields::le(bytes).f32_wide(CALIBRATION + 16)?,
        Fields::le(bytes).f32_wide(CALIBRATION + 20)?,
    );
    for (name, v) in [("x", dx), ("y", dy)] {
        if !(v.is_finite() && v > 0.0) {
            return malformed(format!(
                "the pixel size along {name}, {v} µm, is not positive"
            ));
        }
    }
    let need = nx * ny * 4;
    let body = &bytes[start..];
    let data = body[..need]
        .chunks_exact(4)
        .map(|c| {
            let v = f32::from_le_bytes([c[0], c[1], c[2], c[3]]);
            if v == UNDEFINED || v.is_nan() {
                f64::NAN
            } else {
                f64::from(v)
            }
        })
        .collect();
    let um = Units::same(LengthUnit::Um);
    Ok(HeightField::from_vec([nx, ny], data)?
        .with_spacing([dx, dy])?
        .with_units(um))
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "Sensofar (.plu, .apx)",
    extensions: &["plu", "apx"],
    height: Access::Read,
    notes: "the first layer's f32 heights in µm, pixel sizes from the calibration; undefined points (1000001) read as missing; profiles refused",
    codec: Some(Codec::new(read_channel).channels(channels)),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    /// A file of `nx × ny` heights, pixel size 0.5 × 0.25 µm.
    fn file(kind: u32, nx: u32, ny: u32, heights: &[f32]) -> Vec<u8> {
        let mut b = vec![0u8; FIRST_LAYER];
        b[CALIBRATION..CALIBRATION + 4].copy_from_slice(&ny.to_le_bytes());
        b[CALIBRATION + 4..CALIBRATION + 8].copy_from_slice(&nx.to_le_bytes());
        b[CALIBRATION + 16..CALIBRATION + 20].copy_from_slice(&0.5f32.to_le_bytes());
        b[CALIBRATION + 20..CALIBRATION + 24].copy_from_slice(&0.25f32.to_le_bytes());
        b[CONFIGURATION..CONFIGURATION + 4].copy_from_slice(&kind.to_le_bytes());
        b[LAYERS + 1] = 1;
        b.extend(ny.to_le_bytes());
        b.extend(nx.to_le_bytes());
        b.extend(heights.iter().flat_map(|v| v.to_le_bytes()));
        b.extend([0u8; 8]);
        b
    }

    use crate::error::refused as err;

    #[test]
    fn reads_rows_of_micrometres_with_missing_points() {
        let h = read_channel(&file(3, 3, 2, &[1.0, 2.0, 3.0, 4.0, UNDEFINED, 6.0]), None).unwrap();
        assert_eq!(h.dims(), [3, 2]);
        assert_eq!(h.spacing(), [0.5, 0.25]);
        assert_eq!(h.units().xy, LengthUnit::Um);
        assert_eq!(*h.get(2, 0), 3.0);
        assert_eq!(*h.get(0, 1), 4.0);
        assert!(h.get(1, 1).is_nan());
    }

    #[test]
    fn profiles_truncation_and_bad_headers_are_refused() {
        let good = file(3, 3, 2, &[0.0; 6]);
        for cut in 0..good.len() {
            assert!(read_channel(&good[..cut], None).is_err(), "cut at {cut}");
        }
        assert!(err(read_channel(&file(1, 3, 2, &[0.0; 6]), None)).contains("profile"));
        assert!(err(read_channel(&file(7, 3, 2, &[0.0; 6]), None)).contains("type 7"));
        assert!(err(read_channel(&file(3, 0, 2, &[]), None)).contains("no data"));
        let huge = file(3, u32::MAX, u32::MAX, &[0.0; 6]);
        assert!(err(read_channel(&huge, None)).contains("do not fit"));
        let mut flat = good.clone();
        flat[CALIBRATION + 16..CALIBRATION + 20].copy_from_slice(&0f32.to_le_bytes());
        assert!(err(read_channel(&flat, None)).contains("not positive"));
    }
}
