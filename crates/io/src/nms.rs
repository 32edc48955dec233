//! NanoFocus µsurf `.nms` (confocal microscopes, format `OM_MS_2.0`), read.
//!
//! A 3468-byte little-endian header, then the heights as u16 counts, x
//! fastest, then (when the header says so) one u8 intensity per point. The
//! header fields read here:
//!
//! | offset | type    | field |
//! |-------:|---------|-------|
//! | 0      | u32     | data type (2: u16 counts) |
//! | 4      | u32     | dimension (1: an area; 0: a profile, refused) |
//! | 8, 12  | i32     | the counts `n_low`, `n_high` that map to … |
//! | 16, 24 | f64     | … the heights `z_low`, `z_high`, in µm |
//! | 32     | text    | the version, `OM_MS_2.0` (the format's signature) |
//! | 52     | text    | the image's name (`Confocal Height Image`) |
//! | 1076   | text    | the date of the measurement |
//! | 1368   | u32 × 2 | points along x and y |
//! | 1376   | f64 × 2 | the spacing along x and y, in nm |
//! | 1416   | i32     | whether the intensity plane follows |
//!
//! A height is `z_low + (count − n_low) (z_high − z_low) / (n_high − n_low)`,
//! and a point whose intensity is 0 was not measured (a missing point).
//!
//! The layout was learnt from two independent readers, SurfaceTopography's
//! `NMS.py` and D. Mendroch's `musurf-reader`, and checked on
//! SurfaceTopography's two example files. Where they disagree, asperity
//! follows the file: SurfaceTopography 1.27 divides by 65534 and takes the
//! spacing for millimetres (giving a 160 m field); the header's own `n_high`
//! is 65535, the largest count in both files is 65535 and maps there to the
//! header's `z_high` exactly, and a spacing in nm gives the 160 µm field of a
//! µsurf 100× objective, as `musurf-reader` reads it.

use asperity_core::{HeightField, LengthUnit, Units};

use crate::Metadata;
use crate::bytes::Fields;
use crate::error::{FResult, FormatError, malformed, unsupported};
use crate::format::{Access, Codec, Magic, Registration};

/// The version text at offset 32, the format's signature.
pub(crate) const VERSION: &[u8] = b"OM_MS_2.0";
const VERSION_AT: usize = 32;
const HEADER: usize = 3468;

/// Whether `bytes` start like an `.nms` file.
pub(crate) fn sniff(bytes: &[u8]) -> bool {
    bytes.get(VERSION_AT..VERSION_AT + VERSION.len()) == Some(VERSION)
}

/// The NUL-terminated text of the `len` bytes at `o`.
fn text_at(f: &Fields<'_>, o: usize, len: usize) -> FResult<String> {
    let field = f.bytes(o, len)?;
    let end = field.iter().position(|&c| c == 0).unwrap_or(len);
    Ok(field[..end].iter().map(|&c| char::from(c)).collect())
}

/// The header, checked to be one asperity reads.
fn header(bytes: &[u8]) -> FResult<Fields<'_>> {
    let Some(head) = bytes.get(..HEADER) else {
        return malformed(format!(
            "{} bytes: shorter than the {HEADER}-byte header (truncated?)",
            bytes.len()
        ));
    };
    if !sniff(head) {
        return malformed("no `OM_MS_2.0` version at byte 32: not a µsurf file");
    }
    let f = Fields::le(head);
    match (f.u32(0)?, f.u32(4)?) {
        (2, 1) => Ok(f),
        (2, 0) => unsupported("a profile (dimension type 0); asperity reads µsurf areas"),
        (t, 1) => unsupported(format!("data type {t}; asperity reads type 2 (u16 counts)")),
        (t, d) => malformed(format!("data type {t}, dimension type {d}")),
    }
}

/// The grid (points, spacings in nm) and the map of counts to heights (µm):
/// `z_low + (count − n_low) × scale`.
struct Layout {
    nx: usize,
    ny: usize,
    spacing: [f64; 2],
    n_low: f64,
    z_low: f64,
    scale: f64,
}

impl Layout {
    /// The height of a count (µm), or a missing point where not measured.
    fn height(&self, count: u16, measured: bool) -> f64 {
        if measured {
            self.z_low + (f64::from(count) - self.n_low) * self.scale
        } else {
            f64::NAN
        }
    }
}

fn layout(f: &Fields<'_>) -> FResult<Layout> {
    let (nx, ny) = (f.u32(1368)? as usize, f.u32(1372)? as usize);
    let (dx, dy) = (f.f64(1376)?, f.f64(1384)?);
    let (n_low, n_high) = (f.i32(8)?, f.i32(12)?);
    let (z_low, z_high) = (f.f64(16)?, f.f64(24)?);
    if nx == 0 || ny == 0 {
        return malformed(format!("{nx} × {ny} points: no data"));
    }
    for (name, v) in [("x spacing", dx), ("y spacing", dy)] {
        if !(v.is_finite() && v > 0.0) {
            return malformed(format!("the {name} {v} nm is not a positive length"));
        }
    }
    if n_high == n_low || !(z_low.is_finite() && z_high.is_finite()) {
        return malformed(format!(
            "the counts {n_low}…{n_high} cannot map to the heights {z_low}…{z_high} µm"
        ));
    }
    Ok(Layout {
        nx,
        ny,
        spacing: [dx, dy],
        n_low: f64::from(n_low),
        z_low,
        scale: (z_high - z_low) / (f64::from(n_high) - f64::from(n_low)),
    })
}

/// Reads an `.nms` height field.
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    let head = header(bytes)?;
    let layout = layout(&head)?;
    let (nx, ny, [dx, dy]) = (layout.nx, layout.ny, layout.spacing);
    let points = nx
        .checked_mul(ny)
        .filter(|n| n.checked_mul(3).is_some())
        .ok_or_else(|| FormatError::Malformed(format!("{nx} × {ny} points: too many")))?;
    let with_intensity = head.i32(1416)? > 0;
    let need = points * if with_intensity { 3 } else { 2 };
    let body = &bytes[HEADER..];
    if body.len() < need {
        return malformed(format!(
            "{nx} × {ny} points need {need} bytes after the header, the file has {} (truncated?)",
            body.len()
        ));
    }
    let measured = body[2 * points..].iter().map(|&i| !with_intensity || i > 0);
    let data = body[..2 * points]
        .chunks_exact(2)
        .zip(measured)
        .map(|(c, measured)| layout.height(u16::from_le_bytes([c[0], c[1]]), measured))
        .collect();
    Ok(HeightField::from_vec([nx, ny], data)?
        .with_spacing([dx * 1e-3, dy * 1e-3])?
        .with_units(Units::same(LengthUnit::Um)))
}

/// The header's texts: the version, the image's name and the date.
pub(crate) fn metadata(bytes: &[u8]) -> FResult<Metadata> {
    let head = header(bytes)?;
    let mut out = Metadata::new();
    for (key, at, len) in [("Version", 32, 16), ("Image", 52, 64), ("Date", 1076, 20)] {
        let v = text_at(&head, at, len)?;
        if !v.is_empty() {
            out.push((key.to_owned(), v));
        }
    }
    Ok(out)
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "NanoFocus µsurf (.nms)",
    extensions: &["nms"],
    height: Access::Read,
    notes: "OM_MS_2.0 areas: u16 counts mapped onto the header's height range in µm, spacing in nm, points of intensity 0 missing; version, image name and date as metadata; profiles refused",
    magic: Magic::Test(sniff),
    codec: Some(Codec::new(|b, _| read_height(b)).metadata(metadata)),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3 × 2 file: counts 0, 1, 2, 3, 4, 65535 over 1 µm … 2 µm, 500 nm
    /// spacing, the last-but-one point unmeasured (intensity 0).
    fn sample() -> Vec<u8> {
        let mut b = vec![0u8; HEADER];
        b[0..4].copy_from_slice(&2u32.to_le_bytes());
        b[4..8].copy_from_slice(&1u32.to_le_bytes());
        b[12..16].copy_from_slice(&65535i32.to_le_bytes());
        b[16..24].copy_from_slice(&1.0f64.to_le_bytes());
        b[24..32].copy_from_slice(&2.0f64.to_le_bytes());
        b[32..41].copy_from_slice(VERSION);
        b[52..58].copy_from_slice(b"Height");
        b[1076..1092].copy_from_slice(b"2026-11-28T19:30");
        b[1368..1372].copy_from_slice(&3u32.to_le_bytes());
        b[1372..1376].copy_from_slice(&2u32.to_le_bytes());
        b[1376..1384].copy_from_slice(&500.0f64.to_le_bytes());
        b[1384..1392].copy_from_slice(&250.0f64.to_le_bytes());
        b[1416..1420].copy_from_slice(&1i32.to_le_bytes());
        for c in [0u16, 1, 2, 3, 4, 65535] {
            b.extend(c.to_le_bytes());
        }
        b.extend([9, 9, 9, 9, 0, 9]);
        b
    }

    #[test]
    fn counts_map_onto_the_header_heights_with_unmeasured_points_missing() {
        let h = read_height(&sample()).unwrap();
        assert_eq!(h.dims(), [3, 2]);
        assert_eq!(h.spacing(), [0.5, 0.25]);
        assert_eq!(h.units().xy, LengthUnit::Um);
        assert_eq!(h.data()[0], 1.0);
        assert!((h.data()[3] - (1.0 + 3.0 / 65535.0)).abs() < 1e-15);
        assert!(h.data()[4].is_nan());
        assert_eq!(h.data()[5], 2.0, "n_high maps to z_high");
        let m = metadata(&sample()).unwrap();
        assert_eq!(m[1], ("Image".to_owned(), "Height".to_owned()));
        assert_eq!(m[2].1, "2026-11-28T19:30");
    }

    #[test]
    fn truncated_profiles_and_other_files_are_refused_with_the_reason() {
        let f = sample();
        let short = format!("{:?}", read_height(&f[..f.len() - 1]).unwrap_err());
        assert!(short.contains("truncated"), "{short}");
        assert!(read_height(&f[..100]).is_err());
        let mut profile = f.clone();
        profile[4] = 0;
        let e = format!("{:?}", read_height(&profile).unwrap_err());
        assert!(e.contains("profile"), "{e}");
        let mut other = f;
        other[32] = b'X';
        assert!(read_height(&other).is_err());
    }
}
