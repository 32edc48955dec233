//! Park Systems AFM `.tiff`, read.
//!
//! A TIFF whose first directory carries four private tags: 50432, the magic
//! 0x0E031301; 50433, the version (0x1000001 or 0x1000002); 50434, the data;
//! 50435, the header — little-endian: image type (u32; 0 an image, 2
//! spectroscopy; 1, a line profile, is refused), the source name (32 UTF-16
//! characters), …, points along x and y (u32, at 100), the scan's physical
//! size along x and y (f64 µm, at 140), …, the data gain, scale factor and
//! offset (f64, at 220) and their unit (8 UTF-16 characters, at 244; empty
//! means µm); version 2 adds the data type at 348 (0 int16, 1 int32, 2
//! f32; version 1 is int16). z = (raw × scale + offset) × gain in the data
//! unit, a scale of 0 meaning 1. The lines are stored from the image's last,
//! as SurfaceTopography and Gwyddion show them. Only these tags are read, so
//! the directory is walked here rather than through an image decoder.
//! Layout learnt from SurfaceTopography's `PS.py` and checked on its example
//! file.

use asperity_core::{HeightField, LengthUnit, Units};

use crate::bytes::Fields;
use crate::error::{FResult, FormatError, malformed, unsupported};
use crate::raster::from_last_line;
use crate::format::{Access, Codec, Magic, Registration};

const MAGIC: u32 = 0x0E03_1301;
const TAG_MAGIC: u16 = 50432;
const TAG_VERSION: u16 = 50433;
const TAG_DATA: u16 = 50434;
const TAG_HEADER: u16 = 50435;

/// Whether `bytes` start like a little-endian TIFF (Park files are).
pub(crate) fn sniff(bytes: &[u8]) -> bool {
    bytes.starts_with(b"II*\0")
}

/// The first directory's entries: (tag, type, count, value or offset).
fn directory(bytes: &[u8]) -> FResult<Vec<(u16, u16, u32, u32)>> {
    if !sniff(bytes) {
        return malformed("not a little-endian TIFF (Park Systems files are)");
    }
    let f = Fields::le(bytes);
    let truncated =
        |_| FormatError::Malformed("the TIFF directory is cut short (truncated?)".into());
    let at = f.u32(4).map_err(truncated)? as usize;
    let mut c = f.cursor(at);
    let n = usize::from(c.u16().map_err(truncated)?);
    (0..n)
        .map(|_| Ok((c.u16()?, c.u16()?, c.u32()?, c.u32()?)))
        .collect::<FResult<_>>()
        .map_err(truncated)
}

/// The bytes of a tag holding `count` one-byte items (BYTE or UNDEFINED).
fn block(bytes: &[u8], (_, _, count, value): (u16, u16, u32, u32)) -> FResult<&[u8]> {
    let (start, n) = (value as usize, count as usize);
    if n <= 4 {
        return malformed("a Park tag too short to hold its block");
    }
    start
        .checked_add(n)
        .and_then(|end| bytes.get(start..end))
        .ok_or_else(|| {
            FormatError::Malformed(
                "a Park tag's block runs past the file's end (truncated?)".into(),
            )
        })
}

fn utf16(b: &[u8]) -> String {
    let units: Vec<u16> = b
        .chunks_exact(2)
        .map(|c| u16::from_le_bytes([c[0], c[1]]))
        .collect();
    String::from_utf16_lossy(&units)
        .trim_end_matches(['\0', ' '])
        .to_string()
}

/// What the Park header says: points, scan size (µm), the raw data's type
/// and how a raw value becomes µm.
struct Header {
    nx: usize,
    ny: usize,
    size: [f64; 2],
    /// 0: int16, 1: int32, 2: f32.
    kind: u32,
    /// (raw × scale + offset) × gain, in the data unit; × `to_um` in µm.
    gain: f64,
    scale: f64,
    offset: f64,
    to_um: f64,
}

/// The Park header and data blocks of the first directory, and whether
/// the file is of version 2 (version 1 and other TIFFs refused).
fn park_blocks(bytes: &[u8]) -> FResult<(&[u8], &[u8], bool)> {
    let dir = directory(bytes)?;
    let tag = |t: u16| dir.iter().copied().find(|e| e.0 == t);
    if tag(TAG_MAGIC).map(|e| e.3) != Some(MAGIC) {
        return unsupported("a TIFF without Park Systems' tags (only Park AFM TIFFs are read)");
    }
    let version = tag(TAG_VERSION).map_or(0, |e| e.3);
    if version != 0x100_0001 && version != 0x100_0002 {
        return malformed(format!(
            "Park TIFF version 0x{version:x} (1 and 2 are read)"
        ));
    }
    let missing = |t: u16| FormatError::Malformed(format!("no tag {t}"));
    let head = block(bytes, tag(TAG_HEADER).ok_or_else(|| missing(TAG_HEADER))?)?;
    let data = block(bytes, tag(TAG_DATA).ok_or_else(|| missing(TAG_DATA))?)?;
    Ok((head, data, version == 0x100_0002))
}

/// Reads a Park Systems TIFF.
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    let (head, data, version_2) = park_blocks(bytes)?;
    let h = header(head, version_2)?;
    let (nx, ny, size) = (h.nx, h.ny, if h.kind == 0 { 2 } else { 4 });
    let need = nx.checked_mul(ny).and_then(|n| n.checked_mul(size));
    let Some(data) = need.and_then(|n| data.get(..n)) else {
        return malformed(format!(
            "the data block holds {} bytes, {nx} × {ny} points of {size} need more",
            data.len()
        ));
    };
    // Lateral sizes are µm; heights in the data unit, converted to µm too.
    let heights = from_last_line(data, nx, size)
        .map(|c| {
            let raw = match h.kind {
                0 => f64::from(i16::from_le_bytes([c[0], c[1]])),
                1 => f64::from(i32::from_le_bytes([c[0], c[1], c[2], c[3]])),
                _ => f64::from(f32::from_le_bytes([c[0], c[1], c[2], c[3]])),
            };
            let v = (raw * h.scale + h.offset) * h.gain;
            if h.to_um == 1.0 { v } else { v * h.to_um }
        })
        .collect();
    let [lx, ly] = h.size;
    if !(lx.is_finite() && lx > 0.0 && ly.is_finite() && ly > 0.0) {
        return malformed(format!("the scan size {lx} × {ly} µm is not positive"));
    }
    Ok(HeightField::from_vec([nx, ny], heights)?
        .with_spacing([lx / nx as f64, ly / ny as f64])?
        .with_units(Units::same(LengthUnit::Um)))
}

/// The data's unit (µm when the header names none), a length.
fn data_unit(f: &Fields<'_>) -> FResult<LengthUnit> {
    match utf16(f.bytes(244, 16)?).as_str() {
        "" | "um" | "µm" => Ok(LengthUnit::Um),
        u => LengthUnit::parse(u)
            .ok()
            .filter(|u| *u != LengthUnit::None)
            .ok_or_else(|| FormatError::Malformed(format!("data unit {u:?} is not a length"))),
    }
}

/// The Park header block (284 bytes, 352 in version 2), checked.
fn header(head: &[u8], version_2: bool) -> FResult<Header> {
    let need_head = if version_2 { 352 } else { 284 };
    if head.len() < need_head {
        return malformed(format!(
            "a header of {} bytes (version needs {need_head})",
            head.len()
        ));
    }
    let f = Fields::le(head);
    match f.u32(0)? {
        0 | 2 => {}
        1 => return unsupported("a Park line profile"),
        t => return malformed(format!("image type {t}")),
    }
    let (nx, ny) = (f.u32(100)? as usize, f.u32(104)? as usize);
    let kind = if version_2 { f.u32(348)? } else { 0 };
    if kind > 2 {
        return malformed(format!("data type {kind} (0, 1 and 2 are read)"));
    }
    if nx == 0 || ny == 0 {
        return malformed(format!("{nx} × {ny} points: no data"));
    }
    let z = data_unit(&f)?;
    let scale = f.f64(228)?;
    Ok(Header {
        nx,
        ny,
        size: [f.f64(140)?, f.f64(148)?],
        kind,
        gain: f.f64(220)?,
        scale: if scale == 0.0 { 1.0 } else { scale },
        offset: f.f64(236)?,
        to_um: z.metres().map_or(1.0, |m| m / 1e-6),
    })
}

/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "Park Systems AFM TIFF (.tiff)",
    extensions: &["tiff", "tif"],
    height: Access::Read,
    notes: "the first directory's Park tags: int16/int32/f32 data, (raw × scale + offset) × gain in µm, scan size in µm, lines from the last; other TIFFs and line profiles refused",
    magic: Magic::Test(sniff),
    codec: Some(Codec::new(|b, _| read_height(b))),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    /// A Park TIFF of 3 × 2 int16 values (version 1), gain 2, offset 1.
    fn file(values: &[i16]) -> Vec<u8> {
        let mut head = vec![0u8; 284];
        head[100..104].copy_from_slice(&3u32.to_le_bytes());
        head[104..108].copy_from_slice(&2u32.to_le_bytes());
        head[140..148].copy_from_slice(&6.0f64.to_le_bytes());
        head[148..156].copy_from_slice(&1.0f64.to_le_bytes());
        head[220..228].copy_from_slice(&2.0f64.to_le_bytes());
        head[236..244].copy_from_slice(&1.0f64.to_le_bytes());
        let data: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let (head_at, data_at, dir_at) = (8u32, 8 + 284, 8 + 284 + data.len() as u32);
        let mut f = b"II*\0".to_vec();
        f.extend(dir_at.to_le_bytes());
        f.extend(&head);
        f.extend(&data);
        f.extend(4u16.to_le_bytes());
        for (t, ty, count, value) in [
            (TAG_MAGIC, 4u16, 1u32, MAGIC),
            (TAG_VERSION, 4, 1, 0x100_0001),
            (TAG_DATA, 1, data.len() as u32, data_at),
            (TAG_HEADER, 7, 284, head_at),
        ] {
            f.extend(t.to_le_bytes());
            f.extend(ty.to_le_bytes());
            f.extend(count.to_le_bytes());
            f.extend(value.to_le_bytes());
        }
        f
    }

    #[test]
    fn reads_gain_times_raw_plus_offset_from_the_last_line() {
        let h = read_height(&file(&[0, 1, 2, 3, 4, -5])).unwrap();
        assert_eq!(h.dims(), [3, 2]);
        assert_eq!(h.spacing(), [2.0, 0.5]);
        // Row 0 is the stored second line: (3 + 1) × 2, (4 + 1) × 2, (−5 + 1) × 2.
        assert_eq!(&h.data()[..3], &[8.0, 10.0, -8.0]);
    }

    #[test]
    fn other_tiffs_and_truncation_are_refused() {
        let good = file(&[0; 6]);
        for cut in 0..good.len() {
            assert!(read_height(&good[..cut]).is_err(), "cut at {cut}");
        }
        let mut other = good.clone();
        let n = other.len();
        other[n - 48 + 8..n - 48 + 12].copy_from_slice(&7u32.to_le_bytes());
        assert!(format!("{:?}", read_height(&other).unwrap_err()).contains("Park"));
    }
}
