//! NASA SRTM elevation tiles (`.hgt`), read.
//!
//! A tile has no header: n × n big-endian int16 heights, n = 3601 for one
//! arc-second tiles and 1201 for three arc-second ones (any square is read),
//! row by row from the northern edge, each row from west to east — so the
//! file's rows are asperity's grid rows as other rasters are shown. Heights
//! are metres above the EGM96 geoid; -32768 marks a void (read as a missing
//! point). The lateral step is an angle (1″ or 3″, the file's name giving
//! the tile's corner), not a length: the field is read with step 1 and
//! unitless, as SurfaceTopography reads it, and the tile's size and its
//! resolution are kept as metadata.

use asperity_core::HeightField;

use crate::Metadata;
use crate::error::{FResult, malformed};
use crate::format::{Access, Codec, Registration};

const VOID: i16 = -32768;

/// The side of a square tile of `len` bytes, if it is one.
fn side(len: usize) -> Option<usize> {
    let n = (len / 2).isqrt();
    (len > 0 && 2 * n * n == len).then_some(n)
}

/// Reads an `.hgt` tile.
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    let Some(n) = side(bytes.len()) else {
        return malformed(format!(
            "{} bytes are not a square tile of 16-bit heights (2 × n² bytes; truncated?)",
            bytes.len()
        ));
    };
    let data = bytes
        .chunks_exact(2)
        .map(|b| match i16::from_be_bytes([b[0], b[1]]) {
            VOID => f64::NAN,
            h => f64::from(h),
        })
        .collect();
    Ok(HeightField::from_vec([n, n], data)?)
}

/// The tile's size and resolution.
pub(crate) fn metadata(bytes: &[u8]) -> FResult<Metadata> {
    let Some(n) = side(bytes.len()) else {
        return malformed("not a square tile of 16-bit heights");
    };
    let resolution = match n {
        3601 => "1 arc-second (SRTM1)",
        1201 => "3 arc-seconds (SRTM3)",
        _ => "not an SRTM size (1201 or 3601 points a side)",
    };
    Ok(vec![
        ("Points".to_owned(), format!("{n} × {n}")),
        ("Resolution".to_owned(), resolution.to_owned()),
        (
            "Heights".to_owned(),
            "metres above the EGM96 geoid".to_owned(),
        ),
    ])
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "NASA SRTM elevation tile (.hgt)",
    extensions: &["hgt"],
    height: Access::Read,
    notes: "a square of big-endian int16 heights in metres, rows from the north; voids (-32768) read as missing; the step is an angle (1″ or 3″): read with step 1, unitless, the tile's size and resolution kept as metadata",
    codec: Some(Codec::new(|b, _| read_height(b)).metadata(metadata)),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_tile_is_read_north_first_with_voids_missing() {
        let tile: Vec<u8> = [100i16, -5, VOID, 8848]
            .iter()
            .flat_map(|h| h.to_be_bytes())
            .collect();
        let h = read_height(&tile).unwrap();
        assert_eq!(h.dims(), [2, 2]);
        assert_eq!(h.row(0), &[100.0, -5.0]);
        assert!(h.row(1)[0].is_nan());
        assert_eq!(h.row(1)[1], 8848.0);
        assert_eq!(metadata(&tile).unwrap()[0].1, "2 × 2");
    }

    #[test]
    fn a_file_that_is_no_square_tile_is_refused() {
        for len in [0, 1, 6, 10] {
            let e = format!("{:?}", read_height(&vec![0; len]).unwrap_err());
            assert!(e.contains("square tile"), "{len}: {e}");
        }
    }
}
