//! FRT MicroProf `.frt` (optical profilometers), read.
//!
//! `FRTM_GLIDERV` and a four-character version (`1.00` or `1.01`), the number
//! of blocks (u16), then blocks of an id (u16), a size (u32 in 1.00, u64 in
//! 1.01) and that many bytes. Little-endian. Three blocks describe the
//! topography: 0x66 — points along x and y and the bits per point (u32 each;
//! 16, unsigned, or 32, signed); 0x67 — the field's physical sizes along x
//! and y (f64, metres); 0x6c — the measuring range (u32) and the height scale
//! (f64, metres per count). Block 0x0b holds the counts, row by row, x
//! fastest, the first stored row being the image's last line (flipped, as
//! Gwyddion's `microprof.c` and SurfaceTopography 1.27 read it); a count of 1
//! marks a point not measured, read as a missing point (NaN). Other blocks
//! (instrument settings, intensity, text) are skipped. Layout learnt from
//! SurfaceTopography's `FRT.py` and checked on its example file.

use asperity_core::{HeightField, LengthUnit, Units};

use crate::error::{FResult, FormatError, malformed, unsupported};
use crate::raster::from_last_line;
use crate::bytes::Fields;
use crate::format::{Access, Codec, Magic, Registration};

pub(crate) const MAGIC: &[u8] = b"FRTM_GLIDERV";

/// The blocks by id (the first of each id).
fn blocks(bytes: &[u8]) -> FResult<Vec<(u16, &[u8])>> {
    let version = bytes.get(MAGIC.len()..MAGIC.len() + 4).ok_or_else(|| {
        FormatError::Malformed("the file ends in its version (truncated?)".into())
    })?;
    let wide = match version {
        b"1.00" => false,
        b"1.01" => true,
        v => {
            return unsupported(format!(
                "FRT version {:?} (1.00 and 1.01 are read)",
                String::from_utf8_lossy(v)
            ));
        }
    };
    let mut c = Fields::le(bytes).cursor(MAGIC.len() + 4);
    let count = c.u16().map_err(|_| {
        FormatError::Malformed("the file ends before its blocks (truncated?)".into())
    })?;
    let mut out = Vec::new();
    for _ in 0..count {
        // The last blocks may be absent, as SurfaceTopography allows.
        let Ok(id) = c.u16() else { break };
        let size = if wide { c.u64() } else { c.u32().map(u64::from) };
        let Ok(size) = size else { break };
        let content = usize::try_from(size)
            .map_err(|_| ())
            .and_then(|n| c.take(n).map_err(|_| ()))
            .map_err(|()| {
                FormatError::Malformed(format!(
                    "block 0x{id:04x} of {size} bytes runs past the file's end (truncated?)"
                ))
            })?;
        out.push((id, content));
    }
    Ok(out)
}

/// What the size, extent and scale blocks say: points along x and y, bits
/// per point and their bytes, the x and y sizes (m), metres per count.
struct Layout {
    nx: usize,
    ny: usize,
    bits: u32,
    width: usize,
    size: [f64; 2],
    scale: f64,
}

/// The first block `id` of at least `least` bytes.
fn block<'a>(blocks: &[(u16, &'a [u8])], id: u16, least: usize) -> FResult<Fields<'a>> {
    match blocks.iter().find(|(i, _)| *i == id) {
        Some((_, b)) if b.len() >= least => Ok(Fields::le(b)),
        Some(_) => malformed(format!("block 0x{id:04x} is shorter than {least} bytes")),
        None => malformed(format!(
            "no block 0x{id:04x} (the topography needs 0x0066, 0x0067, 0x006c and 0x000b)"
        )),
    }
}

/// The layout from the blocks 0x0066, 0x0067 and 0x006c, checked.
fn layout(blocks: &[(u16, &[u8])]) -> FResult<Layout> {
    let size = block(blocks, 0x66, 12)?;
    let extent = block(blocks, 0x67, 16)?;
    let (nx, ny, bits) = (size.u32(0)? as usize, size.u32(4)? as usize, size.u32(8)?);
    let scale = block(blocks, 0x6c, 12)?.f64(4)?;
    let [lx, ly] = [extent.f64(0)?, extent.f64(8)?];
    if nx == 0 || ny == 0 {
        return malformed(format!("{nx} × {ny} points: no data"));
    }
    for (name, v) in [("x size", lx), ("y size", ly)] {
        if !(v.is_finite() && v > 0.0) {
            return malformed(format!("the {name} {v} m is not positive"));
        }
    }
    if !scale.is_finite() {
        return malformed("the height scale is not a number");
    }
    let width = match bits {
        16 => 2,
        32 => 4,
        b => return malformed(format!("{b} bits a point (16 and 32 are read)")),
    };
    let size = [lx, ly];
    Ok(Layout { nx, ny, bits, width, size, scale })
}

/// Reads the topography of an FRT file.
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    if !bytes.starts_with(MAGIC) {
        return malformed("missing the `FRTM_GLIDERV` magic");
    }
    let blocks = blocks(bytes)?;
    let Layout { nx, ny, bits, width, size: [lx, ly], scale } = layout(&blocks)?;
    let data = block(&blocks, 0x0b, 0)?.all();
    let need = nx.checked_mul(ny).and_then(|n| n.checked_mul(width));
    if need != Some(data.len()) {
        return malformed(format!(
            "the data block holds {} bytes, {nx} × {ny} points of {bits} bits need {}",
            data.len(),
            need.map_or("more than fit in memory".into(), |n| n.to_string())
        ));
    }
    // Rows stored from the last line up; a count of 1 is a point not measured.
    let heights = from_last_line(data, nx, width)
        .map(|c| match width {
            2 => i64::from(u16::from_le_bytes([c[0], c[1]])),
            _ => i64::from(i32::from_le_bytes([c[0], c[1], c[2], c[3]])),
        })
        .map(|count| if count == 1 { f64::NAN } else { count as f64 * scale })
        .collect();
    Ok(HeightField::from_vec([nx, ny], heights)?
        .with_spacing([lx / nx as f64, ly / ny as f64])?
        .with_units(Units::same(LengthUnit::M)))
}

/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "FRT MicroProf (.frt)",
    extensions: &["frt"],
    height: Access::Read,
    notes: "versions 1.00 and 1.01: the topography's 16/32-bit counts × the height scale in metres, sizes in metres; a count of 1 read as missing",
    magic: Magic::Starts(&[MAGIC]),
    codec: Some(Codec::new(|b, _| read_height(b))),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    fn block(id: u16, content: &[u8]) -> Vec<u8> {
        let mut b = id.to_le_bytes().to_vec();
        b.extend((content.len() as u32).to_le_bytes());
        b.extend(content);
        b
    }

    /// A version 1.00 file of 3 × 2 int32 counts, 6 µm × 1 µm, 1 nm a count.
    fn file(counts: &[i32]) -> Vec<u8> {
        let mut size = Vec::new();
        for v in [3u32, 2, 32] {
            size.extend(v.to_le_bytes());
        }
        let mut extent = Vec::new();
        for v in [6e-6f64, 1e-6, 0.0, 0.0, 1.0] {
            extent.extend(v.to_le_bytes());
        }
        extent.extend(0u32.to_le_bytes());
        let mut range = 7u32.to_le_bytes().to_vec();
        range.extend(1e-9f64.to_le_bytes());
        let data: Vec<u8> = counts.iter().flat_map(|v| v.to_le_bytes()).collect();
        let mut out = MAGIC.to_vec();
        out.extend(b"1.00");
        out.extend(5u16.to_le_bytes());
        out.extend(block(0x65, b"a comment\0"));
        out.extend(block(0x66, &size));
        out.extend(block(0x67, &extent));
        out.extend(block(0x6c, &range));
        out.extend(block(0x0b, &data));
        out
    }

    #[test]
    fn reads_counts_times_the_scale_with_missing_points() {
        // Stored rows: (0, 2, 1) then (−4, 5, 6), the first the last line.
        let h = read_height(&file(&[0, 2, 1, -4, 5, 6])).unwrap();
        assert_eq!(h.dims(), [3, 2]);
        assert_eq!(h.spacing(), [2e-6, 0.5e-6]);
        assert_eq!(*h.get(1, 1), 2e-9);
        assert!(h.get(2, 1).is_nan(), "a count of 1 is not measured");
        assert_eq!(*h.get(0, 0), -4e-9);
    }

    #[test]
    fn truncation_versions_and_missing_blocks_are_refused() {
        let good = file(&[0; 6]);
        for cut in 0..good.len() {
            assert!(read_height(&good[..cut]).is_err(), "cut at {cut}");
        }
        let mut v = good.clone();
        v[MAGIC.len() + 3] = b'9';
        assert!(format!("{:?}", read_height(&v).unwrap_err()).contains("version"));
        let mut no_data = good.clone();
        let at = no_data.len() - 24 - 6;
        no_data[at] = 0x0c;
        assert!(format!("{:?}", read_height(&no_data).unwrap_err()).contains("0x000b"));
    }
}
