//! NT-MDT `.mdt` (Solver and Ntegra AFMs, the Nova software), read.
//!
//! A 33-byte little-endian header — the magic `01 B0 93 FF`, the size of
//! the frame data, the index of the last frame (u16 at byte 12) — then the
//! frames, each a 22-byte header (its size, u32; its type, u16, 0 for scanned
//! data; version; the date as six u16; the size of its variables, u16) and
//! its body. A scanned-data frame's body: the axis scales (x, y, z: offset
//! f32, step f32, unit code i16, the codes −5…0 meaning m, cm, mm, µm, nm,
//! Å), the scan variables (the ADC channel, u8 — 0 Height, 1 DFL, 4 Current,
//! 11 Phase1…; mode; points), the rest of the variables, the frame mode
//! (mode, nx, ny, the number of spectroscopy dots, u16 each), the dots'
//! section if any (14 + 16 bytes a dot), then nx × ny int16 counts stored
//! from the image's last line; height = count × z step + z offset.
//!
//! Every scanned frame whose lateral and height units are lengths is a
//! channel named by its ADC signal (as SurfaceTopography lists them);
//! spectroscopy, text and MDA frames are skipped. Lengths in cm are read in
//! m and ångströms in nm (asperity's units), heights brought to the lateral
//! unit. Layout learnt from SurfaceTopography's `MDT.py` and Gwyddion's
//! `nt-mdt.c`; no instrument file was at hand, so the tests use files built
//! to that layout.

use asperity_core::{HeightField, LengthUnit, Units};

use crate::channel::{Channel, ChannelInfo, pick};
use crate::bytes::Fields;
use crate::error::{FResult, FormatError, malformed, unsupported};
use crate::raster::from_last_line;
use crate::format::{Access, Codec, Magic, Registration};

/// The file's magic.
pub(crate) const MAGIC: &[u8] = b"\x01\xb0\x93\xff";
const HEADER: usize = 33;
const FRAME_HEADER: usize = 22;
/// The scale and scan variables read from a scanned frame.
const PARSED_VARS: usize = 36;

/// One scanned frame: its name, grid, steps, units and where its counts are.
struct Frame {
    name: String,
    nx: usize,
    ny: usize,
    step: [f64; 2],
    z_step: f64,
    z_offset: f64,
    /// Lateral unit, and the factor that brings the heights' numbers to it.
    unit: LengthUnit,
    z_factor: f64,
    data: usize,
}

/// A unit code as an asperity unit and the factor into it.
fn unit(code: i16) -> Option<(LengthUnit, f64)> {
    match code {
        -5 => Some((LengthUnit::M, 1.0)),
        -4 => Some((LengthUnit::M, 1e-2)),
        -3 => Some((LengthUnit::Mm, 1.0)),
        -2 => Some((LengthUnit::Um, 1.0)),
        -1 => Some((LengthUnit::Nm, 1.0)),
        0 => Some((LengthUnit::Nm, 0.1)),
        _ => None,
    }
}

fn signal(adc: u8) -> &'static str {
    const NAMES: [&str; 19] = [
        "Height",
        "DFL",
        "Lateral F",
        "Bias V",
        "Current",
        "FB-Out",
        "MAG",
        "MAG*Sin",
        "MAG*Cos",
        "RMS",
        "CalcMag",
        "Phase1",
        "Phase2",
        "CalcPhase",
        "Ex1",
        "Ex2",
        "HvX",
        "HvY",
        "Snap Back",
    ];
    NAMES.get(usize::from(adc)).copied().unwrap_or("Unknown")
}

/// A scanned frame's body at `at` (after the frame header), if it is a
/// height-like channel.
fn scanned(r: &Fields<'_>, at: usize, var_size: usize) -> FResult<Option<Frame>> {
    if var_size < PARSED_VARS {
        return malformed("a scanned frame's variables are shorter than its scales");
    }
    let axis = |k: usize| -> FResult<(f64, f64, i16)> {
        let o = at + 10 * k;
        Ok((r.f32_wide(o)?, r.f32_wide(o + 4)?, r.i16(o + 8)?))
    };
    let ((_, x_step, xu), (_, y_step, _), (z_offset, z_step, zu)) = (axis(0)?, axis(1)?, axis(2)?);
    let adc = r.u8(at + 30)?;
    let mode = at + var_size;
    let (nx, ny, dots) = (
        usize::from(r.u16(mode + 2)?),
        usize::from(r.u16(mode + 4)?),
        usize::from(r.u16(mode + 6)?),
    );
    let data = mode + 8 + if dots > 0 { 14 + 16 * dots } else { 0 };
    let (Some((unit, xy_factor)), Some((z_unit, z_to))) = (unit(xu), unit(zu)) else {
        return Ok(None); // not lengths: not a channel, as in ST
    };
    if nx == 0 || ny == 0 {
        return Ok(None);
    }
    if !(x_step.is_finite() && y_step.is_finite()) || x_step == 0.0 || y_step == 0.0 {
        return malformed("a scanned frame has a zero or undefined lateral step");
    }
    let per = |u: LengthUnit| u.metres().unwrap_or(1.0);
    Ok(Some(Frame {
        name: signal(adc).to_owned(),
        nx,
        ny,
        step: [x_step.abs() * xy_factor, y_step.abs() * xy_factor],
        z_step: if z_step.is_nan() || z_step == 0.0 {
            1.0
        } else {
            z_step
        },
        z_offset: if z_offset.is_nan() { 0.0 } else { z_offset },
        unit,
        z_factor: z_to * per(z_unit) / per(unit),
        data,
    }))
}

/// The file's scanned frames that are channels.
fn frames(bytes: &[u8]) -> FResult<Vec<Frame>> {
    if !bytes.starts_with(MAGIC) {
        return malformed("missing the NT-MDT magic 01 B0 93 FF");
    }
    let r = Fields::le(bytes);
    let last = usize::from(r.u16(12)?);
    let mut at = HEADER;
    let mut out = Vec::new();
    let mut scanned_frames = 0;
    for _ in 0..=last {
        let size = r.u32(at)? as usize;
        if size < FRAME_HEADER {
            return malformed(format!("a frame of {size} bytes (its header alone is 22)"));
        }
        let end = at
            .checked_add(size)
            .filter(|&e| e <= bytes.len())
            .ok_or_else(|| {
                FormatError::Malformed(format!(
                    "a frame of {size} bytes at {at} runs past the file's end (truncated?)"
                ))
            })?;
        if r.u16(at + 4)? == 0 {
            scanned_frames += 1;
            let var_size = usize::from(r.u16(at + 20)?);
            // The frame's body is read within the frame only.
            let body = Fields::le(&bytes[..end]);
            if let Some(f) = scanned(&body, at + FRAME_HEADER, var_size)? {
                out.push(f);
            }
        }
        at = end;
    }
    if scanned_frames == 0 {
        return unsupported(
            "no scanned-data frame (spectroscopy, text and MDA frames are not read)",
        );
    }
    if out.is_empty() {
        return malformed("no scanned frame has lengths for its axes");
    }
    Ok(out)
}

fn infos(frames: &[Frame]) -> Vec<ChannelInfo> {
    frames
        .iter()
        .enumerate()
        .map(|(index, f)| ChannelInfo {
            index,
            name: f.name.clone(),
            height: true,
        })
        .collect()
}

/// The scanned frames as channels.
pub(crate) fn channels(bytes: &[u8]) -> FResult<Vec<ChannelInfo>> {
    Ok(infos(&frames(bytes)?))
}

/// Reads the frame `choice` names (default the first).
pub(crate) fn read_channel(bytes: &[u8], choice: Option<&Channel>) -> FResult<HeightField> {
    let list = frames(bytes)?;
    let f = &list[pick(&infos(&list), choice)?];
    let need = f.nx * f.ny * 2;
    let counts = bytes
        .get(f.data..f.data.saturating_add(need))
        .ok_or_else(|| {
            FormatError::Malformed(format!(
                "channel {:?}: {} × {} int16 counts at {} run past the file's end (truncated?)",
                f.name, f.nx, f.ny, f.data
            ))
        })?;
    let scale = f.z_step * f.z_factor;
    let offset = f.z_offset * f.z_factor;
    let data = from_last_line(counts, f.nx, 2)
        .map(|c| f64::from(i16::from_le_bytes([c[0], c[1]])) * scale + offset)
        .collect();
    Ok(HeightField::from_vec([f.nx, f.ny], data)?
        .with_spacing(f.step)?
        .with_units(Units {
            xy: f.unit,
            z: f.unit,
        }))
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "NT-MDT (.mdt)",
    extensions: &["mdt"],
    height: Access::Read,
    notes: "scanned-data frames whose axes are lengths, as channels named by their signal (Height, DFL…): int16 counts × z step + offset, from the last line, heights in the lateral unit (cm read in m, Å in nm); spectroscopy, text and MDA frames skipped",
    magic: Magic::Starts(&[MAGIC]),
    codec: Some(Codec::new(read_channel).channels(channels)),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    /// A scanned frame of `nx` × `ny` counts: steps 0.5 and 0.25 in `xy`'s
    /// unit, heights 2 per count + 1 in `z`'s, signal `adc`.
    fn frame(adc: u8, xy: i16, z: i16, nx: u16, ny: u16, counts: &[i16]) -> Vec<u8> {
        let mut body = Vec::new();
        for (off, step, u) in [(0.0f32, 0.5f32, xy), (0.0, 0.25, xy), (1.0, 2.0, z)] {
            body.extend(off.to_le_bytes());
            body.extend(step.to_le_bytes());
            body.extend(u.to_le_bytes());
        }
        body.extend([adc, 0]);
        body.extend(nx.to_le_bytes());
        body.extend(ny.to_le_bytes());
        body.extend([0; 4]); // more variables: var_size 40
        for v in [0u16, nx, ny, 0] {
            body.extend(v.to_le_bytes());
        }
        body.extend(counts.iter().flat_map(|c| c.to_le_bytes()));
        let mut f = ((FRAME_HEADER + body.len()) as u32).to_le_bytes().to_vec();
        f.extend([0u8; 2]); // type 0: scanned
        f.extend([0u8; 14]);
        f.extend(40u16.to_le_bytes());
        f.extend(body);
        f
    }

    fn file(frames: &[Vec<u8>]) -> Vec<u8> {
        let mut b = MAGIC.to_vec();
        b.extend([0; 8]);
        b.extend(((frames.len() - 1) as u16).to_le_bytes());
        b.extend([0; 19]);
        for f in frames {
            b.extend(f);
        }
        b
    }

    #[test]
    fn scanned_frames_are_channels_read_from_their_last_line() {
        let f = file(&[
            frame(0, -1, -1, 3, 2, &[0, 1, 2, 3, 4, 5]),
            frame(11, -1, 5, 3, 2, &[0; 6]), // a phase in no length: skipped
            frame(1, -2, 0, 2, 1, &[10, -10]),
        ]);
        let names: Vec<String> = channels(&f).unwrap().into_iter().map(|c| c.name).collect();
        assert_eq!(names, ["Height", "DFL"]);
        let h = read_channel(&f, None).unwrap();
        assert_eq!((h.dims(), h.spacing()), ([3, 2], [0.5, 0.25]));
        // The last stored line first: counts 3, 4, 5 × 2 + 1.
        assert_eq!(h.row(0), &[7.0, 9.0, 11.0]);
        // Heights in Å (2 Å a count + 1 Å) brought to the lateral µm.
        let d = read_channel(&f, Some(&Channel::parse("DFL"))).unwrap();
        assert_eq!(d.units().xy, LengthUnit::Um);
        assert!((d.data()[0] - 21.0 * 1e-4).abs() < 1e-15, "{:?}", d.data());
    }

    #[test]
    fn truncated_files_and_files_without_scans_are_refused() {
        let f = file(&[frame(0, -1, -1, 3, 2, &[0, 1, 2, 3, 4, 5])]);
        for cut in [0, 10, 40, 80, f.len() - 1] {
            assert!(read_channel(&f[..cut], None).is_err(), "cut at {cut}");
        }
        let mut spectra = frame(0, -1, -1, 1, 1, &[0]);
        spectra[4] = 1; // a spectroscopy frame
        let e = format!("{:?}", read_channel(&file(&[spectra]), None).unwrap_err());
        assert!(e.contains("no scanned-data frame"), "{e}");
    }
}
