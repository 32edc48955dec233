//! Bruker / Veeco / Digital Instruments Nanoscope files (`.spm`, `.di`,
//! `.001`, …), version 4.3 and later, read.
//!
//! A Latin-1 text header of `\*Section` lines and `\Key: value` lines, up to
//! `\*File list end`, then binary data at the offsets the image sections
//! give. The `File list` states the version; the `Scanner list` (or
//! `Microscope list`) and the scan list (`Ciao scan list`, …) hold the
//! "soft" scales, e.g. `\@Sens. Zsens: V 20.8 nm/V`. Each image section
//! (`Ciao image list`, …) is a channel: its `Data offset`, `Data length`,
//! `Bytes/pixel`, `Samps/line` (nx), `Number of lines` (ny), `Scan Size`
//! (`500 500 nm`, or one number for a square scan), its name
//! (`\@2:Image Data: S [Height] "Height"`) and its `\@2:Z scale: V [Sens.
//! Zsens] (0.0050354 V/LSB) 2.910461 V`: the hard value (2.910461 V) over
//! 256^bytes-per-pixel is the scale of one count in volts, times the soft
//! scale named in brackets (20.8 nm/V) gives nanometres. The counts are
//! little-endian int16 (int32 from version 9.2 when the block holds four
//! bytes a point), line by line, the first line the image's last (flipped,
//! as Gwyddion and SurfaceTopography show it).
//!
//! The first channel is read, as SurfaceTopography does by default; a
//! channel whose scale is not a length (phase, amplitude, current) is
//! refused with the file's channels named. Force curves and files with data
//! as text are refused. Layout learnt from SurfaceTopography's `DI.py` and
//! checked on its example file.

use asperity_core::{HeightField, LengthUnit, Units};

use crate::channel::{Channel, ChannelInfo, pick};
use crate::error::{FResult, FormatError, malformed, unsupported};
use crate::raster::from_last_line;
use crate::format::{Access, Codec, Magic, Registration};

/// The header's sections in order: lower-case name and lower-case keys.
type Sections = Vec<(String, Vec<(String, String)>)>;

const END: &str = "\\*file list end";

/// Whether `bytes` start like a Nanoscope header.
pub(crate) fn sniff(bytes: &[u8]) -> bool {
    let lower = |b: &[u8]| b.to_ascii_lowercase();
    [b"\\*File list".as_slice(), b"\\*EC File list".as_slice()]
        .iter()
        .any(|m| bytes.len() >= m.len() && lower(&bytes[..m.len()]) == lower(m))
}

fn parse_header(bytes: &[u8]) -> FResult<Sections> {
    if bytes.starts_with(b"?*") {
        return unsupported("a Nanoscope file with its data as text (only binary data is read)");
    }
    if !sniff(bytes) {
        return malformed("does not start with `\\*File list` (not a Nanoscope file?)");
    }
    let mut sections: Sections = Vec::new();
    let mut ended = false;
    for raw in bytes.split(|&b| b == b'\n') {
        // Latin-1: every byte is the character of the same number.
        let line: String = raw.iter().map(|&b| char::from(b)).collect();
        let line = line.trim();
        if line.to_ascii_lowercase() == END {
            ended = true;
            break;
        }
        if let Some(name) = line.strip_prefix("\\*") {
            sections.push((name.to_ascii_lowercase(), Vec::new()));
        } else if let Some(entry) = line.strip_prefix('\\') {
            let (key, value) = entry.split_once(": ").unwrap_or((entry, ""));
            let Some((_, keys)) = sections.last_mut() else {
                return malformed("a key before the first section");
            };
            keys.push((key.to_ascii_lowercase(), value.trim().to_string()));
        } else if !line.is_empty() {
            return malformed(format!(
                "header line {line:?} does not start with a backslash"
            ));
        }
    }
    if !ended {
        return malformed("the header has no `\\*File list end` (truncated?)");
    }
    Ok(sections)
}

fn get<'a>(keys: &'a [(String, String)], key: &str) -> Option<&'a str> {
    keys.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
}

/// A `V [soft] (hard/LSB) value unit` entry: (soft scale's name, the value,
/// its unit).
fn scaled_value(v: &str) -> Option<(Option<&str>, f64, &str)> {
    let mut rest = v.get(1..)?.trim();
    let mut soft = None;
    if let Some(r) = rest.strip_prefix('[') {
        let end = r.find(']')?;
        soft = Some(r[..end].trim()).filter(|s| !s.is_empty());
        rest = r[end + 1..].trim();
    }
    if rest.starts_with('(') {
        // Units may hold parentheses: match them.
        let mut depth = 0;
        let end = rest.char_indices().find_map(|(i, c)| {
            match c {
                '(' => depth += 1,
                ')' => depth -= 1,
                _ => {}
            }
            (depth == 0).then_some(i)
        })?;
        rest = rest[end + 1..].trim();
    }
    let (number, unit) = rest.split_once(char::is_whitespace).unwrap_or((rest, ""));
    Some((soft, number.parse().ok()?, unit.trim()))
}

/// A Nanoscope length unit (`~m` is µm).
fn length_unit(s: &str) -> Option<LengthUnit> {
    match s.trim() {
        "m" => Some(LengthUnit::M),
        "mm" => Some(LengthUnit::Mm),
        "um" | "~m" | "µm" => Some(LengthUnit::Um),
        "nm" => Some(LengthUnit::Nm),
        _ => None,
    }
}

/// How many `per` one `hard` is, where `hard` is `per` or `per` with an
/// SI prefix (a hard value in mV against a soft scale in nm/V: 1e-3).
fn prefix_factor(hard: &str, per: &str) -> Option<f64> {
    if hard == per {
        return Some(1.0);
    }
    let prefix = hard.strip_suffix(per)?;
    match prefix {
        "m" => Some(1e-3),
        "µ" | "u" => Some(1e-6),
        "n" => Some(1e-9),
        "k" => Some(1e3),
        _ => None,
    }
}

/// One channel's layout and scale.
struct Layout {
    name: String,
    offset: usize,
    size: usize,
    nx: usize,
    ny: usize,
    extent: [f64; 2],
    xy: LengthUnit,
    /// Height of one count and its unit, for a height channel.
    scale: Option<(f64, LengthUnit)>,
    /// One count in the Z scale's own unit (volts, degrees…), for others.
    per_count: f64,
}

fn channel(
    keys: &[(String, String)],
    soft: &dyn Fn(&str) -> Option<String>,
    version: u32,
) -> FResult<Layout> {
    let name = ["@2:image data", "@3:image data", "@4:image data"]
        .iter()
        .find_map(|k| get(keys, k))
        .map(|v| {
            // `S [Name] "Label"`: the bracketed name, else the quoted label.
            let rest = v.get(1..).unwrap_or_default().trim();
            rest.strip_prefix('[')
                .and_then(|r| r.split_once(']'))
                .map(|(name, _)| name.trim())
                .filter(|name| !name.is_empty())
                .unwrap_or_else(|| v.rsplit('"').nth(1).unwrap_or(v))
                .to_string()
        })
        .or_else(|| get(keys, "image data").map(str::to_string))
        .unwrap_or_else(|| "unnamed".into());
    let number = |key: &str| -> FResult<usize> {
        get(keys, key)
            .and_then(|v| v.trim().parse().ok())
            .ok_or_else(|| FormatError::Malformed(format!("channel {name:?} has no {key}")))
    };
    let (nx, ny) = (number("samps/line")?, number("number of lines")?);
    let (offset, length) = (number("data offset")?, number("data length")?);
    let bpp = get(keys, "bytes/pixel").map_or(Ok(2), |_| number("bytes/pixel"))?;
    if bpp != 2 && bpp != 4 {
        return malformed(format!("{bpp} bytes a pixel (2 and 4 are read)"));
    }
    let size = if version >= 0x0920_0000 && length >= 4 * nx * ny {
        4
    } else {
        bpp
    };
    if nx == 0
        || ny == 0
        || nx
            .checked_mul(ny)
            .and_then(|n| n.checked_mul(size))
            .is_none_or(|n| n > length)
    {
        return malformed(format!(
            "channel {name:?}: {nx} × {ny} points of {size} bytes do not fit its {length}-byte block"
        ));
    }
    let scan = get(keys, "scan size").unwrap_or_default();
    let words: Vec<&str> = scan.split_whitespace().collect();
    let (sx, sy, unit) = match words.as_slice() {
        [x, y, unit @ ..] if y.parse::<f64>().is_ok() => {
            (x.parse().ok(), y.parse().ok(), unit.join(" "))
        }
        [x, unit @ ..] => (x.parse().ok(), x.parse().ok(), unit.join(" ")),
        [] => (None, None, String::new()),
    };
    let (Some(sx), Some(sy)) = (sx, sy) else {
        return malformed(format!(
            "channel {name:?}: scan size {scan:?} is not a size"
        ));
    };
    let xy = length_unit(&unit).ok_or_else(|| {
        FormatError::Malformed(format!(
            "channel {name:?}: scan size unit {unit:?} is not a length"
        ))
    })?;
    let z = get(keys, "@2:z scale").or_else(|| get(keys, "@4:z scale"));
    let Some(z) = z else {
        return unsupported("a Nanoscope file without `@2:Z scale` (version 4.2 or earlier)");
    };
    let (quantity, hard, hard_unit) = scaled_value(z)
        .ok_or_else(|| FormatError::Malformed(format!("channel {name:?}: Z scale {z:?}")))?;
    let per_count = hard / 256f64.powi(bpp as i32);
    // The soft scale, e.g. `V 20.82646 nm/V`: a length per the hard unit.
    let scale = quantity
        .and_then(|q| soft(&format!("@{}", q.to_ascii_lowercase())))
        .and_then(|s| {
            let (_, value, unit) = scaled_value(&s)?;
            let (length, per) = unit.split_once('/')?;
            let prefix = prefix_factor(hard_unit, per.trim())?;
            Some((per_count * prefix * value, length_unit(length)?))
        });
    Ok(Layout {
        name,
        offset,
        size,
        nx,
        ny,
        extent: [sx, sy],
        xy,
        scale,
        per_count,
    })
}

/// The instrument's header outside the image sections (file, equipment,
/// scanner and scan lists), as `section\\key` and value.
pub(crate) fn metadata(bytes: &[u8]) -> FResult<Vec<(String, String)>> {
    Ok(parse_header(bytes)?
        .into_iter()
        .filter(|(n, _)| !n.contains("image list"))
        .flat_map(|(n, keys)| keys.into_iter().map(move |(k, v)| (format!("{n}\\{k}"), v)))
        .collect())
}

/// Every image section's layout, in order.
fn layouts(bytes: &[u8]) -> FResult<Vec<Layout>> {
    let sections = parse_header(bytes)?;
    let global = |names: &[&str], key: &str| -> Option<String> {
        sections
            .iter()
            .filter(|(n, _)| names.contains(&n.as_str()))
            .find_map(|(_, keys)| get(keys, key).map(str::to_string))
    };
    let version = global(&["file list", "ec file list"], "version")
        .and_then(|v| u32::from_str_radix(v.trim().trim_start_matches("0x"), 16).ok())
        .unwrap_or(0);
    let mode = sections.iter().find_map(|(_, k)| get(k, "operating mode"));
    if mode.is_some_and(|m| m.trim() == "Force") {
        return unsupported("a Nanoscope file of force curves (not a topography)");
    }
    let soft = |key: &str| {
        global(&["scanner list", "microscope list"], key).or_else(|| {
            global(
                &["ciao scan list", "afm list", "stm list", "nc afm list"],
                key,
            )
        })
    };
    const IMAGES: [&str; 5] = [
        "ciao image list",
        "afm image list",
        "stm image list",
        "ncafm image list",
        "image list",
    ];
    let layouts = sections
        .iter()
        .filter(|(n, _)| IMAGES.contains(&n.as_str()))
        .map(|(_, keys)| channel(keys, &soft, version))
        .collect::<FResult<Vec<_>>>()?;
    if layouts.is_empty() {
        return malformed("no image section (`\\*Ciao image list`)");
    }
    Ok(layouts)
}

/// The file's channels: one per image section.
pub(crate) fn channels(bytes: &[u8]) -> FResult<Vec<ChannelInfo>> {
    Ok(layouts(bytes)?
        .into_iter()
        .enumerate()
        .map(|(index, l)| ChannelInfo {
            index,
            name: l.name,
            height: l.scale.is_some(),
        })
        .collect())
}

/// Reads the channel `choice` names (by default the first height channel).
/// A channel that is no height (phase, amplitude…) is read unitless, in its
/// Z scale's own unit.
pub(crate) fn read_channel(bytes: &[u8], choice: Option<&Channel>) -> FResult<HeightField> {
    let layouts = layouts(bytes)?;
    let list: Vec<ChannelInfo> = layouts
        .iter()
        .enumerate()
        .map(|(index, l)| ChannelInfo {
            index,
            name: l.name.clone(),
            height: l.scale.is_some(),
        })
        .collect();
    let c = &layouts[pick(&list, choice)?];
    let (scale, units) = match c.scale {
        Some((scale, z)) => (scale, Units { xy: z, z }),
        None => (
            c.per_count,
            Units {
                xy: c.xy,
                z: LengthUnit::None,
            },
        ),
    };
    let need = c.nx * c.ny * c.size;
    let data = c
        .offset
        .checked_add(need)
        .and_then(|end| bytes.get(c.offset..end))
        .ok_or_else(|| {
            FormatError::Malformed(format!(
                "channel {:?}'s {need} bytes at {} run past the file's end (truncated?)",
                c.name, c.offset
            ))
        })?;
    let heights = from_last_line(data, c.nx, c.size)
        .map(|b| {
            let count = if c.size == 2 {
                f64::from(i16::from_le_bytes([b[0], b[1]]))
            } else {
                f64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            };
            count * scale
        })
        .collect();
    // Lateral sizes in the heights' unit, as SurfaceTopography reports them.
    let to_z =
        c.xy.metres()
            .zip(units.xy.metres())
            .map_or(1.0, |(a, b)| a / b);
    let [sx, sy] = c.extent.map(|v| v * to_z);
    if !(sx.is_finite() && sx > 0.0 && sy.is_finite() && sy > 0.0) {
        return malformed(format!(
            "channel {:?}: scan size {sx} × {sy} is not positive",
            c.name
        ));
    }
    Ok(HeightField::from_vec([c.nx, c.ny], heights)?
        .with_spacing([sx / c.nx as f64, sy / c.ny as f64])?
        .with_units(units))
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "Bruker Nanoscope (.spm, .di, .001)",
    extensions: &["di", "spm", "001", "002", "003", "004", "005"],
    height: Access::Read,
    notes: "version 4.3 and later: the first channel's int16/int32 counts × its Z scale × the soft scale (nm/V), from the last line; sizes from Scan Size; channels that are no height and force curves refused",
    magic: Magic::Test(sniff),
    codec: Some(Codec::new(read_channel)
        .channels(channels)
        .metadata(metadata)),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3 × 2 Nanoscope file: a height channel, then a phase channel.
    fn file(first_is_height: bool, counts: &[i16]) -> Vec<u8> {
        let height = "\\@2:Image Data: S [Height] \"Height\"\r\n\
             \\@2:Z scale: V [Sens. Zsens] (0.005 V/LSB) 6.5536 V\r\n";
        let phase = "\\@2:Image Data: S [Phase] \"Phase\"\r\n\
             \\@2:Z scale: V [Sens. Phase] (0.005 º/LSB) 360 º\r\n";
        let image = |offset: usize, what: &str| {
            format!(
                "\\*Ciao image list\r\n\\Data offset: {offset}\r\n\\Data length: 12\r\n\
                 \\Bytes/pixel: 2\r\n\\Samps/line: 3\r\n\\Number of lines: 2\r\n\
                 \\Scan Size: 3 1 um\r\n{what}"
            )
        };
        let (a, b) = if first_is_height {
            (height, phase)
        } else {
            (phase, height)
        };
        let mut head = format!(
            "\\*File list\r\n\\Version: 0x07200000\r\n\\*Scanner list\r\n\
             \\@Sens. Zsens: V 20 nm/V\r\n\\*Ciao scan list\r\n\\Samps/line: 3\r\n{}{}\\*File list end\r\n",
            image(1000, a),
            image(1012, b)
        )
        .into_bytes();
        head.resize(1000, 0);
        head.extend(counts.iter().flat_map(|v| v.to_le_bytes()));
        head.extend([0u8; 12]);
        head
    }

    #[test]
    fn reads_the_first_channel_in_nanometres_from_the_last_line() {
        let h = read_channel(&file(true, &[0, 1, 2, 3, 4, -5]), None).unwrap();
        assert_eq!(h.dims(), [3, 2]);
        assert_eq!(
            h.units(),
            Units {
                xy: LengthUnit::Nm,
                z: LengthUnit::Nm
            }
        );
        // 6.5536 V / 65536 = 1e-4 V a count, × 20 nm/V = 2e-3 nm.
        let [dx, dy] = h.spacing();
        assert!(
            (dx - 1000.0).abs() < 1e-9 && (dy - 500.0).abs() < 1e-9,
            "{dx} {dy}"
        );
        let z = |i, j| (*h.get(i, j) / 2e-3 * 1e6).round() / 1e6;
        assert_eq!([z(0, 0), z(1, 0), z(2, 0)], [3.0, 4.0, -5.0]);
        assert_eq!(z(2, 1), 2.0);
        assert_eq!(
            scaled_value("V [Sens. Zsens] (0.0050354 V/LSB) 2.910461 V"),
            Some((Some("Sens. Zsens"), 2.910461, "V"))
        );
    }

    #[test]
    fn a_hard_value_in_millivolts_takes_a_soft_scale_per_volt() {
        assert_eq!(prefix_factor("V", "V"), Some(1.0));
        assert_eq!(prefix_factor("mV", "V"), Some(1e-3));
        assert_eq!(prefix_factor("º", "V"), None);
        assert_eq!(prefix_factor("xV", "V"), None);
    }

    #[test]
    fn channels_are_listed_and_picked_and_truncation_is_refused() {
        let f = file(false, &[0, 1, 2, 3, 4, 5]);
        let names: Vec<(String, bool)> = channels(&f)
            .unwrap()
            .into_iter()
            .map(|c| (c.name, c.height))
            .collect();
        assert_eq!(names, [("Phase".into(), false), ("Height".into(), true)]);
        // By default the height: the second channel, whose data are the zeros after the first's.
        let h = read_channel(&f, None).unwrap();
        assert_eq!(h.units().z, LengthUnit::Nm);
        assert!(h.data().iter().all(|z| *z == 0.0));
        // The phase by name, unitless, in degrees: 360 / 65536 a count.
        let p = read_channel(&f, Some(&Channel::parse("phase"))).unwrap();
        assert_eq!(p.units().z, LengthUnit::None);
        assert_eq!(*p.get(1, 1), 360.0 / 65536.0);
        assert!(read_channel(&f, Some(&Channel::Index(2))).is_err());
        let good = file(true, &[0; 6]);
        for cut in 0..1012 {
            assert!(read_channel(&good[..cut], None).is_err(), "cut at {cut}");
        }
        assert!(read_channel(b"?*File list\r\n", None).is_err());
    }
}
