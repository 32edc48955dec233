//! WSxM (`.stp`, `.top`, `.tom`, `.cur`), the files of the WSxM scanning-probe
//! software (Horcas et al., Rev. Sci. Instrum. 78, 013705, 2007), read: images.
//!
//! Three lines — `WSxM file copyright …`, `SxM Image file`, `Image header
//! size: N` — then an INI-like header (`[Section]`, `key: value`) up to
//! `[Header end]`; the samples start at byte N. `[General Info]` gives the
//! rows, columns, `Image Data Type` (short/integer: int16, float, double) and
//! `Z Amplitude` ("12.3 nm"); `[Control]` the `X Amplitude` and `Y Amplitude`
//! (the field's size). Floating-point samples are heights in the amplitude's
//! unit; integer ones are scaled so that the range `[Miscellaneous]`
//! Minimum…Maximum spans the Z amplitude. The samples are stored from the
//! last row and column: asperity's rows are them in reverse order (as
//! SurfaceTopography reads them).

use std::collections::HashMap;

use asperity_core::{HeightField, Units};

use crate::error::{FResult, FormatError, malformed};
use crate::header_keys::HeaderKeys;
use crate::sur::length_unit;
use crate::format::{Access, Codec, Magic, Registration};

pub(crate) const MAGIC: &[u8] = b"WSxM file copyright";

/// The header's `section/key` values (Latin-1 text).
fn header(text: &str) -> HashMap<String, String> {
    let mut section = String::new();
    let mut out = HashMap::new();
    for line in text.lines().map(str::trim) {
        if line.starts_with('[') && line.ends_with(']') {
            section = line[1..line.len() - 1].to_owned();
        } else if let Some((k, v)) = line.split_once(':') {
            out.insert(format!("{section}/{}", k.trim()), v.trim().to_owned());
        }
    }
    out
}

/// A "value unit" amplitude as (value, unit name).
fn amplitude(v: &str) -> FResult<(f64, &str)> {
    let (num, unit) = v.trim().split_once(' ').unwrap_or((v.trim(), ""));
    let num = num
        .parse()
        .map_err(|_| FormatError::Malformed(format!("amplitude {v:?} is not a number and unit")))?;
    Ok((num, unit.trim()))
}

/// What the header says about the samples.
struct Layout {
    nx: usize,
    ny: usize,
    /// Bytes a sample.
    size_of: usize,
    /// Height per stored unit, in `units.z`.
    scale: f64,
    /// The field's size, in `units.xy`.
    extent: [f64; 2],
    units: Units,
}

/// The samples' layout from the header's values.
fn layout(h: &HashMap<String, String>) -> FResult<Layout> {
    let keys = HeaderKeys::new(h);
    let kind = h
        .get("General Info/Image Data Type")
        .map_or("short", String::as_str);
    let size_of = match kind {
        "short" | "integer" => 2,
        "float" => 4,
        "double" => 8,
        other => {
            return malformed(format!(
                "Image Data Type {other:?} is not short, integer, float or double"
            ));
        }
    };
    let (z_amp, z_unit) = amplitude(keys.text("General Info/Z Amplitude")?)?;
    let (zu, fz) = length_unit(z_unit);
    let (x_amp, x_unit) = amplitude(keys.text("Control/X Amplitude")?)?;
    let (y_amp, y_unit) = match h.get("Control/Y Amplitude") {
        Some(v) => amplitude(v)?,
        None => (x_amp, x_unit),
    };
    let (xu, fx) = length_unit(x_unit);
    let (yu, fy) = length_unit(y_unit);
    // y in x's unit.
    let to_x = yu.metres().unwrap_or(1.0) / xu.metres().unwrap_or(1.0);
    let extent = [x_amp * fx, y_amp * fy * to_x];
    for (k, v) in ["X Amplitude", "Y Amplitude"].into_iter().zip(extent) {
        if !(v.is_finite() && v > 0.0) {
            return malformed(format!("{k} {v} is not a positive length"));
        }
    }
    // Integers span the Z amplitude over Minimum…Maximum.
    let range = h
        .get("Miscellaneous/Maximum")
        .zip(h.get("Miscellaneous/Minimum"))
        .and_then(|(a, b)| Some(a.parse::<f64>().ok()? - b.parse::<f64>().ok()?));
    let per_unit = match range {
        Some(r) if size_of == 2 && r > 0.0 => z_amp / r,
        _ => 1.0,
    };
    Ok(Layout {
        nx: keys.count("General Info/Number of columns")?,
        ny: keys.count("General Info/Number of rows")?,
        size_of,
        scale: per_unit * fz,
        extent,
        units: Units { xy: xu, z: zu },
    })
}

/// The `nx` × `ny` samples of `size_of` bytes (int16, f32 or f64) after
/// the `header`-byte header.
fn samples(body: &[u8], [nx, ny]: [usize; 2], size_of: usize, header: usize) -> FResult<Vec<f64>> {
    let need = nx
        .checked_mul(ny)
        .and_then(|n| n.checked_mul(size_of))
        .ok_or_else(|| FormatError::Malformed("rows × columns is too large".into()))?;
    if body.len() < need {
        return malformed(format!(
            "{nx} × {ny} samples of {size_of} bytes need {need} bytes after the {header}-byte header, the file has {} (truncated?)",
            body.len()
        ));
    }
    Ok(body[..need]
        .chunks_exact(size_of)
        .map(|c| match size_of {
            2 => f64::from(i16::from_le_bytes([c[0], c[1]])),
            4 => f64::from(f32::from_le_bytes([c[0], c[1], c[2], c[3]])),
            _ => f64::from_le_bytes(c.try_into().expect("8 bytes")),
        })
        .collect())
}

/// Reads a WSxM image.
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    if !bytes.starts_with(MAGIC) {
        return malformed("missing the `WSxM file copyright` line");
    }
    let latin1 = |b: &[u8]| -> String { b.iter().map(|&c| char::from(c)).collect() };
    let text = latin1(&bytes[..bytes.len().min(1 << 20)]);
    let mut lines = text.lines();
    let (_, kind, size) = (lines.next(), lines.next(), lines.next());
    if kind.map(str::trim) != Some("SxM Image file") {
        return malformed("the second line is not `SxM Image file` (not an image)");
    }
    let size: usize = size
        .and_then(|l| l.trim().strip_prefix("Image header size:"))
        .and_then(|n| n.trim().parse().ok())
        .ok_or_else(|| FormatError::Malformed("no `Image header size:` line".into()))?;
    let head = latin1(&bytes[..size.min(bytes.len())]);
    if !head.contains("[Header end]") {
        return malformed("the header has no `[Header end]` within its size (truncated?)");
    }
    let Layout {
        nx,
        ny,
        size_of,
        scale,
        extent,
        units,
    } = layout(&header(&head))?;
    let mut data = samples(bytes.get(size..).unwrap_or(&[]), [nx, ny], size_of, size)?;
    for v in &mut data {
        *v *= scale;
    }
    // Stored from the last sample.
    data.reverse();
    // A NaN sample was not measured (a missing point); ±∞ is refused by the
    // read path's check.
    Ok(HeightField::from_vec([nx, ny], data)?
        .with_spacing([extent[0] / nx as f64, extent[1] / ny as f64])?
        .with_units(units))
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "WSxM image (.stp, .top, .tom, .cur)",
    extensions: &["stp", "top", "tom", "cur"],
    height: Access::Read,
    notes: "int16 scaled to the Z amplitude, or f32/f64 heights; sizes from the X/Y amplitudes; stored from the last sample; NaN read as missing",
    magic: Magic::Starts(&[MAGIC]),
    codec: Some(Codec::new(|b, _| read_height(b))),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;
    use asperity_core::LengthUnit;

    fn file(kind: &str, body: &[u8]) -> Vec<u8> {
        let head = format!(
            "[Control]\n    X Amplitude: 600 nm\n    Y Amplitude: 0.3 µm\n\n[General Info]\n    \
             Image Data Type: {kind}\n    Number of columns: 3\n    Number of rows: 2\n    \
             Z Amplitude: 10 nm\n\n[Miscellaneous]\n    Maximum: 5\n    Minimum: 0\n\n[Header end]\n"
        );
        let head: Vec<u8> = head.chars().map(|c| c as u8).collect();
        let mut size = 0;
        for _ in 0..3 {
            let lines = format!(
                "WSxM file copyright UAM\r\nSxM Image file\r\nImage header size: {size}\r\n"
            );
            size = lines.len() + head.len();
        }
        let mut b =
            format!("WSxM file copyright UAM\r\nSxM Image file\r\nImage header size: {size}\r\n")
                .into_bytes();
        b.extend(head);
        assert_eq!(b.len(), size);
        b.extend(body);
        b
    }

    #[test]
    fn images_scaled_and_turned_as_stored() {
        let ints: Vec<u8> = [0i16, 1, 2, 3, 4, 5]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let h = read_height(&file("short", &ints)).unwrap();
        assert_eq!(h.dims(), [3, 2]);
        assert_eq!(h.spacing()[0], 200.0);
        assert!((h.spacing()[1] - 150.0).abs() < 1e-12, "{:?}", h.spacing());
        assert_eq!(
            h.units(),
            Units {
                xy: LengthUnit::Nm,
                z: LengthUnit::Nm
            }
        );
        assert_eq!(h.data(), &[10.0, 8.0, 6.0, 4.0, 2.0, 0.0]);
        let doubles: Vec<u8> = [0.5f64, 1.0, 1.5, 2.0, 2.5, 3.0]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let d = read_height(&file("double", &doubles)).unwrap();
        assert_eq!(d.data(), &[3.0, 2.5, 2.0, 1.5, 1.0, 0.5]);
    }

    #[test]
    fn truncated_and_odd_files_are_refused() {
        let ints: Vec<u8> = [0i16; 6].iter().flat_map(|v| v.to_le_bytes()).collect();
        let good = file("short", &ints);
        for cut in 0..good.len() {
            assert!(read_height(&good[..cut]).is_err(), "cut at {cut}");
        }
        assert!(read_height(&file("complex", &ints)).is_err());
    }
}
