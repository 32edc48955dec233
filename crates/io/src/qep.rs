//! Mahr MarWin `.qep` profile archives (contour and surface measuring
//! instruments), read.
//!
//! A zip archive holding the measured profile `Kontur1.prf` and optionally a
//! reference profile `qe_contour_reference_profil_001.tmp` (the channels
//! `measured` and `reference`, as SurfaceTopography names them). Each is a
//! MarWin `[p3dlin]` line scan: the magic, the number of points (i32 at
//! 0x14), at 0xC4 a table of strings (count, then length-prefixed Latin-1;
//! the `>Key=Value` ones are the metadata: date, machine, software, probe
//! radius…), then the sections `[sellsg]` and `[Trajec]`; 41 bytes after
//! `[Trajec]`'s header the points: n positions (f64, mm), n values not read,
//! n heights (f64, mm), n validity flags (f32, nonzero an invalid point),
//! which must end the member. A uniformly sampled profile is read as a
//! one-row field with its invalid points missing; a non-uniform one is
//! refused with its steps, as asperity refuses every non-uniform line scan.
//! Layout from SurfaceTopography's `QEP.py`; checked against it on a file
//! built to that layout (no instrument file is public).

use asperity_core::{HeightField, LengthUnit};

use crate::Metadata;
use crate::channel::{Channel, ChannelInfo, pick};
use crate::error::{FResult, FormatError, malformed};
use crate::zipped::{self, Archive};
use crate::format::{Access, Codec, Registration};

const MAGIC: &[u8] = b"[p3dlin]";
const MEMBERS: [(&str, &str); 2] = [
    ("Kontur1.prf", "measured"),
    ("qe_contour_reference_profil_001.tmp", "reference"),
];
const POINTS_AT: usize = 0x14;
const STRINGS_AT: usize = 0xC4;
const DATA_AFTER_TRAJEC: usize = 8 + 41;
const BYTES_A_POINT: usize = 28;

/// A parsed profile: metadata, positions, heights (NaN where invalid).
struct Profile {
    meta: Metadata,
    x: Vec<f64>,
    z: Vec<f64>,
}

fn i32_at(b: &[u8], o: usize, what: &str) -> FResult<i32> {
    b.get(o..o + 4)
        .map(|w| i32::from_le_bytes([w[0], w[1], w[2], w[3]]))
        .ok_or_else(|| {
            FormatError::Malformed(format!("{what}: the profile ends at byte {o} (truncated?)"))
        })
}

fn find(hay: &[u8], needle: &[u8], from: usize) -> Option<usize> {
    hay.get(from..)?
        .windows(needle.len())
        .position(|w| w == needle)
        .map(|k| k + from)
}

fn parse(blob: &[u8], name: &str) -> FResult<Profile> {
    if !blob.starts_with(MAGIC) {
        return malformed(format!("member {name} is no MarWin [p3dlin] profile"));
    }
    let n = i32_at(blob, POINTS_AT, name)?;
    let Ok(n) = usize::try_from(n) else {
        return malformed(format!("member {name}: {n} points"));
    };
    let count = i32_at(blob, STRINGS_AT, name)?;
    let mut at = STRINGS_AT + 4;
    let mut meta = Vec::new();
    for _ in 0..count.max(0) {
        let len = i32_at(blob, at, name)?;
        let text = usize::try_from(len)
            .ok()
            .and_then(|len| blob.get(at + 4..at + 4 + len))
            .ok_or_else(|| {
                FormatError::Malformed(format!("member {name}: a string runs past its end"))
            })?;
        at += 4 + text.len();
        let text: String = text.iter().map(|&c| char::from(c)).collect();
        if let Some((k, v)) = text.strip_prefix('>').and_then(|t| t.split_once('=')) {
            meta.push((k.to_owned(), v.to_owned()));
        }
    }
    let sellsg = find(blob, b"[sellsg]", at)
        .ok_or_else(|| FormatError::Malformed(format!("member {name} has no [sellsg] section")))?;
    let trajec = find(blob, b"[Trajec]", sellsg)
        .ok_or_else(|| FormatError::Malformed(format!("member {name} has no [Trajec] section")))?;
    let start = trajec + DATA_AFTER_TRAJEC;
    if n < 2
        || n.checked_mul(BYTES_A_POINT)
            .and_then(|b| b.checked_add(start))
            != Some(blob.len())
    {
        return malformed(format!(
            "member {name}: {n} points do not fill its {} bytes after [Trajec] (truncated?)",
            blob.len().saturating_sub(start)
        ));
    }
    let f64s = |o: usize| -> Vec<f64> {
        blob[o..o + 8 * n]
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
            .collect()
    };
    let x = f64s(start);
    let flags = &blob[start + 24 * n..start + 28 * n];
    let z = f64s(start + 16 * n)
        .into_iter()
        .zip(flags.chunks_exact(4))
        .map(|(z, f)| {
            if f32::from_le_bytes([f[0], f[1], f[2], f[3]]) == 0.0 {
                z
            } else {
                f64::NAN
            }
        })
        .collect();
    Ok(Profile { meta, x, z })
}

fn open(bytes: &[u8]) -> FResult<(Archive<'_>, Vec<(&'static str, &'static str)>)> {
    let zip = zipped::open(bytes, |e| {
        FormatError::Malformed(format!("not a readable QEP archive: {e}"))
    })?;
    let present: Vec<_> = MEMBERS
        .into_iter()
        .filter(|(m, _)| zip.index_for_name(m).is_some())
        .collect();
    if present.is_empty() {
        return malformed("the archive holds no MarWin profile (Kontur1.prf)");
    }
    Ok((zip, present))
}

fn profile(zip: &mut Archive<'_>, member: &str) -> FResult<Profile> {
    let blob = zipped::required(zip, member, u64::MAX, FormatError::Malformed)?;
    parse(&blob, member)
}

fn infos(present: &[(&str, &str)]) -> Vec<ChannelInfo> {
    present
        .iter()
        .enumerate()
        .map(|(index, (_, name))| ChannelInfo {
            index,
            name: (*name).to_owned(),
            height: true,
        })
        .collect()
}

/// The profiles present, as channels.
pub(crate) fn channels(bytes: &[u8]) -> FResult<Vec<ChannelInfo>> {
    Ok(infos(&open(bytes)?.1))
}

/// Reads the profile `choice` names (default the measured one).
pub(crate) fn read_channel(bytes: &[u8], choice: Option<&Channel>) -> FResult<HeightField> {
    let (mut zip, present) = open(bytes)?;
    let (member, _) = present[pick(&infos(&present), choice)?];
    let p = profile(&mut zip, member)?;
    crate::xz::profile(&p.x, p.z, LengthUnit::Mm)
}

/// The measured profile's `>Key=Value` entries.
pub(crate) fn metadata(bytes: &[u8]) -> FResult<Metadata> {
    let (mut zip, present) = open(bytes)?;
    Ok(profile(&mut zip, present[0].0)?.meta)
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "Mahr MarWin QEP (.qep)",
    extensions: &["qep"],
    height: Access::Read,
    notes: "the measured and reference [p3dlin] profiles as channels: a uniformly sampled profile in mm (one row), invalid points missing; non-uniform scans refused with their steps; the >Key=Value entries kept as metadata",
    codec: Some(Codec::new(read_channel)
        .channels(channels)
        .metadata(metadata)
        .declared(crate::zipped::declared_twice)),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use std::io::Cursor;
    use std::io::Write;

    use super::*;

    /// A `[p3dlin]` member of the points `x`, `z` with `flags`.
    fn prf(x: &[f64], z: &[f64], flags: &[f32]) -> Vec<u8> {
        let mut b = vec![0u8; STRINGS_AT];
        b[..8].copy_from_slice(MAGIC);
        b[POINTS_AT..POINTS_AT + 4].copy_from_slice(&(x.len() as i32).to_le_bytes());
        let note = b">MachineName=MarSurf";
        b.extend(1i32.to_le_bytes());
        b.extend((note.len() as i32).to_le_bytes());
        b.extend(note);
        b.extend(b"[sellsg]");
        b.extend(b"[Trajec]");
        b.extend([0; 41]);
        b.extend(x.iter().flat_map(|v| v.to_le_bytes()));
        b.extend(x.iter().flat_map(|_| 0f64.to_le_bytes()));
        b.extend(z.iter().flat_map(|v| v.to_le_bytes()));
        b.extend(flags.iter().flat_map(|v| v.to_le_bytes()));
        b
    }

    fn qep(reference: bool) -> Vec<u8> {
        let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
        let opts = zip::write::SimpleFileOptions::default();
        zip.start_file(MEMBERS[0].0, opts).unwrap();
        zip.write_all(&prf(&[0.0, 0.5, 1.0], &[1.0, 2.0, 3.0], &[0.0, 1.0, 0.0]))
            .unwrap();
        if reference {
            zip.start_file(MEMBERS[1].0, opts).unwrap();
            zip.write_all(&prf(&[0.0, 0.5, 2.0], &[0.0; 3], &[0.0; 3]))
                .unwrap();
        }
        zip.finish().unwrap().into_inner()
    }

    #[test]
    fn a_uniform_profile_is_read_in_millimetres_with_invalid_points_missing() {
        let f = qep(true);
        let names: Vec<String> = channels(&f).unwrap().into_iter().map(|c| c.name).collect();
        assert_eq!(names, ["measured", "reference"]);
        let h = read_channel(&f, None).unwrap();
        assert_eq!((h.dims(), h.spacing()[0]), ([3, 1], 0.5));
        assert_eq!(h.units().xy, LengthUnit::Mm);
        assert!(h.data()[1].is_nan() && h.data()[2] == 3.0);
        let e = format!(
            "{:?}",
            read_channel(&f, Some(&Channel::parse("reference"))).unwrap_err()
        );
        assert!(e.contains("non-uniformly sampled"), "{e}");
        assert_eq!(metadata(&f).unwrap()[0].1, "MarSurf");
    }

    #[test]
    fn truncated_members_are_refused() {
        let blob = prf(&[0.0, 0.5, 1.0], &[1.0, 2.0, 3.0], &[0.0; 3]);
        for cut in [0, 10, STRINGS_AT + 2, blob.len() - 1] {
            assert!(parse(&blob[..cut], "x").is_err(), "cut at {cut}");
        }
        let f = qep(false);
        assert!(read_channel(&f[..f.len() / 2], None).is_err());
    }
}
