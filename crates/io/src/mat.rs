//! MATLAB workspace files (`.mat`), read as SurfaceTopography reads them:
//! every two-dimensional numeric array is a channel (a complex one is listed
//! but refused, where SurfaceTopography drops its imaginary part), named by its
//! variable; the matrix's first (row) index runs along x and its second
//! (column) index along y. MAT files keep no sizes or units: the step is 1
//! and the numbers unitless.
//!
//! **Version 5** (MATLAB 5 to 7.2, and what `scipy.io.savemat` writes;
//! MathWorks, *MAT-File Format*, R2007b, ch. 1): a 128-byte header (text,
//! version 0x0100 and the byte order `IM` or `MI`), then data elements, each
//! an 8-byte tag (type, byte count) or a 4-byte "small element" tag, padded
//! to 8 bytes. A variable is an `miMATRIX` element (type 14) of sub-elements:
//! array flags (class in the low byte, complex bit 0x0800), dimensions, name,
//! real part (stored in any numeric type, which MATLAB narrows, e.g. a double
//! matrix of small integers as `miUINT8`), imaginary part. An `miCOMPRESSED`
//! element (type 15) is one such element deflated with zlib. The data are
//! column-major, so a matrix of r rows and c columns is asperity's field of
//! r × c (nx × ny) points without transposing.
//!
//! **Version 7.3** (`MATLAB 7.3 MAT-file` in the header): an HDF5 file after
//! a 512-byte user block, each variable a dataset with a `MATLAB_class`
//! attribute; MATLAB writes its column-major matrix as an HDF5 dataset of
//! shape (c, r), which is again asperity's layout. Read through [`crate::h5`].
//!
//! Written here rather than with the `matfile` crate (alpha, it prints its
//! errors to stderr and inflates compressed elements without bound): every
//! inflation here is bounded by the size the element's own header declares,
//! and the memory estimate (`declared_points`) counts every array's
//! declared points before any data are read.

use std::io::Read;

use asperity_core::HeightField;
use flate2::read::ZlibDecoder;

use crate::channel::{Channel, ChannelInfo, pick};
use crate::error::{FResult, FormatError, malformed, unsupported};
use crate::format::{Access, Codec, Magic, Registration};

/// The start of every MAT file's header text.
pub(crate) const MAGIC: &[u8] = b"MATLAB";
/// The header text of a version 7.3 (HDF5) file.
const V73: &[u8] = b"MATLAB 7.3 MAT-file";
const HEADER: usize = 128;
const MI_MATRIX: u32 = 14;
const MI_COMPRESSED: u32 = 15;
/// How many inflated bytes are enough for a matrix's flags, sizes and name.
const HEAD_BYTES: u64 = 4096;

/// One variable: its name, rows, columns and, when it is a real numeric
/// matrix, where its real part's bytes are and in which type.
struct Variable {
    name: String,
    dims: Vec<usize>,
    numeric: bool,
    complex: bool,
    real: Option<(u32, Vec<u8>)>,
}

#[derive(Clone, Copy)]
struct Order {
    little: bool,
}

impl Order {
    fn u32(self, b: &[u8]) -> u32 {
        let a = [b[0], b[1], b[2], b[3]];
        if self.little {
            u32::from_le_bytes(a)
        } else {
            u32::from_be_bytes(a)
        }
    }

    fn i32(self, b: &[u8]) -> i32 {
        self.u32(b) as i32
    }
}

/// One data element at the start of `bytes`: its type, its data and the
/// bytes the element takes (padding included).
fn element(bytes: &[u8], o: Order) -> FResult<(u32, &[u8], usize)> {
    let Some(tag) = bytes.get(..8) else {
        return malformed("a data element's tag runs past its end (truncated?)");
    };
    let first = o.u32(tag);
    if first >> 16 != 0 {
        // The small element format: type and size in one word, data in the next.
        let (ty, n) = (first & 0xFFFF, (first >> 16) as usize);
        if n > 4 {
            return malformed(format!("a small data element of {n} bytes (at most 4)"));
        }
        return Ok((ty, &tag[4..4 + n], 8));
    }
    let n = o.u32(&tag[4..]) as usize;
    let data = bytes.get(8..8usize.saturating_add(n)).ok_or_else(|| {
        FormatError::Malformed(format!(
            "a data element of {n} bytes runs past the file's end (truncated?)"
        ))
    })?;
    // Compressed elements are not padded (MATLAB and scipy write them so).
    let padded = if first == MI_COMPRESSED {
        8 + n
    } else {
        8 + n.div_ceil(8) * 8
    };
    Ok((first, data, padded.min(bytes.len())))
}

/// The bytes of one element of each numeric data type.
fn type_bytes(ty: u32) -> Option<usize> {
    match ty {
        1 | 2 => Some(1),
        3 | 4 => Some(2),
        5..=7 => Some(4),
        9 | 12 | 13 => Some(8),
        _ => None,
    }
}

/// A number of data type `ty` from its bytes.
fn number(ty: u32, b: &[u8], o: Order) -> f64 {
    let a8 = |b: &[u8]| {
        let a: [u8; 8] = b.try_into().expect("8 bytes");
        if o.little {
            u64::from_le_bytes(a)
        } else {
            u64::from_be_bytes(a)
        }
    };
    let a2 = |b: &[u8]| {
        let a = [b[0], b[1]];
        if o.little {
            u16::from_le_bytes(a)
        } else {
            u16::from_be_bytes(a)
        }
    };
    match ty {
        1 => f64::from(b[0] as i8),
        2 => f64::from(b[0]),
        3 => f64::from(a2(b) as i16),
        4 => f64::from(a2(b)),
        5 => f64::from(o.i32(b)),
        6 => f64::from(o.u32(b)),
        7 => f64::from(f32::from_bits(o.u32(b))),
        9 => f64::from_bits(a8(b)),
        12 => a8(b) as i64 as f64,
        _ => a8(b) as f64,
    }
}

/// A matrix element's sub-elements: flags, dimensions, name and, when
/// `with_data`, the real part.
fn matrix(data: &[u8], o: Order, with_data: bool) -> FResult<Variable> {
    let (_, flags, used) = element(data, o)?;
    if flags.len() < 8 {
        return malformed("a matrix's array flags are shorter than 8 bytes");
    }
    let word = o.u32(flags);
    let class = word & 0xFF;
    let complex = word & 0x0800 != 0;
    let mut rest = &data[used..];
    let (_, dims, used) = element(rest, o)?;
    let dims: Vec<usize> = dims
        .chunks_exact(4)
        .map(|d| usize::try_from(o.i32(d)).unwrap_or(0))
        .collect();
    rest = &rest[used..];
    let (_, name, used) = element(rest, o)?;
    let name: String = name.iter().map(|&c| char::from(c)).collect();
    rest = &rest[used..];
    // mxDOUBLE … mxUINT64 are 6 … 15 (a logical array is UINT8 with a flag).
    let numeric = (6..=15).contains(&class);
    let real = if with_data && numeric && !complex {
        let (ty, part, _) = element(rest, o)?;
        Some((ty, part.to_vec()))
    } else {
        None
    };
    Ok(Variable {
        name,
        dims,
        numeric,
        complex,
        real,
    })
}

/// Inflates at most `limit` bytes of a compressed element.
fn inflate(data: &[u8], limit: u64) -> FResult<Vec<u8>> {
    let mut out = Vec::new();
    ZlibDecoder::new(data)
        .take(limit)
        .read_to_end(&mut out)
        .map_err(|e| {
            FormatError::Malformed(format!("a compressed element does not inflate: {e}"))
        })?;
    Ok(out)
}

/// The points of a variable's dimensions (0 on overflow: no channel).
fn points(dims: &[usize]) -> usize {
    dims.iter()
        .try_fold(1usize, |n, &d| n.checked_mul(d))
        .unwrap_or(0)
}

/// Every top-level variable of a version 5 file; the real parts only when
/// `with_data` (and then only of the variable `only`, by index, if given).
fn variables(bytes: &[u8], with_data: bool, only: Option<usize>) -> FResult<Vec<Variable>> {
    let Some(head) = bytes.get(..HEADER) else {
        return malformed("shorter than the 128-byte MAT header (truncated?)");
    };
    let o = match &head[126..128] {
        b"IM" => Order { little: true },
        b"MI" => Order { little: false },
        other => {
            return malformed(format!(
                "byte order mark {other:?} (`IM` or `MI` expected): not a MAT file"
            ));
        }
    };
    let mut out = Vec::new();
    let mut at = HEADER;
    while at < bytes.len() {
        let (ty, data, used) = element(&bytes[at..], o)?;
        at += used;
        let want_data = with_data && only.is_none_or(|k| k == out.len());
        let variable = match ty {
            MI_MATRIX => matrix(data, o, want_data)?,
            MI_COMPRESSED => {
                let head = inflate(data, HEAD_BYTES)?;
                if head.len() < 8 {
                    return malformed("a compressed element inflates to less than a tag");
                }
                if o.u32(&head) != MI_MATRIX {
                    continue;
                }
                let peek = matrix(&head[8..], o, false)?;
                if !(want_data && peek.numeric) {
                    peek
                } else {
                    // Bounded by what the header declares: tag, flags, sizes
                    // and name (within HEAD_BYTES), 8 bytes a point, padding.
                    let limit = HEAD_BYTES + 8 * points(&peek.dims) as u64 + 16;
                    let full = inflate(data, limit)?;
                    matrix(&full[8..], o, true)?
                }
            }
            _ => continue, // other top-level elements hold no variable
        };
        out.push(variable);
    }
    Ok(out)
}

/// Whether a variable is a channel: numeric, two-dimensional, not empty (a
/// complex one is listed, as SurfaceTopography lists it, but not read).
fn is_channel(v: &Variable) -> bool {
    v.numeric && v.dims.len() == 2 && v.dims.iter().all(|&d| d > 0) && points(&v.dims) > 0
}

/// The 7.3 file's HDF5 part (after its user block), if it is one.
fn hdf5_part(bytes: &[u8]) -> Option<&[u8]> {
    bytes.starts_with(V73).then(|| bytes.get(512..)).flatten()
}

/// The file's channels: its 2-D numeric variables, in the file's order.
pub(crate) fn channels(bytes: &[u8]) -> FResult<Vec<ChannelInfo>> {
    if let Some(h5) = hdf5_part(bytes) {
        return crate::h5::channels(h5);
    }
    let vars = variables(bytes, false, None)?;
    let channels: Vec<ChannelInfo> = vars
        .iter()
        .filter(|v| is_channel(v))
        .enumerate()
        .map(|(index, v)| ChannelInfo {
            index,
            name: v.name.clone(),
            height: !v.complex,
        })
        .collect();
    if channels.is_empty() {
        return malformed("the file holds no two-dimensional real numeric variable");
    }
    Ok(channels)
}

/// The points of every variable the file declares (the memory estimate).
pub(crate) fn declared_points(bytes: &[u8]) -> FResult<u128> {
    if let Some(h5) = hdf5_part(bytes) {
        return crate::h5::declared_points(h5);
    }
    Ok(variables(bytes, false, None)?
        .iter()
        .map(|v| points(&v.dims) as u128)
        .sum())
}

/// Reads the channel `choice` names (default the first).
pub(crate) fn read_channel(bytes: &[u8], choice: Option<&Channel>) -> FResult<HeightField> {
    if let Some(h5) = hdf5_part(bytes) {
        // MATLAB's (c, r) dataset is asperity's layout: no transposing.
        return crate::h5::read_channel_as_stored(h5, choice);
    }
    if bytes.starts_with(V73) {
        return malformed("a version 7.3 MAT file shorter than its 512-byte user block");
    }
    let list = channels(bytes)?;
    let k = pick(&list, choice)?;
    // The k-th channel's index among all variables.
    let all = variables(bytes, false, None)?;
    let index = all
        .iter()
        .enumerate()
        .filter(|(_, v)| is_channel(v))
        .nth(k)
        .map(|(i, _)| i)
        .expect("a listed channel");
    let vars = variables(bytes, true, Some(index))?;
    let v = &vars[index];
    if v.complex {
        return unsupported(format!(
            "variable {:?} is complex; asperity reads real heights (save its real part)",
            v.name
        ));
    }
    let (nx, ny) = (v.dims[0], v.dims[1]);
    let Some((ty, part)) = &v.real else {
        return malformed(format!("variable {:?} has no data", v.name));
    };
    let Some(size) = type_bytes(*ty) else {
        return unsupported(format!(
            "variable {:?} stored as data type {ty}; asperity reads the numeric types",
            v.name
        ));
    };
    let n = nx * ny; // a channel's points do not overflow (`is_channel`)
    if part.len() / size < n {
        return malformed(format!(
            "variable {:?}: {nx} × {ny} points need {} bytes, its data have {} (truncated?)",
            v.name,
            n.saturating_mul(size),
            part.len()
        ));
    }
    let o = Order {
        little: bytes[126..128] == *b"IM",
    };
    let data = part[..n * size]
        .chunks_exact(size)
        .map(|b| number(*ty, b, o))
        .collect();
    Ok(HeightField::from_vec([nx, ny], data)?)
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "MATLAB (.mat)",
    extensions: &["mat"],
    height: Access::Read,
    notes: "versions 5 (compressed or not, as scipy.io.savemat writes) and 7.3 (HDF5): every two-dimensional real numeric variable a channel by name, the matrix's rows along x (as SurfaceTopography reads it); no sizes or units in the file: step 1, unitless",
    magic: Magic::Starts(&[MAGIC]),
    codec: Some(Codec::new(read_channel)
        .channels(channels)
        .declared(|b| declared_points(b).map(crate::pixel_bytes))),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    /// A little-endian level 5 element: tag, data, padding.
    fn elem(ty: u32, data: &[u8]) -> Vec<u8> {
        let mut e = ty.to_le_bytes().to_vec();
        e.extend((data.len() as u32).to_le_bytes());
        e.extend(data);
        e.resize(8 + data.len().div_ceil(8) * 8, 0);
        e
    }

    /// A matrix variable of class `class` stored as data type `ty`.
    fn var(name: &str, class: u32, dims: &[i32], ty: u32, data: &[u8]) -> Vec<u8> {
        let mut m = elem(6, &[class.to_le_bytes(), 0u32.to_le_bytes()].concat());
        let d: Vec<u8> = dims.iter().flat_map(|d| d.to_le_bytes()).collect();
        m.extend(elem(5, &d));
        m.extend(elem(1, name.as_bytes()));
        m.extend(elem(ty, data));
        elem(MI_MATRIX, &m)
    }

    fn file(vars: &[Vec<u8>]) -> Vec<u8> {
        let mut f = b"MATLAB 5.0 MAT-file, written by a test".to_vec();
        f.resize(124, b' ');
        f.extend([0x00, 0x01, b'I', b'M']);
        for v in vars {
            f.extend(v);
        }
        f
    }

    #[test]
    fn a_column_major_matrix_is_read_with_rows_along_x() {
        // A 3 × 2 double matrix [[1, 4], [2, 5], [3, 6]] (column-major 1…6).
        let data: Vec<u8> = (1..=6).flat_map(|v| f64::from(v).to_le_bytes()).collect();
        let f = file(&[var("z", 6, &[3, 2], 9, &data)]);
        let h = read_channel(&f, None).unwrap();
        assert_eq!(h.dims(), [3, 2]);
        assert_eq!(h.row(0), &[1.0, 2.0, 3.0]);
        assert_eq!(h.row(1), &[4.0, 5.0, 6.0]);
    }

    #[test]
    fn channels_skip_vectors_text_and_complex_and_compressed_ones_are_read() {
        let text = var("label", 4, &[1, 3], 4, &[b'a', 0, b'b', 0, b'c', 0]);
        let vector = var("v", 6, &[1, 1, 2], 9, &[0; 16]);
        let narrowed = var("small", 6, &[2, 2], 2, &[1, 2, 3, 250]);
        let big = var("big", 6, &[2, 2], 9, &[0; 32]);
        let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
        std::io::Write::write_all(&mut z, &big).unwrap();
        let packed = z.finish().unwrap();
        let mut compressed = MI_COMPRESSED.to_le_bytes().to_vec();
        compressed.extend((packed.len() as u32).to_le_bytes());
        compressed.extend(&packed);
        let f = file(&[text, vector, narrowed, compressed]);
        let names: Vec<String> = channels(&f).unwrap().into_iter().map(|c| c.name).collect();
        assert_eq!(names, ["small", "big"]);
        let h = read_channel(&f, None).unwrap();
        assert_eq!(h.data(), &[1.0, 2.0, 3.0, 250.0]);
        let h = read_channel(&f, Some(&Channel::parse("big"))).unwrap();
        assert_eq!(h.data(), &[0.0; 4]);
        assert_eq!(declared_points(&f).unwrap(), 3 + 2 + 4 + 4);
    }

    #[test]
    fn truncated_and_foreign_files_are_refused() {
        let data: Vec<u8> = (1..=6).flat_map(|v| f64::from(v).to_le_bytes()).collect();
        let f = file(&[var("z", 6, &[3, 2], 9, &data)]);
        for cut in [0, 100, 130, f.len() - 9] {
            assert!(read_channel(&f[..cut], None).is_err(), "cut at {cut}");
        }
        let mut other = f;
        other[126] = b'X';
        assert!(read_channel(&other, None).is_err());
    }
}
