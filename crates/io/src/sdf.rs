//! ISO 25178-71 Surface Data File (`.sdf`), the standard's exchange format for
//! areal height data (after the SDF of the EU "SURFSTAND" project, Blunt &
//! Jiang 2003), read in both its variants and written in the text one.
//!
//! A file is a header, a data section and an optional trailer:
//! - text (`aISO-1.0`): `Key = Value` lines, a line `*`, the heights as numbers
//!   separated by white space (a profile after the other), a line `*`, free
//!   text (often `<Tag> … </Tag>` lines) and a final `*`;
//! - binary (`bISO-1.0`): an 81-byte little-endian record (the magic, three
//!   text fields of 10, 12 and 12 bytes, NumPoints and NumProfiles as u16,
//!   Xscale, Yscale, Zscale and Zresolution as f64, then Compression, DataType
//!   and CheckType as one byte each), then the samples.
//!
//! NumPoints samples make a profile along x, NumProfiles profiles run along y;
//! Xscale and Yscale are the spacings in metres, and a stored value times
//! Zscale is a height in metres. DataType 5, 6 and 7 are int16, int32 and
//! f64; other types and any compression are refused. Points marked `BAD` (or
//! the type's minimum, or NaN) were not measured: they are read as missing
//! points (NaN).
//!
//! Written: text, DataType 7, Zscale 1, every length in metres (unitless data
//! is written as metres, as for x3p), dates fixed to zero so that the same
//! input gives the same bytes, and the parameters in the trailer as an
//! `<AsperityParams>` line.

use std::io::Write;

use asperity_core::{HeightField, LengthUnit, Units};

use crate::bytes::Fields;
use crate::error::{FResult, FormatError, malformed};
use crate::header_keys::HeaderKeys;
use crate::format::{Access, Codec, Magic, Registration};

const TEXT_MAGIC: &[u8] = b"aISO-1.0";
const BINARY_MAGIC: &[u8] = b"bISO-1.0";
/// Bytes of the binary header.
const BINARY_HEADER: usize = 81;

/// The header fields asperity uses.
#[derive(Debug)]
struct Header {
    points: usize,
    profiles: usize,
    x_scale: f64,
    y_scale: f64,
    z_scale: f64,
    data_type: u8,
    compression: u8,
}

impl Header {
    fn check(&self) -> FResult<()> {
        if self.points == 0 || self.profiles == 0 {
            return malformed(format!(
                "NumPoints × NumProfiles is {} × {}: no data",
                self.points, self.profiles
            ));
        }
        for (name, v) in [("Xscale", self.x_scale), ("Yscale", self.y_scale)] {
            if !(v.is_finite() && v > 0.0) {
                return malformed(format!("{name} = {v} is not a positive spacing"));
            }
        }
        if !(self.z_scale.is_finite() && self.z_scale != 0.0) {
            return malformed(format!("Zscale = {} is not a finite scale", self.z_scale));
        }
        if self.compression != 0 {
            return Err(FormatError::Unsupported(format!(
                "compressed SDF data (Compression = {}) is not supported",
                self.compression
            )));
        }
        if !matches!(self.data_type, 5..=7) {
            return Err(FormatError::Unsupported(format!(
                "SDF DataType {} is not supported (5 int16, 6 int32, 7 double)",
                self.data_type
            )));
        }
        Ok(())
    }

    /// The field of `values` (stored numbers; NaN where not measured).
    fn field(&self, values: Vec<f64>) -> FResult<HeightField> {
        let data = values.into_iter().map(|v| v * self.z_scale).collect();
        let h = HeightField::from_vec([self.points, self.profiles], data)?
            .with_spacing([self.x_scale, self.y_scale])?
            .with_units(Units::same(LengthUnit::M));
        Ok(h)
    }
}

/// Reads an SDF file of either variant.
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    if bytes.starts_with(TEXT_MAGIC) {
        read_text(bytes)
    } else if bytes.starts_with(BINARY_MAGIC) {
        read_binary(bytes)
    } else {
        malformed("missing the SDF magic `aISO-1.0` or `bISO-1.0`")
    }
}

/// The text between the magic and the first line that is `*`, and the rest.
fn split_section(text: &str) -> Option<(&str, &str)> {
    let mut at = 0;
    for line in text.split_inclusive('\n') {
        if line.trim() == "*" {
            return Some((&text[..at], &text[at + line.len()..]));
        }
        at += line.len();
    }
    None
}

fn read_text(bytes: &[u8]) -> FResult<HeightField> {
    let text = std::str::from_utf8(&bytes[TEXT_MAGIC.len()..])
        .map_err(|_| FormatError::Malformed("the text SDF is not ASCII/UTF-8".into()))?;
    let (head, rest) = split_section(text)
        .ok_or_else(|| FormatError::Malformed("no `*` line ends the header".into()))?;
    let mut keys = std::collections::HashMap::new();
    for line in head.lines().filter(|l| !l.trim().is_empty()) {
        let (k, v) = line
            .split_once('=')
            .ok_or_else(|| FormatError::Malformed(format!("header line {line:?} has no '='")))?;
        keys.insert(k.trim().to_owned(), v.trim().to_owned());
    }
    let header = HeaderKeys::new(&keys);
    let h = Header {
        points: header.whole("NumPoints")?,
        profiles: header.whole("NumProfiles")?,
        x_scale: header.real("Xscale")?,
        y_scale: header.real("Yscale")?,
        z_scale: header.real("Zscale")?,
        data_type: header.small_or_zero("DataType")?,
        compression: header.small_or_zero("Compression")?,
    };
    h.check()?;
    // The data must end with its `*` line: without it a cut inside the last
    // number would still read as a number.
    let (data, _trailer) = split_section(rest).ok_or_else(|| {
        FormatError::Malformed("the data section does not end with a `*` line (truncated?)".into())
    })?;
    let n = h
        .points
        .checked_mul(h.profiles)
        .ok_or_else(|| FormatError::Malformed("NumPoints × NumProfiles is too large".into()))?;
    // Each number takes at least two bytes: a larger count cannot be there.
    if n > data.len() / 2 + 1 {
        return malformed(format!(
            "{} × {} points declared but the data section has {} bytes (truncated?)",
            h.points,
            h.profiles,
            data.len()
        ));
    }
    let mut values = Vec::with_capacity(n);
    for token in data.split_ascii_whitespace() {
        if values.len() == n {
            return malformed(format!(
                "more than the {} × {} values the header declares",
                h.points, h.profiles
            ));
        }
        if token.eq_ignore_ascii_case("BAD") {
            values.push(f64::NAN);
            continue;
        }
        let v: f64 = token
            .parse()
            .map_err(|_| FormatError::Malformed(format!("{token:?} is not a number")))?;
        values.push(if v.is_finite() { v } else { f64::NAN });
    }
    if values.len() != n {
        return malformed(format!(
            "{} values where the header declares {} × {} (truncated?)",
            values.len(),
            h.points,
            h.profiles
        ));
    }
    h.field(values)
}

fn read_binary(bytes: &[u8]) -> FResult<HeightField> {
    let head = bytes.get(..BINARY_HEADER).ok_or_else(|| {
        FormatError::Malformed(format!(
            "a binary SDF header has {BINARY_HEADER} bytes, the file {}",
            bytes.len()
        ))
    })?;
    let f = Fields::le(head);
    // magic 8, ManufacID 10, CreateDate 12, ModDate 12: the numbers from 42.
    let h = Header {
        points: usize::from(f.u16(42)?),
        profiles: usize::from(f.u16(44)?),
        x_scale: f.f64(46)?,
        y_scale: f.f64(54)?,
        z_scale: f.f64(62)?,
        compression: f.u8(78)?,
        data_type: f.u8(79)?,
    };
    h.check()?;
    let values = binary_values(&bytes[BINARY_HEADER..], &h)?;
    h.field(values)
}

/// The samples after a binary header: int16, int32 or f64; the type's
/// least value (non-finite for f64) a point not measured (NaN).
fn binary_values(body: &[u8], h: &Header) -> FResult<Vec<f64>> {
    let size = match h.data_type {
        5 => 2,
        6 => 4,
        _ => 8,
    };
    let n = h.points * h.profiles;
    if body.len() < n * size {
        return malformed(format!(
            "{} × {} samples of {size} bytes need {} bytes after the header, the file has {} (truncated?)",
            h.points,
            h.profiles,
            n * size,
            body.len()
        ));
    }
    Ok(body[..n * size]
        .chunks_exact(size)
        .map(|c| {
            let (v, bad) = match size {
                2 => {
                    let v = i16::from_le_bytes([c[0], c[1]]);
                    (f64::from(v), v == i16::MIN)
                }
                4 => {
                    let v = i32::from_le_bytes([c[0], c[1], c[2], c[3]]);
                    (f64::from(v), v == i32::MIN)
                }
                _ => {
                    let v = f64::from_le_bytes(c.try_into().expect("8 bytes"));
                    (v, !v.is_finite())
                }
            };
            if bad { f64::NAN } else { v }
        })
        .collect())
}

/// The `<AsperityParams>` line of a text SDF's trailer, if any.
pub(crate) fn params(bytes: &[u8]) -> Option<String> {
    let text = std::str::from_utf8(bytes).ok()?;
    let start = text.find("<AsperityParams>")? + "<AsperityParams>".len();
    let end = start + text[start..].find("</AsperityParams>")?;
    Some(text[start..end].to_owned())
}

/// Writes a text SDF (see the module docs).
pub(crate) fn write_height(
    w: &mut dyn Write,
    h: &HeightField,
    params: Option<&str>,
) -> std::io::Result<()> {
    let (fx, fz) = h.units().metre_factors();
    let [dx, dy] = h.spacing().map(|v| v * fx);
    let mut out = String::from("aISO-1.0\n");
    out += "ManufacID = asperity\nCreateDate = 000000000000\nModDate = 000000000000\n";
    out += &format!("NumPoints = {}\nNumProfiles = {}\n", h.nx(), h.ny());
    out += &format!("Xscale = {dx:E}\nYscale = {dy:E}\nZscale = 1.0E0\n");
    out += "Zresolution = -1.0E0\nCompression = 0\nDataType = 7\nCheckType = 0\n*\n";
    w.write_all(out.as_bytes())?;
    let mut line = String::new();
    for j in 0..h.ny() {
        line.clear();
        for (i, &z) in h.row(j).iter().enumerate() {
            if i > 0 {
                line.push(' ');
            }
            // `{:E}` is the shortest text that reads back as the same f64.
            line += &format!("{:E}", z * fz);
        }
        line.push('\n');
        w.write_all(line.as_bytes())?;
    }
    w.write_all(b"*\n")?;
    if let Some(p) = params {
        // A `*` line inside the parameters would end the trailer early.
        let p = p.replace('\n', " ");
        w.write_all(format!("<AsperityParams>{p}</AsperityParams>\n").as_bytes())?;
    }
    w.write_all(b"*\n")
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "ISO 25178-71 SDF (.sdf)",
    extensions: &["sdf"],
    height: Access::ReadWrite,
    notes: "text (aISO) and binary (bISO) read, int16/int32/f64; text written, f64 in metres; unmeasured (BAD) points read as missing, a field with missing points not written",
    magic: Magic::Starts(&[b"aISO-1.0", b"bISO-1.0"]),
    codec: Some(Codec::new(|b, _| read_height(b))),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    use crate::error::refused as err;

    const EXAMPLE: &str = "aISO-1.0\nManufacID = ISOTC213\nCreateDate = 040120100853\n\
        ModDate = 050320101353\nNumPoints = 3\nNumProfiles = 2\nXscale = 1.0E-6\n\
        Yscale = 2.0E-6\nZscale = 1.0E-6\nZresolution = 1.0E-9\nCompression = 0\n\
        DataType = 7\nCheckType = 0\n*\n1.0 0.5 0.25\n-1 0 2\n*\n<A> x </A>\n*\n";

    #[test]
    fn text_file_in_metres() {
        let h = read_height(EXAMPLE.as_bytes()).unwrap();
        assert_eq!(h.dims(), [3, 2]);
        assert_eq!(h.spacing(), [1e-6, 2e-6]);
        assert_eq!(h.units().xy, LengthUnit::M);
        assert_eq!(h.row(0), &[1e-6, 0.5e-6, 0.25e-6]);
        assert_eq!(h.row(1), &[-1e-6, 0.0, 2e-6]);
    }

    #[test]
    fn binary_file_of_int16_with_its_scale() {
        let mut b = BINARY_MAGIC.to_vec();
        b.extend([0u8; 34]);
        b.extend(2u16.to_le_bytes());
        b.extend(2u16.to_le_bytes());
        for v in [0.5e-6f64, 0.25e-6, 1e-9, 1e-10] {
            b.extend(v.to_le_bytes());
        }
        b.extend([0u8, 5, 0]);
        assert_eq!(b.len(), BINARY_HEADER);
        for v in [1i16, -2, 300, 4] {
            b.extend(v.to_le_bytes());
        }
        let h = read_height(&b).unwrap();
        assert_eq!(h.dims(), [2, 2]);
        assert_eq!(h.spacing(), [0.5e-6, 0.25e-6]);
        assert_eq!(h.data(), &[1e-9, -2e-9, 300.0 * 1e-9, 4e-9]);
        b.truncate(b.len() - 1);
        assert!(err(read_height(&b)).contains("truncated"));
    }

    #[test]
    fn unmeasured_points_are_missing_and_bad_headers_are_refused_by_name() {
        let bad = EXAMPLE.replace("0.5 0.25", "BAD 0.25");
        let holed = read_height(bad.as_bytes()).unwrap();
        assert_eq!(holed.missing_count(), 1, "BAD is a missing point");
        let short = EXAMPLE.replace("-1 0 2", "-1 0");
        let e = err(read_height(short.as_bytes()));
        assert!(e.contains("5 values") && e.contains("3 × 2"), "{e}");
        let packed = EXAMPLE.replace("Compression = 0", "Compression = 1");
        assert!(err(read_height(packed.as_bytes())).contains("compressed"));
        let kind = EXAMPLE.replace("DataType = 7", "DataType = 3");
        assert!(err(read_height(kind.as_bytes())).contains("DataType 3"));
        let huge = EXAMPLE.replace("NumPoints = 3", "NumPoints = 4000000000");
        assert!(err(read_height(huge.as_bytes())).contains("truncated"));
        assert!(read_height(b"aISO-1.0\nNumPoints = 3\n").is_err());
    }

    #[test]
    fn written_text_reads_back_exactly() {
        let h = HeightField::from_vec([3, 2], vec![1.5, -2.25e-3, 1.0 / 3.0, 0.0, 7e9, -1e-300])
            .unwrap()
            .with_spacing([0.1, 0.2])
            .unwrap()
            .with_units(Units {
                xy: LengthUnit::Um,
                z: LengthUnit::Nm,
            });
        let mut out = Vec::new();
        write_height(&mut out, &h, Some("{\"seed\": 3}")).unwrap();
        let back = read_height(&out).unwrap();
        assert_eq!(back.dims(), [3, 2]);
        let (fx, fz) = h.units().metre_factors();
        for (b, z) in back.data().iter().zip(h.data()) {
            assert_eq!(*b, z * fz);
        }
        assert_eq!(back.spacing(), [0.1 * fx, 0.2 * fx]);
        assert_eq!(params(&out).as_deref(), Some("{\"seed\": 3}"));
    }
}
