//! Keyence VK laser-scanning confocal microscopes: `.vk3`, `.vk4`, and the
//! zip-wrapped `.vk6`/`.vk7`, read.
//!
//! `.vk3`/`.vk4` (little-endian): the magic `VK3_`/`VK4_`, the DLL version, 4
//! zero bytes, then an offset table of 17 u32 — the sixth to eighth entries
//! (bytes 36, 40, 44) the offsets of up to three height images, 0 when
//! absent. After the table (and 4 more bytes in `.vk4`) come the measurement
//! conditions, u32 fields of which these are read: the date (fields 1–6), the
//! lens magnification (24), the x and y length of a pixel and the height
//! scale (42, 43, 44), all in picometres (read in nanometres). A height image is its width,
//! height, bits per point (8, 16 or 32), compression, byte size (checked to
//! be width × height × bits / 8), palette range, a 768-byte palette, then
//! the unsigned counts row by row (file rows are asperity's grid rows);
//! height = count × height scale. `.vk6`/`.vk7` are zip archives (after
//! their `VK6`/`VK7` magic) whose member `Vk4File` is a `.vk4`.
//!
//! Each height image is a channel (`Default`, `Height 2`, `Height 3`, as
//! SurfaceTopography names them). The layout was learnt from
//! SurfaceTopography's `VK.py` and Gwyddion's `keyence.c`; no instrument file
//! was at hand, so the tests use files built to that layout.

use asperity_core::{HeightField, LengthUnit, Units};

use crate::Metadata;
use crate::channel::{Channel, ChannelInfo, pick};
use crate::bytes::Fields;
use crate::error::{FResult, FormatError, malformed, unsupported};
use crate::zipped;
use crate::format::{Access, Codec, Magic, Registration};

/// The magics of the direct (`VK3_`, `VK4_`) and zipped (`VK6`, `VK7`) files.
pub(crate) const MAGICS: [&[u8]; 4] = [b"VK3_", b"VK4_", b"VK6", b"VK7"];
const CHANNEL_NAMES: [&str; 3] = ["Default", "Height 2", "Height 3"];
/// The zip member of a `.vk6`/`.vk7` that holds the `.vk4`.
const MEMBER: &str = "Vk4File";

/// Whether `bytes` start with a VK magic.
pub(crate) fn sniff(bytes: &[u8]) -> bool {
    MAGICS.iter().any(|m| bytes.starts_with(m))
}

fn u32_at(b: &[u8], o: usize) -> FResult<u32> {
    Fields::le(b).u32(o)
}

/// The `.vk3`/`.vk4` stream: the file itself, or a `.vk6`/`.vk7`'s member.
fn stream(bytes: &[u8]) -> FResult<std::borrow::Cow<'_, [u8]>> {
    if bytes.starts_with(b"VK3_") || bytes.starts_with(b"VK4_") {
        return Ok(bytes.into());
    }
    if !sniff(bytes) {
        return malformed("no VK3_, VK4_, VK6 or VK7 magic: not a Keyence VK file");
    }
    let mut zip = zipped::open(bytes, |e| {
        FormatError::Malformed(format!(
            "a VK6/VK7 file is a zip archive, this one is not: {e}"
        ))
    })?;
    let out = zipped::required(&mut zip, MEMBER, u64::MAX, FormatError::Malformed)?;
    if !(out.starts_with(b"VK4_") || out.starts_with(b"VK3_")) {
        return malformed(format!("member {MEMBER:?} is no VK4 file"));
    }
    Ok(out.into())
}

/// Where the measurement conditions start.
fn conditions(vk: &[u8]) -> usize {
    if vk.starts_with(b"VK4_") { 84 } else { 80 }
}

/// The offsets of the height images present, by channel.
fn images(vk: &[u8]) -> FResult<Vec<(usize, usize)>> {
    let mut out = Vec::new();
    for (k, at) in [36, 40, 44].into_iter().enumerate() {
        let offset = u32_at(vk, at)? as usize;
        if offset != 0 {
            out.push((k, offset));
        } else if k == 0 {
            return malformed("the offset table names no height image");
        }
    }
    Ok(out)
}

/// The file's height images as channels.
pub(crate) fn channels(bytes: &[u8]) -> FResult<Vec<ChannelInfo>> {
    let vk = stream(bytes)?;
    Ok(images(&vk)?
        .into_iter()
        .enumerate()
        .map(|(index, (k, _))| ChannelInfo {
            index,
            name: CHANNEL_NAMES[k].to_owned(),
            height: true,
        })
        .collect())
}

/// The points the file declares (its largest image), for the memory estimate.
pub(crate) fn declared_points(bytes: &[u8]) -> FResult<u128> {
    let vk = stream(bytes)?;
    let mut most = 0u128;
    for (_, at) in images(&vk)? {
        let (w, h) = (u32_at(&vk, at)?, u32_at(&vk, at + 4)?);
        most = most.max(u128::from(w) * u128::from(h));
    }
    Ok(most)
}

/// Reads the height image `choice` names (default the first).
pub(crate) fn read_channel(bytes: &[u8], choice: Option<&Channel>) -> FResult<HeightField> {
    let vk = stream(bytes)?;
    let list = images(&vk)?;
    let infos = channels(bytes)?;
    let (k, at) = list[pick(&infos, choice)?];
    let field = |i: usize| u32_at(&vk, conditions(&vk) + 4 * i);
    let (dx, dy, dz) = (field(42)?, field(43)?, field(44)?);
    if dx == 0 || dy == 0 {
        return malformed(format!("a pixel of {dx} × {dy} pm"));
    }
    // Picometres, read in nanometres (asperity's smallest length unit).
    let ([w, h], heights) = image(&vk, CHANNEL_NAMES[k], at, f64::from(dz) * 1e-3)?;
    let nm = Units::same(LengthUnit::Nm);
    Ok(HeightField::from_vec([w, h], heights)?
        .with_spacing([f64::from(dx) * 1e-3, f64::from(dy) * 1e-3])?
        .with_units(nm))
}

/// The image `name` whose header is at `at`: its width and height, and its
/// counts × `scale`.
fn image(vk: &[u8], name: &str, at: usize, scale: f64) -> FResult<([usize; 2], Vec<f64>)> {
    let [w, h, bits, _, size] = [0, 4, 8, 12, 16].map(|o| u32_at(vk, at + o));
    let (w, h, bits, size) = (w? as usize, h? as usize, bits?, size? as usize);
    if !matches!(bits, 8 | 16 | 32) {
        return unsupported(format!(
            "{name}: {bits} bits a point (8, 16 or 32 are read)"
        ));
    }
    let bytes_per = bits as usize / 8;
    let n = w
        .checked_mul(h)
        .filter(|&n| n > 0 && n.checked_mul(bytes_per) == Some(size))
        .ok_or_else(|| {
            FormatError::Malformed(format!(
                "{name}: {w} × {h} points of {bits} bits are not its {size} bytes"
            ))
        })?;
    let start = at + 28 + 768;
    let data = vk.get(start..start.saturating_add(size)).ok_or_else(|| {
        FormatError::Malformed(format!(
            "{name}: {size} bytes at {start} run past the file's end (truncated?)"
        ))
    })?;
    let heights = data
        .chunks_exact(bytes_per)
        .take(n)
        .map(|c| {
            let count = match c.len() {
                1 => u32::from(c[0]),
                2 => u32::from(u16::from_le_bytes([c[0], c[1]])),
                _ => u32::from_le_bytes([c[0], c[1], c[2], c[3]]),
            };
            f64::from(count) * scale
        })
        .collect();
    Ok(([w, h], heights))
}

/// The date, lens and scales of the measurement conditions.
pub(crate) fn metadata(bytes: &[u8]) -> FResult<Metadata> {
    let vk = stream(bytes)?;
    let field = |i: usize| u32_at(&vk, conditions(&vk) + 4 * i);
    let date = format!(
        "{:04}-{:02}-{:02} {:02}:{:02}:{:02}",
        field(1)?,
        field(2)?,
        field(3)?,
        field(4)?,
        field(5)?,
        field(6)?
    );
    Ok(vec![
        ("Date".to_owned(), date),
        ("Lens magnification".to_owned(), field(24)?.to_string()),
        ("X length per pixel (pm)".to_owned(), field(42)?.to_string()),
        ("Y length per pixel (pm)".to_owned(), field(43)?.to_string()),
        ("Height scale (pm)".to_owned(), field(44)?.to_string()),
    ])
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "Keyence VK (.vk3, .vk4, .vk6, .vk7)",
    extensions: &["vk3", "vk4", "vk6", "vk7"],
    height: Access::Read,
    notes: "the height images as channels: 8/16/32-bit counts × the height scale, pixel lengths from the measurement conditions (pm, read in nm); .vk6/.vk7 as the .vk4 in their zip; date, lens and scales kept as metadata",
    magic: Magic::Test(sniff),
    codec: Some(Codec::new(read_channel)
        .channels(channels)
        .metadata(metadata)
        .declared(|b| declared_points(b).map(crate::pixel_bytes))),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use std::io::Cursor;
    use std::io::Write;

    use super::*;

    /// A `.vk4` with one 3 × 2 16-bit height image: 500 pm pixels along x,
    /// 250 along y, 10 pm a count.
    fn vk4() -> Vec<u8> {
        let mut b = b"VK4_\x01\x00\x00\x00\x00\x00\x00\x00".to_vec();
        let cond = 84;
        let image = cond + 4 * 80;
        b.resize(image, 0);
        b[36..40].copy_from_slice(&(image as u32).to_le_bytes());
        for (i, v) in [
            (1, 2026),
            (2, 11),
            (3, 28),
            (24, 50),
            (42, 500),
            (43, 250),
            (44, 10),
        ] {
            b[cond + 4 * i..cond + 4 * i + 4].copy_from_slice(&(v as u32).to_le_bytes());
        }
        for v in [3u32, 2, 16, 0, 12, 0, 0] {
            b.extend(v.to_le_bytes());
        }
        b.extend([0; 768]);
        for c in [0u16, 1, 2, 3, 4, 65535] {
            b.extend(c.to_le_bytes());
        }
        b
    }

    #[test]
    fn a_vk4_height_image_is_read_from_picometres() {
        let h = read_channel(&vk4(), None).unwrap();
        assert_eq!(h.dims(), [3, 2]);
        assert_eq!(h.spacing(), [0.5, 0.25]);
        assert_eq!(h.units().z, LengthUnit::Nm);
        assert_eq!(h.row(1), &[0.03, 0.04, 655.35]);
        let m = metadata(&vk4()).unwrap();
        assert_eq!(m[0].1, "2026-11-28 00:00:00");
        assert_eq!(m[1].1, "50");
    }

    #[test]
    fn a_vk6_is_the_vk4_in_its_zip() {
        let mut prefixed = Cursor::new(b"VK6".to_vec());
        prefixed.set_position(3);
        let mut zip = zip::ZipWriter::new(prefixed);
        let opts = zip::write::SimpleFileOptions::default();
        zip.start_file(MEMBER, opts).unwrap();
        zip.write_all(&vk4()).unwrap();
        let vk6 = zip.finish().unwrap().into_inner();
        let h = read_channel(&vk6, None).unwrap();
        assert_eq!(h.row(0), &[0.0, 0.01, 0.02]);
        assert_eq!(channels(&vk6).unwrap().len(), 1);
    }

    #[test]
    fn truncated_and_inconsistent_files_are_refused() {
        let f = vk4();
        for cut in [0, 3, 40, 200, f.len() - 1] {
            assert!(read_channel(&f[..cut], None).is_err(), "cut at {cut}");
        }
        let mut wrong = f;
        let image = 84 + 4 * 80;
        wrong[image + 16] = 13; // byte size no longer width × height × 2
        let e = format!("{:?}", read_channel(&wrong, None).unwrap_err());
        assert!(e.contains("are not its 13 bytes"), "{e}");
    }
}
