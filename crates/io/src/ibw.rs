//! Igor binary waves (`.ibw`, version 5), as Asylum Research AFMs write
//! them, read.
//!
//! WaveMetrics' Technical Note 003 describes the file: a 64-byte `BinHeader5`
//! (version 5 — its byte order tells the file's —, the sizes of the wave,
//! formula, note, extended units, dimension units and dimension labels), a
//! 320-byte `WaveHeader5` (at its offsets 12 the point count, 16 the number
//! type, 68 the four dimension sizes, 84 their steps `sfA`, 148 the data
//! units and 152 the dimension units, four characters each), the data, then
//! the formula, the note, the extended units and the dimension labels (32
//! bytes each, the first naming the dimension itself). The data are stored
//! first dimension fastest: x, then y, then the channel.
//!
//! As SurfaceTopography reads them: a wave with a third dimension holds
//! that many images (channels, named by the third dimension's labels, else
//! `no name (k)`); a square two-dimensional wave is one image; another
//! two-dimensional wave is as many line scans as its second dimension, and a
//! one-dimensional wave one line scan (profiles, read with one row). Images
//! are read with their lines from the last, as SurfaceTopography and
//! Gwyddion show them. A channel's unit comes from the Asylum note
//! (`NameUnit`, else the name's prefix — Height, ZSensor, Deflection and
//! Amplitude are metres, Phase degrees, other signals volts…), else the
//! wave's data units; a length is converted to the lateral unit. Channels in
//! other units are read unitless. Complex and four-dimensional waves are
//! refused.

use asperity_core::{HeightField, LengthUnit, Units};

use crate::channel::{Channel, ChannelInfo, pick};
use crate::error::{FResult, FormatError, malformed, unsupported};
use crate::format::{Access, Codec, Registration};

const BIN_HEADER: usize = 64;
const WAVE_HEADER: usize = 320;

/// The Asylum note's `key: value` lines.
type Note = Vec<(String, String)>;

/// What a wave holds, as read from its headers.
struct Wave {
    little: bool,
    kind: i16,
    dims: [usize; 4],
    steps: [f64; 2],
    data_unit: String,
    lateral_unit: String,
    names: Vec<String>,
    note: Note,
    /// Images (true) or line scans.
    images: bool,
    channels: usize,
}

fn zero_padded(b: &[u8]) -> String {
    let end = b.iter().position(|&c| c == 0).unwrap_or(b.len());
    b[..end].iter().map(|&c| char::from(c)).collect()
}

/// Numbers in the file's byte order (the version field tells it).
#[derive(Clone, Copy)]
struct ByteOrder {
    little: bool,
}

impl ByteOrder {
    fn i16(self, b: &[u8], o: usize) -> i16 {
        let b = [b[o], b[o + 1]];
        if self.little {
            i16::from_le_bytes(b)
        } else {
            i16::from_be_bytes(b)
        }
    }

    fn i32(self, b: &[u8], o: usize) -> i32 {
        let b: [u8; 4] = b[o..o + 4].try_into().expect("4 bytes");
        if self.little {
            i32::from_le_bytes(b)
        } else {
            i32::from_be_bytes(b)
        }
    }

    fn f64(self, b: &[u8], o: usize) -> f64 {
        let b: [u8; 8] = b[o..o + 8].try_into().expect("8 bytes");
        if self.little {
            f64::from_le_bytes(b)
        } else {
            f64::from_be_bytes(b)
        }
    }

    /// A size field: negative sizes read as 0.
    fn size(self, b: &[u8], o: usize) -> usize {
        usize::try_from(self.i32(b, o)).unwrap_or(0)
    }
}

fn wave(bytes: &[u8]) -> FResult<Wave> {
    let head = bytes.get(..BIN_HEADER + WAVE_HEADER).ok_or_else(|| {
        FormatError::Malformed("the file is shorter than the IBW headers (truncated?)".into())
    })?;
    let order = match (
        i16::from_le_bytes([head[0], head[1]]),
        i16::from_be_bytes([head[0], head[1]]),
    ) {
        (5, _) => ByteOrder { little: true },
        (_, 5) => ByteOrder { little: false },
        (v, _) => return unsupported(format!("Igor binary wave version {v} (version 5 is read)")),
    };
    let w = BIN_HEADER;
    let kind = order.i16(head, w + 16);
    if kind & 1 != 0 {
        return unsupported("a wave of complex numbers");
    }
    let dims: [usize; 4] = std::array::from_fn(|k| order.size(head, w + 68 + 4 * k));
    if dims[3] != 0 {
        return unsupported("a four-dimensional wave");
    }
    // Every point takes a byte at least: dimensions the file cannot hold are
    // a corrupt header, refused before anything is sized by them.
    let points = dims[..3]
        .iter()
        .filter(|&&n| n != 0)
        .try_fold(1usize, |p, &n| p.checked_mul(n));
    if points.is_none_or(|p| p > bytes.len()) {
        return malformed(format!(
            "dimensions {} × {} × {} cannot fit in the file's {} bytes",
            dims[0],
            dims[1],
            dims[2],
            bytes.len()
        ));
    }
    let (images, channels, label_dim) = layout(dims);
    let (names, note) = trailing_blocks(bytes, order, label_dim, channels)?;
    Ok(Wave {
        little: order.little,
        kind,
        dims,
        steps: [order.f64(head, w + 84), order.f64(head, w + 92)],
        data_unit: zero_padded(&head[w + 148..w + 152]),
        lateral_unit: zero_padded(&head[w + 152..w + 156]),
        names,
        note,
        images,
        channels,
    })
}

/// The blocks after the wave, whose sizes the binary header gives: the
/// channels' names (`channels` of them, from the labels of dimension
/// `label_dim`, `no name (k)` where there are none) and the note's
/// `key: value` lines.
fn trailing_blocks(
    bytes: &[u8],
    order: ByteOrder,
    label_dim: usize,
    channels: usize,
) -> FResult<(Vec<String>, Note)> {
    let size = |o: usize| order.size(bytes, o);
    let (wfm, formula, note_size, data_units) = (size(4), size(8), size(12), size(16));
    let dim_units: usize = (0..4).map(|k| size(20 + 4 * k)).sum();
    let labels: [usize; 4] = std::array::from_fn(|k| size(36 + 4 * k));
    let block = |from: usize, n: usize| -> FResult<&[u8]> {
        from.checked_add(n)
            .and_then(|end| bytes.get(from..end))
            .ok_or_else(|| {
                FormatError::Malformed(
                    "the file ends before the blocks its header declares (truncated?)".into(),
                )
            })
    };
    let mut at = BIN_HEADER + wfm.max(WAVE_HEADER) + formula;
    let note_text: String = block(at, note_size)?
        .iter()
        .map(|&c| char::from(c))
        .collect();
    at += note_size + data_units + dim_units;
    let mut names = Vec::new();
    for (k, &n) in labels.iter().enumerate() {
        let b = block(at, n)?;
        if k == label_dim {
            names = b
                .chunks_exact(32)
                .skip(1)
                .map(zero_padded)
                .take(channels)
                .collect();
        }
        at += n;
    }
    let named = names.len();
    names.extend((1..=channels - named.min(channels)).map(|k| format!("no name ({k})")));
    let note = note_text
        .split(['\r', '\n'])
        .filter_map(|l| l.split_once(':'))
        .map(|(k, v)| (k.trim().to_string(), v.trim().to_string()))
        .collect();
    Ok((names, note))
}

/// Images or line scans, how many channels, and the dimension labelling
/// them (SurfaceTopography's reading of the dimension sizes).
fn layout(dims: [usize; 4]) -> (bool, usize, usize) {
    if dims[2] != 0 {
        (true, dims[2], 2)
    } else if dims[1] != 0 && dims[1] == dims[0] {
        (true, 1, 2)
    } else if dims[1] != 0 {
        (false, dims[1], 1)
    } else {
        (false, 1, 1)
    }
}

/// A channel's data unit: the Asylum note's, else by its name, else the
/// wave's.
fn channel_unit(w: &Wave, index: usize) -> String {
    let name = &w.names[index];
    if w.note.is_empty() || name.starts_with("no name (") {
        return w.data_unit.clone();
    }
    // The name without a trailing `Mod` + digits, then without Trace/Retrace.
    let base = name
        .trim_end_matches(|c: char| c.is_ascii_digit())
        .strip_suffix("Mod")
        .unwrap_or(name);
    let base = base
        .strip_suffix("Retrace")
        .or_else(|| base.strip_suffix("Trace"))
        .unwrap_or(base);
    if let Some((_, u)) = w.note.iter().find(|(k, _)| *k == format!("{base}Unit")) {
        return u.clone();
    }
    let base = base
        .strip_prefix("DAC")
        .or_else(|| base.strip_prefix("Nap"))
        .unwrap_or(base);
    const BY_PREFIX: [(&str, &str); 11] = [
        ("Height", "m"),
        ("ZSensor", "m"),
        ("Deflection", "m"),
        ("Amplitude", "m"),
        ("Phase", "deg"),
        ("Current", "A"),
        ("Frequency", "Hz"),
        ("Capacitance", "F"),
        ("Potential", "V"),
        ("Count", ""),
        ("QFactor", ""),
    ];
    BY_PREFIX
        .iter()
        .find(|(p, _)| base.starts_with(p))
        .map_or("V".into(), |(_, u)| (*u).to_string())
}

/// Igor's units are SI symbols: `A` is the ampere, not the ångström.
fn length_unit(unit: &str) -> Option<LengthUnit> {
    match unit {
        "A" | "" => None,
        "um" => Some(LengthUnit::Um),
        u => LengthUnit::parse(u).ok().filter(|u| *u != LengthUnit::None),
    }
}

/// The wave's note (`key: value` lines, as Asylum Research writes them).
pub(crate) fn metadata(bytes: &[u8]) -> FResult<Vec<(String, String)>> {
    Ok(wave(bytes)?.note)
}

/// The wave's channels.
pub(crate) fn channels(bytes: &[u8]) -> FResult<Vec<ChannelInfo>> {
    let w = wave(bytes)?;
    Ok((0..w.channels)
        .map(|index| ChannelInfo {
            index,
            name: w.names[index].clone(),
            height: length_unit(&channel_unit(&w, index)).is_some(),
        })
        .collect())
}

/// Every value of the wave (its `per_channel` values a channel, in the
/// wave's number type and byte order), as f64.
fn values(bytes: &[u8], w: &Wave, per_channel: usize) -> FResult<Vec<f64>> {
    let size = match w.kind & !0x40 {
        2 | 0x20 => 4,
        4 => 8,
        8 => 1,
        0x10 => 2,
        t => return unsupported(format!("number type 0x{t:x}")),
    };
    let unsigned = w.kind & 0x40 != 0;
    let need = per_channel
        .checked_mul(w.channels)
        .and_then(|n| n.checked_mul(size))
        .filter(|&n| {
            n.checked_add(BIN_HEADER + WAVE_HEADER)
                .is_some_and(|end| end <= bytes.len())
        })
        .ok_or_else(|| {
            FormatError::Malformed("the wave's data run past the file's end (truncated?)".into())
        })?;
    let data = &bytes[BIN_HEADER + WAVE_HEADER..BIN_HEADER + WAVE_HEADER + need];
    Ok(data
        .chunks_exact(size)
        .map(|b| {
            let mut a = [0u8; 8];
            a[..size].copy_from_slice(b);
            if !w.little {
                a[..size].reverse();
            }
            match (w.kind & !0x40, unsigned) {
                (2, _) => f64::from(f32::from_le_bytes(a[..4].try_into().expect("4"))),
                (4, _) => f64::from_le_bytes(a),
                (8, false) => f64::from(a[0] as i8),
                (0x10, false) => f64::from(i16::from_le_bytes([a[0], a[1]])),
                (0x20, false) => f64::from(i32::from_le_bytes(a[..4].try_into().expect("4"))),
                (8, true) => f64::from(a[0]),
                (0x10, true) => f64::from(u16::from_le_bytes([a[0], a[1]])),
                _ => f64::from(u32::from_le_bytes(a[..4].try_into().expect("4"))),
            }
        })
        .collect())
}

/// Channel `c`'s lateral and height units, and the factor that brings its
/// values to the height unit (heights in the lateral unit where both are
/// lengths).
fn units(w: &Wave, c: usize) -> (LengthUnit, LengthUnit, f64) {
    let lateral = length_unit(&w.lateral_unit);
    match (length_unit(&channel_unit(w, c)), lateral) {
        (Some(z), None) => (z, z, 1.0),
        (Some(z), Some(l)) => (l, l, z.metres().zip(l.metres()).map_or(1.0, |(a, b)| a / b)),
        (None, l) => (l.unwrap_or(LengthUnit::None), LengthUnit::None, 1.0),
    }
}

/// Reads the channel `choice` names (by default the first height channel).
pub(crate) fn read_channel(bytes: &[u8], choice: Option<&Channel>) -> FResult<HeightField> {
    let w = wave(bytes)?;
    let list = channels(bytes)?;
    let c = pick(&list, choice)?;
    let (nx, ny) = if w.images {
        (w.dims[0], w.dims[1])
    } else {
        (w.dims[0], 1)
    };
    if nx == 0 || ny == 0 {
        return malformed("an empty wave");
    }
    let values = values(bytes, &w, nx * ny)?;
    let (xy, z, factor) = units(&w, c);
    // Images: lines from the last; a line scan's channel is a column.
    let heights = (0..ny)
        .flat_map(|j| {
            let row = if w.images { ny - 1 - j } else { 0 };
            (0..nx).map(move |i| (i, row))
        })
        .map(|(i, row)| {
            let k = if w.images {
                i + nx * (row + ny * c)
            } else {
                i + nx * c
            };
            values[k] * factor
        })
        .collect();
    let [dx, dy] = w.steps;
    if !(dx.is_finite() && dx > 0.0 && (!w.images || (dy.is_finite() && dy > 0.0))) {
        return malformed(format!("the steps {dx} × {dy} are not positive"));
    }
    let dy = if w.images { dy } else { dx };
    Ok(HeightField::from_vec([nx, ny], heights)?
        .with_spacing([dx, dy])?
        .with_units(Units { xy, z }))
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "Igor binary wave (.ibw)",
    extensions: &["ibw"],
    height: Access::Read,
    notes: "version 5, as Asylum Research AFMs write it: image stacks as channels (labels, else no name (k)), units from the Asylum note or the wave, lengths in the lateral unit, lines from the last; line scans as profiles; complex and 4-D waves refused",
    codec: Some(Codec::new(read_channel)
        .channels(channels)
        .metadata(metadata)),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    /// A little-endian f32 wave of `dims` with labels for dimension 2.
    fn file(dims: [i32; 3], values: &[f32], labels: &[&str], note: &str) -> Vec<u8> {
        let mut b = vec![0u8; BIN_HEADER + WAVE_HEADER];
        b[0..2].copy_from_slice(&5i16.to_le_bytes());
        let data = values.len() * 4;
        let label_bytes = if labels.is_empty() {
            0
        } else {
            32 * (labels.len() + 1)
        };
        for (o, v) in [(4, WAVE_HEADER + data), (12, note.len()), (44, label_bytes)] {
            b[o..o + 4].copy_from_slice(&(v as i32).to_le_bytes());
        }
        let w = BIN_HEADER;
        b[w + 12..w + 16].copy_from_slice(&(values.len() as i32).to_le_bytes());
        b[w + 16..w + 18].copy_from_slice(&2i16.to_le_bytes());
        for (k, d) in dims.iter().enumerate() {
            b[w + 68 + 4 * k..w + 72 + 4 * k].copy_from_slice(&d.to_le_bytes());
        }
        b[w + 84..w + 92].copy_from_slice(&0.5f64.to_le_bytes());
        b[w + 92..w + 100].copy_from_slice(&0.25f64.to_le_bytes());
        b[w + 148] = b'm';
        b[w + 152] = b'm';
        b.extend(values.iter().flat_map(|v| v.to_le_bytes()));
        b.extend(note.as_bytes());
        if !labels.is_empty() {
            b.extend([0u8; 32]);
            for l in labels {
                let mut c = [0u8; 32];
                c[..l.len()].copy_from_slice(l.as_bytes());
                b.extend(c);
            }
        }
        b
    }

    #[test]
    fn reads_the_channels_of_an_asylum_image_stack() {
        // 2 × 2 images: height then phase, x fastest, the last line first.
        let values = [1.0, 2.0, 3.0, 4.0, 10.0, 20.0, 30.0, 40.0];
        let f = file(
            [2, 2, 2],
            &values,
            &["HeightTrace", "PhaseTrace"],
            "Date: 2020-01-01\rHeightUnit: nm\r",
        );
        let list = channels(&f).unwrap();
        assert_eq!(
            list.iter()
                .map(|c| (c.name.as_str(), c.height))
                .collect::<Vec<_>>(),
            [("HeightTrace", true), ("PhaseTrace", false)]
        );
        // Heights in nm by the note (lines split at CR), in the lateral metres.
        let h = read_channel(&f, None).unwrap();
        let z: Vec<f64> = h
            .data()
            .iter()
            .map(|v| (v * 1e9 * 1e6).round() / 1e6)
            .collect();
        assert_eq!(z, [3.0, 4.0, 1.0, 2.0]);
        assert_eq!(metadata(&f).unwrap()[1], ("HeightUnit".into(), "nm".into()));
        assert_eq!(h.spacing(), [0.5, 0.25]);
        assert_eq!(
            h.units(),
            Units {
                xy: LengthUnit::M,
                z: LengthUnit::M
            }
        );
        let p = read_channel(&f, Some(&Channel::parse("phasetrace"))).unwrap();
        assert_eq!(p.data(), &[30.0, 40.0, 10.0, 20.0]);
        assert_eq!(p.units().z, LengthUnit::None);
    }

    #[test]
    fn a_wave_without_labels_and_truncation() {
        let f = file([2, 2, 1], &[1.0, 2.0, 3.0, 4.0], &[], "");
        assert_eq!(channels(&f).unwrap()[0].name, "no name (1)");
        for cut in 0..f.len() {
            assert!(read_channel(&f[..cut], None).is_err(), "cut at {cut}");
        }
        let profile = file([4, 0, 0], &[1.0, 2.0, 3.0, 4.0], &[], "");
        let p = read_channel(&profile, None).unwrap();
        assert_eq!(p.dims(), [4, 1]);
    }
}
