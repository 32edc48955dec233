//! Molecular Imaging / Agilent PicoView `.mi` images, read.
//!
//! A text header of `key value` lines, the key in a 14-character column
//! (indented lines continue a value and are skipped), ending with the line
//! whose key is `data` (`BINARY` for int16, `BINARY_32` for int32; text data
//! are refused). `fileType` must be `Image` (spectroscopy is refused);
//! `xPixels`, `yPixels`, `xLength` and `yLength` (metres) give the grid.
//! Each `bufferLabel` line starts a channel (`bufferRange`, `bufferUnit`);
//! the channels' data follow the header in order, each the image's lines
//! from the last, little-endian. A value is raw × bufferRange / 2^15 (int16)
//! or / 2^31 (int32), in `bufferUnit`; a channel whose unit is a length is a
//! height (the default is the first height channel),
//! others (deflection, friction in volts) are read unitless. Layout learnt
//! from SurfaceTopography's `MI.py` and checked on its example file.

use asperity_core::{HeightField, LengthUnit, Units};

use crate::channel::{Channel, ChannelInfo, pick};
use crate::error::{FResult, FormatError, malformed, unsupported};
use crate::raster::from_last_line;
use crate::format::{Access, Codec, Magic, Registration};

pub(crate) const MAGIC: &[u8] = b"fileType";
const KEY_WIDTH: usize = 14;

struct Header {
    keys: Vec<(String, String)>,
    /// (label, range, unit) of each buffer.
    buffers: Vec<(String, f64, String)>,
    /// The data's first byte.
    start: usize,
}

fn header(bytes: &[u8]) -> FResult<Header> {
    if !bytes.starts_with(MAGIC) {
        return malformed("does not start with `fileType` (not an MI file?)");
    }
    let mut keys = Vec::new();
    let mut buffers: Vec<(String, f64, String)> = Vec::new();
    let mut at = 0;
    loop {
        let Some(end) = bytes[at..].iter().position(|&b| b == b'\n') else {
            return malformed("the header has no `data` line (truncated?)");
        };
        let line: String = bytes[at..at + end].iter().map(|&b| char::from(b)).collect();
        at += end + 1;
        if line.starts_with(' ') || line.trim().is_empty() {
            continue;
        }
        let split = line
            .char_indices()
            .nth(KEY_WIDTH)
            .map_or(line.len(), |(i, _)| i);
        let (key, value) = (line[..split].trim(), line[split..].trim());
        match key {
            "bufferLabel" => buffers.push((value.to_string(), f64::NAN, String::new())),
            "bufferRange" | "bufferUnit" if !buffers.is_empty() => {
                let b = buffers.last_mut().expect("a buffer");
                if key == "bufferRange" {
                    b.1 = value.parse().unwrap_or(f64::NAN);
                } else {
                    b.2 = value.to_string();
                }
            }
            "data" => {
                keys.push((key.to_string(), value.to_string()));
                return Ok(Header {
                    keys,
                    buffers,
                    start: at,
                });
            }
            // After the first buffer, a key describes that buffer.
            _ if !buffers.is_empty() => keys.push((
                format!("buffer {}\\{key}", buffers.len() - 1),
                value.to_string(),
            )),
            _ => keys.push((key.to_string(), value.to_string())),
        }
    }
}

/// `um` and friends; `None` for a unit that is no length.
fn length_unit(unit: &str) -> Option<LengthUnit> {
    match unit {
        "um" | "µm" => Some(LengthUnit::Um),
        u => LengthUnit::parse(u).ok().filter(|u| *u != LengthUnit::None),
    }
}

/// The header's keys; a buffer's own keys (filter, direction, display
/// range…) as `buffer N\\key`.
pub(crate) fn metadata(bytes: &[u8]) -> FResult<Vec<(String, String)>> {
    Ok(header(bytes)?.keys)
}

/// The channels: one per buffer, heights where the unit is a length.
pub(crate) fn channels(bytes: &[u8]) -> FResult<Vec<ChannelInfo>> {
    Ok(header(bytes)?
        .buffers
        .into_iter()
        .enumerate()
        .map(|(index, (name, _, unit))| ChannelInfo {
            index,
            name,
            height: length_unit(&unit).is_some(),
        })
        .collect())
}

/// An image's grid: points and lengths (m), and its samples' size (2 or 4
/// bytes) and full-scale count.
struct Grid {
    nx: usize,
    ny: usize,
    lengths: [f64; 2],
    size: usize,
    range: f64,
}

/// The image's grid from the header, checked (spectroscopy and text data
/// refused).
fn grid(h: &Header) -> FResult<Grid> {
    let get = |k: &str| {
        h.keys
            .iter()
            .find(|(key, _)| key == k)
            .map(|(_, v)| v.as_str())
    };
    match get("fileType") {
        Some("Image") => {}
        Some("Spectroscopy") => return unsupported("an MI spectroscopy file (not an image)"),
        t => return malformed(format!("file type {t:?} (Image is read)")),
    }
    let (size, range) = match get("data") {
        Some("BINARY_32") => (4, 2f64.powi(31)),
        Some("BINARY") | Some("") => (2, 2f64.powi(15)),
        _ => return unsupported("an MI file with its data as text"),
    };
    let number = |k: &str| -> FResult<f64> {
        get(k)
            .and_then(|v| v.parse().ok())
            .ok_or_else(|| FormatError::Malformed(format!("no number {k}")))
    };
    let (nx, ny) = (number("xPixels")? as usize, number("yPixels")? as usize);
    let lengths = [number("xLength")?, number("yLength")?];
    if nx == 0 || ny == 0 {
        return malformed(format!("{nx} × {ny} pixels: no data"));
    }
    Ok(Grid {
        nx,
        ny,
        lengths,
        size,
        range,
    })
}

/// Reads the channel `choice` names (by default the first height channel).
pub(crate) fn read_channel(bytes: &[u8], choice: Option<&Channel>) -> FResult<HeightField> {
    let h = header(bytes)?;
    let Grid {
        nx,
        ny,
        lengths: [lx, ly],
        size,
        range,
    } = grid(&h)?;
    let index = pick(&channels(bytes)?, choice)?;
    let (name, buffer_range, unit) = &h.buffers[index];
    let need = nx
        .checked_mul(ny)
        .and_then(|n| n.checked_mul(size))
        .ok_or_else(|| FormatError::Malformed(format!("{nx} × {ny} pixels overflow")))?;
    // Every channel's data must be there (a shorter file is truncated).
    let all = need
        .checked_mul(h.buffers.len())
        .and_then(|n| n.checked_add(h.start));
    if all.is_none_or(|n| n > bytes.len()) {
        return malformed(format!(
            "{} channels of {nx} × {ny} values need {} bytes after the header, the file has {} (truncated?)",
            h.buffers.len(),
            need.saturating_mul(h.buffers.len()),
            bytes.len() - h.start
        ));
    }
    let data = (index * need)
        .checked_add(h.start)
        .and_then(|a| bytes.get(a..a.checked_add(need)?))
        .ok_or_else(|| {
            FormatError::Malformed(format!(
                "channel {name:?}'s {need} bytes run past the file's end (truncated?)"
            ))
        })?;
    let scale = buffer_range / range;
    if !scale.is_finite() {
        return malformed(format!("channel {name:?} has no bufferRange"));
    }
    let heights = from_last_line(data, nx, size)
        .map(|c| {
            let raw = if size == 2 {
                f64::from(i16::from_le_bytes([c[0], c[1]]))
            } else {
                f64::from(i32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            };
            raw * scale
        })
        .collect();
    let z = length_unit(unit);
    let xy = z.unwrap_or(LengthUnit::M);
    let to = xy.metres().map_or(1.0, |m| 1.0 / m);
    if !(lx.is_finite() && lx > 0.0 && ly.is_finite() && ly > 0.0) {
        return malformed(format!("the lengths {lx} × {ly} m are not positive"));
    }
    Ok(HeightField::from_vec([nx, ny], heights)?
        .with_spacing([lx * to / nx as f64, ly * to / ny as f64])?
        .with_units(Units {
            xy,
            z: z.unwrap_or(LengthUnit::None),
        }))
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "Molecular Imaging (.mi)",
    extensions: &["mi"],
    height: Access::Read,
    notes: "PicoView images: every buffer a channel (heights where bufferUnit is a length; the first by default, as SurfaceTopography), int16/int32 × bufferRange / 2^15 or 2^31, from the last line; spectroscopy and text data refused",
    magic: Magic::Starts(&[MAGIC]),
    codec: Some(Codec::new(read_channel)
        .channels(channels)
        .metadata(metadata)),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    fn line(k: &str, v: &str) -> String {
        format!("{k:<14}{v}\n")
    }

    /// A 3 × 2 file of two int16 channels: a topography in µm, a deflection in V.
    fn file(values: &[i16]) -> Vec<u8> {
        let mut t = line("fileType", "Image");
        for (k, v) in [
            ("xPixels", "3"),
            ("yPixels", "2"),
            ("xLength", "3e-6"),
            ("yLength", "1e-6"),
        ] {
            t += &line(k, v);
        }
        t += " a continuation line\n";
        for (l, u) in [("Topography", "um"), ("Deflection", "V")] {
            t += &line("bufferLabel", l);
            t += &line("bufferRange", "32768");
            t += &line("bufferUnit", u);
        }
        t += &line("data", "BINARY");
        let mut f = t.into_bytes();
        f.extend(values.iter().flat_map(|v| v.to_le_bytes()));
        f.extend([0u8; 12]);
        f
    }

    #[test]
    fn reads_channels_from_the_last_line_in_their_units() {
        let f = file(&[0, 1, 2, 3, 4, -5]);
        let names: Vec<(String, bool)> = channels(&f)
            .unwrap()
            .into_iter()
            .map(|c| (c.name, c.height))
            .collect();
        assert_eq!(
            names,
            [("Topography".into(), true), ("Deflection".into(), false)]
        );
        let h = read_channel(&f, None).unwrap();
        assert_eq!(
            h.units(),
            Units {
                xy: LengthUnit::Um,
                z: LengthUnit::Um
            }
        );
        let [dx, dy] = h.spacing();
        assert!(
            (dx - 1.0).abs() < 1e-12 && (dy - 0.5).abs() < 1e-12,
            "{dx} {dy}"
        );
        assert_eq!([*h.get(0, 0), *h.get(2, 0), *h.get(1, 1)], [3.0, -5.0, 1.0]);
        let d = read_channel(&f, Some(&Channel::parse("deflection"))).unwrap();
        assert_eq!(d.units().z, LengthUnit::None);
    }

    #[test]
    fn truncation_and_other_files_are_refused() {
        let good = file(&[0; 6]);
        for cut in 0..good.len() {
            assert!(read_channel(&good[..cut], None).is_err(), "cut at {cut}");
        }
        let text = String::from_utf8(good.clone())
            .unwrap()
            .replace("BINARY", "ASCII");
        assert!(format!("{:?}", read_channel(text.as_bytes(), None).unwrap_err()).contains("text"));
    }
}
