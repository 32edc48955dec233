//! Digital Metrology OmniSurf3D `.os3d`, read.
//!
//! Little-endian (Digital Metrology's published "OmniSurf3D file format"):
//! the magic `OmniSurf3D`, major and minor version (i32), two texts (u32
//! length, then ASCII: the identification and the date), points along x
//! and y (i32), the step along x and y and the origin (f64, µm), then the
//! heights as f32 in µm, x fastest, row by row (file rows are asperity's
//! grid rows). A height below −3 × 10³⁸ marks an invalid point (missing).
//! Checked against SurfaceTopography's `OS3D.py` on a file built to the
//! published layout (no instrument file is public).

use asperity_core::{HeightField, LengthUnit, Units};

use crate::Metadata;
use crate::bytes::{Cursor, Fields};
use crate::error::{FResult, FormatError, malformed};
use crate::format::{Access, Codec, Magic, Registration};

/// The file's magic.
pub(crate) const MAGIC: &[u8] = b"OmniSurf3D";
const INVALID_BELOW: f64 = -3e38;

/// The header: identification, date, points, steps and where the data start.
struct Header {
    identification: String,
    date: String,
    version: (i32, i32),
    nx: usize,
    ny: usize,
    step: [f64; 2],
    data: usize,
}

/// A text: its length (i32), then Latin-1 bytes (trailing NULs dropped).
fn text(c: &mut Cursor<'_>) -> FResult<String> {
    let n = c.i32()? as u32 as usize;
    Ok(c.take(n)?
        .iter()
        .map(|&ch| char::from(ch))
        .collect::<String>()
        .trim_end_matches('\0')
        .to_owned())
}

fn header(b: &[u8]) -> FResult<Header> {
    if !b.starts_with(MAGIC) {
        return malformed("missing the `OmniSurf3D` magic");
    }
    let mut c = Fields::le(b).cursor(10);
    let version = (c.i32()?, c.i32()?);
    let identification = text(&mut c)?;
    let date = text(&mut c)?;
    let (nx, ny) = (c.i32()?, c.i32()?);
    let step = [c.f64()?, c.f64()?];
    if nx <= 0 || ny <= 0 {
        return malformed(format!("{nx} × {ny} points: no data"));
    }
    if !step.iter().all(|s| s.is_finite() && *s > 0.0) {
        return malformed(format!("the steps {step:?} are not positive lengths"));
    }
    Ok(Header {
        identification,
        date,
        version,
        nx: nx as usize,
        ny: ny as usize,
        step,
        data: c.at() + 16,
    })
}

/// Reads an `.os3d` height field.
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    let h = header(bytes)?;
    let need = h
        .nx
        .checked_mul(h.ny)
        .and_then(|n| n.checked_mul(4))
        .ok_or_else(|| FormatError::Malformed(format!("{} × {} points: too many", h.nx, h.ny)))?;
    let body = Fields::le(bytes).bytes(h.data, need).map_err(|_| {
        FormatError::Malformed(format!(
            "{} × {} f32 heights need {need} bytes after the header (truncated?)",
            h.nx, h.ny
        ))
    })?;
    let data = body
        .chunks_exact(4)
        .map(|c| {
            let z = f64::from(f32::from_le_bytes([c[0], c[1], c[2], c[3]]));
            if z < INVALID_BELOW { f64::NAN } else { z }
        })
        .collect();
    let um = Units::same(LengthUnit::Um);
    Ok(HeightField::from_vec([h.nx, h.ny], data)?
        .with_spacing(h.step)?
        .with_units(um))
}

/// The version, identification and date.
pub(crate) fn metadata(bytes: &[u8]) -> FResult<Metadata> {
    let h = header(bytes)?;
    Ok(vec![
        (
            "Version".to_owned(),
            format!("{}.{}", h.version.0, h.version.1),
        ),
        ("Identification".to_owned(), h.identification),
        ("Date".to_owned(), h.date),
    ])
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "Digital Metrology OmniSurf3D (.os3d)",
    extensions: &["os3d"],
    height: Access::Read,
    notes: "f32 heights and f64 steps in µm; heights below -3e38 read as missing; version, identification and date kept as metadata",
    magic: Magic::Starts(&[MAGIC]),
    codec: Some(Codec::new(|b, _| read_height(b)).metadata(metadata)),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Vec<u8> {
        let mut b = MAGIC.to_vec();
        for v in [1i32, 0] {
            b.extend(v.to_le_bytes());
        }
        for t in ["probe 7", "2026-11-28"] {
            b.extend((t.len() as u32).to_le_bytes());
            b.extend(t.as_bytes());
        }
        for v in [3i32, 2] {
            b.extend(v.to_le_bytes());
        }
        for v in [0.5f64, 0.25, 0.0, 0.0] {
            b.extend(v.to_le_bytes());
        }
        for z in [1.0f32, 2.0, 3.0, -3.4e38, 5.0, 6.0] {
            b.extend(z.to_le_bytes());
        }
        b
    }

    #[test]
    fn heights_are_read_in_micrometres_with_invalid_points_missing() {
        let h = read_height(&sample()).unwrap();
        assert_eq!((h.dims(), h.spacing()), ([3, 2], [0.5, 0.25]));
        assert_eq!(h.row(0), &[1.0, 2.0, 3.0]);
        assert!(h.row(1)[0].is_nan());
        let m = metadata(&sample()).unwrap();
        assert_eq!(
            (m[1].1.as_str(), m[2].1.as_str()),
            ("probe 7", "2026-11-28")
        );
    }

    #[test]
    fn truncated_files_are_refused() {
        let f = sample();
        for cut in [0, 12, 25, 60, f.len() - 1] {
            assert!(read_height(&f[..cut]).is_err(), "cut at {cut}");
        }
    }
}
