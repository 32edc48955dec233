//! Zygo MetroPro `.dat` (the binary files of Zygo's interferometers), read.
//!
//! A big-endian header (834 bytes for header formats 1 and 2, 4096 for 3;
//! the magic `88 1B 03 6F/70/71` says which), the intensity frames, then the
//! phase: `cn_org_height` rows of `cn_org_width` int32. Offsets in the header,
//! from the format's published description (as Gwyddion's `metropro.c` and
//! SurfaceTopography read it): header size (6), intensity width, height,
//! buckets and byte count (52, 54, 56, 60), phase width, height and byte count
//! (68, 70, 72), the interferometric scale factor S, wavelength λ and
//! obliquity factor O (164, 168, 176; f32), the lateral resolution (184; f32,
//! metres a pixel, 0 when not calibrated), the phase resolution (218) and the
//! sign (232). A height is phase × S × O × λ / R metres, R = 4096, 32768 or
//! 131072 for phase resolution 0, 1, 2, negated when the sign is set. Phases
//! of 2147483640 and above mark points not measured: they are read as
//! missing points (NaN).

use asperity_core::{HeightField, LengthUnit, Units};

use crate::bytes::Fields;
use crate::error::{FResult, FormatError, malformed, unsupported};
use crate::format::{Access, Codec, Magic, Registration};

/// The magics of header formats 1, 2 and 3.
pub(crate) const MAGICS: [&[u8]; 3] = [
    b"\x88\x1b\x03\x6f",
    b"\x88\x1b\x03\x70",
    b"\x88\x1b\x03\x71",
];
/// Phases at or above this mark invalid points.
const INVALID: i32 = 2_147_483_640;

/// What the header says of the phase map.
struct Header {
    nx: usize,
    ny: usize,
    /// Metres per phase count.
    scale: f64,
    /// Where the phases start (after the header and the intensity data).
    start: usize,
    /// The bytes of intensity data skipped.
    intensity: usize,
    /// The pixel size and its unit (metres, or pixels without a calibration).
    spacing: f64,
    xy: LengthUnit,
}

/// Reads a MetroPro file.
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    let h = header(bytes)?;
    let data = phases(bytes, &h)?;
    Ok(HeightField::from_vec([h.nx, h.ny], data)?
        .with_spacing([h.spacing, h.spacing])?
        .with_units(Units {
            xy: h.xy,
            z: LengthUnit::M,
        }))
}

/// The header (big-endian, 834 or 4096 bytes by its format), checked.
fn header(bytes: &[u8]) -> FResult<Header> {
    let format = MAGICS
        .iter()
        .position(|m| bytes.starts_with(m))
        .ok_or_else(|| FormatError::Malformed("missing the MetroPro magic".into()))?;
    let expected = if format == 2 { 4096 } else { 834 };
    let head = bytes.get(..expected).ok_or_else(|| {
        FormatError::Malformed(format!(
            "the header has {expected} bytes, the file {} (truncated?)",
            bytes.len()
        ))
    })?;
    let f = Fields::be(head);
    let declared = f.u32(6)? as usize;
    if declared != expected {
        return unsupported(format!(
            "a header of {declared} bytes (header format {} has {expected})",
            format + 1
        ));
    }
    let u16_at = |o: usize| f.u16(o).map(usize::from);
    let intensity = 2 * u16_at(56)? * u16_at(52)? * u16_at(54)?;
    let (nx, ny) = (u16_at(68)?, u16_at(70)?);
    if nx == 0 || ny == 0 {
        return malformed(format!("{nx} × {ny} phase points: no height data"));
    }
    let (scale, spacing, xy) = calibration(&f)?;
    Ok(Header {
        nx,
        ny,
        scale,
        start: expected + intensity,
        intensity,
        spacing,
        xy,
    })
}

/// Metres per phase count (S × O × λ / R, signed), and the pixel size
/// and its unit.
fn calibration(f: &Fields<'_>) -> FResult<(f64, f64, LengthUnit)> {
    let phase_res = match f.i16(218)? {
        0 => 4096.0,
        1 => 32768.0,
        2 => 131072.0,
        r => return malformed(format!("phase resolution {r} is not 0, 1 or 2")),
    };
    let (s, lambda, o) = (f.f32_wide(164)?, f.f32_wide(168)?, f.f32_wide(176)?);
    let sign = if f.i16(232)? != 0 { -1.0 } else { 1.0 };
    let scale = sign * s * o * lambda / phase_res;
    if !scale.is_finite() {
        return malformed("the height scale (S × O × λ) is not finite");
    }
    // Without a lateral calibration the pixels are the unit.
    let lateral = f.f32_wide(184)?;
    let (spacing, xy) = if lateral.is_finite() && lateral > 0.0 {
        (lateral, LengthUnit::M)
    } else {
        (1.0, LengthUnit::None)
    };
    Ok((scale, spacing, xy))
}

/// The phases × the scale; an invalid phase is a point not measured: a
/// missing point (NaN).
fn phases(bytes: &[u8], h: &Header) -> FResult<Vec<f64>> {
    let need = 4 * h.nx * h.ny;
    let body = bytes.get(h.start..).unwrap_or(&[]);
    if body.len() < need {
        return malformed(format!(
            "{} × {} phases need {need} bytes after the header and {} bytes of intensity, the file has {} (truncated?)",
            h.nx,
            h.ny,
            h.intensity,
            body.len()
        ));
    }
    Ok(body[..need]
        .chunks_exact(4)
        .map(|c| match i32::from_be_bytes([c[0], c[1], c[2], c[3]]) {
            p if p >= INVALID => f64::NAN,
            p => f64::from(p) * h.scale,
        })
        .collect())
}

/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "Zygo MetroPro (.dat)",
    extensions: &["dat"],
    height: Access::Read,
    notes: "header formats 1-3; phase × S × O × λ / R in metres, pixels from the lateral resolution; invalid phases read as missing",
    magic: Magic::Starts(&MAGICS),
    codec: Some(Codec::new(|b, _| read_height(b))),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    fn file(phases: &[i32], lateral: f32, sign: i16) -> Vec<u8> {
        let mut h = vec![0u8; 834];
        h[..4].copy_from_slice(MAGICS[0]);
        h[6..10].copy_from_slice(&834u32.to_be_bytes());
        // a 1 × 1 intensity frame of 2 buckets: 4 bytes
        h[52..54].copy_from_slice(&1u16.to_be_bytes());
        h[54..56].copy_from_slice(&1u16.to_be_bytes());
        h[56..58].copy_from_slice(&2u16.to_be_bytes());
        h[68..70].copy_from_slice(&3u16.to_be_bytes());
        h[70..72].copy_from_slice(&2u16.to_be_bytes());
        h[164..168].copy_from_slice(&0.5f32.to_be_bytes());
        h[168..172].copy_from_slice(&6.4e-7f32.to_be_bytes());
        h[176..180].copy_from_slice(&1.0f32.to_be_bytes());
        h[184..188].copy_from_slice(&lateral.to_be_bytes());
        h[218..220].copy_from_slice(&1i16.to_be_bytes());
        h[232..234].copy_from_slice(&sign.to_be_bytes());
        h.extend([9u8; 4]);
        for p in phases {
            h.extend(p.to_be_bytes());
        }
        h
    }

    #[test]
    fn phases_times_the_scale_in_metres() {
        let scale = 0.5 * 1.0 * f64::from(6.4e-7f32) / 32768.0;
        let h = read_height(&file(&[0, 1, 2, -3, 4, 32768], 2e-6, 0)).unwrap();
        assert_eq!(h.dims(), [3, 2]);
        assert_eq!(h.spacing(), [f64::from(2e-6f32); 2]);
        assert_eq!(
            h.units(),
            Units {
                xy: LengthUnit::M,
                z: LengthUnit::M
            }
        );
        assert_eq!(h.data()[5], 32768.0 * scale);
        assert_eq!(h.data()[3], -3.0 * scale);
        let flipped = read_height(&file(&[0, 1, 2, -3, 4, 32768], 0.0, 1)).unwrap();
        assert_eq!(flipped.data()[5], -32768.0 * scale);
        assert_eq!(flipped.units().xy, LengthUnit::None);
    }

    #[test]
    fn invalid_phases_truncation_and_odd_headers_are_refused() {
        let err = |b: &[u8]| match read_height(b) {
            Ok(_) => panic!("accepted"),
            Err(e) => format!("{e:?}"),
        };
        let good = file(&[0; 6], 1e-6, 0);
        let holed = read_height(&file(&[0, INVALID, 0, 0, 0, i32::MAX], 1e-6, 0)).unwrap();
        assert_eq!(holed.missing_count(), 2);
        assert!(holed.data()[1].is_nan() && holed.data()[5].is_nan());
        for cut in 0..good.len() {
            assert!(read_height(&good[..cut]).is_err(), "cut at {cut}");
        }
        let mut odd = good.clone();
        odd[6..10].copy_from_slice(&900u32.to_be_bytes());
        assert!(err(&odd).contains("header of 900 bytes"));
        let mut res = good;
        res[218..220].copy_from_slice(&7i16.to_be_bytes());
        assert!(err(&res).contains("phase resolution 7"));
    }
}
