//! Digital Surf `.sur` (MountainsMap's binary surface file, written by many
//! profilometers and confocal microscopes), read.
//!
//! The file is a 512-byte little-endian header, a comment and a private zone
//! whose sizes the header gives, then NumPoints × NumLines samples (int16 or
//! int32, x fastest). Offsets in the header, from the format's published
//! layout (as SurfaceTopography and Gwyddion read it): the magic
//! `DIGITAL SURF` (0), the object count (14), object and instrument names
//! (20, 50; 30 bytes; not kept yet), the special-points flag (86), bits per
//! sample (98), the lowest stored value zmin (100), samples per line and lines (108,
//! 112; i32), their product (116), the x and y spacings (120, 124; f32), the
//! height per stored unit (128; f32), the units of the spacings and heights
//! (180, 196, 212; 16 bytes), the acquisition time (306–316; u16 seconds,
//! minutes, hours, day, month, year), the comment and private sizes (334,
//! 336) and the data offset (474; f32).
//!
//! Heights are stored value × the height per unit, in the heights' unit; the
//! spacings are in their own units (asperity keeps the x/y unit apart from
//! the z unit). Å and pm are converted to nm; other units (V, A…) are kept as
//! numbers without a unit. Files of several objects (series, multi-channel)
//! are refused: only the first surface is described by the header. With the
//! special-points flag set, the value zmin − 2 marks a point not measured:
//! it is read as a missing point (NaN, see `asperity_core::HeightField`).

use asperity_core::{HeightField, LengthUnit, Units};

use crate::bytes::Fields;
use crate::error::{FResult, FormatError, malformed, unsupported};
use crate::format::{Access, Codec, Magic, Registration};

const MAGIC: &[u8] = b"DIGITAL SURF";
/// Bytes of the header.
const HEADER: usize = 512;

/// A unit name: its length unit and the factor to it (Å and pm to nm), or
/// unitless for anything else (NUL- and space-padded text, Latin-1 unless
/// UTF-8).
fn unit(field: &[u8]) -> (LengthUnit, f64) {
    let field = &field[..field.iter().position(|&b| b == 0).unwrap_or(field.len())];
    // Latin-1 (µ is 0xB5) unless the bytes are UTF-8.
    let text: String = std::str::from_utf8(field).map_or_else(
        |_| field.iter().map(|&b| char::from(b)).collect(),
        str::to_owned,
    );
    length_unit(&text)
}

/// A length unit's name — m, mm, µm (um), nm, Å, pm — as asperity's unit and
/// the factor to it; anything else (V, A…) unitless with the numbers kept.
pub(crate) fn length_unit(text: &str) -> (LengthUnit, f64) {
    match text.trim() {
        "Å" | "A°" | "Angstrom" => (LengthUnit::Nm, 0.1),
        "pm" => (LengthUnit::Nm, 1e-3),
        t => LengthUnit::parse(t).map_or((LengthUnit::None, 1.0), |u| (u, 1.0)),
    }
}

/// What the header says of the surface and its samples.
struct Header {
    nx: usize,
    ny: usize,
    /// Bytes per sample (2 or 4).
    size: usize,
    /// The x and y spacings, in `xy`.
    spacing: [f64; 2],
    units: Units,
    /// Height per stored unit, in `units.z`.
    scale: f64,
    /// The stored value of a point not measured, if the file marks them.
    marker: Option<i64>,
    /// Where the samples start.
    start: usize,
}

/// Reads a Digital Surf file.
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    let h = header(bytes)?;
    let data = samples(bytes, &h)?;
    Ok(HeightField::from_vec([h.nx, h.ny], data)?
        .with_spacing(h.spacing)?
        .with_units(h.units))
}

/// The 512-byte header, checked.
fn header(bytes: &[u8]) -> FResult<Header> {
    if !bytes.starts_with(MAGIC) {
        return malformed("missing the `DIGITAL SURF` magic");
    }
    let head = bytes.get(..HEADER).ok_or_else(|| {
        FormatError::Malformed(format!(
            "the header has {HEADER} bytes, the file {} (truncated?)",
            bytes.len()
        ))
    })?;
    let f = Fields::le(head);
    let objects = f.u16(14)?;
    if objects > 1 {
        return unsupported(format!(
            "a Digital Surf file of {objects} objects (a series or several channels) is not supported"
        ));
    }
    let size = match f.u16(98)? {
        16 => 2,
        32 => 4,
        b => return malformed(format!("{b}-bit samples are not supported (16 or 32)")),
    };
    let [nx, ny] = points(&f)?;
    let (spacing, units, scale) = geometry(&f)?;
    // With the special-points flag, zmin − 2 marks a point not measured.
    let marker = (f.u16(86)? == 1).then_some(i64::from(f.i32(100)?) - 2);
    let start = HEADER + usize::from(f.u16(334)?) + usize::from(f.u16(336)?);
    Ok(Header {
        nx,
        ny,
        size,
        spacing,
        units,
        scale,
        marker,
        start,
    })
}

/// The samples per line and the lines, checked against their product.
fn points(f: &Fields<'_>) -> FResult<[usize; 2]> {
    let (nx, ny) = (f.i32(108)?, f.i32(112)?);
    if nx <= 0 || ny <= 0 {
        return malformed(format!("{nx} × {ny} points: no data"));
    }
    let (nx, ny) = (nx as usize, ny as usize);
    if f.u32(116)? as usize != nx * ny {
        return malformed(format!(
            "the point count does not match {nx} × {ny} (corrupt header)"
        ));
    }
    Ok([nx, ny])
}

/// The spacings (in the x unit), the units, and the height per stored unit.
fn geometry(f: &Fields<'_>) -> FResult<([f64; 2], Units, f64)> {
    let (dx, dy, dz) = (f.f32_wide(120)?, f.f32_wide(124)?, f.f32_wide(128)?);
    for (name, v) in [("x spacing", dx), ("y spacing", dy)] {
        if !(v.is_finite() && v > 0.0) {
            return malformed(format!("the {name} {v} is not a positive length"));
        }
    }
    if !dz.is_finite() {
        return malformed(format!("the height scale {dz} is not finite"));
    }
    let (ux, fx) = unit(f.bytes(180, 16)?);
    let (uy, fy) = unit(f.bytes(196, 16)?);
    let (uz, fz) = unit(f.bytes(212, 16)?);
    // Different x and y units: y in x's unit.
    let fy = if ux == uy {
        fy
    } else {
        fy * uy.metres().unwrap_or(1.0) / ux.metres().unwrap_or(1.0)
    };
    Ok(([dx * fx, dy * fy], Units { xy: ux, z: uz }, dz * fz))
}

/// The heights: stored values × the scale, the marked ones missing (NaN).
fn samples(bytes: &[u8], h: &Header) -> FResult<Vec<f64>> {
    let (n, size) = (h.nx * h.ny, h.size);
    let body = bytes.get(h.start..).unwrap_or(&[]);
    if body.len() < n * size {
        return malformed(format!(
            "{} × {} samples of {size} bytes need {} bytes, the file has {} after its header (truncated?)",
            h.nx,
            h.ny,
            n * size,
            body.len()
        ));
    }
    Ok(body[..n * size]
        .chunks_exact(size)
        .map(|c| {
            let v = if size == 2 {
                i32::from(i16::from_le_bytes([c[0], c[1]]))
            } else {
                i32::from_le_bytes([c[0], c[1], c[2], c[3]])
            };
            match h.marker {
                Some(m) if i64::from(v) == m => f64::NAN,
                _ => f64::from(v) * h.scale,
            }
        })
        .collect())
}

/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "Digital Surf / MountainsMap (.sur)",
    extensions: &["sur"],
    height: Access::Read,
    notes: "one surface of int16/int32 samples times the header's scale, in the file's units (Å, pm as nm); unmeasured points (zmin − 2) read as missing; series and multi-channel files refused",
    magic: Magic::Starts(&[b"DIGITAL SURF"]),
    codec: Some(Codec::new(|b, _| read_height(b))),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    use crate::error::refused as err;

    fn file(bits: u16, units: [&str; 3], values: &[i32]) -> Vec<u8> {
        let mut b = vec![0u8; HEADER];
        b[..12].copy_from_slice(MAGIC);
        b[14..16].copy_from_slice(&1u16.to_le_bytes());
        b[50..55].copy_from_slice(b"Probe");
        b[98..100].copy_from_slice(&bits.to_le_bytes());
        b[108..112].copy_from_slice(&3i32.to_le_bytes());
        b[112..116].copy_from_slice(&2i32.to_le_bytes());
        b[116..120].copy_from_slice(&6u32.to_le_bytes());
        b[120..124].copy_from_slice(&0.5f32.to_le_bytes());
        b[124..128].copy_from_slice(&0.25f32.to_le_bytes());
        b[128..132].copy_from_slice(&0.125f32.to_le_bytes());
        for (k, u) in units.iter().enumerate() {
            let o = 180 + 16 * k;
            b[o..o + u.len()].copy_from_slice(u.as_bytes());
        }
        b[334..336].copy_from_slice(&3u16.to_le_bytes());
        b.extend(b"abc");
        for &v in values {
            if bits == 16 {
                b.extend((v as i16).to_le_bytes());
            } else {
                b.extend(v.to_le_bytes());
            }
        }
        b
    }

    #[test]
    fn samples_times_the_scale_in_their_units() {
        for bits in [16, 32] {
            let h = read_height(&file(bits, ["um", "um", "nm"], &[1, 2, 3, -4, 5, 8])).unwrap();
            assert_eq!(h.dims(), [3, 2]);
            assert_eq!(h.spacing(), [0.5, 0.25]);
            assert_eq!(h.units().xy, LengthUnit::Um);
            assert_eq!(h.units().z, LengthUnit::Nm);
            assert_eq!(h.data(), &[0.125, 0.25, 0.375, -0.5, 0.625, 1.0]);
        }
        let a = read_height(&file(16, ["mm", "mm", "Å"], &[10, 0, 0, 0, 0, 0])).unwrap();
        let latin1 = |u: &str| u.chars().map(|c| c as u8).collect::<Vec<u8>>();
        let mut b = file(16, ["um", "um", "um"], &[1, 0, 0, 0, 0, 0]);
        b[212..214].copy_from_slice(&latin1("µm"));
        assert_eq!(read_height(&b).unwrap().units().z, LengthUnit::Um);
        assert_eq!(a.units().z, LengthUnit::Nm);
        assert!((a.data()[0] - 0.125).abs() < 1e-15);
    }

    #[test]
    fn corrupt_headers_are_refused_by_name() {
        let good = file(16, ["um", "um", "um"], &[0; 6]);
        let mut b = good.clone();
        b.truncate(b.len() - 1);
        assert!(err(read_height(&b)).contains("truncated"));
        let mut b = good.clone();
        b[98] = 8;
        assert!(err(read_height(&b)).contains("8-bit"));
        let mut b = good.clone();
        b[116] = 7;
        assert!(err(read_height(&b)).contains("point count"));
        let mut b = good.clone();
        b[14] = 2;
        assert!(err(read_height(&b)).contains("2 objects"));
        let mut b = good.clone();
        b[86] = 1;
        b[100..104].copy_from_slice(&2i32.to_le_bytes());
        b[HEADER + 3..HEADER + 5].copy_from_slice(&0i16.to_le_bytes());
        let holed = read_height(&b).unwrap();
        assert_eq!(holed.missing_count(), 6, "zmin − 2 marks missing points");
        b[86] = 0;
        assert!(
            read_height(&b).is_ok(),
            "without the flag zmin − 2 is a height"
        );
        let mut b = good;
        b[108..112].copy_from_slice(&(-3i32).to_le_bytes());
        assert!(err(read_height(&b)).contains("no data"));
        assert!(err(read_height(&b"DIGITAL SURF"[..])).contains("truncated"));
    }
}
