//! Point Cloud Library point clouds (`.pcd`, format v0.7, read): the format
//! range scans from PCL and ROS tools come in.
//!
//! A text header of `KEY values` lines — `FIELDS` (names), `SIZE` (bytes),
//! `TYPE` (`F` float, `I` signed, `U` unsigned), `COUNT` (elements per
//! field, default 1), `WIDTH`, `HEIGHT`, `POINTS`, `VIEWPOINT` — ends with
//! `DATA ascii`, `DATA binary` or `DATA binary_compressed`. Ascii data is a
//! point per line; binary data a record per point, fields in order; compressed
//! data two little-endian `u32` (compressed and decompressed sizes) and an
//! LZF stream that decompresses to the fields one after another (each field
//! for every point, then the next). PCL's documentation ("The PCD (Point
//! Cloud Data) file format") and its `pcd_io.cpp` define it.
//!
//! Read: `x y z` (required), `normal_x normal_y normal_z` as normals, `rgb`
//! or `rgba` (a packed 0xAARRGGBB in a float or an unsigned field) as
//! colours, and every other one-element numeric field as a named scalar.
//! Points whose coordinates are not finite (the unmeasured pixels of an
//! organised cloud, stored as NaN) are dropped.
//!
//! LZF decompression is written here (a dozen lines): the `lzf` crate is
//! marked deprecated by its author, and the decoder must bound its output by
//! the size the header declares anyway.

use asperity_core::PointSet;

use crate::Surface;
use crate::error::{FResult, FormatError, malformed};
use crate::format::{Access, Magic, Registration};

/// The registration of Pcd: its row of `asperity formats`, how its files
/// are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "PCL point cloud",
    extensions: &["pcd"],
    points: Access::Read,
    notes: "x y z, normals, rgb(a) and scalar fields; ascii, binary and LZF-compressed data",
    magic: Magic::Starts(&[b"# .PCD", b"VERSION"]),
    read: Some(|b| read(b).map(Surface::Points)),
    declared: Some(declared),
    ..Registration::NONE
};

/// One field of the header.
#[derive(Clone, Debug)]
struct Field {
    name: String,
    size: usize,
    kind: u8,
    count: usize,
}

impl Field {
    /// Bytes of one point's values of this field.
    fn bytes(&self) -> usize {
        self.size * self.count
    }

    /// Element `e` of this field's values starting at byte 0 of `b`.
    fn value(&self, b: &[u8], e: usize) -> f64 {
        let at = &b[e * self.size..(e + 1) * self.size];
        let le = |n: usize| {
            let mut a = [0u8; 8];
            a[..n].copy_from_slice(&at[..n]);
            u64::from_le_bytes(a)
        };
        match (self.kind, self.size) {
            (b'F', 4) => f64::from(f32::from_bits(le(4) as u32)),
            (b'F', 8) => f64::from_bits(le(8)),
            (b'U', n) => le(n) as f64,
            (b'I', n) => {
                let shift = 64 - 8 * n as u32;
                ((le(n) << shift) as i64 >> shift) as f64
            }
            _ => f64::NAN,
        }
    }
}

/// The header: fields, point count, the data's encoding and where it starts.
struct Header {
    fields: Vec<Field>,
    points: usize,
    data: Data,
    start: usize,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Data {
    Ascii,
    Binary,
    Compressed,
}

/// Header lines are short; a header longer than this is not a PCD header.
const MAX_HEADER: usize = 64 * 1024;

fn header(b: &[u8]) -> FResult<Header> {
    let mut names: Vec<String> = Vec::new();
    let (mut sizes, mut kinds, mut counts) = (Vec::new(), Vec::new(), Vec::new());
    let (mut width, mut height, mut points) = (None, 1usize, None);
    let mut at = 0;
    loop {
        if at >= b.len().min(MAX_HEADER) {
            return malformed("no DATA line in the header");
        }
        let end = b[at..].iter().position(|&c| c == b'\n').map_or(b.len(), |e| at + e);
        let line = String::from_utf8_lossy(&b[at..end]);
        at = (end + 1).min(b.len());
        let mut words = line.split_whitespace();
        let Some(key) = words.next() else { continue };
        let rest: Vec<&str> = words.collect();
        let number = |w: &str| -> FResult<usize> {
            w.parse::<usize>()
                .map_err(|_| FormatError::Malformed(format!("{key}: {w:?} is not a count")))
        };
        match key.to_ascii_uppercase().as_str() {
            k if k.starts_with('#') => {}
            "VERSION" | "VIEWPOINT" => {}
            "FIELDS" | "COLUMNS" => names = rest.iter().map(|s| s.to_string()).collect(),
            "SIZE" => sizes = rest.iter().map(|w| number(w)).collect::<FResult<_>>()?,
            "TYPE" => kinds = rest.iter().map(|w| w.as_bytes()[0].to_ascii_uppercase()).collect(),
            "COUNT" => counts = rest.iter().map(|w| number(w)).collect::<FResult<_>>()?,
            "WIDTH" => width = Some(number(rest.first().unwrap_or(&""))?),
            "HEIGHT" => height = number(rest.first().unwrap_or(&""))?,
            "POINTS" => points = Some(number(rest.first().unwrap_or(&""))?),
            "DATA" => {
                let data = match rest.first().map(|w| w.to_ascii_lowercase()).as_deref() {
                    Some("ascii") => Data::Ascii,
                    Some("binary") => Data::Binary,
                    Some("binary_compressed") => Data::Compressed,
                    other => return malformed(format!("DATA {other:?} is not ascii, binary or binary_compressed")),
                };
                if counts.is_empty() {
                    counts = vec![1; names.len()];
                }
                if sizes.len() != names.len() || kinds.len() != names.len() || counts.len() != names.len() {
                    return malformed(format!(
                        "FIELDS names {} fields but SIZE gives {}, TYPE {} and COUNT {}",
                        names.len(),
                        sizes.len(),
                        kinds.len(),
                        counts.len()
                    ));
                }
                let fields: Vec<Field> = (0..names.len())
                    .map(|i| Field { name: names[i].clone(), size: sizes[i], kind: kinds[i], count: counts[i] })
                    .collect();
                for f in &fields {
                    let ok = matches!((f.kind, f.size), (b'F', 4 | 8) | (b'I' | b'U', 1 | 2 | 4 | 8));
                    if !ok || f.count == 0 || f.count > 1 << 16 {
                        return malformed(format!(
                            "field {}: TYPE {} SIZE {} COUNT {} is not a PCD number",
                            f.name, f.kind as char, f.size, f.count
                        ));
                    }
                }
                let points = points
                    .or_else(|| width.map(|w| w.saturating_mul(height)))
                    .ok_or_else(|| FormatError::Malformed("no POINTS (or WIDTH) in the header".into()))?;
                return Ok(Header { fields, points, data, start: at });
            }
            _ => {}
        }
    }
}

/// What a file declares it decodes to: the points' records, and the f64
/// positions, normals and scalars made of them.
fn declared(b: &[u8]) -> FResult<u128> {
    let h = header(b)?;
    let record: usize = h.fields.iter().map(Field::bytes).sum();
    Ok(h.points as u128 * (record as u128 + 8 * 3 * 2 + 8 * h.fields.len() as u128))
}

fn read(b: &[u8]) -> FResult<PointSet> {
    let h = header(b)?;
    let record: usize = h.fields.iter().map(Field::bytes).sum();
    let data = &b[h.start..];
    // Per field, its values for every point: `column(f)(p, e)`.
    let columns: Vec<Vec<f64>> = match h.data {
        Data::Ascii => ascii_columns(data, &h)?,
        Data::Binary => {
            let need = h.points.checked_mul(record).filter(|&n| n <= data.len());
            let Some(need) = need else {
                return malformed(format!(
                    "{} points of {record} bytes need {} bytes of data, the file holds {}",
                    h.points,
                    h.points as u128 * record as u128,
                    data.len()
                ));
            };
            let mut offset = 0;
            h.fields
                .iter()
                .map(|f| {
                    let col = (0..h.points)
                        .flat_map(|p| {
                            let r = &data[p * record + offset..need];
                            (0..f.count).map(move |e| f.value(r, e))
                        })
                        .collect();
                    offset += f.bytes();
                    col
                })
                .collect()
        }
        Data::Compressed => {
            let raw = decompress(data, h.points, record)?;
            let mut offset = 0;
            h.fields
                .iter()
                .map(|f| {
                    let block = &raw[offset..offset + h.points * f.bytes()];
                    offset += h.points * f.bytes();
                    (0..h.points * f.count).map(|i| f.value(block, i)).collect()
                })
                .collect()
        }
    };
    points(&h, &columns)
}

/// The fields of an ascii file, a column per field (its elements per point
/// in a row).
fn ascii_columns(data: &[u8], h: &Header) -> FResult<Vec<Vec<f64>>> {
    let per_point: usize = h.fields.iter().map(|f| f.count).sum();
    let mut columns: Vec<Vec<f64>> = h.fields.iter().map(|_| Vec::new()).collect();
    let mut seen = 0;
    for (n, line) in data.split(|&c| c == b'\n').enumerate() {
        if seen == h.points {
            break;
        }
        let line = String::from_utf8_lossy(line);
        let values: Vec<&str> = line.split_whitespace().collect();
        if values.is_empty() {
            continue;
        }
        if values.len() != per_point {
            return malformed(format!(
                "data line {}: {} values, the fields need {per_point}",
                n + 1,
                values.len()
            ));
        }
        let mut it = values.iter();
        for (f, col) in h.fields.iter().zip(&mut columns) {
            for _ in 0..f.count {
                let w = it.next().copied().unwrap_or("");
                let v = if w.eq_ignore_ascii_case("nan") {
                    f64::NAN
                } else {
                    w.parse::<f64>().map_err(|_| {
                        FormatError::Malformed(format!("data line {}: {w:?} is not a number", n + 1))
                    })?
                };
                // A packed colour written as an integer keeps its bits.
                col.push(if f.kind == b'F' && f.size == 4 && is_colour(&f.name) && !w.contains(['.', 'e', 'E']) && v.fract() == 0.0 {
                    f64::from(f32::from_bits(v as u32))
                } else {
                    v
                });
            }
        }
        seen += 1;
    }
    if seen < h.points {
        return malformed(format!("{} points declared, {seen} in the data", h.points));
    }
    Ok(columns)
}

fn is_colour(name: &str) -> bool {
    matches!(name, "rgb" | "rgba")
}

/// The point set from the fields' columns.
fn points(h: &Header, columns: &[Vec<f64>]) -> FResult<PointSet> {
    let find = |name: &str| h.fields.iter().position(|f| f.name == name && f.count == 1);
    let (Some(x), Some(y), Some(z)) = (find("x"), find("y"), find("z")) else {
        return malformed("no x, y and z fields");
    };
    let keep: Vec<usize> = (0..h.points)
        .filter(|&p| [x, y, z].iter().all(|&c| columns[c][p].is_finite()))
        .collect();
    let gather = |c: usize| -> Vec<f64> { keep.iter().map(|&p| columns[c][p]).collect() };
    let (gx, gy, gz) = (gather(x), gather(y), gather(z));
    let positions: Vec<[f64; 3]> = (0..keep.len()).map(|i| [gx[i], gy[i], gz[i]]).collect();
    let mut set = PointSet::new(positions);
    let normal = [find("normal_x"), find("normal_y"), find("normal_z")];
    if let [Some(a), Some(b), Some(c)] = normal {
        let n: Vec<[f64; 3]> = keep.iter().map(|&p| [columns[a][p], columns[b][p], columns[c][p]]).collect();
        if n.iter().flatten().all(|v| v.is_finite()) {
            set.set_normals(n)?;
        }
    }
    let colour = find("rgba").or(find("rgb"));
    if let Some(c) = colour {
        let f = &h.fields[c];
        let colours = keep
            .iter()
            .map(|&p| {
                let v = columns[c][p];
                let bits = if f.kind == b'F' { (v as f32).to_bits() } else { v as u32 };
                let [b, g, r, a] = bits.to_le_bytes();
                [r, g, b, if f.name == "rgba" { a } else { 255 }]
            })
            .collect();
        set.set_colors(colours)?;
    }
    let taken = [Some(x), Some(y), Some(z), normal[0], normal[1], normal[2], colour];
    for (i, f) in h.fields.iter().enumerate() {
        if taken.contains(&Some(i)) || f.count != 1 || f.name == "_" {
            continue;
        }
        set.add_attribute(&f.name, gather(i))?;
    }
    Ok(set)
}

/// The LZF stream after the two sizes, decompressed to exactly the
/// `points × record` bytes the header implies.
fn decompress(data: &[u8], points: usize, record: usize) -> FResult<Vec<u8>> {
    let sizes = crate::bytes::Fields::le(data);
    let (packed, size) = (sizes.u32(0)? as usize, sizes.u32(4)? as usize);
    if points.checked_mul(record) != Some(size) {
        return malformed(format!(
            "the compressed data declares {size} bytes, {points} points of {record} bytes are {}",
            points as u128 * record as u128
        ));
    }
    // A control byte and a length byte make at most 264 bytes: a stream
    // cannot decode to more than 88 times its size.
    if size as u128 > 88 * packed as u128 + 64 {
        return malformed(format!(
            "the compressed data declares {size} bytes from {packed}: LZF cannot expand that far"
        ));
    }
    let stream = data
        .get(8..8 + packed)
        .ok_or_else(|| FormatError::Malformed(format!("the compressed data ({packed} bytes) is cut short")))?;
    lzf_decompress(stream, size)
}

/// LZF (Marc Lehmann's liblzf): a control byte below 32 copies that many
/// plus one literal bytes; above, its top three bits (7: plus the next byte)
/// plus two are a back-reference's length and its low five bits with the next
/// byte plus one its distance.
fn lzf_decompress(input: &[u8], size: usize) -> FResult<Vec<u8>> {
    let bad = || FormatError::Malformed("the LZF stream is corrupt".into());
    let mut out = Vec::with_capacity(size);
    let mut i = 0;
    while i < input.len() {
        let c = usize::from(input[i]);
        i += 1;
        if c < 32 {
            let run = input.get(i..i + c + 1).ok_or_else(bad)?;
            out.extend_from_slice(run);
            i += c + 1;
        } else {
            let mut len = c >> 5;
            if len == 7 {
                len += usize::from(*input.get(i).ok_or_else(bad)?);
                i += 1;
            }
            let back = ((c & 31) << 8) + usize::from(*input.get(i).ok_or_else(bad)?) + 1;
            i += 1;
            let from = out.len().checked_sub(back).ok_or_else(bad)?;
            for k in 0..len + 2 {
                out.push(out[from + k]);
            }
        }
        if out.len() > size {
            return Err(bad());
        }
    }
    if out.len() != size {
        return malformed(format!("the LZF stream gives {} bytes, the header declares {size}", out.len()));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    const ASCII: &[u8] = b"# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n\
        FIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\nWIDTH 3\nHEIGHT 1\n\
        VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n1 2 3 0.5\nnan nan nan 0\n4 5 6.5 7\n";

    /// The same cloud as ascii, binary and LZF-compressed (a literal run and
    /// back-references written by hand): the same points, the unmeasured one
    /// dropped, the scalar kept.
    #[test]
    fn ascii_binary_and_compressed_agree() {
        let a = read(ASCII).unwrap();
        assert_eq!(a.positions(), &[[1.0, 2.0, 3.0], [4.0, 5.0, 6.5]]);
        assert_eq!(a.attribute("intensity").unwrap(), &[0.5, 7.0]);
        let head = b"VERSION .7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\nWIDTH 3\nHEIGHT 1\nPOINTS 3\n";
        let rows = [[1.0f32, 2.0, 3.0, 0.5], [f32::NAN; 4], [4.0, 5.0, 6.5, 7.0]];
        let mut binary = head.to_vec();
        binary.extend_from_slice(b"DATA binary\n");
        binary.extend(rows.iter().flatten().flat_map(|v| v.to_le_bytes()));
        assert_eq!(read(&binary).unwrap(), a);
        // Column-major, then LZF: one literal run of all 48 bytes would do;
        // split it so that a back-reference is exercised too (x repeats).
        let soa: Vec<u8> = (0..4)
            .flat_map(|f| rows.iter().flat_map(move |r| r[f].to_le_bytes()))
            .collect();
        let mut lzf = vec![31u8];
        lzf.extend_from_slice(&soa[..32]);
        lzf.push(15);
        lzf.extend_from_slice(&soa[32..48]);
        let mut compressed = head.to_vec();
        compressed.extend_from_slice(b"DATA binary_compressed\n");
        compressed.extend((lzf.len() as u32).to_le_bytes());
        compressed.extend(48u32.to_le_bytes());
        compressed.extend(&lzf);
        assert_eq!(read(&compressed).unwrap(), a);
        // A back-reference: 8 bytes, then "copy 8 from 8 back".
        let out = lzf_decompress(&[7, 1, 2, 3, 4, 5, 6, 7, 8, 6 << 5, 7], 16).unwrap();
        assert_eq!(out, [1, 2, 3, 4, 5, 6, 7, 8, 1, 2, 3, 4, 5, 6, 7, 8]);
    }

    /// Normals and a packed float colour.
    #[test]
    fn normals_and_colours() {
        let colour = f32::from_bits(0x00ff8000);
        let text = format!(
            "FIELDS x y z normal_x normal_y normal_z rgb\nSIZE 4 4 4 4 4 4 4\nTYPE F F F F F F F\n\
             POINTS 1\nDATA ascii\n0 0 0 0 0 1 {colour:e}\n"
        );
        let p = read(text.as_bytes()).unwrap();
        assert_eq!(p.normals().unwrap(), &[[0.0, 0.0, 1.0]]);
        assert_eq!(p.colors().unwrap(), &[[255, 128, 0, 255]]);
    }

    #[test]
    fn broken_files_are_refused() {
        for (bytes, says) in [
            (&b"FIELDS x y z\nSIZE 4 4\nTYPE F F F\nPOINTS 1\nDATA ascii\n0 0 0\n"[..], "SIZE gives 2"),
            (b"FIELDS x y\nSIZE 4 4\nTYPE F F\nPOINTS 1\nDATA ascii\n0 0\n", "no x, y and z"),
            (b"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 2\nDATA ascii\n0 0 0\n", "2 points declared"),
            (b"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 9\nDATA binary\n", "need 108 bytes"),
            (b"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1\nDATA lzma\n", "is not ascii"),
            (b"FIELDS x y z\nSIZE 3 4 4\nTYPE F F F\nPOINTS 1\nDATA ascii\n0 0 0\n", "not a PCD number"),
            (b"VERSION .7\nFIELDS x y z\n", "no DATA line"),
            (
                b"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 100000000\nDATA binary_compressed\n\x04\0\0\0\0\x8c\x86\x47\0\0\0\0",
                "cannot expand that far",
            ),
        ] {
            let e = format!("{:?}", read(bytes).unwrap_err());
            assert!(e.contains(says), "{e} (wanted {says})");
        }
        assert!(lzf_decompress(&[1 << 5, 0], 4).is_err(), "a reference before any output");
        assert!(lzf_decompress(&[3, 1, 2], 4).is_err(), "a literal run cut short");
    }
}
