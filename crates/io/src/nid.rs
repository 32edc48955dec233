//! Nanosurf `.nid` / `.ezd` (easyScan and later scanning-probe
//! microscopes), read.
//!
//! An INI-style Latin-1 header — the line `[DataSet]`, then `[Section]` and
//! `key=value` lines — ends at a line starting `#!`, after which the data
//! sets follow one after another. `[DataSet]` names the groups
//! (`GroupCount`, `Gr{i}-Count`) and each group's data sets
//! (`Gr{i}-Ch{j}=Section`; absent ones are skipped). A data set's section
//! gives `Points` (nx), `Lines` (ny), `SaveMode=Binary`, `SaveBits`,
//! `SaveSign`, `SaveOrder` (`Intel`: little-endian), the physical ranges
//! `Dim0Range`/`Dim1Range` in `Dim0Unit`/`Dim1Unit`, and the value range:
//! z = raw × Dim2Range / 2^bits + Dim2Min (+ Dim2Range / 2 for signed data),
//! in `Dim2Unit`. The lines are stored from the image's last, as Gwyddion
//! and SurfaceTopography show them. The channels are the data sets whose
//! values are lengths (`Dim2Unit` a length), named `Frame (Dim2Name)`, as
//! SurfaceTopography lists them; the first is read by default. Layout learnt
//! from SurfaceTopography's `EZD.py` and checked on its example file.

use asperity_core::{HeightField, LengthUnit, Units};

use crate::channel::{Channel, ChannelInfo, pick};
use crate::error::{FResult, FormatError, malformed, unsupported};
use crate::raster::from_last_line;
use crate::format::{Access, Codec, Magic, Registration};

pub(crate) const MAGIC: &[u8] = b"[DataSet]\r\n";

type Section = Vec<(String, String)>;

/// The header's sections and where the data start.
fn header(bytes: &[u8]) -> FResult<(Vec<(String, Section)>, usize)> {
    if !bytes.starts_with(MAGIC) {
        return malformed("does not start with `[DataSet]` (not a Nanosurf file?)");
    }
    let mut sections = vec![("DataSet".to_string(), Section::new())];
    let mut at = MAGIC.len();
    loop {
        let rest = &bytes[at..];
        if rest.starts_with(b"#!") {
            return Ok((sections, at + 2));
        }
        let Some(end) = rest.iter().position(|&b| b == b'\n') else {
            return malformed("the header has no `#!` before the data (truncated?)");
        };
        let line: String = rest[..end].iter().map(|&b| char::from(b)).collect();
        let line = line.trim();
        if let Some(name) = line.strip_prefix('[').and_then(|l| l.strip_suffix(']')) {
            sections.push((name.to_string(), Section::new()));
        } else if let Some((k, v)) = line.split_once('=') {
            let (_, keys) = sections.last_mut().expect("the first section");
            keys.push((k.to_string(), v.trim().to_string()));
        } else if !line.is_empty() {
            return malformed(format!(
                "header line {line:?} is neither a section nor key=value"
            ));
        }
        at += end + 1;
    }
}

fn get<'a>(keys: &'a Section, key: &str) -> Option<&'a str> {
    keys.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
}

/// A data set with lengths as values: its name, layout and scale.
struct Layout {
    name: String,
    nx: usize,
    ny: usize,
    offset: usize,
    bytes: usize,
    signed: bool,
    little: bool,
    extent: [f64; 2],
    unit: LengthUnit,
    scale: f64,
    zero: f64,
}

/// The height data sets in order (offsets from the data's start).
fn layouts(bytes: &[u8]) -> FResult<(Vec<Layout>, usize)> {
    let (sections, start) = header(bytes)?;
    let section = |name: &str| sections.iter().find(|(n, _)| n == name).map(|(_, k)| k);
    let top = section("DataSet").expect("the first section");
    let number = |keys: &Section, key: &str| -> FResult<f64> {
        get(keys, key)
            .and_then(|v| v.parse().ok())
            .ok_or_else(|| FormatError::Malformed(format!("no number {key}")))
    };
    let count = |keys: &Section, key: &str| number(keys, key).map(|v| v.max(0.0) as usize);
    let mut out = Vec::new();
    let mut offset = 0usize;
    // The data sets `Gr{i}-Ch{j}` in group and channel order, i below
    // GroupCount and j below the group's count (found among the keys, so a
    // corrupt count costs nothing).
    let groups = count(top, "GroupCount")?;
    let mut sets: Vec<(usize, usize, &str)> = top
        .iter()
        .filter_map(|(k, v)| {
            let (i, j) = k.strip_prefix("Gr")?.split_once("-Ch")?;
            Some((i.parse().ok()?, j.parse().ok()?, v.as_str()))
        })
        .filter(|&(i, j, _)| i < groups && count(top, &format!("Gr{i}-Count")).is_ok_and(|n| j < n))
        .collect();
    sets.sort_unstable();
    {
        for (_, _, name) in sets {
            let Some(keys) = section(name) else {
                continue;
            };
            if get(keys, "SaveMode") != Some("Binary") {
                return unsupported("a data set not saved as binary");
            }
            let (nx, ny) = (count(keys, "Points")?, count(keys, "Lines")?);
            let bits = count(keys, "SaveBits")?;
            if !matches!(bits, 8 | 16 | 32) {
                return malformed(format!("{bits} bits a value (8, 16 and 32 are read)"));
            }
            let size = nx
                .checked_mul(ny)
                .and_then(|n| n.checked_mul(bits / 8))
                .ok_or_else(|| FormatError::Malformed("a data set's size overflows".into()))?;
            let here = offset;
            offset = offset.saturating_add(size);
            let length = |key: &str| get(keys, key).and_then(|u| LengthUnit::parse(u).ok());
            let Some(unit) = length("Dim2Unit").filter(|u| *u != LengthUnit::None) else {
                continue; // not a topography (a force, a phase…)
            };
            let signed = get(keys, "SaveSign") == Some("Signed");
            let range = number(keys, "Dim2Range")?;
            let scale = range / 2f64.powi(bits as i32);
            let zero = get(keys, "Dim2Min")
                .and_then(|v| v.parse().ok())
                .unwrap_or(0.0)
                + if signed { range / 2.0 } else { 0.0 };
            let to = |key: &str| -> f64 {
                length(key)
                    .and_then(|u| u.metres())
                    .zip(unit.metres())
                    .map_or(1.0, |(a, b)| a / b)
            };
            out.push(Layout {
                name: format!(
                    "{} ({})",
                    get(keys, "Frame").unwrap_or_default(),
                    get(keys, "Dim2Name").unwrap_or_default()
                ),
                nx,
                ny,
                offset: here,
                bytes: bits / 8,
                signed,
                little: get(keys, "SaveOrder") == Some("Intel"),
                extent: [
                    number(keys, "Dim0Range")? * to("Dim0Unit"),
                    number(keys, "Dim1Range")? * to("Dim1Unit"),
                ],
                unit,
                scale,
                zero,
            });
        }
    }
    Ok((out, start))
}

/// The header's descriptive sections (not the data sets' layouts), as
/// `section\\key` and value.
pub(crate) fn metadata(bytes: &[u8]) -> FResult<Vec<(String, String)>> {
    let (sections, _) = header(bytes)?;
    Ok(sections
        .into_iter()
        .filter(|(n, _)| (n != "DataSet" && !n.starts_with("DataSet-")) || n == "DataSet-Info")
        .flat_map(|(n, keys)| keys.into_iter().map(move |(k, v)| (format!("{n}\\{k}"), v)))
        .collect())
}

/// The height channels, as SurfaceTopography lists them.
pub(crate) fn channels(bytes: &[u8]) -> FResult<Vec<ChannelInfo>> {
    Ok(layouts(bytes)?
        .0
        .into_iter()
        .enumerate()
        .map(|(index, l)| ChannelInfo {
            index,
            name: l.name,
            height: true,
        })
        .collect())
}

/// Reads the height channel `choice` names (by default the first).
pub(crate) fn read_channel(bytes: &[u8], choice: Option<&Channel>) -> FResult<HeightField> {
    let (layouts, start) = layouts(bytes)?;
    let list = channels(bytes)?;
    let l = &layouts[pick(&list, choice)?];
    if l.nx == 0 || l.ny == 0 {
        return malformed(format!(
            "{:?} has {} × {} points: no data",
            l.name, l.nx, l.ny
        ));
    }
    let need = l.nx * l.ny * l.bytes;
    let data = start
        .checked_add(l.offset)
        .and_then(|a| Some(a..a.checked_add(need)?))
        .and_then(|r| bytes.get(r))
        .ok_or_else(|| {
            FormatError::Malformed(format!(
                "{:?}'s {need} bytes run past the file's end (truncated?)",
                l.name
            ))
        })?;
    let value = |c: &[u8]| -> f64 {
        let mut b = [0u8; 4];
        b[..c.len()].copy_from_slice(c);
        if !l.little {
            b[..c.len()].reverse();
        }
        let raw = u32::from_le_bytes(b);
        let bits = 8 * c.len() as u32;
        if l.signed {
            // Sign-extend from the stored width.
            f64::from(((raw << (32 - bits)) as i32) >> (32 - bits))
        } else {
            f64::from(raw)
        }
    };
    let heights = from_last_line(data, l.nx, l.bytes)
        .map(|c| value(c) * l.scale + l.zero)
        .collect();
    let [sx, sy] = l.extent;
    if !(sx.is_finite() && sx > 0.0 && sy.is_finite() && sy > 0.0) {
        return malformed(format!("{:?}: ranges {sx} × {sy} are not positive", l.name));
    }
    Ok(HeightField::from_vec([l.nx, l.ny], heights)?
        .with_spacing([sx / l.nx as f64, sy / l.ny as f64])?
        .with_units(Units {
            xy: l.unit,
            z: l.unit,
        }))
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "Nanosurf (.nid, .ezd)",
    extensions: &["nid", "ezd"],
    height: Access::Read,
    notes: "the data sets whose values are lengths (channels, as SurfaceTopography lists them): 8/16/32-bit raw × range / 2^bits + minimum, from the last line",
    magic: Magic::Starts(&[MAGIC]),
    codec: Some(Codec::new(read_channel)
        .channels(channels)
        .metadata(metadata)),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3 × 2 file: a force data set, then a height, both int16.
    fn file(values: &[i16]) -> Vec<u8> {
        let set = |name: &str, unit: &str| {
            format!(
                "[{name}]\r\nPoints=3\r\nLines=2\r\nFrame=Scan forward\r\nDim0Range=3e-6\r\n\
                 Dim0Unit=m\r\nDim1Range=1e-6\r\nDim1Unit=m\r\nDim2Name=Z\r\nDim2Unit={unit}\r\n\
                 Dim2Range=65536e-9\r\nDim2Min=-32768e-9\r\nSaveMode=Binary\r\nSaveBits=16\r\n\
                 SaveSign=Signed\r\nSaveOrder=Intel\r\n"
            )
        };
        let mut f = format!(
            "[DataSet]\r\nGroupCount=1\r\nGr0-Count=3\r\nGr0-Ch0=A\r\nGr0-Ch2=B\r\n{}{}#!",
            set("A", "N"),
            set("B", "m")
        )
        .into_bytes();
        f.extend([0u8; 12]);
        f.extend(values.iter().flat_map(|v| v.to_le_bytes()));
        f
    }

    #[test]
    fn reads_the_height_data_set_from_the_last_line() {
        let f = file(&[0, 1, 2, 3, 4, -5]);
        let list = channels(&f).unwrap();
        assert_eq!(list.len(), 1, "the force is no channel");
        assert_eq!(list[0].name, "Scan forward (Z)");
        let h = read_channel(&f, None).unwrap();
        assert_eq!(h.dims(), [3, 2]);
        assert_eq!(h.units().z, LengthUnit::M);
        assert_eq!(h.spacing(), [1e-6, 0.5e-6]);
        // z = raw × 1e-9 − 32768e-9 + 32768e-9.
        let z = |i, j| (*h.get(i, j) * 1e9).round();
        assert_eq!([z(0, 0), z(2, 0), z(0, 1)], [3.0, -5.0, 0.0]);
    }

    #[test]
    fn truncation_and_bad_headers_are_refused() {
        let good = file(&[0; 6]);
        for cut in 0..good.len() {
            assert!(read_channel(&good[..cut], None).is_err(), "cut at {cut}");
        }
        assert!(read_channel(b"[Data]\r\n", None).is_err());
        assert!(read_channel(&good, Some(&Channel::Index(1))).is_err());
    }
}
