//! KLA Zeta (Zeta Instruments) optical profilers' `.zmg`, read.
//!
//! Little-endian: the magic `Zeta-Instruments`, then at byte 85 the points
//! along x and y (u32), at 97 the steps along x, y and z (f32, µm), at 117
//! the length of a comment (u32), at 131 the recipe's name (68 bytes); the
//! comment follows the 205-byte header, then the heights as u16 counts × the
//! z step, x fastest, row by row (file rows are asperity's grid rows). Layout
//! from Gwyddion's `zmgfile.c` as SurfaceTopography's `ZMG.py` reads it;
//! checked against the latter on a file built to that layout (no instrument
//! file is public).

use asperity_core::{HeightField, LengthUnit, Units};

use crate::Metadata;
use crate::bytes::Fields;
use crate::error::{FResult, FormatError, malformed};
use crate::format::{Access, Codec, Magic, Registration};

/// The file's magic.
pub(crate) const MAGIC: &[u8] = b"Zeta-Instruments";
const HEADER: usize = 205;

struct Header {
    nx: usize,
    ny: usize,
    step: [f64; 3],
    comment: usize,
    recipe: String,
}

fn header(b: &[u8]) -> FResult<Header> {
    if !b.starts_with(MAGIC) {
        return malformed("missing the `Zeta-Instruments` magic");
    }
    let Some(h) = b.get(..HEADER) else {
        return malformed(format!(
            "shorter than the {HEADER}-byte header (truncated?)"
        ));
    };
    let f = Fields::le(h);
    let (nx, ny) = (f.u32(85)? as usize, f.u32(89)? as usize);
    let step = [f.f32_wide(97)?, f.f32_wide(101)?, f.f32_wide(105)?];
    if nx == 0 || ny == 0 {
        return malformed(format!("{nx} × {ny} points: no data"));
    }
    if !(step[..2].iter().all(|s| s.is_finite() && *s > 0.0) && step[2].is_finite()) {
        return malformed(format!("the steps {step:?} are not lengths"));
    }
    let recipe = f
        .bytes(131, 68)?
        .iter()
        .take_while(|&&c| c != 0)
        .map(|&c| char::from(c))
        .collect();
    Ok(Header {
        nx,
        ny,
        step,
        comment: f.u32(117)? as usize,
        recipe,
    })
}

/// Reads a `.zmg` height field.
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    let h = header(bytes)?;
    let start = HEADER.saturating_add(h.comment);
    let n =
        h.nx.checked_mul(h.ny)
            .filter(|n| n.checked_mul(8).is_some());
    let need = n
        .map(|n| n * 2)
        .ok_or_else(|| FormatError::Malformed(format!("{} × {} points: too many", h.nx, h.ny)))?;
    let body = bytes
        .get(start..start.saturating_add(need))
        .ok_or_else(|| {
            FormatError::Malformed(format!(
                "{} × {} u16 counts after a {}-byte comment run past the file's end (truncated?)",
                h.nx, h.ny, h.comment
            ))
        })?;
    let data = body
        .chunks_exact(2)
        .map(|c| f64::from(u16::from_le_bytes([c[0], c[1]])) * h.step[2])
        .collect();
    let um = Units::same(LengthUnit::Um);
    Ok(HeightField::from_vec([h.nx, h.ny], data)?
        .with_spacing([h.step[0], h.step[1]])?
        .with_units(um))
}

/// The recipe's name and the comment.
pub(crate) fn metadata(bytes: &[u8]) -> FResult<Metadata> {
    let h = header(bytes)?;
    let comment = bytes
        .get(HEADER..HEADER.saturating_add(h.comment))
        .map(|c| c.iter().map(|&b| char::from(b)).collect::<String>())
        .unwrap_or_default();
    Ok(vec![
        ("Recipe".to_owned(), h.recipe),
        (
            "Comment".to_owned(),
            comment.trim_end_matches('\0').to_owned(),
        ),
    ])
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "KLA Zeta (.zmg)",
    extensions: &["zmg"],
    height: Access::Read,
    notes: "u16 counts × the z step, steps in µm; the recipe's name and the comment kept as metadata",
    magic: Magic::Starts(&[MAGIC]),
    codec: Some(Codec::new(|b, _| read_height(b)).metadata(metadata)),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Vec<u8> {
        let mut b = vec![0u8; HEADER];
        b[..16].copy_from_slice(MAGIC);
        b[85..89].copy_from_slice(&3u32.to_le_bytes());
        b[89..93].copy_from_slice(&2u32.to_le_bytes());
        for (o, v) in [(97, 0.5f32), (101, 0.25), (105, 0.01)] {
            b[o..o + 4].copy_from_slice(&v.to_le_bytes());
        }
        b[117..121].copy_from_slice(&4u32.to_le_bytes());
        b[131..137].copy_from_slice(b"recipe");
        b.extend(b"note");
        for c in [0u16, 100, 200, 300, 400, 65535] {
            b.extend(c.to_le_bytes());
        }
        b
    }

    #[test]
    fn counts_after_the_comment_are_scaled_by_the_z_step() {
        let h = read_height(&sample()).unwrap();
        assert_eq!((h.dims(), h.spacing()), ([3, 2], [0.5, 0.25]));
        let step = f64::from(0.01f32);
        assert_eq!(h.row(1), &[300.0 * step, 400.0 * step, 65535.0 * step]);
        let m = metadata(&sample()).unwrap();
        assert_eq!((m[0].1.as_str(), m[1].1.as_str()), ("recipe", "note"));
    }

    #[test]
    fn truncated_files_are_refused() {
        let f = sample();
        for cut in [0, 20, 204, 209, f.len() - 1] {
            assert!(read_height(&f[..cut]).is_err(), "cut at {cut}");
        }
    }
}
